# SPDX-License-Identifier: MIT
"""c4g-ident excite --optimize: the Fourier excitation of the rigid-body model. The file it
writes is played by c4g-server --traj against c4g-sim's arm plant without a protocol or
safety event; every row keeps the joint limits (checked here from the motor offsets through
figure 10.1's transmission, independently of the tool); its condition number is lower than
the plain excitation's by an asserted factor; the same seed gives the same bytes; bad
options are refused with exit 2."""
import json
import math
import re
import subprocess
import time

import numpy as np

from e2e_extra import Checks

KIN = "fixtures/ident/smart-six.kin"
PLANT = "fixtures/sim/smart-six.xml"
# the manual's figure 10.1 init packet, the one c4g-sim sends (lib/sim/c4gsim_fixtures.c):
# TxRate (motor turns per joint turn) and AxInfo's wrist coupling k54, k64, k65, as float32
TX = np.array([-181.587296, 159.260864, 162.473694, 72.585968, 78.75, -50.0], dtype=np.float32).astype(float)
K54, K64, K65 = (float(np.float32(x)) for x in (-0.0200, 0.0204, 0.0200))


def kr_matrix():
    """Kr = Kr2 K1^-T (chapter 19): motor rad per joint rad, [motor][joint]"""
    kr = np.diag(TX)
    kr[4, 3] = -TX[4] * K54
    kr[5, 3] = TX[5] * (K65 * K54 - K64)
    kr[5, 4] = -TX[5] * K65
    return kr


def le(ck, what, got, want):
    return ck.ok(what, got <= want, "got %r, want <= %r" % (got, want))


def excite(build, *args, timeout=60):
    return subprocess.run([str(build / "bin" / "c4g-ident"), "excite"] + [str(a) for a in args],
                          capture_output=True, text=True, timeout=timeout)


def read_traj(path):
    rows = [l for l in path.read_text().splitlines() if l and not l.startswith("#")]
    assert rows[0] == "t,ax1,ax2,ax3,ax4,ax5,ax6", rows[0]
    a = np.array([[float(x) for x in r.split(",")] for r in rows[1:]])
    return a[:, 0], a[:, 1:]


def test_optimized_excitation(build, tmp_path):
    """limits on every row, at rest at both ends, condition number 5x below the plain
    excitation's, deterministic bytes, the report's figures"""
    ck = Checks()
    out = tmp_path / "opt.csv"
    t0 = time.monotonic()
    r = excite(build, "--optimize", "--kin", KIN, "-o", out, "--json")
    took = time.monotonic() - t0
    assert r.returncode == 0, (r.returncode, r.stderr)
    rep = json.loads(r.stdout)
    c = rep["condition"]
    print("condition number: optimised %.6g, plain %.6g (%.2fx); %d evaluations in %.1f s (run %.1f s)"
          % (c["optimized"], c["plain"], c["ratio"], rep["evals"], rep["seconds"], took))
    ck.ge("plain / optimised condition number", c["ratio"], 5.0)
    ck.ok("the ratio is the figures'", abs(c["ratio"] - c["plain"] / c["optimized"]) < 1e-6 * c["ratio"])
    ck.eq("base parameters of the arm", rep["base_parameters"], 40)
    ck.eq("columns (with friction)", rep["columns"], 58)
    ck.eq("evaluations", rep["evals"], 2000)
    # the search's time is bounded by its evaluation count (above), not asserted: a loaded
    # host only slows it
    ck.eq("three least determined directions named", len(rep["weakest"]), 3)
    ck.ok("each with members", all(w["members"] for w in rep["weakest"]), rep["weakest"])

    # every row: joint angles from the motor offsets (q = start + 2 pi Kr^-1 offset), speeds
    # and accelerations by central differences, against the limits the report gives
    t, off = read_traj(out)
    dt = 0.002
    ck.eq("rows (3 periods of 10 s every 2 ms, both ends)", len(t), 15001)
    ck.ok("times every 2 ms", np.allclose(np.diff(t), dt, atol=1e-6))
    ck.ok("first and last rows at offset 0", not off[0].any() and not off[-1].any(), (off[0], off[-1]))
    lim = rep["limits"]
    start = np.array([L["start"] for L in lim])
    q = start + 2 * math.pi * np.linalg.solve(kr_matrix(), off.T).T
    qd = (q[2:] - q[:-2]) / (2 * dt)
    qdd = (q[2:] - 2 * q[1:-1] + q[:-2]) / dt ** 2
    for j, L in enumerate(lim):
        ck.ok("joint %d angle within %.4f .. %.4f on every row" % (j + 1, L["q_min"], L["q_max"]),
              q[:, j].min() >= L["q_min"] and q[:, j].max() <= L["q_max"], (q[:, j].min(), q[:, j].max()))
        # the difference quotients of a smooth series: within 0.1 % of the exact peaks
        le(ck, "joint %d |qd| / limit" % (j + 1), np.abs(qd[:, j]).max() / L["qd_max"], 1.0)
        le(ck, "joint %d |qdd| / limit" % (j + 1), np.abs(qdd[:, j]).max() / L["qdd_max"], 1.0)
        ck.ok("joint %d: the report's speed peak is the rows'" % (j + 1),
              abs(np.abs(qd[:, j]).max() - L["qd_peak"]) <= 1e-3 * L["qd_peak"], (np.abs(qd[:, j]).max(), L["qd_peak"]))
        ck.ok("joint %d: margins reported" % (j + 1), all(0.0 <= L["margin"][k] <= 1.0 for k in ("q", "qd", "qdd")),
              L["margin"])
        ck.ok("joint %d: the tightest limit used at 95 %%" % (j + 1), abs(min(L["margin"].values()) - 0.05) < 1e-3,
              L["margin"])
    # at rest at both ends and at each period's end: speed of the first and last steps
    vm = np.abs(np.diff(off, axis=0)) / dt
    le(ck, "motor speed over the first step [turn/s]", vm[0].max(), 0.01)
    le(ck, "motor speed over the last step [turn/s]", vm[-1].max(), 0.01)
    le(ck, "motor speed at most --vmax 10 turn/s", vm.max(), 10.0)
    for k, m in enumerate(rep["motors"]):
        ck.ok("motor %d stroke as reported" % (k + 1),
              abs(off[:, k].min() - m["stroke_min"]) < 1e-6 and abs(off[:, k].max() - m["stroke_max"]) < 1e-6, m)

    # the same options: the same bytes; another seed: another file
    again = tmp_path / "again.csv"
    r2 = excite(build, "--optimize", "--kin", KIN, "-o", again)
    ck.eq("second run exit", r2.returncode, 0)
    ck.ok("same seed, same bytes", again.read_bytes() == out.read_bytes())
    ck.has("text report: both condition numbers", r2.stdout, "condition number, plain excite")
    other = tmp_path / "seed2.csv"
    r3 = excite(build, "--optimize", "--kin", KIN, "-o", other, "--seed", "2", "--evals", "100")
    ck.eq("seed 2 exit", r3.returncode, 0)
    ck.ok("another seed, another file", other.read_bytes() != out.read_bytes())
    ck.done()


def test_played_on_the_arm(build, ports, tmp_path):
    """a short optimised excitation (one period of 4 s) played by c4g-server --traj on
    c4g-sim's arm plant with figure 10.1's following-error check: the whole file, no safety
    event, back at the start; the transmission read from that session's capture (--init) is
    figure 10.1's, so the file it gives is the same"""
    traj = tmp_path / "short.csv"
    r = excite(build, "--optimize", "--kin", KIN, "--f0", "0.25", "--periods", "1", "--evals", "300", "-o", traj)
    assert r.returncode == 0, r.stderr
    port = ports.udp()
    err = tmp_path / "srv.err"
    with open(err, "w") as e:
        srv = subprocess.Popen([str(build / "bin" / "c4g-server"), "-p", str(port), "-c", "127.0.0.1",
                                "--idle-timeout", "5", "--max-seconds", "60", "--traj", str(traj)],
                               stdout=e, stderr=subprocess.STDOUT)
    try:
        end = time.monotonic() + 5
        while "listening on" not in err.read_text() and time.monotonic() < end:
            time.sleep(0.05)
        sim = subprocess.run([str(build / "bin" / "c4g-sim"), "-p", str(port), "-c", "fixtures/sim/fig10-1.ini",
                              "-S", "fixtures/scenarios/ident.scn", "--max-miss", "100000", "--plant", PLANT,
                              "--pcap", str(tmp_path / "run.pcap")],
                             capture_output=True, text=True, timeout=60)
        srv.wait(timeout=15)
    finally:
        if srv.poll() is None:
            srv.kill()
            srv.wait()
    log = err.read_text()
    assert sim.returncode == 0, "c4g-sim: exit %d: %s" % (sim.returncode, sim.stdout[-2000:] + sim.stderr[-2000:])
    ck = Checks()
    ck.has("scenario done", sim.stdout, "expectations 1 passed 0 failed")
    ck.has("the server left with EXIT_FROM_OPEN after the file", log, "EXIT_FROM_OPEN packets per arm: 1 ")
    ck.has("no safety event", log, "first safety event: none")
    ck.has("no following error", log, r"following error \(508\) replies 0")
    # the arm back where it started (within the loops' settling): every axis near 0 turns
    pos = [float(x) for x in re.findall(r"axis \d: mode 0, pos (-?[0-9.]+) turns", sim.stdout)]
    ck.eq("axes reported", len(pos), 6)
    ck.ok("back at the start pose (0.01 turn)", all(abs(p) < 0.01 for p in pos), pos)
    again = tmp_path / "init.csv"
    r = excite(build, "--optimize", "--kin", KIN, "--f0", "0.25", "--periods", "1", "--evals", "300", "-o", again,
               "--init", tmp_path / "run.pcap")
    ck.eq("--init from the session's capture: exit", r.returncode, 0)
    ck.has("the report names it", r.stdout, "transmission: .*run.pcap")
    ck.ok("--init from c4g-sim's capture: the same file as figure 10.1's", again.read_bytes() == traj.read_bytes())
    ck.done()


def test_init_transmission(build, ports, tmp_path):
    """--init takes arm 1's transmission from a capture: a controller whose axis 1 turns its
    motor half as much per joint turn doubles joint 1's default speed and acceleration
    limits, and the motor offsets follow that transmission"""
    cfg = tmp_path / "tx.ini"
    cfg.write_text("[axis 1.1]\ntx_rate = %r\n" % (float(TX[0]) / 2))
    cap = tmp_path / "tx.pcap"
    sim = subprocess.run([str(build / "bin" / "c4g-sim"), "-p", str(ports.udp()), "-c", str(cfg), "-n", "20",
                          "--max-miss", "100000", "--pcap", str(cap), "-q"], capture_output=True, text=True, timeout=30)
    assert sim.returncode == 0, sim.stdout + sim.stderr
    ck = Checks()
    reps = {}
    for name, extra in (("default", []), ("init", ["--init", cap])):
        r = excite(build, "--optimize", "--kin", KIN, "--evals", "100", "-o", tmp_path / (name + ".csv"), "--json", *extra)
        ck.eq("%s: exit" % name, r.returncode, 0)
        reps[name] = json.loads(r.stdout)
    d, i = reps["default"], reps["init"]
    ck.eq("transmission named", (d["transmission"], i["transmission"]), ("figure 10.1", str(cap)))
    for j in range(6):
        f = 2.0 if j == 0 else 1.0
        for k in ("qd_max", "qdd_max"):
            ck.ok("joint %d %s x%g" % (j + 1, k, f), abs(i["limits"][j][k] / d["limits"][j][k] - f) < 1e-6,
                  (i["limits"][j][k], d["limits"][j][k]))
    # the file's motor 1 offsets are the joint's angle through the halved ratio
    t, off = read_traj(tmp_path / "init.csv")
    kr = kr_matrix()
    kr[0, 0] /= 2
    q = np.array([L["start"] for L in i["limits"]]) + 2 * math.pi * np.linalg.solve(kr, off.T).T
    ck.ok("joint 1 within its limits through the capture's transmission",
          i["limits"][0]["q_min"] <= q[:, 0].min() and q[:, 0].max() <= i["limits"][0]["q_max"])
    qd = np.abs(np.diff(q[:, 0])).max() / 0.002
    ck.ok("joint 1 speed within its limit through it", qd <= i["limits"][0]["qd_max"], (qd, i["limits"][0]["qd_max"]))
    ck.done()


def test_optimize_refused(build, tmp_path):
    """bad options: exit 2, the reason on stderr, no file written"""
    out = tmp_path / "x.csv"
    three = tmp_path / "three.kin"
    three.write_text("[arm]\nconvention = modified\nangles = deg\ngravity = 0 0 -9.81\n"
                     + "".join("[joint %d]\na = 0.1\nalpha = 0\nd = 0\ntheta0 = 0\nkt = 0.8\n" % j for j in (1, 2, 3)))
    bad_kin = tmp_path / "bad.kin"
    bad_kin.write_text("[arm]\nconvention = sideways\n")
    cases = [
        (["--optimize", "-o", out], "--optimize needs --kin FILE"),
        (["--optimize", "--kin", KIN], "--optimize writes the trajectory to --out FILE"),
        (["--optimize", "--kin", KIN, "-o", out, "--harmonics", "1"], "--harmonics 1: --optimize takes 2..20"),
        (["--optimize", "--kin", KIN, "-o", out, "--axes", "1,2"], "--axes does not apply to --optimize"),
        (["--optimize", "--kin", KIN, "-o", out, "--duration", "20"], "--duration does not apply to --optimize"),
        (["--optimize", "--kin", KIN, "-o", out, "--f0", "0.01", "--periods", "3"],
         "150000 rows: c4g-server --traj reads at most 20000"),
        (["--optimize", "--kin", KIN, "-o", out, "--f0", "1", "--harmonics", "6"],
         "the highest, 6 Hz, must stay at or below 5 Hz"),
        (["--optimize", "--kin", KIN, "-o", out, "--f0", "0.5", "--harmonics", "8", "--period", "100"],
         "the highest, 4 Hz, must stay at or below 5 Hz and 20 rows"),
        (["--optimize", "--kin", KIN, "-o", out, "--q-min", "0.5"], "joint 1: the start pose"),
        (["--optimize", "--kin", KIN, "-o", out, "--qd-max", "1,2"], "--qd-max: bad value '1,2'"),
        (["--optimize", "--kin", KIN, "-o", out, "--start", "0,0,0"], "--start: bad value '0,0,0'"),
        (["--optimize", "--kin", KIN, "-o", out, "--periods", "0"], "--periods"),
        (["--optimize", "--kin", tmp_path / "none.kin", "-o", out], "none.kin"),
        (["--optimize", "--kin", bad_kin, "-o", out], "bad.kin:2"),
        (["--optimize", "--kin", three, "-o", out], "3 joints; --optimize drives the arm's 6 main axes"),
        (["--kin", KIN, "-o", out], "--kin applies only to --optimize"),
        (["--init", "x.pcap", "-o", out], "--init applies only to --optimize"),
        (["--optimize", "--kin", KIN, "-o", out, "--init", KIN], "--init " + KIN),
        (["--optimize", "--kin", KIN, "-o", out, "--init", tmp_path / "none.pcap"], "none.pcap"),
        (["--periods", "2", "-o", out], "--periods applies only to --optimize"),
    ]
    ck = Checks()
    for args, why in cases:
        r = excite(build, *args)
        ck.ok("refused: %s" % " ".join(str(a) for a in args),
              r.returncode == 2 and why in r.stderr and not out.exists(), (r.returncode, r.stderr))
    r = excite(build, "--optimize", "--kin", KIN, "-o", tmp_path / "nodir" / "x.csv")
    ck.ok("unwritable --out: exit 1", r.returncode == 1 and "nodir" in r.stderr, (r.returncode, r.stderr))
    ck.done()
