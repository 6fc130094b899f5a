/* SPDX-License-Identifier: MIT */
/* CANopen frame codecs: classification, NMT, SYNC, error control, EMCY, PDO packing. */
#include "c4gopen_canopen.h"
#include "c4g_co_internal.h"

bool c4g_co_node_ok(uint8_t node)
{
    return (node >= 1U) && (node <= 127U);
}

void c4g_co_frame_clear(c4g_co_frame_t *f, uint16_t id, uint8_t dlc)
{
    uint32_t i;
    f->t_ns = 0U;
    f->id = id;
    f->rtr = 0U;
    f->dlc = dlc;
    for (i = 0U; i < 8U; i++) {
        f->data[i] = 0U;
    }
}

/* Function code (id >> 7) to kind; node-addressed codes need node 1..127. */
static c4g_co_kind_t kind_of(uint16_t fc, uint8_t node, uint8_t *pdo)
{
    c4g_co_kind_t k = C4G_CO_K_UNKNOWN;
    *pdo = 0U;
    if ((fc >= 3U) && (fc <= 10U)) {
        *pdo = (uint8_t)((fc - 3U) / 2U);
        k = ((fc % 2U) == 1U) ? C4G_CO_K_TPDO : C4G_CO_K_RPDO;
    } else if (fc == 1U) {
        k = C4G_CO_K_EMCY;
    } else if (fc == 11U) {
        k = C4G_CO_K_SDO_TX;
    } else if (fc == 12U) {
        k = C4G_CO_K_SDO_RX;
    } else if (fc == 14U) {
        k = C4G_CO_K_NMT_EC;
    } else {
        k = C4G_CO_K_UNKNOWN;
    }
    if (node == 0U) {
        k = C4G_CO_K_UNKNOWN;
        *pdo = 0U;
    }
    return k;
}

c4g_status_t c4g_co_classify(const c4g_co_frame_t *f, c4g_co_kind_t *kind, uint8_t *node,
                             uint8_t *pdo)
{
    c4g_status_t st = C4G_OK;
    if ((f == NULL) || (kind == NULL) || (node == NULL) || (pdo == NULL)) {
        st = C4G_ERR_NULL;
    } else if (f->id > 0x7FFU) {
        st = C4G_ERR_RANGE;
    } else if (f->dlc > 8U) {
        st = C4G_ERR_LENGTH;
    } else {
        const uint16_t fc = (uint16_t)(f->id >> 7U);
        uint8_t n = (uint8_t)(f->id & 0x7FU);
        *pdo = 0U;
        if (f->id == C4G_CO_COB_NMT) {
            *kind = C4G_CO_K_NMT;
        } else if (f->id == C4G_CO_COB_SYNC) {
            *kind = C4G_CO_K_SYNC;
        } else if (f->id == 0x100U) {
            *kind = C4G_CO_K_TIME;
        } else {
            *kind = kind_of(fc, n, pdo);
        }
        if ((*kind == C4G_CO_K_NMT) || (*kind == C4G_CO_K_SYNC) || (*kind == C4G_CO_K_TIME) ||
            (*kind == C4G_CO_K_UNKNOWN)) {
            n = 0U;
        }
        *node = n;
    }
    return st;
}

c4g_status_t c4g_co_nmt_encode(c4g_co_frame_t *f, uint8_t cmd, uint8_t node)
{
    c4g_status_t st = C4G_OK;
    if (f == NULL) {
        st = C4G_ERR_NULL;
    } else if ((node > 127U) || ((cmd != C4G_CO_NMT_START) && (cmd != C4G_CO_NMT_STOP) &&
                                 (cmd != C4G_CO_NMT_PREOP) && (cmd != C4G_CO_NMT_RESET_NODE) &&
                                 (cmd != C4G_CO_NMT_RESET_COMM))) {
        st = C4G_ERR_ARG;
    } else {
        c4g_co_frame_clear(f, C4G_CO_COB_NMT, 2U);
        f->data[0] = cmd;
        f->data[1] = node;
    }
    return st;
}

c4g_status_t c4g_co_nmt_decode(const c4g_co_frame_t *f, uint8_t *cmd, uint8_t *node)
{
    c4g_status_t st = C4G_OK;
    if ((f == NULL) || (cmd == NULL) || (node == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((f->id != C4G_CO_COB_NMT) || (f->rtr != 0U)) {
        st = C4G_ERR_ARG;
    } else if (f->dlc != 2U) {
        st = C4G_ERR_LENGTH;
    } else {
        c4g_co_frame_t chk;
        st = c4g_co_nmt_encode(&chk, f->data[0], f->data[1]);
        if (st == C4G_OK) {
            *cmd = f->data[0];
            *node = f->data[1];
        } else {
            st = C4G_ERR_RANGE;
        }
    }
    return st;
}

c4g_status_t c4g_co_sync_encode(c4g_co_frame_t *f)
{
    c4g_status_t st = C4G_OK;
    if (f == NULL) {
        st = C4G_ERR_NULL;
    } else {
        c4g_co_frame_clear(f, C4G_CO_COB_SYNC, 0U);
    }
    return st;
}

static bool state_ok(uint8_t state)
{
    return (state == C4G_CO_STATE_BOOTUP) || (state == C4G_CO_STATE_STOPPED) ||
           (state == C4G_CO_STATE_OPERATIONAL) || (state == C4G_CO_STATE_PREOP);
}

c4g_status_t c4g_co_ec_encode(c4g_co_frame_t *f, uint8_t node, uint8_t state, uint8_t toggle)
{
    c4g_status_t st = C4G_OK;
    if (f == NULL) {
        st = C4G_ERR_NULL;
    } else if (!c4g_co_node_ok(node) || !state_ok(state) || (toggle > 1U)) {
        st = C4G_ERR_ARG;
    } else {
        c4g_co_frame_clear(f, (uint16_t)(C4G_CO_COB_NMT_EC + node), 1U);
        f->data[0] = (uint8_t)((uint32_t)state | ((uint32_t)toggle << 7U));
    }
    return st;
}

c4g_status_t c4g_co_ec_decode(const c4g_co_frame_t *f, uint8_t *node, uint8_t *state,
                              uint8_t *toggle)
{
    c4g_status_t st = C4G_OK;
    if ((f == NULL) || (node == NULL) || (state == NULL) || (toggle == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((f->id <= C4G_CO_COB_NMT_EC) || (f->id > 0x77FU) || (f->rtr != 0U)) {
        st = C4G_ERR_ARG;
    } else if (f->dlc != 1U) {
        st = C4G_ERR_LENGTH;
    } else if (!state_ok((uint8_t)(f->data[0] & 0x7FU))) {
        st = C4G_ERR_RANGE;
    } else {
        *node = (uint8_t)(f->id - C4G_CO_COB_NMT_EC);
        *state = (uint8_t)(f->data[0] & 0x7FU);
        *toggle = (uint8_t)((uint32_t)f->data[0] >> 7U);
    }
    return st;
}

c4g_status_t c4g_co_guard_request(c4g_co_frame_t *f, uint8_t node)
{
    c4g_status_t st = C4G_OK;
    if (f == NULL) {
        st = C4G_ERR_NULL;
    } else if (!c4g_co_node_ok(node)) {
        st = C4G_ERR_ARG;
    } else {
        /* A remote request carries the length of the answer it asks for. */
        c4g_co_frame_clear(f, (uint16_t)(C4G_CO_COB_NMT_EC + node), 1U);
        f->rtr = 1U;
    }
    return st;
}

c4g_status_t c4g_co_emcy_encode(c4g_co_frame_t *f, uint8_t node, const c4g_co_emcy_t *e)
{
    c4g_status_t st = C4G_OK;
    if ((f == NULL) || (e == NULL)) {
        st = C4G_ERR_NULL;
    } else if (!c4g_co_node_ok(node)) {
        st = C4G_ERR_ARG;
    } else {
        uint32_t i;
        c4g_co_frame_clear(f, (uint16_t)((uint16_t)C4G_CO_COB_EMCY + node), 8U);
        c4g_put_le(f->data, e->code, 2U);
        f->data[2] = e->reg;
        for (i = 0U; i < 5U; i++) {
            f->data[3U + i] = e->mfr[i];
        }
    }
    return st;
}

c4g_status_t c4g_co_emcy_decode(const c4g_co_frame_t *f, uint8_t *node, c4g_co_emcy_t *e)
{
    c4g_status_t st = C4G_OK;
    if ((f == NULL) || (node == NULL) || (e == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((f->id <= C4G_CO_COB_EMCY) || (f->id > 0x0FFU) || (f->rtr != 0U)) {
        st = C4G_ERR_ARG;
    } else if (f->dlc != 8U) {
        st = C4G_ERR_LENGTH;
    } else {
        uint32_t i;
        *node = (uint8_t)(f->id - C4G_CO_COB_EMCY);
        e->t_ns = f->t_ns;
        e->code = (uint16_t)c4g_get_le(f->data, 2U);
        e->reg = f->data[2];
        for (i = 0U; i < 5U; i++) {
            e->mfr[i] = f->data[3U + i];
        }
    }
    return st;
}

c4g_status_t c4g_co_pdo_length(const c4g_co_pdo_map_t *map, uint8_t *bytes)
{
    c4g_status_t st = C4G_OK;
    if ((map == NULL) || (bytes == NULL)) {
        st = C4G_ERR_NULL;
    } else if (map->n > C4G_CO_MAX_ENTRIES) {
        st = C4G_ERR_RANGE;
    } else {
        uint32_t total = 0U;
        uint32_t i;
        for (i = 0U; (i < map->n) && (st == C4G_OK); i++) {
            const uint32_t bits = map->entry[i] & 0xFFU;
            if ((bits != 8U) && (bits != 16U) && (bits != 32U)) {
                st = C4G_ERR_RANGE;
            }
            total += bits;
        }
        if ((st == C4G_OK) && (total > 64U)) {
            st = C4G_ERR_LENGTH;
        }
        if (st == C4G_OK) {
            *bytes = (uint8_t)(total / 8U);
        }
    }
    return st;
}

c4g_status_t c4g_co_pdo_pack(const c4g_co_pdo_map_t *map, uint16_t cob, const uint32_t *vals,
                             c4g_co_frame_t *f)
{
    uint8_t len = 0U;
    c4g_status_t st = c4g_co_pdo_length(map, &len);
    if ((vals == NULL) || (f == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((st == C4G_OK) && (cob > 0x7FFU)) {
        st = C4G_ERR_ARG;
    } else if (st == C4G_OK) {
        uint32_t off = 0U;
        uint32_t i;
        c4g_co_frame_clear(f, cob, len);
        for (i = 0U; i < map->n; i++) {
            const uint32_t b = (map->entry[i] & 0xFFU) / 8U;
            c4g_put_le(&f->data[off], vals[i], b);
            off += b;
        }
    } else {
        /* st from c4g_co_pdo_length */
    }
    return st;
}

c4g_status_t c4g_co_pdo_unpack(const c4g_co_pdo_map_t *map, const c4g_co_frame_t *f,
                               uint32_t *vals)
{
    uint8_t len = 0U;
    c4g_status_t st = c4g_co_pdo_length(map, &len);
    if ((vals == NULL) || (f == NULL)) {
        st = C4G_ERR_NULL;
    } else if ((st == C4G_OK) && ((f->dlc != len) || (f->rtr != 0U))) {
        st = C4G_ERR_LENGTH;
    } else if (st == C4G_OK) {
        uint32_t off = 0U;
        uint32_t i;
        for (i = 0U; i < map->n; i++) {
            const uint32_t b = (map->entry[i] & 0xFFU) / 8U;
            vals[i] = c4g_get_le(&f->data[off], b);
            off += b;
        }
    } else {
        /* st from c4g_co_pdo_length */
    }
    return st;
}
