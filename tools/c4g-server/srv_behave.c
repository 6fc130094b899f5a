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

static void axis_in(const srv_t *S, uint32_t i, ctlr_in_t *in);

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
        ctlr_in_t in;
        axis_in(S, i, &in);
        if (in.driven && in.ff != NULL && in.ff->set != 0) {
            /* which model this axis's mode 9 evaluates, once per entry */
            srv_log(S, t_ns, "axis %u: mode 9 feedforward: %s%s", (unsigned)i + 1U,
                    (in.ff->kind != CTLR_FF_MODEL) ? "line-format parameters"
                    : in.ff->model.ctrl           ? "model ctrl (k1 (EXT1 - in) + k2 in + friction, in from EXT2)"
                                                  : "model axis (Ja a + friction + gravity)",
                    (in.ff->kind == CTLR_FF_MODEL && in.ff->model.ctrl && in.cfg->ff_ext1)
                        ? "; --ff-ext1 not added (the model holds EXT1)"
                        : "");
        }
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
}

/* The controller's inputs for OPEN axis i. */
static void axis_in(const srv_t *S, uint32_t i, ctlr_in_t *in)
{
    const c4g_axis_map_t *m = srv_map(S);
    const uint32_t arm = m->arm_of[i];
    const uint32_t lax = m->logical_of[i];
    in->cfg = &S->cfg.arm[arm];
    in->traj = &srv_traj[arm];
    in->ff = &S->cfg.ff[arm][lax];
    in->lax = lax;
    in->dt = period_s(S);
    in->az_lim = (double)srv_init_packet(S)->az_lim[arm][lax];
    in->driven = ((S->cfg.arm[arm].axes >> lax) & 1U) != 0U;
    in->q_link = 0.0;
    in->have_q = 0;
}

/* Link angles of a tick, per arm, computed when an identified model first needs them. */
typedef struct link_cache {
    int state[C4G_ARMS];                       /* 0 not yet, 1 q holds them, -1 none */
    double q[C4G_ARMS][C4G_AXES_PER_ARM];
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

/* Every axis's controller; arm_done[a] stays 1 when every open axis of arm a is done, and
 * arm_open[a] says whether it has one. */
static void run_axes(srv_t *S, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx, uint64_t t_ns,
                     uint32_t arm_open[C4G_ARMS], uint32_t arm_done[C4G_ARMS])
{
    link_cache_t lc;
    uint32_t i;
    memset(lc.state, 0, sizeof lc.state);
    for (i = 0U; i < rx->n_axes; i++) {
        const c4g_ctrl_axis_t *r = &rx->ax[i];
        ctlr_axis_t *X = &S->ax[i];
        ctlr_in_t in;
        int done;
        if (r->mode != X->mode) {
            enter_mode(S, i, r->mode, r, t_ns);
        }
        axis_in(S, i, &in);
        if (tx->ax[i].mode == C4G_MODE_9 && in.ff->set != 0 && in.ff->kind == CTLR_FF_MODEL &&
            !in.ff->model.ctrl) {
            model_angle(S, rx, i, &lc, &in);
        }
        done = ctlr_step(X, &in, tx->ax[i].mode, r, &tx->ax[i]);
        if ((X->ff_flags & CTLR_FFF_MODEL) != 0U) {
            S->stats.ff_model_ticks++;
            S->stats.ff_model_clamped += ((X->ff_flags & CTLR_FFF_CLAMPED) != 0U) ? 1U : 0U;
        }
        if (!ctlr_is_open_mode(r->mode) || r->mode == C4G_MODE_2) {
            continue;
        }
        arm_open[srv_map(S)->arm_of[i]] = 1U;
        if (!done) {
            arm_done[srv_map(S)->arm_of[i]] = 0U;
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
