#!/bin/sh
# make check: every gate in turn, each one run even when an earlier one failed (but none
# after a failed build), then one line a CI reader recognises: "check: N passed, M failed".
#   scripts/check.sh MAKE GATE... [-- BESIDE_GATE...]
# The gates after "--" only compute (static analysis, cross builds, fuzzing): they start once
# the build passed and run at nice 19 beside the others, in the time the e2e gate spends
# waiting on real-time sessions. They take the place of one of its busy loops, which keep
# the vCPUs awake (an idle vCPU wakes late), and become a busy loop themselves when done. Their
# output is printed when each is collected, after the foreground gates.
set -u
make_cmd=$1
shift
fg=''; beside=''; after=no
for g in "$@"; do
  if [ "$g" = -- ]; then after=yes
  elif [ $after = yes ]; then beside="$beside $g"
  else fg="$fg $g"
  fi
done
pass=0; fail=0; failed=''
logdir=''; bgpid=''
start_beside() {
  [ -n "$beside" ] || return 0
  logdir=$(mktemp -d "${TMPDIR:-/tmp}/c4g-check.XXXXXX")
  echo "== check: beside the other gates, at nice 19:$beside"
  # shellcheck disable=SC2086
  nice -n 19 sh -c '
    logdir=$1; make_cmd=$2; shift 2
    spin=""
    trap "[ -n \"\$spin\" ] && kill \$spin 2>/dev/null; exit 0" TERM
    for g in "$@"; do
      t0=$(date +%s)
      if $make_cmd "$g" > "$logdir/$g.log" 2>&1; then r=passed; else r=FAILED; fi
      echo "$g $r $(( $(date +%s) - t0 ))" >> "$logdir/status"
    done
    : > "$logdir/done"
    timeout 3600 sh -c "while :; do :; done" & spin=$!
    wait
  ' check-beside "$logdir" "$make_cmd" $beside &
  bgpid=$!
}
collect_beside() {
  [ -n "$bgpid" ] || return 0
  while [ ! -e "$logdir/done" ] && kill -0 "$bgpid" 2>/dev/null; do sleep 1; done
  kill "$bgpid" 2>/dev/null; wait "$bgpid" 2>/dev/null
  for g in $beside; do
    echo "== check: $g (ran beside the other gates)"
    [ -f "$logdir/$g.log" ] && cat "$logdir/$g.log"
    line=$(grep "^$g " "$logdir/status" 2>/dev/null)
    set -- $line
    if [ "${2:-}" = passed ]; then
      pass=$((pass + 1))
      echo "== check: $g passed in $3 s (beside)"
    else
      fail=$((fail + 1)); failed="$failed $g"
      echo "check: gate $g FAILED (after ${3:-?} s, beside)"
    fi
  done
  rm -rf "$logdir"
}
trap '[ -n "$bgpid" ] && kill "$bgpid" 2>/dev/null; [ -n "$logdir" ] && rm -rf "$logdir"; exit 130' INT TERM
for gate in $fg; do
  echo "== check: $gate"
  t0=$(date +%s)
  load=''
  if [ "$gate" = e2e ] && [ -n "$bgpid" ]; then
    # one busy loop fewer: the gates beside are (or become) the other
    load="E2E_LOAD=$(( $(nproc 2>/dev/null || echo 2) - 1 ))"
  fi
  # shellcheck disable=SC2086
  if env $load $make_cmd "$gate"; then
    pass=$((pass + 1))
    echo "== check: $gate passed in $(( $(date +%s) - t0 )) s"
  else
    fail=$((fail + 1)); failed="$failed $gate"
    echo "check: gate $gate FAILED (after $(( $(date +%s) - t0 )) s)"
    if [ "$gate" = all ]; then
      break # nothing else can run without the build
    fi
  fi
  if [ "$gate" = all ]; then
    start_beside
  fi
done
collect_beside
[ -n "$failed" ] && echo "check: failed gates:$failed"
echo "check: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
