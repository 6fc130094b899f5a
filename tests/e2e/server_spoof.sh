#!/bin/sh
# c4g-server end to end, a sender that takes the controller's place: c4g-sim is the
# controller (mode-9 scenario, figure 10.1's AzLim), the server runs a saturating current
# feedforward (fixtures/server/ff_saturating.txt).
#   a) an init packet with AzLim 1e6 A, from the controller's own address and port, between
#      its last sync (NUM 9) and its own init: refused by the ceiling (--az-lim-max, 200 A),
#      named in the log; the controller's init is taken, its session ends normally and every
#      current sent stays within the real AzLim
#   b) the same with AzLim 150 A (under the ceiling): two different init packets in one
#      start-up, both refused ("init conflict"); nothing is answered afterwards, no current
#      is ever sent, the controller gives up (ERR_C4GOPEN_UDP) and the server ends on the
#      loss (exit 3)
#   c) a 504 from the controller's endpoint while axis 1 is in mode 9: the session ends
#      (the PC stops answering: the controller turns its drives off) and the log says
#      "504 out of procedure"
#   d) -c any: a sync from 127.0.0.2 before the controller's first: the session's start-up is
#      contended, both refused and logged; the controller gets no reply
#   e) the controller stalls 3 s (its loss timeout 1 s), then another endpoint's sync
#      (127.0.0.1, another port) starts a new session: served, logged as a new peer; the
#      controller's packets after its stall are not answered (it gives up)
# a) to c) spoof the controller's address and port with a raw socket: they run in a network
# namespace of the test's own (unshare -rn), and are skipped with a message where that is not
# permitted; d) and e) need no privilege.
. tests/e2e/server_helpers/lib.sh "$1"
[ -x "$SIM" ] || { echo "server_spoof: $SIM not built"; exit 1; }
command -v python3 >/dev/null 2>&1 || { echo "server_spoof: python3 needed"; exit 1; }
ATK=tests/e2e/server_helpers/attacker.py
SPOOF=tests/e2e/server_helpers/spoof.py
CHK=tests/e2e/server_helpers/attack_check.py
INIT=fixtures/vectors/init-fig10-1.bin
FF=fixtures/server/ff_saturating.txt
SCN=fixtures/server/sim_mode9.scn

# forged_init AZLIM FILE: figure 10.1's init packet with AzLim AZLIM on its open axes
forged_init() {
    python3 - "$INIT" "$1" "$2" <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], 'rb').read())
for k in range(40):
    if struct.unpack_from('<f', b, 548 + 4 * k)[0] > 0:
        struct.pack_into('<f', b, 548 + 4 * k, float(sys.argv[2]))
open(sys.argv[3], 'wb').write(b)
PY
}

# spoofed NAME PORT TRIGGER [FILE]: server, the spoofer watching for its trigger, c4g-sim
spoofed() {
    name=$1; port=$2; trig=$3; file=${4:-}
    start_server "$name" "$port" --lost-timeout-ms 1000 --ff "$FF" --duration 1 --moni "$T/$name.moni"
    # shellcheck disable=SC2086
    python3 -u "$SPOOF" "$trig" "$port" $file >"$T/$name.spoof" 2>"$T/$name.spoof.err" &
    KPID=$!
    PIDS="$PIDS $KPID"
    wait_until 20 spoof_ready "$name"
    timeout 50 "$SIM" -p "$port" -S "$SCN" --json --max-miss 50 >"$T/$name.sim.json" 2>"$T/$name.sim.err"
    SIMRC=$?
    wait "$KPID"
    wait_server
}
spoof_ready() { grep -q "ready=1" "$T/$1.spoof" 2>/dev/null; }
atk_ready() { grep -q "lport=" "$T/$1.atk" 2>/dev/null; }

currents() {  # currents NAME: the current check of the server's moni CSV
    python3 "$CHK" currents "$T/$1.moni" "$INIT" >"$T/$1.cur" 2>"$T/$1.cur.err"
}

spoof_cases() {
    echo "a) injected init packet, AzLim 1e6 A, from the controller's endpoint:"; F0=$FAILS
    forged_init 1e6 "$T/init1e6.bin"
    spoofed inj1e6 31160 init9 "$T/init1e6.bin"
    currents inj1e6
    ok "inj1e6: the spoofer fired after sync NUM 9" eq "$(kv "$T/inj1e6.spoof" fired)/$(kv "$T/inj1e6.spoof" num)" 1/9
    ok "inj1e6: refused by the ceiling, value and ceiling named" \
        has "$T/inj1e6.err" "refused the initialization packet: AzLim of arm 1 axis 1 is 1e+06 A, above this cell's ceiling 200 A"
    ok "inj1e6: counted as malformed_ceiling" eq "$(jv "$T/inj1e6.json" malformed_ceiling)" 1
    ok "inj1e6: the controller's init taken (init 1), no conflict" \
        eq "$(jv "$T/inj1e6.json" init)/$(jv "$T/inj1e6.json" init_conflicts)" 1/0
    ok "inj1e6: c4g-sim exit 0, result ok" eq "$SIMRC/$(jv "$T/inj1e6.sim.json" result)" 0/ok
    ok "inj1e6: server ended on the controller's 504" eq "$SRC" 0
    ok "inj1e6: the server sent mode-9 currents" ge "$(kv "$T/inj1e6.cur" current_rows)" 100
    ok "inj1e6: every current within the real AzLim (max |total|/AzLim $(kv "$T/inj1e6.cur" max_total_ratio))" \
        eq "$(kv "$T/inj1e6.cur" over)" 0
    [ "$FAILS" -eq "$F0" ] || dump inj1e6

    echo "b) injected init packet, AzLim 150 A (under the ceiling): two init packets, both refused:"; F0=$FAILS
    forged_init 150 "$T/init150.bin"
    spoofed inj150 31161 init9 "$T/init150.bin"
    ok "inj150: the spoofer fired after sync NUM 9" eq "$(kv "$T/inj150.spoof" fired)/$(kv "$T/inj150.spoof" num)" 1/9
    ok "inj150: the conflict logged, the field named" \
        has "$T/inj150.err" "ATTACK? init conflict: a second initialization packet differs from the one accepted (AzLim of arm 1 axis 1: "
    ok "inj150: init_conflicts 1" eq "$(jv "$T/inj150.json" init_conflicts)" 1
    ok "inj150: the session answered nothing after it (cyclic 0, refused >= 1)" \
        eq "$(jv "$T/inj150.json" cyclic)/$([ "$(jv "$T/inj150.json" refused)" -ge 1 ] && echo y)" 0/y
    currents inj150
    ok "inj150: no current ever sent (no moni row)" eq "$(kv "$T/inj150.cur" rows)" 0
    ok "inj150: the controller gave up (exit 1, error raised)" \
        eq "$SIMRC/$(jv "$T/inj150.sim.json" result)" 1/error
    ok "inj150: the server ended on the loss (exit 3)" eq "$SRC" 3
    [ "$FAILS" -eq "$F0" ] || dump inj150

    echo "c) 504 from the controller's endpoint while axis 1 is in mode 9:"; F0=$FAILS
    spoofed e504 31162 mode9
    ok "e504: the spoofer fired during mode 9" eq "$(kv "$T/e504.spoof" fired)" 1
    ok "e504: logged as out of procedure" has "$T/e504.err" "ATTACK? 504 out of procedure: OPEN axis 1 was in mode 9"
    ok "e504: end_unexpected 1" eq "$(jv "$T/e504.json" end_unexpected)" 1
    ok "e504: the session ended, the server stopped (exit 0)" eq "$SRC" 0
    ok "e504: the controller, unanswered, gave up (exit 1, drives off)" \
        eq "$SIMRC/$(jv "$T/e504.sim.json" result)/$(grep -c '"drive_on":true' "$T/e504.sim.json")" 1/error/0
    [ "$FAILS" -eq "$F0" ] || dump e504
}

if [ -z "${C4G_SPOOF_NETNS:-}" ] && unshare -rn true 2>/dev/null; then
    # the spoofing cases in a network namespace of their own (its loopback only)
    C4G_SPOOF_NETNS=1 unshare -rn sh -c 'ip link set lo up 2>/dev/null || ifconfig lo up; exec sh "$0" "$1"' "$0" "$BUILD"
    rc=$?
    [ "$rc" -eq 0 ] || FAILS=$((FAILS + 1))
    CHECKS=$((CHECKS + 1))
elif [ -n "${C4G_SPOOF_NETNS:-}" ]; then
    spoof_cases
    finish
    exit $?
else
    echo "SKIP: a) to c) skipped: cannot create a network namespace (unshare -rn: $(unshare -rn true 2>&1 | head -n 1)); d) and e) run"
fi

echo "d) -c any: a forged sync from 127.0.0.2 before the controller's first:"; F0=$FAILS
start_server cont 31163 -c any --lost-timeout-ms 1000
python3 "$ATK" 31163 sync --src 127.0.0.2 --listen-s 0.3 >"$T/cont.atk" 2>"$T/cont.atk.err"
timeout 50 "$SIM" -p 31163 -S "$SCN" --json >"$T/cont.sim.json" 2>"$T/cont.sim.err"
SIMRC=$?
wait_server
ok "cont: the contention logged with both endpoints" \
    has "$T/cont.err" "ATTACK? start-up contended: a 228-byte start-up packet from 127.0.0.1:"
ok "cont: contended 1" eq "$(jv "$T/cont.json" contended)" 1
ok "cont: no init accepted, no cyclic packet answered" \
    eq "$(jv "$T/cont.json" init)/$(jv "$T/cont.json" cyclic)" 0/0
ok "cont: the controller got no reply and gave up (exit 1)" eq "$SIMRC/$(jv "$T/cont.sim.json" result)" 1/error
[ "$FAILS" -eq "$F0" ] || dump cont

echo "e) a sync from another endpoint after the controller stalled 3 s:"; F0=$FAILS
start_server peer 31164 --persist --lost-timeout-ms 1000
python3 "$ATK" 31164 sync --wait "$T/peer.err" "controller.lost" --listen-s 0.3 >"$T/peer.atk" 2>"$T/peer.atk.err" &
APID=$!
PIDS="$PIDS $APID"
wait_until 30 atk_ready peer
# a 3 s stall: the attacker (a python that can take seconds to start on the loaded host:
# running before the controller starts) has 2 s after the loss to send its sync
timeout 50 "$SIM" -p 31164 -n 2000 --pause 200:1500 --json >"$T/peer.sim.json" 2>"$T/peer.sim.err"
SIMRC=$?
wait "$APID"
kill "$SPID" 2>/dev/null
wait_server
ok "peer: the attacker sent after the loss" eq "$(kv "$T/peer.atk" waited)/$(kv "$T/peer.atk" sent)" 1/1
ok "peer: the new peer logged with both endpoints" \
    has "$T/peer.err" "new peer: the session is now locked to 127.0.0.1:$(kv "$T/peer.atk" lport), not to the lost controller 127.0.0.1:"
ok "peer: new_peers 1" eq "$(jv "$T/peer.json" new_peers)" 1
ok "peer: the controller, unanswered after its stall, gave up (exit 1)" \
    eq "$SIMRC/$(jv "$T/peer.sim.json" result)" 1/error
[ "$FAILS" -eq "$F0" ] || dump peer
finish
