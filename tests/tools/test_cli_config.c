/* SPDX-License-Identifier: MIT */
/* cell-cli's INI file (-c): every error names the file, line, column, key and value
 * (the tool sources are included directly). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "c4gh_textfile.h"
#include "c4gh_cell.h"
#include "cli_config.h"

static int cfg(cli_config_t *c, const char *text, size_t len, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    cli_config_default(c);
    c4gh_tf_open_mem(&f, "c.ini", text, len);
    return cli_config_parse(c, &f, err, errlen);
}

static void test_refuses(void **state)
{
    static const struct {
        const char *text;
        const char *msg;
    } bad[] = {
        {"[robot]\nport = 1e39\n", "c.ini:2:8: [robot] port: '1e39' is not an integer"},
        {"[robot]\nport = 70000\n", "c.ini:2:8: [robot] port: '70000' is out of range 1..65535"},
        {"[cli]\nreply_timeout_ms = 99999999999999999999999\n",
         "c.ini:2:20: [cli] reply_timeout_ms: '99999999999999999999999' is out of range 1..600000"},
        {"[cli]\nconnect_timeout_ms = nan\n", "c.ini:2:22: [cli] connect_timeout_ms: 'nan' is not a finite number"},
        /* inih only gave "line N: unknown key or bad value" */
        {"[robot]\nhost = 127.0.0.1\n  prot = 1\n", "c.ini:3:3: [robot]: unknown key 'prot' (want host or port)"},
        {"[robot]\nport = 1\n[camera]\nport = 2\n",
         "c.ini:3:1: unknown section [camera] (want [robot], [platform], [conditioning] or [cli])"},
        {"[robot]\nhost =\n", "c.ini:2:7: [robot] host: want a host name or IPv4 address (1..255 bytes)"},
        {"[robot]\nport = 2001\x00\n", "c.ini:2:12: NUL byte \\x00 at byte offset 19 (after 'port = 2001'): "
                                       "binary content is not accepted"},
        {"[cli]\nhints = maybe\n", "c.ini:2:9: [cli] hints: 'maybe' is not yes or no"},
        {"[cli]\nhint = no\n",
         "c.ini:2:1: [cli]: unknown key 'hint' (want connect_timeout_ms, reply_timeout_ms or hints)"},
    };
    static const size_t len[] = {0, 0, 0, 0, 0, 0, 0, 21, 0, 0};
    cli_config_t c;
    char err[400];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const size_t n = len[i] != 0U ? len[i] : strlen(bad[i].text);
        if (cfg(&c, bad[i].text, n, err, sizeof err) != -1) {
            fail_msg("accepted: %s", bad[i].text);
        }
        assert_string_equal(err, bad[i].msg);
    }
    assert_int_equal(cli_config_load(&c, "/dev/zero", err, sizeof err), -1);
    assert_string_equal(err, "/dev/zero: more than 1048576 bytes, the limit for this file: refused");
}

static void test_accepts(void **state)
{
    cli_config_t c;
    char err[400];
    const char *t = "[Robot]\nhost = 10.0.0.2\nport = 21001\n[platform]\n  port = 21002\n"
                    "[cli]\nconnect_timeout_ms = 1 ; comment\nreply_timeout_ms = 600000\n";
    (void)state;
    assert_int_equal(cfg(&c, t, strlen(t), err, sizeof err), 0);
    assert_string_equal(c.host[C4GH_CELL_DEV_ROBOT], "10.0.0.2");
    assert_int_equal(c.port[C4GH_CELL_DEV_ROBOT], 21001);
    assert_int_equal(c.port[C4GH_CELL_DEV_PLATFORM], 21002);
    assert_int_equal(c.port[C4GH_CELL_DEV_CONDITIONING], 2003);
    assert_int_equal(c.connect_ms, 1);
    assert_int_equal(c.reply_ms, 600000);
    assert_int_equal(c.hints, 1);
    t = "[cli]\nhints = No\n";
    assert_int_equal(cfg(&c, t, strlen(t), err, sizeof err), 0);
    assert_int_equal(c.hints, 0);
    t = "[cli]\nhints = on\n";
    assert_int_equal(cfg(&c, t, strlen(t), err, sizeof err), 0);
    assert_int_equal(c.hints, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refuses),
        cmocka_unit_test(test_accepts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
