/* SPDX-License-Identifier: MIT */
/* Simulated CANopen DS402 slave node: object dictionary, SDO server (expedited and
 * segmented), NMT, heartbeat producer, node guarding responder, PDOs on SYNC, EMCY on
 * faults, a position axis in cyclic synchronous position mode, and fault injection
 * (docs/canopen.md, "Simulated nodes"). No I/O: frames in, frames out. Every function returns a
 * status: C4G_ERR_NULL for a NULL pointer, C4G_ERR_RANGE for a value outside its range. */
#ifndef C4GSIM_SLAVE_H
#define C4GSIM_SLAVE_H

#include "c4gopen_canopen.h"

#define C4GSIM_SLAVE_OUT 8 /* frames one call can produce */

typedef struct c4gsim_slave {
    uint8_t node_id;
    uint8_t nmt;              /* C4G_CO_STATE_* */
    uint32_t device_type;     /* 0x1000 */
    uint32_t cycle_us;        /* 0x1006 */
    uint16_t guard_ms;        /* 0x100C */
    uint8_t life_factor;      /* 0x100D */
    uint16_t heartbeat_ms;    /* 0x1017 */
    uint32_t pdo_cob[8];      /* 0..3 TPDO 0x1800+k:01, 4..7 RPDO 0x1400+k:01 */
    c4g_co_pdo_map_t pdo[8];  /* 0x1A00+k / 0x1600+k and transmission types */
    uint8_t guard_toggle;
    uint64_t next_hb_ns;
    /* DS402 */
    c4g_co_ds402_t ds402;
    uint16_t controlword;
    int8_t modes;             /* 0x6060 */
    int32_t target;           /* 0x607A */
    int32_t actual;           /* 0x6064 */
    int32_t max_step;         /* counts per SYNC the axis can move */
    uint8_t name[24];         /* 0x1008 (segmented upload) */
    uint8_t name_len;
    /* fault injection */
    bool silent;              /* answers nothing at all (unplugged) */
    bool no_heartbeat;        /* answers SDO but produces no heartbeat */
    uint16_t abort_index;     /* SDO abort on this object (0: none) */
    uint8_t abort_sub;
    uint32_t abort_code;
    uint32_t sdo_requests;    /* SDO requests seen */
    /* segmented transfer state */
    uint8_t seg_active;       /* 1 upload, 2 download */
    uint8_t seg_toggle;
    uint16_t seg_index;
    uint8_t seg_sub;
    uint8_t seg_pos;
} c4gsim_slave_t;

/* A node (@p node_id 1..127) in the boot-up state (it sends its boot-up message at the next
 * poll). */
C4G_NODISCARD c4g_status_t c4gsim_slave_init(c4gsim_slave_t *s, uint8_t node_id, uint32_t device_type);
/* A frame from the bus (dlc 0..8, id 0..0x7FF, else C4G_ERR_RANGE); answers go to
 * out[0..*n), @p out holding C4GSIM_SLAVE_OUT frames. */
C4G_NODISCARD c4g_status_t c4gsim_slave_rx(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out,
                                           int *n);
/* Time passes: boot-up message, heartbeat (out as for c4gsim_slave_rx). */
C4G_NODISCARD c4g_status_t c4gsim_slave_poll(c4gsim_slave_t *s, uint64_t now_ns, c4g_co_frame_t *out, int *n);
/* Power cycle: boot-up state again with a fresh dictionary (a node that comes back). */
C4G_NODISCARD c4g_status_t c4gsim_slave_reset(c4gsim_slave_t *s);
/* Drive fault: EMCY (0x7300-style code, unless silent) and DS402 fault state. */
C4G_NODISCARD c4g_status_t c4gsim_slave_fault(c4gsim_slave_t *s, uint16_t code, c4g_co_frame_t *out, int *n);

#endif /* C4GSIM_SLAVE_H */
