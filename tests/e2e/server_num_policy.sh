#!/bin/sh
# c4g-server end to end: both NUM policies (field NUM + 1, manual echo) against a
# controller that enforces each, the start-up handshake byte by byte, and the NUM wrap.
. tests/e2e/server_helpers/lib.sh "$1"
[ -x "$SIM" ] || { echo "server_num_policy: $SIM not built"; exit 1; }
build_stub

echo "c4g-sim enforcing plus-one, server default:"
SIM_ARGS="--num-policy plus-one"
run_sim p1 31040 fixtures/server/sim_mode0.scn
ok "sim ok" eq "$SIMRC" 0
ok "no wrong NUM" eq "$(jv "$T/p1.sim.json" wrong_num)" 0
ok "server says plus1" has "$T/p1.json" '"num_policy":"plus1"'

echo "c4g-sim enforcing echo, server --num-policy echo:"
SIM_ARGS="--num-policy echo"
run_sim ec 31041 fixtures/server/sim_mode0.scn --num-policy echo
ok "sim ok" eq "$SIMRC" 0
ok "no wrong NUM" eq "$(jv "$T/ec.sim.json" wrong_num)" 0

echo "mismatch (controller enforces echo, server answers NUM + 1):"
# a busy host that holds the server up for 10 periods at the start ends the session before
# a single wrong NUM came: such a run is made again (a server answering the echo NUM would
# show no wrong NUM in any run, and fail)
no_wrong_num() { [ "$(jv "$T/$1.sim.json" wrong_num)" = 0 ]; }
SIM_ARGS="--num-policy echo --max-miss 10"
again_while no_wrong_num run_sim mm 31042 fixtures/server/sim_mode0.scn
ok "controller refused the replies (error raised)" eq "$SIMRC" 1
ok "wrong NUM counted" ge "$(jv "$T/mm.sim.json" wrong_num)" 1
SIM_ARGS=""

echo "handshake and cyclic replies byte by byte (stub), both policies, NUM wrap:"
# what matters here is every reply's bytes, not its timing: the stub waits up to 1 s for each,
# so a server stopped a while by a busy host still answers every packet
run_stub sp 31043 --num-start 32700 --reply-us 1000000 --script 0:200,10:100,504:1 --
ok "plus1: every reply right (732-byte sync echo, 1200-byte init echo, NUM+1, 0x7FFF->1)" eq "$(kv "$T/sp.stub" bad)" 0
ok "plus1: every packet answered" eq "$(kv "$T/sp.stub" missed)" 0
ok "plus1: server saw the 9+2 sync packets and the init" eq "$(jv "$T/sp.json" sync)/$(jv "$T/sp.json" init)" 11/1
run_stub se 31044 --policy echo --num-start 32700 --reply-us 1000000 --script 0:200,10:100,504:1 -- --num-policy echo
ok "echo: every reply right" eq "$(kv "$T/se.stub" bad)" 0
ok "echo: every packet answered" eq "$(kv "$T/se.stub" missed)" 0
run_stub sx 31045 --policy echo --script 0:50,504:1 --
ok "stub enforcing echo rejects the default server" ge "$(kv "$T/sx.stub" bad)" 1
finish
