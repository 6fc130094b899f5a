#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Drive cell-cli's REPL through a pseudo-terminal: commands, help, TAB completion,
# history across runs, hints as you type (run by cell_cli.sh).
import fcntl, os, pty, re, select, struct, sys, termios, time

cli, port, home = sys.argv[1], sys.argv[2], sys.argv[3]
fails = []
steps = []  # the output of the last session, one piece per key typed (from its write on)
PROMPT = re.compile(rb"\ncell [^\r\n>]*> ")

def check(what, ok, detail=""):
    print(("PASS" if ok else "FAIL") + f": {what} {detail}")
    if not ok:
        fails.append(what)

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
check("two TABs on an empty line list the first words", all(w in out for w in ("conditioning", "platform", "quit"))
      and re.search(r"clear\s+help\s+quit", out) is not None, repr(out[-300:]))
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
print("pty checks:", "FAILED " + ", ".join(fails) if fails else "all passed")
sys.exit(1 if fails else 0)
