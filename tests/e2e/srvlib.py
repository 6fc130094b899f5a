# SPDX-License-Identifier: MIT
"""c4g-server against a controller (c4g-sim, or the test stub tests/e2e/helpers/ctrl_stub.c),
for test_server_*.py. Each run's files are in the test's tmp_path under the run's name:
NAME.json (the server's summary), NAME.log (its stdout and stderr); c4g-sim's output is in
sim-PORT.json and sim-PORT.err, a helper's log in its own NAME.log.
The fixture srv is registered by conftest.py."""
import csv
import json
import pathlib
import signal
import struct
import sys

import pytest

from e2elib import ROOT, first, udp_rx_queue, wait_until

# The number of consecutive missing replies after which c4g-sim gives up (the real
# controller: 10). The server is an ordinary process that a busy host can stop for 100 ms
# (50 periods): unless a test is about the 10-in-a-row rule, such a stall is counted.
SIM_PATIENT = ["--max-miss", "500"]


class Run:
    """What one run left: the server's exit code, JSON and log; the controller's exit code
    and JSON (c4g-sim) or key=value report (stub)."""

    def __init__(self, name):
        self.name = name
        self.src = None
        self.json = {}
        self.log = ""
        self.simrc = None
        self.sim = {}
        self.sim_err = ""
        self.stub = {}

    def jv(self, key):
        return first(self.json, key)

    def sv(self, key):
        return first(self.sim, key)

    def pos(self, n):
        """robot position of OPEN axis n (1-based) from c4g-sim's summary"""
        return self.sim["robot"][n - 1]["pos"]

    def sim_late(self):
        """replies c4g-sim counted missing, stale or unjudged (the host held a side up)"""
        r = self.sim.get("replies", {})
        return r.get("missing", 0) + r.get("stale", 0) + r.get("unjudged", 0)


class Srv:
    def __init__(self, procs, bins, ports, tmp):
        self.procs, self.bins, self.ports, self.tmp = procs, bins, ports, tmp
        self.last = None
        # a command prefix for every process of the run (nsenter into a network namespace)
        self.wrap = []

    def path(self, name):
        return self.tmp / name

    def start_server(self, name, port, *args):
        """A background server whose summary goes to NAME.json; returns once it printed
        "listening on" (its socket is bound), so the controller's first packet never races
        its start-up. The loss timeout is 2 s unless a test sets its own: the controllers
        here are ordinary processes that a busy host can stop for longer than 10 periods."""
        h = self.procs.start(self.wrap + [self.bins.server, "-p", port, "--controller", "127.0.0.1", "--idle-timeout", 15,
                              "--max-seconds", 45, "--json-out", self.path(name + ".json"),
                              "--lost-timeout-ms", 2000] + list(args), name=name)
        wait_until(lambda: "listening on" in h.out() or not h.running(), 30, "server %s listening" % name)
        assert "listening on" in h.out(), "server %s did not start: %s" % (name, h.out())
        self.last = h
        return h

    def wait_server(self, h, run):
        """The server ends by itself (504, idle or --max-seconds); its exit code, JSON and
        log go to run."""
        try:
            wait_until(lambda: not h.running(), 60, "server %s to end" % run.name)
        except AssertionError:
            h.signal(signal.SIGTERM)
        run.src = h.wait(30)
        run.log = h.out()
        p = self.path(run.name + ".json")
        run.json = json.loads(p.read_text()) if p.exists() and p.stat().st_size else {}
        return run

    def sim(self, port, *args, timeout=50):
        """c4g-sim in the foreground; its stdout and stderr are also kept in sim-PORT.json
        and sim-PORT.err (for a look after a failure: --basetemp)"""
        r = self.procs.run(self.wrap + [self.bins.sim, "-p", port] + [str(a) for a in args], timeout=timeout)
        self.path("sim-%d.json" % port).write_text(r.stdout)
        self.path("sim-%d.err" % port).write_text(r.stderr)
        return r

    def run_sim(self, name, port, scn, server_args=(), sim_args=SIM_PATIENT, stop=False):
        """server + c4g-sim running scenario scn in the foreground. stop: the controller
        ends on an error (no 504), and the test does not judge how the server ends: it is
        stopped (SIGTERM, its summary still written) once it has read every datagram,
        instead of waiting for its loss timeout."""
        run = Run(name)
        h = self.start_server(name, port, *server_args)
        r = self.sim(port, "-S", scn, "--json", *sim_args)
        read_sim(run, r)
        if stop:
            self.stop_server(h, port)
        return self.wait_server(h, run)

    def stop_server(self, h, port):
        """SIGTERM once the server's socket holds no datagram (nothing left to count)"""
        wait_until(lambda: not udp_rx_queue(port) or not h.running(), 10,
                   "the server to read its socket")
        h.signal(signal.SIGTERM)

    def run_stub(self, name, port, stub_args=(), server_args=(), stop=False):
        """server + the controller stub (its replies are checked byte by byte); stop: as
        for run_sim"""
        run = Run(name)
        h = self.start_server(name, port, *server_args)
        r = self.procs.run([self.bins.helper("ctrl_stub"), "--port", port, "--reply-us", 50000]
                           + [str(a) for a in stub_args], timeout=50)
        run.stub = dict(kv_text(r.stdout))
        run.stub_err = r.stderr
        if stop:
            self.stop_server(h, port)
        return self.wait_server(h, run)


ATTACKER = ROOT / "tests" / "e2e" / "helpers" / "attacker.py"


def attacker(procs, name, port, kind, *opts):
    """tests/e2e/helpers/attacker.py in the background (its key=value report: the log)"""
    return procs.start([sys.executable, "-u", ATTACKER, port, kind] + [str(o) for o in opts], name=name)


def currents(moni, init_bin):
    """Every row of a c4g-server --moni CSV (type 0) where the server sent a current
    (tx_d5 != 0): the total SMP+ current + delta (mode 9) must stay within +/-AzLim of the
    controller's real initialization packet (AzLim at byte 548, [arm][10 axes] little-endian
    floats), or the delta must point back towards 0 (the clamp only shrinks). Returns rows,
    current_rows, over (violations, the first 5 in over_rows), max_tx_d5, max_total_ratio."""
    az = struct.unpack_from("<40f", pathlib.Path(init_bin).read_bytes(), 548)
    out = {"rows": 0, "current_rows": 0, "over": 0, "max_tx_d5": 0.0, "max_total_ratio": 0.0, "over_rows": []}
    if not pathlib.Path(moni).exists():
        return out
    with open(moni, newline="") as f:
        rd = csv.reader(f)
        head = next(rd, [])
        ix = {name: k for k, name in enumerate(head)}
        for row in rd:
            if len(row) < len(head):
                continue
            out["rows"] += 1
            tx = float(row[ix["tx_d5"]])
            if tx == 0.0:
                continue
            out["current_rows"] += 1
            smp = float(row[ix["rx_d5"]])
            lim = az[(int(row[ix["arm"]]) - 1) * 10 + int(row[ix["logical"]]) - 1]
            total = smp + tx
            out["max_tx_d5"] = max(out["max_tx_d5"], abs(tx))
            if lim > 0:
                out["max_total_ratio"] = max(out["max_total_ratio"], abs(total) / lim)
            inside = abs(total) <= lim * (1 + 1e-5)
            shrinks = (tx > 0 and total <= smp) or (tx < 0 and total >= smp)
            if not inside and not shrinks:
                out["over"] += 1
                if out["over"] <= 5:
                    out["over_rows"].append("AzLim %.3f: %s" % (lim, ",".join(row)))
    return out


def pcap_port_counts(path, port):
    """Datagrams of a c4g-server --pcap capture to and from UDP port `port`."""
    data = pathlib.Path(path).read_bytes()
    magic = struct.unpack_from("<I", data, 0)[0]
    end = "<" if magic in (0xA1B2C3D4, 0xA1B23C4D) else ">"
    off = 24
    out = {"frames": 0, "to_port": 0, "from_port": 0}
    while off + 16 <= len(data):
        incl = struct.unpack_from(end + "I", data, off + 8)[0]
        frame = data[off + 16:off + 16 + incl]
        off += 16 + incl
        out["frames"] += 1
        if len(frame) < 14 + 20 + 8:
            continue
        ihl = (frame[14] & 0x0F) * 4
        sport, dport = struct.unpack_from(">HH", frame, 14 + ihl)
        out["to_port"] += dport == port
        out["from_port"] += sport == port
    return out


def read_sim(run, r):
    run.simrc = r.returncode
    run.sim_err = r.stderr
    try:
        run.sim = json.loads(r.stdout)
    except ValueError:
        run.sim = {}


def kv_text(text):
    for line in text.splitlines():
        k, sep, v = line.partition("=")
        if sep:
            yield k, v


def num(v):
    """a key=value figure as a number (None when absent)"""
    try:
        return float(v) if "." in v or "e" in v else int(v)
    except (TypeError, ValueError):
        return None


@pytest.fixture
def srv(procs, bins, ports, tmp_path):
    return Srv(procs, bins, ports, tmp_path)
