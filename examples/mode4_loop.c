/* SPDX-License-Identifier: MIT */
/* Minimal C4G Open PC program: answers the controller and, when an arm enters mode 4,
 * moves every axis of it +0.1 motor turns along a raised cosine, then exits from open.
 * Plain POSIX; build (after make install): cc examples/mode4_loop.c $(pkg-config --cflags
 * --libs c4gopen) -lm     run: ./a.out [-p PORT]    (ends on 504) */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, sched_setscheduler, getopt */
#include "c4gopen.h"
#include <string.h>
#include <arpa/inet.h>
#include <math.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#define PI 3.14159265358979323846

static int usage(FILE *f, int code)
{
    fputs("Usage: mode4_loop [-p PORT]\nAnswers a C4G controller on UDP PORT (default 1000); "
          "in mode 4 each axis moves +0.1 turns, then exits from open. Ends on 504.\n", f);
    return code;
}

static uint64_t now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000ULL + (uint64_t)t.tv_nsec;
}

int main(int argc, char **argv)
{
    static c4g_loop_t lp;    /* session + control engine: large, static, locked by mlockall */
    static double start[C4G_MAX_AXES];
    static uint32_t ticks[C4G_MAX_AXES];
    struct sched_param sp = {0};
    struct sockaddr_in me = {0}, peer;
    uint8_t in[1500], out[C4G_INIT_SIZE];
    long port = 1000;
    char *end = NULL;
    int c, fd;
    if (argc > 1 && strcmp(argv[1], "--help") == 0)
        return usage(stdout, 0);
    while ((c = getopt(argc, argv, "hp:")) != -1) {
        if (c == 'h')
            return usage(stdout, 0);
        if (c != 'p' || (port = strtol(optarg, &end, 10)) < 1 || port > 65535 || *end != '\0')
            return usage(stderr, 2);
    }
    if (optind < argc)
        return usage(stderr, 2);
    fd = socket(AF_INET, SOCK_DGRAM, 0);
    me.sin_family = AF_INET;
    me.sin_port = htons((uint16_t)port);
    if (fd < 0 || bind(fd, (struct sockaddr *)&me, sizeof me) != 0) {
        perror("bind");
        return 1;
    }
    sp.sched_priority = 80; /* real time if allowed; say so if not */
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0 || sched_setscheduler(0, SCHED_FIFO, &sp) != 0)
        fprintf(stderr, "warning: no mlockall/SCHED_FIFO (need root or CAP_SYS_NICE)\n");
    if (c4g_loop_init(&lp, NULL) != C4G_OK)
        return 1;
    for (;;) {
        socklen_t pl = sizeof peer;
        c4g_loop_event_t ev;
        size_t len;
        const ssize_t n = recvfrom(fd, in, sizeof in, 0, (struct sockaddr *)&peer, &pl);
        const uint64_t t_rx = now_ns();
        c4g_endpoint_t from = {{0}, 4, 0};             /* only the session's own controller */
        memcpy(from.addr, &peer.sin_addr, 4);          /* (address and port) may steer it */
        from.port = ntohs(peer.sin_port);
        if (n < 0 || c4g_loop_rx(&lp, in, (size_t)n, t_rx, &from, &ev) != C4G_OK)
            continue;
        const c4g_init_t *init;                        /* the accepted init packet */
        const c4g_axis_map_t *map;
        c4g_engine_t *eng;                             /* takes requests */
        (void)c4g_loop_init_packet(&lp, &init);
        (void)c4g_loop_axis_map(&lp, &map);
        (void)c4g_loop_engine(&lp, &eng);
        const double dt = init->period_ms * 1e-3;
        for (uint32_t i = 0; ev.cmd != NULL && i < ev.cmd->n_axes; i++) {
            if (ev.pkt->ax[i].mode != C4G_MODE_4) {
                ticks[i] = 0;
                continue;
            }
            if (ticks[i]++ == 0) {
                float at = ev.pkt->ax[i].target_pos; /* where the axis stands as mode 4 begins */
                if (c4g_engine_anchor(eng, i, &at) != C4G_OK)
                    fprintf(stderr, "axis %u: no anchor, starting from D1\n", i);
                start[i] = at;
            }
            const double x = fmin(ticks[i] * dt / 2.0, 1.0); /* 2 s raised cosine */
            const double q = 0.05 * (1.0 - cos(PI * x)), dq = 0.05 * PI * sin(PI * x) * dt / 2.0;
            ev.cmd->ax[i].target_pos = (float)(start[i] + q); /* D1: absolute target */
            ev.cmd->ax[i].target_vel = (float)dq;             /* D2: delta turns per tick */
            if (x >= 1.0) /* EXIT_FROM_OPEN; refused (and harmless) while already leaving */
                (void)c4g_engine_request_exit(eng, map->arm_of[i]);
        }
        if (c4g_loop_reply(&lp, out, sizeof out, &len, NULL) == C4G_OK) { /* safety filter */
            sendto(fd, out, len, 0, (struct sockaddr *)&peer, pl);
            (void)c4g_loop_sent(&lp, now_ns()); /* timing statistics only */
        }
        if (ev.events & C4G_EV_END)
            break;                                         /* 504: end of communication */
    }
    c4g_timing_t t;
    const c4g_counters_t *cnt;
    if (c4g_loop_timing(&lp, &t) != C4G_OK || c4g_loop_counters(&lp, &cnt, NULL) != C4G_OK)
        return 1;
    printf("cyclic %llu, malformed %llu, worst cycle %.1f us, jitter [%+.1f; %+.1f] us\n",
           (unsigned long long)cnt->cyclic, (unsigned long long)cnt->malformed_total,
           t.worst_cycle_ns / 1e3, t.min_jitter_ns / 1e3, t.max_jitter_ns / 1e3);
    return 0;
}
