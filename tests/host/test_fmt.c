/* SPDX-License-Identifier: MIT */
/* The shortest float32 text (lib/host/c4gh_fmt): fixed cases, the edges (zeros, subnormals,
 * powers of two, FLT_MAX, NaN and infinities) and 10^6 random bit patterns against strtof
 * and glibc's correctly rounded %.*e. Every 2^32 pattern: bench/fmt_exhaustive.c. */
#include "test_helpers.h"
#include <float.h>
#include <inttypes.h>
#include <math.h>

#include "c4gh_fmt.h"

#include <valgrind/valgrind.h>

static float from_bits(uint32_t b)
{
    float f;
    memcpy(&f, &b, sizeof f);
    return f;
}

static uint32_t bits_of(float f)
{
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b;
}

static const char *fmt(float v)
{
    static char buf[C4GH_F32_TEXT_MAX];
    const size_t n = c4gh_fmt_f32(v, buf);
    assert_int_equal(n, strlen(buf));
    return buf;
}

/* Significant digits of a decimal text, first to last non-zero one ("0.00123" -> 3,
 * "1.5e+10" -> 2, "5770060" -> 6, "0" -> 1). */
static int digits_of(const char *s)
{
    int n = 0, last = 1, lead = 1;
    for (; *s != '\0' && *s != 'e'; s++) {
        if (*s >= '0' && *s <= '9') {
            if (lead && *s == '0') {
                continue;
            }
            lead = 0;
            n++;
            if (*s != '0') {
                last = n;
            }
        }
    }
    return last;
}

/* The checks on one finite float: reads back; no text of fewer digits reads back (glibc's
 * correctly rounded %.*e at each shorter precision); the nearest text of its length when
 * that one reads back; the negative is '-' and the magnitude. */
static void check(uint32_t b)
{
    const float v = from_bits(b);
    char text[C4GH_F32_TEXT_MAX], neg[C4GH_F32_TEXT_MAX], e[40];
    int n, p;
    (void)c4gh_fmt_f32(v, text);
    if (bits_of(strtof(text, NULL)) != b) {
        fail_msg("0x%08" PRIx32 ": \"%s\" reads back as %.9g", b, text, (double)strtof(text, NULL));
    }
    n = digits_of(text);
    assert_true(n >= 1 && n <= 9);
    for (p = 1; p < n; p++) {
        (void)snprintf(e, sizeof e, "%.*e", p - 1, (double)v);
        if (bits_of(strtof(e, NULL)) == b) {
            fail_msg("0x%08" PRIx32 ": \"%s\" has %d digits, \"%s\" reads back too", b, text, n, e);
        }
    }
    (void)snprintf(e, sizeof e, "%.*e", n - 1, (double)v);
    if (bits_of(strtof(e, NULL)) == b && strtof(e, NULL) != 0.0f) {
        /* the nearest n-digit decimal reads back: it must be ours */
        assert_true(strtod(e, NULL) == strtod(text, NULL));
    }
    (void)c4gh_fmt_f32(-v, neg);
    assert_true(neg[0] == '-');
    assert_string_equal(neg + 1, text);
}

static void test_fmt_cases(void **state)
{
    (void)state;
    assert_string_equal(fmt(0.0f), "0");
    assert_string_equal(fmt(-0.0f), "-0");
    assert_string_equal(fmt(1.0f), "1");
    assert_string_equal(fmt(0.1f), "0.1");        /* %.9g: 0.100000001 */
    assert_string_equal(fmt(0.3f), "0.3");        /* %.9g: 0.300000012 */
    assert_string_equal(fmt(-2.5f), "-2.5");
    assert_string_equal(fmt(123.456f), "123.456"); /* %.9g: 123.456001 */
    assert_string_equal(fmt(0.0001f), "0.0001");  /* %.9g: 9.99999975e-05 */
    assert_string_equal(fmt(1e-5f), "1e-05");     /* %g's notation below 1e-4 */
    assert_string_equal(fmt(1000000.0f), "1000000");
    assert_string_equal(fmt(16777216.0f), "16777216");
    assert_string_equal(fmt(123456792.0f), "123456790");
    assert_string_equal(fmt(1e9f), "1e+09");      /* %g's notation from 1e9 */
    assert_string_equal(fmt(1e10f), "1e+10");
    assert_string_equal(fmt(FLT_MAX), "3.4028235e+38");
    assert_string_equal(fmt(-FLT_MAX), "-3.4028235e+38");
    assert_string_equal(fmt(FLT_MIN), "1.1754944e-38");
    assert_string_equal(fmt(from_bits(1U)), "1e-45");
    assert_string_equal(fmt(from_bits(0x15U)), "3e-44"); /* 2.94e-44: one digit */
    assert_string_equal(fmt(from_bits(0x007FFFFFU)), "1.1754942e-38");
    assert_string_equal(fmt(33554432.0f), "33554432");
    assert_string_equal(fmt(1.00000012f), "1.0000001");
    assert_string_equal(fmt(0.142965f), "0.142965");
    assert_string_equal(fmt(-181.587296f), "-181.5873");
    assert_string_equal(fmt(NAN), "nan");
    assert_string_equal(fmt(-NAN), "nan");
    assert_string_equal(fmt(from_bits(0x7F800001U)), "nan");
    assert_string_equal(fmt(from_bits(0xFFFFFFFFU)), "nan");
    assert_string_equal(fmt(INFINITY), "inf");
    assert_string_equal(fmt(-INFINITY), "-inf");
}

/* The longest texts fit C4GH_F32_TEXT_MAX with the NUL. */
static void test_fmt_longest(void **state)
{
    char buf[C4GH_F32_TEXT_MAX + 8];
    (void)state;
    memset(buf, 'x', sizeof buf);
    assert_int_equal(c4gh_fmt_f32(-1.17549435e-38f, buf), 14U);
    assert_string_equal(buf, "-1.1754944e-38");
    assert_int_equal(c4gh_fmt_f32(from_bits(0x83AE442BU), buf), 15U);
    assert_string_equal(buf, "-1.02424515e-36");
    assert_true(buf[C4GH_F32_TEXT_MAX] == 'x');
    assert_int_equal(c4gh_fmt_f32(from_bits(0xB8F00001U), buf), 15U);
    assert_string_equal(buf, "-0.000114440925");
}

/* Each layout the digits are put into, with the trailing zeros the digit pairs end on
 * (none, a whole pair, half a pair, all eight), either sign: the text, and nothing
 * written past C4GH_F32_TEXT_MAX (the digits are copied in blocks of a constant size). */
static void test_fmt_layouts(void **state)
{
    static const struct {
        float v;
        const char *text;
    } cases[] = {
        {1.5e-05f, "1.5e-05"},         {1e-05f, "1e-05"},           {1.17549435e-38f, "1.1754944e-38"},
        {3.4028235e+38f, "3.4028235e+38"}, {1e+09f, "1e+09"},       {0.000123f, "0.000123"},
        {0.00012345678f, "0.00012345678"}, {0.1f, "0.1"},            {0.123456789f, "0.12345679"},
        {100000000.0f, "100000000"},   {12340000.0f, "12340000"},   {7.0f, "7"},
        {8388607.5f, "8388607.5"},     {1.25f, "1.25"},             {123.4f, "123.4"},
        {12.000001f, "12.000001"},     {1000.5f, "1000.5"},         {10.000001f, "10.000001"},
    };
    char buf[C4GH_F32_TEXT_MAX + 8];
    char neg[C4GH_F32_TEXT_MAX + 1];
    size_t i, k;
    (void)state;
    for (i = 0U; i < sizeof cases / sizeof cases[0]; i++) {
        memset(buf, 'x', sizeof buf);
        assert_int_equal(c4gh_fmt_f32(cases[i].v, buf), strlen(cases[i].text));
        assert_string_equal(buf, cases[i].text);
        memset(buf, 'x', sizeof buf);
        (void)snprintf(neg, sizeof neg, "-%s", cases[i].text);
        assert_int_equal(c4gh_fmt_f32(-cases[i].v, buf), strlen(neg));
        assert_string_equal(buf, neg);
        for (k = C4GH_F32_TEXT_MAX; k < sizeof buf; k++) {
            assert_true(buf[k] == 'x');
        }
    }
}

static void test_fmt_edges(void **state)
{
    uint32_t e, m;
    (void)state;
    check(0U);
    check(0x7F7FFFFFU);                       /* FLT_MAX */
    for (m = 1U; m < 4096U; m++) {            /* the smallest subnormals */
        check(m);
    }
    for (m = 0x7FF000U; m <= 0x800FFFU; m++) { /* subnormal to normal */
        check(m);
    }
    for (e = 1U; e < 255U; e++) {             /* every power of two and its neighbours */
        check(e << 23);
        check((e << 23) + 1U);
        check((e << 23) - 1U);
        check((e << 23) | 0x7FFFFFU);
    }
    for (e = 1U; e <= 0x7F7FFFFFU / 0x10001U; e++) {
        check(e * 0x10001U);                  /* spread over every exponent */
    }
}

static void test_fmt_random(void **state)
{
    /* under valgrind (memory checks, 50x slower) a sample of the sample: the values are
     * covered natively and over all 2^32 patterns by make bench */
    const uint32_t n = RUNNING_ON_VALGRIND ? 20000U : 1000000U;
    uint32_t seed = 0x5EED1234U, i;
    (void)state;
    for (i = 0U; i < n; i++) {
        const uint32_t b = th_rand(&seed) & 0x7FFFFFFFU;
        if ((b & 0x7F800000U) == 0x7F800000U) {
            continue; /* NaN and inf: test_fmt_cases */
        }
        check(b);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fmt_cases),
        cmocka_unit_test(test_fmt_longest),
        cmocka_unit_test(test_fmt_layouts),
        cmocka_unit_test(test_fmt_edges),
        cmocka_unit_test(test_fmt_random),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
