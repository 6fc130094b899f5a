# SPDX-License-Identifier: MIT
"""Stand-in of the e2e harness's fixtures (same API): build, bins, ports, procs, load."""
import os
import pathlib
import socket
import subprocess

import pytest



def pytest_addoption(parser):
    parser.addoption("--build", default=os.environ.get("C4G_BUILD", "build"),
                     help="build directory (default: $C4G_BUILD, else ./build)")


@pytest.fixture(scope="session")
def build(request):
    return pathlib.Path(request.config.getoption("--build")).resolve()


class Bins:
    def __init__(self, build):
        b = build / "bin"
        self.sim, self.server, self.replay = b / "c4g-sim", b / "c4g-server", b / "c4g-replay"
        self.ident, self.cell_cli, self.cell_sim = b / "c4g-ident", b / "cell-cli", b / "cell-sim"
        self._e2e = build / "e2e"

    def helper(self, name):
        return self._e2e / name


@pytest.fixture(scope="session")
def bins(build):
    return Bins(build)


class Ports:
    def __init__(self):
        self.given = set()

    def _free(self, kind):
        while True:
            s = socket.socket(socket.AF_INET, kind)
            s.bind(("127.0.0.1", 0))
            p = s.getsockname()[1]
            s.close()
            if p not in self.given:
                self.given.add(p)
                return p

    def udp(self):
        return self._free(socket.SOCK_DGRAM)

    def tcp(self):
        return self._free(socket.SOCK_STREAM)

    def block(self, n, proto="udp"):
        kind = socket.SOCK_DGRAM if proto == "udp" else socket.SOCK_STREAM
        base = 20000 + os.getpid() % 20000
        while True:
            ok = True
            for p in range(base, base + n):
                if p in self.given:
                    ok = False
                    break
                s = socket.socket(socket.AF_INET, kind)
                try:
                    s.bind(("127.0.0.1", p))
                except OSError:
                    ok = False
                finally:
                    s.close()
                if not ok:
                    break
            if ok:
                self.given.update(range(base, base + n))
                return base
            base += n
            if base > 60000:
                base = 20000


@pytest.fixture(scope="session")
def ports():
    return Ports()


class Proc:
    def __init__(self, args, log, env, stdin):
        self.log = log
        self._f = open(log, "wb")
        self.p = subprocess.Popen([str(a) for a in args], stdout=self._f, stderr=subprocess.STDOUT,
                                  stdin=stdin if stdin is not None else subprocess.DEVNULL,
                                  env=env, start_new_session=True)
        self.pid = self.p.pid

    def out(self):
        return self.log.read_text(errors="replace")

    def wait(self, timeout):
        return self.p.wait(timeout)

    def signal(self, sig):
        if self.p.poll() is None:
            self.p.send_signal(sig)

    def running(self):
        return self.p.poll() is None


class Procs:
    def __init__(self, tmp):
        self.tmp, self.all, self.n = tmp, [], 0

    def start(self, args, name=None, env=None, stdin=None):
        self.n += 1
        name = name or "%s-%d" % (pathlib.Path(str(args[0])).name, self.n)
        h = Proc(args, self.tmp / (name + ".log"), env, stdin)
        self.all.append(h)
        return h

    def run(self, args, timeout=60, input=None, env=None):
        return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=timeout,
                              input=input, env=env)

    def close(self, failed):
        for h in self.all:
            if h.running():
                h.p.kill()
            try:
                h.p.wait(10)
            except subprocess.TimeoutExpired:
                pass
            h._f.close()
            if failed:
                print("--- %s (tail)" % h.log)
                print("\n".join(h.out().splitlines()[-25:]))


@pytest.hookimpl(tryfirst=True, hookwrapper=True)
def pytest_runtest_makereport(item, call):
    rep = (yield).get_result()
    setattr(item, "rep_" + rep.when, rep)


@pytest.fixture
def procs(request, tmp_path):
    pr = Procs(tmp_path)
    yield pr
    rep = getattr(request.node, "rep_call", None)
    pr.close(bool(rep and rep.failed))


def pytest_runtest_protocol(item, nextitem):
    # a test whose own figures showed the host held it up (HostDisturbed) runs once more
    from _pytest.runner import runtestprotocol
    item.ihook.pytest_runtest_logstart(nodeid=item.nodeid, location=item.location)
    reports = runtestprotocol(item, nextitem=nextitem, log=False)
    call = [r for r in reports if r.when == "call"]
    if call and call[0].failed and "HostDisturbed" in str(call[0].longrepr):
        print("\ne2e: %s: the host held it up, once more" % item.nodeid)
        reports = runtestprotocol(item, nextitem=nextitem, log=False)
    for r in reports:
        item.ihook.pytest_runtest_logreport(report=r)
    item.ihook.pytest_runtest_logfinish(nodeid=item.nodeid, location=item.location)
    return True


@pytest.fixture(scope="session", autouse=True)
def load():
    n = int(os.environ.get("E2E_LOAD", os.cpu_count() or 2))
    secs = os.environ.get("E2E_LOAD_SECONDS", "900")
    ps = [subprocess.Popen(["timeout", secs, "sh", "-c", "while :; do :; done"]) for _ in range(n)]
    yield
    for p in ps:
        p.terminate()
    for p in ps:
        p.wait()
