# SPDX-License-Identifier: MIT
"""cell-sim's platform on a CANopen bus (real TCP on 127.0.0.1): DS402 and CSP through the
master, a node removed mid-move and its recovery, the Robox diagnostic commands (from a socket
and from cell-cli); a shell that waits without blocking; the bus pcap decoded by real tshark
(its CANopen dissector) against the boot order of the Robox CANopen master documentation; the
candump log; SocketCAN on vcan where the kernel has it."""
import re
import signal
import socket
import statistics
import subprocess
import threading
import time

import pytest

from e2e_extra import Checks, listening_tcp
from e2elib import wait_until
from test_cell_sim import cell_sim_checks


def canopen_checks(ck, plat_port, shell_port):
    """cell-sim's platform on the CANopen bus: DS402 enable, CSP motion from RxPDO targets and
    TxPDO positions, a node removed mid-move (the cell protocol's error reply), its recovery,
    and the Robox diagnostic commands on the CANopen shell.
    The platform on plat_port, the shell on shell_port."""

    def check(what, got, want):
        ok = want(got) if callable(want) else got == want
        ck.ok(what, ok, f"got {got!r}, want {want!r}")

    class Line:
        def __init__(self, port, eol):
            self.s = socket.create_connection(("127.0.0.1", port), 5)
            self.s.settimeout(10)
            self.f = self.s.makefile("rb")
            self.eol = eol

        def req(self, line):
            self.s.sendall(line.encode() + self.eol)
            return self.f.readline().decode().rstrip("\r\n")

    def sta_pose(r):
        # OK<moving><A><B><servo><ovr><err>: OKF+00.0000+00.0000F+00100+00000
        return r[2], float(r[3:11]), float(r[11:19]), r[19], int(r[26:32])

    def wait_for(fn, secs):
        end = time.time() + secs
        while time.time() < end:
            v = fn()
            if v:
                return v
            time.sleep(0.05)
        return fn()

    plat = Line(plat_port, b"\r\n")
    sh = Line(shell_port, b"\n")

    check("booted: node 1 operational", sh.req("CO_RNMT 1"), "node 1: NMT operational (0x05), running")
    check("booted: node 2 operational", sh.req("CO_RNMT 2"), "node 2: NMT operational (0x05), running")
    check("drives wait in ready to switch on", sh.req("CO_STATE_MAC 1"),
          "node 1: DS402 ready to switch on (statusword 0x0231)")
    check("MOV with servo off", plat.req("MOVA+00.2000+00.2000"), "ER+00104")
    check("SRVON through DS402", plat.req("SRVON"), "OK")
    check("drive 1 operation enabled", sh.req("CO_STATE_MAC 1"),
          "node 1: DS402 operation enabled (statusword 0x0237)")
    check("drive 2 operation enabled", sh.req("CO_STATE_MAC 2"),
          "node 2: DS402 operation enabled (statusword 0x0237)")
    check("CSP mode by RxPDO (CO_RTPDO)", sh.req("CO_RTPDO 1 1 2"),
          "node 1 TxPDO1[2] modes_of_operation (0x6060:00) = 8 (0x08)")
    check("MOV", plat.req("MOVA+00.3000-00.2000"), "OK")
    done = wait_for(lambda: (lambda p: p if p[0] == "F" else None)(sta_pose(plat.req("STA"))), 10)
    check("STA: positions from the drives' TxPDOs", done[1:4], (0.3, -0.2, "T"))
    check("CO_RRPDO: actual position of node 1", sh.req("CO_RRPDO 1 1 2"),
          "node 1 RxPDO1[2] real_position (0x6064:00) = 300000 (0x000493E0)")
    check("CO_RTPDO: target of node 2", sh.req("CO_RTPDO 2 1 3"),
          "node 2 TxPDO1[3] ideal_position (0x607A:00) = -200000 (0xFFFCF2C0)")

    # the Robox shell commands
    check("CO_ROBJ DeviceType", sh.req("CO_ROBJ 1 0x1000 0"), "node 1 0x1000:00 = 0x00020192 (131474)")
    check("CO_ROBJ heartbeat", sh.req("CO_ROBJ 1 0x1017 0"), "node 1 0x1017:00 = 0x00000064 (100)")
    check("CO_ROBJ guard time (lifeguard node)", sh.req("CO_ROBJ 2 0x100C 0"), "node 2 0x100C:00 = 0x00000064 (100)")
    check("CO_ROBJ: abort named", sh.req("CO_ROBJ 2 0x2000 0"),
          "ERR node 2 0x2000:00: SDO abort 0x06020000 (object does not exist in the object dictionary)")
    check("CO_WOBJ", sh.req("CO_WOBJ 1 0x100D 0 1 5"), "node 1 0x100D:00 written")
    check("CO_SDO read back", sh.req("CO_SDO 1 r 0x100D 0"), "node 1 0x100D:00 = 0x00000005 (5)")
    check("CO_SDO write refused (read only)", sh.req("CO_SDO 1 w 0x1000 0 4 1"),
          "ERR node 1 0x1000:00: SDO abort 0x06010002 (attempt to write a read only object)")
    check("CO_WSDIAGNO", sh.req("CO_WSDIAGNO 2"),
          lambda r: r.startswith("node 2: running, NMT operational, step 0 failed: none"))
    check("CO_CHDIAGNO", sh.req("CO_CHDIAGNO"),
          lambda r: r.startswith("channel 0: 2 nodes, running, rx ") and "bad frame 0, bad dlc 0" in r)
    check("SIM_FAULT sends EMCY", sh.req("SIM_FAULT 1 0x7305"), "node 1: fault, EMCY 0x7305 sent")
    check("CO_REMCY", wait_for(lambda: (lambda r: r if "1 EMCY" in r else None)(sh.req("CO_REMCY 1")), 2),
          "node 1: 1 EMCY; code 0x7305 register 0x01 mfr 0400000000")
    check("drive 1 in fault (statusword from the next TxPDO)",
          wait_for(lambda: (lambda r: r if "fault" in r else None)(sh.req("CO_STATE_MAC 1")), 2),
          "node 1: DS402 fault (statusword 0x0218)")
    check("STA: the drive fault is servo motor 1 error", sta_pose(plat.req("STA"))[3:5], ("F", 2))
    # SRVON resets the fault (rising edge of controlword bit 7) and enables again
    check("SRVON after a drive fault", plat.req("SRVON"), "OK")
    check("drive 1 enabled again", sh.req("CO_STATE_MAC 1"),
          "node 1: DS402 operation enabled (statusword 0x0237)")

    # a node removed mid-move: the cell protocol's error reply
    check("MOV back", plat.req("MOVA-00.3000+00.3000"), "OK")
    time.sleep(0.05)
    check("unplug node 2 mid-move", sh.req("SIM_UNPLUG 2"), "node 2 unplugged (silent)")
    lost = wait_for(lambda: (lambda p: p if p[4] == 3 else None)(sta_pose(plat.req("STA"))), 5)
    check("STA: stopped, servo off, error +00003 (servo motor 2)", (lost[0], lost[3], lost[4]), ("F", "F", 3))
    check("MOV refused while node 2 is lost", plat.req("MOVA+00.0000+00.0000"), "ER+00003")
    check("SRVON refused while node 2 is lost", plat.req("SRVON"), "ER+00003")
    check("node 2 lost by lifeguard", sh.req("CO_WSDIAGNO 2"),
          lambda r: r.startswith("node 2: lost,") and "guarding failed" in r and "losses 1" in r)
    check("node 1 keeps running", sh.req("CO_RNMT 1"), lambda r: r.endswith("running"))

    # the node comes back: DeviceType polled every 2.5 s, steps 1-6 for it alone
    check("plug node 2 back", sh.req("SIM_PLUG 2"), "node 2 plugged in (power-up, boot-up message)")
    back = wait_for(lambda: (lambda r: r if r.startswith("node 2: running") else None)(sh.req("CO_WSDIAGNO 2")), 6)
    check("node 2 recovered", back, lambda r: r is not None and r.startswith("node 2: running"))
    check("RST clears the error", plat.req("RST"), "OK")
    check("SRVON after the recovery", plat.req("SRVON"), "OK")
    check("MOV after the recovery", plat.req("MOVA+00.1000+00.1000"), "OK")
    done = wait_for(lambda: (lambda p: p if p[0] == "F" else None)(sta_pose(plat.req("STA"))), 10)
    check("position reached after the recovery", done[1:5], (0.1, 0.1, "T", 0))
    # a drive stopped by NMT no longer runs: its targets would be ignored
    check("S_NMT stop", sh.req("S_NMT 1 stop"), "NMT stop sent to node 1")
    check("CO_RNMT: stopped, and no longer running",
          wait_for(lambda: (lambda r: r if "stopped" in r else None)(sh.req("CO_RNMT 1")), 2),
          "node 1: NMT stopped (0x04), lost")
    check("CO_WSDIAGNO names the cause", sh.req("CO_WSDIAGNO 1"),
          lambda r: r.startswith("node 1: lost, NMT stopped") and "left operational (NMT state) 0x00000004" in r)
    check("STA: the stopped drive is servo motor 1 error", sta_pose(plat.req("STA"))[3:5], ("F", 2))
    check("MOV refused while node 1 is stopped", plat.req("MOVA+00.0000+00.0000"), "ER+00002")
    check("S_NMT start", sh.req("S_NMT 0 start"), "NMT start sent to all nodes 0")
    back = wait_for(lambda: (lambda r: r if r.startswith("node 1: running") else None)(sh.req("CO_WSDIAGNO 1")), 6)
    check("node 1 started again: recovered by the DeviceType poll", back,
          lambda r: r is not None and r.startswith("node 1: running, NMT operational"))
    check("SIM_ABORT on a chosen object", sh.req("SIM_ABORT 1 0x6060 0 0x06090030"),
          "node 1: SDO abort 0x06090030 on 0x6060:00")
    check("CO_ROBJ: the injected abort", sh.req("CO_ROBJ 1 0x6060 0"),
          "ERR node 1 0x6060:00: SDO abort 0x06090030 (invalid value for parameter)")
    check("CO_EMCYINFO", sh.req("CO_EMCYINFO"), "EMCY: node 1: 1, last 0x7305; node 2: 0, last 0x0000;")
    check("D_NMT is CO_RNMT", sh.req("D_NMT 2"), lambda r: r.startswith("node 2: NMT operational"))
    check("unknown shell command", sh.req("CO_FOO 1"), "ERR unknown command 'CO_FOO' (HELP lists them)")
    check("bad node", sh.req("CO_RNMT 9"), "ERR node: want the id of a configured node")


def async_checks(ck, robot_port, shell_port):
    """cell-sim --canopen keeps serving while the platform or the CANopen shell waits: robot round
    trips while a SRVON waits for a drive that went away (up to 300 ms) and while SDO reads to a
    lost node are pending (each takes the SDO timeout times the tries), shell clients while
    another shell connection sits idle, two connections' SDOs at once (run by canopen.sh, with
    sdo_timeout_ms = 200 and 2 retries: 600 ms per read of a lost node).
    The robot on robot_port, the shell on shell_port."""

    check = ck.ok

    class Line:
        def __init__(self, port, eol, timeout=10):
            self.s = socket.create_connection(("127.0.0.1", port), 5)
            self.s.settimeout(timeout)
            self.f = self.s.makefile("rb")
            self.eol = eol

        def send(self, line):
            self.s.sendall(line.encode() + self.eol)

        def read(self):
            try:
                return self.f.readline().decode().rstrip("\r\n")
            except OSError as e:  # a blocked server: the check that reads it fails
                return f"no reply ({e})"

        def req(self, line):
            self.send(line)
            return self.read()

        def close(self):
            self.f.close()  # the socket stays open while its file object is
            self.s.close()

    sh = Line(shell_port, b"\n")
    plat = Line(robot_port + 1, b"\r\n")
    check("platform SRVOF", plat.req("SRVOF") == "OK")
    rtts, stop = [], threading.Event()

    def robot_client():
        r = Line(robot_port, b"\r\n")
        while not stop.is_set():
            t = time.monotonic()
            reply = r.req("STA")
            rtts.append((t, time.monotonic() - t, len(reply) == 48))
            time.sleep(0.002)

    def robot_during(what, t0, t1, worst_max):
        during = [d for t, d, ok in rtts if t0 <= t <= t1]
        if not during:
            check(f"robot round trips while {what}", False, "(none)")
            return
        worst, med = max(during), statistics.median(during)
        print(f"robot round trips while {what} ({(t1 - t0) * 1000:.0f} ms): {len(during)}, "
              f"median {med * 1000:.1f} ms, worst {worst * 1000:.1f} ms")
        check(f"robot served while {what}: worst round trip < {worst_max * 1000:.0f} ms",
              worst < worst_max, f"({worst * 1000:.1f} ms)")
        check(f"robot served while {what}: median < 100 ms", med < 0.1, f"({med * 1000:.1f} ms)")

    # SRVON while drive 2 has just gone (not yet found lost): the reply waits for the drives
    th = threading.Thread(target=robot_client)
    th.start()
    time.sleep(0.3)
    check("node 2 unplugged", sh.req("SIM_UNPLUG 2") == "node 2 unplugged (silent)")
    t0 = time.monotonic()
    r = plat.req("SRVON")
    t1 = time.monotonic()
    stop.set()
    th.join()
    print(f"SRVON with drive 2 gone: {r!r} after {(t1 - t0) * 1000:.0f} ms")
    check("SRVON with drive 2 gone: servo motor 2 error", r == "ER+00003", repr(r))
    # blocked, the loop would hold every client for the whole wait (up to 300 ms)
    robot_during("SRVON waits for the drives", t0, t1, 0.15)
    rtts.clear()
    stop.clear()
    end = time.monotonic() + 5
    while time.monotonic() < end and not sh.req("CO_WSDIAGNO 2").startswith("node 2: lost"):
        time.sleep(0.05)
    check("node 2 lost", sh.req("CO_WSDIAGNO 2").startswith("node 2: lost"))

    # a robot client's STA round trips, all along
    th = threading.Thread(target=robot_client)
    th.start()
    time.sleep(0.3)
    # SDO reads of the lost node, one after the other (the recovery poll of the node may hold
    # the SDO client for a while: the read waits for it, as the old code's "busy" is retried)
    t0 = time.monotonic()
    replies = []
    while len(replies) < 4 and time.monotonic() - t0 < 20:
        r = sh.req("CO_ROBJ 2 0x1000 0")
        if "busy" in r:
            time.sleep(0.01)
            continue
        replies.append(r)
    t1 = time.monotonic()
    stop.set()
    th.join()
    check("the SDO reads to the lost node end in a timeout",
          len(replies) == 4 and all(r == "ERR node 2 0x1000:00: SDO timeout 0x05040000 (no answer)" for r in replies),
          repr(replies[:2]))
    check("every robot reply a STA", all(ok for _, _, ok in rtts), f"({len(rtts)} round trips)")
    # blocked, each would hold the loop for a whole read (600 ms); generous bounds for a loaded host
    robot_during(f"{len(replies)} SDO reads of the lost node are pending", t0, t1, 0.3)
    n = len([1 for t, _, _ in rtts if t0 <= t <= t1])
    check("robot served while the SDOs are pending: >= 20 round trips", n >= 20, f"({n})")

    # two connections' SDOs at once: the second waits for the first, both answered
    a, b = Line(shell_port, b"\n"), Line(shell_port, b"\n")
    a.send("CO_ROBJ 2 0x1000 0")
    time.sleep(0.05)
    tb = time.monotonic()
    rb = b.req("CO_ROBJ 1 0x1017 0")
    rb_s = time.monotonic() - tb
    ra = a.read()
    check("two SDOs at once: the lost node's times out", ra == "ERR node 2 0x1000:00: SDO timeout 0x05040000 (no answer)", repr(ra))
    check("two SDOs at once: the other is queued and answered", rb == "node 1 0x1017:00 = 0x00000064 (100)", f"{rb!r} ({rb_s * 1000:.0f} ms)")
    # commands sent together on one connection are answered in order
    a.send("CO_ROBJ 2 0x1000 0\nCO_RNMT 1")
    r1, r2 = a.read(), a.read()
    check("replies in the order of the commands", r1.startswith("ERR node 2 0x1000:00") and r2.startswith("node 1: NMT"),
          repr((r1, r2)))
    a.close()
    b.close()

    # an idle shell connection locks nobody out
    idle = [Line(shell_port, b"\n")]
    time.sleep(0.2)
    t = time.monotonic()
    try:
        other = Line(shell_port, b"\n", timeout=3)
        r = other.req("CO_RNMT 1")
    except OSError as e:
        r = f"no reply ({e})"
    took = time.monotonic() - t
    print(f"second shell client while the first is idle: {r!r} after {took * 1000:.1f} ms")
    check("a second shell client is served while the first is idle (< 1 s)",
          r.startswith("node 1: NMT") and took < 1.0, f"({took * 1000:.1f} ms)")
    other.close()
    try:
        idle += [Line(shell_port, b"\n") for _ in range(7)]
        time.sleep(0.2)
        ninth = Line(shell_port, b"\n", timeout=3)
        idle.append(ninth)
        r = ninth.read()
    except OSError as e:
        r = f"no connection ({e})"
    check("a ninth connection is told the limit", r == "ERR too many shell connections (8): retry later", repr(r))
    for c in idle:
        c.close()
    time.sleep(0.2)
    try:
        r = Line(shell_port, b"\n", timeout=3).req("CO_RNMT 1")
    except OSError as e:
        r = f"no connection ({e})"
    check("served again once they leave", r.startswith("node 1: NMT"), repr(r))


def tshark_checks(ck, path):
    """tshark's CANopen dissector (an independent decoder) on the bus pcap of cell-sim's
    platform: the frames of the boot are named in the order of the Robox CANopen master
    documentation ("Operazioni effettuate dal Master all'avvio della rete", steps 1-7), and the
    node-loss section's recovery (node-addressed NMT) is there too.
    path: tshark -T fields with frame, function code, node, NMT cd, NMT node, SDO index, sub,
    data, guard state, EMCY code, info (separator '|')."""

    rows = []
    for line in open(path):
        f = line.rstrip("\n").split("|")
        if len(f) < 11:
            continue
        rows.append(dict(n=int(f[0]), fc=int(f[1], 16) if f[1] else -1, node=int(f[2], 16) if f[2] else -1,
                         cd=f[3], nmt_node=f[4], idx=f[5], sub=f[6], data=f[7], state=f[8], emcy=f[9],
                         info=f[10]))
    check = ck.ok

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


def start_sim(procs, bins, base, args, name, wait_ports):
    h = procs.start([bins.cell_sim, "-p", base] + [str(a) for a in args], name=name)
    for p in wait_ports:
        wait_until(lambda: listening_tcp(p) or not h.running(), 30, "cell-sim listening on %d" % p)
    assert h.running(), "cell-sim did not start: " + h.out()
    return h


def shell_rnmt(port, node):
    with socket.create_connection(("127.0.0.1", port), 5) as s:
        s.sendall(b"CO_RNMT %d\n" % node)
        return s.makefile("rb").readline().decode().strip()


def shell_state(port):
    """the diagnostic commands' replies (shown when a check failed)"""
    s = socket.create_connection(("127.0.0.1", port), 5)
    f = s.makefile("rb")
    out = []
    for c in ("CO_WSDIAGNO 1", "CO_WSDIAGNO 2", "CO_STATE_MAC 1", "CO_STATE_MAC 2"):
        s.sendall(c.encode() + b"\n")
        out.append(f.readline().decode().strip())
    s.close()
    return out


def test_canopen(procs, bins, ports, tmp_path):
    """DS402 and CSP through the master, a node removed mid-move and its recovery, the Robox
    diagnostic commands, the same from cell-cli; then the bus pcap decoded by real tshark (its
    CANopen dissector) against the boot order of the Robox documentation; the candump log."""
    ck = Checks()
    # the CANopen shell of cell-cli is on the platform port + 10: base + 11
    base = ports.block(12, proto="tcp")
    shell = base + 11
    pcap, log = tmp_path / "bus.pcap", tmp_path / "bus.log"
    sim = start_sim(procs, bins, base, ["-s", 20, "--canopen", "fixtures/canopen/platform.ini", "--canopen-port", shell,
                                        "--can-pcap", pcap, "--can-log", log], "sim", [base + 1, shell])
    # the shell listens before the master has booted the network (NMT start comes some tens
    # of ms later): the checks start once the boot is over, as they did when a new python3
    # process ran them
    wait_until(lambda: all(shell_rnmt(shell, n).endswith("operational (0x05), running") for n in (1, 2)), 10,
               "the CANopen network booted")
    n0 = len(ck.failed)
    canopen_checks(ck, base + 1, shell)
    if len(ck.failed) > n0:
        print("shell state:", shell_state(shell))
    # the same commands from cell-cli (the shell is on the platform port + 10)

    def cli(*args):
        r = procs.run([bins.cell_cli, "-p", base, "canopen"] + [str(a) for a in args])
        return r.returncode, r.stdout.rstrip("\n"), r.stderr

    out = cli("CO_RNMT", 1)[1]
    ck.eq("cell-cli canopen CO_RNMT", out, "node 1: NMT operational (0x05), running")
    ck.eq("cell-cli canopen CO_ROBJ", cli("CO_ROBJ", 2, "0x1000", 0)[1], "node 2 0x1000:00 = 0x00020192 (131474)")
    out = cli("CO_STATE_MAC", 2)[1]
    ck.ok("cell-cli canopen CO_STATE_MAC", out.startswith("node 2: DS402 "), out)
    rc, out, err = cli("CO_ROBJ", 2, "0x2000", 0)
    ck.ok("cell-cli canopen: an SDO abort exits 1 with the abort named on stderr",
          rc == 1 and out == "" and "0x06020000 (object does not exist" in err, (rc, out, err))
    rc, out, err = cli()
    ck.ok("cell-cli canopen without a command exits 2", rc == 2 and "want a command" in err, (rc, err))
    noshell = ports.block(12, proto="tcp")
    r = procs.run([bins.cell_cli, "-p", noshell, "canopen", "CO_RNMT", 1])
    ck.ok("cell-cli canopen without a shell exits 1",
          r.returncode == 1 and "cannot connect to the CANopen shell at 127.0.0.1:%d" % (noshell + 11) in r.stderr,
          (r.returncode, r.stderr))
    sim.signal(signal.SIGTERM)
    sim.wait(10)
    # the candump log: can-utils' format, the boot's first frames
    lines = log.read_text().splitlines()
    head = [re.sub(r"^\([0-9.]*\) ", "", l) for l in lines[:3]]
    ck.eq("candump log starts with the boot-up messages and NMT pre-operational", head,
          ["vcan0 701#00", "vcan0 702#00", "vcan0 000#8000"])
    ck.ok("every candump line is (sec.usec) iface ID#DATA",
          any(re.match(r"^\([0-9]+\.[0-9]{6}\) vcan0 [0-9A-F]{3}#([0-9A-F]{2})*$", l) for l in lines) and
          all(re.match(r"^\([0-9]+\.[0-9]{6}\) vcan0 [0-9A-F]{3}#(([0-9A-F]{2})*|R)$", l) for l in lines),
          [l for l in lines if not re.match(r"^\([0-9]+\.[0-9]{6}\) vcan0 [0-9A-F]{3}#(([0-9A-F]{2})*|R)$", l)][:3])
    # the oracle: tshark's CANopen dissector on the pcap (DLT_CAN_SOCKETCAN)
    r = procs.run(["tshark", "-r", pcap, "-d", "can.subdissector,canopen", "-T", "fields", "-E", "separator=|",
                   "-e", "frame.number", "-e", "canopen.function_code", "-e", "canopen.node_id",
                   "-e", "canopen.nmt_ctrl.cd", "-e", "canopen.nmt_ctrl.node_id", "-e", "canopen.sdo.main_idx",
                   "-e", "canopen.sdo.sub_idx", "-e", "canopen.sdo.data.bytes", "-e", "canopen.nmt_guard.state",
                   "-e", "canopen.em.err_code", "-e", "_ws.col.Info"], timeout=120)
    ck.eq("tshark reads the bus pcap (exit)", r.returncode, 0)
    fields = tmp_path / "tshark.txt"
    fields.write_text(r.stdout)
    tshark_checks(ck, str(fields))
    ck.done()


def test_canopen_waits_without_blocking(procs, bins, ports, tmp_path):
    """robot round trips while SDO reads to a lost node are pending (600 ms each with this
    timeout), an idle shell connection, SDOs of two connections"""
    ck = Checks()
    ini = tmp_path / "slow-sdo.ini"
    text = open("fixtures/canopen/platform.ini").read()
    text = re.sub(r"(?m)^sdo_timeout_ms = .*", "sdo_timeout_ms = 200", text)
    text = re.sub(r"(?m)^sdo_retries = .*", "sdo_retries = 2", text)
    ini.write_text(text)
    base = ports.block(3, proto="tcp")
    shell = ports.tcp()
    start_sim(procs, bins, base, ["--canopen", ini, "--canopen-port", shell], "sim", [base, shell])
    async_checks(ck, base, shell)
    ck.done()


def test_cell_with_platform_on_canopen(procs, bins, ports):
    """pick-and-place and the other devices still run with the platform on the bus"""
    ck = Checks()
    base = ports.block(3, proto="tcp")
    start_sim(procs, bins, base, ["-s", 20, "--canopen", "fixtures/canopen/platform.ini",
                                  "--canopen-port", ports.tcp()], "sim", [base + 1])
    cell_sim_checks(base, ck)
    ck.done()


def test_socketcan(procs, bins, ports, tmp_path):
    """SocketCAN: a real vcan interface where the kernel has one"""
    add = subprocess.run(["ip", "link", "add", "dev", "c4gvcan0", "type", "vcan"], capture_output=True, text=True)
    if add.returncode != 0:
        pytest.skip("cannot create a vcan interface (%s); the tests above ran on the in-process virtual bus"
                    % add.stderr.strip())
    try:
        up = subprocess.run(["ip", "link", "set", "up", "c4gvcan0"], capture_output=True, text=True)
        assert up.returncode == 0, up.stderr
        base = ports.block(3, proto="tcp")
        shell = ports.tcp()
        sim = start_sim(procs, bins, base, ["-s", 20, "--canopen", "fixtures/canopen/platform.ini",
                                            "--canopen-port", shell, "--can-if", "c4gvcan0"], "sim", [shell])
        s = socket.create_connection(("127.0.0.1", shell), 5)
        f = s.makefile("rb")
        time.sleep(0.5)  # the network boots over the real CAN socket meanwhile
        s.sendall(b"CO_RNMT 2\n")
        out = f.readline().decode().strip()
        s.close()
    finally:
        subprocess.run(["ip", "link", "del", "c4gvcan0"], capture_output=True)
    assert out == "node 2: NMT operational (0x05), running", "SocketCAN: %s\n%s" % (out, sim.out()[-2000:])
