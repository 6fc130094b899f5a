# SPDX-License-Identifier: MIT
"""c4g-sim NUM policy enforcement through the process: the option reaches the controller end,
a refused PC ends the run with ERR_C4GOPEN_UDP and exit 1, and the detected policy is reported.
The whole matrix (each policy against each PC, the wrap, the 10th miss) is proved in-process
by tests/lib/test_protocol.c, deterministically; here only what needs processes and sockets."""
import pytest

from simlib import STALL_OK, run_sim, sim_json, start_pc

CASES = [("--echo", "echo", 0), ("", "echo", 1), ("--wrong-num", "either", 1)]


@pytest.mark.parametrize("pc_opt,policy,want", CASES,
                         ids=["%s-vs-%s" % (c[0].lstrip("-") or "plus-one", c[1]) for c in CASES])
def test_policy(procs, bins, ports, pc_opt, policy, want):
    port = ports.udp()
    start_pc(procs, bins, port, *([pc_opt] if pc_opt else []))
    # a refused PC must raise the default 10-in-a-row error; an accepted one may be stalled
    # by a busy host without ending the run
    miss = STALL_OK if want == 0 else []
    r = run_sim(procs, bins, "-p", port, "-n", 100, "--num-policy", policy, *miss, "--json")
    assert r.returncode == want, r.stderr
    rp = sim_json(r)["replies"]
    if want == 1:
        # the refused replies are counted as wrong NUM, stale (a reply that came after its
        # deadline) or malformed (an init echo that came after the sim moved on). How many
        # arrived before the error depends on the PC's scheduling, not on the policy (the
        # ones still in flight when ERR_C4GOPEN_UDP stops the sim are not read), and so does
        # a plus-one reply that comes a period late: its NUM is the next packet's echo.
        assert rp["wrong_num"] + rp["stale"] + rp["malformed"] >= 1, "wrong NUM not counted: %s" % rp
        assert rp["max_consecutive_missing"] == 10, "10 packets in a row without an accepted reply"
        assert "ERR_C4GOPEN_UDP" in r.stdout, "no ERR_C4GOPEN_UDP"
    else:
        assert rp["wrong_num"] == 0


def test_policy_detected(procs, bins, ports):
    port = ports.udp()
    start_pc(procs, bins, port, "--echo")
    r = run_sim(procs, bins, "-p", port, "-n", 50, *STALL_OK, "--json")
    assert sim_json(r)["pc_policy"] == "echo", "either: policy detected from the PC"
