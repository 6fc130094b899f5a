#!/usr/bin/env python3
"""Test-only attacker for tests/e2e/test_server_attacks.py, test_server_stall.py and
test_server_flood.py.

Sends forged C4G Open datagrams at a c4g-server from its own UDP socket (another port than
the controller's, optionally another source address), then listens on that socket and
reports every datagram that came back. Prints key=value lines:
  lport=PORT  sent=N  waited=1|0  replies=N  reply_bytes=N  t_wait_ms=... t_send_ms=...

Usage: attacker.py PORT KIND [--src ADDR] [--wait FILE REGEX] [--wait-s S]
                   [--count N] [--gap-us U] [--spin 1] [--listen-s S] [--num N]
                   [--init FILE]
KIND:
  init    the figure 10.1 initialization packet (fixtures/vectors/init-fig10-1.bin) with
          AzLim 1e6 and FollowError 0 on every axis
  end504  a 6-axis cyclic packet with 504 (end of communication) on every axis
  fe508   a 6-axis cyclic packet with 508 on every axis, an actual position (D3) of 100 turns
          and an old NUM (out of order)
  mode    a 6-axis cyclic packet with an undefined mode (7777) on every axis
  mode3   a 6-axis cyclic packet with mode 3 (defined, not available on the controller)
  zeros   COUNT zero-filled 228-byte datagrams (a 6-axis cyclic packet's size)
  tiny    a 4-byte datagram
  sync    a 228-byte synchronization packet (6 axes, NUM 1, mode 0)
  sync48  COUNT 48-byte synchronization packets (1 axis, NUM 1, mode 0)
--gap-us paces the datagrams with time.sleep (the host adds its timer slack); with --spin 1
it busy-waits instead (a dense stream, one CPU busy). SIGTERM ends the sending early; the
listening and the report follow as usual.
Every loop is bounded: --wait polls at most --wait-s seconds, --count is capped at 100000.
"""
import os
import re
import signal
import socket
import struct
import sys
import time

AZLIM_OFF = 548
FE_OFF = 1040
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


def cyclic(num, mode, d3=0.0, infpar=5, n_axes=6):
    head = struct.pack("<iII", num, infpar, 0)
    ax = struct.pack("<i8f", mode, 0.0, 0.0, d3, 0.0, 0.0, 0.0, 0.0, 0.0)
    return head + ax * n_axes


def forged_init(path):
    b = bytearray(open(path, "rb").read())
    if len(b) != 1200:
        raise SystemExit("attacker: %s: %d bytes, want 1200" % (path, len(b)))
    for k in range(40):  # [arm][10 axes], arm-major, 4-byte little-endian floats
        struct.pack_into("<f", b, AZLIM_OFF + 4 * k, 1e6)
        struct.pack_into("<f", b, FE_OFF + 4 * k, 0.0)
    return bytes(b)


def main(argv):
    if len(argv) < 3:
        sys.stderr.write(__doc__)
        return 2
    port, kind = int(argv[1]), argv[2]
    opt = {"--src": "127.0.0.1", "--wait-s": "20", "--count": "1", "--gap-us": "0",
           "--listen-s": "0.5", "--num": "5000",
           "--init": os.path.join(ROOT, "fixtures", "vectors", "init-fig10-1.bin")}
    wait = None
    i = 3
    while i < len(argv):
        if argv[i] == "--wait":
            wait = (argv[i + 1], argv[i + 2])
            i += 3
        else:
            opt[argv[i]] = argv[i + 1]
            i += 2
    count = max(1, min(int(opt["--count"]), 100000))
    num = int(opt["--num"])
    if kind == "init":
        pkts = [forged_init(opt["--init"])]
    elif kind == "end504":
        pkts = [cyclic(num, 504)]
    elif kind == "fe508":
        pkts = [cyclic(11, 508, d3=100.0)]
    elif kind == "mode":
        pkts = [cyclic(num, 7777)]
    elif kind == "mode3":
        pkts = [cyclic(num, 3)]
    elif kind == "zeros":
        pkts = [bytes(228)]
    elif kind == "sync":
        pkts = [cyclic(1, 0, infpar=0)]
    elif kind == "sync48":
        pkts = [cyclic(1, 0, infpar=0, n_axes=1)]
    elif kind == "tiny":
        pkts = [b"\x0d\x00\x00\x00"]
    else:
        sys.stderr.write("attacker: unknown kind %s\n" % kind)
        return 2
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind((opt["--src"], 0))
    print("lport=%d" % s.getsockname()[1], flush=True)
    t0 = time.monotonic()
    waited = 1
    if wait is not None:
        waited = 0
        end = t0 + float(opt["--wait-s"])
        while time.monotonic() < end:  # bounded by --wait-s
            try:
                with open(wait[0], "r", errors="replace") as f:
                    if re.search(wait[1], f.read()):
                        waited = 1
                        break
            except OSError:
                pass
            time.sleep(0.002)
    t_wait = time.monotonic()
    sent = 0
    gap = float(opt["--gap-us"]) * 1e-6
    spin = opt.get("--spin", "0") == "1"
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    if waited:
        for k in range(count):
            if stop:
                break
            s.sendto(pkts[k % len(pkts)], ("127.0.0.1", port))
            sent += 1
            if gap > 0 and spin:
                nxt = time.monotonic() + gap
                while time.monotonic() < nxt:
                    pass
            elif gap > 0:
                time.sleep(gap)  # at least gap (the host's timer slack adds ~50 us)
    t_send = time.monotonic()
    replies = 0
    nbytes = 0
    s.settimeout(0.05)
    end = time.monotonic() + float(opt["--listen-s"])
    while time.monotonic() < end:  # bounded by --listen-s
        try:
            data, _ = s.recvfrom(4096)
            replies += 1
            nbytes += len(data)
        except socket.timeout:
            pass
    print("sent=%d" % sent)
    print("waited=%d" % waited)
    print("replies=%d" % replies)
    print("reply_bytes=%d" % nbytes)
    print("t_wait_ms=%.1f" % ((t_wait - t0) * 1e3))
    print("t_send_ms=%.1f" % ((t_send - t_wait) * 1e3))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
