# SPDX-License-Identifier: MIT
"""The conventions every tool shares (lib/host/c4gh_cli.c): a bad option is exit 2 and
exactly one line on stderr; an output file that cannot be written fails at start-up, before
any session, with the tool's documented exit code, naming the path once with the system's
reason; bytes that are not printable are shown escaped; c4g-sim's progress line on a terminal;
the per-tick CSV shared by c4g-sim, c4g-server --moni, c4g-replay export --ticks and c4g-ident."""
import os
import pty
import re
import select
import subprocess
import time

import pytest

from e2e_extra import Checks
from e2elib import udp_bound, wait_until

TOOLS = ["c4g-server", "c4g-sim", "c4g-replay", "c4g-ident", "cell-cli", "cell-sim"]
COMMANDS = [("c4g-replay", c) for c in ("summary", "check", "export", "rerun", "live", "plot")] + \
    [("c4g-ident", c) for c in ("fit", "excite")]


@pytest.mark.parametrize("tool,cmd", [(t, None) for t in TOOLS] + COMMANDS)
def test_bad_option(build, procs, tool, cmd):
    """--bogus and -Z: exit 2, one line, the shared wording, nothing on stdout"""
    name = tool + (" " + cmd if cmd else "")
    # c4g-replay's commands keep the tool's name in messages; c4g-ident's carry the command
    who = tool if tool == "c4g-replay" else name
    ck = Checks()
    for opt in ("--bogus", "-Z"):
        r = procs.run([build / "bin" / tool] + ([cmd] if cmd else []) + [opt])
        want = "%s: unrecognized option '%s' (see %s --help)" % (who, opt, name)
        ck.ok("%s %s: exit 2, one line" % (name, opt),
              r.returncode == 2 and r.stderr == want + "\n" and r.stdout == "", (r.returncode, r.stderr, r.stdout))
    ck.done()


def test_missing_value(bins, procs):
    r = procs.run([bins.server, "--json-out"])
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and \
        "option '--json-out' needs a value (see c4g-server --help)" in r.stderr, (r.returncode, r.stderr)


def out_fail(ck, procs, want, opt, path, args):
    """fails fast, one line "OPTION PATH: reason" (the path once), and no session ran (nothing
    on stdout, well before the run's length)"""
    t0 = time.monotonic()
    r = procs.run(args, timeout=20)
    took = time.monotonic() - t0
    shown = path.replace("\x01", "\\x01")
    ck.ok("%s %s %s: exit %d at start-up" % (os.path.basename(str(args[0])), opt, shown, want),
          r.returncode == want and r.stderr.count(shown) == 1 and (opt + " " + shown + ": ") in r.stderr
          and took < 4 and not re.search("session ended|Summary", r.stdout),
          "exit %d after %.1f s: %s" % (r.returncode, took, r.stderr))
    return r


def test_output_files(bins, procs, ports, tmp_path):
    ck = Checks()
    srv = [bins.server, "--controller", "127.0.0.1", "--idle-timeout", "6"]
    out_fail(ck, procs, 1, "--json-out", "/nonexistent/x.json", srv + ["-p", ports.udp(), "--json-out", "/nonexistent/x.json"])
    out_fail(ck, procs, 1, "--pcap", "/x/y.pcap", srv + ["-p", ports.udp(), "--pcap", "/x/y.pcap"])
    out_fail(ck, procs, 1, "--moni", str(tmp_path), srv + ["-p", ports.udp(), "--moni", tmp_path])
    out_fail(ck, procs, 1, "--log", "/x/y.log", srv + ["-p", ports.udp(), "--log", "/x/y.log"])
    ro = tmp_path / "ro.json"
    ro.touch()
    ro.chmod(0o444)
    if os.getuid() != 0:
        out_fail(ck, procs, 1, "--json-out", str(ro), srv + ["-p", ports.udp(), "--json-out", ro])
    ctl = "/no\x01where/x.json"
    r = out_fail(ck, procs, 1, "--json-out", ctl, srv + ["-p", ports.udp(), "--json-out", ctl])
    ck.ok("unprintable byte escaped", "no\\x01where" in r.stderr, r.stderr)
    # bytes of a bad input file are escaped too
    bad = tmp_path / "ctl.csv"
    bad.write_bytes(b"garb\x01age\n")
    r = procs.run([bins.ident, "fit", bad])
    ck.ok("c4g-ident: a bad file's bytes escaped, exit 2",
          r.returncode == 2 and re.search(r"ctl\.csv:1: .*header 'garb\\x01age'", r.stderr), (r.returncode, r.stderr))
    out_fail(ck, procs, 4, "--csv", "/x/y.csv", [bins.sim, "-p", ports.udp(), "-n", "3000", "--csv", "/x/y.csv"])
    out_fail(ck, procs, 4, "--pcap", "/x/y.pcap", [bins.sim, "-p", ports.udp(), "-n", "3000", "--pcap", "/x/y.pcap"])
    out_fail(ck, procs, 1, "--out", "/x/y.png",
             [bins.replay, "plot", "--out", "/x/y.png", "fixtures/replay/mode4.pcap"])
    out_fail(ck, procs, 1, "--out", "/x/arm1.ini", [bins.ident, "fit", "-o", "/x/arm1.ini", "fixtures/replay/mode4.pcap"])
    out_fail(ck, procs, 1, "--plot", "/x/plots", [bins.ident, "fit", "--plot", "/x/plots", "fixtures/replay/mode4.pcap"])
    out_fail(ck, procs, 1, "--out", "/x/e.csv", [bins.ident, "excite", "-o", "/x/e.csv"])
    # an input file: the system's reason, the path once
    r = procs.run([bins.cell_cli, "-c", "/nonexistent.ini", "robot", "sta"])
    ck.ok("cell-cli -c missing: exit 2, the reason, the path once",
          r.returncode == 2 and re.search("/nonexistent.ini: .*No such file or directory", r.stderr)
          and r.stderr.count("/nonexistent.ini") == 1, (r.returncode, r.stderr))
    ck.done()


def progress_checks(ck, sim, port):
    """c4g-sim's progress line: shown on stderr when stderr is a terminal (a pty here), erased
    before the summary; absent when stderr is a file."""
    args = [str(sim), "-p", str(port), "-n", "1200", "--max-miss", "500"]
    pid, fd = pty.fork()
    if pid == 0:
        os.execv(args[0], args)
    out = b""
    end = time.monotonic() + 30
    while time.monotonic() < end:
        r, _, _ = select.select([fd], [], [], 0.1)
        if r:
            try:
                data = os.read(fd, 4096)
            except OSError:
                break
            if not data:
                break
            out += data
    os.waitpid(pid, 0)
    os.close(fd)
    text = out.decode(errors="replace")
    ck.ok("a progress line on a terminal", "\rc4g-sim: tick " in text and " of 1200 (" in text, repr(text[:300]))
    if ck.ok("the progress line is erased", "\r\x1b[K" in text):
        summary = text.rsplit("\r\x1b[K", 1)[1]
        ck.ok("the summary on a clean line",
              summary.lstrip().startswith("c4g-sim ") and "tick " not in summary.split("\n")[0], repr(summary[:200]))
    piped = subprocess.run(args, capture_output=True, text=True, timeout=30)
    ck.ok("no progress written to a file", not ("tick " in piped.stderr and " of 1200" in piped.stderr),
          repr(piped.stderr[:200]))


def test_progress_and_tick_csv(bins, procs, ports, tmp_path):
    ck = Checks()
    port = ports.udp()
    procs.start([bins.server, "-p", port, "--controller", "127.0.0.1", "-q", "--persist", "--idle-timeout", "60"], name="server")
    wait_until(lambda: udp_bound(port), 30, "c4g-server bound to %d" % port)
    progress_checks(ck, bins.sim, port)
    # the per-tick CSV (docs/csv.md): c4g-sim --csv has c4g-server --moni's columns first,
    # and c4g-ident reads it
    csv = tmp_path / "sim.csv"
    r = procs.run([bins.sim, "-p", port, "-n", "300", "--max-miss", "500", "--csv", csv, "-q"])
    lines = csv.read_text().splitlines()
    ck.eq("c4g-sim --csv: the per-tick header", lines[0] if lines else "",
          "t_s,num,axis,arm,logical,rx_mode,rx_d1,rx_d2,rx_d3,rx_d4,rx_d5,rx_e1,rx_e2,rx_e3,tx_infpar,tx_mode,"
          "tx_d1,tx_d2,tx_d3,tx_d4,tx_d5,tick,sent,reply_ok,rx_infpar,rx_cmd")
    ck.eq("c4g-sim --csv: exit, 300 ticks x 6 axes rows", (r.returncode, len(lines) - 1), (0, 1800))
    r = procs.run([bins.ident, "fit", csv])
    ck.ok("c4g-ident reads c4g-sim's per-tick CSV", r.returncode != 2 and
          "moni CSV, 300 controller ticks" in r.stdout + r.stderr, (r.returncode, (r.stdout + r.stderr)[:300]))
    ticks = tmp_path / "ticks.csv"
    r = procs.run([bins.replay, "export", "--ticks", "fixtures/replay/mode4.pcap"])
    ticks.write_text(r.stdout)
    head = r.stdout.split("\n", 1)[0]
    ck.eq("c4g-replay export --ticks: exit, the same header", (r.returncode, head),
          (0, re.sub(",tick,sent,reply_ok,rx_infpar,rx_cmd$", "", lines[0] if lines else "")))
    r = procs.run([bins.ident, "fit", ticks])
    ck.ok("c4g-ident reads export --ticks", r.returncode != 2 and "moni CSV" in r.stdout + r.stderr,
          (r.returncode, (r.stdout + r.stderr)[:300]))
    ck.done()
