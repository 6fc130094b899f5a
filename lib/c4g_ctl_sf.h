/* SPDX-License-Identifier: MIT */
/* The PC-side safety checks as inline functions: the per-tick filter (c4g_control.c) inlines
 * them, c4g_safety.c exports them (c4g_sf_*). Each returns the C4G_SF_* bits it raised; on
 * any non-finite input it leaves the value as given and returns C4G_SF_NONFINITE. */
#ifndef C4G_CTL_SF_H
#define C4G_CTL_SF_H

#include "c4g_ctl_util.h"

/* A limit a check can use: finite and >= 0. */
static inline int sf_limit_ok(float lim)
{
    return ((c4g_f32_finite(lim) != 0) && (lim >= 0.0F)) ? 1 : 0;
}

static inline uint32_t sf_clamp_sym(float v, float lim, uint32_t flag, float *out)
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

static inline uint32_t sf_follow_error(float pos_ref, float pos_mis, float threshold, float *err)
{
    uint32_t r = C4G_SF_NONFINITE;
    float e = 0.0F;
    if ((c4g_f32_finite(pos_ref) != 0) && (c4g_f32_finite(pos_mis) != 0)) {
        e = ctl_absf(pos_ref - pos_mis);
        r = 0U; /* threshold 0: no threshold from the controller (FIELD-FACTS) */
        /* an overflowing difference is certainly too far */
        if ((c4g_f32_finite(e) == 0) || ((threshold > 0.0F) && (e > threshold))) {
            r = C4G_SF_FOLLOW_ERROR;
        }
        if ((c4g_f32_finite(e) != 0) && (sf_limit_ok(threshold) == 0)) {
            r = C4G_SF_BAD_LIMIT;
        }
    }
    if (err != NULL) {
        *err = e;
    }
    return r;
}

static inline uint32_t sf_current(float cur, float lim, float *out)
{
    uint32_t r = C4G_SF_NONFINITE;
    if (out != NULL) {
        *out = cur;
        if (c4g_f32_finite(cur) != 0) {
            r = (sf_limit_ok(lim) != 0) ? sf_clamp_sym(cur, lim, C4G_SF_CURRENT, out) : C4G_SF_BAD_LIMIT;
        }
    }
    return r;
}

static inline uint32_t sf_delta_current(float smp_cur, float delta, float lim, float *out)
{
    uint32_t r = C4G_SF_NONFINITE;
    if (out != NULL) {
        *out = delta;
        if ((c4g_f32_finite(smp_cur) != 0) && (c4g_f32_finite(delta) != 0)) {
            if (sf_limit_ok(lim) == 0) {
                r = C4G_SF_BAD_LIMIT;
            } else {
                /* smp_cur + delta in [-lim, lim]  <=>  delta in [-lim - smp, lim - smp] */
                const float lo = -lim - smp_cur;
                const float hi = lim - smp_cur;
                r = 0U;
                if (delta > hi) {
                    *out = hi;
                    r = C4G_SF_DCURRENT;
                } else if (delta < lo) {
                    *out = lo;
                    r = C4G_SF_DCURRENT;
                } else {
                    /* within limits */
                }
            }
        }
    }
    return r;
}

static inline uint32_t sf_step(float prev, float target, float max_step, float *out)
{
    uint32_t r = C4G_SF_NONFINITE;
    if (out != NULL) {
        *out = target;
        if ((c4g_f32_finite(prev) != 0) && (c4g_f32_finite(target) != 0)) {
            if (sf_limit_ok(max_step) == 0) {
                r = C4G_SF_BAD_LIMIT;
            } else if (max_step > 0.0F) {
                const float d = target - prev;
                float dc = d;
                r = (c4g_f32_finite(d) != 0) ? sf_clamp_sym(d, max_step, C4G_SF_STEP, &dc)
                                             : C4G_SF_NONFINITE;
                if (r == C4G_SF_STEP) {
                    *out = prev + dc;
                }
            } else {
                r = 0U; /* check off */
            }
        }
    }
    return r;
}

static inline uint32_t sf_velocity(float vel, float max_vel, float *out)
{
    uint32_t r = C4G_SF_NONFINITE;
    if (out != NULL) {
        *out = vel;
        if (c4g_f32_finite(vel) != 0) {
            if (sf_limit_ok(max_vel) == 0) {
                r = C4G_SF_BAD_LIMIT;
            } else if (max_vel > 0.0F) {
                r = sf_clamp_sym(vel, max_vel, C4G_SF_VELOCITY, out);
            } else {
                r = 0U;
            }
        }
    }
    return r;
}

static inline uint32_t sf_stroke(float pos, float min, float max, float *out)
{
    uint32_t r = C4G_SF_NONFINITE;
    if (out != NULL) {
        *out = pos;
        if ((c4g_f32_finite(pos) != 0) && (c4g_f32_finite(min) != 0) &&
            (c4g_f32_finite(max) != 0)) {
            r = 0U;
            if (min < max) {
                if (pos > max) {
                    *out = max;
                    r = C4G_SF_STROKE;
                } else if (pos < min) {
                    *out = min;
                    r = C4G_SF_STROKE;
                } else {
                    /* inside the stroke */
                }
            }
        }
    }
    return r;
}

#endif /* C4G_CTL_SF_H */
