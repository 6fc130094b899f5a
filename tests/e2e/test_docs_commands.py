# SPDX-License-Identifier: MIT
"""Every command block of README.md and docs/*.md runs as written.

The rules the pages follow (tests/README.md, "Docs that run", says them for writers):
- A command block is a fenced block marked sh, shell, bash or console, or an unmarked fenced
  or indented block whose first line starts with "$ " or with a command of this project
  (c4g-*, cell-*, build/bin/..., build/e2e/...) or one a page shows (make, cc, sh, tshark,
  sudo, export, pkg-config). In a block whose first line starts with "$ " only the "$ "
  lines are commands (with their continuation lines); the rest is the output shown.
- A command ends with status 0, or with N when its line ends with a comment "# exit N ...".
- A command that ends with "&" is started in the background (a server, a simulator); the
  runner waits until it has bound a socket and keeps it for the rest of the page. Each page
  runs in one shell, in a fresh directory where the repository's folders are linked (so
  fixtures/... and build/bin/... work), with build/bin first in PATH, HOME in that
  directory, and its own network namespace when the host allows one, so the pages' fixed
  ports collide with nothing.
- "make" lines are the build this run already has: counted, not run.
- A block that cannot run here (real hardware, root, minutes of running, an install) has
  the comment "<!-- not run: REASON -->" on the line before it; the runner counts it.
A failed command fails the test naming page:line, the command, its status and its output.
A live run (c4g-sim --capture, c4g-replay live) that exits 1 only for replies the loaded host
delayed, every reply equal to the recorded one, passes and is counted, as in
test_replay_live.py, and so does one whose own sender missed its schedule on 5 % of the
packets or more, and a c4g-sim run whose ERR_C4GOPEN_UDP came while the simulator overran
its own ticks (the PC's replies right); other failures whose output shows the host held
them up (late or stale replies, the simulator's own overruns) rerun the test once
(e2elib.host_disturbed).
"""
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import e2elib

ROOT = e2elib.ROOT
PAGES = ["README.md"] + sorted("docs/" + p.name for p in (ROOT / "docs").glob("*.md"))
RUN_LANGS = {"sh", "shell", "bash", "console"}
FIRST_WORDS = re.compile(r"^(?:\$ |(?:c4g-[a-z]+|cell-[a-z]+|build/(?:bin|e2e)/\S+|make|cc|sh|tshark|"
                         r"wireshark|sudo|export|pkg-config)(?:\s|$))")
NOT_RUN = re.compile(r"^\s*<!--\s*not run:\s*(.+?)\s*-->\s*$")
EXPECT = re.compile(r"#\s*exit\s+(\d+)\b")
# the repository's folders a page names, linked into each page's directory
LINKED = ["fixtures", "examples", "tools", "scripts", "docs", "include", "lib", "tests", "bench",
          "Makefile", "README.md", "LICENSE"]
CMD_TIMEOUT = 90
# figures of c4g-sim and c4g-replay live that show a loaded host (the controller end's count)
DISTURBED = re.compile(r"\b(\d+) (?:late|stale|unjudged)\b|\bown overruns (\d+)|\b(\d+) sent over \d+ us late|"
                       r"\"(?:late|stale|unjudged|overruns)\":(\d+)")


class Block:
    """A code block of a page: its first line's number, info string, lines, not-run reason."""

    def __init__(self, page, line, lang, lines, skip):
        self.page, self.line, self.lang, self.lines, self.skip = page, line, lang, lines, skip


def blocks(page):
    """The code blocks of a page, fenced or indented: each a Block with its first line's
    number, its info string, its lines and the reason it is not run (or None)."""
    text = (ROOT / page).read_text().split("\n")
    out = []
    i = 0
    prev_blank = True
    while i < len(text):
        line = text[i]
        m = re.match(r"^(\s*)(```|~~~)\s*(\S*)", line)
        if m:
            ind, fence = len(m.group(1)), m.group(2)
            j = i + 1
            while j < len(text) and not re.match(r"^\s*" + fence + r"\s*$", text[j]):
                j += 1
            body = [b[ind:] if b[:ind].strip() == "" else b for b in text[i + 1:j]]
            out.append(Block(page, i + 2, m.group(3), body, _reason(text, i)))
            i, prev_blank = j + 1, False
            continue
        m = re.match(r"^( {4,})\S", line)
        if m and prev_blank:
            ind = len(m.group(1))
            j = i
            while j < len(text) and (text[j].startswith(" " * ind) or
                                     (text[j].strip() == "" and j + 1 < len(text) and
                                      text[j + 1].startswith(" " * ind))):
                j += 1
            out.append(Block(page, i + 1, "", [b[ind:] for b in text[i:j]], _reason(text, i)))
            i, prev_blank = j, False
            continue
        prev_blank = line.strip() == ""
        i += 1
    return out


def _reason(text, i):
    """The not-run reason on the last non-blank line before line i, if any."""
    k = i - 1
    while k >= 0 and text[k].strip() == "":
        k -= 1
    m = NOT_RUN.match(text[k]) if k >= 0 else None
    return m.group(1) if m else None


def is_command_block(b):
    """Whether a block holds commands (the rules at the top of this file)."""
    first = next((s for s in b.lines if s.strip()), "")
    if b.lang:
        return b.lang in RUN_LANGS
    return bool(FIRST_WORDS.match(first))


def commands(b):
    """(line number, text, expected status) of each command of a block, continuation lines
    joined (a trailing backslash, or a line ending in a pipe or && / ||)."""
    prompt = next((s for s in b.lines if s.strip()), "").startswith("$ ")
    out = []
    i = 0
    while i < len(b.lines):
        s = b.lines[i]
        if prompt:
            if not s.startswith("$ "):
                i += 1
                continue
            s = s[2:]
        if not s.strip() or s.lstrip().startswith("#"):
            i += 1
            continue
        start = i
        parts = [s]
        while re.search(r"(\\|\||&&)\s*$", parts[-1]) and i + 1 < len(b.lines):
            i += 1
            parts.append(b.lines[i])
        text = "\n".join(parts)
        m = EXPECT.search(parts[-1])
        out.append((b.line + start, text, int(m.group(1)) if m else 0))
        i += 1
    return out


def _family(pid):
    """pid and its descendants (a background loop or pipeline runs the server as a child)."""
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        try:
            for t in os.listdir("/proc/%d/task" % p):
                todo += [int(c) for c in open("/proc/%d/task/%s/children" % (p, t)).read().split()]
        except OSError:
            pass
    return out


def _sockets_bound(pid):
    """The bound UDP and listening TCP sockets of process pid and its descendants (in its
    own network namespace: /proc/PID/net)."""
    try:
        inodes = set()
        for p in _family(pid):
            try:
                fds = os.listdir("/proc/%d/fd" % p)
            except OSError:
                continue
            for fd in fds:
                try:
                    t = os.readlink("/proc/%d/fd/%s" % (p, fd))
                except OSError:
                    continue
                if t.startswith("socket:["):
                    inodes.add(t[8:-1])
        bound = set()
        for name, want in (("udp", None), ("udp6", None), ("tcp", "0A"), ("tcp6", "0A")):
            try:
                rows = open("/proc/%d/net/%s" % (pid, name)).read().split("\n")[1:]
            except OSError:
                continue
            for r in rows:
                f = r.split()
                if len(f) > 9 and f[9] in inodes and (want is None or f[3] == want):
                    bound.add(f[9])
        return frozenset(bound)
    except OSError:
        return frozenset()


class Page:
    """One page's shell: a bash fed one command at a time, in its own directory."""

    def __init__(self, page, build, tmp):
        self.page = page
        self.dir = tmp / page.replace("/", "_").replace(".md", "")
        self.dir.mkdir(parents=True)
        for n in LINKED:
            os.symlink(ROOT / n, self.dir / n)
        os.symlink(build, self.dir / "build")
        self.ctl = self.dir / ".docrun"
        self.ctl.mkdir()
        self.log = self.ctl / "log"
        env = dict(os.environ, PATH="%s:%s" % (self.dir / "build" / "bin", os.environ["PATH"]),
                   HOME=str(self.dir), LC_ALL="C.UTF-8")
        sh = ["bash", "--norc", "--noprofile"]
        self.netns = have_netns()
        if self.netns:
            sh = ["unshare", "-rn", "bash", "--norc", "--noprofile", "-c",
                  "ip link set lo up 2>/dev/null || exit 9; exec bash --norc --noprofile"]
        self.logf = open(self.log, "ab")
        self.proc = subprocess.Popen(sh, stdin=subprocess.PIPE, stdout=self.logf, stderr=subprocess.STDOUT,
                                     cwd=self.dir, env=env, start_new_session=True)
        self.n = 0

    def run(self, text, timeout):
        """Runs one command; returns (status or None on timeout, its output)."""
        self.n += 1
        n = self.n
        (self.ctl / ("cmd%d" % n)).write_text(text + "\n")
        rc, pidf = self.ctl / ("rc%d" % n), self.ctl / ("pid%d" % n)
        start = self.log.stat().st_size
        bg = text.rstrip().endswith("&")
        self.proc.stdin.write((". .docrun/cmd%d </dev/null; echo $? > .docrun/rc%d.t; %s"
                               "mv .docrun/rc%d.t .docrun/rc%d\n" %
                               (n, n, ("echo $! > .docrun/pid%d; " % n) if bg else "", n, n)).encode())
        self.proc.stdin.flush()
        t_end = time.monotonic() + timeout
        while not rc.exists():
            if time.monotonic() > t_end or self.proc.poll() is not None:
                return None, self._out(start)
            time.sleep(0.02)
        status = int(rc.read_text())
        if bg and status == 0:
            pid = int(pidf.read_text())
            # a server is ready once it has bound its sockets: some, and no new one for
            # 0.3 s (cell-sim opens its CANopen shell after the bus booted); at most 10 s
            t_end = time.monotonic() + 10
            last, since = frozenset(), time.monotonic()
            while time.monotonic() < t_end and os.path.exists("/proc/%d" % pid):
                now = _sockets_bound(pid)
                if now != last:
                    last, since = now, time.monotonic()
                elif last and time.monotonic() - since >= 0.3:
                    break
                time.sleep(0.02)
        return status, self._out(start)

    def _out(self, start):
        self.logf.flush()
        with open(self.log, "rb") as f:
            f.seek(start)
            return f.read().decode(errors="replace")

    def close(self):
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.proc.wait()
        self.logf.close()


def have_netns():
    """True when this host lets us open a network namespace of our own (unshare -rn) and
    bring its loopback up."""
    return shutil.which("unshare") is not None and shutil.which("ip") is not None and subprocess.run(
        ["unshare", "-rn", "ip", "link", "set", "lo", "up"], capture_output=True).returncode == 0


def timing_findings_only(out):
    """A live run (c4g-sim --capture, c4g-replay live) whose only findings are replies a
    loaded host delayed: exit 1 with every reply equal to the recorded one, as
    tests/e2e/test_replay_live.py accepts it; or a c4g-sim run that raised ERR_C4GOPEN_UDP
    only while it overran its own ticks."""
    # a simulated controller's run: ERR_C4GOPEN_UDP raised while the simulator itself stalled
    # (its own overruns), the PC answering correctly all the while (text or --json summary)
    m = re.search(r"(?m)^\{\"tool\":\"c4g-sim\".*\"result\":\"error\".*\}$", out)
    if m:
        j = json.loads(m.group(0))
        r = j.get("replies", {})
        return (r.get("ok", 0) > 0 and r.get("wrong_num") == 0 and r.get("malformed") == 0 and
                j.get("overruns", 0) > 0 and {e.get("name") for e in j.get("errors", [])} == {"ERR_C4GOPEN_UDP"})
    m = re.search(r"(?m)^  replies ok (\d+), missing \d+, late \d+, unjudged \d+, wrong NUM (\d+), malformed (\d+)", out)
    if m and re.search(r"(?m)^c4g-sim .*: error \(exit 1\)$", out):
        o = re.search(r"(?m)^  own overruns (\d+)", out)
        errs = re.findall(r"(?m)^  error at tick \d+: (\S+):", out)
        return (int(m.group(1)) > 0 and m.group(2) == m.group(3) == "0" and bool(o) and int(o.group(1)) > 0
                and set(errs) == {"ERR_C4GOPEN_UDP"})
    if sender_stalled(out):
        return True
    m = re.search(r"(?m)^\{.*\"result\":\"findings\".*\}$", out)
    if m:
        j = json.loads(m.group(0))
        r, d = j.get("replies", {}), j.get("divergences", {}).get("differing")
    else:
        m = re.search(r"(?m)^replies \(.*\): (.*)$", out)
        d = re.search(r"(?m)^divergences: (\d+) of ", out)
        if not (m and d and re.search(r"(?m)^result: FINDINGS: ", out)):
            return False
        r = {k.replace(" ", "_").lower(): int(n) for n, k in re.findall(r"(\d+) ([a-z]+(?: NUM)?)", m.group(1))}
        d = int(d.group(1))
    # every reply came (a late one counts as stale where the next tick found it missing)
    return (d == 0 and r.get("wrong_num") == 0 and r.get("malformed") == 0 and
            r.get("missing", 1) + r.get("unjudged", 1) - r.get("stale", 0) <= 0)


def sender_stalled(out):
    """A live run whose own sender missed its schedule by more than 500 us on at least 5 % of
    the packets (a quiet host: well under 1 %): the host, not the PC, made its findings, and
    its verdict is no measurement (test_replay_live.py judges the replies under load)."""
    m = re.search(r"(?m)^\{.*\"result\":\"findings\".*\}$", out)
    if m:
        j = json.loads(m.group(0))
        sent, late = j.get("packets", {}).get("sent", 0), j.get("timing", {}).get("overruns", 0)
    else:
        a = re.search(r"(?m)^sent: (\d+) packets", out)
        b = re.search(r"(?m)^timing: .*; (\d+) sent over \d+ us late", out)
        if not (a and b and re.search(r"(?m)^result: FINDINGS: ", out)):
            return False
        sent, late = int(a.group(1)), int(b.group(1))
    return sent > 0 and late * 20 >= sent


def run_page(page, build, tmp):
    """Runs a page's command blocks; returns (counts, failures)."""
    cnt = {"blocks": 0, "commands": 0, "not_run": [], "make": 0, "timing": [], "t0": time.monotonic()}
    fails = []
    todo = [b for b in blocks(page) if is_command_block(b)]
    if not todo:
        return cnt, fails
    sh = Page(page, build, tmp)
    try:
        for b in todo:
            if b.skip:
                cnt["not_run"].append("%s:%d: %s" % (page, b.line, b.skip))
                continue
            cnt["blocks"] += 1
            for line, text, want in commands(b):
                if re.match(r"^\s*make(\s|$)", text):
                    cnt["make"] += 1
                    continue
                cnt["commands"] += 1
                got, out = sh.run(text, CMD_TIMEOUT)
                if got == 1 and want == 0 and timing_findings_only(out):
                    cnt["timing"].append("%s:%d" % (page, line))
                    continue
                if got != want:
                    fails.append(("%s:%d: %s\n  %s (expected %d)%s\n%s" % (
                        page, line, text, ("the page's shell ended" if sh.proc.poll() is not None else
                                           "did not end in %d s" % CMD_TIMEOUT) if got is None else "exit %d" % got,
                        want, "" if sh.netns else " (no network namespace here)",
                        "\n".join("  | " + s for s in out.rstrip().split("\n")[-25:])), out))
                    return cnt, fails  # the page's later commands build on this one
    finally:
        sh.close()
        cnt["seconds"] = time.monotonic() - cnt["t0"]
    return cnt, fails


def test_docs_commands(build, tmp_path, capsys):
    t0 = time.monotonic()
    # three pages at a time, each in its own network namespace (the ident loop mostly waits),
    # the longest first (c4g-ident.md's loop records 20 s of excitation); without namespaces
    # one at a time, as the pages share ports
    pages = sorted(PAGES, key=lambda p: p != "docs/c4g-ident.md")
    with ThreadPoolExecutor(max_workers=3 if have_netns() else 1) as ex:
        res = list(ex.map(lambda p: (p, run_page(p, build, tmp_path)), pages))
    total = {"blocks": 0, "commands": 0, "make": 0}
    not_run, fails, timing = [], [], []
    for _, (cnt, f) in res:
        for k in total:
            total[k] += cnt[k]
        not_run += cnt["not_run"]
        timing += cnt["timing"]
        fails += f
    with capsys.disabled():
        sys.stdout.write("\ndocs-commands: %d pages, %d blocks run (%d commands, %d make lines counted), "
                         "%d blocks not run, %.0f s\n" % (len(PAGES), total["blocks"], total["commands"],
                                                          total["make"], len(not_run), time.monotonic() - t0))
        for page, (cnt, _) in res:
            if cnt["commands"]:
                sys.stdout.write("  %-22s %2d commands %5.1f s\n" % (page, cnt["commands"], cnt["seconds"]))
        for s in not_run:
            sys.stdout.write("  not run: %s\n" % s)
        for s in timing:
            sys.stdout.write("  exit 1 accepted: %s: the loaded host delayed replies (none wrong) or held up "
                             "the controller end's own sending\n" % s)
    # a run the host held up says so in its own figures (replies the controller end counted
    # late or stale, the simulator's own overruns): one more run, with that evidence
    evidence = []
    for msg, out in fails:
        seen = [m.group(0) for m in DISTURBED.finditer(out) if int(next(g for g in m.groups() if g)) > 0]
        if seen:
            evidence.append("%s: %s" % (msg.split("\n")[0], ", ".join(seen)))
    e2elib.host_disturbed(fails and len(evidence) == len(fails), "; ".join(evidence))
    assert not fails, "%d command(s) of the docs failed:\n%s" % (len(fails), "\n".join(m for m, _ in fails))


def test_docs_code_names_declared_functions():
    """The C and pseudo-code blocks (README's loop, rt-integration.md's, modes.md's, canopen.md's)
    call only functions the public headers declare, so a renamed or removed function cannot
    stay in a page; and the README's loop reaches the engine through the loop object's
    accessor, as examples/mode4_loop.c does, not through the struct's members."""
    headers = "\n".join(p.read_text() for p in (ROOT / "include").glob("*.h"))
    missing = []
    for page in PAGES:
        for b in blocks(page):
            if b.lang not in ("", "c") or is_command_block(b):
                continue
            for k, s in enumerate(b.lines):
                for name in re.findall(r"\b(c4g_[a-z0-9_]+)\s*\(", s):
                    if not re.search(r"\b%s\s*\(" % name, headers):
                        missing.append("%s:%d: %s" % (page, b.line + k, name))
    assert not missing, "functions no public header declares:\n" + "\n".join(missing)
    loop = re.search(r"(?s)```c\n(.*?)```", (ROOT / "README.md").read_text()).group(1)
    assert "c4g_loop_engine(" in loop and "&lp.engine" not in loop, loop
