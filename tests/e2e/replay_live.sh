#!/bin/sh
# c4g-replay live end to end: real processes, real UDP on 127.0.0.1.
#  1. a capture of c4g-sim + c4g-server (--pcap, mode 4 scenario, --sine 0.25,0.5,0.5) played
#     to a fresh c4g-server with the same options: every reply in time and equal, field by
#     field and bit for bit, to the recorded one (the server computes its replies from the
#     ticks and the controller's packets, not from the wall clock); then twice in a row to a
#     c4g-server --persist (--loop 2), and at top speed (twice).
#  2. the same capture to a server with another amplitude: the replies differ, the first
#     divergence is D1 of an axis in mode 4.
#  3. a capture without mode changes played to the deliberately broken reference PC
#     (tests/e2e/helpers/ref_pc.c: wrong NUM, no reply, one reply dropped): live's counts of
#     lost replies and wrong NUMs are c4g-sim's for the same faults (both judge with
#     lib/host/c4gh_ctrlside), and what the fault must give; then a shorter capture
#     played to a reference PC that answers 5 chosen packets late (--late-us): live counts
#     as many late replies as c4g-sim.
#  4. refusals: a capture without its start-up (exit 2, rerun suggested), a bad --to.
# Timing is not asserted (but for the late replies of 3, which are retried when the host
# interfered, see there): the e2e runner loads the host on purpose. A loaded host can make a
# reply miss its deadline, so "no reply lost" is checked as missing + unjudged - stale: the
# replies that never came (a late one arrives, and counts as stale).
. tests/e2e/server_helpers/lib.sh "$1"
RP=$BUILD/bin/c4g-replay
[ -x "$SIM" ] && [ -x "$RP" ] || { echo "replay_live: $SIM or $RP not built"; exit 1; }
command -v python3 >/dev/null 2>&1 || { echo "replay_live: python3 needed"; exit 1; }

# a port range of this process (high ports, loopback only), each port checked free
PORT=$((33000 + ($$ % 400) * 10))
next_port() {
    PORT=$((PORT + 1))
    while udp_bound "$PORT"; do PORT=$((PORT + 1)); done
}
# jget FILE KEY.KEY...: a value of a JSON summary (c4g-replay live, c4g-sim), flattened once
jget() {
    [ -f "$1.kv" ] || python3 -c 'import json, sys
def walk(p, v):
    if isinstance(v, dict):
        for k, x in v.items():
            walk(p + [k], x)
    elif not isinstance(v, list):
        print(".".join(p) + "=" + (str(v).lower() if isinstance(v, bool) else str(v)))
walk([], json.load(open(sys.argv[1])))' "$1" >"$1.kv" 2>/dev/null
    sed -n "s/^$2=//p" "$1.kv" | head -n 1
}
# lost FILE [N504]: replies that never came. A late one counts as stale, or as unexpected when
# it lands while a 504 (whose own reply is not checked: unexpected too, N504 of them) waits.
lost() {
    echo $(( $(jget "$1" replies.missing) + $(jget "$1" replies.unjudged) - $(jget "$1" replies.stale) \
        - $(jget "$1" replies.unexpected) + ${2:-0} ))
}

# Against c4g-server the replay holds it to plus-one: under "either" (the default) a reply to
# the first synchronization packet that a cold server sends a period late would pass as the
# echo reply to the second one (the controller's rule, see docs/c4g-sim.md) and show up as a
# NUM divergence. The reference PC runs below keep the default, as c4g-sim does.
PLUS="--num-policy plus-one"
# live NAME PORT [live args...]: c4g-replay live of $CAP to 127.0.0.1:PORT, JSON in $T/NAME.live.json
live() {
    name=$1; port=$2; shift 2
    timeout 60 "$RP" live "$CAP" --to "127.0.0.1:$port" --json "$@" >"$T/$name.live.json" 2>"$T/$name.live.err"
    LRC=$?
}

echo "1. a capture played to a server with the same options:"; F0=$FAILS
next_port
SIM_ARGS=""
run_sim cap "$PORT" fixtures/server/sim_mode4.scn --sine 0.25,0.5,0.5 --pcap "$T/m4.pcap"
ok "capture: c4g-sim scenario passed" eq "$SIMRC" 0
CAP=$T/m4.pcap
SENT=$(jget "$T/cap.sim.json" packets.sent)
# A replay the host stalled (its own overruns: packets sent late, two at once) can leave a
# reply unaccounted for; such a run is made again. Lost replies without an overrun of the
# replay fail at once.
same_run() {  # same_run NAME: a fresh server with the capture's options, the capture played to it
    next_port; start_server "$1" "$PORT" --sine 0.25,0.5,0.5
    live "$1" "$PORT" $PLUS
    wait_server
    rm -f "$T/$1.live.json.kv"
}
replay_stalled() { [ "$(lost "$T/$1.live.json" 1)" -ne 0 ] && [ "$(jget "$T/$1.live.json" timing.overruns)" -gt 0 ]; }
again_while replay_stalled same_run same
J=$T/same.live.json
ok "same: every controller packet of the capture sent" eq "$(jget "$J" packets.sent)" "$SENT"
ok "same: 0 wrong NUM" eq "$(jget "$J" replies.wrong_num)" 0
ok "same: no reply lost" eq "$(lost "$J" 1)" 0
ok "same: 0 malformed, 0 duplicates" eq "$(jget "$J" replies.malformed)$(jget "$J" replies.duplicates)" 00
ok "same: every reply judged ok compared with the recorded one" eq "$(jget "$J" divergences.compared)" "$(jget "$J" replies.ok)"
ok "same: 0 divergences" eq "$(jget "$J" divergences.differing)" 0
ok "same: no first divergence" eq "$(jget "$J" divergences.first)" None
ok "same: kernel timestamps" eq "$(jget "$J" timestamps)" kernel
ok "same: send timing reported" ge "$(jget "$J" timing.send_error_us.max)" 0
ok "same: server ended by the replayed 504" eq "$SRC" 0
# exit 0 exactly when nothing but clean replies: a loaded host may add late ones
if [ "$(( $(jget "$J" replies.late) + $(jget "$J" replies.missing) + $(jget "$J" replies.unjudged) ))" -eq 0 ]; then
    ok "same: exit 0" eq "$LRC" 0
else
    echo "       (late or missing replies on a loaded host: exit 1 expected)"
    ok "same: exit 1 with timing findings only" eq "$LRC" 1
fi
[ "$FAILS" -eq "$F0" ] || { dump same; dump cap; }

# A reply that a busy host delays past the end of a pass is counted in neither pass: the
# accounting of --loop then misses by one. Such a run (a reply lost, and late ones beside
# it) is made again; a reply really lost would be lost again, without late ones.
passes_run() {  # passes_run NAME [live args...]: the capture twice to a c4g-server --persist
    n=$1; shift
    next_port; start_server "$n" "$PORT" --sine 0.25,0.5,0.5 --persist
    live "$n" "$PORT" --loop 2 "$@" $PLUS
    kill "$SPID" 2>/dev/null; wait "$SPID" 2>/dev/null
    rm -f "$T/$n.live.json.kv"
}
seam_late() { [ "$(lost "$T/$1.live.json" 2)" -ne 0 ] && [ "$(jget "$T/$1.live.json" replies.late)" -gt 0 ]; }
F0=$FAILS
again_while seam_late passes_run loop
J=$T/loop.live.json
ok "--loop 2 (c4g-server --persist): both passes done" eq "$(jget "$J" passes_done)" 2
ok "--loop 2: twice the packets" eq "$(jget "$J" packets.sent)" $((2 * SENT))
ok "--loop 2: two start-ups (init packets)" eq "$(jget "$J" packets.init)" 2
ok "--loop 2: 0 wrong NUM, no reply lost" eq "$(jget "$J" replies.wrong_num):$(lost "$J" 2)" 0:0
ok "--loop 2: 0 divergences" eq "$(jget "$J" divergences.differing)" 0
ok "--loop 2: the server served two sessions to their 504" eq "$(grep -c '504: end of communication' "$T/loop.err")" 2
[ "$FAILS" -eq "$F0" ] || dump loop

F0=$FAILS
again_while seam_late passes_run top --topspeed
J=$T/top.live.json
ok "--topspeed --loop 2: every packet sent" eq "$(jget "$J" packets.sent)" $((2 * SENT))
ok "--topspeed: faster than recorded" awk -v a="$(jget "$J" elapsed_s)" -v b="$(jget "$J" recorded_s)" 'BEGIN { exit !(a < b) }'
# the reply to the first pass's 504 comes after it: counted there, not as a wrong NUM of the next
ok "--topspeed: 0 wrong NUM, no reply lost, 0 divergences" \
    eq "$(jget "$J" replies.wrong_num):$(lost "$J" 2):$(jget "$J" divergences.differing)" 0:0:0
ok "--topspeed: no timing figures" eq "$(jget "$J" timing)" None
[ "$FAILS" -eq "$F0" ] || dump top

echo "2. the same capture to a server with another amplitude:"; F0=$FAILS
next_port; start_server other "$PORT" --sine 0.2,0.5,0.5
live other "$PORT" $PLUS
wait_server
J=$T/other.live.json
ok "other: exit 1 (divergences)" eq "$LRC" 1
ok "other: divergent replies" ge "$(jget "$J" divergences.differing)" 1
ok "other: D1 differs" ge "$(jget "$J" divergences.fields.D1)" 1
ok "other: the first divergence is D1" eq "$(jget "$J" divergences.first.field)" D1
ok "other: ... of an axis in mode 4" eq "$(jget "$J" divergences.first.mode)" 4
ok "other: ... with its tick and NUM" ge "$(jget "$J" divergences.first.num)" 13
ok "other: NUM, INFPAR, modes equal" eq "$(jget "$J" divergences.fields.NUM)$(jget "$J" divergences.fields.INFPAR)$(jget "$J" divergences.fields.mode)" 000
next_port; start_server othertxt "$PORT" --sine 0.2,0.5,0.5
timeout 60 "$RP" live "$CAP" --to "127.0.0.1:$PORT" $PLUS >"$T/othertxt.live.out" 2>&1
wait_server
ok "other, text: the first divergence in words" has "$T/othertxt.live.out" "first: pass 1, cyclic packet NUM [0-9]* (tick [0-9]*), axis [0-9]* in mode 4: D1 recorded"
ok "other, text: the verdict" has "$T/othertxt.live.out" "result: FINDINGS.*divergent replies"
[ "$FAILS" -eq "$F0" ] || dump other

echo "3. faults of the reference PC, live against c4g-sim:"; F0=$FAILS
REF=$T/ref_pc
cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Wall -Wextra -Iinclude -o "$REF" \
    tests/e2e/helpers/ref_pc.c "$BUILD/lib/libc4gopen.a" -lm || { echo "replay_live: cannot build ref_pc"; exit 1; }
pc_up() { grep -qs '^ref_pc: listening' "$T/ref_$1.log" || ! kill -0 "$PCPID" 2>/dev/null; }
ref_pc() {  # ref_pc PORT [options]: in the background until killed
    p=$1; shift
    "$REF" -p "$p" --idle-ms 5000 --max-s 50 "$@" 2>"$T/ref_$p.log" &
    PCPID=$!
    PIDS="$PIDS $PCPID"
    wait_until 30 pc_up "$p"
}
ref_done() { kill "$PCPID" 2>/dev/null; wait "$PCPID" 2>/dev/null; }
# refstat LOG KEY: a number of ref_pc's closing line (slow, held, worst, cyclic...)
refstat() { sed -n "s/^ref_pc: rx .* $2 \([0-9.]*\).*/\1/p" "$1"; }
# the capture: 300 cyclic ticks in mode 0 (what the controller sends does not depend on the
# replies, so c4g-sim sends the same packets to a broken PC)
next_port; start_server fcap "$PORT"
timeout 50 "$SIM" -p "$PORT" -n 300 --max-miss 500 --pcap "$T/f.pcap" --json >"$T/fcap.sim.json" 2>"$T/fcap.sim.err"
kill "$SPID" 2>/dev/null; wait "$SPID" 2>/dev/null
CAP=$T/f.pcap
FSENT=$(jget "$T/fcap.sim.json" packets.sent)
# What each fault must give on both sides: lost replies and wrong NUMs; and on live's side
# whether the controller would raise ERR_C4GOPEN_UDP (10 or more missing in a row; c4g-sim
# runs with --max-miss 100000 and does not say).
want_fault() {
    case $1 in
    wrong-num) echo "$FSENT:$FSENT" ;;
    no-reply) echo "$FSENT:0" ;;
    drop-nth) echo "1:0" ;;
    esac
}
want_err() { case $1 in drop-nth) echo false ;; *) echo true ;; esac; }
got_fault() { echo "$(lost "$1"):$(jget "$1" replies.wrong_num)"; }
# The host disturbed a run (PORT JSON) when a reply came after the next packet or close to
# it: ref_pc sent one more than 1500 us after its packet came (its log), or the controller
# side saw a reply late, stale, unexpected or twice. Busy loops on a 2-core host do that now
# and then (a stalled ref_pc, a stalled sender), and then one more reply is lost, or ten in
# a row. Only such a pair is run again (8 pairs at most: up to 4 seen beside four busy
# loops); a fault judged wrong without that evidence fails at once.
fault_disturbed() {
    w=$(refstat "$T/ref_$1.log" worst)
    awk -v w="${w:-0}" 'BEGIN { exit !(w > 1500) }' && return 0
    [ $(( $(jget "$2" replies.late) + $(jget "$2" replies.stale) + $(jget "$2" replies.unexpected) \
        + $(jget "$2" replies.duplicates) )) -gt 0 ]
}
# fault_pair FAULT: ref_pc with that fault, once against c4g-sim and once against live;
# S and J are their JSON summaries, SPORT and LPORT the ports (ref_pc's logs)
fault_pair() {
    case $1 in drop-nth) fopt="--drop-nth 50" ;; *) fopt="--$1" ;; esac
    rm -f "$T/$1".*.kv
    next_port; ref_pc "$PORT" $fopt --slow-us 1500; SPORT=$PORT
    timeout 50 "$SIM" --bind 127.0.0.1 -p "$PORT" -n 300 --max-miss 100000 --json >"$T/$1.sim.json" 2>/dev/null
    ref_done
    next_port; ref_pc "$PORT" $fopt --slow-us 1500; LPORT=$PORT
    live "$1" "$PORT"
    ref_done
    S=$T/$1.sim.json; J=$T/$1.live.json
    echo "       $1: lost:wrong NUM c4g-sim $(got_fault "$S"), live $(got_fault "$J")" \
        "(ERR_C4GOPEN_UDP $(jget "$J" replies.err_c4gopen_udp)), want $(want_fault "$1") ($(want_err "$1"));" \
        "ref_pc worst $(refstat "$T/ref_$SPORT.log" worst) / $(refstat "$T/ref_$LPORT.log" worst) us"
}
# the pair gave something else than the fault must give, and the host disturbed a run of it
pair_disturbed() {
    [ "$(got_fault "$S")" = "$(want_fault "$1")" ] && [ "$(got_fault "$J")" = "$(want_fault "$1")" ] &&
        [ "$(jget "$J" replies.err_c4gopen_udp)" = "$(want_err "$1")" ] && return 1
    fault_disturbed "$SPORT" "$S" || fault_disturbed "$LPORT" "$J"
}
AGAIN_MAX=8
for fault in wrong-num no-reply drop-nth; do
    again_while pair_disturbed fault_pair "$fault"
    ok "$fault: same packets sent" eq "$(jget "$J" packets.sent)" "$(jget "$S" packets.sent)"
    ok "$fault: live loses the replies c4g-sim loses" eq "$(lost "$J")" "$(lost "$S")"
    ok "$fault: live counts the wrong NUMs c4g-sim counts" eq "$(jget "$J" replies.wrong_num)" "$(jget "$S" replies.wrong_num)"
    ok "$fault: exit 1" eq "$LRC" 1
done
unset AGAIN_MAX
ok "wrong-num: every reply wrong" eq "$(jget "$T/wrong-num.live.json" replies.wrong_num)" "$FSENT"
ok "no-reply: every reply lost" eq "$(lost "$T/no-reply.live.json")" "$FSENT"
ok "no-reply: the controller would raise ERR_C4GOPEN_UDP" eq "$(jget "$T/no-reply.live.json" replies.err_c4gopen_udp)" true
ok "drop-nth: the PC's NUM policy seen (plus-one, under the default either)" eq "$(jget "$T/drop-nth.live.json" pc_policy)" plus-one
ok "drop-nth: one reply lost" eq "$(lost "$T/drop-nth.live.json")" 1
ok "drop-nth: 9 in a row or fewer: no ERR_C4GOPEN_UDP" eq "$(jget "$T/drop-nth.live.json" replies.err_c4gopen_udp)" false
[ "$FAILS" -eq "$F0" ] || { for f in wrong-num no-reply drop-nth; do dump "$f"; done; }

# Late replies: ref_pc holds its replies to cyclic packets 10 to 12, 30 and 50 until 1200 us
# after each packet came: later than T_CYCLE1 (500 us) and before the next packet (2 ms),
# 700 us of margin on the early side, 800 on the late one (the hold itself overshoots by
# about 100). Live and c4g-sim must both count those 5 late (ok, later than t-cycle1), and
# only those. A loaded host makes other replies late too, now and then (1 to 2 % of them
# under the runner's busy loops, the first one after the start-up often), and those would
# count on one side and not on the other. So an attempt counts only when ref_pc's own log
# shows that it sent no other reply more than 400 us after its packet (--slow-us 400: its
# "slow" count is then its "held" count; 400, not 500, because its clock is read after
# sendto) and when the controller judged every reply by its deadline (0 missing, stale,
# unjudged: no held reply pushed past it); otherwise it is run again, up to LATE_TRIES times.
# The capture is short (60 ticks) to make an undisturbed attempt likely: 1 to 11 attempts
# seen under the runner's load on the 2-core test host, up to 17 with a second e2e run
# sharing it.
LATE="--late-us 1200@10,3 --late-us 1200@30 --late-us 1200@50"
LATE_HELD=5
LATE_TRIES=30
next_port; start_server lcap "$PORT"
timeout 50 "$SIM" -p "$PORT" -n 60 --max-miss 500 --pcap "$T/l.pcap" --json >"$T/lcap.sim.json" 2>"$T/lcap.sim.err"
kill "$SPID" 2>/dev/null; wait "$SPID" 2>/dev/null
CAP=$T/l.pcap
# late_run sim|live: attempts until one counts; sets LJ (its JSON), LLOG (ref_pc's log), LTRY
late_run() {
    LTRY=0
    while [ "$LTRY" -lt "$LATE_TRIES" ]; do
        LTRY=$((LTRY + 1))
        # shellcheck disable=SC2086
        next_port; ref_pc "$PORT" $LATE --slow-us 400
        if [ "$1" = sim ]; then
            LJ=$T/late$LTRY.sim.json
            timeout 50 "$SIM" --bind 127.0.0.1 -p "$PORT" -n 60 --max-miss 500 --json >"$LJ" 2>"$T/late$LTRY.sim.err"
        else
            LJ=$T/late$LTRY.live.json
            live "late$LTRY" "$PORT"
        fi
        ref_done
        LLOG=$T/ref_$PORT.log
        if [ "$(refstat "$LLOG" held)" = "$LATE_HELD" ] && [ "$(refstat "$LLOG" slow)" = "$LATE_HELD" ] &&
           [ "$(jget "$LJ" replies.missing)$(jget "$LJ" replies.stale)$(jget "$LJ" replies.unjudged)" = 000 ]; then
            return 0
        fi
        echo "       (late, $1, attempt $LTRY: the host interfered: ref_pc sent $(refstat "$LLOG" slow) replies over 400 us," \
            "$(refstat "$LLOG" held) held, worst $(refstat "$LLOG" worst) us; $1 counted $(jget "$LJ" replies.missing) missing," \
            "$(jget "$LJ" replies.stale) stale, $(jget "$LJ" replies.unjudged) unjudged: again)"
    done
    return 1
}
F0=$FAILS
late_run sim; src=$?
S=$LJ; SLOG=$LLOG
ok "late, c4g-sim: an attempt the host did not disturb ($LTRY of at most $LATE_TRIES)" eq "$src" 0
ok "late, c4g-sim: ref_pc held $LATE_HELD replies, the longest $(refstat "$SLOG" worst) us" eq "$(refstat "$SLOG" held)" "$LATE_HELD"
ok "late, c4g-sim: the $LATE_HELD held replies counted late" eq "$(jget "$S" replies.late)" "$LATE_HELD"
late_run live; lrc=$?
J=$LJ
ok "late, live: an attempt the host did not disturb ($LTRY of at most $LATE_TRIES)" eq "$lrc" 0
ok "late, live: ref_pc held $LATE_HELD replies, the longest $(refstat "$LLOG" worst) us" eq "$(refstat "$LLOG" held)" "$LATE_HELD"
echo "       late: c4g-sim late $(jget "$S" replies.late) of $(jget "$S" replies.ok) ok; live late $(jget "$J" replies.late) of $(jget "$J" replies.ok) ok, latency max $(jget "$J" replies.latency_us.max) us"
ok "late: same packets sent" eq "$(jget "$J" packets.sent)" "$(jget "$S" packets.sent)"
ok "late: live counts the late replies c4g-sim counts" eq "$(jget "$J" replies.late)" "$(jget "$S" replies.late)"
ok "late: a late reply still counts ok (every reply ok, 0 wrong NUM)" \
    eq "$(jget "$J" replies.ok):$(jget "$J" replies.wrong_num)" "$(jget "$J" packets.sent):0"
ok "late: live's latency max over the 1200 us hold" ge "$(jget "$J" replies.latency_us.max)" 1200
ok "late: exit 1, result findings" eq "$LRC:$(jget "$J" result)" 1:findings
[ "$FAILS" -eq "$F0" ] || { dump "$(basename "$S" .sim.json)"; dump "$(basename "$J" .live.json)"; cat "$SLOG" "$LLOG"; }

echo "4. refusals:"; F0=$FAILS
# the first 40 frames (the start-up) cut off the mode 4 capture
python3 - "$T/m4.pcap" "$T/cut.pcap" <<'EOF'
import struct, sys
d = open(sys.argv[1], "rb").read()
out, off, n = [d[:24]], 24, 0
while off + 16 <= len(d):
    incl = struct.unpack_from("<I", d, off + 8)[0]
    if n >= 40:
        out.append(d[off:off + 16 + incl])
    off += 16 + incl
    n += 1
open(sys.argv[2], "wb").write(b"".join(out))
EOF
"$RP" live "$T/cut.pcap" --to 127.0.0.1:9 >"$T/cut.out" 2>"$T/cut.err"; rc=$?
ok "no start-up: exit 2" eq "$rc" 2
ok "no start-up: says so and suggests rerun" has "$T/cut.err" "no session with its start-up.*rerun"
"$RP" live "$T/m4.pcap" --to x >/dev/null 2>"$T/to.err"; rc=$?
ok "bad --to: exit 2" eq "$rc" 2
ok "bad --to: the error names it" has "$T/to.err" "c4g-replay: --to: bad value 'x' (want HOST:PORT)"
"$RP" live "$T/m4.pcap" >/dev/null 2>"$T/noto.err"; rc=$?
ok "no --to: exit 2" eq "$rc" 2
"$RP" live "$T/nothere.pcap" --to 127.0.0.1:9 >/dev/null 2>&1; rc=$?
ok "unreadable file: exit 2" eq "$rc" 2
"$RP" live "$T/m4.pcap" --to 127.0.0.1:9 --session 2 >/dev/null 2>"$T/sess.err"; rc=$?
ok "--session 2 of 1: exit 2, named" eq "$rc:$(grep -c 'has 1 session' "$T/sess.err")" 2:1
[ "$FAILS" -eq "$F0" ] || cat "$T"/*.err
finish
