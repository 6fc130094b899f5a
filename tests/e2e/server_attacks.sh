#!/bin/sh
# c4g-server end to end, forged datagrams during a live session: c4g-sim (the controller,
# 127.0.0.1, its own port) runs a mode-9 scenario against c4g-server with a current
# feedforward that asks for more than AzLim (fixtures/server/ff_saturating.txt), while a
# small attacker (server_helpers/attacker.py) sends from 127.0.0.1 on ANOTHER port, or from
# 127.0.0.2:
#   a) a valid initialization packet with AzLim 1e6 and FollowError 0
#   b) a cyclic packet with 504 (end of communication) on every axis
#   c) 508 on every axis with a fake actual position and an old NUM
#   d) a cyclic packet with an undefined mode (and one with mode 3, defined, not available)
#   e) 2000 zero-filled 228-byte datagrams (the controller's cyclic size)
#   f) a 4-byte datagram, before the controller starts and mid-session
#   g) a 504 from 127.0.0.2 while the server pauses in active freezing, so that it is
#      queued for the drain after the pause (server -c any: the session's endpoint check
#      refuses it; and -c 127.0.0.1: the address filter does)
# For each: the controller's session finishes normally (c4g-sim result ok, EXPECTs passed,
# no controller error, the server ends on the controller's own 504), every current the
# server sent keeps SMP+ current + delta within the real AzLim (figure 10.1, the values
# c4g-sim sends; checked on every row of the server's --moni CSV), nothing went back to
# the attacker (its socket and the server's --pcap). Once the session is cyclic the
# server's socket is connect()ed to the controller, so a mid-session attack never reaches
# the server at all: its --json counts nothing (foreign 0) and its log shows the socket
# connected before the attacker's trigger. Before the session locks (f, a 4-byte datagram
# first) the datagram is counted under its own name (malformed_length).
# Robust on a loaded host (the loss timeout and the controller's patience are not under test
# here; server_stall.sh tests them): c4g-sim runs with --max-miss 50 (consecutive missing
# replies before it gives up; the real controller: 10), the server with --lost-timeout-ms
# 5000: a 2-core test host with CPU steal can hold either process up for tens of ms, even a
# second. A server that stops answering (a session ended by a forged 504) still trips the
# simulator. The freezing runs allow 400 (the simulator only stops checking replies once it
# has applied the reply that carried 500; under load that reply can miss its tick).
. tests/e2e/server_helpers/lib.sh "$1"
[ -x "$SIM" ] || { echo "server_attacks: $SIM not built"; exit 1; }
command -v python3 >/dev/null 2>&1 || { echo "server_attacks: python3 needed"; exit 1; }
ATK=tests/e2e/server_helpers/attacker.py
CHK=tests/e2e/server_helpers/attack_check.py
INIT=fixtures/vectors/init-fig10-1.bin   # the controller's real AzLim (c4g-sim: figure 10.1)
FF=fixtures/server/ff_saturating.txt
MODE9='axis.1:.mode.0.->.9'            # server log line: the controller entered mode 9
MISS="--max-miss 50"

# attack NAME PORT SCENARIO KIND "ATTACKER OPTIONS" [server args...]: server, then the
# attacker in the background (it waits for its log pattern), then c4g-sim in the foreground.
attack() {
    name=$1; port=$2; scn=$3; kind=$4; aopts=$5; shift 5
    start_server "$name" "$port" --lost-timeout-ms 5000 --pcap "$T/$name.pcap" "$@"
    # shellcheck disable=SC2086
    python3 "$ATK" "$port" "$kind" $aopts >"$T/$name.atk" 2>"$T/$name.atk.err" &
    APID=$!
    PIDS="$PIDS $APID"
    # shellcheck disable=SC2086
    timeout 50 "$SIM" -p "$port" -S "$scn" --json $MISS >"$T/$name.sim.json" 2>"$T/$name.sim.err"
    SIMRC=$?
    wait "$APID"
    wait_server
}

# in_order FILE RE1 RE2 RE3: the first lines matching RE1, RE2, RE3 come in this order
in_order() {
    awk -v a="$2" -v b="$3" -v c="$4" '
        !na && $0 ~ a { na = NR } !nb && $0 ~ b { nb = NR } !nc && $0 ~ c { nc = NR }
        END { exit !(na && nb && nc && na < nb && nb < nc) }' "$1" ||
        { echo "       not in order in $1: '$2', '$3', '$4'"; return 1; }
}

# kernel_filtered NAME: the attack came after the socket was connected to the controller,
# and nothing of it reached the server (every foreign counter 0)
kernel_filtered() {
    ok "$1: the socket was connected to the controller (kernel filter)" \
        grep -q "socket connected to the controller 127.0.0.1:" "$T/$1.err"
    ok "$1: nothing reached the server (foreign $(jv "$T/$1.json" foreign), malformed $(jv "$T/$1.json" malformed))" \
        eq "$(jv "$T/$1.json" foreign)/$(jv "$T/$1.json" malformed)" 0/0
}

# figures NAME: the counters of a run, for the log
figures() {
    f=""
    for k in foreign foreign_address foreign_init foreign_cyclic foreign_other malformed \
             malformed_length malformed_phase out_of_order init cyclic delta_clamps \
             follow_error_508 drive_off_505; do
        f="$f $k=$(jv "$T/$1.json" $k)"
    done
    echo "       server:$f"
    echo "       c4g-sim: result=$(jv "$T/$1.sim.json" result) missing=$(jv "$T/$1.sim.json" missing)" \
        "attacker: sent=$(kv "$T/$1.atk" sent) replies=$(kv "$T/$1.atk" replies)"
}

# session_ok NAME: the controller's session ended normally, nothing reached the attacker
session_ok() {
    n=$1
    figures "$n"
    ok "$n: c4g-sim exit 0, result ok" eq "$SIMRC/$(jv "$T/$n.sim.json" result)" "0/ok"
    ok "$n: scenario EXPECTs passed, no controller error" \
        eq "$(jv "$T/$n.sim.json" expect_failed)$(grep -c '"errors":\[\]' "$T/$n.sim.json")" 01
    ok "$n: server ended on the controller's 504 (exit 0)" eq "$SRC" 0
    # every cyclic packet the controller sent was served, or dropped unread by the drain
    # after an active freezing (counted as missed: a NUM gap)
    ok "$n: server saw every cyclic packet the controller sent (cyclic + missed)" \
        eq "$(($(jv "$T/$n.json" cyclic) + $(jv "$T/$n.json" missed)))" \
        "$(grep -o '"cyclic":[0-9]*' "$T/$n.sim.json" | head -n 1 | cut -d: -f2)"
    ok "$n: one initialization packet accepted" eq "$(jv "$T/$n.json" init)" 1
    ok "$n: the attacker sent after its trigger" eq "$(kv "$T/$n.atk" waited)" 1
    ok "$n: nothing came back to the attacker's socket" eq "$(kv "$T/$n.atk" replies)" 0
    if [ -s "$T/$n.pcap" ]; then
        python3 "$CHK" pcap "$T/$n.pcap" "$(kv "$T/$n.atk" lport)" >"$T/$n.pc"
        ok "$n: no datagram to the attacker's port in the server's capture" eq "$(kv "$T/$n.pc" to_port)" 0
    fi
}

# currents_ok NAME: every current sent kept SMP+ current + delta within the real AzLim
currents_ok() {
    n=$1
    python3 "$CHK" currents "$T/$n.moni" "$INIT" >"$T/$n.cur" 2>"$T/$n.cur.err"
    ok "$n: the server sent mode-9 currents" ge "$(kv "$T/$n.cur" current_rows)" 100
    ok "$n: every current within the real AzLim (max |total|/AzLim $(kv "$T/$n.cur" max_total_ratio))" \
        eq "$(kv "$T/$n.cur" over)" 0
    ok "$n: the AzLim clamp was exercised" ge "$(jv "$T/$n.json" delta_clamps)" 1
}

m9() {  # m9 NAME PORT KIND "ATTACKER OPTIONS": a mode-9 session under attack
    attack "$1" "$2" fixtures/server/sim_mode9.scn "$3" "$4" \
        --ff "$FF" --duration 1 --moni "$T/$1.moni"
    session_ok "$1"
    currents_ok "$1"
}

echo "a) forged initialization packet (AzLim 1e6, FollowError 0) from 127.0.0.1:other port:"; F0=$FAILS
m9 init 31140 init "--wait $T/init.err cyclic.communication.started"
kernel_filtered init
ok "init: not taken as a mid-session init (malformed_phase 0)" eq "$(jv "$T/init.json" malformed_phase)" 0
[ "$FAILS" -eq "$F0" ] || dump init

echo "b) forged 504 on every axis:"; F0=$FAILS
m9 e504 31141 end504 "--wait $T/e504.err $MODE9"
kernel_filtered e504
[ "$FAILS" -eq "$F0" ] || dump e504

echo "c) forged 508, fake actual position, old NUM:"; F0=$FAILS
m9 f508 31142 fe508 "--wait $T/f508.err $MODE9"
kernel_filtered f508
ok "508: not seen as an out-of-order packet of the session" eq "$(jv "$T/f508.json" out_of_order)" 0
ok "508: no following error, no drive off in the replies" \
    eq "$(jv "$T/f508.json" follow_error_508)/$(jv "$T/f508.json" drive_off_505)" 0/0
[ "$FAILS" -eq "$F0" ] || dump f508

echo "d) undefined mode (7777) and mode 3 (not available):"; F0=$FAILS
m9 bmode 31143 mode "--wait $T/bmode.err $MODE9"
kernel_filtered bmode
ok "mode 7777: no drive off (505)" eq "$(jv "$T/bmode.json" drive_off_505)" 0
m9 mode3 31144 mode3 "--wait $T/mode3.err $MODE9"
kernel_filtered mode3
ok "mode 3: no drive off (505)" eq "$(jv "$T/mode3.json" drive_off_505)" 0
[ "$FAILS" -eq "$F0" ] || { dump bmode; dump mode3; }

echo "e) flood: 2000 zero-filled 228-byte datagrams (50 us apart):"; F0=$FAILS
# no pcap here: 2000 records would overflow the log ring, which is what it is for
attack flood 31145 fixtures/server/sim_mode9.scn zeros "--wait $T/flood.err $MODE9 --count 2000 --gap-us 50" \
    --ff "$FF" --duration 1 --moni "$T/flood.moni"
rm -f "$T/flood.pcap"
session_ok flood
currents_ok flood
ok "flood: all 2000 sent" eq "$(kv "$T/flood.atk" sent)" 2000
kernel_filtered flood
[ "$FAILS" -eq "$F0" ] || dump flood

echo "f) 4-byte datagram (no 732-byte answer to anyone):"; F0=$FAILS
# before the controller: the session is not locked yet, the datagram is no sync packet
start_server tiny0 31146 --lost-timeout-ms 5000 --ff "$FF" --duration 1 --moni "$T/tiny0.moni" --pcap "$T/tiny0.pcap"
python3 "$ATK" 31146 tiny --listen-s 0.3 >"$T/tiny0.atk" 2>"$T/tiny0.atk.err"
# shellcheck disable=SC2086
timeout 50 "$SIM" -p 31146 -S fixtures/server/sim_mode9.scn --json $MISS >"$T/tiny0.sim.json" \
    2>"$T/tiny0.sim.err"
SIMRC=$?
wait_server
session_ok tiny0
ok "tiny before start-up: counted as malformed_length" eq "$(jv "$T/tiny0.json" malformed_length)" 1
ok "tiny before start-up: no sync packet taken from it" eq "$(jv "$T/tiny0.json" sync)" 11
m9 tiny 31147 tiny "--wait $T/tiny.err $MODE9"
kernel_filtered tiny
[ "$FAILS" -eq "$F0" ] || { dump tiny0; dump tiny; }

echo "g) 504 from 127.0.0.2 sent during an active freezing (500 ms), when the drain reads the queue:"; F0=$FAILS
MISS="--max-miss 400"
# the socket is connected to the controller before the pause: the kernel drops the forged
# 504, so neither the drain after the pause nor the session ever sees it (-c any and
# -c 127.0.0.1 alike)
attack drain 31148 fixtures/server/sim_idle.scn end504 \
    "--src 127.0.0.2 --wait $T/drain.err active.freezing:.pausing" -c any --freeze 300,500
session_ok drain
ok "drain (-c any): the server paused once" eq "$(jv "$T/drain.json" active_freezings)" 1
ok "drain (-c any): the pause ended with the controller's newest packet answered" \
    grep -q "active freezing over: .*[^0-9]0 foreign" "$T/drain.err"
kernel_filtered drain
attack draina 31149 fixtures/server/sim_idle.scn end504 \
    "--src 127.0.0.2 --wait $T/draina.err active.freezing:.pausing" --freeze 300,500
session_ok draina
ok "drain (-c 127.0.0.1): the pause ended with the controller's newest packet answered" \
    grep -q "active freezing over: .*[^0-9]0 foreign" "$T/draina.err"
kernel_filtered draina
[ "$FAILS" -eq "$F0" ] || { dump drain; dump draina; }
MISS="--max-miss 50"
finish
