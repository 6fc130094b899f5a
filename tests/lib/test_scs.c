/* SPDX-License-Identifier: MIT */
/* Soft control switching (chapter 12): chi/eta/rho, reducer, limiter, both directions. */
#include "test_helpers.h"
#include <math.h>

static void test_linear(void **state)
{
    c4g_scs_t s;
    (void)state;
    assert_int_equal(c4g_scs_linear(0, 100, 200, &s), C4G_OK);
    assert_true(s.chi == 0.0f && s.eta == 0.0f && s.rho == 1.0f);
    assert_int_equal(c4g_scs_linear(100, 100, 200, &s), C4G_OK);
    assert_true(s.chi == 0.0f);
    assert_int_equal(c4g_scs_linear(150, 100, 200, &s), C4G_OK);
    assert_true(s.chi == 0.5f && s.eta == 0.5f && s.rho == 0.5f);
    assert_int_equal(c4g_scs_linear(175, 100, 200, &s), C4G_OK);
    assert_true(s.chi == 0.75f && s.rho == 0.25f);
    assert_int_equal(c4g_scs_linear(200, 100, 200, &s), C4G_OK);
    assert_true(s.chi == 1.0f && s.rho == 0.0f);
    assert_int_equal(c4g_scs_linear(UINT64_MAX, 100, 200, &s), C4G_OK);
    assert_true(s.chi == 1.0f);
    /* a span float cannot resolve: still within [0, 1] */
    assert_int_equal(c4g_scs_linear(UINT64_MAX - 1, 0, UINT64_MAX, &s), C4G_OK);
    assert_true(s.chi <= 1.0f && s.chi >= 0.99f);
    assert_int_equal(c4g_scs_linear(0, 200, 200, &s), C4G_ERR_ARG);
    assert_int_equal(c4g_scs_linear(0, 300, 200, &s), C4G_ERR_ARG);
    assert_int_equal(c4g_scs_linear(0, 0, 1, NULL), C4G_ERR_NULL);
}

static void test_reduce_limit(void **state)
{
    float o = 0.0f;
    (void)state;
    assert_int_equal(c4g_scs_reduce(0.5f, 8.0f, &o), C4G_OK);
    assert_true(o == 4.0f);
    assert_int_equal(c4g_scs_reduce(0.0f, 8.0f, &o), C4G_OK);
    assert_true(o == 0.0f);
    assert_int_equal(c4g_scs_reduce(1.0f, -8.0f, &o), C4G_OK);
    assert_true(o == -8.0f);
    assert_int_equal(c4g_scs_reduce(1.01f, 8.0f, &o), C4G_ERR_ARG);
    assert_int_equal(c4g_scs_reduce(-0.01f, 8.0f, &o), C4G_ERR_ARG);
    assert_int_equal(c4g_scs_reduce(NAN, 8.0f, &o), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_reduce(0.5f, INFINITY, &o), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_reduce(0.5f, 1.0f, NULL), C4G_ERR_NULL);
    /* threshold = gain (Imax - Imin) = 0.5 * 20 = 10 */
    assert_int_equal(c4g_scs_limit(0.5f, 20.0f, 0.0f, 10.0f, &o), C4G_OK);
    assert_true(o == 10.0f);
    assert_int_equal(c4g_scs_limit(0.5f, 20.0f, 0.0f, 10.5f, &o), C4G_OK);
    assert_true(o == 10.0f);
    assert_int_equal(c4g_scs_limit(0.5f, 20.0f, 0.0f, -10.5f, &o), C4G_OK);
    assert_true(o == -10.0f);
    assert_int_equal(c4g_scs_limit(0.5f, 20.0f, 0.0f, -3.0f, &o), C4G_OK);
    assert_true(o == -3.0f);
    assert_int_equal(c4g_scs_limit(0.0f, 20.0f, 0.0f, 3.0f, &o), C4G_OK);
    assert_true(o == 0.0f);
    assert_int_equal(c4g_scs_limit(0.5f, 0.0f, 1.0f, 3.0f, &o), C4G_ERR_ARG);
    assert_int_equal(c4g_scs_limit(2.0f, 1.0f, 0.0f, 3.0f, &o), C4G_ERR_ARG);
    assert_int_equal(c4g_scs_limit(NAN, 1.0f, 0.0f, 3.0f, &o), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_limit(0.5f, NAN, 0.0f, 3.0f, &o), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_limit(0.5f, 1.0f, NAN, 3.0f, &o), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_limit(0.5f, 1.0f, 0.0f, NAN, &o), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_limit(1.0f, 3e38f, -3e38f, 1.0f, &o), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_limit(0.5f, 1.0f, 0.0f, 1.0f, NULL), C4G_ERR_NULL);
}

static void test_currents(void **state)
{
    c4g_scs_t s;
    float d = 0.0f, r = 0.0f;
    (void)state;
    assert_int_equal(c4g_scs_linear(25, 0, 100, &s), C4G_OK); /* chi 0.25, rho 0.75 */
    /* to PC: dynamic model * eta, regulator limited by rho (Imax - Imin) */
    assert_int_equal(c4g_scs_currents(&s, C4G_SCS_TO_PC, 8.0f, 20.0f, 20.0f, 0.0f, &d, &r),
                     C4G_OK);
    assert_true(d == 2.0f && r == 15.0f);
    /* back to DSA: dynamic model * rho, regulator limited by eta (Imax - Imin) */
    assert_int_equal(c4g_scs_currents(&s, C4G_SCS_TO_DSA, 8.0f, -20.0f, 20.0f, 0.0f, &d, &r),
                     C4G_OK);
    assert_true(d == 6.0f && r == -5.0f);
    assert_int_equal(c4g_scs_currents(&s, (c4g_scs_dir_t)7, 8.0f, 1.0f, 20.0f, 0.0f, &d, &r),
                     C4G_ERR_ARG);
    assert_int_equal(c4g_scs_currents(&s, C4G_SCS_TO_PC, NAN, 1.0f, 20.0f, 0.0f, &d, &r),
                     C4G_ERR_NONFINITE);
    assert_int_equal(c4g_scs_currents(&s, C4G_SCS_TO_PC, 1.0f, 1.0f, 0.0f, 20.0f, &d, &r),
                     C4G_ERR_ARG);
    assert_int_equal(c4g_scs_currents(NULL, C4G_SCS_TO_PC, 1, 1, 1, 0, &d, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_scs_currents(&s, C4G_SCS_TO_PC, 1, 1, 1, 0, NULL, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_scs_currents(&s, C4G_SCS_TO_PC, 1, 1, 1, 0, &d, NULL), C4G_ERR_NULL);
}

/* A mode-1 START driven by the state machine's phase timestamps. */
static void test_with_phase(void **state)
{
    c4g_init_t in;
    uint64_t period = 0;
    c4g_scs_t s;
    (void)state;
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_period_ns(&in, &period), C4G_OK);
    assert_int_equal(period, 2000000u);
    assert_int_equal(c4g_scs_linear(10 * period, 0, 40 * period, &s), C4G_OK);
    assert_true(s.chi == 0.25f);
    in.period_ms = 0;
    assert_int_equal(c4g_period_ns(&in, &period), C4G_ERR_PERIOD);
    in.period_ms = 1001;
    assert_int_equal(c4g_period_ns(&in, &period), C4G_ERR_PERIOD);
    assert_int_equal(c4g_period_ns(NULL, &period), C4G_ERR_NULL);
    assert_int_equal(c4g_period_ns(&in, NULL), C4G_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear),
        cmocka_unit_test(test_reduce_limit),
        cmocka_unit_test(test_currents),
        cmocka_unit_test(test_with_phase),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
