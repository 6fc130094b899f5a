#!/usr/bin/env python3
"""Checks for tests/e2e/server_attacks.sh (prints key=value lines).

attack_check.py currents MONI INIT_BIN
    MONI: c4g-server --moni CSV (type 0). INIT_BIN: the controller's real initialization
    packet (AzLim at byte 548, [arm][10 axes] little-endian floats). For every row where
    the server sent a current (tx_d5 != 0): the total SMP+ current + delta (mode 9) must stay
    within +/-AzLim, or the delta must point back towards 0 (the clamp only shrinks).
    Prints rows, current_rows, over (violations), max_tx_d5, max_total_ratio (|total|/AzLim).
attack_check.py pcap PCAP PORT
    Counts the datagrams of a c4g-server --pcap capture to and from UDP port PORT:
    to_port, from_port.
"""
import csv
import struct
import sys


def currents(moni, init_bin):
    b = open(init_bin, "rb").read()
    az = struct.unpack_from("<40f", b, 548)
    rows = cur = over = 0
    max_tx = 0.0
    max_ratio = 0.0
    with open(moni, newline="") as f:
        r = csv.reader(f)
        head = next(r)
        ix = {name: k for k, name in enumerate(head)}
        for row in r:
            if len(row) < len(head):
                continue
            rows += 1
            tx = float(row[ix["tx_d5"]])
            if tx == 0.0:
                continue
            cur += 1
            smp = float(row[ix["rx_d5"]])
            lim = az[(int(row[ix["arm"]]) - 1) * 10 + int(row[ix["logical"]]) - 1]
            total = smp + tx
            max_tx = max(max_tx, abs(tx))
            if lim > 0:
                max_ratio = max(max_ratio, abs(total) / lim)
            inside = abs(total) <= lim * (1 + 1e-5)
            shrinks = (tx > 0 and total <= smp) or (tx < 0 and total >= smp)
            if not inside and not shrinks:
                over += 1
                if over <= 5:
                    sys.stderr.write("over AzLim %.3f: %s\n" % (lim, ",".join(row)))
    print("rows=%d" % rows)
    print("current_rows=%d" % cur)
    print("over=%d" % over)
    print("max_tx_d5=%.4f" % max_tx)
    print("max_total_ratio=%.4f" % max_ratio)


def pcap(path, port):
    data = open(path, "rb").read()
    magic = struct.unpack_from("<I", data, 0)[0]
    end = "<" if magic in (0xA1B2C3D4, 0xA1B23C4D) else ">"
    off = 24
    to_port = from_port = frames = 0
    while off + 16 <= len(data):
        incl = struct.unpack_from(end + "I", data, off + 8)[0]
        frame = data[off + 16:off + 16 + incl]
        off += 16 + incl
        frames += 1
        if len(frame) < 14 + 20 + 8:
            continue
        ihl = (frame[14] & 0x0F) * 4
        sport, dport = struct.unpack_from(">HH", frame, 14 + ihl)
        if dport == port:
            to_port += 1
        if sport == port:
            from_port += 1
    print("frames=%d" % frames)
    print("to_port=%d" % to_port)
    print("from_port=%d" % from_port)


def main(argv):
    if len(argv) == 4 and argv[1] == "currents":
        currents(argv[2], argv[3])
    elif len(argv) == 4 and argv[1] == "pcap":
        pcap(argv[2], int(argv[3]))
    else:
        sys.stderr.write(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
