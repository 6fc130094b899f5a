/* SPDX-License-Identifier: MIT */
/* libFuzzer: the session engine fed an arbitrary datagram stream. The input is split
 * into datagrams by a 2-byte length prefix; 0xFFFF inserts the figure 10.1 init packet
 * so that the cyclic phase is reached. Invariants: phase always valid, replies only
 * when armed, reply lengths 732/1200/12+36N, never a crash. */
#include "c4gopen.h"
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static c4g_session_t s;   /* big: keep off the fuzzer's stack */
    c4g_rx_result_t r;
    c4g_init_t in;
    uint8_t init[C4G_INIT_SIZE];
    uint8_t out[C4G_INIT_SIZE];
    size_t pos = 0, len = 0, n;
    uint64_t t = 0;
    (void)c4g_init_fig10_1(&in);
    (void)c4g_init_encode(&in, init, sizeof init, &len);
    if (c4g_session_init(&s, NULL) != C4G_OK) {
        abort();
    }
    while (pos + 2U <= size) {
        size_t dl = ((size_t)data[pos] << 8U) | data[pos + 1U];
        const uint8_t *dg = &data[pos + 2U];
        pos += 2U;
        if (dl == 0xFFFFU) {
            dg = init;
            dl = sizeof init;
        } else {
            dl %= 800U;
            if (dl > size - pos) {
                dl = size - pos;
            }
            pos += dl;
        }
        t += (dl & 1U) ? 2000000U : 25000000U;
        if (c4g_session_rx(&s, dg, dl, t, &r) == C4G_ERR_ENDED) {
            if (s.phase != C4G_PHASE_ENDED) {
                abort();
            }
            (void)c4g_session_init(&s, NULL);
            continue;
        }
        if (s.phase > C4G_PHASE_LOST) {
            abort();
        }
        if (r.kind == C4G_RX_CYCLIC) {
            c4g_pc_packet_t tx;
            if ((r.pkt == NULL) || (c4g_pc_reply_neutral(r.pkt, &tx) != C4G_OK) ||
                (c4g_session_reply(&s, &tx, out, sizeof out, &n) != C4G_OK) ||
                (n != C4G_CYCLIC_SIZE(s.map.n_axes)) || (c4g_session_sent(&s, t + 1000U) != C4G_OK)) {
                abort();
            }
        } else if (r.kind != C4G_RX_DROPPED) {
            if ((c4g_session_reply(&s, NULL, out, sizeof out, &n) != C4G_OK) ||
                (n != ((r.kind == C4G_RX_INIT) ? C4G_INIT_SIZE : C4G_SYNC_REPLY_SIZE))) {
                abort();
            }
        } else if (c4g_session_reply(&s, NULL, out, sizeof out, &n) != C4G_ERR_STATE) {
            abort();
        }
    }
    return 0;
}
