# SPDX-License-Identifier: MIT
"""examples/c4g-server.service: systemd accepts it (systemd-analyze verify, when installed),
it carries the real-time settings docs/rt-integration.md describes, and c4g-server accepts
its ExecStart options (run on loopback with a free port until its idle timeout)."""
import re
import shutil

import pytest

from e2elib import ROOT

UNIT = ROOT / "examples" / "c4g-server.service"


@pytest.mark.parametrize("key", ["CPUSchedulingPolicy=fifo", "LimitMEMLOCK=infinity", "CPUAffinity=",
                                 "LimitRTPRIO=", "AmbientCapabilities=",
                                 "ExecStart=/usr/local/bin/c4g-server "])
def test_unit_has(key):
    assert any(l.startswith(key) for l in UNIT.read_text().splitlines()), "%s has no %s" % (UNIT, key)


def test_systemd_analyze_verify(procs, bins, tmp_path):
    sa = shutil.which("systemd-analyze")
    if sa is None:
        pytest.skip("systemd-analyze not installed")
    unit = tmp_path / "c4g-server.service"
    unit.write_text(UNIT.read_text().replace("/usr/local/bin/c4g-server", str(bins.server)))
    r = procs.run([sa, "verify", unit])
    out = r.stdout + r.stderr
    assert r.returncode == 0 and not re.search("unknown|invalid|ignoring", out, re.I), \
        "systemd-analyze verify: " + out


def test_execstart_options_accepted(procs, bins, ports, tmp_path):
    # the options of ExecStart, with a loopback controller, a free port, files in tmp_path
    line = next(l for l in UNIT.read_text().splitlines()
                if l.startswith("ExecStart=/usr/local/bin/c4g-server "))
    args = line[len("ExecStart=/usr/local/bin/c4g-server "):]
    args = re.sub(r"^--controller [0-9.]*", "--controller 127.0.0.1", args)
    args = args.replace("/var/lib/c4g-server", str(tmp_path)).replace("/var/log/c4g-server", str(tmp_path))
    args = args.replace(" --rt-strict", "")
    r = procs.run([bins.server] + args.split() + ["-p", ports.udp(), "--idle-timeout", "0.3"], timeout=20)
    assert r.returncode == 4, "exit %d at the idle timeout: %s" % (r.returncode, r.stderr)
    assert (tmp_path / "last.json").stat().st_size > 0, "JSON written"
