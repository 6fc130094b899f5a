# SPDX-License-Identifier: MIT
"""One captured session on c4g-sim's arm plant (fixtures/sim/smart-six.xml): a c4g-server
with the given options against a c4g-sim running a scenario, captured by c4g-sim. Shared by
the modules that record on the arm (test_ident_ctrl, test_ident_rigid, test_server_ff_rigid)."""
import json
import subprocess
import time

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
