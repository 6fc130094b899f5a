#!/bin/sh
# c4g-server end to end, faults: one dropped reply is counted and survived; 10 consecutive
# raise ERR_C4GOPEN_UDP; datagrams from a foreign source address (a second socket bound to
# 127.0.0.2) never reach the server once its socket is connected to the controller; truncated or corrupted packets are counted and crash neither side.
. tests/e2e/server_helpers/lib.sh "$1"
[ -x "$SIM" ] || { echo "server_faults: $SIM not built"; exit 1; }
build_stub
SIM_ARGS=""

echo "one dropped reply:"; F0=$FAILS
# (not run again when held up: its counts allow for it, and in 2 s a late reply is common)
run_sim drop1 31030 fixtures/server/sim_idle.scn --skip-replies 300
# missing, or unjudged if the simulator overran that deadline itself
ok "controller counted the missing reply" ge "$(( $(jv "$T/drop1.sim.json" missing) + $(jv "$T/drop1.sim.json" unjudged) ))" 1
ok "controller raised no error" has "$T/drop1.sim.json" '"errors":\[\]'
ok "controller finished ok" eq "$SIMRC" 0
ok "server counted the skipped reply" eq "$(jv "$T/drop1.json" skipped)" 1
ok "server ended by 504" eq "$SRC" 0
[ "$FAILS" -eq "$F0" ] || dump drop1

echo "10 consecutive dropped replies:"; F0=$FAILS
# early (cyclic packet 20), so a host stall of the server before it cannot raise the error first
SIM_ARGS="--max-miss 10"
again_while sim_stalled run_sim drop10 31031 fixtures/server/sim_idle.scn --skip-replies 20,10
SIM_ARGS=""
ok "controller raised ERR_C4GOPEN_UDP" has "$T/drop10.sim.json" ERR_C4GOPEN_UDP
ok "controller exit 1 (table 17.1 error)" eq "$SIMRC" 1
ok "server skipped exactly 10" eq "$(jv "$T/drop10.json" skipped)" 10
again_while stub_stalled run_stub drop10s 31032 --script 0:400,504:1 -- --skip-replies 100,10 --lost-timeout-ms 2000
ok "stub controller raised ERR_C4GOPEN_UDP" eq "$(kv "$T/drop10s.stub" err)" ERR_C4GOPEN_UDP
ok "stub saw 10 in a row" eq "$(kv "$T/drop10s.stub" max_consec_missed)" 10
again_while stub_stalled run_stub drop9s 31033 --script 0:400,504:1 -- --skip-replies 100,9 --lost-timeout-ms 2000
ok "9 in a row survive" eq "$(kv "$T/drop9s.stub" err)" NONE
[ "$FAILS" -eq "$F0" ] || { dump drop10; dump drop10s; dump drop9s; }

echo "foreign source (127.0.0.2):"; F0=$FAILS
again_while stub_stalled run_stub foreign 31034 --foreign 127.0.0.2,5 --script 0:300,504:1 --
# sent during the cyclic phase: the server's socket is connected to the controller by then,
# so the kernel drops them and the server never sees one
ok "the socket was connected to the controller" has "$T/foreign.err" "socket connected to the controller 127.0.0.1:"
ok "the foreign datagrams never reached the server (kernel filter)" eq "$(jv "$T/foreign.json" foreign)" 0
ok "nothing was sent to the foreign source" eq "$(kv "$T/foreign.stub" foreign_replies)" 0
ok "the controller's replies were all right" eq "$(kv "$T/foreign.stub" bad)" 0
ok "server ended by 504" eq "$SRC" 0
[ "$FAILS" -eq "$F0" ] || dump foreign

echo "truncated and corrupted datagrams:"; F0=$FAILS
again_while stub_stalled run_stub garbage 31035 --garbage-every 3 --script 0:20,4:exit,0:300,504:1 -- --sine 0.1,1,1
g=$(kv "$T/garbage.stub" garbage)
ok "stub sent garbage" ge "$g" 100
ok "server counted every bad datagram as malformed" eq "$(jv "$T/garbage.json" malformed)" "$g"
ok "server never answered one (all replies right)" eq "$(kv "$T/garbage.stub" bad)" 0
ok "mode 4 still completed" eq "$(kv "$T/garbage.stub" ph1_exit)" 1
ok "server alive to the 504 (exit 0)" eq "$SRC" 0
[ "$FAILS" -eq "$F0" ] || dump garbage
SIM_ARGS="--corrupt 0.02 --truncate 0.02 --duplicate 0.01 --reorder 0.01 --seed 3"
run_sim simfault 31036 fixtures/server/sim_idle.scn
ok "c4g-sim faults: server counted malformed datagrams" ge "$(jv "$T/simfault.json" malformed)" 1
ok "c4g-sim faults: server exited cleanly (0 = 504, 3 = controller gone)" has "$T/simfault.json" '"exit_code":[03]'
ok "c4g-sim faults: simulator ran to the end" has "$T/simfault.sim.json" '"ticks":'
[ "$FAILS" -eq "$F0" ] || dump simfault
finish
