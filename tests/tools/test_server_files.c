/* SPDX-License-Identifier: MIT */
/* c4g-server input files: trajectory CSV, mode-9 feedforward parameters and the INI
 * configuration refuse out-of-range numbers, binary content, overlong lines and huge
 * files with FILE:LINE:COLUMN (tool sources included directly). */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdlib.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>

#include "c4gh_textfile.h"
#include "c4gh_cli.h"
#include "c4gh_ffmodel.h"
#include "srv_core.h"

static srv_traj_t g_tr;
static srv_ff_t g_ff[C4G_ARMS][C4G_AXES_PER_ARM];
static srv_config_t g_cfg;

static int traj(const char *text, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    c4gh_tf_open_mem(&f, "t.csv", text, strlen(text));
    return srv_parse_traj(&f, &g_tr, err, errlen);
}

static int ff(const char *text, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    memset(g_ff, 0, sizeof g_ff);
    c4gh_tf_open_mem(&f, "f.txt", text, strlen(text));
    return srv_parse_ff(&f, g_ff, err, errlen);
}

static int ini(const char *text, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    srv_config_default(&g_cfg);
    c4gh_tf_open_mem(&f, "s.ini", text, strlen(text));
    return srv_config_parse_ini(&g_cfg, &f, err, errlen);
}

static void test_traj_refuses(void **state)
{
    static const struct {
        const char *text;
        const char *msg;
    } bad[] = {
        /* stored as float: (float)1e39 is undefined behaviour */
        {"t,a\n0,0\n1,1e39\n", "t.csv:3:3: column 2 (axis offset [turns]): '1e39' is out of range -1000000..1000000"},
        {"0,0\n1e300,1\n", "t.csv:2:1: column 1 (t [s]): '1e300' is out of range 0..10000000"},
        {"0,0\n0.5,abc\n", "t.csv:2:5: column 2 (axis offset [turns]): 'abc' is not a decimal number"},
        /* a first row "nan,0" was skipped as a header */
        {"nan,0\n1,1\n", "t.csv:1:1: column 1 (t [s]): 'nan' is not a finite number"},
        {"0;0\n1;inf\n", "t.csv:2:3: column 2 (axis offset [turns]): 'inf' is not a finite number"},
        /* strtok merged ",," and shifted the columns */
        {"0,0,0\n1,,2\n", "t.csv:2:3: empty field"},
        {"0,0,\n", "t.csv:1:5: empty field"},
        {"0,0\n0,1\n", "t.csv:2:1: column 1 (t [s]): 0 is not after the previous row's time 0"},
        {"0 1 2 3 4 5 6 7 8 9 10 11\n", "t.csv:1:24: more than 10 axis columns"},
        {"0,0\n1,1\x1b[2J\n", "t.csv:2:4: control byte \\x1b at byte offset 7 (after '1,1'): binary content is not accepted"},
        {"t,a\n", "t.csv: no data rows"},
    };
    char err[400];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (traj(bad[i].text, err, sizeof err) != -1) {
            fail_msg("accepted: %s", bad[i].text);
        }
        assert_string_equal(err, bad[i].msg);
    }
}

static void test_traj_long_line(void **state)
{
    static char text[10000];
    char err[400];
    c4gh_tf_file_t f;
    (void)state;
    /* fgets(4096) split this line into two rows; now it is one error */
    memset(text, '0', sizeof text);
    memcpy(text, "0,", 2);
    text[5000] = '\n';
    c4gh_tf_open_mem(&f, "t.csv", text, 5001);
    assert_int_equal(srv_parse_traj(&f, &g_tr, err, sizeof err), -1);
    assert_string_equal(err, "t.csv:1:4096: line longer than 4095 bytes, the limit for this file");
}

static void test_traj_accepts(void **state)
{
    char err[400];
    (void)state;
    assert_int_equal(traj("# c\nt ; a ; b\n0 ; 0 ; 0\r\n0.5, -1e6 ,1e6\n", err, sizeof err), 0);
    assert_int_equal(g_tr.rows, 2);
    assert_int_equal(g_tr.cols, 2);
    assert_true(g_tr.t[1] == 0.5 && g_tr.q[1][0] == -1e6f && g_tr.q[1][1] == 1e6f);
    assert_int_equal(srv_load_traj(FIXTURES_DIR "/server/traj_example.csv", &g_tr, err, sizeof err), 0);
    assert_true(g_tr.rows > 10U);
}

static void test_ff_refuses(void **state)
{
    static const struct {
        const char *text;
        const char *msg;
    } bad[] = {
        /* (long)1e30 for the arm is undefined behaviour */
        {"1e30 1 0.5\n", "f.txt:1:1: field 1 (arm): '1e30' is not an integer"},
        {"1 2.5 0.5\n", "f.txt:1:3: field 2 (axis): '2.5' is not an integer"},
        {"1 11 0.5\n", "f.txt:1:3: field 2 (axis): '11' is out of range 1..10"},
        {"1 1 1e30\n", "f.txt:1:5: field 3 (c0): '1e30' is out of range -1000000..1000000"},
        {"1 1 0 0 0 0 0 0 nan\n", "f.txt:1:17: field 9 (gphase): 'nan' is not a finite number"},
        {"1 1 0 0 0 0 0 0 0 0\n", "f.txt:1:19: more than 9 fields"},
        /* a second line for the same axis replaced the first one silently */
        {"1 2 0.1\n# again\n1 2 0.3\n", "f.txt:3:1: arm 1 axis 2 is already set on line 1"},
        {"1 1\n", "f.txt:1: need at least arm, axis, c0 (got 2 fields)"},
        {"1 1 0.5\n\xef\xbf\xbe\xff\n", "f.txt:2:4: invalid UTF-8 byte \\xff at byte offset 11 (after '\\xef\\xbf\\xbe'): "
                                       "binary content is not accepted"},
        {"# only comments\n", "f.txt: no parameter lines"},
    };
    char err[400];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (ff(bad[i].text, err, sizeof err) != -1) {
            fail_msg("accepted: %s", bad[i].text);
        }
        assert_string_equal(err, bad[i].msg);
    }
}

static void test_ff_accepts(void **state)
{
    char err[400];
    (void)state;
    assert_int_equal(ff("2 3 -1e6 1 2 3 4 5 1e6\n", err, sizeof err), 0);
    assert_int_equal(g_ff[1][2].set, 1);
    assert_true(g_ff[1][2].c0 == -1e6 && g_ff[1][2].gphase == 1e6 && g_ff[1][2].gs == 4.0);
    memset(g_ff, 0, sizeof g_ff);
    assert_int_equal(srv_load_ff(FIXTURES_DIR "/server/ff_example.txt", g_ff, err, sizeof err), 0);
    assert_true(g_ff[0][5].set != 0);
}

/* A temporary file holding @p text; its path in @p path (a mkstemp template). */
static void write_tmp(char *path, const char *text)
{
    const int fd = mkstemp(path);
    FILE *fp;
    assert_true(fd >= 0);
    fp = fdopen(fd, "w");
    assert_non_null(fp);
    assert_int_equal(fputs(text, fp) >= 0, 1);
    assert_int_equal(fclose(fp), 0);
}

#define IS_INI(s) srv_ff_is_ini((s), strlen(s))
#define FF_RIGID FIXTURES_DIR "/server/ff_rigid_example.ini"
#define FF_INI FIXTURES_DIR "/server/ff_ident_example.ini"
#define FF_TXT FIXTURES_DIR "/server/ff_example.txt"

/* --ff files of both formats: told apart by content, merged, an axis set twice refused. */
static void test_ff_files(void **state)
{
    char err[800];
    char legacy[] = "/tmp/test_ff_XXXXXX";
    char edited[] = "/tmp/test_ff_XXXXXX";
    char legacy2[] = "/tmp/test_ff_XXXXXX";
    int k;
    (void)state;
    assert_int_equal(IS_INI("[model]\n"), 1);
    assert_int_equal(IS_INI("# c\n; c\n\n \t[model]\n"), 1);
    assert_int_equal(IS_INI("\xef\xbb\xbf[model]"), 1);
    assert_int_equal(IS_INI("\r\n["), 1);
    assert_int_equal(IS_INI("# arm axis c0\n1 1 0.5\n"), 0);
    assert_int_equal(IS_INI("# only comments\n"), 0);
    assert_int_equal(IS_INI(""), 0);
    /* up to 4 files, each an option of its own */
    srv_config_default(&g_cfg);
    for (k = 0; k < 4; k++) {
        assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), 0);
    }
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), -1);
    assert_string_equal(err, "ff: more than 4 parameter files (want a mode-9 parameter file (at "
                             "most 4, under 512 bytes each))");
    assert_int_equal(g_cfg.n_ff, 4U);
    /* the model (arm 1) beside a line file for arm 2 */
    write_tmp(legacy, "# arm axis c0 cv\n2 1 0.5 10\n");
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), 0);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", legacy, 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), 0);
    assert_int_equal(g_cfg.ff[0][1].kind, CTLR_FF_MODEL);
    assert_int_equal(g_cfg.ff[0][1].set, 30);
    assert_int_equal(g_cfg.ff[0][1].file, 0);
    assert_true(g_cfg.ff[0][1].period_ms == 2.0 && g_cfg.ff[0][1].model.gb == 7.5);
    assert_int_equal(g_cfg.ff[0][6].set, 0);
    assert_int_equal(g_cfg.ff[1][0].kind, CTLR_FF_LEGACY);
    assert_int_equal(g_cfg.ff[1][0].set, 2);
    assert_int_equal(g_cfg.ff[1][0].file, 1);
    assert_true(g_cfg.ff[1][0].c0 == 0.5 && g_cfg.ff[1][0].cv == 10.0);
    /* both files set arm 1: named both ways round */
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), 0);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_TXT, 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), -1);
    assert_string_equal(err, "feedforward: " FF_TXT ":15:1: arm 1 axis 1 is already set by " FF_INI ":19");
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_TXT, 0, err, sizeof err), 0);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), -1);
    assert_string_equal(err, "feedforward: " FF_INI ":19:1: arm 1 axis 1 is already set by " FF_TXT ":15");
    /* the same model twice */
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), 0);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), -1);
    assert_string_equal(err, "feedforward: " FF_INI ":19:1: arm 1 axis 1 is already set by " FF_INI ":19");
    /* an edited model: the checksum says so at start-up */
    {
        c4gh_tf_file_t f;
        char text[8192];
        char *p;
        assert_int_equal(c4gh_tf_load(&f, FF_INI, sizeof text - 1U, err, sizeof err), 0);
        memcpy(text, f.data, f.len);
        text[f.len] = '\0';
        c4gh_tf_free(&f);
        p = strstr(text, "gb = 7.5");
        assert_non_null(p);
        p[5] = '8';
        write_tmp(edited, text);
    }
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", edited, 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), -1);
    assert_true(strncmp(err, "feedforward: ", 13U) == 0 && strncmp(err + 13, edited, strlen(edited)) == 0);
    assert_non_null(strstr(err, ":17:12: [model] checksum: checksum mismatch: the file was edited "
                                "after c4g-ident wrote it (expected fnv1a64:"));
    (void)remove(legacy);
    (void)remove(edited);
    /* a rigid-body file: axes 1..6 of arm 1 and the arm's model; a per-axis file for arm 1's
     * axis 1 as well is refused (two models for one axis), a line file for arm 2 is not */
    write_tmp(legacy2, "# arm axis c0 cv\n2 1 0.5 10\n");
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_RIGID, 0, err, sizeof err), 0);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", legacy2, 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), 0);
    assert_int_equal(g_cfg.rigid[0].rigid, 1);
    assert_int_equal(g_cfg.rigid[0].kin.n, 6U);
    assert_int_equal(g_cfg.rigid_file[0], 0U);
    assert_int_equal(g_cfg.rigid[1].rigid, 0);
    for (k = 0; k < 6; k++) {
        assert_int_equal(g_cfg.ff[0][k].kind, CTLR_FF_RIGID);
        assert_true(g_cfg.ff[0][k].set > 0 && g_cfg.ff[0][k].file == 0U);
    }
    assert_int_equal(g_cfg.ff[0][6].set, 0);
    assert_int_equal(g_cfg.ff[1][0].kind, CTLR_FF_LEGACY);
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_RIGID, 0, err, sizeof err), 0);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FF_INI, 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), -1);
    assert_true(strncmp(err, "feedforward: " FF_INI ":19:1: arm 1 axis 1 is already set by " FF_RIGID ":",
                        strlen("feedforward: " FF_INI ":19:1: arm 1 axis 1 is already set by " FF_RIGID ":")) == 0);
    /* the files' own refusals keep their FILE:LINE */
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_apply(&g_cfg, "ff", FIXTURES_DIR "/ident/smart-six.kin", 0, err, sizeof err), 0);
    assert_int_equal(srv_load_files(&g_cfg, err, sizeof err), -1);
    assert_non_null(strstr(err, "smart-six.kin:"));
    (void)remove(legacy2);
}

static void test_huge_files(void **state)
{
    char err[400];
    clock_t t0 = clock();
    (void)state;
    /* fgets on /dev/zero read empty "lines" forever */
    assert_int_equal(srv_load_traj("/dev/zero", &g_tr, err, sizeof err), -1);
    assert_string_equal(err, "/dev/zero: more than 8388608 bytes, the limit for this file: refused");
    assert_int_equal(srv_load_ff("/dev/zero", g_ff, err, sizeof err), -1);
    assert_string_equal(err, "/dev/zero: more than 1048576 bytes, the limit for this file: refused");
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_load_ini(&g_cfg, "/dev/zero", err, sizeof err), -1);
    assert_string_equal(err, "/dev/zero: more than 1048576 bytes, the limit for this file: refused");
    assert_true((double)(clock() - t0) / CLOCKS_PER_SEC < 5.0);
}

static void test_ini_refuses(void **state)
{
    static const struct {
        const char *text;
        const char *msg;
    } bad[] = {
        {"[server]\nidle-timeout = 1e300\n",
         "s.ini:2:16: [server] idle-timeout: '1e300' is out of range 0..10000000 (want seconds >= 0)"},
        {"[server]\nport = 1000.5\n",
         "s.ini:2:8: [server] port: '1000.5' is not an integer (want a UDP port 1..65535)"},
        {"[rt]\nprio = 99999999999999999999\n",
         "s.ini:2:8: [rt] prio: '99999999999999999999' is out of range 0..99 (want a SCHED_FIFO priority 1..99 (0 = off))"},
        {"[arm2]\nsine = 0.1,nan\n",
         "s.ini:2:8: [arm2] sine: 'nan' is not a finite number (want AMP,FREQ[,CYCLES] (turns, Hz > 0, cycles > 0))"},
        /* sscanf("%llu") overflow */
        {"[test]\ninject = 508@99999999999999999999\n",
         "s.ini:2:10: [test] inject: bad value '508@99999999999999999999' (want 505@N or 508@N[:AXIS] "
         "(N = cyclic packet number, AXIS = OPEN index 1..20))"},
        /* atoi("arm99999999999") overflow */
        {"[server]\nport = 31000\n\n[arm99999999999]\nsine = 1,1\n",
         "s.ini:4:1: unknown section [arm99999999999] (want [server], [rt], [output], [test] or [arm1]..[arm4])"},
        {"[server]\n  port = 31000\n  bogus-key = 3\n", "s.ini:3:3: [server] unknown setting 'bogus-key'"},
        /* "rt = 0" switched real time on */
        {"[rt]\nrt = maybe\n", "s.ini:2:6: [rt] rt: bad value 'maybe' (want 1/0, yes/no or true/false)"},
        {"[server]\nport\n", "s.ini:2:1: 'port': expected 'key = value', '[section]' or a ; or # comment"},
    };
    char err[400];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (ini(bad[i].text, err, sizeof err) != -1) {
            fail_msg("accepted: %s", bad[i].text);
        }
        assert_string_equal(err, bad[i].msg);
    }
}

static void test_ini_accepts(void **state)
{
    char err[400];
    (void)state;
    assert_int_equal(ini("[rt]\nrt = 0\nmlock = no\n[arm3]\nhold = 1\nno-exit = false\n", err, sizeof err), 0);
    assert_int_equal(g_cfg.mlock, 0);
    assert_int_equal(g_cfg.prio, 0);
    assert_int_equal(g_cfg.arm[2].src, SRC_NONE);
    assert_int_equal(g_cfg.arm[2].exit_open, 1);
    assert_int_equal(g_cfg.arm[0].src, SRC_SINE);
    assert_int_equal(ini("[test]\ninject = 508@12:3\n[rt]\nrt = yes\n", err, sizeof err), 0);
    assert_int_equal(g_cfg.inject_mode, 508);
    assert_true(g_cfg.inject_at == 12U);
    assert_int_equal(g_cfg.inject_axis, 2);
    assert_int_equal(g_cfg.mlock, 1);
    assert_int_equal(g_cfg.prio, 80);
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_load_ini(&g_cfg, FIXTURES_DIR "/server/server_example.ini", err, sizeof err), 0);
    assert_int_equal(g_cfg.port, 31000);
}

/* The command line overrides the INI file wherever --config stands in it: the file is read
 * first (before 2.0, an option before --config lost to the file). */
static void test_cli_over_config(void **state)
{
    char *before[] = {"c4g-server", "--duration", "7", "-p", "31999", "--config",
                      FIXTURES_DIR "/server/server_example.ini", NULL};
    char *after[] = {"c4g-server", "--config", FIXTURES_DIR "/server/server_example.ini", "--duration", "7",
                     "-p", "31999", NULL};
    char *only[] = {"c4g-server", "--config", FIXTURES_DIR "/server/server_example.ini", NULL};
    (void)state;
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_cli(&g_cfg, "c4g-server", NULL, SRV_CLI_SERVER, 3, only), C4GH_CLI_RUN);
    assert_true(g_cfg.arm[0].duration != 7.0); /* the file's own value: 2 */
    assert_true(g_cfg.port != 31999U);
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_cli(&g_cfg, "c4g-server", NULL, SRV_CLI_SERVER, 7, before), C4GH_CLI_RUN);
    assert_true(g_cfg.arm[0].duration == 7.0);
    assert_int_equal(g_cfg.port, 31999);
    srv_config_default(&g_cfg);
    assert_int_equal(srv_config_cli(&g_cfg, "c4g-server", NULL, SRV_CLI_SERVER, 7, after), C4GH_CLI_RUN);
    assert_true(g_cfg.arm[0].duration == 7.0);
    assert_int_equal(g_cfg.port, 31999);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_traj_refuses),
        cmocka_unit_test(test_cli_over_config),
        cmocka_unit_test(test_traj_long_line),
        cmocka_unit_test(test_traj_accepts),
        cmocka_unit_test(test_ff_refuses),
        cmocka_unit_test(test_ff_accepts),
        cmocka_unit_test(test_ff_files),
        cmocka_unit_test(test_huge_files),
        cmocka_unit_test(test_ini_refuses),
        cmocka_unit_test(test_ini_accepts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
