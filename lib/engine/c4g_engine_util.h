/* SPDX-License-Identifier: MIT */
/* Control engine: private helpers (no libm: tiny float helpers written here). */
#ifndef C4G_ENGINE_UTIL_H
#define C4G_ENGINE_UTIL_H

#include "../c4g_internal.h"

/* Cold paths of the per-tick functions stay out of line, so that the hot loop neither grows
 * nor keeps their intermediate values alive (plain static elsewhere). */
#if defined(__GNUC__) || defined(__clang__)
#define CTL_COLD __attribute__((noinline, cold))
#else
#define CTL_COLD
#endif

/* The per-axis rules, inlined where the caller passes a mode's rules as a constant (the
 * compiler folds every rule test away). Only when optimising: an -O0 build (the coverage
 * gate's) keeps one copy of each, whose lines and branches gcov then counts once. */
#if (defined(__GNUC__) || defined(__clang__)) && defined(__OPTIMIZE__)
#define CTL_INLINE inline __attribute__((always_inline))
#else
#define CTL_INLINE inline
#endif

/* Bit 31 set iff @p f is NaN or infinite (exponent all ones carries into the sign bit):
 * OR several of these and test once. */
static inline uint32_t eng_nonfinite_bit(float f)
{
    return c4g_exp_carry(c4g_f32_bits(f)) & 0x80000000U;
}

/* Exponent carry of a float: bit 31 of the OR of these is set iff one of them is NaN or
 * infinite (the mask test of eng_nonfinite_bit, done once for several values). */
static inline uint32_t eng_exp_carry(float f)
{
    return c4g_exp_carry(c4g_f32_bits(f));
}

static inline float eng_absf(float x)
{
    return (x < 0.0F) ? -x : x;
}

/* Bits of a double, for the finite test. */
static inline int eng_f64_finite(double d)
{
    uint64_t u;
    /* Deviation D-21 (MISRA 21.15): bit-exact reinterpretation, as D-02. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&u, &d, sizeof u);
    return ((u & 0x7FF0000000000000ULL) != 0x7FF0000000000000ULL) ? 1 : 0;
}

static inline bool eng_is_unset(float f)
{
    return c4g_f32_bits(f) == C4G_UNSET_BITS;
}

static inline float eng_unset(void)
{
    const uint32_t u = C4G_UNSET_BITS;
    float f;
    /* Deviation D-21 (MISRA 21.15): bit-exact reinterpretation, as D-02. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&f, &u, sizeof f);
    return f;
}

#endif /* C4G_ENGINE_UTIL_H */
