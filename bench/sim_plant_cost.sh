#!/bin/sh
# c4g-sim's model per simulated tick, in process (no sockets), decoupled plant beside the arm
# plant (fixtures/sim/smart-six.xml, MuJoCo): 1 ms ticks, two DSA steps each, arm 1 moving
# in mode 0. CPU ns per tick (CLOCK_PROCESS_CPUTIME_ID, noisy on a shared machine) and, under
# callgrind, instructions per tick: Ir(2N ticks) - Ir(N ticks) over N, so loading the model
# does not count (N is small: MuJoCo under callgrind is slow). The arm plant's budget: well
# under one core at 1 kHz, i.e. far below 1e6 ns per tick. The instruction counts are
# compared with the figures docs/c4g-sim.md gives (12800 decoupled, 122000 arm plant, before
# the speed work): "no regression" is met within 2 % of them (MuJoCo's own build moves the
# arm plant's count a little). Nothing asserts.
# Usage: sh bench/sim_plant_cost.sh BUILD_DIR
set -eu
build=$1
b="$build/bench/sim_plant"
xml=fixtures/sim/smart-six.xml
mkdir -p "$build/bench"
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host \
  -Itools/c4g-sim -o "$b" bench/sim_plant.c "$build/tools/libc4g-sim.a" "$build/lib/libc4gopen-host.a" \
  "$build/lib/libc4gopen-sim.a" "$build/lib/libc4gopen.a" -linih -lpcap -ljansson -lmujoco -lm
dec=$("$b" 20000)
arm=$("$b" --plant "$xml" 20000)
echo "sim_plant_cost: decoupled plant, 6 axes, 1 ms, 20000 ticks: $dec ns CPU per tick"
echo "sim_plant_cost: arm plant (MuJoCo), 6 axes, 1 ms, 20000 ticks: $arm ns CPU per tick" \
  "($(awk -v a="$arm" 'BEGIN { printf "%.1f", a / 1e4 }') % of one core at 1 kHz)"
if ! command -v valgrind >/dev/null 2>&1; then
  echo "sim_plant_cost: valgrind not installed, Ir skipped"
  exit 0
fi
ir() {  # ir TICKS [--plant FILE] -> total Ir
  out=$(mktemp)
  n=$1
  shift
  valgrind --tool=callgrind --callgrind-out-file="$out" "$b" "$@" "$n" >/dev/null 2>&1
  sed -n 's/^summary: *//p; s/^totals: *//p' "$out" | head -n 1
  rm -f "$out"
}
per_tick() {  # per_tick N [--plant FILE]
  n=$1
  shift
  a=$(ir "$n" "$@")
  c=$(ir $((2 * n)) "$@")
  awk -v a="$a" -v c="$c" -v n="$n" 'BEGIN { printf "%.0f", (c - a) / n }'
}
verdict() {  # verdict WHAT IR REFERENCE
  awk -v w="$1" -v o="$2" -v r="$3" 'BEGIN {
    printf "sim_plant_cost: %s: %d Ir per tick against %d before: %.3fx, no regression (<= 1.02x) %s\n",
      w, o, r, o / r, (o <= 1.02 * r ? "met" : "NOT") }'
}
verdict "decoupled plant (callgrind, 2000 ticks)" "$(per_tick 2000)" 12800
verdict "arm plant (callgrind, 200 ticks)" "$(per_tick 200 --plant "$xml")" 122000
