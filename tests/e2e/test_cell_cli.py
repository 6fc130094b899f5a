# SPDX-License-Identifier: MIT
"""cell-cli against a real cell-sim on 127.0.0.1: one-shot, --json, exit codes, scripts
(stdin and file, ER handling, wait), the spec's pick-and-place task end to end, config file,
timeouts, the REPL through a pty (completion, history, hints), ^C/^D and SIGINT."""
import fcntl
import os
import pty
import re
import select
import signal
import socket
import struct
import subprocess
import termios
import time

from e2e_extra import Checks, listening_tcp
from e2elib import wait_until


def pty_checks(ck, cli, port, home):
    """cell-cli's REPL through a pseudo-terminal: commands, help, TAB completion, history
    across runs, hints as you type (cell-sim's robot on port, HOME in home)."""
    check = ck.ok
    steps = []  # the output of the last session, one piece per key typed (from its write on)
    PROMPT = re.compile(rb"\ncell [^\r\n>]*> ")

    def session(keys, term="dumb", args=(), cols=0):
        """Types keys into the REPL; waits for conditions, not for time: the prompt, with the
        terminal in raw mode, before typing and after each Enter, then the end of output after ^D
        (a 15 s bound only stops a broken run). A key given as (bytes, pattern) waits, after it
        is typed, until the output since then matches the pattern."""
        pid, fd = pty.fork()
        if pid == 0:
            os.environ["HOME"] = home
            os.environ["TERM"] = term
            if cols:  # the terminal's width, set before the REPL asks for it
                fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", 24, cols, 0, 0))
            os.execv(cli, [cli, "-p", port, *args])
        out = b""
        closed = False
        def read_until(done, limit=15.0):
            nonlocal out, closed
            end = time.monotonic() + limit
            while not closed and not done() and time.monotonic() < end:
                r, _, _ = select.select([fd], [], [], 0.05)
                if r:
                    try:
                        data = os.read(fd, 4096)
                    except OSError:  # EIO: the REPL exited and closed the terminal
                        data = b""
                    if not data:
                        closed = True
                    out += data
        def reading():
            # libedit reads with the terminal in raw mode; bytes typed while it is cooked (a
            # command still running) go through the line discipline, which turns ^D into NUL
            try:
                return not termios.tcgetattr(fd)[3] & termios.ICANON
            except termios.error:
                return False
        # a fresh prompt starts a line ("cell not connected> ", "cell robot@HOST:PORT> "); a
        # redraw (TAB, history) starts with \r instead
        def prompts():
            return len(PROMPT.findall(out))
        read_until(lambda: prompts() > 0 and reading())
        marks = []
        for k in keys:
            want = None
            if isinstance(k, tuple):
                k, want = k
            n, start = prompts(), len(out)
            marks.append(start)
            os.write(fd, k)
            if want is not None:
                read_until(lambda: re.search(want, out[start:]) is not None)
            if k.endswith(b"\r"):
                read_until(lambda: prompts() > n and reading())
        marks.append(len(out))
        os.write(fd, b"\x04")  # EOF leaves the REPL
        read_until(lambda: False)
        steps[:] = [out[a:b] for a, b in zip(marks, marks[1:])]
        _, status = os.waitpid(pid, 0)
        os.close(fd)
        return out.decode(errors="replace"), os.waitstatus_to_exitcode(status)

    out, rc = session([b"robot sta\r", b"help ovr\r", b"platform servo on\r", b"bogus\r"])
    check("REPL banner", "Type help." in out)
    check("REPL STA table", "x [mm]" in out and "c [rad]" in out)
    check("REPL per-command help", "set the override 0..100 %" in out)
    check("REPL command OK", "platform: OK" in out)
    check("REPL error message, carries on", "unknown device or command 'bogus'" in out)
    check("REPL exit status 0 on EOF", rc == 0, f"(rc {rc})")
    # TAB completion: "rob<TAB> st<TAB><TAB>" -> "robot sta" (st: sta or stp -> list); use unique prefixes
    out, rc = session([b"rob\t", b"ov\t", b"70\r", b"rob\t", b"sta\r"])
    check("TAB completes the device and the command", "robot: OK" in out and "override 70 %" in out,
          "")
    # history across runs: the file was written, and Up-arrow recalls the last command
    hist = os.path.join(home, ".cell_cli_history")
    check("history file written", os.path.exists(hist) and "robot" in open(hist).read() and "ovr" in open(hist).read())
    out, rc = session([b"\x1b[A\r"])
    check("history recalled in a new run (Up arrow)", "override 70 %" in out)
    # TAB on an empty word offers the next word's choices (^U clears the line before EOF)
    def listing(keys):
        out, _ = session(keys + [b"\x15"])
        return out.split("Type help.", 1)[-1]
    out = listing([(b"\t", rb"\x07")])
    check("one TAB on an empty line only beeps", "conditioning" not in out and "\x07" in out, repr(out[-300:]))
    out = listing([b"\t\t"])
    check("two TABs on an empty line list the first words",
          all(re.search(r"\b%s\b" % w, out) for w in ("clear", "conditioning", "connect", "help", "platform", "quit",
                                                        "raw", "robot", "sleep", "wait"))
          and re.search(r"clear\s+connect\s+platform", out) is not None, repr(out[-300:]))
    out = listing([b"robot \t\t"])
    check("robot <TAB><TAB> lists robot commands", "srvon" in out and "pnp" in out and "sleep" not in out
          and "conditioning" not in out, repr(out[-300:]))
    out = listing([b"platform mov \t\t"])
    check("platform mov <TAB><TAB> lists abs rel", re.search(r"abs\s+rel", out) is not None and "srvon" not in out,
          repr(out[-300:]))
    out = listing([b"robot mov abs \t\t"])
    check("robot mov abs <TAB><TAB> lists the axis keys", re.search(r"c=\s+x=\s+y=\s+z=", out) is not None
          and "rel" not in out, repr(out[-300:]))
    out = listing([b"conditioning hnd 1 \t\t"])
    check("conditioning hnd 1 <TAB><TAB> lists open close", re.search(r"close\s+open", out) is not None,
          repr(out[-300:]))
    out = listing([b"robot ovr \t"])
    check("TAB where nothing completes shows the argument hint", "DEV ovr PERCENT" in out, repr(out[-300:]))
    out = listing([b"ROBOT SR\t\t"])
    check("upper-case words complete too", "srvof" in out and "srvon" in out, repr(out[-300:]))
    # the prompt: "not connected" before any command, then the device and its address; upper
    # case; clear
    out, rc = session([b"ROBOT STA\r", b"clear\r"])
    check("prompt says not connected at first", "\ncell not connected> " in out, repr(out[:300]))
    check("prompt names the device and address", f"\ncell robot@127.0.0.1:{port}> " in out,
          repr(out[-400:]))
    check("ROBOT STA works in the REPL", "x [mm]" in out)
    check("clear clears the screen", "\x1b[H\x1b[2J" in out)
    # hints as you type (a terminal that takes colours): in grey after the cursor, the
    # arguments still to come, updated as words are typed, erased before the next key acts
    GREY = b"\x1b[90m"
    def hint(text):
        return re.escape(GREY + text + b"\x1b[0m")
    out, rc = session([(b"robot", hint(b" sta|srvon|srvof|ovr|mov|stp|rst|clo|itr|pnp")),
                       (b" mov ", hint(b"abs|rel x=MM y=MM z=MM c=RAD")),
                       (b"abs", hint(b" x=MM y=MM z=MM c=RAD")),
                       (b" x=1 ", hint(b"y=MM z=MM c=RAD")),
                       (b"y=2 z=3 c=0.5", rb"c=0\.5"), b"\r"], term="xterm")
    check("hint after a device word lists its commands",
          re.search(hint(b" sta|srvon|srvof|ovr|mov|stp|rst|clo|itr|pnp"), steps[0]) is not None,
          repr(steps[0]))
    check("hint after 'robot mov ' (typed at once: one hint, at the end)",
          steps[1].count(GREY) == 1 and re.search(hint(b"abs|rel x=MM y=MM z=MM c=RAD") + rb"\x1b\[\d+D$", steps[1])
          is not None, repr(steps[1]))
    check("hint after 'abs' drops the mode", re.search(hint(b" x=MM y=MM z=MM c=RAD"), steps[2]) is not None,
          repr(steps[2]))
    check("hint drops the axis typed, erased before the next key",
          steps[3].startswith(b"\x1b[K") and re.search(hint(b"y=MM z=MM c=RAD"), steps[3]) is not None
          and b"x=MM" not in steps[3], repr(steps[3]))
    check("no hint once every axis is given", GREY not in steps[4] + steps[5], repr(steps[4] + steps[5]))
    check("the line typed with hints runs as typed", re.search(r"robot: (OK|ER)", out) is not None
          and "error:" not in out, repr(out[-300:]))
    out, rc = session([(b"robot ovr", hint(b" PERCENT")), (b" 5", rb"5"), (b"\x7f", hint(b"PERCENT")),
                       b"\x15"], term="xterm")
    check("no hint once the argument is typed", GREY not in steps[1], repr(steps[1]))
    check("backspace brings the hint back", steps[2].count(GREY) == 1, repr(steps[2]))
    out, rc = session([(b"bogus ", rb"bogus "), (b"robot fly ", rb"fly "), b"\x15"], term="xterm")
    check("no hint for an unknown word", GREY.decode() not in out, repr(out[-200:]))
    out, rc = session([(b"robot mov ", rb"mov "), b"\x15"], term="xterm", args=("--no-hints",))
    check("--no-hints shows none", GREY.decode() not in out and "robot mov" in out, repr(out[-200:]))
    ini = os.path.join(home, "nohints.ini")
    with open(ini, "w") as f:
        f.write("[cli]\nhints = no\n")
    out, rc = session([(b"robot mov ", rb"mov "), b"\x15"], term="xterm", args=("-c", ini))
    check("[cli] hints = no shows none", GREY.decode() not in out and "robot mov" in out, repr(out[-200:]))
    out, rc = session([(b"robot mov ", rb"mov "), b"\x15"])
    check("TERM=dumb shows no hints", GREY.decode() not in out and "robot mov" in out, repr(out[-200:]))
    out, rc = session([(b"robot mov ", hint(b"abs|rel x") + rb"\x1b\[9D"), (b"abs x=1 y=2", rb"y="),
                       (b" z=3", rb"z=3"), b"\x15"], term="xterm", cols=40)
    check("a hint is cut at the right margin (40 columns)",
          re.search(hint(b"abs|rel x") + rb"\x1b\[9D$", steps[0]) is not None, repr(steps[0]))
    check("no hint where the line reaches the margin", GREY not in steps[1] + steps[2],
          repr(steps[1] + steps[2]))
    out = session([b"robot \t\t", b"\x15"], term="xterm")[0].split("Type help.", 1)[-1]
    check("TAB lists the choices with hints on", "srvon" in out and "pnp" in out, repr(out[-300:]))


def intr_checks(ck, cli, port, home):
    """^C and ^D in cell-cli's REPL through a pseudo-terminal against a real cell-sim: ^C during
    a wait stops the robot the REPL moved (STP, its reply shown) and returns to the prompt;
    ^C at a prompt clears the line as a shell does; ^D exits with status 0."""
    check = ck.ok
    PROMPT = re.compile(rb"\ncell [^\r\n>]*> ")

    pid, fd = pty.fork()
    if pid == 0:
        os.environ["HOME"] = home
        os.environ["TERM"] = "dumb"
        os.execv(cli, [cli, "-p", port, "--no-history"])
    out = b""
    closed = False

    def read_until(done, limit=15.0):
        """Reads the terminal until done() or the bound (which only stops a broken run)."""
        nonlocal out, closed
        end = time.monotonic() + limit
        while not closed and not done() and time.monotonic() < end:
            r, _, _ = select.select([fd], [], [], 0.05)
            if r:
                try:
                    data = os.read(fd, 4096)
                except OSError:  # EIO: the REPL exited
                    data = b""
                if not data:
                    closed = True
                out += data
        return done()

    def editing():
        # libedit reads keys with the terminal in raw mode (no ICANON)
        try:
            return not termios.tcgetattr(fd)[3] & termios.ICANON
        except termios.error:
            return False

    def prompts():
        return len(PROMPT.findall(out))

    def command(text):
        """Types a command and Enter; waits for the next prompt. Returns its output."""
        n, start = prompts(), len(out)
        os.write(fd, text + b"\r")
        read_until(lambda: prompts() > n and editing())
        return out[start:].decode(errors="replace")

    read_until(lambda: prompts() > 0 and editing())
    check("REPL started", prompts() == 1, repr(out[-200:]))
    command(b"robot rst")
    check("servo on", "robot: OK" in command(b"robot srvon"))
    check("override 1 %", "robot: OK" in command(b"robot ovr 1"))
    check("motion started", "robot: OK" in command(b"robot mov abs x=100 y=100 z=100 c=0"))
    # the wait polls STA with the terminal cooked: ^C is SIGINT for the REPL
    n, start = prompts(), len(out)
    os.write(fd, b"wait robot stopped 60\r")
    read_until(lambda: not editing(), 5)
    time.sleep(0.4)
    t0 = time.monotonic()
    os.write(fd, b"\x03")
    back = read_until(lambda: prompts() > n and editing(), 10)
    took = time.monotonic() - t0
    text = out[start:].decode(errors="replace")
    check("^C during a wait returns to the prompt", back and not closed, f"({took:.2f} s) {text[-300:]!r}")
    check("^C during a wait says so and shows the STP reply",
          re.search(r"interrupted.*\n.*robot: OK", text) is not None and "STP" in text, repr(text[-300:]))
    # the device itself, on a connection of its own: no motion left behind
    with socket.create_connection(("127.0.0.1", int(port)), 5) as c:
        c.sendall(b"STA\r\n")
        raw = c.makefile("rb").readline()
    check("after ^C the device reports stopped (STA moving flag F)", raw[2:3] == b"F", repr(raw))
    sta = command(b"robot sta")
    check("after ^C the robot is stopped", "robot: stopped" in sta, repr(sta[-300:]))
    # ^C while a line is being typed: the line is dropped, nothing runs, the REPL stays
    n, start = prompts(), len(out)
    os.write(fd, b"robot srvof")
    read_until(lambda: b"srvof" in out[start:], 5)
    os.write(fd, b"\x03")
    read_until(lambda: prompts() > n and editing(), 5)
    check("^C at a partial line shows ^C and a fresh prompt", prompts() == n + 1 and b"^C" in out[start:],
          repr(out[start:]))
    command(b"")
    sta = command(b"robot sta")
    check("the cleared line did not run (servo still on)", "servo ON" in sta, repr(sta[-300:]))
    n, start = prompts(), len(out)
    os.write(fd, b"\x03")
    read_until(lambda: prompts() > n and editing(), 5)
    check("^C at an empty prompt: a fresh prompt, no exit", prompts() == n + 1 and not closed,
          repr(out[start:]))
    check("the REPL still answers", "robot: stopped" in command(b"robot sta"))
    os.write(fd, b"\x04")  # ^D leaves the REPL
    read_until(lambda: False, 5)
    _, status = os.waitpid(pid, 0)
    check("^D exits with status 0", os.waitstatus_to_exitcode(status) == 0,
          f"(status {os.waitstatus_to_exitcode(status)})")
    os.close(fd)


def start_sim(procs, bins, base, args=(), name="sim"):
    h = procs.start([bins.cell_sim, "-p", base, *args], name=name)
    wait_until(lambda: listening_tcp(base + 2) or not h.running(), 30, "cell-sim listening on %d" % (base + 2))
    assert h.running(), "cell-sim did not start: " + h.out()
    return h


def test_cli(procs, bins, ports, tmp_path):
    """cell-cli against a real cell-sim: one-shot, --json, exit codes, scripts (stdin and file,
    ER handling, wait), the spec's pick-and-place task end to end, config file, timeouts."""
    ck = Checks()
    base = ports.block(3, proto="tcp")
    sim = start_sim(procs, bins, base, ["-s", "20"])
    cli = str(bins.cell_cli)

    def run(*args, input=None):
        r = procs.run([cli, "-p", base] + [str(a) for a in args], input=input)
        return r.returncode, r.stdout, r.stderr

    def c(*args, input=None):  # the human format: stdout is a pipe here, where replies are raw by default
        return run("--no-raw", *args, input=input)

    def rc_is(want, got, what):
        ck.eq(what + " (exit)", got, want)

    rc, out, _ = c("robot", "sta")
    rc_is(0, rc, "one-shot robot sta")
    ck.ok("STA shown readable", "robot: stopped, servo off, override 100 %, error +00000 (no error)" in out, out)
    ck.ok("STA table has z=50.000", "50.000" in out, out)
    rc, out, _ = run("--json", "platform", "sta")
    rc_is(0, rc, "--json platform sta")
    ck.eq("--json STA object", out.strip(), '{"device":"platform","request":"STA","raw":"OKF+00.0000+00.0000F+00100+00000",'
          '"reply":"OK","moving":false,"servo":false,"override":100,"error":0,"error_text":"no error",'
          '"position":{"a":0.0,"b":0.0}}')
    rc, out, _ = c("robot", "mov", "abs", "x=10", "y=-2", "z=5.999", "c=-1.2322")
    rc_is(1, rc, "MOV with servo off -> ER")
    ck.ok("ER explained", "ER +00104  servo is off (project code)" in out, out)
    rc_is(0, c("--json", "raw", "robot", "SRVON")[0], "raw SRVON")
    rc_is(0, c("robot", "mov", "abs", "x=10", "y=-2", "z=5.999", "c=-1.2322")[0], "spec MOV example")
    rc, out, _ = c("raw", "robot", "MOVA+010.000-002.000+005.999-01.2322")
    rc_is(1, rc, "raw MOV while moving -> ER")
    ck.ok("busy explained", "+00107" in out, out)
    rc, out, err = c(input="wait robot stopped 10\nrobot sta\n")
    rc_is(0, rc, "script from stdin with wait")
    ck.ok("arrived at the spec's pose", "10.000      -2.000       5.999     -1.2322" in out + err, out + err)
    rc, out, _ = c("--json", "raw", "robot", "STA")
    ck.eq("raw STA = spec example reply (override 100, servo-off error latched)",
          re.sub(r'.*"raw":"([^"]*)".*', r"\1", out.strip()), "OKF+010.000-002.000+005.999-01.2322T+00100+00104")
    # output for pipes: raw replies unless --no-raw; --csv with a header; -r/-i lines stamped
    ck.eq("raw reply when stdout is a pipe", run("platform", "sta")[1].strip(), "OKF+00.0000+00.0000F+00100+00000")
    out = run("--csv", "-r", "2", "platform", "sta")[1]
    lines = out.splitlines()
    ck.eq("--csv header (time first with -r)", lines[0] if lines else "",
          "time,device,request,reply,raw,moving,servo,override,error,p1,p2,p3,p4")
    ck.ok("--csv rows", len(lines) == 3 and re.match(r"^20[0-9-]+T[0-9:.]+Z,platform,STA,OK,OKF\+00.0000\+00.0000F"
                                                     r"\+00100\+00000,0,0,100,0,0.0000,0.0000,,$", lines[1]), out)
    out = run("--json", "-r", "2", "-i", "0.05", "platform", "sta")[1]
    ck.eq("-r/-i JSON lines carry the time",
          len(re.findall(r'^\{"time":"20[0-9-]*T[0-9:.]*Z","device":"platform"', out, re.M)), 2)
    out = run("--json", "platform", "sta")[1]
    ck.ok("one-shot JSON without time", '"time"' not in out, out)
    rc_is(2, run("--json", "--csv", "robot", "sta")[0], "--json with --csv refused")
    rc, out, _ = c("ROBOT", "STA")
    rc_is(0, rc, "upper-case device and command")
    ck.ok("ROBOT STA shown", "robot: stopped" in out, out)
    rc, out, _ = c(input="clear\nrobot sta\n")
    rc_is(0, rc, "clear in a script")
    ck.ok("clear prints nothing off a terminal", out.startswith("robot: "), out)
    out = c("help")[1]
    ck.has("help: platform mov indented like the rest", out, r"^  platform mov abs\|rel a=RAD b=RAD")
    # usage errors: exit 2, message names the problem
    rc, _, err = c("robot", "mov", "abs", "x=1", "y=2")
    rc_is(2, rc, "missing axis")
    ck.ok("missing axis named", "missing z=" in err, err)
    rc_is(2, c("robot", "ovr", "101")[0], "override 101")
    rc, _, err = c("robot", "mov", "abs", "x=1000", "y=0", "z=0", "c=0")
    rc_is(2, rc, "x=1000 out of range")
    ck.ok("range error named", "out of range" in err, err)
    rc_is(2, c("frobnicate")[0], "unknown command")
    rc_is(2, procs.run([cli, "--bogus"]).returncode, "unknown option")
    # workspace error from the device
    rc, out, _ = c("robot", "mov", "abs", "x=300", "y=0", "z=0", "c=0")
    rc_is(1, rc, "workspace limit")
    ck.ok("workspace ER shown", "+00105" in out, out)
    # connection refused / reply timeout: exit 3
    r = procs.run([cli, "-p", ports.tcp(), "robot", "sta"])
    rc_is(3, r.returncode, "connection refused")
    ck.ok("refusal named", "connection refused" in r.stderr, r.stderr)
    # a silent device: accepts and never answers, until the test ends it (a fixed hold time
    # could run out before a slow client gave up)
    silent = socket.socket()
    silent.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    silent.bind(("127.0.0.1", 0))
    silent.listen(1)
    r = procs.run([cli, "--robot", "127.0.0.1:%d" % silent.getsockname()[1], "-t", "300", "robot", "sta"])
    silent.close()
    rc_is(3, r.returncode, "reply timeout")
    ck.ok("timeout named", "no reply within 300 ms" in r.stderr, r.stderr)
    # repeat / interval
    ck.eq("-r 5 gives 5 replies", c("--json", "-r", "5", "-i", "0.05", "robot", "sta")[1].count('"reply":"OK"'), 5)
    # scripts: first ER stops (exit 1) unless --keep-going
    s1 = tmp_path / "s1"
    s1.write_text("robot sta\nraw robot XYZ\nrobot sta\n")
    rc, out, _ = c("-f", s1)
    rc_is(1, rc, "script stops at the first ER")
    ck.eq("script stopped after the ER line", len(re.findall("^robot: ", out, re.M)), 2)
    rc, out, _ = c("-k", "-f", s1)
    ck.eq("--keep-going runs on", len(re.findall("^robot: ", out, re.M)), 3)
    rc_is(1, rc, "--keep-going still reports the ER")
    s2 = tmp_path / "s2"
    s2.write_text("robot sta\nrobot flyaway\n")
    rc, _, err = c("-f", s2)
    rc_is(2, rc, "script syntax error")
    ck.ok("syntax error with file:line", "s2:2: unknown command 'flyaway'" in err, err)
    # config file: ports from the file, options override it
    cfg = tmp_path / "cfg.ini"
    cfg.write_text("[robot]\nhost = 127.0.0.1\nport = %d\n[platform]\nport = %d\n[cli]\nreply_timeout_ms = 1500\n"
                   % (base, base + 1))
    rc_is(0, procs.run([cli, "-c", cfg, "robot", "sta"]).returncode, "config file")
    bad = tmp_path / "bad.ini"
    bad.write_text("[robot]\nprot = 1\n")
    r = procs.run([cli, "-c", bad, "robot", "sta"])
    rc_is(2, r.returncode, "config typo rejected")
    ck.ok("config typo: line, column and key named", "bad.ini:2:1: [robot]: unknown key 'prot'" in r.stderr, r.stderr)
    bad2 = tmp_path / "bad2.ini"
    bad2.write_text("[robot]\nport = 1e39\n")
    r = procs.run([cli, "-c", bad2, "robot", "sta"])
    rc_is(2, r.returncode, "config port 1e39 rejected")
    ck.ok("config 1e39: line, column, key, value named", "bad2.ini:2:8: [robot] port: '1e39' is not an integer"
          in r.stderr, r.stderr)
    rc_is(2, procs.run([cli, "-c", "/dev/zero", "robot", "sta"], timeout=20).returncode,
          "config /dev/zero refused, not hung")
    r = procs.run([cli, "-f", "/dev/zero"], timeout=20)
    rc_is(2, r.returncode, "script /dev/zero refused, not hung")
    ck.has("script NUL byte named", r.stderr, r"/dev/zero:1: column 1: control byte .x00")
    # the spec's section 6 pick-and-place task, end to end
    rc, out, err = c("-f", "fixtures/cell/pick_and_place.cell")
    pp = out + err
    rc_is(0, rc, "pick_and_place.cell")
    ck.eq("pick-and-place: every instruction OK", len(re.findall(": OK$", pp, re.M)), 18)
    ck.ok("robot ends at the place pose", "40.000      25.000       8.000     -0.5000" in pp, pp)
    ck.ok("platform ends at the pick orientation", "0.7854     -0.2618" in pp, pp)
    ck.has("blow pulse reached the conditioning controller", sim.out(),
           r"conditioning 127\.0\.0\.1:[0-9]* command: HND\+00001CLOSE: blow off")
    # CLO closes; the next command reconnects
    rc_is(0, c(input="robot clo\nrobot sta\n")[0], "CLO then reconnect")
    # help, version
    ck.ok("--help has examples", "Examples:" in procs.run([cli, "--help"]).stdout)
    ck.has("--version", procs.run([cli, "--version"]).stdout, "^cell-cli [0-9]")
    ck.ok("help mov", "absolute needs every axis" in c("help", "mov")[1])
    ck.done()


def test_repl_pty(procs, bins, ports, tmp_path):
    ck = Checks()
    base = ports.block(3, proto="tcp")
    start_sim(procs, bins, base, ["-s", "20"])
    home = tmp_path / "home"
    home.mkdir()
    pty_checks(ck, str(bins.cell_cli), str(base), str(home))
    ck.done()


def test_interrupts(procs, bins, ports, tmp_path):
    """^C and ^D in the REPL, SIGINT in a script and in a monitor, against a cell-sim at real
    speed (a motion long enough to cut)."""
    ck = Checks()
    base = ports.block(3, proto="tcp")
    start_sim(procs, bins, base)
    home = tmp_path / "home"
    home.mkdir()
    cli = str(bins.cell_cli)
    intr_checks(ck, cli, str(base), str(home))
    # SIGINT in a script: STP to the motion the script started, exit 130
    s3 = tmp_path / "s3"
    s3.write_text("robot srvof\nrobot rst\nrobot srvon\nrobot ovr 1\nrobot mov abs x=-100 y=-100 z=100 c=0\n"
                  "wait robot stopped 60\n")
    out3, err3 = tmp_path / "o3", tmp_path / "e3"
    with open(out3, "w") as o, open(err3, "w") as e:
        p = subprocess.Popen([cli, "-p", str(base), "-f", str(s3)], stdout=o, stderr=e)
        wait_until(lambda: len(re.findall("^OK$", out3.read_text(), re.M)) >= 5 or p.poll() is not None, 10,
                   "the script's five OK replies")
        time.sleep(0.3)
        p.send_signal(signal.SIGINT)
        ck.eq("SIGINT during a script's wait (exit)", p.wait(30), 130)
    ck.ok("SIGINT: STP sent to the robot the script moved", "robot: interrupted: sending STP" in err3.read_text(),
          err3.read_text())
    r = procs.run([cli, "-p", base, "--no-raw", "robot", "sta"])
    ck.ok("SIGINT: the robot is stopped afterwards", "robot: stopped" in r.stdout + r.stderr, r.stdout + r.stderr)
    # a monitor does not stop a robot it did not move
    procs.run([cli, "-p", base, "robot", "mov", "rel", "x=5"])
    out4, err4 = tmp_path / "o4", tmp_path / "e4"
    with open(out4, "w") as o, open(err4, "w") as e:
        mon = subprocess.Popen([cli, "-p", str(base), "-r", "-1", "-i", "0.05", "robot", "sta"], stdout=o, stderr=e)
        time.sleep(0.5)
        mon.send_signal(signal.SIGINT)
        ck.eq("SIGINT ends -r -1 (exit)", mon.wait(30), 130)
    lines = out4.read_text().splitlines()
    ck.ok("SIGINT: a monitor sends no STP", "STP" not in err4.read_text(), err4.read_text())
    ck.ok("SIGINT: the motion the monitor watched goes on", bool(lines) and lines[-1].startswith("OKT"), lines[-2:])
    ck.done()
