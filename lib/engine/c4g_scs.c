/* SPDX-License-Identifier: MIT */
/* Soft control switching (manual chapter 12): the linear model chi/eta/rho, the
 * variable-gain reducer and the variable-threshold limiter, plus a timing helper. */
#include "c4g_engine_util.h"

static int gain_ok(float g)
{
    return ((c4g_f32_finite(g) != 0) && (g >= 0.0F) && (g <= 1.0F)) ? 1 : 0;
}

c4g_status_t c4g_scs_linear(uint64_t t_ns, uint64_t t1_ns, uint64_t t2_ns, c4g_scs_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (out != NULL) {
        st = C4G_ERR_ARG;
        if (t2_ns > t1_ns) {
            float chi;
            if (t_ns <= t1_ns) {
                chi = 0.0F;
            } else if (t_ns >= t2_ns) {
                chi = 1.0F;
            } else {
                /* Ratio of two ns spans; float keeps 24 bits, ample for a gain. */
                const uint64_t num = t_ns - t1_ns;
                const uint64_t den = t2_ns - t1_ns;
                chi = (float)num / (float)den;
                chi = (chi > 1.0F) ? 1.0F : chi;
            }
            out->chi = chi;
            out->eta = chi;
            out->rho = 1.0F - chi;
            st = C4G_OK;
        }
    }
    return st;
}

c4g_status_t c4g_scs_reduce(float gain, float i, float *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (out != NULL) {
        if ((c4g_f32_finite(gain) == 0) || (c4g_f32_finite(i) == 0)) {
            st = C4G_ERR_NONFINITE;
        } else if (gain_ok(gain) == 0) {
            st = C4G_ERR_ARG;
        } else {
            *out = gain * i;
            st = C4G_OK;
        }
    }
    return st;
}

c4g_status_t c4g_scs_limit(float gain, float i_max, float i_min, float i, float *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (out != NULL) {
        if ((c4g_f32_finite(gain) == 0) || (c4g_f32_finite(i_max) == 0) ||
            (c4g_f32_finite(i_min) == 0) || (c4g_f32_finite(i) == 0)) {
            st = C4G_ERR_NONFINITE;
        } else if ((gain_ok(gain) == 0) || (i_max < i_min)) {
            st = C4G_ERR_ARG;
        } else {
            const float thr = gain * (i_max - i_min);
            if (c4g_f32_finite(thr) == 0) {
                st = C4G_ERR_NONFINITE;
            } else {
                if (i > thr) {
                    *out = thr;
                } else if (i < -thr) {
                    *out = -thr;
                } else {
                    *out = i;
                }
                st = C4G_OK;
            }
        }
    }
    return st;
}

c4g_status_t c4g_scs_currents(const c4g_scs_t *s, c4g_scs_dir_t dir, float i_dyn, float i_reg,
                              float i_max, float i_min, float *dyn_out, float *reg_out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (dyn_out != NULL) && (reg_out != NULL)) {
        float g_dyn = s->eta;
        float g_reg = s->rho;
        st = C4G_OK;
        if (dir == C4G_SCS_TO_DSA) {
            g_dyn = s->rho;
            g_reg = s->eta;
        } else if (dir != C4G_SCS_TO_PC) {
            st = C4G_ERR_ARG;
        } else {
            /* TO_PC: the defaults above */
        }
        if (st == C4G_OK) {
            float d = 0.0F;
            float r = 0.0F;
            st = c4g_scs_reduce(g_dyn, i_dyn, &d);
            if (st == C4G_OK) {
                st = c4g_scs_limit(g_reg, i_max, i_min, i_reg, &r);
            }
            if (st == C4G_OK) {
                *dyn_out = d;
                *reg_out = r;
            }
        }
    }
    return st;
}

c4g_status_t c4g_period_ns(const c4g_init_t *init, uint64_t *ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((init != NULL) && (ns != NULL)) {
        st = C4G_ERR_PERIOD;
        if ((init->period_ms >= 1) && (init->period_ms <= 1000)) {
            *ns = (uint64_t)init->period_ms * 1000000U;
            st = C4G_OK;
        }
    }
    return st;
}
