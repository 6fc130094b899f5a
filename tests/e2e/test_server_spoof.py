# SPDX-License-Identifier: MIT
"""c4g-server end to end, a sender that takes the controller's place: c4g-sim is the
controller (mode-9 scenario, figure 10.1's AzLim), the server runs a saturating current
feedforward (fixtures/server/ff_saturating.txt).
  a) an init packet with AzLim 1e6 A, from the controller's own address and port, between
     its last sync (NUM 9) and its own init: refused by the ceiling (--az-lim-max, 200 A),
     named in the log; the controller's init is taken, its session ends normally and every
     current sent stays within the real AzLim
  b) the same with AzLim 150 A (under the ceiling): two different init packets in one
     start-up, both refused ("init conflict"); nothing is answered afterwards, no current is
     ever sent, the controller gives up (ERR_C4GOPEN_UDP) and the server ends on the loss
     (exit 3)
  c) a 504 from the controller's endpoint while axis 1 is in mode 9: the session ends (the
     PC stops answering: the controller turns its drives off) and the log says "504 out of
     procedure"
  d) -c any: a sync from 127.0.0.2 before the controller's first: the session's start-up is
     contended, both refused and logged; the controller gets no reply
  e) the controller stalls 3 s (its loss timeout 1 s), then another endpoint's sync
     (127.0.0.1, another port) starts a new session: served, logged as a new peer; the
     controller's packets after its stall are not answered (it gives up)
a) to c) spoof the controller's address and port with a raw socket: their processes run in a
network namespace of the test's own (unshare -rn, entered with nsenter), and are skipped
with the reason where that is not permitted; d) and e) need no privilege."""
import shutil
import signal
import struct
import subprocess
import sys

import pytest

from e2elib import Checks, ROOT, kv, wait_until
from srvlib import Run, attacker, currents, num, read_sim

SPOOF = ROOT / "tests" / "e2e" / "helpers" / "spoof.py"
INIT = "fixtures/vectors/init-fig10-1.bin"
FF = "fixtures/server/ff_saturating.txt"
SCN = "fixtures/server/sim_mode9.scn"


def forged_init(azlim, path):
    """figure 10.1's init packet with AzLim azlim on its open axes"""
    b = bytearray((ROOT / INIT).read_bytes())
    for k in range(40):
        if struct.unpack_from("<f", b, 548 + 4 * k)[0] > 0:
            struct.pack_into("<f", b, 548 + 4 * k, azlim)
    path.write_bytes(bytes(b))
    return path


@pytest.fixture
def netns(procs):
    """a network namespace of the test's own (its loopback up), held by a sleeping process;
    the command prefix that runs a process inside it"""
    if not shutil.which("unshare") or not shutil.which("nsenter"):
        pytest.skip("a) to c) skipped: unshare/nsenter not installed")
    probe = subprocess.run(["unshare", "-rn", "true"], capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip("a) to c) skipped: cannot create a network namespace (unshare -rn: %s)"
                    % (probe.stderr.strip().splitlines() or ["?"])[0])
    h = procs.start(["unshare", "-rn", "sh", "-c",
                     "{ ip link set lo up 2>/dev/null || ifconfig lo up; } && echo up && exec sleep 300"],
                    name="netns")
    wait_until(lambda: "up" in h.out() or not h.running(), 20, "the network namespace's loopback up")
    assert h.running(), "netns: " + h.out()
    return ["nsenter", "-t", str(h.pid), "-U", "-n", "--preserve-credentials"]


def spoofed(srv, name, trig, file=None):
    """server, the spoofer watching for its trigger, c4g-sim; all in srv.wrap's namespace"""
    port = srv.ports.udp()
    h = srv.start_server(name, port, "--lost-timeout-ms", 1000, "--ff", FF, "--duration", 1,
                         "--moni", srv.path(name + ".moni"))
    k = srv.procs.start(srv.wrap + [sys.executable, "-u", SPOOF, trig, port] + ([file] if file else []),
                        name=name + ".spoof")
    wait_until(lambda: "ready=1" in k.out() or not k.running(), 20, "the spoofer ready")
    r = Run(name)
    read_sim(r, srv.sim(port, "-S", SCN, "--json", "--max-miss", 50))
    k.wait(60)
    srv.wait_server(h, r)
    r.spoof = kv(k.log)
    return r


def spoofer_late(r):
    """the spoofer (a python process) sends its init after seeing the controller's sync NUM
    9; the controller sends its own 2 ms later: a host that holds the spoofer up that long
    puts the forged init second on the wire, which is another case than the one under test"""
    return (r.spoof.get("first_init") == "controller",
            "%s: the controller's init crossed the loopback before the forged one" % r.name)


def test_a_injected_init_over_the_ceiling(srv, netns):
    srv.wrap = netns
    r = spoofed(srv, "inj1e6", "init9", forged_init(1e6, srv.path("init1e6.bin")))
    cur = currents(srv.path("inj1e6.moni"), INIT)
    c = Checks()
    c.eq("inj1e6: the forged init reached the server before the controller's", r.spoof.get("first_init"), "forged")
    c.eq("inj1e6: the spoofer fired after sync NUM 9", (r.spoof.get("fired"), r.spoof.get("num")), ("1", "9"))
    c.has("inj1e6: refused by the ceiling, value and ceiling named", r.log,
          r"refused the initialization packet: AzLim of arm 1 axis 1 is 1e\+06 A, above this cell's ceiling 200 A")
    c.eq("inj1e6: counted as malformed_ceiling", r.jv("malformed_ceiling"), 1)
    c.eq("inj1e6: the controller's init taken (init 1), no conflict", (r.jv("init"), r.jv("init_conflicts")), (1, 0))
    c.eq("inj1e6: c4g-sim exit 0, result ok", (r.simrc, r.sv("result")), (0, "ok"))
    c.eq("inj1e6: server ended on the controller's 504", r.src, 0)
    c.ge("inj1e6: the server sent mode-9 currents", cur["current_rows"], 100)
    c.eq("inj1e6: every current within the real AzLim (max |total|/AzLim %.4f)" % cur["max_total_ratio"],
         (cur["over"], cur["over_rows"]), (0, []))
    c.done(disturbed=spoofer_late(r))


def test_b_injected_init_under_the_ceiling(srv, netns):
    srv.wrap = netns
    r = spoofed(srv, "inj150", "init9", forged_init(150, srv.path("init150.bin")))
    cur = currents(srv.path("inj150.moni"), INIT)
    c = Checks()
    c.eq("inj150: the forged init reached the server before the controller's", r.spoof.get("first_init"), "forged")
    c.eq("inj150: the spoofer fired after sync NUM 9", (r.spoof.get("fired"), r.spoof.get("num")), ("1", "9"))
    c.has("inj150: the conflict logged, the field named", r.log,
          r"ATTACK\? init conflict: a second initialization packet differs from the one accepted "
          r"\(AzLim of arm 1 axis 1: ")
    c.eq("inj150: init_conflicts 1", r.jv("init_conflicts"), 1)
    # whether the controller sends anything after its own init depends on when the echo of
    # the forged one reaches it (it gives up on that echo): refused datagrams may be 0
    c.ok("inj150: the session answered nothing after it (cyclic 0; refused %s)" % r.jv("refused"),
         r.jv("cyclic") == 0, (r.jv("cyclic"), r.jv("refused")))
    c.eq("inj150: no current ever sent (no moni row)", cur["rows"], 0)
    c.eq("inj150: the controller gave up (exit 1, error raised)", (r.simrc, r.sv("result")), (1, "error"))
    c.eq("inj150: the server ended on the loss (exit 3)", r.src, 3)
    c.done(disturbed=spoofer_late(r))


def test_c_504_in_mode_9(srv, netns):
    srv.wrap = netns
    r = spoofed(srv, "e504", "mode9")
    c = Checks()
    c.eq("e504: the spoofer fired during mode 9", r.spoof.get("fired"), "1")
    c.has("e504: logged as out of procedure", r.log, r"ATTACK\? 504 out of procedure: OPEN axis 1 was in mode 9")
    c.eq("e504: end_unexpected 1", r.jv("end_unexpected"), 1)
    c.eq("e504: the session ended, the server stopped (exit 0)", r.src, 0)
    c.eq("e504: the controller, unanswered, gave up (exit 1, drives off)",
         (r.simrc, r.sv("result"), any(a["drive_on"] for a in r.sim.get("robot", []))), (1, "error", False))
    c.done()


def test_d_contended_start(srv):
    # -c any: a forged sync from 127.0.0.2 before the controller's first
    port = srv.ports.udp()
    h = srv.start_server("cont", port, "--controller", "any", "--lost-timeout-ms", 1000)
    a = attacker(srv.procs, "cont.atk", port, "sync", "--src", "127.0.0.2", "--listen-s", 0.3)
    a.wait(60)
    r = Run("cont")
    read_sim(r, srv.sim(port, "-S", SCN, "--json"))
    srv.wait_server(h, r)
    c = Checks()
    c.has("cont: the contention logged with both endpoints", r.log,
          r"ATTACK\? start-up contended: a 228-byte start-up packet from 127\.0\.0\.1:")
    c.eq("cont: contended 1", r.jv("contended"), 1)
    c.eq("cont: no init accepted, no cyclic packet answered", (r.jv("init"), r.jv("cyclic")), (0, 0))
    c.eq("cont: the controller got no reply and gave up (exit 1)", (r.simrc, r.sv("result")), (1, "error"))
    c.done()


def test_e_new_peer_after_a_stall(srv):
    # a sync from another endpoint after the controller stalled 3 s
    port = srv.ports.udp()
    h = srv.start_server("peer", port, "--persist", "--lost-timeout-ms", 1000)
    a = attacker(srv.procs, "peer.atk", port, "sync", "--wait", h.log, "controller.lost", "--listen-s", 0.3)
    wait_until(lambda: "lport=" in a.out(), 30, "the attacker's socket")
    # a 3 s stall: the attacker (running before the controller starts) has 2 s after the
    # loss to send its sync
    r = Run("peer")
    read_sim(r, srv.sim(port, "-n", 2000, "--pause", "200:1500", "--json"))
    a.wait(60)
    h.signal(signal.SIGTERM)
    srv.wait_server(h, r)
    atk = kv(a.log)
    c = Checks()
    c.eq("peer: the attacker sent after the loss", (num(atk.get("waited")), num(atk.get("sent"))), (1, 1))
    c.has("peer: the new peer logged with both endpoints", r.log,
          r"new peer: the session is now locked to 127\.0\.0\.1:%s, not to the lost controller 127\.0\.0\.1:"
          % atk.get("lport"))
    c.eq("peer: new_peers 1", r.jv("new_peers"), 1)
    c.eq("peer: the controller, unanswered after its stall, gave up (exit 1)", (r.simrc, r.sv("result")), (1, "error"))
    c.done()
