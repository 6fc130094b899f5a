#!/usr/bin/env python3
"""Test-only spoofer for tests/e2e/test_server_spoof.py: sends a datagram whose source is the
controller's own address and port (what an attacker on the network can do; a second
ordinary socket cannot), with a raw IPv4 socket. Needs CAP_NET_RAW: the test runs it inside
a network namespace of its own (unshare -rn), where it has it.

It watches the loopback interface (AF_PACKET) for the controller's datagrams to the PC's
port and fires once its trigger is seen:
  init9 PORT FILE     after the controller's sync NUM 9 (its last before the init packet):
                      the 1200-byte FILE, from the controller's endpoint
  mode9 PORT          after a cyclic packet with mode 9 on axis 1: a 6-axis cyclic packet
                      with 504 on every axis and the next NUM, from the controller's endpoint
Prints key=value lines: fired=1|0 src_port=N num=N, and for init9 first_init=forged|
controller|none: which init packet reached the PC's port first (the wire's order). Every wait is bounded (--wait-s, 20 s).
"""
import socket
import struct
import sys
import time

ETH_P_IP = 0x0800


def ip_udp(src, sport, dst, dport, payload):
    udp_len = 8 + len(payload)
    udp = struct.pack("!HHHH", sport, dport, udp_len, 0) + payload  # checksum 0: none (IPv4)
    total = 20 + udp_len
    hdr = struct.pack("!BBHHHBBH4s4s", 0x45, 0, total, 0, 0x4000, 64, socket.IPPROTO_UDP, 0,
                      socket.inet_aton(src), socket.inet_aton(dst))
    csum = 0
    for i in range(0, 20, 2):
        csum += (hdr[i] << 8) | hdr[i + 1]
    while csum >> 16:
        csum = (csum & 0xFFFF) + (csum >> 16)
    hdr = hdr[:10] + struct.pack("!H", ~csum & 0xFFFF) + hdr[12:]
    return hdr + udp


def first_init(sniff, port, forged):
    """Which 1200-byte datagram to the PC's port crossed the loopback first once the forged
    one was sent: "forged", "controller" (the spoofer came too late: the host held it up),
    or "none" within 2 s. The capture queue keeps the wire's order."""
    end = time.monotonic() + 2.0
    while time.monotonic() < end:
        try:
            pkt, addr = sniff.recvfrom(4096)
        except socket.timeout:
            continue
        if addr[2] == socket.PACKET_OUTGOING or len(pkt) < 28 or pkt[9] != socket.IPPROTO_UDP:
            continue
        ihl = (pkt[0] & 0x0F) * 4
        dport = struct.unpack("!H", pkt[ihl + 2:ihl + 4])[0]
        data = pkt[ihl + 8:]
        if dport == port and len(data) == 1200:
            return "forged" if data == forged else "controller"
    return "none"


def main(argv):
    if len(argv) < 3 or argv[1] not in ("init9", "mode9"):
        sys.stderr.write(__doc__)
        return 2
    kind, port = argv[1], int(argv[2])
    payload = None
    if kind == "init9":
        payload = open(argv[3], "rb").read()
    wait_s = 20.0
    sniff = socket.socket(socket.AF_PACKET, socket.SOCK_DGRAM, socket.htons(ETH_P_IP))
    sniff.bind(("lo", 0))
    sniff.settimeout(0.2)
    raw = socket.socket(socket.AF_INET, socket.SOCK_RAW, socket.IPPROTO_RAW)
    end = time.monotonic() + wait_s
    print("ready=1", flush=True)
    while time.monotonic() < end:
        try:
            pkt, addr = sniff.recvfrom(4096)
        except socket.timeout:
            continue
        if addr[2] == socket.PACKET_OUTGOING or len(pkt) < 28 or pkt[9] != socket.IPPROTO_UDP:
            continue
        ihl = (pkt[0] & 0x0F) * 4
        sport, dport = struct.unpack("!HH", pkt[ihl:ihl + 4])
        data = pkt[ihl + 8:]
        if dport != port or len(data) < 16:
            continue
        num = struct.unpack("<i", data[0:4])[0]
        mode0 = struct.unpack("<i", data[12:16])[0]
        src = socket.inet_ntoa(pkt[12:16])
        if kind == "init9" and len(data) != 1200 and num == 9:
            forged = payload
        elif kind == "mode9" and len(data) != 1200 and mode0 == 9 and num > 12:
            head = struct.pack("<iII", num + 1, 5, 0)
            forged = head + struct.pack("<i8f", 504, *([0.0] * 8)) * 6
        else:
            continue
        raw.sendto(ip_udp(src, sport, "127.0.0.1", port, forged), ("127.0.0.1", 0))
        print("fired=1\nsrc_port=%d\nnum=%d" % (sport, num), flush=True)
        if kind == "init9":
            print("first_init=%s" % first_init(sniff, port, forged), flush=True)
        return 0
    print("fired=0", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
