#!/bin/sh
# Per-tick cost of the PC side against the struct-copy baseline of bench/tick.c, same run:
# instructions per tick under callgrind, Ir(2N ticks) - Ir(N ticks) over N (the repeatable
# figure), and ns per tick (median of interleaved batches; noisy on a shared machine).
# Goals: 20 axes wire <= 740 Ir, full <= 5017 Ir; 6 axes wire <= 453 Ir, full <= 1883 Ir
# (0.5x and 0.8x of the field library measured unmodified: wire 906 / 1481, mode 4 2354 / 6271)
# (half of what a struct-cast library without any validation spends, measured on it), and
# the floor of a mode-4 filter loop over arrays (bench/filter_floor.c) beside them.
# Last, mode 9's rigid-body model (bench/ff_rigid_cost.c, 6 axes) per tick beside the mode-4
# full tick: what c4g-server adds to a tick with a model = rigid-body-1 file.
# Usage: sh bench/tick_cost.sh BUILD_DIR
set -eu
build=$1
b="$build/bench/tick"
mkdir -p "$build/bench"
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host -o "$b" \
  bench/tick.c lib/sim/c4gsim_fixtures.c "$build/lib/libc4gopen.a" -lm
ns=$(mktemp)
trap 'rm -f "$ns"' EXIT
"$b" >"$ns"
have_vg=1
command -v valgrind >/dev/null 2>&1 || { have_vg=0; echo "tick_cost: valgrind not installed, Ir skipped"; }
ir() {
  out=$(mktemp)
  valgrind --tool=callgrind --callgrind-out-file="$out" "$b" --only "$1" "$2" "$3" >/dev/null 2>&1
  sed -n 's/^summary: *//p; s/^totals: *//p' "$out" | head -n 1
  rm -f "$out"
}
per_tick() {  # per_tick PATH AXES -> Ir per tick
  if [ "$have_vg" = 0 ]; then echo 0; return; fi
  n=5000
  a=$(ir "$1" "$2" $n); c=$(ir "$1" "$2" $((2 * n)))
  awk -v a="$a" -v c="$c" -v n="$n" 'BEGIN { printf "%.0f", (c - a) / n }'
}
printf '%-7s %5s %9s %9s %7s %9s %9s %9s %7s\n' path axes "ours Ir" "base Ir" ratio "goal Ir" "ours ns" "base ns" ratio
for path in wire wire-tx full; do
  for axes in 6 20; do
    base=base-$path
    [ "$path" = wire-tx ] && base=base-wire
    o=$(per_tick "$path" "$axes"); bb=$(per_tick "$base" "$axes")
    [ "$path" = wire ] && eval "wire_ir_$axes=$o"   # the floor below adds it
    [ "$path$axes" = full6 ] && full_ir_6=$o        # the rigid model's line below
    case "$path$axes" in wire6) g=453 ;; wire20) g=740 ;; full6) g=1883 ;; full20) g=5017 ;; *) g=0 ;; esac
    set -- $(awk -v p="$path" -v a="$axes" '$1 == p && $2 == a { print $3, $4, $5 }' "$ns")
    awk -v p="$path" -v a="$axes" -v o="$o" -v b="$bb" -v g="$g" -v on="$1" -v bn="$2" -v r="$3" 'BEGIN {
      printf "%-7s %5s %9d %9d %6.1fx %5s %-3s %9.1f %9.1f %7s\n", p, a, o, b, (b > 0 ? o / b : 0),
        (g > 0 ? g : "-"), (g == 0 ? "" : (o <= g ? "met" : "NOT")), on, bn, r }'
  done
done
echo "(ours: wire = session rx + c4g_session_reply_neutral (the neutral reply encoded from the checked"
echo " packet), mode 0; wire-tx = the same with the reply built as a PC packet and encoded and checked"
echo " again; full = loop object, mode 4, setpoints,"
echo " packet rules and safety filter. base = struct copy in/out, no validation; Ir/tick = (Ir(2N) - Ir(N))/N)"
# The floor of the full path's goal (bench/filter_floor.c): the mode-4 filter alone as one
# loop over arrays, fewer checks than the library's. Wire + this is what a full tick could
# at best cost with every check kept.
if [ "$have_vg" = 1 ]; then
  f="$build/bench/filter_floor"
  ${CC:-cc} -std=c99 -O2 -Wall -Wextra -o "$f" bench/filter_floor.c
  fir() {
    out=$(mktemp)
    valgrind --tool=callgrind --callgrind-out-file="$out" "$f" "$1" "$2" >/dev/null 2>&1
    sed -n 's/^summary: *//p; s/^totals: *//p' "$out" | head -n 1
    rm -f "$out"
  }
  for axes in 6 20; do
    a=$(fir "$axes" 5000); c=$(fir "$axes" 10000)
    eval "w=\$wire_ir_$axes"
    case $axes in 6) g=1883 ;; *) g=5017 ;; esac
    awk -v a="$a" -v c="$c" -v w="$w" -v g="$g" -v n="$axes" 'BEGIN { f = (c - a) / 5000;
      printf "floor: %2d axes, mode-4 filter loop over arrays %5.0f Ir (setpoints included) + wire %4d = %5.0f Ir against the full goal %d\n", n, f, w, f + w, g }'
  done
fi
# mode 9's rigid-body model (c4gh_ffr_current on the arm plant's exact file) per tick
r="$build/bench/ff_rigid_cost"
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Iinclude -Ilib/sim -Ilib/host -o "$r" \
  bench/ff_rigid_cost.c lib/sim/c4gsim_fixtures.c "$build/lib/libc4gopen-host.a" "$build/lib/libc4gopen.a" -linih -lm
rns=$("$r" | sed -n 's/.*ns\/tick \([0-9.]*\).*/\1/p')
if [ "$have_vg" = 1 ]; then
  rir() {
    out=$(mktemp)
    valgrind --tool=callgrind --callgrind-out-file="$out" "$r" "$1" >/dev/null 2>&1
    sed -n 's/^summary: *//p; s/^totals: *//p' "$out" | head -n 1
    rm -f "$out"
  }
  a=$(rir 5000); c=$(rir 10000)
  awk -v a="$a" -v c="$c" -v f="${full_ir_6:-0}" -v ns="$rns" 'BEGIN { r = (c - a) / 5000;
    printf "rigid:  6 axes, mode-9 rigid-body model (c4gh_ffr_current) %5.0f Ir per tick (%.0f ns), %.1fx the mode-4 full tick of %d Ir\n", r, ns, (f > 0 ? r / f : 0), f }'
else
  echo "rigid:  6 axes, mode-9 rigid-body model (c4gh_ffr_current) $rns ns per tick"
fi
