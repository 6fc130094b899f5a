/* SPDX-License-Identifier: MIT */
/* The worst tick: the instructions of every single tick of the PC-side loop object over the
 * fuzz corpora, under callgrind, against the typical tick of the same axis count measured
 * the same way in the same run.
 *
 * A tick is what the loop object runs for one received datagram: c4g_loop_rx, then
 * c4g_loop_reply and c4g_loop_sent when a reply is due. The caller's own code between them
 * (the setpoints) is not counted. Collection is switched on around each of those calls
 * (CALLGRIND_TOGGLE_COLLECT) and the tick's count dumped (CALLGRIND_DUMP_STATS) when the
 * next tick starts; this program reads each dump's total and deletes it. The cost of one
 * switch on and off with nothing between (a few instructions) is measured and subtracted.
 *
 * Inputs:
 *   session FILES   fuzz_session's format (a datagram stream: 2-byte length prefixes, 0xFFFF
 *                   the figure 10.1 init packet, the prefix's top bits the sender; its clock)
 *                   fed to a loop object with the safety filter's limits on (step, velocity,
 *                   stroke, following error, as bench/tick.c), setpoints as bench/tick.c's
 *                   on every cyclic packet: every packet shape the session accepts or drops,
 *                   every mode the controller sends;
 *   world FILES     fuzz_safety_world's seeds, the library's property fuzzer, run as it is
 *                   (tests/fuzz/fuzz_safety_world.c included, its loop calls counted):
 *                   start-up, restarts, losses, honest and dishonest controllers, every
 *                   mode, arbitrary replies;
 *   typical AXES    the steady mode-4 tick of bench/tick.c's full path (200 ticks, median).
 * Each tick prints one line: "tick SOURCE INDEX KIND AXES IR" (KIND: cyclic, init, sync,
 * dropped, ended). --keep SOURCE INDEX keeps that tick's dump (its path printed) for
 * callgrind_annotate. Run by bench/worst_tick.sh:
 *   valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file=BASE \
 *     worst_tick --base BASE [--keep SRC N] session|world|typical ARGS */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include "../tests/fuzz/fuzz_stream.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <valgrind/callgrind.h>

static const char *g_base;   /* callgrind's --callgrind-out-file */
static unsigned g_part;      /* dumps so far */
static const char *g_src;    /* the input being run */
static unsigned g_index;     /* ticks of that input so far */
static const char *g_keep_src;
static unsigned g_keep_index;
static unsigned long long g_empty; /* Ir of one empty on/off pair */
static int g_open;           /* a tick is being counted */
static unsigned g_pairs;     /* on/off pairs in it */
static const char *g_kind;
static uint32_t g_axes;

/* The total of dump @p part, deleted unless kept. */
static unsigned long long read_dump(unsigned part, int keep)
{
    char path[512], line[512];
    unsigned long long v = 0ULL;
    FILE *f;
    (void)snprintf(path, sizeof path, "%s.%u", g_base, part);
    f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "worst_tick: no dump %s: run under callgrind with --callgrind-out-file=%s\n", path, g_base);
        exit(1);
    }
    while (fgets(line, sizeof line, f) != NULL) {
        if (strncmp(line, "summary:", 8) == 0 || strncmp(line, "totals:", 7) == 0) {
            v = strtoull(strchr(line, ':') + 1, NULL, 10);
            break;
        }
    }
    fclose(f);
    if (keep) {
        printf("kept %s\n", path);
    } else {
        (void)remove(path);
    }
    return v;
}

static void tick_end(void)
{
    unsigned long long ir;
    int keep;
    if (!g_open) {
        return;
    }
    g_open = 0;
    CALLGRIND_DUMP_STATS;
    g_part++;
    keep = (g_keep_src != NULL && strcmp(g_keep_src, g_src) == 0 && g_keep_index == g_index);
    ir = read_dump(g_part, keep);
    ir = (ir > g_pairs * g_empty) ? ir - g_pairs * g_empty : 0ULL;
    printf("tick %s %u %s %u %llu\n", g_src, g_index, g_kind, (unsigned)g_axes, ir);
    g_index++;
}

static const char *kind_name(c4g_status_t st, const c4g_loop_event_t *ev)
{
    if (st == C4G_ERR_ENDED) {
        return "ended";
    }
    switch (ev->kind) {
    case C4G_RX_CYCLIC: return "cyclic";
    case C4G_RX_INIT: return "init";
    case C4G_RX_SYNC: return "sync";
    case C4G_RX_DROPPED: return "dropped";
    default: return "other";
    }
}

/* The counted calls: a receive starts a tick, a reply and a send belong to it. */
static c4g_status_t bench_loop_rx(c4g_loop_t *lp, const uint8_t *buf, size_t len, uint64_t now_ns,
                                  const c4g_endpoint_t *from, c4g_loop_event_t *ev)
{
    c4g_status_t st;
    tick_end();
    g_open = 1;
    g_pairs = 1U;
    CALLGRIND_TOGGLE_COLLECT;
    st = c4g_loop_rx(lp, buf, len, now_ns, from, ev);
    CALLGRIND_TOGGLE_COLLECT;
    g_kind = kind_name(st, ev);
    g_axes = (ev->pkt != NULL) ? ev->pkt->n_axes : lp->session.map.n_axes;
    return st;
}

static c4g_status_t bench_loop_reply(c4g_loop_t *lp, uint8_t *buf, size_t cap, size_t *out_len,
                                     c4g_engine_report_t *rep)
{
    c4g_status_t st;
    g_pairs++;
    CALLGRIND_TOGGLE_COLLECT;
    st = c4g_loop_reply(lp, buf, cap, out_len, rep);
    CALLGRIND_TOGGLE_COLLECT;
    return st;
}

static c4g_status_t bench_loop_sent(c4g_loop_t *lp, uint64_t now_ns)
{
    c4g_status_t st;
    g_pairs++;
    CALLGRIND_TOGGLE_COLLECT;
    st = c4g_loop_sent(lp, now_ns);
    CALLGRIND_TOGGLE_COLLECT;
    return st;
}

/* The property fuzzer, run as it is, its loop calls counted (included, not linked: its
 * entry point is all it exports, and the calls are renamed to the counting ones). */
#define c4g_loop_rx bench_loop_rx
#define c4g_loop_reply bench_loop_reply
#define c4g_loop_sent bench_loop_sent
#include "../tests/fuzz/fuzz_safety_world.c"
#undef c4g_loop_rx
#undef c4g_loop_reply
#undef c4g_loop_sent

/* ---------------------------------------------------------------- limits as bench/tick.c */

static void tick_limits(c4g_axis_limits_t *l)
{
    memset(l, 0, sizeof *l);
    l->max_step = 0.5f;
    l->max_vel = 0.5f;
    l->motor_min = -100.0f;
    l->motor_max = 100.0f;
}

static void loop_start(c4g_loop_t *lp)
{
    c4g_axis_limits_t l;
    uint32_t a, x;
    tick_limits(&l);
    if (c4g_loop_init(lp, NULL) != C4G_OK) {
        abort();
    }
    for (a = 0U; a < C4G_ARMS; a++) {
        for (x = 0U; x < 10U; x++) {
            (void)c4g_loop_set_limits(lp, a, x, &l);
        }
    }
}

static void setpoints(const c4g_loop_event_t *ev)
{
    uint32_t i;
    if (ev->cmd == NULL || ev->pkt == NULL) {
        return;
    }
    for (i = 0U; i < ev->cmd->n_axes && i < C4G_MAX_AXES; i++) { /* bench/tick.c's */
        ev->cmd->ax[i].target_pos = ev->pkt->ax[i].target_pos + 0.001f;
        ev->cmd->ax[i].target_vel = 0.001f;
    }
}

/* fuzz_session's stream, through the loop object. */
static void run_session(const uint8_t *data, size_t size)
{
    static c4g_loop_t lp;
    static fuzz_stream_t st;
    uint8_t out[C4G_INIT_SIZE];
    const uint8_t *dg;
    size_t dl;
    size_t n;
    const c4g_endpoint_t *from;
    fuzz_stream_start(&st, data, size);
    loop_start(&lp);
    while (fuzz_stream_next(&st, &dg, &dl, &from)) {
        c4g_loop_event_t ev;
        if (bench_loop_rx(&lp, dg, dl, st.t, from, &ev) == C4G_ERR_ENDED) {
            tick_end();
            loop_start(&lp);
            continue;
        }
        setpoints(&ev);
        if (bench_loop_reply(&lp, out, sizeof out, &n, NULL) == C4G_OK) {
            (void)bench_loop_sent(&lp, st.t + 1000U);
        }
    }
    tick_end();
}

/* ---------------------------------------------------------------- the typical tick */

static void typical(uint32_t axes)
{
    static c4g_loop_t lp;
    c4g_init_t in;
    c4g_ctrl_packet_t p;
    c4g_axis_limits_t l;
    c4g_loop_event_t ev;
    uint8_t init[C4G_INIT_SIZE], pkt[C4G_MAX_CYCLIC_SIZE], out[C4G_INIT_SIZE];
    size_t n, plen;
    uint64_t now = 1000000U;
    int32_t num = 11;
    uint32_t i;
    int k;
    (void)c4gsim_fig10_1(&in);
    in.n_ax_open = (int32_t)axes;
    for (i = 0; i < 40U; i++) { /* bench/tick.c's init packet */
        const uint32_t a = i / 10U, x = i % 10U;
        in.open_ax[a][x] = (i < axes) ? (int32_t)i : C4G_OPEN_AX_NONE;
        if (i < axes) {
            in.az_lim[a][x] = 10.0f;
            in.tx_rate[a][x] = 50.0f + (float)x;
            in.follow_error[a][x] = 5.0f;
        }
    }
    memset(&p, 0, sizeof p);
    p.n_axes = axes;
    p.infpar = (axes > 10U) ? 0x0505U : 0x05U;
    for (i = 0; i < axes; i++) {
        p.ax[i].mode = C4G_MODE_4;
        p.ax[i].target_pos = 1.0f + (float)i;
        p.ax[i].actual_pos = 1.0f + (float)i;
        p.ax[i].current_ref = 2.0f;
    }
    if (c4g_init_encode(&in, init, sizeof init, &n) != C4G_OK || c4g_ctrl_encode(&p, pkt, sizeof pkt, &plen) != C4G_OK ||
        c4g_loop_init(&lp, NULL) != C4G_OK || c4g_loop_rx(&lp, init, n, now, NULL, &ev) != C4G_OK ||
        c4g_loop_reply(&lp, out, sizeof out, &n, NULL) != C4G_OK) {
        fprintf(stderr, "worst_tick: typical set-up failed\n");
        exit(1);
    }
    tick_limits(&l);
    for (i = 0; i < axes; i++) {
        if (c4g_engine_set_limits(&lp.engine, i / 10U, i % 10U, &l) != C4G_OK) {
            abort();
        }
    }
    for (k = 0; k < 200; k++) {
        num = (num + 1) & 0x7FFF;
        pkt[0] = (uint8_t)(num & 0xFF);
        pkt[1] = (uint8_t)((num >> 8) & 0x7F);
        now += 1000000U;
        if (bench_loop_rx(&lp, pkt, plen, now, NULL, &ev) != C4G_OK || ev.cmd == NULL) {
            abort();
        }
        setpoints(&ev);
        if (bench_loop_reply(&lp, out, sizeof out, &n, NULL) != C4G_OK || bench_loop_sent(&lp, now + 1000U) != C4G_OK) {
            abort();
        }
    }
    tick_end();
    if (lp.report.n_filtered != 0U || lp.finish_status != C4G_OK) {
        fprintf(stderr, "worst_tick: the filter acted on the typical tick's setpoints\n");
        exit(1);
    }
}

static uint8_t *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    uint8_t *b;
    long sz;
    if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (sz = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fprintf(stderr, "worst_tick: cannot read %s\n", path);
        exit(1);
    }
    b = malloc((size_t)sz + 1U);
    if (b == NULL || fread(b, 1U, (size_t)sz, f) != (size_t)sz) {
        fprintf(stderr, "worst_tick: cannot read %s\n", path);
        exit(1);
    }
    fclose(f);
    *n = (size_t)sz;
    return b;
}

int main(int argc, char **argv)
{
    int a = 1, k;
    while (a + 1 < argc && argv[a][0] == '-') {
        if (strcmp(argv[a], "--base") == 0) {
            g_base = argv[a + 1];
            a += 2;
        } else if (strcmp(argv[a], "--keep") == 0 && a + 2 < argc) {
            g_keep_src = argv[a + 1];
            g_keep_index = (unsigned)atoi(argv[a + 2]);
            a += 3;
        } else {
            break;
        }
    }
    if (g_base == NULL || a >= argc || RUNNING_ON_VALGRIND == 0) {
        fprintf(stderr, "usage: valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file=BASE \\\n"
                        "  worst_tick --base BASE [--keep SRC N] session FILES | world FILES | typical AXES\n");
        return 2;
    }
    /* the cost of an empty on/off pair: the least of a few */
    g_src = "empty";
    for (k = 0; k < 5; k++) {
        unsigned long long v;
        CALLGRIND_TOGGLE_COLLECT;
        CALLGRIND_TOGGLE_COLLECT;
        CALLGRIND_DUMP_STATS;
        g_part++;
        v = read_dump(g_part, 0);
        if (k == 0 || v < g_empty) {
            g_empty = v;
        }
    }
    if (strcmp(argv[a], "typical") == 0 && a + 1 < argc) {
        g_src = "typical";
        typical((uint32_t)atoi(argv[a + 1]));
        return 0;
    }
    for (k = a + 1; k < argc; k++) {
        size_t n;
        uint8_t *d = slurp(argv[k], &n);
        g_src = argv[k];
        g_index = 0U;
        if (strcmp(argv[a], "session") == 0) {
            run_session(d, n);
        } else if (strcmp(argv[a], "world") == 0) {
            (void)LLVMFuzzerTestOneInput(d, n);
            tick_end();
        } else {
            fprintf(stderr, "worst_tick: unknown input kind '%s'\n", argv[a]);
            return 2;
        }
        free(d);
    }
    return 0;
}
