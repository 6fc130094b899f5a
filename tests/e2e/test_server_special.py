# SPDX-License-Identifier: MIT
"""c4g-server end to end, special modes: 501 end detected, 505 and 508 from the PC drive
off, 504 ends both sides cleanly, 506 restarts with a new initialization packet, active
freezing survives a PC pause longer than 10 periods and passive freezing a controller
silence longer than the loss timeout. Controller: c4g-sim (and the test stub for a following
error the server detects itself)."""
from e2elib import Checks
from srvlib import num

IDLE = "fixtures/server/sim_idle.scn"


def errors(r):
    return [e.get("name") for e in r.sim.get("errors", [])]


def drives_off(r):
    return all(not a["drive_on"] for a in r.sim["robot"])


def test_501_and_504(srv):
    r = srv.run_sim("d501", srv.ports.udp(), IDLE)
    c = Checks()
    c.ge("501: server detected the end of the drive-on", r.jv("drive_on_end"), 1)
    c.eq("501: sim ok", r.simrc, 0)
    c.eq("504: server exit 0 after the controller's 504", r.src, 0)
    c.ok("504: server reason names 504", str(r.json.get("reason")).startswith("504"), r.json.get("reason"))
    c.eq("504: sim scenario ran to its EXIT OPEN (not aborted)", r.sim["scenario"]["aborted"], False)
    c.done()


def test_505_from_the_pc(srv):
    r = srv.run_sim("d505", srv.ports.udp(), IDLE, ["--inject", "505@400"], stop=True)
    c = Checks()
    c.ok("505: controller raised ERR_C4GOPEN_DRIVEOFF_SERVER", "ERR_C4GOPEN_DRIVEOFF_SERVER" in errors(r), errors(r))
    c.ok("505: robot drives off", drives_off(r), r.sim.get("robot"))
    c.ge("505: server counted its 505 replies", r.jv("drive_off_505"), 1)
    c.done()


def test_508_requested(srv):
    r = srv.run_sim("d508", srv.ports.udp(), IDLE, ["--inject", "508@400:1"], stop=True)
    c = Checks()
    c.ok("508: controller raised ERR_C4GOPEN_FOLLOW_ERROR", "ERR_C4GOPEN_FOLLOW_ERROR" in errors(r), errors(r))
    c.ok("508: robot drives off", drives_off(r), r.sim.get("robot"))
    c.ge("508: server counted its 508 replies", r.jv("follow_error_508"), 1)
    c.done()


def test_508_by_the_safety_filter(srv):
    r = srv.run_stub("fe", srv.ports.udp(), ["--fe", 0.05, "--fe-push-at", 100, "--script", "0:20,4:400,0:20,504:1"],
                     ["--sine", "0.1,0.5,1"])
    c = Checks()
    c.eq("508: the stub controller saw 508 and drove off", r.stub.get("err"), "ERR_C4GOPEN_FOLLOW_ERROR")
    c.eq("508: every other reply byte was right", num(r.stub.get("bad")), 0)
    c.ok("508: server logged the following error", str(r.jv("first")).startswith("following error"), r.jv("first"))
    c.done()


def test_506_restart(srv):
    r = srv.run_sim("r506", srv.ports.udp(), "fixtures/server/sim_restart.scn")
    c = Checks()
    c.eq("506: sim ok (init packet re-sent without sync packets)", r.simrc, 0)
    c.eq("506: server saw the restart", r.jv("restarts"), 1)
    c.eq("506: server accepted two init packets", r.jv("init"), 2)
    c.eq("506: server exit 0 at the final 504", r.src, 0)
    c.done()


def test_passive_freezing(srv):
    # 502 .. 503, 1 s = 500 periods of silence, loss timeout 500 ms
    r = srv.run_sim("pf", srv.ports.udp(), "fixtures/server/sim_freeze.scn", ["--lost-timeout-ms", 500])
    c = Checks()
    c.eq("passive: sim ok", r.simrc, 0)
    c.eq("passive: server saw 502", r.jv("passive_freezings"), 1)
    c.eq("passive: no lost controller", r.jv("lost"), 0)
    c.eq("passive: server exit 0", r.src, 0)
    c.done()


def test_active_freezing(srv):
    # 500, the PC pauses 150 ms = 75 periods, then EXIT_FROM_OPEN
    r = srv.run_sim("af", srv.ports.udp(), IDLE, ["--freeze", "300,150"])
    c = Checks()
    c.eq("active: sim ok, no ERR_C4GOPEN_UDP", r.simrc, 0)
    c.eq("active: no controller error", r.sim.get("errors"), [])
    c.eq("active: server paused once", r.jv("active_freezings"), 1)
    c.eq("active: server exit 0", r.src, 0)
    r = srv.run_stub("afs", srv.ports.udp(), ["--script", "0:600,504:1"], ["--freeze", "200,100"])
    c.eq("active (stub): controller resumed after EXIT_FROM_OPEN", num(r.stub.get("freeze_survived")), 1)
    c.eq("active (stub): no bad reply", num(r.stub.get("bad")), 0)
    c.done()
