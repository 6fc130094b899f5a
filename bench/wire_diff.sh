#!/bin/sh
# Differential check of the wire layer: bench/wire_record.c's record of every decoder,
# encoder, neutral reply and session call over the fuzz corpora (and generated
# initialization packets), each input with MUTATIONS seeded variants, run against this
# tree's library and against the one git revision REF builds (its lib/ and include/, same
# compiler and -O2); the two records must be identical line for line. A change meant to
# make lib/wire cheaper proves with it that it changed no status, diagnostic, decoded value,
# encoded byte or session state.
#   Usage: sh bench/wire_diff.sh BUILD_DIR [REF [MUTATIONS]]   (REF: HEAD, MUTATIONS: 40)
set -eu
build=${1:?usage: sh bench/wire_diff.sh BUILD_DIR [REF [MUTATIONS]]}
ref=${2:-HEAD}
muts=${3:-40}
# (make bench runs it against HEAD: uncommitted changes of lib/ are what it compares)
git rev-parse --verify -q "$ref^{commit}" >/dev/null 2>&1 ||
  { echo "wire_diff: no git revision '$ref' here (a source tree without .git?), skipped"; exit 0; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/c4g-wire-diff.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
cc=${CC:-cc}
flags="-std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra"
# the reference library: REF's own sources, one archive
mkdir -p "$tmp/ref"
git archive "$ref" lib include | tar -x -C "$tmp/ref"
for f in "$tmp"/ref/lib/wire/*.c "$tmp"/ref/lib/engine/*.c "$tmp"/ref/lib/loop/*.c "$tmp"/ref/lib/cell/*.c \
         "$tmp"/ref/lib/canopen/*.c "$tmp"/ref/lib/dyn/*.c; do
  [ -f "$f" ] || continue
  o="$tmp/ref/$(echo "$f" | sed 's|.*/lib/||; s|/|_|g; s|\.c$|.o|')"
  $cc $flags -I"$tmp/ref/include" -c "$f" -o "$o"
done
ar rcs "$tmp/ref.a" "$tmp"/ref/*.o
inputs="@init1 @init6 @init6s @init20 @init20s $(ls fixtures/fuzz/fuzz_session/* fixtures/fuzz/fuzz_init_decode/* \
  fixtures/fuzz/fuzz_ctrl_decode/* | LC_ALL=C sort)"
# shellcheck disable=SC2086 # one argument per input
$cc $flags -I"$tmp/ref/include" -Ilib/sim -o "$tmp/rec-ref" bench/wire_record.c lib/sim/c4gsim_fixtures.c "$tmp/ref.a" -lm
$cc $flags -Iinclude -Ilib/sim -o "$tmp/rec-new" bench/wire_record.c lib/sim/c4gsim_fixtures.c "$build/lib/libc4gopen.a" -lm
"$tmp/rec-ref" "$muts" $inputs > "$tmp/ref.txt"
"$tmp/rec-new" "$muts" $inputs > "$tmp/new.txt"
lines=$(wc -l < "$tmp/ref.txt")
cases=$(grep -c '^== ' "$tmp/ref.txt")
if cmp -s "$tmp/ref.txt" "$tmp/new.txt"; then
  echo "wire_diff: identical to $ref: $lines lines over $cases inputs ($muts mutations each)"
else
  echo "wire_diff: DIFFERENT from $ref ($lines lines over $cases inputs):"
  diff "$tmp/ref.txt" "$tmp/new.txt" | head -n 40
  exit 1
fi
