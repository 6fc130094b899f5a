# SPDX-License-Identifier: MIT
"""c4g-sim reply checking like the controller: 10 consecutive missing replies raise
ERR_C4GOPEN_UDP (exit 1, drives off, communication stops); a PC that never answers fails
during the handshake. That one missing reply is survived and counted is proved in-process
(tests/lib/test_protocol.c, test_dropped)."""
from simlib import run_sim, sim_json, start_pc


def test_ten_missing_raise(procs, bins, ports):
    # (this run also proves that 9 in a row do not raise: the error came at 10)
    port = ports.udp()
    start_pc(procs, bins, port, "--stop-after", 60)
    r = run_sim(procs, bins, "-p", port, "-n", 500, "--json")
    assert r.returncode == 1, r.stderr
    j = sim_json(r)
    assert any(e.get("name") == "ERR_C4GOPEN_UDP" and e.get("message") == "C4GOpen: communication error"
               for e in j["errors"]), "no ERR_C4GOPEN_UDP with its manual message in %s" % j["errors"]
    rp = j["replies"]
    # unanswered = missing, or unjudged if the simulator overran that deadline itself
    assert rp["missing"] + rp["unjudged"] >= 10, rp
    assert rp["max_consecutive_missing"] == 10
    assert all(not a["drive_on"] for a in j["robot"]), "drive on after the error"
    assert rp["ok"] + rp["missing"] + rp["unjudged"] == j["packets"]["sent"], \
        "every packet answered, missing or unjudged: %s" % rp


def test_silent_pc(procs, bins, ports):
    port = ports.udp()
    start_pc(procs, bins, port, "--no-reply")
    r = run_sim(procs, bins, "-p", port, "-n", 100, "--json")
    assert r.returncode == 1, r.stderr
    j = sim_json(r)
    assert j["packets"]["sent"] == 10, "packets sent before giving up (9 sync + init)"
    assert "ERR_C4GOPEN_UDP" in r.stdout


def test_max_miss_1(procs, bins, ports):
    port = ports.udp()
    start_pc(procs, bins, port, "--drop-nth", 30)
    r = run_sim(procs, bins, "-p", port, "-n", 100, "--max-miss", 1, "--json")
    assert r.returncode == 1, r.stderr
