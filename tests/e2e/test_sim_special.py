# SPDX-License-Identifier: MIT
"""c4g-sim special modes: 505 and 508 from the PC drive off with the matching error; 504
ends the communication; 506 resends the init packet without syncs; 502/503 passive
freezing stops the packets; selector change forces mode 0."""
import shutil

from e2elib import csv_rows
from simlib import STALL_OK, run_sim, sim_json, start_pc


def has_error(j, name, message):
    return any(e.get("name") == name and e.get("message") == message for e in j["errors"])


def sim_against_pc(procs, bins, ports, scn, *args, pc_opts=()):
    port = ports.udp()
    pc = start_pc(procs, bins, port, *pc_opts)
    r = run_sim(procs, bins, "-p", port, *STALL_OK, "-S", "fixtures/scenarios/%s.scn" % scn,
                *args, "--json")
    return r, sim_json(r), pc, port


def test_505_from_the_pc(procs, bins, ports):
    r, j, _, _ = sim_against_pc(procs, bins, ports, "mode0", pc_opts=("--request", "505@300"))
    assert r.returncode == 1, r.stderr
    assert has_error(j, "ERR_C4GOPEN_DRIVEOFF_SERVER", "C4GOpen: Drive Off from Pc"), j["errors"]
    assert not j["robot"][0]["drive_on"]


def test_508_from_the_pc(procs, bins, ports):
    r, j, _, _ = sim_against_pc(procs, bins, ports, "mode0", pc_opts=("--request", "508@300"))
    assert r.returncode == 1, r.stderr
    assert has_error(j, "ERR_C4GOPEN_FOLLOW_ERROR",
                     "C4GOpen: arm 1 axis 1 Following error out of range"), j["errors"]


def test_504_ends_the_pc_session(procs, bins, ports, tmp_path):
    r, j, pc, port = sim_against_pc(procs, bins, ports, "exit-open", "--pcap", tmp_path / "c.pcap")
    assert r.returncode == 0, r.stderr
    # the PC ends by itself on the 504
    assert pc.wait(30) == 0
    assert "ended 1" in pc.out(), "504: the PC did not see the end: " + pc.out()


def test_506_restart(procs, bins, ports, tmp_path):
    pcap = tmp_path / "d.pcap"
    r, j, _, port = sim_against_pc(procs, bins, ports, "restart", "--pcap", pcap)
    assert r.returncode == 0, r.stderr
    assert j["packets"]["init"] == 2, "506: init packets sent"
    assert j["packets"]["sync"] == 11, "506: sync packets sent (cold start only)"
    tshark = shutil.which("tshark")
    if tshark:
        t = procs.run([tshark, "-r", pcap, "-Y", "udp.dstport == %d && udp.length == 1208" % port])
        assert len(t.stdout.splitlines()) == 2, "506: 1200-byte datagrams to the PC in the pcap"


def test_passive_freeze(procs, bins, ports, tmp_path):
    csv = tmp_path / "e.csv"
    r, j, _, _ = sim_against_pc(procs, bins, ports, "freeze", "--csv", csv)
    assert r.returncode == 0, r.stdout
    rows = csv_rows(csv)
    # one row per axis (docs/csv.md): ticks whose "sent" is 0, each counted once
    silent = {row["tick"] for row in rows if row["sent"] == "0"}
    assert len(silent) == 99, "freeze: ticks without a packet (200 ms at 2 ms)"
    text = csv.read_text()
    assert ",502," in text and ",503," in text, "freeze: 502/503 not sent"
    assert j["errors"] == []


def test_selector_forces_mode_0(procs, bins, ports):
    r, j, _, _ = sim_against_pc(procs, bins, ports, "selector")
    assert r.returncode == 1, r.stderr
    assert any(e.get("message") == "C4GOpen: arm 1 , forced 0 modality" for e in j["errors"]), j["errors"]
    assert j["scenario"]["expect_failed"] == 0
