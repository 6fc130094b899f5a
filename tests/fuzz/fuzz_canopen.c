/* SPDX-License-Identifier: MIT */
/* libFuzzer target: CANopen frame decoders and the master's receive path. The input is a
   sequence of frames (2 bytes id/flags, 1 byte dlc, 8 data bytes, 1 byte time step) fed to
   every decoder and to a master that has booted one node.
   Invariants: decoders that accept a frame re-encode it to the same bytes; the master
   counts every frame; its queues never exceed their bounds; node slots stay valid. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "c4gopen.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_codecs(const c4g_co_frame_t *f)
{
    c4g_co_kind_t k;
    uint8_t node = 0, pdo = 0, cmd = 0, st = 0, tg = 0;
    c4g_co_frame_t g;
    c4g_co_emcy_t e;
    if (c4g_co_classify(f, &k, &node, &pdo) == C4G_OK && (node > 127 || pdo > 3)) {
        abort();
    }
    if (c4g_co_nmt_decode(f, &cmd, &node) == C4G_OK) {
        if (c4g_co_nmt_encode(&g, cmd, node) != C4G_OK || memcmp(g.data, f->data, 2) != 0) {
            abort();
        }
    }
    if (c4g_co_ec_decode(f, &node, &st, &tg) == C4G_OK) {
        if (c4g_co_ec_encode(&g, node, st, tg) != C4G_OK || g.data[0] != f->data[0] || g.id != f->id) {
            abort();
        }
    }
    if (c4g_co_emcy_decode(f, &node, &e) == C4G_OK) {
        if (c4g_co_emcy_encode(&g, node, &e) != C4G_OK || memcmp(g.data, f->data, 8) != 0) {
            abort();
        }
    }
    (void)c4g_co_ds402_state((uint16_t)(f->data[0] | (f->data[1] << 8)));
}

static c4g_co_master_t m;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    c4g_co_net_cfg_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.bitrate = 500000;
    cfg.sync_period_ns = 1000000U;
    cfg.sdo_timeout_ns = 5000000U;
    cfg.sdo_retries = 1;
    cfg.n_nodes = 2;
    for (int i = 0; i < 2; i++) {
        c4g_co_node_cfg_t *n = &cfg.node[i];
        n->node_id = (uint8_t)(i + 1);
        n->station = (uint8_t)(i + 1);
        n->axis = 1;
        n->device_type = 0x00020192;
        n->watchdog = (uint8_t)(i == 0 ? C4G_CO_WD_HEARTBEAT : C4G_CO_WD_LIFEGUARD);
        n->heartbeat_ms = 10;
        n->consumer_ms = 30;
        n->guard_ms = 10;
        n->life_factor = 3;
        n->flags = C4G_CO_F_RECOVERY | C4G_CO_F_BYPASS_PDO;
        n->rx[0].n = 2;
        n->rx[0].trans = 1;
        n->rx[0].entry[0] = C4G_CO_MAP(0x6041, 0, 16);
        n->rx[0].entry[1] = C4G_CO_MAP(0x6064, 0, 32);
    }
    if (c4g_co_master_init(&m, &cfg) != C4G_OK || c4g_co_master_start(&m, 0) != C4G_OK) {
        abort();
    }
    uint64_t now = 0;
    for (size_t off = 0; off + 12 <= size; off += 12) {
        c4g_co_frame_t f;
        memset(&f, 0, sizeof f);
        f.id = (uint16_t)((data[off] | (data[off + 1] << 8)) & 0x0FFF);
        f.rtr = (uint8_t)(data[off + 1] >> 7);
        f.dlc = data[off + 2] & 0x0F;
        memcpy(f.data, &data[off + 3], 8);
        now += (uint64_t)data[off + 11] * 500000u;
        f.t_ns = now;
        check_codecs(&f);
        const uint32_t rx = m.count.rx;
        if (c4g_co_master_rx(&m, &f) != C4G_OK || m.count.rx != rx + 1) {
            abort();
        }
        uint64_t next = 0U;
        if (c4g_co_master_poll(&m, now, &next) != C4G_OK) {
            abort();
        }
        if (next <= now) {
            abort(); /* a deadline already passed: a caller that sleeps until it would spin */
        }
        c4g_co_frame_t out;
        c4g_co_event_t ev;
        bool have = true;
        while (have) {
            if (c4g_co_master_tx(&m, &out, &have) != C4G_OK || (have && (out.dlc > 8 || out.id > 0x7FF))) {
                abort();
            }
        }
        have = true;
        while (have) {
            if (c4g_co_master_event(&m, &ev, &have) != C4G_OK || (have && ev.node != 1 && ev.node != 2)) {
                abort();
            }
        }
        if (m.txq_n > C4G_CO_TXQ_LEN || m.evq_n > C4G_CO_EVQ_LEN ||
            (m.cur != 0xFF && m.cur >= 2) || m.node[0].emcy_n > C4G_CO_EMCY_DEPTH) {
            abort();
        }
    }
    return 0;
}
