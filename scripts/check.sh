#!/bin/sh
# make check: every gate in turn, each one run even when an earlier one failed (but none
# after a failed build), then one line a CI reader recognises: "check: N passed, M failed".
#   scripts/check.sh MAKE GATE...
set -u
make_cmd=$1
shift
pass=0; fail=0; failed=''
for gate in "$@"; do
  echo "== check: $gate"
  t0=$(date +%s)
  if $make_cmd "$gate"; then
    pass=$((pass + 1))
    echo "== check: $gate passed in $(( $(date +%s) - t0 )) s"
  else
    fail=$((fail + 1)); failed="$failed $gate"
    echo "check: gate $gate FAILED (after $(( $(date +%s) - t0 )) s)"
    if [ "$gate" = all ]; then
      break # nothing else can run without the build
    fi
  fi
done
[ -n "$failed" ] && echo "check: failed gates:$failed"
echo "check: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
