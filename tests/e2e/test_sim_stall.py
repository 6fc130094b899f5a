# SPDX-License-Identifier: MIT
"""c4g-sim does not blame the PC for its own lateness: the test stops the simulator process
(SIGSTOP .. SIGCONT, as a busy host deschedules it) for more than 10 periods, several times,
while the reference PC answers. The replies that waited in the simulator's socket arrived
before their deadlines (kernel receive timestamps), so none may count as missing, and the
stalls must show as the simulator's own overruns. On a busy host the reference PC is
descheduled too, and then its replies are really late: it logs every reply it sent more
than 1 ms after its packet arrived (the simulator leaves it at least 1.5 ms), and each
missing reply must be one of those."""
import re
import signal
import time

from e2elib import wait_until
from simlib import STALL_OK, json_line, start_pc, stop_pc

STOPS = 5


def test_own_stalls_are_overruns(procs, bins, ports):
    port = ports.udp()
    pc = start_pc(procs, bins, port, "--slow-us", 1000, idle_ms=300)
    sim = procs.start([bins.sim, "--bind", "127.0.0.1", "-p", port, "-n", 1500] + STALL_OK
                      + ["-v", "--json"], name="sim")
    wait_until(lambda: "ref_pc: cyclic" in pc.out(), 30, "a cyclic packet at the PC")
    for i in range(STOPS):
        # each stop lasts at least 30 ms (15 periods); a busy host only makes it longer
        assert sim.running(), "c4g-sim ended before stop %d" % (i + 1)
        sim.signal(signal.SIGSTOP)
        time.sleep(0.03)
        sim.signal(signal.SIGCONT)
        time.sleep(0.05)
    assert sim.wait(60) == 0, sim.out()[-2000:]
    log = stop_pc(pc, port)
    out = sim.out()
    j = json_line(out)
    assert j["overruns"] >= STOPS, "overruns %d, want >= %d (one per stop at least)" % (
        j["overruns"], STOPS)
    missing = set(re.findall(r"Rx Debug \(NUM (\d+),", out))
    slow = set(re.findall(r"^ref_pc: slow reply to NUM (\d+):", log, re.M))
    assert len(missing) == j["replies"]["missing"], "missing replies in the summary and in the log"
    unexplained = sorted(missing - slow, key=int)
    assert not unexplained, "missing replies the PC sent in time (NUM %s): the simulator " \
        "blamed the PC" % " ".join(unexplained)
