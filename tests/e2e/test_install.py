# SPDX-License-Identifier: MIT
"""make install into a DESTDIR (once, for the tests that read it), a program built against it
with pkg-config (static and shared) and run; the README's compile line on the shipped
example; man pages and bash completions installed; the installed pages work where they are;
make uninstall removes every installed file."""
import glob
import os
import re
import shutil
import subprocess
from concurrent.futures import ThreadPoolExecutor

import pytest

APP = r'''#include <c4gopen.h>
#include <stdio.h>
int main(void)
{
    c4g_loop_t lp;
    c4g_loop_config_t cfg;
    c4g_pc_packet_t neutral = {0};
    unsigned char buf[C4G_MAX_CYCLIC_SIZE];
    size_t n = 0;
    neutral.n_axes = 6;
    if (c4g_session_config_default(&cfg.session) != C4G_OK ||
        c4g_engine_config_default(&cfg.engine) != C4G_OK || c4g_loop_init(&lp, &cfg) != C4G_OK ||
        c4g_pc_encode(&neutral, buf, sizeof buf, &n) != C4G_OK)
        return 1;
    printf("%s %u %s\n", C4G_VERSION_STRING, (unsigned)n, c4g_strerror(C4G_ERR_CELL_HEAD));
    return n == C4G_CYCLIC_SIZE(6) ? 0 : 1;
}
'''


def sh(args, **kw):
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=300, **kw)
    assert r.returncode == 0, "%s: exit %d: %s%s" % (" ".join(map(str, args)), r.returncode, r.stdout, r.stderr)
    return r.stdout


@pytest.fixture(scope="module")
def installed(build, tmp_path_factory):
    """one make install into a DESTDIR, PREFIX /opt/c4g, for the module's tests: (DESTDIR,
    the prefix in it); test_uninstall, after the tests that read it, removes it"""
    root = tmp_path_factory.mktemp("install") / "root"
    sh(["make", "-s", "BUILD=%s" % build, "install", "DESTDIR=%s" % root, "PREFIX=/opt/c4g"])
    return root, root / "opt" / "c4g"


def test_install(build, installed):
    root, pre = installed
    assert (pre / "include" / "c4gopen.h").is_file()
    assert (pre / "lib" / "libc4gopen.a").is_file()
    soname = re.search(r"SONAME.*\[(.*)\]", sh(["readelf", "-d", pre / "lib" / "libc4gopen.so"])).group(1)
    assert soname == "libc4gopen.so.2", soname
    env = dict(os.environ, PKG_CONFIG_PATH=str(pre / "lib" / "pkgconfig"), PKG_CONFIG_SYSROOT_DIR=str(root))
    flags = sh(["pkg-config", "--cflags", "--libs", "c4gopen"], env=env).split()
    app = root / "app.c"
    app.write_text(APP)
    run_env = dict(os.environ, LD_LIBRARY_PATH=str(pre / "lib"))
    sh(["cc", "-std=c99", "-o", root / "app_shared", app] + flags)
    out = sh([root / "app_shared"], env=run_env)
    # the version of the SONAME's major, a 6-axis cyclic packet's 228 bytes, a status named
    assert re.match(r"^2\.\d+\.\d+ 228 cell: \S", out), out
    # the archive needs libm (lib/dyn: sqrt, sincos), as pkg-config --static says below
    sh(["cc", "-std=c99", "-o", root / "app_static", app] + sh(["pkg-config", "--cflags", "c4gopen"], env=env).split()
       + [pre / "lib" / "libc4gopen.a", "-lm"])
    assert sh([root / "app_static"]) == out
    # the README's compile line, verbatim, on the shipped example; then its --help
    line = re.search(r"(?m)^cc -o mode4_loop examples/mode4_loop\.c .*$", open("README.md").read())
    assert line, "no compile line for examples/mode4_loop.c in README.md"
    src = root / "src"
    src.mkdir()
    shutil.copytree("examples", src / "examples")
    r = subprocess.run(["sh", "-c", line.group(0)], cwd=src, capture_output=True, text=True, env=env)
    assert r.returncode == 0, "the README's compile line failed: " + r.stderr
    r = subprocess.run([src / "mode4_loop", "--help"], capture_output=True, text=True, env=run_env)
    assert re.search(r"(?m)^Usage: mode4_loop \[-p PORT\]", r.stdout), r.stdout
    r = subprocess.run([src / "mode4_loop", "-p", "nope"], capture_output=True, text=True, env=run_env)
    assert r.returncode == 2, (r.returncode, r.stderr)
    # static: pkg-config --static carries Libs.private (-lm)
    assert "-lm" in sh(["pkg-config", "--static", "--libs", "c4gopen"], env=env).split()
    # man pages and bash completion installed; the pages render
    for p in ("man1/c4g-server.1", "man1/c4g-sim.1", "man1/c4g-replay.1", "man1/c4g-ident.1", "man1/cell-cli.1",
              "man1/cell-sim.1", "man3/c4gopen.3"):
        f = pre / "share" / "man" / p
        assert f.is_file() and f.stat().st_size > 0, "not installed: " + p
    assert "c4g_loop_rx" in sh(["man", "-l", pre / "share" / "man" / "man3" / "c4gopen.3"],
                               env=dict(os.environ, MANWIDTH="80"))
    # a page per header and a link per function: man c4g_loop_rx opens c4gopen_loop(3)
    for h in ("base", "wire", "engine", "loop", "ctrl", "cell", "canopen"):
        assert (pre / "share" / "man" / "man3" / ("c4gopen_%s.3" % h)).is_file(), "no page for c4gopen_%s.h" % h
    r = subprocess.run(["man", "-M", pre / "share" / "man", "3", "c4g_loop_rx"], capture_output=True, text=True,
                       env=dict(os.environ, MANWIDTH="100", LC_ALL="C", MANPAGER="cat", PAGER="cat"))
    assert r.returncode == 0 and "c4gopen_loop - " in r.stdout and "c4g_loop_rx()" in r.stdout, r.stdout[:500] + r.stderr
    assert len(list((pre / "share" / "man" / "man3").glob("c4g_*.3"))) >= 150
    comp = pre / "share" / "bash-completion" / "completions"
    for t in ("c4g-server", "c4g-sim", "c4g-replay", "c4g-ident", "cell-cli", "cell-sim"):
        assert os.access(comp / t, os.R_OK), "no completion for " + t
    assert "complete -F _c4gopen" in (comp / "cell-cli").read_text()


def test_installed_docs(installed):
    """the installed pages work where they are (see check_installed_docs)"""
    check_installed_docs(*installed)


def test_uninstall(build, installed):
    """make uninstall removes every file make install wrote: the library, tools, man pages,
    completions, the pages with their pictures, the fixtures"""
    root, pre = installed
    assert (pre / "share" / "c4gopen" / "fixtures").is_dir() and (pre / "share" / "doc" / "libc4gopen" / "img").is_dir()
    sh(["make", "-s", "BUILD=%s" % build, "uninstall", "DESTDIR=%s" % root, "PREFIX=/opt/c4g"])
    left = [p for p in (root / "opt").rglob("*") if p.is_file() or p.is_symlink()]
    assert left == [], "files left after uninstall: %s" % left[:10]


def check_installed_docs(root, pre):
    """The installed pages work where they are: every relative link (c4g-ident.md's pictures
    in img/, README.md's links to the pages beside it) resolves, every installed path a page
    names (the fixtures under share/c4gopen, the tools under bin) exists, and no page still
    names the source tree's fixtures/ or build/bin/ (but the fuzz corpus, a source folder)."""
    doc = pre / "share" / "doc" / "libc4gopen"
    ident = (doc / "c4g-ident.md").read_text()
    imgs = re.findall(r"!\[[^\]]*\]\((img/[^)]+)\)", ident)
    assert "img/ident-current.png" in imgs, imgs
    bad, named = [], 0
    for page in sorted(doc.glob("*.md")):
        text = page.read_text()
        for t in re.findall(r"\]\(([^)\s#]+)(?:#[^)]*)?\)", text):
            if not re.match(r"[a-z]+:", t) and not (doc / t).exists():
                bad.append("%s: link %s" % (page.name, t))
        for t in re.findall(r"/opt/c4g/(?:share/c4gopen|bin)/[^\s`'\")\]]+", text):
            named += 1
            if not glob.glob(str(root) + t.rstrip(".,:;")):
                bad.append("%s: names %s" % (page.name, t))
        for m in re.finditer(r"(?m)(?:^|[^A-Za-z0-9_./-])(?:fixtures/(?!fuzz/)|build/bin/)\S*", text):
            bad.append("%s: source-tree path %s" % (page.name, m.group(0).strip()))
    assert not bad, "installed pages that do not work where they are (%d):\n%s" % (len(bad), "\n".join(bad[:40]))
    assert named > 50, "the installed pages name %d installed paths" % named
    assert "/opt/c4g/share/c4gopen/fixtures/replay/mode4.pcap" in (doc / "c4g-replay.md").read_text()


def test_install_ldconfig(build):
    """ldconfig only for root into a default prefix of the system without DESTDIR; another
    prefix is told the two variables (make -n: the commands install would run)"""
    def plan(args):
        return sh(["make", "-n", "BUILD=%s" % build, "install", "LDCONFIG=/sbin/ldconfig"] + list(args)).splitlines()
    # the four plans at once (make -n reads the Makefile and writes nothing)
    with ThreadPoolExecutor(max_workers=4) as pool:
        usr_local, usr, staged, other = pool.map(plan, (["PREFIX=/usr/local"], ["PREFIX=/usr"],
                                                        ["PREFIX=/usr/local", "DESTDIR=/tmp/stage"], ["PREFIX=/opt/c4g"]))
    root = os.getuid() == 0
    assert ("/sbin/ldconfig" in usr_local) == root
    assert ("/sbin/ldconfig" in usr) == root
    assert "/sbin/ldconfig" not in staged
    assert "/sbin/ldconfig" not in other
    assert any("export PKG_CONFIG_PATH=/opt/c4g/lib/pkgconfig LD_LIBRARY_PATH=/opt/c4g/lib" in line for line in other), other[-3:]


def test_readme_without_our_build(tmp_path):
    """the README's compile line for a copy of include/ and lib/ in another project, run
    there as it stands; the program answers --help"""
    line = re.search(r"(?m)^cc -std=c99 -O2 -Ic4gopen/include .*$", open("README.md").read())
    assert line, "no compile line from a copy of the sources in README.md"
    proj = tmp_path / "proj"
    (proj / "c4gopen" / "lib").mkdir(parents=True)
    shutil.copytree("include", proj / "c4gopen" / "include")
    shutil.copy("lib/c4g_internal.h", proj / "c4gopen" / "lib")
    for d in ("wire", "engine", "loop", "cell", "canopen"):
        shutil.copytree("lib/" + d, proj / "c4gopen" / "lib" / d)
    shutil.copytree("examples", proj / "examples")
    r = subprocess.run(["sh", "-c", line.group(0)], cwd=proj, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, "the README's line failed: " + r.stderr[-2000:]
    r = subprocess.run([proj / "mode4_loop", "--help"], capture_output=True, text=True)
    assert re.search(r"(?m)^Usage: mode4_loop \[-p PORT\]", r.stdout), r.stdout
