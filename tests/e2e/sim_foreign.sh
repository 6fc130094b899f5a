#!/bin/sh
# c4g-sim ignores (and counts) datagrams that do not come from the configured PC:
# a sender on 127.0.0.2 aims well-formed replies at the simulator's port.
. tests/e2e/helpers/sim_lib.sh
next_port; start_pc $PORT
next_port; SIMPORT=$PORT
# The simulator runs until it is told to stop (-n only bounds a broken run); the sender
# starts once the simulator's socket is bound, so no datagram races its start-up.
"$SIM" --bind 127.0.0.1 -p $((SIMPORT - 1)) --local-port $SIMPORT -n 20000 $STALL_OK --json >"$T/f.json" &
SIMPID=$!; PIDS="$PIDS $SIMPID"
wait_until 30 udp_bound $SIMPORT || fail "c4g-sim never bound 127.0.0.1:$SIMPORT"
python3 - $SIMPORT <<'PY' || fail "foreign sender failed"
import socket, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(('127.0.0.2', 0))
for i in range(20):
    s.sendto(bytes(12 + 36 * 6), ('127.0.0.1', int(sys.argv[1])))
PY
# Loopback delivers within sendto: the 20 datagrams are in the simulator's socket now, and
# a stopped simulator reads what already arrived before its summary.
kill -TERM $SIMPID; wait $SIMPID; rc=$?
expect_eq "foreign sender: exit status" $rc 0
expect_eq "foreign sender: stopped by the signal" "$(jget "$T/f.json" result)" interrupted
expect_eq "foreign datagrams counted" "$(jget "$T/f.json" foreign)" 20
exit 0
