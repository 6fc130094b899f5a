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
ok "examples/mode4_loop.c is under 120 lines" le "$(wc -l <examples/mode4_loop.c)" 119
ex_gone() { ! kill -0 "$EPID" 2>/dev/null; }
if [ -x "$SIM" ] && [ -x "$BUILD/examples/mode4_loop" ]; then
    "$BUILD/examples/mode4_loop" -p 31060 >"$T/ex.out" 2>"$T/ex.err" &
    EPID=$!; PIDS="$PIDS $EPID"
    # the controller starts once the example's socket is bound (it prints nothing before)
    wait_until 30 udp_bound 31060 || echo "mode4_loop never bound port 31060"
    # --max-miss 500: a busy host may stop the example for 100 ms; counted, not fatal
    timeout 30 "$SIM" -p 31060 -S fixtures/server/sim_example.scn --max-miss 500 --json >"$T/ex.sim.json" 2>"$T/ex.sim.err"
    rc=$?
    wait_until 30 ex_gone
    ok "mode4_loop: sim scenario passed (mode 4 ran, EXIT_FROM_OPEN seen)" eq "$rc" 0
    ok "mode4_loop: robot moved +0.1 turns from 0.2" near "$(simpos "$T/ex.sim.json" 1)" 0.3 0.02
    ok "mode4_loop: ended on 504 with its report" has "$T/ex.out" "worst cycle"
fi
finish
