#!/bin/sh
# Runs the e2e tests (tests/e2e/test_*.py, pytest) against the build directory $1: real
# processes, loopback, one test at a time. Prints one PASS/FAIL line per module with its
# seconds, and the failed checks again at the end. How to write a test: tests/README.md.
#   E2E_ONLY="a b"        run only tests/e2e/test_a.py and test_b.py
#   E2E_LOAD=0            no busy loops beside the run (debugging); E2E_LOAD=N: N loops
#                         (default: one per core, so timing-bound tests fail here rather
#                         than on a busy CI host)
#   E2E_LOAD_SECONDS=S    each loop stops by itself after S seconds (default 900)
# Extra arguments after the build directory go to pytest (e.g. -k 'mode4' -x).
# A test is run a second time only when its own figures showed that the host held it up
# (e2elib.host_disturbed); the summary names the evidence. No other rerun exists.
set -u
build=${1:?usage: sh scripts/run-e2e.sh BUILD_DIR [pytest args]}
shift
# Debian's pytest (python3-pytest), not whatever python3 comes first in PATH
py=/usr/bin/python3
"$py" -c 'import pytest' 2>/dev/null ||
  { echo "e2e: $py has no pytest (scripts/deps.sh installs python3-pytest)" >&2; exit 2; }
# (tests/e2e/pytest.ini makes tests/e2e the root: its conftest.py is the harness)
exec "$py" -m pytest -q -p no:cacheprovider tests/e2e --build "$build" "$@"
