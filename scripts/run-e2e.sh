#!/bin/sh
# Runs every tests/e2e/*.sh with the build directory as $1 (real processes, loopback).
set -u
build=$1
pass=0; fail=0; failed=''
for t in tests/e2e/*.sh; do
  [ -f "$t" ] || continue
  name=$(basename "$t" .sh)
  log="$build/e2e-$name.log"
  if timeout 600 sh "$t" "$build" >"$log" 2>&1; then
    pass=$((pass + 1)); echo "e2e: PASS $name"
  else
    fail=$((fail + 1)); failed="$failed $name"; echo "e2e: FAIL $name (log: $log)"; tail -n 30 "$log" | sed 's/^/    /'
  fi
done
echo "e2e: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
