#!/bin/sh
# c4g-ident end to end on loopback (scripts/ident-loop.sh): excitation trajectory, a real
# c4g-server + c4g-sim identification run captured, the fit against c4g-sim's truth, the
# parameter file applied by c4g-server's mode 9 on a fast move (against mode 0 and a wrong
# file); then the same fit from the server's moni CSV and c4g-replay's export CSV, plots,
# a still axis, and hostile inputs.
set -u
B=${1:?usage: sh tests/e2e/ident.sh BUILD_DIR}
ID=$B/bin/c4g-ident
fail() { echo "FAIL: $*"; exit 1; }
[ -x "$ID" ] || fail "$ID not built"
T=$(mktemp -d "${TMPDIR:-/tmp}/c4gident.XXXXXX")
trap 'rm -rf "$T"' EXIT
trap 'exit 1' INT TERM
rc=0
ok() { echo "ok: $*"; }
bad() { echo "FAIL: $*"; rc=1; }

# the loop (a session the host disturbed is run again inside it)
sh scripts/ident-loop.sh "$B" "$T/loop" 41620 >"$T/loop.out" 2>&1 \
  || { cat "$T/loop.out"; fail "ident-loop"; }
sed -n '/== fit against/,$p' "$T/loop.out"
python3 - "$T/loop/loop.json" "$T/loop/fit.json" <<'PY' || rc=1
import json, sys
L = json.load(open(sys.argv[1])); F = json.load(open(sys.argv[2]))
bad = []
# one run on loopback, possibly beside busy loops that disturb its sessions: the gross limits
# here; the accuracy figures come from the in-process harness (tests/ident/accuracy.cpp)
lim = {'Ja': 5.0, 'gb': 2.0}
for ax in L['axes']:
    for k, p in ax['parameters'].items():
        if k in lim and abs(p['error_pct']) > lim[k]:
            bad.append('axis %d %s error %.3f %% > %.1f %%' % (ax['axis'], k, p['error_pct'], lim[k]))
    if ax['validation_x_noise'] is None or ax['validation_x_noise'] > 1.5:
        bad.append('axis %d held-out RMS %s x noise' % (ax['axis'], ax['validation_x_noise']))
v = {a['axis']: a['variant'] for a in F['axes']}
if 'gravity' not in (v.get(2) or ''): bad.append('axis 2 variant %s, want a gravity variant' % v.get(2))
m = L['moves']
if L['follow_ratio'] < 5.0: bad.append('following error mode 0 / mode 9 only %.2fx' % L['follow_ratio'])
if L['dsa_ratio'] < 5.0: bad.append('DSA current mode 0 / mode 9 only %.2fx' % L['dsa_ratio'])
if m['wrong9']['follow_rms'] < 2.0 * m['move9']['follow_rms']:
    bad.append('the wrong file does not follow worse: %s vs %s' % (m['wrong9'], m['move9']))
if m['wrong9']['dsa_current_rms'] < 2.0 * m['move9']['dsa_current_rms']:
    bad.append('the wrong file is not worse: %s vs %s' % (m['wrong9'], m['move9']))
for b in bad: print('FAIL: ' + b)
sys.exit(1 if bad else 0)
PY
[ $rc -eq 0 ] && ok "fit within limits of the truth, variants chosen, mode-9 feedforward cuts the following error 5x or more"

# the server applied the file: its summary counts identified-model ticks
grep -q "mode-9 identified model: [1-9]" "$T/loop/move9.srv.out" && ok "c4g-server applied arm1.ini" || bad "no identified-model ticks in c4g-server's summary"

# the same run from c4g-replay's export and from the moni CSV: the same Ja on axis 1. The
# export carries each reply's latency, so its fit drops the ticks after a late reply as the
# capture's does; the moni CSV does not say when the controller got a reply, so it is held
# against the capture fitted with --keep-late. A busy host makes late replies, and the two
# comparisons stay exact however many there are.
"$ID" fit "$T/loop/ident.csv" --axes 1 --json >"$T/export.json" || bad "fit of the export CSV"
"$ID" fit "$T/loop/ident.moni.csv" --axes 1 --json >"$T/moni.json" || bad "fit of the moni CSV"
"$ID" fit "$T/loop/ident.pcap" --axes 1 --keep-late --json >"$T/keep.json" || bad "fit of the capture, --keep-late"
# A CSV does not carry the current limit (AzLim) the capture's init packet gives: without it
# the ticks at the limit stay in (on a loaded host, a stall drives the current there).
# --az-lim gives it; the moni fit then drops what the capture's fit drops.
AZ=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["axes"][0]["az_lim"])' "$T/keep.json")
"$ID" fit "$T/loop/ident.moni.csv" --axes 1 --az-lim "1:$AZ" --json >"$T/moni_az.json" || bad "fit of the moni CSV, --az-lim"
for v in "1:0|'0' is not a current limit in A (0..1000)" "x|'x' is not a current limit" \
         "nan|'nan' is not a current limit" "11:3|'11' is not a logical axis 1..10" \
         "1:2,3|'3': want A for every axis, or AXIS:A pairs"; do
    arg=${v%%|*}; why=${v#*|}
    "$ID" fit "$T/loop/ident.moni.csv" --az-lim "$arg" >/dev/null 2>"$T/az.err"; azrc=$?
    [ "$azrc" = 2 ] && grep -qF "c4g-ident fit: --az-lim: bad value '$arg' ($why" "$T/az.err" &&
        ok "--az-lim $arg: exit 2, named" || bad "--az-lim $arg: exit $azrc, $(cat "$T/az.err")"
done
# one reply taken out of the export, in the middle of 61 ticks of axis 1 in motion whose
# replies all came in time (else its neighbours may be dropped already): that tick and its
# neighbours leave the fit
python3 - "$T/loop/ident.csv" "$T/lost1.csv" <<'PY' || bad "no stretch of replies in time to take one out of"
import sys
rows = open(sys.argv[1]).read().split('\n')
hdr = rows[0].split(','); pf, lu, v = hdr.index('pc_frame'), hdr.index('latency_us'), hdr.index('c1_d4')
f = [r.split(',') for r in rows[1:] if r]
ok = [x[pf] != '' and float(x[lu]) <= 2000.0 and abs(float(x[v])) > 0.002 for x in f]
k = next(k for k in range(len(f) // 2, len(f) - 30) if all(ok[k - 30:k + 31]))
f[k][pf] = f[k][lu] = ''
open(sys.argv[2], 'w').write('\n'.join([rows[0]] + [','.join(x) for x in f]) + '\n')
PY
"$ID" fit "$T/lost1.csv" --axes 1 --json >"$T/lost1.json" || bad "fit of the export without one reply"
# the server's log ring may drop rows when its writer is held up: the moni CSV then lacks them
DROPS=$(sed -n 's/.*log records dropped \([0-9]*\).*/\1/p' "$T/loop/ident.srv.out")
python3 - "$T/loop/fit.json" "$T/export.json" "$T/keep.json" "$T/moni.json" "$T/lost1.json" "$T/moni_az.json" "${DROPS:-0}" <<'PY' || rc=1
import json, sys
cap, exp, keep, moni, lost1, moni_az = [json.load(open(p)) for p in sys.argv[1:7]]
drops = int(sys.argv[7])
ja = lambda d: d['axes'][0]['parameters']['Ja']['value']
late = lambda d: d['axes'][0]['ticks']['late_reply']
sat = lambda d: d['axes'][0]['ticks']['saturated']
az = lambda d: (d['axes'][0]['az_lim'], d['axes'][0]['az_lim_from'])
bad = []
if az(cap)[1] != 'init packet' or az(moni) != (None, 'none') or az(moni_az) != (az(cap)[0], '--az-lim'):
    bad.append('current limits: capture %s, moni %s, moni --az-lim %s' % (az(cap), az(moni), az(moni_az)))
if drops == 0 and sat(moni_az) != sat(keep):
    bad.append('saturated ticks: moni --az-lim %d, capture --keep-late %d' % (sat(moni_az), sat(keep)))
if abs(ja(exp) - ja(cap)) > 5e-3 * abs(ja(cap)):
    bad.append('export CSV Ja %s, capture %s' % (ja(exp), ja(cap)))
# the export carries no AzLim: the capture's saturated ticks count there as other drops
if abs(late(exp) - late(cap)) > cap['axes'][0]['ticks']['saturated'] + 5:
    bad.append('ticks dropped after a late reply: export %d, capture %d' % (late(exp), late(cap)))
# 2 %: the moni CSV is the server's own record, and one loaded run differed from the
# capture by 0.9 % even with the late ticks kept in both (cause not yet found)
# (the saturated ticks the CSV kept are one candidate: --az-lim now drops them)
if abs(ja(moni_az) - ja(keep)) > 2e-2 * abs(ja(keep)) or late(moni_az) != 0 or late(keep) != 0:
    bad.append('moni CSV Ja %s (late %d), capture --keep-late %s (late %d)' % (ja(moni_az), late(moni_az), ja(keep), late(keep)))
if moni['inputs'][0]['reply_times'] or not exp['inputs'][0]['reply_times']:
    bad.append('reply_times: moni %s, export %s' % (moni['inputs'][0]['reply_times'], exp['inputs'][0]['reply_times']))
if late(lost1) <= late(exp):
    bad.append('a reply taken out of the export dropped no tick (%d vs %d)' % (late(lost1), late(exp)))
for b in bad: print('FAIL: ' + b)
if bad: sys.exit(1)
print('ok: Ja from the capture %s = export CSV %s (%d vs %d ticks after late replies dropped); '
      'moni CSV --az-lim %s (without: %s) = capture --keep-late %s, %d saturated ticks dropped in both; '
      'a missing reply drops %d more ticks'
      % (ja(cap), ja(exp), late(cap), late(exp), ja(moni_az), ja(moni), ja(keep), sat(keep), late(lost1) - late(exp)))
PY

# plots: PNG and SVG of each axis
for f in current residual friction; do
  for e in png svg; do [ -s "$T/loop/plots/arm1_axis1_$f.$e" ] || bad "plot $f.$e missing"; done
done
head -c 8 "$T/loop/plots/arm1_axis2_current.png" | od -An -c | grep -q "P   N   G" && ok "plots written" || bad "not a PNG"

# --samples: one CSV per axis, as many rows as the report's kept ticks, refitted to the same Ja
"$B/bin/c4g-ident" fit "$T/loop/ident.pcap" --axes 1 --json --samples "$T/smp" >"$T/smp.json" || bad "--samples run"
python3 - "$T/smp.json" "$T/smp/arm1_axis1.csv" <<'PY' && ok "--samples: the fitted samples, one row per kept tick" || bad "--samples"
import json, sys
a = json.load(open(sys.argv[1]))['axes'][0]
rows = open(sys.argv[2]).read().splitlines()
assert rows[0].startswith('# c4g-ident samples: arm 1 axis 1 variant ' + a['variant']), rows[0]
assert rows[1] == 'v,a,i,cos_q,sin_q', rows[1]
assert len(rows) - 2 == a['ticks']['kept'], (len(rows) - 2, a['ticks']['kept'])
assert all(len(r.split(',')) == 5 for r in rows[2:])
PY

# a still axis (4 never moved): reported unidentifiable, exit 3, nothing fitted
"$ID" fit "$T/loop/ident.pcap" --axes 4 >"$T/still.out" 2>&1; r=$?
[ $r -eq 3 ] && grep -q "UNIDENTIFIABLE: the axis hardly moved" "$T/still.out" && ok "still axis unidentifiable (exit 3)" || { cat "$T/still.out"; bad "still axis: exit $r"; }

# hostile inputs: exit 2, one line naming the file and what was wrong
printf 't_s,num,axis,arm,logical,rx_mode,rx_d1,rx_d2,rx_d3,rx_d4,rx_d5,rx_e1,rx_e2,rx_e3,tx_infpar,tx_mode,tx_d1,tx_d2,tx_d3,tx_d4,tx_d5\n0.002,1,1,1,1,0,1,2,3,4,zz,0,0,0,0,0,0,0,0,0,0\n' >"$T/bad.csv"
"$ID" fit "$T/bad.csv" 2>"$T/err"; r=$?
[ $r -eq 2 ] && grep -q "bad.csv:2: field 11 (rx_d5): 'zz' is not a number" "$T/err" && ok "bad CSV value named" || { cat "$T/err"; bad "bad CSV: exit $r"; }
awk -F, -v OFS=, 'NR == 3 { $8 = "1e" } { print }' "$T/loop/ident.csv" >"$T/badlat.csv"
"$ID" fit "$T/badlat.csv" 2>"$T/err"; r=$?
[ $r -eq 2 ] && grep -q "badlat.csv:3: field latency_us: '1e' is not a number" "$T/err" && ok "bad latency in an export named" || { cat "$T/err"; bad "bad latency: exit $r"; }
printf 'hello\n' >"$T/junk.txt"
"$ID" fit "$T/junk.txt" 2>"$T/err"; r=$?
[ $r -eq 2 ] && grep -q "junk.txt:1: not a capture" "$T/err" && ok "junk refused" || { cat "$T/err"; bad "junk: exit $r"; }
"$ID" fit "$T/nonexistent.pcap" 2>"$T/err"; r=$?
[ $r -eq 2 ] && grep -q "nonexistent.pcap" "$T/err" && ok "missing file named" || { cat "$T/err"; bad "missing: exit $r"; }
head -c 3000 "$T/loop/ident.pcap" >"$T/cut.pcap"
"$ID" fit "$T/cut.pcap" >/dev/null 2>"$T/err"; r=$?
[ $r -ne 0 ] && [ $r -ne 139 ] && ok "cut capture: exit $r, no crash" || bad "cut capture: exit $r"
"$ID" excite --duration 100 -o "$T/x.csv" 2>"$T/err"; r=$?
[ $r -eq 2 ] && grep -q "at most 20000" "$T/err" && ok "excite refuses more rows than --traj reads" || bad "excite rows: exit $r"
"$ID" fit --bogus x 2>"$T/err"; r=$?
[ $r -eq 2 ] && ok "bad option exit 2" || bad "bad option: exit $r"
# an edited parameter file: c4g-server refuses it at start-up
sed 's/^Ja = /Ja = 1/' "$T/loop/arm1.ini" >"$T/edited.ini"
"$B/bin/c4g-server" -p 41640 --ff "$T/edited.ini" --max-seconds 1 >/dev/null 2>"$T/err"; r=$?
[ $r -ne 0 ] && grep -q "checksum" "$T/err" && ok "edited parameter file refused by c4g-server (exit $r)" || { cat "$T/err"; bad "edited file: exit $r"; }
exit $rc
