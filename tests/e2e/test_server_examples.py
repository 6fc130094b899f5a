# SPDX-License-Identifier: MIT
"""examples/*.c compile against the public header and the static library (C99, pedantic,
-Werror), and examples/mode4_loop.c runs a real mode-4 session against c4g-sim."""
import os

import pytest

from e2elib import ROOT, udp_bound, wait_until

EXAMPLES = sorted(p.name for p in (ROOT / "examples").glob("*.c"))


def compile_example(procs, build, src, out):
    cc = os.environ.get("CC", "cc")
    return procs.run([cc, "-std=c99", "-D_POSIX_C_SOURCE=200809L", "-pedantic", "-Wall", "-Wextra",
                      "-Werror", "-O2", "-Iinclude", "-o", out, "examples/" + src,
                      build / "lib" / "libc4gopen.a", "-lm"], timeout=120)


@pytest.mark.parametrize("src", EXAMPLES)
def test_example_compiles(procs, build, tmp_path, src):
    r = compile_example(procs, build, src, tmp_path / src[:-2])
    assert r.returncode == 0, "examples/%s (C99, -pedantic -Werror, static lib): %s" % (src, r.stderr)


def test_mode4_loop_short():
    n = len((ROOT / "examples" / "mode4_loop.c").read_text().splitlines())
    assert n <= 119, "examples/mode4_loop.c is under 120 lines (%d)" % n


def test_mode4_loop_runs(procs, bins, build, ports, tmp_path):
    from simlib import json_line
    exe = tmp_path / "mode4_loop"
    assert compile_example(procs, build, "mode4_loop.c", exe).returncode == 0
    port = ports.udp()
    ex = procs.start([exe, "-p", port], name="mode4_loop")
    # the controller starts once the example's socket is bound (it prints nothing before)
    wait_until(lambda: udp_bound(port) or not ex.running(), 30, "mode4_loop bound to port %d" % port)
    # --max-miss 500: a busy host may stop the example for 100 ms; counted, not fatal
    r = procs.run([bins.sim, "-p", port, "-S", "fixtures/server/sim_example.scn", "--max-miss", 500,
                   "--json"], timeout=30)
    ex.wait(30)
    assert r.returncode == 0, "sim scenario (mode 4 ran, EXIT_FROM_OPEN seen): " + r.stderr
    pos = json_line(r.stdout)["robot"][0]["pos"]
    assert abs(pos - 0.3) <= 0.02, "robot moved +0.1 turns from 0.2: %r" % pos
    assert "worst cycle" in ex.out(), "ended on 504 with its report"
