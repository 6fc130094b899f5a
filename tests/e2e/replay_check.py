#!/usr/bin/env python3
"""Checks for tests/e2e/replay.sh (c4g-replay end to end).

  oracle HELPER FILE...      the payloads c4g-replay's reader extracts (HELPER prints
                             "FRAME HEX" / "FRAME bad") equal tshark's udp.payload, frame by frame
  facts REPLAY               the key facts fixtures/replay/README.md states, from summary --json
  live-capture REPLAY FILE LINK CYCLIC [PORT]
                             a capture made by tcpdump during a sim + server run: one session
                             ended by 504, LINK link type, CYCLIC cyclic ticks, each answered
  field REPLAY ITEM          c4g-replay's verdicts on the field-made captures of
                             fixtures/replay/field (README.md there): ITEM clock-step,
                             no-session, rerun-midsession, rerun-late, policy, doubled,
                             num-range, small
  docs BINDIR FILE.md        every ```console block: each "$ COMMAND" run (BINDIR first in
                             PATH) prints exactly the lines that follow it
Every failure prints "FAIL: ..." and the exit status is 1.
"""
import json
import subprocess
import sys

FAILS = []


def fail(msg):
    FAILS.append(msg)
    print("FAIL: " + msg)


def tshark_payloads(path):
    out = subprocess.run(["tshark", "-r", path, "-T", "fields", "-e", "frame.number", "-e", "udp.payload"],
                         capture_output=True, text=True, check=False).stdout
    got = {}
    for line in out.splitlines():
        parts = line.split("\t")
        if len(parts) == 2 and parts[1]:
            got[int(parts[0])] = parts[1].replace(":", "").lower()
    return got


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


def cmd_oracle(args):
    helper, files = args[0], args[1:]
    total = 0
    for path in files:
        rc, mine, bad = reader_payloads(helper, path)
        if rc == 2:
            print("oracle: %s: not a capture the reader opens" % path)
            continue
        theirs = tshark_payloads(path)
        if rc == 1:  # a damaged file: the frames before the damage are compared
            theirs = {k: v for k, v in theirs.items() if k <= max(list(mine) + list(bad) + [0])}
        for frame, hx in sorted(mine.items()):
            if frame not in theirs:
                fail("%s: frame %d: c4g-replay reads a UDP datagram, tshark none" % (path, frame))
            elif theirs[frame] != hx:
                fail("%s: frame %d: payloads differ (c4g-replay %d bytes, tshark %d bytes)" %
                     (path, frame, len(hx) // 2, len(theirs[frame]) // 2))
        # tshark may show a payload c4g-replay refuses: only a frame it reported as damaged
        # (an IP fragment tshark reassembles, a datagram cut by the snapshot length)
        for frame in sorted(set(theirs) - set(mine)):
            if frame not in bad:
                fail("%s: frame %d: tshark reads a UDP datagram, c4g-replay neither reads nor reports it" %
                     (path, frame))
        total += len(mine)
    print("oracle: %d files, %d datagrams equal to tshark's udp.payload" % (len(files), total))


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
    cmds, i, inblock = [], 0, False
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


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    cmd, args = sys.argv[1], sys.argv[2:]
    {"oracle": cmd_oracle, "facts": cmd_facts, "live-capture": cmd_live_capture, "docs": cmd_docs,
     "field": cmd_field}[cmd](args)
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
