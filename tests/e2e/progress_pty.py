#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# c4g-sim's progress line: shown on stderr when stderr is a terminal (a pty here), erased
# before the summary; absent when stderr is a file (run by cli_conventions.sh).
#   progress_pty.py SIM PORT
import os, pty, select, subprocess, sys, time

sim, port = sys.argv[1], sys.argv[2]
args = [sim, "-p", port, "-n", "1200", "--max-miss", "500"]
pid, fd = pty.fork()
if pid == 0:
    os.execv(sim, args)
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
text = out.decode(errors="replace")
fails = []
if "\rc4g-sim: tick " not in text or " of 1200 (" not in text:
    fails.append("no progress line on a terminal: " + repr(text[:300]))
if "\r\x1b[K" not in text:
    fails.append("the progress line is not erased")
else:
    summary = text.rsplit("\r\x1b[K", 1)[1]
    if not summary.lstrip().startswith("c4g-sim ") or "tick " in summary.split("\n")[0]:
        fails.append("summary not on a clean line: " + repr(summary[:200]))
piped = subprocess.run(args, capture_output=True, text=True, timeout=30)
if "tick " in piped.stderr and " of 1200" in piped.stderr:
    fails.append("progress written to a file: " + repr(piped.stderr[:200]))
for f in fails:
    print("FAIL:", f)
if not fails:
    print("PASS: progress line on a terminal, erased before the summary; none in a file")
sys.exit(1 if fails else 0)
