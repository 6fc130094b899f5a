/* SPDX-License-Identifier: MIT */
/* Cell codec cost per message, against a baseline measured in the same run (a
 * memcpy of the same line). Median of 31 batches of 20000 messages each. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "c4gopen.h"

#define BATCH 20000
#define RUNS 31

static volatile uint32_t g_sink;

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

static const char k_sta[] = "OKF+010.000-002.000+005.999-01.2322T+00080+00000\r\n";
static const char k_mov[] = "MOVA+010.000-002.000+005.999-01.2322\r\n";

static void op_memcpy(void)
{
    char out[64];
    memcpy(out, k_sta, sizeof k_sta - 1);
    g_sink += (uint32_t)out[g_sink & 31U];
}

static void op_sta_decode(void)
{
    c4g_cell_reply_t r;
    g_sink += (uint32_t)c4g_cell_reply_decode(k_sta, sizeof k_sta - 1, &r, NULL) + (uint32_t)r.pose.v[0];
}

static void op_sta_encode(void)
{
    static c4g_cell_reply_t r = {C4G_CELL_REPLY_STA, 0, 0, 1, 80, {4, {10000, -2000, 5999, -12322}}};
    char out[64];
    size_t n = 0;
    r.error = (int32_t)(g_sink & 7U);
    g_sink += (uint32_t)c4g_cell_reply_encode(&r, out, sizeof out, &n) + (uint32_t)out[n - 3];
}

static void op_mov_decode(void)
{
    c4g_cell_instr_t in;
    g_sink += (uint32_t)c4g_cell_instr_decode(k_mov, sizeof k_mov - 1, &in, NULL) + (uint32_t)in.pose.v[3];
}

static void op_mov_encode(void)
{
    static c4g_cell_instr_t in;
    char out[64];
    size_t n = 0;
    in.cmd = C4G_CELL_CMD_MOV;
    in.pose.n_axes = 4;
    in.pose.v[0] = (int32_t)(g_sink & 1023U);
    in.pose.v[1] = -2000;
    in.pose.v[2] = 5999;
    in.pose.v[3] = -12322;
    g_sink += (uint32_t)c4g_cell_instr_encode(&in, out, sizeof out, &n) + (uint32_t)out[7];
}

static void op_split(void)
{
    char buf[C4G_CELL_LINE_MAX];
    c4g_cell_splitter_t sp;
    size_t used = 0, len = 0;
    const char *line = NULL;
    c4g_cell_split_event_t ev;
    (void)c4g_cell_split_init(&sp, buf, sizeof buf);
    (void)c4g_cell_split_push(&sp, k_sta, sizeof k_sta - 1, &used);
    (void)c4g_cell_split_next(&sp, &ev, &line, &len);
    g_sink += (uint32_t)len + (uint32_t)ev;
}

static void op_split_decode(void)
{
    char buf[C4G_CELL_LINE_MAX];
    c4g_cell_splitter_t sp;
    size_t used = 0, len = 0;
    const char *line = NULL;
    c4g_cell_split_event_t ev;
    c4g_cell_reply_t r;
    (void)c4g_cell_split_init(&sp, buf, sizeof buf);
    (void)c4g_cell_split_push(&sp, k_sta, sizeof k_sta - 1, &used);
    (void)c4g_cell_split_next(&sp, &ev, &line, &len);
    g_sink += (uint32_t)c4g_cell_reply_decode(line, len, &r, NULL) + (uint32_t)r.override_pct;
}

static double measure(void (*op)(void))
{
    double v[RUNS];
    for (int r = 0; r < RUNS; r++) {
        uint64_t t0 = now_ns();
        for (int i = 0; i < BATCH; i++) {
            op();
        }
        v[r] = (double)(now_ns() - t0) / BATCH;
    }
    qsort(v, RUNS, sizeof v[0], cmp_d);
    return v[RUNS / 2];
}

int main(void)
{
    static const struct {
        const char *name;
        void (*op)(void);
    } ops[] = {
        {"baseline: memcpy 50-byte line", op_memcpy},
        {"decode robot STA reply (50 B)", op_sta_decode},
        {"encode robot STA reply (50 B)", op_sta_encode},
        {"decode robot MOV (38 B)", op_mov_decode},
        {"encode robot MOV (38 B)", op_mov_encode},
        {"splitter: push + next (50 B)", op_split},
        {"splitter + decode STA reply", op_split_decode},
    };
    double base = 0;
    printf("%-34s %12s %10s\n", "operation (median of 31 x 20000)", "ns/message", "x baseline");
    for (size_t i = 0; i < sizeof ops / sizeof ops[0]; i++) {
        double ns = measure(ops[i].op);
        if (i == 0) {
            base = ns > 0 ? ns : 1e-3;
        }
        printf("%-34s %12.1f %10.1f\n", ops[i].name, ns, ns / base);
    }
    return 0;
}
