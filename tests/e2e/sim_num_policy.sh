#!/bin/sh
# c4g-sim NUM policy enforcement: plus-one (field), echo (manual) or either (default).
. tests/e2e/helpers/sim_lib.sh
check() { # check PC_OPTS SIM_POLICY WANT_EXIT
  next_port; start_pc $PORT $1
  run_sim -p $PORT -n 100 --num-policy "$2" --json >"$T/p.json"; rc=$?
  expect_eq "PC '${1:-plus-one}' vs --num-policy $2: exit status" $rc "$3"
  if [ "$3" = 1 ]; then
    # the refused replies (all but possibly the last, still in flight when the error is
    # raised) are counted as wrong NUM, stale, or (an init echo that arrives
    # after the sim moved on, on a loaded machine) malformed
    w=$(( $(jget "$T/p.json" wrong_num) + $(jget "$T/p.json" stale) + $(jget "$T/p.json" malformed) ))
    [ "$w" -ge 9 ] || fail "wrong NUM not counted: $(cat "$T/p.json")"
    ok "replies with a NUM the policy rejects counted: $w (wrong_num + stale)"
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
run_sim -p $PORT -n 50 --json >"$T/e.json"
expect_eq "either: policy detected from the PC" "$(jget "$T/e.json" pc_policy)" echo
exit 0
