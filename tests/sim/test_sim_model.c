/* SPDX-License-Identifier: MIT */
/* Unit tests for c4g-sim's robot model and scenario parser (the tool sources are
 * included directly: they are not part of the library). */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdlib.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "c4gh_textfile.h"
#include "c4gsim_model.h"
#include "scenario.h"

static void test_rng_repeatable(void **state)
{
    c4gsim_rng_t a, b;
    int i;
    (void)state;
    c4gsim_rng_seed(&a, 42);
    c4gsim_rng_seed(&b, 42);
    for (i = 0; i < 1000; i++) {
        assert_true(c4gsim_rng_next(&a) == c4gsim_rng_next(&b));
    }
    c4gsim_rng_seed(&b, 43);
    assert_false(c4gsim_rng_next(&a) == c4gsim_rng_next(&b));
}

static void test_trap_profile(void **state)
{
    c4gsim_trap_t t;
    double p, v, tmin;
    (void)state;
    tmin = c4gsim_trap_min_time(2.0, 20.0, 200.0);
    assert_true(tmin > 0.0);
    c4gsim_trap_plan(&t, 1.0, 3.0, tmin);
    c4gsim_trap_eval(&t, 0.0, &p, &v);
    assert_true(fabs(p - 1.0) < 1e-12 && fabs(v) < 1e-12);
    c4gsim_trap_eval(&t, tmin / 2.0, &p, &v);
    assert_true(fabs(p - 2.0) < 1e-9);          /* symmetric: half way at half time */
    assert_true(v <= 20.0 + 1e-9 && v > 0.0);   /* within vmax */
    c4gsim_trap_eval(&t, tmin * 2.0, &p, &v);
    assert_true(fabs(p - 3.0) < 1e-12 && v == 0.0);
}

/* Closed loop: the DSA brings an axis with gravity to a step reference. */
static void test_axis_reaches_reference(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    int k;
    (void)state;
    c4gsim_axis_params_default(&p, 1); /* axis 2: gravity */
    c4gsim_rng_seed(&r, 1);
    c4gsim_axis_reset(&a, &p, &r);
    a.drive_on = 1;
    memset(&in, 0, sizeof in);
    in.pos_ref = 0.5;
    for (k = 0; k < 4000; k++) { /* 2 s at 2 kHz */
        c4gsim_axis_step(&a, &p, &in, 0.0005, &r);
        assert_true(fabs(a.cur) <= p.az_lim + 1e-9);
    }
    assert_true(fabs(a.pos - 0.5) < 0.01);
}

static void test_drive_off_brakes(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    int k;
    (void)state;
    c4gsim_axis_params_default(&p, 1);
    p.pos0 = 3.0;
    c4gsim_rng_seed(&r, 1);
    c4gsim_axis_reset(&a, &p, &r);
    memset(&in, 0, sizeof in);
    in.pos_ref = 10.0;
    for (k = 0; k < 100; k++) {
        c4gsim_axis_step(&a, &p, &in, 0.0005, &r);
    }
    assert_true(a.pos == 3.0 && a.cur == 0.0);
}

static void test_scenario_ok(void **state)
{
    static scn_t s;
    char err[200];
    const char *t = "# comment\nDRIVE ON 1\nmove 1 1 2 3 NOWAIT\nWAIT FOR PC 2 TIMEOUT 500\n"
                    "MODE 1 4 AXES 1 3\nEXPECT POS 1 2 0.5 0.01\nEXPECT ERROR NONE\nEXIT OPEN\n";
    (void)state;
    assert_int_equal(scn_parse("t.scn", t, strlen(t), &s, err, sizeof err), 0);
    assert_int_equal(s.n, 7);
    assert_int_equal(s.cmd[1].op, SCN_MOVE);
    assert_int_equal(s.cmd[1].n, 3);
    assert_int_equal(s.cmd[1].nowait, 1);
    assert_int_equal(s.cmd[2].op, SCN_WAIT_PC);
    assert_int_equal(s.cmd[2].arm, 2);
    assert_true(s.cmd[2].ms == 500.0);
    assert_int_equal(s.cmd[3].axes_mask, 0x5U);
    assert_int_equal(s.cmd[3].line, 5);
}

static void test_scenario_errors(void **state)
{
    static scn_t s;
    char err[200];
    static const struct { const char *text; const char *msg; } bad[] = {
        {"DRIVE ON 5\n", "t.scn:1:10: DRIVE: arm: '5' is out of range 1..4"},
        {"\nMOVE 1\n", "t.scn:2: MOVE: no targets"},
        {"MOVE 1 1 nan\n", "t.scn:1:10: MOVE: target 2 [turns]: 'nan' is not a finite number"},
        {"DELAY -1\n", "t.scn:1:7: DELAY: time [ms]: '-1' is out of range 0..3600000"},
        {"MODE 1 4 AXES 11\n", "t.scn:1:15: MODE: axis: '11' is out of range 1..10"},
        {"CMD 1 256\n", "t.scn:1:7: CMD: value: '256' is out of range 0..255"},
        {"END now\n", "t.scn:1:5: END: unexpected 'now'"},
        {"HELLO\n", "t.scn:1:1: unknown command 'HELLO'"},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(scn_parse("t.scn", bad[i].text, strlen(bad[i].text), &s, err, sizeof err), -1);
        assert_string_equal(err, bad[i].msg);
    }
    assert_int_equal(scn_parse("t.scn", "DELAY 1\0\n", 9, &s, err, sizeof err), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rng_repeatable),
        cmocka_unit_test(test_trap_profile),
        cmocka_unit_test(test_axis_reaches_reference),
        cmocka_unit_test(test_drive_off_brakes),
        cmocka_unit_test(test_scenario_ok),
        cmocka_unit_test(test_scenario_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
