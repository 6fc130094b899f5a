#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Ctrl-C and Ctrl-D in cell-cli's REPL through a pseudo-terminal against a real cell-sim
# (run by cell_cli.sh): ^C during a wait stops the robot the REPL moved (STP, its reply
# shown) and returns to the prompt; ^C at a prompt clears the line as a shell does; ^D
# exits with status 0. Usage: cell_cli_intr.py CELL_CLI PORT_BASE HOME
import os, pty, re, select, sys, termios, time

cli, port, home = sys.argv[1], sys.argv[2], sys.argv[3]
fails = []
PROMPT = re.compile(rb"\ncell [^\r\n>]*> ")


def check(what, ok, detail=""):
    print(("PASS" if ok else "FAIL") + f": {what} {detail}")
    if not ok:
        fails.append(what)


pid, fd = pty.fork()
if pid == 0:
    os.environ["HOME"] = home
    os.environ["TERM"] = "dumb"
    os.execv(cli, [cli, "-p", port, "--no-history"])
out = b""
closed = False


def read_until(done, limit=15.0):
    """Reads the terminal until done() or the bound (which only stops a broken run)."""
    global out, closed
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
import socket
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
print("interrupt checks:", "FAILED " + ", ".join(fails) if fails else "all passed")
sys.exit(1 if fails else 0)
