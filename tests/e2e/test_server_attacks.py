# SPDX-License-Identifier: MIT
"""c4g-server end to end, forged datagrams during a live session: c4g-sim (the controller,
127.0.0.1, its own port) runs a mode-9 scenario against c4g-server with a current
feedforward that asks for more than AzLim (fixtures/server/ff_saturating.txt), while a small
attacker (tests/e2e/helpers/attacker.py) sends from 127.0.0.1 on ANOTHER port, or from
127.0.0.2:
  a) a valid initialization packet with AzLim 1e6 and FollowError 0
  b) a cyclic packet with 504 (end of communication) on every axis
  c) 508 on every axis with a fake actual position and an old NUM
  d) a cyclic packet with an undefined mode (and one with mode 3, defined, not available)
  e) 2000 zero-filled 228-byte datagrams (the controller's cyclic size)
  f) a 4-byte datagram, before the controller starts and mid-session
  g) a 504 from 127.0.0.2 while the server pauses in active freezing, so that it is queued
     for the drain after the pause (server -c any: the session's endpoint check refuses
     it; and --controller 127.0.0.1: the address filter does)
For each: the controller's session finishes normally (c4g-sim result ok, EXPECTs passed, no
controller error, the server ends on the controller's own 504), every current the server
sent keeps SMP+ current + delta within the real AzLim (figure 10.1, the values c4g-sim
sends; checked on every row of the server's --moni CSV), nothing went back to the attacker
(its socket and the server's --pcap). Once the session is cyclic the server's socket is
connect()ed to the controller, so a mid-session attack never reaches the server at all: its
--json counts nothing (foreign 0) and its log shows the socket connected before the
attacker's trigger. Before the session locks (f, a 4-byte datagram first) the datagram is
counted under its own name (malformed_length).
Robust on a loaded host (the loss timeout and the controller's patience are not under test
here; test_server_stall.py tests them): c4g-sim runs with --max-miss 50, the server with
--lost-timeout-ms 5000: a 2-core test host with CPU steal can hold either process up for
tens of ms, even a second. A server that stops answering (a session ended by a forged 504)
still trips the simulator. The freezing runs allow 400 (the simulator only stops checking
replies once it has applied the reply that carried 500; under load that reply can miss its
tick)."""
import pytest

from e2elib import Checks, kv
from srvlib import Run, attacker, currents, num, pcap_port_counts, read_sim

INIT = "fixtures/vectors/init-fig10-1.bin"   # the controller's real AzLim (c4g-sim: figure 10.1)
FF = "fixtures/server/ff_saturating.txt"
MODE9 = "axis.1:.mode.0.->.9"                # server log line: the controller entered mode 9
M9SCN = "fixtures/server/sim_mode9.scn"


def attack(srv, name, scn, kind, aopts, server_args, miss=50, pcap=True):
    """server, then the attacker in the background (it waits for its log pattern, given as
    aopts' "{log}"), then c4g-sim in the foreground"""
    port = srv.ports.udp()
    args = ["--lost-timeout-ms", 5000] + (["--pcap", srv.path(name + ".pcap")] if pcap else []) + server_args
    h = srv.start_server(name, port, *args)
    a = attacker(srv.procs, name + ".atk", port, kind, *[h.log if o == "{log}" else o for o in aopts])
    r = Run(name)
    read_sim(r, srv.sim(port, "-S", scn, "--json", "--max-miss", miss))
    a.wait(60)
    srv.wait_server(h, r)
    r.atk = kv(a.log)
    r.pcap = srv.path(name + ".pcap") if pcap else None
    return r


def figures(r):
    keys = ["foreign", "foreign_address", "foreign_init", "foreign_cyclic", "foreign_other", "malformed",
            "malformed_length", "malformed_phase", "out_of_order", "init", "cyclic", "delta_clamps",
            "follow_error_508", "drive_off_505"]
    print("       server: " + " ".join("%s=%s" % (k, r.jv(k)) for k in keys))
    print("       c4g-sim: result=%s missing=%s attacker: sent=%s replies=%s" % (
        r.sv("result"), r.sv("missing"), r.atk.get("sent"), r.atk.get("replies")))


def session_ok(c, r):
    """the controller's session ended normally, nothing reached the attacker"""
    n = r.name
    figures(r)
    c.eq("%s: c4g-sim exit 0, result ok" % n, (r.simrc, r.sv("result")), (0, "ok"))
    c.eq("%s: scenario EXPECTs passed, no controller error" % n, (r.sv("expect_failed"), r.sim.get("errors")), (0, []))
    c.eq("%s: server ended on the controller's 504 (exit 0)" % n, r.src, 0)
    # every cyclic packet the controller sent was served, or dropped unread by the drain
    # after an active freezing (counted as missed: a NUM gap)
    c.eq("%s: server saw every cyclic packet the controller sent (cyclic + missed)" % n,
         (r.jv("cyclic") or 0) + (r.jv("missed") or 0), r.sv("cyclic"))
    c.eq("%s: one initialization packet accepted" % n, r.jv("init"), 1)
    c.eq("%s: the attacker sent after its trigger" % n, num(r.atk.get("waited")), 1)
    c.eq("%s: nothing came back to the attacker's socket" % n, num(r.atk.get("replies")), 0)
    if r.pcap is not None and r.pcap.exists() and r.pcap.stat().st_size:
        c.eq("%s: no datagram to the attacker's port in the server's capture" % n,
             pcap_port_counts(r.pcap, num(r.atk.get("lport")))["to_port"], 0)


def currents_ok(c, r, srv):
    """every current sent kept SMP+ current + delta within the real AzLim"""
    cur = currents(srv.path(r.name + ".moni"), INIT)
    c.ge("%s: the server sent mode-9 currents" % r.name, cur["current_rows"], 100)
    c.eq("%s: every current within the real AzLim (max |total|/AzLim %.4f)" % (r.name, cur["max_total_ratio"]),
         (cur["over"], cur["over_rows"]), (0, []))
    c.ge("%s: the AzLim clamp was exercised" % r.name, r.jv("delta_clamps"), 1)


def kernel_filtered(c, r):
    """the attack came after the socket was connected to the controller, and nothing of it
    reached the server (every foreign counter 0)"""
    c.has("%s: the socket was connected to the controller (kernel filter)" % r.name, r.log,
          r"socket connected to the controller 127\.0\.0\.1:")
    c.eq("%s: nothing reached the server (foreign, malformed)" % r.name, (r.jv("foreign"), r.jv("malformed")), (0, 0))


def m9(srv, name, kind, aopts):
    """a mode-9 session under attack"""
    r = attack(srv, name, M9SCN, kind, aopts, ["--ff", FF, "--duration", 1, "--moni", srv.path(name + ".moni")])
    c = Checks()
    session_ok(c, r)
    currents_ok(c, r, srv)
    kernel_filtered(c, r)
    return c, r


def test_a_forged_init(srv):
    # AzLim 1e6, FollowError 0, from 127.0.0.1:other port
    c, r = m9(srv, "init", "init", ["--wait", "{log}", "cyclic.communication.started"])
    c.eq("init: not taken as a mid-session init (malformed_phase 0)", r.jv("malformed_phase"), 0)
    c.done()


def test_b_forged_504(srv):
    c, _ = m9(srv, "e504", "end504", ["--wait", "{log}", MODE9])
    c.done()


def test_c_forged_508(srv):
    # fake actual position, old NUM
    c, r = m9(srv, "f508", "fe508", ["--wait", "{log}", MODE9])
    c.eq("508: not seen as an out-of-order packet of the session", r.jv("out_of_order"), 0)
    c.eq("508: no following error, no drive off in the replies", (r.jv("follow_error_508"), r.jv("drive_off_505")), (0, 0))
    c.done()


@pytest.mark.parametrize("kind,label", [("mode", "mode 7777"), ("mode3", "mode 3")])
def test_d_bad_mode(srv, kind, label):
    # undefined mode (7777) and mode 3 (not available)
    c, r = m9(srv, "b" + kind, kind, ["--wait", "{log}", MODE9])
    c.eq("%s: no drive off (505)" % label, r.jv("drive_off_505"), 0)
    c.done()


def test_e_zero_flood(srv):
    # 2000 zero-filled 228-byte datagrams, 50 us apart; no pcap here: 2000 records would
    # overflow the log ring, which is what it is for
    r = attack(srv, "flood", M9SCN, "zeros", ["--wait", "{log}", MODE9, "--count", 2000, "--gap-us", 50],
               ["--ff", FF, "--duration", 1, "--moni", srv.path("flood.moni")], pcap=False)
    c = Checks()
    session_ok(c, r)
    currents_ok(c, r, srv)
    c.eq("flood: all 2000 sent", num(r.atk.get("sent")), 2000)
    kernel_filtered(c, r)
    c.done()


def test_f_tiny_before_start(srv):
    # 4-byte datagram before the controller: the session is not locked yet, the datagram is
    # no sync packet (no 732-byte answer to anyone)
    port = srv.ports.udp()
    h = srv.start_server("tiny0", port, "--lost-timeout-ms", 5000, "--ff", FF, "--duration", 1,
                         "--moni", srv.path("tiny0.moni"), "--pcap", srv.path("tiny0.pcap"))
    a = attacker(srv.procs, "tiny0.atk", port, "tiny", "--listen-s", 0.3)
    a.wait(60)
    r = Run("tiny0")
    read_sim(r, srv.sim(port, "-S", M9SCN, "--json", "--max-miss", 50))
    srv.wait_server(h, r)
    r.atk = kv(a.log)
    r.pcap = srv.path("tiny0.pcap")
    c = Checks()
    session_ok(c, r)
    c.eq("tiny before start-up: counted as malformed_length", r.jv("malformed_length"), 1)
    c.eq("tiny before start-up: no sync packet taken from it", r.jv("sync"), 11)
    c.done()


def test_f_tiny_mid_session(srv):
    c, _ = m9(srv, "tiny", "tiny", ["--wait", "{log}", MODE9])
    c.done()


@pytest.mark.parametrize("ctrl", ["any", "127.0.0.1"])
def test_g_504_queued_for_the_drain(srv, ctrl):
    # a 504 from 127.0.0.2 sent during an active freezing (500 ms), when the drain reads the
    # queue: the socket is connected to the controller before the pause, so the kernel drops
    # the forged 504, and neither the drain after the pause nor the session ever sees it
    name = "drain" if ctrl == "any" else "draina"
    r = attack(srv, name, "fixtures/server/sim_idle.scn", "end504",
               ["--src", "127.0.0.2", "--wait", "{log}", "active.freezing:.pausing"],
               (["--controller", "any"] if ctrl == "any" else []) + ["--freeze", "300,500"], miss=400)
    c = Checks()
    session_ok(c, r)
    if ctrl == "any":
        c.eq("drain (-c any): the server paused once", r.jv("active_freezings"), 1)
    c.has("drain (-c %s): the pause ended with the controller's newest packet answered" % ctrl, r.log,
          "active freezing over: .*[^0-9]0 foreign")
    kernel_filtered(c, r)
    c.done()
