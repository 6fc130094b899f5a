/* SPDX-License-Identifier: MIT */
/* The PC-side safety checks as inline functions. Each rule has a core (sfc_*: finite inputs,
 * valid limits, as the per-tick filter in c4g_safety.c guarantees) and a checked form
 * (sf_*: validates first, exported by c4g_safety.c as c4g_sf_*). Every form returns the
 * C4G_SF_* bits it raised; the checked forms return C4G_SF_NONFINITE on any non-finite
 * input and C4G_SF_BAD_LIMIT on a limit that is negative or non-finite, leaving the value. */
#ifndef C4G_SAFETY_FILTER_H
#define C4G_SAFETY_FILTER_H

#include "c4g_engine_util.h"

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

/* ------------------------------------------------------------------ checked forms */

/* A limit a check can use: finite and >= 0. */
static inline int sf_limit_ok(float lim)
{
    return ((c4g_f32_finite(lim) != 0) && (lim >= 0.0F)) ? 1 : 0;
}

static inline uint32_t sf_follow_error(float pos_ref, float pos_mis, float threshold, float *err)
{
    uint32_t r = C4G_SF_NONFINITE;
    float e = 0.0F;
    if ((c4g_f32_finite(pos_ref) != 0) && (c4g_f32_finite(pos_mis) != 0)) {
        r = sfc_follow_error(pos_ref, pos_mis, threshold, &e);
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
            r = (sf_limit_ok(lim) != 0) ? sfc_sym(cur, lim, C4G_SF_CURRENT, out) : C4G_SF_BAD_LIMIT;
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
            r = (sf_limit_ok(lim) != 0) ? sfc_delta_current(smp_cur, delta, lim, out)
                                        : C4G_SF_BAD_LIMIT;
        }
    }
    return r;
}

static inline uint32_t sf_step(float prev, float target, float max_step, float *out)
{
    uint32_t r = C4G_SF_NONFINITE;
    if (out != NULL) {
        *out = target;
        if ((c4g_f32_finite(prev) != 0) && (c4g_f32_finite(target) != 0) &&
            (c4g_f32_finite(target - prev) != 0)) {
            r = (sf_limit_ok(max_step) != 0) ? sfc_step(prev, target, max_step, out)
                                             : C4G_SF_BAD_LIMIT;
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
            r = (sf_limit_ok(max_vel) != 0) ? sfc_velocity(vel, max_vel, out) : C4G_SF_BAD_LIMIT;
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
            /* off only as 0, 0: an empty or reversed stroke is a bad limit, never "off" */
            const uint32_t off = c4g_flag(((c4g_f32_bits(min) | c4g_f32_bits(max)) &
                                           0x7FFFFFFFU) == 0U);
            r = ((off != 0U) || (min < max)) ? sfc_stroke(pos, min, max, out) : C4G_SF_BAD_LIMIT;
        }
    }
    return r;
}

#endif /* C4G_SAFETY_FILTER_H */
