/* SPDX-License-Identifier: MIT */
/* The floor of the full path's goal: what the mode-4 safety filter alone costs when it is
 * written as one loop over arrays (a structure of arrays for the limits and the last safe
 * targets), with fewer checks than the library's finish: the reply's NaN/infinity pass
 * (64-bit lanes), the mode restore, the step from the last safe target, the stroke ends, the
 * velocity limit and the following error, and the record of the target sent. No required
 * fields, no currents, no latches, no arm state, no report beyond one flag word per axis.
 * tick_cost.sh runs it under callgrind beside the library's paths: added to the wire tick,
 * it shows whether the full-path goal is reachable while every check stays.
 *
 *   filter_floor AXES N    N ticks of the loop (the per-axis setpoints written first) */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_AXES 20

typedef struct floor_axis {
    int32_t mode;
    float d[8];
} floor_axis_t;

typedef struct floor_state {
    float last[MAX_AXES], anchor[MAX_AXES], max_step[MAX_AXES], motor_min[MAX_AXES];
    float motor_max[MAX_AXES], max_vel[MAX_AXES], follow_error[MAX_AXES];
    uint8_t same_mode[MAX_AXES];
} floor_state_t;

/* written so that GCC makes both bounds branch-free (minss, then maxss) */
static float clampf(float x, float lo, float hi)
{
    const float t = (hi < x) ? hi : x;
    return (t < lo) ? lo : t;
}

/* 0xFFFFFFFF: a non-finite value somewhere (the slow path would name it) */
static uint32_t __attribute__((noinline)) filter4(floor_state_t *s, const floor_axis_t *rx,
                                                  floor_axis_t *tx, uint32_t n, uint32_t *flags)
{
    const uint8_t *p = (const uint8_t *)tx;
    const uint32_t words = n * 9U;
    uint64_t acc = 0U, lane;
    uint32_t any = 0U, q, i;
    for (q = 0U; q + 2U <= words; q += 2U) {
        memcpy(&lane, p + 4U * q, sizeof lane);
        acc |= (lane & 0x7F8000007F800000ULL) + 0x0080000000800000ULL;
    }
    if (q < words) {
        uint32_t w;
        memcpy(&w, p + 4U * q, sizeof w);
        acc |= (uint64_t)((w & 0x7F800000U) + 0x00800000U);
    }
    if ((((uint32_t)(acc >> 32) | (uint32_t)acc) & 0x80000000U) != 0U) {
        return 0xFFFFFFFFU;
    }
    for (i = 0U; i < n; i++) {
        const float base = (s->same_mode[i] != 0U) ? s->last[i] : s->anchor[i];
        const float req = tx[i].d[0] - base;
        const float d = clampf(req, -s->max_step[i], s->max_step[i]);
        const float pos = clampf(base + d, s->motor_min[i], s->motor_max[i]);
        const float vel = clampf(tx[i].d[1], -s->max_vel[i], s->max_vel[i]);
        const float fe = pos - rx[i].d[2];
        uint32_t f = (d != req) ? 1U : 0U;
        f |= (pos != base + d) ? 2U : 0U;
        f |= (vel != tx[i].d[1]) ? 4U : 0U;
        f |= ((fe > s->follow_error[i]) || (-fe > s->follow_error[i])) ? 8U : 0U;
        f |= (tx[i].mode != 4) ? 16U : 0U;
        tx[i].mode = 4;
        tx[i].d[0] = pos;
        tx[i].d[1] = vel;
        s->last[i] = pos;
        flags[i] = f;
        any |= f;
    }
    return any;
}

int main(int argc, char **argv)
{
    static floor_state_t s;
    static floor_axis_t rx[MAX_AXES], tx[MAX_AXES];
    static uint32_t flags[MAX_AXES];
    uint32_t n, i, sink = 0U;
    long k, ticks;
    if (argc != 3 || (n = (uint32_t)atoi(argv[1])) < 1U || n > MAX_AXES || (ticks = atol(argv[2])) < 1) {
        fprintf(stderr, "usage: filter_floor AXES(1..20) TICKS\n");
        return 2;
    }
    for (i = 0U; i < MAX_AXES; i++) {
        s.max_step[i] = 0.5F;
        s.motor_min[i] = -100.0F;
        s.motor_max[i] = 100.0F;
        s.max_vel[i] = 0.5F;
        s.follow_error[i] = 5.0F;
        s.same_mode[i] = 1U;
        rx[i].mode = 4;
        rx[i].d[0] = rx[i].d[2] = 1.0F + (float)i;
    }
    for (k = 0; k < ticks; k++) {
        for (i = 0U; i < n; i++) { /* the user's setpoints, as in tick.c */
            tx[i].d[0] = rx[i].d[0] + 0.001F;
            tx[i].d[1] = 0.001F;
        }
        sink += filter4(&s, rx, tx, n, flags);
    }
    printf("%u\n", sink);
    return 0;
}
