/* SPDX-License-Identifier: MIT */
/* In-process virtual CAN bus: one CANopen master (libc4gopen) and simulated slave
 * nodes exchange frames in order, each frame logged once with its time. Used where no
 * SocketCAN interface exists, and by the tests. */
#ifndef C4GSIM_VBUS_H
#define C4GSIM_VBUS_H

#include "c4gsim_slave.h"

typedef void (*c4gsim_bus_log_fn)(void *ctx, const c4g_co_frame_t *f);

typedef struct c4gsim_vbus {
    c4g_co_master_t *master;
    c4gsim_slave_t *slave[C4G_CO_MAX_NODES];
    uint32_t n_slaves;
    c4gsim_bus_log_fn log;  /* optional: every frame on the bus */
    void *log_ctx;
    uint64_t frames;
} c4gsim_vbus_t;

/* Every function returns a status: C4G_ERR_NULL for a NULL pointer. @p m may be NULL (a bus
 * of nodes alone). */
C4G_NODISCARD c4g_status_t c4gsim_vbus_init(c4gsim_vbus_t *b, c4g_co_master_t *m);
/* A node on the bus; C4G_ERR_CAPACITY past C4G_CO_MAX_NODES. */
C4G_NODISCARD c4g_status_t c4gsim_vbus_add(c4gsim_vbus_t *b, c4gsim_slave_t *s);
/* Puts a frame on the bus as if a node had sent it (injection, EMCY of a fault). */
C4G_NODISCARD c4g_status_t c4gsim_vbus_inject(c4gsim_vbus_t *b, const c4g_co_frame_t *f, uint64_t now_ns);
/* Time passes to now_ns: master timers, then every frame until the bus is quiet. */
C4G_NODISCARD c4g_status_t c4gsim_vbus_step(c4gsim_vbus_t *b, uint64_t now_ns);

#endif /* C4GSIM_VBUS_H */
