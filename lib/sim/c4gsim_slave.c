/* SPDX-License-Identifier: MIT */
/* Simulated CANopen DS402 slave node (see c4gsim_slave.h). */
#include "c4gsim_slave.h"

#include <string.h>

static const char default_name[] = "c4g-sim DS402 drive";

static void defaults(c4gsim_slave_t *s)
{
    int k;
    s->cycle_us = 0;
    s->guard_ms = 0;
    s->life_factor = 0;
    s->heartbeat_ms = 0;
    s->guard_toggle = 0;
    for (k = 0; k < 8; k++) {
        const uint32_t base = (k < 4) ? C4G_CO_COB_TPDO1 : C4G_CO_COB_RPDO1;
        s->pdo_cob[k] = (base + 0x100U * (uint32_t)(k % 4) + s->node_id) | 0x80000000UL;
        memset(&s->pdo[k], 0, sizeof s->pdo[k]);
        s->pdo[k].trans = (k < 4) ? 1 : 255;
    }
    s->ds402 = C4G_CO_DS402_SWITCH_ON_DISABLED;
    s->controlword = 0;
    s->modes = 0;
    s->seg_active = 0;
    s->nmt = C4G_CO_STATE_BOOTUP;
}

void c4gsim_slave_init(c4gsim_slave_t *s, uint8_t node_id, uint32_t device_type)
{
    memset(s, 0, sizeof *s);
    s->node_id = node_id;
    s->device_type = device_type;
    s->max_step = 200000;
    s->name_len = (uint8_t)strlen(default_name);
    memcpy(s->name, default_name, s->name_len);
    defaults(s);
}

void c4gsim_slave_reset(c4gsim_slave_t *s)
{
    s->actual = 0;
    s->target = 0;
    defaults(s);
}

static void emit(c4g_co_frame_t *out, int *n, const c4g_co_frame_t *f)
{
    if (*n < C4GSIM_SLAVE_OUT) {
        out[(*n)++] = *f;
    }
}

/* Size in bytes of an object (0: no such object). */
static int od_size(const c4gsim_slave_t *s, uint16_t index, uint8_t sub)
{
    int size = 0;
    if ((index & 0xFF00U) == 0x1400U || (index & 0xFF00U) == 0x1800U) {
        if ((index & 0xFFU) < 4U) {
            size = (sub == 1) ? 4 : (sub == 2) ? 1 : 0;
        }
    } else if ((index & 0xFF00U) == 0x1600U || (index & 0xFF00U) == 0x1A00U) {
        if ((index & 0xFFU) < 4U) {
            size = (sub == 0) ? 1 : (sub <= C4G_CO_MAX_ENTRIES) ? 4 : 0;
        }
    } else if (sub == 0) {
        switch (index) {
        case 0x1000: case 0x1006: case 0x6064: case 0x607A: size = 4; break;
        case 0x1001: case 0x100D: case 0x6060: size = 1; break;
        case 0x100C: case 0x1017: case 0x6040: case 0x6041: size = 2; break;
        case 0x1008: size = s->name_len; break;
        default: size = 0; break;
        }
    }
    return size;
}

/* PDO slot of a communication/mapping index: 0..3 TPDO, 4..7 RPDO. */
static int pdo_slot(uint16_t index)
{
    const int k = index & 3;
    const int hi = index & 0xFF00;
    return (hi == 0x1800 || hi == 0x1A00) ? k : 4 + k;
}

static uint32_t od_read(const c4gsim_slave_t *s, uint16_t index, uint8_t sub)
{
    uint16_t sw = 0;
    const int hi = index & 0xFF00;
    if (hi == 0x1400 || hi == 0x1800) {
        const int p = pdo_slot(index);
        return (sub == 1) ? s->pdo_cob[p] : s->pdo[p].trans;
    }
    if (hi == 0x1600 || hi == 0x1A00) {
        const int p = pdo_slot(index);
        return (sub == 0) ? s->pdo[p].n : s->pdo[p].entry[sub - 1];
    }
    switch (index) {
    case 0x1000: return s->device_type;
    case 0x1001: return (s->ds402 == C4G_CO_DS402_FAULT) ? 1U : 0U;
    case 0x1006: return s->cycle_us;
    case 0x100C: return s->guard_ms;
    case 0x100D: return s->life_factor;
    case 0x1017: return s->heartbeat_ms;
    case 0x6040: return s->controlword;
    case 0x6041: (void)c4g_co_ds402_statusword(s->ds402, &sw); return sw;
    case 0x6060: return (uint8_t)s->modes;
    case 0x6064: return (uint32_t)s->actual;
    case 0x607A: return (uint32_t)s->target;
    default: return 0;
    }
}

static void set_controlword(c4gsim_slave_t *s, uint16_t cw)
{
    c4g_co_ds402_t next = s->ds402;
    if (c4g_co_ds402_apply(s->ds402, s->controlword, cw, &next) == C4G_OK) {
        if (next == C4G_CO_DS402_ENABLED && s->ds402 != C4G_CO_DS402_ENABLED) {
            s->target = s->actual; /* a drive enables where it stands */
        }
        s->ds402 = next;
    }
    s->controlword = cw;
}

/* Writes an object; returns 0 or an abort code. */
static uint32_t od_write(c4gsim_slave_t *s, uint16_t index, uint8_t sub, uint32_t v, int size)
{
    const int want = od_size(s, index, sub);
    const int hi = index & 0xFF00;
    if (want == 0) {
        return (index == 0x1400 || hi == 0x6000 || hi == 0x1000) ? C4G_CO_ABORT_NO_OBJECT
                                                                : C4G_CO_ABORT_NO_SUB;
    }
    if (size != want) {
        return C4G_CO_ABORT_TYPE_LENGTH;
    }
    if (hi == 0x1400 || hi == 0x1800) {
        const int p = pdo_slot(index);
        if (sub == 1) {
            s->pdo_cob[p] = v;
        } else {
            s->pdo[p].trans = (uint8_t)v;
        }
        return 0;
    }
    if (hi == 0x1600 || hi == 0x1A00) {
        const int p = pdo_slot(index);
        if (sub == 0) {
            uint8_t bytes = 0;
            c4g_co_pdo_map_t m = s->pdo[p];
            if (v > C4G_CO_MAX_ENTRIES) {
                return C4G_CO_ABORT_VALUE_HIGH;
            }
            m.n = (uint8_t)v;
            if (c4g_co_pdo_length(&m, &bytes) != C4G_OK) {
                return C4G_CO_ABORT_MAP_LENGTH;
            }
            s->pdo[p].n = (uint8_t)v;
        } else {
            s->pdo[p].entry[sub - 1] = v;
        }
        return 0;
    }
    switch (index) {
    case 0x1006: s->cycle_us = v; return 0;
    case 0x100C: s->guard_ms = (uint16_t)v; return 0;
    case 0x100D: s->life_factor = (uint8_t)v; return 0;
    case 0x1017:
        s->heartbeat_ms = (uint16_t)v;
        s->next_hb_ns = 0;
        return 0;
    case 0x6040: set_controlword(s, (uint16_t)v); return 0;
    case 0x6060: s->modes = (int8_t)v; return 0;
    case 0x607A: s->target = (int32_t)v; return 0;
    default: return C4G_CO_ABORT_READ_ONLY;
    }
}

static void sdo_reply(c4gsim_slave_t *s, c4g_co_frame_t *r)
{
    memset(r, 0, sizeof *r);
    r->id = (uint16_t)(C4G_CO_COB_SDO_TX + s->node_id);
    r->dlc = 8;
}

static void sdo_abort(c4gsim_slave_t *s, uint16_t index, uint8_t sub, uint32_t code,
                      c4g_co_frame_t *out, int *n)
{
    c4g_co_frame_t r;
    (void)c4g_co_sdo_abort_encode(&r, (uint16_t)(C4G_CO_COB_SDO_TX + s->node_id), index, sub,
                                  code);
    s->seg_active = 0;
    emit(out, n, &r);
}

static void sdo_initiate(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out,
                         int *n)
{
    const uint8_t ccs = f->data[0] >> 5;
    const uint16_t index = (uint16_t)(f->data[1] | (f->data[2] << 8));
    const uint8_t sub = f->data[3];
    const int size = od_size(s, index, sub);
    c4g_co_frame_t r;
    sdo_reply(s, &r);
    r.data[1] = f->data[1];
    r.data[2] = f->data[2];
    r.data[3] = sub;
    if (s->abort_index != 0 && index == s->abort_index && sub == s->abort_sub) {
        sdo_abort(s, index, sub, s->abort_code, out, n);
    } else if (ccs == 2) { /* upload */
        if (size == 0) {
            sdo_abort(s, index, sub, C4G_CO_ABORT_NO_OBJECT, out, n);
        } else if (size <= 4) {
            uint32_t v = od_read(s, index, sub);
            r.data[0] = (uint8_t)(0x43 | ((4 - size) << 2));
            memcpy(&r.data[4], (uint8_t[4]){(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16),
                                            (uint8_t)(v >> 24)}, 4);
            emit(out, n, &r);
        } else {
            r.data[0] = 0x41;
            r.data[4] = (uint8_t)size;
            s->seg_active = 1;
            s->seg_toggle = 0;
            s->seg_pos = 0;
            s->seg_index = index;
            s->seg_sub = sub;
            emit(out, n, &r);
        }
    } else if ((f->data[0] & 0x02) != 0) { /* expedited download */
        const int len = (f->data[0] & 0x01) ? 4 - ((f->data[0] >> 2) & 3) : 4;
        const uint32_t v = (uint32_t)f->data[4] | ((uint32_t)f->data[5] << 8) |
                           ((uint32_t)f->data[6] << 16) | ((uint32_t)f->data[7] << 24);
        const uint32_t code = od_write(s, index, sub, v, len);
        if (code != 0) {
            sdo_abort(s, index, sub, code, out, n);
        } else {
            r.data[0] = 0x60;
            emit(out, n, &r);
        }
    } else if (index == 0x1008 && sub == 0) { /* segmented download of the name */
        s->seg_active = 2;
        s->seg_toggle = 0;
        s->seg_pos = 0;
        s->seg_index = index;
        s->seg_sub = sub;
        r.data[0] = 0x60;
        emit(out, n, &r);
    } else {
        sdo_abort(s, index, sub, (size == 0) ? C4G_CO_ABORT_NO_OBJECT : C4G_CO_ABORT_TYPE_LENGTH,
                  out, n);
    }
}

static void sdo_segment(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    const uint8_t t = (f->data[0] >> 4) & 1;
    c4g_co_frame_t r;
    sdo_reply(s, &r);
    if (t != s->seg_toggle) {
        sdo_abort(s, s->seg_index, s->seg_sub, C4G_CO_ABORT_TOGGLE, out, n);
        return;
    }
    if (s->seg_active == 1 && (f->data[0] >> 5) == 3) {
        int k = s->name_len - s->seg_pos;
        int last = 0;
        if (k <= 7) {
            last = 1;
        } else {
            k = 7;
        }
        r.data[0] = (uint8_t)((t << 4) | ((7 - k) << 1) | last);
        memcpy(&r.data[1], &s->name[s->seg_pos], (size_t)k);
        s->seg_pos = (uint8_t)(s->seg_pos + k);
        s->seg_active = last ? 0 : 1;
    } else if (s->seg_active == 2 && (f->data[0] >> 5) == 0) {
        const int k = 7 - ((f->data[0] >> 1) & 7);
        if (s->seg_pos + k > (int)sizeof s->name) {
            sdo_abort(s, s->seg_index, s->seg_sub, C4G_CO_ABORT_TYPE_HIGH, out, n);
            return;
        }
        memcpy(&s->name[s->seg_pos], &f->data[1], (size_t)k);
        s->seg_pos = (uint8_t)(s->seg_pos + k);
        r.data[0] = (uint8_t)(0x20 | (t << 4));
        if (f->data[0] & 1) {
            s->name_len = s->seg_pos;
            s->seg_active = 0;
        }
    } else {
        sdo_abort(s, s->seg_index, s->seg_sub, C4G_CO_ABORT_COMMAND, out, n);
        return;
    }
    s->seg_toggle ^= 1;
    emit(out, n, &r);
}

static void on_sdo(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    const uint8_t ccs = f->data[0] >> 5;
    s->sdo_requests++;
    if (f->dlc != 8 || s->nmt == C4G_CO_STATE_STOPPED || s->nmt == C4G_CO_STATE_BOOTUP) {
        return;
    }
    if (ccs == 4) {
        s->seg_active = 0; /* the client aborted */
    } else if (ccs == 1 || ccs == 2) {
        sdo_initiate(s, f, out, n);
    } else if (s->seg_active != 0 && (ccs == 3 || ccs == 0)) {
        sdo_segment(s, f, out, n);
    } else {
        sdo_abort(s, (uint16_t)(f->data[1] | (f->data[2] << 8)), f->data[3],
                  C4G_CO_ABORT_COMMAND, out, n);
    }
}

static void on_nmt(c4gsim_slave_t *s, const c4g_co_frame_t *f)
{
    uint8_t cmd = 0, node = 0;
    if (c4g_co_nmt_decode(f, &cmd, &node) != C4G_OK || (node != 0 && node != s->node_id)) {
        return;
    }
    switch (cmd) {
    case C4G_CO_NMT_START: s->nmt = C4G_CO_STATE_OPERATIONAL; break;
    case C4G_CO_NMT_STOP: s->nmt = C4G_CO_STATE_STOPPED; break;
    case C4G_CO_NMT_PREOP: s->nmt = C4G_CO_STATE_PREOP; break;
    default: c4gsim_slave_reset(s); break; /* reset node / communication */
    }
}

static void on_sync(c4gsim_slave_t *s, c4g_co_frame_t *out, int *n)
{
    int k;
    if (s->nmt != C4G_CO_STATE_OPERATIONAL) {
        return;
    }
    if (s->ds402 == C4G_CO_DS402_ENABLED && s->modes == (int8_t)C4G_CO_MODE_CSP) {
        int32_t d = s->target - s->actual;
        if (d > s->max_step) {
            d = s->max_step;
        } else if (d < -s->max_step) {
            d = -s->max_step;
        }
        s->actual += d;
    }
    for (k = 0; k < 4; k++) {
        const c4g_co_pdo_map_t *m = &s->pdo[k];
        if ((s->pdo_cob[k] & 0x80000000UL) == 0 && m->n > 0 && m->trans >= 1 && m->trans <= 240) {
            uint32_t vals[C4G_CO_MAX_ENTRIES];
            c4g_co_frame_t f;
            int e;
            for (e = 0; e < m->n; e++) {
                vals[e] = od_read(s, (uint16_t)(m->entry[e] >> 16), (uint8_t)(m->entry[e] >> 8));
            }
            if (c4g_co_pdo_pack(m, (uint16_t)(s->pdo_cob[k] & 0x7FFU), vals, &f) == C4G_OK) {
                emit(out, n, &f);
            }
        }
    }
}

static void on_rpdo(c4gsim_slave_t *s, const c4g_co_frame_t *f, int k)
{
    const c4g_co_pdo_map_t *m = &s->pdo[4 + k];
    uint32_t vals[C4G_CO_MAX_ENTRIES];
    int e;
    if (s->nmt != C4G_CO_STATE_OPERATIONAL || c4g_co_pdo_unpack(m, f, vals) != C4G_OK) {
        return;
    }
    for (e = 0; e < m->n; e++) {
        const uint16_t index = (uint16_t)(m->entry[e] >> 16);
        const uint8_t sub = (uint8_t)(m->entry[e] >> 8);
        (void)od_write(s, index, sub, vals[e], od_size(s, index, sub));
    }
}

void c4gsim_slave_rx(c4gsim_slave_t *s, const c4g_co_frame_t *f, c4g_co_frame_t *out, int *n)
{
    int k;
    *n = 0;
    if (s->silent) {
        return;
    }
    if (f->id == C4G_CO_COB_NMT) {
        on_nmt(s, f);
    } else if (f->id == C4G_CO_COB_SYNC) {
        on_sync(s, out, n);
    } else if (f->id == C4G_CO_COB_SDO_RX + s->node_id && f->rtr == 0) {
        on_sdo(s, f, out, n);
    } else if (f->id == C4G_CO_COB_NMT_EC + s->node_id && f->rtr != 0) {
        if (!s->no_heartbeat && s->nmt != C4G_CO_STATE_BOOTUP) {
            c4g_co_frame_t r;
            (void)c4g_co_ec_encode(&r, s->node_id, s->nmt, s->guard_toggle);
            s->guard_toggle ^= 1;
            emit(out, n, &r);
        }
    } else {
        for (k = 0; k < 4; k++) {
            if ((s->pdo_cob[4 + k] & 0x80000000UL) == 0 && f->id == (s->pdo_cob[4 + k] & 0x7FFU)) {
                on_rpdo(s, f, k);
            }
        }
    }
}

void c4gsim_slave_poll(c4gsim_slave_t *s, uint64_t now_ns, c4g_co_frame_t *out, int *n)
{
    c4g_co_frame_t f;
    *n = 0;
    if (s->silent) {
        return;
    }
    if (s->nmt == C4G_CO_STATE_BOOTUP) {
        (void)c4g_co_ec_encode(&f, s->node_id, C4G_CO_STATE_BOOTUP, 0);
        emit(out, n, &f);
        s->nmt = C4G_CO_STATE_PREOP;
        s->next_hb_ns = 0;
        return;
    }
    if (s->heartbeat_ms == 0 || s->no_heartbeat) {
        return;
    }
    if (s->next_hb_ns == 0) {
        s->next_hb_ns = now_ns + 1000000ULL * s->heartbeat_ms;
    } else if (now_ns >= s->next_hb_ns) {
        (void)c4g_co_ec_encode(&f, s->node_id, s->nmt, 0);
        emit(out, n, &f);
        s->next_hb_ns += 1000000ULL * s->heartbeat_ms;
        if (s->next_hb_ns <= now_ns) {
            s->next_hb_ns = now_ns + 1000000ULL * s->heartbeat_ms;
        }
    }
}

void c4gsim_slave_fault(c4gsim_slave_t *s, uint16_t code, c4g_co_frame_t *out, int *n)
{
    c4g_co_emcy_t e;
    c4g_co_frame_t f;
    *n = 0;
    memset(&e, 0, sizeof e);
    e.code = code;
    e.reg = 0x01;
    e.mfr[0] = (uint8_t)s->ds402;
    s->ds402 = C4G_CO_DS402_FAULT;
    if (!s->silent && c4g_co_emcy_encode(&f, s->node_id, &e) == C4G_OK) {
        emit(out, n, &f);
    }
}
