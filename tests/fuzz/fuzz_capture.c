/* SPDX-License-Identifier: MIT */
/* Fuzz target: any bytes as a capture file, through c4g-replay's reader and the whole
 * session analysis (flows, direction, sessions, reply judging, findings, export rows). */
#include "c4gh_analyze.h"
#include "c4gh_capture.h"

#include <stdio.h>
#include <string.h>

static unsigned long rows;

static void on_exchange(void *ctx, const c4gh_an_exchange_t *x)
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
    c4gh_an_options_t o;
    c4gh_an_t a;
    c4gh_cap_t *c;
    c4gh_cap_pkt_t p;
    FILE *fp;
    if (size == 0U) {
        return 0;
    }
    fp = fmemopen((void *)(uintptr_t)data, size, "rb");
    if (fp == NULL) {
        return 0;
    }
    c = c4gh_cap_open_stream(fp, "fuzz", err, sizeof err);
    if (c == NULL) {
        return 0;
    }
    c4gh_an_options_default(&o);
    o.on_exchange = on_exchange;
    o.max_step = 0.5;
    if (c4gh_an_init(&a, &o) != 0) {
        c4gh_cap_close(c);
        return 0;
    }
    for (;;) {
        const c4gh_cap_res_t r = c4gh_cap_next(c, &p, err, sizeof err);
        if (r == C4GH_CAP_END || r == C4GH_CAP_FATAL) {
            break;
        }
        if (r == C4GH_CAP_DATAGRAM) {
            c4gh_an_datagram(&a, "fuzz", &p);
        }
    }
    c4gh_an_file_end(&a, "fuzz");
    c4gh_an_free(&a);
    c4gh_cap_close(c);
    return 0;
}
