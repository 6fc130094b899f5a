#!/bin/sh
# c4g-sim fault injection on its own packets (drop, delay, duplicate, reorder, corrupt,
# truncate, pause) is applied and counted; the PC side sees it; --seed makes runs repeat
# (identical per-tick CSV), a different seed changes the noise.
. tests/e2e/helpers/sim_lib.sh
next_port; start_pc $PORT
run_sim -p $PORT -n 1000 --max-miss 1000 --seed 3 --drop 0.02 --duplicate 0.02 --reorder 0.02 \
  --corrupt 0.02 --truncate 0.02 --delay 0.02:200 --json >"$T/f.json"; rc=$?
expect_eq "faults: exit status" $rc 0
for f in drop duplicate reorder corrupt truncate delay; do
  n=$(jget "$T/f.json" $f)
  [ "$n" -gt 0 ] || fail "fault $f not injected/counted: $(cat "$T/f.json")"
  ok "fault $f injected and counted: $n"
done
# unanswered = missing, or unjudged when the simulator itself overran that deadline
m=$(( $(jget "$T/f.json" missing) + $(jget "$T/f.json" unjudged) ))
[ "$m" -ge "$(jget "$T/f.json" drop)" ] || fail "dropped packets must go unanswered (missing + unjudged $m)"
ok "missing + unjudged replies ($m) >= dropped packets"
wait_pc
grep -q "dropped [1-9]" "$T/ref_$PORT.log" || fail "the PC rejected no corrupted/truncated datagram: $(cat "$T/ref_$PORT.log")"
ok "the PC side rejected malformed datagrams: $(cat "$T/ref_$PORT.log")"

next_port; start_pc $PORT
run_sim -p $PORT -n 300 --pause 100:30 --max-miss 1000 --json >"$T/p.json"; rc=$?
expect_eq "pause: exit status" $rc 0
expect_eq "pause: ticks without a packet" "$(jget "$T/p.json" paused_ticks)" 30
expect_eq "pause: cyclic packets sent" "$(jget "$T/p.json" cyclic)" 270

# Reproducibility: same seed -> identical CSV (what the simulator sent; what it received
# depends on host timing and is left out); another seed -> different measurement noise.
for s in 1 2; do
  next_port; start_pc $PORT
  run_sim -p $PORT -S fixtures/scenarios/mode0.scn $STALL_OK --seed 42 --csv "$T/s$s.csv" -q || fail "seed run $s"
done
next_port; start_pc $PORT
run_sim -p $PORT -S fixtures/scenarios/mode0.scn $STALL_OK --seed 43 --csv "$T/s3.csv" -q || fail "seed run 3"
# the simulator's own columns (docs/csv.md): t_s..rx_e3 (the packet sent) and tick, sent;
# the tx_* columns and reply_ok depend on when the PC's replies came
for s in 1 2 3; do
  head -1 "$T/s$s.csv" | grep -q '^t_s,num,axis,arm,logical,rx_mode,.*,tx_d5,tick,sent,reply_ok,rx_infpar,rx_cmd$' || fail "CSV header: $(head -1 "$T/s$s.csv")"
  awk -F, '{ o = $1; for (i = 2; i <= 14; i++) o = o "," $i; print o "," $22 "," $23 "," $25 "," $26 }' "$T/s$s.csv" >"$T/c$s.csv"
done
cmp -s "$T/c1.csv" "$T/c2.csv" || { diff "$T/c1.csv" "$T/c2.csv" | head -5; fail "--seed 42 twice: CSVs differ"; }
ok "--seed 42 twice: identical CSV ($(wc -l <"$T/c1.csv") lines)"
cmp -s "$T/c1.csv" "$T/c3.csv" && fail "--seed 43 gave the same CSV as --seed 42"
ok "--seed 43: different CSV"
exit 0
