# SPDX-License-Identifier: MIT
"""c4g-server: command line, INI file, input files, exit codes, real-time refusals and the
pcap / moni / JSON outputs. Bad input never crashes the server: it names what was wrong."""
import re
import shutil
import signal

import pytest

from e2elib import Checks, ROOT
from srvlib import num


def test_help_version_bad_options(srv, procs, bins):
    c = Checks()
    r = procs.run([bins.server, "--help"])
    c.eq("--help exit 0", r.returncode, 0)
    c.has("--help documents exit codes", r.stdout + r.stderr, "Exit codes")
    c.has("--help has examples", r.stdout + r.stderr, "Examples")
    # (the shell test read include/c4gopen.h, which no longer defines it: an empty pattern
    # that matched anything)
    ver = re.search(r'^#define C4G_VERSION_STRING "(.*)"', (ROOT / "include" / "c4gopen_base.h").read_text(),
                    re.M).group(1)
    c.has("--version names the library version", procs.run([bins.server, "--version"]).stdout,
          r"\(libc4gopen %s[,)]" % re.escape(ver))
    r = procs.run([bins.server, "--bogus"])
    c.eq("unknown option: exit 2", r.returncode, 2)
    c.has("unknown option named", r.stderr, "'--bogus'")
    r = procs.run([bins.server, "--sine", "1"])
    c.eq("bad value: exit 2", r.returncode, 2)
    c.has("bad value names option and value", r.stderr, "sine: bad value '1'")
    r = procs.run([bins.server, "--arm", "7", "--sine", "1,1"])
    c.eq("bad arm: exit 2", r.returncode, 2)
    r = procs.run([bins.server, "-c", "300.1.1.1", "-p", srv.ports.udp()])
    c.eq("bad controller address: exit 2", r.returncode, 2)
    c.has("bad controller address named", r.stderr, r"300\.1\.1\.1")
    c.done()


# (what, file name, content, option, exit code or None, the message (a regular expression));
# a file of None: the option takes the name as it is
FILES = [
    ("bad trajectory", "bad.csv", "t,ax1\n0,0\n0.5,abc\n", "--traj", 2,
     r"bad\.csv:3:5: column 2 \(axis offset \[turns\]\): 'abc' is not a decimal number"),
    ("non-increasing time", "bad2.csv", "t,ax1\n0,0\n0,1\n", "--traj", None, r"bad2\.csv:3:1: column 1 \(t \[s\]\)"),
    ("bad feedforward file", "bad.ff", "1 11 0.5\n", "--ff", 2,
     r"bad\.ff:1:3: field 2 \(axis\): '11' is out of range 1\.\.10"),
    ("missing file", "nonexistent.csv", None, "--traj", None, r"nonexistent\.csv: cannot open"),
    ("bad INI key", "bad.ini", "[server]\nport = 31051\nbogus-key = 3\n", "--config", 2,
     r"bad\.ini:3:1: \[server\] unknown setting 'bogus-key'"),
    ("bad INI section", "bad2.ini", "[arm9]\nsine = 1,1\n", "--config", 2, ""),
    # files users write: out-of-range numbers and endless input are refused at load
    ("trajectory 1e39", "big.csv", "t,ax1\n0,0\n1,1e39\n", "--traj", 2,
     r"big\.csv:3:3: column 2 \(axis offset \[turns\]\): '1e39' is out of range -1000000\.\.1000000"),
    ("feedforward 1e30", "big.ff", "1 1 1e30\n", "--ff", None,
     r"big\.ff:1:5: field 3 \(c0\): '1e30' is out of range -1000000\.\.1000000"),
    ("INI 1e300", "big.ini", "[server]\nport = 31051\n  idle-timeout = 1e300\n", "--config", 2,
     r"big\.ini:3:18: \[server\] idle-timeout: '1e300' is out of range"),
]


@pytest.mark.parametrize("what,name,content,opt,rc,pattern", FILES, ids=[f[0] for f in FILES])
def test_bad_input_file(procs, bins, tmp_path, what, name, content, opt, rc, pattern):
    path = tmp_path / name
    if content is not None:
        path.write_text(content)
    r = procs.run([bins.server, opt, path])
    # every refused file: exit 2 (the shell test asserted the code for some, the message
    # for the others)
    assert r.returncode == (rc if rc is not None else 2), "%s: exit %d: %s" % (what, r.returncode, r.stderr)
    assert re.search(pattern, r.stderr), "%s: %r not in %s" % (what, pattern, r.stderr)


def ident_copy(tmp_path, name, old, new):
    text = (ROOT / "fixtures/server/ff_ident_example.ini").read_text()
    assert re.search("^" + re.escape(old) + "$", text, re.M), old
    (tmp_path / name).write_text(re.sub("^" + re.escape(old) + "$", new, text, flags=re.M))
    return tmp_path / name


def test_ident_model_files(procs, bins, tmp_path):
    # c4g-ident's parameter files: an edited copy, a bad value, two files for one arm
    c = Checks()
    r = procs.run([bins.server, "--ff", ident_copy(tmp_path, "edited.ini", "gb = 7.5", "gb = 8.5")])
    c.eq("edited model file: exit 2", r.returncode, 2)
    c.has("edited model file: checksum mismatch named", r.stderr,
          r"edited\.ini:17:12: \[model\] checksum: checksum mismatch: the file was edited after c4g-ident wrote it")
    r = procs.run([bins.server, "--ff", ident_copy(tmp_path, "nan.ini", "Ja = 0.00314159", "Ja = nan")])
    c.eq("model file with NaN: exit 2", r.returncode, 2)
    c.has("model file with NaN: file, line, section, key", r.stderr, r"nan\.ini:21:6: \[axis 1\] Ja: 'nan' is not a finite number")
    r = procs.run([bins.server, "--ff", "fixtures/server/ff_ident_example.ini", "--ff", "fixtures/server/ff_example.txt"])
    c.eq("two files for arm 1: exit 2", r.returncode, 2)
    c.has("two files for arm 1: both named", r.stderr,
          r"ff_example\.txt:15:1: arm 1 axis 1 is already set by fixtures/server/ff_ident_example\.ini:19")
    c.done()


@pytest.mark.parametrize("opt", ["--traj", "--ff", "--config"])
def test_dev_zero_refused(procs, bins, opt):
    r = procs.run([bins.server, opt, "/dev/zero"], timeout=20)
    assert r.returncode == 2, "%s /dev/zero refused (not hung): exit %d" % (opt, r.returncode)
    assert "/dev/zero: more than" in r.stderr, "%s /dev/zero: the limit named: %s" % (opt, r.stderr)


def test_ini_idle_port_in_use_rt(srv, procs, bins):
    c = Checks()
    p = srv.ports.udp()
    r = procs.run([bins.server, "--config", "fixtures/server/server_example.ini", "-p", p, "--idle-timeout", 0.3])
    c.eq("example INI loads; idle timeout: exit 4", r.returncode, 4)
    c.has("listening on the overridden port", r.stderr, r"0\.0\.0\.0:%d" % p)
    p = srv.ports.udp()
    h = srv.start_server("busy", p)
    r = procs.run([bins.server, "-p", p, "--controller", "127.0.0.1", "--idle-timeout", 0.3])
    c.eq("port in use: exit 1", r.returncode, 1)
    c.has("port in use: bind error named", r.stderr, r"bind 0\.0\.0\.0:%d" % p)
    h.signal(signal.SIGTERM)
    r = procs.run([bins.server, "-p", srv.ports.udp(), "--controller", "127.0.0.1", "--cpu", 999, "--idle-timeout", 0.3])
    c.eq("refused RT setting: says what and why, continues (idle exit 4)", r.returncode, 4)
    c.has("refused RT setting named", r.stderr, "CPU affinity to CPU 999 refused")
    r = procs.run([bins.server, "-p", srv.ports.udp(), "--controller", "127.0.0.1", "--cpu", 999, "--rt-strict",
                   "--idle-timeout", 0.3])
    c.eq("--rt-strict: refused RT setting is fatal (exit 1)", r.returncode, 1)
    c.done()


def test_outputs(srv, procs):
    pcap, moni = srv.path("out.pcap"), srv.path("out.csv")
    r = srv.run_stub("out", srv.ports.udp(), ["--script", "0:100,4:exit,0:50,504:1"],
                     ["--pcap", pcap, "--moni", moni, "--moni-type", 21, "--sine", "0.1,1,1"])
    c = Checks()
    c.eq("session ok", num(r.stub.get("bad")), 0)
    c.eq("pcap written (pcap magic)", pcap.read_bytes()[:4].hex(), "d4c3b2a1")
    tshark = shutil.which("tshark")
    if tshark:
        t = procs.run([tshark, "-r", pcap, "-T", "fields", "-e", "udp.payload"])
        n = sum(1 for l in t.stdout.splitlines() if l)
        c.eq("tshark reads every datagram in and out", n, r.jv("rx") + r.jv("tx"))
    text = moni.read_text()
    c.has("moni type 21 header", text, "moni type 21")
    c.eq("moni rows: one per axis per cyclic packet", sum(1 for l in text.splitlines() if l[:1].isdigit()),
         r.jv("cyclic") * 6)
    c.eq("JSON summary has timing, counters, safety",
         [k for k in r.json if k in ("timing", "counters", "safety")], ["timing", "counters", "safety"])
    c.done()


def test_sigint(srv):
    h = srv.start_server("sig", srv.ports.udp())
    h.signal(signal.SIGINT)
    from srvlib import Run
    r = srv.wait_server(h, Run("sig"))
    c = Checks()
    c.eq("SIGINT: exit 130", r.src, 130)
    c.has("SIGINT: report printed", r.log, r"stopped by SIGINT \(exit code 130\)")
    c.done()
