#!/bin/sh
# c4g-ident end to end on a long capture, and its per-axis fit against scipy, same run:
#   - a generated session (bench/gen_capture.c --dynamics): 10 minutes x 6 axes at 1 ms, D5
#     the current of a known axis model (inertia, viscous, Coulomb and Stribeck friction,
#     offset, noise), about 343 MB; written once into a temporary directory;
#   - `c4g-ident fit` on it: wall time (best of IDENT_BENCH_RUNS, default 2) and peak RSS (GNU
#     time's %M), against the targets 10 s and 1 GB on a 2-core machine;
#   - the fit of each axis (bench/ident_fit.cpp: c4g-ident's own fit on the samples it used)
#     against scipy.optimize.least_squares ('trf', Huber, analytic Jacobian:
#     bench/ident_scipy.py) on the same samples, best of 3 each, when python3-scipy is there.
# Knobs: IDENT_BENCH_MINUTES (10), IDENT_BENCH_RUNS (2).
#   Usage: sh bench/ident_bench.sh BUILD_DIR
set -eu
build=${1:?usage: sh bench/ident_bench.sh BUILD_DIR}
minutes=${IDENT_BENCH_MINUTES:-10}
runs=${IDENT_BENCH_RUNS:-2}
ident=$build/bin/c4g-ident
if [ ! -x /usr/bin/time ]; then
    echo "ident_bench: /usr/bin/time (GNU time) not installed, skipped"
    exit 0
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/c4g-ident-bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM
mkdir -p "$build/bench"
cc=${CC:-cc}
cxx=${CXX:-g++}
$cc -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host \
    -o "$build/bench/gen_capture" bench/gen_capture.c lib/host/c4gh_pcap.c lib/sim/c4gsim_fixtures.c \
    "$build/lib/libc4gopen.a" -lpcap -lm
$cxx -std=c++17 -O2 -Wall -Wextra -Iinclude -isystem /usr/include/eigen3 -Itools/c4g-ident \
    -o "$build/bench/ident_fit" bench/ident_fit.cpp tools/c4g-ident/signal.cpp tools/c4g-ident/fit.cpp \
    tools/c4g-ident/excite.cpp -lceres -lglog -lpthread -lm

"$build/bench/gen_capture" --dynamics --minutes "$minutes" "$tmp/long.pcap"
size=$(wc -c < "$tmp/long.pcap")
echo "capture: $minutes min x 6 axes at 1 ms, $((size / 1000000)) MB"
best=''
rss=0
i=0
while [ "$i" -lt "$runs" ]; do
    /usr/bin/time -f '%e %M' -o "$tmp/time" "$ident" fit "$tmp/long.pcap" --json -o "$tmp/arm1.ini" \
        > "$tmp/fit.json"
    read -r w m < "$tmp/time"
    best=$(awk -v a="$best" -v b="$w" 'BEGIN { print (a == "" || b < a) ? b : a }')
    [ "$m" -gt "$rss" ] && rss=$m
    i=$((i + 1))
done
axes=$(grep -o '"identifiable": *true' "$tmp/fit.json" | wc -l)
echo "c4g-ident fit, end to end: $best s wall (best of $runs; target <= 10 s), peak RSS $((rss / 1024)) MB (target <= 1024 MB), $axes axes identified"
awk -v w="$best" -v m="$rss" 'BEGIN { printf "  -> %s wall, %s memory\n", (w <= 10) ? "within" : "OVER", (m <= 1048576) ? "within" : "OVER" }'

# the samples each axis was fitted to (not timed: 3.5 M lines of text)
"$ident" fit "$tmp/long.pcap" -q --samples "$tmp/samples"
"$build/bench/ident_fit" --runs 3 "$tmp"/samples/*.csv > "$tmp/ours.txt"
# the first Python with SciPy: python3 on the PATH, else the system's (Debian's python3-scipy)
py=''
for p in python3 /usr/bin/python3; do
    if command -v "$p" >/dev/null 2>&1 && "$p" -c 'import scipy' 2>/dev/null; then py=$p; break; fi
done
if [ -n "$py" ]; then
    "$py" bench/ident_scipy.py --runs 3 "$tmp"/samples/*.csv > "$tmp/scipy.txt"
    echo "per-axis fit, same samples (best of 3): c4g-ident (Ceres) vs scipy least_squares (trf, huber, analytic J)"
    printf '  %-6s %9s %-16s %10s %10s %8s %12s %12s\n' axis samples variant "ours s" "scipy s" ratio "Ja ours" "Ja scipy"
    awk 'NR == FNR { s[FNR] = $4; j[FNR] = $5; next }
         { n = split($1, p, "_axis"); ax = p[n]; sub(/\.csv$/, "", ax)
           r = (($4 > 0) ? s[FNR] / $4 : 0); tot_o += $4; tot_s += s[FNR]
           printf "  %-6s %9d %-16s %10.3f %10.3f %7.1fx %12.6g %12.6g\n", ax, $2, $3, $4, s[FNR], r, $5, j[FNR] }
         END { printf "  all axes: ours %.3f s, scipy %.3f s: scipy / ours = %.1fx (target >= 2x)\n", tot_o, tot_s, (tot_o > 0) ? tot_s / tot_o : 0 }' \
        "$tmp/scipy.txt" "$tmp/ours.txt"
else
    echo "per-axis fit: python3-scipy not installed, the comparison is skipped"
    cat "$tmp/ours.txt"
fi
