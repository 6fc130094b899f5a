/* SPDX-License-Identifier: MIT */
/* Control engine: init and user limits, the per-tick step (state machines, prepared reply
 * with the unset marker in every field the mode requires) and the PC requests. The finish
 * with the safety filter is c4g_safety.c. */
#include "c4g_engine_rules.h"

float c4g_unset(void)
{
    return eng_unset();
}

bool c4g_is_unset(float f)
{
    return eng_is_unset(f);
}

/* ------------------------------------------------------------------ init and limits */

c4g_status_t c4g_engine_init(c4g_engine_t *eng, const c4g_init_t *init, const c4g_engine_config_t *cfg)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((eng != NULL) && (init != NULL)) {
        c4g_engine_config_t c;
        (void)c4g_engine_config_default(&c);
        if (cfg != NULL) {
            c = *cfg;
        }
        st = c4g_engine_config_check(&c);
        if (st == C4G_OK) {
            st = c4g_init_validate(init, NULL);
        }
        if (st == C4G_OK) {
            (void)memset(eng, 0, sizeof *eng);
            eng->cfg = c;
            st = c4g_axis_map_build(init, &eng->map, NULL);
        }
        if (st == C4G_OK) {
            uint32_t a;
            uint32_t i;
            for (a = 0U; a < C4G_ARMS; a++) {
                (void)c4g_arm_sm_init(&eng->arm[a], eng->map.n_axes_arm[a]);
                eng->kin_ok[a] = 0U;
                if (c4g_kin_from_init(init, a, &eng->kin[a]) == C4G_OK) {
                    eng->kin_ok[a] = 1U;
                }
            }
            for (i = 0U; i < eng->map.n_axes; i++) {
                const uint32_t arm = eng->map.arm_of[i];
                const uint32_t lax = eng->map.logical_of[i];
                eng->ctrl_fe[i] = init->follow_error[arm][lax];
                eng->ctrl_az[i] = init->az_lim[arm][lax];
                eng->lim[i].follow_error = eng->ctrl_fe[i];
                eng->lim[i].current_max = eng->ctrl_az[i];
            }
        }
    }
    return st;
}

c4g_status_t c4g_engine_config_check(const c4g_engine_config_t *cfg)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (cfg != NULL) {
        st = C4G_OK;
        if ((c4g_f32_finite(cfg->moving_eps) == 0) || (cfg->moving_eps < 0.0F)) {
            st = C4G_ERR_ARG;
        }
    }
    return st;
}

/* A stroke [lo, hi] is off when both ends are 0, else it must be a real interval: an empty
 * or reversed one (a negative transmission ratio swaps the ends of a converted stroke) would
 * switch the check off silently. */
static c4g_status_t check_stroke(float lo, float hi)
{
    c4g_status_t st = C4G_OK;
    const uint32_t off = c4g_flag((c4g_f32_bits(lo) | c4g_f32_bits(hi) | 0x80000000U) ==
                                  0x80000000U); /* +0 or -0 at both ends */
    if ((off == 0U) && (!(lo < hi))) {
        st = C4G_ERR_LIMITS;
    }
    return st;
}

static c4g_status_t check_limits(const c4g_axis_limits_t *lim)
{
    c4g_status_t st = C4G_OK;
    const float v[8] = {lim->follow_error, lim->current_max, lim->max_step, lim->max_vel,
                        lim->motor_min, lim->motor_max, lim->joint_min, lim->joint_max};
    uint32_t k;
    for (k = 0U; k < 8U; k++) {
        if (c4g_f32_finite(v[k]) == 0) {
            st = C4G_ERR_NONFINITE;
        }
    }
    if ((st == C4G_OK) && ((lim->follow_error < 0.0F) || (lim->current_max < 0.0F) ||
                           (lim->max_step < 0.0F) || (lim->max_vel < 0.0F))) {
        st = C4G_ERR_LIMITS;
    }
    if (st == C4G_OK) {
        st = check_stroke(lim->motor_min, lim->motor_max);
    }
    if (st == C4G_OK) {
        st = check_stroke(lim->joint_min, lim->joint_max);
    }
    return st;
}

/* Joint stroke ends need every logical axis up to the arm's last open one, and its ratios. */
static c4g_status_t joint_span(const c4g_engine_t *eng, uint32_t arm, uint32_t *n_out)
{
    c4g_status_t st = C4G_OK;
    uint32_t n = 0U;
    uint32_t j;
    for (j = 0U; j < C4G_AXES_PER_ARM; j++) {
        if (eng->map.open_of[arm][j] != NO_AXIS) {
            n = j + 1U;
        }
    }
    for (j = 0U; (j < n) && (st == C4G_OK); j++) {
        if (eng->map.open_of[arm][j] == NO_AXIS) {
            st = C4G_ERR_NOT_OPEN;
        } else if ((eng->kin_ok[arm] == 0U) ||
                   ((eng->kin[arm].kr[j] <= 0.0) && (eng->kin[arm].kr[j] >= 0.0))) {
            st = C4G_ERR_SINGULAR;
        } else {
            /* usable */
        }
    }
    *n_out = n;
    return st;
}

c4g_status_t c4g_engine_set_limits(c4g_engine_t *eng, uint32_t arm, uint32_t axis,
                                const c4g_axis_limits_t *lim)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((eng != NULL) && (lim != NULL)) {
        uint32_t idx = NO_AXIS;
        uint32_t n = 0U;
        st = C4G_ERR_ARG;
        if ((arm < C4G_ARMS) && (axis < C4G_AXES_PER_ARM)) {
            idx = eng->map.open_of[arm][axis];
            st = (idx == NO_AXIS) ? C4G_ERR_NOT_OPEN : check_limits(lim);
        }
        if ((st == C4G_OK) && (lim->joint_min < lim->joint_max)) {
            st = joint_span(eng, arm, &n);
        }
        if (st == C4G_OK) {
            uint32_t i;
            eng->lim[idx] = *lim;
            eng->lim[idx].follow_error = tighter(eng->ctrl_fe[idx], lim->follow_error);
            eng->lim[idx].current_max = tighter(eng->ctrl_az[idx], lim->current_max);
            eng->priv.joint_on[arm] = 0U;
            for (i = 0U; i < eng->map.n_axes; i++) {
                if ((eng->map.arm_of[i] == arm) && (eng->lim[i].joint_min < eng->lim[i].joint_max)) {
                    eng->priv.joint_on[arm] = 1U;
                }
            }
            if (n > 0U) {
                eng->priv.n_joint[arm] = n;
            }
        }
    }
    return st;
}

/* ------------------------------------------------------------------ step */

/* The status of the first bad axis of a packet rx_scan flagged (axis count already checked). */
static CTL_COLD c4g_status_t check_rx(const c4g_engine_t *eng, const c4g_ctrl_packet_t *rx)
{
    c4g_status_t st = C4G_OK;
    uint32_t i;
    for (i = 0U; (i < C4G_MAX_AXES) && (i < rx->n_axes) && (st == C4G_OK); i++) {
        const c4g_ctrl_axis_t *a = &rx->ax[i];
        const uint32_t bad = eng_nonfinite_bit(a->target_pos) | eng_nonfinite_bit(a->target_vel) |
                             eng_nonfinite_bit(a->actual_pos) | eng_nonfinite_bit(a->actual_vel) |
                             eng_nonfinite_bit(a->current_ref) | eng_nonfinite_bit(a->ext[0]) |
                             eng_nonfinite_bit(a->ext[1]) | eng_nonfinite_bit(a->ext[2]);
        /* the mode prepared last tick is known: skip the lookup when it repeats */
        if ((a->mode != eng->priv.prep_mode[i]) && (!c4g_mode_is_known(a->mode))) {
            st = C4G_ERR_MODE;
        } else if (bad != 0U) {
            st = C4G_ERR_NONFINITE;
        } else {
            /* valid axis */
        }
    }
    return st;
}

/* Per-arm view of a packet: special > non-zero > 0 (the first of the highest class wins),
 * mixed when the arm's axes disagree, moving when SMP+ moves some axis. */
typedef struct arm_view {
    int32_t mode;
    int32_t first;
    uint32_t seen;
    uint32_t mixed;
    uint32_t moving;
} arm_view_t;

/* The aggregated modes, for packets where some arm is mixed (rx_scan did the rest). */
static CTL_COLD void arm_modes(const c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                               arm_view_t v[C4G_ARMS])
{
    int32_t m[C4G_ARMS] = {0, 0, 0, 0};
    uint32_t i;
    for (i = 0U; (i < C4G_MAX_AXES) && (i < rx->n_axes); i++) {
        const uint32_t a = eng->map.arm_of[i];
        const int32_t am = rx->ax[i].mode;
        if (am != m[a]) {
            if ((m[a] == C4G_MODE_0) ||
                ((c4g_mode_is_special(am)) && (!c4g_mode_is_special(m[a])))) {
                m[a] = am;
            }
        }
    }
    for (i = 0U; i < C4G_ARMS; i++) {
        v[i].mode = m[i];
    }
}

static inline uint32_t rx_axis_carry(const c4g_ctrl_axis_t *a)
{
    return eng_exp_carry(a->target_pos) | eng_exp_carry(a->target_vel) | eng_exp_carry(a->actual_pos) |
           eng_exp_carry(a->actual_vel) | eng_exp_carry(a->current_ref) | eng_exp_carry(a->ext[0]) |
           eng_exp_carry(a->ext[1]) | eng_exp_carry(a->ext[2]);
}

/* Fast pass over a packet of the context's axis count: 1 if some axis carries an unknown
 * mode or a non-finite value (check_rx then names the status), else 0 with the per-arm
 * first mode, mixed and moving filled (the aggregated mode is exact for unmixed arms).
 * @p check 0: the packet comes from the library's own decoder, which checked every value and
 * mode of it already (the loop object's path): only the arm view is built. */
static uint32_t rx_scan(const c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                        arm_view_t v[C4G_ARMS], uint32_t check)
{
    const uint32_t n = axes_in(eng->map.n_axes);
    uint32_t carry = 0U;
    uint32_t unknown = 0U;
    uint32_t i;
    (void)memset(v, 0, sizeof(arm_view_t) * C4G_ARMS);
    /* the value and mode checks in a pass of their own: the decoded path's view loop then
     * carries no per-axis test of @p check */
    if (check != 0U) {
        for (i = 0U; i < n; i++) {
            const c4g_ctrl_axis_t *a = &rx->ax[i];
            carry |= rx_axis_carry(a);
            /* the mode prepared last tick is known: skip the lookup when it repeats */
            if ((a->mode != eng->priv.prep_mode[i]) && (!c4g_mode_is_known(a->mode))) {
                unknown = 1U;
            }
        }
    }
    for (i = 0U; i < n; i++) {
        const c4g_ctrl_axis_t *a = &rx->ax[i];
        arm_view_t *w = &v[eng->map.arm_of[i]];
        const int32_t am = a->mode;
        if (w->seen == 0U) {
            w->first = am;
            w->mode = am;
            w->seen = 1U;
        } else if (am != w->first) {
            w->mixed = 1U;
        } else {
            /* same as the first axis */
        }
        if (eng_absf(a->target_vel) > eng->cfg.moving_eps) {
            w->moving = 1U;
        }
    }
    return (((carry & 0x80000000U) != 0U) || (unknown != 0U)) ? 1U : 0U;
}

/* The reply data c4g_engine_step prepares for @p mode: the required fields unset, the others
 * zero (mode 0' is copied back per tick instead). */
static CTL_COLD void prep_template(uint32_t rules, int32_t mode, c4g_pc_axis_t *t)
{
    const float u = eng_unset();
    (void)memset(t, 0, sizeof *t);
    t->mode = mode;
    if ((rules & C4G_MR_COPY) == 0U) {
        t->target_pos = ((rules & C4G_PCF_D1) != 0U) ? u : 0.0F;
        t->target_vel = ((rules & C4G_PCF_D2) != 0U) ? u : 0.0F;
        t->measure = ((rules & C4G_PCF_D3) != 0U) ? u : 0.0F;
        t->vel_add = ((rules & C4G_PCF_D4) != 0U) ? u : 0.0F;
        t->current_add = ((rules & C4G_PCF_D5) != 0U) ? u : 0.0F;
    }
}

/* Reply data of one axis before the caller fills it. */
static inline void prepare_axis(c4g_engine_t *eng, const int32_t over[C4G_ARMS], uint32_t some,
                                const c4g_ctrl_axis_t *rx, uint32_t i, c4g_pc_axis_t *tx)
{
    const int32_t mode = rx->mode; /* the PC echoes the mode (manual figure 24.3) */
    int32_t shown;
    /* The anchor: the controller's reference where the axis's current mode began (every
     * packet of mode 0 or 0'), whichever packet of the mode arrives first. After a passive
     * freezing or a stand-by the mode begins again where the axis stands, not in mode 0. */
    if ((mode != eng->priv.prep_mode[i]) || (mode == C4G_MODE_0) || (mode == C4G_MODE_0_DEBUG) ||
        (eng->priv.anchor_set[i] == 0U)) {
        eng->priv.anchor[i] = rx->target_pos;
        eng->priv.anchor_set[i] = 1U;
    }
    /* prep_mode / prep_rules / prep_tx start consistent (mode 0, no rules, zero data):
     * look up on change only */
    if (mode != eng->priv.prep_mode[i]) {
        eng->priv.prep_mode[i] = mode;
        eng->priv.prep_rules[i] = mode_rules(mode);
        prep_template(eng->priv.prep_rules[i], mode, &eng->priv.prep_tx[i]);
    }
    shown = (some != 0U) ? overlay_mode(eng, over, i, mode) : mode;
    if (shown != mode) {
        /* hold while a safety request goes out: what the controller applied, nothing new */
        hold_axis(eng->priv.prep_rules[i], rx, eng->lim[i].current_max, tx);
    } else if ((eng->priv.prep_rules[i] & C4G_MR_COPY) != 0U) {
        (void)memset(tx, 0, sizeof *tx);
        copy_back(rx, tx);
    } else {
        *tx = eng->priv.prep_tx[i]; /* required fields unset, the others zero */
    }
    tx->mode = shown;
}

/* The arms' state machines on this packet; a cleared latch clears its axes' FE latches. */
static void step_arms(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, const arm_view_t v[C4G_ARMS],
                      uint64_t now_ns, c4g_engine_report_t *r)
{
    uint32_t a;
    uint32_t i;
    for (a = 0U; a < C4G_ARMS; a++) {
        c4g_arm_sm_t *sm = &eng->arm[a];
        if (sm->n_axes > 0U) {
            uint32_t ev = 0U;
            /* the arm's INFPAR byte (byte a, as c4g_arm_byte), shifted here: no call per arm */
            const uint8_t drive = (uint8_t)((rx->infpar >> (a * 8U)) & 0xFFU);
            (void)c4g_arm_sm_update(sm, &eng->cfg, v[a].mode, v[a].mixed, drive, v[a].moving,
                                    now_ns, &ev);
            if ((ev & C4G_CEV_LATCH_CLEARED) != 0U) {
                uint32_t any = 0U;
                for (i = 0U; i < eng->map.n_axes; i++) {
                    eng->priv.fe_latch[i] = (eng->map.arm_of[i] == a) ? 0U : eng->priv.fe_latch[i];
                    any |= eng->priv.fe_latch[i];
                }
                eng->priv.fe_any = any;
            }
            r->arm_events[a] = ev;
            r->events |= ev;
        }
    }
}

/* The prepared reply: header and every axis. */
static inline void step_prepare(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                c4g_pc_packet_t *tx)
{
    const uint32_t n = axes_in(rx->n_axes);
    int32_t over[C4G_ARMS];
    uint32_t some;
    uint32_t same = 1U;
    uint32_t i;
    tx->num = rx->num;
    tx->infpar = 0U;
    tx->cmd = 0U;
    tx->n_axes = rx->n_axes;
    some = arm_overlays(eng, over);
    for (i = 0U; i < n; i++) {
        prepare_axis(eng, over, some, &rx->ax[i], i, &tx->ax[i]);
        same &= c4g_flag(eng->priv.prep_rules[i] == eng->priv.prep_rules[0]);
    }
    /* one rule word for every axis: the filter's loop for that mode (c4g_safety.c) */
    eng->priv.uni_rules = (same != 0U) ? eng->priv.prep_rules[0] : R_MIXED;
    eng->priv.stepped = 1U;
    eng->priv.step_num = rx->num;
}

static c4g_status_t engine_step(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, uint64_t now_ns,
                                c4g_pc_packet_t *tx, c4g_engine_report_t *rep, uint32_t check)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((eng != NULL) && (rx != NULL) && (tx != NULL)) {
        c4g_engine_report_t local;
        c4g_engine_report_t *r = rep;
        arm_view_t v[C4G_ARMS];
        if (r == NULL) {
            r = &local;
        }
        (void)memset(r, 0, sizeof *r);
        st = C4G_ERR_PACKET;
        if (rx->n_axes == eng->map.n_axes) {
            st = C4G_OK;
            if (rx_scan(eng, rx, v, check) != 0U) {
                st = check_rx(eng, rx);
            }
        }
        if (st == C4G_OK) {
            if ((v[0].mixed | v[1].mixed | v[2].mixed | v[3].mixed) != 0U) {
                arm_modes(eng, rx, v); /* special > non-zero > 0 on mixed arms */
            }
            step_arms(eng, rx, v, now_ns, r);
            step_prepare(eng, rx, tx);
        }
    }
    return st;
}

c4g_status_t c4g_engine_step(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, uint64_t now_ns,
                          c4g_pc_packet_t *tx, c4g_engine_report_t *rep)
{
    return engine_step(eng, rx, now_ns, tx, rep, 1U);
}

c4g_status_t c4g_engine_step_decoded(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                     uint64_t now_ns, c4g_pc_packet_t *tx,
                                     c4g_engine_report_t *rep)
{
    return engine_step(eng, rx, now_ns, tx, rep, 0U);
}

/* ------------------------------------------------------------------ requests */

static c4g_status_t request(c4g_engine_t *eng, uint32_t arm, c4g_req_kind_t kind, int32_t mode)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (eng != NULL) {
        st = C4G_ERR_ARG;
        if (arm < C4G_ARMS) {
            st = c4g_arm_sm_check(&eng->arm[arm], kind, mode);
        }
    }
    return st;
}

/* Refused: only the controller's PDL2 program starts a mode (see check_mode_req). */
c4g_status_t c4g_engine_request_mode(c4g_engine_t *eng, uint32_t arm, int32_t mode)
{
    return request(eng, arm, C4G_REQ_MODE, mode);
}

c4g_status_t c4g_engine_anchor(const c4g_engine_t *eng, uint32_t axis, float *pos)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((eng != NULL) && (pos != NULL)) {
        st = C4G_ERR_ARG;
        if ((axis < eng->map.n_axes) && (axis < C4G_MAX_AXES)) {
            st = C4G_ERR_STATE;
            if (eng->priv.anchor_set[axis] != 0U) {
                *pos = eng->priv.anchor[axis];
                st = C4G_OK;
            }
        }
    }
    return st;
}

c4g_status_t c4g_engine_request_exit(c4g_engine_t *eng, uint32_t arm)
{
    c4g_status_t st = request(eng, arm, C4G_REQ_EXIT, 0);
    if (st == C4G_OK) {
        c4g_arm_sm_t *sm = &eng->arm[arm];
        if ((sm->exit_req == 0U) && (sm->leaving == 0U)) {
            sm->exit_req = 1U;
            sm->exit_ticks = 0U;
            sm->exit_from = sm->mode;
        }
    }
    return st;
}

c4g_status_t c4g_engine_request_drive_off(c4g_engine_t *eng, uint32_t arm)
{
    c4g_status_t st = request(eng, arm, C4G_REQ_DRIVE_OFF, 0);
    if (st == C4G_OK) {
        c4g_arm_sm_t *sm = &eng->arm[arm];
        sm->latch |= C4G_LATCH_DRIVE_OFF;
        sm->latch_sent = 0U;
    }
    return st;
}

c4g_status_t c4g_engine_request_follow_error(c4g_engine_t *eng, uint32_t arm)
{
    c4g_status_t st = request(eng, arm, C4G_REQ_FOLLOW_ERROR, 0);
    if (st == C4G_OK) {
        c4g_arm_sm_t *sm = &eng->arm[arm];
        sm->latch |= C4G_LATCH_FOLLOW_ERROR;
        sm->latch_sent = 0U;
    }
    return st;
}

c4g_status_t c4g_engine_request_freeze(c4g_engine_t *eng, uint32_t arm)
{
    c4g_status_t st = request(eng, arm, C4G_REQ_FREEZE, 0);
    if (st == C4G_OK) {
        eng->arm[arm].frozen = C4G_MODE_FREEZING_A;
    }
    return st;
}
