#!/bin/sh
# Runs every tests/e2e/*.sh with the build directory as $1 (real processes, loopback).
#
# By default the whole run shares the machine with another job: one busy loop per core at
# normal priority, so timing-bound tests fail here rather than on a busy CI host.
#   E2E_LOAD=0            no load (debugging)
#   E2E_LOAD=N            N busy loops instead of one per core
#   E2E_LOAD_SECONDS=S    each loop stops by itself after S seconds (default 900), so a
#                         runner killed with SIGKILL leaves nothing spinning for long
#   E2E_ONLY="a b"        run only these tests (names without .sh)
# One test at a time: a second one beside (tried: ident next to the others) disturbed the
# timing that c4g-sim and the fits judge, and a test failed.
set -u
build=$1
load=${E2E_LOAD:-$(nproc 2>/dev/null || echo 2)}
load_s=${E2E_LOAD_SECONDS:-900}
loaders=''
stop_load() {
  for p in $loaders; do kill "$p" 2>/dev/null; done
  for p in $loaders; do wait "$p" 2>/dev/null; done
  loaders=''
}
trap stop_load EXIT
trap 'exit 130' INT TERM
i=0
while [ "$i" -lt "$load" ]; do
  timeout "$load_s" sh -c 'while :; do :; done' &
  loaders="$loaders $!"
  i=$((i + 1))
done
[ "$load" -gt 0 ] && echo "e2e: $load busy loop(s) running alongside (E2E_LOAD=0 turns them off)"
pass=0; fail=0; failed=''; rerun=''
recap=$build/e2e-failed.txt
: >"$recap"
# fail_lines LOG: the failed checks of a run (each test prints "FAIL description")
fail_lines() { grep -n 'FAIL' "$1" | head -n 8 | sed 's/^/    /'; }
for t in tests/e2e/*.sh; do
  [ -f "$t" ] || continue
  name=$(basename "$t" .sh)
  if [ -n "${E2E_ONLY:-}" ]; then
    case " $E2E_ONLY " in *" $name "*) ;; *) continue ;; esac
  fi
  log="$build/e2e-$name.log"
  t0=$(date +%s)
  if timeout 600 sh "$t" "$build" >"$log" 2>&1; then
    pass=$((pass + 1)); echo "e2e: PASS $name ($(( $(date +%s) - t0 )) s)"
    continue
  fi
  # A failed test runs once more. Every test here already makes again a run whose own
  # figures show the host held it up; this second run is for a disturbance no figure
  # showed. It is reported, with the first run's failed checks, here and in the summary:
  # a real fault fails both runs.
  mv "$log" "$build/e2e-$name.first.log"
  echo "e2e: FAIL $name, first run ($(( $(date +%s) - t0 )) s, log: $build/e2e-$name.first.log); once more:"
  fail_lines "$build/e2e-$name.first.log"
  t0=$(date +%s)
  if timeout 600 sh "$t" "$build" >"$log" 2>&1; then
    pass=$((pass + 1)); rerun="$rerun $name"
    echo "e2e: PASS $name on its second run ($(( $(date +%s) - t0 )) s)"
    { echo "e2e: $name passed only on its second run; the first failed:"; fail_lines "$build/e2e-$name.first.log"; } >>"$recap"
  else
    fail=$((fail + 1)); failed="$failed $name"; echo "e2e: FAIL $name ($(( $(date +%s) - t0 )) s, log: $log)"
    # the failed checks first (a long dump would push them out of the tail), then the tail
    grep -n -A2 'FAIL' "$log" | head -n 20 | sed 's/^/    /'; echo "    ..."; tail -n 30 "$log" | sed 's/^/    /'
    { echo "e2e: FAIL $name (both runs); the second run's failed checks:"; fail_lines "$log"; } >>"$recap"
  fi
done
# the failed checks once more next to the verdict: a reader who sees only the end of a long
# log (a CI excerpt) still sees what failed
cat "$recap"
echo "e2e: $pass passed${rerun:+ (on a second run:$rerun)}, $fail failed${failed:+ (failed:$failed)}"
[ "$fail" -eq 0 ]
