#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Drive cell-cli's REPL through a pseudo-terminal: commands, help, TAB completion,
# history across runs (run by cell_cli.sh).
import os, pty, re, select, sys, termios, time

cli, port, home = sys.argv[1], sys.argv[2], sys.argv[3]
fails = []
PROMPT = re.compile(rb"\ncell [^\r\n>]*> ")

def check(what, ok, detail=""):
    print(("PASS" if ok else "FAIL") + f": {what} {detail}")
    if not ok:
        fails.append(what)

def session(keys):
    """Types keys into the REPL; waits for conditions, not for time: the prompt, with the
    terminal in raw mode, before typing and after each Enter, then the end of output after ^D
    (a 15 s bound only stops a broken run)."""
    pid, fd = pty.fork()
    if pid == 0:
        os.environ["HOME"] = home
        os.environ["TERM"] = "dumb"
        os.execv(cli, [cli, "-p", port])
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
    for k in keys:
        n = prompts()
        os.write(fd, k)
        if k.endswith(b"\r"):
            read_until(lambda: prompts() > n and reading())
    os.write(fd, b"\x04")  # EOF leaves the REPL
    read_until(lambda: False)
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
# TAB on an empty word offers the next word's choices (^U clears the line before EOF)
def listing(keys):
    out, _ = session(keys + [b"\x15"])
    return out.split("Type help.", 1)[-1]
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
print("pty checks:", "FAILED " + ", ".join(fails) if fails else "all passed")
sys.exit(1 if fails else 0)
