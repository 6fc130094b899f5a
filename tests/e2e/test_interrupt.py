# SPDX-License-Identifier: MIT
"""Interrupting a tool (docs/cli.md, "Interrupting a tool"): one rule for the family, checked
with a real signal on a running process of each tool: SIGINT exits 130 (as a shell reports an
interrupted command) after the report that was due; SIGTERM exits 0 in the two servers
(c4g-server, cell-sim: how a service manager stops them) and 143 elsewhere."""
import signal
import socket
import threading
import time

import pytest

from e2elib import wait_until

CAPTURE = "fixtures/replay/data-clean.pcap"


def listening_tcp(port):
    try:
        socket.create_connection(("127.0.0.1", port), 0.5).close()
        return True
    except OSError:
        return False


def server(procs, port, name):
    h = procs.start([procs.bins.server, "-p", port, "-b", "127.0.0.1", "--controller", "127.0.0.1",
                     "--persist", "--lost-timeout-ms", 60000], name=name)
    wait_until(lambda: "listening on" in h.out() or not h.running(), 30, "c4g-server listening")
    return h


@pytest.fixture
def tools(procs, bins):
    """procs, with the tools at hand"""
    procs.bins = bins
    return procs


def stop(h, sig):
    h.signal(sig)
    return h.wait(30)


@pytest.mark.parametrize("sig,want", [(signal.SIGINT, 130), (signal.SIGTERM, 0)], ids=["int", "term"])
def test_c4g_server(tools, ports, sig, want):
    h = server(tools, ports.udp(), "srv")
    time.sleep(0.2)
    assert stop(h, sig) == want, h.out()
    assert "stopped by %s (exit code %d)" % (sig.name, want) in h.out(), h.out()


@pytest.mark.parametrize("sig,want", [(signal.SIGINT, 130), (signal.SIGTERM, 143)], ids=["int", "term"])
def test_c4g_sim(tools, bins, ports, sig, want):
    port = ports.udp()
    srv = server(tools, port, "srv")
    sim = tools.start([bins.sim, "-s", "127.0.0.1", "-p", port], name="sim")
    time.sleep(1.0)  # the session runs (the summary below shows its replies)
    assert sim.running(), sim.out()
    assert stop(sim, sig) == want, sim.out()
    out = sim.out()
    assert ": interrupted (exit %d)" % want in out, out
    assert "replies ok " in out, "the summary of the session, not the short one: " + out
    stop(srv, signal.SIGTERM)


def echo_pc(port, stop_evt):
    """answers every datagram with its own bytes: not a valid PC, but one that answers"""
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind(("127.0.0.1", port))
    s.settimeout(0.1)
    while not stop_evt.is_set():
        try:
            d, a = s.recvfrom(2048)
            s.sendto(d, a)
        except socket.timeout:
            pass
    s.close()


def test_c4g_replay_live(tools, bins, ports):
    port = ports.udp()
    done = threading.Event()
    th = threading.Thread(target=echo_pc, args=(port, done), daemon=True)
    th.start()
    try:
        live = tools.start([bins.replay, "live", CAPTURE, "--target", "127.0.0.1:%d" % port, "--loop", 1000],
                           name="live")
        time.sleep(1.5)
        assert live.running(), live.out()
        assert stop(live, signal.SIGINT) == 130, live.out()
        assert "(interrupted)" in live.out(), live.out()
    finally:
        done.set()
        th.join(5)


@pytest.mark.parametrize("sig,want", [(signal.SIGINT, 130), (signal.SIGTERM, 0)], ids=["int", "term"])
def test_cell_sim(tools, bins, ports, sig, want):
    base = ports.block(3, proto="tcp")
    h = tools.start([bins.cell_sim, "--port-base", base], name="cell")
    wait_until(lambda: listening_tcp(base) or not h.running(), 30, "cell-sim listening")
    assert stop(h, sig) == want, h.out()
    assert "stopped by %s" % sig.name in h.out(), h.out()


def test_cell_cli(tools, bins, ports):
    base = ports.block(3, proto="tcp")
    sim = tools.start([bins.cell_sim, "--port-base", base], name="cell")
    wait_until(lambda: listening_tcp(base) or not sim.running(), 30, "cell-sim listening")
    mon = tools.start([bins.cell_cli, "--port-base", base, "-r", "-1", "-i", "0.05", "robot", "sta"], name="mon")
    time.sleep(0.5)
    assert stop(mon, signal.SIGINT) == 130, mon.out()
    stop(sim, signal.SIGTERM)
