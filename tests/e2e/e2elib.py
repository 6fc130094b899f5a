# SPDX-License-Identifier: MIT
"""What the e2e tests share beside the fixtures of conftest.py: waiting, reading the tools'
outputs, and the one way to ask for a rerun (host_disturbed)."""
import csv
import json
import os
import pathlib
import re
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


class HostDisturbed(Exception):
    """The test's own figures show that the host held it up: the harness reruns it once."""


def host_disturbed(cond, evidence):
    """When cond is true (figures of this run show the host held it up, e.g. replies the
    simulator counted late or stale), raises HostDisturbed(evidence): the harness runs the
    test once more and prints the evidence in its summary. The condition must need evidence
    of the disturbance, so that a real fault fails both runs."""
    if cond:
        raise HostDisturbed(evidence)


def wait_until(pred, timeout, what):
    """Polls pred every 20 ms until it returns a true value, which is returned; raises
    AssertionError naming `what` after timeout seconds. A bound for a broken run, never a
    timing assertion: a loaded host only makes it slower."""
    end = time.monotonic() + timeout
    while True:
        v = pred()
        if v:
            return v
        if time.monotonic() > end:
            raise AssertionError("timed out after %s s waiting for %s" % (timeout, what))
        time.sleep(0.02)


def read_json(path):
    with open(path) as f:
        return json.load(f)


def csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def udp_bound(port):
    """Some socket on this host (IPv4 or IPv6) is bound to UDP port `port`."""
    for table in ("/proc/net/udp", "/proc/net/udp6"):
        try:
            with open(table) as f:
                next(f)
                for line in f:
                    local = line.split()[1]
                    if int(local.rsplit(":", 1)[1], 16) == port:
                        return True
        except FileNotFoundError:
            continue
    return False


def udp_rx_queue(port):
    """Bytes waiting in the receive queues of the IPv4 UDP sockets bound to `port` (None
    when none is bound)."""
    total = None
    with open("/proc/net/udp") as f:
        next(f)
        for line in f:
            cols = line.split()
            if int(cols[1].rsplit(":", 1)[1], 16) == port:
                total = (total or 0) + int(cols[4].split(":")[1], 16)
    return total


def environ(extra):
    """The test's environment with `extra` (a dict, or None) on top."""
    env = dict(os.environ)
    if extra:
        env.update({k: str(v) for k, v in extra.items()})
    return env


def first(obj, key):
    """The first value of `key` in a JSON document, in document order, at any depth (the
    tools' summaries name each counter once); None when absent."""
    stack = [iter([(None, obj)])]
    while stack:
        try:
            k, v = next(stack[-1])
        except StopIteration:
            stack.pop()
            continue
        if k == key:
            return v
        if isinstance(v, dict):
            stack.append(iter(v.items()))
        elif isinstance(v, list):
            stack.append((None, x) for x in v)
    return None


def kv(path):
    """key=value lines (the test helpers' reports) as a dict of strings."""
    out = {}
    for line in pathlib.Path(path).read_text(errors="replace").splitlines():
        k, sep, v = line.partition("=")
        if sep and k not in out:
            out[k] = v
    return out


class Checks:
    """Named checks of one case: each prints ok/FAIL with its figures, and done() fails the
    test listing every failed one, so that one run shows all that is wrong."""

    def __init__(self):
        self.failed = []
        self.n = 0

    def ok(self, what, cond, detail=""):
        self.n += 1
        print("  %s %s%s" % ("ok  " if cond else "FAIL", what, "" if cond else ": " + str(detail)))
        if not cond:
            self.failed.append("%s: %s" % (what, detail))
        return bool(cond)

    def eq(self, what, got, want):
        return self.ok(what, got == want, "got %r, want %r" % (got, want))

    def ge(self, what, got, want):
        return self.ok(what, got is not None and got >= want, "got %r, want >= %r" % (got, want))

    def le(self, what, got, want):
        return self.ok(what, got is not None and got <= want, "got %r, want <= %r" % (got, want))

    def near(self, what, got, want, tol):
        return self.ok(what, got is not None and abs(got - want) <= tol,
                       "got %r, want %r +/- %r" % (got, want, tol))

    def has(self, what, text, pattern):
        """pattern, a regular expression as grep takes it, somewhere in text"""
        return self.ok(what, re.search(pattern, text, re.M) is not None,
                       "%r not in ...%r" % (pattern, text[-800:]))

    def done(self, disturbed=(False, "")):
        """Fails the test when a check failed; disturbed = (cond, evidence): when a check
        failed and cond holds (the run's own figures show the host held it up), the test is
        rerun once instead (host_disturbed). A run that passed is never made again."""
        print("%d/%d checks passed" % (self.n - len(self.failed), self.n))
        if self.failed:
            host_disturbed(disturbed[0], "%s (failed: %s)" % (disturbed[1], "; ".join(self.failed)[:300]))
        assert not self.failed, "%d of %d checks failed:\n  " % (len(self.failed), self.n) + \
            "\n  ".join(self.failed)
