/* SPDX-License-Identifier: MIT */
/* Cyclic packet codec (both directions), the wire's words, per-arm bytes, neutral reply. */
#include "../c4g_internal.h"
#include "c4g_wire_hot.h"

uint32_t c4g_le_u32(const uint8_t *p)
{
    return c4g_get_u32le(p);
}

int32_t c4g_le_i32(const uint8_t *p)
{
    return c4g_get_i32le(p);
}

float c4g_le_f32(const uint8_t *p)
{
    return c4g_f32_from_bits(c4g_get_u32le(p));
}

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

/* One axis on the wire: SM + D1..D5 + EXT1..EXT3. The raw helpers take one pointer or
 * value per field so that, inlined, they compile to straight loads and stores for both
 * packet directions (one implementation, two typed structs). */

/* 1 if the float with these bits is NaN or infinite (see c4g_exp_carry). */
static inline uint32_t nonfinite(uint32_t bits)
{
    return c4g_exp_carry(bits) >> 31U;
}

/* Slow path, only on error (unknown mode or NaN/inf): name the field in the diagnostic. */
static c4g_status_t axis_error(int32_t mode, const uint8_t *p, uint32_t index, c4g_diag_t *diag)
{
    static const c4g_field_t float_field[AXIS_FLOATS] = {
        C4G_FIELD_D1, C4G_FIELD_D2, C4G_FIELD_D3, C4G_FIELD_D4,
        C4G_FIELD_D5, C4G_FIELD_EXT1, C4G_FIELD_EXT2, C4G_FIELD_EXT3};
    const uint32_t base = C4G_HEADER_SIZE + (index * C4G_AXIS_SIZE);
    c4g_status_t st;
    if (!c4g_mode_is_known(mode)) {
        st = C4G_ERR_MODE;
        c4g_diag_set(diag, st, C4G_FIELD_SM, base, -1, (int32_t)index, (int64_t)mode);
    } else {
        uint32_t k = 0U;
        while ((k < (AXIS_FLOATS - 1U)) &&
               (nonfinite(c4g_get_u32le(&p[4U + (4U * k)])) == 0U)) {
            k++;
        }
        st = C4G_ERR_NONFINITE;
        c4g_diag_set(diag, st, float_field[k], base + 4U + (4U * k), -1, (int32_t)index,
                     (int64_t)c4g_get_u32le(&p[4U + (4U * k)]));
    }
    return st;
}

/* The first bad axis of a datagram the bulk check refused, named from its wire bytes. */
static c4g_status_t first_bad_axis(const uint8_t *buf, uint32_t n, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint32_t i;
    for (i = 0U; (i < n) && (st == C4G_OK); i++) {
        const uint8_t *p = &buf[C4G_CYCLIC_SIZE(i)];
        const int32_t mode = c4g_get_i32le(p);
        uint32_t carry = 0U;
        uint32_t k;
        for (k = 1U; k <= AXIS_FLOATS; k++) {
            carry |= c4g_exp_carry(c4g_get_u32le(&p[(size_t)k * 4U]));
        }
        if (((carry & 0x80000000U) != 0U) || (!c4g_mode_is_known(mode))) {
            st = axis_error(mode, p, i, diag);
        }
    }
    return st;
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

/* The axes of a datagram whose header decoded: one copy into host order, one check of the
 * copy; the axes past @p n zero (deterministic output, and the bulk check reads up to three
 * words of them). */
static c4g_status_t decode_axes(const uint8_t *buf, uint32_t n, uint8_t *ax, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint32_t mixed;
    (void)memset(&ax[(size_t)n * C4G_AXIS_SIZE], 0, ((size_t)C4G_MAX_AXES - (size_t)n) * C4G_AXIS_SIZE);
    c4g_words_le(ax, &buf[C4G_HEADER_SIZE], (size_t)n * C4G_AXIS_WORDS, c4g_host_big_endian());
    if (axes_bad(ax, n, 1U, &mixed) != 0U) {
        st = first_bad_axis(buf, n, diag);
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
        out->n_axes = 0U;
        st = decode_header(buf, len, n_axes, &out->num, &out->infpar, &out->cmd, &n, diag);
        if (st == C4G_OK) {
            st = decode_axes(buf, n, (uint8_t *)out->ax, diag);
        }
        if (st == C4G_OK) {
            out->n_axes = n;
        } else {
            (void)memset(out, 0, sizeof *out);
        }
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
        out->n_axes = 0U;
        st = decode_header(buf, len, n_axes, &out->num, &out->infpar, &out->cmd, &n, diag);
        if (st == C4G_OK) {
            st = decode_axes(buf, n, (uint8_t *)out->ax, diag);
        }
        if (st == C4G_OK) {
            out->n_axes = n;
        } else {
            (void)memset(out, 0, sizeof *out);
        }
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

/* Why the axes were refused: the first axis with an unknown mode or a NaN/inf decides. */
static c4g_status_t encode_refusal(const uint8_t *ax, uint32_t n)
{
    c4g_status_t st = C4G_OK;
    uint32_t i;
    for (i = 0U; (i < n) && (st == C4G_OK); i++) {
        const uint8_t *p = &ax[(size_t)i * C4G_AXIS_SIZE];
        if (!c4g_mode_is_known(c4g_host_i32_at(p))) {
            st = C4G_ERR_MODE;
        } else if (c4g_words_carry(&p[4], AXIS_FLOATS) != 0U) {
            st = C4G_ERR_NONFINITE;
        } else {
            /* a good axis */
        }
    }
    return st;
}

/* The axes after a written header: checked in one pass (nothing past the axes is read: the
 * rest of the caller's struct may be uninitialised), then one copy to the wire. A failed
 * encode must not leave a half-written packet that someone might send: the header
 * (cap >= 48 was checked) is zeroed, so the bytes are not a valid packet. */
static c4g_status_t encode_axes(const uint8_t *ax, uint32_t n, uint8_t *buf)
{
    c4g_status_t st = C4G_OK;
    uint32_t mixed;
    if (axes_bad(ax, n, 0U, &mixed) != 0U) {
        st = encode_refusal(ax, n);
    }
    if (st != C4G_OK) {
        (void)memset(buf, 0, C4G_HEADER_SIZE);
    } else {
        c4g_words_le(&buf[C4G_HEADER_SIZE], ax, (size_t)n * C4G_AXIS_WORDS,
                     c4g_host_big_endian());
    }
    return st;
}

c4g_status_t c4g_ctrl_encode(const c4g_ctrl_packet_t *pkt, uint8_t *buf, size_t cap,
                             size_t *out_len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((pkt != NULL) && (buf != NULL) && (out_len != NULL)) {
        *out_len = 0U;
        st = encode_header(pkt->num, pkt->infpar, pkt->cmd, pkt->n_axes, buf, cap);
        if (st == C4G_OK) {
            st = encode_axes((const uint8_t *)pkt->ax, pkt->n_axes, buf);
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
        *out_len = 0U;
        st = encode_header(pkt->num, pkt->infpar, pkt->cmd, pkt->n_axes, buf, cap);
        if (st == C4G_OK) {
            st = encode_axes((const uint8_t *)pkt->ax, pkt->n_axes, buf);
        }
        if (st == C4G_OK) {
            *out_len = C4G_CYCLIC_SIZE(pkt->n_axes);
        }
    }
    return st;
}

/* One axis of the neutral reply, mode @p r->mode with rules @p rules: it holds. */
static void neutral_axis(const c4g_ctrl_axis_t *r, uint32_t rules, c4g_pc_axis_t *a)
{
    a->mode = r->mode;
    if (r->mode == C4G_MODE_0_DEBUG) {
        /* Mode 0': the field library copies D1..D5 back unchanged. */
        a->target_pos = r->target_pos;
        a->target_vel = r->target_vel;
        a->measure = r->actual_pos;
        a->vel_add = r->actual_vel;
        a->current_add = r->current_ref;
    } else {
        /* hold: the reference and the current the controller applied (a zero there would
         * mean "go to 0", "no current"), nothing added */
        if ((rules & C4G_MR_ABS) != 0U) {
            a->target_pos = r->target_pos;
        }
        if ((rules & C4G_MR_CUR) != 0U) {
            a->current_add = r->current_ref;
        }
    }
}

c4g_status_t c4g_pc_reply_neutral(const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((rx != NULL) && (tx != NULL)) {
        st = C4G_ERR_AXES;
        if ((rx->n_axes >= 1U) && (rx->n_axes <= C4G_MAX_AXES)) {
            int32_t looked_up = C4G_MODE_0;
            uint32_t rules = 0U; /* of mode 0 */
            uint32_t i;
            tx->num = rx->num;
            tx->infpar = 0U;
            tx->cmd = 0U;
            tx->n_axes = rx->n_axes;
            (void)memset(tx->ax, 0, sizeof tx->ax);
            for (i = 0U; i < rx->n_axes; i++) {
                if (rx->ax[i].mode != looked_up) { /* the axes of an arm mostly share one mode */
                    looked_up = rx->ax[i].mode;
                    rules = c4g_mode_rules(looked_up);
                }
                neutral_axis(&rx->ax[i], rules, &tx->ax[i]);
            }
            st = C4G_OK;
        }
    }
    return st;
}
