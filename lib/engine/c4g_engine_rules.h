/* SPDX-License-Identifier: MIT */
/* Control engine internals shared by the step (c4g_engine.c) and the finish with the safety
 * filter (c4g_safety.c): per-mode rules from the mode table and the request overlays. */
#ifndef C4G_ENGINE_RULES_H
#define C4G_ENGINE_RULES_H

#include "c4g_safety_filter.h"

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
/* c4g_engine_priv_t.uni_rules when the axes' rules differ (no mode's rules have this bit). */
#define R_MIXED 0x80000000U
/* The rule words of the modes a PC drives (mode_rules: the table's rules and PC fields). */
#define R_MODE_1 (C4G_MR_ABS | C4G_MR_VEL | C4G_MR_VADD | C4G_MR_CUR | C4G_MR_FE | C4G_PCF_D1 | \
                  C4G_PCF_D2 | C4G_PCF_D4 | C4G_PCF_D5)
#define R_MODE_2 (C4G_MR_VADD | C4G_MR_CUR | C4G_MR_FE | C4G_PCF_D4 | C4G_PCF_D5)
#define R_MODE_4 (C4G_MR_ABS | C4G_MR_VEL | C4G_MR_FE | C4G_PCF_D1 | C4G_PCF_D2)
#define R_MODE_5 (C4G_MR_INT_D2 | C4G_MR_VEL | C4G_MR_FE | C4G_PCF_D1 | C4G_PCF_D2)
#define R_MODE_7 (C4G_MR_INT_D1 | C4G_MR_FE | C4G_PCF_D1)
#define R_MODE_8 (C4G_MR_INT_D4 | C4G_MR_VADD | C4G_MR_FE | C4G_PCF_D4)
#define R_MODE_9 (C4G_MR_DCUR | C4G_MR_FE | C4G_PCF_D5)
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
    for (a = 0U; a < C4G_ARMS; a++) {
        over[a] = arm_overlay(&eng->arm[a]);
        if (over[a] != 0) {
            some = 1U;
        }
    }
    /* fe_any: some fe_latch[] set (kept by the filter and the step) */
    return ((some | eng->priv.fe_any) != 0U) ? 1U : 0U;
}

#endif /* C4G_ENGINE_RULES_H */
