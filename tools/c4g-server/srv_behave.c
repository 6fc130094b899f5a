/* SPDX-License-Identifier: MIT */
/* The server's behaviours (per arm, chosen by the mode the controller reports) on top of
 * the library's loop object: c4g_loop_rx steps the control engine and prepares the reply
 * (mode echo, mode-10 copy, required fields marked unset), the controllers
 * (tools/c4g-server/controllers.h) fill the fields of the mode, requests (exit from
 * open, 505, 508, active freezing) go through c4g_engine_request_*, and c4g_loop_reply
 * applies the packet rules and the PC-side safety filter. Runs on the real-time path: no
 * allocation, no I/O (log lines go to the caller's logger, srv_log), loops bounded by
 * the axis count. */
#include "srv_core.h"

#include <math.h>
#include <string.h>

void srv_behave_reset(srv_t *S)
{
    uint32_t i;
    for (i = 0U; i < C4G_MAX_AXES; i++) {
        ctlr_axis_reset(&S->ax[i]);
    }
}

static double period_s(const srv_t *S)
{
    const int32_t p = srv_init_packet(S)->period_ms;
    return (p > 0) ? (double)p * 1e-3 : 1e-3;
}

static void axis_in_of(const srv_t *S, const c4g_axis_map_t *m, const c4g_init_t *init, double dt,
                       uint32_t i, ctlr_in_t *in);

/* The controller's inputs for OPEN axis i. */
static void axis_in(const srv_t *S, uint32_t i, ctlr_in_t *in)
{
    axis_in_of(S, srv_map(S), srv_init_packet(S), period_s(S), i, in);
}

/* Which model axis i's mode 9 evaluates, once per entry: rigid (the arm's rigid-body
 * file), axis, ctrl, the line format, or only EXT1 (--ff-ext1). */
static void ff_entry_log(srv_t *S, uint32_t i, uint64_t t_ns)
{
    ctlr_in_t in;
    const char *what;
    const char *ext1 = "";
    axis_in(S, i, &in);
    if (!in.driven) {
        return;
    }
    if (in.ff == NULL || in.ff->set == 0) {
        if (in.cfg->ff_ext1) {
            srv_log(S, t_ns, "axis %u: mode 9 feedforward: EXT1 (the controller's model, --ff-ext1; "
                    "no file sets this axis)", (unsigned)i + 1U);
        }
        return;
    }
    if (in.ff->kind == CTLR_FF_RIGID) {
        const uint32_t arm = srv_map(S)->arm_of[i];
        srv_log(S, t_ns, "axis %u: mode 9 feedforward: model rigid (arm %u's rigid-body model, joint %u of %u, %s)%s%s",
                (unsigned)i + 1U, (unsigned)arm + 1U, (unsigned)in.lax + 1U, (unsigned)S->cfg.rigid[arm].kin.n,
                S->cfg.ff_path[S->cfg.rigid_file[arm]],
                (S->ffr_ok[arm] > 0) ? "" : "; NOT evaluated: the init packet's transmission does not fit it (0 A)",
                in.cfg->ff_ext1 ? "; --ff-ext1 not added (the model replaces EXT1)" : "");
        return;
    }
    what = (in.ff->kind != CTLR_FF_MODEL) ? "line-format parameters"
           : in.ff->model.ctrl           ? "model ctrl (k1 (EXT1 - in) + k2 in + friction, in from EXT2)"
                                         : "model axis (Ja a + friction + gravity)";
    if (in.cfg->ff_ext1) {
        ext1 = (in.ff->kind == CTLR_FF_MODEL && in.ff->model.ctrl) ? "; --ff-ext1 not added (the model holds EXT1)"
                                                                   : "; + EXT1 (--ff-ext1)";
    }
    srv_log(S, t_ns, "axis %u: mode 9 feedforward: %s%s", (unsigned)i + 1U, what, ext1);
}

/* The axis reports another mode than on its previous packet: log, count, restart its
 * controller from where it stood before the mode. */
static void enter_mode(srv_t *S, uint32_t i, int32_t mode, const c4g_ctrl_axis_t *r, uint64_t t_ns)
{
    const int32_t old = S->ax[i].mode;
    float anchor = r->target_pos;
    if ((old == C4G_MODE_DRIVING_ON) && (mode != C4G_MODE_DRIVING_ON)) {
        srv_log(S, t_ns, "axis %u: drive-on finished (501 -> %d)", (unsigned)i + 1U, (int)mode);
    }
    if (old >= 0) {
        S->stats.mode_changes++;
    }
    if (old >= 0 && (S->cfg.verbose || srv_map(S)->logical_of[i] == 0U)) {
        srv_log(S, t_ns, "axis %u: mode %d -> %d", (unsigned)i + 1U, (int)old, (int)mode);
    }
    /* where the axis stood when this mode began (after a passive freezing or a stand-by:
     * where it stands now, not where it stood in mode 0) */
    (void)c4g_engine_anchor(srv_engine(S), i, &anchor);
    (void)ctlr_axis_enter(&S->ax[i], mode, (double)anchor, r);
    if (mode == C4G_MODE_9) {
        ff_entry_log(S, i, t_ns);
    }
}

/* An identified model fits the period it was measured at; another one is worth a word,
 * not a refusal (the model's units are per second). Once per file and init packet. */
static void ff_period_check(srv_t *S, uint64_t t_ns)
{
    const int32_t p = srv_init_packet(S)->period_ms;
    uint32_t warned = 0U;
    uint32_t a, l;
    for (a = 0U; a < C4G_ARMS; a++) {
        for (l = 0U; l < C4G_AXES_PER_ARM; l++) {
            const srv_ff_t *f = &S->cfg.ff[a][l];
            if (f->set == 0 || f->kind != CTLR_FF_MODEL || f->file >= SRV_MAX_FF_FILES ||
                ((warned >> f->file) & 1U) != 0U || fabs(f->period_ms - (double)p) < 1e-9) {
                continue;
            }
            warned |= 1U << f->file;
            srv_log(S, t_ns, "warning: feedforward %s: model identified at a %g ms period, the "
                    "controller runs at %d ms; applied anyway", S->cfg.ff_path[f->file],
                    f->period_ms, (int)p);
        }
    }
}

/* The rigid-body files against the init packet's transmission (c4gh_ffr_setup). The
 * axes of the arm that are not open stand at their calibration with ratio 1, as for the
 * link angles (link_ahead). */
static void ff_rigid_init(srv_t *S, uint64_t t_ns)
{
    const c4g_engine_t *E = srv_engine_view(S);
    const c4g_axis_map_t *m = srv_map(S);
    uint32_t a, l;
    memset(S->ffr_logged, 0, sizeof S->ffr_logged);
    for (a = 0U; a < C4G_ARMS; a++) {
        c4g_kin_t kin;
        S->ffr_ok[a] = 0;
        if (!S->cfg.rigid[a].rigid) {
            continue;
        }
        S->ffr_ok[a] = -1;
        if (E->kin_ok[a] == 0U) {
            srv_log(S, t_ns, "warning: feedforward %s: arm %u has no kinematics in the init packet: "
                    "the rigid-body model is not evaluated (0 A)", S->cfg.ff_path[S->cfg.rigid_file[a]],
                    (unsigned)a + 1U);
            continue;
        }
        kin = E->kin[a];
        for (l = 0U; l < C4G_AXES_PER_ARM; l++) {
            if (m->open_of[a][l] >= m->n_axes) {
                kin.kr[l] = 1.0;
            }
        }
        if (c4gh_ffr_setup(&S->ffr[a], &S->cfg.rigid[a], &kin) != 0) {
            srv_log(S, t_ns, "warning: feedforward %s: the transmission of arm %u is singular for its "
                    "rigid-body model: not evaluated (0 A)", S->cfg.ff_path[S->cfg.rigid_file[a]],
                    (unsigned)a + 1U);
            continue;
        }
        S->ffr_ok[a] = 1;
    }
}

/* After an accepted init packet (the loop started the control engine on it): the user
 * limits per axis. */
void srv_behave_init(srv_t *S, uint64_t t_ns)
{
    const c4g_axis_map_t *m = srv_map(S);
    uint32_t i;
    srv_behave_reset(S);
    if (!srv_state(S).engine_ready) {
        /* the loop keeps only the count: ask the engine again for the reason */
        static c4g_engine_t scratch;
        const c4g_status_t st = c4g_engine_init(&scratch, srv_init_packet(S), &S->loop_cfg.engine);
        srv_log(S, t_ns, "engine refused the init packet: %s", c4g_strerror(st));
        return;
    }
    for (i = 0U; i < m->n_axes; i++) {
        const uint32_t arm = m->arm_of[i], lax = m->logical_of[i];
        const srv_arm_cfg_t *A = &S->cfg.arm[arm];
        c4g_axis_limits_t lim;
        c4g_status_t st;
        memset(&lim, 0, sizeof lim);
        lim.follow_error = (float)A->fe_limit;
        lim.max_step = (float)A->max_step;
        if (A->have_stroke) {
            lim.motor_min = (float)A->pos_min[lax];
            lim.motor_max = (float)A->pos_max[lax];
        }
        st = c4g_engine_set_limits(srv_engine(S), arm, lax, &lim);
        if (st != C4G_OK) {
            srv_log(S, t_ns, "limits of arm %u axis %u refused: %s", (unsigned)arm + 1U,
                    (unsigned)lax + 1U, c4g_strerror(st));
        }
    }
    ff_period_check(S, t_ns);
    ff_rigid_init(S, t_ns);
}

/* The controller's inputs for OPEN axis i, from the session's map, init packet and period
 * (run_axes looks them up once a tick, not once an axis). */
static void axis_in_of(const srv_t *S, const c4g_axis_map_t *m, const c4g_init_t *init, double dt,
                       uint32_t i, ctlr_in_t *in)
{
    const uint32_t arm = m->arm_of[i];
    const uint32_t lax = m->logical_of[i];
    in->cfg = &S->cfg.arm[arm];
    in->traj = &srv_traj[arm];
    in->ff = &S->cfg.ff[arm][lax];
    in->lax = lax;
    in->dt = dt;
    in->az_lim = (double)init->az_lim[arm][lax];
    in->driven = ((S->cfg.arm[arm].axes >> lax) & 1U) != 0U;
    in->q_link = 0.0;
    in->have_q = 0;
    in->ff_cur = 0.0;
    in->ff_cur_ok = 0;
    in->ff_cur_clamped = 0;
}

/* Link angles of a tick, per arm, computed when an identified model first needs them;
 * the same for a rigid-body model's currents. */
typedef struct link_cache {
    int state[C4G_ARMS];                       /* 0 not yet, 1 q holds them, -1 none */
    double q[C4G_ARMS][C4G_AXES_PER_ARM];
    int rstate[C4G_ARMS];                      /* 0 not yet, 1 rout holds them, -1 failed */
    c4gh_ffr_out_t rout[C4G_ARMS];
} link_cache_t;

/* Link angles [rad] of the arm's logical axes one tick ahead (D1 + D2), through the arm's
 * kinematics (the control engine built them with c4g_kin_from_init from the init
 * packet). An axis that is not open stands at its calibration position with ratio 1:
 * it moves no other axis and cannot make the transform singular. 0, or -1: none. */
static int link_ahead(const srv_t *S, const c4g_ctrl_packet_t *rx, uint32_t arm,
                      double q[C4G_AXES_PER_ARM])
{
    const c4g_engine_t *E = srv_engine_view(S);
    const c4g_axis_map_t *m = srv_map(S);
    c4g_kin_t kin;
    double qm[C4G_AXES_PER_ARM];
    uint32_t l, n = 0U;
    if (!srv_state(S).engine_ready || E->kin_ok[arm] == 0U) {
        return -1;
    }
    kin = E->kin[arm];
    for (l = 0U; l < C4G_AXES_PER_ARM; l++) {
        const uint32_t i = m->open_of[arm][l];
        if (i < rx->n_axes) {
            qm[l] = (double)rx->ax[i].target_pos + (double)rx->ax[i].target_vel;
            n = l + 1U;
        } else {
            kin.kr[l] = 1.0;
            qm[l] = kin.cal[l];
        }
    }
    return (n > 0U && c4g_kin_motor_to_link(&kin, qm, n, q) == C4G_OK) ? 0 : -1;
}

/* The link angle of OPEN axis i for its identified model's gravity terms. */
static void model_angle(const srv_t *S, const c4g_ctrl_packet_t *rx, uint32_t i,
                        link_cache_t *lc, ctlr_in_t *in)
{
    const uint32_t arm = srv_map(S)->arm_of[i];
    if (lc->state[arm] == 0) {
        lc->state[arm] = (link_ahead(S, rx, arm, lc->q[arm]) == 0) ? 1 : -1;
    }
    in->have_q = (lc->state[arm] > 0) ? 1 : 0;
    in->q_link = in->have_q ? lc->q[arm][in->lax] : 0.0;
}

/* The arm's rigid-body model on this tick: motor positions one tick ahead (D1 + D2), the
 * velocity and acceleration of the tick the reply is applied on, as ctlr_ff_model_current
 * predicts them from D2 and the axis's previous D2. An axis that enters its mode on this
 * packet (its controller restarts: no previous D2) counts no acceleration. */
static int rigid_arm(const srv_t *S, const c4g_ctrl_packet_t *rx, uint32_t arm, c4gh_ffr_out_t *o)
{
    const c4g_axis_map_t *m = srv_map(S);
    const c4gh_ffr_t *r = &S->ffr[arm];
    const double T = r->kin.period_s;
    double qm[C4G_DYN_MAX_LINKS], vm[C4G_DYN_MAX_LINKS], am[C4G_DYN_MAX_LINKS];
    uint32_t l;
    for (l = 0U; l < r->n; l++) {
        const uint32_t i = m->open_of[arm][l];
        if (i < rx->n_axes) {
            const c4g_ctrl_axis_t *x = &rx->ax[i];
            const ctlr_axis_t *X = &S->ax[i];
            const double d2 = (double)x->target_vel;
            const double prev = (X->mode != x->mode || X->ticks == 0U) ? d2 : X->v_prev;
            am[l] = (d2 - prev) / (T * T);
            vm[l] = d2 / T + am[l] * T;
            qm[l] = (double)x->target_pos + d2;
        } else {
            qm[l] = r->kin.cal[l];
            vm[l] = 0.0;
            am[l] = 0.0;
        }
    }
    return c4gh_ffr_current(r, qm, vm, am, o);
}

static const char *const ffr_what[3] = {"angle", "velocity", "acceleration"};

/* Axis i's share of its arm's rigid-body model; each clamp (and a failure) logged once
 * per axis and session, with the value. */
static void rigid_current(srv_t *S, uint32_t i, const link_cache_t *lc,
                          ctlr_in_t *in, uint64_t t_ns)
{
    const uint32_t arm = srv_map(S)->arm_of[i];
    const uint32_t l = in->lax;
    const c4gh_ffm_file_t *f = &S->cfg.rigid[arm];
    const c4gh_ffr_out_t *o = &lc->rout[arm];
    unsigned b;
    if (S->ffr_ok[arm] <= 0 || l >= S->ffr[arm].n) {
        return;
    }
    if (lc->rstate[arm] == 0) {
        return; /* not computed: the axis is not in mode 9 */
    }
    if (lc->rstate[arm] < 0) {
        if ((S->ffr_logged[i] & 8U) == 0U) {
            S->ffr_logged[i] |= 8U;
            srv_log(S, t_ns, "axis %u: rigid model: not evaluable on this packet (a value not finite): 0 A "
                    "(logged once per axis)", (unsigned)i + 1U);
        }
        return;
    }
    in->ff_cur = o->cur[l];
    in->ff_cur_ok = 1;
    for (b = 0U; b < 3U; b++) {
        const unsigned bit = 1U << b;
        const double v = (b == 0U) ? o->q[l] : ((b == 1U) ? o->qd[l] : o->qdd[l]);
        double lo, hi;
        if ((o->clamped[l] & bit) == 0U) {
            continue;
        }
        in->ff_cur_clamped = 1;
        if ((S->ffr_logged[i] & bit) != 0U) {
            continue;
        }
        S->ffr_logged[i] |= bit;
        lo = (b == 0U) ? f->q_min[l] : -((b == 1U) ? f->qd_max[l] : f->qdd_max[l]);
        hi = (b == 0U) ? f->q_max[l] : ((b == 1U) ? f->qd_max[l] : f->qdd_max[l]);
        srv_log(S, t_ns, "axis %u: rigid model: joint %s %.6g %s outside the fitted range %.6g..%.6g: "
                "clamped (logged once per axis and session)", (unsigned)i + 1U, ffr_what[b], v,
                (b == 0U) ? "rad" : ((b == 1U) ? "rad/s" : "rad/s^2"), lo, hi);
    }
}

/* Every axis's controller; arm_done[a] stays 1 when every open axis of arm a is done, and
 * arm_open[a] says whether it has one. */
static void run_axes(srv_t *S, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx, uint64_t t_ns,
                     uint32_t arm_open[C4G_ARMS], uint32_t arm_done[C4G_ARMS])
{
    const c4g_axis_map_t *m = srv_map(S);
    const c4g_init_t *init = srv_init_packet(S);
    const double dt = period_s(S);
    link_cache_t lc;
    uint32_t i;
    memset(lc.state, 0, sizeof lc.state);
    memset(lc.rstate, 0, sizeof lc.rstate);
    /* the rigid models first: they read every axis's previous D2, which ctlr_step updates */
    for (i = 0U; i < rx->n_axes; i++) {
        const uint32_t arm = m->arm_of[i];
        if (tx->ax[i].mode == C4G_MODE_9 && S->ffr_ok[arm] > 0 && lc.rstate[arm] == 0) {
            lc.rstate[arm] = (rigid_arm(S, rx, arm, &lc.rout[arm]) == 0) ? 1 : -1;
        }
    }
    for (i = 0U; i < rx->n_axes; i++) {
        const c4g_ctrl_axis_t *r = &rx->ax[i];
        ctlr_axis_t *X = &S->ax[i];
        ctlr_in_t in;
        int done;
        if (r->mode != X->mode) {
            enter_mode(S, i, r->mode, r, t_ns);
        }
        axis_in_of(S, m, init, dt, i, &in);
        if (tx->ax[i].mode == C4G_MODE_9 && in.ff->set != 0 && in.ff->kind == CTLR_FF_MODEL &&
            !in.ff->model.ctrl) {
            model_angle(S, rx, i, &lc, &in);
        }
        if (tx->ax[i].mode == C4G_MODE_9 && in.ff->set != 0 && in.ff->kind == CTLR_FF_RIGID && in.driven) {
            rigid_current(S, i, &lc, &in, t_ns);
        }
        done = ctlr_step(X, &in, tx->ax[i].mode, r, &tx->ax[i]);
        if ((X->ff_flags & CTLR_FFF_MODEL) != 0U) {
            S->stats.ff_model_ticks++;
            S->stats.ff_model_clamped += ((X->ff_flags & CTLR_FFF_CLAMPED) != 0U) ? 1U : 0U;
        }
        if (!ctlr_is_open_mode(r->mode) || r->mode == C4G_MODE_2) {
            continue;
        }
        arm_open[m->arm_of[i]] = 1U;
        if (!done) {
            arm_done[m->arm_of[i]] = 0U;
        } else if (!X->done) {
            X->done = 1;
            if (in.lax == 0U || S->cfg.verbose) {
                srv_log(S, t_ns, "axis %u: mode %d behaviour done after %u ticks",
                        (unsigned)i + 1U, (int)r->mode, (unsigned)X->ticks);
            }
        }
    }
}

/* EXIT_FROM_OPEN on the arms whose behaviour is done (once: not while one is under way). */
static void request_exits(srv_t *S, const uint32_t arm_open[C4G_ARMS],
                          const uint32_t arm_done[C4G_ARMS], uint64_t t_ns)
{
    uint32_t a;
    for (a = 0U; a < C4G_ARMS; a++) {
        bool pending = true;
        if (!arm_open[a] || !arm_done[a] || !S->cfg.arm[a].exit_open ||
            c4g_loop_exit_pending(&S->loop, a, &pending) != C4G_OK || pending) {
            continue;
        }
        if (c4g_engine_request_exit(srv_engine(S), a) == C4G_OK) {
            srv_log(S, t_ns, "arm %u: EXIT_FROM_OPEN requested", (unsigned)a + 1U);
        }
    }
}

/* Test hooks: requests through the engine, like a user program would. */
static void test_hooks(srv_t *S, uint64_t t_ns)
{
    const c4g_axis_map_t *m = srv_map(S);
    c4g_engine_t *ctl = srv_engine(S);
    uint32_t a;
    c4g_status_t st;
    if (S->cfg.inject_at == S->cyc_k && S->cfg.inject_mode != 0) {
        const uint32_t ia = ((uint32_t)S->cfg.inject_axis < m->n_axes) ? m->arm_of[S->cfg.inject_axis] : 0U;
        st = (S->cfg.inject_mode == C4G_MODE_DRIVE_OFF) ? c4g_engine_request_drive_off(ctl, ia)
                                                        : c4g_engine_request_follow_error(ctl, ia);
        S->safety.injected++;
        srv_log(S, t_ns, "injected %d on arm %u: %s", S->cfg.inject_mode, (unsigned)ia + 1U,
                c4g_strerror(st));
    }
    if (S->cfg.freeze_at == S->cyc_k) {
        for (a = 0U; a < C4G_ARMS; a++) {
            if (m->n_axes_arm[a] > 0U) {
                st = c4g_engine_request_freeze(ctl, a);
                srv_log(S, t_ns, "active freezing requested on arm %u: %s", (unsigned)a + 1U,
                        c4g_strerror(st));
            }
        }
    }
    if (S->thaw) {
        for (a = 0U; a < C4G_ARMS; a++) {
            if (m->n_axes_arm[a] > 0U) {
                (void)c4g_engine_request_exit(ctl, a);
            }
        }
        srv_log(S, t_ns, "active freezing over: EXIT_FROM_OPEN requested");
        S->thaw = 0;
    }
}

void srv_behave(srv_t *S, const c4g_loop_event_t *ev, uint64_t t_ns)
{
    uint32_t arm_open[C4G_ARMS] = {0U, 0U, 0U, 0U};
    uint32_t arm_done[C4G_ARMS] = {1U, 1U, 1U, 1U};
    if ((ev->engine_events & C4G_CEV_DRIVING_ON_END) != 0U) {
        S->stats.drive_on_end++;
        srv_log(S, t_ns, "drive-on finished (501 left)");
    }
    run_axes(S, ev->pkt, ev->cmd, t_ns, arm_open, arm_done);
    request_exits(S, arm_open, arm_done, t_ns);
    test_hooks(S, t_ns);
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

static void note_flags(srv_t *S, uint32_t i, uint32_t f, float fe, const c4g_pc_packet_t *tx,
                       uint64_t t_ns)
{
    srv_safety_t *sf = &S->safety;
    c4g_axis_limits_t lim;
    if (f == 0U) {
        return;
    }
    memset(&lim, 0, sizeof lim);
    (void)c4g_loop_limits(&S->loop, i, &lim);
    if ((f & C4G_SF_FOLLOW_ERROR) != 0U) {
        safety_event(S, t_ns, "following error", i, (double)fe, (double)lim.follow_error);
    }
    if ((f & C4G_SF_FE_SENT) != 0U) sf->follow_error++;
    if ((f & C4G_SF_DRIVE_OFF) != 0U) sf->drive_off++;
    if ((f & C4G_SF_CURRENT) != 0U) sf->cur_saturated++;
    if ((f & C4G_SF_DCURRENT) != 0U) sf->delta_clamped++;
    if ((f & (C4G_SF_STROKE | C4G_SF_STROKE_JOINT)) != 0U) {
        sf->stroke++;
        safety_event(S, t_ns, "stroke end", i, (double)tx->ax[i].target_pos,
                     (double)lim.motor_max);
    }
    if ((f & (C4G_SF_STEP | C4G_SF_VELOCITY)) != 0U) {
        sf->continuity++;
        safety_event(S, t_ns, "reference step/velocity limited", i, (double)tx->ax[i].target_pos,
                     (double)lim.max_step);
    }
    if ((f & (C4G_SF_NONFINITE | C4G_SF_MISSING)) != 0U) {
        sf->nonfinite++;
        safety_event(S, t_ns, (f & C4G_SF_MISSING) ? "missing mode data" : "non-finite value", i,
                     0.0, 0.0);
    }
}

void srv_behave_done(srv_t *S, const c4g_engine_report_t *rep, uint64_t t_ns)
{
    const c4g_pc_packet_t *tx = srv_reply_packet(S);
    uint32_t i, a;
    const c4g_status_t fin = srv_state(S).finish_status;
    if (fin != C4G_OK) {
        srv_log(S, t_ns, "engine: %s", c4g_strerror(fin));
    }
    for (a = 0U; a < C4G_ARMS; a++) {
        if (c4g_arm_byte(tx->infpar, a) == C4G_EXIT_FROM_OPEN) {
            S->stats.exits_sent[a]++;
        }
    }
    for (i = 0U; i < tx->n_axes; i++) {
        note_flags(S, i, rep->axis_flags[i], rep->follow_err[i], tx, t_ns);
    }
}
