/* SPDX-License-Identifier: MIT */
/* Control layer cost per tick: decode + c4g_engine_step + caller fill + c4g_safety_filter (state
 * machines, packet rules, safety filter) + encode, 20 axes in mode 4, against a baseline
 * measured in the same run: memcpy of the same packet in and out. Median over 1000 batches
 * of 1000 ticks (1e6 ticks each). Goal: < 400 ns and < 10x the baseline. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "c4gopen.h"
#include "c4gsim_fixtures.h"

#define BATCH 1000
#define RUNS 1000

static volatile uint32_t g_sink;
static uint8_t g_in[C4G_MAX_CYCLIC_SIZE];
static uint8_t g_out[C4G_MAX_CYCLIC_SIZE];
static c4g_engine_t g_ctl;
static c4g_ctrl_packet_t g_rx;
static c4g_pc_packet_t g_tx;
static c4g_engine_report_t g_rep;
static int32_t g_num;

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void op_memcpy(void)
{
    static uint8_t a[C4G_MAX_CYCLIC_SIZE], b[C4G_MAX_CYCLIC_SIZE];
    memcpy(a, g_in, sizeof a);          /* packet in */
    a[0] = (uint8_t)g_sink;
    memcpy(b, a, sizeof b);             /* packet out */
    memcpy(g_out, b, sizeof b);
    g_sink += g_out[g_sink & 511U];
}

static void next_packet(void)
{
    g_num = (g_num >= C4G_NUM_MAX) ? 1 : g_num + 1;
    g_in[0] = (uint8_t)(g_num & 0xFF);
    g_in[1] = (uint8_t)((g_num >> 8) & 0xFF);
}

static void op_wire(void)
{
    size_t len = 0;
    next_packet();
    g_sink += (uint32_t)c4g_ctrl_decode(g_in, sizeof g_in, 20, &g_rx, NULL);
    (void)c4g_pc_reply_neutral(&g_rx, &g_tx);
    g_sink += (uint32_t)c4g_pc_encode(&g_tx, g_out, sizeof g_out, &len) + g_out[20];
}

static void op_full(void)
{
    size_t len = 0;
    uint32_t i;
    next_packet();
    g_sink += (uint32_t)c4g_ctrl_decode(g_in, sizeof g_in, 20, &g_rx, NULL);
    g_sink += (uint32_t)c4g_engine_step(&g_ctl, &g_rx, (uint64_t)g_num * 2000000U, &g_tx, &g_rep);
    for (i = 0; i < 20; i++) {      /* the user: mode 4 absolute targets */
        g_tx.ax[i].target_pos = g_rx.ax[i].target_pos + 0.001f;
        g_tx.ax[i].target_vel = 0.001f;
    }
    g_sink += (uint32_t)c4g_safety_filter(&g_ctl, &g_rx, &g_tx, &g_rep);
    g_sink += (uint32_t)c4g_pc_encode(&g_tx, g_out, sizeof g_out, &len) + g_out[20];
}

static double median_ns(void (*op)(void))
{
    static double per[RUNS];
    int r, k;
    for (k = 0; k < BATCH; k++) op(); /* warm up */
    for (r = 0; r < RUNS; r++) {
        const uint64_t t0 = now_ns();
        for (k = 0; k < BATCH; k++) op();
        per[r] = (double)(now_ns() - t0) / BATCH;
    }
    qsort(per, RUNS, sizeof per[0], cmp_d);
    return per[RUNS / 2];
}

static void setup(void)
{
    c4g_init_t in;
    c4g_ctrl_packet_t p;
    c4g_axis_limits_t l;
    size_t len = 0;
    uint32_t a, x, i;
    c4gsim_fig10_1(&in);
    in.n_ax_open = 20;
    for (a = 0; a < 2; a++) {
        for (x = 0; x < 10; x++) {
            in.open_ax[a][x] = (int32_t)(a * 10 + x);
            in.tx_rate[a][x] = 50.0f + (float)x;
            in.az_lim[a][x] = 10.0f;
            in.follow_error[a][x] = 5.0f;
        }
    }
    if (c4g_engine_init(&g_ctl, &in, NULL) != C4G_OK) { fprintf(stderr, "init failed\n"); exit(1); }
    memset(&l, 0, sizeof l);
    l.max_step = 0.5f;
    l.max_vel = 0.5f;
    l.motor_min = -100.0f;
    l.motor_max = 100.0f;
    for (a = 0; a < 2; a++) {
        for (x = 0; x < 10; x++) {
            if (c4g_engine_set_limits(&g_ctl, a, x, &l) != C4G_OK) { fprintf(stderr, "limits\n"); exit(1); }
        }
    }
    memset(&p, 0, sizeof p);
    p.num = 1;
    p.n_axes = 20;
    p.infpar = 0x0505U;
    for (i = 0; i < 20; i++) {
        p.ax[i].mode = C4G_MODE_4;
        p.ax[i].target_pos = 1.0f + (float)i;
        p.ax[i].actual_pos = 1.0f + (float)i;
        p.ax[i].current_ref = 2.0f;
    }
    if (c4g_ctrl_encode(&p, g_in, sizeof g_in, &len) != C4G_OK) { fprintf(stderr, "enc\n"); exit(1); }
}

int main(int argc, char **argv)
{
    double base, wire, full;
    setup();
    if (argc == 4 && strcmp(argv[1], "--only") == 0) { /* N ticks of one path, for callgrind */
        const long n = atol(argv[3]);
        void (*op)(void) = (strcmp(argv[2], "full") == 0)   ? op_full
                           : (strcmp(argv[2], "wire") == 0) ? op_wire
                                                            : op_memcpy;
        long k;
        for (k = 0; k < n; k++) op();
        return 0;
    }
    base = median_ns(op_memcpy);
    wire = median_ns(op_wire);
    full = median_ns(op_full);
    if (g_rep.n_filtered != 0 || g_tx.ax[0].mode != C4G_MODE_4) {
        fprintf(stderr, "bench_control: unexpected filter action\n");
        return 1;
    }
    printf("%-46s %9s %9s\n", "per tick, 20 axes, mode 4 (median of 1e6)", "ns", "x memcpy");
    printf("%-46s %9.1f %9.2f\n", "baseline: memcpy packet in + out (732 B)", base, 1.0);
    printf("%-46s %9.1f %9.2f\n", "decode + neutral reply + encode", wire, wire / base);
    printf("%-46s %9.1f %9.2f\n", "decode + ctl step + filter + finish + encode", full, full / base);
    printf("%-46s %9.1f\n", "  of which control layer (step + finish)", full - wire);
    printf("goal: < 400 ns and < 10x baseline: %s\n",
           (full < 400.0 && full < 10.0 * base) ? "met" : "NOT met");
    return (int)(g_sink & 0U);
}
