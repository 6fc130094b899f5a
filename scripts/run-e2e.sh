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
#   E2E_BESIDE="a b"      run these tests one after the other in a second lane, beside the
#                         rest (default: ident, the longest, whose ports no other test uses and
#                         whose sessions run SCHED_FIFO); E2E_BESIDE= runs everything in one lane
set -u
build=$1
load=${E2E_LOAD:-$(nproc 2>/dev/null || echo 2)}
load_s=${E2E_LOAD_SECONDS:-900}
beside=${E2E_BESIDE-ident}
loaders=''
lane=''
stop_load() {
  [ -n "$lane" ] && kill "$lane" 2>/dev/null
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
selected() {  # selected NAME: in E2E_ONLY (when set)
  [ -z "${E2E_ONLY:-}" ] && return 0
  case " $E2E_ONLY " in *" $1 "*) return 0 ;; esac
  return 1
}
in_beside() { case " $beside " in *" $1 "*) return 0 ;; esac; return 1; }
# run_one NAME: runs tests/e2e/NAME.sh, prints PASS/FAIL and the log's tail, exit status as the test's
run_one() {
  log="$build/e2e-$1.log"
  t0=$(date +%s)
  if timeout 600 sh "tests/e2e/$1.sh" "$build" >"$log" 2>&1; then
    echo "e2e: PASS $1 ($(( $(date +%s) - t0 )) s)"
  else
    echo "e2e: FAIL $1 ($(( $(date +%s) - t0 )) s, log: $log)"; tail -n 30 "$log" | sed 's/^/    /'
    return 1
  fi
}
pass=0; fail=0; failed=''
count() {  # count NAME STATUS
  if [ "$2" -eq 0 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); failed="$failed $1"; fi
}
# the second lane: its results in a file, read when it is done
results="$build/e2e-beside.results"
rm -f "$results"
todo=''
for n in $beside; do [ -f "tests/e2e/$n.sh" ] && selected "$n" && todo="$todo $n"; done
if [ -n "$todo" ]; then
  mkdir -p "$build"
  ( for n in $todo; do run_one "$n"; echo "$n $?" >>"$results"; done ) &
  lane=$!
fi
for t in tests/e2e/*.sh; do
  [ -f "$t" ] || continue
  name=$(basename "$t" .sh)
  selected "$name" || continue
  in_beside "$name" && continue
  run_one "$name"; count "$name" $?
done
if [ -n "$lane" ]; then
  wait "$lane"; lane=''
  for n in $todo; do
    st=$(sed -n "s/^$n //p" "$results" 2>/dev/null)
    count "$n" "${st:-1}"
  done
fi
echo "e2e: $pass passed, $fail failed${failed:+ (failed:$failed)}"
[ "$fail" -eq 0 ]
