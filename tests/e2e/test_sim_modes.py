# SPDX-License-Identifier: MIT
"""c4g-sim scenarios for every supported mode against the reference PC: each must end with
exit 0 (all EXPECTs met) and show the manual's mode sequence on axis 1."""
import itertools

import pytest

from simlib import STALL_OK, run_sim, sim_json, start_pc

MODES = [("mode0", "501 0"), ("mode10", "501 0 10 0"), ("mode1", "501 0 1 11 0"),
         ("mode2", "501 0 2 12 0"), ("mode4", "501 0 4 14 0"), ("mode5", "501 0 5 15 0"),
         ("mode7", "501 0 7 170 0"), ("mode8", "501 0 8 0"), ("mode9", "501 0 9 0")]


@pytest.mark.parametrize("scn,want", MODES, ids=[m[0] for m in MODES])
def test_mode(procs, bins, ports, tmp_path, scn, want):
    port = ports.udp()
    start_pc(procs, bins, port)
    csv = tmp_path / (scn + ".csv")
    r = run_sim(procs, bins, "-p", port, "-S", "fixtures/scenarios/%s.scn" % scn, *STALL_OK,
                "--csv", csv, "--json")
    assert r.returncode == 0, r.stdout + r.stderr
    lines = csv.read_text().splitlines()
    rows = [l.split(",") for l in lines[1:]]
    seq = " ".join(k for k, _ in itertools.groupby(c[5] for c in rows if c[2] == "1"))
    assert seq == want, "%s: mode sequence of axis 1" % scn
    j = sim_json(r)
    assert j["scenario"]["expect_failed"] == 0, "%s: expectations failed" % scn
    assert j["scenario"]["expect_passed"] > 0
    if scn == "mode5":
        # INFPAR byte 5 once the drives are on, CMD byte from the scenario (mode 5: CMD 1 3)
        assert any(l.endswith(",0x00000005,0x00000003") for l in lines), \
            "mode5: INFPAR 5 / CMD 3 not seen on the wire"
