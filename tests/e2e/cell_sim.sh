#!/bin/sh
# cell-sim behaviour per command (real TCP on 127.0.0.1:21001-21003), plus the
# injected servo fault (+00002/+00003) on 21004-21006, and option errors.
set -u
build=$1
bin=$build/bin
log=$(mktemp); log2=$(mktemp)
pids=''
cleanup() { for p in $pids; do kill "$p" 2>/dev/null; done; rm -f "$log" "$log2"; }
trap cleanup EXIT INT TERM

wait_port() { # port: until cell-sim listens on it (30 s bound for a broken run)
  i=0
  until ss -Htln "sport = :$1" | grep -q LISTEN; do
    i=$((i + 1)); [ $i -gt 1500 ] && { echo "FAIL: port $1 never opened"; exit 1; }; sleep 0.02
  done
}

"$bin/cell-sim" -p 21001 -s 20 >"$log" 2>&1 & pids="$pids $!"
wait_port 21001; wait_port 21002; wait_port 21003
timeout 60 python3 tests/e2e/cell_sim_check.py 21001 || { echo "--- cell-sim log"; tail -40 "$log"; exit 1; }

"$bin/cell-sim" -p 21004 --servo-fault robot:1 --servo-fault platform:2 >"$log2" 2>&1 & pids="$pids $!"
wait_port 21004; wait_port 21005
fail=0
out=$(python3 - <<'PY'
import socket
def req(port, line):
    s = socket.create_connection(("127.0.0.1", port), 5); f = s.makefile("rb")
    s.sendall(line + b"\r\n"); r = f.readline(); s.sendall(b"STA\r\n"); r2 = f.readline(); s.close()
    return (r + r2).decode().replace("\r\n", "|")
print(req(21004, b"SRVON") + req(21005, b"SRVON"))
PY
)
want='ER+00002|OKF+000.000+000.000+050.000+00.0000F+00100+00002|ER+00003|OKF+00.0000+00.0000F+00100+00003|'
if [ "$out" = "$want" ]; then echo "PASS: injected servo faults: $out"; else echo "FAIL: servo faults: $out (want $want)"; fail=1; fi

# every connection and error is logged with the peer address
if grep -q 'robot 127.0.0.1:[0-9]* error: ER+00002' "$log2"; then echo "PASS: servo fault logged with the peer"; else echo "FAIL: servo fault not logged"; cat "$log2"; fail=1; fi
if grep -q 'robot 127.0.0.1:[0-9]* connect' "$log"; then echo "PASS: connections logged with the peer"; else echo "FAIL: no connect log"; fail=1; fi

# option errors: exit 2 with a message naming the problem
"$bin/cell-sim" --workspace robot:q:0:1 2>"$log2"; rc=$?
if [ $rc -eq 2 ] && grep -q workspace "$log2"; then echo "PASS: bad --workspace exits 2"; else echo "FAIL: bad --workspace rc=$rc"; fail=1; fi
"$bin/cell-sim" -p 21001 2>"$log2"; rc=$?
if [ $rc -eq 3 ] && grep -q "cannot listen" "$log2"; then echo "PASS: busy port exits 3"; else echo "FAIL: busy port rc=$rc"; fail=1; fi
"$bin/cell-sim" --version | grep -q "^cell-sim [0-9]" && echo "PASS: --version" || { echo "FAIL: --version"; fail=1; }
"$bin/cell-sim" --help | grep -q "Examples:" && echo "PASS: --help has examples" || { echo "FAIL: --help"; fail=1; }
# the INI file (-c): [cell-sim] takes the long options, [DEVICE] port/workspace/home/servo_fault;
# the command line wins over the file (ports 21031-21033)
ini=$(mktemp); bad=$(mktemp)
printf '[cell-sim]\nport_base = 21041\nspeed_factor = 20\n[robot]\nservo_fault = 1\nworkspace = z:-20:80\n' >"$ini"
"$bin/cell-sim" -c "$ini" -p 21031 >"$log2" 2>&1 & pids="$pids $!"
wait_port 21031; wait_port 21033
out=$(python3 - <<'PY'
import socket
s = socket.create_connection(("127.0.0.1", 21031), 5); f = s.makefile("rb")
s.sendall(b"SRVON\r\n"); print(f.readline().decode().strip())
PY
)
[ "$out" = "ER+00002" ] && echo "PASS: config file read ([robot] servo_fault), -p wins over port_base" || { echo "FAIL: config: $out"; fail=1; }
printf '[cell-sim]\nspeed_factor = 10\n[robot]\nprot = 1\n' >"$bad"
"$bin/cell-sim" -c "$bad" 2>"$log2"; rc=$?
if [ $rc -eq 2 ] && grep -q "$(basename "$bad"):4:1: \[robot\] unknown key 'prot'" "$log2"; then echo "PASS: config typo named with line and column"; else echo "FAIL: config typo rc=$rc: $(cat "$log2")"; fail=1; fi
printf '[cell-sim]\nspeed_factor = -1\n' >"$bad"
"$bin/cell-sim" -c "$bad" 2>"$log2"; rc=$?
if [ $rc -eq 2 ] && grep -q ":2:16: \[cell-sim\] speed_factor: bad value '-1'" "$log2"; then echo "PASS: config bad value named"; else echo "FAIL: config bad value rc=$rc: $(cat "$log2")"; fail=1; fi
"$bin/cell-sim" -c /nonexistent.ini 2>"$log2"; rc=$?
if [ $rc -eq 2 ] && grep -q "/nonexistent.ini: .*No such file or directory" "$log2"; then echo "PASS: missing config file: $(cat "$log2")"; else echo "FAIL: missing config rc=$rc: $(cat "$log2")"; fail=1; fi
rm -f "$ini" "$bad"
exit $fail
