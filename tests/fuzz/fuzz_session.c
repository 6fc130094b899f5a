/* SPDX-License-Identifier: MIT */
/* libFuzzer: the session engine fed an arbitrary datagram stream. The input is split
 * into datagrams by a 2-byte length prefix; 0xFFFF inserts the figure 10.1 init packet
 * so that the cyclic phase is reached; the prefix's top two bits pick the sender (none, the
 * controller, another port, another address). Invariants: phase always valid, replies only
 * when armed, reply lengths 732/1200/12+36N (no more than 9 sync replies per start-up), a
 * sync reply only to a datagram of a cyclic packet's shape and never with a non-finite
 * value, a foreign datagram never changes the phase (but to REFUSED when it contends a
 * start-up) or the newest packet, a refused session accepts nothing, never a crash. Differential: the session's inline decode
 * equals the public decoder's output, and a twin session answering every cyclic packet with
 * c4g_session_reply_neutral sends the bytes c4g_pc_reply_neutral + c4g_session_reply send. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include "fuzz_stream.h"
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static c4g_session_t s;   /* big: keep off the fuzzer's stack */
    static c4g_session_t twin;
    static c4g_ctrl_packet_t pub;
    c4g_rx_result_t r, r2;
    uint8_t out2[C4G_INIT_SIZE];
    size_t n2;
    static fuzz_stream_t st;
    uint8_t out[C4G_INIT_SIZE];
    size_t n;
    uint64_t t;
    const uint8_t *dg;
    size_t dl;
    const c4g_endpoint_t *from;
    fuzz_stream_start(&st, data, size);
    if ((c4g_session_init(&s, NULL) != C4G_OK) || (c4g_session_init(&twin, NULL) != C4G_OK)) {
        abort();
    }
    while (fuzz_stream_next(&st, &dg, &dl, &from)) {
        const c4g_phase_t phase_before = s.phase;
        const int32_t newest_before = s.priv.last_num;
        t = st.t;
        if (c4g_session_rx_from(&twin, dg, dl, t, from, &r2) == C4G_ERR_ENDED) {
            (void)c4g_session_init(&twin, NULL);
        }
        if (c4g_session_rx_from(&s, dg, dl, t, from, &r) == C4G_ERR_ENDED) {
            if (s.phase != C4G_PHASE_ENDED) {
                abort();
            }
            (void)c4g_session_init(&s, NULL);
            continue;
        }
        if ((r.kind != r2.kind) || (r.events != r2.events) || (s.phase != twin.phase) ||
            (memcmp(&r.diag, &r2.diag, sizeof r.diag) != 0)) {
            abort();
        }
        if (s.phase > C4G_PHASE_REFUSED) {
            abort();
        }
        if (((r.events & C4G_EV_FOREIGN) != 0U) &&
            ((r.kind != C4G_RX_DROPPED) || (s.priv.last_num != newest_before) ||
             ((s.phase != phase_before) && (phase_before != C4G_PHASE_CYCLIC) &&
              (phase_before != C4G_PHASE_POST_SYNC) && (phase_before != C4G_PHASE_REFUSED) &&
              ((r.events & C4G_EV_CONTENDED) == 0U)))) {
            abort(); /* (the silence check may move CYCLIC or REFUSED to LOST on any datagram;
                        another endpoint's start-up packet refuses a start-up) */
        }
        if ((s.phase == C4G_PHASE_REFUSED) && (r.kind != C4G_RX_DROPPED)) {
            abort(); /* a refused session accepts nothing */
        }
        if (r.kind == C4G_RX_CYCLIC) {
            c4g_pc_packet_t tx;
            /* the session's neutral reply (held current bounded by AzLim), as the twin sends */
            if ((r.pkt == NULL) || (c4g_session_neutral(&s, r.pkt, &tx) != C4G_OK) ||
                (c4g_session_reply(&s, &tx, out, sizeof out, &n) != C4G_OK) ||
                (n != C4G_CYCLIC_SIZE(s.map.n_axes)) || (c4g_session_sent(&s, t + 1000U) != C4G_OK)) {
                abort();
            }
            /* the inline decode is the public decoder's, axes past the count zero included */
            if ((c4g_ctrl_decode(dg, dl, s.map.n_axes, &pub, NULL) != C4G_OK) ||
                (memcmp(&pub, r.pkt, sizeof pub) != 0)) {
                abort();
            }
            if ((c4g_session_reply_neutral(&twin, out2, sizeof out2, &n2) != C4G_OK) || (n2 != n) ||
                (memcmp(out, out2, n) != 0) || (twin.priv.frozen_active != s.priv.frozen_active) ||
                (c4g_session_sent(&twin, t + 1000U) != C4G_OK)) {
                abort();
            }
        } else if (r.kind != C4G_RX_DROPPED) {
            c4g_ctrl_packet_t echo;
            if ((c4g_session_reply(&s, NULL, out, sizeof out, &n) != C4G_OK) ||
                ((r.kind == C4G_RX_INIT) && (n != C4G_INIT_SIZE)) ||
                ((r.kind == C4G_RX_SYNC) && (n != C4G_SYNC_REPLY_SIZE)) ||
                (c4g_session_reply_neutral(&twin, out2, sizeof out2, &n2) != C4G_OK) ||
                (n2 != n) || (memcmp(out, out2, n) != 0)) {
                abort();
            }
            if ((r.kind == C4G_RX_SYNC) &&
                ((dl < C4G_CYCLIC_SIZE(1U)) || (((dl - C4G_HEADER_SIZE) % C4G_AXIS_SIZE) != 0U) ||
                 (c4g_ctrl_decode(out, n, 0U, &echo, NULL) != C4G_OK))) {
                abort(); /* amplified, or a NaN / unknown mode echoed */
            }
        } else if ((c4g_session_reply(&s, NULL, out, sizeof out, &n) != C4G_ERR_STATE) ||
                   (c4g_session_reply_neutral(&twin, out2, sizeof out2, &n2) != C4G_ERR_STATE)) {
            abort();
        }
    }
    return 0;
}
