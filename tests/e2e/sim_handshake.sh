#!/bin/sh
# c4g-sim start-up handshake on the wire, read back from its pcap with tshark:
# 9 sync packets (NUM 1..9) answered with 732 bytes (NUM + 1), the 1200-byte init packet
# (NUM 10) echoed with NUM 11, 2 more syncs (NUM 11, 12), then cyclic packets from NUM 13.
# Also: the pcap payloads equal what an independent reader of the file finds.
. tests/e2e/helpers/sim_lib.sh
command -v tshark >/dev/null || fail "tshark not installed"
next_port; start_pc $PORT
run_sim -p $PORT -n 40 $STALL_OK --pcap "$T/h.pcap" --json >"$T/h.json"; rc=$?
expect_eq "exit status" $rc 0
tshark -r "$T/h.pcap" -T fields -e udp.dstport -e udp.length -e udp.payload 2>/dev/null >"$T/h.txt"
[ -s "$T/h.txt" ] || fail "tshark read nothing"
: >"$T/tx.txt"; : >"$T/rx.txt"
while read -r dport ulen payload; do
  h=$(echo "$payload" | cut -c1-8)
  num=$(( 0x$(echo "$h" | cut -c7-8)$(echo "$h" | cut -c5-6)$(echo "$h" | cut -c3-4)$(echo "$h" | cut -c1-2) ))
  if [ "$dport" = "$PORT" ]; then echo "$((ulen - 8)) $num" >>"$T/tx.txt"; else echo "$((ulen - 8)) $num" >>"$T/rx.txt"; fi
done <"$T/h.txt"
# Each direction in its own order: how the two interleave depends on the host's scheduling
# (a reply may come after the next packet left), what each side sends does not.
want_tx=""; want_rx=""
i=1; while [ $i -le 9 ]; do want_tx="$want_tx$i:228 $i;"; want_rx="$want_rx$i:732 $((i + 1));"; i=$((i + 1)); done
want_tx="${want_tx}10:1200 10;11:228 11;12:228 12;13:228 13;"
want_rx="${want_rx}10:1200 11;11:732 12;12:732 13;13:228 14;"
got_tx=$(head -13 "$T/tx.txt" | awk '{ printf "%d:%s;", NR, $0 }')
got_rx=$(head -13 "$T/rx.txt" | awk '{ printf "%d:%s;", NR, $0 }')
expect_eq "to the PC: 9 sync (228 B, NUM 1..9), init (1200 B, NUM 10), 2 sync (NUM 11, 12), cyclic from NUM 13" "$got_tx" "$want_tx"
expect_eq "from the PC: 732 B NUM n + 1 per sync, the init echoed with NUM 11, cyclic replies 228 B" "$got_rx" "$want_rx"
n_tx=$(wc -l <"$T/tx.txt"); n_rx=$(wc -l <"$T/rx.txt")
expect_eq "datagrams to the PC (9 + 1 + 2 + 40)" "$n_tx" 52
# the PC answers each one once; the last replies may come after the sim stopped listening
[ "$n_rx" -ge 50 ] && [ "$n_rx" -le 52 ] || fail "$n_rx datagrams from the PC for 52 sent"; ok "$n_rx datagrams from the PC for 52 sent"
# every packet the sim judged got its reply in time, or was counted (missing = the PC was
# late; on a busy host that can happen, and is not what this test is about)
expect_eq "every packet judged" "$(( $(jget "$T/h.json" ok) + $(jget "$T/h.json" missing) + $(jget "$T/h.json" unjudged) ))" 52
# Independent oracle: parse the pcap file itself and compare every payload with tshark.
python3 - "$T/h.pcap" "$T/h.txt" <<'PY' || fail "pcap payloads differ from tshark's"
import struct, sys
data = open(sys.argv[1], 'rb').read()
magic, = struct.unpack('<I', data[:4])
assert magic == 0xa1b2c3d4, hex(magic)
linktype, = struct.unpack('<I', data[20:24]); assert linktype == 1
off, mine = 24, []
while off < len(data):
    ts, us, incl, orig = struct.unpack('<IIII', data[off:off + 16]); off += 16
    f = data[off:off + incl]; off += incl
    assert f[12:14] == b'\x08\x00' and f[23] == 17
    ih = f[14:34]; s = sum(struct.unpack('>10H', ih))
    while s >> 16: s = (s & 0xffff) + (s >> 16)
    assert s == 0xffff, 'bad IPv4 header checksum'
    ulen, = struct.unpack('>H', f[38:40])
    mine.append(f[42:42 + ulen - 8].hex())
theirs = [l.rstrip('\n').split('\t')[2] for l in open(sys.argv[2])]
assert mine == theirs, (len(mine), len(theirs))
print('ok: %d payloads identical (pcap reader vs tshark), IPv4 checksums valid' % len(mine))
PY
# A PC whose init echo differs from the init packet (one byte of AzLim, axis 1) holds other
# limits than the controller's: the session fails at once (ERR_C4GOPEN, exit 1, drives off),
# with the byte offset and the field named.
next_port; start_pc $PORT --alter-init
run_sim -p $PORT -n 200 --json >"$T/a.json" 2>"$T/a.err"; rc=$?
expect_eq "altered init echo: exit status" $rc 1
grep -q '"name":"ERR_C4GOPEN"' "$T/a.json" || fail "altered init echo: no ERR_C4GOPEN in $(cat "$T/a.json")"
ok "altered init echo: ERR_C4GOPEN raised"
grep -q "init echo differs from the init packet sent at byte offset 549 (field AzLim" "$T/a.err" ||
  fail "altered init echo: message: $(cat "$T/a.err")"
ok "altered init echo: offset 549 and field AzLim named"
expect_eq "altered init echo: no cyclic packet sent" "$(jget "$T/a.json" cyclic)" 0
expect_eq "altered init echo: drives off" "$(jget "$T/a.json" drive_on)" false
exit 0
