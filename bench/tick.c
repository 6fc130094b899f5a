/* SPDX-License-Identifier: MIT */
/* Per-tick cost of the PC side against a struct-copy baseline measured in the same run.
 *
 * The baseline does what a library built on struct casts does: the datagram is copied
 * into a struct laid out like the wire (the code a cast compiles to), the reply struct is
 * filled and copied out; nothing is validated (no length, NUM, mode or NaN check, no
 * session, no safety filter) and the byte order is the host's.
 *
 *   wire  ours: c4g_session_rx + c4g_session_reply_neutral + c4g_session_sent, mode 0
 *         base: copy in, neutral reply (NUM + 1, modes echoed, data zero), copy out
 *   wire-tx  ours: the same with the reply built as a PC packet and encoded (checked)
 *         again: c4g_pc_reply_neutral + c4g_session_reply (what a caller's own reply costs)
 *   full  ours: the loop object, mode 4: c4g_loop_rx + per-axis setpoints + c4g_loop_reply
 *               (packet rules and the safety filter: step, velocity, stroke, following
 *               error on) + c4g_loop_sent
 *         base: the wire baseline plus the same per-axis setpoint copy
 *
 *   tick                         ns table (median of batches, ours and base interleaved)
 *   tick --only PATH AXES N      N ticks of one path for callgrind; PATH is wire, full,
 *                                wire-tx, base-wire or base-full */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BATCH 1000
#define BATCHES 400

/* ---------------------------------------------------------------- the struct baseline */

typedef struct base_axis {
    int32_t mode;
    float d[8];
} base_axis_t;

typedef struct base_packet {
    int32_t num;
    uint32_t infpar;
    uint32_t cmd;
    base_axis_t ax[C4G_MAX_AXES];
} base_packet_t;

static base_packet_t b_rx, b_tx;

static uint8_t g_pkt[C4G_MAX_CYCLIC_SIZE];
static uint8_t g_out[C4G_INIT_SIZE];
static size_t g_len;
static uint32_t g_axes;
static int32_t g_num;
static uint64_t g_now;
volatile uint32_t g_sink;

static c4g_session_t g_sess;
static c4g_loop_t g_loop;

static void next_num(void)
{
    g_num = (g_num + 1) & 0x7FFF;
    g_pkt[0] = (uint8_t)(g_num & 0xFF);
    g_pkt[1] = (uint8_t)((g_num >> 8) & 0x7F);
    g_now += 1000000U;
}

static void base_reply(void)
{
    uint32_t i;
    memcpy(&b_rx, g_pkt, g_len); /* what *(base_packet_t *)buf compiles to */
    b_tx.num = (b_rx.num >= 0x7FFF) ? 1 : b_rx.num + 1;
    b_tx.infpar = 0U;
    b_tx.cmd = 0U;
    for (i = 0U; i < g_axes; i++) {
        b_tx.ax[i].mode = b_rx.ax[i].mode;
        memset(b_tx.ax[i].d, 0, sizeof b_tx.ax[i].d);
    }
}

static void tick_base_wire(void)
{
    next_num();
    base_reply();
    memcpy(g_out, &b_tx, g_len);
    g_sink += g_out[20];
}

static void tick_base_full(void)
{
    uint32_t i;
    next_num();
    base_reply();
    for (i = 0U; i < g_axes; i++) { /* the user's setpoints */
        b_tx.ax[i].d[0] = b_rx.ax[i].d[0] + 0.001f;
        b_tx.ax[i].d[1] = 0.001f;
    }
    memcpy(g_out, &b_tx, g_len);
    g_sink += g_out[20];
}

/* ---------------------------------------------------------------- ours */

static void tick_wire(void)
{
    c4g_rx_result_t r;
    size_t n;
    next_num();
    if (c4g_session_rx(&g_sess, g_pkt, g_len, g_now, &r) != C4G_OK || r.kind != C4G_RX_CYCLIC ||
        c4g_session_reply_neutral(&g_sess, g_out, sizeof g_out, &n) != C4G_OK ||
        c4g_session_sent(&g_sess, g_now + 1000U) != C4G_OK) {
        abort();
    }
    g_sink += g_out[20];
}

static void tick_wire_tx(void)
{
    c4g_rx_result_t r;
    c4g_pc_packet_t tx;
    size_t n;
    next_num();
    if (c4g_session_rx(&g_sess, g_pkt, g_len, g_now, &r) != C4G_OK || r.kind != C4G_RX_CYCLIC ||
        c4g_pc_reply_neutral(r.pkt, &tx) != C4G_OK ||
        c4g_session_reply(&g_sess, &tx, g_out, sizeof g_out, &n) != C4G_OK ||
        c4g_session_sent(&g_sess, g_now + 1000U) != C4G_OK) {
        abort();
    }
    g_sink += g_out[20];
}

static void tick_full(void)
{
    c4g_loop_event_t ev;
    size_t n;
    uint32_t i;
    next_num();
    if (c4g_loop_rx(&g_loop, g_pkt, g_len, g_now, NULL, &ev) != C4G_OK || ev.cmd == NULL) {
        abort();
    }
    for (i = 0U; i < g_axes; i++) { /* the user's setpoints */
        ev.cmd->ax[i].target_pos = ev.pkt->ax[i].target_pos + 0.001f;
        ev.cmd->ax[i].target_vel = 0.001f;
    }
    if (c4g_loop_reply(&g_loop, g_out, sizeof g_out, &n, NULL) != C4G_OK ||
        c4g_loop_sent(&g_loop, g_now + 1000U) != C4G_OK) {
        abort();
    }
    g_sink += g_out[20];
}

/* ---------------------------------------------------------------- set-up */

static void init_packet(uint32_t axes, uint8_t *buf, size_t *n)
{
    c4g_init_t in;
    uint32_t i;
    c4gsim_fig10_1(&in);
    in.n_ax_open = (int32_t)axes;
    for (i = 0; i < 40U; i++) {
        const uint32_t a = i / 10U, x = i % 10U;
        in.open_ax[a][x] = (i < axes) ? (int32_t)i : C4G_OPEN_AX_NONE;
        if (i < axes) {
            in.az_lim[a][x] = 10.0f;
            in.tx_rate[a][x] = 50.0f + (float)x;
            in.follow_error[a][x] = 5.0f;
        }
    }
    if (c4g_init_encode(&in, buf, C4G_INIT_SIZE, n) != C4G_OK) {
        fprintf(stderr, "tick: init packet refused\n");
        exit(1);
    }
}

static void cyclic_packet(uint32_t axes, int32_t mode)
{
    c4g_ctrl_packet_t p;
    uint32_t i;
    memset(&p, 0, sizeof p);
    p.n_axes = axes;
    p.infpar = (axes > 10U) ? 0x0505U : 0x05U; /* drives on */
    for (i = 0; i < axes; i++) {
        p.ax[i].mode = mode;
        p.ax[i].target_pos = 1.0f + (float)i;
        p.ax[i].actual_pos = 1.0f + (float)i;
        p.ax[i].current_ref = 2.0f;
    }
    if (c4g_ctrl_encode(&p, g_pkt, sizeof g_pkt, &g_len) != C4G_OK) {
        fprintf(stderr, "tick: cyclic packet refused\n");
        exit(1);
    }
}

static void setup(const char *path, uint32_t axes)
{
    uint8_t init[C4G_INIT_SIZE];
    c4g_loop_event_t ev;
    c4g_rx_result_t r;
    c4g_axis_limits_t l;
    size_t n;
    uint32_t i;
    g_axes = axes;
    g_num = 11;
    g_now = 1000000U;
    init_packet(axes, init, &n);
    cyclic_packet(axes, (strstr(path, "full") != NULL) ? C4G_MODE_4 : C4G_MODE_0);
    /* the wire path: the session alone */
    if (c4g_session_init(&g_sess, NULL) != C4G_OK ||
        c4g_session_rx(&g_sess, init, n, g_now, &r) != C4G_OK || r.kind != C4G_RX_INIT ||
        c4g_session_reply(&g_sess, NULL, g_out, sizeof g_out, &n) != C4G_OK) {
        fprintf(stderr, "tick: session set-up failed\n");
        exit(1);
    }
    /* the full path: the loop object with the filter's checks on */
    init_packet(axes, init, &n);
    if (c4g_loop_init(&g_loop, NULL) != C4G_OK ||
        c4g_loop_rx(&g_loop, init, n, g_now, NULL, &ev) != C4G_OK || ev.kind != C4G_RX_INIT ||
        c4g_loop_reply(&g_loop, g_out, sizeof g_out, &n, NULL) != C4G_OK) {
        fprintf(stderr, "tick: loop set-up failed\n");
        exit(1);
    }
    memset(&l, 0, sizeof l);
    l.max_step = 0.5f;
    l.max_vel = 0.5f;
    l.motor_min = -100.0f;
    l.motor_max = 100.0f;
    for (i = 0; i < axes; i++) {
        if (c4g_engine_set_limits(&g_loop.engine, i / 10U, i % 10U, &l) != C4G_OK) {
            fprintf(stderr, "tick: limits refused\n");
            exit(1);
        }
    }
}

/* ---------------------------------------------------------------- timing */

static uint64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median per-tick time of @p ours and @p base, batches interleaved. */
static void measure(void (*ours)(void), void (*base)(void), double *o_ns, double *b_ns)
{
    static double o[BATCHES], b[BATCHES];
    int k, i;
    for (i = 0; i < BATCH; i++) {
        ours();
        base();
    }
    for (k = 0; k < BATCHES; k++) {
        const uint64_t t0 = mono_ns();
        uint64_t t1, t2;
        for (i = 0; i < BATCH; i++) {
            base();
        }
        t1 = mono_ns();
        for (i = 0; i < BATCH; i++) {
            ours();
        }
        t2 = mono_ns();
        b[k] = (double)(t1 - t0) / BATCH;
        o[k] = (double)(t2 - t1) / BATCH;
    }
    qsort(o, BATCHES, sizeof o[0], cmp_double);
    qsort(b, BATCHES, sizeof b[0], cmp_double);
    *o_ns = o[BATCHES / 2];
    *b_ns = b[BATCHES / 2];
}

typedef void (*tick_fn)(void);

static tick_fn path_fn(const char *path)
{
    if (strcmp(path, "wire") == 0) {
        return tick_wire;
    }
    if (strcmp(path, "wire-tx") == 0) {
        return tick_wire_tx;
    }
    if (strcmp(path, "full") == 0) {
        return tick_full;
    }
    if (strcmp(path, "base-wire") == 0) {
        return tick_base_wire;
    }
    if (strcmp(path, "base-full") == 0) {
        return tick_base_full;
    }
    fprintf(stderr, "tick: unknown path '%s' (wire, wire-tx, full, base-wire, base-full)\n", path);
    exit(2);
}

int main(int argc, char **argv)
{
    static const char *const paths[] = {"wire", "wire-tx", "full"};
    static const uint32_t sizes[] = {6, 20};
    unsigned p, s;
    if (argc == 5 && strcmp(argv[1], "--only") == 0) {
        const tick_fn f = path_fn(argv[2]);
        const long n = atol(argv[4]);
        long i;
        setup(argv[2], (uint32_t)atoi(argv[3]));
        for (i = 0; i < n; i++) {
            f();
        }
        return 0;
    }
    printf("%-6s %5s %10s %10s %8s\n", "path", "axes", "ours ns", "base ns", "ratio");
    for (p = 0; p < 3; p++) {
        for (s = 0; s < 2; s++) {
            double o, b;
            setup(paths[p], sizes[s]);
            measure(path_fn(paths[p]), p < 2 ? tick_base_wire : tick_base_full, &o, &b);
            if (p == 2 && (g_loop.report.n_filtered != 0U || g_loop.finish_status != C4G_OK)) {
                fprintf(stderr, "tick: the filter acted on the benchmark's setpoints\n");
                return 1;
            }
            printf("%-6s %5u %10.1f %10.1f %7.1fx\n", paths[p], sizes[s], o, b, o / b);
        }
    }
    return 0;
}
