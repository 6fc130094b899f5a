/* SPDX-License-Identifier: MIT */
/* c4g-server behaviours (per arm, chosen by the mode the controller reports) on top of
 * the library's control layer: c4g_engine_step prepares the reply (mode echo, mode-10 copy,
 * required fields marked unset), a behaviour fills the fields of the mode, requests
 * (exit from open, 505, 508, active freezing) go through c4g_engine_request_*, and
 * c4g_engine_finish applies the packet rules and the PC-side safety filter. Runs on the
 * real-time path: no allocation, no I/O (log lines go through the rtlog ring), loops
 * bounded by the axis count. */
#include "srv.h"

#include <float.h>
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
        srv_log(S, t_ns, "axis %u: drive-on finished (501 -> %d)", (unsigned)i + 1U, (int)mode);
    }
    if (old >= 0) {
        S->stats.mode_changes++;
    }
    if (old >= 0 && (S->cfg.verbose || S->session.map.logical_of[i] == 0U)) {
        srv_log(S, t_ns, "axis %u: mode %d -> %d", (unsigned)i + 1U, (int)old, (int)mode);
    }
    /* Stand-by modes continue the regulator of their main mode. */
    if (!((old == C4G_MODE_1 && mode == C4G_MODE_1_STANDBY) ||
          (old == C4G_MODE_2 && mode == C4G_MODE_2_STANDBY) ||
          (old == C4G_MODE_2_STANDBY && mode == C4G_MODE_2))) {
        float anchor = r->target_pos;
        X->ticks = 0U;
        /* where the axis stood in mode 0, not this one packet's target: the packet that
         * opens the mode may be the second one the controller sent in it */
        (void)c4g_engine_anchor(&S->ctl, i, &anchor);
        X->start = (double)anchor;
        X->q_prev = 0.0;
        X->have_ref_prev = 0;
        X->integ = (double)r->current_ref; /* bumpless: start from the SMP+ current */
        X->v_prev = (double)r->target_vel;
        X->done = 0;
    }
    X->mode = mode;
}


/* Control layer set-up after an accepted init packet: state machines, user limits. */
void srv_behave_init(srv_t *S, uint64_t t_ns)
{
    const c4g_axis_map_t *m = &S->session.map;
    c4g_status_t st;
    uint32_t i;
    srv_behave_reset(S);
    (void)c4g_engine_config_default(&S->engine_cfg);
    S->engine_cfg.start_ns = (uint64_t)(S->cfg.arm[0].scs * 1e9);
    st = c4g_engine_init(&S->ctl, &S->session.init, &S->engine_cfg);
    S->ctl_ok = (st == C4G_OK);
    if (!S->ctl_ok) {
        srv_log(S, t_ns, "control layer refused the init packet: %s", c4g_strerror(st));
        return;
    }
    for (i = 0U; i < m->n_axes; i++) {
        const uint32_t arm = m->arm_of[i], lax = m->logical_of[i];
        const srv_arm_cfg_t *A = &S->cfg.arm[arm];
        c4g_axis_limits_t lim;
        memset(&lim, 0, sizeof lim);
        lim.follow_error = (float)A->fe_limit;
        lim.max_step = (float)A->max_step;
        if (A->have_stroke) {
            lim.motor_min = (float)A->pos_min[lax];
            lim.motor_max = (float)A->pos_max[lax];
        }
        st = c4g_engine_set_limits(&S->ctl, arm, lax, &lim);
        if (st != C4G_OK) {
            srv_log(S, t_ns, "limits of arm %u axis %u refused: %s", (unsigned)arm + 1U,
                    (unsigned)lax + 1U, c4g_strerror(st));
        }
    }
}

/* Fill the fields mode @p pm requires for axis i; returns 1 when its behaviour is done. */
static int fill_axis(srv_t *S, uint32_t i, int32_t pm, const c4g_ctrl_axis_t *r, c4g_pc_axis_t *o,
                     int driven, double t)
{
    const c4g_axis_map_t *m = &S->session.map;
    srv_axis_t *X = &S->ax[i];
    const uint32_t arm = m->arm_of[i];
    const uint32_t lax = m->logical_of[i];
    const srv_arm_cfg_t *A = &S->cfg.arm[arm];
    int done = 1;
    switch (pm) {
    case C4G_MODE_4:
    case C4G_MODE_5: {
        const double q = driven ? gen_offset(A, arm, lax, t, &done) : 0.0;
        const double dq = q - X->q_prev;
        if (pm == C4G_MODE_4) {
            o->target_pos = (float)(X->start + q); /* absolute */
        } else {
            o->target_pos = (float)dq;             /* relative: this tick's step */
        }
        o->target_vel = (float)dq;                 /* delta turns this tick */
        X->q_prev = q;
        break;
    }
    case C4G_MODE_7: {
        const double off = driven ? offset_profile(A, t, &done) : 0.0;
        o->target_pos = (float)(off - X->q_prev);  /* per-tick position addition */
        X->q_prev = off;
        break;
    }
    case C4G_MODE_8: {
        const double f = (A->vel_freq > 0.0) ? A->vel_freq : 1.0;
        o->vel_add = 0.0f;
        if (driven && t < A->vel_cycles / f) {
            done = 0;
            o->vel_add = (float)(A->vel_amp * sin(2.0 * PI * f * t)); /* zero mean */
        }
        break;
    }
    case C4G_MODE_9: {
        const srv_ff_t *p = &S->cfg.ff[arm][lax];
        const double v = (double)r->target_vel;
        o->current_add = 0.0f;
        done = (t >= A->duration) ? 1 : 0;
        if (driven && !done && p->set) {
            const double acc = v - X->v_prev;
            const double sg = (v > 0.0) ? 1.0 : ((v < 0.0) ? -1.0 : 0.0);
            o->current_add = sat_float(p->c0 + p->cv * v + p->cc * sg + p->ca * acc +
                                       p->gs * sin(p->gscale * (double)r->target_pos + p->gphase));
        }
        X->v_prev = v;
        break;
    }
    case C4G_MODE_1:
    case C4G_MODE_1_STANDBY: {
        /* PC trajectory (generator, or hold) and PC loops (PD + anti-windup). */
        double q = X->q_prev;
        if (pm == C4G_MODE_1 && driven) {
            q = gen_offset(A, arm, lax, t, &done);
            if (A->src != SRC_NONE && t < A->duration) {
                done = 0; /* hold at least `duration` */
            }
        }
        o->target_pos = (float)(X->start + q);
        o->target_vel = (float)(q - X->q_prev);
        o->vel_add = 0.0f;
        o->current_add = (float)pd_current(S, i, A, X->start + q, q - X->q_prev, r, t);
        X->q_prev = q;
        break;
    }
    case C4G_MODE_2:
    case C4G_MODE_2_STANDBY:
        /* SMP+ trajectory, PC loops: current from the PD on the SMP+ target. PDL2 ends
         * mode 2 by setting 12 (the control layer refuses a PC exit from mode 2). */
        o->vel_add = 0.0f;
        o->current_add = (float)pd_current(S, i, A, (double)r->target_pos, (double)r->target_vel,
                                           r, t);
        done = 0;
        break;
    default:
        break; /* the prepared reply is complete (echo, zero data, mode-10 copy) */
    }
    return done;
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

static void note_flags(srv_t *S, uint32_t i, uint32_t f, float fe, const c4g_ctrl_packet_t *rx,
                       const c4g_pc_packet_t *tx, uint64_t t_ns)
{
    srv_safety_t *sf = &S->safety;
    const uint32_t arm = S->session.map.arm_of[i], lax = S->session.map.logical_of[i];
    if (f == 0U) {
        return;
    }
    if ((f & C4G_SF_FOLLOW_ERROR) != 0U) {
        safety_event(S, t_ns, "following error", i, (double)fe, (double)S->ctl.lim[i].follow_error);
    }
    if ((f & C4G_SF_FE_SENT) != 0U) sf->follow_error++;
    if ((f & C4G_SF_DRIVE_OFF) != 0U) sf->drive_off++;
    if ((f & C4G_SF_CURRENT) != 0U) sf->cur_saturated++;
    if ((f & C4G_SF_DCURRENT) != 0U) sf->delta_clamped++;
    if ((f & (C4G_SF_STROKE | C4G_SF_STROKE_JOINT)) != 0U) {
        sf->stroke++;
        safety_event(S, t_ns, "stroke end", i, (double)tx->ax[i].target_pos,
                     (double)S->ctl.lim[i].motor_max);
    }
    if ((f & (C4G_SF_STEP | C4G_SF_VELOCITY)) != 0U) {
        sf->continuity++;
        safety_event(S, t_ns, "reference step/velocity limited", i, (double)tx->ax[i].target_pos,
                     (double)S->ctl.lim[i].max_step);
    }
    if ((f & (C4G_SF_NONFINITE | C4G_SF_MISSING)) != 0U) {
        sf->nonfinite++;
        safety_event(S, t_ns, (f & C4G_SF_MISSING) ? "missing mode data" : "non-finite value", i,
                     0.0, 0.0);
    }
    (void)rx;
    (void)arm;
    (void)lax;
}

/* Build the reply to one cyclic packet. Returns 0 (tx ready to encode), -1 when the
 * control layer refused the packet (tx is then the neutral reply). */
int srv_reply(srv_t *S, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx, uint64_t t_ns)
{
    const c4g_axis_map_t *m = &S->session.map;
    const double dt = period_s(S);
    c4g_engine_report_t rep;
    uint32_t arm_open[C4G_ARMS] = {0U, 0U, 0U, 0U};
    uint32_t arm_done[C4G_ARMS] = {1U, 1U, 1U, 1U};
    uint32_t i, a;
    c4g_status_t st;

    if (!S->ctl_ok || c4g_engine_step(&S->ctl, rx, t_ns, tx, &rep) != C4G_OK) {
        (void)c4g_pc_reply_neutral(rx, tx);
        return -1;
    }
    if ((rep.events & C4G_CEV_DRIVING_ON_END) != 0U) {
        S->stats.drive_on_end++;
        srv_log(S, t_ns, "drive-on finished (501 left)");
    }
    for (i = 0U; i < rx->n_axes; i++) {
        const c4g_ctrl_axis_t *r = &rx->ax[i];
        srv_axis_t *X = &S->ax[i];
        const uint32_t arm = m->arm_of[i];
        const uint32_t lax = m->logical_of[i];
        const int driven = ((S->cfg.arm[arm].axes >> lax) & 1U) != 0U;
        int done;
        if (r->mode != X->mode) {
            enter_mode(S, i, r->mode, r, t_ns);
        }
        done = fill_axis(S, i, tx->ax[i].mode, r, &tx->ax[i], driven, (double)X->ticks * dt);
        X->ticks++;
        if (is_open_mode(r->mode) && r->mode != C4G_MODE_2) {
            arm_open[arm] = 1U;
            if (!done) {
                arm_done[arm] = 0U;
            } else if (!X->done) {
                X->done = 1;
                if (lax == 0U || S->cfg.verbose) {
                    srv_log(S, t_ns, "axis %u: mode %d behaviour done after %u ticks",
                            (unsigned)i + 1U, (int)r->mode, (unsigned)X->ticks);
                }
            }
        }
    }
    for (a = 0U; a < C4G_ARMS; a++) {
        S->arm_busy[a] = arm_open[a];
        if (arm_open[a] && arm_done[a] && S->cfg.arm[a].exit_open &&
            S->ctl.arm[a].exit_req == 0U && S->ctl.arm[a].leaving == 0U) {
            st = c4g_engine_request_exit(&S->ctl, a);
            if (st == C4G_OK) {
                srv_log(S, t_ns, "arm %u: EXIT_FROM_OPEN requested", (unsigned)a + 1U);
            }
        }
    }
    /* test hooks: requests through the control layer, like a user program would */
    if (S->cfg.inject_at == S->cyc_k && S->cfg.inject_mode != 0) {
        const uint32_t ia = ((uint32_t)S->cfg.inject_axis < m->n_axes) ? m->arm_of[S->cfg.inject_axis] : 0U;
        st = (S->cfg.inject_mode == C4G_MODE_DRIVE_OFF) ? c4g_engine_request_drive_off(&S->ctl, ia)
                                                        : c4g_engine_request_follow_error(&S->ctl, ia);
        S->safety.injected++;
        srv_log(S, t_ns, "injected %d on arm %u: %s", S->cfg.inject_mode, (unsigned)ia + 1U,
                c4g_strerror(st));
    }
    if (S->cfg.freeze_at == S->cyc_k) {
        for (a = 0U; a < C4G_ARMS; a++) {
            if (m->n_axes_arm[a] > 0U) {
                st = c4g_engine_request_freeze(&S->ctl, a);
                srv_log(S, t_ns, "active freezing requested on arm %u: %s", (unsigned)a + 1U,
                        c4g_strerror(st));
            }
        }
    }
    if (S->thaw) {
        for (a = 0U; a < C4G_ARMS; a++) {
            if (m->n_axes_arm[a] > 0U) {
                (void)c4g_engine_request_exit(&S->ctl, a);
            }
        }
        srv_log(S, t_ns, "active freezing over: EXIT_FROM_OPEN requested");
        S->thaw = 0;
    }
    st = c4g_engine_finish(&S->ctl, rx, tx, &rep);
    if (st != C4G_OK) {
        srv_log(S, t_ns, "control layer: %s", c4g_strerror(st));
    }
    for (a = 0U; a < C4G_ARMS; a++) {
        if (c4g_arm_byte(tx->infpar, a) == C4G_EXIT_FROM_OPEN) {
            S->stats.exits_sent[a]++;
        }
    }
    for (i = 0U; i < rx->n_axes; i++) {
        note_flags(S, i, rep.axis_flags[i], rep.follow_err[i], rx, tx, t_ns);
    }
    return 0;
}
