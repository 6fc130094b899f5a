# SPDX-License-Identifier: MIT
"""Man pages and bash completion: every page the build made renders with man -l without a
warning, has its sections, and names every long option of its tool's --help (each command's
for c4g-replay and c4g-ident); the completion script offers each tool's options, c4g-replay's
and c4g-ident's commands, files for FILE options and cell-cli's words."""
import functools
import glob
import os
import re
import subprocess
import time

import pytest

HEADER_PAGES = ["c4gopen_%s.3" % h for h in ("base", "wire", "engine", "loop", "ctrl", "cell", "canopen", "dyn")]
PAGES = ["c4g-server.1", "c4g-sim.1", "c4g-replay.1", "c4g-ident.1", "cell-cli.1", "cell-sim.1", "c4gopen.3"] + HEADER_PAGES
ENV = dict(os.environ, LC_ALL="C", MANWIDTH="100")


@functools.lru_cache(maxsize=None)
def render(build, page):
    """man -l of a page of the build (each page rendered once for the module's tests)"""
    return subprocess.run(["man", "-l", str(build / "man" / page)], capture_output=True, text=True, env=ENV)


@pytest.mark.parametrize("page", PAGES)
def test_page_renders(build, page):
    assert (build / "man" / page).stat().st_size > 0, page + " was not built"
    r = render(build, page)
    assert r.returncode == 0 and r.stderr == "", "%s: man -l exit %d: %s" % (page, r.returncode, r.stderr[:300])
    assert re.search("^NAME", r.stdout, re.M) and re.search("^SEE ALSO", r.stdout, re.M), page + ": NAME or SEE ALSO"
    if page.endswith(".1"):
        src = (build / "man" / page).read_text()
        assert re.search("^EXIT STATUS", src, re.M) or re.search("^EXIT STATUS", r.stdout, re.M), page + ": EXIT STATUS"
    elif page == "c4gopen.3":
        assert "c4g_loop_rx" in r.stdout and "pkg-config" in r.stdout, "c4gopen(3): the loop and the linking"
    else:
        assert re.search("^FUNCTIONS", r.stdout, re.M), page + ": FUNCTIONS"


def test_c4gopen3_names_every_header(build):
    text = render(build, "c4gopen.3").stdout
    headers = sorted(os.path.basename(h) for h in glob.glob("include/*.h"))
    missing = [h for h in headers if h != "c4gopen.h" and h not in text]
    assert len(headers) >= 9 and not missing, "c4gopen(3) does not name: %s" % missing
    missing = [p[:-2] for p in HEADER_PAGES if p[:-2] + "(3)" not in text]
    assert not missing, "c4gopen(3) SEE ALSO misses: %s" % missing


def test_header_pages_list_every_function(build):
    """every function the library exports (nm, not the header parser) is on the page of the
    header that declares it, and every header with a function has a page"""
    nm = subprocess.run(["nm", "-g", "--defined-only", str(build / "lib" / "libc4gopen.a")], capture_output=True,
                        text=True, check=True).stdout
    exported = sorted({f[2] for f in (line.split() for line in nm.splitlines()) if len(f) == 3 and f[1] == "T"})
    texts = {h: open(h).read() for h in glob.glob("include/*.h")}
    unlisted = []
    for fn in exported:
        decl = [h for h, t in texts.items() if re.search(r"\b%s\s*\(" % fn, t) and
                re.search(r"(?m)^(C4G_NODISCARD )?\w[\w *]*\b%s\(" % fn, t)]
        assert len(decl) == 1, "%s declared in %s" % (fn, decl)
        page = os.path.basename(decl[0])[:-2] + ".3"
        assert page in HEADER_PAGES, "%s has no page" % decl[0]
        if (fn + "()") not in render(build, page).stdout:
            unlisted.append(fn)
    assert len(exported) > 150 and not unlisted, "%d exported, not on their page: %s" % (len(exported), unlisted)
    links = sorted(p.name[:-2] for p in (build / "man" / "fn").glob("c4g_*.3"))
    assert links == exported, "man/fn links differ: %s" % sorted(set(links) ^ set(exported))


def options_of(argv):
    out = subprocess.run([str(a) for a in argv] + ["--help"], capture_output=True, text=True, env=ENV).stdout
    return sorted({m.group(2) for m in re.finditer(r"(?m)^ +(-[A-Za-z0-9], )?(--[a-z0-9-]*)", out)})


@pytest.mark.parametrize("page,tool,cmd", [(t + ".1", t, None) for t in ("c4g-server", "c4g-sim", "cell-cli", "cell-sim")]
                         + [("c4g-replay.1", "c4g-replay", c) for c in ("summary", "check", "export", "rerun", "live", "plot", "follow")]
                         + [("c4g-ident.1", "c4g-ident", c) for c in ("fit", "excite")])
def test_page_names_every_option(build, page, tool, cmd):
    text = render(build, page).stdout
    opts = options_of([build / "bin" / tool] + ([cmd] if cmd else []))
    missing = [o for o in opts if not re.search(re.escape(o) + r"\b", text)]
    assert len(opts) > 2 and not missing, "%s: %d options, missing: %s" % (page, len(opts), missing)


COMPLETIONS = [
    ("--json", ["c4g-server", "--js"]),
    ("--moni --moni-type", ["c4g-server", "--mon"]),
    ("--json", ["c4g-sim", "--js"]),
    ("--csv", ["c4g-sim", "--cs"]),
    ("summary", ["c4g-replay", "su"]),
    ("--allow", ["c4g-replay", "check", "--al"]),
    ("--plot", ["c4g-ident", "fit", "--pl"]),
    ("fit", ["c4g-ident", "f"]),
    ("--workspace", ["cell-sim", "--works"]),
    ("--no-raw --no-history --no-hints", ["cell-cli", "--no-"]),
    ("robot", ["cell-cli", "rob"]),
    ("abs rel", ["cell-cli", "robot", "mov", ""]),
    ("fixtures/server/traj_example.csv", ["c4g-server", "--traj", "fixtures/server/traj_ex"]),
    ("", ["c4g-server", "--port", ""]),
    # short options take their values as the long ones do
    ("fixtures/scenarios/mode0.scn", ["c4g-sim", "-S", "fixtures/scenarios/mode0"]),
    ("", ["c4g-sim", "-p", ""]),
    # the values an option's help lists
    ("plus-one echo either", ["c4g-sim", "--num-policy", ""]),
    ("plus-one echo", ["c4g-server", "--num-policy", ""]),
    ("drop truncate", ["c4g-sim", "--entry-fault", ""]),
    ("huber cauchy none", ["c4g-ident", "fit", "--loss", ""]),
    ("server echo", ["c4g-replay", "rerun", "-b", ""]),
    ("ctrl pc", ["c4g-replay", "plot", "--side", ""]),
    # each device's own commands (the conditioning controller's only after conditioning)
    ("sta srvon srvof ovr mov stp rst clo itr pnp", ["cell-cli", "robot", ""]),
    ("sta srvon srvof ovr mov stp rst clo itr", ["cell-cli", "platform", ""]),
    ("rst clo acq hnd", ["cell-cli", "conditioning", ""]),
    ("rst", ["cell-cli", "-p", "3000", "conditioning", "r"]),
    ("conditioning connect", ["cell-cli", "con"]),
    ("robot platform conditioning", ["cell-cli", "connect", ""]),
    ("", ["cell-cli", "connect", "robot", ""]),
    ("sta srvon srvof stp sleep", ["cell-cli", "help", "s"]),
]


@pytest.mark.parametrize("want,words", COMPLETIONS, ids=[" ".join(w) for _, w in COMPLETIONS])
def test_completion(build, want, words):
    """the completions of the last word"""
    script = ('. scripts/completion/c4gopen.bash\n'
              'COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); _c4gopen; echo "${COMPREPLY[*]}"\n')
    env = dict(ENV, PATH=str(build / "bin") + os.pathsep + os.environ["PATH"])
    r = subprocess.run(["bash", "-c", script, "t"] + words, capture_output=True, text=True, env=env)
    assert r.stdout.rstrip("\n") == want, "complete %r -> %r, want %r" % (words, r.stdout, want)


def test_completion_parses():
    r = subprocess.run(["bash", "-n", "scripts/completion/c4gopen.bash"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_completion_in_bash(build, tmp_path):
    """TAB in a real interactive bash (tmux): a directory completes with its "/", a short
    option's file value and a listed value complete on the line"""
    sock = str(tmp_path / "tmux.sock")
    env = dict(ENV, PATH=str(build / "bin") + os.pathsep + os.environ["PATH"], TERM="xterm", HOME=str(tmp_path))
    rc = tmp_path / "bashrc"
    rc.write_text("PS1='$ '\n. %s/scripts/completion/c4gopen.bash\n" % os.getcwd())

    def tmux(*args):
        return subprocess.run(["tmux", "-S", sock] + list(args), capture_output=True, text=True, env=env, timeout=30)
    assert tmux("new-session", "-d", "-x", "150", "-y", "20", "bash", "--rcfile", str(rc), "--noprofile", "-i").returncode == 0
    try:
        def line_after(keys):
            tmux("send-keys", "C-u")
            tmux("send-keys", "-l", keys)
            tmux("send-keys", "Tab")
            want = None
            for _ in range(100):
                time.sleep(0.05)
                screen = [ln.rstrip() for ln in tmux("capture-pane", "-p").stdout.splitlines()]
                last = [ln for ln in screen if ln.startswith("$ ")][-1:] or [""]
                if last[0] != "$ " + keys:
                    want = last[0]
                    break
            return want
        tmux("send-keys", "cd %s" % os.getcwd(), "Enter")
        time.sleep(0.3)
        assert line_after("c4g-server --traj fixtures/serv") == "$ c4g-server --traj fixtures/server/"
        assert line_after("c4g-sim -S fixtures/scen") == "$ c4g-sim -S fixtures/scenarios/"
        assert line_after("c4g-sim --entry-fault tr") == "$ c4g-sim --entry-fault truncate"
        assert line_after("cell-cli conditioning ac") == "$ cell-cli conditioning acq"
    finally:
        tmux("kill-server")
