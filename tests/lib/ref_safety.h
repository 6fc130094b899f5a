/* SPDX-License-Identifier: MIT */
/* The reference of the differential tests (test_ref_safety.c, fuzz_safety_ref.c): the
 * per-tick engine step and safety filter exactly as they were before the filter was
 * restructured for speed (lib/engine/c4g_engine.c's step, c4g_safety.c's finish and the
 * inline rules of c4g_safety_filter.h / c4g_engine_rules.h / c4g_engine_util.h), renamed
 * ref_engine_step, ref_engine_step_decoded and ref_safety_filter. Used only by tests: the
 * library's step and filter must give the same bits, statuses and engine state for every
 * input. Do not edit it to follow the library: a difference is a finding. */
#ifndef REF_SAFETY_H
#define REF_SAFETY_H

#include "../../lib/c4g_internal.h"

#include <string.h>

#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
/* Control engine: private helpers (no libm: tiny float helpers written here). */

/* Cold paths of the per-tick functions stay out of line, so that the hot loop neither grows
 * nor keeps their intermediate values alive (plain static elsewhere). */
#if defined(__GNUC__) || defined(__clang__)
#define CTL_COLD __attribute__((noinline, cold))
#else
#define CTL_COLD
#endif

/* Bit 31 set iff @p f is NaN or infinite (exponent all ones carries into the sign bit):
 * OR several of these and test once. */
static inline uint32_t eng_nonfinite_bit(float f)
{
    return c4g_exp_carry(c4g_f32_bits(f)) & 0x80000000U;
}

/* Exponent carry of a float: bit 31 of the OR of these is set iff one of them is NaN or
 * infinite (the mask test of eng_nonfinite_bit, done once for several values). */
static inline uint32_t eng_exp_carry(float f)
{
    return c4g_exp_carry(c4g_f32_bits(f));
}

static inline float eng_absf(float x)
{
    return (x < 0.0F) ? -x : x;
}

/* Bits of a double, for the finite test. */
static inline int eng_f64_finite(double d)
{
    uint64_t u;
    /* Deviation D-21 (MISRA 21.15): bit-exact reinterpretation, as D-02. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&u, &d, sizeof u);
    return ((u & 0x7FF0000000000000ULL) != 0x7FF0000000000000ULL) ? 1 : 0;
}

static inline bool eng_is_unset(float f)
{
    return c4g_f32_bits(f) == C4G_UNSET_BITS;
}

static inline float eng_unset(void)
{
    const uint32_t u = C4G_UNSET_BITS;
    float f;
    /* Deviation D-21 (MISRA 21.15): bit-exact reinterpretation, as D-02. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&f, &u, sizeof f);
    return f;
}

/* ------------------------------------------------------------------ cores */

static inline uint32_t sfc_sym(float v, float lim, uint32_t flag, float *out)
{
    uint32_t r = 0U;
    float o = v;
    if (v > lim) {
        o = lim;
        r = flag;
    } else if (v < -lim) {
        o = -lim;
        r = flag;
    } else {
        /* within limits */
    }
    *out = o;
    return r;
}

/* err = |ref - mis|; a threshold of 0 means none (field facts); an overflowing
 * difference is certainly too far. */
static inline uint32_t sfc_follow_error(float ref, float mis, float threshold, float *err)
{
    const float e = eng_absf(ref - mis);
    uint32_t r = 0U;
    if ((eng_nonfinite_bit(e) != 0U) || ((threshold > 0.0F) && (e > threshold))) {
        r = C4G_SF_FOLLOW_ERROR;
    }
    *err = e;
    return r;
}

/* @p v kept inside [lo, hi] by shrinking it towards 0 only: a value of the sign that
 * leaves the interval is cut to its edge, or to 0 when the edge is on the other side of 0;
 * a value of the other sign is kept (it goes back towards the interval). */
static inline uint32_t sfc_toward_zero(float v, float lo, float hi, uint32_t flag, float *out)
{
    uint32_t r = 0U;
    float o = v;
    if ((v > hi) && (v > 0.0F)) {
        o = (hi > 0.0F) ? hi : 0.0F;
        r = flag;
    } else if ((v < lo) && (v < 0.0F)) {
        o = (lo < 0.0F) ? lo : 0.0F;
        r = flag;
    } else {
        /* inside, or on its way back */
    }
    *out = o;
    return r;
}

/* smp + delta within [-lim, lim]  <=>  delta within [-lim - smp, lim - smp], reached only by
 * shrinking delta: a clamp never creates or reverses a current (with SMP+ already beyond the
 * limit, a delta pushing further becomes 0, one bringing it back stays). */
static inline uint32_t sfc_delta_current(float smp, float delta, float lim, float *out)
{
    return sfc_toward_zero(delta, -lim - smp, lim - smp, C4G_SF_DCURRENT, out);
}

/* A motion @p d from @p base kept inside [min, max] (off when min >= max) the same way:
 * from outside the stroke it may move back, never further out. */
static inline uint32_t sfc_shrink(float base, float d, float min, float max, float *out)
{
    uint32_t r = 0U;
    *out = d;
    if (min < max) {
        r = sfc_toward_zero(d, min - base, max - base, C4G_SF_STROKE, out);
    }
    return r;
}

/* |target - prev| <= max_step; 0 = off. */
static inline uint32_t sfc_step(float prev, float target, float max_step, float *out)
{
    uint32_t r = 0U;
    float o = target;
    if (max_step > 0.0F) {
        const float d = target - prev;
        if (d > max_step) {
            o = prev + max_step;
            r = C4G_SF_STEP;
        } else if (d < -max_step) {
            o = prev - max_step;
            r = C4G_SF_STEP;
        } else {
            /* continuous */
        }
    }
    *out = o;
    return r;
}

static inline uint32_t sfc_velocity(float vel, float max_vel, float *out)
{
    uint32_t r = 0U;
    *out = vel;
    if (max_vel > 0.0F) {
        r = sfc_sym(vel, max_vel, C4G_SF_VELOCITY, out);
    }
    return r;
}

/* Clamp into [min, max]; off when min >= max. */
static inline uint32_t sfc_stroke(float pos, float min, float max, float *out)
{
    uint32_t r = 0U;
    float o = pos;
    if (min < max) {
        if (pos > max) {
            o = max;
            r = C4G_SF_STROKE;
        } else if (pos < min) {
            o = min;
            r = C4G_SF_STROKE;
        } else {
            /* inside the stroke */
        }
    }
    *out = o;
    return r;
}

/* Control engine internals shared by the step (c4g_engine.c) and the finish with the safety
 * filter (c4g_safety.c): per-mode rules from the mode table and the request overlays. */

#define NO_AXIS 0xFFU

/* ------------------------------------------------------------------ helpers */

/* An axis count bounded by the packet arrays (one test per loop iteration, not two). */
static inline uint32_t axes_in(uint32_t n)
{
    return (n < C4G_MAX_AXES) ? n : C4G_MAX_AXES;
}

/* What the controller does with the PC's fields in a mode (the mode table's rules column,
 * C4G_MR_*), with the PC fields (C4G_PCF_*) in the low bits. */
#define R_FIELDS 0x001FU
#define R_SHOWN 0x40000U /* (axis_data_check only) the axis carries its prepared mode */
#define R_INT (C4G_MR_INT_D1 | C4G_MR_INT_D2 | C4G_MR_INT_D4)
/* A mode the C4G does not have (3, 6, 1xx, 201, 202): no rule can bound its fields, so the
 * reply carries none and the arm is sent 505. */
#define R_NORULE 0x80000U
/* The rules that give some PC field a meaning the filter bounds. */
#define R_FIELD_RULES (C4G_MR_ABS | R_INT | C4G_MR_VEL | C4G_MR_VADD | C4G_MR_CUR | \
                       C4G_MR_DCUR | C4G_MR_COPY)

static inline uint32_t mode_rules(int32_t m)
{
    const c4g_mode_info_t *row = c4g_mode_find(m);
    uint32_t r = 0U;
    if (row != NULL) {
        r = ((row->flags & C4G_MF_AVAILABLE) != 0U) ? (row->rules | row->pc_fields) : R_NORULE;
    }
    return r;
}

static inline float tighter(float ctrl_value, float user)
{
    float r = ctrl_value;
    if ((user > 0.0F) && ((ctrl_value <= 0.0F) || (user < ctrl_value))) {
        r = user;
    }
    return r;
}

static inline void copy_back(const c4g_ctrl_axis_t *rx, c4g_pc_axis_t *tx)
{
    tx->target_pos = rx->target_pos;
    tx->target_vel = rx->target_vel;
    tx->measure = rx->actual_pos;
    tx->vel_add = rx->actual_vel;
    tx->current_add = rx->current_ref;
}

/* What holding an axis means in a mode: the reference the controller applied last (D1 of
 * an absolute mode: its reported reference; the current of a mode where the PC closes the
 * loops: the controller's own, within @p cur_max), no addition, no velocity, no delta; mode
 * 0' copies back. The caller sets the mode. */
static inline void hold_axis(uint32_t rules, const c4g_ctrl_axis_t *rx, float cur_max,
                             c4g_pc_axis_t *tx)
{
    (void)memset(tx, 0, sizeof *tx);
    if ((rules & C4G_MR_COPY) != 0U) {
        copy_back(rx, tx);
    } else {
        if ((rules & C4G_MR_ABS) != 0U) {
            tx->target_pos = rx->target_pos;
        }
        if ((rules & C4G_MR_CUR) != 0U) {
            (void)sfc_sym(rx->current_ref, cur_max, 0U, &tx->current_add);
        }
    }
}

/* Mode every axis of an arm carries because of a latch or an active freezing, 0 if none. */
static inline int32_t arm_overlay(const c4g_arm_sm_t *sm)
{
    int32_t m = 0;
    if ((sm->latch & C4G_LATCH_FOLLOW_ERROR) != 0U) {
        m = C4G_MODE_FOLLOW_ERROR;
    } else if ((sm->latch & (C4G_LATCH_DRIVE_OFF | C4G_LATCH_STROKE)) != 0U) {
        m = C4G_MODE_DRIVE_OFF;
    } else if (sm->frozen == C4G_MODE_FREEZING_A) {
        m = C4G_MODE_FREEZING_A;
    } else {
        /* the prepared modes go out */
    }
    return m;
}

/* Mode the axis finally carries: safety latches and active freezing override. */
static inline int32_t overlay_mode(const c4g_engine_t *eng, const int32_t over[C4G_ARMS], uint32_t i,
                            int32_t base)
{
    int32_t m = base;
    if (eng->priv.fe_latch[i] != 0U) {
        m = C4G_MODE_FOLLOW_ERROR;
    } else if (over[eng->map.arm_of[i]] != 0) {
        m = over[eng->map.arm_of[i]];
    } else {
        /* the prepared mode */
    }
    return m;
}

/* The overlay of every arm; 1 if some axis may carry a mode other than its prepared one (an
 * arm overlay, or an axis latched to 508), 0 if none can. */
static inline uint32_t arm_overlays(const c4g_engine_t *eng, int32_t over[C4G_ARMS])
{
    uint32_t some = 0U;
    uint32_t a;
    uint32_t i;
    for (a = 0U; a < C4G_ARMS; a++) {
        over[a] = arm_overlay(&eng->arm[a]);
        if (over[a] != 0) {
            some = 1U;
        }
    }
    /* the whole array (zero past the open axes): a fixed count the compiler can vectorize */
    for (i = 0U; i < C4G_MAX_AXES; i++) {
        some |= eng->priv.fe_latch[i];
    }
    return (some != 0U) ? 1U : 0U;
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
    for (i = 0U; i < n; i++) {
        const c4g_ctrl_axis_t *a = &rx->ax[i];
        arm_view_t *w = &v[eng->map.arm_of[i]];
        const int32_t am = a->mode;
        if (check != 0U) {
            carry |= rx_axis_carry(a);
            /* the mode prepared last tick is known: skip the lookup when it repeats */
            if ((am != eng->priv.prep_mode[i]) && (!c4g_mode_is_known(am))) {
                unknown = 1U;
            }
        }
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
            (void)c4g_arm_sm_update(sm, &eng->cfg, v[a].mode, v[a].mixed,
                                    c4g_arm_byte(rx->infpar, a), v[a].moving, now_ns, &ev);
            if ((ev & C4G_CEV_LATCH_CLEARED) != 0U) {
                for (i = 0U; i < eng->map.n_axes; i++) {
                    eng->priv.fe_latch[i] = (eng->map.arm_of[i] == a) ? 0U : eng->priv.fe_latch[i];
                }
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
    uint32_t i;
    tx->num = rx->num;
    tx->infpar = 0U;
    tx->cmd = 0U;
    tx->n_axes = rx->n_axes;
    some = arm_overlays(eng, over);
    for (i = 0U; i < n; i++) {
        prepare_axis(eng, over, some, &rx->ax[i], i, &tx->ax[i]);
    }
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

static c4g_status_t ref_engine_step(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, uint64_t now_ns,
                          c4g_pc_packet_t *tx, c4g_engine_report_t *rep)
{
    return engine_step(eng, rx, now_ns, tx, rep, 1U);
}

static c4g_status_t ref_engine_step_decoded(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                     uint64_t now_ns, c4g_pc_packet_t *tx,
                                     c4g_engine_report_t *rep)
{
    return engine_step(eng, rx, now_ns, tx, rep, 0U);
}

/* The safety unit: the finish of every cyclic reply (request overlays, per-mode packet
 * rules, mode-0' copy-back, the safety filter on what the controller will do with each
 * field, following error, joint stroke ends, 505 on faults) and the public single-rule
 * checks (sections 14.17.2 and 15.7). The rule primitives are c4g_safety_filter.h. */

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
static inline uint32_t axis_data_check(const c4g_pc_axis_t *tx, uint32_t fields)
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
static inline uint32_t rewritten_check(const c4g_pc_axis_t *tx)
{
    return value_check(tx->target_pos, 0U) | value_check(tx->target_vel, 0U) |
           value_check(tx->vel_add, 0U) | value_check(tx->current_add, 0U);
}

/* The field the controller integrates in this mode (R_INT_*). */
static inline float *int_field(uint32_t rules, c4g_pc_axis_t *tx)
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
static inline uint32_t filter_targets(const c4g_engine_t *eng, uint32_t i, uint32_t rules,
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

static inline uint32_t filter_axis(const c4g_engine_t *eng, uint32_t i, uint32_t rules,
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
static inline uint32_t filter_fe(c4g_engine_t *eng, uint32_t i, uint32_t rules,
                                 const c4g_ctrl_axis_t *rx, const c4g_pc_axis_t *tx,
                                 float *fe_out)
{
    uint32_t f = 0U;
    if ((rules & C4G_MR_FE) != 0U) {
        const float ref = ((rules & C4G_MR_ABS) != 0U) ? tx->target_pos : rx->target_pos;
        f = sfc_follow_error(ref, rx->actual_pos, eng->lim[i].follow_error, fe_out);
        if ((f & C4G_SF_FOLLOW_ERROR) != 0U) {
            eng->priv.fe_latch[i] = 1U;
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
static inline uint32_t no_rule_fields(uint32_t rules, c4g_pc_axis_t *tx)
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
static inline uint32_t finish_axis(c4g_engine_t *eng, uint32_t i, int32_t shown,
                                   const c4g_ctrl_axis_t *rx, c4g_pc_axis_t *tx, float *fe_out)
{
    const int32_t m = eng->priv.prep_mode[i];
    const uint32_t rules = eng->priv.prep_rules[i];
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
static inline void keep_axis(c4g_pc_axis_t *dst, const c4g_pc_axis_t *src)
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
static inline void record_axis(const c4g_engine_t *eng, uint32_t i, int32_t shown, c4g_pc_axis_t *tx,
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
 * must be recorded again once the overlays are final. */
static inline uint32_t finish_axes(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx,
                                   c4g_pc_packet_t *tx, c4g_engine_report_t *r, uint32_t n,
                                   uint32_t *rec)
{
    int32_t over[C4G_ARMS];
    const uint32_t some = arm_overlays(eng, over);
    uint32_t any = 0U;
    uint32_t i;
    for (i = 0U; i < n; i++) {
        const int32_t shown = (some != 0U) ? overlay_mode(eng, over, i, eng->priv.prep_mode[i])
                                           : eng->priv.prep_mode[i];
        c4g_pc_axis_t d;
        keep_axis(&d, &tx->ax[i]);
        r->follow_err[i] = 0.0F;
        r->axis_flags[i] |= finish_axis(eng, i, shown, &rx->ax[i], &d, &r->follow_err[i]);
        any |= r->axis_flags[i];
        if ((any & REDO_FLAGS) != 0U) {
            *rec = 0U;
        }
        if (*rec != 0U) {
            record_axis(eng, i, shown, &d, r);
        }
        keep_axis(&tx->ax[i], &d);
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
    tx->infpar = exit_bytes(eng, r);
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
    latches_sent(eng);
    eng->priv.stepped = 0U;
    return st;
}

static c4g_status_t ref_safety_filter(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx,
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

#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic pop
#endif

#endif /* REF_SAFETY_H */
