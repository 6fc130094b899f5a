#!/bin/sh
# c4g-sim start-up handshake on the wire, read back from its pcap with tshark:
# 9 sync packets (NUM 1..9) answered with 732 bytes (NUM + 1), the 1200-byte init packet
# (NUM 10) echoed with NUM 11, 2 more syncs (NUM 11, 12), then cyclic packets from NUM 13.
# Also: the pcap payloads equal what an independent reader of the file finds.
. tests/e2e/helpers/sim_lib.sh
command -v tshark >/dev/null || fail "tshark not installed"
next_port; start_pc $PORT
run_sim -p $PORT -n 40 --pcap "$T/h.pcap" --json >"$T/h.json"; rc=$?
expect_eq "exit status" $rc 0
expect_eq "missing replies" "$(jget "$T/h.json" missing)" 0
tshark -r "$T/h.pcap" -T fields -e udp.dstport -e udp.length -e udp.payload 2>/dev/null >"$T/h.txt"
[ -s "$T/h.txt" ] || fail "tshark read nothing"
: >"$T/seq.txt"
while read -r dport ulen payload; do
  dir=rx; [ "$dport" = "$PORT" ] && dir=tx
  h=$(echo "$payload" | cut -c1-8)
  num=$(( 0x$(echo "$h" | cut -c7-8)$(echo "$h" | cut -c5-6)$(echo "$h" | cut -c3-4)$(echo "$h" | cut -c1-2) ))
  echo "$dir $((ulen - 8)) $num" >>"$T/seq.txt"
done <"$T/h.txt"
want=""
i=1; while [ $i -le 9 ]; do want="$want
tx 228 $i
rx 732 $((i + 1))"; i=$((i + 1)); done
want="$want
tx 1200 10
rx 1200 11
tx 228 11
rx 732 12
tx 228 12
rx 732 13
tx 228 13
rx 228 14"
got=$(head -26 "$T/seq.txt")
[ "$(echo "$want" | sed 1d)" = "$got" ] || { echo "$got"; fail "handshake sequence differs"; }
ok "handshake: 9 x (228 -> 732 B, NUM n -> n+1), init 1200 B NUM 10 -> 11, 2 syncs, cyclic from NUM 13"
n_tx=$(grep -c '^tx' "$T/seq.txt"); n_rx=$(grep -c '^rx' "$T/seq.txt")
expect_eq "datagrams to the PC (9 + 1 + 2 + 40)" "$n_tx" 52
[ "$n_rx" -ge 50 ] || fail "only $n_rx datagrams from the PC"; ok "$n_rx datagrams from the PC (>= 50)"
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
exit 0
