# SPDX-License-Identifier: MIT
"""Hostile clients against cell-sim (64 KiB line, 1000 connections dropped, garbage, 1 byte/s
sender, non-reading and silent clients, 200 kB of newlines) while a well-behaved client keeps
getting correct replies, and the log stays small (also with -q); then cell-cli against a
hostile device (escape sequences, unsolicited lines, replies of the wrong shape).
Loopback only."""
import os
import random
import re
import resource
import select
import socket
import struct
import subprocess
import threading
import time

from e2e_extra import Checks, listening_tcp
from e2elib import wait_until


def hostile_checks(ck, base, logpath, flood_only):
    """Hostile clients against the cell-sim on ports base..base+2 (its log in logpath) while a
    well-behaved client keeps getting correct replies; flood_only: the newline flood alone."""
    check = ck.ok
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))

    def conn(port=base, timeout=5):
        return socket.create_connection(("127.0.0.1", port), timeout=timeout)

    # The well-behaved client: STA / OVR in a loop, checking every reply and its latency.
    stop = threading.Event()
    stats = {"n": 0, "bad": 0, "worst": 0.0}
    def good_client():
        s = conn(); f = s.makefile("rb")
        i = 0
        while not stop.is_set():
            ovr = 10 + (i % 90)
            t = time.monotonic()
            s.sendall(b"OVR%+06d\r\n" % ovr)
            a = f.readline()
            s.sendall(b"STA\r\n")
            b = f.readline()
            dt = time.monotonic() - t
            stats["worst"] = max(stats["worst"], dt)
            if a != b"OK\r\n" or len(b) != 50 or not b.startswith(b"OK") or b[36:42] != b"%+06d" % ovr:
                stats["bad"] += 1
                print(f"bad reply: {a!r} {b!r}")
            stats["n"] += 1
            i += 1
            time.sleep(0.005)
        s.close()
    g = threading.Thread(target=good_client); g.start()

    def newline_flood():
        """200 kB of bare newlines: 200000 ER replies, but the log grows by a few lines
        (per-client rate limit and one summary), and others are still served."""
        before = os.path.getsize(logpath)
        served = stats["n"]
        s = conn(timeout=30); f = s.makefile("rb")
        peer = "%s:%d" % s.getsockname()
        t0 = time.monotonic()
        s.sendall(b"\n" * 200000 + b"STA\r\n")
        n_er = 0
        while True:
            line = f.readline()
            if not line or len(line) == 50:
                break
            n_er += line == b"ER+00102\r\n"
        took = time.monotonic() - t0
        check("newline flood: every line answered ER+00102, then STA", n_er == 200000 and len(line) == 50,
              f"({n_er} ER)")
        # the burst is over after 1 s without a line: one summary line (10 s bound a broken run)
        end = time.monotonic() + 10

        def summarised():
            with open(logpath, "rb") as lf:
                lf.seek(before)
                return any(" " + peer + " " in l and "burst over" in l
                           for l in lf.read().decode("utf-8", "replace").splitlines())
        while not summarised() and time.monotonic() < end:
            time.sleep(0.05)
        after_burst = os.path.getsize(logpath)
        s.close()
        time.sleep(0.3)
        grown = after_burst - before
        with open(logpath, "rb") as lf:
            lf.seek(before)
            mine = [l for l in lf.read().decode("utf-8", "replace").splitlines() if " " + peer + " " in l]
        errors = [l for l in mine if " error: ER+00102" in l]
        sup = [int(l.split("suppressed: ")[1].split()[0]) for l in mine if " suppressed: " in l]
        mine_bytes = sum(len(l.encode()) + 1 for l in mine)
        print(f"newline flood: log grew {grown} bytes ({mine_bytes} from the flooding client) for "
              f"200000 bad lines in {took:.2f} s ({len(errors)} error lines, suppressed {sup})")
        # without -q the well-behaved client's OVR commands are logged meanwhile: count the
        # flooding client's lines; with -q (errors only) the whole log must stay small
        check("newline flood: its log lines stay small", mine_bytes < 4096, f"({mine_bytes} bytes)")
        if flood_only:
            check("newline flood: the -q log stays small", grown < 8192, f"({grown} bytes)")
        check("newline flood: at most 5 error lines per second", 0 < len(errors) <= 5 * (2 + int(took)),
              f"({len(errors)})")
        check("newline flood: one summary counts the rest",
              len(sup) >= 1 and len(errors) + sum(sup) == 200000 and
              any("burst over" in l for l in mine), f"({sup})")
        check("newline flood: others served meanwhile", stats["n"] > served, f"({stats['n'] - served} round trips)")

    if flood_only:
        newline_flood()
        stop.set(); g.join()
        check("well-behaved client: every reply correct", stats["bad"] == 0 and stats["n"] > 10,
              f"({stats['n']} round trips, {stats['bad']} bad)")
        s = conn(); f = s.makefile("rb"); s.sendall(b"STA\r\n")
        check("cell-sim alive at the end", len(f.readline()) == 50)
        return

    # 1) a 64 KiB line without CR LF: one ER+00102, the connection stays usable
    s = conn(); f = s.makefile("rb")
    s.sendall(b"X" * 65536)
    s.sendall(b"\r\nSTA\r\n")
    r1 = f.readline(); r2 = f.readline()
    check("64 KiB line without CR LF is rejected once", r1 == b"ER+00102\r\n", repr(r1))
    check("the same connection works after it", len(r2) == 50, repr(r2[:12]))
    s.close()

    # 2) 1000 connections opened and dropped (in waves of 250 held open, then closed;
    #    some with an abortive RST, some mid-line)
    opened = 0
    for wave in range(4):
        socks = []
        for k in range(250):
            try:
                c = conn(base + (k % 3))
                socks.append(c)
                opened += 1
            except OSError as e:
                print("connect failed:", e)
        for k, c in enumerate(socks):
            if k % 3 == 0:
                c.sendall(b"MOVA+01")              # abrupt disconnect mid-line
            if k % 2 == 0:
                c.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))  # RST
            c.close()
    check("1000 connections opened and dropped", opened == 1000, f"({opened})")

    # 3) garbage: random bytes, then a valid request on the same connection
    rnd = random.Random(1234)
    s = conn(); f = s.makefile("rb")
    garbage = b"\n".join(bytes(rnd.randrange(256) for _ in range(rnd.randrange(1, 120))).replace(b"\n", b"")
                         for _ in range(300))
    s.sendall(garbage + b"\nSTA\r\n")
    replies = []
    while True:
        line = f.readline()
        replies.append(line)
        if len(line) == 50 or not line:
            break
    check("garbage gets one ER reply per line", len(replies) == 301 and all(x.startswith(b"ER+001") for x in replies[:-1]), f"({len(replies) - 1} ER)")
    check("valid request after garbage", len(replies[-1]) == 50)
    s.close()

    # 4) a client sending 1 byte per second ("STA\r\n" over ~5 s) while others are served
    s = conn(timeout=10); f = s.makefile("rb")
    before = stats["n"]
    for ch in b"STA\r\n":
        s.sendall(bytes([ch]))
        time.sleep(1.0)
    r = f.readline()
    check("1 byte/s sender gets its reply", len(r) == 50, repr(r[:12]))
    # progress is the point, not a rate (a busy host serves fewer): blocked would be ~0
    check("others served meanwhile", stats["n"] - before > 20, f"({stats['n'] - before} round trips)")
    s.close()

    # 5) a client that never reads its replies (pipelines 2 MB of STA) does not block others
    s = conn(); s.setblocking(False)
    sent = 0
    t0 = time.monotonic()
    while time.monotonic() - t0 < 2.0:
        try:
            sent += s.send(b"STA\r\n" * 2000)
        except BlockingIOError:
            time.sleep(0.05)
    # others keep being served: wait for 20 more round trips (10 s only bounds a broken run)
    before = stats["n"]; t0 = time.monotonic()
    while stats["n"] - before <= 20 and time.monotonic() - t0 < 10.0:
        time.sleep(0.02)
    check("non-reading client: others still served", stats["n"] - before > 20, f"({stats['n'] - before} round trips, it sent {sent} bytes)")
    s.close()

    # 6) 200 kB of newlines: the log stays small
    if logpath:
        newline_flood()

    # 7) a silent client: connects, says nothing
    silent = conn()
    time.sleep(0.5)

    stop.set(); g.join()
    silent.close()
    check("well-behaved client: every reply correct", stats["bad"] == 0 and stats["n"] > 200,
          f"({stats['n']} round trips, {stats['bad']} bad, worst {stats['worst'] * 1000:.1f} ms)")
    check("well-behaved client: worst round trip < 1 s", stats["worst"] < 1.0)
    # finally the server is alive and answers a fresh connection
    s = conn(); f = s.makefile("rb"); s.sendall(b"STA\r\n")
    check("cell-sim alive at the end", len(f.readline()) == 50)


def device_checks(ck, cli, port):
    """cell-cli (the binary cli) against a fake robot on 127.0.0.1:port (and a fake CANopen
    shell on port + 11)."""
    check = ck.ok
    STA = b"OKF+010.000-002.000+005.999-01.2322T+00100+00000\r\n"
    PLATFORM_STA = b"OKF+00.0000+00.0000F+00100+00000\r\n"

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

    listeners = []
    for p in (port, port + 11):
        ls = socket.socket()
        ls.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        ls.bind(("127.0.0.1", p))
        ls.listen(8)
        listeners.append(ls)
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
    for ls in listeners:
        ls.shutdown(socket.SHUT_RDWR)
        ls.close()


def test_hostile_clients(procs, bins, ports):
    ck = Checks()
    base = ports.block(3, proto="tcp")
    sim = procs.start([bins.cell_sim, "-p", base], name="sim")
    wait_until(lambda: listening_tcp(base + 2) or not sim.running(), 30, "cell-sim listening")
    hostile_checks(ck, base, str(sim.log), False)
    ck.ok("cell-sim still running", sim.running())
    log = sim.out()
    n = log.count("connect: connection accepted")
    ck.ge("connections logged with their peer", n, 1000)
    ck.ok("overlong line logged", "error: ER+00102: line longer than 64 bytes dropped" in log)
    ck.done()


def test_quiet_log_flood(procs, bins, ports):
    # -q (errors only) used to log one line per bad line: 200 kB of newlines, 30.8 MB of log
    ck = Checks()
    base = ports.block(3, proto="tcp")
    sim = procs.start([bins.cell_sim, "-q", "-p", base], name="simq")
    wait_until(lambda: listening_tcp(base + 2) or not sim.running(), 30, "cell-sim -q listening")
    hostile_checks(ck, base, str(sim.log), True)
    ck.done()


def test_cli_hostile_device(bins, ports):
    ck = Checks()
    # the fake device listens on port and port + 11 (the CANopen shell of a platform on port + 1)
    while True:
        port = ports.tcp()
        try:
            s = socket.socket()
            s.bind(("127.0.0.1", port + 11))
            s.close()
            break
        except OSError:
            s.close()
    device_checks(ck, str(bins.cell_cli), port)
    ck.done()
