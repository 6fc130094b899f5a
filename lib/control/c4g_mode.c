/* SPDX-License-Identifier: MIT */
/* Mode table and predicates, controller transition rules, the per-arm state machine and
 * the PC request rules (manual chapters 13, 14, 15, 24; field facts mode list). */
#include "c4g_engine_util.h"

#define AV C4G_MF_AVAILABLE
#define TRJ C4G_MF_PC_TRAJ
#define LOOP C4G_MF_PC_LOOPS
#define SPC C4G_MF_SPECIAL
#define SBY C4G_MF_STANDBY
#define PCR C4G_MF_PC_REQUEST
#define F1 C4G_PCF_D1
#define F2 C4G_PCF_D2
#define F3 C4G_PCF_D3
#define F4 C4G_PCF_D4
#define F5 C4G_PCF_D5

#define N_MODES 30U

/* field facts "What the PC must fill per mode"; stand-by modes of 1 and 2 keep the loop
 * data (the PC holds the robot while SMP+ switches back, 24.2.3-4); 17/170 carry null data. */
typedef struct mode_row {
    int32_t code;
    uint32_t flags;
    uint32_t pc_fields;
    int32_t operating;
} mode_row_t;



static const mode_row_t *find_mode(int32_t mode)
{
    static const mode_row_t mode_table[N_MODES] = {
        {C4G_MODE_0, AV, 0U, C4G_MODE_0},
        {C4G_MODE_0_DEBUG, AV, F1 | F2, C4G_MODE_0_DEBUG},
        {C4G_MODE_1, AV | TRJ | LOOP, F1 | F2 | F4 | F5, C4G_MODE_1},
        {C4G_MODE_1_STANDBY, AV | TRJ | LOOP | SBY, F1 | F2 | F4 | F5, C4G_MODE_1},
        {C4G_MODE_2, AV | LOOP, F4 | F5, C4G_MODE_2},
        {C4G_MODE_2_STANDBY, AV | LOOP | SBY, F4 | F5, C4G_MODE_2},
        {C4G_MODE_3, LOOP, F5, C4G_MODE_3},
        {C4G_MODE_4, AV | TRJ, F1 | F2, C4G_MODE_4},
        {C4G_MODE_4_STANDBY, AV | SBY, 0U, C4G_MODE_4},
        {C4G_MODE_5, AV | TRJ, F1 | F2, C4G_MODE_5},
        {C4G_MODE_5_STANDBY, AV | SBY, 0U, C4G_MODE_5},
        {C4G_MODE_6, TRJ, F2, C4G_MODE_6},
        {C4G_MODE_7, AV | TRJ, F1, C4G_MODE_7},
        {C4G_MODE_7_STANDBY, AV | SBY, 0U, C4G_MODE_7},
        {C4G_MODE_7_STANDBY_EXIT, AV | SBY, 0U, C4G_MODE_7},
        {C4G_MODE_8, AV, F4, C4G_MODE_8},
        {C4G_MODE_9, AV, F5, C4G_MODE_9},
        {C4G_MODE_101, 0U, F3, C4G_MODE_101},
        {C4G_MODE_102, 0U, F3, C4G_MODE_102},
        {C4G_MODE_103, 0U, F3, C4G_MODE_103},
        {C4G_MODE_201, TRJ, 0U, C4G_MODE_201},
        {C4G_MODE_202, TRJ, 0U, C4G_MODE_202},
        {C4G_MODE_FREEZING_A, AV | SPC, 0U, C4G_MODE_FREEZING_A},
        {C4G_MODE_DRIVING_ON, AV | SPC, 0U, C4G_MODE_DRIVING_ON},
        {C4G_MODE_FREEZING_P_IN, AV | SPC, 0U, C4G_MODE_FREEZING_P_IN},
        {C4G_MODE_FREEZING_P_OUT, AV | SPC, 0U, C4G_MODE_FREEZING_P_OUT},
        {C4G_MODE_EXIT_OPEN, AV | SPC, 0U, C4G_MODE_EXIT_OPEN},
        {C4G_MODE_DRIVE_OFF, AV | SPC | PCR, 0U, C4G_MODE_DRIVE_OFF},
        {C4G_MODE_SVR_RESTART, AV | SPC, 0U, C4G_MODE_SVR_RESTART},
        {C4G_MODE_FOLLOW_ERROR, AV | SPC | PCR, 0U, C4G_MODE_FOLLOW_ERROR},
    };
    /* A switch, not a search: this runs several times per axis and tick. */
    uint32_t i;
    const mode_row_t *row = NULL;
    switch (mode) {
    case C4G_MODE_0: i = 0U; break;
    case C4G_MODE_0_DEBUG: i = 1U; break;
    case C4G_MODE_1: i = 2U; break;
    case C4G_MODE_1_STANDBY: i = 3U; break;
    case C4G_MODE_2: i = 4U; break;
    case C4G_MODE_2_STANDBY: i = 5U; break;
    case C4G_MODE_3: i = 6U; break;
    case C4G_MODE_4: i = 7U; break;
    case C4G_MODE_4_STANDBY: i = 8U; break;
    case C4G_MODE_5: i = 9U; break;
    case C4G_MODE_5_STANDBY: i = 10U; break;
    case C4G_MODE_6: i = 11U; break;
    case C4G_MODE_7: i = 12U; break;
    case C4G_MODE_7_STANDBY: i = 13U; break;
    case C4G_MODE_7_STANDBY_EXIT: i = 14U; break;
    case C4G_MODE_8: i = 15U; break;
    case C4G_MODE_9: i = 16U; break;
    case C4G_MODE_101: i = 17U; break;
    case C4G_MODE_102: i = 18U; break;
    case C4G_MODE_103: i = 19U; break;
    case C4G_MODE_201: i = 20U; break;
    case C4G_MODE_202: i = 21U; break;
    case C4G_MODE_FREEZING_A: i = 22U; break;
    case C4G_MODE_DRIVING_ON: i = 23U; break;
    case C4G_MODE_FREEZING_P_IN: i = 24U; break;
    case C4G_MODE_FREEZING_P_OUT: i = 25U; break;
    case C4G_MODE_EXIT_OPEN: i = 26U; break;
    case C4G_MODE_DRIVE_OFF: i = 27U; break;
    case C4G_MODE_SVR_RESTART: i = 28U; break;
    case C4G_MODE_FOLLOW_ERROR: i = 29U; break;
    default: i = N_MODES; break;
    }
    if (i < N_MODES) {
        row = &mode_table[i];
    }
    return row;
}

c4g_status_t c4g_mode_info(int32_t mode, c4g_mode_info_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (out != NULL) {
        const mode_row_t *row = find_mode(mode);
        st = C4G_ERR_MODE;
        if (row != NULL) {
            out->code = row->code;
            out->name = c4g_mode_name(mode);
            out->description = c4g_mode_description(mode);
            out->flags = row->flags;
            out->pc_fields = row->pc_fields;
            out->operating = row->operating;
            st = C4G_OK;
        }
    }
    return st;
}

uint32_t c4g_mode_flags(int32_t mode)
{
    const mode_row_t *row = find_mode(mode);
    return (row != NULL) ? row->flags : 0U;
}

static uint32_t mode_flags(int32_t mode)
{
    return c4g_mode_flags(mode);
}

static int has_flag(int32_t mode, uint32_t flag)
{
    return ((mode_flags(mode) & flag) != 0U) ? 1 : 0;
}

/* Switches over string literals: a pointer table would land in .data.rel.ro under PIE,
 * a char table is a partial initialization (MISRA 9.3). */
const char *c4g_mode_name(int32_t mode)
{
    const char *t;
    switch (mode) {
    case C4G_MODE_0: t = "MODE_0"; break;
    case C4G_MODE_0_DEBUG: t = "MODE_0_DEBUG"; break;
    case C4G_MODE_1: t = "MODE_1"; break;
    case C4G_MODE_1_STANDBY: t = "MODE_1_STANDBY"; break;
    case C4G_MODE_2: t = "MODE_2"; break;
    case C4G_MODE_2_STANDBY: t = "MODE_2_STANDBY"; break;
    case C4G_MODE_3: t = "MODE_3"; break;
    case C4G_MODE_4: t = "MODE_4"; break;
    case C4G_MODE_4_STANDBY: t = "MODE_4_STANDBY"; break;
    case C4G_MODE_5: t = "MODE_5"; break;
    case C4G_MODE_5_STANDBY: t = "MODE_5_STANDBY"; break;
    case C4G_MODE_6: t = "MODE_6"; break;
    case C4G_MODE_7: t = "MODE_7"; break;
    case C4G_MODE_7_STANDBY: t = "MODE_7_STANDBY"; break;
    case C4G_MODE_7_STANDBY_EXIT: t = "MODE_7_STANDBY_EXIT"; break;
    case C4G_MODE_8: t = "MODE_8"; break;
    case C4G_MODE_9: t = "MODE_9"; break;
    case C4G_MODE_101: t = "MODE_101"; break;
    case C4G_MODE_102: t = "MODE_102"; break;
    case C4G_MODE_103: t = "MODE_103"; break;
    case C4G_MODE_201: t = "MODE_201"; break;
    case C4G_MODE_202: t = "MODE_202"; break;
    case C4G_MODE_FREEZING_A: t = "FREEZING_A"; break;
    case C4G_MODE_DRIVING_ON: t = "DRIVING_ON"; break;
    case C4G_MODE_FREEZING_P_IN: t = "FREEZING_P_IN"; break;
    case C4G_MODE_FREEZING_P_OUT: t = "FREEZING_P_OUT"; break;
    case C4G_MODE_EXIT_OPEN: t = "EXIT_OPEN"; break;
    case C4G_MODE_DRIVE_OFF: t = "DRIVE_OFF"; break;
    case C4G_MODE_SVR_RESTART: t = "SVR_RESTART"; break;
    case C4G_MODE_FOLLOW_ERROR: t = "FOLLOW_ERROR"; break;
    default: t = "UNKNOWN"; break;
    }
    return t;
}

const char *c4g_mode_description(int32_t mode)
{
    const char *t;
    switch (mode) {
    case C4G_MODE_0:
        t = "SMP+ generates the trajectory and closes the loops; PC data ignored";
        break;
    case C4G_MODE_0_DEBUG:
        t = "mode 0': debug echo, the PC copies D1..D5 back";
        break;
    case C4G_MODE_1:
        t = "PC generates the trajectory and closes the loops (currents)";
        break;
    case C4G_MODE_1_STANDBY:
        t = "mode 1 exit: PC holds the robot while SMP+ switches back";
        break;
    case C4G_MODE_2:
        t = "SMP+ generates the trajectory, the PC closes the loops (currents)";
        break;
    case C4G_MODE_2_STANDBY:
        t = "mode 2 exit (set by PDL2): PC loops while SMP+ switches back";
        break;
    case C4G_MODE_3:
        t = "SMP+ velocity target, PC velocity loop (not available)";
        break;
    case C4G_MODE_4:
        t = "PC generates absolute position targets, SMP+ closes the loops";
        break;
    case C4G_MODE_4_STANDBY:
        t = "mode 4 stand-by";
        break;
    case C4G_MODE_5:
        t = "PC generates relative position targets, SMP+ closes the loops";
        break;
    case C4G_MODE_5_STANDBY:
        t = "mode 5 stand-by";
        break;
    case C4G_MODE_6:
        t = "PC generates velocity targets (not available)";
        break;
    case C4G_MODE_7:
        t = "PC adds a position delta to the SMP+ trajectory";
        break;
    case C4G_MODE_7_STANDBY:
        t = "mode 7 exit: SMP+ ends its motion, PC sends a null delta";
        break;
    case C4G_MODE_7_STANDBY_EXIT:
        t = "mode 7 exit: null references, then mode 0";
        break;
    case C4G_MODE_8:
        t = "PC adds a velocity contribution to the SMP+ trajectory";
        break;
    case C4G_MODE_9:
        t = "PC adds a current contribution to the SMP+ control";
        break;
    case C4G_MODE_101:
        t = "accelerometer measure from the PC (not available)";
        break;
    case C4G_MODE_102:
        t = "vision measure from the PC (not available)";
        break;
    case C4G_MODE_103:
        t = "force measure from the PC (not available)";
        break;
    case C4G_MODE_201:
        t = "PC cartesian position target (not available)";
        break;
    case C4G_MODE_202:
        t = "PC cartesian position delta (not available)";
        break;
    case C4G_MODE_FREEZING_A:
        t = "active freezing: SMP+ stops checking the PC (from mode 0)";
        break;
    case C4G_MODE_DRIVING_ON:
        t = "drive on in progress: mode requests are ignored";
        break;
    case C4G_MODE_FREEZING_P_IN:
        t = "passive freezing: SMP+ stops sending";
        break;
    case C4G_MODE_FREEZING_P_OUT:
        t = "passive freezing over";
        break;
    case C4G_MODE_EXIT_OPEN:
        t = "end of communication";
        break;
    case C4G_MODE_DRIVE_OFF:
        t = "PC request: drive off";
        break;
    case C4G_MODE_SVR_RESTART:
        t = "client restart: a new initialization packet follows";
        break;
    case C4G_MODE_FOLLOW_ERROR:
        t = "PC request: following error";
        break;
    default:
        t = "unknown mode";
        break;
    }
    return t;
}

int c4g_mode_is_available(int32_t mode)
{
    return has_flag(mode, C4G_MF_AVAILABLE);
}

int c4g_mode_pc_trajectory(int32_t mode)
{
    return has_flag(mode, C4G_MF_PC_TRAJ);
}

int c4g_mode_pc_loops(int32_t mode)
{
    return has_flag(mode, C4G_MF_PC_LOOPS);
}

int c4g_mode_is_special(int32_t mode)
{
    return has_flag(mode, C4G_MF_SPECIAL);
}

int c4g_mode_is_standby(int32_t mode)
{
    return has_flag(mode, C4G_MF_STANDBY);
}

uint32_t c4g_mode_pc_fields(int32_t mode)
{
    const mode_row_t *row = find_mode(mode);
    return (row != NULL) ? row->pc_fields : 0U;
}

int32_t c4g_mode_operating(int32_t mode)
{
    const mode_row_t *row = find_mode(mode);
    return (row != NULL) ? row->operating : -1;
}

/* An operating mode the controller can enter from mode 0 (not stand-by, not special). */
static int enterable(int32_t mode)
{
    const uint32_t f = mode_flags(mode);
    return (((f & C4G_MF_AVAILABLE) != 0U) && ((f & (C4G_MF_STANDBY | C4G_MF_SPECIAL)) == 0U))
               ? 1
               : 0;
}

/* Stand-by sequences of chapter 24: 1->11, 2->12, 4->14, 5->15, 7->17, 7->170, 17->170. */
static int standby_step(int32_t from, int32_t to)
{
    int ok = 0;
    if (c4g_mode_is_standby(to) != 0) {
        if ((c4g_mode_operating(to) == from) ||
            ((from == C4G_MODE_7_STANDBY) && (to == C4G_MODE_7_STANDBY_EXIT))) {
            ok = 1;
        }
    }
    return ok;
}

static int idle_mode(int32_t mode)
{
    return ((mode == C4G_MODE_0) || (mode == C4G_MODE_0_DEBUG)) ? 1 : 0;
}

/* Transitions into a special mode. */
static int to_special(int32_t from, int32_t to)
{
    int ok;
    switch (to) {
    case C4G_MODE_DRIVING_ON:   /* drive on happens in mode 0 (chapter 11) */
    case C4G_MODE_FREEZING_A:   /* active freezing only from mode 0 (15.1) */
        ok = idle_mode(from);
        break;
    case C4G_MODE_FREEZING_P_OUT:
        ok = 0;
        if (from == C4G_MODE_FREEZING_P_IN) {
            ok = 1;
        }
        break;
    default: /* 502, 504, 506 any time; 505 / 508 are echoes of PC requests */
        ok = 1;
        break;
    }
    return ok;
}

int c4g_mode_transition_ok(int32_t from, int32_t to)
{
    int ok = 0;
    if ((c4g_mode_is_known(from) == 0) || (c4g_mode_is_known(to) == 0)) {
        ok = 0;
    } else if ((from == to) || (to == C4G_MODE_0)) {
        ok = 1; /* mode 0 can always be forced (505, 508, selector, exits) */
    } else if (c4g_mode_is_special(to) != 0) {
        ok = to_special(from, to);
    } else if ((idle_mode(from) != 0) || (from == C4G_MODE_DRIVING_ON) ||
               (from == C4G_MODE_FREEZING_P_OUT)) {
        ok = enterable(to); /* after drive on the mode set by PC or PDL2 (15.2) */
    } else {
        ok = standby_step(from, to);
    }
    return ok;
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

static c4g_fsm_state_t infer_fsm(const c4g_arm_sm_t *sm)
{
    c4g_fsm_state_t s = C4G_FSM_UNKNOWN;
    const int32_t m = sm->mode;
    if ((sm->drive_on == 0U) || (c4g_mode_is_special(m) != 0)) {
        s = C4G_FSM_UNKNOWN;
    } else if (idle_mode(m) != 0) {
        s = (sm->moving != 0U) ? C4G_FSM_S10 : C4G_FSM_S00;
    } else {
        const int32_t op = c4g_mode_operating(m);
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
    if ((sm->leaving != 0U) && (idle_mode(mode) != 0)) {
        sm->leaving = 0U;
        ev |= C4G_CEV_EXIT_DONE;
    }
    return ev;
}

static uint32_t enter_mode(c4g_arm_sm_t *sm, int32_t old, int32_t mode, uint64_t now_ns)
{
    uint32_t ev = C4G_CEV_MODE_CHANGE;
    if ((sm->started != 0U) && (c4g_mode_transition_ok(old, mode) == 0)) {
        ev |= C4G_CEV_UNEXPECTED;
    }
    sm->prev_mode = old;
    sm->mode = mode;
    sm->mode_since_ns = now_ns;
    sm->ticks_in_mode = 0U;
    ev |= special_change(sm, old, mode);
    ev |= requests_on_change(sm, mode);
    if (c4g_mode_is_special(mode) != 0) {
        sm->phase = C4G_MPH_SPECIAL;
        sm->phase_since_ns = now_ns;
    } else if (idle_mode(mode) != 0) {
        if ((mode == C4G_MODE_0) && (sm->op_mode != 0)) {
            ev |= C4G_CEV_MODE0;
        }
        sm->op_mode = 0;
        sm->phase = C4G_MPH_NONE;
        sm->phase_since_ns = now_ns;
    } else if (c4g_mode_is_standby(mode) != 0) {
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

c4g_status_t c4g_arm_sm_update(c4g_arm_sm_t *sm, const c4g_engine_config_t *cfg, int32_t mode,
                               uint32_t mixed, uint8_t drive_byte, uint32_t moving,
                               uint64_t now_ns, uint32_t *events)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((sm != NULL) && (cfg != NULL) && (events != NULL)) {
        uint32_t drive_on = 0U;
        if (drive_byte == (uint8_t)C4G_STS_MOVING) {
            drive_on = 1U;
        }
        *events = 0U;
        st = C4G_ERR_MODE;
        if (c4g_mode_is_known(mode) != 0) {
            uint32_t ev = 0U;
            if ((sm->started != 0U) && (drive_on != sm->drive_on)) {
                ev |= (drive_on != 0U) ? C4G_CEV_DRIVE_ON : C4G_CEV_DRIVE_OFF;
            }
            sm->drive_on = drive_on;
            sm->moving = 0U;
            if (moving != 0U) {
                sm->moving = 1U;
            }
            if ((mixed != 0U) && (sm->mixed == 0U)) {
                ev |= C4G_CEV_MIXED;
            }
            sm->mixed = 0U;
            if (mixed != 0U) {
                sm->mixed = 1U;
            }
            if ((sm->started == 0U) || (mode != sm->mode)) {
                ev |= enter_mode(sm, sm->mode, mode, now_ns);
            } else {
                ev |= stay_in_mode(sm, cfg, now_ns);
            }
            sm->started = 1U;
            sm->driving_on = 0U;
            if (mode == C4G_MODE_DRIVING_ON) {
                sm->driving_on = 1U;
            }
            /* A 505 / 508 latch ends once it went out and the drives are off (15.5, 15.7). */
            if ((sm->latch != 0U) && (sm->latch_sent != 0U) && (drive_on == 0U)) {
                sm->latch = 0U;
                sm->latch_sent = 0U;
                ev |= C4G_CEV_LATCH_CLEARED;
            }
            sm->fsm = infer_fsm(sm);
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
    if (c4g_mode_is_known(mode) == 0) {
        st = C4G_ERR_MODE;
    }
    return st;
}

/* May the arm's mode @p m be left with EXIT_FROM_OPEN? */
static c4g_status_t exit_from_mode(int32_t m)
{
    c4g_status_t st = C4G_OK;
    if (idle_mode(m) != 0) {
        st = C4G_ERR_NOT_IN_OPEN;
    } else if (c4g_mode_is_standby(m) != 0) {
        st = C4G_ERR_LEAVING;
    } else if ((m == C4G_MODE_2) || (c4g_mode_is_special(m) != 0)) {
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
