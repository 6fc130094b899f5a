#!/bin/sh
# make demo: a real C4G Open session on loopback, then the identification loop, told in a
# few lines; every log, summary and capture is kept in BUILD/demo for a closer look.
#   1. c4g-server (the PC side) against c4g-sim (the controller) on 127.0.0.1: handshake,
#      drive on, a mode-4 raised cosine from the PC on every axis, EXIT_FROM_OPEN, drive
#      off, 504;
#   2. the identification loop (scripts/ident-loop.sh) on c4g-sim's arm plant (a coupled
#      6-axis arm simulated by MuJoCo, fixtures/sim/smart-six.xml, with the controller's own
#      dynamic model): excite, record, fit with c4g-ident --model ctrl (a correction of the
#      controller's model: the per-axis model cannot describe the arm), and the same fast
#      move in mode 0, in mode 9 with the fitted file and with a wrong one.
# Bounded; kills what it starts.
set -u
build=${1:-build}
srv=$build/bin/c4g-server
sim=$build/bin/c4g-sim
rp=$build/bin/c4g-replay
port=${DEMO_PORT:-31070}
for b in "$srv" "$sim" "$rp"; do
    [ -x "$b" ] || { echo "demo: $b not built (make all)" >&2; exit 1; }
done
out=$build/demo
rm -rf "$out" && mkdir -p "$out/session" "$out/ident" || exit 1
d=$out/session
spid=""
cleanup() { [ -n "$spid" ] && kill "$spid" 2>/dev/null && wait "$spid" 2>/dev/null; }
trap cleanup EXIT
trap 'exit 130' INT TERM
t0=$(date +%s)

echo "make demo: a C4G Open session on loopback, then the identification loop (1 to 3 minutes)"
"$srv" -p "$port" --controller 127.0.0.1 --idle-timeout 10 --max-seconds 30 --sine 0.1,0.5,1 \
    --json-out "$d/server.json" >"$d/server.txt" 2>"$d/server.log" &
spid=$!
i=0
while ! grep -q "listening on" "$d/server.log" 2>/dev/null && [ $i -lt 40 ]; do
    sleep 0.05; i=$((i + 1))
done
timeout 30 "$sim" -p "$port" -S fixtures/server/sim_demo.scn -v --pcap "$d/session.pcap" -j \
    >"$d/sim.json" 2>"$d/sim.log"
simrc=$?
i=0
while kill -0 "$spid" 2>/dev/null && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
kill "$spid" 2>/dev/null
wait "$spid"; srvrc=$?
spid=""
python3 - "$d" "$simrc" "$srvrc" "$port" <<'EOF'
import json, sys
d, simrc, srvrc, port = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
try:
    s = json.load(open(d + "/sim.json"))
    v = json.load(open(d + "/server.json"))
except (OSError, ValueError) as e:
    print("session   no summary to read (%s): see %s" % (e, d))
    sys.exit(0)
rp, pk = s.get("replies", {}), s.get("packets", {})
sent = pk.get("sent", 0)
print("session   c4g-server (PC) <-> c4g-sim (controller: figure 10.1 arm, 6 axes, 2 ms) on 127.0.0.1:%s" % port)
print("          handshake, drive on, mode 4 raised cosine on every axis, EXIT_FROM_OPEN, drive off,"
      " 504: exit %d (controller) and %d (PC)" % (simrc, srvrc))
miss = rp.get("missing", 0) + rp.get("unjudged", 0)
line = "          %d packets, %d replies in time, %d missed" % (sent, rp.get("ok", 0), miss)
if miss:
    worst = s.get("overrun_max_us") or 0.0
    line += " (%s)" % ("a busy host held the processes up: c4g-sim woke up to %.1f ms late; the protocol"
                       " survives 9 in a row" % (worst / 1000.0) if worst > 1000.0 else
                       "the host, not the protocol: 9 in a row are survived")
print(line)
saf = v.get("safety", {})
n_saf = sum(x for x in saf.values() if isinstance(x, int))
print("          safety filter events %d, malformed packets %d, foreign datagrams %d"
      % (n_saf, v.get("counters", {}).get("malformed", 0), v.get("counters", {}).get("foreign", 0)))
EOF

PLANT=${DEMO_PLANT-fixtures/sim/smart-six.xml} sh scripts/ident-loop.sh "$build" "$out/ident" 41690 \
    >"$out/ident/loop.txt" 2>&1
identrc=$?
o=$out/ident
if [ $identrc -eq 0 ] && [ -f "$o/loop.json" ]; then
    "$rp" follow --axes 1-3 --json --no-progress "$o/move0.pcap" "$o/move9.pcap" "$o/wrong9.pcap" >"$o/follow.json" 2>/dev/null
    "$rp" follow --axes 1-3 --per-axis --no-progress "$o/move0.pcap" "$o/move9.pcap" "$o/wrong9.pcap" >"$o/follow.txt" 2>&1
    python3 - "$o" <<'EOF'
import json, sys
o = sys.argv[1]
L, F = json.load(open(o + "/loop.json")), json.load(open(o + "/fit.json"))
axes = [a for a in F.get("axes", []) if a.get("identifiable", True)]
left = ["%d (%s)" % (a["axis"], a.get("why", "")) for a in F.get("axes", []) if not a.get("identifiable", True)]
worst = max((a.get("validation", {}).get("x_noise") or 0.0) for a in axes) if axes else 0.0
print("identify  the arm plant (MuJoCo, 6 coupled axes): 20 s excitation on axes 1-3 in mode 4, captured,")
print("          fitted by c4g-ident --model ctrl (a per-axis correction of the controller's own model,"
      " EXT1/EXT2):\n          %s identified, held-out current error at most %.2fx the noise floor"
      " (%s/fit.txt)" % (("axes " + ", ".join(str(a["axis"]) for a in axes)) if len(axes) != 1
                         else "axis %d" % axes[0]["axis"], worst, o))
for l in left:
    print("          axis %s: left out of the file; mode 9 gives it the controller's model (--ff-ext1)" % l)
try:
    C = json.load(open(o + "/follow.json"))["captures"]
except (OSError, ValueError, KeyError):
    C = []
def than(x, ref):
    """x against mode 0's figure, in the words that read right either way"""
    return ("%.1fx smaller" % (ref / max(x, 1e-12))) if x <= ref else ("%.1fx larger" % (x / max(ref, 1e-12)))
if len(C) == 3:
    m0, m9, w9 = (c["follow_rms"] for c in C)
    print("move      the same fast move, following error RMS: mode 0 (the controller's own model as feedforward)"
          " %.3g turn,\n          mode 9 with the fitted file %.3g (%s), with a deliberately wrong file"
          " (inertia x2.5, friction x2) %.3g (%s)" % (m0, m9, than(m9, m0), w9, than(w9, m0)))
    if m9 > m0 / 2.0:
        print("          mode 9 is not clearly better than the controller's own model here: see the fit's"
              " refusals and\n          warnings in %s/loop.txt, and docs/c4g-ident.md on the two families" % o)
    late = C[1]["mode9_late"]
    if late:
        print("          %d of the %d mode-9 ticks had no addition by the deadline: a loaded host delays the PC's"
              " replies, and the figure then measures the scheduler too" % (late, C[1]["mode9_ticks"]))
EOF
    sed -n '/== fit against/,/^$/p' "$o/loop.txt" >"$o/fit.txt"
else
    echo "identify  the loop failed (exit $identrc): $o/loop.txt says where"
fi
echo "details   $out/: session/ (server.log, sim.log, server.json, sim.json, session.pcap),"
echo "          ident/ (loop.txt, fit.json, arm1.ini, the captures, follow.txt); $(($(date +%s) - t0)) s in all"
echo "next      $rp summary $d/session.pcap"
echo "          $rp follow --per-axis $o/move0.pcap $o/move9.pcap; docs/c4g-ident.md walks the loop by hand"
[ "$simrc" -eq 0 ] && [ "$srvrc" -eq 0 ] && [ "$identrc" -eq 0 ]
