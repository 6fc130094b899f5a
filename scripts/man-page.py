#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# A man page's scdoc source from its hand-written part (docs/man/NAME.scd) and the tool's own
# --help: a line "%options TOOL [COMMAND]%" becomes the option list, "%examples TOOL
# [COMMAND]%" the examples, each taken from the option table the tool parses with, so the
# page and the tool cannot disagree about an option. Output on stdout, for scdoc.
#   scripts/man-page.py docs/man/c4g-sim.1.scd build/bin > build/man/c4g-sim.1.scd
import re
import subprocess
import sys


def escape(text):
    """Text for scdoc: its markup characters taken literally."""
    return text.replace("\\", "\\\\").replace("*", "\\*").replace("_", "\\_")


def help_text(bindir, words):
    run = subprocess.run([f"{bindir}/{words[0]}"] + words[1:] + ["--help"], capture_output=True,
                         text=True, check=False)
    if run.returncode != 0:
        sys.exit(f"man-page: {' '.join(words)} --help exited {run.returncode}")
    return run.stdout.splitlines()


def section(lines, title):
    """The lines of one --help section ("Options:", "Examples:"), up to a blank line."""
    out, inside = [], False
    for line in lines:
        if line.strip() == title:
            inside = True
            continue
        if inside:
            if not line.strip():
                break
            out.append(line)
    return out


def options(lines):
    """Each option of --help as (names, argument, description)."""
    rows = []
    for line in section(lines, "Options:"):
        m = re.match(r"^  (-\w, )?(--[\w-]+)(?: (\S+))?\s*(.*)$", line)
        if m and line.startswith("  -"):
            rows.append([m.group(1), m.group(2), m.group(3), m.group(4).strip()])
        elif line.startswith("      --") or line.startswith("  -"):
            m = re.match(r"^\s+(-\w, )?(--[\w-]+)(?: (\S+))?\s*(.*)$", line)
            rows.append([m.group(1), m.group(2), m.group(3), m.group(4).strip()])
        elif rows:  # a description on the next line (the option and argument were too long)
            rows[-1][3] = (rows[-1][3] + " " + line.strip()).strip()
    out = []
    for short, long_, arg, desc in rows:
        head = (f"*{escape(short.rstrip(', '))}*, " if short else "") + f"*{escape(long_)}*"
        if arg:
            head += f" _{escape(arg)}_"
        text = escape(desc[:1].upper() + desc[1:]) + ("." if desc and desc[-1] not in ".)" else "")
        if text[:1] in "-[":  # would start a list or a table
            text = "\\" + text
        out += [head, "\t" + text, ""]
    return out


def examples(lines):
    return ["```"] + [line.strip() for line in section(lines, "Examples:")] + ["```"]


def main():
    src, bindir = sys.argv[1], sys.argv[2]
    for line in open(src, encoding="utf-8").read().splitlines():
        m = re.match(r"^%(options|examples) ([\w -]+)%$", line)
        if not m:
            print(line)
            continue
        lines = help_text(bindir, m.group(2).split())
        print("\n".join(options(lines) if m.group(1) == "options" else examples(lines)))


main()
