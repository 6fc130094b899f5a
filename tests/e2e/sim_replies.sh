#!/bin/sh
# c4g-sim reply checking like the controller: 10 consecutive missing replies raise
# ERR_C4GOPEN_UDP (exit 1, drives off, communication stops); one missing reply is survived
# and counted; a PC that never answers fails during the handshake.
. tests/e2e/helpers/sim_lib.sh
next_port; start_pc $PORT --stop-after 60
run_sim -p $PORT -n 500 --json >"$T/a.json"; rc=$?
expect_eq "stop replying after 60: exit status" $rc 1
grep -q '"name":"ERR_C4GOPEN_UDP","message":"C4GOpen: communication error"' "$T/a.json" ||
  fail "no ERR_C4GOPEN_UDP with its manual message in $(cat "$T/a.json")"
ok "ERR_C4GOPEN_UDP raised with the manual's message"
# unanswered = missing, or unjudged if the simulator overran that deadline itself
u=$(jget "$T/a.json" unjudged)
m=$(jget "$T/a.json" missing); [ $((m + u)) -ge 10 ] || fail "missing $m + unjudged $u < 10"; ok "missing replies $m, unjudged $u (10 after the PC stopped)"
expect_eq "max consecutive missing" "$(jget "$T/a.json" max_consecutive_missing)" 10
expect_eq "drive on after the error" "$(jget "$T/a.json" drive_on)" false
expect_eq "every packet answered, missing or unjudged" "$(( $(jget "$T/a.json" ok) + m + u ))" "$(jget "$T/a.json" sent)"

# (the run above proves that 9 in a row do not raise: the error came at 10)
next_port; start_pc $PORT --drop-nth 20
run_sim -p $PORT -n 200 $STALL_OK --json >"$T/b.json"; rc=$?
expect_eq "one dropped reply: exit status" $rc 0
m=$(( $(jget "$T/b.json" missing) + $(jget "$T/b.json" unjudged) ))
[ "$m" -ge 1 ] || fail "dropped reply not counted"; ok "dropped reply counted as missing or unjudged ($m; more than 1 only if the PC was late too)"
expect_eq "one dropped reply: errors" "$(grep -o '"errors":\[\]' "$T/b.json")" '"errors":[]'

next_port; start_pc $PORT --no-reply
run_sim -p $PORT -n 100 --json >"$T/c.json"; rc=$?
expect_eq "silent PC: exit status" $rc 1
expect_eq "silent PC: packets sent before giving up (9 sync + init)" "$(jget "$T/c.json" sent)" 10
grep -q ERR_C4GOPEN_UDP "$T/c.json" || fail "silent PC: no ERR_C4GOPEN_UDP"
ok "silent PC: ERR_C4GOPEN_UDP after 10 unanswered sync packets"

next_port; start_pc $PORT --drop-nth 30
run_sim -p $PORT -n 100 --max-miss 1 --json >"$T/d.json"; rc=$?
expect_eq "--max-miss 1: exit status" $rc 1
exit 0
