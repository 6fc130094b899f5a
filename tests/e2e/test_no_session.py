# SPDX-License-Identifier: MIT
"""Runs in which no session ever starts fail loudly and report briefly (docs/cli.md, "When no
session starts"): real processes, real UDP on 127.0.0.1.
 1. c4g-sim to a port where nothing listens: one line on stderr naming the address, a summary
    of a few lines saying no session started instead of a page of zeros.
 2. c4g-server whose --controller is not the host that sends: it names the address the
    controller's packets come from, once, and its report is one line saying why no session
    started; with nothing sending at all, the line says no datagram came.
 3. c4g-replay live to a port where nothing listens: it stops after 10 unanswered packets
    instead of playing the whole capture, says so on stderr and exits 5."""
import json
import re
import time

from e2elib import wait_until

CAPTURE = "fixtures/replay/data-clean.pcap"


def test_sim_nothing_answered(bins, ports, procs):
    port = ports.udp()  # free: nothing listens there
    r = procs.run([bins.sim, "-s", "127.0.0.1", "-p", port, "-n", 500], timeout=30)
    assert r.returncode == 1, r.stdout + r.stderr
    want = "c4g-sim: no session started: nothing answered on 127.0.0.1:%d (is c4g-server running there?)\n" % port
    assert r.stderr == want, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].endswith(": error (exit 1)"), r.stdout
    assert lines[1].startswith("  no session started: nothing answered on 127.0.0.1:%d" % port), r.stdout
    assert "sent 10 (sync 9, init 1, cyclic 0)" in lines[1], r.stdout
    assert "ERR_C4GOPEN_UDP" in lines[2], r.stdout
    assert len(lines) == 3, "a short summary, not %d lines of zeros:\n%s" % (len(lines), r.stdout)
    # --quiet: the summary goes, the error stays
    r = procs.run([bins.sim, "-s", "127.0.0.1", "-p", port, "-n", 500, "-q"], timeout=30)
    assert (r.returncode, r.stdout, r.stderr) == (1, "", want)


def test_server_wrong_controller(bins, ports, procs):
    port = ports.udp()
    srv = procs.start([bins.server, "-p", port, "-b", "127.0.0.1", "--controller", "127.0.0.2",
                       "--idle-timeout", 3], name="srv")
    wait_until(lambda: "listening on" in srv.out() or not srv.running(), 20, "c4g-server listening")
    sim = procs.run([bins.sim, "-s", "127.0.0.1", "-p", port, "-n", 200], timeout=30)
    assert sim.returncode == 1
    assert srv.wait(30) == 4  # the idle timeout: no controller
    out = srv.out()
    src = re.search(r"dropped 228-byte datagram from foreign source (127\.0\.0\.1:\d+)", out)
    assert src, out
    hint = "the controller's packets come from %s: is that your controller? (--controller gives 127.0.0.2)" % src.group(1)
    assert out.count(hint) == 1, out
    assert out.count("is that your controller") == 1, out
    tail = out[out.index("c4g-server: session ended"):].splitlines()
    assert tail == ["c4g-server: session ended: idle timeout: no controller (exit code 4)",
                    "c4g-server: no session started: 10 datagrams came from other addresses than the "
                    "controller's (--controller 127.0.0.2); the controller's packets came from %s" % src.group(1)], out


def test_server_nothing_came(bins, ports, procs):
    port = ports.udp()
    r = procs.run([bins.server, "-p", port, "-b", "127.0.0.1", "--controller", "127.0.0.1",
                   "--idle-timeout", 0.3], timeout=30)
    assert r.returncode == 4, r.stdout + r.stderr
    assert r.stdout.splitlines() == [
        "c4g-server: session ended: idle timeout: no controller (exit code 4)",
        "c4g-server: no session started: no datagram came to 127.0.0.1:%d (is the controller, or "
        "c4g-sim, sending to this address and port?)" % port], r.stdout


def test_replay_live_stops_when_nothing_answers(bins, ports, procs):
    port = ports.udp()
    t0 = time.monotonic()
    # 50 passes of a 0.34 s capture: 17 s if it were played through
    r = procs.run([bins.replay, "live", CAPTURE, "--target", "127.0.0.1:%d" % port, "--loop", 50],
                  timeout=60)
    took = time.monotonic() - t0
    assert r.returncode == 5, r.stdout + r.stderr
    m = re.search(r"c4g-replay: live: nothing answered on 127\.0\.0\.1:%d \(is c4g-server running there\?\): "
                  r"stopped after 10 packets \([0-9.]+ s\) of pass 1 without a datagram back\n" % port, r.stderr)
    assert m, r.stderr
    assert r.stdout.splitlines()[1:] == ["result: NO ANSWER"], r.stdout
    assert "no session started: nothing answered there (stopped after 10 packets of pass 1" in r.stdout, r.stdout
    assert took < 10, "stopped early, not after the 50 passes: %.1f s" % took
    r = procs.run([bins.replay, "live", CAPTURE, "--target", "127.0.0.1:%d" % port, "--json"], timeout=60)
    assert r.returncode == 5, r.stdout + r.stderr
    rep = json.loads(r.stdout)
    assert (rep["result"], rep["packets"]["sent"], rep["passes_done"]) == ("no-answer", 10, 0), rep
