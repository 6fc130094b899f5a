/* SPDX-License-Identifier: MIT */
/* The CANopen master's first boot steps with no bus at all: the caller moves the frames.
   Prints the frames in candump's notation; exits 1 if the order is not the documented one. */
#include <stdio.h>
#include <string.h>

#include "c4gopen.h"

static void show(const c4g_co_frame_t *f)
{
    printf("%03X#", f->id);
    for (int i = 0; i < f->dlc; i++) {
        printf("%02X", f->data[i]);
    }
    printf("\n");
}

int main(void)
{
    static c4g_co_master_t m; /* caller-owned, no heap */
    c4g_co_net_cfg_t cfg;
    c4g_co_frame_t f;
    bool have = false;
    memset(&cfg, 0, sizeof cfg);
    cfg.bitrate = 500000;
    cfg.sync_period_ns = 10000000;  /* 10 ms: every time of the library is in ns */
    cfg.sdo_timeout_ns = 50000000;
    cfg.n_nodes = 1;
    cfg.node[0].node_id = 1;
    cfg.node[0].station = 1;
    cfg.node[0].axis = 1;
    cfg.node[0].device_type = 0x00020192; /* DS402 servo drive */
    cfg.node[0].cycle_period_us = 10000;
    cfg.node[0].watchdog = C4G_CO_WD_HEARTBEAT;
    cfg.node[0].heartbeat_ms = 100;
    cfg.node[0].consumer_ms = 300;
    if (c4g_co_master_init(&m, &cfg) != C4G_OK || c4g_co_master_start(&m, 0) != C4G_OK) {
        return 1;
    }
    /* step 1: NMT Enter Pre-Operational to all; step 2: SDO upload of 0x1000:00 */
    if (c4g_co_master_tx(&m, &f, &have) != C4G_OK || !have || f.id != 0x000 || f.data[0] != 0x80) {
        return 1;
    }
    show(&f);
    if (c4g_co_master_tx(&m, &f, &have) != C4G_OK || !have || f.id != 0x601 || f.data[0] != 0x40) {
        return 1;
    }
    show(&f);
    /* the node answers DeviceType = 0x00020192 */
    memset(&f, 0, sizeof f);
    f.id = 0x581;
    f.dlc = 8;
    f.t_ns = 1000000;
    memcpy(f.data, "\x43\x00\x10\x00\x92\x01\x02\x00", 8);
    if (c4g_co_master_rx(&m, &f) != C4G_OK) {
        return 1;
    }
    /* step 3: SDO download of 0x1006:00 = 10000 us */
    if (c4g_co_master_tx(&m, &f, &have) != C4G_OK || !have || f.data[1] != 0x06 || f.data[2] != 0x10) {
        return 1;
    }
    show(&f);
    return m.node[0].devtype_read == 0x00020192 ? 0 : 1;
}
