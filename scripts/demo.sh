#!/bin/sh
# make demo: a real C4G Open session on loopback. Starts c4g-server (the PC side) and
# c4g-sim (the controller) on high ports, runs a mode-4 scenario for a few seconds
# (drive on, approach, mode 4 sine from the PC, EXIT_FROM_OPEN, drive off, 504) and
# prints both summaries. Bounded (30 s); kills what it starts.
set -u
build=${1:-build}
srv=$build/bin/c4g-server
sim=$build/bin/c4g-sim
port=${DEMO_PORT:-31070}
for b in "$srv" "$sim"; do
    [ -x "$b" ] || { echo "demo: $b not built (make all)" >&2; exit 1; }
done
tmp=$(mktemp -d "${TMPDIR:-/tmp}/c4g-demo.XXXXXX")
spid=""
cleanup() {
    [ -n "$spid" ] && kill "$spid" 2>/dev/null && wait "$spid" 2>/dev/null
    rm -rf "$tmp"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "== demo: c4g-server on 127.0.0.1:$port (mode 4: raised cosine 0.1 turns, 0.5 Hz, on every axis)"
"$srv" -p "$port" -c 127.0.0.1 --idle-timeout 10 --max-seconds 30 --sine 0.1,0.5,1 \
    --json "$tmp/server.json" >"$tmp/server.out" 2>"$tmp/server.err" &
spid=$!
i=0
while ! grep -q "listening on" "$tmp/server.err" 2>/dev/null && [ $i -lt 40 ]; do
    sleep 0.05; i=$((i + 1))
done
echo "== demo: c4g-sim running fixtures/server/sim_demo.scn (2 ms period, 6 axes, figure 10.1)"
timeout 30 "$sim" -p "$port" -S fixtures/server/sim_demo.scn -v >"$tmp/sim.out" 2>"$tmp/sim.err"
simrc=$?
i=0
while kill -0 "$spid" 2>/dev/null && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
kill "$spid" 2>/dev/null
wait "$spid"; srvrc=$?
spid=""
echo
echo "== controller (c4g-sim) events, the last 15 (Rx Debug lines left out)"
grep -v "Rx Debug" "$tmp/sim.err" | tail -n 15
echo
echo "== controller (c4g-sim) summary, exit $simrc"
cat "$tmp/sim.out"
echo
echo "== PC (c4g-server) log, the last 15 lines (axis 1's lines only; axes 2-6 log the same)"
grep -v "axis [2-9]:\|axis 1[0-9]:" "$tmp/server.err" | tail -n 15
echo
echo "== PC (c4g-server) summary, exit $srvrc"
cat "$tmp/server.out"
echo
echo "   The two sides count the same losses from each end: the simulator's 'missing' are"
echo "   packets it got no reply to by its next tick, 'stale' replies that came after that"
echo "   (to an older packet), 'late' replies after its t-cycle1 budget; the server's"
echo "   'gaps (missed N)' are controller packets that never reached it, 'duplicates' and"
echo "   'out of order' what arrived twice or behind a newer one."
echo
echo "== PC (c4g-server) JSON summary (--json), pretty-printed"
python3 -m json.tool "$tmp/server.json"
echo
echo "== identification: excite, record, fit (c4g-ident), then the same fast move in modes 0 and 9"
sh scripts/ident-loop.sh "$build" "$tmp/ident" 41690
identrc=$?
[ "$simrc" -eq 0 ] && [ "$srvrc" -eq 0 ] && [ "$identrc" -eq 0 ]
