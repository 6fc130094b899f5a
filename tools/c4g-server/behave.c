/* SPDX-License-Identifier: MIT */
/* c4g-server behaviours (per arm, chosen by the mode the controller reports) and the
 * PC-side safety filter. Runs on the real-time path: no allocation, no I/O (log lines
 * go through the rtlog ring), loops bounded by the axis count. */
#include "srv.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

srv_traj_t srv_traj[C4G_ARMS];

void srv_behave_reset(srv_t *S)
{
    uint32_t i;
    for (i = 0U; i < C4G_MAX_AXES; i++) {
        memset(&S->ax[i], 0, sizeof S->ax[i]);
        S->ax[i].mode = -1;
    }
    S->safety.drive_off_latched = 0;
}

static double period_s(const srv_t *S)
{
    const int32_t p = S->session.init.period_ms;
    return (p > 0) ? (double)p * 1e-3 : 1e-3;
}

/* Raised cosine: 0 at t = 0 with zero slope, peak amp at half a period. */
static double raised_cos(double amp, double f, double t)
{
    return amp * 0.5 * (1.0 - cos(2.0 * PI * f * t));
}

/* Generator offset for modes 1, 4, 5 at time t; sets *done past its end. */
static double gen_offset(const srv_arm_cfg_t *A, uint32_t arm, uint32_t lax, double t, int *done)
{
    double q = 0.0;
    *done = 0;
    if (A->src == SRC_SINE) {
        const double f = (A->sine_freq > 0.0) ? A->sine_freq : 1.0;
        const double tend = A->sine_cycles / f;
        if (t >= tend) {
            t = tend;
            *done = 1;
        }
        q = raised_cos(A->sine_amp, f, t);
    } else if (A->src == SRC_FILE) {
        const srv_traj_t *tr = &srv_traj[arm];
        if ((tr->rows == 0U) || (lax >= tr->cols)) {
            *done = 1;
        } else if (t >= tr->t[tr->rows - 1U]) {
            q = tr->q[tr->rows - 1U][lax];
            *done = 1;
        } else {
            /* binary search the segment, then interpolate linearly: O(log rows) */
            uint32_t lo = 0U, hi = tr->rows - 1U;
            while (hi - lo > 1U) {
                const uint32_t mid = (lo + hi) / 2U;
                if (tr->t[mid] <= t) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            if (t <= tr->t[lo]) {
                q = tr->q[lo][lax];
            } else {
                const double w = (t - tr->t[lo]) / (tr->t[hi] - tr->t[lo]);
                q = (double)tr->q[lo][lax] + w * ((double)tr->q[hi][lax] - (double)tr->q[lo][lax]);
            }
        }
    } else {
        *done = (t >= A->duration) ? 1 : 0;
    }
    return q;
}

/* Smooth 0 -> amp step (half cosine) over ramp seconds. */
static double offset_profile(const srv_arm_cfg_t *A, double t, int *done)
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
    return A->offset_amp * 0.5 * (1.0 - cos(PI * x));
}

static double azlim(const srv_t *S, uint32_t i)
{
    const c4g_axis_map_t *m = &S->session.map;
    return (double)S->session.init.az_lim[m->arm_of[i]][m->logical_of[i]];
}

/* PD(+I) joint controller with anti-windup (clamped integrator plus back-calculation)
 * and the soft-control-switching limiter (eta ramps 0 -> 1 over A->scs seconds). */
static double pd_current(srv_t *S, uint32_t i, const srv_arm_cfg_t *A, double ref, double vref,
                         const c4g_ctrl_axis_t *r, double t)
{
    srv_axis_t *X = &S->ax[i];
    const double dt = period_s(S);
    const double lim_az = azlim(S, i);
    const double e = ref - (double)r->actual_pos;
    const double ilim = (A->i_max > 0.0) ? A->i_max : ((lim_az > 0.0) ? lim_az : 1e9);
    double u, lim, eta = 1.0;
    X->integ += A->ki * e * dt;
    if (X->integ > ilim) {
        X->integ = ilim;
    } else if (X->integ < -ilim) {
        X->integ = -ilim;
    }
    u = A->kp * e + A->kd * (vref - (double)r->actual_vel) + X->integ;
    if (A->scs > 0.0 && t < A->scs) {
        eta = t / A->scs;
    }
    lim = (lim_az > 0.0) ? lim_az : 1e9;
    lim *= eta;
    if (u > lim) {
        X->integ -= u - lim; /* back-calculation: the integrator gives back the excess */
        u = lim;
    } else if (u < -lim) {
        X->integ -= u + lim;
        u = -lim;
    }
    return u;
}

static int is_open_mode(int32_t m)
{
    return (m == C4G_MODE_1) || (m == C4G_MODE_2) || (m == C4G_MODE_4) || (m == C4G_MODE_5) ||
           (m == C4G_MODE_7) || (m == C4G_MODE_8) || (m == C4G_MODE_9);
}

static void enter_mode(srv_t *S, uint32_t i, int32_t mode, const c4g_ctrl_axis_t *r, uint64_t t_ns)
{
    srv_axis_t *X = &S->ax[i];
    const int32_t old = X->mode;
    if ((old == C4G_MODE_DRIVING_ON) && (mode != C4G_MODE_DRIVING_ON)) {
        S->stats.drive_on_end++;
        srv_log(S, t_ns, "axis %u: drive-on finished (501 -> %d)", (unsigned)i + 1U, (int)mode);
    }
    if (old >= 0) {
        S->stats.mode_changes++;
        srv_log(S, t_ns, "axis %u: mode %d -> %d", (unsigned)i + 1U, (int)old, (int)mode);
    }
    /* Stand-by modes continue the regulator of their main mode. */
    if (!((old == C4G_MODE_1 && mode == C4G_MODE_1_STANDBY) ||
          (old == C4G_MODE_2 && mode == C4G_MODE_2_STANDBY) ||
          (old == C4G_MODE_2_STANDBY && mode == C4G_MODE_2))) {
        X->ticks = 0U;
        X->start = (double)r->target_pos;
        X->q_prev = 0.0;
        X->have_ref_prev = 0;
        X->integ = (double)r->current_ref; /* bumpless: start from the SMP+ current */
        X->v_prev = (double)r->target_vel;
        X->done = 0;
    }
    if (mode == C4G_MODE_0 || mode == C4G_MODE_0_DEBUG) {
        X->fe_latched = 0;
    }
    X->mode = mode;
}

void srv_behave_step(srv_t *S, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx, uint64_t t_ns)
{
    const c4g_axis_map_t *m = &S->session.map;
    const double dt = period_s(S);
    uint32_t arm_open[C4G_ARMS] = {0U, 0U, 0U, 0U};
    uint32_t arm_done[C4G_ARMS] = {1U, 1U, 1U, 1U};
    uint32_t i, a;

    /* Start from the field library's neutral reply: mode echo, INFPAR = CMD = 0, mode-10 copy. */
    (void)c4g_pc_reply_neutral(rx, tx);

    for (i = 0U; i < rx->n_axes; i++) {
        const c4g_ctrl_axis_t *r = &rx->ax[i];
        c4g_pc_axis_t *o = &tx->ax[i];
        srv_axis_t *X = &S->ax[i];
        const uint32_t arm = m->arm_of[i];
        const uint32_t lax = m->logical_of[i];
        const srv_arm_cfg_t *A = &S->cfg.arm[arm];
        const int driven = ((A->axes >> lax) & 1U) != 0U;
        double t;
        int done = 1;
        if (r->mode != X->mode) {
            enter_mode(S, i, r->mode, r, t_ns);
        }
        t = (double)X->ticks * dt;
        if (!driven || X->fe_latched) {
            X->ticks++;
            if (is_open_mode(r->mode)) {
                arm_open[arm] = 1U;
            }
            continue;
        }
        switch (r->mode) {
        case C4G_MODE_4:
        case C4G_MODE_5: {
            const double q = gen_offset(A, arm, lax, t, &done);
            const double ref = X->start + q;
            if (r->mode == C4G_MODE_4) {
                o->target_pos = (float)ref;          /* absolute */
            } else {
                o->target_pos = (float)q;            /* relative to the entry position */
            }
            o->target_vel = (float)(q - X->q_prev);  /* delta turns this tick */
            X->q_prev = q;
            break;
        }
        case C4G_MODE_7: {
            const double off = offset_profile(A, t, &done);
            o->target_pos = (float)(off - X->q_prev); /* per-tick position addition */
            X->q_prev = off;
            break;
        }
        case C4G_MODE_7_STANDBY:
        case C4G_MODE_7_STANDBY_EXIT:
            break; /* null delta */
        case C4G_MODE_8: {
            const double f = (A->vel_freq > 0.0) ? A->vel_freq : 1.0;
            const double tend = A->vel_cycles / f;
            if (t < tend) {
                done = 0;
                o->vel_add = (float)(A->vel_amp * sin(2.0 * PI * f * t)); /* zero mean */
            }
            break;
        }
        case C4G_MODE_9: {
            const srv_ff_t *p = &S->cfg.ff[arm][lax];
            done = (t >= A->duration) ? 1 : 0;
            if (!done && p->set) {
                const double v = (double)r->target_vel;
                const double acc = v - X->v_prev;
                const double sg = (v > 0.0) ? 1.0 : ((v < 0.0) ? -1.0 : 0.0);
                o->current_add = (float)(p->c0 + p->cv * v + p->cc * sg + p->ca * acc +
                                         p->gs * sin(p->gscale * (double)r->target_pos + p->gphase));
            }
            X->v_prev = (double)r->target_vel;
            break;
        }
        case C4G_MODE_1:
        case C4G_MODE_1_STANDBY: {
            /* PC trajectory (the generator, or hold) and PC loops. */
            double q = X->q_prev;
            if (r->mode == C4G_MODE_1) {
                q = gen_offset(A, arm, lax, t, &done);
                if (A->src != SRC_NONE && t < A->duration) {
                    done = 0; /* hold at least `duration` */
                }
            }
            {
                const double ref = X->start + q;
                const double vref = q - X->q_prev;
                o->target_pos = (float)ref;
                o->target_vel = (float)vref;
                o->vel_add = 0.0f;
                o->current_add = (float)pd_current(S, i, A, ref, vref, r, t);
            }
            X->q_prev = q;
            break;
        }
        case C4G_MODE_2:
        case C4G_MODE_2_STANDBY:
            /* SMP+ trajectory, PC loops: current from the PD on the SMP+ target. */
            done = (A->duration > 0.0 && t >= A->duration) ? 1 : 0;
            o->vel_add = 0.0f;
            o->current_add = (float)pd_current(S, i, A, (double)r->target_pos,
                                               (double)r->target_vel, r, t);
            break;
        default:
            break; /* neutral reply */
        }
        if (is_open_mode(r->mode)) {
            arm_open[arm] = 1U;
            if (!done) {
                arm_done[arm] = 0U;
            } else if (!X->done) {
                X->done = 1;
                srv_log(S, t_ns, "axis %u: mode %d behaviour done after %u ticks", (unsigned)i + 1U,
                        (int)r->mode, (unsigned)X->ticks);
            }
        }
        X->ticks++;
    }
    for (a = 0U; a < C4G_ARMS; a++) {
        S->arm_busy[a] = arm_open[a];
        if (arm_open[a] && arm_done[a] && S->cfg.arm[a].exit_open) {
            /* mode 2 ends with the controller's stand-by, unless a duration was given */
            tx->infpar = c4g_arm_byte_set(tx->infpar, a, (uint8_t)C4G_EXIT_FROM_OPEN);
            S->stats.exits_sent[a]++;
        }
    }
}

static void safety_event(srv_t *S, uint64_t t_ns, const char *what, uint32_t i, double v, double lim)
{
    if (S->safety.first[0] == '\0') {
        (void)snprintf(S->safety.first, sizeof S->safety.first,
                       "%s on axis %u (value %.6g, limit %.6g) at t=%.3f s", what,
                       (unsigned)i + 1U, v, lim, (double)(t_ns - S->t0_ns) * 1e-9);
    }
    srv_log(S, t_ns, "SAFETY %s axis %u value %.6g limit %.6g", what, (unsigned)i + 1U, v, lim);
}

/* PC-side safety filter (FIELD-FACTS "PC-side safety", manual 14.17.2 and 15.7).
 * Stand-in until the control layer's filter is available: same rules, applied to the
 * reply after the behaviours. */
void srv_safety_filter(srv_t *S, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx, uint64_t t_ns)
{
    const c4g_axis_map_t *m = &S->session.map;
    int drive_off = S->safety.drive_off_latched;
    uint32_t i;
    for (i = 0U; i < rx->n_axes; i++) {
        const c4g_ctrl_axis_t *r = &rx->ax[i];
        c4g_pc_axis_t *o = &tx->ax[i];
        srv_axis_t *X = &S->ax[i];
        const uint32_t arm = m->arm_of[i];
        const uint32_t lax = m->logical_of[i];
        const srv_arm_cfg_t *A = &S->cfg.arm[arm];
        const double lim = azlim(S, i);
        const int32_t mode = r->mode;
        int k;
        const float *f[5];
        f[0] = &o->target_pos; f[1] = &o->target_vel; f[2] = &o->measure;
        f[3] = &o->vel_add; f[4] = &o->current_add;
        for (k = 0; k < 5; k++) {
            if (!isfinite(*f[k])) {
                S->safety.nonfinite++;
                safety_event(S, t_ns, "non-finite reference", i, 0.0, 0.0);
                drive_off = 1;
            }
        }
        /* absolute current: saturate to +/- AzLim */
        if ((mode == C4G_MODE_1 || mode == C4G_MODE_2 || mode == C4G_MODE_1_STANDBY ||
             mode == C4G_MODE_2_STANDBY) && lim > 0.0 && fabs((double)o->current_add) > lim) {
            S->safety.cur_saturated++;
            o->current_add = (float)((o->current_add > 0.0f) ? lim : -lim);
        }
        /* delta current: SMP+ current + delta stays within +/- AzLim */
        if (mode == C4G_MODE_9 && lim > 0.0) {
            const double tot = (double)r->current_ref + (double)o->current_add;
            if (tot > lim) {
                S->safety.delta_clamped++;
                o->current_add = (float)(lim - (double)r->current_ref);
            } else if (tot < -lim) {
                S->safety.delta_clamped++;
                o->current_add = (float)(-lim - (double)r->current_ref);
            }
        }
        /* stroke ends and continuity of PC-generated absolute references (14.17.2) */
        if (mode == C4G_MODE_4 || mode == C4G_MODE_1) {
            const double ref = (double)o->target_pos;
            if (A->have_stroke && (ref < A->pos_min[lax] || ref > A->pos_max[lax])) {
                S->safety.stroke++;
                safety_event(S, t_ns, "stroke end", i, ref,
                             ref < A->pos_min[lax] ? A->pos_min[lax] : A->pos_max[lax]);
                drive_off = 1;
            }
            if (A->max_step > 0.0 && X->have_ref_prev && fabs(ref - X->ref_prev) > A->max_step) {
                S->safety.continuity++;
                safety_event(S, t_ns, "reference step", i, ref - X->ref_prev, A->max_step);
                drive_off = 1;
            }
            X->ref_prev = ref;
            X->have_ref_prev = 1;
        }
        /* following error |target - actual| > threshold -> 508 on this axis */
        if (mode == C4G_MODE_1 || mode == C4G_MODE_2 || mode == C4G_MODE_4 || mode == C4G_MODE_5 ||
            mode == C4G_MODE_1_STANDBY || mode == C4G_MODE_2_STANDBY || X->fe_latched) {
            const double thr = (A->fe_limit > 0.0) ? A->fe_limit
                                                   : (double)S->session.init.follow_error[arm][lax];
            const double fe = fabs((double)r->target_pos - (double)r->actual_pos);
            if ((thr > 0.0 && fe > thr) || X->fe_latched) {
                if (!X->fe_latched) {
                    safety_event(S, t_ns, "following error", i, fe, thr);
                }
                X->fe_latched = 1;
                if (mode != C4G_MODE_0 && mode != C4G_MODE_DRIVING_ON) {
                    o->mode = C4G_MODE_FOLLOW_ERROR;
                    S->safety.follow_error++;
                }
            }
        }
    }
    if (drive_off) {
        if (!S->safety.drive_off_latched) {
            srv_log(S, t_ns, "SAFETY drive off requested (505 on every axis)");
        }
        S->safety.drive_off_latched = 1;
        for (i = 0U; i < tx->n_axes; i++) {
            tx->ax[i].mode = C4G_MODE_DRIVE_OFF;
            tx->ax[i].target_pos = 0.0f;
            tx->ax[i].target_vel = 0.0f;
            tx->ax[i].measure = 0.0f;
            tx->ax[i].vel_add = 0.0f;
            tx->ax[i].current_add = 0.0f;
        }
        tx->infpar = 0U;
        S->safety.drive_off++;
        /* The request ends once the controller reports its drives off. */
        if (S->session.drives == 0U) {
            S->safety.drive_off_latched = 0;
        }
    }
}
