# SPDX-License-Identifier: MIT
"""The e2e harness: fixtures (build, bins, ports, procs), the busy loops that share the host
with the run, the one rerun a test may get (HostDisturbed, with its evidence) and the
per-module PASS/FAIL lines. How to write a test: tests/README.md."""
import os
import pathlib
import signal
import socket
import subprocess
import sys
import time

import pytest

import e2elib

ROOT = e2elib.ROOT
# the fixture srv (c4g-server against a controller) of the test_server_* modules, and
# arm_recordings (the arm plant's excitations, recorded once a run) of the arm modules
pytest_plugins = ["srvlib", "armlib"]


def pytest_addoption(parser):
    parser.addoption("--build", default=os.environ.get("C4G_BUILD", "build"),
                     help="build directory (default: $C4G_BUILD, else ./build)")


def pytest_configure(config):
    # tests name files relative to the repository (fixtures/..., as the tools print them)
    os.chdir(ROOT)
    config._e2e = {"modules": [], "reruns": [], "t0": {}}


@pytest.fixture(scope="session")
def build(request):
    b = pathlib.Path(request.config.getoption("--build"))
    return (b if b.is_absolute() else ROOT / b).resolve()


class Bins:
    """The tools under BUILD/bin and the C helpers under BUILD/e2e (make e2e-helpers)."""

    def __init__(self, build):
        b = build / "bin"
        self.sim = b / "c4g-sim"
        self.server = b / "c4g-server"
        self.replay = b / "c4g-replay"
        self.ident = b / "c4g-ident"
        self.cell_cli = b / "cell-cli"
        self.cell_sim = b / "cell-sim"
        self._e2e = build / "e2e"

    def helper(self, name):
        p = self._e2e / name
        if not os.access(p, os.X_OK):
            pytest.fail("%s not built (make e2e-helpers)" % p)
        return p


@pytest.fixture(scope="session")
def bins(build):
    return Bins(build)


class Ports:
    """Free 127.0.0.1 ports, none handed out twice in a run. A port is free when a socket
    bound to port 0 got it (the kernel picks from its ephemeral range, so tools that bind
    fixed ports elsewhere are not in the way)."""

    def __init__(self):
        self.given = set()

    @staticmethod
    def _kind(proto):
        return socket.SOCK_DGRAM if proto == "udp" else socket.SOCK_STREAM

    def _free(self, proto):
        for _ in range(1000):
            with socket.socket(socket.AF_INET, self._kind(proto)) as s:
                s.bind(("127.0.0.1", 0))
                p = s.getsockname()[1]
            if p not in self.given:
                self.given.add(p)
                return p
        raise AssertionError("no free %s port" % proto)

    def udp(self):
        return self._free("udp")

    def tcp(self):
        return self._free("tcp")

    def block(self, n, proto="udp"):
        """First of n consecutive free ports (tools that take a port base)."""
        for _ in range(1000):
            with socket.socket(socket.AF_INET, self._kind(proto)) as s:
                s.bind(("127.0.0.1", 0))
                base = s.getsockname()[1]
            if base + n > 65536 or any(p in self.given for p in range(base, base + n)):
                continue
            if all(self._bindable(p, proto) for p in range(base, base + n)):
                self.given.update(range(base, base + n))
                return base
        raise AssertionError("no %d consecutive free %s ports" % (n, proto))

    def _bindable(self, port, proto):
        with socket.socket(socket.AF_INET, self._kind(proto)) as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                return False
        return True


@pytest.fixture(scope="session")
def ports():
    return Ports()


class Proc:
    """One background process; stdout and stderr go to self.log."""

    def __init__(self, args, log, env, stdin):
        self.args = [str(a) for a in args]
        self.name = log.stem
        self.log = log
        self._f = open(log, "wb")
        self.p = subprocess.Popen(self.args, stdout=self._f, stderr=subprocess.STDOUT,
                                  stdin=subprocess.DEVNULL if stdin is None else stdin,
                                  env=e2elib.environ(env), cwd=ROOT)
        self.pid = self.p.pid

    def out(self):
        return self.log.read_text(errors="replace")

    def wait(self, timeout):
        try:
            return self.p.wait(timeout)
        except subprocess.TimeoutExpired:
            raise AssertionError("%s did not end within %s s" % (self.name, timeout)) from None

    def signal(self, sig):
        if self.p.poll() is None:
            self.p.send_signal(sig)

    def running(self):
        return self.p.poll() is None

    @property
    def stdin(self):
        """the process's stdin when started with stdin=subprocess.PIPE"""
        return self.p.stdin

    @property
    def returncode(self):
        return self.p.poll()

    def _close(self):
        if self.p.poll() is None:
            self.p.kill()
        try:
            self.p.wait(10)
        except subprocess.TimeoutExpired:
            pass
        self._f.close()


class Procs:
    def __init__(self, tmp):
        self.tmp = tmp
        self.all = []

    def start(self, args, name=None, env=None, stdin=None):
        """args (str or Path items) in the background from the repository's root."""
        name = name or pathlib.Path(str(args[0])).name
        log = self.tmp / (name + ".log")
        k = 1
        while log.exists():
            k += 1
            log = self.tmp / ("%s.%d.log" % (name, k))
        h = Proc(args, log, env, stdin)
        self.all.append(h)
        return h

    def run(self, args, timeout=60, input=None, env=None):
        """args in the foreground, bounded in time: CompletedProcess, text stdout/stderr."""
        args = [str(a) for a in args]
        try:
            return subprocess.run(args, capture_output=True, text=True, timeout=timeout,
                                  input=input, env=e2elib.environ(env), cwd=ROOT,
                                  stdin=None if input is not None else subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            raise AssertionError("%s did not end within %s s" % (args[0], timeout)) from None

    def close(self, failed):
        for h in self.all:
            h._close()
        if failed:
            for h in self.all:
                print("--- %s (%s), last lines:" % (h.log, " ".join(h.args)[:200]))
                print("\n".join(h.out().splitlines()[-25:]))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    rep = (yield).get_result()
    if call.excinfo is not None and call.excinfo.errisinstance(e2elib.HostDisturbed):
        rep.host_disturbed = str(call.excinfo.value)
    setattr(item, "rep_" + rep.when, rep)


@pytest.fixture
def procs(request, tmp_path):
    pr = Procs(tmp_path)
    yield pr
    rep = getattr(request.node, "rep_call", None)
    pr.close(bool(rep is not None and rep.failed))


def _module(item):
    return pathlib.Path(item.nodeid.split("::")[0]).stem


def _reporter(config):
    tr = config.pluginmanager.get_plugin("terminalreporter")
    if tr is not None:
        tr.write("\n")  # after the progress dots (-q)
    return tr


def pytest_runtest_protocol(item, nextitem):
    """Runs a test; once more if its own figures showed that the host held it up
    (HostDisturbed). Only the last run is reported; the evidence goes to the summary."""
    from _pytest.runner import runtestprotocol
    st = item.config._e2e
    mod = _module(item)
    st["t0"].setdefault(mod, time.monotonic())
    item.ihook.pytest_runtest_logstart(nodeid=item.nodeid, location=item.location)
    # teardown down to the module only: the same test is set up again
    reports = runtestprotocol(item, nextitem=item.parent, log=False)
    evidence = [getattr(r, "host_disturbed", None) for r in reports if r.when == "call"]
    if evidence and evidence[0]:
        st["reruns"].append((item.nodeid, evidence[0]))
        tr = _reporter(item.config)
        if tr is not None:
            tr.write_line("e2e: %s: the host held it up (%s): once more" % (item.nodeid, evidence[0]))
        reports = runtestprotocol(item, nextitem=nextitem, log=False)
    else:
        # the teardown above stopped at the module: finish it towards the next test
        item.session._setupstate.teardown_exact(nextitem)
    for r in reports:
        item.ihook.pytest_runtest_logreport(report=r)
    item.ihook.pytest_runtest_logfinish(nodeid=item.nodeid, location=item.location)
    failed = any(r.failed for r in reports)
    mods = st["modules"]
    if not mods or mods[-1][0] != mod:
        mods.append([mod, True, 0.0])
    mods[-1][1] = mods[-1][1] and not failed
    if nextitem is None or _module(nextitem) != mod:
        mods[-1][2] = time.monotonic() - st["t0"][mod]
        tr = _reporter(item.config)
        if tr is not None:
            tr.write_line("e2e: %s %s (%.0f s)" % ("PASS" if mods[-1][1] else "FAIL", mod, mods[-1][2]))
    return True


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    """The failed checks once more at the very end (a reader who sees only the tail of a
    long log still sees what failed), and every rerun with its evidence."""
    tr = terminalreporter
    st = config._e2e
    for nodeid, ev in st["reruns"]:
        tr.write_line("e2e: %s ran twice, the host held up its first run: %s" % (nodeid, ev))
    for rep in tr.stats.get("failed", []) + tr.stats.get("error", []):
        msg = ""
        crash = getattr(rep.longrepr, "reprcrash", None)
        if crash is not None:
            msg = crash.message.splitlines()[0] if crash.message else ""
        tr.write_line("e2e: FAILED %s (%s): %s" % (rep.nodeid, rep.when, msg[:300]))
    mods = st["modules"]
    if mods:
        failed = [m[0] for m in mods if not m[1]]
        tr.write_line("e2e: %d modules passed, %d failed%s; %.0f s" % (
            len(mods) - len(failed), len(failed),
            " (%s)" % " ".join(failed) if failed else "", sum(m[2] for m in mods)))


@pytest.fixture(scope="session", autouse=True)
def load(request):
    """One busy loop per core beside the run (E2E_LOAD=N loops, 0 none), so timing-bound
    tests fail here rather than on a busy CI host; each loop ends by itself after
    E2E_LOAD_SECONDS (900), so a runner killed with SIGKILL leaves nothing spinning long."""
    n = int(os.environ.get("E2E_LOAD", str(os.cpu_count() or 2)))
    secs = os.environ.get("E2E_LOAD_SECONDS", "900")
    loops = [subprocess.Popen(["timeout", secs, "sh", "-c", "while :; do :; done"])
             for _ in range(n)]
    if n > 0:
        tr = _reporter(request.config)
        if tr is not None:
            tr.write_line("e2e: %d busy loop(s) running alongside (E2E_LOAD=0 turns them off)" % n)
    yield n
    for p in loops:
        p.send_signal(signal.SIGTERM)
    for p in loops:
        p.wait()


def pytest_collection_modifyitems(session, config, items):
    # E2E_ONLY="a b" selects tests/e2e/test_a.py and test_b.py (names as the old runner's)
    only = os.environ.get("E2E_ONLY", "").split()
    if not only:
        return
    want = {n if n.startswith("test_") else "test_" + n for n in only}
    keep = [i for i in items if _module(i) in want]
    drop = [i for i in items if _module(i) not in want]
    missing = want - {_module(i) for i in items}
    if missing:
        raise pytest.UsageError("E2E_ONLY: no such e2e module: %s" % " ".join(sorted(missing)))
    config.hook.pytest_deselected(items=drop)
    items[:] = keep


if sys.version_info < (3, 7):
    raise SystemExit("the e2e harness needs Python 3.7 or newer")
