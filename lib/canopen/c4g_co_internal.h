/* SPDX-License-Identifier: MIT */
/* CANopen internals shared by lib/canopen/ files. */
#ifndef C4G_CO_INTERNAL_H
#define C4G_CO_INTERNAL_H

#include "c4gopen_canopen.h"
#include "../c4g_internal.h"
#include <string.h>

C4G_INTERNAL bool c4g_co_node_ok(uint8_t node);
C4G_INTERNAL void c4g_co_frame_clear(c4g_co_frame_t *f, uint16_t id, uint8_t dlc);

/* Master internals (c4g_co_master.c / c4g_co_run.c). */
#define C4G_CO_PHASE_IDLE 0U
#define C4G_CO_PHASE_BOOT 1U
#define C4G_CO_PHASE_RUN 2U
#define C4G_CO_NO_SLOT 0xFFU

C4G_INTERNAL void c4g_co_push_tx(c4g_co_master_t *m, const c4g_co_frame_t *f);
C4G_INTERNAL void c4g_co_push_ev(c4g_co_master_t *m, const c4g_co_event_t *e);
C4G_INTERNAL void c4g_co_push_event(c4g_co_master_t *m, uint8_t kind, uint8_t slot, uint64_t t_ns);
C4G_INTERNAL void c4g_co_node_lost(c4g_co_master_t *m, uint8_t slot, uint8_t cause, uint64_t now_ns);
C4G_INTERNAL void c4g_co_run_rx(c4g_co_master_t *m, const c4g_co_frame_t *f, c4g_co_kind_t kind,
                   uint8_t slot, uint8_t pdo);
C4G_INTERNAL void c4g_co_run_poll(c4g_co_master_t *m, uint64_t now_ns);
C4G_INTERNAL void c4g_co_sdo_answer(c4g_co_master_t *m, const c4g_co_frame_t *f);
C4G_INTERNAL void c4g_co_start_node(c4g_co_master_t *m, uint8_t slot, uint64_t now_ns);

#endif /* C4G_CO_INTERNAL_H */
