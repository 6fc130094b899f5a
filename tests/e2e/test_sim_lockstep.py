# SPDX-License-Identifier: MIT
"""c4g-sim --lockstep: the simulated controller waits for each reply and counts it on time,
so a PC that stalls costs wall time, not replies. The test stops c4g-server with SIGSTOP for 50 ms in the middle of a 1 kHz session, once without lockstep (replies missing:
the controller went on without them) and once with it (none missing, the wait reported,
every tick of the run still played). A real C4G does not wait; this is for measuring a
model apart from the host."""
import json
import signal
import time

from e2elib import wait_until

CYCLIC = 1500


def session(procs, bins, ports, tmp_path, name, lockstep):
    port = ports.udp()
    srv = procs.start([bins.server, "-p", port, "--controller", "127.0.0.1", "--idle-timeout", 3,
                       "--max-seconds", 60, "--lost-timeout-ms", 2000, "--json-out", tmp_path / (name + ".json")],
                      name=name + "-srv")
    wait_until(lambda: "listening on" in srv.out() or not srv.running(), 30, "c4g-server listening")
    sim = procs.start([bins.sim, "--bind", "127.0.0.1", "-p", port, "-T", 1, "-n", CYCLIC, "--max-miss", 1000,
                       "--json"] + (["--lockstep"] if lockstep else []), name=name + "-sim")
    # well into the cyclic phase (the start-up takes some 30 packets): stop the PC 50 ms
    wait_until(lambda: "cyclic" in srv.out() or not sim.running(), 30, "the session at the PC")
    time.sleep(0.4)
    assert sim.running(), sim.out()[-2000:]
    srv.signal(signal.SIGSTOP)
    time.sleep(0.05)
    srv.signal(signal.SIGCONT)
    assert sim.wait(60) == 0, sim.out()[-2000:]
    out = sim.out()
    j = json.loads(out[out.index("{"):])
    srv.signal(signal.SIGTERM)
    srv.wait(30)
    return j, srv.out()


def test_lockstep_absorbs_a_stalled_pc(procs, bins, ports, tmp_path):
    rt, _ = session(procs, bins, ports, tmp_path, "rt", False)
    ls, log = session(procs, bins, ports, tmp_path, "ls", True)
    lost_rt = rt["replies"]["missing"] + rt["replies"]["unjudged"]
    # 50 ms at 1 kHz: some 50 packets went out while the PC was stopped
    assert lost_rt >= 20, "without lockstep the stop must cost replies: %s" % rt["replies"]
    assert rt["lockstep"] is False and rt["lockstep_waits"] == 0
    assert ls["lockstep"] is True
    assert ls["replies"]["missing"] == 0 and ls["replies"]["unjudged"] == 0, ls["replies"]
    assert ls["replies"]["stale"] == 0, ls["replies"]
    assert ls["lockstep_waits"] >= 1, ls
    assert ls["lockstep_wait_max_us"] >= 30000.0, ls
    assert ls["errors"] == [], ls["errors"]
    # simulated time is one period per packet: every tick asked for was played and answered
    assert ls["packets"]["cyclic"] == CYCLIC, ls["packets"]
    assert ls["replies"]["ok"] >= CYCLIC, ls["replies"]
    # the PC was not told it lost its controller
    srv = json.loads((tmp_path / "ls.json").read_text())
    assert srv.get("lost", 0) == 0, srv


def test_lockstep_refused_with_capture(bins):
    import subprocess
    r = subprocess.run([str(bins.sim), "--capture", "fixtures/replay/mode0.pcap", "--lockstep", "-p", "9"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 2
    assert "--lockstep is for the model" in r.stderr


def test_lockstep_help_says_it_is_not_a_c4g(bins):
    import subprocess
    r = subprocess.run([str(bins.sim), "--help"], capture_output=True, text=True, timeout=30)
    assert "--lockstep" in r.stdout and "not what a real C4G does" in " ".join(r.stdout.split())
