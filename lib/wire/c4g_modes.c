/* SPDX-License-Identifier: MIT */
/* The mode vocabulary: lookups, predicates and transition rules, all derived from the one
 * mode table C4G_MODE_TABLE in c4gopen_wire.h. */
#include "c4gopen.h"

/* Deviation D-05 (MISRA 20.10): the X-macro names each row by pasting its id. */
/* cppcheck-suppress misra-c2012-20.10 */
#define MODE_INDEX_(id, code, flags, fields, rules, op, from, name, text) MODE_IX_##id,
/* Deviation D-05 (MISRA 2.4): the row indexes are constants, the enum needs no tag. */
/* cppcheck-suppress misra-c2012-2.4 */
enum { C4G_MODE_TABLE(MODE_INDEX_) N_MODES };

/* Row index of @p mode, N_MODES for a code the protocol does not define. A switch, not a
 * search: it runs several times per axis and tick. */
static inline uint32_t mode_index(int32_t mode)
{
    uint32_t i;
/* Deviation D-05 (MISRA 20.10), as above. */
/* cppcheck-suppress misra-c2012-20.10 */
#define MODE_CASE_(id, code, flags, fields, rules, op, from, name, text) \
    case (code): i = (uint32_t)MODE_IX_##id; break;
    switch (mode) {
    C4G_MODE_TABLE(MODE_CASE_)
    default: i = (uint32_t)N_MODES; break;
    }
    return i;
}

const c4g_mode_info_t *c4g_mode_find(int32_t mode)
{
#define MODE_ROW_(id, code, flags, fields, rules, op, from, name, text) \
    {(code), (flags), (fields), (rules), (op), (from), (name), (text)},
    static const c4g_mode_info_t mode_table[N_MODES] = {C4G_MODE_TABLE(MODE_ROW_)};
    const uint32_t i = mode_index(mode);
    const c4g_mode_info_t *row = NULL;
    if (i < (uint32_t)N_MODES) {
        row = &mode_table[i];
    }
    return row;
}

bool c4g_mode_is_known(int32_t mode)
{
    return c4g_mode_find(mode) != NULL;
}

c4g_status_t c4g_mode_info(int32_t mode, c4g_mode_info_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (out != NULL) {
        const c4g_mode_info_t *row = c4g_mode_find(mode);
        st = C4G_ERR_MODE;
        if (row != NULL) {
            *out = *row;
            st = C4G_OK;
        }
    }
    return st;
}

uint32_t c4g_mode_flags(int32_t mode)
{
    const c4g_mode_info_t *row = c4g_mode_find(mode);
    return (row != NULL) ? row->flags : 0U;
}

static bool has_flag(int32_t mode, uint32_t flag)
{
    return (c4g_mode_flags(mode) & flag) != 0U;
}

const char *c4g_mode_name(int32_t mode)
{
    const c4g_mode_info_t *row = c4g_mode_find(mode);
    return (row != NULL) ? row->name : "UNKNOWN";
}

const char *c4g_mode_description(int32_t mode)
{
    const c4g_mode_info_t *row = c4g_mode_find(mode);
    return (row != NULL) ? row->description : "unknown mode";
}

bool c4g_mode_is_available(int32_t mode)
{
    return has_flag(mode, C4G_MF_AVAILABLE);
}

bool c4g_mode_pc_trajectory(int32_t mode)
{
    return has_flag(mode, C4G_MF_PC_TRAJ);
}

bool c4g_mode_pc_loops(int32_t mode)
{
    return has_flag(mode, C4G_MF_PC_LOOPS);
}

bool c4g_mode_is_special(int32_t mode)
{
    return has_flag(mode, C4G_MF_SPECIAL);
}

bool c4g_mode_is_standby(int32_t mode)
{
    return has_flag(mode, C4G_MF_STANDBY);
}

uint32_t c4g_mode_pc_fields(int32_t mode)
{
    const c4g_mode_info_t *row = c4g_mode_find(mode);
    return (row != NULL) ? row->pc_fields : 0U;
}

uint32_t c4g_mode_rules(int32_t mode)
{
    const c4g_mode_info_t *row = c4g_mode_find(mode);
    return (row != NULL) ? row->rules : 0U;
}

int32_t c4g_mode_operating(int32_t mode)
{
    const c4g_mode_info_t *row = c4g_mode_find(mode);
    return (row != NULL) ? row->operating : -1;
}

static bool mode_is_idle(int32_t mode)
{
    return (mode == C4G_MODE_0) || (mode == C4G_MODE_0_DEBUG);
}

/* The `from` column: any, idle, or one named mode (a stand-by mode may also follow its
 * operating mode). */
static bool from_ok(const c4g_mode_info_t *row, int32_t from)
{
    bool ok;
    if (row->from == C4G_FROM_ANY) {
        ok = true;
    } else if (row->from == C4G_FROM_IDLE) {
        ok = mode_is_idle(from);
    } else {
        ok = (from == row->from) ||
             (((row->flags & C4G_MF_STANDBY) != 0U) && (from == row->operating));
    }
    return ok;
}

bool c4g_mode_transition_ok(int32_t from, int32_t to)
{
    const c4g_mode_info_t *row_to = c4g_mode_find(to);
    bool ok = false;
    if ((row_to != NULL) && c4g_mode_is_known(from)) {
        if ((from == to) || (to == C4G_MODE_0)) {
            ok = true; /* mode 0 can always be forced (505, 508, selector, exits) */
        } else if ((row_to->flags & (C4G_MF_SPECIAL | C4G_MF_STANDBY)) != 0U) {
            ok = from_ok(row_to, from);
        } else {
            /* an operating mode the controller has: from mode 0, or after drive on or
             * passive freezing (15.2) */
            ok = ((row_to->flags & C4G_MF_AVAILABLE) != 0U) &&
                 (mode_is_idle(from) || (from == C4G_MODE_DRIVING_ON) ||
                  (from == C4G_MODE_FREEZING_P_OUT));
        }
    }
    return ok;
}
