/* SPDX-License-Identifier: MIT */
/* The datagram stream of the session fuzz target (and of bench/worst_tick.c, which runs its
 * corpus): 2-byte big-endian length prefixes; 0xFFFF inserts the figure 10.1 init packet so
 * that the cyclic phase is reached; the prefix's top two bits pick the sender (none, the
 * controller, another port, another address); an odd length advances the clock by 2 ms, an
 * even one by 25 ms. */
#ifndef FUZZ_STREAM_H
#define FUZZ_STREAM_H

#include <stdint.h>
#include <string.h>

#include "c4gopen.h"
#include "c4gsim_fixtures.h"

typedef struct fuzz_stream {
    const uint8_t *data;
    size_t size;
    size_t pos;
    uint64_t t;                 /* the clock of the datagram last returned [ns] */
    c4g_endpoint_t eps[3];      /* the controller, another port, another address */
    uint8_t init[C4G_INIT_SIZE];
} fuzz_stream_t;

static void fuzz_stream_start(fuzz_stream_t *st, const uint8_t *data, size_t size)
{
    c4g_init_t in;
    size_t len = 0U;
    memset(st, 0, sizeof *st);
    st->data = data;
    st->size = size;
    st->eps[0].addr[0] = st->eps[1].addr[0] = st->eps[2].addr[0] = 127;
    st->eps[0].addr[3] = st->eps[1].addr[3] = 1;
    st->eps[2].addr[3] = 2;
    st->eps[0].addr_len = st->eps[1].addr_len = st->eps[2].addr_len = 4;
    st->eps[0].port = 3600;
    st->eps[1].port = 3601;
    st->eps[2].port = 3600;
    (void)c4gsim_fig10_1(&in);
    (void)c4g_init_encode(&in, st->init, sizeof st->init, &len);
}

/* The next datagram: 1 with *dg, *dl, *from (NULL: no sender) and st->t set; 0 at the end. */
static int fuzz_stream_next(fuzz_stream_t *st, const uint8_t **dg, size_t *dl, const c4g_endpoint_t **from)
{
    const uint8_t *data = st->data;
    size_t n;
    unsigned who;
    if (st->pos + 2U > st->size) {
        return 0;
    }
    n = ((size_t)data[st->pos] << 8U) | data[st->pos + 1U];
    who = (unsigned)(data[st->pos] >> 6U);
    *from = (who == 0U) ? NULL : &st->eps[who - 1U];
    *dg = &data[st->pos + 2U];
    st->pos += 2U;
    if (n == 0xFFFFU) {
        *dg = st->init;
        n = sizeof st->init;
    } else {
        n %= 800U;
        if (n > st->size - st->pos) {
            n = st->size - st->pos;
        }
        st->pos += n;
    }
    st->t += (n & 1U) ? 2000000U : 25000000U;
    *dl = n;
    return 1;
}

#endif
