#!/usr/bin/env python3
"""cell-sim's platform on the CANopen bus: DS402 enable, CSP motion from RxPDO targets and
TxPDO positions, a node removed mid-move (the cell protocol's error reply), its recovery,
and the Robox diagnostic commands on the CANopen shell.
Usage: canopen_check.py PLATFORM_PORT SHELL_PORT"""
import socket
import sys
import time

fails = 0


def check(what, got, want):
    global fails
    ok = got == want if not callable(want) else want(got)
    print(("PASS: " if ok else "FAIL: ") + what + ("" if ok else f": got {got!r}, want {want!r}"))
    if not ok:
        fails += 1


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


plat = Line(int(sys.argv[1]), b"\r\n")
sh = Line(int(sys.argv[2]), b"\n")

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
sys.exit(1 if fails else 0)
