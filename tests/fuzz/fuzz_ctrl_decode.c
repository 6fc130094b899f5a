/* SPDX-License-Identifier: MIT */
/* libFuzzer: cyclic decoders (both directions); a decoded packet must re-encode to the
 * same bytes, and a rejected one must name a field. */
#include "c4gopen.h"
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t q;
    c4g_diag_t d;
    uint8_t out[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;
    uint32_t n = (size > 0U) ? (uint32_t)(data[0] % 22U) : 0U;
    if (c4g_ctrl_decode(data, size, 0, &p, &d) == C4G_OK) {
        if ((c4g_ctrl_encode(&p, out, sizeof out, &len) != C4G_OK) || (len != size) ||
            (memcmp(out, data, size) != 0)) {
            abort();
        }
    } else if ((d.status == C4G_OK) || (d.field == C4G_FIELD_NONE)) {
        abort();
    }
    if (c4g_pc_decode(data, size, n, &q, &d) == C4G_OK) {
        if (((n != 0U) && (q.n_axes != n)) || (c4g_pc_encode(&q, out, sizeof out, &len) != C4G_OK) ||
            (memcmp(out, data, size) != 0)) {
            abort();
        }
    }
    return 0;
}
