# SPDX-License-Identifier: MIT
"""c4g-sim ignores (and counts) datagrams that do not come from the configured PC: a sender
on 127.0.0.2 aims well-formed replies at the simulator's port."""
import signal
import socket

from e2elib import udp_bound, wait_until
from simlib import STALL_OK, json_line, start_pc


def test_foreign_sender_counted(procs, bins, ports):
    pc_port, sim_port = ports.udp(), ports.udp()
    start_pc(procs, bins, pc_port)
    # the simulator runs until it is told to stop (-n only bounds a broken run); the sender
    # starts once the simulator's socket is bound, so no datagram races its start-up
    sim = procs.start([bins.sim, "--bind", "127.0.0.1", "-p", pc_port, "--local-port", sim_port,
                       "-n", 20000] + STALL_OK + ["--json"], name="sim")
    wait_until(lambda: udp_bound(sim_port), 30, "c4g-sim bound to 127.0.0.1:%d" % sim_port)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.2", 0))
        for _ in range(20):
            s.sendto(bytes(12 + 36 * 6), ("127.0.0.1", sim_port))
    # loopback delivers within sendto: the 20 datagrams are in the simulator's socket now,
    # and a stopped simulator reads what already arrived before its summary
    sim.signal(signal.SIGTERM)
    assert sim.wait(30) == 143, sim.out()  # SIGTERM (docs/cli.md)
    j = json_line(sim.out())
    assert j["result"] == "interrupted"
    assert j["replies"]["foreign"] == 20
