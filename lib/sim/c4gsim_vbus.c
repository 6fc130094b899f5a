/* SPDX-License-Identifier: MIT */
/* In-process virtual CAN bus (see c4gsim_vbus.h). */
#include "c4gsim_vbus.h"

#include <stddef.h>
#include <string.h>

c4g_status_t c4gsim_vbus_init(c4gsim_vbus_t *b, c4g_co_master_t *m)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (b != NULL) {
        (void)memset(b, 0, sizeof *b);
        b->master = m;
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4gsim_vbus_add(c4gsim_vbus_t *b, c4gsim_slave_t *s)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((b != NULL) && (s != NULL)) {
        st = (b->n_slaves < C4G_CO_MAX_NODES) ? C4G_OK : C4G_ERR_CAPACITY;
    }
    if (st == C4G_OK) {
        b->slave[b->n_slaves] = s;
        b->n_slaves++;
    }
    return st;
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
        /* the bus delivers what a node sent; the master judges it and counts what it refuses */
        (void)c4g_co_master_rx(b->master, f);
    }
}

/* A node's answers, in order. */
static void from_nodes(c4gsim_vbus_t *b, c4g_co_frame_t *out, int n, uint64_t now_ns)
{
    int k;
    for (k = 0; k < n; k++) {
        from_node(b, &out[k], now_ns);
    }
}

c4g_status_t c4gsim_vbus_inject(c4gsim_vbus_t *b, const c4g_co_frame_t *f, uint64_t now_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((b != NULL) && (f != NULL)) {
        c4g_co_frame_t c = *f;
        from_node(b, &c, now_ns);
        st = C4G_OK;
    }
    return st;
}

/* Delivers one master frame to every node, then the nodes' answers to the master. */
static void deliver(c4gsim_vbus_t *b, c4g_co_frame_t *f, uint64_t now_ns)
{
    uint32_t i;
    put(b, f, now_ns);
    for (i = 0U; i < b->n_slaves; i++) {
        c4g_co_frame_t out[C4GSIM_SLAVE_OUT];
        int n = 0;
        if (c4gsim_slave_rx(b->slave[i], f, out, &n) == C4G_OK) {
            from_nodes(b, out, n, now_ns);
        }
    }
}

c4g_status_t c4gsim_vbus_step(c4gsim_vbus_t *b, uint64_t now_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (b != NULL) {
        uint32_t i;
        for (i = 0U; i < b->n_slaves; i++) {
            c4g_co_frame_t out[C4GSIM_SLAVE_OUT];
            int n = 0;
            if (c4gsim_slave_poll(b->slave[i], now_ns, out, &n) == C4G_OK) {
                from_nodes(b, out, n, now_ns);
            }
        }
        if (b->master != NULL) {
            bool more = true;
            uint32_t guard;
            uint64_t next_ns = 0U;
            /* the master's timers; what they found comes out as frames and events (the bus
             * is stepped by its caller's clock, so the next deadline is not needed here) */
            (void)c4g_co_master_poll(b->master, now_ns, &next_ns);
            /* each master frame may start the next SDO: bounded by the queue's length */
            for (guard = 0U; (guard < (4U * C4G_CO_TXQ_LEN)) && more; guard++) {
                c4g_co_frame_t f;
                bool have = false;
                more = (c4g_co_master_tx(b->master, &f, &have) == C4G_OK) && have;
                if (more) {
                    deliver(b, &f, now_ns);
                }
            }
        }
        st = C4G_OK;
    }
    return st;
}
