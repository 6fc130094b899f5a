/* SPDX-License-Identifier: MIT */
/* PC-side safety checks (sections 14.17.2 and 15.7): pure functions, one per rule
 * (bodies in c4g_engine_sf.h, shared with the inlined per-tick filter). */
#include "c4g_safety_filter.h"

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
