# Shared helpers for tests/e2e/server_*.sh (sourced). POSIX sh.
# Usage in a test: . tests/e2e/server_helpers/lib.sh "$1"
set -u
BUILD=${1:-build}
SRV=$BUILD/bin/c4g-server
SIM=$BUILD/bin/c4g-sim
STUB=$BUILD/e2e-server/ctrl_stub
T=$(mktemp -d "${TMPDIR:-/tmp}/c4g-srv-e2e.XXXXXX")
PIDS=""
FAILS=0
CHECKS=0

srv_cleanup() {
    for p in $PIDS; do kill "$p" 2>/dev/null; done
    for p in $PIDS; do wait "$p" 2>/dev/null; done
    # C4G_E2E_KEEP=DIR keeps the run's files (logs, JSON, pcap, moni) in DIR
    [ -n "${C4G_E2E_KEEP:-}" ] && { rm -rf "$C4G_E2E_KEEP"; cp -r "$T" "$C4G_E2E_KEEP"; }
    rm -rf "$T"
}
trap srv_cleanup EXIT
trap 'exit 130' INT TERM

[ -x "$SRV" ] || { echo "server e2e: $SRV not built (make BUILD=$BUILD all)"; exit 1; }

build_stub() {
    mkdir -p "$BUILD/e2e-server"
    if [ ! -x "$STUB" ] || [ tests/e2e/server_helpers/ctrl_stub.c -nt "$STUB" ] || \
       [ "$BUILD/lib/libc4gopen.a" -nt "$STUB" ]; then
        ${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -Werror \
            -Iinclude -Ilib/sim -Ilib/host -o "$STUB" tests/e2e/server_helpers/ctrl_stub.c lib/sim/c4gsim_fixtures.c "$BUILD/lib/libc4gopen.a" -lm \
            || { echo "server e2e: cannot build ctrl_stub"; exit 1; }
    fi
}

. tests/e2e/helpers/wait.sh
udp_bound() { ss -Huln "sport = :$1" | grep -q .; }   # some socket is bound to UDP port $1
srv_up() { grep -q "listening on" "$T/$1.err" 2>/dev/null || ! kill -0 "$SPID" 2>/dev/null; }
srv_gone() { ! kill -0 "$SPID" 2>/dev/null; }

# start_server NAME PORT [args...]: background server, JSON in $T/NAME.json, logs in $T/NAME.err.
# Returns once the server printed "listening on" (its socket is bound), so the controller's
# first packet never races the server's start-up. The loss timeout is 2 s unless a test sets
# its own: the controllers here are ordinary processes that a busy host can stop for longer
# than 10 periods (100 ms seen), which would measure the host's scheduler, not the server.
start_server() {
    name=$1; port=$2; shift 2
    "$SRV" -p "$port" -c 127.0.0.1 --idle-timeout 15 --max-seconds 45 --json "$T/$name.json" \
        --lost-timeout-ms 2000 "$@" >"$T/$name.out" 2>"$T/$name.err" &
    SPID=$!
    PIDS="$PIDS $SPID"
    wait_until 30 srv_up "$name"
    grep -q "listening on" "$T/$name.err" 2>/dev/null || { echo "server $name did not start:"; cat "$T/$name.err"; }
}

# wait_server: waits for the last started server (it ends by itself: 504, idle or
# --max-seconds), sets SRC (its exit code)
wait_server() {
    wait_until 60 srv_gone || kill "$SPID" 2>/dev/null
    wait "$SPID"; SRC=$?
}

kv() { sed -n "s/^$2=//p" "$1" | head -n 1; }              # key=value files (stub)
jv() { grep -o "\"$2\":[^,}]*" "$1" | head -n 1 | cut -d: -f2- | tr -d '"'; }   # flat JSON

ok() {  # ok DESCRIPTION COMMAND...
    desc=$1; shift
    CHECKS=$((CHECKS + 1))
    if "$@"; then echo "  ok   $desc"; else echo "  FAIL $desc"; FAILS=$((FAILS + 1)); fi
}
eq() { [ "$1" = "$2" ] || { echo "       got '$1', want '$2'"; return 1; }; }
ge() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 >= b + 0) }' || { echo "       got $1, want >= $2"; return 1; }; }
le() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 <= b + 0) }' || { echo "       got $1, want <= $2"; return 1; }; }
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }' || { echo "       got $1, want $2 +/- $3"; return 1; }; }
has() { grep -q -- "$2" "$1" || { echo "       '$2' not in $1"; return 1; }; }

dump() {  # dump NAME: show logs of a run (on failure); binary captures are skipped
    for f in "$T/$1".*; do
        case $f in *.pcap) continue ;; esac
        [ -f "$f" ] && { echo "--- $f"; tail -n 25 "$f"; }
    done
}

finish() {
    echo "$(basename "$0" .sh): $((CHECKS - FAILS))/$CHECKS checks passed"
    [ "$FAILS" -eq 0 ]
}

# run_sim NAME PORT SCENARIO [server args...]: server + c4g-sim (extra sim options in
# $SIM_ARGS); sets SIMRC and SRC; sim JSON in $T/NAME.sim.json. The server is an ordinary
# process that a busy host can stop for 100 ms (50 periods): unless a test is about the
# 10-in-a-row rule (it then puts --max-miss 10 in $SIM_ARGS), the simulator counts such a
# stall as missing replies instead of ending the session with ERR_C4GOPEN_UDP.
run_sim() {
    name=$1; port=$2; scn=$3; shift 3
    start_server "$name" "$port" "$@"
    # shellcheck disable=SC2086
    timeout 50 "$SIM" -p "$port" -S "$scn" --json --max-miss 500 ${SIM_ARGS:-} >"$T/$name.sim.json" 2>"$T/$name.sim.err"
    SIMRC=$?
    wait_server
}

# run_stub NAME PORT [stub args...] -- [server args...]
run_stub() {
    name=$1; port=$2; shift 2
    sargs=""
    while [ $# -gt 0 ] && [ "$1" != "--" ]; do sargs="$sargs $1"; shift; done
    [ $# -gt 0 ] && shift
    start_server "$name" "$port" "$@"
    # shellcheck disable=SC2086
    timeout 50 "$STUB" --port "$port" --reply-us 50000 $sargs >"$T/$name.stub" 2>"$T/$name.stub.err"
    STUBRC=$?
    wait_server
}

# The host held up an exchange of run NAME: a reply came after the controller's deadline
# (the stub's stale replies, c4g-sim's late or stale ones). A test about missing replies
# cannot tell such a reply from one the server left out.
stub_stalled() { [ "$(kv "$T/$1.stub" stale)" -gt 0 ] 2>/dev/null; }
sim_stalled() { [ $(( $(jv "$T/$1.sim.json" late) + $(jv "$T/$1.sim.json" stale) )) -gt 0 ] 2>/dev/null; }

# again_while PRED RUNNER NAME ARGS...: runs RUNNER NAME ARGS (run_stub, run_sim or a test's
# own runner), and again, $AGAIN_MAX runs at most (default 3), while PRED NAME says the host
# disturbed the run. PRED must need evidence of the disturbance, so that a real fault fails
# every run.
again_while() {
    apred=$1; shift; atry=1
    "$@"
    while [ "$atry" -lt "${AGAIN_MAX:-3}" ] && "$apred" "$2"; do
        echo "       (run $2, attempt $atry: the host held it up ($apred): again)"
        atry=$((atry + 1))
        "$@"
    done
}

# robot position of OPEN axis N (1-based) from a c4g-sim JSON summary
simpos() { grep -o '"robot":\[.*\]' "$1" | tr '{' '\n' | sed -n "$(($2 + 1))p" | grep -o '"pos":[-0-9.e+]*' | cut -d: -f2; }
