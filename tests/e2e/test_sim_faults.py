# SPDX-License-Identifier: MIT
"""c4g-sim fault injection on its own packets (drop, delay, duplicate, reorder, corrupt,
truncate, pause) is applied and counted; the PC side sees it; --seed makes runs repeat
(identical per-tick CSV), a different seed changes the noise."""
import re

from simlib import STALL_OK, run_sim, sim_json, start_pc, stop_pc


def test_faults_injected_and_counted(procs, bins, ports):
    port = ports.udp()
    pc = start_pc(procs, bins, port)
    r = run_sim(procs, bins, "-p", port, "-n", 1000, "--max-miss", 1000, "--seed", 3,
                "--drop", 0.02, "--duplicate", 0.02, "--reorder", 0.02, "--corrupt", 0.02,
                "--truncate", 0.02, "--delay", "0.02:200", "--json")
    assert r.returncode == 0, r.stderr
    j = sim_json(r)
    for f in ("drop", "duplicate", "reorder", "corrupt", "truncate", "delay"):
        assert j["faults"][f] > 0, "fault %s not injected/counted: %s" % (f, j["faults"])
    # unanswered = missing, or unjudged when the simulator itself overran that deadline
    m = j["replies"]["missing"] + j["replies"]["unjudged"]
    assert m >= j["faults"]["drop"], \
        "dropped packets must go unanswered (missing + unjudged %d, dropped %d)" % (m, j["faults"]["drop"])
    log = stop_pc(pc, port)
    assert re.search(r"dropped [1-9]", log), "the PC rejected no corrupted/truncated datagram: " + log


def test_pause(procs, bins, ports):
    port = ports.udp()
    start_pc(procs, bins, port)
    r = run_sim(procs, bins, "-p", port, "-n", 300, "--pause", "100:30", "--max-miss", 1000, "--json")
    assert r.returncode == 0, r.stderr
    j = sim_json(r)
    assert j["paused_ticks"] == 30
    assert j["packets"]["cyclic"] == 270


def sent_columns(path):
    """The simulator's own columns (docs/csv.md): t_s..rx_e3 (the packet sent) and tick,
    sent; the tx_* columns and reply_ok depend on when the PC's replies came."""
    lines = path.read_text().splitlines()
    assert re.match(r"^t_s,num,axis,arm,logical,rx_mode,.*,tx_d5,tick,sent,reply_ok,rx_infpar,rx_cmd$",
                    lines[0]), "CSV header: " + lines[0]
    out = []
    for line in lines:
        c = line.split(",")
        out.append(",".join(c[0:14] + [c[21], c[22], c[24], c[25]]))
    return out


def test_seed_repeats(procs, bins, ports, tmp_path):
    # same seed -> identical CSV (what the simulator sent; what it received depends on host
    # timing and is left out); another seed -> different measurement noise
    csvs = []
    for k, seed in enumerate((42, 42, 43)):
        port = ports.udp()
        start_pc(procs, bins, port)
        path = tmp_path / ("s%d.csv" % k)
        r = run_sim(procs, bins, "-p", port, "-S", "fixtures/scenarios/mode0.scn", *STALL_OK,
                    "--seed", seed, "--csv", path, "-q")
        assert r.returncode == 0, "seed run %d: %s" % (k + 1, r.stderr)
        csvs.append(sent_columns(path))
    assert csvs[0] == csvs[1], "--seed 42 twice: CSVs differ, first at line %d" % next(
        i for i, (a, b) in enumerate(zip(csvs[0], csvs[1])) if a != b)
    assert len(csvs[0]) > 1
    assert csvs[0] != csvs[2], "--seed 43 gave the same CSV as --seed 42"
