/* SPDX-License-Identifier: MIT */
/* c4g-server's controllers (see c4g_controllers.h): pure functions of the configuration,
 * the controller's packet and the caller's per-axis state. No allocation, no I/O, loops
 * bounded by the trajectory's rows (binary search). */
#include "controllers.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define CTLR_PI 3.14159265358979323846
#define CTLR_NO_LIMIT 1e9 /* [A] when AzLim is not positive */

double ctlr_raised_cos(double amp, double f, double t)
{
    return amp * 0.5 * (1.0 - cos(2.0 * CTLR_PI * f * t));
}

/* Converting a double beyond float's range to float is undefined behaviour; the
 * feedforward scales the controller's own D2 by file coefficients, so saturate (the
 * safety filter then clamps the current to AzLim; NaN stays NaN and gives 505). */
static float sat_float(double x)
{
    if (x > FLT_MAX) {
        return FLT_MAX;
    }
    if (x < -FLT_MAX) {
        return -FLT_MAX;
    }
    return (float)x;
}

double ctlr_traj_at(const ctlr_traj_t *tr, uint32_t lax, double t, int *done)
{
    uint32_t lo = 0U, hi;
    *done = 0;
    if ((tr == NULL) || (tr->rows == 0U) || (lax >= tr->cols)) {
        *done = 1;
        return 0.0;
    }
    hi = tr->rows - 1U;
    if (t >= tr->t[hi]) {
        *done = 1;
        return (double)tr->q[hi][lax];
    }
    /* binary search the segment, then interpolate linearly: O(log rows) */
    while (hi - lo > 1U) {
        const uint32_t mid = (lo + hi) / 2U;
        if (tr->t[mid] <= t) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    if (t <= tr->t[lo]) {
        return (double)tr->q[lo][lax];
    }
    {
        const double w = (t - tr->t[lo]) / (tr->t[hi] - tr->t[lo]);
        return (double)tr->q[lo][lax] + w * ((double)tr->q[hi][lax] - (double)tr->q[lo][lax]);
    }
}

double ctlr_gen_offset(const ctlr_arm_cfg_t *A, const ctlr_traj_t *tr, uint32_t lax, double t,
                       int *done)
{
    *done = 0;
    if (A->src == CTLR_SRC_SINE) {
        const double f = (A->sine_freq > 0.0) ? A->sine_freq : 1.0;
        const double tend = A->sine_cycles / f;
        if (t >= tend) {
            t = tend;
            *done = 1;
        }
        return ctlr_raised_cos(A->sine_amp, f, t);
    }
    if (A->src == CTLR_SRC_FILE) {
        return ctlr_traj_at(tr, lax, t, done);
    }
    *done = (t >= A->duration) ? 1 : 0;
    return 0.0;
}

double ctlr_offset_profile(const ctlr_arm_cfg_t *A, double t, int *done)
{
    double x;
    *done = (t >= A->offset_ramp + A->offset_hold) ? 1 : 0;
    if (A->offset_ramp <= 0.0) {
        return A->offset_amp;
    }
    x = t / A->offset_ramp;
    if (x > 1.0) {
        x = 1.0;
    }
    return A->offset_amp * 0.5 * (1.0 - cos(CTLR_PI * x));
}

double ctlr_vel_add(const ctlr_arm_cfg_t *A, double t, int *done)
{
    const double f = (A->vel_freq > 0.0) ? A->vel_freq : 1.0;
    if (t < A->vel_cycles / f) {
        *done = 0;
        return A->vel_amp * sin(2.0 * CTLR_PI * f * t); /* zero mean over whole cycles */
    }
    *done = 1;
    return 0.0;
}

float ctlr_ff_current(const ctlr_ff_t *p, double v, double acc, double pos)
{
    const double sg = (v > 0.0) ? 1.0 : ((v < 0.0) ? -1.0 : 0.0);
    return sat_float(p->c0 + p->cv * v + p->cc * sg + p->ca * acc +
                     p->gs * sin(p->gscale * pos + p->gphase));
}

/* |x| <= lim when lim > 0; *hit when it had to be moved. */
static double clamp_range(double x, double lim, int *hit)
{
    if (lim > 0.0 && x > lim) {
        *hit = 1;
        return lim;
    }
    if (lim > 0.0 && x < -lim) {
        *hit = 1;
        return -lim;
    }
    return x;
}

float ctlr_ff_model_current(const ctlr_ff_t *p, double d2, double d2_prev, double dt, double q,
                            int have_q, int *clamped)
{
    const double T = (dt > 0.0) ? dt : 1e-3;
    double a = (d2 - d2_prev) / (T * T);
    /* the controller applies the reply on its next tick: predict that tick's velocity */
    double v = d2 / T + a * T;
    int hit = 0;
    v = clamp_range(v, p->model.v_max, &hit); /* the fit holds only inside its range */
    a = clamp_range(a, p->model.a_max, &hit);
    *clamped = hit;
    return sat_float(c4gh_ffm_current(&p->model, v, a, q, have_q));
}

float ctlr_ff_ctrl_current(const ctlr_ff_t *p, double d2, double d2_prev, double dt, double ext1,
                           double ext2, int *clamped)
{
    const double T = (dt > 0.0) ? dt : 1e-3;
    double a = (d2 - d2_prev) / (T * T);
    double v = d2 / T + a * T;
    int hit = 0;
    v = clamp_range(v, p->model.v_max, &hit);
    a = clamp_range(a, p->model.a_max, &hit);
    *clamped = hit;
    if (!isfinite(ext1) || !isfinite(ext2)) {
        return 0.0f;
    }
    return sat_float(c4gh_ffm_current_ctrl(&p->model, v, a, ext1, ext2));
}

double ctlr_pd(ctlr_axis_t *X, const ctlr_in_t *in, double ref, double vref,
               const c4g_ctrl_axis_t *r, double t)
{
    const ctlr_arm_cfg_t *A = in->cfg;
    const double e = ref - (double)r->actual_pos;
    const double lim_az = (in->az_lim > 0.0) ? in->az_lim : CTLR_NO_LIMIT;
    const double ilim = (A->i_max > 0.0) ? A->i_max : lim_az;
    double u, lim, eta = 1.0;
    X->integ += A->ki * e * in->dt;
    if (X->integ > ilim) {
        X->integ = ilim;
    } else if (X->integ < -ilim) {
        X->integ = -ilim;
    }
    u = A->kp * e + A->kd * (vref - (double)r->actual_vel) + X->integ;
    if (A->scs > 0.0 && t < A->scs) {
        eta = t / A->scs;
    }
    lim = lim_az * eta;
    if (u > lim) {
        X->integ -= u - lim; /* back-calculation: the integrator gives back the excess */
        u = lim;
    } else if (u < -lim) {
        X->integ -= u + lim;
        u = -lim;
    }
    return u;
}

int ctlr_is_open_mode(int32_t m)
{
    return (m == C4G_MODE_1) || (m == C4G_MODE_2) || (m == C4G_MODE_4) || (m == C4G_MODE_5) ||
           (m == C4G_MODE_7) || (m == C4G_MODE_8) || (m == C4G_MODE_9);
}

void ctlr_axis_reset(ctlr_axis_t *X)
{
    (void)memset(X, 0, sizeof *X);
    X->mode = -1;
}

int ctlr_axis_enter(ctlr_axis_t *X, int32_t mode, double anchor, const c4g_ctrl_axis_t *r)
{
    const int32_t old = X->mode;
    const int keep = (old == C4G_MODE_1 && mode == C4G_MODE_1_STANDBY) ||
                     (old == C4G_MODE_2 && mode == C4G_MODE_2_STANDBY) ||
                     (old == C4G_MODE_2_STANDBY && mode == C4G_MODE_2);
    X->mode = mode;
    if (keep) {
        return 0;
    }
    X->ticks = 0U;
    X->start = anchor;
    X->q_prev = 0.0;
    X->integ = (double)r->current_ref; /* bumpless: start from the SMP+ current */
    X->v_prev = (double)r->target_vel;
    X->done = 0;
    return 1;
}

/* Modes 4 (absolute target) and 5 (relative): the generator's offset. */
static int step_pos(ctlr_axis_t *X, const ctlr_in_t *in, int32_t pm, c4g_pc_axis_t *o, double t)
{
    int done = 1;
    const double q = in->driven ? ctlr_gen_offset(in->cfg, in->traj, in->lax, t, &done) : 0.0;
    const double dq = q - X->q_prev;
    if (pm == C4G_MODE_4) {
        o->target_pos = (float)(X->start + q); /* absolute */
    } else {
        o->target_pos = (float)dq;             /* relative: this tick's step */
    }
    o->target_vel = (float)dq;                 /* delta turns this tick */
    X->q_prev = q;
    return done;
}

/* Mode 7: per-tick position addition of the offset profile. */
static int step_offset(ctlr_axis_t *X, const ctlr_in_t *in, c4g_pc_axis_t *o, double t)
{
    int done = 1;
    const double off = in->driven ? ctlr_offset_profile(in->cfg, t, &done) : 0.0;
    o->target_pos = (float)(off - X->q_prev);
    X->q_prev = off;
    return done;
}

/* Mode 9: current feedforward on the SMP+ trajectory, for `duration`. */
static int step_ff(ctlr_axis_t *X, const ctlr_in_t *in, const c4g_ctrl_axis_t *r,
                   c4g_pc_axis_t *o, double t)
{
    const double v = (double)r->target_vel;
    const int done = (t >= in->cfg->duration) ? 1 : 0;
    o->current_add = 0.0f;
    if (in->driven && !done && in->ff != NULL && in->ff->set) {
        if (in->ff->kind == CTLR_FF_RIGID) {
            /* evaluated for the whole arm by the caller; none (0 A) when it failed */
            o->current_add = in->ff_cur_ok ? sat_float(in->ff_cur) : 0.0f;
            X->ff_flags = CTLR_FFF_MODEL | (in->ff_cur_clamped ? CTLR_FFF_CLAMPED : 0U);
        } else if (in->ff->kind == CTLR_FF_MODEL) {
            int clamped = 0;
            /* the mode's first packet has no previous velocity: no acceleration */
            const double prev = (X->ticks == 0U) ? v : X->v_prev;
            o->current_add =
                in->ff->model.ctrl
                    ? ctlr_ff_ctrl_current(in->ff, v, prev, in->dt, (double)r->ext[0],
                                           (double)r->ext[1], &clamped)
                    : ctlr_ff_model_current(in->ff, v, prev, in->dt, in->q_link, in->have_q,
                                            &clamped);
            X->ff_flags = CTLR_FFF_MODEL | (clamped ? CTLR_FFF_CLAMPED : 0U);
        } else {
            o->current_add = ctlr_ff_current(in->ff, v, v - X->v_prev, (double)r->target_pos);
        }
    }
    /* a model = ctrl file holds EXT1 already (k1 EXT1), a rigid-body file replaces it:
     * never twice */
    if (in->driven && !done && in->cfg->ff_ext1 && isfinite(r->ext[0]) &&
        !(in->ff != NULL && in->ff->set &&
          ((in->ff->kind == CTLR_FF_MODEL && in->ff->model.ctrl) || in->ff->kind == CTLR_FF_RIGID))) {
        /* the controller's own model current, which mode 9 no longer hands its drives
         * (manual 14.12.4): passed back through D5 */
        o->current_add += r->ext[0];
    }
    X->v_prev = v;
    return done;
}

/* Modes 1 and 11: PC trajectory (generator, or hold) and PC loops (PD + anti-windup). */
static int step_pc_loops(ctlr_axis_t *X, const ctlr_in_t *in, int32_t pm,
                         const c4g_ctrl_axis_t *r, c4g_pc_axis_t *o, double t)
{
    int done = 1;
    double q = X->q_prev;
    if (pm == C4G_MODE_1 && in->driven) {
        q = ctlr_gen_offset(in->cfg, in->traj, in->lax, t, &done);
        if (in->cfg->src != CTLR_SRC_NONE && t < in->cfg->duration) {
            done = 0; /* hold at least `duration` */
        }
    }
    o->target_pos = (float)(X->start + q);
    o->target_vel = (float)(q - X->q_prev);
    o->vel_add = 0.0f;
    o->current_add = (float)ctlr_pd(X, in, X->start + q, q - X->q_prev, r, t);
    X->q_prev = q;
    return done;
}

int ctlr_step(ctlr_axis_t *X, const ctlr_in_t *in, int32_t pm, const c4g_ctrl_axis_t *r,
              c4g_pc_axis_t *o)
{
    const double t = (double)X->ticks * in->dt;
    int done = 1;
    X->ff_flags = 0U;
    switch (pm) {
    case C4G_MODE_4:
    case C4G_MODE_5:
        done = step_pos(X, in, pm, o, t);
        break;
    case C4G_MODE_7:
        done = step_offset(X, in, o, t);
        break;
    case C4G_MODE_8:
        o->vel_add = in->driven ? (float)ctlr_vel_add(in->cfg, t, &done) : 0.0f;
        break;
    case C4G_MODE_9:
        done = step_ff(X, in, r, o, t);
        break;
    case C4G_MODE_1:
    case C4G_MODE_1_STANDBY:
        done = step_pc_loops(X, in, pm, r, o, t);
        break;
    case C4G_MODE_2:
    case C4G_MODE_2_STANDBY:
        /* SMP+ trajectory, PC loops: current from the PD on the SMP+ target. PDL2 ends
         * mode 2 by setting 12 (the engine refuses a PC exit from mode 2). */
        o->vel_add = 0.0f;
        o->current_add = (float)ctlr_pd(X, in, (double)r->target_pos, (double)r->target_vel,
                                        r, t);
        done = 0;
        break;
    default:
        break; /* the prepared reply is complete (echo, zero data, mode-10 copy) */
    }
    X->ticks++;
    return done;
}
