# SPDX-License-Identifier: MIT
"""Generic helpers of the e2e tests beyond the harness's API (tests/e2e/e2elib.py)."""
import re


class Checks:
    """Named checks of one test: each is printed (ok/FAIL with its figures) and the test
    fails at the end with every failed one listed, so one run shows all that is wrong."""

    def __init__(self):
        self.failed = []
        self.n = 0

    def ok(self, what, cond, detail=""):
        self.n += 1
        if cond:
            print("  ok   %s" % what)
        else:
            line = what + (": " + str(detail) if detail != "" else "")
            print("  FAIL %s" % line)
            self.failed.append(line)
        return bool(cond)

    def eq(self, what, got, want):
        return self.ok(what, got == want, "got %r, want %r" % (got, want))

    def ge(self, what, got, want):
        return self.ok(what, got is not None and got >= want, "got %r, want >= %r" % (got, want))

    def has(self, what, text, pattern):
        """pattern (a regular expression, as grep takes it) found in text"""
        return self.ok(what, re.search(pattern, text, re.M) is not None,
                       "%r not in %r" % (pattern, text[-600:]))

    def done(self):
        print("%d/%d checks passed" % (self.n - len(self.failed), self.n))
        assert not self.failed, "%d of %d checks failed:\n  " % (len(self.failed), self.n) + \
            "\n  ".join(self.failed)


def flat(d, prefix=""):
    """A JSON object flattened to {"a.b.c": value} (lists left out), as the shell tests read it."""
    out = {}
    for k, v in d.items():
        key = prefix + k
        if isinstance(v, dict):
            out.update(flat(v, key + "."))
        elif not isinstance(v, list):
            out[key] = v
    return out


def listening_tcp(port):
    """some socket listens on TCP port `port` of this host"""
    import subprocess
    out = subprocess.run(["ss", "-Htln", "sport = :%d" % port], capture_output=True, text=True).stdout
    return "LISTEN" in out


_ONCE = {}


def once(key, make):
    """make() run once per test session, its result (or its failure) given to every test that
    asks for key: an expensive run (a capture, a long loop) shared by the tests of a module
    without a fixture scope wider than the harness's fixtures."""
    if key not in _ONCE:
        try:
            _ONCE[key] = (True, make())
        except Exception as e:  # every test that needs it fails with the same reason
            _ONCE[key] = (False, "%s: %s" % (type(e).__name__, e))
    good, value = _ONCE[key]
    assert good, "%s failed: %s" % (key, value)
    return value


def forget(key):
    """the next once(key, ...) makes its run again (the one kept was disturbed)"""
    _ONCE.pop(key, None)
