# SPDX-License-Identifier: MIT
"""Helpers the e2e tests share (stand-in of the harness's library: same API)."""
import csv
import json
import subprocess
import time


class HostDisturbed(Exception):
    """The test's own figures show that the host held it up: the harness reruns it once."""


def host_disturbed(cond, evidence):
    """Raises HostDisturbed(evidence) when cond is true (a run the host held up)."""
    if cond:
        raise HostDisturbed(evidence)


def wait_until(pred, timeout, what):
    """Polls pred every 20 ms until it is true; AssertionError naming what after timeout s.
    A bound for a broken run, never a timing assertion."""
    end = time.monotonic() + timeout
    while True:
        if pred():
            return
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
    """Some socket is bound to UDP port `port` on this host."""
    out = subprocess.run(["ss", "-Huln", "sport = :%d" % port], capture_output=True, text=True).stdout
    return bool(out.strip())
