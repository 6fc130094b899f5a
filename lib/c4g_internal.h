/* SPDX-License-Identifier: MIT */
/* Internal helpers: explicit little-endian access (never cast a buffer onto a struct). */
#ifndef C4G_INTERNAL_H
#define C4G_INTERNAL_H

#include "c4gopen.h"
#include <string.h>

/* Functions shared between the library's own files: hidden from the shared object, and
 * localised in the static archive (one relocatable object, see the Makefile), so a program
 * links only what the public headers declare. */
#if defined(__GNUC__)
#define C4G_INTERNAL __attribute__((visibility("hidden")))
#else
#define C4G_INTERNAL
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

/* The one little-endian helper set of the library: the wire's 32-bit words below, and
 * words of 1..4 bytes (CANopen's object dictionary) here. */
/* NUM distance from @p from to @p to modulo 2^15 (0..0x7FFF), inline for the per-datagram
 * path; c4g_num_delta is the public form. Unsigned arithmetic: either value may be a raw,
 * unvalidated field, and 2^32 is a multiple of the modulus. */
static inline int32_t c4g_num_wrap_delta(int32_t from, int32_t to)
{
    const uint32_t d = ((uint32_t)to - (uint32_t)from) & ((uint32_t)C4G_NUM_MODULO - 1U);
    return (int32_t)d;
}

/* The reply NUM of @p num under @p policy (c4g_reply_num, inline for the per-tick reply). */
static inline int32_t c4g_reply_num_inline(int32_t num, c4g_num_policy_t policy)
{
    int32_t r = num;
    if (policy == C4G_NUM_PLUS_ONE) {
        /* Field library: NUM + 1, 0x7FFF wraps to 1 (never 0). */
        r = ((num >= C4G_NUM_MAX) || (num < 0)) ? 1 : (num + 1);
    }
    return r;
}

static inline void c4g_put_le(uint8_t *p, uint32_t v, uint32_t bytes)
{
    uint32_t i;
    for (i = 0U; i < bytes; i++) {
        p[i] = (uint8_t)((v >> (8U * i)) & 0xFFU);
    }
}

static inline uint32_t c4g_get_le(const uint8_t *p, uint32_t bytes)
{
    uint32_t v = 0U;
    uint32_t i;
    for (i = 0U; i < bytes; i++) {
        v |= ((uint32_t)p[i]) << (8U * i);
    }
    return v;
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
 * values branch-free (the hot paths in lib/wire/c4g_codec.c and the engine do that). */
static inline uint32_t c4g_exp_carry(uint32_t bits)
{
    return (bits & 0x7F800000U) + 0x00800000U;
}

static inline int c4g_f32_finite(float f)
{
    return ((c4g_exp_carry(c4g_f32_bits(f)) & 0x80000000U) == 0U) ? 1 : 0;
}

/* ---- bulk wire words: the per-tick codec copies and checks whole packets, not fields */

/* Words of one cyclic axis on the wire and in c4g_ctrl_axis_t / c4g_pc_axis_t: SM, D1..D5,
 * EXT1..EXT3, 4 bytes each, no padding (every member is 4 bytes; tests/test_codec.c checks the
 * sizes), in wire order. */
#define C4G_AXIS_WORDS 9U

/* 1 when the host stores a uint32_t most significant byte first. Compilers fold it to a
 * constant, so the byte reversal below costs nothing on a little-endian host. */
static inline uint32_t c4g_host_big_endian(void)
{
    const uint32_t probe = 0x01020304U;
    uint8_t b[4];
    /* Deviation D-02 (MISRA 21.15): the bytes of a word, bit-exact. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(b, &probe, sizeof b);
    return (b[0] == 0x01U) ? 1U : 0U;
}

/* Copy @p nwords 4-byte words between the little-endian wire and host order (the same
 * operation both ways): one memcpy, then, when @p swap is set (a big-endian host), every
 * word's bytes reversed in place. */
static inline void c4g_words_le(uint8_t *dst, const uint8_t *src, size_t nwords, uint32_t swap)
{
    const size_t n = nwords * 4U;
    (void)memcpy(dst, src, n);
    if (swap != 0U) {
        size_t k;
        for (k = 0U; k < n; k += 4U) {
            const uint8_t b0 = dst[k];
            const uint8_t b1 = dst[k + 1U];
            dst[k] = dst[k + 3U];
            dst[k + 1U] = dst[k + 2U];
            dst[k + 2U] = b1;
            dst[k + 3U] = b0;
        }
    }
}

/* One host-order word of a struct seen as bytes (@p p: 4 readable bytes). */
static inline uint32_t c4g_word_at(const uint8_t *p)
{
    uint32_t u;
    /* Deviation D-02 (MISRA 21.15): bit-exact reinterpretation, same size. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&u, p, sizeof u);
    return u;
}

/* One host-order int32_t of a struct seen as bytes. */
static inline int32_t c4g_host_i32_at(const uint8_t *p)
{
    int32_t r;
    /* Deviation D-02 (MISRA 21.15): bit-exact reinterpretation, same size. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&r, p, sizeof r);
    return r;
}

/* Bit 31 set iff one of @p nwords host-order words (bytes @p p) has an all-ones float
 * exponent (NaN/infinity; see c4g_exp_carry). Used off the hot path (one axis, a diagnostic). */
static inline uint32_t c4g_words_carry(const uint8_t *p, size_t nwords)
{
    uint32_t a = 0U;
    size_t k;
    for (k = 0U; k < nwords; k++) {
        a |= c4g_exp_carry(c4g_word_at(&p[k * 4U]));
    }
    return a & 0x80000000U;
}

/* The exponent carry (c4g_exp_carry) of two host-order words at once: the masked low word
 * plus one exponent LSB ends at bit 31 at most, so it never carries into the high word. */
#define C4G_EXP_MASK2 0x7F8000007F800000ULL
#define C4G_EXP_LSB2 0x0080000000800000ULL
#define C4G_SIGN_BITS2 0x8000000080000000ULL

/* One 8-byte lane of a struct seen as bytes. */
static inline uint64_t c4g_lane_at(const uint8_t *p)
{
    uint64_t u;
    /* Deviation D-02 (MISRA 21.15): bit-exact reinterpretation, same size. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&u, p, sizeof u);
    return u;
}

/* The exponent carries of the two words of the 8-byte lane at @p p (see C4G_EXP_MASK2). */
static inline uint64_t c4g_lane_carry(const uint8_t *p)
{
    return (c4g_lane_at(p) & C4G_EXP_MASK2) + C4G_EXP_LSB2;
}

/* Nonzero if a word of the axis array @p ax (host order, C4G_MAX_AXES axes) among the first
 * @p nwords has an all-ones exponent. With @p round_up set the check reads whole 16-byte
 * quads (never past the array: it holds 180 words, a multiple of 4), so up to three words
 * past @p nwords take part: for arrays whose words past the axes are zero (a session's own
 * buffers, a decoder's output). Without it the last words are read one by one and nothing
 * past @p nwords is read (a caller's struct, whose other words may be uninitialised).
 * 64 bytes per step into four independent 64-bit lanes: compilers turn them into vector
 * operations without intrinsics, and the final reduction is two lanes, not eight. */
static inline uint64_t c4g_axes_carry(const uint8_t *ax, size_t nwords, uint32_t round_up)
{
    const size_t quads = (round_up != 0U) ? ((nwords + 3U) / 4U) : (nwords / 4U);
    const size_t steps = quads / 4U;
    const uint8_t *q = ax;
    uint64_t a0 = 0U;
    uint64_t a1 = 0U;
    uint64_t a2 = 0U;
    uint64_t a3 = 0U;
    size_t g;
    for (g = 0U; g < steps; g++) {
        a0 |= c4g_lane_carry(q) | c4g_lane_carry(&q[32]);
        a1 |= c4g_lane_carry(&q[8]) | c4g_lane_carry(&q[40]);
        a2 |= c4g_lane_carry(&q[16]) | c4g_lane_carry(&q[48]);
        a3 |= c4g_lane_carry(&q[24]) | c4g_lane_carry(&q[56]);
        q = &q[64];
    }
    if ((quads & 2U) != 0U) {
        a0 |= c4g_lane_carry(q);
        a1 |= c4g_lane_carry(&q[8]);
        a2 |= c4g_lane_carry(&q[16]);
        a3 |= c4g_lane_carry(&q[24]);
        q = &q[32];
    }
    if ((quads & 1U) != 0U) {
        a0 |= c4g_lane_carry(q);
        a1 |= c4g_lane_carry(&q[8]);
    }
    if (round_up == 0U) {
        size_t k;
        for (k = quads * 4U; k < nwords; k++) {
            a2 |= (uint64_t)c4g_exp_carry(c4g_word_at(&ax[k * 4U]));
        }
    }
    return (a0 | a1 | a2 | a3) & C4G_SIGN_BITS2;
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

/* c4g_init_decode that also returns the packet's axis maps (as c4g_axis_map_build builds
 * them; valid when C4G_OK): the session's decode of an initialization packet, one pass. */
C4G_INTERNAL c4g_status_t c4g_init_decode_map(const uint8_t *buf, size_t len, c4g_init_t *out,
                                              c4g_axis_map_t *map, c4g_diag_t *diag);

/* c4g_engine_step for a packet c4g_ctrl_decode produced (the loop object's path): the
 * decoder checked every value and mode of it, so the step does not check them again. */
C4G_INTERNAL c4g_status_t c4g_engine_step_decoded(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                     uint64_t now_ns, c4g_pc_packet_t *tx,
                                     c4g_engine_report_t *rep);

#endif /* C4G_INTERNAL_H */
