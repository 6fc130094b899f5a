#!/bin/sh
# Regenerates the capture fixtures of c4g-replay in fixtures/replay/ (README.md there says
# what each file holds): real sessions of c4g-sim against c4g-server (or the test reference
# PC, tests/e2e/helpers/ref_pc.c) on 127.0.0.1, one fixed pair of high ports per capture,
# crafted sessions from tests/e2e/helpers/forge_capture.c for what the real tools refuse to
# send, format variants of one crafted session, and hostile files in fixtures/replay/bad/.
#
#   sh scripts/make-replay-fixtures.sh BUILD_DIR      (or: make replay-fixtures BUILD=...)
#
# Needs the built tools and static library in BUILD_DIR, cc, libpcap, tshark, editcap and
# mergecap (wireshark-common). Fixed seeds, tick counts and ports:
# the crafted files come out byte for byte the same; the real runs differ in timestamps,
# reply latency and whatever a busy host delays. A run whose key facts (exit codes, the
# controller's error, skipped replies, no reply later than 500 us where lateness is not the
# point ...) are not what the fixture is for is repeated, up to 8 times.
# ONLY=NAME[,NAME..] regenerates just those files (names without .pcap; bad = fixtures/replay/bad).
set -u
cd "$(dirname "$0")/.." || exit 1
B=${1:?usage: sh scripts/make-replay-fixtures.sh BUILD_DIR}
SIM=$B/bin/c4g-sim
SRV=$B/bin/c4g-server
LIB=$B/lib/libc4gopen.a
OUT=fixtures/replay
IN=$OUT/inputs
FAST=$IN/fast.ini
IDLE=$IN/idle.scn
ONLY=${ONLY:-}
for f in "$SIM" "$SRV" "$LIB"; do
    [ -e "$f" ] || { echo "make-replay-fixtures: $f not built (make BUILD=$B tools lib)"; exit 1; }
done
for c in cc tshark editcap mergecap; do
    command -v "$c" >/dev/null 2>&1 || { echo "make-replay-fixtures: $c not found"; exit 1; }
done

T=$(mktemp -d "${TMPDIR:-/tmp}/c4g-replay-fx.XXXXXX")
PIDS=""   # started in the background and not waited for yet (so their ids are still ours)
cleanup() {
    for p in $PIDS; do kill "$p" 2>/dev/null; done
    wait 2>/dev/null
    rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
FAILED=""
say() { echo "make-replay-fixtures: $*"; }

CFLAGS="-std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -Werror -Iinclude -Ilib/sim -Ilib/host"
# shellcheck disable=SC2086
cc $CFLAGS -o "$T/ref_pc" tests/e2e/helpers/ref_pc.c "$LIB" -lm || exit 1
# shellcheck disable=SC2086
cc $CFLAGS -o "$T/forge" tests/e2e/helpers/forge_capture.c lib/host/c4gh_pcap.c \
    lib/sim/c4gsim_fixtures.c "$LIB" -lpcap -lm || exit 1
FORGE=$T/forge
mkdir -p "$OUT/bad"

wanted() { [ -z "$ONLY" ] && return 0; case ",$ONLY," in *",$1,"*) return 0 ;; esac; return 1; }
# reap PID: wait for a background process; its exit status
reap() {
    wait "$1"
    rs=$?
    PIDS=$(echo " $PIDS " | sed "s/ $1 / /")
    return $rs
}
jv() { grep -o "\"$2\":[^,}]*" "$1" | head -n 1 | cut -d: -f2- | tr -d '"'; }
# wait_for FILE TEXT PID: until FILE holds TEXT (a tool's start-up line) or PID is gone
wait_for() {
    n=0
    until grep -qs "$2" "$1"; do
        kill -0 "$3" 2>/dev/null || return 1
        n=$((n + 1)); [ $n -ge 500 ] && return 1
        sleep 0.02
    done
}

# start_server NAME PORT [server options]: c4g-server on 127.0.0.1:PORT, its capture in
# $T/NAME.srv.pcap
start_server() {
    sn=$1; sp=$2; shift 2
    "$SRV" -p "$sp" -b 127.0.0.1 --controller 127.0.0.1 --idle-timeout 10 --max-seconds 60 \
        --lost-timeout-ms 500 --json-out "$T/$sn.srv.json" --pcap "$T/$sn.srv.pcap" "$@" \
        >"$T/$sn.srv.out" 2>"$T/$sn.srv.err" &
    SPID=$!
    PIDS="$PIDS $SPID"
    wait_for "$T/$sn.srv.err" "listening on" "$SPID" || { cat "$T/$sn.srv.err"; return 1; }
}
# run_sim NAME PORT [sim options]: c4g-sim from 127.0.0.1:PORT+500 to PORT; sets SIMRC
run_sim() {
    rn=$1; rp=$2; shift 2
    timeout 60 "$SIM" --bind 127.0.0.1 --local-port $((rp + 500)) -p "$rp" --seed 1 --json "$@" \
        >"$T/$rn.sim.json" 2>"$T/$rn.sim.err"
    SIMRC=$?
}
# pair NAME PORT SCENARIO "SIM OPTIONS" [server options]: one session; the capture is the
# server's, or with SIDE=sim the simulator's; sets SIMRC and SRC (the server's exit code)
pair() {
    pn=$1; pp=$2; ps=$3; pa=$4; shift 4
    start_server "$pn" "$pp" "$@" || return 1
    # shellcheck disable=SC2086
    run_sim "$pn" "$pp" -c "$FAST" -S "$ps" --max-miss 500 --pcap "$T/$pn.sim.pcap" $pa
    reap "$SPID"; SRC=$?
    if [ "${SIDE:-server}" = sim ]; then mv "$T/$pn.sim.pcap" "$T/$pn.pcap"; else mv "$T/$pn.srv.pcap" "$T/$pn.pcap"; fi
}
# with_ref NAME PORT "REF_PC OPTIONS" [sim options]: the reference PC, the simulator's capture
with_ref() {
    wn=$1; wp=$2; wr=$3; shift 3
    # shellcheck disable=SC2086
    "$T/ref_pc" -p "$wp" --idle-ms 1500 --max-s 50 $wr 2>"$T/$wn.ref.log" &
    RPID=$!
    PIDS="$PIDS $RPID"
    wait_for "$T/$wn.ref.log" "listening" "$RPID" || { cat "$T/$wn.ref.log"; return 1; }
    run_sim "$wn" "$wp" -c "$FAST" --pcap "$T/$wn.pcap" "$@"
    reap "$RPID"
}
check() {  # check WHAT GOT WANT
    [ "$2" = "$3" ] && return 0
    say "  $CUR: $1: got '$2', want '$3'"
    return 1
}
# make_cap NAME FUNCTION: runs FUNCTION (which leaves $T/NAME.pcap and returns 0 when the run
# shows what the fixture is for) up to 8 times, a second apart (a busy spell of the host
# passes), then installs the capture as NAME.pcap; a failed fixture keeps its old file
make_cap() {
    CUR=$1
    wanted "$1" || return 0
    for try in 1 2 3 4 5 6 7 8; do
        [ "$try" -gt 1 ] && sleep 1
        rm -f "$T/$1".*
        if "$2" "$1" && [ -s "$T/$1.pcap" ]; then
            mv "$T/$1.pcap" "$OUT/$1.pcap"
            say "$1.pcap"
            return 0
        fi
        say "  $1: attempt $try did not show what it is for"
    done
    for f in "$T/$1".*err "$T/$1".*log; do [ -f "$f" ] && tail -n 5 "$f"; done
    FAILED="$FAILED $1"
}
# timing FILE [echo]: "LATE SILENT": replies in the capture more than T_CYCLE1 (500 us) after
# the packet they answer (by NUM: plus-one unless echo), and silences of the controller longer
# than 8 ms; per conversation, whose controller is the side that sent its first datagram
timing() {
    tshark -r "$1" -T fields -e frame.time_epoch -e udp.srcport -e udp.dstport -e udp.payload 2>/dev/null |
        awk -v echo="${2:-}" '
        function hex(h,   i, v) {
            v = 0
            for (i = 1; i <= length(h); i++) v = v * 16 + index("0123456789abcdef", substr(h, i, 1)) - 1
            return v
        }
        NF == 4 && length($4) >= 8 {
            c = ($2 < $3) ? $2 "-" $3 : $3 "-" $2
            if (!(c in ctrl)) ctrl[c] = $2
            n = hex(substr($4, 7, 2) substr($4, 5, 2) substr($4, 3, 2) substr($4, 1, 2))
            if ($2 == ctrl[c]) {
                if ((c in last) && ($1 - last[c]) > 0.008) silent++
                last[c] = $1
                sent[c, n] = $1
                next
            }
            if (echo == "") n = n - 1
            if (((c, n) in sent) && ($1 - sent[c, n]) * 1e6 > 500) late++
        }
        END { print late + 0, silent + 0 }'
}
# clean NAME [echo|""] [SILENCES]: a busy host can hold up any process; a fixture should show
# no late reply and no controller silence the host caused, only the ones it is for
clean() {
    check "late replies, controller silences in the capture" "$(timing "$T/$1.pcap" "${2:-}")" "0 ${3:-0}"
}
atleast() {  # atleast WHAT GOT MIN
    [ "${2:-0}" -ge "$3" ] 2>/dev/null && return 0
    say "  $CUR: $1: got '$2', want at least $3"
    return 1
}
atmost() {  # atmost WHAT GOT MAX
    [ "${2:-0}" -le "$3" ] 2>/dev/null && return 0
    say "  $CUR: $1: got '$2', want at most $3"
    return 1
}
ok_pair() { check "c4g-sim exit" "$SIMRC" 0 && check "c4g-server exit" "$SRC" 0 && clean "$CUR"; }

# ---------------------------------------------------------------- one per mode
# fixtures/server/sim_modeN.scn with the server options of tests/e2e/test_server_modes.py, the
# PC's profiles shortened (0.5 s); 6 axes (figure 10.1), 2 ms
m_0() { pair "$1" 46100 fixtures/server/sim_mode0.scn "" && ok_pair; }
m_10() { pair "$1" 46101 fixtures/server/sim_mode10.scn "" && ok_pair; }
m_1() { pair "$1" 46102 fixtures/server/sim_mode1.scn "" --hold --duration 0.5 --gains 30,200,300 && ok_pair; }
m_2() { pair "$1" 46103 fixtures/server/sim_mode2.scn "" --gains 30,200,300 && ok_pair; }
m_4() { pair "$1" 46104 fixtures/server/sim_mode4.scn "" --sine 0.25,1,0.5 && ok_pair; }
m_5() { pair "$1" 46105 fixtures/server/sim_mode5.scn "" --sine 0.25,1,0.5 && ok_pair; }
m_7() { pair "$1" 46106 fixtures/server/sim_mode7.scn "" --offset 0.1,0.25,0.25 && ok_pair; }
m_8() { pair "$1" 46107 fixtures/server/sim_mode8.scn "" --vel 0.001,2,1 && ok_pair; }
m_9() { pair "$1" 46108 fixtures/server/sim_mode9.scn "" --ff fixtures/server/ff_example.txt --duration 0.5 && ok_pair; }
for m in 0 10 1 2 4 5 7 8 9; do make_cap "mode$m" "m_$m"; done

# ---------------------------------------------------------------- special modes
# the controller drives the arm off, raises the error (exit 1) and aborts the scenario; it
# keeps sending (--hold) up to tick 250, then stops without a 504 (the server ends with the
# loss, exit 3)
s_505() {
    pair "$1" 46110 "$IDLE" "--open-axes 2 --hold -n 250" --inject 505@150 &&
        check "c4g-sim exit" "$SIMRC" 1 && grep -q ERR_C4GOPEN_DRIVEOFF_SERVER "$T/$1.sim.json" && clean "$1"
}
s_508() {
    pair "$1" 46111 "$IDLE" "--open-axes 2 --hold -n 250" --inject 508@150:2 &&
        check "c4g-sim exit" "$SIMRC" 1 && grep -q ERR_C4GOPEN_FOLLOW_ERROR "$T/$1.sim.json" && clean "$1"
}
s_passive() {
    pair "$1" 46112 fixtures/server/sim_freeze.scn "--open-axes 3" && check "c4g-sim exit" "$SIMRC" 0 &&
        check "c4g-server exit" "$SRC" 0 && clean "$1" "" 1 &&
        check "passive freezings" "$(jv "$T/$1.srv.json" passive_freezings)" 1
}
# the simulator's capture: c4g-server drops what queued during its pause without recording it.
# After the pause it answers the newest queued packet, up to one period after it came: that
# one reply may be late, no other
s_active() {
    SIDE=sim pair "$1" 46113 "$IDLE" "--open-axes 2" --freeze 120,100 && check "c4g-sim exit" "$SIMRC" 0 &&
        check "c4g-server exit" "$SRC" 0 && check "active freezings" "$(jv "$T/$1.srv.json" active_freezings)" 1 &&
        tm=$(timing "$T/$1.pcap") && atmost "late replies in the capture" "${tm% *}" 1 &&
        check "controller silences in the capture" "${tm#* }" 0
}
s_504() { pair "$1" 46114 fixtures/scenarios/exit-open.scn "" && ok_pair; }
s_506() {
    pair "$1" 46115 fixtures/server/sim_restart.scn "" && ok_pair &&
        check "restarts" "$(jv "$T/$1.srv.json" restarts)" 1
}
make_cap special-drive-off-505 s_505
make_cap special-follow-error-508 s_508
make_cap special-freeze-passive s_passive
make_cap special-freeze-active s_active
make_cap special-exit-504 s_504
make_cap restart-506 s_506

# ---------------------------------------------------------------- two arms, two controllers
two_arms() {
    cat fixtures/sim/two-arms.ini "$FAST" >"$T/two-arms-fast.ini"
    start_server "$1" 46116 --arm 1 --axes 1,2 --sine 0.25,2,0.5 --arm 2 --offset 0.1,0.1,0.1 || return 1
    run_sim "$1" 46116 -c "$T/two-arms-fast.ini" -S fixtures/server/sim_two_arms.scn --max-miss 500
    reap "$SPID"; SRC=$?
    mv "$T/$1.srv.pcap" "$T/$1.pcap"
    ok_pair
}
two_ctrl() {
    start_server "$1.a" 46117 || return 1
    PA=$SPID
    start_server "$1.b" 46118 || return 1
    PB=$SPID
    run_sim "$1.a" 46117 -c "$FAST" -S "$IDLE" --open-axes 2 --max-miss 500 &
    SA=$!
    PIDS="$PIDS $SA"
    run_sim "$1.b" 46118 -c "$FAST" -S "$IDLE" --open-axes 3 -T 1 --max-miss 500
    reap "$SA"; reap "$PA"; RA=$?; reap "$PB"; RB=$?
    check "server A exit" "$RA" 0 && check "server B exit" "$RB" 0 &&
        mergecap -F pcap -w "$T/$1.pcap" "$T/$1.a.srv.pcap" "$T/$1.b.srv.pcap" && clean "$1"
}
make_cap two-arms two_arms
make_cap two-controllers two_ctrl

# ---------------------------------------------------------------- faults
# idle scenario, 2 axes, server-side capture unless the PC is ref_pc (then the simulator's)
f_drop() {
    pair "$1" 46120 "$IDLE" "--open-axes 2 --drop 0.02 --seed 5" && ok_pair &&
        atleast "NUM gaps" "$(jv "$T/$1.srv.json" gaps)" 1
}
f_skip3() {
    pair "$1" 46121 "$IDLE" "--open-axes 2" --skip-replies 150,3 && ok_pair &&
        check "skipped" "$(jv "$T/$1.srv.json" skipped)" 3
}
f_skip10() {
    pair "$1" 46122 "$IDLE" "--open-axes 2 --max-miss 10" --skip-replies 150,10 &&
        check "skipped" "$(jv "$T/$1.srv.json" skipped)" 10 && check "c4g-sim exit" "$SIMRC" 1 && clean "$1" &&
        grep -q '"ERR_C4GOPEN_UDP"' "$T/$1.sim.json" && check "max consecutive missing" \
        "$(jv "$T/$1.sim.json" max_consecutive_missing)" 10
}
f_late() {
    with_ref "$1" 46123 "--late-us 800@100,20 --late-us 2300@180" -S "$IDLE" --open-axes 2 --max-miss 500 &&
        check "c4g-sim exit" "$SIMRC" 0 && grep -q "held 21" "$T/$1.ref.log" &&
        check "late replies, controller silences in the capture" "$(timing "$T/$1.pcap")" "21 0"
}
f_wrongnum() {
    with_ref "$1" 46124 "--wrong-num-at 150,3" -S "$IDLE" --open-axes 2 --max-miss 500 &&
        check "c4g-sim exit" "$SIMRC" 0 && check "wrong NUM" "$(jv "$T/$1.sim.json" wrong_num)" 3 && clean "$1"
}
f_policy() {
    pair "$1" 46125 "$IDLE" "--open-axes 2 --num-policy plus-one --max-miss 10" --num-policy echo &&
        check "c4g-sim exit" "$SIMRC" 1 && grep -q '"ERR_C4GOPEN_UDP"' "$T/$1.sim.json" && clean "$1" echo
}
f_echo() {
    pair "$1" 46126 "$IDLE" "--open-axes 2" --num-policy echo && check "c4g-sim exit" "$SIMRC" 0 &&
        check "c4g-server exit" "$SRC" 0 && clean "$1" echo &&
        check "PC policy" "$(jv "$T/$1.sim.json" pc_policy)" echo
}
f_dup() {
    pair "$1" 46127 "$IDLE" "--open-axes 2 --duplicate 0.02 --seed 3" && ok_pair &&
        atleast "duplicates" "$(jv "$T/$1.srv.json" duplicates)" 1
}
f_reorder() {
    pair "$1" 46128 "$IDLE" "--open-axes 2 --reorder 0.02 --seed 3" && ok_pair &&
        atleast "out of order" "$(jv "$T/$1.srv.json" out_of_order)" 1
}
f_trunc() {
    pair "$1" 46129 "$IDLE" "--open-axes 2 --truncate 0.01 --seed 4" && ok_pair &&
        atleast "malformed (length)" "$(jv "$T/$1.srv.json" malformed_length)" 1
}
# the seed puts three of the flipped bytes in mode fields, one in a float exponent
f_corrupt() {
    pair "$1" 46130 "$IDLE" "--open-axes 2 --corrupt 0.02 --seed 6" && ok_pair &&
        atleast "malformed (mode)" "$(jv "$T/$1.srv.json" malformed_mode)" 1
}
f_pause() {
    pair "$1" 46131 "$IDLE" "--open-axes 2 --pause 150:20" && check "c4g-sim exit" "$SIMRC" 0 &&
        check "c4g-server exit" "$SRC" 0 && clean "$1" "" 1
}
make_cap fault-drop f_drop
make_cap fault-skip-3 f_skip3
make_cap fault-skip-10 f_skip10
make_cap fault-late f_late
make_cap fault-wrong-num f_wrongnum
make_cap fault-num-policy-mismatch f_policy
make_cap num-echo f_echo
make_cap fault-duplicate f_dup
make_cap fault-reorder f_reorder
make_cap fault-truncate f_trunc
make_cap fault-corrupt f_corrupt
make_cap fault-pause f_pause

# ---------------------------------------------------------------- crafted data findings
forge() { fn=$1; shift; wanted "$fn" || return 0; "$FORGE" --out "$OUT/$fn.pcap" "$@" >/dev/null && say "$fn.pcap" || FAILED="$FAILED $fn"; }
forge data-clean --ticks 160 --pc-port 46200 --ctrl-port 46700
forge data-follow-error --ticks 160 --inject follow-error --at 100 --pc-port 46201 --ctrl-port 46701
forge data-current-mode2 --ticks 160 --inject current --mode 2 --at 100 --pc-port 46202 --ctrl-port 46702
forge data-current-mode9 --ticks 160 --inject current --mode 9 --at 100 --pc-port 46203 --ctrl-port 46703
forge data-nan-ctrl-d3 --ticks 160 --inject nan-d3 --at 120 --pc-port 46204 --ctrl-port 46704
forge data-inf-pc-d1 --ticks 160 --inject inf-d1 --at 120 --pc-port 46205 --ctrl-port 46705
forge data-step-mode4 --ticks 160 --inject step --at 100 --pc-port 46206 --ctrl-port 46706
forge data-truncated-reply --ticks 160 --inject truncate --at 100 --pc-port 46207 --ctrl-port 46707
forge data-unknown-mode --ticks 160 --inject unknown-mode --at 100 --pc-port 46208 --ctrl-port 46708
forge data-unknown-mode-pc --ticks 160 --inject unknown-mode-pc --at 100 --pc-port 46209 --ctrl-port 46709
# a capture started in the middle of a session, across the NUM wrap 0x7FFF -> 0
forge data-midsession-wrap --ticks 120 --axes 2 --first-num 32700 --pc-port 46210 --ctrl-port 46710

# ---------------------------------------------------------------- format variants
# one small clean session (80 ticks, 2 axes), the same packets in every file
FMT="--ticks 80 --axes 2 --pc-port 46300 --ctrl-port 46800"
for l in eth vlan raw null sll sll2; do
    # shellcheck disable=SC2086
    forge "fmt-$l" $FMT --link $l
done
# shellcheck disable=SC2086
forge fmt-frag-init $FMT --fragment-init
if wanted fmt-pcapng; then
    editcap -F pcapng "$OUT/fmt-eth.pcap" "$OUT/fmt-pcapng.pcapng" && say fmt-pcapng.pcapng || FAILED="$FAILED fmt-pcapng"
fi
if wanted fmt-nsec; then
    editcap -F nsecpcap "$OUT/fmt-eth.pcap" "$OUT/fmt-nsec.pcap" && say fmt-nsec.pcap || FAILED="$FAILED fmt-nsec"
fi

# ---------------------------------------------------------------- field-made captures
# fixtures/replay/field/: what field engineers make of good captures with the usual tools
# (editcap, mergecap, text2pcap), each from a fixture above; byte for byte the same every time.
# The e2e test holds c4g-replay's verdict on each one (README.md, "Field-made captures").
field() {
    wanted field || return 0
    F=$OUT/field
    M4=$OUT/mode4.pcap
    mkdir -p "$F"
    # the capture's clock steps back 1 s after frame 400 (an NTP step during tcpdump)
    editcap -F pcap -r "$M4" "$T/s1.pcap" 1-400 && editcap -F pcap -r "$M4" "$T/s2.pcap" 401-806 &&
        editcap -F pcap -t -1 "$T/s2.pcap" "$T/s2b.pcap" &&
        mergecap -F pcap -a -w "$F/clock-step.pcap" "$T/s1.pcap" "$T/s2b.pcap" || return 1
    # a capture started after the initialization packet (tick 38 on), on a port not 1000/1001
    editcap -F pcap -r "$M4" "$F/midsession-mode4.pcap" 101-806 || return 1
    # the second file of a capture rotated every 300 packets (tcpdump -C, editcap -c)
    editcap -F pcap -c 300 "$M4" "$T/rot.pcap" || return 1
    cp "$(ls "$T"/rot_00001_* | head -n 1)" "$F/rotated-2.pcap" || return 1
    # every frame twice (mergecap of a file with itself)
    mergecap -F pcap -w "$F/doubled.pcap" "$OUT/special-exit-504.pcap" "$OUT/special-exit-504.pcap" || return 1
    # the same datagrams as IPv6 (::1), from their bytes (text2pcap)
    tshark -r "$OUT/fmt-eth.pcap" -T fields -e udp.srcport -e udp.payload 2>/dev/null |
        awk '{ printf "%s %s\n", $1, $2 }' >"$T/pl.txt" || return 1
    : >"$T/v6.pcap"
    python3 - "$T/pl.txt" "$T/v6.hex" <<'PY' || return 1
import sys
out = open(sys.argv[2], "w")
for n, line in enumerate(open(sys.argv[1])):
    port, hexs = line.split()
    data = bytes.fromhex(hexs.replace(":", ""))
    out.write("%s 1700000000.000000\n" % ("I" if port == "46800" else "O"))  # a fixed time
    for i in range(0, len(data), 16):
        out.write("%06x %s\n" % (i, " ".join("%02x" % b for b in data[i:i + 16])))
PY
    text2pcap -q -F pcap -D -6 ::1,::1 -u 46800,46300 -t "%s." "$T/v6.hex" "$F/ipv6.pcap" >/dev/null 2>&1 || return 1
    # replies held after the controller's next packet (moved 2.2 ms later): the replies to
    # ticks 60, 150 and 300 of mode4 (frames 146, 326, 626)
    editcap -F pcap -r "$M4" "$T/late.pcap" 146 326 626 && editcap -F pcap -t 0.0022 "$T/late.pcap" "$T/late2.pcap" &&
        editcap -F pcap "$M4" "$T/rest.pcap" 146 326 626 &&
        mergecap -F pcap -w "$F/late-replies.pcap" "$T/rest.pcap" "$T/late2.pcap" || return 1
    # late-replies with its initialization echo held after the next synchronization packet
    # (frame 20 moved 2.5 ms): no policy from the echo, and late plus-one replies
    editcap -F pcap -r "$F/late-replies.pcap" "$T/echo.pcap" 20 && editcap -F pcap -t 0.0025 "$T/echo.pcap" "$T/echo2.pcap" &&
        editcap -F pcap "$F/late-replies.pcap" "$T/rest2.pcap" 20 &&
        mergecap -F pcap -w "$F/late-init-echo.pcap" "$T/rest2.pcap" "$T/echo2.pcap" || return 1
    # a capture of fault-late started mid-session: its stale plus-one reply (to NUM 192)
    editcap -F pcap -r "$OUT/fault-late.pcap" "$F/midsession-late.pcap" 101-526 || return 1
    # a controller NUM near INT32_MAX (0x7FFFF000: not a stale NUM, so NUM arithmetic would see it) in tick 30 of fmt-eth (frame 55)
    python3 - "$OUT/fmt-eth.pcap" "$F/num-huge.pcap" 55 <<'PY' || return 1
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
off, n = 24, 0
while off < len(b):
    n += 1
    incl = struct.unpack_from("<I", b, off + 8)[0]
    if n == int(sys.argv[3]):
        struct.pack_into("<i", b, off + 16 + 42, 0x7FFFF000)  # Ethernet + IPv4 + UDP headers
        struct.pack_into(">H", b, off + 16 + 40, 0)            # no UDP checksum
    off += 16 + incl
open(sys.argv[2], "wb").write(b)
PY
    # controller frame 251 (tick 114, NUM 126) lost by the capture, not the wire: its reply is there
    editcap -F pcap "$M4" "$F/lost-frame.pcap" 251 || return 1
    # the reply to tick 114 (frame 252) stamped 300 us earlier: before its packet, in capture order after it
    editcap -F pcap -r "$M4" "$T/b1.pcap" 1-251 && editcap -F pcap -r "$M4" "$T/b2.pcap" 252 &&
        editcap -F pcap -t -0.0003 "$T/b2.pcap" "$T/b2s.pcap" && editcap -F pcap -r "$M4" "$T/b3.pcap" 253-806 &&
        mergecap -F pcap -a -w "$F/reply-before.pcap" "$T/b1.pcap" "$T/b2s.pcap" "$T/b3.pcap" || return 1
    # 10 s without a packet after frame 500 (the rest of the file 10 s later)
    editcap -F pcap -r "$M4" "$T/h1.pcap" 1-500 && editcap -F pcap -r "$M4" "$T/h2.pcap" 501-806 &&
        editcap -F pcap -t 10 "$T/h2.pcap" "$T/h2s.pcap" &&
        mergecap -F pcap -a -w "$F/hole-10s.pcap" "$T/h1.pcap" "$T/h2s.pcap" || return 1
    # a nanosecond pcapng (its interface's if_tsresol 9)
    editcap -F pcapng "$OUT/fmt-nsec.pcap" "$F/nsec.pcapng" || return 1
    # a compressed capture
    gzip -n -c "$OUT/mode0.pcap" >"$F/mode0.pcap.gz" || return 1
    say "field/*.pcap"
}
field || FAILED="$FAILED field"

# ---------------------------------------------------------------- hostile files
oct() { printf '\\%d%d%d' $(($1 / 64)) $(($1 / 8 % 8)) $(($1 % 8)); }   # printf's escape of byte $1
# the 4 bytes of a little-endian 32-bit value
le32() {
    v=$1; s=""
    for _ in 1 2 3 4; do s="$s$(oct $((v & 255)))"; v=$((v >> 8)); done
    # shellcheck disable=SC2059 # the format is the escapes
    printf "$s"
}
bad() {
    wanted bad || return 0
    BASE=$OUT/fmt-eth.pcap
    D=$OUT/bad
    : >"$D/empty.pcap"
    printf 'This is not a capture.\nc4g-replay must say so and exit, not crash.\n' >"$D/text.pcap"
    # records 1..10 of the base file, then more or less of record 11
    editcap -F pcap -r "$BASE" "$T/r10.pcap" 1-10 && editcap -F pcap -r "$BASE" "$T/r11.pcap" 1-11 || return 1
    a=$(wc -c <"$T/r10.pcap"); b=$(wc -c <"$T/r11.pcap")
    head -c $(((a + b) / 2)) "$T/r11.pcap" >"$D/truncated-record.pcap"
    head -c $((a + 8)) "$T/r11.pcap" >"$D/truncated-record-header.pcap"
    # record 11 claims 0x7FFFFFF0 bytes (over any snaplen), then 64 bytes follow
    { cat "$T/r10.pcap"; le32 1700000000; le32 30000; le32 2147483632; le32 2147483632
      head -c 64 "$T/r11.pcap"; } >"$D/caplen-huge.pcap"
    # records 1..20 with the global header's snaplen set to 1000: the initialization packet
    # and its echo (records 19, 20: 1242-byte frames) are longer than the snaplen says
    editcap -F pcap -r "$BASE" "$T/r20.pcap" 1-20 || return 1
    { head -c 16 "$T/r20.pcap"; le32 1000; tail -c +21 "$T/r20.pcap"; } >"$D/caplen-over-snaplen.pcap"
    editcap -F pcap -s 64 "$BASE" "$D/snaplen-64.pcap" || return 1
    # a valid global header, then 4096 bytes of pseudo-random garbage (fixed seed)
    { head -c 24 "$BASE"
      x=7; i=0
      while [ $i -lt 64 ]; do
          s=""; j=0
          while [ $j -lt 64 ]; do
              x=$(((x * 1103515245 + 12345) % 2147483648)); y=$(((x >> 16) & 255))
              s="$s\\$((y / 64))$((y / 8 % 8))$((y % 8))"; j=$((j + 1))
          done
          # shellcheck disable=SC2059 # the format is the escapes
          printf "$s"; i=$((i + 1))
      done; } >"$D/garbage-after-header.pcap"
    head -c 24 "$BASE" >"$D/header-only.pcap"
    editcap -F pcap -T user0 -r "$BASE" "$D/linktype-user0.pcap" 1-40 || return 1
    say "bad/*.pcap"
}
bad || FAILED="$FAILED bad"

if [ -z "$ONLY" ]; then
    echo
    echo "file frames udp-conversations bytes"
    for f in "$OUT"/*.pcap "$OUT"/*.pcapng; do
        fr=$(tshark -r "$f" -T fields -e frame.number 2>/dev/null | wc -l)
        cv=$(tshark -r "$f" -q -z conv,udp 2>/dev/null | grep -c '<->')
        echo "$(basename "$f") $fr $cv $(wc -c <"$f")"
    done
    echo "total: $(du -cb "$OUT"/*.pcap "$OUT"/*.pcapng "$OUT"/bad/* | tail -n 1 | cut -f1) bytes"
fi
[ -z "$FAILED" ] || { say "FAILED:$FAILED"; exit 1; }
