#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# A man page's scdoc source from its hand-written part (docs/man/NAME.scd) and the tool's own
# --help: a line "%options TOOL [COMMAND]%" becomes the option list, "%examples TOOL
# [COMMAND]%" the examples, each taken from the option table the tool parses with, so the
# page and the tool cannot disagree about an option. A line "%header include/NAME.h%" becomes
# a library page's NAME, SYNOPSIS, DESCRIPTION and FUNCTIONS: every function the header
# declares with its comment, so a section-3 page cannot miss one. Output on stdout, for scdoc.
#   scripts/man-page.py docs/man/c4g-sim.1.scd build/bin > build/man/c4g-sim.1.scd
#   scripts/man-page.py --functions include/c4gopen_loop.h    (the names, one a line)
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


def doc_text(raw):
    """A /** */ comment as one paragraph: the leading stars, Doxygen's @-words and code
    blocks dropped (@return becomes "Returns")."""
    lines, code = [], False
    for line in raw.splitlines():
        line = re.sub(r"^\s*\*+ ?", "", line).strip()
        if line.startswith("@code") or line.startswith("@endcode"):
            code = line.startswith("@code")
            if code:
                lines.append("(the example is in the header)")
            continue
        if not code and not line.startswith("@file"):
            lines.append(line)
    text = " ".join(x for x in lines if x)
    text = re.sub(r"@brief\s+", "", text)
    text = re.sub(r"@return\s+", "Returns ", text)
    text = re.sub(r"@param(\[[\w,]+\])?\s+(\w+)", r"\2:", text)
    text = re.sub(r"@p\s+", "", text)
    return re.sub(r"\s+", " ", text).strip()


def header_functions(path):
    """(file comment, [(name, prototype, comment)]) of a public header: the declarations of
    functions named c4g_*, each with the /** */ comment just before it."""
    text = open(path, encoding="utf-8").read()
    file_doc = re.search(r"/\*\*(.*?)\*/", text, re.S)
    docs = []

    def keep(m):
        docs.append(m.group(1))
        return " \0%d\0 " % (len(docs) - 1)
    text = re.sub(r"/\*\*(?!<)(.*?)\*/", keep, text, flags=re.S)
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r"(?m)^\s*#(?:[^\n]*\\\n)*[^\n]*", " ", text)
    funcs = []
    for chunk in re.split(r"[;{}]", text):
        marks = re.findall(r"\0(\d+)\0", chunk)
        decl = re.sub(r"\s+", " ", re.sub(r"\0\d+\0", " ", chunk)).strip()
        m = re.match(r"^(?:extern )?(?:C4G_NODISCARD )?([\w ]+?[\w *]*?)\b(c4g_\w+) ?\((.*)\)$", decl, re.S)
        if m and "typedef" not in decl:
            proto = decl.replace("C4G_NODISCARD ", "") + ";"
            funcs.append((m.group(2), proto, doc_text(docs[int(marks[-1])]) if marks else ""))
    return (doc_text(file_doc.group(1)) if file_doc else ""), funcs


def header_page(path):
    """NAME, SYNOPSIS, DESCRIPTION and FUNCTIONS of a section-3 page for one header"""
    about, funcs = header_functions(path)
    name = path.rsplit("/", 1)[-1]
    brief = about.split(". ")[0].rstrip(".")
    out = ["# NAME", "", "%s - %s" % (escape(name[:-2]), escape(brief[:1].lower() + brief[1:])), "",
           "# SYNOPSIS", "", "```", "#include <%s>" % name, ""]
    out += [p for _, p, _ in funcs] + ["```", "", "# DESCRIPTION", "", escape(about), "", "# FUNCTIONS", ""]
    for fname, _, doc in funcs:
        out += ["*%s*()" % escape(fname), "\t" + (escape(doc) if doc else "See the header."), ""]
    return out


def main():
    if sys.argv[1] == "--functions":
        for name, _, _ in header_functions(sys.argv[2])[1]:
            print(name)
        return
    src, bindir = sys.argv[1], sys.argv[2]
    for line in open(src, encoding="utf-8").read().splitlines():
        h = re.match(r"^%header (\S+)%$", line)
        if h:
            print("\n".join(header_page(h.group(1))))
            continue
        m = re.match(r"^%(options|examples) ([\w -]+)%$", line)
        if not m:
            print(line)
            continue
        lines = help_text(bindir, m.group(2).split())
        print("\n".join(options(lines) if m.group(1) == "options" else examples(lines)))


main()
