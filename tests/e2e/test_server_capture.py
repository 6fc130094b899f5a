# SPDX-License-Identifier: MIT
"""c4g-server --capture: the server's host loop and core over a recorded capture instead of
its socket, every reply compared with the recorded one; c4g-replay rerun is its front end
(c4g-server --replay-rerun) and prints the same report. The options of the capture refused
without it, an unreadable capture named, and the front end without c4g-server says so."""
import json
import os
import shutil

from e2elib import Checks

FX = "fixtures/replay/"


def test_capture_report_and_exit(procs, bins, tmp_path):
    c = Checks()
    r = procs.run([bins.server, "--capture", FX + "mode4.pcap", "--sine", "0.25,1,0.5"])
    c.eq("its own capture with the options it ran with: exit 0", r.returncode, 0)
    c.has("  ... the first line names the file and the options", r.stdout,
          r"^fixtures/replay/mode4\.pcap: behaviour server, c4g-server options: --capture "
          r"fixtures/replay/mode4\.pcap --sine 0\.25,1,0\.5$")
    c.has("  ... every reply equal", r.stdout, r"^verdict: 0 divergences in 403 replies")
    c.eq("  ... nothing on stderr", r.stderr, "")
    r = procs.run([bins.server, "--capture", FX + "mode4.pcap", "--sine", "0.3,1,0.5", "--json"])
    c.eq("another amplitude: exit 1", r.returncode, 1)
    d = json.loads(r.stdout) if r.returncode == 1 else {}
    f = d.get("first") or {}
    c.eq("  ... JSON on stdout, the tool named", d.get("tool"), "c4g-server --capture")
    c.eq("  ... the first divergence: D1 of arm 1 axis 1 at tick 114",
         (f.get("field"), f.get("arm"), f.get("axis"), f.get("tick")), ("d1", 1, 1, 114))
    out = tmp_path / "report.json"
    r = procs.run([bins.server, "--capture", FX + "mode4.pcap", "--sine", "0.3,1,0.5", "--json-out", out])
    c.eq("--json-out FILE: exit 1", r.returncode, 1)
    c.has("  ... the text report on stdout", r.stdout, r"^verdict: 250 of 403 replies diverge")
    c.eq("  ... the JSON report in the file", json.loads(out.read_text()).get("divergent") if out.exists() else None,
         250)
    r = procs.run([bins.server, "--capture", FX + "special-freeze-active.pcap", "--freeze", "120,100"])
    c.eq("active freezing over the controller's capture: exit 0", r.returncode, 0)
    c.has("  ... the packets queued during the pause dropped, the newest answered", r.stdout,
          r"\(48 dropped unanswered after an active-freezing pause\)")
    c.has("  ... no divergence", r.stdout, r"^verdict: 0 divergences in 263 replies")
    c.done()


def test_rerun_is_the_same_report(procs, bins):
    """c4g-replay rerun runs c4g-server --replay-rerun: the same figures, its own first line"""
    c = Checks()
    opts = ["--sine", "0.3,1,0.5"]
    a = procs.run([bins.server, "--capture", FX + "two-arms.pcap", "--list", "3"] + opts)
    b = procs.run([bins.replay, "rerun", "--list", "3", FX + "two-arms.pcap", "--"] + opts)
    c.eq("exit codes", (a.returncode, b.returncode), (1, 1))
    head = FX + "two-arms.pcap: behaviour server, c4g-server options:"
    c.eq("the divergences listed and the report but its options line",
         [l for l in a.stdout.split("\n") if not l.startswith(head)],
         [l for l in b.stdout.split("\n") if not l.startswith(head)])
    c.has("rerun's first line names only the options after --", b.stdout,
          r"^fixtures/replay/two-arms\.pcap: behaviour server, c4g-server options: --sine 0\.3,1,0\.5$")
    a = procs.run([bins.server, "--capture", FX + "two-controllers.pcap", "--session", "2", "--json"])
    b = procs.run([bins.replay, "rerun", "--json", "--session", "2", FX + "two-controllers.pcap"])
    ja, jb = json.loads(a.stdout or "{}"), json.loads(b.stdout or "{}")
    for k in ("tool", "server_options"):
        ja.pop(k, None)
        jb.pop(k, None)
    c.eq("--session 2 as JSON: exit 0 both, the same object but the tool and its options",
         (a.returncode, b.returncode, ja), (0, 0, jb))
    c.done()


def test_capture_refusals(procs, bins, tmp_path):
    c = Checks()
    r = procs.run([bins.server, "--tolerance", "0.5", "--sine", "0.2,1"])
    c.eq("a capture option without --capture: exit 2", r.returncode, 2)
    c.has("  ... named", r.stderr, r"--tolerance.*need --capture FILE")
    r = procs.run([bins.server, "--capture", FX + "no-such.pcap"])
    c.eq("an unreadable capture: exit 2", r.returncode, 2)
    c.has("  ... the file named", r.stderr, r"^c4g-server: fixtures/replay/no-such\.pcap: No such file")
    r = procs.run([bins.server, "--capture", FX + "bad/header-only.pcap"])
    c.eq("a capture without a controller packet: exit 2", r.returncode, 2)
    c.has("  ... said", r.stderr, r"header-only\.pcap: no controller packet to run$")
    r = procs.run([bins.server, "--capture", FX + "mode4.pcap", "--capture-ports", "0"])
    c.eq("a bad --capture-ports: exit 2", r.returncode, 2)
    c.has("  ... the value named", r.stderr, r"--capture-ports: bad value '0'")
    # the front end alone: no c4g-server beside it, none on PATH
    alone = tmp_path / "bin"
    alone.mkdir()
    shutil.copy(bins.replay, alone / "c4g-replay")
    r = procs.run([alone / "c4g-replay", "rerun", FX + "mode4.pcap"], env={"PATH": "/usr/bin:/bin"})
    c.eq("rerun without c4g-server: exit 1", r.returncode, 1)
    c.has("  ... said", r.stderr, r"^c4g-replay: rerun: cannot run c4g-server \(beside c4g-replay or on PATH\)")
    c.ok("  ... (no c4g-server on that PATH)", shutil.which("c4g-server", path="/usr/bin:/bin") is None)
    c.done()


def test_docs_examples(procs, bins):
    """docs/c4g-server.md: every console example prints what the page shows"""
    c = Checks()
    env = {"PATH": str(bins.server.parent) + os.pathsep + os.environ.get("PATH", "")}
    cmds, block = [], False
    for ln, line in enumerate(open("docs/c4g-server.md").read().split("\n"), 1):
        if line.startswith("```console"):
            block = True
        elif line.startswith("```") and block:
            block = False
        elif block and line.startswith("$ "):
            cmds.append((ln, line[2:], []))
        elif block and cmds:
            cmds[-1][2].append(line)
    c.ok("the page has examples", len(cmds) >= 2, len(cmds))
    for ln, cmd, want in cmds:
        r = procs.run(["sh", "-c", cmd], env=env)
        c.eq("docs/c4g-server.md:%d: %s" % (ln, cmd), r.stdout.rstrip("\n").split("\n"), want)
    c.done()
