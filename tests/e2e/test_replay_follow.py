# SPDX-License-Identifier: MIT
"""c4g-replay follow on real captures: the figures against an independent computation from
the export CSV of the same capture, the ratio to the first capture, JSON, and the errors (a
capture without a moving tick, an unreadable file). The page's example is run by
test_replay.py with the others."""
import csv
import io
import json
import math
import subprocess

FX = "fixtures/replay"


def run(bins, *args):
    return subprocess.run([str(bins.replay)] + [str(a) for a in args], capture_output=True,
                          text=True, timeout=60)


def from_export(bins, pcap, axes):
    """following error and DSA current RMS over the moving ticks, from the export CSV"""
    r = run(bins, "export", pcap)
    assert r.returncode == 0, r.stderr
    fe = dsa = 0.0
    n = 0
    for row in csv.DictReader(io.StringIO(r.stdout)):
        for a in axes:
            d2 = float(row["c%d_d2" % a])
            if not abs(d2) > 1e-6:
                continue
            add = float(row["p%d_d5" % a]) if row["p%d_mode" % a] == "9" else 0.0
            fe += (float(row["c%d_d1" % a]) - float(row["c%d_d3" % a])) ** 2
            dsa += (float(row["c%d_d5" % a]) - add) ** 2
            n += 1
    return n, math.sqrt(fe / n), math.sqrt(dsa / n)


def test_figures_match_the_export(bins):
    caps = ["%s/mode0.pcap" % FX, "%s/data-current-mode9.pcap" % FX]
    r = run(bins, "follow", "--axes", "1-3", "--json", *caps)
    assert r.returncode == 0, r.stderr
    j = json.loads(r.stdout)["captures"]
    for c, cap in zip(j, caps):
        n, fe, dsa = from_export(bins, cap, (1, 2, 3))
        assert c["ticks"] == n, (cap, c["ticks"], n)
        assert math.isclose(c["follow_rms"], fe, rel_tol=1e-6), (cap, c["follow_rms"], fe)
        assert math.isclose(c["dsa_current_rms"], dsa, rel_tol=1e-6), (cap, c["dsa_current_rms"], dsa)
        assert [a["axis"] for a in c["axes"]] == [1, 2, 3]
    assert j[1]["mode9_ticks"] > 0 and j[1]["mode9_late"] == 0
    assert math.isclose(j[1]["first_over_this"], j[0]["follow_rms"] / j[1]["follow_rms"], rel_tol=1e-7)
    assert "first_over_this" not in j[0]


def test_no_moving_tick_is_an_error(bins):
    r = run(bins, "follow", "%s/fault-drop.pcap" % FX)
    assert r.returncode == 1
    assert "fixtures/replay/fault-drop.pcap: no tick where the target moves" in r.stderr


def test_unreadable(bins, tmp_path):
    bad = tmp_path / "x.pcap"
    bad.write_bytes(b"not a capture")
    r = run(bins, "follow", bad)
    assert r.returncode == 2, r.stderr
    assert str(bad) in r.stderr


def test_usage(bins):
    r = run(bins, "follow", "--axes", "0", "%s/mode0.pcap" % FX)
    assert r.returncode == 2 and "--axes" in r.stderr
    r = run(bins, "follow", "--from", "2", "--to", "1", "%s/mode0.pcap" % FX)
    assert r.returncode == 2 and "before --from" in r.stderr
