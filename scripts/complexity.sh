#!/bin/sh
# Cognitive complexity gate: every function of the given files at or below $1.
#   sh scripts/complexity.sh THRESHOLD "COMPILER FLAGS" FILE...
set -u
limit=$1; flags=$2; shift 2
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for f in "$@"; do
  # shellcheck disable=SC2086
  clang-tidy --quiet --checks='-*,readability-function-cognitive-complexity' \
    --config="{CheckOptions: [{key: readability-function-cognitive-complexity.Threshold, value: $limit}, {key: readability-function-cognitive-complexity.IgnoreMacros, value: true}]}" \
    "$f" -- $flags 2>/dev/null | grep 'warning: function' >>"$out"
done
if [ -s "$out" ]; then
  cat "$out" >&2
  echo "complexity: $(wc -l <"$out") function(s) above $limit" >&2
  exit 1
fi
echo "complexity: $# files, every function at or below $limit"
