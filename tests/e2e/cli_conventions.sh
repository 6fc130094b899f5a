#!/bin/sh
# The conventions every tool shares (lib/host/c4gh_cli.c): a bad option is exit 2 and
# exactly one line on stderr; an output file that cannot be written fails at start-up,
# before any session, with the tool's documented exit code, naming the path once with the
# system's reason; bytes that are not printable are shown escaped.
# Ports: UDP 31400-31409 (c4g-server), 41400-41409 (c4g-sim).
set -u
build=$1
bin=$build/bin
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
pass() { echo "PASS: $*"; }
bad() { echo "FAIL: $*"; fail=1; }

# bad_option TOOL [SUBCOMMAND...]: --bogus and -Z, exit 2, one line, the shared wording
bad_option() {
  tool=$1; shift
  name=$tool; [ $# -gt 0 ] && name="$tool $*"
  # c4g-replay's commands keep the tool's name in messages; c4g-ident's carry the command
  who=$name; [ "$tool" = c4g-replay ] && who=$tool
  for opt in --bogus -Z; do
    "$bin/$tool" "$@" "$opt" >"$tmp/out" 2>"$tmp/err"; rc=$?
    lines=$(wc -l <"$tmp/err")
    want="$who: unrecognized option '$opt' (see $name --help)"
    if [ "$rc" -eq 2 ] && [ "$lines" -eq 1 ] && [ "$(cat "$tmp/err")" = "$want" ] && [ ! -s "$tmp/out" ]; then
      pass "$name $opt: exit 2, one line"
    else
      bad "$name $opt: exit $rc, $lines line(s): $(head -3 "$tmp/err")"
    fi
  done
}
for t in c4g-server c4g-sim c4g-replay c4g-ident cell-cli cell-sim; do bad_option "$t"; done
for c in summary check export rerun live plot; do bad_option c4g-replay "$c"; done
for c in fit excite; do bad_option c4g-ident "$c"; done

# a missing option value: exit 2, one line
"$bin/c4g-server" --json >/dev/null 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "option '--json' needs a value (see c4g-server --help)" "$tmp/err" \
  && pass "missing value: exit 2, one line" || bad "missing value: exit $rc: $(cat "$tmp/err")"

# out_fail WANT_RC OPTION PATH -- COMMAND...: fails fast, one line "OPTION PATH: reason"
# (the path once), and no session ran (nothing on stdout, well before the run's length)
out_fail() {
  want=$1 opt=$2 path=$3; shift 4
  start=$(date +%s)
  timeout 20 "$@" >"$tmp/out" 2>"$tmp/err"; rc=$?
  took=$(( $(date +%s) - start ))
  shown=$(printf '%s' "$path" | sed 's/\x01/\\x01/g')
  n=$(grep -o -F "$shown" "$tmp/err" | wc -l)
  if [ "$rc" -eq "$want" ] && [ "$n" -eq 1 ] && grep -q -F -e "$opt $shown: " "$tmp/err" && [ "$took" -lt 4 ] \
      && ! grep -q "session ended\|Summary" "$tmp/out"; then
    pass "$(basename "$1") $opt $shown: exit $rc at start-up: $(grep -F "$shown" "$tmp/err")"
  else
    bad "$(basename "$1") $opt $path: exit $rc (want $want) after ${took}s: $(cat "$tmp/err")"
  fi
}
S="$bin/c4g-server -c 127.0.0.1 --idle-timeout 6"
# shellcheck disable=SC2086
out_fail 1 --json /nonexistent/x.json -- $S -p 31400 --json /nonexistent/x.json
# shellcheck disable=SC2086
out_fail 1 --pcap /x/y.pcap -- $S -p 31401 --pcap /x/y.pcap
# shellcheck disable=SC2086
out_fail 1 --moni "$tmp" -- $S -p 31402 --moni "$tmp"
# shellcheck disable=SC2086
out_fail 1 --log /x/y.log -- $S -p 31403 --log /x/y.log
touch "$tmp/ro.json"; chmod 444 "$tmp/ro.json"
if [ "$(id -u)" -ne 0 ]; then
  # shellcheck disable=SC2086
  out_fail 1 --json "$tmp/ro.json" -- $S -p 31404 --json "$tmp/ro.json"
fi
ctl=$(printf '/no\001where/x.json')
# shellcheck disable=SC2086
out_fail 1 --json "$ctl" -- $S -p 31405 --json "$ctl"
grep -q 'no\\x01where' "$tmp/err" && pass "unprintable byte escaped" || bad "escape: $(cat "$tmp/err")"
# bytes of a bad input file are escaped too
printf 'garb\001age\n' >"$tmp/ctl.csv"
"$bin/c4g-ident" fit "$tmp/ctl.csv" >/dev/null 2>"$tmp/err"; rc=$?
if [ "$rc" -eq 2 ] && grep -q "ctl.csv:1: .*header 'garb\\\\x01age'" "$tmp/err"; then
  pass "c4g-ident: a bad file's bytes escaped, exit 2"
else
  bad "c4g-ident bad file: exit $rc: $(cat -v "$tmp/err")"
fi
out_fail 4 --csv /x/y.csv -- "$bin/c4g-sim" -p 41400 -n 3000 --csv /x/y.csv
out_fail 4 --pcap /x/y.pcap -- "$bin/c4g-sim" -p 41401 -n 3000 --pcap /x/y.pcap
out_fail 1 --output /x/y.png -- "$bin/c4g-replay" plot --output /x/y.png fixtures/replay/mode4.pcap
out_fail 1 --out /x/arm1.ini -- "$bin/c4g-ident" fit -o /x/arm1.ini fixtures/replay/mode4.pcap
out_fail 1 --plot /x/plots -- "$bin/c4g-ident" fit --plot /x/plots fixtures/replay/mode4.pcap
out_fail 1 --out /x/e.csv -- "$bin/c4g-ident" excite -o /x/e.csv

# an input file: the system's reason, the path once
"$bin/cell-cli" -c /nonexistent.ini robot sta 2>"$tmp/err"; rc=$?
[ "$rc" -eq 2 ] && grep -q "/nonexistent.ini: .*No such file or directory" "$tmp/err" \
  && [ "$(grep -o /nonexistent.ini "$tmp/err" | wc -l)" -eq 1 ] && pass "cell-cli -c missing: $(cat "$tmp/err")" \
  || bad "cell-cli -c missing: exit $rc: $(cat "$tmp/err")"

# c4g-sim -n N: a progress line on stderr when it is a terminal, nothing when it is a file
"$bin/c4g-server" -p 31406 -c 127.0.0.1 -q --persist --idle-timeout 60 >/dev/null 2>&1 &
srv=$!
i=0; until ss -Huln "sport = :31406" | grep -q .; do i=$((i + 1)); [ $i -gt 1500 ] && break; sleep 0.02; done
timeout 90 python3 tests/e2e/progress_pty.py "$bin/c4g-sim" 31406 || fail=1
# the per-tick CSV (docs/csv.md): c4g-sim --csv has c4g-server --moni's columns first, and
# c4g-ident reads it
"$bin/c4g-sim" -p 31406 -n 300 --max-miss 500 --csv "$tmp/sim.csv" -q; rc=$?
head -1 "$tmp/sim.csv" | grep -q "^t_s,num,axis,arm,logical,rx_mode,rx_d1,rx_d2,rx_d3,rx_d4,rx_d5,rx_e1,rx_e2,rx_e3,tx_infpar,tx_mode,tx_d1,tx_d2,tx_d3,tx_d4,tx_d5,tick,sent,reply_ok,rx_infpar,rx_cmd$" \
  && pass "c4g-sim --csv: the per-tick header" || bad "c4g-sim --csv header: $(head -1 "$tmp/sim.csv")"
rows=$(($(wc -l <"$tmp/sim.csv") - 1))
[ "$rc" -eq 0 ] && [ "$rows" -eq 1800 ] && pass "c4g-sim --csv: 300 ticks x 6 axes = $rows rows" || bad "c4g-sim --csv: exit $rc, $rows rows"
"$bin/c4g-ident" fit "$tmp/sim.csv" >"$tmp/fit.out" 2>&1; rc=$?
[ "$rc" -ne 2 ] && grep -q "moni CSV, 300 controller ticks" "$tmp/fit.out" && pass "c4g-ident reads c4g-sim's per-tick CSV (exit $rc)" \
  || bad "c4g-ident on c4g-sim's CSV: exit $rc: $(head -3 "$tmp/fit.out")"
"$bin/c4g-replay" export --ticks fixtures/replay/mode4.pcap >"$tmp/ticks.csv"; rc=$?
[ "$rc" -eq 0 ] && [ "$(head -1 "$tmp/ticks.csv")" = "$(head -1 "$tmp/sim.csv" | sed 's/,tick,sent,reply_ok,rx_infpar,rx_cmd$//')" ] \
  && pass "c4g-replay export --ticks: the same header" || bad "export --ticks: exit $rc: $(head -1 "$tmp/ticks.csv")"
"$bin/c4g-ident" fit "$tmp/ticks.csv" >"$tmp/fit2.out" 2>&1; rc=$?
[ "$rc" -ne 2 ] && grep -q "moni CSV" "$tmp/fit2.out" && pass "c4g-ident reads export --ticks (exit $rc)" || bad "c4g-ident on export --ticks: exit $rc"
kill "$srv" 2>/dev/null; wait "$srv" 2>/dev/null
exit $fail
