#!/bin/sh
# The worst tick against the typical one (bench/worst_tick.c), callgrind, same run: the
# instructions of every single tick of the loop object over the fuzz corpora
# (fixtures/fuzz/fuzz_session: datagram streams of every shape the session accepts or drops;
# fixtures/fuzz/fuzz_safety_world: the property fuzzer's seeds, every mode, start-ups,
# restarts, losses, arbitrary replies), grouped by what the tick was (cyclic, init, sync,
# dropped, ended), against the median steady mode-4 tick of the same axis count (the full
# path of bench/tick.c). Goal: the worst tick at most 1.3x the typical. Then where the worst
# ticks spend their instructions (callgrind_annotate, inclusive, the library's functions).
# About 3 minutes (one callgrind dump per tick, some 44000 ticks); WORST_TICK_MAX_INPUTS=N
# takes the first N inputs of each corpus only.
#   Usage: sh bench/worst_tick.sh BUILD_DIR
set -eu
build=${1:?usage: sh bench/worst_tick.sh BUILD_DIR}
command -v valgrind >/dev/null 2>&1 || { echo "worst_tick: valgrind not installed, skipped"; exit 0; }
[ -f /usr/include/valgrind/callgrind.h ] || { echo "worst_tick: valgrind/callgrind.h missing, skipped"; exit 0; }
mkdir -p "$build/bench"
b=$build/bench/worst_tick
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -g -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host -o "$b" \
    bench/worst_tick.c lib/sim/c4gsim_fixtures.c "$build/lib/libc4gopen.a" -lm
tmp=$(mktemp -d "${TMPDIR:-/tmp}/c4g-worst-tick.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM
cg() {  # cg ARGS...: the program under callgrind, each tick's line on stdout
    valgrind --tool=callgrind --collect-atstart=no --compress-strings=no \
        --callgrind-out-file="$tmp/cg" "$b" --base "$tmp/cg" "$@" 2>"$tmp/vg.err" ||
        { echo "worst_tick: $* failed:" >&2; tail -n 5 "$tmp/vg.err" >&2; exit 1; }
}
max=${WORST_TICK_MAX_INPUTS:-1000000}   # a quick look: the first N inputs of each corpus
# shellcheck disable=SC2046 # one argument per input file
cg session $(ls fixtures/fuzz/fuzz_session/* | head -n "$max") > "$tmp/ticks"
# shellcheck disable=SC2046
cg world $(ls fixtures/fuzz/fuzz_safety_world/* | head -n "$max") >> "$tmp/ticks"
# the typical tick at each axis count met (0: before any init packet, against 6 axes)
for n in $(awk '$1 == "tick" { print ($5 == 0) ? 6 : $5 }' "$tmp/ticks" | sort -un); do
    cg typical "$n" | awk '$1 == "tick" { print $6 }' | sort -n |
        awk -v n="$n" '{ v[NR] = $1 } END { print n, v[int((NR + 1) / 2)] }' >> "$tmp/typical"
done
echo "one tick of the loop object (c4g_loop_rx + c4g_loop_reply + c4g_loop_sent), callgrind Ir, over the fuzz corpora"
awk 'NR == FNR { typ[$1] = $2; next }
     $1 != "tick" { next }
     { src = $2; sub("^.*fixtures/fuzz/", "", src); c = src; sub("/.*", "", c)
       ax = ($5 == 0) ? 6 : $5; r = $6 / typ[ax]; k = c " " $4
       n[k]++; if (!(k in mx) || $6 > mx[k]) { mx[k] = $6; at[k] = src " tick " $3; rr[k] = r; axk[k] = $5 }
       if (r > worst) { worst = r; wk = $4; wir = $6; wat = src " tick " $3; wax = ax }
       if ($4 == "cyclic" && r > cworst) { cworst = r; cir = $6; cat_ = src " tick " $3; cax = ax } }
     END {
       for (a in typ) printf "typical steady mode-4 tick, %2d axes: %6d Ir (median of 200)\n", a, typ[a]
       printf "%-18s %-8s %7s %8s %6s  %s\n", "corpus", "tick", "ticks", "max Ir", "x typ", "the worst one"
       for (k in n) { split(k, p, " ")
         printf "%-18s %-8s %7d %8d %5.2fx  %s (%d axes)\n", p[1], p[2], n[k], mx[k], rr[k], at[k], axk[k] | "sort" }
       close("sort")
       printf "worst cyclic tick: %d Ir = %.2fx the typical %d-axis tick (%s); goal <= 1.3x: %s\n",
         cir, cworst, cax, cat_, (cworst <= 1.3) ? "met" : "NOT"
       printf "worst tick of any kind: %d Ir (%s) = %.2fx the typical %d-axis tick (%s); goal <= 1.3x: %s\n",
         wir, wk, worst, wax, wat, (worst <= 1.3) ? "met" : "NOT"
       print wat > "'"$tmp/worst_any"'"; print cat_ > "'"$tmp/worst_cyclic"'" }' "$tmp/typical" "$tmp/ticks"
# where the two worst ticks go: the kept dump, inclusive costs of the library's functions
for w in worst_cyclic worst_any; do
    read -r src _ idx < "$tmp/$w"
    kept=$(cg --keep "fixtures/fuzz/$src" "$idx" "$(case $src in fuzz_session/*) echo session ;; *) echo world ;; esac)" \
        "fixtures/fuzz/$src" | sed -n 's/^kept //p')
    echo "$w ($src tick $idx), inclusive Ir of the library's functions:"
    callgrind_annotate --inclusive=yes "$kept" 2>/dev/null | sed 's/ *\[.*\]//; s|/[^ ]*/lib/|lib/|' |
        grep -E ' lib/(wire|engine|loop)/' | grep -v 'cold' | awk '!seen[$0]++' | head -n 8 | sed 's/^/  /'
done
