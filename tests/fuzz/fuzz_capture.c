/* SPDX-License-Identifier: MIT */
/* Fuzz target: any bytes as a capture file, through c4g-replay's reader and the whole
 * session analysis (flows, direction, sessions, reply judging, findings, export rows). */
#include "analyze.h"
#include "capture.h"

#include <stdio.h>
#include <string.h>

static unsigned long rows;

static void on_exchange(void *ctx, const an_exchange_t *x)
{
    (void)ctx;
    if (x->ctrl_len > 0U && x->ctrl[0] == 0xFFU) {
        rows++;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[400];
    an_options_t o;
    an_t a;
    cap_t *c;
    cap_pkt_t p;
    FILE *fp;
    if (size == 0U) {
        return 0;
    }
    fp = fmemopen((void *)(uintptr_t)data, size, "rb");
    if (fp == NULL) {
        return 0;
    }
    c = cap_open_stream(fp, "fuzz", err, sizeof err);
    if (c == NULL) {
        return 0;
    }
    an_options_default(&o);
    o.on_exchange = on_exchange;
    o.max_step = 0.5;
    if (an_init(&a, &o) != 0) {
        cap_close(c);
        return 0;
    }
    for (;;) {
        const cap_res_t r = cap_next(c, &p, err, sizeof err);
        if (r == CAP_END || r == CAP_FATAL) {
            break;
        }
        if (r == CAP_DATAGRAM) {
            an_datagram(&a, "fuzz", &p);
        }
    }
    an_file_end(&a, "fuzz");
    an_free(&a);
    cap_close(c);
    return 0;
}
