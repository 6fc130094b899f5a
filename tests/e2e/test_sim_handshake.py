# SPDX-License-Identifier: MIT
"""c4g-sim start-up handshake on the wire, read back from its pcap with tshark: 9 sync
packets (NUM 1..9) answered with 732 bytes (NUM + 1), the 1200-byte init packet (NUM 10)
echoed with NUM 11, 2 more syncs (NUM 11, 12), then cyclic packets from NUM 13. Also: the
pcap payloads equal what an independent reader of the file finds."""
import shutil
import struct

from simlib import STALL_OK, run_sim, sim_json, start_pc


def pcap_payloads(path):
    """UDP payloads of a pcap file (Ethernet, IPv4), read here without any library; each
    IPv4 header checksum is checked."""
    data = path.read_bytes()
    magic, = struct.unpack("<I", data[:4])
    assert magic == 0xa1b2c3d4, hex(magic)
    linktype, = struct.unpack("<I", data[20:24])
    assert linktype == 1
    off, out = 24, []
    while off < len(data):
        _, _, incl, _ = struct.unpack("<IIII", data[off:off + 16])
        off += 16
        f = data[off:off + incl]
        off += incl
        assert f[12:14] == b"\x08\x00" and f[23] == 17
        s = sum(struct.unpack(">10H", f[14:34]))
        while s >> 16:
            s = (s & 0xffff) + (s >> 16)
        assert s == 0xffff, "bad IPv4 header checksum"
        ulen, = struct.unpack(">H", f[38:40])
        out.append(f[42:42 + ulen - 8].hex())
    return out


def test_handshake_on_the_wire(procs, bins, ports, tmp_path):
    tshark = shutil.which("tshark")
    assert tshark, "tshark not installed"
    port = ports.udp()
    start_pc(procs, bins, port)
    pcap = tmp_path / "h.pcap"
    r = run_sim(procs, bins, "-p", port, "-n", 40, *STALL_OK, "--pcap", pcap, "--json")
    assert r.returncode == 0, r.stderr
    j = sim_json(r)
    t = procs.run([tshark, "-r", pcap, "-T", "fields", "-e", "udp.dstport", "-e", "udp.length",
                   "-e", "udp.payload"])
    rows = [l.split("\t") for l in t.stdout.splitlines()]
    assert rows, "tshark read nothing: " + t.stderr
    tx, rx = [], []
    for dport, ulen, payload in rows:
        num = struct.unpack("<i", bytes.fromhex(payload[:8]))[0]
        (tx if int(dport) == port else rx).append((int(ulen) - 8, num))
    # each direction in its own order: how the two interleave depends on the host's
    # scheduling (a reply may come after the next packet left), what each side sends does not
    want_tx = [(228, n) for n in range(1, 10)] + [(1200, 10), (228, 11), (228, 12), (228, 13)]
    want_rx = [(732, n + 1) for n in range(1, 10)] + [(1200, 11), (732, 12), (732, 13), (228, 14)]
    assert tx[:13] == want_tx, "to the PC: 9 sync (228 B, NUM 1..9), init (1200 B, NUM 10), " \
        "2 sync (NUM 11, 12), cyclic from NUM 13"
    assert rx[:13] == want_rx, "from the PC: 732 B NUM n + 1 per sync, the init echoed with " \
        "NUM 11, cyclic replies 228 B"
    assert len(tx) == 52, "datagrams to the PC (9 + 1 + 2 + 40)"
    # the PC answers each one once; the last replies may come after the sim stopped listening
    assert 50 <= len(rx) <= 52, "%d datagrams from the PC for 52 sent" % len(rx)
    # every packet the sim judged got its reply in time, or was counted (missing = the PC
    # was late; on a busy host that can happen, and is not what this test is about)
    rp = j["replies"]
    assert rp["ok"] + rp["missing"] + rp["unjudged"] == 52, "every packet judged: %s" % rp
    # independent oracle: the pcap file parsed here, every payload compared with tshark's
    assert pcap_payloads(pcap) == [row[2] for row in rows], "pcap payloads differ from tshark's"


def test_altered_init_echo(procs, bins, ports):
    # a PC whose init echo differs from the init packet (one byte of AzLim, axis 1) holds
    # other limits than the controller's: the session fails at once (ERR_C4GOPEN, exit 1,
    # drives off), with the byte offset and the field named
    port = ports.udp()
    start_pc(procs, bins, port, "--alter-init")
    r = run_sim(procs, bins, "-p", port, "-n", 200, "--json")
    assert r.returncode == 1, r.stderr
    j = sim_json(r)
    assert any(e.get("name") == "ERR_C4GOPEN" for e in j["errors"]), j["errors"]
    assert "init echo differs from the init packet sent at byte offset 549 (field AzLim" in r.stderr, r.stderr
    assert j["packets"]["cyclic"] == 0, "no cyclic packet sent"
    assert all(not a["drive_on"] for a in j["robot"]), "drives off"
