/* SPDX-License-Identifier: MIT */
/* libFuzzer target: the SDO client against arbitrary server answers. Input: byte 0 picks
   upload or download and its length, then 9-byte records (8 data bytes and a time step)
   are answers on 0x581 or, with the step's top bit, a poll.
   Invariants: the client never holds more than C4G_CO_SDO_MAX bytes, its position stays
   within the length, frames it sends are 8-byte SDO requests on 0x601, and an ended
   transfer always has a result. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "c4gopen.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(c4g_co_sdo_client_t *c)
{
    c4g_co_frame_t f;
    bool have = false;
    if (c->len > C4G_CO_SDO_MAX || c->pos > c->len + 7 || c->toggle > 1) {
        abort();
    }
    if (c4g_co_sdo_take(c, &f, &have) != C4G_OK) {
        abort();
    }
    if (have && (f.id != 0x601 || f.dlc != 8)) {
        abort();
    }
    if (!c4g_co_sdo_busy(c) && c->result == C4G_CO_SDO_NONE) {
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    c4g_co_sdo_client_t c;
    uint8_t payload[C4G_CO_SDO_MAX];
    uint64_t now = 0;
    if (size < 1 || c4g_co_sdo_init(&c, 10000000U, 2) != C4G_OK) {
        return 0;
    }
    for (size_t i = 0; i < sizeof payload; i++) {
        payload[i] = (uint8_t)i;
    }
    const uint16_t len = (uint16_t)(1 + (data[0] & 0x3F));
    const c4g_status_t st = (data[0] & 0x80) ? c4g_co_sdo_download(&c, 1, 0x2000, 1, payload, len, now)
                                             : c4g_co_sdo_upload(&c, 1, 0x2000, 1, now);
    if (st != C4G_OK) {
        abort();
    }
    check(&c);
    for (size_t off = 1; off + 9 <= size; off += 9) {
        now += (uint64_t)(data[off + 8] & 0x7F) * 1000000u;
        if (data[off + 8] & 0x80) {
            if (c4g_co_sdo_poll(&c, now) != C4G_OK) {
                abort();
            }
        } else {
            c4g_co_frame_t f;
            memset(&f, 0, sizeof f);
            f.id = 0x581;
            f.dlc = 8;
            f.t_ns = now;
            memcpy(f.data, &data[off], 8);
            if (c4g_co_sdo_rx(&c, &f) != C4G_OK) {
                abort();
            }
        }
        check(&c);
        if (!c4g_co_sdo_busy(&c)) {
            uint32_t v;
            (void)c4g_co_sdo_value(&c, &v);
            break;
        }
    }
    return 0;
}
