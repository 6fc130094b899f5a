/* SPDX-License-Identifier: MIT */
/* Kinematic transforms of chapter 19 on the figure 10.1 robot: matrices, hand-computed
 * motor positions, round trips (link -> motor -> link within 1e-6 relative), velocities,
 * auxiliary axes, linear axes, and every error path. */
#include "test_helpers.h"
#include <math.h>

static c4g_kin_t kin_fig(void)
{
    c4g_init_t in;
    c4g_kin_t k;
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_OK);
    return k;
}

static void near(double a, double b, double rel)
{
    const double tol = rel * (fabs(b) > 1.0 ? fabs(b) : 1.0);
    if (fabs(a - b) > tol) {
        fail_msg("%.12g != %.12g", a, b);
    }
}

static void test_from_init(void **state)
{
    c4g_init_t in;
    c4g_kin_t k;
    (void)state;
    k = kin_fig();
    /* field facts: k54 = AxInfo[3], k64 = AxInfo[4], k65 = AxInfo[5]: -0.0200, 0.0204, 0.0200 */
    near(k.k54, -0.0200, 1e-6);
    near(k.k64, 0.0204, 1e-6);
    near(k.k65, 0.0200, 1e-6);
    near(k.kr[0], -181.587296, 1e-7);
    near(k.cal[4], 0.039380, 1e-6);
    near(k.period_s, 0.002, 1e-12);
    assert_int_equal(k.linear[0], C4G_KIN_ROTARY);
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_kin_from_init(NULL, 0, &k), C4G_ERR_NULL);
    assert_int_equal(c4g_kin_from_init(&in, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_kin_from_init(&in, 4, &k), C4G_ERR_ARG);
    in.period_ms = 0;
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_ERR_PERIOD);
    in.period_ms = 1001;
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_ERR_PERIOD);
    in.period_ms = 2;
    in.tx_rate[0][9] = NAN;
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_ERR_NONFINITE);
    in.tx_rate[0][9] = 0;
    in.cal_data[0][2] = INFINITY;
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_ERR_NONFINITE);
    in.cal_data[0][2] = 0;
    in.ax_info[0][4] = NAN;
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_ERR_NONFINITE);
}

static void test_matrices(void **state)
{
    c4g_kin_t k = kin_fig();
    c4g_kin_matrices_t m;
    double inv[6][6] = {{0}};
    int i, j, l;
    (void)state;
    assert_int_equal(c4g_kin_matrices(&k, &m), C4G_OK);
    /* chapter 19's closed form of Kr */
    near(m.kr[4][3], -78.75 * -0.0200, 1e-6);
    near(m.kr[5][3], -50.0 * (0.0200 * -0.0200 - 0.0204), 1e-6);
    near(m.kr[5][4], 50.0 * 0.0200, 1e-6);
    near(m.kr[3][3], 72.585968, 1e-7);
    assert_true(m.kr[3][4] == 0.0 && m.kr[0][5] == 0.0);
    near(m.k1[3][4], -0.0200, 1e-6);
    near(m.k1[3][5], 0.0204, 1e-6);
    near(m.k1[4][5], 0.0200, 1e-6);
    /* Kr K1^T = Kr2 (i.e. Kr = Kr2 K1^-T) */
    for (i = 0; i < 6; i++) {
        for (j = 0; j < 6; j++) {
            for (l = 0; l < 6; l++) {
                inv[i][j] += m.kr[i][l] * m.k1[j][l];
            }
            near(inv[i][j], m.kr2[i][j], 1e-9);
        }
    }
    assert_int_equal(c4g_kin_matrices(NULL, &m), C4G_ERR_NULL);
    assert_int_equal(c4g_kin_matrices(&k, NULL), C4G_ERR_NULL);
    k.k65 = NAN;
    assert_int_equal(c4g_kin_matrices(&k, &m), C4G_ERR_NONFINITE);
    k = kin_fig();
    k.cal[8] = INFINITY;
    assert_int_equal(c4g_kin_matrices(&k, &m), C4G_ERR_NONFINITE);
}

static void test_hand_values(void **state)
{
    /* q = (0.1, -0.2, 0.3, 0.4, -0.5, 0.6) rad on the figure 10.1 robot, by hand:
     * axis 1: -181.587296 * 0.1 / 2pi + 0.142965 = -2.747087
     * axis 5: 78.75 * (-0.5 + 0.0200 * 0.4) / 2pi + 0.039380 = -6.127078 */
    static const double q[6] = {0.1, -0.2, 0.3, 0.4, -0.5, 0.6};
    static const double want[6] = {-2.747086565, -4.899077762, 7.980207455,
                                   5.026849258, -6.127078273, -4.432193310};
    c4g_kin_t k = kin_fig();
    c4g_kin_matrices_t m;
    double qm[6], back[6];
    int i, j;
    (void)state;
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, qm), C4G_OK);
    assert_int_equal(c4g_kin_matrices(&k, &m), C4G_OK);
    for (i = 0; i < 6; i++) {
        double y = k.cal[i];
        near(qm[i], want[i], 1e-8);
        for (j = 0; j < 6; j++) {
            y += m.kr[i][j] * q[j] / (2.0 * M_PI);
        }
        near(qm[i], y, 1e-12); /* same as the printed matrix */
    }
    assert_int_equal(c4g_kin_motor_to_link(&k, qm, 6, back), C4G_OK);
    for (i = 0; i < 6; i++) {
        near(back[i], q[i], 1e-12);
    }
}

static void test_round_trip(void **state)
{
    c4g_kin_t k = kin_fig();
    uint32_t seed = 0x5eedu;
    int round;
    (void)state;
    k.kr[6] = 12.5;   /* auxiliary axes: identity influence */
    k.kr[7] = -3.0;
    k.cal[6] = 0.25;
    k.linear[7] = C4G_KIN_LINEAR;
    for (round = 0; round < 5000; round++) {
        double q[8], qm[8], back[8], v[8], vm[8], vb[8];
        int i;
        for (i = 0; i < 8; i++) {
            q[i] = (double)th_randf(&seed) / 100.0;  /* +-10 rad */
            v[i] = (double)th_randf(&seed) / 200.0;
        }
        assert_int_equal(c4g_kin_link_to_motor(&k, q, 8, qm), C4G_OK);
        assert_int_equal(c4g_kin_motor_to_link(&k, qm, 8, back), C4G_OK);
        assert_int_equal(c4g_kin_link_vel_to_motor(&k, v, 8, vm), C4G_OK);
        assert_int_equal(c4g_kin_motor_vel_to_link(&k, vm, 8, vb), C4G_OK);
        for (i = 0; i < 8; i++) {
            if (fabs(back[i] - q[i]) > 1e-6 * (fabs(q[i]) > 1e-3 ? fabs(q[i]) : 1e-3) ||
                fabs(vb[i] - v[i]) > 1e-6 * (fabs(v[i]) > 1e-3 ? fabs(v[i]) : 1e-3)) {
                fail_msg("seed 0x5eed round %d axis %d: %.12g %.12g", round, i, back[i], q[i]);
            }
        }
    }
    {   /* auxiliary and linear units by hand */
        double q[8] = {0, 0, 0, 0, 0, 0, 2.0 * M_PI, 4.0}, qm[8];
        assert_int_equal(c4g_kin_link_to_motor(&k, q, 8, qm), C4G_OK);
        near(qm[6], 12.5 + 0.25, 1e-12);
        near(qm[7], -12.0, 1e-12);
    }
    {   /* velocity: 1 rad/s on axis 1 at 2 ms = kr * 0.002 / 2pi turns per tick */
        double v[1] = {1.0}, vm[1];
        assert_int_equal(c4g_kin_link_vel_to_motor(&k, v, 1, vm), C4G_OK);
        near(vm[0], -181.587296 * 0.002 / (2.0 * M_PI), 1e-7);
    }
    {   /* fewer than 5 or 6 axes: no coupling terms */
        double q[5] = {0, 0, 0, 1.0, 1.0}, qm[5], b[5];
        assert_int_equal(c4g_kin_link_to_motor(&k, q, 5, qm), C4G_OK);
        assert_int_equal(c4g_kin_motor_to_link(&k, qm, 5, b), C4G_OK);
        near(b[3], 1.0, 1e-12);
        near(b[4], 1.0, 1e-12);
        assert_int_equal(c4g_kin_link_to_motor(&k, q, 4, qm), C4G_OK);
    }
}

static void test_errors(void **state)
{
    c4g_kin_t k = kin_fig();
    double q[10] = {0}, out[10];
    (void)state;
    assert_int_equal(c4g_kin_link_to_motor(NULL, q, 6, out), C4G_ERR_NULL);
    assert_int_equal(c4g_kin_link_to_motor(&k, NULL, 6, out), C4G_ERR_NULL);
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 0, out), C4G_ERR_ARG);
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 11, out), C4G_ERR_ARG);
    /* axes 7..10 have no ratio in figure 10.1 */
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 7, out), C4G_ERR_SINGULAR);
    assert_int_equal(c4g_kin_motor_to_link(&k, q, 10, out), C4G_ERR_SINGULAR);
    q[2] = NAN;
    assert_int_equal(c4g_kin_motor_to_link(&k, q, 7, out), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_kin_link_vel_to_motor(&k, q, 6, out), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_kin_motor_vel_to_link(&k, q, 6, out), C4G_ERR_NONFINITE);
    q[2] = 1e308; /* result overflows */
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, out), C4G_ERR_NONFINITE);
    q[2] = 0;
    q[0] = 1e307;
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, out), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_kin_link_vel_to_motor(&k, q, 6, out), C4G_OK);
    q[0] = 1.7e308;
    assert_int_equal(c4g_kin_motor_to_link(&k, q, 6, out), C4G_OK);
    q[0] = -1.7e308;
    q[3] = 1.7e308;
    assert_int_equal(c4g_kin_motor_to_link(&k, q, 6, out), C4G_OK);
    q[0] = 1.7e308;
    k.cal[0] = -1.7e308; /* qm - q0 overflows */
    assert_int_equal(c4g_kin_motor_to_link(&k, q, 6, out), C4G_ERR_NONFINITE);
    k = kin_fig();
    q[0] = 1e308;
    q[3] = 0;
    k.kr[0] = 1e-300;
    assert_int_equal(c4g_kin_motor_vel_to_link(&k, q, 1, out), C4G_ERR_NONFINITE);
    k = kin_fig();
    k.period_s = 0.0;
    q[0] = 1.0;
    assert_int_equal(c4g_kin_motor_vel_to_link(&k, q, 1, out), C4G_ERR_PERIOD);
    k.period_s = 1e300;
    q[0] = 1e300;
    k.kr[0] = 1e-300;
    assert_int_equal(c4g_kin_link_vel_to_motor(&k, q, 1, out), C4G_ERR_NONFINITE);
    k = kin_fig();
    k.k54 = INFINITY;
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, out), C4G_ERR_NONFINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_from_init),
        cmocka_unit_test(test_matrices),
        cmocka_unit_test(test_hand_values),
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
