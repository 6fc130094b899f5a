/* SPDX-License-Identifier: MIT */
/* model = rigid-body-1's evaluation (c4gh_ffmodel.h): the controller's motor-side target
 * through the arm's transmission to the link side, clamped to the range the fit holds
 * in, the rigid-body torques (c4g_dyn_model_rnea, on the parameters checked once at
 * setup) plus the rotors, back to motor torques and currents, plus each motor's friction
 * and offset. No allocation, no I/O; every loop is
 * bounded by C4G_DYN_MAX_LINKS. */
#include "c4gh_ffmodel.h"

#include <math.h>
#include <string.h>

#define FFR_TWO_PI 6.283185307179586

int c4gh_ffr_setup(c4gh_ffr_t *r, const c4gh_ffm_file_t *m, const c4g_kin_t *kin)
{
    const double T = kin->period_s;
    uint32_t i, j;
    memset(r, 0, sizeof *r);
    if (!m->rigid || m->kin.n < 1U || m->kin.n > C4G_DYN_MAX_LINKS || !(T > 0.0)) {
        return -1;
    }
    /* the parameters are constant: checked here, once, not by every tick's rnea */
    if (c4g_dyn_model_init(&r->dyn, &m->kin.chain, m->pi, m->ia) != C4G_OK) {
        return -1;
    }
    r->m = m;
    r->kin = *kin;
    r->n = m->kin.n;
    /* the transmission is linear: a unit velocity gives a column (turns per tick <-> rad/s) */
    for (j = 0U; j < r->n; j++) {
        double e[C4G_DYN_MAX_LINKS];
        double y[C4G_DYN_MAX_LINKS];
        memset(e, 0, sizeof e);
        e[j] = 1.0;
        if (c4g_kin_link_vel_to_motor(kin, e, r->n, y) != C4G_OK) {
            return -1;
        }
        for (i = 0U; i < r->n; i++) {
            r->kr[i][j] = (y[i] * FFR_TWO_PI) / T;
        }
        if (c4g_kin_motor_vel_to_link(kin, e, r->n, y) != C4G_OK) {
            return -1;
        }
        for (i = 0U; i < r->n; i++) {
            r->kinv[i][j] = (y[i] * T) / FFR_TWO_PI;
        }
    }
    return 0;
}

/* x into [lo, hi]; the bit in *hit when it had to move. */
static double ffr_clamp(double x, double lo, double hi, unsigned bit, unsigned *hit)
{
    if (x < lo) {
        *hit |= bit;
        return lo;
    }
    if (x > hi) {
        *hit |= bit;
        return hi;
    }
    return x;
}

int c4gh_ffr_current(const c4gh_ffr_t *r, const double *qm, const double *vm, const double *am,
                     c4gh_ffr_out_t *o)
{
    const c4gh_ffm_file_t *m = r->m;
    const uint32_t n = r->n;
    double q[C4G_DYN_MAX_LINKS], qd[C4G_DYN_MAX_LINKS], qdd[C4G_DYN_MAX_LINKS];
    double vmc[C4G_DYN_MAX_LINKS];
    unsigned any = 0U;
    uint32_t i, k;
    memset(o, 0, sizeof *o);
    if (m == NULL || n == 0U || c4g_kin_motor_to_link(&r->kin, qm, n, o->q) != C4G_OK) {
        return -1;
    }
    for (i = 0U; i < n; i++) {
        double v = 0.0, a = 0.0;
        for (k = 0U; k < n; k++) {
            v += r->kinv[i][k] * vm[k];
            a += r->kinv[i][k] * am[k];
        }
        o->qd[i] = v * FFR_TWO_PI;
        o->qdd[i] = a * FFR_TWO_PI;
        /* the fit holds only inside the range it saw: hold the state at its edge */
        q[i] = ffr_clamp(o->q[i], m->q_min[i], m->q_max[i], C4GH_FFR_Q, &o->clamped[i]);
        qd[i] = ffr_clamp(o->qd[i], -m->qd_max[i], m->qd_max[i], C4GH_FFR_QD, &o->clamped[i]);
        qdd[i] = ffr_clamp(o->qdd[i], -m->qdd_max[i], m->qdd_max[i], C4GH_FFR_QDD, &o->clamped[i]);
        any |= o->clamped[i];
    }
    if (c4g_dyn_model_rnea(&r->dyn, q, qd, qdd, o->tau) != C4G_OK) {
        memset(o->tau, 0, sizeof o->tau);
        return -1;
    }
    for (k = 0U; k < n; k++) {
        vmc[k] = vm[k];
        if ((any & C4GH_FFR_QD) != 0U) {
            /* friction at the motor velocity of the clamped joint velocities */
            double v = 0.0;
            for (i = 0U; i < n; i++) {
                v += r->kr[k][i] * qd[i];
            }
            vmc[k] = v / FFR_TWO_PI;
        }
    }
    for (k = 0U; k < n; k++) {
        double t = 0.0; /* tau_m = Kr^-T tau */
        for (i = 0U; i < n; i++) {
            t += r->kinv[i][k] * o->tau[i];
        }
        o->cur[k] = t / m->kin.j[k].kt + c4gh_ffm_current(&m->ax[k], vmc[k], 0.0, 0.0, 0);
        if (!isfinite(o->cur[k])) {
            memset(o->cur, 0, sizeof o->cur);
            return -1;
        }
    }
    return 0;
}
