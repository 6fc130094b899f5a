/* SPDX-License-Identifier: MIT */
/* Unit tests for c4g-sim's scenario parser (tools/c4g-sim/scenario.c, in the tool's
 * archive); the model it drives is tested in tests/sim. */
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
#include "scenario.h"

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
        cmocka_unit_test(test_scenario_ok),
        cmocka_unit_test(test_scenario_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
