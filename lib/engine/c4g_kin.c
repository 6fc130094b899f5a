/* SPDX-License-Identifier: MIT */
/* Transformations under kinematic influences (manual chapter 19), in double precision.
 * Kr = Kr2 K1^-T; qm = Kr q / 2 pi + q0; q = 2 pi K1^T Kr2^-1 (qm - q0). K1 couples only the
 * wrist (axes 4, 5, 6: k54, k64, k65); auxiliary axes 7..10 have identity influence. */
#include "c4g_engine_util.h"

#define TWO_PI 6.283185307179586
#define N_MAIN 6U
#define AX4 3U
#define AX5 4U
#define AX6 5U

c4g_status_t c4g_kin_from_init(const c4g_init_t *init, uint32_t arm, c4g_kin_t *kin)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((init != NULL) && (kin != NULL)) {
        uint32_t i;
        st = C4G_OK;
        if (arm >= C4G_ARMS) {
            st = C4G_ERR_ARG;
        } else if ((init->period_ms < 1) || (init->period_ms > 1000)) {
            st = C4G_ERR_PERIOD;
        } else {
            for (i = 0U; i < C4G_AXES_PER_ARM; i++) {
                if ((c4g_f32_finite(init->tx_rate[arm][i]) == 0) ||
                    (c4g_f32_finite(init->cal_data[arm][i]) == 0) ||
                    (c4g_f32_finite(init->ax_info[arm][i]) == 0)) {
                    st = C4G_ERR_NONFINITE;
                }
            }
        }
        if (st == C4G_OK) {
            (void)memset(kin, 0, sizeof *kin);
            for (i = 0U; i < C4G_AXES_PER_ARM; i++) {
                kin->kr[i] = (double)init->tx_rate[arm][i];
                kin->cal[i] = (double)init->cal_data[arm][i];
                kin->linear[i] = C4G_KIN_ROTARY;
            }
            /* field facts: 0-based AxInfo[3], [4], [5] (the manual counts from 1). */
            kin->k54 = (double)init->ax_info[arm][AX4];
            kin->k64 = (double)init->ax_info[arm][AX5];
            kin->k65 = (double)init->ax_info[arm][AX6];
            kin->period_s = (double)init->period_ms / 1000.0;
        }
    }
    return st;
}

static int kin_finite(const c4g_kin_t *kin)
{
    int ok = 0;
    if ((eng_f64_finite(kin->k54) != 0) && (eng_f64_finite(kin->k64) != 0) &&
        (eng_f64_finite(kin->k65) != 0) && (eng_f64_finite(kin->period_s) != 0)) {
        ok = 1;
    }
    uint32_t i;
    for (i = 0U; i < C4G_AXES_PER_ARM; i++) {
        if ((eng_f64_finite(kin->kr[i]) == 0) || (eng_f64_finite(kin->cal[i]) == 0)) {
            ok = 0;
        }
    }
    return ok;
}

c4g_status_t c4g_kin_matrices(const c4g_kin_t *kin, c4g_kin_matrices_t *m)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((kin != NULL) && (m != NULL)) {
        st = C4G_ERR_NONFINITE;
        if (kin_finite(kin) != 0) {
            uint32_t i;
            (void)memset(m, 0, sizeof *m);
            for (i = 0U; i < N_MAIN; i++) {
                m->kr2[i][i] = kin->kr[i];
                m->k1[i][i] = 1.0;
                m->kr[i][i] = kin->kr[i];
            }
            m->k1[AX4][AX5] = kin->k54;
            m->k1[AX4][AX6] = kin->k64;
            m->k1[AX5][AX6] = kin->k65;
            /* Kr = Kr2 K1^-T: the closed form printed in chapter 19. */
            m->kr[AX5][AX4] = -kin->kr[AX5] * kin->k54;
            m->kr[AX6][AX4] = kin->kr[AX6] * ((kin->k65 * kin->k54) - kin->k64);
            m->kr[AX6][AX5] = -kin->kr[AX6] * kin->k65;
            st = C4G_OK;
        }
    }
    return st;
}

/* Common argument checks; every kr[0..n-1] must be non-zero (Kr invertible). */
static c4g_status_t conv_check(const c4g_kin_t *kin, const double *in, uint32_t n,
                               const double *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((kin != NULL) && (in != NULL) && (out != NULL)) {
        uint32_t i;
        st = C4G_OK;
        if ((n == 0U) || (n > C4G_AXES_PER_ARM)) {
            st = C4G_ERR_ARG;
        } else if (kin_finite(kin) == 0) {
            st = C4G_ERR_NONFINITE;
        } else {
            for (i = 0U; i < n; i++) {
                if (eng_f64_finite(in[i]) == 0) {
                    st = C4G_ERR_NONFINITE;
                } else if ((kin->kr[i] > 0.0) || (kin->kr[i] < 0.0)) {
                    /* usable ratio */
                } else {
                    st = (st == C4G_OK) ? C4G_ERR_SINGULAR : st;
                }
            }
        }
    }
    return st;
}

static double unit_scale(const c4g_kin_t *kin, uint32_t i)
{
    return (kin->linear[i] == C4G_KIN_LINEAR) ? 1.0 : TWO_PI;
}

static c4g_status_t all_finite(const double *v, uint32_t n)
{
    c4g_status_t st = C4G_OK;
    uint32_t i;
    for (i = 0U; i < n; i++) {
        if (eng_f64_finite(v[i]) == 0) {
            st = C4G_ERR_NONFINITE;
        }
    }
    return st;
}

/* x (link, per unit: rad/2pi or mm) -> motor without offsets: y = Kr x. */
static void kr_apply(const c4g_kin_t *kin, const double *x, uint32_t n, double *y)
{
    uint32_t i;
    for (i = 0U; i < n; i++) {
        y[i] = kin->kr[i] * x[i];
    }
    if (n > AX5) {
        y[AX5] = kin->kr[AX5] * (x[AX5] - (kin->k54 * x[AX4]));
    }
    if (n > AX6) {
        y[AX6] = kin->kr[AX6] *
                 (x[AX6] - (kin->k65 * x[AX5]) + (((kin->k65 * kin->k54) - kin->k64) * x[AX4]));
    }
}

/* y (motor, no offsets) -> x = K1^T Kr2^-1 y. */
static void kr_inverse(const c4g_kin_t *kin, const double *y, uint32_t n, double *x)
{
    uint32_t i;
    for (i = 0U; i < n; i++) {
        x[i] = y[i] / kin->kr[i];
    }
    if (n > AX6) {
        x[AX6] += (kin->k64 * x[AX4]) + (kin->k65 * x[AX5]);
    }
    if (n > AX5) {
        x[AX5] += kin->k54 * x[AX4];
    }
}

c4g_status_t c4g_kin_link_to_motor(const c4g_kin_t *kin, const double *q, uint32_t n,
                                   double *qm)
{
    c4g_status_t st = conv_check(kin, q, n, qm);
    if (st == C4G_OK) {
        double x[C4G_AXES_PER_ARM];
        double y[C4G_AXES_PER_ARM];
        uint32_t i;
        (void)memset(x, 0, sizeof x);
        (void)memset(y, 0, sizeof y);
        for (i = 0U; i < n; i++) {
            x[i] = q[i] / unit_scale(kin, i);
        }
        kr_apply(kin, x, n, y);
        for (i = 0U; i < n; i++) {
            y[i] += kin->cal[i];
        }
        st = all_finite(y, n);
        if (st == C4G_OK) {
            (void)memcpy(qm, y, n * sizeof y[0]);
        }
    }
    return st;
}

c4g_status_t c4g_kin_motor_to_link(const c4g_kin_t *kin, const double *qm, uint32_t n,
                                   double *q)
{
    c4g_status_t st = conv_check(kin, qm, n, q);
    if (st == C4G_OK) {
        double x[C4G_AXES_PER_ARM];
        double y[C4G_AXES_PER_ARM];
        uint32_t i;
        (void)memset(x, 0, sizeof x);
        (void)memset(y, 0, sizeof y);
        for (i = 0U; i < n; i++) {
            y[i] = qm[i] - kin->cal[i];
        }
        kr_inverse(kin, y, n, x);
        for (i = 0U; i < n; i++) {
            x[i] *= unit_scale(kin, i);
        }
        st = all_finite(x, n);
        if (st == C4G_OK) {
            (void)memcpy(q, x, n * sizeof x[0]);
        }
    }
    return st;
}

c4g_status_t c4g_kin_link_vel_to_motor(const c4g_kin_t *kin, const double *v, uint32_t n,
                                       double *vm)
{
    c4g_status_t st = conv_check(kin, v, n, vm);
    if (st == C4G_OK) {
        double x[C4G_AXES_PER_ARM];
        double y[C4G_AXES_PER_ARM];
        uint32_t i;
        (void)memset(x, 0, sizeof x);
        (void)memset(y, 0, sizeof y);
        /* per second -> per controller tick */
        for (i = 0U; i < n; i++) {
            x[i] = (v[i] * kin->period_s) / unit_scale(kin, i);
        }
        kr_apply(kin, x, n, y);
        st = all_finite(y, n);
        if (st == C4G_OK) {
            (void)memcpy(vm, y, n * sizeof y[0]);
        }
    }
    return st;
}

c4g_status_t c4g_kin_motor_vel_to_link(const c4g_kin_t *kin, const double *vm, uint32_t n,
                                       double *v)
{
    c4g_status_t st = conv_check(kin, vm, n, v);
    if ((st == C4G_OK) && (kin->period_s <= 0.0)) {
        st = C4G_ERR_PERIOD;
    }
    if (st == C4G_OK) {
        double x[C4G_AXES_PER_ARM];
        uint32_t i;
        (void)memset(x, 0, sizeof x);
        kr_inverse(kin, vm, n, x);
        for (i = 0U; i < n; i++) {
            x[i] = (x[i] * unit_scale(kin, i)) / kin->period_s;
        }
        st = all_finite(x, n);
        if (st == C4G_OK) {
            (void)memcpy(v, x, n * sizeof x[0]);
        }
    }
    return st;
}
