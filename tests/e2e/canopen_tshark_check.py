#!/usr/bin/env python3
"""tshark's CANopen dissector (an independent decoder) on the bus pcap of cell-sim's
platform: the frames of the boot are named in the order of the Robox CANopen master
documentation ("Operazioni effettuate dal Master all'avvio della rete", steps 1-7), and the
node-loss section's recovery (node-addressed NMT) is there too.
Input: tshark -T fields with frame, function code, node, NMT cd, NMT node, SDO index, sub,
data, guard state, EMCY code, info (separator '|')."""
import sys

rows = []
for line in open(sys.argv[1]):
    f = line.rstrip("\n").split("|")
    if len(f) < 11:
        continue
    rows.append(dict(n=int(f[0]), fc=int(f[1], 16) if f[1] else -1, node=int(f[2], 16) if f[2] else -1,
                     cd=f[3], nmt_node=f[4], idx=f[5], sub=f[6], data=f[7], state=f[8], emcy=f[9],
                     info=f[10]))
fails = 0


def check(what, ok, detail=""):
    global fails
    print(("PASS: " if ok else "FAIL: ") + what + ("" if ok else ": " + detail))
    if not ok:
        fails += 1


def first(pred, start=0):
    for i in range(start, len(rows)):
        if pred(rows[i]):
            return i
    return None


# the platform's configuration (fixtures/canopen/platform.ini): node 1 heartbeat 100 ms,
# node 2 lifeguard 100 ms x 3 with bit 30 set (0x1017 = 0 first)
def pdo(node, comm, entries, cob):
    m = comm + 0x200
    seq = [(comm, 1, "%08x" % (cob | 0x80000000)), (m, 0, "00"), ]
    seq += [(m, i + 1, "%08x" % e) for i, e in enumerate(entries)]
    seq += [(m, 0, "%02x" % len(entries)), (comm, 2, "01"), (comm, 1, "%08x" % cob)]
    return seq


def le(hexword, size):
    v = int(hexword, 16)
    return "".join("%02x" % ((v >> (8 * i)) & 0xFF) for i in range(4))


def expect(node, wd):
    seq = [(0x1000, 0, None), (0x1006, 0, "00002710")] + wd
    seq += pdo(node, 0x1800, [0x60410010, 0x60640020], 0x180 + node)
    seq += pdo(node, 0x1400, [0x60400010, 0x60600008, 0x607A0020], 0x200 + node)
    return [(i, s, None if d is None else le(d, 4)) for i, s, d in seq]


want = {1: expect(1, [(0x1017, 0, "00000064")]),
        2: expect(2, [(0x1017, 0, "00000000"), (0x100C, 0, "00000064"), (0x100D, 0, "00000003")])}

# step 1: broadcast Enter Pre-Operational before anything else the master sends
i1 = first(lambda r: r["fc"] == 0)
check("step 1: first master frame is NMT Enter pre-operational to all",
      i1 is not None and rows[i1]["cd"] == "0x80" and rows[i1]["nmt_node"] == "0x00"
      and "Enter pre-operational" in rows[i1]["info"] and first(lambda r: r["fc"] == 0x0c) > i1,
      str(rows[i1] if i1 is not None else None))
# steps 2-5 per node, one node after the other, every SDO request answered
i6 = first(lambda r: r["fc"] == 0 and r["cd"] == "0x01")
reqs = [r for r in rows[i1:i6] if r["fc"] == 0x0c]
got = {}
for r in reqs:
    got.setdefault(r["node"], []).append((int(r["idx"], 16), int(r["sub"], 16), r["data"] or None))
for node in (1, 2):
    g = got.get(node, [])
    ok = len(g) == len(want[node]) and all(
        a[0] == b[0] and a[1] == b[1] and (b[2] is None or a[2].startswith(b[2][:len(a[2])]) and len(a[2]) >= 2)
        for a, b in zip(g, want[node]))
    check(f"steps 2-5 of node {node}: DeviceType, 0x1006, watchdog, PDOs in order ({len(g)} SDOs)", ok,
          f"got {[(hex(a), b, c) for a, b, c in g]}")
nodes_in_order = [r["node"] for r in reqs]
check("nodes configured one after the other", nodes_in_order == sorted(nodes_in_order), str(nodes_in_order))
up = [r for r in rows[i1:i6] if r["fc"] == 0x0b and r["idx"] == "0x1000"]
check("step 2: DeviceType answers 0x00020192 from both nodes",
      [(r["node"], r["data"]) for r in up] == [(1, "92010200"), (2, "92010200")], str(up))
wd2 = [int(r["idx"], 16) for r in reqs if r["node"] == 2 and r["idx"] in ("0x1017", "0x100c", "0x100d")]
check("step 4: lifeguard with bit 30: 0x1017 = 0, then 0x100C, 0x100D", wd2 == [0x1017, 0x100C, 0x100D], str(wd2))
# step 6: broadcast start; step 7: RxPDOs of the drives, SYNC, TxPDOs, heartbeats
check("step 6: NMT Start remote node to all", i6 is not None and rows[i6]["nmt_node"] == "0x00"
      and "Start" in rows[i6]["info"], str(rows[i6] if i6 else None))
i_rpdo = first(lambda r: r["fc"] == 4, i6)
i_sync = first(lambda r: r["fc"] == 1 and r["node"] == 0, i6)
i_tpdo = first(lambda r: r["fc"] == 3, i6)
check("step 7: master TxPDO (0x201), then SYNC, then the node's PDO (0x181)",
      None not in (i_rpdo, i_sync, i_tpdo) and i_rpdo < i_sync < i_tpdo,
      f"{i_rpdo} {i_sync} {i_tpdo}")
check("tshark names PDO and SYNC frames",
      "PDO" in rows[i_rpdo]["info"] and "SYNC" in rows[i_sync]["info"].upper(), rows[i_sync]["info"])
hb = first(lambda r: r["fc"] == 0x0e and r["node"] == 1 and r["state"] == "0x05", i6)
check("heartbeat of node 1: operational", hb is not None)
guard = first(lambda r: r["fc"] == 0x0e and r["node"] == 2 and r["state"] == "0x05", i6)
check("node guarding reply of node 2: operational", guard is not None)
em = first(lambda r: r["fc"] == 1 and r["node"] == 1 and r["emcy"] == "0x7305")
check("EMCY 0x7305 of node 1", em is not None and "EMCY" in rows[em]["info"].upper(), rows[em]["info"] if em else "")
# node loss: recovery of node 2 with node-addressed NMT only
pre2 = first(lambda r: r["fc"] == 0 and r["cd"] == "0x80" and r["nmt_node"] == "0x02")
st2 = first(lambda r: r["fc"] == 0 and r["cd"] == "0x01" and r["nmt_node"] == "0x02")
check("recovery: NMT pre-operational to node 2, its configuration, NMT start to node 2",
      None not in (pre2, st2) and pre2 < st2 and any(r["fc"] == 0x0c and r["node"] == 2 and r["idx"] == "0x1000"
                                                     for r in rows[pre2:st2]), f"{pre2} {st2}")
bc = [r for r in rows[(pre2 or 0):] if r["fc"] == 0 and r["nmt_node"] == "0x00" and r["cd"] in ("0x80",)]
check("recovery sends no broadcast NMT", not bc, str(bc[:2]))
sys.exit(1 if fails else 0)
