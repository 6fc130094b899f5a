/* SPDX-License-Identifier: MIT */
/* libFuzzer: initialization packet decoder and axis maps. The input is laid over the
 * figure 10.1 packet so that the fuzzer reaches the deep validation paths. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    c4g_init_t in;
    c4g_axis_map_t m;
    c4g_diag_t d;
    uint8_t buf[C4G_INIT_SIZE];
    uint8_t out[C4G_INIT_SIZE];
    size_t len = 0;
    uint32_t i;
    /* raw input as is */
    (void)c4g_init_decode(data, size, &in, &d);
    /* overlay: first 2 bytes pick an offset, the rest overwrite from there */
    (void)c4gsim_fig10_1(&in);
    (void)c4g_init_encode(&in, buf, sizeof buf, &len);
    if (size >= 2U) {
        size_t off = (((size_t)data[0] << 8U) | data[1]) % C4G_INIT_SIZE;
        size_t n = size - 2U;
        if (n > C4G_INIT_SIZE - off) {
            n = C4G_INIT_SIZE - off;
        }
        memcpy(&buf[off], &data[2], n);
    }
    if (c4g_init_decode(buf, sizeof buf, &in, &d) == C4G_OK) {
        uint32_t total = 0;
        if (c4g_axis_map_build(&in, &m, NULL) != C4G_OK) {
            abort();
        }
        for (i = 0; i < m.n_axes; i++) {
            if ((m.arm_of[i] >= C4G_ARMS) || (m.logical_of[i] >= C4G_AXES_PER_ARM) ||
                (m.open_of[m.arm_of[i]][m.logical_of[i]] != i)) {
                abort();
            }
        }
        for (i = 0; i < C4G_ARMS; i++) {
            total += m.n_axes_arm[i];
        }
        if ((total != m.n_axes) || (m.n_axes != (uint32_t)in.n_ax_open) ||
            (c4g_init_encode(&in, out, sizeof out, &len) != C4G_OK) ||
            (memcmp(out, buf, sizeof out) != 0)) {
            abort();
        }
    } else if ((d.status == C4G_OK) || (d.field == C4G_FIELD_NONE) || (d.offset >= C4G_INIT_SIZE)) {
        abort();
    }
    return 0;
}
