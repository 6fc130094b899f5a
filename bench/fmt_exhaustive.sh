#!/bin/sh
# The shortest float32 text of the CSV export (lib/host/c4gh_fmt.c) over all 2^32 bit
# patterns (bench/fmt_exhaustive.c): every finite float reads back through strtof bit for
# bit, no text one digit shorter does, negatives are '-' and the magnitude, NaN and
# infinities are spelled as the CSV module spells them. Then its speed against
# snprintf %.9g. FMT_THREADS threads (default 2); a few minutes on 2 cores.
#   Usage: sh bench/fmt_exhaustive.sh BUILD_DIR
set -eu
build=${1:?usage: sh bench/fmt_exhaustive.sh BUILD_DIR}
mkdir -p "$build/bench"
b=$build/bench/fmt_exhaustive
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Ilib/host -o "$b" \
    bench/fmt_exhaustive.c lib/host/c4gh_fmt.c -lpthread
"$b" --threads "${FMT_THREADS:-2}"
