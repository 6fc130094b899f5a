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
. tests/e2e/helpers/wait.sh
# start_pc PORT [ref_pc options]: reference PC in the background on 127.0.0.1:PORT; returns
# once its socket is bound (its "listening" line), so no datagram races its start-up
start_pc() {
  p=$1; shift
  "$REF" -p "$p" --idle-ms 1500 --max-s 50 "$@" 2>"$T/ref_$p.log" &
  PCPID=$!
  PIDS="$PIDS $PCPID"
  wait_until 30 pc_up "$p" || fail "ref_pc did not start on port $p"
  grep -qs '^ref_pc: listening' "$T/ref_$p.log" || fail "ref_pc on port $p: $(cat "$T/ref_$p.log")"
}
udp_bound() { ss -Huln "sport = :$1" | grep -q .; }   # some socket is bound to UDP port $1
pc_up() { grep -qs '^ref_pc: listening' "$T/ref_$1.log" || ! kill -0 "$PCPID" 2>/dev/null; }
# wait_pc: waits for the last reference PC to end (504, or --idle-ms after the last packet)
# and print its summary line
wait_pc() { wait "$PCPID"; }
# run_sim ARGS: the simulator on loopback, bounded in time
run_sim() { timeout 50 "$SIM" --bind 127.0.0.1 "$@"; }
# The reference PC is an ordinary process: a busy host can stop it for 100 ms (50 periods)
# while the simulator runs. Tests that are not about the 10-in-a-row rule pass $STALL_OK, so
# such a stall is counted (missing) instead of ending the run with ERR_C4GOPEN_UDP; the rule
# itself is tested with the default in sim_replies.sh and sim_num_policy.sh.
STALL_OK="--max-miss 500"
# jget FILE KEY: first value of "KEY": in a JSON summary
jget() { grep -o "\"$2\":[^,}]*" "$1" | head -1 | cut -d: -f2 | tr -d '"'; }
# expect_eq WHAT GOT WANT
expect_eq() { [ "$2" = "$3" ] || fail "$1: got '$2', want '$3'"; ok "$1 = $3"; }
