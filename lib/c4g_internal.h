/* SPDX-License-Identifier: MIT */
/* Internal helpers: explicit little-endian access (never cast a buffer onto a struct). */
#ifndef C4G_INTERNAL_H
#define C4G_INTERNAL_H

#include "c4gopen.h"
#include <string.h>

/* Hot-path helpers that must inline for the per-tick budget (bench/bench_wire.c);
 * plain inline on compilers without the attribute. */
#if defined(__GNUC__) || defined(__clang__)
#define C4G_HOT_INLINE __attribute__((always_inline)) inline
#else
#define C4G_HOT_INLINE inline
#endif

/* A condition as a 0/1 flag word (the struct flags are uint32_t). */
static inline uint32_t c4g_flag(bool b)
{
    uint32_t r = 0U;
    if (b) {
        r = 1U;
    }
    return r;
}

static inline uint32_t c4g_get_u32le(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8U) | ((uint32_t)p[2] << 16U) |
           ((uint32_t)p[3] << 24U);
}

static inline void c4g_put_u32le(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFU);
    p[1] = (uint8_t)((v >> 8U) & 0xFFU);
    p[2] = (uint8_t)((v >> 16U) & 0xFFU);
    p[3] = (uint8_t)((v >> 24U) & 0xFFU);
}

/* Two's complement reinterpretation, well defined for every value. */
static inline int32_t c4g_get_i32le(const uint8_t *p)
{
    uint32_t u = c4g_get_u32le(p);
    int32_t r;
    /* Deviation D-02 (MISRA 21.15): bit-exact reinterpretation, same size. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&r, &u, sizeof r);
    return r;
}

static inline void c4g_put_i32le(uint8_t *p, int32_t v)
{
    uint32_t u;
    /* Deviation D-02 (MISRA 21.15): bit-exact reinterpretation, same size. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&u, &v, sizeof u);
    c4g_put_u32le(p, u);
}

static inline float c4g_f32_from_bits(uint32_t u)
{
    float f;
    /* Deviation D-02 (MISRA 21.15): bit-exact reinterpretation, same size. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&f, &u, sizeof f);
    return f;
}

static inline float c4g_get_f32le(const uint8_t *p)
{
    return c4g_f32_from_bits(c4g_get_u32le(p));
}

static inline uint32_t c4g_f32_bits(float f)
{
    uint32_t u;
    /* Deviation D-02 (MISRA 21.15): bit-exact reinterpretation, same size. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&u, &f, sizeof u);
    return u;
}

static inline void c4g_put_f32le(uint8_t *p, float f)
{
    c4g_put_u32le(p, c4g_f32_bits(f));
}

/* NaN/inf test on the bit pattern (no libm, no FP exceptions, same on every target).
 * Adding one exponent LSB to the masked exponent carries into bit 31 only when the
 * exponent is all ones, so OR-ing several carries and testing bit 31 once checks many
 * values branch-free (the hot paths in lib/c4g_codec.c and the control layer do that). */
static inline uint32_t c4g_exp_carry(uint32_t bits)
{
    return (bits & 0x7F800000U) + 0x00800000U;
}

static inline int c4g_f32_finite(float f)
{
    return ((c4g_exp_carry(c4g_f32_bits(f)) & 0x80000000U) == 0U) ? 1 : 0;
}

static inline void c4g_diag_set(c4g_diag_t *d, c4g_status_t st, c4g_field_t field,
                                uint32_t offset, int32_t arm, int32_t axis, int64_t value)
{
    if (d != NULL) {
        d->status = st;
        d->field = field;
        d->offset = offset;
        d->arm = (int16_t)arm;
        d->axis = (int16_t)axis;
        d->value = value;
    }
}

#endif /* C4G_INTERNAL_H */
