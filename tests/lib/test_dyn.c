/* SPDX-License-Identifier: MIT */
/* Rigid-body dynamics (c4gopen_dyn.h): a pendulum and a two-link planar arm against their
 * textbook closed forms, the regressor against the Newton-Euler pass on a six-link arm
 * with random parameters and motion, the power balance (qd . tau = dE/dt) on the same
 * arm, the two DH conventions describing one arm, and every error path. */
#include "test_helpers.h"
#include <math.h>

#define G 9.81

static void near(double a, double b, double tol)
{
    const double t = tol * (fabs(b) > 1.0 ? fabs(b) : 1.0);
    if (fabs(a - b) > t) {
        fail_msg("%.12g != %.12g", a, b);
    }
}

/* a small deterministic generator: tests repeat exactly */
static double rnd(uint32_t *s)
{
    *s = (*s * 1664525U) + 1013904223U;
    return ((double)(*s >> 8) / 16777216.0) * 2.0 - 1.0;
}

/* point-like link: mass m at c, inertia about the centre diag(ix, iy, iz) */
static void link_params(double m, double cx, double cy, double cz, double ix, double iy, double iz, double *pi)
{
    const double c[3] = {cx, cy, cz};
    const double ic[6] = {ix, 0, 0, iy, 0, iz};
    assert_int_equal(c4g_dyn_params_from_com(m, c, ic, pi), C4G_OK);
}

static void test_pendulum(void **state)
{
    /* joint axis z, gravity along -y: tau = (Izz + m l^2) qdd + m g l cos q */
    const double zero = 0.0;
    const double a = 0.0;
    const double g[3] = {0.0, -G, 0.0};
    c4g_dyn_chain_t ch;
    double pi[10];
    double ia = 0.3;
    double tau;
    double q;
    (void)state;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 1, C4G_DYN_DH_MODIFIED, &a, &zero, &zero, &zero, g), C4G_OK);
    link_params(2.0, 0.5, 0.0, 0.0, 0.01, 0.02, 0.03, pi);
    for (q = -3.0; q < 3.0; q += 0.7) {
        const double qd = 1.3;
        const double qdd = -0.4;
        assert_int_equal(c4g_dyn_rnea(&ch, &q, &qd, &qdd, pi, NULL, &tau), C4G_OK);
        near(tau, ((0.03 + 2.0 * 0.25) * qdd) + (2.0 * G * 0.5 * cos(q)), 1e-12);
        assert_int_equal(c4g_dyn_rnea(&ch, &q, &qd, &qdd, pi, &ia, &tau), C4G_OK);
        near(tau, ((0.33 + 2.0 * 0.25) * qdd) + (2.0 * G * 0.5 * cos(q)), 1e-12);
    }
}

/* two-link planar arm, links of length l1, l2, point masses at their ends (Spong's form) */
static void planar_closed_form(const double q[2], const double qd[2], const double qdd[2], double tau[2])
{
    const double m1 = 3.0;
    const double m2 = 1.5;
    const double l1 = 0.7;
    const double l2 = 0.4;
    const double c2 = cos(q[1]);
    const double s2 = sin(q[1]);
    const double d11 = (m1 * l1 * l1) + (m2 * ((l1 * l1) + (l2 * l2) + (2.0 * l1 * l2 * c2)));
    const double d12 = m2 * ((l2 * l2) + (l1 * l2 * c2));
    const double d22 = m2 * l2 * l2;
    const double h = -m2 * l1 * l2 * s2;
    const double g1 = ((m1 + m2) * G * l1 * cos(q[0])) + (m2 * G * l2 * cos(q[0] + q[1]));
    const double g2 = m2 * G * l2 * cos(q[0] + q[1]);
    tau[0] = (d11 * qdd[0]) + (d12 * qdd[1]) + (h * ((2.0 * qd[0] * qd[1]) + (qd[1] * qd[1]))) + g1;
    tau[1] = (d12 * qdd[0]) + (d22 * qdd[1]) - (h * qd[0] * qd[0]) + g2;
}

static void test_planar_two_conventions(void **state)
{
    const double zero[2] = {0.0, 0.0};
    const double g[3] = {0.0, -G, 0.0};
    const double a_mod[2] = {0.0, 0.7};
    const double a_std[2] = {0.7, 0.4};
    c4g_dyn_chain_t mod;
    c4g_dyn_chain_t std;
    double pi[20];
    uint32_t seed = 7U;
    int t;
    (void)state;
    assert_int_equal(c4g_dyn_chain_dh(&mod, 2, C4G_DYN_DH_MODIFIED, a_mod, zero, zero, zero, g), C4G_OK);
    assert_int_equal(c4g_dyn_chain_dh(&std, 2, C4G_DYN_DH_STANDARD, a_std, zero, zero, zero, g), C4G_OK);
    link_params(3.0, 0.7, 0.0, 0.0, 0.0, 0.0, 0.0, &pi[0]);
    link_params(1.5, 0.4, 0.0, 0.0, 0.0, 0.0, 0.0, &pi[10]);
    for (t = 0; t < 50; t++) {
        double q[2];
        double qd[2];
        double qdd[2];
        double want[2];
        double got[2];
        double got_std[2];
        int k;
        for (k = 0; k < 2; k++) {
            q[k] = 3.0 * rnd(&seed);
            qd[k] = 2.0 * rnd(&seed);
            qdd[k] = 5.0 * rnd(&seed);
        }
        planar_closed_form(q, qd, qdd, want);
        assert_int_equal(c4g_dyn_rnea(&mod, q, qd, qdd, pi, NULL, got), C4G_OK);
        assert_int_equal(c4g_dyn_rnea(&std, q, qd, qdd, pi, NULL, got_std), C4G_OK);
        near(got[0], want[0], 1e-11);
        near(got[1], want[1], 1e-11);
        near(got_std[0], want[0], 1e-11);
        near(got_std[1], want[1], 1e-11);
    }
}

/* a six-link arm with a spherical wrist, modified DH */
static void six_link(c4g_dyn_chain_t *ch)
{
    const double hp = 1.5707963267948966;
    const double a[6] = {0.0, 0.15, 0.59, 0.11, 0.0, 0.0};
    const double alpha[6] = {0.0, -hp, 0.0, -hp, hp, -hp};
    const double d[6] = {0.45, 0.0, 0.0, 0.64, 0.0, 0.0};
    const double th[6] = {0.0, -hp, 0.0, 0.0, 0.0, 0.0};
    const double g[3] = {0.0, 0.0, -G};
    assert_int_equal(c4g_dyn_chain_dh(ch, 6, C4G_DYN_DH_MODIFIED, a, alpha, d, th, g), C4G_OK);
}

static void random_params(uint32_t *seed, double *pi)
{
    int j;
    for (j = 0; j < 6; j++) {
        link_params(2.0 + 20.0 * fabs(rnd(seed)), 0.2 * rnd(seed), 0.2 * rnd(seed), 0.2 * rnd(seed),
                    0.1 + 0.2 * fabs(rnd(seed)), 0.1 + 0.2 * fabs(rnd(seed)), 0.1 + 0.2 * fabs(rnd(seed)),
                    &pi[j * 10]);
    }
}

static void test_regressor_equals_rnea(void **state)
{
    c4g_dyn_chain_t ch;
    double y[6 * 60];
    double pi[60];
    uint32_t seed = 11U;
    int t;
    (void)state;
    six_link(&ch);
    for (t = 0; t < 40; t++) {
        double q[6];
        double qd[6];
        double qdd[6];
        double tau[6];
        int i;
        int k;
        random_params(&seed, pi);
        for (k = 0; k < 6; k++) {
            q[k] = 3.0 * rnd(&seed);
            qd[k] = 2.0 * rnd(&seed);
            qdd[k] = 8.0 * rnd(&seed);
        }
        assert_int_equal(c4g_dyn_rnea(&ch, q, qd, qdd, pi, NULL, tau), C4G_OK);
        assert_int_equal(c4g_dyn_regressor(&ch, q, qd, qdd, y, 6 * 60), C4G_OK);
        for (i = 0; i < 6; i++) {
            double s = 0.0;
            for (k = 0; k < 60; k++) {
                s += y[i * 60 + k] * pi[k];
            }
            near(s, tau[i], 1e-10);
            /* a joint carries nothing of the links before it */
            for (k = 0; k < i * 10; k++) {
                assert_true(y[i * 60 + k] == 0.0);
            }
        }
    }
}

/* energy of the arm: kinetic from the mass matrix (columns by unit accelerations without
 * velocity and gravity), potential from the gravity torques integrated numerically would
 * need a path; instead the balance qd . (tau - g(q)) = d/dt (qd^T M qd / 2) is checked
 * with M(q) and its time derivative by central differences along the motion. */
static void mass_matrix(const c4g_dyn_chain_t *ch0, const double *q, const double *pi, double m[6][6])
{
    c4g_dyn_chain_t ch = *ch0;
    const double z[6] = {0, 0, 0, 0, 0, 0};
    int c;
    ch.gravity[0] = ch.gravity[1] = ch.gravity[2] = 0.0;
    for (c = 0; c < 6; c++) {
        double e[6] = {0, 0, 0, 0, 0, 0};
        double col[6];
        int r;
        e[c] = 1.0;
        assert_int_equal(c4g_dyn_rnea(&ch, q, z, e, pi, NULL, col), C4G_OK);
        for (r = 0; r < 6; r++) {
            m[r][c] = col[r];
        }
    }
}

static double kinetic(const c4g_dyn_chain_t *ch, const double *q, const double *qd, const double *pi)
{
    double m[6][6];
    double e = 0.0;
    int r;
    int c;
    mass_matrix(ch, q, pi, m);
    for (r = 0; r < 6; r++) {
        for (c = 0; c < 6; c++) {
            e += 0.5 * qd[r] * m[r][c] * qd[c];
            /* symmetric */
            near(m[r][c], m[c][r], 1e-10);
        }
    }
    return e;
}

static void test_power_balance(void **state)
{
    c4g_dyn_chain_t ch;
    c4g_dyn_chain_t nog;
    double pi[60];
    uint32_t seed = 3U;
    int t;
    (void)state;
    six_link(&ch);
    nog = ch;
    nog.gravity[2] = 0.0;
    random_params(&seed, pi);
    for (t = 0; t < 10; t++) {
        const double h = 1e-5;
        double q[6];
        double qd[6];
        double qdd[6];
        double qp[6];
        double qm[6];
        double vp[6];
        double vm[6];
        double tau[6];
        double power = 0.0;
        double dedt;
        int k;
        for (k = 0; k < 6; k++) {
            q[k] = 3.0 * rnd(&seed);
            qd[k] = 2.0 * rnd(&seed);
            qdd[k] = 8.0 * rnd(&seed);
        }
        for (k = 0; k < 6; k++) {
            qp[k] = q[k] + h * qd[k] + 0.5 * h * h * qdd[k];
            qm[k] = q[k] - h * qd[k] + 0.5 * h * h * qdd[k];
            vp[k] = qd[k] + h * qdd[k];
            vm[k] = qd[k] - h * qdd[k];
        }
        assert_int_equal(c4g_dyn_rnea(&nog, q, qd, qdd, pi, NULL, tau), C4G_OK);
        for (k = 0; k < 6; k++) {
            power += qd[k] * tau[k];
        }
        dedt = (kinetic(&nog, qp, vp, pi) - kinetic(&nog, qm, vm, pi)) / (2.0 * h);
        near(power, dedt, 1e-5);
    }
}

static void test_errors(void **state)
{
    c4g_dyn_chain_t ch;
    const double z6[6] = {0, 0, 0, 0, 0, 0};
    const double g[3] = {0.0, 0.0, -G};
    double a6[6] = {0, 0, 0, 0, 0, 0};
    double y[360];
    double pi[60];
    double tau[6];
    double q[6] = {0, 0, 0, 0, 0, 0};
    double bad_g[3] = {0.0, 0.0, 1000.0};
    const double c[3] = {0, 0, 0};
    double ic[6] = {1, 0, 0, 1, 0, 1};
    (void)state;
    memset(pi, 0, sizeof pi);
    assert_int_equal(c4g_dyn_chain_dh(NULL, 6, C4G_DYN_DH_MODIFIED, a6, z6, z6, z6, g), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_chain_dh(&ch, 0, C4G_DYN_DH_MODIFIED, a6, z6, z6, z6, g), C4G_ERR_ARG);
    assert_int_equal(c4g_dyn_chain_dh(&ch, 8, C4G_DYN_DH_MODIFIED, a6, z6, z6, z6, g), C4G_ERR_ARG);
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, (c4g_dyn_convention_t)5, a6, z6, z6, z6, g), C4G_ERR_ARG);
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, C4G_DYN_DH_MODIFIED, a6, z6, z6, z6, bad_g), C4G_ERR_RANGE);
    a6[2] = 101.0;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, C4G_DYN_DH_MODIFIED, a6, z6, z6, z6, g), C4G_ERR_RANGE);
    a6[2] = 0.0;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, C4G_DYN_DH_STANDARD, a6, a6, a6, z6, g), C4G_OK);
    a6[2] = NAN;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, C4G_DYN_DH_MODIFIED, z6, a6, z6, z6, g), C4G_ERR_NONFINITE);
    a6[2] = 7.0;
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, C4G_DYN_DH_MODIFIED, z6, z6, z6, a6, g), C4G_ERR_RANGE);
    assert_int_equal(c4g_dyn_chain_dh(&ch, 6, C4G_DYN_DH_MODIFIED, z6, z6, z6, z6, g), C4G_OK);

    assert_int_equal(c4g_dyn_rnea(NULL, q, q, q, pi, NULL, tau), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_rnea(&ch, q, q, q, NULL, NULL, tau), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_rnea(&ch, q, q, q, pi, NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_regressor(&ch, q, q, q, NULL, 360), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_regressor(&ch, q, q, q, y, 359), C4G_ERR_CAPACITY);
    assert_int_equal(c4g_dyn_regressor(&ch, q, q, q, y, 360), C4G_OK);
    q[3] = INFINITY;
    assert_int_equal(c4g_dyn_rnea(&ch, q, z6, z6, pi, NULL, tau), C4G_ERR_NONFINITE);
    assert_int_equal(c4g_dyn_regressor(&ch, z6, q, z6, y, 360), C4G_ERR_NONFINITE);
    q[3] = 0.0;
    pi[13] = NAN;
    assert_int_equal(c4g_dyn_rnea(&ch, q, z6, z6, pi, NULL, tau), C4G_ERR_NONFINITE);
    pi[13] = 0.0;
    q[0] = NAN;
    assert_int_equal(c4g_dyn_rnea(&ch, z6, z6, z6, pi, q, tau), C4G_ERR_NONFINITE);
    /* finite inputs whose torque overflows */
    pi[0] = 1e308;
    pi[10] = 1e308;
    q[0] = 0.0;
    ch.gravity[2] = -50.0;
    assert_int_equal(c4g_dyn_rnea(&ch, q, z6, z6, pi, NULL, tau), C4G_ERR_NONFINITE);
    ch.gravity[2] = NAN;
    assert_int_equal(c4g_dyn_rnea(&ch, q, z6, z6, pi, NULL, tau), C4G_ERR_NONFINITE);
    ch.gravity[2] = -G;
    ch.n = 0;
    assert_int_equal(c4g_dyn_rnea(&ch, q, z6, z6, pi, NULL, tau), C4G_ERR_ARG);
    ch.n = 6;
    {
        double big[6] = {1e200, 1e200, 1e200, 1e200, 1e200, 1e200};
        assert_int_equal(c4g_dyn_regressor(&ch, z6, big, z6, y, 360), C4G_ERR_NONFINITE);
    }
    assert_int_equal(c4g_dyn_params_from_com(1.0, NULL, ic, pi), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_params_from_com(-1.0, c, ic, pi), C4G_ERR_RANGE);
    assert_int_equal(c4g_dyn_params_from_com(NAN, c, ic, pi), C4G_ERR_NONFINITE);
    ic[4] = INFINITY;
    assert_int_equal(c4g_dyn_params_from_com(1.0, c, ic, pi), C4G_ERR_NONFINITE);
}

/* The once-checked model gives c4g_dyn_rnea's torques (with and without rotors), refuses
 * what c4g_dyn_rnea refuses per call at init instead, and will not run unchecked. */
static void test_model_checked_once(void **state)
{
    c4g_dyn_chain_t ch;
    c4g_dyn_model_t m, m0;
    double pi[60];
    double ia[6] = {0.1, 0.2, 0.05, 0.01, 0.02, 0.003};
    double tau[6], want[6];
    const double z6[6] = {0, 0, 0, 0, 0, 0};
    uint32_t seed = 29U;
    int t, k;
    (void)state;
    six_link(&ch);
    random_params(&seed, pi);
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, ia), C4G_OK);
    assert_int_equal(m.checked, C4G_DYN_CHECKED);
    assert_int_equal(c4g_dyn_model_init(&m0, &ch, pi, NULL), C4G_OK);
    for (t = 0; t < 20; t++) {
        double q[6], qd[6], qdd[6];
        for (k = 0; k < 6; k++) {
            q[k] = 3.0 * rnd(&seed);
            qd[k] = 2.0 * rnd(&seed);
            qdd[k] = 8.0 * rnd(&seed);
        }
        assert_int_equal(c4g_dyn_rnea(&ch, q, qd, qdd, pi, ia, want), C4G_OK);
        assert_int_equal(c4g_dyn_model_rnea(&m, q, qd, qdd, tau), C4G_OK);
        assert_memory_equal(tau, want, sizeof tau);
        assert_int_equal(c4g_dyn_rnea(&ch, q, qd, qdd, pi, NULL, want), C4G_OK);
        assert_int_equal(c4g_dyn_model_rnea(&m0, q, qd, qdd, tau), C4G_OK);
        for (k = 0; k < 6; k++) {
            assert_true(tau[k] == want[k]);
        }
    }
    /* the motion is still checked on every call */
    {
        double q[6] = {0, 0, NAN, 0, 0, 0};
        assert_int_equal(c4g_dyn_model_rnea(&m, q, z6, z6, tau), C4G_ERR_NONFINITE);
        assert_int_equal(c4g_dyn_model_rnea(&m, z6, z6, NULL, tau), C4G_ERR_NULL);
    }
    assert_int_equal(c4g_dyn_model_rnea(NULL, z6, z6, z6, tau), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_model_rnea(&m, z6, z6, z6, NULL), C4G_ERR_NULL);
    /* refused at init: what the per-call check would refuse */
    assert_int_equal(c4g_dyn_model_init(NULL, &ch, pi, ia), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_model_init(&m, NULL, pi, ia), C4G_ERR_NULL);
    assert_int_equal(c4g_dyn_model_init(&m, &ch, NULL, ia), C4G_ERR_NULL);
    pi[37] = NAN;
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, ia), C4G_ERR_NONFINITE);
    assert_int_equal(m.checked, 0U);
    assert_int_equal(c4g_dyn_model_rnea(&m, z6, z6, z6, tau), C4G_ERR_STATE);
    pi[37] = 0.5;
    ia[4] = INFINITY;
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, ia), C4G_ERR_NONFINITE);
    ia[4] = 0.02;
    ch.gravity[1] = NAN;
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, ia), C4G_ERR_NONFINITE);
    ch.gravity[1] = 0.0;
    ch.n = 8U;
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, ia), C4G_ERR_ARG);
    ch.n = 0U;
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, ia), C4G_ERR_ARG);
    ch.n = 6U;
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, ia), C4G_OK);
    /* a torque that overflows is still refused */
    pi[0] = 1e308;
    pi[10] = 1e308;
    ch.gravity[2] = -50.0;
    assert_int_equal(c4g_dyn_model_init(&m, &ch, pi, NULL), C4G_OK);
    assert_int_equal(c4g_dyn_model_rnea(&m, z6, z6, z6, tau), C4G_ERR_NONFINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pendulum),
        cmocka_unit_test(test_planar_two_conventions),
        cmocka_unit_test(test_regressor_equals_rnea),
        cmocka_unit_test(test_power_balance),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_model_checked_once),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
