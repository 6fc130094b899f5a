/* SPDX-License-Identifier: MIT */
/* The per-tick checks of a cyclic packet, inlined where a packet is decoded or encoded. */
#ifndef C4G_WIRE_HOT_H
#define C4G_WIRE_HOT_H

#include "../c4g_internal.h"

/* Modes 0..17 that exist, as a bit set derived from the mode table: the hot path avoids
 * the full lookup. */
#define LOW_MODES_LIMIT 18
#define LOW_MODE_BIT_(id, code, flags, fields, rules, op, from, name, text) \
    | (((code) < LOW_MODES_LIMIT) ? (1U << ((uint32_t)(code) % 18U)) : 0U)
#define LOW_MODES_MASK (0U C4G_MODE_TABLE(LOW_MODE_BIT_))

static inline uint32_t mode_unknown_fast(int32_t mode)
{
    uint32_t unknown = 0U;
    if ((mode >= 0) && (mode < LOW_MODES_LIMIT)) {
        /* Deviation D-05 (MISRA 12.2): the mask's shift counts are code % 18, below 32. */
        /* cppcheck-suppress misra-c2012-12.2 */
        const uint32_t shifted = LOW_MODES_MASK >> (uint32_t)mode;
        unknown = (shifted & 1U) ^ 1U;
    } else if (!c4g_mode_is_known(mode)) {
        unknown = 1U;
    } else {
        /* a known mode above 17 */
    }
    return unknown;
}

/* 1 if some of the @p n axes (bytes @p ax, host order) carries an unknown mode; *mixed = 1
 * when they do not all carry the first axis's mode. A packet usually carries one mode on
 * every axis: one pass compares them with the first, one lookup checks it; a packet of
 * several modes checks each. */
static inline uint32_t modes_unknown(const uint8_t *ax, uint32_t n, uint32_t *mixed)
{
    const int32_t first = c4g_host_i32_at(ax);
    const uint8_t *const end = &ax[(size_t)n * C4G_AXIS_SIZE];
    const uint8_t *m;
    uint32_t diff = 0U;
    uint32_t u;
    /* two axes a step: the loads are independent, the loop overhead halves */
    for (m = &ax[C4G_AXIS_SIZE]; &m[C4G_AXIS_SIZE] < end; m = &m[(size_t)2U * C4G_AXIS_SIZE]) {
        diff |= ((uint32_t)c4g_host_i32_at(m) ^ (uint32_t)first) |
                ((uint32_t)c4g_host_i32_at(&m[C4G_AXIS_SIZE]) ^ (uint32_t)first);
    }
    if (m < end) {
        diff |= (uint32_t)c4g_host_i32_at(m) ^ (uint32_t)first;
    }
    u = mode_unknown_fast(first);
    *mixed = 0U;
    if (diff != 0U) {
        *mixed = 1U;
        for (m = &ax[C4G_AXIS_SIZE]; m < end; m = &m[C4G_AXIS_SIZE]) {
            u |= mode_unknown_fast(c4g_host_i32_at(m));
        }
    }
    return u;
}

/* 1 if the @p n axes (bytes @p ax, host order, a whole axis array) hold a NaN/inf or an
 * unknown mode: every word in one pass (a mode word with an all-ones exponent is an unknown
 * mode anyway), then the modes. @p zero_past: the words past the axes are zero, so the pass
 * may read whole quads (see c4g_axes_carry). */
static inline uint32_t axes_bad(const uint8_t *ax, uint32_t n, uint32_t zero_past,
                                uint32_t *mixed)
{
    const uint32_t modes = modes_unknown(ax, n, mixed);
    return c4g_flag((c4g_axes_carry(ax, (size_t)n * C4G_AXIS_WORDS, zero_past) != 0U) ||
                    (modes != 0U));
}

/* The hot decode of a cyclic packet of @p n axes (1..20) into a session's own buffer @p out,
 * whose axes past @p n are zero and stay so: length, NUM, every value and every mode
 * checked. 1 when accepted (*mixed = 1 when the axes carry several modes); 0 when refused,
 * with @p out partly written: the caller decodes again with c4g_ctrl_decode, which names
 * what was wrong and zeroes @p out. */
static inline uint32_t c4g_cyclic_decode_hot(const uint8_t *buf, size_t len, uint32_t n,
                                             c4g_ctrl_packet_t *out, uint32_t *mixed)
{
    uint32_t ok = 0U;
    if ((buf != NULL) && (len == C4G_CYCLIC_SIZE(n))) {
        const int32_t num = c4g_get_i32le(buf);
        if ((num >= 0) && (num <= C4G_NUM_MAX)) {
            uint8_t *ax = (uint8_t *)out->ax;
            c4g_words_le(ax, &buf[C4G_HEADER_SIZE], (size_t)n * C4G_AXIS_WORDS,
                         c4g_host_big_endian());
            if (axes_bad(ax, n, 1U, mixed) == 0U) {
                out->num = num;
                out->infpar = c4g_get_u32le(&buf[4]);
                out->cmd = c4g_get_u32le(&buf[8]);
                out->n_axes = n;
                ok = 1U;
            }
        }
    }
    return ok;
}

#endif
