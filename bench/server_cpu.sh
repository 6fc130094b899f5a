#!/bin/sh
# c4g-server's CPU per packet at 1 kHz on loopback against a bare blocking recvfrom/sendto
# echo loop (tests/e2e/server_helpers/udp_echo.c) driven the same way in the same run, 6 and
# 20 axes, mode 0: user + system time of the whole process (every thread) from
# /proc/PID/stat over the controller stub's run, divided by the replies it received; and
# the round-trip p50 / p99 the stub measured. Goal: CPU per packet at most 1.2x the echo
# loop's, p99 no worse. /proc/PID/stat counts in clock ticks (10 ms): BENCH_SECONDS
# (default 10) sets the resolution. Extra server options: SERVER_OPTS.
# Usage: sh bench/server_cpu.sh BUILD_DIR
set -u
build=${1:-build}
secs=${BENCH_SECONDS:-10}
port=${BENCH_PORT:-31090}
srv=$build/bin/c4g-server
stub=$build/e2e-server/ctrl_stub
echo_bin=$build/e2e-server/udp_echo
tmp=$(mktemp -d "${TMPDIR:-/tmp}/c4g-srvcpu.XXXXXX")
bpid=""
cleanup() { [ -n "$bpid" ] && kill "$bpid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
trap 'exit 130' INT TERM
mkdir -p "$build/e2e-server"
cc=${CC:-cc}
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Iinclude -Itools/common -o "$stub" \
    tests/e2e/server_helpers/ctrl_stub.c tools/common/c4g_fixtures.c "$build/lib/libc4gopen.a" -lm || exit 1
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -o "$echo_bin" \
    tests/e2e/server_helpers/udp_echo.c || exit 1
tck=$(getconf CLK_TCK)
ticks=$((secs * 1000))
kv() { sed -n "s/^$2=//p" "$1" | head -n 1; }
# utime + stime of a process, in clock ticks (fields 14 and 15 after the command name)
cpu_ticks() { sed 's/^.*) //' "/proc/$1/stat" | awk '{ print $12 + $13 }'; }
# run_one NAME: the process in $bpid serves; the stub runs; prints "us_per_packet p50 p99"
run_one() {
    sleep 0.3
    c0=$(cpu_ticks "$bpid")
    "$stub" --port "$port" --period-ms 1 --arms "$arms" --reply-us 900 --quiet \
        --script "0:$ticks" >"$tmp/$1" 2>/dev/null
    c1=$(cpu_ticks "$bpid")
    kill "$bpid" 2>/dev/null; wait "$bpid" 2>/dev/null; bpid=""
    awk -v c0="$c0" -v c1="$c1" -v t="$tck" -v n="$(kv "$tmp/$1" rtt_n)" \
        -v p50="$(kv "$tmp/$1" rtt_p50_us)" -v p99="$(kv "$tmp/$1" rtt_p99_us)" \
        'BEGIN { printf "%.1f %s %s %d\n", (n > 0 ? (c1 - c0) / t * 1e6 / n : 0), p50, p99, n }'
}
echo "c4g-server CPU per packet at 1 kHz on loopback, $secs s per configuration ($(nproc) CPUs)"
printf '%-5s %-16s %8s %12s %8s %8s %8s %s\n' axes process replies "CPU us/pkt" "x echo" "p50 us" "p99 us" "goal (<= 1.2x, p99 <= echo)"
for arms in 6 10,10; do
    n=6; [ "$arms" = "10,10" ] && n=20
    "$echo_bin" "$port" & bpid=$!
    set -- $(run_one "echo$n"); e_cpu=$1; e_p50=$2; e_p99=$3; e_n=$4
    # shellcheck disable=SC2086
    "$srv" -p "$port" -c 127.0.0.1 -q --idle-timeout 10 --max-seconds $((secs + 30)) \
        ${SERVER_OPTS:-} & bpid=$!
    set -- $(run_one "srv$n"); s_cpu=$1; s_p50=$2; s_p99=$3; s_n=$4
    printf '%-5s %-16s %8s %12s %8s %8s %8s\n' "$n" "echo loop" "$e_n" "$e_cpu" "1.00x" "$e_p50" "$e_p99"
    awk -v n="$n" -v c="$s_cpu" -v e="$e_cpu" -v p50="$s_p50" -v p99="$s_p99" -v ep99="$e_p99" -v k="$s_n" 'BEGIN {
        r = (e > 0 ? c / e : 0);
        printf "%-5s %-16s %8s %12s %7.2fx %8s %8s %s\n", n, "c4g-server", k, c, r, p50, p99,
            ((r <= 1.2 ? "CPU met" : "CPU NOT met") ", " (p99 + 0 <= ep99 + 0 ? "p99 met" : "p99 NOT met")) }'
done
echo "(CPU: utime + stime of the whole process over the stub's run, per reply; round trip ="
echo " controller send -> reply received. A shared machine moves the p99 by tens of us run to run.)"
