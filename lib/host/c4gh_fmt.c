/* SPDX-License-Identifier: MIT */
/* The shortest float32 text (c4gh_fmt.h). The digits come from the Schubfach method
 * (R. Giulietti, "The Schubfach way to render doubles", 2020) in its float32 form: the
 * rounding interval of the float, scaled by a power of ten picked so that it holds at most
 * one multiple of ten units (the shorter text) and at least one unit, is computed with one
 * 64 x 64-bit multiplication per bound against a table of 63-bit powers of ten (rounded
 * up, with a sticky bit: exact enough to decide every comparison the method makes, which
 * the exhaustive test in bench/fmt_exhaustive.c checks over all 2^32 floats). No division
 * and no loop over digits (nine_digits): about 200 instructions a float, where glibc's
 * %.9g takes ten times the time. */
#include "c4gh_fmt.h"

#include <stdint.h>
#include <string.h>

#define P_BITS 24            /* significand bits, the hidden one included */
#define Q_MIN (-149)         /* exponent of the smallest subnormal's unit */
#define C_MIN (1U << 23)     /* smallest normal significand */
#define K_MIN (-45)          /* the table's first power: 10^45 */
#define MASK32 UINT64_C(0xFFFFFFFF)
#define FRAC48 UINT64_C(0xFFFFFFFFFFFF)

/* g(k) = floor(10^-k 2^(62 - r)), r = floor(log2 10^-k), k = -45..31: 2^62 <= g < 2^63.
 * scripts/gen-f32-table.py computes it with exact integers (and checks the logarithm
 * approximations below over every exponent they meet). */
static const uint64_t g_pow10[] = {
    UINT64_C(0x59AEDFC10D7279C5), /* k = -45 */
    UINT64_C(0x47BF19673DF52E37), /* k = -44 */
    UINT64_C(0x72CB5BD86321E38C), /* k = -43 */
    UINT64_C(0x5BD5E313828182D6), /* k = -42 */
    UINT64_C(0x4977E8DC68679BDF), /* k = -41 */
    UINT64_C(0x758CA7C70D7292FE), /* k = -40 */
    UINT64_C(0x5E0A1FD271287598), /* k = -39 */
    UINT64_C(0x4B3B4CA85A86C47A), /* k = -38 */
    UINT64_C(0x785EE10D5DA46D90), /* k = -37 */
    UINT64_C(0x604BE73DE4838AD9), /* k = -36 */
    UINT64_C(0x4D0985CB1D3608AE), /* k = -35 */
    UINT64_C(0x7B426FAB61F00DE3), /* k = -34 */
    UINT64_C(0x629B8C891B267182), /* k = -33 */
    UINT64_C(0x4EE2D6D415B85ACE), /* k = -32 */
    UINT64_C(0x7E37BE2022C0914B), /* k = -31 */
    UINT64_C(0x64F964E68233A76F), /* k = -30 */
    UINT64_C(0x50C783EB9B5C85F2), /* k = -29 */
    UINT64_C(0x409F9CBC7C4A04C2), /* k = -28 */
    UINT64_C(0x6765C793FA10079D), /* k = -27 */
    UINT64_C(0x52B7D2DCC80CD2E4), /* k = -26 */
    UINT64_C(0x422CA8B0A00A4250), /* k = -25 */
    UINT64_C(0x69E10DE76676D080), /* k = -24 */
    UINT64_C(0x54B40B1F852BDA00), /* k = -23 */
    UINT64_C(0x43C33C1937564800), /* k = -22 */
    UINT64_C(0x6C6B935B8BBD4000), /* k = -21 */
    UINT64_C(0x56BC75E2D6310000), /* k = -20 */
    UINT64_C(0x4563918244F40000), /* k = -19 */
    UINT64_C(0x6F05B59D3B200000), /* k = -18 */
    UINT64_C(0x58D15E1762800000), /* k = -17 */
    UINT64_C(0x470DE4DF82000000), /* k = -16 */
    UINT64_C(0x71AFD498D0000000), /* k = -15 */
    UINT64_C(0x5AF3107A40000000), /* k = -14 */
    UINT64_C(0x48C2739500000000), /* k = -13 */
    UINT64_C(0x746A528800000000), /* k = -12 */
    UINT64_C(0x5D21DBA000000000), /* k = -11 */
    UINT64_C(0x4A817C8000000000), /* k = -10 */
    UINT64_C(0x7735940000000000), /* k = -9 */
    UINT64_C(0x5F5E100000000000), /* k = -8 */
    UINT64_C(0x4C4B400000000000), /* k = -7 */
    UINT64_C(0x7A12000000000000), /* k = -6 */
    UINT64_C(0x61A8000000000000), /* k = -5 */
    UINT64_C(0x4E20000000000000), /* k = -4 */
    UINT64_C(0x7D00000000000000), /* k = -3 */
    UINT64_C(0x6400000000000000), /* k = -2 */
    UINT64_C(0x5000000000000000), /* k = -1 */
    UINT64_C(0x4000000000000000), /* k = 0 */
    UINT64_C(0x6666666666666666), /* k = 1 */
    UINT64_C(0x51EB851EB851EB85), /* k = 2 */
    UINT64_C(0x4189374BC6A7EF9D), /* k = 3 */
    UINT64_C(0x68DB8BAC710CB295), /* k = 4 */
    UINT64_C(0x53E2D6238DA3C211), /* k = 5 */
    UINT64_C(0x431BDE82D7B634DA), /* k = 6 */
    UINT64_C(0x6B5FCA6AF2BD215E), /* k = 7 */
    UINT64_C(0x55E63B88C230E77E), /* k = 8 */
    UINT64_C(0x44B82FA09B5A52CB), /* k = 9 */
    UINT64_C(0x6DF37F675EF6EADF), /* k = 10 */
    UINT64_C(0x57F5FF85E592557F), /* k = 11 */
    UINT64_C(0x465E6604B7A84465), /* k = 12 */
    UINT64_C(0x709709A125DA0709), /* k = 13 */
    UINT64_C(0x5A126E1A84AE6C07), /* k = 14 */
    UINT64_C(0x480EBE7B9D58566C), /* k = 15 */
    UINT64_C(0x734ACA5F6226F0AD), /* k = 16 */
    UINT64_C(0x5C3BD5191B525A24), /* k = 17 */
    UINT64_C(0x49C97747490EAE83), /* k = 18 */
    UINT64_C(0x760F253EDB4AB0D2), /* k = 19 */
    UINT64_C(0x5E72843249088D75), /* k = 20 */
    UINT64_C(0x4B8ED0283A6D3DF7), /* k = 21 */
    UINT64_C(0x78E480405D7B9658), /* k = 22 */
    UINT64_C(0x60B6CD004AC94513), /* k = 23 */
    UINT64_C(0x4D5F0A66A23A9DA9), /* k = 24 */
    UINT64_C(0x7BCB43D769F762A8), /* k = 25 */
    UINT64_C(0x63090312BB2C4EED), /* k = 26 */
    UINT64_C(0x4F3A68DBC8F03F24), /* k = 27 */
    UINT64_C(0x7EC3DAF941806506), /* k = 28 */
    UINT64_C(0x65697BFA9ACD1D9F), /* k = 29 */
    UINT64_C(0x51212FFBAF0A7E18), /* k = 30 */
    UINT64_C(0x40E7599625A1FE7A), /* k = 31 */
};

/* floor(x / 2^s) for either sign, without right-shifting a negative number. */
static int32_t floor_shr(int64_t x, unsigned s)
{
    int64_t r;
    if (x >= 0) {
        r = x >> s;
    } else {
        r = ~((~x) >> s); /* ~x = -x - 1 >= 0 */
    }
    return (int32_t)r;
}

static int32_t flog10_pow2(int32_t q) { return floor_shr((int64_t)q * INT64_C(661971961083), 41U); }

static int32_t flog10_three_quarters_pow2(int32_t q)
{
    return floor_shr((int64_t)q * INT64_C(661971961083) - INT64_C(274743187321), 41U);
}

static int32_t flog2_pow10(int32_t e) { return floor_shr((int64_t)e * INT64_C(913124641741), 38U); }

static uint64_t mul_high(uint64_t a, uint64_t b)
{
#if defined(__SIZEOF_INT128__)
    __extension__ typedef unsigned __int128 u128_t;
    return (uint64_t)(((u128_t)a * b) >> 64);
#else
    const uint64_t al = a & MASK32, ah = a >> 32, bl = b & MASK32, bh = b >> 32;
    const uint64_t ll = al * bl, lh = al * bh, hl = ah * bl, hh = ah * bh;
    const uint64_t mid = (ll >> 32) + (lh & MASK32) + (hl & MASK32);
    return hh + (lh >> 32) + (hl >> 32) + (mid >> 32);
#endif
}

/* cp g / 2^95, rounded to odd: the truncated quotient with its lowest bit set when
 * anything was cut off. */
static uint32_t round_odd(uint64_t g, uint64_t cp)
{
    const uint64_t x = mul_high(g, cp);
    return (uint32_t)((x >> 31) | (((x & MASK32) + MASK32) >> 32));
}

static const char two_digits[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* Number of decimal digits of m (0 < m < 10^9): a few comparisons, no loop. */
static unsigned count_digits(uint32_t m)
{
    unsigned n;
    if (m < 100000U) {
        n = (m < 100U) ? ((m < 10U) ? 1U : 2U) : ((m < 1000U) ? 3U : ((m < 10000U) ? 4U : 5U));
    } else {
        n = (m < 10000000U) ? ((m < 1000000U) ? 6U : 7U) : ((m < 100000000U) ? 8U : 9U);
    }
    return n;
}

static const uint32_t p10_u32[] = {1U, 10U, 100U, 1000U, 10000U, 100000U, 1000000U, 10000000U, 100000000U};

/* The 9 digits of v (10^8 <= v < 10^9) into d[0..8], left to right without a division,
 * and how many there are without the trailing zeros (the zero pairs, then one digit):
 * the first digit is v 1441151881 / 2^57, the other eight are v mod 10^8 as a 48-bit
 * fraction of 10^6 (times ceil(2^48 / 10^6)) whose integer part, times 100 each step,
 * gives two digits at a time. Both are exact for every v below 10^9 (a loop over all of
 * them, against / and %, takes a second); bench/fmt_exhaustive.c checks every float. */
static unsigned nine_digits(uint32_t v, char *d)
{
    const uint32_t h = (uint32_t)(((uint64_t)v * UINT64_C(1441151881)) >> 57);
    const uint64_t y0 = (uint64_t)(v - h * 100000000U) * UINT64_C(281474977);
    const uint64_t y1 = (y0 & FRAC48) * 100U;
    const uint64_t y2 = (y1 & FRAC48) * 100U;
    const uint64_t y3 = (y2 & FRAC48) * 100U;
    const uint32_t p0 = (uint32_t)(y0 >> 48), p1 = (uint32_t)(y1 >> 48);
    const uint32_t p2 = (uint32_t)(y2 >> 48), p3 = (uint32_t)(y3 >> 48);
    unsigned n = 9U;
    d[0] = (char)('0' + h);
    (void)memcpy(d + 1, two_digits + 2U * p0, 2U);
    (void)memcpy(d + 3, two_digits + 2U * p1, 2U);
    (void)memcpy(d + 5, two_digits + 2U * p2, 2U);
    (void)memcpy(d + 7, two_digits + 2U * p3, 2U);
    if (p3 == 0U) {
        n = (p2 != 0U) ? 7U : ((p1 != 0U) ? 5U : ((p0 != 0U) ? 3U : 1U));
    }
    if (d[n - 1U] == '0') { /* d[0] is not '0' */
        n--;
    }
    return n;
}

/* f 10^e as %g would print f's digits: 0 < f < 10^9. The digits are made once, as the
 * 9-digit f 10^(9 - n0) (so the zeros an integer needs come with them), and put in place
 * with copies of a constant size: no loop over digits, no call into memcpy. */
static size_t to_chars(uint32_t f, int32_t e, char *out)
{
    char d[16];
    const unsigned n0 = count_digits(f);
    const int32_t x = e + (int32_t)n0 - 1; /* the decimal exponent of the first digit */
    unsigned n; /* significant digits: the shortest text has no trailing zero */
    size_t len;
    (void)memcpy(d + 8U, "00000000", 8U); /* d[9..15]: read by the copies below, never shown */
    n = nine_digits(f * p10_u32[9U - n0], d);
    if ((x < -4) || (x >= 9)) {
        unsigned ax;
        out[0] = d[0]; /* d.ddd */
        out[1] = '.';
        (void)memcpy(out + 2, d + 1, 8U);
        len = (n > 1U) ? (size_t)n + 1U : 1U;
        out[len++] = 'e';
        out[len++] = (x < 0) ? '-' : '+';
        ax = (unsigned)((x < 0) ? -x : x); /* |x| <= 45 */
        out[len++] = two_digits[2U * ax];
        out[len++] = two_digits[2U * ax + 1U];
    } else if (x < 0) {
        const unsigned z = (unsigned)(-x - 1); /* 0.000ddd, z <= 3 zeros */
        (void)memcpy(out, "0.000", 5U);
        (void)memcpy(out + 2U + z, d, 9U);
        len = 2U + z + n;
    } else if ((unsigned)x + 1U >= n) { /* an integer: d holds the zeros up to the point */
        (void)memcpy(out, d, 9U);
        len = (size_t)x + 1U;
    } else {
        const unsigned ip = (unsigned)x + 1U; /* ddd.ddd, 1 <= ip <= 8 */
        char t[24];
        (void)memcpy(t, d, 8U);
        (void)memcpy(t + ip + 1U, d + ip, 8U);
        t[ip] = '.';
        (void)memcpy(out, t, 10U);
        len = n + 1U;
    }
    out[len] = '\0';
    return len;
}

/* The shortest decimal of c 2^q (c > 0), nearest among the shortest, as f 10^*e; the names
 * follow the paper: vb, vbl, vbr are 4 v, and the interval's ends, scaled by 10^-k. */
static uint32_t to_decimal(int32_t q, uint32_t c, int32_t *e)
{
    const uint32_t odd = c & 1U; /* an even significand owns its interval's ends */
    const uint64_t cb = (uint64_t)c << 2;
    const uint64_t cbr = cb + 2U;
    uint64_t cbl;
    int32_t k, h;
    uint64_t g;
    uint32_t vb, vbl, vbr, s, t;
    int32_t cmp;
    if ((c != C_MIN) || (q == Q_MIN)) {
        cbl = cb - 2U; /* regular spacing */
        k = flog10_pow2(q);
    } else {
        cbl = cb - 1U; /* a power of two: the float below is half as far */
        k = flog10_three_quarters_pow2(q);
    }
    h = q + flog2_pow10(-k) + 33;
    g = g_pow10[k - K_MIN] + 1U;
    vb = round_odd(g, cb << h);
    vbl = round_odd(g, cbl << h);
    vbr = round_odd(g, cbr << h);
    s = vb >> 2;
    *e = k;
    {
        /* One digit fewer: the multiples of ten around s (the interval holds at most one).
         * Java asks for two digits at least and skips this below s = 100; the shortest text
         * of a small subnormal (3e-44, not 2.9e-44) needs it. */
        const uint32_t sp10 = 10U * (uint32_t)(((uint64_t)s * UINT64_C(1717986919)) >> 34);
        const uint32_t tp10 = sp10 + 10U;
        const int upin = (sp10 != 0U) && ((vbl + odd) <= (sp10 << 2));
        const int wpin = ((tp10 << 2) + odd) <= vbr;
        if (upin != wpin) {
            return upin ? sp10 : tp10;
        }
    }
    t = s + 1U;
    {
        const int uin = (vbl + odd) <= (s << 2);
        const int win = ((t << 2) + odd) <= vbr;
        if (uin != win) {
            return uin ? s : t;
        }
    }
    /* both in the interval: the nearer, the even one on a tie */
    cmp = (int32_t)vb - (int32_t)((s + t) << 1);
    return ((cmp < 0) || ((cmp == 0) && ((s & 1U) == 0U))) ? s : t;
}

size_t c4gh_fmt_f32(float v, char *buf)
{
    uint32_t bits, frac, be, c, f;
    int32_t mq, e = 0;
    size_t sign = 0U;
    memcpy(&bits, &v, sizeof bits);
    frac = bits & 0x7FFFFFU;
    be = (bits >> 23) & 0xFFU;
    if (be == 0xFFU) {
        if (frac != 0U) {
            memcpy(buf, "nan", 4U);
            return 3U;
        }
        if ((bits >> 31) != 0U) {
            memcpy(buf, "-inf", 5U);
            return 4U;
        }
        memcpy(buf, "inf", 4U);
        return 3U;
    }
    if ((bits >> 31) != 0U) {
        buf[0] = '-';
        sign = 1U;
    }
    if ((be | frac) == 0U) {
        buf[sign] = '0';
        buf[sign + 1U] = '\0';
        return sign + 1U;
    }
    /* v = c 2^-mq; one call of to_decimal and of to_chars each, so that both are inlined */
    if (be != 0U) {
        mq = -Q_MIN + 1 - (int32_t)be;
        c = C_MIN | frac;
    } else {
        mq = -Q_MIN; /* subnormal */
        c = frac;
    }
    if ((mq > 0) && (mq < P_BITS) && (((c >> mq) << mq) == c)) {
        f = c >> mq; /* an integer below 2^24 */
    } else {
        f = to_decimal(-mq, c, &e);
    }
    return sign + to_chars(f, e, buf + sign);
}
