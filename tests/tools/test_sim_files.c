/* SPDX-License-Identifier: MIT */
/* c4g-sim input files: the scenario parser and the INI configuration refuse values
 * out of range, binary content and overlong lines with FILE:LINE:COLUMN (the tool
 * sources are included directly: they are not part of the library). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "c4gh_textfile.h"
#include "c4gsim_model.h"
#include "scenario.h"
#include "sim.h"

static scn_t g_scn;

static void test_scenario_refuses(void **state)
{
    static const struct {
        const char *text;
        const char *msg;
    } bad[] = {
        /* the timeout became (unsigned long)ceil(1e300 / period): undefined behaviour */
        {"DRIVE ON 1\nWAIT PC 1 TIMEOUT 1e300\n",
         "s.scn:2:19: WAIT: timeout [ms]: '1e300' is out of range 0..3600000"},
        {"WAIT FOR PC 1 TIMEOUT inf\n", "s.scn:1:23: WAIT: timeout [ms]: 'inf' is not a finite number"},
        /* the mode was stored as a double and compared as (int)1e300 */
        {"EXPECT MODE 1 1 1e300\n", "s.scn:1:17: EXPECT: mode: '1e300' is not an integer"},
        {"EXPECT MODE 1 1 4.5\n", "s.scn:1:17: EXPECT: mode: '4.5' is not an integer"},
        {"MOVE 1 0 1e39\n", "s.scn:1:10: MOVE: target 2 [turns]: '1e39' is out of range -1000000..1000000"},
        {"MOVEREL 1 -1e400\n", "s.scn:1:11: MOVEREL: target 1 [turns]: '-1e400' is out of range -1000000..1000000"},
        {"EXPECT POS 1 1 0 1e300\n", "s.scn:1:18: EXPECT: tolerance [turns]: '1e300' is out of range 0..1000000"},
        {"CMD 1 99999999999999999999\n", "s.scn:1:7: CMD: value: '99999999999999999999' is out of range 0..255"},
        {"MODE 1 0x4\n", "s.scn:1:8: MODE: mode: '0x4' is not a decimal number"},
        {"OVERRIDE NaN\n", "s.scn:1:10: OVERRIDE: percent: 'NaN' is not a finite number"},
        {"DELAY 1\nDELAY 2\x01\n", "s.scn:2:8: control byte \\x01 at byte offset 15 (after 'DELAY 2'): "
                                   "binary content is not accepted"},
        {"# caf\xc3\xa9\nDELAY \xfe\n", "s.scn:2:7: invalid UTF-8 byte \\xfe at byte offset 14 (after 'DELAY '): "
                                        "binary content is not accepted"},
    };
    char err[400];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (scn_parse("s.scn", bad[i].text, strlen(bad[i].text), &g_scn, err, sizeof err) != -1) {
            fail_msg("accepted: %s", bad[i].text);
        }
        assert_string_equal(err, bad[i].msg);
    }
    /* NUL bytes: reported escaped, with the byte offset */
    assert_int_equal(scn_parse("s.scn", "DELAY 1\n\0\0\0", 11, &g_scn, err, sizeof err), -1);
    assert_string_equal(err, "s.scn:2:1: NUL byte \\x00 at byte offset 8: binary content is not accepted");
}

static void test_scenario_long_line(void **state)
{
    char text[1200];
    char err[400];
    (void)state;
    /* 600 bytes of one number: an error at column 512, never two lines */
    memset(text, '1', sizeof text);
    memcpy(text, "DELAY ", 6);
    text[600] = '\n';
    memcpy(text + 601, "END\n", 4);
    assert_int_equal(scn_parse("s.scn", text, 605, &g_scn, err, sizeof err), -1);
    assert_string_equal(err, "s.scn:1:512: line longer than 511 bytes, the limit for this file");
    /* 511 bytes is fine (blank padding then a comment) */
    memset(text, ' ', 511);
    memcpy(text, "DELAY 1 #", 9);
    text[511] = '\n';
    assert_int_equal(scn_parse("s.scn", text, 512, &g_scn, err, sizeof err), 0);
    assert_int_equal(g_scn.n, 1);
    assert_true(g_scn.cmd[0].ms == 1.0);
}

static void test_scenario_accepts_limits(void **state)
{
    const char *t = "WAIT PC 1 TIMEOUT 3600000\nMOVE 1 -1000000 1e6 +.5\nEXPECT MODE 1 2 504\r\n"
                    "CMD 1 255\nDELAY 0\n";
    char err[400];
    (void)state;
    assert_int_equal(scn_parse("s.scn", t, strlen(t), &g_scn, err, sizeof err), 0);
    assert_int_equal(g_scn.n, 5);
    assert_true(g_scn.cmd[0].ms == 3600000.0);
    assert_true(g_scn.cmd[1].v[0] == -1e6 && g_scn.cmd[1].v[1] == 1e6 && g_scn.cmd[1].v[2] == 0.5);
    assert_true(g_scn.cmd[2].v[0] == 504.0);
    assert_int_equal(g_scn.cmd[3].iv, 255);
}

static int cfg_text(sim_config_t *c, const char *text, size_t len, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    sim_config_default(c);
    c4gh_tf_open_mem(&f, "c.ini", text, len);
    return sim_config_parse(c, &f, err, errlen);
}

static void test_config_refuses(void **state)
{
    static const struct {
        const char *text;
        const char *msg;
    } bad[] = {
        {"[sim]\nswitch_ms = 1e39\n", "c.ini:2:13: [sim] switch_ms: '1e39' is out of range 0..100000"},
        {"[sim]\nmax_miss = 99999999999999999999\n",
         "c.ini:2:12: [sim] max_miss: '99999999999999999999' is out of range 1..1000000"},
        /* fractions were truncated by the (unsigned) conversion */
        {"[sim]\nt_cycle1_us = 499.9\n", "c.ini:2:15: [sim] t_cycle1_us: '499.9' is not an integer"},
        {"[sim]\nfollow_check = 0.5\n", "c.ini:2:16: [sim] follow_check: '0.5' is not an integer"},
        {"[sim]\nseed = 18446744073709551616\n",
         "c.ini:2:8: [sim] seed: '18446744073709551616' is out of range 0..18446744073709551615"},
        /* sscanf("%d") overflow is undefined behaviour */
        {"[sim]\nversion = 3.99999999999.1\n",
         "c.ini:2:11: [sim] version: '3.99999999999.1' is not a version MAJOR.MINOR.BUILD (each 0..65535)"},
        {"[sim]\nversion = 3.11\n", "c.ini:2:11: [sim] version: '3.11' is not a version MAJOR.MINOR.BUILD"},
        {"[model]\nkp = nan\n", "c.ini:2:6: [model] kp: 'nan' is not a finite number"},
        {"[axis 1.2]\nkp = -4\n", "c.ini:2:6: [axis 1.2] kp: '-4' is out of range 0..100000"},
        {"[arm 1]\nopen = 1 2 99999999999999999999\n", "c.ini:2:8: [arm 1] open: '1 2 99999999999999999999' "
                                                       "is not a list of logical axes 1..10"},
        {"[arm 1]\nstartup_mode = 33\n", "c.ini:2:16: [arm 1] startup_mode: '33' is not a mode code"},
        /* sscanf("arm %u") took "arm 4294967297" as arm 1 */
        {"[sim]\nport = 1000\n[arm 4294967297]\nopen = 1\n",
         "c.ini:3:1: unknown section [arm 4294967297] (want [sim], [plant], [model], [arm 1..4] or [axis A.L])"},
        {"[axis 1.2x]\nkp = 1\n", "c.ini:1:1: unknown section [axis 1.2x] (want [sim], [plant], [model], [arm 1..4] or [axis A.L])"},
        {"[sim]\n  port = 1000\n  speed = 3\n", "c.ini:3:3: [sim]: unknown key 'speed'"},
        /* inih alone gave the line of the first error with the message of the last one */
        {"[sim]\nport = 0\nperiod_ms = 3\n", "c.ini:2:8: [sim] port: '0' is out of range 1..65535"},
        {"[sim]\nport 1000\nperiod_ms = 3\n",
         "c.ini:2:1: 'port 1000': expected 'key = value', '[section]' or a ; or # comment"},
    };
    static sim_config_t c;
    char err[400];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (cfg_text(&c, bad[i].text, strlen(bad[i].text), err, sizeof err) != -1) {
            fail_msg("accepted: %s", bad[i].text);
        }
        assert_string_equal(err, bad[i].msg);
    }
}

static void test_config_accepts(void **state)
{
    static sim_config_t c;
    const char *t = "; comment\n[sim]\nport = 41000\n  seed = 18446744073709551615\nversion = 3.11.116\n"
                    "[arm 2]\nopen = 1, 2 3\n[axis 2.3]\nkp = 1e3 ; inline comment\n";
    char err[400];
    (void)state;
    assert_int_equal(cfg_text(&c, t, strlen(t), err, sizeof err), 0);
    assert_int_equal(c.port, 41000);
    assert_true(c.seed == UINT64_MAX);
    assert_int_equal(c.version[2], 116);
    assert_int_equal(c.n_arms, 2);
    assert_int_equal(c.open_mask[1], 0x7);
    assert_true(c.ax[1][2].kp == 1e3);
    /* the shipped examples load */
    sim_config_default(&c);
    assert_int_equal(sim_config_load(&c, FIXTURES_DIR "/sim/fig10-1.ini", err, sizeof err), 0);
    sim_config_default(&c);
    assert_int_equal(sim_config_load(&c, FIXTURES_DIR "/sim/two-arms.ini", err, sizeof err), 0);
    assert_int_equal(c.n_arms, 2);
}

static void test_config_files(void **state)
{
    static sim_config_t c;
    char err[400];
    (void)state;
    sim_config_default(&c);
    assert_int_equal(sim_config_load(&c, "/dev/zero", err, sizeof err), -1);
    assert_string_equal(err, "/dev/zero: more than 1048576 bytes, the limit for this file: refused");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scenario_refuses),
        cmocka_unit_test(test_scenario_long_line),
        cmocka_unit_test(test_scenario_accepts_limits),
        cmocka_unit_test(test_config_refuses),
        cmocka_unit_test(test_config_accepts),
        cmocka_unit_test(test_config_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
