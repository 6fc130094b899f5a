/* SPDX-License-Identifier: MIT */
/* The safety unit: the finish of every cyclic reply (request overlays, per-mode packet
 * rules, mode-0' copy-back, the safety filter on what the controller will do with each
 * field, following error, joint stroke ends, 505 on faults) and the public single-rule
 * checks (sections 14.17.2 and 15.7). The rule primitives are c4g_safety_filter.h. */
#include "c4g_engine_rules.h"

/* ------------------------------------------------------------------ finish: the filter */

static CTL_COLD uint32_t axis_data_slow(float d1, float d2, float d3, float d4, float d5,
                                        float e1, float e2, float e3, uint32_t fields);

/* One float of the reply: non-finite is MISSING when it is the unset marker of a required
 * field, else NONFINITE. The common (finite) case is one mask test. */
static inline uint32_t value_check(float f, uint32_t required)
{
    uint32_t r = 0U;
    if (c4g_f32_finite(f) == 0) {
        r = C4G_SF_NONFINITE;
        if ((required != 0U) && (eng_is_unset(f))) {
            r = C4G_SF_MISSING;
        }
    }
    return r;
}

/* @p fields: C4G_PCF_* whose unset marker means MISSING (the others: NONFINITE). */
static CTL_INLINE uint32_t axis_data_check(const c4g_pc_axis_t *tx, uint32_t fields)
{
    const uint32_t carry = eng_exp_carry(tx->target_pos) | eng_exp_carry(tx->target_vel) |
                           eng_exp_carry(tx->measure) | eng_exp_carry(tx->vel_add) |
                           eng_exp_carry(tx->current_add) | eng_exp_carry(tx->ext[0]) |
                           eng_exp_carry(tx->ext[1]) | eng_exp_carry(tx->ext[2]);
    return ((carry & 0x80000000U) == 0U)
               ? 0U
               : axis_data_slow(tx->target_pos, tx->target_vel, tx->measure, tx->vel_add,
                                tx->current_add, tx->ext[0], tx->ext[1], tx->ext[2], fields);
}

/* By value: the per-tick filter keeps the axis data in registers. */
static CTL_COLD uint32_t axis_data_slow(float d1, float d2, float d3, float d4, float d5,
                                        float e1, float e2, float e3, uint32_t fields)
{
    /* the unset marker in a field that is not required (or under an overlay) is NONFINITE */
    const uint32_t required = ((fields & R_SHOWN) != 0U) ? (fields & R_FIELDS) : 0U;
    return value_check(d1, required & C4G_PCF_D1) | value_check(d2, required & C4G_PCF_D2) |
           value_check(d3, required & C4G_PCF_D3) | value_check(d4, required & C4G_PCF_D4) |
           value_check(d5, required & C4G_PCF_D5) | value_check(e1, 0U) | value_check(e2, 0U) |
           value_check(e3, 0U);
}

/* What the filter rewrote, checked again: an overflow is never sent. */
static CTL_INLINE uint32_t rewritten_check(const c4g_pc_axis_t *tx)
{
    return value_check(tx->target_pos, 0U) | value_check(tx->target_vel, 0U) |
           value_check(tx->vel_add, 0U) | value_check(tx->current_add, 0U);
}

/* The field the controller integrates in this mode (R_INT_*). */
static CTL_INLINE float *int_field(uint32_t rules, c4g_pc_axis_t *tx)
{
    float *f = &tx->target_pos;
    if ((rules & C4G_MR_INT_D2) != 0U) {
        f = &tx->target_vel;
    } else if ((rules & C4G_MR_INT_D4) != 0U) {
        f = &tx->vel_add;
    } else {
        /* D1 */
    }
    return f;
}

/* Continuity and stroke ends on the position the controller will hold next tick: base + d,
 * d the per-tick motion the PC asks for (the integrated field, or target - base). The base
 * is what the controller applied last, as it reports it: for an absolute mode its reference
 * D1 (whatever came before: another mode, a freezing, an overlay, a lost reply), for an
 * integrating mode D1 advanced by its own target velocity D2 (the worst case, which may
 * count the PC's last step once more). Both checks only shrink d towards 0: the filter
 * never creates a motion, even back into the stroke. */
static CTL_INLINE uint32_t filter_targets(const c4g_engine_t *eng, uint32_t i, uint32_t rules,
                                      const c4g_ctrl_axis_t *rx, c4g_pc_axis_t *tx)
{
    const c4g_axis_limits_t *l = &eng->lim[i];
    const float base = ((rules & C4G_MR_ABS) != 0U) ? rx->target_pos
                                               : (rx->target_pos + rx->target_vel);
    float *field = int_field(rules, tx);
    const float req = ((rules & C4G_MR_ABS) != 0U) ? (tx->target_pos - base) : *field;
    uint32_t f = 0U;
    float d = req;
    if ((eng_nonfinite_bit(req) | eng_nonfinite_bit(base) | eng_nonfinite_bit(base + req)) != 0U) {
        f = C4G_SF_NONFINITE; /* target - base or base + delta overflows: never sent */
    } else {
        f = sfc_step(0.0F, req, l->max_step, &d);
        if (sfc_shrink(base, d, l->motor_min, l->motor_max, &d) != 0U) {
            f |= C4G_SF_STROKE;
        }
        if (f != 0U) { /* rewritten only when a check changed it (base + d may round) */
            if ((rules & C4G_MR_ABS) != 0U) {
                tx->target_pos = base + d;
            } else {
                *field = d;
            }
        }
    }
    return f;
}

/* The value of that field. */
static inline float int_value(uint32_t rules, const c4g_pc_axis_t *tx)
{
    float v = tx->target_pos;
    if ((rules & C4G_MR_INT_D2) != 0U) {
        v = tx->target_vel;
    } else if ((rules & C4G_MR_INT_D4) != 0U) {
        v = tx->vel_add;
    } else {
        /* D1 */
    }
    return v;
}

static CTL_INLINE uint32_t filter_axis(const c4g_engine_t *eng, uint32_t i, uint32_t rules,
                                   const c4g_ctrl_axis_t *rx, c4g_pc_axis_t *tx)
{
    const c4g_axis_limits_t *l = &eng->lim[i];
    uint32_t f = 0U;
    float o = 0.0F;
    if ((rules & (C4G_MR_ABS | R_INT)) != 0U) {
        f = filter_targets(eng, i, rules, rx, tx);
    }
    if ((rules & C4G_MR_VEL) != 0U) {
        f |= sfc_velocity(tx->target_vel, l->max_vel, &o);
        tx->target_vel = o;
    }
    if ((rules & C4G_MR_VADD) != 0U) {
        f |= sfc_velocity(tx->vel_add, l->max_vel, &o);
        tx->vel_add = o;
    }
    if ((rules & C4G_MR_CUR) != 0U) {
        f |= sfc_sym(tx->current_add, l->current_max, C4G_SF_CURRENT, &o);
        tx->current_add = o;
    } else if ((rules & C4G_MR_DCUR) != 0U) {
        f |= sfc_delta_current(rx->current_ref, tx->current_add, l->current_max, &o);
        tx->current_add = o;
    } else {
        /* no current from the PC in this mode */
    }
    return f;
}

/* Following error (15.7) on the final targets: the axis carries 508 (field library). */
static CTL_INLINE uint32_t filter_fe(c4g_engine_t *eng, uint32_t i, uint32_t rules,
                                 const c4g_ctrl_axis_t *rx, const c4g_pc_axis_t *tx,
                                 float *fe_out)
{
    uint32_t f = 0U;
    if ((rules & C4G_MR_FE) != 0U) {
        const float ref = ((rules & C4G_MR_ABS) != 0U) ? tx->target_pos : rx->target_pos;
        f = sfc_follow_error(ref, rx->actual_pos, eng->lim[i].follow_error, fe_out);
        if ((f & C4G_SF_FOLLOW_ERROR) != 0U) {
            eng->priv.fe_latch[i] = 1U;
            eng->priv.fe_any = 1U;
            eng->arm[eng->map.arm_of[i]].latch |= C4G_LATCH_AXIS_FE;
        }
    }
    return f;
}

/* Where each logical axis of @p arm starts this tick (@p base: the reference the controller
 * holds, as filter_targets measures it) and how far the PC moves it (@p d, 0 where SMP+
 * drives the axis), in motor turns. */
static void joint_motion(const c4g_engine_t *eng, uint32_t arm, const c4g_ctrl_packet_t *rx,
                         const c4g_pc_packet_t *tx, double base[C4G_AXES_PER_ARM],
                         double d[C4G_AXES_PER_ARM])
{
    uint32_t j;
    for (j = 0U; j < eng->priv.n_joint[arm]; j++) {
        const uint32_t i = eng->map.open_of[arm][j];
        const uint32_t rules = eng->priv.prep_rules[i];
        const c4g_ctrl_axis_t *r = &rx->ax[i];
        if ((rules & C4G_MR_ABS) != 0U) {
            base[j] = (double)r->target_pos;
            d[j] = (double)tx->ax[i].target_pos - base[j];
        } else {
            base[j] = (double)r->target_pos + (double)r->target_vel;
            d[j] = ((rules & R_INT) != 0U) ? (double)int_value(rules, &tx->ax[i]) : 0.0;
        }
    }
}

/* The largest share a in [0, 1] of the motion q0 -> q1 of every joint that keeps each one
 * inside its stroke, or moving back towards it (a joint already beyond an end may not go
 * further). */
static double joint_share(const c4g_engine_t *eng, uint32_t arm, const double q0[C4G_AXES_PER_ARM],
                          const double q1[C4G_AXES_PER_ARM])
{
    double a = 1.0;
    uint32_t j;
    for (j = 0U; j < eng->priv.n_joint[arm]; j++) {
        const c4g_axis_limits_t *l = &eng->lim[eng->map.open_of[arm][j]];
        const double lo = (double)l->joint_min;
        const double hi = (double)l->joint_max;
        const double dq = q1[j] - q0[j];
        double s = 1.0;
        if ((l->joint_min < l->joint_max) && (q1[j] > hi) && (dq > 0.0)) {
            s = (q0[j] < hi) ? ((hi - q0[j]) / dq) : 0.0;
        } else if ((l->joint_min < l->joint_max) && (q1[j] < lo) && (dq < 0.0)) {
            s = (q0[j] > lo) ? ((lo - q0[j]) / dq) : 0.0;
        } else {
            /* inside, or on its way back */
        }
        a = (s < a) ? s : a;
    }
    return (a > 0.0) ? a : 0.0;
}

/* Joint stroke ends through the kinematics (chapter 19). The joints are affine in the motor
 * positions, so the PC's motion of the whole arm is shrunk by one share: every PC-driven
 * axis moves by the same fraction of what it asked (never more, never elsewhere), the
 * binding joint stops at its end (to the float resolution of the motor reference), SMP+-driven
 * axes are untouched; where the kinematics cannot convert, the arm holds. Every axis whose
 * motion shrank is flagged (the arm stops). */
static CTL_COLD void filter_joints(c4g_engine_t *eng, uint32_t arm, const c4g_ctrl_packet_t *rx,
                                   c4g_pc_packet_t *tx, c4g_engine_report_t *r)
{
    const uint32_t n = eng->priv.n_joint[arm];
    double base[C4G_AXES_PER_ARM];
    double d[C4G_AXES_PER_ARM];
    double m1[C4G_AXES_PER_ARM];
    double q0[C4G_AXES_PER_ARM];
    double q1[C4G_AXES_PER_ARM];
    double a = 0.0;
    uint32_t j;
    joint_motion(eng, arm, rx, tx, base, d);
    for (j = 0U; j < n; j++) {
        m1[j] = base[j] + d[j];
    }
    if ((c4g_kin_motor_to_link(&eng->kin[arm], base, n, q0) == C4G_OK) &&
        (c4g_kin_motor_to_link(&eng->kin[arm], m1, n, q1) == C4G_OK)) {
        a = joint_share(eng, arm, q0, q1);
    }
    if (a < 1.0) {
        for (j = 0U; j < n; j++) {
            const uint32_t i = eng->map.open_of[arm][j];
            const uint32_t rules = eng->priv.prep_rules[i];
            c4g_pc_axis_t *o = &tx->ax[i];
            if ((d[j] > 0.0) || (d[j] < 0.0)) {
                const double moved = a * d[j];
                const double vel = a * (double)o->target_vel;
                const double to = base[j] + moved;
                if ((rules & C4G_MR_ABS) != 0U) {
                    o->target_pos = (float)to;
                    o->target_vel = (float)vel;
                } else {
                    *int_field(rules, o) = (float)moved;
                }
                r->axis_flags[i] |= C4G_SF_STROKE_JOINT;
            }
        }
    }
}

/* EXIT_FROM_OPEN bytes, and the END phase on the first packet carrying one. */
static uint32_t exit_bytes(c4g_engine_t *eng, c4g_engine_report_t *r)
{
    uint32_t infpar = 0U;
    uint32_t a;
    for (a = 0U; a < C4G_ARMS; a++) {
        c4g_arm_sm_t *sm = &eng->arm[a];
        if (sm->exit_req != 0U) {
            infpar = c4g_arm_byte_set(infpar, a, (uint8_t)C4G_EXIT_FROM_OPEN);
            sm->exit_ticks++;
            if (sm->exit_ticks == 1U) {
                uint32_t ev = C4G_CEV_EXIT_SENT;
                if ((sm->frozen != C4G_MODE_FREEZING_A) && (sm->phase != C4G_MPH_END)) {
                    sm->phase = C4G_MPH_END;
                    sm->phase_since_ns = sm->mode_since_ns;
                    ev |= C4G_CEV_END;
                }
                r->arm_events[a] |= ev;
                r->events |= ev;
            }
        }
    }
    return infpar;
}

/* Arms with a bad axis: bad axes hold (hold_axis), every axis carries 505. */
static CTL_COLD c4g_status_t arm_faults(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                        c4g_pc_packet_t *tx, c4g_engine_report_t *r)
{
    c4g_status_t st = C4G_OK;
    uint32_t bad_arm[C4G_ARMS] = {0U, 0U, 0U, 0U};
    uint32_t i;
    for (i = 0U; i < tx->n_axes; i++) {
        const uint32_t f = r->axis_flags[i];
        if ((f & (C4G_SF_MISSING | C4G_SF_NONFINITE)) != 0U) {
            bad_arm[eng->map.arm_of[i]] = 1U;
            if ((f & C4G_SF_MISSING) != 0U) {
                st = C4G_ERR_MISSING_DATA;
            } else if (st == C4G_OK) {
                st = C4G_ERR_NONFINITE;
            } else {
                /* keep the missing-data status */
            }
            hold_axis(eng->priv.prep_rules[i], &rx->ax[i], eng->lim[i].current_max, &tx->ax[i]);
            r->axis_flags[i] |= C4G_SF_HELD;
        }
        if ((f & C4G_SF_NO_RULE) != 0U) {
            bad_arm[eng->map.arm_of[i]] = 1U;
        }
    }
    for (i = 0U; i < C4G_ARMS; i++) {
        if (bad_arm[i] != 0U) {
            eng->arm[i].latch |= C4G_LATCH_DRIVE_OFF;
        }
    }
    return st;
}

/* Overflow check of what the filter wrote, then the following error on the final target. */
static uint32_t finish_fe(c4g_engine_t *eng, uint32_t i, const c4g_ctrl_axis_t *rx,
                          const c4g_pc_axis_t *tx, float *fe_out)
{
    uint32_t f = rewritten_check(tx);
    if (f == 0U) {
        f = filter_fe(eng, i, eng->priv.prep_rules[i], rx, tx, fe_out);
    }
    return f;
}

/* The data fields of a mode without field rules, zeroed; a mode the C4G does not have is
 * flagged whatever the PC wrote (its arm is sent 505). */
static CTL_INLINE uint32_t no_rule_fields(uint32_t rules, c4g_pc_axis_t *tx)
{
    tx->target_pos = 0.0F;
    tx->target_vel = 0.0F;
    tx->measure = 0.0F;
    tx->vel_add = 0.0F;
    tx->current_add = 0.0F;
    return ((rules & R_NORULE) != 0U) ? C4G_SF_NO_RULE : 0U;
}

/* Mode rules, copy back, required fields and the per-axis filter of one axis (@p tx: a copy
 * of the reply data, written back by the caller). */
static CTL_INLINE uint32_t finish_axis_r(c4g_engine_t *eng, uint32_t i, int32_t shown,
                                       const c4g_ctrl_axis_t *rx, c4g_pc_axis_t *tx,
                                       float *fe_out, uint32_t rules)
{
    const int32_t m = eng->priv.prep_mode[i];
    uint32_t f = 0U;
    if ((tx->mode != m) && (tx->mode != shown)) {
        f = C4G_SF_MODE_RESTORED; /* only the request API changes modes */
    }
    tx->mode = m;
    if ((rules & R_FIELD_RULES) == 0U) {
        /* no field of this mode means anything the filter bounds: none is sent */
        f |= no_rule_fields(rules, tx);
    } else if ((rules & C4G_MR_COPY) != 0U) {
        copy_back(rx, tx);
        f |= C4G_SF_COPY_BACK;
    } else {
        /* the filter's rules below */
    }
    f |= axis_data_check(tx, (shown == m) ? (rules | R_SHOWN) : rules);
    if ((f & (C4G_SF_MISSING | C4G_SF_NONFINITE)) == 0U) {
        const uint32_t clamps = filter_axis(eng, i, rules, rx, tx);
        f |= clamps;
        /* without a joint check on the arm the targets are final here; values a clamp
         * rewrote are checked again (an overflow is never sent) */
        if ((eng->priv.joint_on[eng->map.arm_of[i]] == 0U) && ((f & C4G_SF_NONFINITE) == 0U)) {
            uint32_t g = 0U;
            if (clamps != 0U) {
                g = rewritten_check(tx);
            }
            if (g == 0U) {
                g = filter_fe(eng, i, rules, rx, tx, fe_out);
            }
            f |= g;
        }
    }
    return f;
}


/* Field by field: the reply was just written with 4-byte stores, and a struct copy's wide
 * loads would stall on store forwarding (it cost 15 % of c4g_safety_filter); the per-tick filter
 * works on such a copy in registers. */
static CTL_INLINE void keep_axis(c4g_pc_axis_t *dst, const c4g_pc_axis_t *src)
{
    dst->mode = src->mode;
    dst->target_pos = src->target_pos;
    dst->target_vel = src->target_vel;
    dst->measure = src->measure;
    dst->vel_add = src->vel_add;
    dst->current_add = src->current_add;
    dst->ext[0] = src->ext[0];
    dst->ext[1] = src->ext[1];
    dst->ext[2] = src->ext[2];
}

/* Final mode of one axis (latches, freezing) and its report. Idempotent except for the
 * n_filtered count. (latch_sent: c4g_safety_filter.) */
static CTL_INLINE void record_axis(const c4g_engine_t *eng, uint32_t i, int32_t shown, c4g_pc_axis_t *tx,
                               c4g_engine_report_t *r)
{
    const uint32_t arm = eng->map.arm_of[i];
    tx->mode = shown;
    if (shown == C4G_MODE_DRIVE_OFF) {
        r->axis_flags[i] |= C4G_SF_DRIVE_OFF;
    } else if (shown == C4G_MODE_FOLLOW_ERROR) {
        r->axis_flags[i] |= C4G_SF_FE_SENT;
    } else {
        /* no safety request on this axis */
    }
    if ((r->axis_flags[i] & ~(C4G_SF_COPY_BACK)) != 0U) {
        r->n_filtered++;
        r->arm_events[arm] |= C4G_CEV_SAFETY;
        r->events |= C4G_CEV_SAFETY;
    }
}

/* Every axis recorded with the final overlays. */
static CTL_COLD void finish_record(const c4g_engine_t *eng, const int32_t over[C4G_ARMS], c4g_pc_packet_t *tx,
                          c4g_engine_report_t *r)
{
    uint32_t i;
    for (i = 0U; i < tx->n_axes; i++) {
        record_axis(eng, i, overlay_mode(eng, over, i, eng->priv.prep_mode[i]), &tx->ax[i], r);
    }
}

/* Filter flags after which the overlays of axes already recorded may change. */
#define REDO_FLAGS (C4G_SF_MISSING | C4G_SF_NONFINITE | C4G_SF_FOLLOW_ERROR | C4G_SF_STROKE | \
                    C4G_SF_STROKE_JOINT | C4G_SF_NO_RULE)

/* A stroke end stops the arm: every axis carries 505 from this reply on (the reference sent
 * with it stays inside the stroke: the motion stops before the limit, not after). */
static CTL_COLD void stroke_stops(c4g_engine_t *eng, uint32_t n, const c4g_engine_report_t *r)
{
    uint32_t i;
    for (i = 0U; i < n; i++) {
        if ((r->axis_flags[i] & (C4G_SF_STROKE | C4G_SF_STROKE_JOINT)) != 0U) {
            eng->arm[eng->map.arm_of[i]].latch |= C4G_LATCH_STROKE;
        }
    }
}

/* The per-axis pass: mode rules, filter and (while the overlays cannot change any more)
 * the record of each axis. Returns the OR of the axis flags; clears *rec when the axes
 * must be recorded again once the overlays are final. @p uni: the rules of every axis when
 * they are all the same and no overlay applies (@p some 0), passed as a constant by
 * finish_axes so that the compiler drops the rule tests and the overlays; 0 otherwise. */
static CTL_INLINE uint32_t finish_axes_r(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                         c4g_pc_packet_t *tx, c4g_engine_report_t *r,
                                         uint32_t n, uint32_t *rec, uint32_t some,
                                         const int32_t over[C4G_ARMS], uint32_t uni)
{
    uint32_t any = 0U;
    uint32_t keep = *rec;
    uint32_t i;
    for (i = 0U; i < n; i++) {
        const int32_t m = eng->priv.prep_mode[i];
        const int32_t shown = (some != 0U) ? overlay_mode(eng, over, i, m) : m;
        const uint32_t rules = (uni != R_MIXED) ? uni : eng->priv.prep_rules[i];
        c4g_pc_axis_t d;
        keep_axis(&d, &tx->ax[i]);
        r->follow_err[i] = 0.0F;
        r->axis_flags[i] |= finish_axis_r(eng, i, shown, &rx->ax[i], &d, &r->follow_err[i], rules);
        any |= r->axis_flags[i];
        if ((any & REDO_FLAGS) != 0U) {
            keep = 0U;
        }
        if (keep != 0U) {
            record_axis(eng, i, shown, &d, r);
        }
        keep_axis(&tx->ax[i], &d);
    }
    *rec = keep;
    return any;
}

/* finish_axes_r with the rules as a constant when every axis is in the same mode, one of the
 * modes a PC drives or mode 0, and no overlay applies (same code, same results). */
static inline uint32_t finish_axes(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                   c4g_pc_packet_t *tx, c4g_engine_report_t *r, uint32_t n,
                                   uint32_t *rec)
{
    int32_t over[C4G_ARMS];
    const uint32_t some = arm_overlays(eng, over);
    const uint32_t uni = (some == 0U) ? eng->priv.uni_rules : R_MIXED;
    uint32_t any;
    if (uni == R_MODE_4) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, R_MODE_4);
    } else if (uni == 0U) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, 0U);
    } else if (uni == R_MODE_1) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, R_MODE_1);
    } else if (uni == R_MODE_5) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, R_MODE_5);
    } else if (uni == R_MODE_7) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, R_MODE_7);
    } else if (uni == R_MODE_8) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, R_MODE_8);
    } else if (uni == R_MODE_9) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, R_MODE_9);
    } else if (uni == R_MODE_2) {
        any = finish_axes_r(eng, rx, tx, r, n, rec, 0U, over, R_MODE_2);
    } else {
        any = finish_axes_r(eng, rx, tx, r, n, rec, some, over, R_MIXED);
    }
    return any;
}

/* Joint stroke ends of the arms with a joint check, then the following error on the final
 * targets of their axes. Returns the OR of the axis flags. */
static CTL_COLD uint32_t finish_joints(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                       c4g_pc_packet_t *tx, c4g_engine_report_t *r)
{
    uint32_t any = 0U;
    uint32_t a;
    uint32_t i;
    for (a = 0U; a < C4G_ARMS; a++) {
        if (eng->priv.joint_on[a] != 0U) { /* set only on arms with open axes */
            filter_joints(eng, a, rx, tx, r);
        }
    }
    for (i = 0U; i < tx->n_axes; i++) {
        if ((eng->priv.joint_on[eng->map.arm_of[i]] != 0U) &&
            ((r->axis_flags[i] & (C4G_SF_MISSING | C4G_SF_NONFINITE)) == 0U)) {
            r->axis_flags[i] |= finish_fe(eng, i, &rx->ax[i], &tx->ax[i], &r->follow_err[i]);
            any |= r->axis_flags[i];
        }
    }
    return any;
}

/* The faults of this reply: 505 on faulty arms (with their status), stroke stops. */
static CTL_COLD c4g_status_t finish_faults(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                           c4g_pc_packet_t *tx, c4g_engine_report_t *r,
                                           uint32_t n, uint32_t any)
{
    c4g_status_t st = C4G_OK;
    if ((any & (C4G_SF_MISSING | C4G_SF_NONFINITE | C4G_SF_NO_RULE)) != 0U) {
        st = arm_faults(eng, rx, tx, r);
    }
    if ((any & (C4G_SF_STROKE | C4G_SF_STROKE_JOINT)) != 0U) {
        stroke_stops(eng, n, r);
    }
    return st;
}

/* Every open axis of an arm went out with its latch: the latch was sent. */
static void latches_sent(c4g_engine_t *eng)
{
    uint32_t a;
    for (a = 0U; a < C4G_ARMS; a++) {
        if ((eng->map.n_axes_arm[a] != 0U) && (eng->arm[a].latch != 0U)) {
            eng->arm[a].latch_sent = 1U;
        }
    }
}

static c4g_status_t finish_packet(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                  c4g_pc_packet_t *tx, c4g_engine_report_t *r)
{
    const uint32_t n = axes_in(rx->n_axes);
    const uint32_t n_filtered = r->n_filtered;
    c4g_status_t st = C4G_OK;
    uint32_t any;
    /* Each axis is recorded as soon as it is filtered while nothing can change the
     * overlays of the axes before it (no joint check, no fault, no following error);
     * otherwise every axis is recorded again once the overlays are final. */
    uint32_t rec = c4g_flag((eng->priv.joint_on[0] | eng->priv.joint_on[1] | eng->priv.joint_on[2] |
                             eng->priv.joint_on[3]) == 0U);
    uint32_t exits = 0U;
    uint32_t latched = 0U;
    uint32_t a;
    for (a = 0U; a < C4G_ARMS; a++) {
        exits |= eng->arm[a].exit_req;
        latched |= eng->arm[a].latch;
    }
    tx->infpar = (exits != 0U) ? exit_bytes(eng, r) : 0U;
    any = finish_axes(eng, rx, tx, r, n, &rec);
    if (rec == 0U) {
        int32_t over[C4G_ARMS];
        any |= finish_joints(eng, rx, tx, r);
        st = finish_faults(eng, rx, tx, r, n, any);
        (void)arm_overlays(eng, over); /* the filter may have latched an arm or an axis */
        r->n_filtered = n_filtered;
        finish_record(eng, over, tx, r);
    }
    if ((st == C4G_OK) && ((any & C4G_SF_MODE_RESTORED) != 0U)) {
        st = C4G_ERR_MODE_RESTORED; /* a fault's status comes first */
    }
    /* only the pass that records again (rec 0) latches an arm: without a latch before it and
     * without that pass, no latch was sent */
    if ((latched != 0U) || (rec == 0U)) {
        latches_sent(eng);
    }
    eng->priv.stepped = 0U;
    return st;
}

c4g_status_t c4g_safety_filter(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx,
                            c4g_engine_report_t *rep)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((eng != NULL) && (rx != NULL) && (tx != NULL)) {
        c4g_engine_report_t local;
        c4g_engine_report_t *r = rep;
        if (r == NULL) {
            (void)memset(&local, 0, sizeof local);
            r = &local;
        }
        st = C4G_ERR_STATE;
        if ((eng->priv.stepped != 0U) && (rx->num == eng->priv.step_num) &&
            (rx->n_axes == eng->map.n_axes) && (tx->n_axes == rx->n_axes)) {
            st = finish_packet(eng, rx, tx, r);
        }
    }
    return st;
}

/* ------------------------------------------------------------------ single rules */

uint32_t c4g_sf_follow_error(float pos_ref, float pos_mis, float threshold, float *err)
{
    return sf_follow_error(pos_ref, pos_mis, threshold, err);
}

uint32_t c4g_sf_current(float cur, float lim, float *out)
{
    return sf_current(cur, lim, out);
}

uint32_t c4g_sf_delta_current(float smp_cur, float delta, float lim, float *out)
{
    return sf_delta_current(smp_cur, delta, lim, out);
}

uint32_t c4g_sf_step(float prev, float target, float max_step, float *out)
{
    return sf_step(prev, target, max_step, out);
}

uint32_t c4g_sf_velocity(float vel, float max_vel, float *out)
{
    return sf_velocity(vel, max_vel, out);
}

uint32_t c4g_sf_stroke(float pos, float min, float max, float *out)
{
    return sf_stroke(pos, min, max, out);
}
