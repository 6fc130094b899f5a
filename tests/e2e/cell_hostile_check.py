#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Hostile clients against cell-sim while a well-behaved client keeps getting correct
# replies (run by cell_hostile.sh). Loopback only.
import os, random, resource, socket, struct, sys, threading, time

# usage: cell_hostile_check.py PORT_BASE [LOG_FILE [--flood-only]]
base = int(sys.argv[1])
logpath = sys.argv[2] if len(sys.argv) > 2 else None
flood_only = "--flood-only" in sys.argv[3:]
fails = []
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

def check(what, ok, detail=""):
    print(("PASS" if ok else "FAIL") + f": {what} {detail}")
    if not ok:
        fails.append(what)

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
    time.sleep(2.5)  # the burst is over after 1 s without a line: one summary line
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
    print("flood checks:", "FAILED " + ", ".join(fails) if fails else "all passed")
    sys.exit(1 if fails else 0)

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
print("hostile checks:", "FAILED " + ", ".join(fails) if fails else "all passed")
sys.exit(1 if fails else 0)
