# SPDX-License-Identifier: MIT
"""c4g-server's mode 9 with a model = rigid-body-1 parameter file on c4g-sim's arm plant
(fixtures/sim/smart-six.xml): the EXACT parameters (tests/e2e/helpers/arm_exact) make the
fast six-axis move of fixtures/scenarios/rigid-move9.scn follow far better than mode 0
(rigid-move0.scn, the controller's loops alone); the log names each axis's model; a file
whose range the move leaves is clamped and says so once per axis; a bad file is refused
with FILE:LINE."""
import json
import subprocess

from armlib import arm_session
from e2elib import host_disturbed




def session(bins, port, out, name, scn, *srv_opts):
    """one arm-plant session on c4g-sim's default axes (the ones arm_exact writes): (pcap,
    server log, its JSON summary)"""
    return arm_session(bins.server, bins.sim, port, out, name, scn, srv_opts, json_out=True)


def follow(bins, *pcaps):
    r = subprocess.run([str(bins.replay), "follow", "--json", "--axes", "1-6"] + [str(p) for p in pcaps],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)["captures"]


def exact(bins, path, *opts):
    r = subprocess.run([str(bins.helper("arm_exact")), "--out", str(path)] + list(opts),
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return path


def test_rigid_exact_beats_mode0(bins, ports, tmp_path):
    """the exact rigid file in mode 9: every axis logged as model rigid, no clamp, the
    following error RMS over axes 1-6 at least 3x smaller than mode 0's"""
    port = ports.udp()
    ini = exact(bins, tmp_path / "exact.ini")
    m0, _, _ = session(bins, port, tmp_path, "move0", "rigid-move0.scn")
    m9, log, js = session(bins, port, tmp_path, "rigid9", "rigid-move9.scn", "--ff", ini, "--duration", "6",
                          "--ff-ext1")
    for a in range(1, 7):
        assert ("axis %d: mode 9 feedforward: model rigid (arm 1's rigid-body model, joint %d of 6, %s); "
                "--ff-ext1 not added (the model replaces EXT1)" % (a, a, ini)) in log, log
    assert "clamped" not in log, log
    assert "SAFETY" not in log, log
    assert js["counters"]["ff_model_ticks"] > 6 * 1000 and js["counters"]["ff_model_clamped"] == 0, js
    f0, f9 = follow(bins, m0, m9)
    ratio = f0["follow_rms"] / f9["follow_rms"]
    print("fast six-axis move, FE RMS: mode 0 %.6f turn, mode 9 exact rigid file %.6f turn (%.2fx); "
          "DSA RMS %.4f -> %.4f A; late %d" % (f0["follow_rms"], f9["follow_rms"], ratio, f0["dsa_current_rms"],
                                             f9["dsa_current_rms"], f9["mode9_late"]))
    host_disturbed(ratio <= 3.0 and f9["mode9_late"] > 0,
                   "%d mode-9 ticks without the PC's addition in time" % f9["mode9_late"])
    # measured 8.4x on an idle host (FE RMS 0.00263 -> 0.00031 turn), 5.6x on a loaded one
    # with 12 late mode-9 ticks. What is left is the plant's friction smoothing
    # (v/sqrt(v^2+eps^2) against the model's tanh), the wrist's off-diagonal rotor inertia
    # the plant leaves out, and the one-tick prediction of the acceleration. 3x stays below
    # both with margin; a model that left out the arm's coupling or gravity would not reach
    # it (the narrow-range file of the next test, clamped nearly everywhere: 1.3x).
    assert ratio > 3.0, "the exact rigid file follows only %.2fx better than mode 0" % ratio


def test_rigid_clamp_logged_once(bins, ports, tmp_path):
    """a file whose fitted range is narrower than the move: the state is clamped, each
    clamp logged once per axis and session with its value and the range, counted in the
    summary; the result still passes the safety filter (no safety event)"""
    port = ports.udp()
    ini = exact(bins, tmp_path / "narrow.ini", "--q-range", "-0.05,0.05", "--qd-max", "0.5", "--qdd-max", "5")
    # 3 s of mode 9: the move, both ways, is over 1.7 s into it (axis 1's D1 still after tick 850)
    _, log, js = session(bins, port, tmp_path, "narrow9", "rigid-move9.scn", "--ff", ini, "--duration", "3")
    lines = [ln for ln in log.splitlines() if "rigid model: joint" in ln]
    for a in range(1, 7):
        mine = [ln for ln in lines if "axis %d: rigid model:" % a in ln]
        for what, rng in (("angle", "-0.05..0.05"), ("velocity", "-0.5..0.5")):
            hits = [ln for ln in mine if ("joint %s " % what) in ln]
            assert len(hits) == 1, (a, what, log)
            assert ("outside the fitted range %s: clamped (logged once per axis and session)" % rng) in hits[0]
            v = float(hits[0].split("joint %s " % what)[1].split()[0])
            assert abs(v) > float(rng.split("..")[1]), hits[0]
    assert 0 < js["counters"]["ff_model_clamped"] <= js["counters"]["ff_model_ticks"], js
    assert "SAFETY" not in log, log


def test_rigid_bad_file_refused(bins, tmp_path):
    """an edited rigid file: refused at start with FILE:LINE:COL, exit 2, nothing served"""
    good = exact(bins, tmp_path / "exact.ini").read_text()
    bad = tmp_path / "bad.ini"
    bad.write_text(good.replace("qdd_max = 1000\n", "qdd_max = -1\n", 1))
    line = good.splitlines().index("qdd_max = 1000") + 1
    r = subprocess.run([str(bins.server), "-p", "1", "--ff", str(bad), "--max-seconds", "1"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert ("%s:%d:11: [joint 1] qdd_max: '-1' is out of range 0..1000000" % (bad, line)) in r.stderr, r.stderr
    assert "listening on" not in r.stderr
    # a checksum that no longer fits: the same refusal style, the checksum line named
    bad.write_text(good.replace("m = 40\n", "m = 41\n", 1))
    r = subprocess.run([str(bins.server), "-p", "1", "--ff", str(bad), "--max-seconds", "1"],
                       capture_output=True, text=True, timeout=30)
    line = good.splitlines().index(next(ln for ln in good.splitlines() if ln.startswith("checksum"))) + 1
    assert r.returncode == 2 and ("%s:%d:12: [model] checksum: checksum mismatch" % (bad, line)) in r.stderr, \
        r.stderr
