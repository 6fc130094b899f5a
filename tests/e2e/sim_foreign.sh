#!/bin/sh
# c4g-sim ignores (and counts) datagrams that do not come from the configured PC:
# a sender on 127.0.0.2 aims well-formed replies at the simulator's port.
. tests/e2e/helpers/sim_lib.sh
next_port; start_pc $PORT
next_port; SIMPORT=$PORT
python3 - $SIMPORT <<'PY' &
import socket, sys, time
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(('127.0.0.2', 0))
time.sleep(0.3)
for i in range(20):
    s.sendto(bytes(12 + 36 * 6), ('127.0.0.1', int(sys.argv[1])))
    time.sleep(0.01)
PY
PIDS="$PIDS $!"
run_sim -p $((SIMPORT - 1)) --local-port $SIMPORT -n 400 --json >"$T/f.json"; rc=$?
expect_eq "foreign sender: exit status" $rc 0
expect_eq "foreign datagrams counted" "$(jget "$T/f.json" foreign)" 20
exit 0
