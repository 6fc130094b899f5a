#!/bin/sh
# c4g-sim's own CPU cost per tick: run it for N ticks at 1 ms against the reference PC and
# read the getrusage figure from its --json summary; next to it, in the same run, a bare
# UDP ping-pong loop (the cost of the socket calls alone) as the baseline. Informational:
# nothing here asserts on time.  Usage: sh bench/sim_cost.sh BUILD_DIR [TICKS]
set -u
B=${1:?usage: sh bench/sim_cost.sh BUILD_DIR [TICKS]}
N=${2:-5000}
T=$(mktemp -d "${TMPDIR:-/tmp}/simcost.XXXXXX")
PIDS=""
trap 'for p in $PIDS; do kill $p 2>/dev/null; done; wait 2>/dev/null; rm -rf "$T"' EXIT
cc -std=c99 -O2 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Iinclude -o "$T/ref_pc" \
  tests/e2e/helpers/ref_pc.c "$B/lib/libc4gopen.a" -lm || exit 1
cat >"$T/pingpong.c" <<'C'
#define _POSIX_C_SOURCE 200809L
#include <arpa/inet.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
int main(int argc, char **argv)
{
    int n = atoi(argv[1]), i, a = socket(AF_INET, SOCK_DGRAM, 0), b = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in sa, sb; socklen_t l = sizeof sb; unsigned char buf[228];
    struct rusage ru; double cpu; struct timespec ts; int paced = argc > 2;
    memset(&sa, 0, sizeof sa); sa.sin_family = AF_INET; sa.sin_addr.s_addr = htonl(0x7F000001);
    sb = sa; bind(a, (struct sockaddr *)&sa, sizeof sa); bind(b, (struct sockaddr *)&sb, sizeof sb);
    getsockname(b, (struct sockaddr *)&sb, &l); l = sizeof sa; getsockname(a, (struct sockaddr *)&sa, &l);
    memset(buf, 0, sizeof buf);
    clock_gettime(CLOCK_MONOTONIC, &ts);
    for (i = 0; i < n; i++) {
        if (paced) {   /* the floor of any 1 kHz program: one absolute-deadline sleep a tick */
            ts.tv_nsec += 1000000;
            if (ts.tv_nsec >= 1000000000) { ts.tv_nsec -= 1000000000; ts.tv_sec++; }
            clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
        }
        sendto(a, buf, sizeof buf, 0, (struct sockaddr *)&sb, sizeof sb);
        recv(b, buf, sizeof buf, 0);
        sendto(b, buf, sizeof buf, 0, (struct sockaddr *)&sa, sizeof sa);
        recv(a, buf, sizeof buf, 0);
    }
    getrusage(RUSAGE_SELF, &ru);
    cpu = ru.ru_utime.tv_sec + ru.ru_utime.tv_usec / 1e6 + ru.ru_stime.tv_sec + ru.ru_stime.tv_usec / 1e6;
    printf("%.0f\n", cpu * 1e9 / n);
    return 0;
}
C
cc -O2 -o "$T/pingpong" "$T/pingpong.c" || exit 1
PORT=$(( 45000 + $$ % 1000 ))
"$T/ref_pc" -p $PORT --idle-ms 1000 --max-s 120 2>/dev/null & PIDS="$PIDS $!"
sleep 0.2
"$B/bin/c4g-sim" --bind 127.0.0.1 -p $PORT -T 1 -n "$N" --json >"$T/s.json" || true
sim=$(grep -o '"ns_per_packet":[0-9]*' "$T/s.json" | cut -d: -f2)
# the same with the arm plant (MuJoCo, fixtures/sim/smart-six.xml), the drives on and arm 1
# moving back and forth (with the brakes on, MuJoCo would not step)
{ echo "DRIVE ON 1"; i=0; while [ $i -lt 100 ]; do echo "MOVE 1 2 -1.5 1 0.5 -0.5 0.25"; echo "MOVE 1 0 0 0 0 0 0"; i=$((i + 1)); done; } >"$T/arm.scn"
"$T/ref_pc" -p $((PORT + 1)) --idle-ms 1000 --max-s 120 2>/dev/null & PIDS="$PIDS $!"
sleep 0.2
"$B/bin/c4g-sim" --bind 127.0.0.1 -p $((PORT + 1)) -T 1 -n "$N" --hold -S "$T/arm.scn" \
  --plant fixtures/sim/smart-six.xml --json >"$T/a.json" || true
arm=$(grep -o '"ns_per_packet":[0-9]*' "$T/a.json" | cut -d: -f2)
base=$("$T/pingpong" "$N")
paced=$("$T/pingpong" "$N" paced)
echo "sim_cost: c4g-sim, 6 axes, 1 ms, $N ticks: ${sim} ns CPU per tick (user+sys, whole process)"
echo "sim_cost: c4g-sim --plant (arm plant), 6 axes, 1 ms, $N ticks: ${arm} ns CPU per tick (whole process)"
echo "sim_cost: baseline UDP ping-pong (2 sendto + 2 recv per round): ${base} ns CPU per round"
echo "sim_cost: baseline 1 kHz paced ping-pong (+ clock_nanosleep per tick): ${paced} ns CPU per tick"
awk -v s="$sim" -v p="$paced" 'BEGIN { if (s > 0 && p > 0) printf "sim_cost: c4g-sim / paced baseline = %.1fx\n", s / p }'
