# SPDX-License-Identifier: MIT
"""c4g-server end to end, floods and amplification:
  a) 30 synchronization packets of 48 bytes (1 axis) to a server in its start-up: the first
     18 (the handshake's 9, each of which may be duplicated on the path) get the field's
     732-byte reply, the rest none. At most 18 x 732 bytes per start-up.
  b) c4g-sim runs 3000 ticks (6 s, the real controller's patience: 10 missing replies in a
     row raise ERR_C4GOPEN_UDP) against the server while a sender on 127.0.0.2, which -c
     refuses, sends zero-filled 228-byte datagrams as fast as one process can, for 4 s, from
     the moment the server's socket is connected to the controller. The kernel drops them
     (the server sees none of them: foreign_address 0), and the session holds without --rt.
The flood and the simulator share the host's 2 cores with the busy loops: a failed run that
the host held up (c4g-sim overran its own period) is made again."""
import json
import signal

from e2elib import Checks, host_disturbed, kv, wait_until
from srvlib import Run, attacker, num


def test_amplification(srv):
    # (python can take a second to start on the loaded host: the server waits for it, and is
    # stopped once the attacker is done)
    port = srv.ports.udp()
    h = srv.start_server("amp", port)
    a = attacker(srv.procs, "amp.atk", port, "sync48", "--count", 30, "--gap-us", 1000, "--listen-s", 0.5)
    a.wait(60)
    h.signal(signal.SIGTERM)
    r = srv.wait_server(h, Run("amp"))
    atk = kv(a.log)
    c = Checks()
    c.eq("amp: 30 sent, 18 answered", (num(atk.get("sent")), num(atk.get("replies"))), (30, 18))
    c.eq("amp: 18 x 732 bytes back (for 30 x 48 = 1440 sent)", num(atk.get("reply_bytes")), 13176)
    c.eq("amp: the rest counted as sync_excess", r.jv("sync_excess"), 12)
    c.has("amp: logged", r.log, "dropped a 48-byte sync: more than 18 before an init packet, not answered")
    c.done()


def test_flood_during_a_session(srv, bins):
    port = srv.ports.udp()
    h = srv.start_server("flood", port)
    sim = srv.procs.start([bins.sim, "-p", port, "-n", 3000, "--json"], name="flood.sim")
    wait_until(lambda: "socket connected to the controller" in h.out() or not h.running(), 20,
               "the server's socket connected to the controller")
    fl = srv.procs.run([bins.helper("flood"), port, "127.0.0.2", 228, 4], timeout=60)
    simrc = sim.wait(60)
    h.signal(signal.SIGTERM)
    r = srv.wait_server(h, Run("flood"))
    r.simrc = simrc
    r.sim = json.loads(next((l for l in sim.out().splitlines() if l.startswith("{")), "{}"))
    # the host held a failed run up: c4g-sim overran its own period (the flood, the busy
    # loops and both processes share 2 cores). A real loss fails both runs.
    host_disturbed(r.sim.get("result") != "ok" and (r.sim.get("overruns") or 0) > 0,
                   "flood: c4g-sim result %s with %s overruns of its own" % (r.sim.get("result"), r.sim.get("overruns")))
    f = dict(x.split("=", 1) for x in fl.stdout.split() if "=" in x)
    print("       flood: %s; c4g-sim: result %s, missing %s, max in a row %s" % (
        fl.stdout.strip(), r.sv("result"), r.sv("missing"), r.sv("max_consecutive_missing")))
    c = Checks()
    c.ge("flood: the flood ran (>= 20000 datagrams)", num(f.get("sent")), 20000)
    c.has("flood: the socket was connected to the controller", r.log, "socket connected to the controller 127.0.0.1:")
    c.eq("flood: c4g-sim exit 0, result ok (no ERR_C4GOPEN_UDP)", (r.simrc, r.sv("result")), (0, "ok"))
    c.eq("flood: the server did not lose the controller", r.jv("lost"), 0)
    c.eq("flood: none of the flood reached the server (foreign_address 0)", r.jv("foreign_address"), 0)
    c.done()
