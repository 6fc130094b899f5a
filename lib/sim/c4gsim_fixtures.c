/* SPDX-License-Identifier: MIT */
/* Test and demo fixtures (not part of the real-time library). */
#include "c4gsim_fixtures.h"

#include <string.h>

/* Figure 10.1 of the manual: 6 axes on ARM 1, 2 ms, version 3.11.115. */
c4g_status_t c4gsim_fig10_1(c4g_init_t *out)
{
    static const float fig_cal[6] = {0.142965F, 0.170353F, 0.222660F, 0.405883F, 0.039380F, 0.355824F};
    static const float fig_azlim[6] = {24.5F, 24.5F, 24.5F, 9.5F, 9.5F, 9.5F};
    static const float fig_axinfo[6] = {0.0F, 0.0F, 0.0F, -0.0200F, 0.0204F, 0.0200F};
    static const float fig_txrate[6] = {-181.587296F, 159.260864F, 162.473694F,
                                        72.585968F,   78.750000F,  -50.000000F};
    static const float fig_follow[6] = {7.5F, 7.5F, 7.5F, 7.5F, 7.5F, 0.0F};
    static const int32_t fig_types[C4G_N_FIELD_TYPES] = {1, 2, 3, 1, 2, 2, 2, 2, 2, 3, 3, 3};
    c4g_status_t st = C4G_ERR_NULL;
    if (out != NULL) {
        uint32_t arm;
        uint32_t ax;
        (void)memset(out, 0, sizeof *out);
        out->num = C4G_INIT_NUM;
        out->n_field_pck = C4G_FIELDS_PER_PACKET;
        out->n_field_ax = C4G_FIELDS_PER_AXIS;
        out->n_ax_open = 6;
        for (ax = 0U; ax < C4G_N_FIELD_TYPES; ax++) {
            out->field_type[ax] = fig_types[ax];
        }
        out->period_ms = 2;
        for (arm = 0U; arm < C4G_ARMS; arm++) {
            for (ax = 0U; ax < C4G_AXES_PER_ARM; ax++) {
                out->open_ax[arm][ax] = C4G_OPEN_AX_NONE;
            }
        }
        for (ax = 0U; ax < 6U; ax++) {
            out->open_ax[0][ax] = (int32_t)ax;
            out->cal_data[0][ax] = fig_cal[ax];
            out->az_lim[0][ax] = fig_azlim[ax];
            out->ax_info[0][ax] = fig_axinfo[ax];
            out->tx_rate[0][ax] = fig_txrate[ax];
            out->follow_error[0][ax] = fig_follow[ax];
        }
        out->version_major = 3;
        out->version_minor = 11;
        out->version_build = 115;
        st = C4G_OK;
    }
    return st;
}
