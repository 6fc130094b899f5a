#!/bin/sh
# c4g-sim special modes: 505 and 508 from the PC drive off with the matching error;
# 504 ends the communication; 506 resends the init packet without syncs; 502/503
# passive freezing stops the packets; selector change forces mode 0.
. tests/e2e/helpers/sim_lib.sh
next_port; start_pc $PORT --request 505@300
run_sim -p $PORT $STALL_OK -S fixtures/scenarios/mode0.scn --json >"$T/a.json"; rc=$?
expect_eq "505 from the PC: exit status" $rc 1
grep -q '"name":"ERR_C4GOPEN_DRIVEOFF_SERVER","message":"C4GOpen: Drive Off from Pc"' "$T/a.json" ||
  fail "505: $(cat "$T/a.json")"
expect_eq "505: drive on" "$(jget "$T/a.json" drive_on)" false

next_port; start_pc $PORT --request 508@300
run_sim -p $PORT $STALL_OK -S fixtures/scenarios/mode0.scn --json >"$T/b.json"; rc=$?
expect_eq "508 from the PC: exit status" $rc 1
grep -q '"name":"ERR_C4GOPEN_FOLLOW_ERROR","message":"C4GOpen: arm 1 axis 1 Following error out of range"' \
  "$T/b.json" || fail "508: $(cat "$T/b.json")"
ok "508: ERR_C4GOPEN_FOLLOW_ERROR arm 1 axis 1"

next_port; start_pc $PORT
run_sim -p $PORT $STALL_OK -S fixtures/scenarios/exit-open.scn --pcap "$T/c.pcap" --json >"$T/c.json"; rc=$?
expect_eq "504: exit status" $rc 0
wait_pc
grep -q "ended 1" "$T/ref_$PORT.log" || fail "504: the PC did not see the end ($(cat "$T/ref_$PORT.log"))"
ok "504: the PC's session ended"

next_port; start_pc $PORT
run_sim -p $PORT $STALL_OK -S fixtures/scenarios/restart.scn --pcap "$T/d.pcap" --json >"$T/d.json"; rc=$?
expect_eq "506: exit status" $rc 0
expect_eq "506: init packets sent" "$(jget "$T/d.json" init)" 2
expect_eq "506: sync packets sent (cold start only)" "$(jget "$T/d.json" sync)" 11
if command -v tshark >/dev/null; then
  n=$(tshark -r "$T/d.pcap" -Y "udp.dstport == $PORT && udp.length == 1208" 2>/dev/null | wc -l)
  expect_eq "506: 1200-byte datagrams to the PC in the pcap" "$n" 2
fi

next_port; start_pc $PORT
run_sim -p $PORT $STALL_OK -S fixtures/scenarios/freeze.scn --csv "$T/e.csv" --json >"$T/e.json"; rc=$?
[ $rc -eq 0 ] || cat "$T/e.json"
expect_eq "freeze: exit status" $rc 0
# one row per axis (docs/csv.md): ticks whose "sent" is 0, each counted once
silent=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "tick") t = i; if ($i == "sent") s = i }; next }
                  $s == 0 && !seen[$t]++' "$T/e.csv" | wc -l)
expect_eq "freeze: ticks without a packet (200 ms at 2 ms)" "$silent" 99
grep -q ',502,' "$T/e.csv" && grep -q ',503,' "$T/e.csv" || fail "freeze: 502/503 not sent"
ok "freeze: 502 then silence then 503"
expect_eq "freeze: errors" "$(grep -o "\"errors\":\[\]" "$T/e.json")" "\"errors\":[]"

next_port; start_pc $PORT
run_sim -p $PORT $STALL_OK -S fixtures/scenarios/selector.scn --json >"$T/f.json"; rc=$?
expect_eq "selector: exit status" $rc 1
grep -q '"message":"C4GOpen: arm 1 , forced 0 modality"' "$T/f.json" || fail "selector: $(cat "$T/f.json")"
expect_eq "selector: expectations failed" "$(jget "$T/f.json" expect_failed)" 0
exit 0
