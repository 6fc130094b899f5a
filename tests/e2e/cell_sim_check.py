#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# cell-sim behaviour per command, over real TCP on 127.0.0.1 (run by cell_sim.sh).
import socket, sys, time

base = int(sys.argv[1])
fails = 0

def check(what, got, want):
    global fails
    ok = got == want
    print(("PASS" if ok else "FAIL") + f": {what}: got {got!r}" + ("" if ok else f", want {want!r}"))
    if not ok:
        fails += 1

class Dev:
    def __init__(self, port):
        self.s = socket.create_connection(("127.0.0.1", port), timeout=5)
        self.f = self.s.makefile("rb")
    def req(self, line):
        self.s.sendall(line.encode() + b"\r\n")
        return self.f.readline().decode()
    def sta(self):
        return self.req("STA")
    def wait_stopped(self, limit=10.0):
        t = time.time()
        while time.time() - t < limit:
            r = self.sta()
            if r[2] == "F":
                return r
            time.sleep(0.02)
        return "timeout"

r = Dev(base); p = Dev(base + 1); c = Dev(base + 2)
# initial state: at home, stopped, servo off, override 100, no error
check("robot STA at start", r.sta(), "OKF+000.000+000.000+050.000+00.0000F+00100+00000\r\n")
check("platform STA at start", p.sta(), "OKF+00.0000+00.0000F+00100+00000\r\n")
# servo off refuses motion (+00104, latched in STA)
check("MOV with servo off", r.req("MOVA+010.000+000.000+050.000+00.0000"), "ER+00104\r\n")
check("STA error field latched", r.sta()[-8:], "+00104\r\n")
check("RST clears the error", r.req("RST"), "OK\r\n")
check("STA after RST", r.sta(), "OKF+000.000+000.000+050.000+00.0000F+00100+00000\r\n")
check("SRVON", r.req("SRVON"), "OK\r\n")
check("OVR+00050", r.req("OVR+00050"), "OK\r\n")
check("OVR out of range", r.req("OVR+00101"), "ER+00103\r\n")
check("STA shows servo and override", r.sta(), "OKF+000.000+000.000+050.000+00.0000T+00050+00000\r\n")
# the spec's example move; it takes time (velocity limited), STA shows T then F
check("spec MOVA", r.req("MOVA+010.000-002.000+005.999-01.2322"), "OK\r\n")
s = r.sta()
check("moving flag right after MOV", s[2], "T")
check("MOV while moving is refused", r.req("MOVA+000.000+000.000+000.000+00.0000"), "ER+00107\r\n")
check("arrives at the target", r.wait_stopped(), "OKF+010.000-002.000+005.999-01.2322T+00050+00000\r\n")
# relative move
check("MOVR", r.req("MOVR+001.500+000.000-000.999+00.2322"), "OK\r\n")
check("relative target reached", r.wait_stopped(), "OKF+011.500-002.000+005.000-01.0000T+00050+00000\r\n")
# workspace limit (robot x in -200..200 by default)
check("workspace limit", r.req("MOVA+300.000+000.000+000.000+00.0000"), "ER+00105\r\n")
check("workspace error latched", r.sta()[-8:], "+00105\r\n")
r.req("RST"); r.wait_stopped()
check("RST homes", r.sta(), "OKF+000.000+000.000+050.000+00.0000T+00050+00000\r\n")
# STP stops mid-way; position between start and target (at 1 % the move takes 10 s, so a
# busy host stretching the 0.1 s below cannot let it arrive)
r.req("OVR+00001")
r.req("MOVA+100.000+000.000+050.000+00.0000")
time.sleep(0.1)
check("STP", r.req("STP"), "OK\r\n")
s = r.sta()
x = float(s[3:11])
check("STP: stopped", s[2], "F")
check("STP: stopped part-way", 0.0 < x < 100.0, True)
time.sleep(0.1)
check("STP: does not move on", float(r.sta()[3:11]), x)
# ITR (project extension) behaves like STP
r.req("MOVA+000.000+000.000+050.000+00.0000")
check("ITR", r.req("ITR"), "OK\r\n")
check("ITR: stopped", r.sta()[2], "F")
r.req("OVR+00100")
# override 0 holds a motion
r.req("OVR+00000"); r.req("MOVA+000.000+000.000+050.000+00.0000")
a = r.sta(); time.sleep(0.1); b = r.sta()
check("override 0 holds the motion", (a[2], a[3:35] == b[3:35]), ("T", True))
r.req("OVR+00100"); r.wait_stopped()
# PNP (project extension): lift, travel, descend
check("PNP", r.req("PNP+080.000+020.000+010.000+030.000+00.5000"), "OK\r\n")
seen_high = False
t = time.time()
while time.time() - t < 10:
    s = r.sta()
    if float(s[19:27]) > 79.0:
        seen_high = True
    if s[2] == "F":
        break
    time.sleep(0.01)
check("PNP travels at the clearance height", seen_high, True)
check("PNP final pose", r.sta(), "OKF+020.000+010.000+030.000+00.5000T+00100+00000\r\n")
check("PNP clearance below target", r.req("PNP+010.000+020.000+010.000+030.000+00.5000"), "ER+00103\r\n")
check("PNP on the platform", p.req("PNP+080.000+020.000+010.000+030.000+00.5000"), "ER+00106\r\n")
# protocol errors: not latched
check("unknown head", r.req("XYZ"), "ER+00101\r\n")
check("malformed MOV", r.req("MOVA+010.000"), "ER+00102\r\n")
check("platform MOV to the robot", r.req("MOVA+01.0000+01.0000"), "ER+00102\r\n")
check("lowercase", r.req("sta"), "ER+00101\r\n")
check("bare LF line", r.req(""), "ER+00102\r\n")
check("protocol errors not latched", r.sta()[-8:], "+00000\r\n")
check("HND on the robot", r.req("HND+00000OPEN"), "ER+00106\r\n")
# platform
check("platform SRVON (spec example)", p.req("SRVON"), "OK\r\n")
check("platform MOVA", p.req("MOVA+01.0000-00.5000"), "OK\r\n")
check("platform arrives", p.wait_stopped(), "OKF+01.0000-00.5000T+00100+00000\r\n")
check("platform STP (spec example)", p.req("STP"), "OK\r\n")
check("platform limit", p.req("MOVA+02.0000+00.0000"), "ER+00105\r\n")
check("platform SRVOF", p.req("SRVOF"), "OK\r\n")
check("platform servo off in STA", p.sta()[19], "F")
# conditioning: gripper valves and cameras
check("vacuum on", c.req("HND+00000OPEN"), "OK\r\n")
check("vacuum off (16-char CLOSE)", c.req("HND+00000CLOSE"), "OK\r\n")
check("blow on", c.req("HND+00001OPEN"), "OK\r\n")
check("blow off", c.req("HND+00001CLOSE"), "OK\r\n")
check("no gripper 2", c.req("HND+00002OPEN"), "ER+00103\r\n")
check("camera 1", c.req("ACQ+00001"), "OK\r\n")
check("camera 2", c.req("ACQ+00002"), "OK\r\n")
check("no camera 3", c.req("ACQ+00003"), "ER+00103\r\n")
check("conditioning has no STA", c.req("STA"), "ER+00106\r\n")
check("conditioning RST", c.req("RST"), "OK\r\n")
# several instructions in one segment, replies in order
r.s.sendall(b"STA\r\nOVR+00060\r\nXYZ\r\nSTA\r\n")
got = [r.f.readline().decode() for _ in range(4)]
check("pipelined replies in order", [g[:2] for g in got], ["OK", "OK", "ER", "OK"])
check("pipelined override applied", got[3][36:42], "+00060")
# CLO: OK then the device closes the connection
check("CLO", r.req("CLO"), "OK\r\n")
check("connection closed after CLO", r.f.readline(), b"")
# a new connection still works and sees the same device state
r2 = Dev(base)
check("new connection after CLO", r2.sta()[36:42], "+00060")
print(f"cell-sim checks: {'FAILED ' + str(fails) if fails else 'all passed'}")
sys.exit(1 if fails else 0)
