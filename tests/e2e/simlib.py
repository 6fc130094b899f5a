# SPDX-License-Identifier: MIT
"""c4g-sim against the reference PC (tests/e2e/helpers/ref_pc.c), for test_sim_*.py."""
import json
import signal

from e2elib import udp_rx_queue, wait_until

# The reference PC is an ordinary process: a busy host can stop it for 100 ms (50 periods)
# while the simulator runs. Tests that are not about the 10-in-a-row rule pass STALL_OK, so
# such a stall is counted (missing) instead of ending the run with ERR_C4GOPEN_UDP; the rule
# itself is tested with the default in test_sim_replies.py and test_sim_num_policy.py.
STALL_OK = ["--max-miss", "500"]


def start_pc(procs, bins, port, *opts, idle_ms=1500):
    """The reference PC on 127.0.0.1:port; returns once its socket is bound (its
    "listening" line), so no datagram races its start-up."""
    pc = procs.start([bins.helper("ref_pc"), "-p", port, "--idle-ms", idle_ms, "--max-s", 50]
                     + list(opts), name="ref_%d" % port)
    wait_until(lambda: "ref_pc: listening" in pc.out() or not pc.running(), 30,
               "ref_pc listening on port %d" % port)
    assert "ref_pc: listening" in pc.out(), "ref_pc on port %d: %s" % (port, pc.out())
    return pc


def stop_pc(pc, port):
    """Ends the reference PC once it has read every datagram waiting for it (instead of its
    idle timeout) and returns its log, whose last line is its summary."""
    wait_until(lambda: udp_rx_queue(port) == 0 or not pc.running(), 10,
               "ref_pc on port %d to read its socket" % port)
    pc.signal(signal.SIGTERM)
    pc.wait(10)
    return pc.out()


def run_sim(procs, bins, *args, timeout=50):
    """c4g-sim on loopback, bounded in time: CompletedProcess."""
    return procs.run([bins.sim, "--bind", "127.0.0.1"] + [str(a) for a in args], timeout=timeout)


def json_line(text):
    """The JSON summary among a process's log lines (stdout and stderr together)."""
    for line in text.splitlines():
        if line.startswith("{"):
            return json.loads(line)
    raise AssertionError("no JSON summary in: %r" % text[-500:])


def sim_json(r):
    """The --json summary c4g-sim printed on stdout."""
    try:
        return json.loads(r.stdout)
    except ValueError:
        raise AssertionError("c4g-sim printed no JSON summary (exit %d): %r %r"
                             % (r.returncode, r.stdout[-500:], r.stderr[-500:])) from None
