#!/bin/sh
# c4g-server latency benchmark at 1 kHz (T_SMP+ = 1 ms, manual chapter 21), 6 and 20 open
# axes, on loopback:
#   - round-trip latency seen by the controller (the e2e controller stub: send -> reply,
#     p50 / p99 / p99.9 / max, replies later than 500 us = T_CYCLE1),
#   - the server's own cycle time (rx -> sent, its --json-out summary) and its late replies,
#   - an in-run baseline: a bare UDP echo loop (tests/e2e/helpers/udp_echo.c) measured
#     the same way in the same run, so the numbers separate the machine from the server,
#   - the latency seen by c4g-sim itself (min / avg / p50 / p99 / p99.9 / max), 6 and 20 axes.
# Default: BENCH_SECONDS=10 per configuration; C4G_BENCH_LONG=1 runs 60 s each.
# Extra server options (e.g. "--rt --cpu 1" on a PREEMPT-RT machine): SERVER_OPTS.
set -u
build=${1:-build}
secs=${BENCH_SECONDS:-10}
[ "${C4G_BENCH_LONG:-0}" = 1 ] && secs=60
port=${BENCH_PORT:-31080}
sim=$build/bin/c4g-sim
tmpname=c4g-bench
. bench/lib/server_common.sh
ticks=$((secs * 1000))
jv() { grep -o "\"$2\":[^,}]*" "$1" | head -n 1 | cut -d: -f2-; }

row() {  # row LABEL STUBFILE [SERVERJSON]
    if [ -n "${3:-}" ]; then
        srvcol=$(printf '%6s %6s %7s %7s %6s' "$(jv "$3" cycle_p50_us)" "$(jv "$3" cycle_p99_us)" \
            "$(jv "$3" cycle_p999_us)" "$(jv "$3" cycle_max_us | cut -d. -f1)" "$(jv "$3" late)")
    else
        srvcol=$(printf '%6s %6s %7s %7s %6s' - - - - -)
    fi
    printf '%-22s %8s %8s %8s %8s %8s %7s | %s\n' "$1" "$(kv "$2" rtt_n)" "$(kv "$2" rtt_p50_us)" \
        "$(kv "$2" rtt_p99_us)" "$(kv "$2" rtt_p999_us)" "$(kv "$2" rtt_max_us)" \
        "$(kv "$2" rtt_over500)" "$srvcol"
}

echo "c4g-server latency at 1 kHz on loopback, $secs s per configuration ($(nproc) CPUs, $(uname -r))"
printf '%-22s %8s %8s %8s %8s %8s %7s | %s\n' "configuration" "replies" "p50 us" "p99 us" \
    "p99.9 us" "max us" ">500us" "server cycle: p50  p99  p99.9    max   late"
for arms in 6 10,10; do
    n=6; [ "$arms" = "10,10" ] && n=20
    # baseline: bare UDP echo, same controller, same rate
    "$echo_bin" "$port" & bpid=$!
    sleep 0.2
    "$stub" --port "$port" --period-ms 1 --arms "$arms" --reply-us 900 --quiet \
        --script "0:$ticks" >"$tmp/echo$n" 2>/dev/null
    kill "$bpid" 2>/dev/null; wait "$bpid" 2>/dev/null; bpid=""
    row "baseline echo, $n axes" "$tmp/echo$n"
    # c4g-server
    # shellcheck disable=SC2086
    "$srv" -p "$port" --controller 127.0.0.1 -q --idle-timeout 10 --max-seconds $((secs + 30)) \
        --json-out "$tmp/srv$n.json" ${SERVER_OPTS:-} & bpid=$!
    sleep 0.3
    "$stub" --port "$port" --period-ms 1 --arms "$arms" --reply-us 900 --quiet \
        --script "0:$ticks,504:1" >"$tmp/stub$n" 2>/dev/null
    wait "$bpid" 2>/dev/null; bpid=""
    row "c4g-server, $n axes" "$tmp/stub$n" "$tmp/srv$n.json"
done
# the same seen by the simulator (its own clock, socket path and percentiles), 6 and 20 axes
if [ -x "$sim" ]; then
    for axes in 6 10,10; do
        # shellcheck disable=SC2086
        "$srv" -p "$port" --controller 127.0.0.1 -q --idle-timeout 10 --max-seconds $((secs + 30)) \
            --json-out "$tmp/srvsim.json" ${SERVER_OPTS:-} & bpid=$!
        sleep 0.3
        "$sim" -p "$port" -T 1 --axes "$axes" -n "$ticks" --json -q >"$tmp/sim.json" 2>/dev/null
        kill "$bpid" 2>/dev/null; wait "$bpid" 2>/dev/null; bpid=""
        lat=$(grep -o '"latency_us":{[^}]*}' "$tmp/sim.json")
        echo "c4g-sim, axes $axes, 1 ms: $lat, late $(jv "$tmp/sim.json" late), missing $(jv "$tmp/sim.json" missing); server p99 $(jv "$tmp/srvsim.json" cycle_p99_us) us, late $(jv "$tmp/srvsim.json" late)"
    done
fi
echo "(round trip = controller send -> reply received; server cycle = recvfrom return -> sendto"
echo " return; late = later than 500 us. Without --rt (SCHED_FIFO, mlockall) on a shared, non-RT"
echo " kernel the tail is the scheduler's, as the baseline row shows.)"
