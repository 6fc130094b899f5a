# SPDX-License-Identifier: MIT
"""c4g-ident excite --optimize --init CAPTURE writes its rows at the capture's period (its
init packet's): rows of another spacing are interpolated linearly by c4g-server, and the
kink at every row is a current ripple no model predicts. The capture is recorded here from
c4g-sim at 1 ms; without --init the rows stay at 2 ms, and -T still wins."""
import json
import subprocess

from simlib import start_pc, stop_pc

OPT = ["excite", "--optimize", "--kin", "fixtures/ident/smart-six.kin", "--periods", "1", "--f0", "0.25",
       "--evals", "10", "--json"]


def excite(bins, tmp_path, *args):
    r = subprocess.run([str(bins.ident)] + OPT + ["-o", str(tmp_path / "x.csv")] + [str(a) for a in args],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_rows_follow_the_captures_period(procs, bins, ports, tmp_path):
    port = ports.udp()
    pc = start_pc(procs, bins, port, idle_ms=300)
    cap = tmp_path / "1ms.pcap"
    r = subprocess.run([str(bins.sim), "--bind", "127.0.0.1", "-p", str(port), "-T", "1", "-n", "50", "--pcap",
                        str(cap), "-q"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    stop_pc(pc, port)
    j = excite(bins, tmp_path, "--init", cap)
    assert j["row_ms"] == 1.0 and j["rows"] == 4001, (j["row_ms"], j["rows"])
    rows = [x for x in (tmp_path / "x.csv").read_text().splitlines() if x and not x.startswith("#")]
    assert len(rows) >= 4001
    # without a capture: the 2 ms default; -T given: it wins over the capture's
    assert excite(bins, tmp_path)["row_ms"] == 2.0
    assert excite(bins, tmp_path, "--init", cap, "-T", "2")["row_ms"] == 2.0


def test_help_says_which_period(bins):
    r = subprocess.run([str(bins.ident), "excite", "--help"], capture_output=True, text=True, timeout=30)
    text = " ".join(r.stdout.split())
    assert "the controller's period (-T 1 at 1 kHz)" in text
    assert "With --optimize --init CAPTURE the default is the capture's period" in text
