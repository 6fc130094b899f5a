#!/bin/sh
# examples/*.c compile against the public header and the static library (C99, pedantic,
# -Werror), and examples/mode4_loop.c runs a real mode-4 session against c4g-sim.
. tests/e2e/server_helpers/lib.sh "$1"
mkdir -p "$BUILD/examples"
for f in examples/*.c; do
    [ -f "$f" ] || continue
    b="$BUILD/examples/$(basename "$f" .c)"
    ${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -pedantic -Wall -Wextra -Werror -O2 -Iinclude \
        -o "$b" "$f" "$BUILD/lib/libc4gopen.a" -lm 2>"$T/cc.err"
    ok "$f compiles (C99, -pedantic -Werror, static lib)" eq "$?" 0 || cat "$T/cc.err"
done
ok "examples/mode4_loop.c is under 100 lines" le "$(wc -l <examples/mode4_loop.c)" 99
if [ -x "$SIM" ] && [ -x "$BUILD/examples/mode4_loop" ]; then
    "$BUILD/examples/mode4_loop" 31060 >"$T/ex.out" 2>"$T/ex.err" &
    EPID=$!; PIDS="$PIDS $EPID"
    sleep 0.3
    timeout 30 "$SIM" -p 31060 -S fixtures/server/sim_example.scn --json >"$T/ex.sim.json" 2>"$T/ex.sim.err"
    rc=$?
    i=0; while kill -0 "$EPID" 2>/dev/null && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
    ok "mode4_loop: sim scenario passed (mode 4 ran, EXIT_FROM_OPEN seen)" eq "$rc" 0
    ok "mode4_loop: robot moved +0.1 turns from 0.2" near "$(simpos "$T/ex.sim.json" 1)" 0.3 0.02
    ok "mode4_loop: ended on 504 with its report" has "$T/ex.out" "worst cycle"
fi
finish
