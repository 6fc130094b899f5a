#!/bin/sh
# c4g-server's CPU per packet at 1 kHz on loopback against a bare blocking recvfrom/sendto
# echo loop (tests/e2e/helpers/udp_echo.c) driven the same way in the same run, 6 and
# 20 axes, mode 0: CPU time (user + system) of the whole process, every thread, over the
# controller stub's run, divided by the replies it received; and the round-trip p50 / p99
# the stub measured. Goal: CPU per packet at most 1.2x the echo loop's, p99 no worse.
# CPU time is the kernel's on-CPU time of each thread in ns (/proc/PID/task/*/schedstat);
# where that file is missing, utime + stime of /proc/PID/stat (10 ms clock ticks: then
# BENCH_SECONDS, default 10, sets the resolution). BENCH_RUNS (default 3) pairs of runs,
# echo and server alternating; the medians are shown. Extra server options: SERVER_OPTS.
# Usage: sh bench/server_cpu.sh BUILD_DIR
set -u
build=${1:-build}
secs=${BENCH_SECONDS:-10}
runs=${BENCH_RUNS:-3}
port=${BENCH_PORT:-31090}
tmpname=c4g-srvcpu
. bench/lib/server_common.sh
tck=$(getconf CLK_TCK)
ticks=$((secs * 1000))
# CPU time of a process in ns: the sum of its threads' on-CPU time, else utime + stime
# (fields 14 and 15, after the command name) in clock ticks
cpu_ns() {
    if [ -r "/proc/$1/schedstat" ]; then
        cat /proc/"$1"/task/*/schedstat 2>/dev/null | awk '{ s += $1 } END { printf "%.0f\n", s }'
    else
        sed 's/^.*) //' "/proc/$1/stat" | awk -v t="$tck" '{ printf "%.0f\n", ($12 + $13) / t * 1e9 }'
    fi
}
# run_one NAME: the process in $bpid serves; the stub runs; prints "us_per_packet p50 p99"
run_one() {
    sleep 0.3
    c0=$(cpu_ns "$bpid")
    "$stub" --port "$port" --period-ms 1 --arms "$arms" --reply-us 900 --quiet \
        --script "0:$ticks" >"$tmp/$1" 2>/dev/null
    c1=$(cpu_ns "$bpid")
    kill "$bpid" 2>/dev/null; wait "$bpid" 2>/dev/null; bpid=""
    awk -v c0="$c0" -v c1="$c1" -v n="$(kv "$tmp/$1" rtt_n)" \
        -v p50="$(kv "$tmp/$1" rtt_p50_us)" -v p99="$(kv "$tmp/$1" rtt_p99_us)" \
        'BEGIN { printf "%.2f %s %s %d\n", (n > 0 ? (c1 - c0) / 1e3 / n : 0), p50, p99, n }'
}
# median of the numbers on stdin
median() { sort -n | awk '{ v[NR] = $1 } END { if (NR == 0) print 0; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "c4g-server CPU per packet at 1 kHz on loopback, $runs x $secs s per configuration ($(nproc) CPUs, medians)"
printf '%-5s %-16s %8s %12s %8s %8s %8s %s\n' axes process replies "CPU us/pkt" "x echo" "p50 us" "p99 us" "goal (<= 1.2x, p99 <= echo)"
for arms in 6 10,10; do
    n=6; [ "$arms" = "10,10" ] && n=20
    : >"$tmp/e$n"; : >"$tmp/s$n"
    r=0
    while [ "$r" -lt "$runs" ]; do
        "$echo_bin" "$port" & bpid=$!
        run_one "echo$n" >>"$tmp/e$n"
        # shellcheck disable=SC2086
        "$srv" -p "$port" -c 127.0.0.1 -q --idle-timeout 10 --max-seconds $((secs + 30)) \
            ${SERVER_OPTS:-} & bpid=$!
        run_one "srv$n" >>"$tmp/s$n"
        r=$((r + 1))
    done
    e_cpu=$(cut -d' ' -f1 "$tmp/e$n" | median); e_p50=$(cut -d' ' -f2 "$tmp/e$n" | median)
    e_p99=$(cut -d' ' -f3 "$tmp/e$n" | median); e_n=$(cut -d' ' -f4 "$tmp/e$n" | median)
    s_cpu=$(cut -d' ' -f1 "$tmp/s$n" | median); s_p50=$(cut -d' ' -f2 "$tmp/s$n" | median)
    s_p99=$(cut -d' ' -f3 "$tmp/s$n" | median); s_n=$(cut -d' ' -f4 "$tmp/s$n" | median)
    printf '%-5s %-16s %8s %12s %8s %8s %8s\n' "$n" "echo loop" "$e_n" "$e_cpu" "1.00x" "$e_p50" "$e_p99"
    awk -v n="$n" -v c="$s_cpu" -v e="$e_cpu" -v p50="$s_p50" -v p99="$s_p99" -v ep99="$e_p99" -v k="$s_n" 'BEGIN {
        r = (e > 0 ? c / e : 0);
        printf "%-5s %-16s %8s %12s %7.2fx %8s %8s %s\n", n, "c4g-server", k, c, r, p50, p99,
            ((r <= 1.2 ? "CPU met" : "CPU NOT met") ", " (p99 + 0 <= ep99 + 0 ? "p99 met" : "p99 NOT met")) }'
done
echo "(CPU: on-CPU time of every thread of the process over the stub's run, per reply; round trip ="
echo " controller send -> reply received. A shared machine moves the p99 by tens of us run to run.)"
