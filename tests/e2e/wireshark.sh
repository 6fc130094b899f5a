#!/bin/sh
# The Wireshark dissector (tools/wireshark/c4gopen.lua) under real tshark, checked packet by
# packet against an independent decode of the same captures (tests/e2e/wireshark_check.py):
# - fixtures/wireshark/mode4-short.pcap (c4g-server --sine 0.25,2,0.5 against c4g-sim -S
#   fixtures/server/sim_mode4.scn, PC on port 31000): sender, type, NUM, INFPAR, CMD, modes,
#   D1..D5 and EXT1..EXT3 as exact float32 of every packet, all 300 fields of the init
#   packet and its echo, reply links, display filters; the sender again with Decode As only
#   (no port preference) and from a cut that starts in mid-stream on a PC packet;
# - crafted datagrams on the default port 1000 (NaN and infinity, unknown mode 77, 13 and
#   733 bytes, NUM out of range, an init packet out of range): their expert info; and every
#   mode code of the header's C4G_MODE_TABLE, named as the table names it; sync packets
#   whose replies come late, each reply still a sync reply;
# - a fresh two-arm capture (c4g-sim -c fixtures/sim/two-arms.ini, 1 ms period, 9 axes):
#   the same full comparison, arms and axes from the init packet's OpenAx;
# - `c4g-replay export` against the dissector, tick by tick (controller and reply frames,
#   NUMs, INFPAR, CMD, every axis's mode and floats as exact float32 both ways): on the two
#   captures above and on c4g-replay fixtures chosen for what they add (mode4-short has the
#   mode 4 exit already): two arms with their own INFPAR and EXIT_FROM_OPEN, a plus-one reply
#   late past the next packet, duplicated controller packets (no new tick), NaN from the
#   controller (unanswered), infinity from the PC (a reply the controller refuses), and two
#   more link layers.
set -u
B=${1:?usage: sh tests/e2e/wireshark.sh BUILD_DIR}
LUA=tools/wireshark/c4gopen.lua
CHECK="python3 tests/e2e/wireshark_check.py --lua $LUA"
fail() { echo "FAIL: $*"; exit 1; }
command -v tshark >/dev/null || fail "tshark not installed"
command -v editcap >/dev/null || fail "editcap not installed"
T=$(mktemp -d "${TMPDIR:-/tmp}/c4gws.XXXXXX")
SPID=""
cleanup() {
  [ -n "$SPID" ] && kill "$SPID" 2>/dev/null && wait "$SPID" 2>/dev/null
  rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 1' INT TERM
rc=0
# (every tshark run of the checker fails on a Lua error on stderr)
RP=$B/bin/c4g-replay
[ -x "$RP" ] || fail "$RP not built"
$CHECK --tmp "$T" capture fixtures/wireshark/mode4-short.pcap --pc-port 31000 \
  --name mode4-short --filters --direction --replay "$RP" || rc=1
F=fixtures/replay
$CHECK export-compare --replay "$RP" $F/two-arms.pcap:46116 $F/fault-late.pcap:46123 \
  $F/fault-duplicate.pcap:46127 $F/data-nan-ctrl-d3.pcap:46204 $F/data-inf-pc-d1.pcap:46205 \
  $F/fmt-vlan.pcap:46300 $F/fmt-sll2.pcap:46300 || rc=1
$CHECK --tmp "$T" crafted --init-bin fixtures/vectors/init-fig10-1.bin \
  --header include/c4gopen_wire.h || rc=1
# A fresh capture: two arms, 1 ms period; the simulator records both directions.
if [ -x "$B/bin/c4g-server" ] && [ -x "$B/bin/c4g-sim" ]; then
  . tests/e2e/helpers/wait.sh
  PORT=$(( 36000 + ($$ % 2000) ))
  while ss -Huln "sport = :$PORT" | grep -q .; do PORT=$((PORT + 1)); done
  "$B/bin/c4g-server" -p "$PORT" -c 127.0.0.1 --max-seconds 30 --lost-timeout-ms 2000 \
    >"$T/srv.out" 2>"$T/srv.err" &
  SPID=$!
  srv_up() { grep -qs "listening on" "$T/srv.err" || ! kill -0 "$SPID" 2>/dev/null; }
  wait_until 30 srv_up
  timeout 30 "$B/bin/c4g-sim" --bind 127.0.0.1 -p "$PORT" -c fixtures/sim/two-arms.ini -n 150 \
    --max-miss 500 -q --pcap "$T/two.pcap" >"$T/sim.out" 2>&1
  kill "$SPID" 2>/dev/null; wait "$SPID" 2>/dev/null; SPID=""
  if [ -s "$T/two.pcap" ]; then
    $CHECK --tmp "$T" capture "$T/two.pcap" --pc-port "$PORT" --name two-arms \
      --replay "$RP" || rc=1
  else
    echo "FAIL: no two-arm capture: $(cat "$T/sim.out" "$T/srv.err")"; rc=1
  fi
else
  echo "FAIL: $B/bin/c4g-server or c4g-sim not built"; rc=1
fi
exit $rc
