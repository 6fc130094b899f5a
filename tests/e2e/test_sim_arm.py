# SPDX-License-Identifier: MIT
"""c4g-sim's arm plant (--plant fixtures/sim/smart-six.xml: MuJoCo mechanics, the controller's
own dynamic model in EXT1/EXT2) against c4g-server: the mode-4 sine on every axis, and the
server's mode-4, -5, -7, -8, -2 and -9 behaviours of test_server_modes.py. Real processes, real UDP on
127.0.0.1. The physics itself is checked in process (tests/tools/test_sim_arm.c)."""
import pytest

from e2elib import Checks, csv_rows
from simlib import run_sim
from srvlib import SIM_PATIENT

ARM = ["--plant", "fixtures/sim/smart-six.xml"]
FOLLOW_ERROR = 7.5   # turns: the init packet's FollowError of axes 1..5 (figure 10.1)


def protocol_clean(c, label, r):
    """c4g-sim exit 0 with no error and no protocol fault on either side"""
    c.eq("%s: c4g-sim exit 0" % label, r.simrc, 0)
    c.eq("%s: no EXPECT failed" % label, r.sv("expect_failed"), 0)
    c.eq("%s: no controller error" % label, r.sim.get("errors"), [])
    rep = r.sim.get("replies", {})
    c.eq("%s: no reply with a wrong NUM" % label, rep.get("wrong_num"), 0)
    # a plus-one reply to the init packet that comes after the next packet left reads, under
    # the default policy `either`, as an echo of that packet with the init's length: counted
    # malformed, and its own packet missing. Only such a late reply may be malformed here.
    late = (rep.get("missing") or 0) + (rep.get("unjudged") or 0)
    c.ok("%s: no malformed reply but a late one's (malformed %s, missing or unjudged %s)"
         % (label, rep.get("malformed"), late), (rep.get("malformed") or 0) <= late)
    c.eq("%s: server ended by 504 (exit 0)" % label, r.src, 0)
    c.eq("%s: server answered every packet it accepted" % label, r.jv("rx"), r.jv("tx"))
    c.eq("%s: no safety event" % label, (r.jv("drive_off_505"), r.jv("follow_error_508")), (0, 0))


def test_arm_mode4_sine_all_axes(srv):
    c = Checks()
    csv = srv.path("arm4.csv")
    r = srv.run_sim("arm4", srv.ports.udp(), "fixtures/scenarios/arm-mode4-sine.scn", ["--sine", "5,0.5,2"],
                    SIM_PATIENT + ARM + ["--csv", csv])
    protocol_clean(c, "arm mode 4 sine", r)
    fe = {}
    for row in csv_rows(csv):
        if row["rx_mode"] == "4":
            a = int(row["axis"])
            fe[a] = max(fe.get(a, 0.0), abs(float(row["rx_d1"]) - float(row["rx_d3"])))
    c.eq("every axis ran in mode 4", sorted(fe), [1, 2, 3, 4, 5, 6])
    for a in sorted(fe):
        # measured 0.015..0.018 turns on an idle host; a missing reply holds the reference a tick
        c.le("axis %d: largest |D1 - D3| in mode 4 [turns]" % a, fe[a], 0.1)
        c.le("axis %d: within the following-error limit" % a, fe[a], FOLLOW_ERROR)
    c.done((r.sim_late() > 0, "c4g-sim counted %d late replies" % r.sim_late()))


# the last two: mode 2 (the switching counter fades the controller's model out) and mode 9
# (the drives get the PC's D5 instead of the model: the loops take over gravity)
MODES = [(4, 0.45, ["--sine", "0.25,0.5,0.5"]), (5, 0.125, ["--sine", "0.25,0.5,0.5"]),
         (7, 1.1, ["--offset", "0.1,0.5,0.5"]), (8, -1, ["--vel", "0.0005,1,1"]),
         (2, 0.5, ["--gains", "30,200,300"]),
         (9, 0.5, ["--ff", "fixtures/server/ff_example.txt", "--duration", 1])]


@pytest.mark.parametrize("m,want,args", MODES, ids=["mode%d" % m[0] for m in MODES])
def test_arm_server_modes(srv, m, want, args):
    c = Checks()
    label = "arm mode %d" % m
    r = srv.run_sim("arm%d" % m, srv.ports.udp(), "fixtures/server/sim_mode%d.scn" % m, args, SIM_PATIENT + ARM)
    protocol_clean(c, label, r)
    c.near("%s: robot axis 1 at %s" % (label, want), r.pos(1) if r.sim else None, want, 0.05)
    c.done()


REFUSED = [
    (["--payload", "5"], "c4g-sim: --payload, --ctrl-payload, --ctrl-error and the INI [plant] keys apply to "
     "the arm plant: give --plant FILE (or [plant] file)"),
    (ARM + ["--open-axes", "5"], "c4g-sim: fixtures/sim/smart-six.xml: the arm plant moves axes 1..6 of arm 1: axis 6 "
     "is not open"),
    (["--plant", "fixtures/sim/no-such.xml"], "c4g-sim: fixtures/sim/no-such.xml: XML parse error 3: "
     "Error=XML_ERROR_FILE_NOT_FOUND"),
    (ARM + ["--payload", "5@1,2"], "c4g-sim: --payload: bad value '5@1,2' (centre '1,2' is not X,Y,Z (m, flange "
     "frame))"),
    (ARM + ["--ctrl-error", "9"], "c4g-sim: --ctrl-error: bad value '9' (not a factor 0..5)"),
]


@pytest.mark.parametrize("args,msg", REFUSED, ids=["payload-alone", "axes", "file", "payload-centre", "ctrl-error"])
def test_arm_refusals(procs, bins, args, msg):
    # refused before any datagram: nothing listens on the port
    r = run_sim(procs, bins, "-p", 9, "-n", 1, *args)
    assert r.returncode == 2, r.stderr
    assert msg in r.stderr, r.stderr
