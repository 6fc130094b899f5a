# SPDX-License-Identifier: MIT
"""c4g-replay on real captures (the live command has its own test, test_replay_live.py):
 1. every fixture in fixtures/replay against its golden summary (fixtures/replay/golden), the
    key facts fixtures/replay/README.md states, and check's exit status per fixture;
 2. the independent oracle: the payloads the reader extracts equal tshark's udp.payload,
    frame by frame, on every fixture and every hostile file;
 3. hostile files: the exit status and a message naming the file, the packet and its byte
    offset; never a crash (an exit status above 128);
 4. a real tcpdump capture on lo of a c4g-sim + c4g-server session, and one with -i any
    (Linux cooked SLL2), read back; the first converted to pcapng by editcap gives the same
    sessions; c4g-server --pcap against the wire with the server stopped 60 ms mid-run;
 5. rerun: 0 divergences on c4g-server's own captures with the options they were made with;
    another amplitude or gain gives the first divergent field where it must be;
 6. export (CSV, moni rows, JSON lines) and plot (PNG, SVG, text) on a fixture;
 7. the field-made captures (fixtures/replay/field): every verdict; the examples of
    docs/c4g-replay.md print what the page shows."""
import difflib
import functools
import glob
import json
import os
import re
import shutil
import signal
import struct
import subprocess
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from e2elib import host_disturbed, read_json, wait_until

FX = "fixtures/replay"


FAILS = []


def fail(msg):
    FAILS.append(msg)
    print("FAIL: " + msg)


def tshark_payloads(path):
    """{frame number: payload hex} of every UDP datagram tshark reads in path"""
    return _tshark_fields(path)[None]


def _tshark_fields(path, by_interface=False):
    """tshark's udp.payload per frame; by_interface: {interface id: {frame: payload}}, frames
    numbered from each interface's first (mergecap -I none gives every file its own)"""
    fields = ["-e", "frame.interface_id"] if by_interface else []
    out = subprocess.run(["tshark", "-r", path, "-T", "fields"] + fields + ["-e", "frame.number", "-e", "udp.payload"],
                         capture_output=True, text=True, check=False).stdout
    got, first = {}, {}
    for line in out.splitlines():
        parts = line.split("\t")
        iface = int(parts.pop(0)) if by_interface and parts and parts[0] else None
        if len(parts) != 2:
            continue
        frame = int(parts[0])
        first.setdefault(iface, frame)
        got.setdefault(iface, {})
        if parts[1]:
            got[iface][frame - first[iface] + 1] = parts[1].replace(":", "").lower()
    got.setdefault(None, {})
    return got


def tshark_many(paths, tmp):
    """tshark_payloads of each of paths, from one tshark run over their concatenation
    (mergecap -a -I none: file k's frames in order, on interface k): tshark's start-up
    (0.6 s of CPU) once instead of once a file. Only for whole files without fragments
    (the reader reported no damaged frame): nothing then carries tshark's state, such as
    IP reassembly, from one file into the next. None when mergecap refuses them."""
    merged = tmp / "oracle-merged.pcapng"
    r = subprocess.run(["mergecap", "-a", "-I", "none", "-F", "pcapng", "-w", str(merged)] + list(paths),
                       capture_output=True, text=True)
    if r.returncode != 0:
        print("oracle: mergecap refused the files (%s): one tshark a file" % r.stderr.strip()[:200])
        return None
    got = _tshark_fields(merged, by_interface=True)
    return {p: got.get(k, {}) for k, p in enumerate(paths)}


def reader_payloads(helper, path):
    res = subprocess.run([helper, path], capture_output=True, text=True)
    got, bad = {}, set()
    for line in res.stdout.splitlines():
        frame, _, hx = line.partition(" ")
        if hx == "bad":
            bad.add(int(frame))
        else:
            got[int(frame)] = hx
    return res.returncode, got, bad


def cmd_oracle(args, tmp=None):
    """the reader's payloads (helper args[0]) of each file args[1:] against tshark's; tmp: a
    folder where the whole pcap files without damaged frames are read by one tshark run"""
    helper, files = args[0], args[1:]
    total = 0
    mine = {path: reader_payloads(helper, path) for path in files}
    whole = [p for p in files if tmp is not None and p.endswith(".pcap") and mine[p][0] == 0 and not mine[p][2]]
    theirs_of = tshark_many(whole, tmp) if len(whole) > 1 else None
    # tshark (0.6 s a file) two at a time for the rest the reader opens
    with ThreadPoolExecutor(max_workers=2) as pool:
        runs = {path: pool.submit(tshark_payloads, path) for path in files
                if mine[path][0] != 2 and (theirs_of is None or path not in theirs_of)}
    for path in files:
        rc, mine_p, bad = mine[path]
        if rc == 2:
            print("oracle: %s: not a capture the reader opens" % path)
            continue
        theirs = theirs_of[path] if theirs_of is not None and path in theirs_of else runs[path].result()
        if rc == 1:  # a damaged file: the frames before the damage are compared
            theirs = {k: v for k, v in theirs.items() if k <= max(list(mine_p) + list(bad) + [0])}
        for frame, hx in sorted(mine_p.items()):
            if frame not in theirs:
                fail("%s: frame %d: c4g-replay reads a UDP datagram, tshark none" % (path, frame))
            elif theirs[frame] != hx:
                fail("%s: frame %d: payloads differ (c4g-replay %d bytes, tshark %d bytes)" %
                     (path, frame, len(hx) // 2, len(theirs[frame]) // 2))
        # tshark may show a payload c4g-replay refuses: only a frame it reported as damaged
        # (an IP fragment tshark reassembles, a datagram cut by the snapshot length)
        for frame in sorted(set(theirs) - set(mine_p)):
            if frame not in bad:
                fail("%s: frame %d: tshark reads a UDP datagram, c4g-replay neither reads nor reports it" %
                     (path, frame))
        total += len(mine_p)
    print("oracle: %d files (%d by one tshark run), %d datagrams equal to tshark's udp.payload"
          % (len(files), len(theirs_of or ()), total))


def summary(replay, path, *opts):
    res = subprocess.run([replay, "summary", "--json", "--no-progress", *opts, path], capture_output=True, text=True)
    if res.returncode != 0:
        fail("%s: summary exit %d: %s" % (path, res.returncode, res.stderr.strip()))
        return None
    return json.loads(res.stdout)


def findings(sess):
    return {f["kind"]: f for f in sess["findings"]}


def expect(path, what, got, want):
    if got != want:
        fail("%s: %s is %r, want %r" % (path, what, got, want))


def cmd_facts(args):
    replay = args[0]
    fx = "fixtures/replay/"
    n = 0

    def one(name, *opts):
        d = summary(replay, fx + name, *opts)
        return d, (d["sessions"] if d else [])

    d, ss = one("fault-late.pcap")
    if ss:
        r = ss[0]["replies"]
        expect("fault-late", "late replies", r["late"], 20)
        expect("fault-late", "missing replies", r["missing"], 1)
        expect("fault-late", "NUM mismatches", r["num_mismatch"], 0)
        n += 1
    d, ss = one("fault-skip-3.pcap")
    if ss:
        r = ss[0]["replies"]
        expect("fault-skip-3", "missing", r["missing"], 3)
        expect("fault-skip-3", "longest run", r["longest_missing_run"], 3)
        expect("fault-skip-3", "run start NUM", r["longest_run_from_num"], 162)
        n += 1
    d, ss = one("fault-wrong-num.pcap")
    if ss:
        f = findings(ss[0])
        expect("fault-wrong-num", "num findings", f.get("num", {}).get("count"), 3)
        expect("fault-wrong-num", "first wrong reply NUM", f.get("num", {}).get("num"), 168)
        n += 1
    d, ss = one("fault-drop.pcap")
    if ss:
        expect("fault-drop", "ctrl-gap count", findings(ss[0]).get("ctrl-gap", {}).get("count"), 8)
        n += 1
    d, ss = one("data-follow-error.pcap")
    if ss:
        f = findings(ss[0]).get("follow-error", {})
        expect("data-follow-error", "follow-error count", f.get("count"), 1)
        expect("data-follow-error", "follow-error NUM", f.get("num"), 112)
        n += 1
    d, ss = one("data-current-mode9.pcap")
    if ss:
        expect("data-current-mode9", "current-limit count", findings(ss[0]).get("current-limit", {}).get("count"), 2)
        n += 1
    d, ss = one("data-nan-ctrl-d3.pcap")
    if ss:
        expect("data-nan-ctrl-d3", "nonfinite NUM", findings(ss[0]).get("nonfinite", {}).get("num"), 132)
        n += 1
    d, ss = one("restart-506.pcap")
    if d:
        expect("restart-506", "sessions", len(ss), 2)
        if len(ss) == 2:
            expect("restart-506", "first session's end", ss[0]["end"], "506 restart")
            expect("restart-506", "second session's end", ss[1]["end"], "504 end of communication")
        n += 1
    d, ss = one("two-controllers.pcap")
    if d:
        expect("two-controllers", "sessions", len(ss), 2)
        expect("two-controllers", "PC ports", sorted(s["pc"]["port"] for s in ss), [46117, 46118])
        expect("two-controllers", "findings", sum(len(s["findings"]) for s in ss), 0)
        n += 1
    d, ss = one("data-midsession-wrap.pcap", "--port", "46210")
    if ss:
        expect("data-midsession-wrap", "findings", len(ss[0]["findings"]), 0)
        n += 1
    d, ss = one("fmt-frag-init.pcap")
    if d:
        expect("fmt-frag-init", "damaged frames", d["files"][0]["damaged"], 2)
        expect("fmt-frag-init", "controller side port", ss[0]["controller"]["port"] if ss else None, 46800)
        n += 1
    for name in ("fmt-eth", "fmt-vlan", "fmt-sll", "fmt-sll2", "fmt-raw", "fmt-null", "fmt-nsec"):
        d, ss = one(name + ".pcap")
        if d:
            expect(name, "sessions", len(ss), 1)
            expect(name, "verdict", d["verdict"], "clean")
            n += 1
    print("facts: %d fixtures checked" % n)


def cmd_live_capture(args):
    replay, path, link, cyclic = args[0], args[1], args[2], int(args[3])
    d = summary(replay, path, "--port", args[4]) if len(args) > 4 else summary(replay, path)
    if d is None:
        return
    expect(path, "link type", d["files"][0]["link"], link)
    expect(path, "damaged frames", d["files"][0]["damaged"], 0)
    ss = d["sessions"]
    expect(path, "sessions", len(ss), 1)
    if len(ss) != 1:
        return
    s = ss[0]
    expect(path, "end", s["end"], "504 end of communication")
    expect(path, "controller cyclic packets", s["packets"]["controller"]["cyclic"], cyclic)
    # every packet answered once; a loaded host may make a reply late (timing is not judged here)
    pk = s["packets"]
    expect(path, "PC datagrams", sum(pk["pc"].values()), sum(pk["controller"].values()))
    expect(path, "NUM mismatches", s["replies"]["num_mismatch"], 0)
    print("live capture %s: %s, %d cyclic packets, one session ended by 504" % (path, link, cyclic))


def run(replay, *args):
    res = subprocess.run([replay, *args], capture_output=True, text=True)
    return res.returncode, res.stdout, res.stderr


def field_clock_step(replay, fd):
    f = fd + "clock-step.pcap"
    rc, out, _ = run(replay, "export", "--no-progress", f)
    rows = out.strip().split("\n")[1:]
    expect(f, "export exit status", rc, 0)
    expect(f, "export rows (every cyclic tick)", len(rows), 391)
    expect(f, "export times never go back", all(float(b.split(",")[2]) >= float(a.split(",")[2])
                                               for a, b in zip(rows, rows[1:])), True)
    d = summary(replay, f)
    if d:
        s = d["sessions"][0]
        fs = findings(s)
        expect(f, "findings", sorted(fs), ["clock-step"])
        expect(f, "clock-step frame", fs.get("clock-step", {}).get("frame"), 401)
        expect(f, "clock-step size (s)", round(fs.get("clock-step", {}).get("worst", 0), 6), 0.998024)
        expect(f, "missing replies", s["replies"]["missing"], 0)
        expect(f, "duration > 0.8 s", s["duration_s"] > 0.8, True)


def field_no_session(replay, fd):
    for f in ["fixtures/replay/bad/header-only.pcap", fd + "ipv6.pcap"]:
        rc, out, _ = run(replay, "check", "--no-progress", f)
        expect(f, "check exit status", rc, 3)
        expect(f, "check's no-session line", (f + ": no-session: no C4G Open session found") in out, True)
        expect(f, "check's closing line", out.strip().split("\n")[-1].startswith("NO SESSION: 1 file, 0 sessions"), True)
    rc, out, _ = run(replay, "check", "--no-progress", "fixtures/replay/mode0.pcap", "fixtures/replay/bad/header-only.pcap")
    expect("mode0 + header-only", "check exit status", rc, 3)
    # found by the shape of their datagrams, without --port
    for f, ticks in [(fd + "rotated-2.pcap", 150), (fd + "midsession-mode4.pcap", 353),
                     ("fixtures/replay/data-midsession-wrap.pcap", 120)]:
        rc, out, _ = run(replay, "check", "--no-progress", f)
        expect(f, "check exit status", rc, 0)
        expect(f, "check's closing line", out.strip(), "CLEAN: 1 file, 1 session, 0 findings")
        d = summary(replay, f)
        if d and d["sessions"]:
            expect(f, "cyclic packets", d["sessions"][0]["packets"]["controller"]["cyclic"], ticks)


def field_rerun_midsession(replay, fd):
    f = fd + "midsession-mode4.pcap"
    for opts in [["--port", "46104"], []]:
        rc, out, err = run(replay, "rerun", "--json", "--no-progress", *opts, f, "--", "--sine", "0.25,1,0.5")
        expect(f, "rerun %s exit status" % opts, rc, 0)
        if rc in (0, 1):
            d = json.loads(out)
            expect(f, "divergent", d["divergent"], 0)
            expect(f, "compared", d["compared"], 353)
            expect(f, "synthetic start-up", d["sessions"][0].get("synthetic_startup"), True)


def field_rerun_late(replay, fd):
    f = fd + "late-replies.pcap"
    rc, out, _ = run(replay, "rerun", "--json", "--no-progress", f, "--", "--sine", "0.25,1,0.5")
    expect(f, "rerun exit status (the capture's options)", rc, 0)
    if rc in (0, 1):
        d = json.loads(out)
        expect(f, "divergent", d["divergent"], 0)
        expect(f, "timing only", d.get("timing_only"), 3)
    rc, out, _ = run(replay, "rerun", "--json", "--no-progress", f, "--", "--sine", "0.3,1,0.5")
    expect(f, "rerun exit status (another amplitude)", rc, 1)
    if rc in (0, 1):
        d = json.loads(out)
        fi = d["first"] or {}
        expect(f, "first divergence (field, tick)", (fi.get("field"), fi.get("tick")), ("d1", 114))
        expect(f, "no 'reply' divergence", "reply" in d["fields"], False)
    d = summary(replay, f)
    if d:
        expect(f, "the recording's late replies: missing", d["sessions"][0]["replies"]["missing"], 3)


def field_policy(replay, fd):
    for f, opts, missing in [(fd + "midsession-late.pcap", ["--port", "46123"], 1), (fd + "late-init-echo.pcap", [], 4)]:
        d = summary(replay, f, *opts)
        if not d or not d["sessions"]:
            fail("%s: no session" % f)
            continue
        s = d["sessions"][0]
        expect(f, "NUM policy", s["num_policy"], "plus-one")
        expect(f, "duplicate replies", s["replies"]["duplicates"], 0)
        expect(f, "findings without duplicate or num", sorted(k for k in findings(s) if k in ("duplicate", "num")), [])
        expect(f, "missing", s["replies"]["missing"], missing)


def field_doubled(replay, fd):
    f = fd + "doubled.pcap"
    d = summary(replay, f)
    if d:
        expect(f, "sessions", len(d["sessions"]), 1)
        expect(f, "frames captured twice", d["files"][0].get("doubled"), 166)
        if d["sessions"]:
            s = d["sessions"][0]
            expect(f, "missing", s["replies"]["missing"], 0)
            expect(f, "session findings", [x["kind"] for x in s["findings"]], [])
            expect(f, "cyclic replies", s["replies"]["in_time"], 82)
    rc, out, _ = run(replay, "check", "--no-progress", f)
    expect(f, "check exit status", rc, 1)
    expect(f, "check: one capture line", sum(1 for l in out.split("\n") if ": capture: 166 frames captured twice" in l), 1)


def field_num_range(replay, fd):
    f = fd + "num-huge.pcap"
    d = summary(replay, f, "--port", "46300")
    if d:
        s = d["sessions"][0]
        fs = findings(s)
        expect(f, "malformed finding", "NUM 2147479552 outside 0..32767" in fs.get("malformed", {}).get("first", ""), True)
        expect(f, "no reorder finding", "reorder" in fs, False)
        expect(f, "controller NUM gaps (NUM 27 -> 29 around the bad one)", s["controller_num"]["skipped"], 1)


def field_small(replay, fd):
    f = fd + "lost-frame.pcap"
    d = summary(replay, f)
    if d:
        s = d["sessions"][0]
        expect(f, "findings (the ctrl-gap alone)", sorted(findings(s)), ["ctrl-gap"])
        expect(f, "NUM mismatches", s["replies"]["num_mismatch"], 0)
        expect(f, "replies to lost packets", s["controller_num"].get("replies_to_lost"), 1)
    f = fd + "reply-before.pcap"
    d = summary(replay, f)
    if d:
        fs = findings(d["sessions"][0])
        expect(f, "a clock-step finding at the reply (frame 252)", fs.get("clock-step", {}).get("frame"), 252)
    f = fd + "hole-10s.pcap"
    d = summary(replay, f)
    if d:
        fs = findings(d["sessions"][0])
        expect(f, "a silence finding at frame 501", fs.get("silence", {}).get("frame"), 501)
        expect(f, "silence over 10 s", fs.get("silence", {}).get("worst", 0) > 10.0, True)
    f = fd + "nsec.pcapng"
    d = summary(replay, f)
    if d:
        expect(f, "nanosecond", d["files"][0]["nanosecond"], True)
    f = fd + "mode0.pcap.gz"
    rc, out, err = run(replay, "summary", "--no-progress", f)
    expect(f, "summary exit status", rc, 2)
    expect(f, "named as gzip", "a gzip-compressed file" in err, True)
    res = subprocess.run([replay, "check", "-"], stdin=open("fixtures/replay/mode0.pcap", "rb"),
                         capture_output=True, text=True)
    expect("mode0 on stdin", "check - exit status", res.returncode, 0)
    expect("mode0 on stdin", "check - closing line", res.stdout.strip(), "CLEAN: 1 file, 1 session, 0 findings")
    res = subprocess.run("cat fixtures/replay/mode0.pcap | %s export --no-progress - | wc -l" % replay, shell=True,
                         capture_output=True, text=True)
    expect("mode0 through a pipe", "export rows + header", res.stdout.strip(), "160")
    rc, out, err = run(replay, "export", "--from", "5", "--to", "2", "fixtures/replay/mode0.pcap")
    expect("export --from 5 --to 2", "exit status", rc, 2)
    rc, out, _ = run(replay, "check", "--no-progress", "fixtures/replay/fault-late.pcap", "fixtures/replay/fault-skip-3.pcap")
    expect("check of two files", "the second file's session numbered 1",
           "fixtures/replay/fault-skip-3.pcap: session 1: missing" in out, True)


def cmd_field(args):
    replay, item = args[0], args[1]
    {"clock-step": field_clock_step, "no-session": field_no_session, "rerun-midsession": field_rerun_midsession,
     "rerun-late": field_rerun_late, "policy": field_policy, "doubled": field_doubled,
     "num-range": field_num_range, "small": field_small}[item](replay, "fixtures/replay/field/")


def cmd_docs(args):
    import os
    bindir, path = args[0], args[1]
    env = dict(os.environ, PATH=os.path.abspath(bindir) + os.pathsep + os.environ.get("PATH", ""))
    lines = open(path).read().split("\n")
    cmds, inblock = [], False
    for ln, line in enumerate(lines, 1):
        if line.startswith("```console"):
            inblock = True
        elif line.startswith("```") and inblock:
            inblock = False
        elif inblock and line.startswith("$ "):
            cmds.append([ln, line[2:], []])
        elif inblock and cmds:
            cmds[-1][2].append(line)
    for ln, cmd, want in cmds:
        got = subprocess.run(cmd, shell=True, capture_output=True, text=True, env=env).stdout.rstrip("\n").split("\n")
        if got != want:
            fail("%s:%d: '%s' prints other lines than the page shows" % (path, ln, cmd))
            for k in range(max(len(got), len(want))):
                a = want[k] if k < len(want) else "<none>"
                b = got[k] if k < len(got) else "<none>"
                if a != b:
                    print("  line %d: page: %s\n          run:  %s" % (k + 1, a, b))
                    break
    print("docs: %d examples of %s run" % (len(cmds), path))


# ------------------------------------------------------------------ the tests
def checked(test):
    """every fail() of the test fails it, all of them listed"""
    @functools.wraps(test)
    def run(*args, **kwargs):
        FAILS.clear()
        test(*args, **kwargs)
        assert not FAILS, "%d check(s) failed:\n  " % len(FAILS) + "\n  ".join(FAILS)
    return run


def rp(bins, *args, stdin=None):
    """c4g-replay ARGS: (exit status, stdout, stderr)"""
    r = subprocess.run([str(bins.replay)] + [str(a) for a in args], capture_output=True, text=True, timeout=120,
                       stdin=stdin)
    return r.returncode, r.stdout, r.stderr


def ok(what, cond, detail=""):
    if cond:
        print("  ok   " + what)
    else:
        fail(what + (": " + str(detail) if detail != "" else ""))


def golden_options():
    opts = {}
    for line in open(FX + "/golden/OPTIONS"):
        f = line.split()
        if f:
            opts[f[0]] = f[1:]
    return opts


@checked
def test_golden_and_check(build, bins):
    """1. fixtures: golden summaries, key facts, check's exit status"""
    # what scripts/make-replay-golden.sh --check compares (summary --json without the "tool"
    # key, which carries the version, as json.dumps(indent=2) writes it), in this process
    opts = golden_options()
    fixtures = sorted(glob.glob(FX + "/*.pcap") + glob.glob(FX + "/*.pcapng"))
    for f in fixtures:
        name = os.path.basename(f).rsplit(".", 1)[0]
        rc, out, err = rp(bins, "summary", "--json", "--no-progress", *opts.get(name, []), f)
        try:
            d = json.loads(out)
        except ValueError:
            fail("%s: summary failed: exit %d: %s" % (f, rc, err[-300:]))
            continue
        d.pop("tool", None)
        got = json.dumps(d, indent=2) + "\n"
        gold = FX + "/golden/" + name + ".json"
        want = open(gold).read() if os.path.exists(gold) else None
        ok("summary --json of %s equals its golden file" % name, got == want,
           "no golden file" if want is None else "".join(list(difflib.unified_diff(
               want.splitlines(True), got.splitlines(True), gold, "summary"))[:40]))
    ok("every golden file has its fixture", len(glob.glob(FX + "/golden/*.json")) == len(fixtures),
       (len(glob.glob(FX + "/golden/*.json")), len(fixtures)))
    cmd_facts([str(bins.replay)])
    # every fixture: check exits 0 on a clean golden verdict, else 1
    for g in sorted(glob.glob(FX + "/golden/*.json")):
        name = os.path.basename(g)[:-5]
        f = FX + "/" + name + ".pcap"
        if not os.path.exists(f):
            f = FX + "/" + name + ".pcapng"
        want = 0 if read_json(g)["verdict"] == "clean" else 1
        rc = rp(bins, "check", "-q", *opts.get(name, []), f)[0]
        ok("check %s: exit %d" % (name, want), rc == want, "exit %d" % rc)
    rc, out, err = rp(bins, "check", *sorted(glob.glob(FX + "/*.pcap")))
    ok("check over every fixture at once: exit 1, one line per finding", rc == 1, rc)
    ok("  ... the late replies of fault-late among them", re.search("fault-late.pcap: session [0-9]*: late: 20, ", out),
       out[-600:])
    ok("check --allow all: exit 0", rp(bins, "check", "--allow", "all", "-q", *sorted(glob.glob(FX + "/*.pcap")))[0] == 0)
    ok("check --allow late,missing on fault-late: exit 0",
       rp(bins, "check", "--allow", "late,missing", "-q", FX + "/fault-late.pcap")[0] == 0)


@checked
def test_oracle(bins, tmp_path):
    """2. the reader's payloads against tshark's udp.payload: every datagram of every fixture
    and hostile file"""
    cmd_oracle([str(bins.helper("cap_payloads"))] + sorted(glob.glob(FX + "/*.pcap")) +
               sorted(glob.glob(FX + "/*.pcapng")) + sorted(glob.glob(FX + "/bad/*.pcap")), tmp_path)


HOSTILE = [
    ("empty file", "bad/empty.pcap", 2, "bad/empty.pcap: empty file, not a capture"),
    ("text file: its first bytes", "bad/text.pcap", 2, "not a pcap or pcapng file (starts with 54 68 69 73)"),
    ("a directory", "bad", 2, "is a directory, not a capture file"),
    ("a missing file", "none.pcap", 2, "none.pcap: No such file or directory"),
    ("unknown link type, named", "bad/linktype-user0.pcap", 2, "link type 147 (unknown) is not supported"),
    ("header only (a capture with no packets)", "bad/header-only.pcap", 0, ""),
    ("truncated record at packet 11, offset 4684", "bad/truncated-record.pcap", 1,
     "packet 11 (offset 4684): truncated dump file"),
    ("truncated record header at packet 11", "bad/truncated-record-header.pcap", 1,
     "packet 11 (offset 4684): truncated dump file; tried to read 16 header bytes, only got 8"),
    ("huge caplen at packet 11", "bad/caplen-huge.pcap", 1, "packet 11 (offset 4684): invalid packet capture length"),
    ("garbage after the header: packet 1, offset 24", "bad/garbage-after-header.pcap", 1, "packet 1 (offset 24)"),
    ("snaplen 64: every datagram reported cut", "bad/snaplen-64.pcap", 0,
     "packet 1 (offset 24): snapshot length cut the datagram: 50 of 112 IP bytes captured"),
    ("init packet cut by the snaplen: reported at packet 19", "bad/caplen-over-snaplen.pcap", 0,
     "packet 19 (offset 8412): snapshot length cut the datagram"),
]


@pytest.mark.parametrize("what,path,status,message", HOSTILE, ids=[h[1] for h in HOSTILE])
@checked
def test_hostile_file(bins, tmp_path, what, path, status, message):
    """3. summary's exit status and the first error line; never a crash"""
    f = str(tmp_path / path) if path == "none.pcap" else FX + "/" + path
    rc, out, err = rp(bins, "summary", f)
    ok("%s: not killed by a signal" % what, rc < 128, "exit %d" % rc)
    ok("%s: exit %d" % (what, status), rc == status, "exit %d: %s" % (rc, err[:300]))
    ok("%s: the message" % what, message in err, "%r not in %r" % (message, err[:300]))
    if path == "bad/snaplen-64.pcap":
        ok("  ... the 184 cut frames counted", "184 damaged frames in all" in err, err[-300:])


@checked
def test_hostile_analysis_goes_on(bins):
    """the analysis goes on after the bad packets: the records before the damage are a session"""
    rc, out, _ = rp(bins, "summary", "--json", "--port", "46300", FX + "/bad/truncated-record.pcap")
    d = json.loads(out)
    f = d["files"][0]
    ok("truncated record: the 10 records before it analysed, the file marked incomplete",
       f["frames"] == 10 and f["complete"] is False and len(d["sessions"]) == 1, (f, len(d["sessions"])))
    rc, out, _ = rp(bins, "summary", FX + "/bad/text.pcap", FX + "/mode0.pcap")
    ok("a bad file among good ones: the good one is still summarised (exit 2)", rc == 2, rc)
    ok("  ... mode0's session in the report", "ended by 504" in out, out[-300:])


def start_server(procs, bins, name, port, tmp, *args):
    """c4g-server on 127.0.0.1:port, returned once it listens"""
    h = procs.start([bins.server, "-p", port, "--controller", "127.0.0.1"] + [str(a) for a in args], name=name)
    wait_until(lambda: "listening on" in h.out() or not h.running(), 30, "c4g-server %s listening" % name)
    return h


def can_capture():
    td = shutil.which("tcpdump") or "/usr/sbin/tcpdump"
    return os.path.exists(td) and subprocess.run([td, "-D"], capture_output=True).returncode == 0 and \
        os.getuid() == 0, td


def tcpdump_start(procs, td, iface, port, pcap, name):
    h = procs.start([td, "-i", iface, "-U", "-n", "-w", pcap, "udp and port %d" % port], name=name)
    wait_until(lambda: "listening on" in h.out() or not h.running(), 20, "tcpdump listening")
    return h


def frames_in(bins, pcap):
    rc, out, _ = rp(bins, "summary", "--json", "--no-progress", pcap)
    try:
        return json.loads(out)["files"][0]["frames"]
    except (ValueError, KeyError, IndexError):
        return 0


def tcpdump_session(bins, procs, ports, tmp, iface):
    """a capture of one mode-0 session (c4g-server + c4g-sim, 2 axes) on IFACE: its file, its
    port and c4g-sim's summary"""
    capable, td = can_capture()
    if not capable:
        pytest.skip("tcpdump missing or not allowed to capture (needs root)")
    port = ports.udp()
    pcap = tmp / (iface + ".pcap")
    dump = tcpdump_start(procs, td, iface, port, pcap, "tcpdump-" + iface)
    assert dump.running(), "tcpdump -i %s starts: %s" % (iface, dump.out())
    srv = start_server(procs, bins, "server", port, tmp, "--idle-timeout", 15, "--max-seconds", 45, "--json-out",
                       tmp / "srv.json", "--lost-timeout-ms", 2000)
    sj = tmp / "sim.json"
    r = procs.run([bins.sim, "-p", port, "-S", FX + "/inputs/idle.scn", "--json", "--max-miss", "500", "--open-axes", "2"],
                  timeout=50)
    sj.write_text(r.stdout)
    srv.wait(60)
    sim = json.loads(r.stdout)
    # tcpdump on a loaded host lags behind the session, and what it has not read when it is
    # stopped is lost: wait (at most 20 s) until the file holds every datagram c4g-sim sent
    # and its replies (-U writes each packet as it is read)
    want = 2 * sim["packets"]["sent"]
    wait_until(lambda: frames_in(bins, pcap) >= want, 20, "tcpdump's file holds the %d datagrams" % want)
    dump.signal(signal.SIGINT)
    dump.wait(20)
    return pcap, port, sim


@checked
def test_tcpdump_lo(bins, procs, ports, tmp_path):
    """4. tcpdump -i lo: one session, every cyclic packet of c4g-sim; editcap -F pcapng of it:
    the same session; the oracle on both"""
    pcap, port, sim = tcpdump_session(bins, procs, ports, tmp_path, "lo")
    cyc = sim["packets"]["cyclic"]
    cmd_live_capture([str(bins.replay), str(pcap), "EN10MB", str(cyc), str(port)])
    ng = tmp_path / "lo.pcapng"
    subprocess.run(["editcap", "-F", "pcapng", str(pcap), str(ng)], capture_output=True)
    cmd_live_capture([str(bins.replay), str(ng), "EN10MB", str(cyc), str(port)])
    cmd_oracle([str(bins.helper("cap_payloads")), str(pcap), str(ng)])


@checked
def test_tcpdump_any(bins, procs, ports, tmp_path):
    """4. tcpdump -i any (Linux cooked SLL2): one session; the oracle"""
    pcap, port, sim = tcpdump_session(bins, procs, ports, tmp_path, "any")
    cmd_live_capture([str(bins.replay), str(pcap), "LINUX_SLL2", str(sim["packets"]["cyclic"]), str(port)])
    cmd_oracle([str(bins.helper("cap_payloads")), str(pcap)])


def missing_of(bins, pcap, port):
    rc, out, _ = rp(bins, "summary", "--json", "--no-progress", "--port", port, pcap)
    try:
        return json.loads(out)["sessions"][0]["replies"]["missing"]
    except (ValueError, KeyError, IndexError):
        return None


@checked
def test_server_pcap_stopped(bins, procs, ports, tmp_path):
    """4b. c4g-server --pcap against the wire, the server stopped 60 ms mid-run: the datagrams
    that wait in the server's socket meanwhile must show their wire times in the server's own
    capture (kernel stamps): its missing replies are those c4g-sim counts and those of a
    tcpdump of the same run, not 0"""
    port = ports.udp()
    capable, td = can_capture()
    dump = tcpdump_start(procs, td, "lo", port, tmp_path / "ss.td.pcap", "tcpdump") if capable else None
    srv = start_server(procs, bins, "server", port, tmp_path, "-b", "127.0.0.1", "--idle-timeout", 10,
                       "--max-seconds", 30, "--lost-timeout-ms", 2000, "--pcap", tmp_path / "ss.srv.pcap")
    sim = procs.start([bins.sim, "--bind", "127.0.0.1", "--local-port", ports.udp(), "-p", port, "-c",
                       FX + "/inputs/fast.ini", "-S", FX + "/inputs/idle.scn", "--axes", "2", "--max-miss", "500",
                       "--json"], name="sim")
    time.sleep(0.4)
    srv.signal(signal.SIGSTOP)
    time.sleep(0.06)
    srv.signal(signal.SIGCONT)
    sim.wait(60)
    srv.wait(60)
    if dump:
        time.sleep(0.5)
        dump.signal(signal.SIGINT)
        dump.wait(20)
    m_srv = missing_of(bins, tmp_path / "ss.srv.pcap", port)
    out = sim.out()
    try:
        r = json.loads(out[out.index("{"):])["replies"]
        m_sim = "%d missing, %d unjudged" % (r["missing"], r["unjudged"])
        sim_lost = r["missing"] + r["unjudged"]
    except (ValueError, KeyError):
        m_sim, sim_lost = "none", 0
    # the stop leaves ~30 packets unanswered in time (c4g-sim counted m_sim; on a loaded host
    # it calls some unjudged, its own lateness): a capture stamped after recvfrom shows none
    ok("the server's own capture shows the replies the stop delayed as missing (>= 10): %s (c4g-sim: %s)"
       % (m_srv, m_sim), m_srv is not None and m_srv >= 10)
    if dump:
        m_td = missing_of(bins, tmp_path / "ss.td.pcap", port)
        # the stop (60 ms, 30 periods) leaves about 30 replies missing on the controller's
        # side; 10 more there mean the host held the server up again after it, and replies
        # the server stamped in time then reach the wire late
        host_disturbed(m_srv is not None and m_td is not None and abs(m_srv - m_td) > 5 and sim_lost > 40,
                       "c4g-sim counted %s (the 60 ms stop leaves about 30); server capture %s missing, "
                       "tcpdump %s" % (m_sim, m_srv, m_td))
        ok("  ... as many as tcpdump -i lo of the same run shows (%s, +/- 5)" % m_td,
           m_srv is not None and m_td is not None and abs(m_srv - m_td) <= 5)


def server_fixtures():
    """(file, c4g-server options) of every c4g-server capture the fixtures' README lists"""
    return [(m.group(1), m.group(2).split()) for m in
            re.finditer(r"(?m)^\| ([a-z0-9-]*\.pcap) \| `SRV [0-9]*([^`]*)`", open(FX + "/README.md").read())]


@checked
def test_rerun(bins):
    """5. rerun through c4g-server's core"""
    srv = server_fixtures()
    ok("the README lists c4g-server captures", len(srv) > 0)
    for f, o in srv:
        rc, out, err = rp(bins, "rerun", "--no-progress", FX + "/" + f, "--", *o)
        first = re.search(r"(?m)^(first|verdict).*", out + err)
        ok("0 divergences on %s (%s)" % (f, " ".join(o)), rc == 0, "exit %d: %s" % (rc, first.group(0) if first else ""))
    rc, out, _ = rp(bins, "rerun", "--json", FX + "/mode4.pcap", "--", "--sine", "0.3,1,0.5")
    ok("mode4 with another amplitude: exit 1", rc == 1, rc)
    d = json.loads(out)
    f = d["first"]
    ok("  ... the first divergence is D1 of arm 1 axis 1 at tick 114 (NUM 126), the second tick of mode 4",
       (f["field"], f["arm"], f["axis"], f["tick"], f["num"]) == ("d1", 1, 1, 114, 126), f)
    c = {k: v["count"] for k, v in d["fields"].items()}
    ok("  ... D1 and D2 diverge on the 6 axes of the 250 mode-4 ticks after the first, nothing else",
       c == {"d1": 1500, "d2": 1500} and d["divergent"] == 250, (c, d["divergent"]))
    rc, out, _ = rp(bins, "rerun", "--json", FX + "/mode1.pcap", "--", "--hold", "--duration", "0.5", "--gains",
                    "31,200,300")
    f = json.loads(out)["first"]
    ok("mode1 with another KP: exit 1, the first divergence is a D5 current at mode 1's first tick",
       rc == 1 and (f["field"], f["tick"]) == ("d5", 76), (rc, f))
    rc, out, err = rp(bins, "rerun", FX + "/two-arms.pcap", "--", "--arm", "1", "--axes", "1,2", "--sine",
                      "0.25,2,0.5", "--arm", "2", "--offset", "0.2,0.1,0.1")
    ok("two arms, another offset on arm 2: exit 1, the first divergence on arm 2",
       rc == 1 and re.search(r"(?m)^first divergence: .* arm 2 axis 1 \(OPEN 7\) d1", out + err), (rc, out[-400:]))
    rc, out, err = rp(bins, "rerun", "--session", "2", FX + "/two-controllers.pcap")
    ok("two controllers, --session 2: exit 0, session 1 named as not rerun",
       rc == 0 and "not rerun: 1 session(s) of another controller (1)" in out + err, (rc, out[-400:]))
    rc, out, err = rp(bins, "rerun", FX + "/mode4.pcap", "--", "--sine", "fast")
    ok("a bad c4g-server option: exit 2, named", rc == 2, rc)
    ok("  ... the option and its value in the message", "--sine: bad value 'fast'" in err, err)


def f32_bits(x):
    return struct.unpack("<I", struct.pack("<f", x))[0]


def shortest_digits(x):
    """The fewest significant digits whose %g text reads back to the float32 x."""
    for p in range(1, 10):
        if f32_bits(float("%.*g" % (p, x))) == f32_bits(x):
            return p
    return 9


def sig_digits(text):
    mant = text.lstrip("-").split("e")[0].replace(".", "").lstrip("0").rstrip("0")
    return max(len(mant), 1)


def shortest_floats(bins):
    """export's CSV floats: each reads back to the float32 its JSON line carries (a 9-digit
    decimal there), in the fewest digits that do so."""
    rc, out, _ = rp(bins, "export", FX + "/mode4.pcap")
    rc2, js, _ = rp(bins, "export", "--json-lines", FX + "/mode4.pcap")
    rows = out.splitlines()[1:]
    objs = [json.loads(l) for l in js.splitlines()]
    ok("export CSV and JSON lines of mode4.pcap: exit 0, the same ticks",
       (rc, rc2, len(rows)) == (0, 0, len(objs)) and len(rows) > 300, (rc, rc2, len(rows), len(objs)))
    names = ("d1", "d2", "d3", "d4", "d5", "ext1", "ext2", "ext3")
    bad, n, shorter = [], 0, 0
    for row, o in zip(rows, objs):
        f = row.split(",")
        col = 12
        for side in ("ctrl", "pc"):
            axes = o[side]["axes"] if o[side] else []
            for ax in axes:
                for k, name in enumerate(names):
                    text, want = f[col + 1 + k], ax[name]
                    n += 1
                    if want is None:
                        good = text in ("nan", "inf", "-inf")
                    else:
                        good = (f32_bits(float(text)) == f32_bits(want) and
                                sig_digits(text) == shortest_digits(float(text)))
                        shorter += len(text) < len("%.9g" % struct.unpack("<f", struct.pack("<f", want))[0])
                    if not good and len(bad) < 5:
                        bad.append((o["tick"], side, ax["axis"], name, text, want))
                col += 9
    ok("export CSV: every float the shortest text of the JSON line's float32 (%d fields, %d "
       "shorter than %%.9g)" % (n, shorter), n > 10000 and not bad and shorter > 0, bad)


@checked
def test_export_plot(bins, tmp_path):
    """6. export and plot"""
    rc, out, _ = rp(bins, "export", FX + "/mode0.pcap")
    lines = out.splitlines()
    ok("export: exit 0, a header and one row per cyclic tick (159)", (rc, len(lines) - 1) == (0, 159),
       (rc, len(lines) - 1))
    f = lines[1].split(",") if len(lines) > 1 else []
    ok("  ... tick 1 carries NUM 13, its reply NUM 14", f[1:2] + f[5:7] == ["1", "13", "14"], f[:8])
    shortest_floats(bins)
    rc, out, _ = rp(bins, "export", "--moni", "20", FX + "/mode0.pcap")
    ok("export --moni 20: exit 0, rows", rc == 0 and len(out.splitlines()) > 100, (rc, len(out.splitlines())))
    rc, out, _ = rp(bins, "export", "--json-lines", "--from", "0.1", "--to", "0.2", FX + "/mode0.pcap")
    rows = [json.loads(l) for l in out.splitlines()]
    ok("export --json-lines --from/--to: every line JSON, inside the window",
       rows and all(0.1 <= r["time"] <= 0.2 for r in rows), len(rows))
    assert shutil.which("gnuplot"), "gnuplot installed (scripts/deps.sh)"
    png = tmp_path / "p.png"
    rc, _, _ = rp(bins, "plot", "--axis", "1", "--field", "d1", "--out", png, FX + "/mode4.pcap")
    ok("plot PNG: exit 0, a PNG file", rc == 0 and png.read_bytes()[:4] == b"\x89PNG", rc)
    svg = tmp_path / "l.svg"
    rc, _, _ = rp(bins, "plot", "--latency", "--out", svg, FX + "/mode4.pcap")
    ok("plot --latency SVG: exit 0, an SVG file", rc == 0 and svg.read_text().count("<svg") == 1, rc)
    ta = tmp_path / "ta.png"
    rc, out, err = rp(bins, "plot", "--axis", "1", "--field", "d1,d3", "--output", ta, FX + "/mode4.pcap")
    ok("plot --field d1,d3 (target and actual in one plot) with --output, the old spelling of --out: exit 0, "
       "a PNG, nothing on stdout, one note on stderr",
       rc == 0 and ta.read_bytes()[:4] == b"\x89PNG" and out == "" and
       err.splitlines()[0] == "c4g-replay: --output is spelt --out now, as in the other tools (--output is accepted until 3.0)",
       (rc, out[:200], err))
    rc, _, err = rp(bins, "plot", "--axis", "1", "--field", "d1,nope", FX + "/mode4.pcap")
    ok("  ... a bad field in the list: exit 2, named", rc == 2 and err.count("bad value 'd1,nope'") == 1, (rc, err))
    rc, out, err = rp(bins, "plot", "--axis", "1", "--field", "d1", FX + "/mode4.pcap")
    ok("plot in the terminal (text): exit 0, a drawing", rc == 0 and len((out + err).splitlines()) > 10, rc)


@pytest.mark.parametrize("item", ["clock-step", "no-session", "rerun-midsession", "rerun-late", "policy", "doubled",
                                  "num-range", "small"])
@checked
def test_field(bins, item):
    """7. field-made captures (fixtures/replay/field): every verdict true. clock-step: a clock
    step back is a finding at its frame, no tick dropped, no false missing reply; no-session:
    header only, IPv6 is exit 3, not CLEAN; mid-session captures found on any port;
    rerun-midsession: a synthetic start-up, 0 divergences; rerun-late: a recorded reply after
    the next packet is a timing difference, the first divergence is content; policy: plus-one
    without an init echo in time, no false duplicate; doubled: said once, analysed once;
    num-range: a controller NUM near INT32_MAX is malformed, no arithmetic on it; small: a
    frame lost by the capture, a reply stamped before its packet, a 10 s hole, gzip, stdin,
    --from > --to"""
    cmd_field([str(bins.replay), item])


@checked
def test_live_late(bins, procs, ports, tmp_path):
    """live of late-replies to c4g-server with the capture's options: the recording's late
    replies are timing differences, not divergences"""
    port = ports.udp()
    srv = start_server(procs, bins, "server", port, tmp_path, "-b", "127.0.0.1", "--sine", "0.25,1,0.5", "--persist",
                       "--max-seconds", 30)
    rc, out, _ = rp(bins, "live", FX + "/field/late-replies.pcap", "--target", "127.0.0.1:%d" % port, "--num-policy",
                    "plus-one", "--topspeed", "--json")
    srv.signal(signal.SIGTERM)
    d = json.loads(out)["divergences"]
    ok("live: 0 differing, 3 timing-only", d["differing"] == 0 and d["timing_only"] == 3, d)


@checked
def test_docs(build):
    """docs/c4g-replay.md: every example prints what the page shows"""
    cmd_docs([str(build / "bin"), "docs/c4g-replay.md"])
