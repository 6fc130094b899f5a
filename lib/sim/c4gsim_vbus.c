/* SPDX-License-Identifier: MIT */
/* In-process virtual CAN bus (see c4g_co_bus.h). */
#include "c4gsim_vbus.h"

#include <string.h>

void c4gsim_vbus_init(c4gsim_vbus_t *b, c4g_co_master_t *m)
{
    memset(b, 0, sizeof *b);
    b->master = m;
}

int c4gsim_vbus_add(c4gsim_vbus_t *b, c4gsim_slave_t *s)
{
    if (b->n_slaves >= (int)C4G_CO_MAX_NODES) {
        return -1;
    }
    b->slave[b->n_slaves++] = s;
    return 0;
}

static void put(c4gsim_vbus_t *b, c4g_co_frame_t *f, uint64_t now_ns)
{
    f->t_ns = now_ns;
    b->frames++;
    if (b->log != NULL) {
        b->log(b->log_ctx, f);
    }
}

/* A node's frame: to the master (and the other nodes ignore what is not theirs). */
static void from_node(c4gsim_vbus_t *b, c4g_co_frame_t *f, uint64_t now_ns)
{
    put(b, f, now_ns);
    if (b->master != NULL) {
        (void)c4g_co_master_rx(b->master, f);
    }
}

void c4gsim_vbus_inject(c4gsim_vbus_t *b, const c4g_co_frame_t *f, uint64_t now_ns)
{
    c4g_co_frame_t c = *f;
    from_node(b, &c, now_ns);
}

/* Delivers one master frame to every node, then the nodes' answers to the master. */
static void deliver(c4gsim_vbus_t *b, c4g_co_frame_t *f, uint64_t now_ns)
{
    int i;
    put(b, f, now_ns);
    for (i = 0; i < b->n_slaves; i++) {
        c4g_co_frame_t out[C4GSIM_SLAVE_OUT];
        int n = 0, k;
        c4gsim_slave_rx(b->slave[i], f, out, &n);
        for (k = 0; k < n; k++) {
            from_node(b, &out[k], now_ns);
        }
    }
}

void c4gsim_vbus_step(c4gsim_vbus_t *b, uint64_t now_ns)
{
    int i, guard;
    c4g_co_frame_t f;
    bool have = false;
    for (i = 0; i < b->n_slaves; i++) {
        c4g_co_frame_t out[C4GSIM_SLAVE_OUT];
        int n = 0, k;
        c4gsim_slave_poll(b->slave[i], now_ns, out, &n);
        for (k = 0; k < n; k++) {
            from_node(b, &out[k], now_ns);
        }
    }
    if (b->master == NULL) {
        return;
    }
    {
        uint64_t next;
        (void)c4g_co_master_poll(b->master, now_ns, &next);
    }
    /* each master frame may start the next SDO: bounded by the queue's length */
    for (guard = 0; guard < 4 * (int)C4G_CO_TXQ_LEN; guard++) {
        if (c4g_co_master_tx(b->master, &f, &have) != C4G_OK || !have) {
            break;
        }
        deliver(b, &f, now_ns);
    }
}
