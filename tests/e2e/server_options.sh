#!/bin/sh
# c4g-server: command line, INI file, input files, exit codes, real-time refusals and the
# pcap / moni / JSON outputs. Bad input never crashes the server: it names what was wrong.
. tests/e2e/server_helpers/lib.sh "$1"
build_stub

echo "help, version, bad options:"
"$SRV" --help >"$T/help" 2>&1; rc=$?
ok "--help exit 0" eq "$rc" 0
ok "--help documents exit codes" has "$T/help" "Exit codes"
ok "--help has examples" has "$T/help" "Examples"
ok "--version names the library version" has "$("$SRV" --version >"$T/ver"; echo "$T/ver")" "$(sed -n 's/^#define C4G_VERSION_STRING "\(.*\)"/\1/p' include/c4gopen.h)"
"$SRV" --bogus >/dev/null 2>"$T/e1"; rc=$?
ok "unknown option: exit 2" eq "$rc" 2
ok "unknown option named" has "$T/e1" "'--bogus'"
"$SRV" --sine 1 >/dev/null 2>"$T/e2"; rc=$?
ok "bad value: exit 2" eq "$rc" 2
ok "bad value names option and value" has "$T/e2" "sine: bad value '1'"
"$SRV" --arm 7 --sine 1,1 >/dev/null 2>"$T/e3"; rc=$?
ok "bad arm: exit 2" eq "$rc" 2
"$SRV" -c 300.1.1.1 -p 31050 >/dev/null 2>"$T/e4"; rc=$?
ok "bad controller address: exit 2" eq "$rc" 2
ok "bad controller address named" has "$T/e4" "300.1.1.1"

echo "input files:"
printf 't,ax1\n0,0\n0.5,abc\n' >"$T/bad.csv"
"$SRV" --traj "$T/bad.csv" >/dev/null 2>"$T/e5"; rc=$?
ok "bad trajectory: exit 2" eq "$rc" 2
ok "bad trajectory: file, line, column, value" has "$T/e5" "bad.csv:3:5: column 2 (axis offset \[turns\]): 'abc' is not a decimal number"
printf 't,ax1\n0,0\n0,1\n' >"$T/bad2.csv"
"$SRV" --traj "$T/bad2.csv" >/dev/null 2>"$T/e6"; rc=$?
ok "non-increasing time: exit 2, named" has "$T/e6" "bad2.csv:3:1: column 1 (t \[s\])"
printf '1 11 0.5\n' >"$T/bad.ff"
"$SRV" --ff "$T/bad.ff" >/dev/null 2>"$T/e7"; rc=$?
ok "bad feedforward file: exit 2" eq "$rc" 2
ok "bad feedforward file: line, field, value" has "$T/e7" "bad.ff:1:3: field 2 (axis): '11' is out of range 1..10"
"$SRV" --traj "$T/nonexistent.csv" >/dev/null 2>"$T/e8"; rc=$?
ok "missing file: exit 2 and named" has "$T/e8" "nonexistent.csv: cannot open"
printf '[server]\nport = 31051\nbogus-key = 3\n' >"$T/bad.ini"
"$SRV" --config "$T/bad.ini" >/dev/null 2>"$T/e9"; rc=$?
ok "bad INI key: exit 2" eq "$rc" 2
ok "bad INI key named with file, line, column and section" has "$T/e9" "bad.ini:3:1: \[server\] unknown setting 'bogus-key'"
printf '[arm9]\nsine = 1,1\n' >"$T/bad2.ini"
"$SRV" --config "$T/bad2.ini" >/dev/null 2>"$T/e10"; rc=$?
ok "bad INI section: exit 2" eq "$rc" 2
# Files users write: out-of-range numbers and endless input are refused at load.
printf 't,ax1\n0,0\n1,1e39\n' >"$T/big.csv"
"$SRV" --traj "$T/big.csv" >/dev/null 2>"$T/e13"; rc=$?
ok "trajectory 1e39: exit 2" eq "$rc" 2
ok "trajectory 1e39 named" has "$T/e13" "big.csv:3:3: column 2 (axis offset \[turns\]): '1e39' is out of range -1000000..1000000"
printf '1 1 1e30\n' >"$T/big.ff"
"$SRV" --ff "$T/big.ff" >/dev/null 2>"$T/e14"; rc=$?
ok "feedforward 1e30 named" has "$T/e14" "big.ff:1:5: field 3 (c0): '1e30' is out of range -1000000..1000000"
# c4g-ident's parameter files: an edited copy, a bad value, two files for one arm
sed 's/^gb = 7.5$/gb = 8.5/' fixtures/server/ff_ident_example.ini >"$T/edited.ini"
"$SRV" --ff "$T/edited.ini" >/dev/null 2>"$T/e17"; rc=$?
ok "edited model file: exit 2" eq "$rc" 2
ok "edited model file: checksum mismatch named" has "$T/e17" \
    "edited.ini:17:12: \[model\] checksum: checksum mismatch: the file was edited after c4g-ident wrote it"
sed 's/^Ja = 0.00314159$/Ja = nan/' fixtures/server/ff_ident_example.ini >"$T/nan.ini"
"$SRV" --ff "$T/nan.ini" >/dev/null 2>"$T/e18"; rc=$?
ok "model file with NaN: exit 2" eq "$rc" 2
ok "model file with NaN: file, line, section, key" has "$T/e18" "nan.ini:21:6: \[axis 1\] Ja: 'nan' is not a finite number"
"$SRV" --ff fixtures/server/ff_ident_example.ini --ff fixtures/server/ff_example.txt >/dev/null 2>"$T/e19"; rc=$?
ok "two files for arm 1: exit 2" eq "$rc" 2
ok "two files for arm 1: both named" has "$T/e19" \
    "ff_example.txt:15:1: arm 1 axis 1 is already set by fixtures/server/ff_ident_example.ini:19"
for opt in --traj --ff --config; do
  timeout 20 "$SRV" $opt /dev/zero >/dev/null 2>"$T/e15"; rc=$?
  ok "$opt /dev/zero refused (not hung): exit 2" eq "$rc" 2
  ok "$opt /dev/zero: the limit named" has "$T/e15" "/dev/zero: more than"
done
printf '[server]\nport = 31051\n  idle-timeout = 1e300\n' >"$T/big.ini"
"$SRV" --config "$T/big.ini" >/dev/null 2>"$T/e16"; rc=$?
ok "INI 1e300: exit 2" eq "$rc" 2
ok "INI 1e300: line, column, key" has "$T/e16" "big.ini:3:18: \[server\] idle-timeout: '1e300' is out of range"

echo "INI example, idle timeout, port in use, RT refusal:"
"$SRV" --config fixtures/server/server_example.ini -p 31052 --idle-timeout 0.3 >"$T/ini.out" 2>"$T/ini.err"; rc=$?
ok "example INI loads; idle timeout: exit 4" eq "$rc" 4
ok "listening on the overridden port" has "$T/ini.err" "0.0.0.0:31052"
start_server busy 31053
"$SRV" -p 31053 -c 127.0.0.1 --idle-timeout 0.3 >/dev/null 2>"$T/e11"; rc=$?
ok "port in use: exit 1" eq "$rc" 1
ok "port in use: bind error named" has "$T/e11" "bind 0.0.0.0:31053"
kill "$SPID" 2>/dev/null
"$SRV" -p 31054 -c 127.0.0.1 --cpu 999 --idle-timeout 0.3 >/dev/null 2>"$T/e12"; rc=$?
ok "refused RT setting: says what and why, continues (idle exit 4)" eq "$rc" 4
ok "refused RT setting named" has "$T/e12" "CPU affinity to CPU 999 refused"
"$SRV" -p 31055 -c 127.0.0.1 --cpu 999 --rt-strict --idle-timeout 0.3 >/dev/null 2>"$T/e13"; rc=$?
ok "--rt-strict: refused RT setting is fatal (exit 1)" eq "$rc" 1

echo "outputs (pcap, moni, JSON), SIGINT:"
run_stub out 31056 --script 0:100,4:exit,0:50,504:1 -- --pcap "$T/out.pcap" --moni "$T/out.csv" --moni-type 21 --sine 0.1,1,1
ok "session ok" eq "$(kv "$T/out.stub" bad)" 0
ok "pcap written (pcap magic)" eq "$(od -An -tx1 -N4 "$T/out.pcap" | tr -d ' ')" d4c3b2a1
if command -v tshark >/dev/null 2>&1; then
    n=$(tshark -r "$T/out.pcap" -T fields -e udp.payload 2>/dev/null | grep -c .)
    ok "tshark reads every datagram in and out" eq "$n" "$(( $(jv "$T/out.json" rx) + $(jv "$T/out.json" tx) ))"
fi
ok "moni type 21 header" has "$T/out.csv" "moni type 21"
ok "moni rows: one per axis per cyclic packet" eq "$(grep -c '^[0-9]' "$T/out.csv")" "$(( $(jv "$T/out.json" cyclic) * 6 ))"
ok "JSON summary has timing, counters, safety" has "$T/out.json" '"timing":{.*"counters":{.*"safety":{'
start_server sig 31057
kill -INT "$SPID"
wait_server
ok "SIGINT: exit 5" eq "$SRC" 5
ok "SIGINT: report printed" has "$T/sig.out" "stopped by a signal"
finish
