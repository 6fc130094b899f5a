#!/bin/sh
# Builds and runs every bench/bench_*.c (each prints its own table with an in-run
# baseline), then every bench/*.sh with the build directory as $1.
set -eu
build=$1
mkdir -p "$build/bench"
for f in bench/bench_*.c; do
  [ -f "$f" ] || continue
  b="$build/bench/$(basename "$f" .c)"
  ${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host -o "$b" "$f" \
    lib/sim/c4gsim_fixtures.c lib/host/c4gh_csv.c \
    "$build/lib/libc4gopen.a" -lm
  echo "== $(basename "$f" .c)"
  "$b"
done
for s in bench/*.sh; do
  [ -f "$s" ] || continue
  echo "== $(basename "$s" .sh)"
  sh "$s" "$build"
done
