# SPDX-License-Identifier: MIT
"""A user who is not root, on a machine with a C compiler but none of the QA toolchain
(no valgrind, qemu, ARM compiler, tshark, clang-tidy ... in PATH), builds the library with
`make lib`; `make` would build the tools whose libraries are present and name the one it
leaves out; `make check` stops naming the missing packages and the command that installs
them, having built nothing."""
import os
import shutil
import subprocess
import tempfile

import pytest

# what a C build needs in PATH (gcc finds its own cc1, as and ld through its prefix)
BUILD_CMDS = ["sh", "make", "cc", "gcc", "as", "ld", "ar", "objcopy", "sed", "grep", "mkdir", "rm", "ln",
              "touch", "id", "cat"]


@pytest.fixture
def user_tree():
    """a copy of the source tree (no build folder) owned by an unprivileged user, a PATH of
    compiler tools only, and how to run a command as that user"""
    top = tempfile.mkdtemp(prefix="c4g-nonroot-", dir="/tmp")
    os.chmod(top, 0o755)
    src = os.path.join(top, "src")
    skip = shutil.ignore_patterns("build", ".git", "__pycache__")
    shutil.copytree(".", src, ignore=skip, symlinks=True)
    bindir = os.path.join(top, "bin")
    os.mkdir(bindir)
    for c in BUILD_CMDS:
        where = shutil.which(c)
        assert where, "%s is not installed" % c
        os.symlink(where, os.path.join(bindir, c))
    prefix = []
    if os.getuid() == 0:  # drop to nobody; a non-root runner is that user already
        subprocess.run(["chown", "-R", "65534:65534", src], check=True)
        prefix = [shutil.which("setpriv"), "--reuid=65534", "--regid=65534", "--clear-groups"]
    env = {"PATH": bindir, "HOME": top, "LC_ALL": "C"}

    def run(*args):
        return subprocess.run(prefix + list(args), cwd=src, env=env, capture_output=True, text=True, timeout=600)

    yield src, run
    shutil.rmtree(top, ignore_errors=True)


def test_lib_without_root_or_qa_tools(user_tree):
    src, run = user_tree
    assert run("id", "-u").stdout.strip() != "0"
    r = run("make", "-j2", "lib")
    out = r.stdout + r.stderr
    assert r.returncode == 0, "make lib as a user: exit %d\n%s" % (r.returncode, out[-2000:])
    for f in ("libc4gopen.a", "libc4gopen.so.2", "c4gopen.pc"):
        assert os.path.isfile(os.path.join(src, "build", "lib", f)), f + " not built"
    assert "deps (lib): all present" in out
    # nothing of the QA set was asked for
    assert "valgrind" not in out and "apt-get" not in out, out[-2000:]


def test_tools_build_what_is_present(user_tree):
    _, run = user_tree
    # dry run: which tools make would build in this PATH (no g++ in it: c4g-ident is C++)
    r = run("make", "-n", "tools")
    out = r.stdout + r.stderr
    assert r.returncode == 0, out[-2000:]
    assert "-o build/bin/c4g-server " in out and "-o build/bin/cell-cli " in out, out[-3000:]
    assert "-o build/bin/c4g-ident " not in out
    assert "c4g-ident not built: missing g++" in out, out[-2000:]
    # the tools' packages named once (the user is not root: nothing installed)
    assert "deps (tools): missing: " in out and "g++" in out and "scdoc" in out, out[:2000]


def test_check_names_the_missing_packages(user_tree):
    src, run = user_tree
    r = run("make", "check")
    out = r.stdout + r.stderr
    assert r.returncode != 0, "make check without the QA set passed?\n" + out[-2000:]
    missing = [line for line in out.splitlines() if line.startswith("deps (check): missing: ")]
    assert missing, out[-2000:]
    for pkg in ("valgrind", "qemu-user", "gcc-arm-none-eabi", "tshark", "clang-tidy"):
        assert " " + pkg in missing[0], "%s not named: %s" % (pkg, missing[0])
    assert "sudo apt-get install -y " in out
    # it stopped before building anything
    assert not os.path.exists(os.path.join(src, "build", "obj")), "make check compiled without its packages"
