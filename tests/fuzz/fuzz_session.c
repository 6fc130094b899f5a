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
    c4g_init_t in;
    uint8_t init[C4G_INIT_SIZE];
    uint8_t out[C4G_INIT_SIZE];
    size_t pos = 0, len = 0, n;
    uint64_t t = 0;
    c4g_endpoint_t eps[3];
    memset(eps, 0, sizeof eps);
    eps[0].addr[0] = eps[1].addr[0] = eps[2].addr[0] = 127;
    eps[0].addr[3] = eps[1].addr[3] = 1;
    eps[2].addr[3] = 2;
    eps[0].addr_len = eps[1].addr_len = eps[2].addr_len = 4;
    eps[0].port = 3600;
    eps[1].port = 3601;
    eps[2].port = 3600;
    (void)c4gsim_fig10_1(&in);
    (void)c4g_init_encode(&in, init, sizeof init, &len);
    if ((c4g_session_init(&s, NULL) != C4G_OK) || (c4g_session_init(&twin, NULL) != C4G_OK)) {
        abort();
    }
    while (pos + 2U <= size) {
        size_t dl = ((size_t)data[pos] << 8U) | data[pos + 1U];
        const uint8_t *dg = &data[pos + 2U];
        const unsigned who = (unsigned)(data[pos] >> 6U);
        const c4g_endpoint_t *from = (who == 0U) ? NULL : &eps[who - 1U];
        const c4g_phase_t phase_before = s.phase;
        const int32_t newest_before = s.priv.last_num;
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
