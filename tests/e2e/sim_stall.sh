#!/bin/sh
# c4g-sim does not blame the PC for its own lateness: the test stops the simulator process
# (SIGSTOP .. SIGCONT, as a busy host deschedules it) for more than 10 periods, several
# times, while the reference PC answers. The replies that waited in the simulator's socket
# arrived before their deadlines (kernel receive timestamps), so none may count as missing,
# and the stalls must show as the simulator's own overruns.
# On a busy host the reference PC is descheduled too, and then its replies are really late:
# it logs every reply it sent more than 1 ms after its packet arrived (the simulator leaves
# it at least 1.5 ms), and each missing reply must be one of those.
. tests/e2e/helpers/sim_lib.sh
stops=5
next_port; start_pc $PORT --idle-ms 300 --slow-us 1000
"$SIM" --bind 127.0.0.1 -p $PORT -n 1500 $STALL_OK -v --json >"$T/s.json" 2>"$T/s.err" &
SIMPID=$!; PIDS="$PIDS $SIMPID"
wait_until 30 grep -q '^ref_pc: cyclic' "$T/ref_$PORT.log" || fail "no cyclic packet reached the PC"
i=0
while [ $i -lt $stops ]; do
  # each stop lasts at least 30 ms (15 periods); a busy host only makes it longer
  kill -STOP $SIMPID || fail "c4g-sim ended before stop $((i + 1))"
  sleep 0.03
  kill -CONT $SIMPID
  sleep 0.05
  i=$((i + 1))
done
wait $SIMPID; rc=$?
wait_pc
expect_eq "exit status" $rc 0
o=$(jget "$T/s.json" overruns)
[ "$o" -ge $stops ] || fail "overruns $o, want >= $stops (one per stop at least): $(cat "$T/s.json")"
ok "the simulator counted its own overruns: $o (worst $(jget "$T/s.json" overrun_max_us) us after the tick)"
sed -n 's/.*Rx Debug (NUM \([0-9]*\),.*/\1/p' "$T/s.err" | sort -u >"$T/missing"
sed -n 's/^ref_pc: slow reply to NUM \([0-9]*\):.*/\1/p' "$T/ref_$PORT.log" | sort -u >"$T/slow"
expect_eq "missing replies in the summary and in the log" "$(wc -l <"$T/missing")" "$(jget "$T/s.json" missing)"
comm -23 "$T/missing" "$T/slow" >"$T/unexplained"
[ -s "$T/unexplained" ] && fail "missing replies the PC sent in time (NUM $(tr '\n' ' ' <"$T/unexplained")): the simulator blamed the PC"
ok "missing replies $(jget "$T/s.json" missing), each one a reply the PC itself sent late ($(wc -l <"$T/slow") slow)"
ok "late $(jget "$T/s.json" late), unjudged $(jget "$T/s.json" unjudged), ok $(jget "$T/s.json" ok); $(tail -1 "$T/ref_$PORT.log")"
exit 0
