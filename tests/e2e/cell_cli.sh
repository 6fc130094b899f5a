#!/bin/sh
# cell-cli against a real cell-sim on 127.0.0.1:21011-21013: one-shot, --json,
# exit codes, scripts (stdin and file, ER handling, wait), the spec's pick-and-place
# task end to end, config file, timeouts, and the REPL through a pty.
set -u
build=$1
cli=$build/bin/cell-cli
tmp=$(mktemp -d)
pids=''
cleanup() { for p in $pids; do kill "$p" 2>/dev/null; done; rm -rf "$tmp"; }
trap cleanup EXIT INT TERM
fail=0
pass() { echo "PASS: $*"; }
bad() { echo "FAIL: $*"; fail=1; }
expect_rc() { # want got what
  if [ "$1" -eq "$2" ]; then pass "$3 (exit $2)"; else bad "$3: exit $2, want $1"; fi
}

# wait_listen PORT: until some socket listens on TCP PORT (30 s bound for a broken run)
wait_listen() {
  i=0
  until ss -Htln "sport = :$1" | grep -q LISTEN; do
    i=$((i + 1)); [ $i -gt 1500 ] && return 1; sleep 0.02
  done
}
"$build/bin/cell-sim" -p 21011 -s 20 >"$tmp/sim.log" 2>&1 & pids="$pids $!"
wait_listen 21013 || { echo "FAIL: cell-sim did not start"; exit 1; }
# the human format: stdout is a pipe here, where replies are raw by default
c() { "$cli" -p 21011 --no-raw "$@"; }

# one-shot
out=$(c robot sta); rc=$?
expect_rc 0 $rc "one-shot robot sta"
echo "$out" | grep -q "robot: stopped, servo off, override 100 %, error +00000 (no error)" && pass "STA shown readable" || bad "STA text: $out"
echo "$out" | grep -q "50.000" && pass "STA table has z=50.000" || bad "STA table: $out"
out=$("$cli" -p 21011 --json platform sta); rc=$?
expect_rc 0 $rc "--json platform sta"
[ "$out" = '{"device":"platform","request":"STA","raw":"OKF+00.0000+00.0000F+00100+00000","reply":"OK","moving":false,"servo":false,"override":100,"error":0,"error_text":"no error","position":{"a":0.0,"b":0.0}}' ] && pass "--json STA object" || bad "--json: $out"
out=$(c robot mov abs x=10 y=-2 z=5.999 c=-1.2322); rc=$?
expect_rc 1 $rc "MOV with servo off -> ER"
echo "$out" | grep -q "ER +00104  servo is off (project code)" && pass "ER explained" || bad "ER text: $out"
c --json raw robot SRVON >/dev/null; expect_rc 0 $? "raw SRVON"
out=$(c robot mov abs x=10 y=-2 z=5.999 c=-1.2322); expect_rc 0 $? "spec MOV example"
out=$(c raw robot 'MOVA+010.000-002.000+005.999-01.2322'); rc=$?
expect_rc 1 $rc "raw MOV while moving -> ER"
echo "$out" | grep -q "+00107" && pass "busy explained" || bad "busy: $out"
printf 'wait robot stopped 10\nrobot sta\n' | c >"$tmp/o" 2>&1; expect_rc 0 $? "script from stdin with wait"
grep -q "10.000      -2.000       5.999     -1.2322" "$tmp/o" && pass "arrived at the spec's pose" || { bad "pose after wait"; cat "$tmp/o"; }
out=$(c --json raw robot STA); [ "$(echo "$out" | sed 's/.*"raw":"\([^"]*\)".*/\1/')" = "OKF+010.000-002.000+005.999-01.2322T+00100+00104" ] && pass "raw STA = spec example reply (override 100, servo-off error latched)" || bad "raw STA: $out"
# output for pipes: raw replies unless --no-raw; --csv with a header; -r/-i lines stamped
out=$("$cli" -p 21011 platform sta); [ "$out" = "OKF+00.0000+00.0000F+00100+00000" ] && pass "raw reply when stdout is a pipe" || bad "raw by default: $out"
out=$("$cli" -p 21011 --csv -r 2 platform sta)
[ "$(echo "$out" | head -1)" = "time,device,request,reply,raw,moving,servo,override,error,p1,p2,p3,p4" ] && pass "--csv header (time first with -r)" || bad "--csv header: $out"
echo "$out" | sed -n 2p | grep -Eq '^20[0-9-]+T[0-9:.]+Z,platform,STA,OK,OKF\+00.0000\+00.0000F\+00100\+00000,0,0,100,0,0.0000,0.0000,,$' && [ "$(echo "$out" | wc -l)" -eq 3 ] && pass "--csv rows" || bad "--csv rows: $out"
out=$("$cli" -p 21011 --json -r 2 -i 0.05 platform sta)
[ "$(echo "$out" | grep -c '^{"time":"20[0-9-]*T[0-9:.]*Z","device":"platform"')" -eq 2 ] && pass "-r/-i JSON lines carry the time" || bad "stamped JSON: $out"
out=$("$cli" -p 21011 --json platform sta); echo "$out" | grep -q '"time"' && bad "one-shot JSON stamped: $out" || pass "one-shot JSON without time"
"$cli" -p 21011 --json --csv robot sta 2>"$tmp/e"; expect_rc 2 $? "--json with --csv refused"
out=$(c ROBOT STA); expect_rc 0 $? "upper-case device and command"
echo "$out" | grep -q "robot: stopped" && pass "ROBOT STA shown" || bad "ROBOT STA: $out"
out=$(printf 'clear\nrobot sta\n' | c); expect_rc 0 $? "clear in a script"
echo "$out" | head -1 | grep -q "^robot: " && pass "clear prints nothing off a terminal" || bad "clear: $out"
c help | grep -q "^  platform mov abs|rel a=RAD b=RAD" && pass "help: platform mov indented like the rest" || bad "help indentation: $(c help | grep 'platform mov')"
# usage errors: exit 2, message names the problem
c robot mov abs x=1 y=2 2>"$tmp/e"; expect_rc 2 $? "missing axis"
grep -q "missing z=" "$tmp/e" && pass "missing axis named" || bad "msg: $(cat "$tmp/e")"
c robot ovr 101 2>"$tmp/e"; expect_rc 2 $? "override 101"
c robot mov abs x=1000 y=0 z=0 c=0 2>"$tmp/e"; expect_rc 2 $? "x=1000 out of range"
grep -q "out of range" "$tmp/e" && pass "range error named" || bad "msg: $(cat "$tmp/e")"
c frobnicate 2>/dev/null; expect_rc 2 $? "unknown command"
"$cli" --bogus 2>/dev/null; expect_rc 2 $? "unknown option"
# workspace error from the device
out=$(c robot mov abs x=300 y=0 z=0 c=0); expect_rc 1 $? "workspace limit"
echo "$out" | grep -q "+00105" && pass "workspace ER shown" || bad "$out"
# connection refused / reply timeout: exit 3
"$cli" -p 21991 robot sta 2>"$tmp/e"; expect_rc 3 $? "connection refused"
grep -q "connection refused" "$tmp/e" && pass "refusal named" || bad "msg: $(cat "$tmp/e")"
# a silent device: accepts and never answers, until the test's cleanup ends it (a fixed
# hold time could run out before a slow client gave up)
python3 -c "
import socket,time
s=socket.socket(); s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1); s.bind(('127.0.0.1',21019)); s.listen(1)
c,_=s.accept(); time.sleep(120)" & pids="$pids $!"
wait_listen 21019 || bad "the silent listener on 21019 never started"
"$cli" --robot 127.0.0.1:21019 -t 300 robot sta 2>"$tmp/e"; expect_rc 3 $? "reply timeout"
grep -q "no reply within 300 ms" "$tmp/e" && pass "timeout named" || bad "msg: $(cat "$tmp/e")"
# repeat / interval
n=$(c --json -r 5 -i 0.05 robot sta | grep -c '"reply":"OK"'); [ "$n" -eq 5 ] && pass "-r 5 gives 5 replies" || bad "-r 5 gave $n"
# scripts: first ER stops (exit 1) unless --keep-going
printf 'robot sta\nraw robot XYZ\nrobot sta\n' >"$tmp/s1"
n=$(c -f "$tmp/s1" 2>/dev/null | grep -c "robot: "); rc=$?
c -f "$tmp/s1" >/dev/null 2>&1; expect_rc 1 $? "script stops at the first ER"
[ "$n" -eq 2 ] && pass "script stopped after the ER line" || bad "script ran $n commands"
n=$(c -k -f "$tmp/s1" 2>/dev/null | grep -c "robot: ")
[ "$n" -eq 3 ] && pass "--keep-going runs on" || bad "--keep-going ran $n"
c -k -f "$tmp/s1" >/dev/null 2>&1; expect_rc 1 $? "--keep-going still reports the ER"
printf 'robot sta\nrobot flyaway\n' >"$tmp/s2"
c -f "$tmp/s2" 2>"$tmp/e" >/dev/null; expect_rc 2 $? "script syntax error"
grep -q "s2:2: unknown command 'flyaway'" "$tmp/e" && pass "syntax error with file:line" || bad "msg: $(cat "$tmp/e")"
# config file: ports from the file, options override it
cat >"$tmp/cfg.ini" <<INI
[robot]
host = 127.0.0.1
port = 21011
[platform]
port = 21012
[cli]
reply_timeout_ms = 1500
INI
"$cli" -c "$tmp/cfg.ini" robot sta >/dev/null; expect_rc 0 $? "config file"
printf '[robot]\nprot = 1\n' >"$tmp/bad.ini"
"$cli" -c "$tmp/bad.ini" robot sta 2>"$tmp/e"; expect_rc 2 $? "config typo rejected"
grep -q "bad.ini:2:1: \[robot\]: unknown key 'prot'" "$tmp/e" && pass "config typo: line, column and key named" || { bad "config typo message"; cat "$tmp/e"; }
printf '[robot]\nport = 1e39\n' >"$tmp/bad2.ini"
"$cli" -c "$tmp/bad2.ini" robot sta 2>"$tmp/e"; expect_rc 2 $? "config port 1e39 rejected"
grep -q "bad2.ini:2:8: \[robot\] port: '1e39' is not an integer" "$tmp/e" && pass "config 1e39: line, column, key, value named" || { bad "config 1e39 message"; cat "$tmp/e"; }
timeout 20 "$cli" -c /dev/zero robot sta 2>"$tmp/e"; expect_rc 2 $? "config /dev/zero refused, not hung"
timeout 20 "$cli" -f /dev/zero 2>"$tmp/e"; expect_rc 2 $? "script /dev/zero refused, not hung"
grep -q "/dev/zero:1: column 1: control byte .x00" "$tmp/e" && pass "script NUL byte named" || { bad "script NUL message"; cat "$tmp/e"; }
# the spec's section 6 pick-and-place task, end to end
c -f fixtures/cell/pick_and_place.cell >"$tmp/pp" 2>&1; rc=$?
expect_rc 0 $rc "pick_and_place.cell"
[ "$(grep -c ": OK$" "$tmp/pp")" -eq 18 ] && pass "pick-and-place: every instruction OK" || { bad "pick-and-place replies"; cat "$tmp/pp"; }
grep -q "40.000      25.000       8.000     -0.5000" "$tmp/pp" && pass "robot ends at the place pose" || bad "final robot pose"
grep -q "0.7854     -0.2618" "$tmp/pp" && pass "platform ends at the pick orientation" || bad "final platform pose"
grep -q "conditioning 127.0.0.1:[0-9]* command: HND+00001CLOSE: blow off" "$tmp/sim.log" && pass "blow pulse reached the conditioning controller" || bad "blow pulse not logged"
# CLO closes; the next command reconnects
printf 'robot clo\nrobot sta\n' | c >/dev/null 2>&1; expect_rc 0 $? "CLO then reconnect"
# help, version
"$cli" --help | grep -q "Examples:" && pass "--help has examples" || bad "--help"
"$cli" --version | grep -q "^cell-cli [0-9]" && pass "--version" || bad "--version"
c help mov | grep -q "absolute needs every axis" && pass "help mov" || bad "help mov"
# REPL through a pty
mkdir -p "$tmp/home"
timeout 60 python3 tests/e2e/cell_cli_pty.py "$cli" 21011 "$tmp/home" || fail=1
# ^C and ^D in the REPL, against a cell-sim at real speed (a motion long enough to cut)
"$build/bin/cell-sim" -p 21051 >"$tmp/sim2.log" 2>&1 & pids="$pids $!"
wait_listen 21053 || bad "cell-sim on 21051 did not start"
timeout 90 python3 tests/e2e/cell_cli_intr.py "$cli" 21051 "$tmp/home" || fail=1
# SIGINT in a script: STP to the motion the script started, exit 130
printf 'robot srvof\nrobot rst\nrobot srvon\nrobot ovr 1\nrobot mov abs x=-100 y=-100 z=100 c=0\nwait robot stopped 60\n' >"$tmp/s3"
"$cli" -p 21051 -f "$tmp/s3" >"$tmp/o3" 2>"$tmp/e3" & cp=$!
i=0
until [ "$(grep -c '^OK$' "$tmp/o3")" -ge 5 ]; do i=$((i + 1)); [ $i -gt 500 ] && break; sleep 0.02; done
sleep 0.3
kill -INT "$cp"; wait "$cp"; expect_rc 130 $? "SIGINT during a script's wait"
grep -q "robot: interrupted: sending STP" "$tmp/e3" && pass "SIGINT: STP sent to the robot the script moved" || bad "SIGINT: $(cat "$tmp/e3")"
out=$("$cli" -p 21051 --no-raw robot sta 2>&1)
echo "$out" | grep -q "robot: stopped" && pass "SIGINT: the robot is stopped afterwards" || bad "after SIGINT: $out"
# a monitor does not stop a robot it did not move
"$cli" -p 21051 robot mov rel x=5 >/dev/null 2>&1
"$cli" -p 21051 -r -1 -i 0.05 robot sta >"$tmp/o4" 2>"$tmp/e4" & cp=$!
sleep 0.5; kill -INT "$cp"; wait "$cp"; expect_rc 130 $? "SIGINT ends -r -1"
grep -q "STP" "$tmp/e4" && bad "a monitor sent STP: $(cat "$tmp/e4")" || pass "SIGINT: a monitor sends no STP"
tail -1 "$tmp/o4" | grep -q "^OKT" && pass "SIGINT: the motion the monitor watched goes on" || bad "monitor: $(tail -2 "$tmp/o4")"
exit $fail
