#!/bin/sh
# Instructions per tick under callgrind (deterministic, unlike time on a shared machine):
# Ir(2N ticks) - Ir(N ticks), divided by N, removes the start-up cost.
set -eu
build=$1
b="$build/bench/bench_wire"
command -v valgrind >/dev/null 2>&1 || { echo "callgrind: valgrind not installed, skipped"; exit 0; }
ir() {
  out=$(mktemp)
  valgrind --tool=callgrind --callgrind-out-file="$out" "$b" --only "$1" "$2" "$3" >/dev/null 2>&1
  sed -n 's/^summary: *//p; s/^totals: *//p' "$out" | head -n 1
  rm -f "$out"
}
n=20000
printf '%-6s %16s %16s %8s\n' axes "engine Ir/tick" "memcpy Ir/tick" ratio
for axes in 6 20; do
  e1=$(ir engine $axes $n); e2=$(ir engine $axes $((2 * n)))
  m1=$(ir memcpy $axes $n); m2=$(ir memcpy $axes $((2 * n)))
  awk -v a="$axes" -v e1="$e1" -v e2="$e2" -v m1="$m1" -v m2="$m2" -v n="$n" 'BEGIN {
    e = (e2 - e1) / n; m = (m2 - m1) / n;
    printf "%-6s %16.0f %16.0f %7.1fx\n", a, e, m, e / m }'
done
