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
bad "scenario bad number" "a.scn:2:10: MOVE: target 2 \[turns\]: 'x' is not a decimal number" -S "$T/a.scn"
printf 'DRIVE ON 1\nFLY 1\n' >"$T/b.scn"
bad "scenario unknown command" "b.scn:2:1: unknown command 'FLY'" -S "$T/b.scn"
printf '[sim]\nperiod_ms = 2\n[axis 1.2]\nkp = -4\n' >"$T/a.ini"
bad "config bad value" "a.ini:4:6: \[axis 1.2\] kp: '-4' is out of range 0..100000" -c "$T/a.ini"
printf '[sim]\nspeed = 3\n' >"$T/b.ini"
bad "config unknown key" "b.ini:2:1: \[sim\]: unknown key 'speed'" -c "$T/b.ini"
bad "missing scenario" "nope.scn" -S "$T/nope.scn"
# Files users write: out-of-range numbers, binary bytes, endless or huge input.
printf 'DRIVE ON 1\nWAIT PC 1 TIMEOUT 1e300\n' >"$T/c.scn"
bad "scenario timeout out of range" "c.scn:2:19: WAIT: timeout \[ms\]: '1e300' is out of range 0..3600000" -S "$T/c.scn"
printf 'DELAY 1\0\n' >"$T/d.scn"
bad "scenario NUL byte" 'd.scn:1:8: NUL byte \\x00 at byte offset 7' -S "$T/d.scn"
bad "scenario /dev/zero" "/dev/zero: more than 1048576 bytes, the limit for this file: refused" -S /dev/zero
bad "config /dev/zero" "/dev/zero: more than 1048576 bytes, the limit for this file: refused" -c /dev/zero
printf '[sim]\nswitch_ms = 1e39\n' >"$T/c.ini"
bad "config 1e39" "c.ini:2:13: \[sim\] switch_ms: '1e39' is out of range 0..100000" -c "$T/c.ini"
printf '[sim]\nport = 41000\n  seed = 3\nmax_miss = 99999999999999999999\n' >"$T/d.ini"
bad "config int overflow, indented key" "d.ini:4:12: \[sim\] max_miss: '99999999999999999999' is out of range" -c "$T/d.ini"
head -c 4000 /dev/urandom >"$T/r.scn"
run_sim -S "$T/r.scn" -n 1 >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || [ $rc -eq 1 ] || [ $rc -eq 0 ] || fail "random scenario: exit $rc (crash?)"
ok "random bytes as a scenario: exit $rc, no crash"

# A failed EXPECT: the summary (no -v) names the line and why; a scenario cut short says
# where it stopped, never "running"
printf 'DRIVE ON 1\nDELAY 20\nEXPECT MODE 1 1 4\nDRIVE OFF 1\nEXIT OPEN\n' >"$T/x.scn"
next_port; start_pc $PORT
run_sim -p $PORT -S "$T/x.scn" $STALL_OK >"$T/x.out" 2>"$T/x.err"; rc=$?
wait_pc
expect_eq "failed EXPECT: exit" $rc 3
grep -q "first failed expectation: scenario line 3: EXPECT MODE failed: mode 0, expected 4" "$T/x.out" \
  || fail "failed EXPECT not named without -v: $(cat "$T/x.out")"
grep -q "running" "$T/x.out" && fail "summary says running: $(grep scenario "$T/x.out")"
ok "failed EXPECT named without -v: $(grep 'first failed' "$T/x.out")"
exit 0
