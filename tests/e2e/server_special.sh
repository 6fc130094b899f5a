#!/bin/sh
# c4g-server end to end, special modes: 501 end detected, 505 and 508 from the PC drive
# off, 504 ends both sides cleanly, 506 restarts with a new initialization packet, active
# freezing survives a PC pause longer than 10 periods and passive freezing a controller
# silence longer than the loss timeout. Controller: c4g-sim (and the test stub for a
# following error the server detects itself).
. tests/e2e/server_helpers/lib.sh "$1"
[ -x "$SIM" ] || { echo "server_special: $SIM not built"; exit 1; }
build_stub

echo "501 (driving on) end:"
SIM_ARGS=""
run_sim d501 31020 fixtures/server/sim_idle.scn
ok "501: server detected the end of the drive-on" ge "$(jv "$T/d501.json" drive_on_end)" 1
ok "501: sim ok" eq "$SIMRC" 0
ok "504: server exit 0 after the controller's 504" eq "$SRC" 0
ok "504: server reason names 504" has "$T/d501.json" '"reason":"504'
ok "504: sim scenario ran to its EXIT OPEN (not aborted)" has "$T/d501.sim.json" '"aborted":false'

echo "505 from the PC:"; F0=$FAILS
run_sim d505 31021 fixtures/server/sim_idle.scn --inject 505@400
ok "505: controller raised ERR_C4GOPEN_DRIVEOFF_SERVER" has "$T/d505.sim.json" ERR_C4GOPEN_DRIVEOFF_SERVER
ok "505: robot drives off" has "$T/d505.sim.json" '"drive_on":false'
ok "505: server counted its 505 replies" ge "$(jv "$T/d505.json" drive_off_505)" 1
[ "$FAILS" -eq "$F0" ] || dump d505

echo "508 from the PC (request):"
run_sim d508 31022 fixtures/server/sim_idle.scn --inject 508@400:1
ok "508: controller raised ERR_C4GOPEN_FOLLOW_ERROR" has "$T/d508.sim.json" ERR_C4GOPEN_FOLLOW_ERROR
ok "508: robot drives off" has "$T/d508.sim.json" '"drive_on":false'
ok "508: server counted its 508 replies" ge "$(jv "$T/d508.json" follow_error_508)" 1

echo "508 from the PC (following error detected by the safety filter):"
run_stub fe 31023 --fe 0.05 --fe-push-at 100 --script 0:20,4:400,0:20,504:1 -- --sine 0.1,0.5,1
ok "508: the stub controller saw 508 and drove off" eq "$(kv "$T/fe.stub" err)" ERR_C4GOPEN_FOLLOW_ERROR
ok "508: every other reply byte was right" eq "$(kv "$T/fe.stub" bad)" 0
ok "508: server logged the following error" has "$T/fe.json" '"first":"following error'

echo "506 restart:"
run_sim r506 31024 fixtures/server/sim_restart.scn
ok "506: sim ok (init packet re-sent without sync packets)" eq "$SIMRC" 0
ok "506: server saw the restart" eq "$(jv "$T/r506.json" restarts)" 1
ok "506: server accepted two init packets" eq "$(jv "$T/r506.json" init)" 2
ok "506: server exit 0 at the final 504" eq "$SRC" 0

echo "passive freezing (502 .. 503, 1 s = 500 periods of silence, loss timeout 500 ms):"
run_sim pf 31025 fixtures/server/sim_freeze.scn --lost-timeout-ms 500
ok "passive: sim ok" eq "$SIMRC" 0
ok "passive: server saw 502" eq "$(jv "$T/pf.json" passive_freezings)" 1
ok "passive: no lost controller" eq "$(jv "$T/pf.json" lost)" 0
ok "passive: server exit 0" eq "$SRC" 0

F0=$FAILS; echo "active freezing (500, the PC pauses 150 ms = 75 periods, then EXIT_FROM_OPEN):"
run_sim af 31026 fixtures/server/sim_idle.scn --freeze 300,150
ok "active: sim ok, no ERR_C4GOPEN_UDP" eq "$SIMRC" 0
ok "active: no controller error" has "$T/af.sim.json" '"errors":\[\]'
ok "active: server paused once" eq "$(jv "$T/af.json" active_freezings)" 1
ok "active: server exit 0" eq "$SRC" 0
run_stub afs 31027 --script 0:600,504:1 -- --freeze 200,100
ok "active (stub): controller resumed after EXIT_FROM_OPEN" eq "$(kv "$T/afs.stub" freeze_survived)" 1
ok "active (stub): no bad reply" eq "$(kv "$T/afs.stub" bad)" 0
[ "$FAILS" -eq "$F0" ] || { dump af; dump afs; }
finish
