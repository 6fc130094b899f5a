#!/bin/sh
# cell-sim's platform on a CANopen bus (real TCP on 127.0.0.1:23701-23703, shell 23712;
# 23751-23753 and 23762 for the shell that waits without blocking):
# DS402 and CSP through the master, a node removed mid-move and its recovery, the Robox
# diagnostic commands; then the bus pcap decoded by real tshark (its CANopen dissector)
# against the boot order of the Robox CANopen master documentation; the candump log;
# SocketCAN on vcan where the kernel has it.
set -u
build=$1
bin=$build/bin
dir=$(mktemp -d)
pids=''
cleanup() { for p in $pids; do kill "$p" 2>/dev/null; done; rm -rf "$dir"; }
trap cleanup EXIT INT TERM
. tests/e2e/helpers/wait.sh
listening() { ss -Htln "sport = :$1" | grep -q LISTEN; }
fail=0

"$bin/cell-sim" -p 23701 -s 20 --canopen fixtures/canopen/platform.ini --canopen-port 23712 \
  --can-pcap "$dir/bus.pcap" --can-log "$dir/bus.log" >"$dir/sim.log" 2>&1 & pids="$pids $!"
wait_until 30 listening 23702 && wait_until 30 listening 23712 || { echo "FAIL: cell-sim did not start"; cat "$dir/sim.log"; exit 1; }
timeout 120 python3 tests/e2e/canopen_check.py 23702 23712 || { fail=1; echo "--- cell-sim log"; tail -30 "$dir/sim.log"; }
check_state() { python3 - "$1" <<'PY'
import socket, sys
s = socket.create_connection(("127.0.0.1", int(sys.argv[1])), 5); f = s.makefile("rb")
for c in ("CO_WSDIAGNO 1", "CO_WSDIAGNO 2", "CO_STATE_MAC 1", "CO_STATE_MAC 2"):
    s.sendall(c.encode() + b"\n"); print(f.readline().decode().strip())
PY
}
[ $fail -eq 0 ] || check_state 23712
# the same commands from cell-cli (the shell is on the platform port + 10)
cli() { "$bin/cell-cli" -p 23701 canopen "$@"; }
out=$(cli CO_RNMT 1); [ "$out" = "node 1: NMT operational (0x05), running" ] &&
  echo "PASS: cell-cli canopen CO_RNMT: $out" || { echo "FAIL: cell-cli canopen CO_RNMT: $out"; fail=1; }
out=$(cli CO_ROBJ 2 0x1000 0); [ "$out" = "node 2 0x1000:00 = 0x00020192 (131474)" ] &&
  echo "PASS: cell-cli canopen CO_ROBJ" || { echo "FAIL: cell-cli canopen CO_ROBJ: $out"; fail=1; }
out=$(cli CO_STATE_MAC 2); case $out in "node 2: DS402 "*) echo "PASS: cell-cli canopen CO_STATE_MAC: $out" ;; *) echo "FAIL: CO_STATE_MAC: $out"; fail=1 ;; esac
cli CO_ROBJ 2 0x2000 0 >"$dir/o.txt" 2>"$dir/e.txt"; rc=$?
[ $rc -eq 1 ] && [ ! -s "$dir/o.txt" ] && grep -q "0x06020000 (object does not exist" "$dir/e.txt" &&
  echo "PASS: cell-cli canopen: an SDO abort exits 1 with the abort named on stderr" || { echo "FAIL: abort rc=$rc $(cat "$dir/e.txt")"; fail=1; }
cli >/dev/null 2>"$dir/e.txt"; rc=$?
[ $rc -eq 2 ] && grep -q "want a command" "$dir/e.txt" && echo "PASS: cell-cli canopen without a command exits 2" || { echo "FAIL: usage rc=$rc"; fail=1; }
"$bin/cell-cli" -p 23801 canopen CO_RNMT 1 2>"$dir/e.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "cannot connect to the CANopen shell at 127.0.0.1:23812" "$dir/e.txt" &&
  echo "PASS: cell-cli canopen without a shell exits 1" || { echo "FAIL: no shell rc=$rc"; fail=1; }
kill $pids 2>/dev/null; wait 2>/dev/null; pids=''
# the shell waits without blocking: robot round trips while SDO reads to a lost node are
# pending (600 ms each with this timeout), an idle shell connection, SDOs of two connections
sed -e 's/^sdo_timeout_ms = .*/sdo_timeout_ms = 200/' -e 's/^sdo_retries = .*/sdo_retries = 2/' \
  fixtures/canopen/platform.ini >"$dir/slow-sdo.ini"
"$bin/cell-sim" -p 23751 --canopen "$dir/slow-sdo.ini" --canopen-port 23762 >"$dir/sim4.log" 2>&1 & pids="$pids $!"
wait_until 30 listening 23751 && wait_until 30 listening 23762 || { echo "FAIL: cell-sim did not start"; cat "$dir/sim4.log"; exit 1; }
timeout 120 python3 tests/e2e/canopen_async_check.py 23751 23762 || { fail=1; echo "--- cell-sim log"; tail -20 "$dir/sim4.log"; }
kill $pids 2>/dev/null; wait 2>/dev/null; pids=''
# pick-and-place and the other devices still run with the platform on the bus
"$bin/cell-sim" -p 23741 -s 20 --canopen fixtures/canopen/platform.ini >"$dir/sim3.log" 2>&1 & pids="$pids $!"
wait_until 30 listening 23742 || { echo "FAIL: cell-sim did not start"; exit 1; }
timeout 60 python3 tests/e2e/cell_sim_check.py 23741 >"$dir/cell.txt" 2>&1 && echo "PASS: cell_sim_check (pick-and-place) with the platform on CANopen" || {
  grep FAIL "$dir/cell.txt"; echo "FAIL: cell_sim_check with the platform on CANopen"; fail=1; }
kill $pids 2>/dev/null; wait 2>/dev/null; pids=''

# the candump log: can-utils' format, the boot's first frames
head -3 "$dir/bus.log" | sed 's/^([0-9.]*) //' > "$dir/head.txt"
printf 'vcan0 701#00\nvcan0 702#00\nvcan0 000#8000\n' | diff - "$dir/head.txt" >/dev/null &&
  echo "PASS: candump log starts with the boot-up messages and NMT pre-operational" ||
  { echo "FAIL: candump log head:"; cat "$dir/head.txt"; fail=1; }
grep -Eq '^\([0-9]+\.[0-9]{6}\) vcan0 [0-9A-F]{3}#([0-9A-F]{2})*$' "$dir/bus.log" &&
  ! grep -Evq '^\([0-9]+\.[0-9]{6}\) vcan0 [0-9A-F]{3}#(([0-9A-F]{2})*|R)$' "$dir/bus.log" &&
  echo "PASS: every candump line is (sec.usec) iface ID#DATA" || { echo "FAIL: candump format"; fail=1; }

# the oracle: tshark's CANopen dissector on the pcap (DLT_CAN_SOCKETCAN)
tshark -r "$dir/bus.pcap" -d can.subdissector,canopen -T fields -E separator='|' \
  -e frame.number -e canopen.function_code -e canopen.node_id -e canopen.nmt_ctrl.cd \
  -e canopen.nmt_ctrl.node_id -e canopen.sdo.main_idx -e canopen.sdo.sub_idx \
  -e canopen.sdo.data.bytes -e canopen.nmt_guard.state -e canopen.em.err_code -e _ws.col.Info \
  >"$dir/tshark.txt" 2>"$dir/tshark.err" || { echo "FAIL: tshark"; cat "$dir/tshark.err"; fail=1; }
python3 tests/e2e/canopen_tshark_check.py "$dir/tshark.txt" || fail=1

# SocketCAN: a real vcan interface where the kernel has one
if ip link add dev c4gvcan0 type vcan 2>"$dir/vcan.err" && ip link set up c4gvcan0 2>>"$dir/vcan.err"; then
  "$bin/cell-sim" -p 23721 -s 20 --canopen fixtures/canopen/platform.ini --canopen-port 23732 \
    --can-if c4gvcan0 >"$dir/sim2.log" 2>&1 & pids="$pids $!"
  wait_until 30 listening 23732
  out=$(python3 - <<'PY'
import socket, time
s = socket.create_connection(("127.0.0.1", 23732), 5); f = s.makefile("rb")
time.sleep(0.5)
s.sendall(b"CO_RNMT 2\n"); print(f.readline().decode().strip())
PY
)
  ip link del c4gvcan0 2>/dev/null
  [ "$out" = "node 2: NMT operational (0x05), running" ] && echo "PASS: SocketCAN (vcan): network booted over a real CAN socket" ||
    { echo "FAIL: SocketCAN: $out"; tail "$dir/sim2.log"; fail=1; }
else
  echo "SKIP: SocketCAN test skipped: cannot create a vcan interface ($(head -1 "$dir/vcan.err")); the tests above ran on the in-process virtual bus"
fi
exit $fail
