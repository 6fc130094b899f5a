/* SPDX-License-Identifier: MIT */
/* Unit tests for lib/host/c4gh_textfile.c: strict numbers, checked lines, capped
 * file loading and the INI layer over inih (positions of errors). */
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
#include <unistd.h>
#include <cmocka.h>

#include "c4gh_textfile.h"

static void test_parse_double(void **state)
{
    static const struct {
        const char *s;
        double lo, hi;
        c4gh_tf_num_t st;
        double v;
    } t[] = {
        {"1.5", -10, 10, C4GH_TF_NUM_OK, 1.5},
        {"+.5", -10, 10, C4GH_TF_NUM_OK, 0.5},
        {"5.", -10, 10, C4GH_TF_NUM_OK, 5.0},
        {"-2e3", -1e4, 1e4, C4GH_TF_NUM_OK, -2000.0},
        {"1e39", -1e308, 1e308, C4GH_TF_NUM_OK, 1e39},
        {"1e39", -3.4e38, 3.4e38, C4GH_TF_NUM_RANGE, 0},   /* beyond float */
        {"1e400", -1e308, 1e308, C4GH_TF_NUM_RANGE, 0},    /* strtod: inf + ERANGE */
        {"1e-400", -1, 1, C4GH_TF_NUM_RANGE, 0},           /* underflow */
        {"11", 0, 10, C4GH_TF_NUM_RANGE, 0},
        {"nan", -1, 1, C4GH_TF_NUM_NONFINITE, 0},
        {"-Inf", -1, 1, C4GH_TF_NUM_NONFINITE, 0},
        {"INFINITY", -1, 1, C4GH_TF_NUM_NONFINITE, 0},
        {"nan(123)", -1, 1, C4GH_TF_NUM_NONFINITE, 0},
        {"0x10", 0, 100, C4GH_TF_NUM_SYNTAX, 0},          /* hex floats are not decimal */
        {" 1", 0, 10, C4GH_TF_NUM_SYNTAX, 0},
        {"1 ", 0, 10, C4GH_TF_NUM_SYNTAX, 0},
        {"1,5", 0, 10, C4GH_TF_NUM_SYNTAX, 0},
        {".", 0, 10, C4GH_TF_NUM_SYNTAX, 0},
        {"1e", 0, 10, C4GH_TF_NUM_SYNTAX, 0},
        {"-", 0, 10, C4GH_TF_NUM_SYNTAX, 0},
        {"", 0, 10, C4GH_TF_NUM_EMPTY, 0},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof t / sizeof t[0]; i++) {
        double v = -777.0;
        const c4gh_tf_num_t st = c4gh_tf_parse_double(t[i].s, t[i].lo, t[i].hi, &v);
        if (st != t[i].st) {
            fail_msg("'%s': status %d, want %d", t[i].s, (int)st, (int)t[i].st);
        }
        if (st == C4GH_TF_NUM_OK) {
            assert_true(v == t[i].v);
        } else {
            assert_true(v == -777.0); /* untouched on an error */
        }
    }
}

static void test_parse_int(void **state)
{
    long long v = 0;
    unsigned long long u = 0;
    char why[200];
    (void)state;
    assert_int_equal(c4gh_tf_parse_int("42", 0, 100, &v), C4GH_TF_NUM_OK);
    assert_true(v == 42);
    assert_int_equal(c4gh_tf_parse_int("010", 0, 100, &v), C4GH_TF_NUM_OK); /* decimal, not octal */
    assert_true(v == 10);
    assert_int_equal(c4gh_tf_parse_int("-5", -10, 10, &v), C4GH_TF_NUM_OK);
    assert_true(v == -5);
    assert_int_equal(c4gh_tf_parse_int("4.0", 0, 100, &v), C4GH_TF_NUM_NOT_INT);
    assert_int_equal(c4gh_tf_parse_int("1e3", 0, 10000, &v), C4GH_TF_NUM_NOT_INT);
    assert_int_equal(c4gh_tf_parse_int("99999999999999999999", 0, 100, &v), C4GH_TF_NUM_RANGE);
    assert_int_equal(c4gh_tf_parse_int("2147483648", 0, 2147483647, &v), C4GH_TF_NUM_RANGE);
    assert_int_equal(c4gh_tf_parse_int("-1", 0, 100, &v), C4GH_TF_NUM_RANGE);
    assert_int_equal(c4gh_tf_parse_int("0x10", 0, 100, &v), C4GH_TF_NUM_SYNTAX);
    assert_int_equal(c4gh_tf_parse_int("nan", 0, 100, &v), C4GH_TF_NUM_NONFINITE);
    assert_int_equal(c4gh_tf_parse_int("", 0, 100, &v), C4GH_TF_NUM_EMPTY);
    assert_int_equal(c4gh_tf_parse_uint("18446744073709551615", ~0ULL, &u), C4GH_TF_NUM_OK);
    assert_true(u == ~0ULL);
    assert_int_equal(c4gh_tf_parse_uint("18446744073709551616", ~0ULL, &u), C4GH_TF_NUM_RANGE);
    assert_int_equal(c4gh_tf_parse_uint("-1", ~0ULL, &u), C4GH_TF_NUM_RANGE);
    assert_int_equal(c4gh_tf_parse_uint("1.5", ~0ULL, &u), C4GH_TF_NUM_NOT_INT);

    c4gh_tf_num_explain(C4GH_TF_NUM_RANGE, "1e39", -1e6, 1e6, why, sizeof why);
    assert_string_equal(why, "'1e39' is out of range -1000000..1000000");
    c4gh_tf_num_explain(C4GH_TF_NUM_NONFINITE, "nan", 0, 1, why, sizeof why);
    assert_string_equal(why, "'nan' is not a finite number");
    c4gh_tf_num_explain(C4GH_TF_NUM_NOT_INT, "1.5", 0, 1, why, sizeof why);
    assert_string_equal(why, "'1.5' is not an integer");
    c4gh_tf_num_explain(C4GH_TF_NUM_SYNTAX, "a\x01", 0, 1, why, sizeof why);
    assert_string_equal(why, "'a\\x01' is not a decimal number");
}

static void test_escape(void **state)
{
    char out[16];
    (void)state;
    c4gh_tf_escape("ab\0c\\", 5, out, sizeof out);
    assert_string_equal(out, "ab\\x00c\\x5c");
    c4gh_tf_escape("0123456789abcdefghij", 20, out, sizeof out);
    assert_string_equal(out, "0123456789ab...");
    assert_true(strlen(out) < sizeof out);
}

static void test_lines(void **state)
{
    static const char text[] = "a\r\nb\n\n\tc d\xc3\xa9";
    c4gh_tf_file_t f;
    char line[16];
    char err[300];
    (void)state;
    c4gh_tf_open_mem(&f, "x.txt", text, sizeof text - 1U);
    assert_int_equal(c4gh_tf_next_line(&f, line, sizeof line, err, sizeof err), 1);
    assert_string_equal(line, "a"); /* CR LF */
    assert_int_equal(c4gh_tf_next_line(&f, line, sizeof line, err, sizeof err), 1);
    assert_string_equal(line, "b");
    assert_int_equal(c4gh_tf_next_line(&f, line, sizeof line, err, sizeof err), 1);
    assert_string_equal(line, "");
    assert_int_equal(c4gh_tf_next_line(&f, line, sizeof line, err, sizeof err), 1);
    assert_string_equal(line, "\tc d\xc3\xa9"); /* TAB and UTF-8 are text */
    assert_int_equal(f.line, 4);
    assert_int_equal(c4gh_tf_next_line(&f, line, sizeof line, err, sizeof err), 0);
}

static void test_line_errors(void **state)
{
    static const struct {
        const char *text;
        size_t len;
        const char *msg;
    } t[] = {
        {"ok\nDELAY 1\0\n", 11, "x.txt:2:8: NUL byte \\x00 at byte offset 10 (after 'DELAY 1'): "
                                 "binary content is not accepted"},
        {"\x7f" "ELF", 4, "x.txt:1:1: control byte \\x7f at byte offset 0: binary content is not accepted"},
        {"a\rb\n", 4, "x.txt:1:2: control byte \\x0d at byte offset 1 (after 'a'): binary content is not accepted"},
        {"key \xff\n", 6, "x.txt:1:5: invalid UTF-8 byte \\xff at byte offset 4 (after 'key '): "
                          "binary content is not accepted"},
        {"\xc0\xaf", 2, "x.txt:1:1: invalid UTF-8 byte \\xc0 at byte offset 0: binary content is not accepted"},
        {"\xed\xa0\x80", 3, "x.txt:1:1: invalid UTF-8 byte \\xed at byte offset 0: binary content is not accepted"},
        {"1234567\n12345678\n", 17, "x.txt:2:8: line longer than 7 bytes, the limit for this file"},
        {"0123456789012345678901234567890123456789\x01", 41,
         "x.txt:1:41: control byte \\x01 at byte offset 40 (after '...678901234567890123456789'): "
         "binary content is not accepted"},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof t / sizeof t[0]; i++) {
        c4gh_tf_file_t f;
        char line[64];
        char err[300];
        int r;
        const size_t cap = (i == 6) ? 8U : sizeof line;
        c4gh_tf_open_mem(&f, "x.txt", t[i].text, t[i].len);
        while ((r = c4gh_tf_next_line(&f, line, cap, err, sizeof err)) > 0) {
        }
        if (r != -1) {
            fail_msg("case %zu: no error", i);
        }
        assert_string_equal(err, t[i].msg);
    }
}

static void test_load(void **state)
{
    char path[] = "/tmp/tf_test_XXXXXX";
    char err[300];
    c4gh_tf_file_t f;
    FILE *fp;
    int fd;
    clock_t t0;
    size_t k;
    (void)state;
    /* /dev/zero has no size: refused at the cap, promptly */
    t0 = clock();
    assert_int_equal(c4gh_tf_load(&f, "/dev/zero", 4096U, err, sizeof err), -1);
    assert_string_equal(err, "/dev/zero: more than 4096 bytes, the limit for this file: refused");
    assert_true((double)(clock() - t0) / CLOCKS_PER_SEC < 2.0);
    assert_int_equal(c4gh_tf_load(&f, "/", 4096U, err, sizeof err), -1);
    assert_string_equal(err, "/: is a directory, not a text file");
    assert_int_equal(c4gh_tf_load(&f, "/nonexistent/x.ini", 4096U, err, sizeof err), -1);
    assert_string_equal(err, "/nonexistent/x.ini: cannot open: No such file or directory");

    fd = mkstemp(path);
    assert_true(fd >= 0);
    fp = fdopen(fd, "wb");
    assert_non_null(fp);
    for (k = 0; k < 5000U; k++) {
        fputc('a' + (int)(k % 26U), fp);
    }
    fclose(fp);
    assert_int_equal(c4gh_tf_load(&f, path, 4999U, err, sizeof err), -1);
    assert_non_null(strstr(err, ": 5000 bytes, more than the 4999-byte limit for this file: refused"));
    assert_int_equal(c4gh_tf_load(&f, path, 5000U, err, sizeof err), 0);
    assert_int_equal(f.len, 5000);
    assert_true(f.data[0] == 'a' && f.data[4999] == 'a' + (4999 % 26));
    c4gh_tf_free(&f);
    unlink(path);
}

/* ---- INI */

typedef struct rec {
    int calls;
    char last[200];
    const char *fail_key;    /* key that gets C4GH_TF_INI_BAD_VALUE */
    c4gh_tf_ini_rc_t fail_rc;
} rec_t;

static c4gh_tf_ini_rc_t rec_handler(void *user, const char *section, const char *name, const char *value,
                               char *msg, size_t msglen)
{
    rec_t *r = user;
    r->calls++;
    snprintf(r->last, sizeof r->last, "[%s] %s=%s", section, name, value);
    if (r->fail_key != NULL && strcmp(name, r->fail_key) == 0) {
        snprintf(msg, msglen, "[%s] %s: bad '%s'", section, name, value);
        return r->fail_rc;
    }
    return C4GH_TF_INI_OK;
}

static int ini(const char *text, size_t len, rec_t *r, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    c4gh_tf_open_mem(&f, "x.ini", text, len);
    return c4gh_tf_ini_parse(&f, rec_handler, r, err, errlen);
}

static void test_ini_positions(void **state)
{
    rec_t r;
    char err[300];
    char big[400];
    (void)state;
    /* An indented key is a key, not a continuation of the previous value. */
    memset(&r, 0, sizeof r);
    assert_int_equal(ini("[s]\na = 1\n  b = 2\n", sizeof("[s]\na = 1\n  b = 2\n") - 1U, &r, err, sizeof err), 0);
    assert_int_equal(r.calls, 2);
    assert_string_equal(r.last, "[s] b=2");

    /* A bad value: its own line and the value's column, and nothing after it runs. */
    memset(&r, 0, sizeof r);
    r.fail_key = "port";
    r.fail_rc = C4GH_TF_INI_BAD_VALUE;
    assert_int_equal(ini("[s]\nseed = 1\n  port  =   1e39\nz = 3\nq = 4\n", sizeof("[s]\nseed = 1\n  port  =   1e39\nz = 3\nq = 4\n") - 1U, &r, err, sizeof err), -1);
    assert_string_equal(err, "x.ini:3:13: [s] port: bad '1e39'");
    assert_int_equal(r.calls, 2);

    /* A bad key: the key's column. */
    memset(&r, 0, sizeof r);
    r.fail_key = "speed";
    r.fail_rc = C4GH_TF_INI_BAD_KEY;
    assert_int_equal(ini("[s]\n\n\tspeed = 3\n", sizeof("[s]\n\n\tspeed = 3\n") - 1U, &r, err, sizeof err), -1);
    assert_string_equal(err, "x.ini:3:2: [s] speed: bad '3'");

    /* A bad section: reported at the [section] line, not at the key. */
    memset(&r, 0, sizeof r);
    r.fail_key = "k";
    r.fail_rc = C4GH_TF_INI_BAD_SECTION;
    assert_int_equal(ini("[a]\nx = 1\n [bogus]\n; c\nk = 1\n", sizeof("[a]\nx = 1\n [bogus]\n; c\nk = 1\n") - 1U, &r, err, sizeof err), -1);
    assert_string_equal(err, "x.ini:3:2: [bogus] k: bad '1'");

    /* The first error wins: a syntax error before a bad value ... */
    memset(&r, 0, sizeof r);
    r.fail_key = "b";
    r.fail_rc = C4GH_TF_INI_BAD_VALUE;
    assert_int_equal(ini("[s]\nport 1000\nb = 2\n", sizeof("[s]\nport 1000\nb = 2\n") - 1U, &r, err, sizeof err), -1);
    assert_string_equal(err, "x.ini:2:1: 'port 1000': expected 'key = value', '[section]' or a ; or # comment");
    /* ... and a bad value before a syntax error. */
    memset(&r, 0, sizeof r);
    r.fail_key = "b";
    r.fail_rc = C4GH_TF_INI_BAD_VALUE;
    assert_int_equal(ini("[s]\nb = 2\nport 1000\n", sizeof("[s]\nb = 2\nport 1000\n") - 1U, &r, err, sizeof err), -1);
    assert_string_equal(err, "x.ini:2:5: [s] b: bad '2'");
    memset(&r, 0, sizeof r);
    assert_int_equal(ini("[s\nk = 1\n", sizeof("[s\nk = 1\n") - 1U, &r, err, sizeof err), -1);
    assert_string_equal(err, "x.ini:1:1: '[s': a section header needs a closing ']'");

    /* A line longer than inih's buffer is an error on that line; inih alone would
     * split it and parse the tail as more lines. */
    memset(&r, 0, sizeof r);
    memset(big, 'x', sizeof big);
    memcpy(big, "[s]\nk = ", 8);
    big[sizeof big - 1] = '\n';
    assert_int_equal(ini(big, sizeof big, &r, err, sizeof err), -1);
    assert_non_null(strstr(err, "x.ini:2:"));
    assert_non_null(strstr(err, ": line longer than "));
    assert_int_equal(r.calls, 0);

    /* inih would cut a long section name silently. */
    memset(&r, 0, sizeof r);
    assert_int_equal(ini("[0123456789012345678901234567890123456789012345678901]\nk=1\n", sizeof("[0123456789012345678901234567890123456789012345678901]\nk=1\n") - 1U, &r, err,
                         sizeof err), -1);
    assert_string_equal(err, "x.ini:1:1: section name longer than 49 characters");
    assert_int_equal(r.calls, 0);

    /* Binary content. */
    memset(&r, 0, sizeof r);
    assert_int_equal(ini("[s]\nk = 1\0\n", sizeof("[s]\nk = 1\0\n") - 1U, &r, err, sizeof err), -1);
    assert_string_equal(err, "x.ini:2:6: NUL byte \\x00 at byte offset 9 (after 'k = 1'): binary content is not accepted");
    assert_int_equal(r.calls, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_double),
        cmocka_unit_test(test_parse_int),
        cmocka_unit_test(test_escape),
        cmocka_unit_test(test_lines),
        cmocka_unit_test(test_line_errors),
        cmocka_unit_test(test_load),
        cmocka_unit_test(test_ini_positions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
