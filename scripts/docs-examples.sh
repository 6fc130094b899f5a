#!/bin/sh
# Every docs/examples/*.c compiles against the public header and static library, and runs.
# The examples use the manual's figure 10.1 fixture and the moni CSV text from the tool
# helpers (lib/sim, lib/host), which are not part of the real-time library.
set -eu
build=$1
mkdir -p "$build/docs-examples"
n=0
for f in docs/examples/*.c; do
  [ -f "$f" ] || continue
  b="$build/docs-examples/$(basename "$f" .c)"
  ${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -pedantic -Wall -Wextra -Werror -Iinclude -Ilib/sim -Ilib/host \
    -o "$b" "$f" lib/sim/c4gsim_fixtures.c lib/host/c4gh_csv.c "$build/lib/libc4gopen.a" -lm
  "$b" >/dev/null || { echo "docs-examples: $f exited non-zero" >&2; exit 1; }
  n=$((n + 1))
done
echo "docs-examples: $n compiled and ran"
