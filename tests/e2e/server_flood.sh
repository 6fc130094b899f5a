#!/bin/sh
# c4g-server end to end, floods and amplification:
#   a) 30 synchronization packets of 48 bytes (1 axis) to a server in its start-up: the
#      first 18 (the handshake's 9, each of which may be duplicated on the path) get the
#      field's 732-byte reply, the rest none. At most 18 x 732 bytes per start-up.
#   b) c4g-sim runs 3000 ticks (6 s, the real controller's patience: 10 missing replies in a
#      row raise ERR_C4GOPEN_UDP) against the server while a sender on 127.0.0.2, which -c
#      refuses, sends zero-filled 228-byte datagrams as fast as one process can, for 4 s,
#      from the moment the server's socket is connected to the controller. The kernel drops
#      them (the server sees none of them: foreign_address 0), and the session holds
#      without --rt.
# The flood and the simulator share the host's 2 cores with the test's busy loops: a failed
# run that the host held up (c4g-sim overran its own period) is made again.
. tests/e2e/server_helpers/lib.sh "$1"
[ -x "$SIM" ] || { echo "server_flood: $SIM not built"; exit 1; }
command -v python3 >/dev/null 2>&1 || { echo "server_flood: python3 needed"; exit 1; }
ATK=tests/e2e/server_helpers/attacker.py
FLOOD=$BUILD/e2e-server/flood
mkdir -p "$BUILD/e2e-server"
if [ ! -x "$FLOOD" ] || [ tests/e2e/server_helpers/flood.c -nt "$FLOOD" ]; then
    ${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Werror -o "$FLOOD" \
        tests/e2e/server_helpers/flood.c || { echo "server_flood: cannot build flood"; exit 1; }
fi

connected() { grep -q "socket connected to the controller" "$T/$1.err" 2>/dev/null || ! kill -0 "$SPID" 2>/dev/null; }

# flooded NAME PORT: the session under a flood from 127.0.0.2
flooded() {
    name=$1; port=$2
    start_server "$name" "$port"
    timeout 50 "$SIM" -p "$port" -n 3000 --json >"$T/$name.sim.json" 2>"$T/$name.sim.err" &
    MPID=$!
    PIDS="$PIDS $MPID"
    wait_until 20 connected "$name"
    "$FLOOD" "$port" 127.0.0.2 228 4 >"$T/$name.flood" 2>"$T/$name.flood.err"
    wait "$MPID"
    SIMRC=$?
    kill "$SPID" 2>/dev/null
    wait_server
}
# the host held a failed run up: c4g-sim overran its own period (the flood, the busy loops
# and both processes share 2 cores). A real loss fails every run.
flood_stalled() {
    [ "$(jv "$T/$1.sim.json" result)" != ok ] && [ "$(jv "$T/$1.sim.json" overruns)" -gt 0 ] 2>/dev/null
}

echo "a) 30 syncs of 48 bytes: 9 answered:"; F0=$FAILS
# (python can take seconds to start on the loaded host: the server waits for it, and is
# stopped once the attacker is done)
start_server amp 31171
python3 "$ATK" 31171 sync48 --count 30 --gap-us 1000 --listen-s 0.5 >"$T/amp.atk" 2>"$T/amp.atk.err"
kill "$SPID" 2>/dev/null
wait_server
ok "amp: 30 sent, 18 answered" eq "$(kv "$T/amp.atk" sent)/$(kv "$T/amp.atk" replies)" 30/18
ok "amp: 18 x 732 bytes back (for 30 x 48 = 1440 sent)" eq "$(kv "$T/amp.atk" reply_bytes)" 13176
ok "amp: the rest counted as sync_excess" eq "$(jv "$T/amp.json" sync_excess)" 12
ok "amp: logged" has "$T/amp.err" "dropped a 48-byte sync: more than 18 before an init packet, not answered"
[ "$FAILS" -eq "$F0" ] || dump amp
echo "b) flood from 127.0.0.2 at full rate during a session (no --rt):"; F0=$FAILS
again_while flood_stalled flooded flood 31170
echo "       flood: $(cat "$T/flood.flood"); c4g-sim: result $(jv "$T/flood.sim.json" result)," \
    "missing $(jv "$T/flood.sim.json" missing), max in a row $(jv "$T/flood.sim.json" max_consecutive_missing)"
ok "flood: the flood ran (>= 20000 datagrams)" ge "$(kv "$T/flood.flood" sent)" 20000
ok "flood: the socket was connected to the controller" has "$T/flood.err" "socket connected to the controller 127.0.0.1:"
ok "flood: c4g-sim exit 0, result ok (no ERR_C4GOPEN_UDP)" eq "$SIMRC/$(jv "$T/flood.sim.json" result)" 0/ok
ok "flood: the server did not lose the controller" eq "$(jv "$T/flood.json" lost)" 0
ok "flood: none of the flood reached the server (foreign_address 0)" eq "$(jv "$T/flood.json" foreign_address)" 0
[ "$FAILS" -eq "$F0" ] || dump flood

finish
