/* SPDX-License-Identifier: MIT */
/* Simulated CANopen DS402 slave node (see c4gsim_slave.h). */
#include "c4gsim_slave.h"

#include <stddef.h>
#include <string.h>

#define PDO_OFF 0x80000000UL  /* COB-ID bit 31: PDO not valid */
#define N_TPDO 4U             /* slots 0..3 TPDO, 4..7 RPDO */
#define NAME_CAP 24U          /* sizeof name */

/* ---- frames out ----------------------------------------------------------- */

static void emit(c4g_co_frame_t *out, int *n, const c4g_co_frame_t *f)
{
    if (*n < (int)C4GSIM_SLAVE_OUT) {
        out[*n] = *f;
        (*n)++;
    }
}

/* ---- the object dictionary ------------------------------------------------- */

static void defaults(c4gsim_slave_t *s)
{
    uint32_t k;
    s->cycle_us = 0U;
    s->guard_ms = 0U;
    s->life_factor = 0U;
    s->heartbeat_ms = 0U;
    s->guard_toggle = 0U;
    for (k = 0U; k < 8U; k++) {
        const uint32_t base = (k < N_TPDO) ? (uint32_t)C4G_CO_COB_TPDO1 : (uint32_t)C4G_CO_COB_RPDO1;
        s->pdo_cob[k] = (base + (0x100U * (k % N_TPDO)) + (uint32_t)s->node_id) | PDO_OFF;
        (void)memset(&s->pdo[k], 0, sizeof s->pdo[k]);
        s->pdo[k].trans = (k < N_TPDO) ? 1U : 255U;
    }
    s->ds402 = C4G_CO_DS402_SWITCH_ON_DISABLED;
    s->controlword = 0U;
    s->modes = 0;
    s->seg_active = 0U;
    s->nmt = C4G_CO_STATE_BOOTUP;
}

static void power_cycle(c4gsim_slave_t *s)
{
    s->actual = 0;
    s->target = 0;
    defaults(s);
}

static bool is_pdo_comm(uint16_t index)
{
    const uint16_t hi = index & 0xFF00U;
    return (hi == 0x1400U) || (hi == 0x1800U);
}

static bool is_pdo_map(uint16_t index)
{
    const uint16_t hi = index & 0xFF00U;
    return (hi == 0x1600U) || (hi == 0x1A00U);
}

/* Size in bytes of a PDO communication or mapping object (0: no such object). */
static uint8_t pdo_size(uint16_t index, uint8_t sub)
{
    uint8_t size = 0U;
    if ((index & 0xFFU) < 4U) {
        if (is_pdo_comm(index)) {
            size = (sub == 1U) ? 4U : ((sub == 2U) ? 1U : 0U);
        } else {
            size = (sub == 0U) ? 1U : ((sub <= C4G_CO_MAX_ENTRIES) ? 4U : 0U);
        }
    }
    return size;
}

/* Size in bytes of an object (0: no such object). */
static uint8_t od_size(const c4gsim_slave_t *s, uint16_t index, uint8_t sub)
{
    uint8_t size = 0U;
    if (is_pdo_comm(index) || is_pdo_map(index)) {
        size = pdo_size(index, sub);
    } else if (sub == 0U) {
        switch (index) {
        case 0x1000U: case 0x1006U: case 0x6064U: case 0x607AU: size = 4U; break;
        case 0x1001U: case 0x100DU: case 0x6060U: size = 1U; break;
        case 0x100CU: case 0x1017U: case 0x6040U: case 0x6041U: size = 2U; break;
        case 0x1008U: size = s->name_len; break;
        default: size = 0U; break;
        }
    } else {
        size = 0U;
    }
    return size;
}

/* PDO slot of a communication/mapping index: 0..3 TPDO, 4..7 RPDO. */
static uint32_t pdo_slot(uint16_t index)
{
    const uint32_t k = (uint32_t)index & 3U;
    const uint16_t hi = index & 0xFF00U;
    return ((hi == 0x1800U) || (hi == 0x1A00U)) ? k : (N_TPDO + k);
}

static uint32_t pdo_read(const c4gsim_slave_t *s, uint16_t index, uint8_t sub)
{
    const uint32_t p = pdo_slot(index);
    uint32_t v;
    if (is_pdo_comm(index)) {
        v = (sub == 1U) ? s->pdo_cob[p] : (uint32_t)s->pdo[p].trans;
    } else if (sub == 0U) {
        v = s->pdo[p].n;
    } else if (sub <= C4G_CO_MAX_ENTRIES) {
        v = s->pdo[p].entry[sub - 1U];
    } else {
        v = 0U; /* a mapping that names a sub-index past the table reads nothing */
    }
    return v;
}

static uint32_t od_read(const c4gsim_slave_t *s, uint16_t index, uint8_t sub)
{
    uint16_t sw = 0U;
    uint32_t v = 0U;
    if (is_pdo_comm(index) || is_pdo_map(index)) {
        v = pdo_read(s, index, sub);
    } else {
        switch (index) {
        case 0x1000U: v = s->device_type; break;
        case 0x1001U: v = (s->ds402 == C4G_CO_DS402_FAULT) ? (uint32_t)1U : (uint32_t)0U; break;
        case 0x1006U: v = s->cycle_us; break;
        case 0x100CU: v = s->guard_ms; break;
        case 0x100DU: v = s->life_factor; break;
        case 0x1017U: v = s->heartbeat_ms; break;
        case 0x6040U: v = s->controlword; break;
        case 0x6041U:
            (void)c4g_co_ds402_statusword(s->ds402, &sw); /* a state of our own: cannot fail */
            v = sw;
            break;
        case 0x6060U: v = (uint8_t)s->modes; break;
        case 0x6064U: v = (uint32_t)s->actual; break;
        case 0x607AU: v = (uint32_t)s->target; break;
        default: v = 0U; break;
        }
    }
    return v;
}

static void set_controlword(c4gsim_slave_t *s, uint16_t cw)
{
    c4g_co_ds402_t next = s->ds402;
    if (c4g_co_ds402_apply(s->ds402, s->controlword, cw, &next) == C4G_OK) {
        if ((next == C4G_CO_DS402_ENABLED) && (s->ds402 != C4G_CO_DS402_ENABLED)) {
            s->target = s->actual; /* a drive enables where it stands */
        }
        s->ds402 = next;
    }
    s->controlword = cw;
}

/* Writes a PDO mapping object; returns 0 or an abort code. */
static uint32_t map_write(c4gsim_slave_t *s, uint32_t p, uint8_t sub, uint32_t v)
{
    uint32_t code = 0U;
    if (sub == 0U) {
        uint8_t bytes = 0U;
        c4g_co_pdo_map_t m;
        m = s->pdo[p];
        if (v > C4G_CO_MAX_ENTRIES) {
            code = (uint32_t)C4G_CO_ABORT_VALUE_HIGH;
        } else {
            m.n = (uint8_t)v;
            if (c4g_co_pdo_length(&m, &bytes) != C4G_OK) {
                code = (uint32_t)C4G_CO_ABORT_MAP_LENGTH;
            } else {
                s->pdo[p].n = (uint8_t)v;
            }
        }
    } else {
        s->pdo[p].entry[sub - 1U] = v;
    }
    return code;
}

/* Writes one of the device's own objects; returns 0 or an abort code. */
static uint32_t object_write(c4gsim_slave_t *s, uint16_t index, uint32_t v)
{
    uint32_t code = 0U;
    switch (index) {
    case 0x1006U: s->cycle_us = v; break;
    case 0x100CU: s->guard_ms = (uint16_t)v; break;
    case 0x100DU: s->life_factor = (uint8_t)v; break;
    case 0x1017U:
        s->heartbeat_ms = (uint16_t)v;
        s->next_hb_ns = 0U;
        break;
    case 0x6040U: set_controlword(s, (uint16_t)v); break;
    case 0x6060U: s->modes = (int8_t)(uint8_t)v; break;
    case 0x607AU: s->target = (int32_t)v; break;
    default: code = (uint32_t)C4G_CO_ABORT_READ_ONLY; break;
    }
    return code;
}

/* Writes an object of @p size bytes; returns 0 or an abort code. */
static uint32_t od_write(c4gsim_slave_t *s, uint16_t index, uint8_t sub, uint32_t v, uint8_t size)
{
    const uint8_t want = od_size(s, index, sub);
    const uint16_t hi = index & 0xFF00U;
    uint32_t code = 0U;
    if (want == 0U) {
        code = ((index == 0x1400U) || (hi == 0x6000U) || (hi == 0x1000U)) ? (uint32_t)C4G_CO_ABORT_NO_OBJECT
                                                                       : (uint32_t)C4G_CO_ABORT_NO_SUB;
    } else if (size != want) {
        code = (uint32_t)C4G_CO_ABORT_TYPE_LENGTH;
    } else if (is_pdo_comm(index)) {
        const uint32_t p = pdo_slot(index);
        if (sub == 1U) {
            s->pdo_cob[p] = v;
        } else {
            s->pdo[p].trans = (uint8_t)v;
        }
    } else if (is_pdo_map(index)) {
        code = map_write(s, pdo_slot(index), sub, v);
    } else {
        code = object_write(s, index, v);
    }
    return code;
}

/* ---- SDO server ------------------------------------------------------------- */

static void sdo_reply(const c4gsim_slave_t *s, c4g_co_frame_t *r)
{
    (void)memset(r, 0, sizeof *r);
    r->id = (uint16_t)(C4G_CO_COB_SDO_TX + (uint32_t)s->node_id);
    r->dlc = 8U;
}

static void sdo_abort(c4gsim_slave_t *s, uint16_t index, uint8_t sub, uint32_t code,
                      c4g_co_frame_t *out, int *n)
{
    c4g_co_frame_t r;
    /* our own identifier and a frame on the stack: the encoder cannot fail */
    (void)c4g_co_sdo_abort_encode(&r, (uint16_t)(C4G_CO_COB_SDO_TX + (uint32_t)s->node_id), index,
                                  sub, code);
    s->seg_active = 0U;
    emit(out, n, &r);
}

static void seg_start(c4gsim_slave_t *s, uint8_t kind, uint16_t index, uint8_t sub)
{
    s->seg_active = kind;
    s->seg_toggle = 0U;
    s->seg_pos = 0U;
    s->seg_index = index;
    s->seg_sub = sub;
}

/* Upload: expedited up to 4 bytes, segmented beyond (the name 0x1008). */
static void sdo_upload(c4gsim_slave_t *s, uint16_t index, uint8_t sub, c4g_co_frame_t *r,
                       c4g_co_frame_t *out, int *n)
{
    const uint8_t size = od_size(s, index, sub);
    if (size == 0U) {
        sdo_abort(s, index, sub, C4G_CO_ABORT_NO_OBJECT, out, n);
    } else if (size <= 4U) {
        const uint32_t v = od_read(s, index, sub);
        r->data[0] = (uint8_t)(0x43U | ((4U - (uint32_t)size) << 2U));
        r->data[4] = (uint8_t)v;
        r->data[5] = (uint8_t)(v >> 8U);
        r->data[6] = (uint8_t)(v >> 16U);
        r->data[7] = (uint8_t)(v >> 24U);
        emit(out, n, r);
    } else {
        r->data[0] = 0x41U;
        r->data[4] = size;
        seg_start(s, 1U, index, sub);
        emit(out, n, r);
    }
}

/* Download: expedited to any writable object, segmented to the name 0x1008 alone. */
static void sdo_download(c4gsim_slave_t *s, const c4g_co_frame_t *f, uint16_t index, uint8_t sub,
                         c4g_co_frame_t *r, c4g_co_frame_t *out, int *n)
{
    const uint8_t cmd = f->data[0];
    if ((cmd & 0x02U) != 0U) {
        const uint8_t len = ((cmd & 0x01U) != 0U) ? (uint8_t)(4U - (((uint32_t)cmd >> 2U) & 3U)) : 4U;
        const uint32_t v = (uint32_t)f->data[4] | ((uint32_t)f->data[5] << 8U) |
                           ((uint32_t)f->data[6] << 16U) | ((uint32_t)f->data[7] << 24U);
        const uint32_t code = od_write(s, index, sub, v, len);
        if (code != 0U) {
            sdo_abort(s, index, sub, code, out, n);
        } else {
            r->data[0] = 0x60U;
            emit(out, n, r);
        }
    } else if ((index == 0x1008U) && (sub == 0U)) {
        seg_start(s, 2U, index, sub);
        r->data[0] = 0x60U;
        emit(out, n, r);
    } else {
        sdo_abort(s, index, sub,
                  (od_size(s, index, sub) == 0U) ? C4G_CO_ABORT_NO_OBJECT : C4G_CO_ABORT_TYPE_LENGTH,
                  out, n);
    }
}

static uint16_t sdo_index(const c4g_co_frame_t *f)
{
    return (uint16_t)((uint32_t)f->data[1] | ((uint32_t)f->data[2] << 8U));
}

static void sdo_initiate(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    const uint8_t ccs = f->data[0] >> 5U;
    const uint16_t index = sdo_index(f);
    const uint8_t sub = f->data[3];
    c4g_co_frame_t r;
    sdo_reply(s, &r);
    r.data[1] = f->data[1];
    r.data[2] = f->data[2];
    r.data[3] = sub;
    if ((s->abort_index != 0U) && (index == s->abort_index) && (sub == s->abort_sub)) {
        sdo_abort(s, index, sub, s->abort_code, out, n);
    } else if (ccs == 2U) {
        sdo_upload(s, index, sub, &r, out, n);
    } else {
        sdo_download(s, f, index, sub, &r, out, n);
    }
}

/* The next segment of the name's upload into @p r. */
static void segment_up(c4gsim_slave_t *s, uint8_t t, c4g_co_frame_t *r)
{
    uint32_t k = (uint32_t)s->name_len - (uint32_t)s->seg_pos;
    uint32_t last = 0U;
    if (k <= 7U) {
        last = 1U;
    } else {
        k = 7U;
    }
    r->data[0] = (uint8_t)(((uint32_t)t << 4U) | ((7U - k) << 1U) | last);
    (void)memcpy(&r->data[1], &s->name[s->seg_pos], (size_t)k);
    s->seg_pos = (uint8_t)((uint32_t)s->seg_pos + k);
    s->seg_active = (uint8_t)((last != 0U) ? 0U : 1U);
}

/* One segment of the name's download into the dictionary; false: too long (aborted). */
static bool segment_down(c4gsim_slave_t *s, const c4g_co_frame_t *f, uint8_t t, c4g_co_frame_t *r,
                         c4g_co_frame_t *out, int *n)
{
    const uint32_t k = 7U - (((uint32_t)f->data[0] >> 1U) & 7U);
    bool ok = ((uint32_t)s->seg_pos + k) <= NAME_CAP;
    if (!ok) {
        sdo_abort(s, s->seg_index, s->seg_sub, C4G_CO_ABORT_TYPE_HIGH, out, n);
    } else {
        (void)memcpy(&s->name[s->seg_pos], &f->data[1], (size_t)k);
        s->seg_pos = (uint8_t)((uint32_t)s->seg_pos + k);
        r->data[0] = (uint8_t)(0x20U | ((uint32_t)t << 4U));
        if ((f->data[0] & 1U) != 0U) {
            s->name_len = s->seg_pos;
            s->seg_active = 0U;
        }
    }
    return ok;
}

static void sdo_segment(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    const uint8_t t = (uint8_t)(((uint32_t)f->data[0] >> 4U) & 1U);
    const uint8_t ccs = f->data[0] >> 5U;
    bool answer = false;
    c4g_co_frame_t r;
    sdo_reply(s, &r);
    if (t != s->seg_toggle) {
        sdo_abort(s, s->seg_index, s->seg_sub, C4G_CO_ABORT_TOGGLE, out, n);
    } else if ((s->seg_active == 1U) && (ccs == 3U)) {
        segment_up(s, t, &r);
        answer = true;
    } else if ((s->seg_active == 2U) && (ccs == 0U)) {
        answer = segment_down(s, f, t, &r, out, n);
    } else {
        sdo_abort(s, s->seg_index, s->seg_sub, C4G_CO_ABORT_COMMAND, out, n);
    }
    if (answer) {
        s->seg_toggle ^= 1U;
        emit(out, n, &r);
    }
}

static void on_sdo(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    const uint8_t ccs = f->data[0] >> 5U;
    s->sdo_requests++;
    if ((f->dlc == 8U) && (s->nmt != C4G_CO_STATE_STOPPED) && (s->nmt != C4G_CO_STATE_BOOTUP)) {
        if (ccs == 4U) {
            s->seg_active = 0U; /* the client aborted */
        } else if ((ccs == 1U) || (ccs == 2U)) {
            sdo_initiate(s, f, out, n);
        } else if ((s->seg_active != 0U) && ((ccs == 3U) || (ccs == 0U))) {
            sdo_segment(s, f, out, n);
        } else {
            sdo_abort(s, sdo_index(f), f->data[3], C4G_CO_ABORT_COMMAND, out, n);
        }
    }
}

/* ---- NMT, SYNC, PDOs, node guarding ------------------------------------------ */

static void on_nmt(c4gsim_slave_t *s, const c4g_co_frame_t *f)
{
    uint8_t cmd = 0U;
    uint8_t node = 0U;
    if ((c4g_co_nmt_decode(f, &cmd, &node) == C4G_OK) && ((node == 0U) || (node == s->node_id))) {
        switch (cmd) {
        case C4G_CO_NMT_START: s->nmt = C4G_CO_STATE_OPERATIONAL; break;
        case C4G_CO_NMT_STOP: s->nmt = C4G_CO_STATE_STOPPED; break;
        case C4G_CO_NMT_PREOP: s->nmt = C4G_CO_STATE_PREOP; break;
        default: power_cycle(s); break; /* reset node / communication */
        }
    }
}

/* Cyclic synchronous position: the axis moves towards its target, max_step per SYNC. */
static void csp_move(c4gsim_slave_t *s)
{
    if ((s->ds402 == C4G_CO_DS402_ENABLED) && (s->modes == (int8_t)C4G_CO_MODE_CSP)) {
        int32_t d = s->target - s->actual;
        if (d > s->max_step) {
            d = s->max_step;
        } else if (d < -s->max_step) {
            d = -s->max_step;
        } else {
            /* within one step: there */
        }
        s->actual += d;
    }
}

static void send_tpdo(const c4gsim_slave_t *s, uint32_t k, c4g_co_frame_t *out, int *n)
{
    const c4g_co_pdo_map_t *m = &s->pdo[k];
    if (((s->pdo_cob[k] & PDO_OFF) == 0U) && (m->n > 0U) && (m->trans >= 1U) && (m->trans <= 240U)) {
        uint32_t vals[C4G_CO_MAX_ENTRIES];
        c4g_co_frame_t f;
        uint32_t e;
        for (e = 0U; e < (uint32_t)m->n; e++) {
            vals[e] = od_read(s, (uint16_t)(m->entry[e] >> 16U), (uint8_t)(m->entry[e] >> 8U));
        }
        if (c4g_co_pdo_pack(m, (uint16_t)(s->pdo_cob[k] & 0x7FFU), vals, &f) == C4G_OK) {
            emit(out, n, &f);
        }
    }
}

static void node_on_sync(c4gsim_slave_t *s, c4g_co_frame_t *out, int *n)
{
    if (s->nmt == C4G_CO_STATE_OPERATIONAL) {
        csp_move(s);
        for (uint32_t k = 0U; k < N_TPDO; k++) {
            send_tpdo(s, k, out, n);
        }
    }
}

static void on_rpdo(c4gsim_slave_t *s, const c4g_co_frame_t *f, uint32_t k)
{
    const c4g_co_pdo_map_t *m = &s->pdo[N_TPDO + k];
    uint32_t vals[C4G_CO_MAX_ENTRIES];
    if ((s->nmt == C4G_CO_STATE_OPERATIONAL) && (c4g_co_pdo_unpack(m, f, vals) == C4G_OK)) {
        for (uint32_t e = 0U; e < (uint32_t)m->n; e++) {
            const uint16_t index = (uint16_t)(m->entry[e] >> 16U);
            const uint8_t sub = (uint8_t)(m->entry[e] >> 8U);
            /* a PDO has no answer: an object it cannot write stays as it is */
            (void)od_write(s, index, sub, vals[e], od_size(s, index, sub));
        }
    }
}

static void on_guard(c4gsim_slave_t *s, c4g_co_frame_t *out, int *n)
{
    if ((!s->no_heartbeat) && (s->nmt != C4G_CO_STATE_BOOTUP)) {
        c4g_co_frame_t r;
        (void)c4g_co_ec_encode(&r, s->node_id, s->nmt, s->guard_toggle); /* valid node: cannot fail */
        s->guard_toggle ^= 1U;
        emit(out, n, &r);
    }
}

static void on_other(c4gsim_slave_t *s, const c4g_co_frame_t *f)
{
    uint32_t k;
    for (k = 0U; k < N_TPDO; k++) {
        const uint32_t cob = s->pdo_cob[N_TPDO + k];
        if (((cob & PDO_OFF) == 0U) && ((uint32_t)f->id == (cob & 0x7FFU))) {
            on_rpdo(s, f, k);
        }
    }
}

static void node_dispatch(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    const uint32_t id = f->id;
    const uint32_t node = s->node_id;
    if (id == C4G_CO_COB_NMT) {
        on_nmt(s, f);
    } else if (id == C4G_CO_COB_SYNC) {
        node_on_sync(s, out, n);
    } else if ((id == (C4G_CO_COB_SDO_RX + node)) && (f->rtr == 0U)) {
        on_sdo(s, f, out, n);
    } else if ((id == (C4G_CO_COB_NMT_EC + node)) && (f->rtr != 0U)) {
        on_guard(s, out, n);
    } else {
        on_other(s, f);
    }
}

/* The heartbeat producer: the first one a period after it was configured, then one per
 * period (a late poll sends one and starts again from now). */
static void heartbeat(c4gsim_slave_t *s, uint64_t now_ns, c4g_co_frame_t *out, int *n)
{
    const uint64_t period = 1000000ULL * (uint64_t)s->heartbeat_ms;
    if (s->next_hb_ns == 0U) {
        s->next_hb_ns = now_ns + period;
    } else if (now_ns >= s->next_hb_ns) {
        c4g_co_frame_t f;
        (void)c4g_co_ec_encode(&f, s->node_id, s->nmt, 0U); /* valid node: cannot fail */
        emit(out, n, &f);
        s->next_hb_ns += period;
        if (s->next_hb_ns <= now_ns) {
            s->next_hb_ns = now_ns + period;
        }
    } else {
        /* not due yet */
    }
}

/* ---- the API ---------------------------------------------------------------- */

c4g_status_t c4gsim_slave_init(c4gsim_slave_t *s, uint8_t node_id, uint32_t device_type)
{
    static const char default_name[] = "c4g-sim DS402 drive";
    c4g_status_t st = C4G_ERR_NULL;
    if (s != NULL) {
        st = ((node_id >= 1U) && (node_id <= 127U)) ? C4G_OK : C4G_ERR_RANGE;
    }
    if (st == C4G_OK) {
        (void)memset(s, 0, sizeof *s);
        s->node_id = node_id;
        s->device_type = device_type;
        s->max_step = 200000;
        s->name_len = (uint8_t)((sizeof default_name) - 1U);
        (void)memcpy(s->name, default_name, s->name_len);
        defaults(s);
    }
    return st;
}

c4g_status_t c4gsim_slave_reset(c4gsim_slave_t *s)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (s != NULL) {
        power_cycle(s);
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4gsim_slave_rx(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (f != NULL) && (out != NULL) && (n != NULL)) {
        *n = 0;
        st = ((f->dlc <= 8U) && (f->id <= 0x7FFU)) ? C4G_OK : C4G_ERR_RANGE;
    }
    if ((st == C4G_OK) && (!s->silent)) {
        node_dispatch(s, f, out, n);
    }
    return st;
}

c4g_status_t c4gsim_slave_poll(c4gsim_slave_t *s, uint64_t now_ns, c4g_co_frame_t *out, int *n)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (out != NULL) && (n != NULL)) {
        *n = 0;
        st = C4G_OK;
    }
    if ((st == C4G_OK) && (!s->silent)) {
        if (s->nmt == C4G_CO_STATE_BOOTUP) {
            c4g_co_frame_t f;
            (void)c4g_co_ec_encode(&f, s->node_id, C4G_CO_STATE_BOOTUP, 0U); /* cannot fail */
            emit(out, n, &f);
            s->nmt = C4G_CO_STATE_PREOP;
            s->next_hb_ns = 0U;
        } else if ((s->heartbeat_ms != 0U) && (!s->no_heartbeat)) {
            heartbeat(s, now_ns, out, n);
        } else {
            /* no heartbeat configured, or muted */
        }
    }
    return st;
}

c4g_status_t c4gsim_slave_fault(c4gsim_slave_t *s, uint16_t code, c4g_co_frame_t *out, int *n)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (out != NULL) && (n != NULL)) {
        c4g_co_emcy_t e;
        c4g_co_frame_t f;
        *n = 0;
        (void)memset(&e, 0, sizeof e);
        e.code = code;
        e.reg = 0x01U;
        e.mfr[0] = (uint8_t)s->ds402;
        s->ds402 = C4G_CO_DS402_FAULT;
        if ((!s->silent) && (c4g_co_emcy_encode(&f, s->node_id, &e) == C4G_OK)) {
            emit(out, n, &f);
        }
        st = C4G_OK;
    }
    return st;
}
