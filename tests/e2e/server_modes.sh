#!/bin/sh
# c4g-server end to end, one test per supported mode (0, 10, 1, 2, 4, 5, 7, 8, 9): real
# processes, real UDP on 127.0.0.1. The controller is c4g-sim running a scenario from
# fixtures/server/; the assertions are on what the simulated robot did (the scenario's
# EXPECT lines, the final positions) and on both summaries.
. tests/e2e/server_helpers/lib.sh "$1"
[ -x "$SIM" ] || { echo "server_modes: $SIM not built"; exit 1; }

# mode_test MODE PORT EXPECTED_POS_AX1 [server args...]; the run's files are $T/mMODE.*, or
# $T/$MT_NAME.* when MT_NAME is set (a second run of one mode)
mode_test() {
    m=$1; port=$2; want=$3; shift 3; F0=$FAILS; n=${MT_NAME:-m$m}; l="mode $m${MT_NAME:+ ($MT_NAME)}"
    echo "$l:"
    SIM_ARGS=""
    run_sim "$n" "$port" "fixtures/server/sim_mode$m.scn" "$@"
    ok "$l: c4g-sim exit 0 (scenario EXPECTs passed, no controller error)" eq "$SIMRC" 0
    ok "$l: no EXPECT failed" eq "$(jv "$T/$n.sim.json" expect_failed)" 0
    ok "$l: no controller error" has "$T/$n.sim.json" '"errors":\[\]'
    ok "$l: robot axis 1 at $want" near "$(simpos "$T/$n.sim.json" 1)" "$want" 0.05
    ok "$l: server ended by 504 (exit 0)" eq "$SRC" 0
    ok "$l: server answered every packet it accepted" eq "$(jv "$T/$n.json" rx)" "$(jv "$T/$n.json" tx)"
    ok "$l: no safety event" eq "$(jv "$T/$n.json" drive_off_505)$(jv "$T/$n.json" follow_error_508)" 00
    [ "$FAILS" -eq "$F0" ] || dump "$n"
}

mode_test 0 31010 0.5
mode_test 10 31011 1
mode_test 4 31012 0.45 --sine 0.25,0.5,0.5
ok "mode 4: server sent EXIT_FROM_OPEN on arm 1" ge "$(grep -o '"exits_sent":\[[0-9]*' "$T/m4.json" | cut -d[ -f2)" 1
mode_test 5 31013 0.125 --sine 0.25,0.5,0.5
mode_test 7 31014 1.1 --offset 0.1,0.5,0.5
mode_test 8 31015 -1 --vel 0.0005,1,1
mode_test 9 31016 0.5 --ff fixtures/server/ff_example.txt --duration 1 --moni "$T/m9.moni"
# moni columns: ... 6 rx_mode ... 16 tx_mode ... 21 tx_d5
ok "mode 9: the server sent a current feedforward (D5) in mode 9" \
    ge "$(awk -F, '$6 == 9 && $21 != 0 { n++ } END { print n + 0 }' "$T/m9.moni")" 100
# the same with the model c4g-ident would write for c4g-sim's arm (INI, checksummed)
MT_NAME=m9ident
mode_test 9 31007 0.5 --ff fixtures/server/ff_ident_example.ini --duration 1 --moni "$T/m9ident.moni"
MT_NAME=
ok "mode 9 (m9ident): the identified model gave the current of 6 axes for the whole second" \
    ge "$(jv "$T/m9ident.json" ff_model_ticks)" 2400
ok "mode 9 (m9ident): D5 sent in mode 9" \
    ge "$(awk -F, '$6 == 9 && $21 != 0 { n++ } END { print n + 0 }' "$T/m9ident.moni")" 100
# axis 4 ([axis 4]: Ja 0.00125664, Fv 0.01256637, Fc 0.1, eps 0.01, no gravity, no range):
# every D5 is the model one tick ahead, a = (D2 - D2 before) / T^2, v = D2 / T + a T
ok "mode 9 (m9ident): axis 4's D5 is the model's current (moni rows in a row, +/- 1e-4 A)" \
    eq "$(awk -F, -v ja=0.00125664 -v fv=0.01256637 -v fc=0.1 -v eps=0.01 -v T=0.002 '
        $3 == 4 && $6 == 9 {
            if (pn != "" && $2 == pn + 1 && $21 != 0) {
                a = ($8 - pd) / (T * T); v = $8 / T + a * T; x = v / eps
                th = (x > 20) ? 1 : ((x < -20) ? -1 : (exp(2 * x) - 1) / (exp(2 * x) + 1))
                d = ja * a + fv * v + fc * th - $21; if (d < 0) d = -d
                n++; if (d > 1e-4) bad++
            }
            pn = $2; pd = $8
        }
        END { print (n >= 20 ? "" : "few rows ") (bad + 0) " off" }' "$T/m9ident.moni")" "0 off"
ok "mode 9 (m9ident): the text report counts the model's ticks" has "$T/m9ident.out" "mode-9 identified model:"
mode_test 1 31017 0 --hold --duration 1 --gains 30,200,300 --moni "$T/m1.moni"
ok "mode 1: the PC closed the loops (D1 target and D5 current in every mode-1 reply)" \
    eq "$(awk -F, '$6 == 1 && ($17 == "" || $21 == 0) { n++ } END { print n + 0 }' "$T/m1.moni")" 0
mode_test 2 31018 0.5 --gains 30,200,300

echo "per-arm behaviours (arm 1 mode 4 on axes 1-2, arm 2 mode 7, at the same time):"; F0=$FAILS
SIM_ARGS="--axes 6,4"
run_sim arms 31019 fixtures/server/sim_two_arms.scn --arm 1 --axes 1,2 --sine 0.25,0.5,0.5 \
    --arm 2 --offset 0.1,0.3,0.2
ok "two arms: sim scenario passed" eq "$SIMRC" 0
ok "two arms: arm 1 axis 1 moved +0.25" near "$(simpos "$T/arms.sim.json" 1)" 0.25 0.02
ok "two arms: arm 1 axis 3 (not selected) stayed" near "$(simpos "$T/arms.sim.json" 3)" 0 0.02
# mode 7 integrates the additions of the replies that arrived in time: with every reply in
# time the offset is exact; a host that stalled the server loses the additions of the late
# replies (the controller's rule), never adds any: the arm then ends between 0 and +0.1
late=$(( $(jv "$T/arms.sim.json" missing) + $(jv "$T/arms.sim.json" stale) + $(jv "$T/arms.sim.json" unjudged) ))
for ix in 7 10; do
    if [ "$late" -eq 0 ]; then
        ok "two arms: arm 2 OPEN index $ix offset +0.1" near "$(simpos "$T/arms.sim.json" $ix)" 0.1 0.02
    else
        echo "       ($late replies late on a loaded host: arm 2 short of +0.1 by the lost additions)"
        ok "two arms: arm 2 OPEN index $ix offset in (0, +0.1]" \
            awk -v p="$(simpos "$T/arms.sim.json" $ix)" 'BEGIN { exit !(p > 0 && p <= 0.1 + 0.0005) }'
    fi
done
ok "two arms: EXIT_FROM_OPEN sent on both arms" has "$T/arms.json" '"exits_sent":\[[1-9][0-9]*,[1-9]'
ok "two arms: server ended by 504" eq "$SRC" 0
[ "$FAILS" -eq "$F0" ] || dump arms
SIM_ARGS=""

echo "trajectory file and 20 axes (controller stub, every reply checked byte by byte):"; F0=$FAILS
build_stub
run_stub traj 31009 --script 0:20,4:exit,0:20,504:1 -- --traj fixtures/server/traj_example.csv
ok "traj: mode 4 ended with EXIT_FROM_OPEN" eq "$(kv "$T/traj.stub" ph1_exit)" 1
ok "traj: axis 1 followed the file (peak offset 0.2 turns)" near "$(kv "$T/traj.stub" ph1_maxdev)" 0.2 0.005
ok "traj: axis 1 back at the start (last row 0)" near "$(kv "$T/traj.stub" ph1_end)" 0 0.001
ok "traj: every reply right" eq "$(kv "$T/traj.stub" bad)" 0
run_stub ax20 31008 --arms 10,10 --period-ms 1 --script 0:20,4:exit,0:20,504:1 -- --sine 0.1,1,1
ok "20 axes: mode 4 ended with EXIT_FROM_OPEN" eq "$(kv "$T/ax20.stub" ph1_exit)" 1
ok "20 axes: every reply right (732-byte cyclic replies)" eq "$(kv "$T/ax20.stub" bad)" 0
ok "20 axes: server saw 20 axes" eq "$(jv "$T/ax20.json" axes)" 20
ok "20 axes: EXIT_FROM_OPEN on arm 2 too" has "$T/ax20.json" '"exits_sent":\[[1-9][0-9]*,[1-9]'
[ "$FAILS" -eq "$F0" ] || { dump traj; dump ax20; }
finish
