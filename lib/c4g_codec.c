/* SPDX-License-Identifier: MIT */
/* Cyclic packet codec (both directions), per-arm bytes, reply NUM, neutral reply. */
#include "c4g_internal.h"

#define AXIS_FLOATS 8U

/* Place value of each arm's byte: multiplication instead of a variable shift. */
static const uint32_t arm_place[C4G_ARMS] = {0x1U, 0x100U, 0x10000U, 0x1000000U};

uint8_t c4g_arm_byte(uint32_t word, uint32_t arm)
{
    uint8_t b = 0U;
    if (arm < C4G_ARMS) {
        const uint32_t shifted = word / arm_place[arm];
        b = (uint8_t)(shifted & 0xFFU);
    }
    return b;
}

uint32_t c4g_arm_byte_set(uint32_t word, uint32_t arm, uint8_t value)
{
    uint32_t w = word;
    if (arm < C4G_ARMS) {
        const uint32_t place = arm_place[arm];
        w = (w & ~(0xFFU * place)) | ((uint32_t)value * place);
    }
    return w;
}

int c4g_mode_is_known(int32_t mode)
{
    int known;
    switch (mode) {
    case C4G_MODE_0: case C4G_MODE_0_DEBUG: case C4G_MODE_1: case C4G_MODE_1_STANDBY:
    case C4G_MODE_2: case C4G_MODE_2_STANDBY: case C4G_MODE_3: case C4G_MODE_4:
    case C4G_MODE_4_STANDBY: case C4G_MODE_5: case C4G_MODE_5_STANDBY: case C4G_MODE_6:
    case C4G_MODE_7: case C4G_MODE_7_STANDBY: case C4G_MODE_7_STANDBY_EXIT: case C4G_MODE_8:
    case C4G_MODE_9: case C4G_MODE_101: case C4G_MODE_102: case C4G_MODE_103:
    case C4G_MODE_201: case C4G_MODE_202: case C4G_MODE_FREEZING_A: case C4G_MODE_DRIVING_ON:
    case C4G_MODE_FREEZING_P_IN: case C4G_MODE_FREEZING_P_OUT: case C4G_MODE_EXIT_OPEN:
    case C4G_MODE_DRIVE_OFF: case C4G_MODE_SVR_RESTART: case C4G_MODE_FOLLOW_ERROR:
        known = 1;
        break;
    default:
        known = 0;
        break;
    }
    return known;
}

int32_t c4g_reply_num(int32_t num, c4g_num_policy_t policy)
{
    int32_t r = num;
    if (policy == C4G_NUM_PLUS_ONE) {
        /* Field library: NUM + 1, 0x7FFF wraps to 1 (never 0). */
        r = ((num >= C4G_NUM_MAX) || (num < 0)) ? 1 : (num + 1);
    }
    return r;
}

/* Axis count implied by a datagram length, 0 if no valid count fits. */
static uint32_t axes_for_length(size_t len)
{
    uint32_t n = 0U;
    if ((len >= C4G_CYCLIC_SIZE(1U)) && (len <= C4G_MAX_CYCLIC_SIZE) &&
        (((len - C4G_HEADER_SIZE) % C4G_AXIS_SIZE) == 0U)) {
        n = (uint32_t)((len - C4G_HEADER_SIZE) / C4G_AXIS_SIZE);
    }
    return n;
}

static c4g_status_t check_length(size_t len, uint32_t n_axes, uint32_t *n_out, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint32_t n = n_axes;
    if (n_axes > C4G_MAX_AXES) {
        st = C4G_ERR_AXES;
        c4g_diag_set(diag, st, C4G_FIELD_LENGTH, 0U, -1, -1, (int64_t)n_axes);
    } else {
        if (n == 0U) {
            n = axes_for_length(len);
        }
        if ((n == 0U) || (len != C4G_CYCLIC_SIZE(n))) {
            st = C4G_ERR_LENGTH;
            c4g_diag_set(diag, st, C4G_FIELD_LENGTH, 0U, -1, -1, (int64_t)len);
        }
    }
    *n_out = n;
    return st;
}

static c4g_status_t check_num(int32_t num, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    if ((num < 0) || (num > C4G_NUM_MAX)) {
        st = C4G_ERR_NUM;
        c4g_diag_set(diag, st, C4G_FIELD_NUM, 0U, -1, -1, (int64_t)num);
    }
    return st;
}

/* Decode one axis: mode + 8 floats, validated; fields[] point into the typed struct. */
static c4g_status_t decode_axis(const uint8_t *p, uint32_t index, int32_t *mode,
                                float *const fields[AXIS_FLOATS], c4g_diag_t *diag)
{
    static const c4g_field_t float_field[AXIS_FLOATS] = {
        C4G_FIELD_D1, C4G_FIELD_D2, C4G_FIELD_D3, C4G_FIELD_D4,
        C4G_FIELD_D5, C4G_FIELD_EXT1, C4G_FIELD_EXT2, C4G_FIELD_EXT3};
    c4g_status_t st = C4G_OK;
    const uint32_t base = C4G_HEADER_SIZE + (index * C4G_AXIS_SIZE);
    uint32_t k;
    *mode = c4g_get_i32le(p);
    if (c4g_mode_is_known(*mode) == 0) {
        st = C4G_ERR_MODE;
        c4g_diag_set(diag, st, C4G_FIELD_SM, base, -1, (int32_t)index, (int64_t)*mode);
    }
    for (k = 0U; (k < AXIS_FLOATS) && (st == C4G_OK); k++) {
        const float f = c4g_get_f32le(&p[4U + (4U * k)]);
        if (c4g_f32_finite(f) == 0) {
            st = C4G_ERR_NONFINITE;
            c4g_diag_set(diag, st, float_field[k], base + 4U + (4U * k),
                         -1, (int32_t)index, (int64_t)c4g_f32_bits(f));
        } else {
            *fields[k] = f;
        }
    }
    return st;
}

static c4g_status_t encode_axis(uint8_t *p, uint32_t index, int32_t mode,
                                const float *const fields[AXIS_FLOATS])
{
    c4g_status_t st = C4G_OK;
    uint32_t k;
    (void)index;
    if (c4g_mode_is_known(mode) == 0) {
        st = C4G_ERR_MODE;
    }
    for (k = 0U; (k < AXIS_FLOATS) && (st == C4G_OK); k++) {
        if (c4g_f32_finite(*fields[k]) == 0) {
            st = C4G_ERR_NONFINITE;
        } else {
            c4g_put_f32le(&p[4U + (4U * k)], *fields[k]);
        }
    }
    if (st == C4G_OK) {
        c4g_put_i32le(p, mode);
    }
    return st;
}

static void ctrl_fields(c4g_ctrl_axis_t *a, float *f[AXIS_FLOATS])
{
    f[0] = &a->target_pos;
    f[1] = &a->target_vel;
    f[2] = &a->actual_pos;
    f[3] = &a->actual_vel;
    f[4] = &a->current_ref;
    f[5] = &a->ext[0];
    f[6] = &a->ext[1];
    f[7] = &a->ext[2];
}

static void pc_fields(c4g_pc_axis_t *a, float *f[AXIS_FLOATS])
{
    f[0] = &a->target_pos;
    f[1] = &a->target_vel;
    f[2] = &a->measure;
    f[3] = &a->vel_add;
    f[4] = &a->current_add;
    f[5] = &a->ext[0];
    f[6] = &a->ext[1];
    f[7] = &a->ext[2];
}

static void ctrl_fields_const(const c4g_ctrl_axis_t *a, const float *f[AXIS_FLOATS])
{
    f[0] = &a->target_pos;
    f[1] = &a->target_vel;
    f[2] = &a->actual_pos;
    f[3] = &a->actual_vel;
    f[4] = &a->current_ref;
    f[5] = &a->ext[0];
    f[6] = &a->ext[1];
    f[7] = &a->ext[2];
}

static void pc_fields_const(const c4g_pc_axis_t *a, const float *f[AXIS_FLOATS])
{
    f[0] = &a->target_pos;
    f[1] = &a->target_vel;
    f[2] = &a->measure;
    f[3] = &a->vel_add;
    f[4] = &a->current_add;
    f[5] = &a->ext[0];
    f[6] = &a->ext[1];
    f[7] = &a->ext[2];
}

static c4g_status_t decode_header(const uint8_t *buf, size_t len, uint32_t n_axes, int32_t *num,
                                  uint32_t *infpar, uint32_t *cmd, uint32_t *n_out,
                                  c4g_diag_t *diag)
{
    c4g_status_t st = check_length(len, n_axes, n_out, diag);
    if (st == C4G_OK) {
        *num = c4g_get_i32le(buf);
        *infpar = c4g_get_u32le(&buf[4]);
        *cmd = c4g_get_u32le(&buf[8]);
        st = check_num(*num, diag);
    }
    return st;
}

c4g_status_t c4g_ctrl_decode(const uint8_t *buf, size_t len, uint32_t n_axes,
                             c4g_ctrl_packet_t *out, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_ERR_NULL;
    c4g_diag_set(diag, C4G_OK, C4G_FIELD_NONE, 0U, -1, -1, 0);
    if ((buf != NULL) && (out != NULL)) {
        uint32_t n = 0U;
        uint32_t i;
        (void)memset(out, 0, sizeof *out);
        st = decode_header(buf, len, n_axes, &out->num, &out->infpar, &out->cmd, &n, diag);
        for (i = 0U; (i < n) && (st == C4G_OK); i++) {
            float *f[AXIS_FLOATS];
            ctrl_fields(&out->ax[i], f);
            st = decode_axis(&buf[C4G_CYCLIC_SIZE(i)], i, &out->ax[i].mode, f, diag);
        }
        out->n_axes = (st == C4G_OK) ? n : 0U;
    } else {
        c4g_diag_set(diag, st, C4G_FIELD_NONE, 0U, -1, -1, 0);
    }
    return st;
}

c4g_status_t c4g_pc_decode(const uint8_t *buf, size_t len, uint32_t n_axes,
                           c4g_pc_packet_t *out, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_ERR_NULL;
    c4g_diag_set(diag, C4G_OK, C4G_FIELD_NONE, 0U, -1, -1, 0);
    if ((buf != NULL) && (out != NULL)) {
        uint32_t n = 0U;
        uint32_t i;
        (void)memset(out, 0, sizeof *out);
        st = decode_header(buf, len, n_axes, &out->num, &out->infpar, &out->cmd, &n, diag);
        for (i = 0U; (i < n) && (st == C4G_OK); i++) {
            float *f[AXIS_FLOATS];
            pc_fields(&out->ax[i], f);
            st = decode_axis(&buf[C4G_CYCLIC_SIZE(i)], i, &out->ax[i].mode, f, diag);
        }
        out->n_axes = (st == C4G_OK) ? n : 0U;
    } else {
        c4g_diag_set(diag, st, C4G_FIELD_NONE, 0U, -1, -1, 0);
    }
    return st;
}

static c4g_status_t encode_header(int32_t num, uint32_t infpar, uint32_t cmd, uint32_t n,
                                  uint8_t *buf, size_t cap)
{
    c4g_status_t st = C4G_OK;
    if ((n == 0U) || (n > C4G_MAX_AXES)) {
        st = C4G_ERR_AXES;
    } else if ((num < 0) || (num > C4G_NUM_MAX)) {
        st = C4G_ERR_NUM;
    } else if (cap < C4G_CYCLIC_SIZE(n)) {
        st = C4G_ERR_CAPACITY;
    } else {
        c4g_put_i32le(buf, num);
        c4g_put_u32le(&buf[4], infpar);
        c4g_put_u32le(&buf[8], cmd);
    }
    return st;
}

c4g_status_t c4g_ctrl_encode(const c4g_ctrl_packet_t *pkt, uint8_t *buf, size_t cap,
                             size_t *out_len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((pkt != NULL) && (buf != NULL) && (out_len != NULL)) {
        uint32_t i;
        *out_len = 0U;
        st = encode_header(pkt->num, pkt->infpar, pkt->cmd, pkt->n_axes, buf, cap);
        for (i = 0U; (i < pkt->n_axes) && (st == C4G_OK); i++) {
            const float *f[AXIS_FLOATS];
            ctrl_fields_const(&pkt->ax[i], f);
            st = encode_axis(&buf[C4G_CYCLIC_SIZE(i)], i, pkt->ax[i].mode, f);
        }
        if (st == C4G_OK) {
            *out_len = C4G_CYCLIC_SIZE(pkt->n_axes);
        }
    }
    return st;
}

c4g_status_t c4g_pc_encode(const c4g_pc_packet_t *pkt, uint8_t *buf, size_t cap,
                           size_t *out_len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((pkt != NULL) && (buf != NULL) && (out_len != NULL)) {
        uint32_t i;
        *out_len = 0U;
        st = encode_header(pkt->num, pkt->infpar, pkt->cmd, pkt->n_axes, buf, cap);
        for (i = 0U; (i < pkt->n_axes) && (st == C4G_OK); i++) {
            const float *f[AXIS_FLOATS];
            pc_fields_const(&pkt->ax[i], f);
            st = encode_axis(&buf[C4G_CYCLIC_SIZE(i)], i, pkt->ax[i].mode, f);
        }
        if (st == C4G_OK) {
            *out_len = C4G_CYCLIC_SIZE(pkt->n_axes);
        }
    }
    return st;
}

c4g_status_t c4g_pc_reply_neutral(const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((rx != NULL) && (tx != NULL)) {
        st = C4G_ERR_AXES;
        if ((rx->n_axes >= 1U) && (rx->n_axes <= C4G_MAX_AXES)) {
            uint32_t i;
            (void)memset(tx, 0, sizeof *tx);
            tx->num = rx->num;
            tx->n_axes = rx->n_axes;
            for (i = 0U; i < rx->n_axes; i++) {
                tx->ax[i].mode = rx->ax[i].mode;
                if (rx->ax[i].mode == C4G_MODE_0_DEBUG) {
                    /* Mode 0': the field library copies D1..D5 back unchanged. */
                    tx->ax[i].target_pos = rx->ax[i].target_pos;
                    tx->ax[i].target_vel = rx->ax[i].target_vel;
                    tx->ax[i].measure = rx->ax[i].actual_pos;
                    tx->ax[i].vel_add = rx->ax[i].actual_vel;
                    tx->ax[i].current_add = rx->ax[i].current_ref;
                }
            }
            st = C4G_OK;
        }
    }
    return st;
}
