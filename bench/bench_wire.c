/* SPDX-License-Identifier: MIT */
/* Per-tick cost of the wire layer: decode + session step + reply encode, against a
 * baseline measured in the same run (memcpy of the same packet in and out).
 * Batches of both are interleaved so that machine noise hits both alike; the figure
 * is the median over batches of the per-tick average.
 *   bench_wire                       table for 6 and 20 axes (>= 1e6 ticks each)
 *   bench_wire --only KIND AXES N    run N ticks of one loop (for callgrind) */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BATCH 1000
#define BATCHES 1000

static c4g_session_t sess;
static uint8_t pkt[C4G_MAX_CYCLIC_SIZE];
static uint8_t rxcopy[C4G_MAX_CYCLIC_SIZE];
static uint8_t out[C4G_INIT_SIZE];
static size_t pkt_len;
static int32_t num;
static uint64_t now_ns;
volatile uint32_t sink;

static uint64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}

static void setup(uint32_t axes)
{
    c4g_init_t in;
    c4g_ctrl_packet_t p;
    c4g_rx_result_t r;
    size_t n;
    uint32_t i;
    c4gsim_fig10_1(&in);
    in.n_ax_open = (int32_t)axes;
    for (i = 0; i < 40; i++) {
        in.open_ax[i / 10][i % 10] = (i < axes) ? (int32_t)i : C4G_OPEN_AX_NONE;
        if (i < axes && i >= 6) {
            in.az_lim[i / 10][i % 10] = 10.0f; /* an open axis needs AzLim > 0 */
        }
    }
    if (c4g_init_encode(&in, out, sizeof out, &n) != C4G_OK) {
        abort();
    }
    (void)c4g_session_init(&sess, NULL);
    (void)c4g_session_rx(&sess, out, n, 0, &r);
    (void)c4g_session_reply(&sess, NULL, out, sizeof out, &n);
    memset(&p, 0, sizeof p);
    p.n_axes = axes;
    for (i = 0; i < axes; i++) {
        p.ax[i].mode = C4G_MODE_4;
        p.ax[i].actual_pos = 1.5f * (float)i;
        p.ax[i].target_pos = 1.5f * (float)i;
    }
    (void)c4g_ctrl_encode(&p, pkt, sizeof pkt, &pkt_len);
    num = 11;
    now_ns = 1000000;
}

static void tick_engine(void)
{
    c4g_rx_result_t r;
    c4g_pc_packet_t tx;
    size_t n;
    pkt[0] = (uint8_t)(num & 0xFF);
    pkt[1] = (uint8_t)((num >> 8) & 0x7F);
    num = (num + 1) & 0x7FFF;
    now_ns += 1000000;
    if (c4g_session_rx(&sess, pkt, pkt_len, now_ns, &r) != C4G_OK || r.kind != C4G_RX_CYCLIC ||
        c4g_pc_reply_neutral(r.pkt, &tx) != C4G_OK ||
        c4g_session_reply(&sess, &tx, out, sizeof out, &n) != C4G_OK ||
        c4g_session_sent(&sess, now_ns + 1000) != C4G_OK) {
        abort();
    }
    sink += out[0];
}

static void tick_memcpy(void)
{
    memcpy(rxcopy, pkt, pkt_len);
    memcpy(out, rxcopy, pkt_len);
    sink += out[0];
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void measure(uint32_t axes, double *engine_ns, double *base_ns)
{
    static double e[BATCHES], b[BATCHES];
    int k, i;
    setup(axes);
    for (k = 0; k < BATCHES; k++) {
        uint64_t t0 = mono_ns();
        for (i = 0; i < BATCH; i++) {
            tick_memcpy();
        }
        uint64_t t1 = mono_ns();
        for (i = 0; i < BATCH; i++) {
            tick_engine();
        }
        uint64_t t2 = mono_ns();
        b[k] = (double)(t1 - t0) / BATCH;
        e[k] = (double)(t2 - t1) / BATCH;
    }
    qsort(e, BATCHES, sizeof e[0], cmp_double);
    qsort(b, BATCHES, sizeof b[0], cmp_double);
    *engine_ns = e[BATCHES / 2];
    *base_ns = b[BATCHES / 2];
}

int main(int argc, char **argv)
{
    static const uint32_t sizes[] = {6, 20};
    unsigned s;
    if (argc == 5 && strcmp(argv[1], "--only") == 0) {
        long n = atol(argv[4]), i;
        setup((uint32_t)atoi(argv[3]));
        for (i = 0; i < n; i++) {
            if (strcmp(argv[2], "engine") == 0) {
                tick_engine();
            } else {
                tick_memcpy();
            }
        }
        return 0;
    }
    printf("wire layer per tick: decode + session step + neutral reply + encode\n");
    printf("(median of %d batches x %d ticks; baseline = memcpy of the packet in and out)\n",
           BATCHES, BATCH);
    printf("%-6s %-7s %12s %12s %8s %s\n", "axes", "bytes", "engine ns", "memcpy ns", "ratio",
           "goal (<400 ns, <10x)");
    for (s = 0; s < 2; s++) {
        double e, b;
        measure(sizes[s], &e, &b);
        printf("%-6u %-7u %12.1f %12.1f %7.1fx %s\n", sizes[s], (unsigned)C4G_CYCLIC_SIZE(sizes[s]),
               e, b, e / b, (e < 400.0 && e / b < 10.0) ? "met" : "NOT met");
    }
    return 0;
}
