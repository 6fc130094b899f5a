# SPDX-License-Identifier: MIT
"""c4g-server end to end, faults: one dropped reply is counted and survived; 10 consecutive
raise ERR_C4GOPEN_UDP; datagrams from a foreign source address (a second socket bound to
127.0.0.2) never reach the server once its socket is connected to the controller; truncated
or corrupted packets are counted and crash neither side."""
import re

from e2elib import Checks
from srvlib import SIM_PATIENT, num

IDLE = "fixtures/server/sim_idle.scn"


def stub_stalled(r):
    """the host held up an exchange: a reply came after the stub's deadline (stale); a test
    about missing replies cannot tell such a reply from one the server left out"""
    return ((num(r.stub.get("stale")) or 0) > 0, "%s: stub: %s stale replies" % (r.name, r.stub.get("stale")))


def test_one_dropped_reply(srv):
    # (no rerun when held up: its counts allow for it, and in 2 s a late reply is common)
    r = srv.run_sim("drop1", srv.ports.udp(), IDLE, ["--skip-replies", 300])
    c = Checks()
    # missing, or unjudged if the simulator overran that deadline itself
    c.ge("controller counted the missing reply", r.sv("missing") + r.sv("unjudged"), 1)
    c.eq("controller raised no error", r.sim.get("errors"), [])
    c.eq("controller finished ok", r.simrc, 0)
    c.eq("server counted the skipped reply", r.jv("skipped"), 1)
    c.eq("server ended by 504", r.src, 0)
    c.done()


def test_ten_dropped_replies_sim(srv):
    # early (cyclic packet 20), so a host stall of the server before it cannot raise the
    # error first
    r = srv.run_sim("drop10", srv.ports.udp(), IDLE, ["--skip-replies", "20,10"], ["--max-miss", 10],
                    stop=True)
    c = Checks()
    c.ok("controller raised ERR_C4GOPEN_UDP", any(e.get("name") == "ERR_C4GOPEN_UDP" for e in r.sim["errors"]),
         r.sim.get("errors"))
    c.eq("controller exit 1 (table 17.1 error)", r.simrc, 1)
    c.eq("server skipped exactly 10", r.jv("skipped"), 10)
    c.done(disturbed=((r.sv("late") or 0) + (r.sv("stale") or 0) > 0,
                      "drop10: c4g-sim late %s, stale %s" % (r.sv("late"), r.sv("stale"))))


def test_ten_dropped_replies_stub(srv):
    r = srv.run_stub("drop10s", srv.ports.udp(), ["--script", "0:400,504:1"],
                     ["--skip-replies", "100,10", "--lost-timeout-ms", 2000])
    c = Checks()
    c.eq("stub controller raised ERR_C4GOPEN_UDP", r.stub.get("err"), "ERR_C4GOPEN_UDP")
    c.eq("stub saw 10 in a row", num(r.stub.get("max_consec_missed")), 10)
    c.done(disturbed=stub_stalled(r))


def test_nine_dropped_replies_survive(srv):
    r = srv.run_stub("drop9s", srv.ports.udp(), ["--script", "0:400,504:1"],
                     ["--skip-replies", "100,9", "--lost-timeout-ms", 2000])
    c = Checks()
    c.eq("9 in a row survive", r.stub.get("err"), "NONE")
    c.done(disturbed=stub_stalled(r))


def test_foreign_source(srv):
    r = srv.run_stub("foreign", srv.ports.udp(), ["--foreign", "127.0.0.2,5", "--script", "0:300,504:1"])
    c = Checks()
    # sent during the cyclic phase: the server's socket is connected to the controller by
    # then, so the kernel drops them. connect() keeps what was already queued: a foreign
    # datagram sent between the init echo and the connect reaches the server, which drops it
    # right after; none may come later
    c.has("the socket was connected to the controller", r.log, "socket connected to the controller 127.0.0.1:")
    t_conn = [float(t) for t in re.findall(r"\[ *([0-9.]+)\] socket connected to the controller", r.log)]
    t_drop = [float(t) for t in re.findall(r"\[ *([0-9.]+)\] dropped \d+-byte datagram from foreign source", r.log)]
    c.ok("the foreign datagrams the server saw were queued before the connect (kernel filter after it)",
         len(t_conn) == 1 and r.jv("foreign") == len(t_drop) <= 2 and all(t - t_conn[0] < 0.02 for t in t_drop),
         (t_conn, t_drop, r.jv("foreign")))
    c.eq("nothing was sent to the foreign source", num(r.stub.get("foreign_replies")), 0)
    c.eq("the controller's replies were all right", num(r.stub.get("bad")), 0)
    c.eq("server ended by 504", r.src, 0)
    c.done(disturbed=stub_stalled(r))


def test_garbage_from_the_stub(srv):
    r = srv.run_stub("garbage", srv.ports.udp(), ["--garbage-every", 3, "--script", "0:20,4:exit,0:300,504:1"],
                     ["--sine", "0.1,1,1"])
    g = num(r.stub.get("garbage"))
    c = Checks()
    c.ge("stub sent garbage", g, 100)
    c.eq("server counted every bad datagram as malformed", r.jv("malformed"), g)
    c.eq("server never answered one (all replies right)", num(r.stub.get("bad")), 0)
    c.eq("mode 4 still completed", num(r.stub.get("ph1_exit")), 1)
    c.eq("server alive to the 504 (exit 0)", r.src, 0)
    c.done(disturbed=stub_stalled(r))


def test_sim_faults(srv):
    r = srv.run_sim("simfault", srv.ports.udp(), IDLE, sim_args=SIM_PATIENT + [
        "--corrupt", 0.02, "--truncate", 0.02, "--duplicate", 0.01, "--reorder", 0.01, "--seed", 3])
    c = Checks()
    c.ge("c4g-sim faults: server counted malformed datagrams", r.jv("malformed"), 1)
    c.ok("c4g-sim faults: server exited cleanly (0 = 504, 3 = controller gone)",
         r.json.get("exit_code") in (0, 3), r.json.get("exit_code"))
    c.ok("c4g-sim faults: simulator ran to the end", "ticks" in r.sim, r.sim_err[-500:])
    c.done()
