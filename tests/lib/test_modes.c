/* SPDX-License-Identifier: MIT */
/* Modes: table and predicates, controller transition rules (exhaustive, against an
 * independent list), the per-arm state machine (every transition and event), the request
 * rules (every forbidden request), and the PDL2 sequences of figure 24.4. */
#include "test_helpers.h"

static const int32_t all_modes[] = {0, 10, 1, 11, 2, 12, 3, 4, 14, 5, 15, 6, 7, 17, 170, 8, 9,
                                    101, 102, 103, 201, 202, 500, 501, 502, 503, 504, 505,
                                    506, 508};
#define N_ALL ((int)(sizeof all_modes / sizeof all_modes[0]))

static c4g_engine_config_t cfg0(void)
{
    c4g_engine_config_t c;
    assert_int_equal(c4g_engine_config_default(&c), C4G_OK);
    return c;
}

static void test_table(void **state)
{
    c4g_mode_info_t mi;
    int i;
    (void)state;
    for (i = 0; i < N_ALL; i++) {
        const int32_t m = all_modes[i];
        assert_int_equal(c4g_mode_info(m, &mi), C4G_OK);
        assert_int_equal(mi.code, m);
        assert_non_null(mi.name);
        assert_true(strlen(mi.description) > 5);
        assert_string_equal(c4g_mode_name(m), mi.name);
        assert_string_equal(c4g_mode_description(m), mi.description);
        assert_int_equal(c4g_mode_pc_fields(m), mi.pc_fields);
        assert_int_equal(c4g_mode_operating(m), mi.operating);
        assert_int_equal(c4g_mode_is_known(m), 1);
        assert_int_equal(c4g_mode_rules(m), mi.rules);
        assert_ptr_equal(c4g_mode_find(m)->name, mi.name);
    }
    assert_null(c4g_mode_find(13));
    assert_int_equal(c4g_mode_rules(13), 0);
    /* the filter rules: what the controller does with the PC's fields */
    assert_int_equal(c4g_mode_rules(C4G_MODE_4), C4G_MR_ABS | C4G_MR_VEL | C4G_MR_FE);
    assert_int_equal(c4g_mode_rules(C4G_MODE_5), C4G_MR_INT_D2 | C4G_MR_VEL | C4G_MR_FE);
    assert_int_equal(c4g_mode_rules(C4G_MODE_7), C4G_MR_INT_D1 | C4G_MR_FE);
    assert_int_equal(c4g_mode_rules(C4G_MODE_8), C4G_MR_INT_D4 | C4G_MR_VADD | C4G_MR_FE);
    assert_int_equal(c4g_mode_rules(C4G_MODE_9), C4G_MR_DCUR | C4G_MR_FE);
    assert_int_equal(c4g_mode_rules(C4G_MODE_0_DEBUG), C4G_MR_COPY);
    assert_int_equal(c4g_mode_rules(C4G_MODE_4_STANDBY), 0);
    /* the transition columns */
    assert_int_equal(c4g_mode_find(C4G_MODE_7_STANDBY_EXIT)->from, C4G_MODE_7_STANDBY);
    assert_int_equal(c4g_mode_find(C4G_MODE_FREEZING_P_OUT)->from, C4G_MODE_FREEZING_P_IN);
    assert_int_equal(c4g_mode_find(C4G_MODE_FREEZING_A)->from, C4G_FROM_IDLE);
    assert_int_equal(c4g_mode_find(C4G_MODE_EXIT_OPEN)->from, C4G_FROM_ANY);
    assert_int_equal(c4g_mode_info(13, &mi), C4G_ERR_MODE);
    assert_int_equal(c4g_mode_info(0, NULL), C4G_ERR_NULL);
    assert_string_equal(c4g_mode_name(13), "UNKNOWN");
    assert_string_equal(c4g_mode_description(-1), "unknown mode");
    assert_int_equal(c4g_mode_pc_fields(13), 0);
    assert_int_equal(c4g_mode_operating(13), -1);
    assert_string_equal(c4g_mode_name(C4G_MODE_7_STANDBY_EXIT), "MODE_7_STANDBY_EXIT");
    assert_string_equal(c4g_mode_name(C4G_MODE_FOLLOW_ERROR), "FOLLOW_ERROR");
}

static void test_predicates(void **state)
{
    (void)state;
    /* field facts: 3, 6, 1xx, 201, 202 not available */
    const int32_t na[] = {3, 6, 101, 102, 103, 201, 202, 13, -1};
    const int32_t av[] = {0, 10, 1, 11, 2, 12, 4, 14, 5, 15, 7, 17, 170, 8, 9, 500, 501, 502,
                          503, 504, 505, 506, 508};
    size_t i;
    for (i = 0; i < sizeof na / sizeof na[0]; i++) {
        assert_int_equal(c4g_mode_is_available(na[i]), 0);
    }
    for (i = 0; i < sizeof av / sizeof av[0]; i++) {
        assert_int_equal(c4g_mode_is_available(av[i]), 1);
    }
    assert_int_equal(c4g_mode_pc_trajectory(1), 1);
    assert_int_equal(c4g_mode_pc_trajectory(4), 1);
    assert_int_equal(c4g_mode_pc_trajectory(5), 1);
    assert_int_equal(c4g_mode_pc_trajectory(7), 1);
    assert_int_equal(c4g_mode_pc_trajectory(11), 1);
    assert_int_equal(c4g_mode_pc_trajectory(2), 0);
    assert_int_equal(c4g_mode_pc_trajectory(9), 0);
    assert_int_equal(c4g_mode_pc_trajectory(0), 0);
    assert_int_equal(c4g_mode_pc_loops(1), 1);
    assert_int_equal(c4g_mode_pc_loops(2), 1);
    assert_int_equal(c4g_mode_pc_loops(12), 1);
    assert_int_equal(c4g_mode_pc_loops(4), 0);
    assert_int_equal(c4g_mode_pc_loops(13), 0);
    assert_int_equal(c4g_mode_is_special(500), 1);
    assert_int_equal(c4g_mode_is_special(508), 1);
    assert_int_equal(c4g_mode_is_special(170), 0);
    assert_int_equal(c4g_mode_is_standby(170), 1);
    assert_int_equal(c4g_mode_is_standby(14), 1);
    assert_int_equal(c4g_mode_is_standby(7), 0);
    /* field facts "What the PC must fill per mode" */
    assert_int_equal(c4g_mode_pc_fields(0), 0);
    assert_int_equal(c4g_mode_pc_fields(10), C4G_PCF_D1 | C4G_PCF_D2);
    assert_int_equal(c4g_mode_pc_fields(1), C4G_PCF_D1 | C4G_PCF_D2 | C4G_PCF_D4 | C4G_PCF_D5);
    assert_int_equal(c4g_mode_pc_fields(2), C4G_PCF_D4 | C4G_PCF_D5);
    assert_int_equal(c4g_mode_pc_fields(4), C4G_PCF_D1 | C4G_PCF_D2);
    assert_int_equal(c4g_mode_pc_fields(5), C4G_PCF_D1 | C4G_PCF_D2);
    assert_int_equal(c4g_mode_pc_fields(7), C4G_PCF_D1);
    assert_int_equal(c4g_mode_pc_fields(8), C4G_PCF_D4);
    assert_int_equal(c4g_mode_pc_fields(9), C4G_PCF_D5);
    assert_int_equal(c4g_mode_operating(11), 1);
    assert_int_equal(c4g_mode_operating(170), 7);
    assert_int_equal(c4g_mode_operating(17), 7);
}

/* Independent list of the transitions the controller may make (chapters 13, 15, 24). */
static int oracle(int32_t f, int32_t t)
{
    static const int32_t pairs[][2] = {
        {1, 11}, {2, 12}, {4, 14}, {5, 15}, {7, 17}, {7, 170}, {17, 170},
        {502, 503},
    };
    static const int32_t enter[] = {10, 1, 2, 4, 5, 7, 8, 9};
    size_t k;
    if (f == t || t == 0) return 1;
    if (t == 502 || t == 504 || t == 506 || t == 505 || t == 508) return 1;
    if (t == 501 || t == 500) return f == 0 || f == 10;
    for (k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
        if (pairs[k][0] == f && pairs[k][1] == t) return 1;
    }
    if (f == 0 || f == 10 || f == 501 || f == 503) {
        for (k = 0; k < sizeof enter / sizeof enter[0]; k++) {
            if (enter[k] == t) return 1;
        }
    }
    return 0;
}

static void test_transitions_exhaustive(void **state)
{
    int i, j, n_ok = 0;
    (void)state;
    for (i = 0; i < N_ALL; i++) {
        for (j = 0; j < N_ALL; j++) {
            const int r = c4g_mode_transition_ok(all_modes[i], all_modes[j]);
            if (r != oracle(all_modes[i], all_modes[j])) {
                fail_msg("transition %d -> %d: got %d", all_modes[i], all_modes[j], r);
            }
            n_ok += r;
        }
    }
    assert_true(n_ok > 100);
    assert_int_equal(c4g_mode_transition_ok(13, 0), 0);
    assert_int_equal(c4g_mode_transition_ok(0, 13), 0);
}

/* ---------------------------------------------------------------- state machine */

typedef struct sm_in {
    int32_t mode;
    uint8_t drive;
    uint32_t moving;
    uint64_t t;
} sm_in_t;

static uint32_t feed(c4g_arm_sm_t *sm, const c4g_engine_config_t *c, int32_t mode, uint8_t drive,
                     uint32_t moving, uint64_t t)
{
    uint32_t ev = 0xFFFFFFFFu;
    assert_int_equal(c4g_arm_sm_update(sm, c, mode, 0, drive, moving, t, &ev), C4G_OK);
    return ev;
}

static void test_sm_args(void **state)
{
    c4g_arm_sm_t sm;
    c4g_engine_config_t c = cfg0();
    uint32_t ev;
    (void)state;
    assert_int_equal(c4g_engine_config_default(NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_arm_sm_init(NULL, 1), C4G_ERR_NULL);
    assert_int_equal(c4g_arm_sm_init(&sm, 11), C4G_ERR_ARG);
    assert_int_equal(c4g_arm_sm_init(&sm, 6), C4G_OK);
    assert_int_equal(c4g_arm_sm_update(NULL, &c, 0, 0, 5, 0, 0, &ev), C4G_ERR_NULL);
    assert_int_equal(c4g_arm_sm_update(&sm, NULL, 0, 0, 5, 0, 0, &ev), C4G_ERR_NULL);
    assert_int_equal(c4g_arm_sm_update(&sm, &c, 0, 0, 5, 0, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_arm_sm_update(&sm, &c, 13, 0, 5, 0, 0, &ev), C4G_ERR_MODE);
    assert_int_equal(ev, 0);
    assert_int_equal(c4g_arm_sm_check(NULL, C4G_REQ_MODE, 4), C4G_ERR_NULL);
    assert_int_equal(c4g_arm_sm_check(&sm, (c4g_req_kind_t)99, 4), C4G_ERR_ARG);
    assert_int_equal(c4g_arm_sm_init(&sm, 0), C4G_OK);
    assert_int_equal(c4g_arm_sm_check(&sm, C4G_REQ_DRIVE_OFF, 0), C4G_ERR_NOT_OPEN);
}

static void test_sm_mode1_cycle(void **state)
{
    c4g_arm_sm_t sm;
    c4g_engine_config_t c = cfg0();
    uint32_t ev;
    (void)state;
    c.start_ns = 1000;
    assert_int_equal(c4g_arm_sm_init(&sm, 6), C4G_OK);
    ev = feed(&sm, &c, 501, 0, 0, 0);                 /* driving on */
    assert_true(ev & C4G_CEV_DRIVING_ON);
    assert_false(ev & C4G_CEV_UNEXPECTED);
    assert_int_equal(sm.driving_on, 1);
    assert_int_equal(sm.phase, C4G_MPH_SPECIAL);
    assert_int_equal(sm.fsm, C4G_FSM_UNKNOWN);
    ev = feed(&sm, &c, 501, 5, 0, 1);
    assert_true(ev & C4G_CEV_DRIVE_ON);
    ev = feed(&sm, &c, 0, 5, 0, 2);                   /* end of DRIVING ON */
    assert_true(ev & C4G_CEV_DRIVING_ON_END);
    assert_int_equal(sm.driving_on, 0);
    assert_int_equal(sm.fsm, C4G_FSM_S00);
    ev = feed(&sm, &c, 0, 5, 1, 3);
    assert_int_equal(sm.fsm, C4G_FSM_S10);
    assert_int_equal(ev, 0);
    ev = feed(&sm, &c, 1, 5, 0, 10);
    assert_true(ev & C4G_CEV_START);
    assert_int_equal(sm.phase, C4G_MPH_START);
    assert_int_equal(sm.op_mode, 1);
    assert_int_equal(sm.fsm, C4G_FSM_S01);
    ev = feed(&sm, &c, 1, 5, 0, 500);                 /* switching counter running */
    assert_int_equal(sm.phase, C4G_MPH_START);
    assert_int_equal(ev, 0);
    ev = feed(&sm, &c, 1, 5, 0, 1010);
    assert_true(ev & C4G_CEV_CRUISE);
    assert_int_equal(sm.phase, C4G_MPH_CRUISE);
    assert_int_equal(sm.phase_since_ns, 1010);
    ev = feed(&sm, &c, 11, 5, 0, 1100);
    assert_true(ev & C4G_CEV_END);
    assert_int_equal(sm.phase, C4G_MPH_END);
    assert_int_equal(sm.op_mode, 1);
    ev = feed(&sm, &c, 0, 5, 0, 1200);
    assert_true(ev & C4G_CEV_MODE0);
    assert_int_equal(sm.op_mode, 0);
    assert_int_equal(sm.prev_mode, 11);
    assert_int_equal(sm.ticks_in_mode, 0);
    ev = feed(&sm, &c, 0, 0, 0, 1300);
    assert_true(ev & C4G_CEV_DRIVE_OFF);
    assert_int_equal(sm.fsm, C4G_FSM_UNKNOWN);
    assert_int_equal(sm.ticks_in_mode, 1);
}

static void test_sm_mode7_and_specials(void **state)
{
    c4g_arm_sm_t sm;
    c4g_engine_config_t c = cfg0();
    uint32_t ev;
    (void)state;
    assert_int_equal(c4g_arm_sm_init(&sm, 6), C4G_OK);
    feed(&sm, &c, 0, 5, 0, 0);
    ev = feed(&sm, &c, 7, 5, 1, 1);
    assert_true(ev & C4G_CEV_START);
    assert_int_equal(sm.fsm, C4G_FSM_S11);            /* OPEN TYPE B */
    ev = feed(&sm, &c, 7, 5, 0, 2);
    assert_true(ev & C4G_CEV_CRUISE);                  /* no counter in mode 7 */
    assert_int_equal(sm.fsm, C4G_FSM_S01);             /* END MOVE: A1101 */
    ev = feed(&sm, &c, 17, 5, 1, 3);
    assert_true(ev & C4G_CEV_END);
    ev = feed(&sm, &c, 170, 5, 0, 4);
    assert_false(ev & C4G_CEV_END);                    /* already in END */
    assert_false(ev & C4G_CEV_UNEXPECTED);
    ev = feed(&sm, &c, 0, 5, 0, 5);
    assert_true(ev & C4G_CEV_MODE0);
    /* unexpected transitions are reported, followed anyway */
    ev = feed(&sm, &c, 11, 5, 0, 6);
    assert_true(ev & C4G_CEV_UNEXPECTED);
    assert_int_equal(sm.mode, 11);
    ev = feed(&sm, &c, 4, 5, 0, 7);
    assert_true(ev & C4G_CEV_UNEXPECTED);
    /* passive freezing */
    ev = feed(&sm, &c, 502, 5, 0, 8);
    assert_true(ev & C4G_CEV_FREEZE_P_IN);
    assert_int_equal(sm.frozen, 502);
    ev = feed(&sm, &c, 503, 5, 0, 9);
    assert_true(ev & C4G_CEV_FREEZE_P_OUT);
    assert_int_equal(sm.frozen, 0);
    ev = feed(&sm, &c, 503, 5, 0, 9);
    ev = feed(&sm, &c, 4, 5, 0, 10);
    assert_false(ev & C4G_CEV_UNEXPECTED);
    /* a 503 without 502 */
    ev = feed(&sm, &c, 503, 5, 0, 11);
    assert_true(ev & C4G_CEV_UNEXPECTED);
    assert_true(ev & C4G_CEV_FREEZE_P_OUT);
    /* 500 from the controller */
    feed(&sm, &c, 0, 5, 0, 12);
    ev = feed(&sm, &c, 500, 5, 0, 13);
    assert_true(ev & C4G_CEV_FREEZE_A);
    assert_int_equal(sm.frozen, 500);
    ev = feed(&sm, &c, 0, 5, 0, 14);
    assert_true(ev & C4G_CEV_FREEZE_A_END);
    assert_int_equal(sm.frozen, 0);
    ev = feed(&sm, &c, 506, 5, 0, 15);
    assert_true(ev & C4G_CEV_RESTART);
    assert_int_equal(sm.restart, 1);
    ev = feed(&sm, &c, 504, 5, 0, 16);
    assert_true(ev & C4G_CEV_END_COMM);
    assert_int_equal(sm.ended, 1);
    assert_int_equal(c4g_arm_sm_check(&sm, C4G_REQ_DRIVE_OFF, 0), C4G_ERR_ENDED);
}

static void test_sm_mixed_and_first_packet(void **state)
{
    c4g_arm_sm_t sm;
    c4g_engine_config_t c = cfg0();
    uint32_t ev;
    (void)state;
    assert_int_equal(c4g_arm_sm_init(&sm, 6), C4G_OK);
    /* first packet in an operating mode: START, never UNEXPECTED */
    assert_int_equal(c4g_arm_sm_update(&sm, &c, 4, 1, 5, 0, 0, &ev), C4G_OK);
    assert_true(ev & C4G_CEV_START);
    assert_true(ev & C4G_CEV_MIXED);
    assert_false(ev & (C4G_CEV_UNEXPECTED | C4G_CEV_DRIVE_ON));
    assert_int_equal(sm.mixed, 1);
    assert_int_equal(c4g_arm_sm_update(&sm, &c, 4, 1, 5, 0, 1, &ev), C4G_OK);
    assert_false(ev & C4G_CEV_MIXED);                  /* reported once */
    assert_int_equal(c4g_arm_sm_update(&sm, &c, 4, 0, 5, 0, 2, &ev), C4G_OK);
    assert_int_equal(sm.mixed, 0);
    /* stand-by entered directly (first packet) */
    assert_int_equal(c4g_arm_sm_init(&sm, 6), C4G_OK);
    ev = feed(&sm, &c, 12, 5, 0, 0);
    assert_true(ev & C4G_CEV_END);
    assert_int_equal(sm.op_mode, 2);
    ev = feed(&sm, &c, 10, 5, 0, 1);
    assert_false(ev & C4G_CEV_MODE0);                  /* 0' is not mode 0 */
    assert_true(ev & C4G_CEV_UNEXPECTED);              /* 12 goes to 0 */
    assert_int_equal(sm.phase, C4G_MPH_NONE);
    /* ticks saturate */
    sm.ticks_in_mode = UINT32_MAX;
    feed(&sm, &c, 10, 5, 0, 2);
    assert_int_equal(sm.ticks_in_mode, UINT32_MAX);
}

/* Request rules: every combination of arm condition and request kind. */
static void test_request_rules(void **state)
{
    c4g_arm_sm_t sm;
    size_t i;
    (void)state;
    struct {
        const char *what;
        int32_t mode;
        uint32_t drive_on, driving_on, latch, req, exit_req, leaving, mixed;
        int32_t frozen;
        int st_mode4, st_exit, st_freeze;
    } rows[] = {
        {"mode 0 idle", 0, 1, 0, 0, 0, 0, 0, 0, 0, C4G_OK, C4G_ERR_NOT_IN_OPEN, C4G_OK},
        {"mode 0'", 10, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN, C4G_ERR_NOT_IN_OPEN,
         C4G_ERR_NOT_MODE0},
        {"mode 0 mixed", 0, 1, 0, 0, 0, 0, 0, 1, 0, C4G_ERR_FORBIDDEN,
         C4G_ERR_NOT_IN_OPEN, C4G_ERR_NOT_MODE0},
        {"drives off", 0, 0, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_DRIVES_OFF,
         C4G_ERR_NOT_IN_OPEN, C4G_OK},
        {"driving on", 501, 1, 1, 0, 0, 0, 0, 0, 0, C4G_ERR_DRIVING_ON,
         C4G_ERR_DRIVING_ON, C4G_ERR_DRIVING_ON},
        {"latched", 0, 1, 0, 1, 0, 0, 0, 0, 0, C4G_ERR_LATCHED, C4G_ERR_NOT_IN_OPEN,
         C4G_ERR_LATCHED},
        {"mode 4", 4, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN, C4G_OK,
         C4G_ERR_NOT_MODE0},
        {"mode 4 exit sent", 4, 1, 0, 0, 0, 1, 0, 0, 0, C4G_OK, C4G_OK, C4G_ERR_NOT_MODE0},
        {"mode 1 leaving", 11, 1, 0, 0, 0, 0, 1, 0, 0, C4G_OK, C4G_OK, C4G_ERR_NOT_MODE0},
        {"mode 11", 11, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN, C4G_ERR_LEAVING,
         C4G_ERR_NOT_MODE0},
        {"mode 2", 2, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN, C4G_ERR_FORBIDDEN,
         C4G_ERR_NOT_MODE0},
        {"mode 12", 12, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN, C4G_ERR_LEAVING,
         C4G_ERR_NOT_MODE0},
        {"mode 7", 7, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN, C4G_OK,
         C4G_ERR_NOT_MODE0},
        {"mode 9", 9, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN, C4G_OK,
         C4G_ERR_NOT_MODE0},
        {"mode 503", 503, 1, 0, 0, 0, 0, 0, 0, 0, C4G_ERR_FORBIDDEN,
         C4G_ERR_FORBIDDEN, C4G_ERR_NOT_MODE0},
        {"passive frozen", 502, 1, 0, 0, 0, 0, 0, 0, 502, C4G_ERR_FROZEN,
         C4G_ERR_FROZEN, C4G_ERR_FROZEN},
        {"active frozen", 0, 1, 0, 0, 0, 0, 0, 0, 500, C4G_ERR_FROZEN, C4G_OK, C4G_OK},
    };
    for (i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        assert_int_equal(c4g_arm_sm_init(&sm, 6), C4G_OK);
        sm.started = 1;
        sm.mode = rows[i].mode;
        sm.drive_on = rows[i].drive_on;
        sm.driving_on = rows[i].driving_on;
        sm.latch = rows[i].latch;
        (void)rows[i].req;
        sm.exit_req = rows[i].exit_req;
        sm.leaving = rows[i].leaving;
        sm.mixed = rows[i].mixed;
        sm.frozen = rows[i].frozen;
        (void)rows[i].st_mode4; /* 0.1 rules; a mode is never the PC's to start */
        if (c4g_arm_sm_check(&sm, C4G_REQ_MODE, 4) != C4G_ERR_PDL_ONLY ||
            c4g_arm_sm_check(&sm, C4G_REQ_EXIT, 0) != rows[i].st_exit ||
            c4g_arm_sm_check(&sm, C4G_REQ_FREEZE, 0) != rows[i].st_freeze) {
            fail_msg("%s: mode %d exit %d freeze %d", rows[i].what,
                     c4g_arm_sm_check(&sm, C4G_REQ_MODE, 4), c4g_arm_sm_check(&sm, C4G_REQ_EXIT, 0),
                     c4g_arm_sm_check(&sm, C4G_REQ_FREEZE, 0));
        }
        /* safety requests are never refused */
        assert_int_equal(c4g_arm_sm_check(&sm, C4G_REQ_DRIVE_OFF, 0), C4G_OK);
        assert_int_equal(c4g_arm_sm_check(&sm, C4G_REQ_FOLLOW_ERROR, 0), C4G_OK);
    }
    /* no mode may be requested by the PC: PDL2 starts them all (manual 24.2) */
    assert_int_equal(c4g_arm_sm_init(&sm, 6), C4G_OK);
    sm.started = 1;
    sm.drive_on = 1;
    for (i = 0; i < (size_t)N_ALL; i++) {
        const int32_t m = all_modes[i];
        assert_int_equal(c4g_arm_sm_check(&sm, C4G_REQ_MODE, m), C4G_ERR_PDL_ONLY);
    }
    assert_int_equal(c4g_arm_sm_check(&sm, C4G_REQ_MODE, 13), C4G_ERR_MODE);
    /* exit from a mode that is not an operating one: 500 seen without our freezing */
    sm.mode = 500;
    assert_int_equal(c4g_arm_sm_check(&sm, C4G_REQ_EXIT, 0), C4G_ERR_FORBIDDEN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),
        cmocka_unit_test(test_predicates),
        cmocka_unit_test(test_transitions_exhaustive),
        cmocka_unit_test(test_sm_args),
        cmocka_unit_test(test_sm_mode1_cycle),
        cmocka_unit_test(test_sm_mode7_and_specials),
        cmocka_unit_test(test_sm_mixed_and_first_packet),
        cmocka_unit_test(test_request_rules),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
