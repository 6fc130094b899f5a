#!/bin/sh
# Hostile clients against cell-sim (64 KiB line, 1000 connections dropped, garbage,
# 1 byte/s sender, non-reading and silent clients, 200 kB of newlines) while a
# well-behaved client keeps getting correct replies, and the log stays small (also with
# -q). Ports 21021-21026 on 127.0.0.1. Then cell-cli against a hostile device (escape
# sequences, unsolicited lines, replies of the wrong shape) on 21061 and 21072.
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
timeout 90 python3 tests/e2e/cell_hostile_check.py 21021 "$log"; rc=$?
kill -0 "$pid" 2>/dev/null && echo "PASS: cell-sim still running" || { echo "FAIL: cell-sim died"; rc=1; }
n=$(grep -c 'connect: connection accepted' "$log")
[ "$n" -ge 1000 ] && echo "PASS: $n connections logged with their peer" || { echo "FAIL: only $n connections logged"; rc=1; }
grep -q 'error: ER+00102: line longer than 64 bytes dropped' "$log" && echo "PASS: overlong line logged" || { echo "FAIL: overlong line not logged"; rc=1; }
[ $rc -eq 0 ] || tail -20 "$log"
# -q (errors only) used to log one line per bad line: 200 kB of newlines, 30.8 MB of log.
log2=$(mktemp)
"$build/bin/cell-sim" -q -p 21024 >"$log2" 2>&1 & pid2=$!
i=0
while ! python3 -c "import socket; socket.create_connection(('127.0.0.1',21026),0.2)" 2>/dev/null; do
  i=$((i + 1)); [ $i -gt 50 ] && { echo "FAIL: cell-sim -q did not start"; rc=1; break; }; sleep 0.1
done
timeout 60 python3 tests/e2e/cell_hostile_check.py 21024 "$log2" --flood-only || { rc=1; tail -20 "$log2"; }
kill "$pid2" 2>/dev/null; wait "$pid2" 2>/dev/null
rm -f "$log2"
timeout 300 python3 tests/e2e/cell_cli_device_check.py "$build/bin/cell-cli" 21061 || rc=1
exit $rc
