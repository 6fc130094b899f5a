# SPDX-License-Identifier: MIT
"""c4g-ident end to end on loopback (scripts/ident-loop.sh): excitation trajectory, a real
c4g-server + c4g-sim identification run captured, the fit against c4g-sim's truth, the
parameter file applied by c4g-server's mode 9 on a fast move (against mode 0 and a wrong
file); then the same fit from the server's moni CSV and c4g-replay's export CSV, plots, a
still axis, and hostile inputs."""
import json
import re
import subprocess
from concurrent.futures import ThreadPoolExecutor

import pytest

from e2e_extra import Checks, forget, once
from e2elib import host_disturbed, read_json


@pytest.fixture
def loop(build, ports, tmp_path_factory):
    """the loop's output directory, made once for the module's tests (a session the host
    disturbed is run again inside it)"""
    return once("ident loop", lambda: run_loop(build, ports.udp(), tmp_path_factory.mktemp("ident") / "loop"))


def run_loop(build, port, out):
    r = subprocess.run(["sh", "scripts/ident-loop.sh", str(build), str(out), str(port)],
                       capture_output=True, text=True, timeout=480)
    text = r.stdout + r.stderr
    # the figures the loop printed, and the sessions it ran again, in the test's output
    print("\n".join(l for l in text.splitlines() if l.startswith("ident-loop:")))
    print(text[text.find("== fit against"):] if "== fit against" in text else text)
    assert r.returncode == 0, "ident-loop: exit %d:\n%s" % (r.returncode, text[-3000:])
    (out / "loop.out").write_text(text)
    return out


def fit(build, *args):
    r = subprocess.run([str(build / "bin" / "c4g-ident"), "fit"] + [str(a) for a in args],
                       capture_output=True, text=True, timeout=120)
    return r


def fit_json(build, *args):
    r = fit(build, *args, "--json")
    assert r.returncode == 0, "c4g-ident fit %s: exit %d: %s" % (args, r.returncode, r.stderr)
    return json.loads(r.stdout)


def test_fit_and_feedforward(loop):
    """fit within limits of the truth, variants chosen, mode-9 feedforward cuts the following
    error 5x or more"""
    L, F = read_json(loop / "loop.json"), read_json(loop / "fit.json")
    ck = Checks()
    # one run on loopback, possibly beside busy loops that disturb its sessions: the gross
    # limits here; the accuracy figures come from the in-process harness (tests/ident/accuracy.cpp)
    lim = {"Ja": 5.0, "gb": 2.0}
    for ax in L["axes"]:
        for k, p in ax["parameters"].items():
            if k in lim:
                ck.ok("axis %d %s error %.3f %% within %.1f %%" % (ax["axis"], k, p["error_pct"], lim[k]),
                      abs(p["error_pct"]) <= lim[k])
        vx = ax["validation_x_noise"]
        ck.ok("axis %d held-out RMS %s x noise <= 1.5" % (ax["axis"], vx), vx is not None and vx <= 1.5)
    # the loop measures a mode-9 move again while the host disturbs it (late replies, or a
    # move that follows less than 5x better than mode 0), 6 times at most, then keeps the
    # last one and says so: such a move measured the host, not the feedforward
    kept = [l for l in (loop / "loop.out").read_text().splitlines() if l.startswith("ident-loop:") and "kept" in l]
    if kept and (L["follow_ratio"] < 5.0 or L["dsa_ratio"] < 5.0):
        forget("ident loop")
        host_disturbed(True, "following error ratio %.2f, DSA ratio %.2f after: %s"
                       % (L["follow_ratio"], L["dsa_ratio"], "; ".join(kept)))
    v = {a["axis"]: a["variant"] for a in F["axes"]}
    ck.ok("axis 2 variant %s is a gravity variant" % v.get(2), "gravity" in (v.get(2) or ""))
    m = L["moves"]
    ck.ge("following error mode 0 / mode 9", L["follow_ratio"], 5.0)
    ck.ge("DSA current mode 0 / mode 9", L["dsa_ratio"], 5.0)
    ck.ok("the wrong file follows worse (2x)", m["wrong9"]["follow_rms"] >= 2.0 * m["move9"]["follow_rms"],
          "%s vs %s" % (m["wrong9"], m["move9"]))
    ck.ok("the wrong file's DSA current is worse (2x)",
          m["wrong9"]["dsa_current_rms"] >= 2.0 * m["move9"]["dsa_current_rms"], "%s vs %s" % (m["wrong9"], m["move9"]))
    # the server applied the file: its summary counts identified-model ticks
    ck.has("c4g-server applied arm1.ini", (loop / "move9.srv.out").read_text(), "mode-9 identified model: [1-9]")
    ck.done()


def test_csv_fits(build, loop, tmp_path):
    """the same run from c4g-replay's export and from the moni CSV: the same Ja on axis 1.
    The export carries each reply's latency, so its fit drops the ticks after a late reply as
    the capture's does; the moni CSV does not say when the controller got a reply, so it is
    held against the capture fitted with --keep-late. A busy host makes late replies, and the
    two comparisons stay exact however many there are."""
    # one reply taken out of the export, in the middle of 61 ticks of axis 1 in motion whose
    # replies all came in time (else its neighbours may be dropped already): that tick and its
    # neighbours leave the fit
    rows = (loop / "ident.csv").read_text().split("\n")
    hdr = rows[0].split(",")
    pf, lu, vi = hdr.index("pc_frame"), hdr.index("latency_us"), hdr.index("c1_d4")
    f = [r.split(",") for r in rows[1:] if r]
    good = [x[pf] != "" and float(x[lu]) <= 2000.0 and abs(float(x[vi])) > 0.002 for x in f]
    k = next((k for k in range(len(f) // 2, len(f) - 30) if all(good[k - 30:k + 31])), None)
    assert k is not None, "no stretch of replies in time to take one out of"
    f[k][pf] = f[k][lu] = ""
    (tmp_path / "lost1.csv").write_text("\n".join([rows[0]] + [",".join(x) for x in f]) + "\n")
    # A CSV does not carry the current limit (AzLim) the capture's init packet gives: without
    # it the ticks at the limit stay in (on a loaded host, a stall drives the current there).
    # --az-lim gives it; the moni fit then drops what the capture's fit drops.
    az_cap = read_json(loop / "fit.json")["axes"][0]["az_lim"]
    # the five fits two at a time (each one process, CPU-bound)
    with ThreadPoolExecutor(max_workers=2) as pool:
        exp, moni, keep, moni_az, lost1 = pool.map(lambda a: fit_json(build, *a), [
            (loop / "ident.csv", "--axes", 1), (loop / "ident.moni.csv", "--axes", 1),
            (loop / "ident.pcap", "--axes", 1, "--keep-late"),
            (loop / "ident.moni.csv", "--axes", 1, "--az-lim", "1:%s" % az_cap),
            (tmp_path / "lost1.csv", "--axes", 1)])
    assert keep["axes"][0]["az_lim"] == az_cap, (keep["axes"][0]["az_lim"], az_cap)
    cap = read_json(loop / "fit.json")
    # the server's log ring may drop rows when its writer is held up: the moni CSV then lacks them
    m = re.search(r"log records dropped (\d+)", (loop / "ident.srv.out").read_text())
    drops = int(m.group(1)) if m else 0

    def ja(d):
        return d["axes"][0]["parameters"]["Ja"]["value"]

    def late(d):
        return d["axes"][0]["ticks"]["late_reply"]

    def sat(d):
        return d["axes"][0]["ticks"]["saturated"]

    def az(d):
        return (d["axes"][0]["az_lim"], d["axes"][0]["az_lim_from"])

    ck = Checks()
    ck.ok("current limits: capture from the init packet, moni none, moni --az-lim the capture's",
          az(cap)[1] == "init packet" and az(moni) == (None, "none") and az(moni_az) == (az(cap)[0], "--az-lim"),
          "capture %s, moni %s, moni --az-lim %s" % (az(cap), az(moni), az(moni_az)))
    if drops == 0:
        ck.eq("saturated ticks: moni --az-lim = capture --keep-late", sat(moni_az), sat(keep))
    ck.ok("export CSV Ja = capture's (0.5 %)", abs(ja(exp) - ja(cap)) <= 5e-3 * abs(ja(cap)),
          "export %s, capture %s" % (ja(exp), ja(cap)))
    # the export carries no AzLim: the capture's saturated ticks count there as other drops
    ck.ok("ticks dropped after a late reply: export = capture (+ saturated + 5)",
          abs(late(exp) - late(cap)) <= cap["axes"][0]["ticks"]["saturated"] + 5,
          "export %d, capture %d" % (late(exp), late(cap)))
    # 2 %: the moni CSV is the server's own record, and one loaded run differed from the
    # capture by 0.9 % even with the late ticks kept in both (cause not yet found)
    # (the saturated ticks the CSV kept are one candidate: --az-lim now drops them)
    ck.ok("moni CSV --az-lim Ja = capture --keep-late (2 %), no late ticks in either",
          abs(ja(moni_az) - ja(keep)) <= 2e-2 * abs(ja(keep)) and late(moni_az) == 0 and late(keep) == 0,
          "moni %s (late %d), capture --keep-late %s (late %d)" % (ja(moni_az), late(moni_az), ja(keep), late(keep)))
    ck.ok("reply_times: none in the moni CSV, some in the export",
          not moni["inputs"][0]["reply_times"] and exp["inputs"][0]["reply_times"],
          (moni["inputs"][0]["reply_times"], exp["inputs"][0]["reply_times"]))
    ck.ok("a reply taken out of the export drops ticks", late(lost1) > late(exp), (late(lost1), late(exp)))
    print("Ja from the capture %s = export CSV %s (%d vs %d ticks after late replies dropped); moni CSV --az-lim %s "
          "(without: %s) = capture --keep-late %s, %d saturated ticks dropped in both; a missing reply drops %d more"
          % (ja(cap), ja(exp), late(cap), late(exp), ja(moni_az), ja(moni), ja(keep), sat(keep), late(lost1) - late(exp)))
    ck.done()


@pytest.mark.parametrize("arg,why", [("1:0", "'0' is not a current limit in A (0..1000)"),
                                     ("x", "'x' is not a current limit"), ("nan", "'nan' is not a current limit"),
                                     ("11:3", "'11' is not a logical axis 1..10"),
                                     ("1:2,3", "'3': want A for every axis, or AXIS:A pairs")])
def test_az_lim_refused(build, loop, arg, why):
    r = fit(build, loop / "ident.moni.csv", "--az-lim", arg)
    assert r.returncode == 2 and ("c4g-ident fit: --az-lim: bad value '%s' (%s" % (arg, why)) in r.stderr, \
        (r.returncode, r.stderr)


def test_plots_and_samples(build, loop, tmp_path):
    ck = Checks()
    # plots: PNG and SVG of each axis
    for f in ("current", "residual", "friction"):
        for e in ("png", "svg"):
            p = loop / "plots" / ("arm1_axis1_%s.%s" % (f, e))
            ck.ok("plot %s.%s written" % (f, e), p.exists() and p.stat().st_size > 0)
    ck.eq("a PNG", (loop / "plots" / "arm1_axis2_current.png").read_bytes()[1:4], b"PNG")
    # --samples: one CSV per axis, as many rows as the report's kept ticks
    a = fit_json(build, loop / "ident.pcap", "--axes", 1, "--samples", tmp_path / "smp")["axes"][0]
    rows = (tmp_path / "smp" / "arm1_axis1.csv").read_text().splitlines()
    ck.ok("--samples: its header names the axis and variant",
          rows[0].startswith("# c4g-ident samples: arm 1 axis 1 variant " + a["variant"]), rows[0])
    ck.eq("--samples: the columns", rows[1], "v,a,i,cos_q,sin_q")
    ck.eq("--samples: one row per kept tick", len(rows) - 2, a["ticks"]["kept"])
    ck.ok("--samples: five values a row", all(len(r.split(",")) == 5 for r in rows[2:]))
    # a still axis (4 never moved): reported unidentifiable, exit 3, nothing fitted
    r = fit(build, loop / "ident.pcap", "--axes", 4)
    ck.ok("still axis unidentifiable (exit 3)", r.returncode == 3 and "UNIDENTIFIABLE: the axis hardly moved" in
          r.stdout + r.stderr, (r.returncode, r.stdout + r.stderr))
    ck.done()


def test_hostile_inputs(build, bins, ports, loop, tmp_path):
    """exit 2, one line naming the file and what was wrong"""
    ck = Checks()
    bad = tmp_path / "bad.csv"
    bad.write_text("t_s,num,axis,arm,logical,rx_mode,rx_d1,rx_d2,rx_d3,rx_d4,rx_d5,rx_e1,rx_e2,rx_e3,tx_infpar,tx_mode,"
                   "tx_d1,tx_d2,tx_d3,tx_d4,tx_d5\n0.002,1,1,1,1,0,1,2,3,4,zz,0,0,0,0,0,0,0,0,0,0\n")
    r = fit(build, bad)
    ck.ok("bad CSV value named", r.returncode == 2 and "bad.csv:2: field 11 (rx_d5): 'zz' is not a number" in r.stderr,
          (r.returncode, r.stderr))
    lines = (loop / "ident.csv").read_text().split("\n")
    f = lines[2].split(",")
    f[7] = "1e"
    lines[2] = ",".join(f)
    (tmp_path / "badlat.csv").write_text("\n".join(lines))
    r = fit(build, tmp_path / "badlat.csv")
    ck.ok("bad latency in an export named",
          r.returncode == 2 and "badlat.csv:3: field latency_us: '1e' is not a number" in r.stderr, (r.returncode, r.stderr))
    (tmp_path / "junk.txt").write_text("hello\n")
    r = fit(build, tmp_path / "junk.txt")
    ck.ok("junk refused", r.returncode == 2 and "junk.txt:1: not a capture" in r.stderr, (r.returncode, r.stderr))
    r = fit(build, tmp_path / "nonexistent.pcap")
    ck.ok("missing file named", r.returncode == 2 and "nonexistent.pcap" in r.stderr, (r.returncode, r.stderr))
    (tmp_path / "cut.pcap").write_bytes((loop / "ident.pcap").read_bytes()[:3000])
    r = fit(build, tmp_path / "cut.pcap")
    ck.ok("cut capture: an error exit, no crash", r.returncode not in (0, 139) and r.returncode > 0,
          (r.returncode, r.stderr))
    r = subprocess.run([str(bins.ident), "excite", "--duration", "100", "-o", str(tmp_path / "x.csv")],
                       capture_output=True, text=True)
    ck.ok("excite refuses more rows than --traj reads", r.returncode == 2 and "at most 20000" in r.stderr,
          (r.returncode, r.stderr))
    r = fit(build, "--bogus", "x")
    ck.eq("bad option exit", r.returncode, 2)
    # an edited parameter file: c4g-server refuses it at start-up
    text = (loop / "arm1.ini").read_text()
    (tmp_path / "edited.ini").write_text(re.sub(r"(?m)^Ja = ", "Ja = 1", text))
    r = subprocess.run([str(bins.server), "-p", str(ports.udp()), "--ff", str(tmp_path / "edited.ini"),
                        "--max-seconds", "1"], capture_output=True, text=True, timeout=30)
    ck.ok("edited parameter file refused by c4g-server", r.returncode != 0 and "checksum" in r.stderr,
          (r.returncode, r.stderr))
    ck.done()


# ---- honest answers: synthetic logs with a known truth, written as the tools write them
# (no loop needed). The plant: i = Ja*a + Fv*v + Fc*sign(v) + off (+ gravity), the current
# read at the middle of each tick (a delay of -0.5), white noise 0.02 A.

TRUTH = {"Ja": 0.003, "Fv": 0.008, "Fc": 0.15, "off": 0.02}
MONI_HDR = ("t_s,num,axis,arm,logical,rx_mode,rx_d1,rx_d2,rx_d3,rx_d4,rx_d5,rx_e1,rx_e2,rx_e3,tx_infpar,"
            "tx_mode,tx_d1,tx_d2,tx_d3,tx_d4,tx_d5")
EXPORT_HDR = ("session,tick,time,ctrl_frame,pc_frame,ctrl_num,pc_num,latency_us,ctrl_infpar,ctrl_cmd,pc_infpar,pc_cmd,"
              "c1_mode,c1_d1,c1_d2,c1_d3,c1_d4,c1_d5,c1_ext1,c1_ext2,c1_ext3")


def plant(seconds=30.0, vamp=10.0, seed=1, noise=0.02, gravity=0.0, tx=100.0, sines=8, f0=0.2, shape=None):
    """t, D3, D4 and D5 of one axis moved by a multi-sine of speed amplitude vamp [turn/s]
    (shape "triangle": constant speed vamp both ways, no acceleration but at the reversals)"""
    np = pytest.importorskip("numpy")
    T = 0.002
    rng = np.random.default_rng(seed)
    n = int(seconds / T)
    k = np.arange(n + 1)
    f = f0 * np.arange(1, sines + 1)
    ph = rng.uniform(0, 2 * np.pi, sines)
    amp = vamp / (2 * np.pi * f) / np.sqrt(sines)

    def pva(t):
        if shape == "triangle":
            per = 4.0
            u = (t / per) % 1.0
            up = u < 0.5
            p = np.where(up, vamp * per * u, vamp * per * (1.0 - u))
            return p, np.where(up, vamp, -vamp), np.zeros_like(t)
        w = 2 * np.pi * f[:, None]
        x = w * t[None, :] + ph[:, None]
        return ((amp[:, None] * np.sin(x)).sum(0), (amp[:, None] * w * np.cos(x)).sum(0),
                (-amp[:, None] * w * w * np.sin(x)).sum(0))

    p, _, _ = pva(k * T)
    pd, v, a = pva((k - 0.5) * T)
    i = (TRUTH["Ja"] * a + TRUTH["Fv"] * v + TRUTH["Fc"] * np.tanh(v / 1e-3) + TRUTH["off"]
         + gravity * np.sin(2 * np.pi * pd / tx) + noise * rng.standard_normal(n + 1))
    return k[1:] * T, p[1:], np.diff(p), i[1:]


def write_moni(path, log, keep=None):
    t, d3, d4, d5 = log
    with open(path, "w") as fh:
        fh.write(MONI_HDR + "\n")
        for j in range(len(t)):
            if keep is None or keep[j]:
                fh.write("%.6f,%d,1,1,1,4,%.9g,0,%.9g,%.9g,%.9g,0,0,0,0,0,0,0,0,0,0\n"
                         % (t[j], (j + 1) % 32768, d3[j], d3[j], d4[j], d5[j]))
    return path


def write_export(path, log, drop=()):
    """c4g-replay export's columns, every reply in time, drives on (INFPAR byte 5); drop: header
    columns left out"""
    t, d3, d4, d5 = log
    names = EXPORT_HDR.split(",")
    keep = [c not in drop for c in names]
    with open(path, "w") as fh:
        fh.write(",".join(c for c, k in zip(names, keep) if k) + "\n")
        for j in range(len(t)):
            row = [1, j + 1, "%.9f" % t[j], 2 * j + 1, 2 * j + 2, (j + 1) % 32768, (j + 2) % 32768, 300, "00000005", 0,
                   "00000005", 0, 4, "%.9g" % d3[j], 0, "%.9g" % d3[j], "%.9g" % d4[j], "%.9g" % d5[j], 0, 0, 0]
            fh.write(",".join(str(x) for x, k in zip(row, keep) if k) + "\n")
    return path


def within(d, name, pct):
    got = d["axes"][0]["parameters"][name]["value"]
    return abs(got - TRUTH[name]) <= pct / 100.0 * abs(TRUTH[name]), "%s %.6g (truth %.6g)" % (name, got, TRUTH[name])


def test_num_gaps(build, tmp_path):
    """1 % of the controller's packets missing: ticks are numbered from NUM, the filter never
    reaches across a gap (nor does the fit, as after a missing reply), the report counts them"""
    np = pytest.importorskip("numpy")
    log = plant(seed=3)
    keep = np.random.default_rng(5).uniform(size=len(log[0])) >= 0.01
    keep[0] = True
    d = fit_json(build, write_moni(tmp_path / "gaps.csv", log, keep), "--variant", "coulomb")
    whole = fit_json(build, write_moni(tmp_path / "whole.csv", log), "--variant", "coulomb")
    ck = Checks()
    inp = d["inputs"][0]
    ck.eq("packets missing from the NUM sequence", inp.get("num_missing"), int((~keep).sum()))
    tk, tw = d["axes"][0]["ticks"], whole["axes"][0]["ticks"]
    ck.ok("ticks near a gap dropped (the filter's reach at the gap's ends, the drive's settling beyond)",
          tk.get("num_gap", 0) > 0 and tk["edges"] >= tw["edges"] + 2 * 12 * inp.get("num_gaps", 0) // 2, (tk, tw))
    ck.eq("no gap in the whole log", whole["inputs"][0].get("num_missing"), 0)
    for p in ("Ja", "Fv", "Fc"):
        ck.ok(*within(d, p, 3.0))
    ck.done()


@pytest.mark.parametrize("col", ["c1_d5", "ctrl_num", "ctrl_infpar", "latency_us"])
def test_export_missing_column(build, tmp_path, col):
    """a column the fit reads is missing from an export CSV's header: a named error, exit 2
    (it was read from column 0: axis 1 fitted to the session number)"""
    f = write_export(tmp_path / "x.csv", plant(seconds=4.0), drop=(col,))
    r = fit(build, f, "-o", tmp_path / "x.ini")
    assert r.returncode == 2 and ("x.csv:1: header: column %s missing" % col) in r.stderr, (r.returncode, r.stderr)
    assert not (tmp_path / "x.ini").exists()


def test_moni_header_checked(build, tmp_path):
    f = tmp_path / "m.csv"
    write_moni(f, plant(seconds=2.0))
    f.write_text(f.read_text().replace("rx_d4,rx_d5", "rx_d5,rx_d4", 1))
    r = fit(build, f)
    assert r.returncode == 2 and "m.csv:1: header field 10: expected rx_d4, found 'rx_d5'" in r.stderr, \
        (r.returncode, r.stderr)


def test_export_fits(build, tmp_path):
    """the export's own reading (NUM from ctrl_num, drive from ctrl_infpar) gives the truth"""
    d = fit_json(build, write_export(tmp_path / "x.csv", plant(seed=4)), "--variant", "coulomb")
    ck = Checks()
    for p in ("Ja", "Fv", "Fc"):
        ck.ok(*within(d, p, 3.0))
    ck.done()


def test_refused_usage(build, tmp_path):
    """a directory, an axis asked for that the log lacks, contradicting options: exit 2, named"""
    ck = Checks()
    r = fit(build, tmp_path)
    ck.ok("a directory is named as one", r.returncode == 2 and "Is a directory" in r.stderr, (r.returncode, r.stderr))
    f = write_moni(tmp_path / "m.csv", plant(seconds=10.0))
    r = fit(build, f, "--axes", "1,7")
    ck.ok("--axes 1,7 on a log of axis 1: 7 named",
          r.returncode == 2 and "--axes: axis 7 of arm 1 is not in the log(s) (they carry axes 1)" in r.stderr,
          (r.returncode, r.stderr))
    r = fit(build, f, "--no-gravity", "--variant", "stribeck+gravity")
    ck.ok("--no-gravity with a gravity variant refused",
          r.returncode == 2 and "--no-gravity and --variant stribeck+gravity contradict each other" in r.stderr,
          (r.returncode, r.stderr))
    ck.done()


def test_nothing_identified_writes_nothing(build, tmp_path):
    """no axis identified: no parameter file (c4g-server would refuse one without axes), exit 3"""
    f = write_moni(tmp_path / "still.csv", plant(seconds=10.0, vamp=0.0))
    r = fit(build, f, "-o", tmp_path / "p.ini")
    assert r.returncode == 3 and "no axis identified: --out" in r.stderr, (r.returncode, r.stderr)
    assert not (tmp_path / "p.ini").exists()


def test_csv_gravity_refused(build, tmp_path):
    """a gravity-loaded axis in a CSV (no link angle): refused with the reason, not fitted as
    inertia and friction (it came out Ja = 1e-12, Fv = 0, exit 0)"""
    f = write_moni(tmp_path / "g.csv", plant(gravity=2.0, tx=20.0))
    r = fit(build, f, "--json", "-o", tmp_path / "g.ini")
    a = json.loads(r.stdout)["axes"][0]
    assert r.returncode == 3 and not a["identifiable"] and "depends on the position" in a["why"], (r.returncode, a)
    assert not (tmp_path / "g.ini").exists()


def test_barely_moving_unidentifiable(build, tmp_path):
    """+-0.03 turn of motion: the count of moving samples passes, the parameters' own
    uncertainty does not (this one came out identifiable, a Stribeck dip the plant does not
    have, Fv 0.289 against 0.008, exit 0)"""
    log = plant(vamp=0.12, f0=0.5, sines=4, seconds=20.0)
    assert abs(log[1]).max() < 0.05
    r = fit(build, write_moni(tmp_path / "b.csv", log), "--json")
    a = json.loads(r.stdout)["axes"][0]
    assert r.returncode == 3 and not a["identifiable"], (r.returncode, a.get("parameters"), a.get("why"))
    assert "not pinned by this run" in a["why"] or "hardly moved" in a["why"], a["why"]


def test_delay_unpinned_is_said(build, tmp_path):
    """slow, gentle motion (four sines from 0.05 Hz): the data hardly pin the delay of D5
    after D4 (it came out -0.73 ticks, the plant's is -0.5, said nowhere). The fit says so:
    refused at the search's end, or a warning with the delay's share in the intervals; the
    delay's share is in the intervals (their coverage is counted over many seeds in
    tests/ident/accuracy.cpp, not on one run)"""
    r = fit(build, write_moni(tmp_path / "slow.csv", plant(vamp=10.0, f0=0.05, sines=4)), "--json", "--variant", "coulomb")
    a = json.loads(r.stdout)["axes"][0]
    refused = r.returncode == 3 and "the end of its search" in a.get("why", "")
    warned = r.returncode == 0 and any("poorly pinned" in w for w in a.get("warnings", []))
    assert refused or warned, (r.returncode, a.get("delay_ticks"), a.get("why"), a.get("warnings"))
    if warned:
        for p in ("Ja", "Fv", "Fc"):
            assert a["parameters"][p]["sigma_delay"] > 0, (p, a["parameters"][p])


def test_still_axis_delay_and_inertia(build, tmp_path):
    """constant speed both ways: no acceleration outside the reversals (dropped), so nothing
    pins the inertia (it came out Ja = 1e-12 at its bound, exit 0): refused"""
    r = fit(build, write_moni(tmp_path / "tri.csv", plant(shape="triangle", vamp=2.0)), "--json")
    a = json.loads(r.stdout)["axes"][0]
    assert r.returncode == 3 and not a["identifiable"], (r.returncode, a.get("parameters"), a.get("why"))


def test_capture_num_gaps(build, loop, tmp_path):
    """1 % of the controller's cyclic packets taken out of the loop's capture (as a capture
    that missed them, or a PC that never got them): the ticks are numbered from NUM, so the
    fit sees the gaps and leaves their reach out. Numbered by packets seen, the inertia came
    out 0.9 % low, outside its own +-95 % interval (0.25 %)"""
    import random
    import struct
    data = (loop / "ident.pcap").read_bytes()
    assert struct.unpack("<I", data[:4])[0] == 0xa1b2c3d4 and struct.unpack("<I", data[20:24])[0] == 1, \
        "the loop's capture: little-endian pcap, Ethernet"
    out, off, rng, ctrl, seen, dropped = [data[:24]], 24, random.Random(3), None, 0, 0
    while off + 16 <= len(data):
        incl = struct.unpack("<I", data[off + 8:off + 12])[0]
        rec = data[off:off + 16 + incl]
        off += 16 + incl
        sport = struct.unpack(">H", rec[16 + 34:16 + 36])[0]
        ctrl = sport if ctrl is None else ctrl  # the controller's sync comes first
        if sport == ctrl and incl == 270:       # its cyclic packets (6 axes)
            seen += 1
            if seen > 200 and rng.random() < 0.01:
                dropped += 1
                continue
        out.append(rec)
    (tmp_path / "gaps.pcap").write_bytes(b"".join(out))
    full = fit_json(build, loop / "ident.pcap", "--axes", 1)
    gaps = fit_json(build, tmp_path / "gaps.pcap", "--axes", 1)
    ck = Checks()
    ck.ok("some packets taken out", dropped > 50, dropped)
    ck.eq("packets missing from the NUM sequence", gaps["inputs"][0].get("num_missing"), dropped)
    ck.ok("ticks near a gap dropped", gaps["axes"][0]["ticks"].get("num_gap", 0) > 0, gaps["axes"][0]["ticks"])
    jf, jg = full["axes"][0]["parameters"]["Ja"]["value"], gaps["axes"][0]["parameters"]["Ja"]
    ck.ok("Ja with the gaps = Ja of the whole capture (0.5 %), inside its own interval",
          abs(jg["value"] - jf) <= min(5e-3 * jf, jg["ci95"]), "gaps %s, whole %s" % (jg, jf))
    ck.done()


def test_loop_csv_gravity_axis_refused(build, loop, tmp_path):
    """the loop's moni CSV, axis 2 (gravity 7.5 A at the motor): no link angle in a CSV, so
    refused for the position-dependent current (it came out Ja = 1e-12, exit 0); axis 1 of the
    same file is fitted and written alone"""
    r = fit(build, loop / "ident.moni.csv", "--axes", "1,2", "--json", "-o", tmp_path / "m.ini")
    a = {x["axis"]: x for x in json.loads(r.stdout)["axes"]}
    assert r.returncode == 3 and a[1]["identifiable"] and not a[2]["identifiable"], (r.returncode, a)
    assert "depends on the position" in a[2]["why"], a[2]["why"]
    text = (tmp_path / "m.ini").read_text()
    assert "[axis 1]" in text and "[axis 2]" not in text, text
