#!/bin/sh
# c4g-replay on real captures (the live command has its own test, replay_live.sh):
#  1. every fixture in fixtures/replay against its golden summary (fixtures/replay/golden),
#     the key facts fixtures/replay/README.md states, and check's exit status per fixture;
#  2. the independent oracle: the payloads the reader extracts equal tshark's udp.payload,
#     frame by frame, on every fixture and every hostile file;
#  3. hostile files: the exit status and a message naming the file, the packet and its byte
#     offset; never a crash (an exit status above 128);
#  4. a real tcpdump capture on lo of a c4g-sim + c4g-server session, and one with -i any
#     (Linux cooked SLL2), read back; the first converted to pcapng by editcap gives the same
#     sessions;
#  5. rerun: 0 divergences on c4g-server's own captures with the options they were made with;
#     another amplitude or gain gives the first divergent field where it must be;
#  6. export (CSV, moni rows, JSON lines) and plot (PNG, SVG, text) on a fixture; the
#     examples of docs/c4g-replay.md print what the page shows.
. tests/e2e/server_helpers/lib.sh "$1"
RP=$BUILD/bin/c4g-replay
FX=fixtures/replay
[ -x "$SIM" ] && [ -x "$RP" ] || { echo "replay: $SIM or $RP not built"; exit 1; }
for t in python3 tshark editcap; do
    command -v "$t" >/dev/null 2>&1 || { echo "replay: $t needed (scripts/deps.sh installs it)"; exit 1; }
done
CHECK="python3 tests/e2e/replay_check.py"

echo "1. fixtures: golden summaries, key facts, check's exit status"
ok "summary --json of every fixture equals its golden file" sh scripts/make-replay-golden.sh "$BUILD" --check
ok "the README's key facts" $CHECK facts "$RP"
check_status() {  # every fixture: check exits 0 on a clean golden verdict, else 1
    st=0
    for g in $FX/golden/*.json; do
        name=$(basename "$g" .json)
        f=$FX/$name.pcap; [ -f "$f" ] || f=$FX/$name.pcapng
        opts=$(awk -v n="$name" '$1 == n { $1 = ""; print }' $FX/golden/OPTIONS)
        want=1; grep -q '"verdict": "clean"' "$g" && want=0
        # shellcheck disable=SC2086
        "$RP" check -q $opts "$f" >"$T/check.out" 2>&1; got=$?
        [ "$got" = "$want" ] || { echo "       $name: check exit $got, want $want"; st=1; }
    done
    return $st
}
ok "check: exit 0 on the clean fixtures, 1 on the others" check_status
"$RP" check $FX/*.pcap >"$T/all.out" 2>&1; rc=$?
ok "check over every fixture at once: exit 1, one line per finding" eq "$rc" 1
ok "  ... the late replies of fault-late among them" has "$T/all.out" "fault-late.pcap: session [0-9]*: late: 20, "
"$RP" check --allow all -q $FX/*.pcap >/dev/null 2>&1; rc=$?
ok "check --allow all: exit 0" eq "$rc" 0
"$RP" check --allow late,missing -q $FX/fault-late.pcap >/dev/null 2>&1; rc=$?
ok "check --allow late,missing on fault-late: exit 0" eq "$rc" 0

echo "2. oracle: the reader's payloads against tshark's udp.payload"
HELP=$T/cap_payloads
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -Werror -Itools/c4g-replay \
    -o "$HELP" tests/e2e/helpers/cap_payloads.c lib/host/c4gh_capture.c -lpcap || { echo "replay: cannot build cap_payloads"; exit 1; }
ok "every datagram of every fixture and hostile file" $CHECK oracle "$HELP" $FX/*.pcap $FX/*.pcapng $FX/bad/*.pcap

echo "3. hostile files"
hostile() {  # hostile FILE STATUS MESSAGE: summary's exit status and the first error line
    "$RP" summary "$1" >"$T/h.out" 2>"$T/h.err"; got=$?
    [ "$got" -lt 128 ] || { echo "       $1: killed by signal $((got - 128))"; return 1; }
    eq "$got" "$2" || return 1
    [ -z "$3" ] || grep -q -- "$3" "$T/h.err" || { echo "       '$3' not in: $(head -n 2 "$T/h.err")"; return 1; }
}
ok "empty file: exit 2, named" hostile $FX/bad/empty.pcap 2 "bad/empty.pcap: empty file, not a capture"
ok "text file: exit 2, its first bytes" hostile $FX/bad/text.pcap 2 "not a pcap or pcapng file (starts with 54 68 69 73)"
ok "a directory: exit 2" hostile $FX/bad 2 "is a directory, not a capture file"
ok "a missing file: exit 2" hostile "$T/none.pcap" 2 "none.pcap: No such file or directory"
ok "unknown link type: exit 2, the type named" hostile $FX/bad/linktype-user0.pcap 2 "link type 147 (unknown) is not supported"
ok "header only: exit 0 (a capture with no packets)" hostile $FX/bad/header-only.pcap 0 ""
ok "truncated record: exit 1 at packet 11, offset 4684" hostile $FX/bad/truncated-record.pcap 1 \
    "packet 11 (offset 4684): truncated dump file"
ok "truncated record header: exit 1 at packet 11" hostile $FX/bad/truncated-record-header.pcap 1 \
    "packet 11 (offset 4684): truncated dump file; tried to read 16 header bytes, only got 8"
ok "huge caplen: exit 1 at packet 11" hostile $FX/bad/caplen-huge.pcap 1 "packet 11 (offset 4684): invalid packet capture length"
ok "garbage after the header: exit 1 at packet 1, offset 24" hostile $FX/bad/garbage-after-header.pcap 1 "packet 1 (offset 24)"
ok "snaplen 64: every datagram reported cut, exit 0" hostile $FX/bad/snaplen-64.pcap 0 \
    "packet 1 (offset 24): snapshot length cut the datagram: 50 of 112 IP bytes captured"
ok "  ... the 184 cut frames counted" has "$T/h.err" "184 damaged frames in all"
ok "init packet cut by the snaplen: reported at packet 19" hostile $FX/bad/caplen-over-snaplen.pcap 0 \
    "packet 19 (offset 8412): snapshot length cut the datagram"
# the analysis goes on after the bad packets: the records before the damage are a session
"$RP" summary --json --port 46300 $FX/bad/truncated-record.pcap >"$T/tr.json" 2>/dev/null
ok "truncated record: the 10 records before it analysed, the file marked incomplete" \
    python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); f = d["files"][0]
sys.exit(not (f["frames"] == 10 and f["complete"] is False and len(d["sessions"]) == 1))' "$T/tr.json"
"$RP" summary $FX/bad/text.pcap $FX/mode0.pcap >"$T/two.out" 2>"$T/two.err"; rc=$?
ok "a bad file among good ones: the good one is still summarised (exit 2)" eq "$rc" 2
ok "  ... mode0's session in the report" has "$T/two.out" "ended by 504"

echo "4. real tcpdump captures of a c4g-sim + c4g-server session"
TCPDUMP=$(command -v tcpdump || echo /usr/sbin/tcpdump)
tcpdump_run() {  # tcpdump_run NAME IFACE PORT: capture one session of mode 0 on IFACE
    name=$1; iface=$2; port=$3
    "$TCPDUMP" -i "$iface" -U -n -w "$T/$name.pcap" "udp and port $port" >"$T/$name.td.out" 2>"$T/$name.td.err" &
    TPID=$!
    PIDS="$PIDS $TPID"
    td_up() { grep -q "listening on" "$T/$name.td.err" 2>/dev/null || ! kill -0 "$TPID" 2>/dev/null; }
    wait_until 20 td_up
    kill -0 "$TPID" 2>/dev/null || return 1
    SIM_ARGS="--axes 2" run_sim "$name" "$port" $FX/inputs/idle.scn
    # tcpdump on a loaded host lags behind the session, and what it has not read when it
    # is stopped is lost: wait (at most 20 s) until the file holds every datagram c4g-sim
    # sent and its replies (-U writes each packet as it is read)
    want=$(python3 -c 'import json, sys; print(2 * json.load(open(sys.argv[1]))["packets"]["sent"])' "$T/$name.sim.json" 2>/dev/null || echo 0)
    n=0
    while [ "$n" -lt 40 ]; do
        have=$("$RP" summary --json --no-progress "$T/$name.pcap" 2>/dev/null |
            python3 -c 'import json, sys; print(json.load(sys.stdin)["files"][0]["frames"])' 2>/dev/null || echo 0)
        [ "$have" -ge "$want" ] && break
        n=$((n + 1)); sleep 0.5
    done
    kill -INT "$TPID" 2>/dev/null
    wait "$TPID" 2>/dev/null
    return 0
}
if [ -x "$TCPDUMP" ] && "$TCPDUMP" -D >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    next_free() { p=$1; while udp_bound "$p" || udp_bound $((p + 500)); do p=$((p + 1)); done; echo "$p"; }
    P1=$(next_free $((34000 + ($$ % 300) * 3)))
    if tcpdump_run lo lo "$P1"; then
        cyc=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["packets"]["cyclic"])' "$T/lo.sim.json" 2>/dev/null)
        ok "tcpdump -i lo: one session, every cyclic packet of c4g-sim ($cyc)" \
            $CHECK live-capture "$RP" "$T/lo.pcap" EN10MB "$cyc" "$P1"
        editcap -F pcapng "$T/lo.pcap" "$T/lo.pcapng" >/dev/null 2>&1
        ok "editcap -F pcapng of it: the same session" $CHECK live-capture "$RP" "$T/lo.pcapng" EN10MB "$cyc" "$P1"
        ok "  ... and the oracle on both" $CHECK oracle "$HELP" "$T/lo.pcap" "$T/lo.pcapng"
    else
        ok "tcpdump -i lo starts" false
    fi
    P2=$(next_free $((P1 + 1)))
    if tcpdump_run any any "$P2"; then
        cyc=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["packets"]["cyclic"])' "$T/any.sim.json" 2>/dev/null)
        ok "tcpdump -i any (Linux cooked SLL2): one session ($cyc cyclic)" \
            $CHECK live-capture "$RP" "$T/any.pcap" LINUX_SLL2 "$cyc" "$P2"
        ok "  ... and the oracle" $CHECK oracle "$HELP" "$T/any.pcap"
    else
        ok "tcpdump -i any starts" false
    fi
else
    echo "  skip tcpdump captures: tcpdump missing or not allowed to capture (needs root)"
fi

echo "4b. c4g-server --pcap against the wire: the server stopped 60 ms mid-run"
# the datagrams that wait in the server's socket meanwhile must show their wire times in the
# server's own capture (kernel stamps): its missing replies are those c4g-sim counts and those
# of a tcpdump of the same run, not 0
srv_stop_run() {  # srv_stop_run PORT: $T/ss.srv.pcap, $T/ss.sim.json (and $T/ss.td.pcap)
    sp=$1
    TD=""
    if [ -x "$TCPDUMP" ] && "$TCPDUMP" -D >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
        "$TCPDUMP" -i lo -U -n -w "$T/ss.td.pcap" "udp and port $sp" >/dev/null 2>"$T/ss.td.err" &
        TD=$!
        PIDS="$PIDS $TD"
        td_up2() { grep -q "listening on" "$T/ss.td.err" 2>/dev/null || ! kill -0 "$TD" 2>/dev/null; }
        wait_until 20 td_up2
    fi
    "$SRV" -p "$sp" -b 127.0.0.1 -c 127.0.0.1 --idle-timeout 10 --max-seconds 30 --lost-timeout-ms 2000 \
        --pcap "$T/ss.srv.pcap" >"$T/ss.srv.out" 2>"$T/ss.srv.err" &
    SS=$!
    PIDS="$PIDS $SS"
    ss_up() { grep -q "listening on" "$T/ss.srv.err" 2>/dev/null || ! kill -0 "$SS" 2>/dev/null; }
    wait_until 20 ss_up
    "$SIM" --bind 127.0.0.1 --local-port $((sp + 500)) -p "$sp" -c $FX/inputs/fast.ini -S $FX/inputs/idle.scn \
        --axes 2 --max-miss 500 --json >"$T/ss.sim.json" 2>"$T/ss.sim.err" &
    SM=$!
    sleep 0.4; kill -STOP "$SS"; sleep 0.06; kill -CONT "$SS"
    wait "$SM"; wait "$SS"
    [ -z "$TD" ] || { sleep 0.5; kill -INT "$TD"; wait "$TD"; }
    return 0
}
missing_of() { "$RP" summary --json --no-progress --port "$2" "$1" 2>/dev/null |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["sessions"][0]["replies"]["missing"])' 2>/dev/null || echo none; }
next_free2() { p=$1; while udp_bound "$p" || udp_bound $((p + 500)); do p=$((p + 1)); done; echo "$p"; }
P3=$(next_free2 $((35000 + ($$ % 300) * 3)))
srv_stop_run "$P3"
m_srv=$(missing_of "$T/ss.srv.pcap" "$P3")
m_sim=$(python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))["replies"]
print("%d missing, %d unjudged" % (r["missing"], r["unjudged"]))' "$T/ss.sim.json" 2>/dev/null || echo none)
# the stop leaves ~30 packets unanswered in time (c4g-sim counted $m_sim; on a loaded host it
# calls some unjudged, its own lateness): a capture stamped after recvfrom shows none
ok "the server's own capture shows the replies the stop delayed as missing (>= 10): $m_srv (c4g-sim: $m_sim)" \
    ge "$m_srv" 10
if [ -f "$T/ss.td.pcap" ]; then
    m_td=$(missing_of "$T/ss.td.pcap" "$P3")
    ok "  ... as many as tcpdump -i lo of the same run shows ($m_td, +/- 5)" near "$m_srv" "$m_td" 5
fi

echo "5. rerun through c4g-server's core"
rerun_zero() {  # every c4g-server capture of the fixtures with its options: 0 divergences
    st=0
    grep -o '^| [a-z0-9-]*\.pcap | `SRV [0-9]*[^`]*`' $FX/README.md |
        sed 's/^| \([^ ]*\) | `SRV [0-9]*\(.*\)`/\1|\2/' >"$T/srv-fixtures"
    [ -s "$T/srv-fixtures" ] || return 1
    while IFS='|' read -r f o; do
        # shellcheck disable=SC2086
        "$RP" rerun --no-progress "$FX/$f" -- $o >"$T/rr.out" 2>&1; rc=$?
        [ "$rc" = 0 ] || { echo "       $f ($o): exit $rc: $(grep -m1 '^first\|^verdict' "$T/rr.out")"; st=1; }
    done <"$T/srv-fixtures"
    return $st
}
ok "0 divergences on every c4g-server capture ($(grep -c 'SRV [0-9]' $FX/README.md) runs) with its options" rerun_zero
"$RP" rerun --json $FX/mode4.pcap -- --sine 0.3,1,0.5 >"$T/rr4.json" 2>"$T/rr4.err"; rc=$?
ok "mode4 with another amplitude: exit 1" eq "$rc" 1
ok "  ... the first divergence is D1 of arm 1 axis 1 at tick 114 (NUM 126), the second tick of mode 4" \
    python3 -c 'import json, sys; f = json.load(open(sys.argv[1]))["first"]
sys.exit(not (f["field"] == "d1" and f["arm"] == 1 and f["axis"] == 1 and f["tick"] == 114 and f["num"] == 126))' "$T/rr4.json"
ok "  ... D1 and D2 diverge on the 6 axes of the 250 mode-4 ticks after the first, nothing else" \
    python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); c = {k: v["count"] for k, v in d["fields"].items()}
sys.exit(not (c == {"d1": 1500, "d2": 1500} and d["divergent"] == 250))' "$T/rr4.json"
"$RP" rerun --json $FX/mode1.pcap -- --hold --duration 0.5 --gains 31,200,300 >"$T/rr1.json" 2>/dev/null; rc=$?
ok "mode1 with another KP: exit 1, the first divergence is a D5 current at mode 1's first tick" \
    python3 -c 'import json, sys; f = json.load(open(sys.argv[1]))["first"]
sys.exit(not (f["field"] == "d5" and f["tick"] == 76))' "$T/rr1.json"
"$RP" rerun $FX/two-arms.pcap -- --arm 1 --axes 1,2 --sine 0.25,2,0.5 --arm 2 --offset 0.2,0.1,0.1 >"$T/rr2.out" 2>&1; rc=$?
ok "two arms, another offset on arm 2: exit 1, the first divergence on arm 2" has "$T/rr2.out" "^first divergence: .* arm 2 axis 1 (OPEN 7) d1"
"$RP" rerun --session 2 $FX/two-controllers.pcap >"$T/rr5.out" 2>&1; rc=$?
ok "two controllers, --session 2: exit 0, session 1 named as not rerun" has "$T/rr5.out" "not rerun: 1 session(s) of another controller (1)"
"$RP" rerun $FX/mode4.pcap -- --sine fast >"$T/rr6.out" 2>"$T/rr6.err"; rc=$?
ok "a bad c4g-server option: exit 2, named" eq "$rc" 2
ok "  ... the option and its value in the message" has "$T/rr6.err" "--sine: bad value 'fast'"

echo "6. export and plot"
"$RP" export $FX/mode0.pcap >"$T/m0.csv" 2>"$T/m0.err"; rc=$?
ok "export: exit 0, a header and one row per cyclic tick (159)" eq "$rc:$(($(wc -l <"$T/m0.csv") - 1))" "0:159"
ok "  ... tick 1 carries NUM 13, its reply NUM 14" eq "$(sed -n 2p "$T/m0.csv" | cut -d, -f2,6,7)" "1,13,14"
"$RP" export --moni 20 $FX/mode0.pcap >"$T/m20.csv" 2>/dev/null; rc=$?
ok "export --moni 20: exit 0, rows" eq "$rc:$([ "$(wc -l <"$T/m20.csv")" -gt 100 ] && echo rows)" "0:rows"
"$RP" export --json-lines --from 0.1 --to 0.2 $FX/mode0.pcap >"$T/m0.jl" 2>/dev/null
ok "export --json-lines --from/--to: every line JSON, inside the window" python3 -c 'import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
sys.exit(not (rows and all(0.1 <= r["time"] <= 0.2 for r in rows)))' "$T/m0.jl"
if command -v gnuplot >/dev/null 2>&1; then
    "$RP" plot --axis 1 --field d1 --output "$T/p.png" $FX/mode4.pcap >/dev/null 2>"$T/p.err"; rc=$?
    ok "plot PNG: exit 0, a PNG file" eq "$rc:$(head -c 4 "$T/p.png" | od -An -c | tr -d ' ')" '0:211PNG'
    "$RP" plot --latency --output "$T/l.svg" $FX/mode4.pcap >/dev/null 2>&1; rc=$?
    ok "plot --latency SVG: exit 0, an SVG file" eq "$rc:$(grep -c '<svg' "$T/l.svg")" "0:1"
    "$RP" plot --axis 1 --field d1,d3 --output "$T/ta.png" $FX/mode4.pcap >"$T/ta.out" 2>"$T/ta.err"; rc=$?
    ok "plot --field d1,d3 (target and actual in one plot): exit 0, a PNG, nothing on stdout" \
        eq "$rc:$(head -c 4 "$T/ta.png" | od -An -c | tr -d ' '):$(wc -c <"$T/ta.out")" '0:211PNG:0'
    "$RP" plot --axis 1 --field d1,nope $FX/mode4.pcap >/dev/null 2>"$T/tb.err"; rc=$?
    ok "  ... a bad field in the list: exit 2, named" eq "$rc:$(grep -c "bad value 'd1,nope'" "$T/tb.err")" "2:1"
    "$RP" plot --axis 1 --field d1 $FX/mode4.pcap >"$T/p.txt" 2>&1; rc=$?
    ok "plot in the terminal (text): exit 0, a drawing" eq "$rc:$([ "$(wc -l <"$T/p.txt")" -gt 10 ] && echo drawn)" "0:drawn"
else
    ok "gnuplot installed (scripts/deps.sh)" false
fi
echo "7. field-made captures (fixtures/replay/field): every verdict true"
ok "a clock step back: a clock-step finding at its frame, no tick dropped, no false missing reply" \
    $CHECK field "$RP" clock-step
ok "no session found (header only, IPv6) is exit 3, not CLEAN; mid-session captures found on any port" \
    $CHECK field "$RP" no-session
ok "rerun of a capture that starts after the init packet: a synthetic start-up, 0 divergences" \
    $CHECK field "$RP" rerun-midsession
ok "rerun: a recorded reply after the next packet is a timing difference; the first divergence is content" \
    $CHECK field "$RP" rerun-late
ok "NUM policy without an init echo in time: plus-one, no false duplicate" $CHECK field "$RP" policy
ok "every frame captured twice: said once, analysed once" $CHECK field "$RP" doubled
ok "a controller NUM near INT32_MAX: malformed, no arithmetic on it" $CHECK field "$RP" num-range
live_late() {  # live of late-replies to c4g-server with the capture's options: 3 timing differences
    lp=$(next_free2 $((P3 + 2)))
    "$SRV" -p "$lp" -b 127.0.0.1 -c 127.0.0.1 --sine 0.25,1,0.5 --persist --max-seconds 30 \
        >"$T/ll.srv.out" 2>"$T/ll.srv.err" &
    LS=$!
    PIDS="$PIDS $LS"
    ll_up() { grep -q "listening on" "$T/ll.srv.err" 2>/dev/null || ! kill -0 "$LS" 2>/dev/null; }
    wait_until 20 ll_up
    "$RP" live $FD/late-replies.pcap --to "127.0.0.1:$lp" --num-policy plus-one --topspeed --json \
        >"$T/ll.json" 2>/dev/null
    kill "$LS" 2>/dev/null; wait "$LS" 2>/dev/null
    python3 -c 'import json, sys; d = json.load(open(sys.argv[1]))["divergences"]
sys.exit(not (d["differing"] == 0 and d["timing_only"] == 3))' "$T/ll.json" ||
        { echo "       $(grep -o '"divergences": {[^}]*' "$T/ll.json" | head -c 300)"; return 1; }
}
FD=$FX/field
ok "live: the recording's late replies are timing differences, not divergences" live_late
ok "smaller: a frame lost by the capture, a reply stamped before its packet, a 10 s hole, gzip, stdin, --from > --to" \
    $CHECK field "$RP" small
ok "docs/c4g-replay.md: every example prints what the page shows" $CHECK docs "$BUILD/bin" docs/c4g-replay.md
finish
