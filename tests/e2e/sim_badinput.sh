#!/bin/sh
# c4g-sim command line, configuration and scenario errors: exit 2 with the file, line and
# value named on stderr; --help and --version exit 0; no crash on garbage input.
. tests/e2e/helpers/sim_lib.sh
"$SIM" --help >"$T/h.txt"; expect_eq "--help exit" $? 0
grep -q "Examples:" "$T/h.txt" || fail "--help has no examples"
"$SIM" --version | grep -q "^c4g-sim " || fail "--version"
ok "--help and --version"
bad() { # bad WHAT PATTERN ARGS...
  what=$1; pat=$2; shift 2
  run_sim "$@" >/dev/null 2>"$T/e.txt"; rc=$?
  expect_eq "$what: exit" $rc 2
  grep -q "$pat" "$T/e.txt" || fail "$what: stderr lacks '$pat': $(cat "$T/e.txt")"
  ok "$what: $(cat "$T/e.txt")"
}
bad "unknown option" "unrecognized" --frobnicate
bad "period 3" "period" -T 3
bad "21 axes" "ERR_C4GOPEN" --axes 10,10,1
bad "bad policy" "num-policy" --num-policy sometimes
printf 'DRIVE ON 1\nMOVE 1 1 x 3\n' >"$T/a.scn"
bad "scenario bad number" "a.scn: line 2: MOVE: target 2 'x'" -S "$T/a.scn"
printf 'DRIVE ON 1\nFLY 1\n' >"$T/b.scn"
bad "scenario unknown command" "line 2: unknown command 'FLY'" -S "$T/b.scn"
printf '[sim]\nperiod_ms = 2\n[axis 1.2]\nkp = -4\n' >"$T/a.ini"
bad "config bad value" "a.ini:4: \[axis 1.2\] kp: bad value '-4'" -c "$T/a.ini"
printf '[sim]\nspeed = 3\n' >"$T/b.ini"
bad "config unknown key" "b.ini:2: \[sim\]: unknown key 'speed'" -c "$T/b.ini"
bad "missing scenario" "nope.scn" -S "$T/nope.scn"
head -c 4000 /dev/urandom >"$T/r.scn"
run_sim -S "$T/r.scn" -n 1 >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || [ $rc -eq 1 ] || [ $rc -eq 0 ] || fail "random scenario: exit $rc (crash?)"
ok "random bytes as a scenario: exit $rc, no crash"
exit 0
