# SPDX-License-Identifier: MIT
"""c4g-sim command line, configuration and scenario errors: exit 2 with the file, line and
value named on stderr; --help and --version exit 0; no crash on garbage input."""
import os
import random
import re

import pytest

from simlib import STALL_OK, run_sim, start_pc, stop_pc


def test_help_and_version(procs, bins):
    r = procs.run([bins.sim, "--help"])
    assert r.returncode == 0
    assert "Examples:" in r.stdout, "--help has no examples"
    r = procs.run([bins.sim, "--version"])
    assert re.match(r"^c4g-sim ", r.stdout, re.M), r.stdout


# (what, the message on stderr (a regular expression), files to write, arguments); {T} is
# the test's temporary directory
BAD = [
    ("unknown option", "unrecognized", {}, ["--frobnicate"]),
    ("period 3", "period", {}, ["-T", "3"]),
    ("21 axes", "ERR_C4GOPEN", {}, ["--open-axes", "10,10,1"]),
    ("bad policy", "num-policy", {}, ["--num-policy", "sometimes"]),
    ("scenario bad number", r"a\.scn:2:10: MOVE: target 2 \[turns\]: 'x' is not a decimal number",
     {"a.scn": b"DRIVE ON 1\nMOVE 1 1 x 3\n"}, ["-S", "{T}/a.scn"]),
    ("scenario unknown command", r"b\.scn:2:1: unknown command 'FLY'",
     {"b.scn": b"DRIVE ON 1\nFLY 1\n"}, ["-S", "{T}/b.scn"]),
    ("config bad value", r"a\.ini:4:6: \[axis 1\.2\] kp: '-4' is out of range 0\.\.100000",
     {"a.ini": b"[sim]\nperiod_ms = 2\n[axis 1.2]\nkp = -4\n"}, ["-c", "{T}/a.ini"]),
    ("config unknown key", r"b\.ini:2:1: \[sim\]: unknown key 'speed'",
     {"b.ini": b"[sim]\nspeed = 3\n"}, ["-c", "{T}/b.ini"]),
    ("missing scenario", r"nope\.scn", {}, ["-S", "{T}/nope.scn"]),
    # files users write: out-of-range numbers, binary bytes, endless or huge input
    ("scenario timeout out of range",
     r"c\.scn:2:19: WAIT: timeout \[ms\]: '1e300' is out of range 0\.\.3600000",
     {"c.scn": b"DRIVE ON 1\nWAIT PC 1 TIMEOUT 1e300\n"}, ["-S", "{T}/c.scn"]),
    ("scenario NUL byte", r"d\.scn:1:8: NUL byte \\x00 at byte offset 7",
     {"d.scn": b"DELAY 1\0\n"}, ["-S", "{T}/d.scn"]),
    ("scenario /dev/zero", "/dev/zero: more than 1048576 bytes, the limit for this file: refused",
     {}, ["-S", "/dev/zero"]),
    ("config /dev/zero", "/dev/zero: more than 1048576 bytes, the limit for this file: refused",
     {}, ["-c", "/dev/zero"]),
    ("config 1e39", r"c\.ini:2:13: \[sim\] switch_ms: '1e39' is out of range 0\.\.100000",
     {"c.ini": b"[sim]\nswitch_ms = 1e39\n"}, ["-c", "{T}/c.ini"]),
    ("config int overflow, indented key",
     r"d\.ini:4:12: \[sim\] max_miss: '99999999999999999999' is out of range",
     {"d.ini": b"[sim]\nport = 41000\n  seed = 3\nmax_miss = 99999999999999999999\n"},
     ["-c", "{T}/d.ini"]),
]


@pytest.mark.parametrize("what,pattern,files,args", BAD, ids=[b[0] for b in BAD])
def test_bad_input(procs, bins, tmp_path, what, pattern, files, args):
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    r = run_sim(procs, bins, *[a.replace("{T}", str(tmp_path)) for a in args])
    assert r.returncode == 2, "%s: exit %d: %s" % (what, r.returncode, r.stderr)
    assert re.search(pattern, r.stderr), "%s: stderr lacks %r: %s" % (what, pattern, r.stderr)


def test_random_scenario(procs, bins, tmp_path):
    # new bytes every run, from a seed the failure message names (to make them again)
    seed = int.from_bytes(os.urandom(8), "little")
    (tmp_path / "r.scn").write_bytes(random.Random(seed).randbytes(4000))
    r = run_sim(procs, bins, "-S", tmp_path / "r.scn", "-n", 1)
    assert r.returncode in (0, 1, 2), \
        "4000 random bytes (random.Random(%d).randbytes) as a scenario: exit %d (crash?)" % (
            seed, r.returncode)


def test_failed_expect_named(procs, bins, ports, tmp_path):
    # the summary (no -v) names the line and why; a scenario cut short says where it
    # stopped, never "running"
    (tmp_path / "x.scn").write_text("DRIVE ON 1\nDELAY 20\nEXPECT MODE 1 1 4\nDRIVE OFF 1\nEXIT OPEN\n")
    port = ports.udp()
    pc = start_pc(procs, bins, port)
    r = run_sim(procs, bins, "-p", port, "-S", tmp_path / "x.scn", *STALL_OK)
    stop_pc(pc, port)
    assert r.returncode == 3, r.stdout + r.stderr
    assert "first failed expectation: scenario line 3: EXPECT MODE failed: mode 0, expected 4" \
        in r.stdout, r.stdout
    assert "running" not in r.stdout, r.stdout
