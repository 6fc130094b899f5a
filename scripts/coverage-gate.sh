#!/bin/sh
# lcov capture of the pure archives' sources only, then gate: lines >= $2 %, branches >= $3 %.
#   sh scripts/coverage-gate.sh DIR MIN_LINES MIN_BRANCHES SOURCE...   (the files that count)
set -eu
dir=$1; min_lines=$2; min_br=$3; shift 3
lcov --quiet --capture --directory "$dir" --rc lcov_branch_coverage=1 -o "$dir/all.info" >/dev/null 2>&1
pats=''
for f in "$@"; do pats="$pats */$f"; done
# shellcheck disable=SC2086
lcov --quiet --extract "$dir/all.info" $pats --rc lcov_branch_coverage=1 -o "$dir/lib.info" >/dev/null 2>&1
summary=$(lcov --summary "$dir/lib.info" --rc lcov_branch_coverage=1 2>&1)
echo "$summary" | grep -E 'lines|branches|functions' | sed 's/^ */coverage: /'
lines=$(echo "$summary" | awk '/lines/ {gsub("%","",$2); print $2}')
br=$(echo "$summary" | awk '/branches/ {gsub("%","",$2); print $2}')
ok=$(awk -v l="$lines" -v b="$br" -v ml="$min_lines" -v mb="$min_br" 'BEGIN { print (l + 0 >= ml && b + 0 >= mb) ? 1 : 0 }')
if [ "$ok" -ne 1 ]; then
  echo "coverage: FAILED gate (lines $lines% < $min_lines% or branches $br% < $min_br%)" >&2
  lcov --list "$dir/lib.info" --rc lcov_branch_coverage=1 >&2 || true
  exit 1
fi
echo "coverage: gate passed (lines >= $min_lines%, branches >= $min_br%)"
