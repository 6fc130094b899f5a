#!/bin/sh
# Hostile clients against cell-sim (64 KiB line, 1000 connections dropped, garbage,
# 1 byte/s sender, non-reading and silent clients) while a well-behaved client keeps
# getting correct replies. Ports 21021-21023 on 127.0.0.1.
set -u
build=$1
log=$(mktemp)
pid=''
cleanup() { [ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -f "$log"; }
trap cleanup EXIT INT TERM
"$build/bin/cell-sim" -p 21021 >"$log" 2>&1 & pid=$!
i=0
until ss -Htln "sport = :21023" | grep -q LISTEN; do   # the last of its three ports
  i=$((i + 1)); [ $i -gt 1500 ] && { echo "FAIL: cell-sim did not start"; cat "$log"; exit 1; }; sleep 0.02
done
timeout 90 python3 tests/e2e/cell_hostile_check.py 21021; rc=$?
kill -0 "$pid" 2>/dev/null && echo "PASS: cell-sim still running" || { echo "FAIL: cell-sim died"; rc=1; }
n=$(grep -c 'connect: connection accepted' "$log")
[ "$n" -ge 1000 ] && echo "PASS: $n connections logged with their peer" || { echo "FAIL: only $n connections logged"; rc=1; }
grep -q 'error: ER+00102: line longer than 64 bytes dropped' "$log" && echo "PASS: overlong line logged" || { echo "FAIL: overlong line not logged"; rc=1; }
[ $rc -eq 0 ] || tail -20 "$log"
exit $rc
