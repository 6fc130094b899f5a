/* SPDX-License-Identifier: MIT */
/* Monitoring records equivalent to the controller's moni types 19..24 (manual chapter 16)
 * (the CSV text of a record is a tool helper: lib/host/c4gh_csv.c).
 * The manual speaks from the SMP+: its "RX packet" is the PC's reply (pc_*), its
 * "TX packet" the controller's packet (smp_*). */
#include "c4g_engine_util.h"

#define N_TYPES 6U
#define N_VALUES 5U

typedef enum src {
    PC_D1 = 0, PC_D2, PC_D3, PC_D4, PC_D5, SMP_D1, SMP_D2, SMP_D3, SMP_D4, SMP_D5, SMP_E1, SMP_E2
} src_t;

static const src_t moni_src[N_TYPES][N_VALUES] = {
    {PC_D1, PC_D2, PC_D3, PC_D4, PC_D5},      /* 19: the whole packet from the PC */
    {SMP_D1, SMP_D2, SMP_D3, SMP_D4, SMP_D5}, /* 20: the whole packet from SMP+ */
    {PC_D1, PC_D2, SMP_D1, SMP_D3, SMP_D5},   /* 21: mode 5 */
    {PC_D4, PC_D5, SMP_D1, SMP_D3, SMP_D5},   /* 22: mode 2 */
    {SMP_D1, SMP_D5, SMP_E1, SMP_E2, PC_D5},  /* 23: mode 9 */
    {SMP_D1, SMP_D5, SMP_E1, SMP_E2, PC_D4},  /* 24: mode 8 */
};



static float src_value(src_t s, const c4g_ctrl_axis_t *rx, const c4g_pc_axis_t *tx)
{
    float v;
    switch (s) {
    case PC_D1: v = tx->target_pos; break;
    case PC_D2: v = tx->target_vel; break;
    case PC_D3: v = tx->measure; break;
    case PC_D4: v = tx->vel_add; break;
    case PC_D5: v = tx->current_add; break;
    case SMP_D1: v = rx->target_pos; break;
    case SMP_D2: v = rx->target_vel; break;
    case SMP_D3: v = rx->actual_pos; break;
    case SMP_D4: v = rx->actual_vel; break;
    case SMP_D5: v = rx->current_ref; break;
    case SMP_E1: v = rx->ext[0]; break;
    case SMP_E2:
    default: v = rx->ext[1]; break;
    }
    return v;
}

static const char *src_name(src_t s)
{
    const char *t;
    switch (s) {
    case PC_D1: t = "pc_d1"; break;
    case PC_D2: t = "pc_d2"; break;
    case PC_D3: t = "pc_d3"; break;
    case PC_D4: t = "pc_d4"; break;
    case PC_D5: t = "pc_d5"; break;
    case SMP_D1: t = "smp_d1"; break;
    case SMP_D2: t = "smp_d2"; break;
    case SMP_D3: t = "smp_d3"; break;
    case SMP_D4: t = "smp_d4"; break;
    case SMP_D5: t = "smp_d5"; break;
    case SMP_E1: t = "smp_e1"; break;
    case SMP_E2:
    default: t = "smp_e2"; break;
    }
    return t;
}

static int type_ok(uint32_t type)
{
    return ((type >= C4G_MONI_FIRST) && (type <= C4G_MONI_LAST)) ? 1 : 0;
}

c4g_status_t c4g_moni_record(uint32_t type, const c4g_ctrl_packet_t *rx,
                             const c4g_pc_packet_t *tx, uint32_t axis, c4g_moni_rec_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((rx != NULL) && (tx != NULL) && (out != NULL)) {
        if (type_ok(type) == 0) {
            st = C4G_ERR_ARG;
        } else if ((axis >= rx->n_axes) || (axis >= tx->n_axes) || (axis >= C4G_MAX_AXES)) {
            st = C4G_ERR_AXES;
        } else {
            uint32_t k;
            const uint32_t t = type - C4G_MONI_FIRST;
            out->type = type;
            out->num = rx->num;
            out->axis = axis;
            out->mode = rx->ax[axis].mode;
            for (k = 0U; k < N_VALUES; k++) {
                out->v[k] = src_value(moni_src[t][k], &rx->ax[axis], &tx->ax[axis]);
            }
            st = C4G_OK;
        }
    }
    return st;
}

const char *c4g_moni_value_name(uint32_t type, uint32_t k)
{
    const char *name = "?";
    if ((type_ok(type) != 0) && (k < N_VALUES)) {
        name = src_name(moni_src[type - C4G_MONI_FIRST][k]);
    }
    return name;
}
