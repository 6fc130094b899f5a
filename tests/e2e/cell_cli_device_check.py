#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# cell-cli against a hostile or confused device (run by cell_hostile.sh): escape sequences
# in replies never reach the terminal raw, in any output format; unsolicited lines are not
# taken for replies; a reply must have the shape its request asks for. The device is a
# fake robot on 127.0.0.1:PORT (and a fake CANopen shell on PORT + 11). Loopback only.
# Usage: cell_cli_device_check.py CELL_CLI PORT
import os, re, select, socket, subprocess, sys, threading

cli, port = sys.argv[1], int(sys.argv[2])
fails = []
STA = b"OKF+010.000-002.000+005.999-01.2322T+00100+00000\r\n"
PLATFORM_STA = b"OKF+00.0000+00.0000F+00100+00000\r\n"


def check(what, ok, detail=""):
    print(("PASS" if ok else "FAIL") + f": {what} {detail}")
    if not ok:
        fails.append(what)


# what the device does: on_connect() -> bytes, on_line(request) -> bytes
behave = {"connect": lambda: b"", "line": lambda req: STA}


def serve(lsock):
    while True:
        try:
            c, _ = lsock.accept()
        except OSError:
            return
        threading.Thread(target=conn, args=(c,), daemon=True).start()


def conn(c):
    try:
        c.sendall(behave["connect"]())
        f = c.makefile("rb")
        for line in f:
            c.sendall(behave["line"](line))
    except OSError:
        pass
    finally:
        c.close()


for p in (port, port + 11):
    ls = socket.socket()
    ls.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    ls.bind(("127.0.0.1", p))
    ls.listen(8)
    threading.Thread(target=serve, args=(ls,), daemon=True).start()


def run(args, tty):
    """cell-cli with stdout and stderr on a pseudo-terminal (tty) or on pipes: its exit
    status and everything it wrote."""
    argv = [cli, "--robot", f"127.0.0.1:{port}", "-p", str(port), "-t", "2000"] + args
    if not tty:
        p = subprocess.run(argv, capture_output=True, timeout=30)
        return p.returncode, p.stdout, p.stderr
    master, slave = os.openpty()
    p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=slave, stderr=slave)
    os.close(slave)
    out = b""
    while True:
        r, _, _ = select.select([master], [], [], 30)
        if not r:
            break
        try:
            data = os.read(master, 4096)
        except OSError:
            break
        if not data:
            break
        out += data
    os.close(master)
    return p.wait(timeout=30), out, b""


# bytes a terminal acts on: ESC, BEL, 8-bit C1 controls (raw or as UTF-8), other C0 but
# CR LF TAB
DANGER = re.compile(rb"[\x00-\x08\x0b-\x0c\x0e-\x1f\x7f\x80-\x9f]|\xc2[\x80-\x9f]")
HOSTILE = {
    "OSC title": b"\x1b]0;pwned\x07",
    "screen clear and a fake 'robot: stopped'": b"\x1b[H\x1b[2Jrobot: stopped, servo off",
    "cursor position query": b"\x1b[6n",
    "OSC 52 clipboard write": b"\x1b]52;c;cm0gLXJmIH4K\x07",
    "8-bit CSI": b"\x9b2J\x9b6n",
}
for name, payload in HOSTILE.items():
    behave["connect"] = lambda: b""
    behave["line"] = lambda req, p=payload: b"OK" + p + b"\r\n"
    for fmt in ([], ["--raw"], ["--json"], ["--csv"]):
        rc, out, _ = run(fmt + ["robot", "sta"], tty=True)
        bad = DANGER.search(out)
        check(f"{name} {' '.join(fmt) or 'text'} on a terminal: escaped, exit 4",
              rc == 4 and bad is None and out.strip() != b"",
              f"(exit {rc}, {bad.group(0) if bad else ''!r}) {out[-160:]!r}")
    rc, out, err = run(["robot", "sta"], tty=False)
    check(f"{name} raw to a pipe: escaped, exit 4", rc == 4 and DANGER.search(out + err) is None,
          f"(exit {rc}) {out[-120:]!r}")
    # the same bytes as a line nobody asked for, before the reply
    behave["line"] = lambda req, p=payload: STA + b"OK" + p + b"\r\n"
    rc, out, _ = run(["-r", "2", "robot", "sta"], tty=True)
    check(f"{name} unsolicited: escaped on a terminal", DANGER.search(out) is None
          and b"unsolicited line dropped" in out, repr(out[-200:]))
    # the CANopen shell's reply
    behave["connect"] = lambda: b""
    behave["line"] = lambda req, p=payload: b"node 1: " + p + b"\n"
    rc, out, _ = run(["canopen", "CO_RNMT", "1"], tty=True)
    check(f"{name} from the CANopen shell: escaped", rc == 0 and DANGER.search(out) is None
          and b"node 1: " in out, f"(exit {rc}) {out[-160:]!r}")
    behave["line"] = lambda req, p=payload: b"ERR " + p + b"\n"
    rc, out, _ = run(["canopen", "CO_RNMT", "1"], tty=True)
    check(f"{name} in a CANopen shell error: escaped", rc == 1 and DANGER.search(out) is None,
          f"(exit {rc}) {out[-160:]!r}")
behave["connect"] = lambda: b""
behave["line"] = lambda req: b"OK\x1b]0;pwned\x07\r\n"
rc, out, _ = run(["--no-raw", "robot", "sta"], tty=True)
check("the escaped bytes are shown, not dropped", b"\\x1b]0;pwned\\x07" in out, repr(out))

# unsolicited lines after each reply: -r 3 must show three status replies, not ER and OK
behave["line"] = lambda req: STA + b"ER+00102\r\nOK\r\n"
rc, out, err = run(["-r", "3", "robot", "sta"], tty=False)
lines = out.splitlines()
check("-r 3 with two extra lines after each reply: three STA replies, exit 0",
      rc == 0 and len(lines) == 3 and all(l == STA.rstrip() for l in lines), f"(exit {rc}) {out!r}")
check("the extra lines are reported on stderr", err.count(b"unsolicited line dropped") == 4, repr(err))
# a line partly received before the request is not the reply either
behave["n"] = 0
def half(req):
    first = behave["n"] == 0
    behave["n"] += 1
    return (b"" if first else b"102\r\n") + STA + b"ER+00"
behave["line"] = half
rc, out, err = run(["-r", "2", "robot", "sta"], tty=False)
check("a line that began before the request is not its reply", rc == 0 and out.splitlines() == [STA.rstrip()] * 2,
      f"(exit {rc}) {out!r} {err!r}")
# reply shapes
behave["line"] = lambda req: b"OK\r\n"
rc, out, err = run(["robot", "sta"], tty=False)
check("a bare OK is no STA reply: exit 4", rc == 4, f"(exit {rc}) {out!r} {err!r}")
rc, out, err = run(["--no-raw", "wait", "robot", "stopped", "2"], tty=False)
check("wait: a bare OK is no STA reply: exit 4", rc == 4 and b"invalid reply" in out, f"(exit {rc}) {out!r}")
behave["line"] = lambda req: PLATFORM_STA
rc, out, err = run(["--no-raw", "robot", "sta"], tty=False)
check("a platform's status from the robot: exit 4", rc == 4 and b"2 axes" in out, f"(exit {rc}) {out!r}")
behave["line"] = lambda req: STA
rc, out, err = run(["--json", "robot", "srvon"], tty=False)
check("a status reply to SRVON: exit 4", rc == 4 and b'"reply":"invalid"' in out, f"(exit {rc}) {out!r}")
rc, out, err = run(["robot", "sta"], tty=False)
check("a good STA still passes", rc == 0 and out == STA.rstrip() + b"\n", f"(exit {rc}) {out!r}")
behave["line"] = lambda req: b"ER+00104\r\n" if req.startswith(b"STA") else b"OK\r\n"
rc, out, err = run(["-r", "2", "robot", "sta"], tty=False)
check("ER answers any request (exit 1)", rc == 1, f"(exit {rc}) {out!r}")
print("device checks:", "FAILED " + ", ".join(fails) if fails else "all passed")
sys.exit(1 if fails else 0)
