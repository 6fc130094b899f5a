# SPDX-License-Identifier: MIT
"""cell-cli as a redis-cli user drives it, in a real terminal (tmux) against cell-sim on
127.0.0.1: "N CMD" repeats, connect HOST PORT, help naming the addresses in use, help of a
word (servo) and of a device, STA after a fixed error saying the error is latched, and
--latency's readout ended by ^C."""
import os
import re
import signal
import subprocess
import time

from e2e_extra import listening_tcp
from e2elib import wait_until


def start_sim(procs, bins, base):
    h = procs.start([bins.cell_sim, "-p", base], name="sim%d" % base)
    wait_until(lambda: listening_tcp(base + 2) or not h.running(), 30, "cell-sim listening on %d" % (base + 2))
    assert h.running(), "cell-sim did not start: " + h.out()
    return h


class Term:
    """cell-cli's REPL in a tmux pane; type() waits for the prompt count to grow"""

    def __init__(self, tmp_path, argv):
        self.sock = str(tmp_path / "tmux.sock")
        home = tmp_path / "home"
        home.mkdir(exist_ok=True)
        self.env = dict(os.environ, HOME=str(home), TERM="xterm", LC_ALL="C")
        cmd = " ".join(argv) + " --no-history --no-hints"
        assert self.tmux("new-session", "-d", "-x", "160", "-y", "200", cmd).returncode == 0
        self.wait(lambda s: s.count("> ") >= 1, "the first prompt")

    def tmux(self, *args):
        return subprocess.run(["tmux", "-S", self.sock] + list(args), capture_output=True, text=True,
                              env=self.env, timeout=30)

    def screen(self):
        return self.tmux("capture-pane", "-p", "-S", "-", "-J").stdout

    def wait(self, cond, what, limit=15.0):
        end = time.monotonic() + limit
        while time.monotonic() < end:
            s = self.screen()
            if cond(s):
                return s
            time.sleep(0.05)
        raise AssertionError("%s: not seen in\n%s" % (what, self.screen()))

    def type(self, line):
        """the output of one command line (what follows its prompt up to the next one)"""
        before = self.screen()
        n = len(re.findall(r"(?m)^cell [^\n>]*> ", before))
        self.tmux("send-keys", "-l", line)
        self.tmux("send-keys", "Enter")
        s = self.wait(lambda s: len(re.findall(r"(?m)^cell [^\n>]*> ", s)) > n, "the prompt after " + line)
        rows = s.splitlines()
        at = max(i for i, r in enumerate(rows) if re.fullmatch(r"cell [^>]*> " + re.escape(line) + r"\s*", r))
        end = next(i for i in range(at + 1, len(rows)) if re.match(r"cell [^>]*> ", rows[i]))
        return "\n".join(r.rstrip() for r in rows[at + 1:end]).strip("\n")

    def close(self):
        self.tmux("kill-server")


def test_repl_habits(procs, bins, ports, tmp_path):
    a = ports.block(3, proto="tcp")
    b = ports.block(3, proto="tcp")
    start_sim(procs, bins, a)
    start_sim(procs, bins, b)
    t = Term(tmp_path, [str(bins.cell_cli), "-p", str(a)])
    try:
        # help: the addresses in use, not the default ports
        out = t.type("help")
        assert out.startswith("Devices: robot (127.0.0.1:%d), platform (127.0.0.1:%d), conditioning "
                              "(127.0.0.1:%d);" % (a, a + 1, a + 2)), out
        assert "2001" not in out
        # help servo: both commands the word starts
        out = t.type("help servo")
        assert "(SRVON)" in out and "(SRVOF)" in out, out
        out = t.type("help conditioning")
        assert "conditioning acq CAMERA" in out and " sta " not in out, out
        # N CMD: three STA replies
        out = t.type("3 robot sta")
        assert len(re.findall(r"(?m)^robot: stopped, servo off", out)) == 3, out
        out = t.type("2 robot nope")
        assert out == "error: unknown command 'nope' for the robot (try: help)", out
        # an error, then the command that fixes it: STA calls the error latched, not current
        assert t.type("robot mov abs x=1 y=1 z=1 c=0").startswith("robot: ER +00104  servo is off")
        assert t.type("robot srvon") == "robot: OK"
        out = t.type("robot sta")
        assert out.startswith("robot: stopped, servo ON, override 100 %, last error +00104 (servo is off), "
                              "latched until rst"), out
        assert t.type("robot rst") == "robot: OK"
        out = t.type("robot sta")
        assert out.startswith("robot: stopped, servo ON, override 100 %, error +00000 (no error)"), out
        # a motion started here and not seen finished keeps its connection (^C's STP needs it)
        assert t.type("robot ovr 1") == "robot: OK"
        assert t.type("robot mov abs x=100 y=100 z=100 c=0") == "robot: OK"
        out = t.type("connect 127.0.0.1 %d" % b)
        assert out == ("cell-cli: robot: a motion started here is not seen finished: 'robot stp' or 'wait robot "
                       "stopped' before connect"), out
        assert t.type("robot stp") == "robot: OK"
        # connect HOST PORT: the second cell, whose robot is still off; the prompt follows
        out = t.type("connect 127.0.0.1 %d" % b)
        assert out.splitlines() == ["robot: connected to 127.0.0.1:%d" % b, "platform: connected to 127.0.0.1:%d" % (b + 1),
                                    "conditioning: connected to 127.0.0.1:%d" % (b + 2)], out
        out = t.type("robot sta")
        assert out.startswith("robot: stopped, servo off"), out
        assert ("cell robot@127.0.0.1:%d> " % b) in t.screen()
        assert ("(127.0.0.1:%d)" % b) in t.type("help")
        # one device elsewhere: back to the first cell's robot, servo on there
        out = t.type("connect robot 127.0.0.1:%d" % a)
        assert out == "robot: connected to 127.0.0.1:%d" % a, out
        assert t.type("robot sta").startswith("robot: stopped, servo ON")
        # a port where nothing listens: said, and the REPL goes on
        dead = ports.block(3, proto="tcp")
        out = t.type("connect 127.0.0.1 %d" % dead)
        assert "robot at 127.0.0.1:%d: " % dead in out, out
        assert t.type("help servo").count("(SRV") == 2
        # TAB after a count completes the command's words
        t.tmux("send-keys", "-l", "3 rob")
        t.tmux("send-keys", "Tab")
        t.wait(lambda s: s.rstrip().endswith("> 3 robot"), "3 rob<TAB> -> 3 robot")
        t.tmux("send-keys", "-l", "co")
        t.tmux("send-keys", "Tab")
        t.wait(lambda s: s.rstrip().endswith("> 3 robot co"), "no conditioning command after robot")
        t.tmux("send-keys", "C-u")
    finally:
        t.close()


def test_latency(procs, bins, ports, tmp_path):
    base = ports.block(3, proto="tcp")
    start_sim(procs, bins, base)
    cli = str(bins.cell_cli)
    # -r N: N samples, one final line
    r = subprocess.run([cli, "-p", str(base), "--latency", "-r", "20"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, r.stderr
    m = re.fullmatch(r"robot 127\.0\.0\.1:%d: min (\S+), max (\S+), avg (\S+) ms \(20 samples\)\n" % base, r.stdout)
    assert m, r.stdout
    lo, hi, avg = (float(x) for x in m.groups())
    assert 0 < lo <= avg <= hi < 1000, (lo, avg, hi)
    # until ^C: a line a second (stdout is a file), then the final one; exit 0
    p = subprocess.Popen([cli, "-p", str(base), "--latency", "platform"], stdout=subprocess.PIPE, text=True)
    time.sleep(2.3)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=10)
    assert p.returncode == 0, p.returncode
    lines = out.splitlines()
    assert len(lines) >= 3 and all(re.fullmatch(r"platform 127\.0\.0\.1:%d: min \S+, max \S+, avg \S+ ms \(\d+ samples\)"
                                                % (base + 1), ln) for ln in lines), out
    assert int(re.search(r"\((\d+) samples", lines[-1]).group(1)) >= 50, out  # one every 10 ms (+ reply time)
    r = subprocess.run([cli, "-p", str(base), "--latency", "conditioning"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 2 and "STA needs a device with axes" in r.stderr, (r.returncode, r.stderr)
