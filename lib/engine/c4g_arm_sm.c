/* SPDX-License-Identifier: MIT */
/* The per-arm mode state machine and the PC request rules (manual chapters 13, 14, 15, 24; field facts mode list). */
#include "c4g_engine_util.h"

static bool idle_mode(int32_t mode)
{
    return (mode == C4G_MODE_0) || (mode == C4G_MODE_0_DEBUG);
}

/* ------------------------------------------------------------------ state machine */

c4g_status_t c4g_engine_config_default(c4g_engine_config_t *cfg)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (cfg != NULL) {
        cfg->request_timeout_ticks = 100U;
        cfg->start_ns = 0U;
        cfg->moving_eps = 0.0F;
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_arm_sm_init(c4g_arm_sm_t *sm, uint32_t n_axes)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (sm != NULL) {
        st = C4G_ERR_ARG;
        if (n_axes <= C4G_AXES_PER_ARM) {
            (void)memset(sm, 0, sizeof *sm);
            sm->n_axes = n_axes;
            st = C4G_OK;
        }
    }
    return st;
}

/* @p row: the table row of sm->mode (the caller looked it up once for the whole update). */
static c4g_fsm_state_t infer_fsm(const c4g_arm_sm_t *sm, const c4g_mode_info_t *row)
{
    c4g_fsm_state_t s = C4G_FSM_UNKNOWN;
    const int32_t m = sm->mode;
    if ((sm->drive_on == 0U) || ((row->flags & C4G_MF_SPECIAL) != 0U)) {
        s = C4G_FSM_UNKNOWN;
    } else if (idle_mode(m)) {
        s = (sm->moving != 0U) ? C4G_FSM_S10 : C4G_FSM_S00;
    } else {
        const int32_t op = row->operating;
        /* OPEN TYPE A: no SMP+ trajectory (1, 4, 5); TYPE B when SMP+ moves too. */
        if ((op == C4G_MODE_1) || (op == C4G_MODE_4) || (op == C4G_MODE_5)) {
            s = C4G_FSM_S01;
        } else {
            s = (sm->moving != 0U) ? C4G_FSM_S11 : C4G_FSM_S01;
        }
    }
    return s;
}

/* Special mode entered / left: flags and events. */
static uint32_t special_change(c4g_arm_sm_t *sm, int32_t old, int32_t mode)
{
    uint32_t ev = 0U;
    if (old == C4G_MODE_DRIVING_ON) {
        ev |= C4G_CEV_DRIVING_ON_END;
    }
    if ((old == C4G_MODE_FREEZING_A) && (sm->frozen == C4G_MODE_FREEZING_A)) {
        sm->frozen = 0;
        sm->exit_req = 0U;
        ev |= C4G_CEV_FREEZE_A_END;
    }
    switch (mode) {
    case C4G_MODE_DRIVING_ON:
        ev |= C4G_CEV_DRIVING_ON;
        break;
    case C4G_MODE_FREEZING_A:
        sm->frozen = C4G_MODE_FREEZING_A;
        ev |= C4G_CEV_FREEZE_A;
        break;
    case C4G_MODE_FREEZING_P_IN:
        sm->frozen = C4G_MODE_FREEZING_P_IN;
        ev |= C4G_CEV_FREEZE_P_IN;
        break;
    case C4G_MODE_FREEZING_P_OUT:
        if (sm->frozen == C4G_MODE_FREEZING_P_IN) {
            sm->frozen = 0;
        }
        ev |= C4G_CEV_FREEZE_P_OUT;
        break;
    case C4G_MODE_EXIT_OPEN:
        sm->ended = 1U;
        ev |= C4G_CEV_END_COMM;
        break;
    case C4G_MODE_SVR_RESTART:
        sm->restart = 1U;
        ev |= C4G_CEV_RESTART;
        break;
    default:
        break;
    }
    return ev;
}

/* Requests when the mode changed. */
static uint32_t requests_on_change(c4g_arm_sm_t *sm, int32_t mode)
{
    uint32_t ev = 0U;
    if ((sm->exit_req != 0U) && (sm->frozen != C4G_MODE_FREEZING_A)) {
        sm->exit_req = 0U; /* the controller acted on the exit */
        sm->leaving = 1U;
    }
    if ((sm->leaving != 0U) && (idle_mode(mode))) {
        sm->leaving = 0U;
        ev |= C4G_CEV_EXIT_DONE;
    }
    return ev;
}

static uint32_t enter_mode(c4g_arm_sm_t *sm, int32_t old, int32_t mode, uint64_t now_ns)
{
    uint32_t ev = C4G_CEV_MODE_CHANGE;
    if ((sm->started != 0U) && (!c4g_mode_transition_ok(old, mode))) {
        ev |= C4G_CEV_UNEXPECTED;
    }
    sm->prev_mode = old;
    sm->mode = mode;
    sm->mode_since_ns = now_ns;
    sm->ticks_in_mode = 0U;
    ev |= special_change(sm, old, mode);
    ev |= requests_on_change(sm, mode);
    if (c4g_mode_is_special(mode)) {
        sm->phase = C4G_MPH_SPECIAL;
        sm->phase_since_ns = now_ns;
    } else if (idle_mode(mode)) {
        if ((mode == C4G_MODE_0) && (sm->op_mode != 0)) {
            ev |= C4G_CEV_MODE0;
        }
        sm->op_mode = 0;
        sm->phase = C4G_MPH_NONE;
        sm->phase_since_ns = now_ns;
    } else if (c4g_mode_is_standby(mode)) {
        if (sm->phase != C4G_MPH_END) {
            ev |= C4G_CEV_END;
            sm->phase_since_ns = now_ns;
        }
        sm->op_mode = c4g_mode_operating(mode);
        sm->phase = C4G_MPH_END;
    } else {
        sm->op_mode = mode;
        sm->phase = C4G_MPH_START;
        sm->phase_since_ns = now_ns;
        ev |= C4G_CEV_START;
    }
    return ev;
}

/* Same mode as the previous packet: phases advance, requests age. */
static uint32_t stay_in_mode(c4g_arm_sm_t *sm, const c4g_engine_config_t *cfg, uint64_t now_ns)
{
    uint32_t ev = 0U;
    if (sm->ticks_in_mode < UINT32_MAX) {
        sm->ticks_in_mode++;
    }
    if (sm->phase == C4G_MPH_START) {
        const int32_t op = sm->op_mode;
        int counted = 0;
        if ((op == C4G_MODE_1) || (op == C4G_MODE_2)) {
            counted = 1;
        }
        /* Modes 1 and 2: SMP+ ramps its switching counter for start_ns (24.2.3-4). */
        if ((counted == 0) || ((now_ns - sm->phase_since_ns) >= cfg->start_ns)) {
            sm->phase = C4G_MPH_CRUISE;
            sm->phase_since_ns = now_ns;
            ev |= C4G_CEV_CRUISE;
        }
    }
    if (sm->exit_req != 0U) {
        if ((sm->frozen == C4G_MODE_FREEZING_A) &&
            ((sm->mode != C4G_MODE_FREEZING_A) || (sm->exit_ticks >= cfg->request_timeout_ticks))) {
            /* The exit went out; the controller is in mode 0 (it need not echo 500). */
            if (sm->exit_ticks >= 1U) {
                sm->frozen = 0;
                sm->exit_req = 0U;
                ev |= C4G_CEV_FREEZE_A_END;
            }
        } else if (sm->exit_ticks >= cfg->request_timeout_ticks) {
            sm->exit_req = 0U;
            sm->phase = (sm->phase == C4G_MPH_END) ? C4G_MPH_CRUISE : sm->phase;
            ev |= C4G_CEV_REQ_TIMEOUT;
        } else {
            /* still waiting for the controller */
        }
    }
    return ev;
}

/* Drive, motion and mixed-mode flags of this packet, with their change events. */
static uint32_t arm_flags(c4g_arm_sm_t *sm, uint32_t mixed, uint32_t drive_on, uint32_t moving)
{
    uint32_t ev = 0U;
    if ((sm->started != 0U) && (drive_on != sm->drive_on)) {
        ev |= (drive_on != 0U) ? C4G_CEV_DRIVE_ON : C4G_CEV_DRIVE_OFF;
    }
    if ((mixed != 0U) && (sm->mixed == 0U)) {
        ev |= C4G_CEV_MIXED;
    }
    sm->drive_on = drive_on;
    sm->moving = c4g_flag(moving != 0U);
    sm->mixed = c4g_flag(mixed != 0U);
    return ev;
}

/* A 505 / 508 latch ends once it went out and the drives are off (15.5, 15.7). */
static uint32_t latch_end(c4g_arm_sm_t *sm)
{
    uint32_t ev = 0U;
    if ((sm->latch != 0U) && (sm->latch_sent != 0U) && (sm->drive_on == 0U)) {
        sm->latch = 0U;
        sm->latch_sent = 0U;
        ev = C4G_CEV_LATCH_CLEARED;
    }
    return ev;
}

c4g_status_t c4g_arm_sm_update(c4g_arm_sm_t *sm, const c4g_engine_config_t *cfg, int32_t mode,
                               uint32_t mixed, uint8_t drive_byte, uint32_t moving,
                               uint64_t now_ns, uint32_t *events)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((sm != NULL) && (cfg != NULL) && (events != NULL)) {
        /* one table lookup per tick: the known-mode check and the FSM's flags */
        const c4g_mode_info_t *row = c4g_mode_find(mode);
        *events = 0U;
        st = C4G_ERR_MODE;
        if (row != NULL) {
            const uint32_t drive_on = c4g_flag(drive_byte == (uint8_t)C4G_STS_MOVING);
            uint32_t ev = arm_flags(sm, mixed, drive_on, moving);
            if ((sm->started == 0U) || (mode != sm->mode)) {
                ev |= enter_mode(sm, sm->mode, mode, now_ns);
            } else {
                ev |= stay_in_mode(sm, cfg, now_ns);
            }
            sm->started = 1U;
            sm->driving_on = c4g_flag(mode == C4G_MODE_DRIVING_ON);
            ev |= latch_end(sm);
            sm->fsm = infer_fsm(sm, row); /* sm->mode == mode here */
            *events = ev;
            st = C4G_OK;
        }
    }
    return st;
}

/* ------------------------------------------------------------------ request rules */

/* Every operating mode is started by the controller's PDL2 program (manual 24.2: "START
 * begins when SW_PDL sets this mode", for modes 0', 1, 2, 4, 5, 7, 8 and 9; figure 24.3 has
 * SW_PC echo the mode it receives). The PC's own requests are EXIT_FROM_OPEN, 500, 505 and
 * 508, each with its own call. */
static c4g_status_t check_mode_req(int32_t mode)
{
    c4g_status_t st = C4G_ERR_PDL_ONLY;
    if (!c4g_mode_is_known(mode)) {
        st = C4G_ERR_MODE;
    }
    return st;
}

/* May the arm's mode @p m be left with EXIT_FROM_OPEN? */
static c4g_status_t exit_from_mode(int32_t m)
{
    c4g_status_t st = C4G_OK;
    if (idle_mode(m)) {
        st = C4G_ERR_NOT_IN_OPEN;
    } else if (c4g_mode_is_standby(m)) {
        st = C4G_ERR_LEAVING;
    } else if ((m == C4G_MODE_2) || (c4g_mode_is_special(m))) {
        st = C4G_ERR_FORBIDDEN; /* mode 2 ends by PDL2 setting 12 (24.2.4) */
    } else {
        /* an operating mode the PC may end */
    }
    return st;
}

static c4g_status_t check_exit(const c4g_arm_sm_t *sm)
{
    c4g_status_t st = C4G_OK;
    /* An active freezing is always left with an exit (15.1); a repeated exit is a no-op. */
    if (sm->frozen != C4G_MODE_FREEZING_A) {
        if (sm->driving_on != 0U) {
            st = C4G_ERR_DRIVING_ON;
        } else if (sm->frozen != 0) {
            st = C4G_ERR_FROZEN;
        } else if ((sm->exit_req == 0U) && (sm->leaving == 0U)) {
            st = exit_from_mode(sm->mode);
        } else {
            /* already sent: idempotent */
        }
    }
    return st;
}

static c4g_status_t check_freeze(const c4g_arm_sm_t *sm)
{
    c4g_status_t st = C4G_OK;
    if (sm->frozen != C4G_MODE_FREEZING_A) { /* already frozen: idempotent */
        if (sm->driving_on != 0U) {
            st = C4G_ERR_DRIVING_ON;
        } else if (sm->latch != 0U) {
            st = C4G_ERR_LATCHED;
        } else if (sm->frozen != 0) {
            st = C4G_ERR_FROZEN;
        } else if ((sm->mode != C4G_MODE_0) || (sm->mixed != 0U) || (sm->exit_req != 0U) ||
                   (sm->leaving != 0U)) {
            st = C4G_ERR_NOT_MODE0; /* 15.1: only from mode 0 */
        } else {
            /* from mode 0: allowed */
        }
    }
    return st;
}

c4g_status_t c4g_arm_sm_check(const c4g_arm_sm_t *sm, c4g_req_kind_t kind, int32_t mode)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (sm != NULL) {
        if (sm->n_axes == 0U) {
            st = C4G_ERR_NOT_OPEN;
        } else if (sm->ended != 0U) {
            st = C4G_ERR_ENDED;
        } else {
            switch (kind) {
            case C4G_REQ_MODE:
                st = check_mode_req(mode);
                break;
            case C4G_REQ_EXIT:
                st = check_exit(sm);
                break;
            case C4G_REQ_FREEZE:
                st = check_freeze(sm);
                break;
            case C4G_REQ_DRIVE_OFF:
            case C4G_REQ_FOLLOW_ERROR:
                st = C4G_OK; /* safety requests are never refused */
                break;
            default:
                st = C4G_ERR_ARG;
                break;
            }
        }
    }
    return st;
}
