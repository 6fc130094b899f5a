# Shared by tests/e2e/sim_*.sh (sourced, POSIX sh). $1 = build directory.
# Builds the reference PC (helpers/ref_pc.c) against the static library, gives each test
# its own temporary directory and port range, and kills what it started on exit.
set -u
B=${1:?usage: sh tests/e2e/sim_X.sh BUILD_DIR}
SIM=$B/bin/c4g-sim
[ -x "$SIM" ] || { echo "FAIL: $SIM not built"; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/c4gsim.XXXXXX")
PIDS=""
cleanup() {
  for p in $PIDS; do kill "$p" 2>/dev/null; done
  wait 2>/dev/null
  rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 1' INT TERM
fail() { echo "FAIL: $*"; exit 1; }
ok() { echo "ok: $*"; }
REF=$T/ref_pc
cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Wall -Wextra -Iinclude -o "$REF" \
  tests/e2e/helpers/ref_pc.c "$B/lib/libc4gopen.a" -lm || fail "cannot build ref_pc"
# A port range per test process (high ports, loopback only).
PORT=$(( 42000 + ($$ % 1500) * 12 ))
next_port() { PORT=$((PORT + 1)); }
# start_pc PORT [ref_pc options]: reference PC in the background on 127.0.0.1:PORT
start_pc() {
  p=$1; shift
  "$REF" -p "$p" --idle-ms 1500 --max-s 50 "$@" 2>"$T/ref_$p.log" &
  PIDS="$PIDS $!"
  sleep 0.2
}
# run_sim ARGS: the simulator on loopback, bounded in time
run_sim() { timeout 50 "$SIM" --bind 127.0.0.1 "$@"; }
# jget FILE KEY: first value of "KEY": in a JSON summary
jget() { grep -o "\"$2\":[^,}]*" "$1" | head -1 | cut -d: -f2 | tr -d '"'; }
# expect_eq WHAT GOT WANT
expect_eq() { [ "$2" = "$3" ] || fail "$1: got '$2', want '$3'"; ok "$1 = $3"; }
