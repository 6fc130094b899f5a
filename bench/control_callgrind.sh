#!/bin/sh
# Instructions per tick of the whole PC path (decode + engine step + caller fill + finish
# with the safety filter + encode, 20 axes in mode 4) under callgrind, against the memcpy
# baseline of the same run: Ir(2N ticks) - Ir(N ticks), divided by N.
set -eu
build=$1
b="$build/bench/bench_control"
command -v valgrind >/dev/null 2>&1 || { echo "callgrind: valgrind not installed, skipped"; exit 0; }
ir() {
  out=$(mktemp)
  valgrind --tool=callgrind --callgrind-out-file="$out" "$b" --only "$1" "$2" >/dev/null 2>&1
  sed -n 's/^summary: *//p; s/^totals: *//p' "$out" | head -n 1
  rm -f "$out"
}
n=5000
printf '%-8s %14s %8s\n' path "Ir/tick" "x memcpy"
m1=$(ir memcpy $n); m2=$(ir memcpy $((2 * n)))
for path in wire full; do
  e1=$(ir $path $n); e2=$(ir $path $((2 * n)))
  awk -v p="$path" -v e1="$e1" -v e2="$e2" -v m1="$m1" -v m2="$m2" -v n="$n" 'BEGIN {
    e = (e2 - e1) / n; m = (m2 - m1) / n;
    printf "%-8s %14.0f %7.1fx\n", p, e, e / m }'
done
