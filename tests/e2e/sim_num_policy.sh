#!/bin/sh
# c4g-sim NUM policy enforcement: plus-one (field), echo (manual) or either (default).
. tests/e2e/helpers/sim_lib.sh
check() { # check PC_OPTS SIM_POLICY WANT_EXIT
  next_port; start_pc $PORT $1
  # a refused PC must raise the default 10-in-a-row error; an accepted one may be stalled by
  # a busy host without ending the run
  miss=""; [ "$3" = 0 ] && miss=$STALL_OK
  run_sim -p $PORT -n 100 --num-policy "$2" $miss --json >"$T/p.json"; rc=$?
  expect_eq "PC '${1:-plus-one}' vs --num-policy $2: exit status" $rc "$3"
  if [ "$3" = 1 ]; then
    # the refused replies are counted as wrong NUM, stale (a reply that came after its
    # deadline) or malformed (an init echo that came after the sim moved on). How many
    # arrived before the error depends on the PC's scheduling, not on the policy (the ones
    # still in flight when ERR_C4GOPEN_UDP stops the sim are not read), and so does a
    # plus-one reply that comes a period late: its NUM is the next packet's echo.
    w=$(( $(jget "$T/p.json" wrong_num) + $(jget "$T/p.json" stale) + $(jget "$T/p.json" malformed) ))
    [ "$w" -ge 1 ] || fail "wrong NUM not counted: $(cat "$T/p.json")"
    ok "replies with a NUM the policy rejects counted: $w (wrong_num + stale + malformed)"
    expect_eq "10 packets in a row without an accepted reply" "$(jget "$T/p.json" max_consecutive_missing)" 10
    grep -q ERR_C4GOPEN_UDP "$T/p.json" || fail "no ERR_C4GOPEN_UDP"
  else
    expect_eq "wrong NUM" "$(jget "$T/p.json" wrong_num)" 0
  fi
}
check "" plus-one 0
check "" either 0
check "" echo 1
check "--echo" echo 0
check "--echo" either 0
check "--echo" plus-one 1
check "--wrong-num" either 1
next_port; start_pc $PORT --echo
run_sim -p $PORT -n 50 $STALL_OK --json >"$T/e.json"
expect_eq "either: policy detected from the PC" "$(jget "$T/e.json" pc_policy)" echo
exit 0
