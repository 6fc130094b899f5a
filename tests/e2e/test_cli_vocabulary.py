# SPDX-License-Identifier: MIT
"""The tools' shared vocabulary (docs/cli.md) against what each tool's --help says: a short
letter of the shared table means its one option in every tool and command, a shared option
is spelt with its short letter or none, and --num-policy offers only the shared words. A
deviation passes only when docs/cli.md lists it as an exception."""
import json
import re
import subprocess

import pytest

DOC = "docs/cli.md"
TOOLS = [("c4g-server", None), ("c4g-sim", None), ("cell-cli", None), ("cell-sim", None)] + \
    [("c4g-replay", c) for c in ("summary", "check", "export", "rerun", "live", "plot", "follow")] + \
    [("c4g-ident", c) for c in ("fit", "excite")]


def tables():
    """(shared rows: short -> long, long -> short; exceptions: set of (tool, command, short, long))"""
    text = open(DOC).read()
    shared, short_of, exc = {}, {}, set()
    part = 0
    for line in text.splitlines():
        if line.startswith("## "):
            part += 1
        if not line.startswith("|") or line.startswith("|---"):
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        if part == 1 and cells[0] != "short":
            short = cells[0].strip("`")
            long_ = cells[1].strip("`")
            if short:
                shared[short] = long_
            short_of[long_] = short
        elif part == 2 and cells[0] != "tool":
            opts = re.findall(r"`(-[A-Za-z0-9]|--[a-z0-9-]+)`", cells[1])
            short = next((o for o in opts if re.fullmatch(r"-[A-Za-z0-9]", o)), "")
            long_ = next((o for o in opts if o.startswith("--")), "")
            m = re.match(r"(\S+)\s*(.*)", cells[0])
            for cmd in [c.strip() for c in m.group(2).split(",")] if m.group(2) else [None]:
                exc.add((m.group(1), cmd, short, long_))
    return shared, short_of, exc


def help_options(build, tool, cmd):
    argv = [str(build / "bin" / tool)] + ([cmd] if cmd else []) + ["--help"]
    out = subprocess.run(argv, capture_output=True, text=True, timeout=30).stdout
    rows = re.findall(r"(?m)^ +(?:(-[A-Za-z0-9]), )?(--[a-z0-9-]+)(?: (\S+))?(.*)$", out)
    return [(s, l, a, rest) for s, l, a, rest in rows]


def excepted(exc, tool, cmd, short, long_):
    return any(t == tool and c in (cmd, None) and (s == short or not s) and l == long_
               for t, c, s, l in exc)


@pytest.mark.parametrize("tool,cmd", TOOLS, ids=["%s%s" % (t, "-" + c if c else "") for t, c in TOOLS])
def test_tool_follows_the_vocabulary(build, tool, cmd):
    shared, short_of, exc = tables()
    assert len(shared) >= 10 and len(exc) >= 10, "docs/cli.md tables not read"
    rows = help_options(build, tool, cmd)
    assert len(rows) >= 3, "%s %s: no options in --help" % (tool, cmd)
    bad = []
    for short, long_, arg, rest in rows:
        if short and short in shared and shared[short] != long_ and not excepted(exc, tool, cmd, short, long_):
            bad.append("%s means %s here, %s in the vocabulary" % (short, long_, shared[short]))
        want = short_of.get(long_)
        if short and want is not None and want != short and not excepted(exc, tool, cmd, short, long_):
            bad.append("%s is spelt %s here, %s in the vocabulary" % (long_, short, want or "without a letter"))
        if long_ == "--num-policy":
            words = set(re.findall(r"[a-z][a-z0-9-]*", rest)) & {"plus1", "plus-one", "echo", "either", "auto", "plusone"}
            odd = words - {"plus-one", "echo", "either", "auto"}
            if odd:
                bad.append("--num-policy offers %s" % sorted(odd))
    assert not bad, "%s%s: %s (docs/cli.md)" % (tool, " " + cmd if cmd else "", "; ".join(bad))


def test_exceptions_are_real(build):
    """every exception listed still exists: a fixed one leaves the table"""
    _, _, exc = tables()
    seen = set()
    for tool, cmd in TOOLS:
        for short, long_, _, _ in help_options(build, tool, cmd):
            seen.add((tool, cmd, short, long_))
    stale = [e for e in exc if not any(t == e[0] and (e[1] is None or c == e[1]) and l == e[3]
                                       and (not e[2] or s == e[2]) for t, c, s, l in seen)]
    assert not stale, "docs/cli.md lists exceptions no tool has any more: %s" % stale


def test_renamed_spellings(bins, ports, procs, tmp_path):
    """-c is --config in c4g-server too, and c4g-sim's open-axes counts are --open-axes; the
    old spellings still work for this release, with a one-line note, and --help hides them"""
    port = ports.udp()
    ini = tmp_path / "s.ini"
    ini.write_text("[server]\ncontroller = 127.0.0.3\nidle-timeout = 0.2\n")
    r = procs.run([bins.server, "-c", ini, "-p", port, "-b", "127.0.0.1"], timeout=30)
    assert r.returncode == 4 and "controller 127.0.0.3" in r.stderr, r.stderr  # the file was read
    assert "note" not in r.stderr, r.stderr
    r = procs.run([bins.server, "-c", "127.0.0.2", "-p", port, "-b", "127.0.0.1", "--idle-timeout", 0.2], timeout=30)
    assert r.returncode == 4 and "controller 127.0.0.2" in r.stderr, r.stderr
    notes = [l for l in r.stderr.splitlines() if "note" in l]
    assert notes == ["c4g-server: note: -c/--config 127.0.0.2: the controller's address is --controller "
                     "127.0.0.2 now (-c is --config FILE in every tool); taken as --controller until 3.0"], r.stderr
    out = procs.run([bins.server, "--help"]).stdout
    assert re.search(r"(?m)^  -c, --config FILE", out) and re.search(r"(?m)^      --controller ADDR", out), out
    r = procs.run([bins.sim, "-s", "127.0.0.1", "-p", ports.udp(), "--axes", "2", "--json", "-q"], timeout=30)
    assert json.loads(r.stdout)["axes"] == 2, r.stdout
    assert "--axes" in r.stderr and "--open-axes" in r.stderr, r.stderr
    r = procs.run([bins.sim, "-s", "127.0.0.1", "-p", ports.udp(), "--open-axes", "2", "--json", "-q"], timeout=30)
    assert json.loads(r.stdout)["axes"] == 2 and "--axes" not in r.stderr, r.stderr
    out = procs.run([bins.sim, "--help"]).stdout
    assert "--open-axes COUNTS" in out and not re.search(r"(?m)^ +--axes", out), out


def test_server_json_flag(bins, ports, procs, tmp_path):
    """c4g-server's --json is the flag of every tool (the summary on stdout); the file is
    --json-out FILE; the old --json FILE (and json = FILE in an INI file) still writes the
    file, with a one-line note"""
    args = [bins.server, "-p", ports.udp(), "-b", "127.0.0.1", "--idle-timeout", 0.2, "-q"]
    for flag in ("--json", "-j"):
        r = procs.run(args + [flag], timeout=30)
        assert r.returncode == 4 and json.loads(r.stdout)["exit_code"] == 4 and r.stderr == "", (flag, r.stdout, r.stderr)
    out = tmp_path / "new.json"
    r = procs.run(args + ["--json-out", out], timeout=30)
    assert r.returncode == 4 and json.loads(out.read_text())["exit_code"] == 4 and r.stderr == "", r.stderr
    note = ("c4g-server: note: --json FILE is --json-out FILE now (--json alone is the JSON summary on "
            "stdout, as in every tool); taken as --json-out until 3.0\n")
    for old in (["--json", tmp_path / "old.json"], ["--json=%s" % (tmp_path / "old.json")]):
        (tmp_path / "old.json").unlink(missing_ok=True)
        r = procs.run(args + old, timeout=30)
        assert r.returncode == 4 and r.stdout == "" and r.stderr == note, (old, r.stdout, r.stderr)
        assert json.loads((tmp_path / "old.json").read_text())["exit_code"] == 4
    ini = tmp_path / "s.ini"
    ini.write_text("[output]\njson = %s\n" % (tmp_path / "ini.json"))
    r = procs.run(args + ["--config", ini], timeout=30)
    assert r.returncode == 4 and "json = %s: the summary's file is json-out now" % (tmp_path / "ini.json") in r.stderr, r.stderr
    assert json.loads((tmp_path / "ini.json").read_text())["exit_code"] == 4
    out = procs.run([bins.server, "--help"]).stdout
    assert re.search(r"(?m)^  -j, --json +JSON summary", out) and "--json-out FILE" in out, out
