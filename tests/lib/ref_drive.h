/* SPDX-License-Identifier: MIT */
/* The differential drive of the per-tick engine step and safety filter: two engines built
 * the same way, one run by the library (c4g_engine_step / c4g_safety_filter), one by the
 * reference (ref_safety.h, the code before it was restructured for speed), fed the same
 * packets, the same replies written by a "caller" and the same requests and limits. After
 * every call the statuses, the prepared and filtered replies, the reports and the whole
 * engine state must be equal to the bit. The choices come from a byte source: a seeded
 * generator (test_ref_safety.c) or the fuzzer's bytes (fuzz_safety_ref.c).
 *
 * The values are drawn from palettes that reach every rule: targets just inside and just
 * outside the step, stroke and velocity limits, exactly on them, +/-0, subnormals, huge
 * values whose differences overflow, NaN, infinities and the unset marker; modes from the
 * whole table (available, stand-by, special, not available) and unknown codes; every kind
 * of request, limits set, refused and changed between ticks, joint strokes through the
 * kinematics. */
#ifndef REF_DRIVE_H
#define REF_DRIVE_H

#include "ref_safety.h"
#include "c4gsim_fixtures.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* The engine state both implementations keep: everything before the library's own caches
 * (uni_rules, fe_any: the reference does not keep them; the differential below proves
 * they change no output). */
#define REF_ENGINE_BYTES (offsetof(c4g_engine_t, priv) + offsetof(c4g_engine_priv_t, uni_rules))

typedef struct ref_src {
    const uint8_t *buf; /* NULL: the generator */
    size_t len;
    size_t pos;
    uint64_t rng;
} ref_src_t;

static inline uint32_t ref_u32(ref_src_t *s)
{
    uint32_t v = 0U;
    if (s->buf == NULL) {
        s->rng ^= s->rng << 13;
        s->rng ^= s->rng >> 7;
        s->rng ^= s->rng << 17;
        v = (uint32_t)(s->rng >> 16);
    } else {
        uint32_t k;
        for (k = 0U; k < 4U; k++) {
            v = (v << 8) | ((s->pos < s->len) ? s->buf[s->pos] : 0U);
            s->pos++;
        }
    }
    return v;
}

/* 0..n-1 */
static inline uint32_t ref_below(ref_src_t *s, uint32_t n)
{
    return ref_u32(s) % n;
}

static inline float ref_bits(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline int ref_exhausted(const ref_src_t *s)
{
    return (s->buf != NULL) && (s->pos >= s->len);
}

/* A value near @p around on the scale of @p lim: inside, on, just past the limit, far, or
 * one of the special values. */
static inline float ref_value(ref_src_t *s, float around, float lim)
{
    const uint32_t k = ref_below(s, 24U);
    const float frac = (float)ref_below(s, 2001U) / 1000.0F - 1.0F; /* -1 .. 1 */
    float v = around;
    switch (k) {
    case 0: v = around + lim; break;
    case 1: v = around - lim; break;
    case 2: v = around + lim * 1.0000001F; break;
    case 3: v = around - lim * 1.0000001F; break;
    case 4: v = ref_bits(0x7FC00000U); break;              /* NaN */
    case 5: v = ref_bits(0x7F800000U); break;              /* +inf */
    case 6: v = ref_bits(0xFF800000U); break;              /* -inf */
    case 7: v = ref_bits(C4G_UNSET_BITS); break;           /* the unset marker */
    case 8: v = 0.0F; break;
    case 9: v = -0.0F; break;
    case 10: v = ref_bits(0x00000001U); break;             /* subnormal */
    case 11: v = 3.0e38F * ((frac < 0.0F) ? -1.0F : 1.0F); break; /* differences overflow */
    case 12: v = ref_bits(ref_u32(s)); break;              /* any bits */
    case 13: v = around + frac * lim * 10.0F; break;
    case 14: v = around; break;
    case 15: v = ref_bits(0xFFC4C0DEU); break;             /* the marker's sign flipped */
    default: v = around + frac * lim; break;
    }
    return v;
}

static const int32_t ref_modes[] = {
    C4G_MODE_0, C4G_MODE_0_DEBUG, C4G_MODE_1, C4G_MODE_1_STANDBY, C4G_MODE_2,
    C4G_MODE_2_STANDBY, C4G_MODE_3, C4G_MODE_4, C4G_MODE_4_STANDBY, C4G_MODE_5,
    C4G_MODE_5_STANDBY, C4G_MODE_6, C4G_MODE_7, C4G_MODE_7_STANDBY, C4G_MODE_7_STANDBY_EXIT,
    C4G_MODE_8, C4G_MODE_9, C4G_MODE_101, C4G_MODE_102, C4G_MODE_103, C4G_MODE_201,
    C4G_MODE_202, C4G_MODE_FREEZING_A, C4G_MODE_DRIVING_ON, C4G_MODE_FREEZING_P_IN,
    C4G_MODE_FREEZING_P_OUT, C4G_MODE_EXIT_OPEN, C4G_MODE_DRIVE_OFF, C4G_MODE_SVR_RESTART,
    C4G_MODE_FOLLOW_ERROR, 13, -1, 0x7FFFFFFF};
#define REF_N_MODES (sizeof ref_modes / sizeof ref_modes[0])
#define REF_N_KNOWN (REF_N_MODES - 3U)

typedef struct ref_world {
    c4g_engine_t a; /* the library */
    c4g_engine_t b; /* the reference */
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx_a, tx_b;
    c4g_engine_report_t rep_a, rep_b;
    int32_t mode_of[C4G_MAX_AXES]; /* the mode each axis is in (kept most ticks) */
    float scale[C4G_MAX_AXES];     /* the axis's step limit, the scale of its values */
    uint32_t n;
    uint64_t now;
    uint64_t ticks;
    char why[160];
} ref_world_t;

/* Limits of one axis: checks off or on, hit often, sometimes refused. */
static inline void ref_limits(ref_src_t *s, c4g_axis_limits_t *l)
{
    static const float small[] = {0.0F, 0.001F, 0.01F, 0.5F, 5.0F};
    memset(l, 0, sizeof *l);
    l->follow_error = small[ref_below(s, 5U)];
    l->current_max = small[ref_below(s, 5U)] * 4.0F;
    l->max_step = small[ref_below(s, 5U)];
    l->max_vel = small[ref_below(s, 5U)];
    if (ref_below(s, 3U) != 0U) {
        l->motor_min = -(float)ref_below(s, 40U) * 0.25F;
        l->motor_max = (float)ref_below(s, 40U) * 0.25F + 0.125F;
    }
    if (ref_below(s, 4U) == 0U) {
        l->joint_min = -(float)ref_below(s, 30U) * 0.1F;
        l->joint_max = (float)ref_below(s, 30U) * 0.1F + 0.05F;
    }
    if (ref_below(s, 32U) == 0U) {
        l->max_step = ref_value(s, 0.0F, 1.0F); /* refused (or not) by the library */
    }
}

/* A world of 1..20 open axes on up to two arms, both engines identical. 0 if the set-up was
 * refused (the caller draws another). */
static inline int ref_world_init(ref_world_t *w, ref_src_t *s)
{
    c4g_init_t in;
    c4g_engine_config_t cfg;
    uint32_t i;
    int ok = 1;
    memset(w, 0, sizeof *w);
    /* the engine keeps a copy of the configuration, padding included, and the state is
     * compared byte for byte: no byte of it may be left undefined (valgrind) */
    memset(&in, 0, sizeof in);
    memset(&cfg, 0, sizeof cfg);
    w->n = 1U + ref_below(s, 20U);
    (void)c4gsim_fig10_1(&in);
    in.n_ax_open = (int32_t)w->n;
    for (i = 0U; i < 40U; i++) {
        const uint32_t a = i / 10U;
        const uint32_t x = i % 10U;
        in.open_ax[a][x] = (i < w->n) ? (int32_t)i : C4G_OPEN_AX_NONE;
        if (i < w->n) {
            in.az_lim[a][x] = 1.0F + (float)ref_below(s, 4U) * 5.0F;
            in.tx_rate[a][x] = (ref_below(s, 4U) == 0U) ? -(30.0F + (float)x) : (50.0F + (float)x);
            in.follow_error[a][x] = (float)ref_below(s, 3U) * 2.5F;
        }
    }
    (void)c4g_engine_config_default(&cfg);
    cfg.moving_eps = (float)ref_below(s, 3U) * 0.001F;
    if (c4g_engine_init(&w->a, &in, &cfg) != C4G_OK) {
        ok = 0;
    } else {
        for (i = 0U; i < w->n; i++) {
            c4g_axis_limits_t l;
            ref_limits(s, &l);
            if ((ref_below(s, 8U) != 0U) &&
                (c4g_engine_set_limits(&w->a, i / 10U, i % 10U, &l) == C4G_OK)) {
                w->scale[i] = l.max_step;
            }
            if (w->scale[i] <= 0.0F) {
                w->scale[i] = 0.01F;
            }
            w->mode_of[i] = ref_modes[ref_below(s, REF_N_KNOWN)];
        }
        memcpy(&w->b, &w->a, sizeof w->b);
    }
    return ok;
}

/* The controller's packet: the modes kept, changed per arm or per axis; values around the
 * previous targets; sometimes an invalid value or an unknown mode (step: not decoded). */
static inline uint32_t ref_packet(ref_world_t *w, ref_src_t *s)
{
    uint32_t valid = 1U;
    uint32_t i;
    const uint32_t change = ref_below(s, 8U);
    c4g_ctrl_packet_t *p = &w->rx;
    p->num = (int32_t)((w->ticks + 1U) & 0x7FFFU);
    p->n_axes = w->n;
    p->infpar = 0U;
    for (i = 0U; i < C4G_ARMS; i++) {
        static const uint8_t sts[] = {C4G_STS_MOVING, C4G_STS_MOVING, C4G_STS_MOVING, 0U, 1U, 7U};
        p->infpar |= (uint32_t)sts[ref_below(s, 6U)] << (8U * i);
    }
    if (change == 0U) { /* one mode for every axis */
        const int32_t m = ref_modes[ref_below(s, REF_N_KNOWN)];
        for (i = 0U; i < w->n; i++) {
            w->mode_of[i] = m;
        }
    }
    for (i = 0U; i < w->n; i++) {
        c4g_ctrl_axis_t *a = &p->ax[i];
        const float sc = w->scale[i];
        if ((change == 1U) && (ref_below(s, 3U) == 0U)) {
            w->mode_of[i] = ref_modes[ref_below(s, REF_N_KNOWN)];
        }
        a->mode = w->mode_of[i];
        if ((ref_below(s, 2U) == 0U) || (w->ticks == 0U)) {
            a->target_pos = ((float)ref_below(s, 41U) - 20.0F) * 0.25F;
            a->target_vel = (ref_below(s, 2U) == 0U) ? 0.0F : sc * 0.5F;
            a->actual_pos = a->target_pos + sc * 0.5F;
            a->actual_vel = 0.0F;
            a->current_ref = (float)ref_below(s, 9U) - 4.0F;
        } else {
            a->target_pos = a->target_pos + a->target_vel;
            a->actual_pos = a->target_pos - sc * 0.25F * (float)ref_below(s, 40U);
        }
        if (ref_below(s, 64U) == 0U) {
            float *f[] = {&a->target_pos, &a->target_vel, &a->actual_pos, &a->actual_vel,
                          &a->current_ref, &a->ext[0], &a->ext[1], &a->ext[2]};
            float *t = f[ref_below(s, 8U)];
            *t = ref_value(s, *t, sc);
        }
        if (ref_below(s, 128U) == 0U) {
            a->mode = ref_modes[REF_N_KNOWN + ref_below(s, 3U)];
        }
    }
    for (i = 0U; i < w->n; i++) { /* what the decoder would have refused (values carry over) */
        const c4g_ctrl_axis_t *a = &p->ax[i];
        const float f[] = {a->target_pos, a->target_vel, a->actual_pos, a->actual_vel,
                           a->current_ref, a->ext[0], a->ext[1], a->ext[2]};
        uint32_t k;
        for (k = 0U; k < 8U; k++) {
            valid &= (c4g_f32_finite(f[k]) != 0) ? 1U : 0U;
        }
        valid &= c4g_mode_is_known(a->mode) ? 1U : 0U;
    }
    return valid;
}

/* What a caller writes into the prepared reply (same bytes into both). */
static inline void ref_caller(ref_world_t *w, ref_src_t *s, c4g_pc_packet_t *tx)
{
    const uint32_t style = ref_below(s, 6U);
    uint32_t i;
    for (i = 0U; (i < w->n) && (style != 0U); i++) {
        c4g_pc_axis_t *o = &tx->ax[i];
        const c4g_ctrl_axis_t *a = &w->rx.ax[i];
        const float sc = w->scale[i];
        if ((style == 1U) || (ref_below(s, 4U) != 0U)) { /* a well-behaved setpoint */
            o->target_pos = a->target_pos + sc * ((float)ref_below(s, 9U) - 4.0F) * 0.3F;
            o->target_vel = sc * ((float)ref_below(s, 5U) - 2.0F) * 0.6F;
            o->vel_add = sc * ((float)ref_below(s, 5U) - 2.0F) * 0.6F;
            o->current_add = (float)ref_below(s, 17U) - 8.0F;
            o->measure = 0.0F;
            if ((style == 2U) && (ref_below(s, 2U) == 0U)) {
                o->target_pos = a->target_pos + o->target_vel; /* continuous */
            }
        } else {
            o->target_pos = ref_value(s, a->target_pos, sc);
            o->target_vel = ref_value(s, 0.0F, sc);
            o->vel_add = ref_value(s, 0.0F, sc);
            o->current_add = ref_value(s, a->current_ref, 4.0F);
            o->measure = ref_value(s, 0.0F, 1.0F);
        }
        if (ref_below(s, 16U) == 0U) {
            o->ext[ref_below(s, 3U)] = ref_value(s, 0.0F, 1.0F);
        }
        if (ref_below(s, 24U) == 0U) {
            o->mode = ref_modes[ref_below(s, REF_N_MODES)];
        }
        if (ref_below(s, 12U) == 0U) {
            o->target_pos = ref_bits(C4G_UNSET_BITS); /* left unset */
        }
    }
    if (ref_below(s, 64U) == 0U) {
        tx->n_axes = (ref_below(s, 2U) == 0U) ? (w->n + 1U) : 0U; /* refused: ERR_STATE */
    }
}

/* The same request or limit change to both engines (the library's API: it only touches
 * the state both read). */
static inline void ref_requests(ref_world_t *w, ref_src_t *s)
{
    const uint32_t k = ref_below(s, 48U);
    const uint32_t arm = ref_below(s, 3U);
    if (k == 0U) {
        (void)c4g_engine_request_drive_off(&w->a, arm);
        (void)c4g_engine_request_drive_off(&w->b, arm);
    } else if (k == 1U) {
        (void)c4g_engine_request_follow_error(&w->a, arm);
        (void)c4g_engine_request_follow_error(&w->b, arm);
    } else if (k == 2U) {
        (void)c4g_engine_request_freeze(&w->a, arm);
        (void)c4g_engine_request_freeze(&w->b, arm);
    } else if (k == 3U) {
        (void)c4g_engine_request_exit(&w->a, arm);
        (void)c4g_engine_request_exit(&w->b, arm);
    } else if (k == 4U) {
        c4g_axis_limits_t l;
        const uint32_t i = ref_below(s, w->n);
        ref_limits(s, &l);
        if (c4g_engine_set_limits(&w->a, i / 10U, i % 10U, &l) == C4G_OK) {
            (void)c4g_engine_set_limits(&w->b, i / 10U, i % 10U, &l);
            w->scale[i] = (l.max_step > 0.0F) ? l.max_step : 0.01F;
        }
    } else {
        /* no request this tick */
    }
}

static inline int ref_same(ref_world_t *w, const char *what, c4g_status_t sa, c4g_status_t sb)
{
    const char *diff = NULL;
    if (sa != sb) {
        diff = "status";
    } else if (memcmp(&w->tx_a, &w->tx_b, sizeof w->tx_a) != 0) {
        diff = "reply";
    } else if (memcmp(&w->rep_a, &w->rep_b, sizeof w->rep_a) != 0) {
        diff = "report";
    } else if (memcmp(&w->a, &w->b, REF_ENGINE_BYTES) != 0) {
        diff = "engine state";
    } else {
        /* equal */
    }
    if (diff != NULL) {
        (void)snprintf(w->why, sizeof w->why, "tick %llu, %s: %s differs (status %d / ref %d)",
                       (unsigned long long)w->ticks, what, diff, (int)sa, (int)sb);
    }
    return (diff == NULL) ? 1 : 0;
}

/* One tick: requests, step, the caller's reply, filter. 0 on the first difference (w->why). */
static inline int ref_tick(ref_world_t *w, ref_src_t *s)
{
    const uint32_t valid = ref_packet(w, s);
    const uint32_t rep_null = (ref_below(s, 16U) == 0U) ? 1U : 0U;
    const uint32_t skip_step = (ref_below(s, 64U) == 0U) ? 1U : 0U;
    c4g_status_t sa = C4G_OK;
    c4g_status_t sb = C4G_OK;
    int ok = 1;
    w->now += 2000000U;
    ref_requests(w, s);
    if (skip_step == 0U) {
        /* c4g_engine_step_decoded is internal (the archive hides it): on a valid packet the
         * reference's decoded step (the loop object's path) must match the library's
         * checked one */
        sa = c4g_engine_step(&w->a, &w->rx, w->now, &w->tx_a, (rep_null != 0U) ? NULL : &w->rep_a);
        if ((valid != 0U) && (ref_below(s, 2U) == 0U)) {
            sb = ref_engine_step_decoded(&w->b, &w->rx, w->now, &w->tx_b,
                                         (rep_null != 0U) ? NULL : &w->rep_b);
        } else {
            sb = ref_engine_step(&w->b, &w->rx, w->now, &w->tx_b, (rep_null != 0U) ? NULL : &w->rep_b);
        }
        ok = ref_same(w, "step", sa, sb);
    }
    if (ok != 0) {
        ref_caller(w, s, &w->tx_a);
        memcpy(&w->tx_b, &w->tx_a, sizeof w->tx_b);
        sa = c4g_safety_filter(&w->a, &w->rx, &w->tx_a, (rep_null != 0U) ? NULL : &w->rep_a);
        sb = ref_safety_filter(&w->b, &w->rx, &w->tx_b, (rep_null != 0U) ? NULL : &w->rep_b);
        ok = ref_same(w, "filter", sa, sb);
    }
    if ((ok != 0) && (ref_below(s, 32U) == 0U)) { /* a second finish is refused */
        sa = c4g_safety_filter(&w->a, &w->rx, &w->tx_a, &w->rep_a);
        sb = ref_safety_filter(&w->b, &w->rx, &w->tx_b, &w->rep_b);
        ok = ref_same(w, "second filter", sa, sb);
    }
    w->tx_a.n_axes = w->n;
    w->tx_b.n_axes = w->n;
    w->ticks++;
    return ok;
}

#endif /* REF_DRIVE_H */
