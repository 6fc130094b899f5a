#!/bin/sh
# Bounded libFuzzer runs: each target for $2 seconds in all from its seed corpus in
# fixtures/fuzz/NAME. libFuzzer runs every seed before it mutates anything, whatever the
# bound (its INITED line): a short bound still replays the whole corpus.
set -eu
dir=$1; secs=$2; shift 2
for n in "$@"; do
  corpus="$dir/corpus-$n"
  rm -rf "$corpus"; mkdir -p "$corpus"
  [ -d "fixtures/fuzz/$n" ] && cp fixtures/fuzz/"$n"/* "$corpus"/ 2>/dev/null || true
  seeds=$(ls "$corpus" | wc -l)
  log="$dir/$n.log"
  if ! "$dir/$n" -max_total_time="$secs" -timeout=5 -rss_limit_mb=2048 -print_final_stats=1 \
       -artifact_prefix="$dir/$n-" "$corpus" >"$log" 2>&1; then
    tail -n 40 "$log" >&2
    echo "fuzz: $n FAILED (log: $log)" >&2
    exit 1
  fi
  if ! grep -q 'INITED' "$log"; then
    tail -n 20 "$log" >&2
    echo "fuzz: $n FAILED: did not finish its $seeds seed(s) (log: $log)" >&2
    exit 1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  echo "fuzz: $n ok, $seeds seeds, $execs executions in ${secs}s"
done
