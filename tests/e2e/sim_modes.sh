#!/bin/sh
# c4g-sim scenarios for every supported mode against the reference PC: each must end
# with exit 0 (all EXPECTs met) and show the manual's mode sequence on axis 1.
. tests/e2e/helpers/sim_lib.sh
run_mode() { # run_mode SCENARIO WANT_SEQUENCE
  next_port; start_pc $PORT
  run_sim -p $PORT -S fixtures/scenarios/$1.scn $STALL_OK --csv "$T/$1.csv" --json >"$T/$1.json"; rc=$?
  [ $rc -eq 0 ] || { cat "$T/$1.json"; fail "$1: exit status $rc"; }
  seq=$(awk -F, 'NR > 1 && $3 == 1 { print $6 }' "$T/$1.csv" | uniq | tr '\n' ' ' | sed 's/ $//')
  expect_eq "$1: mode sequence of axis 1" "$seq" "$2"
  [ "$(jget "$T/$1.json" expect_failed)" = 0 ] || fail "$1: expectations failed"
  ok "$1: $(jget "$T/$1.json" expect_passed) expectations met"
}
run_mode mode0 "501 0"
run_mode mode10 "501 0 10 0"
run_mode mode1 "501 0 1 11 0"
run_mode mode2 "501 0 2 12 0"
run_mode mode4 "501 0 4 14 0"
run_mode mode5 "501 0 5 15 0"
run_mode mode7 "501 0 7 170 0"
run_mode mode8 "501 0 8 0"
run_mode mode9 "501 0 9 0"
# INFPAR byte 5 once the drives are on, CMD byte from the scenario (mode 5: CMD 1 3)
grep -q ',0x00000005,0x00000003$' "$T/mode5.csv" || fail "mode5: INFPAR 5 / CMD 3 not seen"
ok "INFPAR byte 5 (drives on) and CMD byte 3 on the wire"
exit 0
