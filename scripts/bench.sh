#!/bin/sh
# Builds and runs every bench/bench_*.c (each prints its own table with an in-run
# baseline), then every bench/*.sh with the build directory as $1; last, every line that
# states a goal ("met" or "NOT") again, together, with the bench that printed it.
set -eu
build=$1
mkdir -p "$build/bench"
log="$build/bench/bench.log"
: >"$log"
(
for f in bench/bench_*.c; do
  [ -f "$f" ] || continue
  b="$build/bench/$(basename "$f" .c)"
  ${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host -o "$b" "$f" \
    lib/sim/c4gsim_fixtures.c lib/host/c4gh_csv.c \
    "$build/lib/libc4gopen.a" -lm || { echo "bench: FAILED $(basename "$f" .c) (build)"; continue; }
  echo "== $(basename "$f" .c)"
  "$b" || echo "bench: FAILED $(basename "$f" .c)"
done
for s in bench/*.sh; do
  [ -f "$s" ] || continue
  echo "== $(basename "$s" .sh)"
  sh "$s" "$build" || echo "bench: FAILED $(basename "$s" .sh)"
done
) 2>&1 | tee "$log"
# the pipeline's status is tee's: a failed bench leaves its mark in the log
if grep -q '^bench: FAILED' "$log"; then failed=1; else failed=0; fi
echo "== goals (every line above with met or NOT)"
awk '/^== [a-z_]+$/ { b = $2 } /(^|[^A-Za-z])(met|NOT)([^A-Za-z]|$)/ && !/^== / { printf "%-18s %s\n", b, $0 }' "$log"
exit $failed
