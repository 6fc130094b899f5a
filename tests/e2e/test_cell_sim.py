# SPDX-License-Identifier: MIT
"""cell-sim behaviour per command over real TCP on 127.0.0.1 (a port block of three), the
injected servo faults (+00002/+00003), the INI file (-c) and option errors."""
import socket
import time

from e2e_extra import Checks, listening_tcp
from e2elib import wait_until


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


def cell_sim_checks(base, ck):
    """Every command of the three devices of a cell-sim on ports base..base+2 (also run by
    test_canopen.py with the platform on the CANopen bus)."""
    check = ck.eq
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


def start_sim(procs, bins, args, name, wait_ports):
    h = procs.start([bins.cell_sim] + [str(a) for a in args], name=name)
    for p in wait_ports:
        wait_until(lambda: listening_tcp(p) or not h.running(), 30, "cell-sim listening on %d" % p)
    assert h.running(), "cell-sim did not start: " + h.out()
    return h


def test_commands(procs, bins, ports):
    base = ports.block(3, proto="tcp")
    start_sim(procs, bins, ["-p", base, "-s", 20], "sim", [base, base + 1, base + 2])
    ck = Checks()
    cell_sim_checks(base, ck)
    ck.done()


def req(port, line):
    s = socket.create_connection(("127.0.0.1", port), 5)
    f = s.makefile("rb")
    s.sendall(line + b"\r\n")
    r = f.readline()
    s.sendall(b"STA\r\n")
    r2 = f.readline()
    s.close()
    return (r + r2).decode().replace("\r\n", "|")


def test_faults_config_options(procs, bins, ports, tmp_path):
    ck = Checks()
    base = ports.block(3, proto="tcp")
    sim = start_sim(procs, bins, ["-p", base, "-s", 20], "sim", [base, base + 2])
    # every connection is logged with the peer address
    Dev(base).sta()
    fb = ports.block(3, proto="tcp")
    flt = start_sim(procs, bins, ["-p", fb, "--servo-fault", "robot:1", "--servo-fault", "platform:2"],
                    "faults", [fb, fb + 1])
    out = req(fb, b"SRVON") + req(fb + 1, b"SRVON")
    ck.eq("injected servo faults", out, "ER+00002|OKF+000.000+000.000+050.000+00.0000F+00100+00002|"
          "ER+00003|OKF+00.0000+00.0000F+00100+00003|")
    ck.has("servo fault logged with the peer", flt.out(), r"robot 127\.0\.0\.1:[0-9]* error: ER\+00002")
    ck.has("connections logged with the peer", sim.out(), r"robot 127\.0\.0\.1:[0-9]* connect")
    # option errors: exit 2 with a message naming the problem
    r = procs.run([bins.cell_sim, "--workspace", "robot:q:0:1"])
    ck.ok("bad --workspace exits 2, named", r.returncode == 2 and "workspace" in r.stderr, (r.returncode, r.stderr))
    r = procs.run([bins.cell_sim, "-p", base])
    ck.ok("busy port exits 3", r.returncode == 3 and "cannot listen" in r.stderr, (r.returncode, r.stderr))
    r = procs.run([bins.cell_sim, "--version"])
    ck.has("--version", r.stdout, "^cell-sim [0-9]")
    ck.ok("--help has examples", "Examples:" in procs.run([bins.cell_sim, "--help"]).stdout)
    # the INI file (-c): [cell-sim] takes the long options, [DEVICE] port/workspace/home/
    # servo_fault; the command line wins over the file
    ini = tmp_path / "cfg.ini"
    unused = ports.block(3, proto="tcp")
    cb = ports.block(3, proto="tcp")
    ini.write_text("[cell-sim]\nport_base = %d\nspeed_factor = 20\n[robot]\nservo_fault = 1\n"
                   "workspace = z:-20:80\n" % unused)
    start_sim(procs, bins, ["-c", ini, "-p", cb], "ini", [cb, cb + 2])
    s = socket.create_connection(("127.0.0.1", cb), 5)
    f = s.makefile("rb")
    s.sendall(b"SRVON\r\n")
    ck.eq("config file read ([robot] servo_fault), -p wins over port_base", f.readline().decode().strip(),
          "ER+00002")
    s.close()
    bad = tmp_path / "bad.ini"
    bad.write_text("[cell-sim]\nspeed_factor = 10\n[robot]\nprot = 1\n")
    r = procs.run([bins.cell_sim, "-c", bad])
    ck.ok("config typo named with line and column",
          r.returncode == 2 and "bad.ini:4:1: [robot] unknown key 'prot'" in r.stderr, (r.returncode, r.stderr))
    bad.write_text("[cell-sim]\nspeed_factor = -1\n")
    r = procs.run([bins.cell_sim, "-c", bad])
    ck.ok("config bad value named", r.returncode == 2 and ":2:16: [cell-sim] speed_factor: bad value '-1'" in r.stderr,
          (r.returncode, r.stderr))
    r = procs.run([bins.cell_sim, "-c", "/nonexistent.ini"])
    ck.has("missing config file: exit 2, named", "%d %s" % (r.returncode, r.stderr),
           "^2 .*/nonexistent.ini: .*No such file or directory")
    ck.done()
