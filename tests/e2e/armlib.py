# SPDX-License-Identifier: MIT
"""One captured session on c4g-sim's arm plant (fixtures/sim/smart-six.xml): a c4g-server
with the given options against a c4g-sim running a scenario, captured by c4g-sim. Shared by
the modules that record on the arm (test_ident_ctrl, test_ident_rigid, test_server_ff_rigid).
The fixture arm_recordings (registered by conftest.py) records each excitation of the six axes
once per e2e run, for every module that fits one."""
import json
import subprocess
import time

import pytest

PLANT = "fixtures/sim/smart-six.xml"


def arm_session(server, sim, port, out, name, scn, srv_opts=(), sim_config=None, max_seconds=60,
                json_out=False):
    """Run one session; c4g-sim must end with exit 0. Returns (pcap, the server's log, its
    --json-out summary or None). sim_config: c4g-sim's -c (None: its default axes, the ones
    tests/e2e/helpers/arm_exact writes)."""
    err = out / (name + ".srv.err")
    js = out / (name + ".json")
    args = [str(server), "-p", str(port), "--controller", "127.0.0.1", "--idle-timeout", "5",
            "--max-seconds", str(max_seconds)]
    if json_out:
        args += ["--json-out", str(js)]
    with open(err, "w") as e:
        srv = subprocess.Popen(args + [str(o) for o in srv_opts], stdout=subprocess.DEVNULL, stderr=e)
    try:
        end = time.monotonic() + 5
        while "listening on" not in err.read_text() and time.monotonic() < end:
            time.sleep(0.05)
        pcap = out / (name + ".pcap")
        cfg = ["-c", sim_config] if sim_config else []
        r = subprocess.run([str(sim), "-p", str(port)] + cfg + ["-S", "fixtures/scenarios/" + scn, "--max-miss",
                                                                "100000", "--pcap", str(pcap), "-q", "--plant", PLANT],
                           capture_output=True, text=True, timeout=max_seconds)
        assert r.returncode == 0, "c4g-sim %s: exit %d: %s" % (name, r.returncode, r.stderr[-2000:])
        srv.wait(timeout=15)
    finally:
        if srv.poll() is None:
            srv.kill()
            srv.wait()
    return pcap, err.read_text(), (json.loads(js.read_text()) if json_out else None)


# the six-axis excitations played in mode 4 on the decoupled-truth axes (fixtures/ident/
# sim-truth.ini): name -> (seed, vmax, amax, seconds). "fit": wide (the shoulder's gravity
# terms need its angle to travel); "val": another trajectory inside the first one's range.
EXCITATIONS = {"fit": (4, 60, 600, 30), "val": (7, 30, 300, 15)}


class ArmRecordings:
    """Each excitation's capture, recorded the first time a test asks for it (a failed
    recording fails every test that asks, with its reason, without recording again)."""

    def __init__(self, build, ports, tmp_path_factory):
        self.build, self.ports, self.out = build, ports, tmp_path_factory.mktemp("arm")
        self.done = {}

    def get(self, name):
        if name not in self.done:
            try:
                self.done[name] = (True, self._record(name))
            except Exception as e:  # noqa: BLE001 (every asking test fails with the reason)
                self.done[name] = (False, "%s: %s" % (type(e).__name__, e))
        good, value = self.done[name]
        assert good, "the arm recording %s failed: %s" % (name, value)
        return value

    def _record(self, name):
        seed, vmax, amax, seconds = EXCITATIONS[name]
        traj = self.out / (name + ".csv")
        subprocess.run([str(self.build / "bin" / "c4g-ident"), "excite", "--axes", "1,2,3,4,5,6", "--vmax", str(vmax),
                        "--amax", str(amax), "--duration", str(seconds), "--seed", str(seed), "-o", str(traj)],
                       check=True, capture_output=True, timeout=30)
        return arm_session(self.build / "bin" / "c4g-server", self.build / "bin" / "c4g-sim", self.ports.udp(), self.out,
                           name, "ident.scn", ["--traj", traj], "fixtures/ident/sim-truth.ini", max_seconds=90)[0]


@pytest.fixture(scope="session")
def arm_recordings(build, ports, tmp_path_factory):
    """ArmRecordings: arm_recordings.get("fit") or get("val"), the capture's path"""
    return ArmRecordings(build, ports, tmp_path_factory)
