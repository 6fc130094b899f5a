#!/bin/sh
# c4g-replay on a long capture, against tshark and against the floor of any libpcap reader
# (bench/pcap_bare.c: pcap_next_ex and a sum of every byte), all in the same run:
#   - a generated session (bench/gen_capture.c): 10 minutes at 1 ms, 6 axes = 1.2 M cyclic
#     packets plus replies, about 343 MB; written once into a temporary directory;
#   - wall time, best of 3 runs (a shared 2-CPU machine: the best run is the least
#     disturbed), CPU time (user + system) and peak RSS (wait4's rusage) of
#     `c4g-replay summary`, `c4g-replay export`, `tshark -T fields` and pcap_bare;
#   - peak RSS of summary on a 1-minute capture against the long one;
#   - instructions per packet under callgrind: Ir(20 s) - Ir(10 s) over the packets between;
#   - the goals: summary's CPU at most 1.2x the bare loop's, tshark at least 50x summary's
#     time, export's CPU at most 5x summary's, each with "met" or "NOT".
# tshark is timed on the 1-minute capture and scaled per packet when the long one would
# take it longer than REPLAY_BENCH_TSHARK_MAX_S (180 s); the output says so.
# Knobs: REPLAY_BENCH_MINUTES (10), REPLAY_BENCH_RUNS (3), REPLAY_BENCH_EXPORT_RUNS (= RUNS).
#   Usage: sh bench/replay_bench.sh BUILD_DIR
set -eu
build=${1:?usage: sh bench/replay_bench.sh BUILD_DIR}
minutes=${REPLAY_BENCH_MINUTES:-10}
runs=${REPLAY_BENCH_RUNS:-3}
export_runs=${REPLAY_BENCH_EXPORT_RUNS:-$runs}
tshark_max=${REPLAY_BENCH_TSHARK_MAX_S:-180}
replay=$build/bin/c4g-replay
gen=$build/bench/gen_capture
bare=$build/bench/pcap_bare
cpu_run=$build/bench/cpu_run
tmp=$(mktemp -d "${TMPDIR:-/tmp}/c4g-replay-bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

mkdir -p "$build/bench"
cc=${CC:-cc}
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host \
    -o "$gen" bench/gen_capture.c lib/host/c4gh_pcap.c lib/sim/c4gsim_fixtures.c \
    "$build/lib/libc4gopen.a" -lpcap -lm
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -o "$bare" \
    bench/pcap_bare.c -lpcap
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -o "$cpu_run" bench/cpu_run.c

# 6 axes at 1 ms: 2 x 286 bytes a tick, 34.3 MB a minute. Keep a margin for the short
# captures and anything else writing to the same disk.
avail_kb=$(df -Pk "$tmp" | awk 'NR == 2 { print $4 }')
need_kb=$(( (minutes + 2) * 36000 ))
if [ "$avail_kb" -lt "$need_kb" ]; then
    fit=$(( avail_kb / 36000 - 2 ))
    [ "$fit" -ge 1 ] || { echo "replay_bench: $avail_kb KB free in $tmp, skipped"; exit 0; }
    echo "replay_bench: only $avail_kb KB free in $tmp: $fit minutes instead of $minutes"
    minutes=$fit
fi
long=$tmp/long.pcap
short=$tmp/short.pcap
"$gen" --minutes "$minutes" "$long"
"$gen" --minutes 1 "$short"
"$gen" --seconds 10 "$tmp/s10.pcap"
"$gen" --seconds 20 "$tmp/s20.pcap"
frames_long=$(( 2 * (12 + minutes * 60000) ))
frames_short=$(( 2 * (12 + 60000) ))
mb_long=$(awk -v b="$(wc -c < "$long")" 'BEGIN { printf "%.1f", b / 1e6 }')

# One run: "wall_us cpu_s rss_kb" (the command's output is thrown away). The CPU time is
# wait4's rusage to the microsecond (GNU time prints it to 10 ms, 5 % of summary's time).
run1() {
    if ! "$cpu_run" "$tmp/time" "$@" >/dev/null 2>"$tmp/err"; then
        echo "replay_bench: '$*' failed:" >&2
        tail -n 5 "$tmp/err" >&2
        return 1
    fi
    cat "$tmp/time"
}

# Best of N runs: "wall_s cpu_s rss_kb" (least wall and CPU time, most memory).
best() {
    n=$1
    shift
    : >"$tmp/runs"
    i=0
    while [ "$i" -lt "$n" ]; do
        run1 "$@" >>"$tmp/runs"
        i=$((i + 1))
    done
    awk 'NR == 1 || $1 < w { w = $1 } NR == 1 || $2 < c { c = $2 } $3 > m { m = $3 }
         END { printf "%.3f %.3f %d\n", w / 1e6, c, m }' "$tmp/runs"
}

row() {  # row LABEL "wall cpu rss" FRAMES [NOTE]
    # shellcheck disable=SC2086 # the three figures become $2..$4
    set -- "$1" $2 "$3" "${4:-}"
    awk -v l="$1" -v w="$2" -v c="$3" -v m="$4" -v f="$5" -v note="$6" 'BEGIN {
        printf "%-34s %9.3f %8.3f %10.0f %10.1f%s\n", l, w, c, w * 1e9 / f, m / 1024,
            (note == "") ? "" : "  " note }'
}

echo "c4g-replay on a generated session: $minutes min at 1 ms, 6 axes, $frames_long frames, $mb_long MB"
echo "(best of $runs runs; $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg))"
printf '%-34s %9s %8s %10s %10s\n' program "wall s" "CPU s" "wall ns/f" "peak MB"
b=$(best "$runs" "$bare" "$long")
row "pcap_bare (baseline)" "$b" "$frames_long"
s=$(best "$runs" "$replay" summary "$long")
row "c4g-replay summary" "$s" "$frames_long"
e=$(best "$export_runs" "$replay" export "$long")
row "c4g-replay export > /dev/null" "$e" "$frames_long" "(best of $export_runs)"
t=""
if command -v tshark >/dev/null 2>&1; then
    tsh() { best "$1" tshark -r "$2" -T fields -e frame.time_epoch -e udp.length; }
    t1=$(tsh 1 "$short")
    est=$(echo "$t1" | awk -v a="$frames_long" -v b="$frames_short" '{ printf "%.0f", $1 * a / b }')
    if [ "$est" -gt "$tshark_max" ]; then
        # too long on the whole capture: the 1-minute one, scaled per frame (memory as measured)
        t=$(tsh "$runs" "$short" | awk -v a="$frames_long" -v b="$frames_short" \
            '{ printf "%.3f %.3f %d\n", $1 * a / b, $2 * a / b, $3 }')
        row "tshark -T fields" "$t" "$frames_long" "scaled from the 1-minute capture (about $est s); peak MB of that run"
    else
        t=$(tsh "$runs" "$long")
        row "tshark -T fields" "$t" "$frames_long"
    fi
else
    echo "tshark not installed: no tshark row"
fi
s1=$(best "$runs" "$replay" summary "$short")

echo "ratios:"
if [ -n "$t" ]; then
    echo "$t $s" | awk '{ r = $1 / $4; printf "  tshark / summary, wall: %.0fx (CPU %.0fx); goal >= 50x: %s\n",
        r, $2 / $5, (r >= 50) ? "met" : "NOT" }'
fi
echo "$b $s" | awk '{ r = $5 / $2; printf "  summary CPU / bare loop CPU: %.2fx (wall %.2fx); goal <= 1.2x: %s\n",
    r, $4 / $1, (r <= 1.2) ? "met" : "NOT" }'
echo "$s $e" | awk '{ r = $5 / $2; printf "  export CPU / summary CPU: %.2fx (wall %.2fx); goal <= 5x: %s\n",
    r, $4 / $1, (r <= 5) ? "met" : "NOT" }'
echo "$s1 $s" | awk -v m="$minutes" '{ d = $6 - $3;
    printf "  summary peak RSS: 1 min %.1f MB, %d min %.1f MB; goal independent of length (within 1 MB): %s\n",
    $3 / 1024, m, $6 / 1024, (d <= 1024 && d >= -1024) ? "met" : "NOT met" }'

if command -v valgrind >/dev/null 2>&1; then
    ir() {
        out=$tmp/cg.out
        valgrind --tool=callgrind --callgrind-out-file="$out" "$@" >/dev/null 2>&1
        sed -n 's/^summary: *//p; s/^totals: *//p' "$out" | head -n 1
        rm -f "$out"
    }
    per=20000 # frames between the 10 s and the 20 s capture
    s10=$(ir "$replay" summary "$tmp/s10.pcap"); s20=$(ir "$replay" summary "$tmp/s20.pcap")
    b10=$(ir "$bare" "$tmp/s10.pcap"); b20=$(ir "$bare" "$tmp/s20.pcap")
    e10=$(ir "$replay" export "$tmp/s10.pcap"); e20=$(ir "$replay" export "$tmp/s20.pcap")
    awk -v s1="$s10" -v s2="$s20" -v b1="$b10" -v b2="$b20" -v e1="$e10" -v e2="$e20" -v n="$per" 'BEGIN {
        s = (s2 - s1) / n; b = (b2 - b1) / n; e = (e2 - e1) / n;
        printf "callgrind, Ir per frame (Ir(20 s) - Ir(10 s) over %d frames): summary %.0f, bare loop %.0f (%.2fx), export %.0f (%.2fx summary)\n",
            n, s, b, s / b, e, e / s }'
else
    echo "callgrind: valgrind not installed, skipped"
fi
echo "(wall ns/f: best wall time per frame; CPU: user + system of the best run by CPU; peak MB:"
echo " the largest RSS of the runs. pcap_bare reads and sums every captured byte, nothing else.)"
