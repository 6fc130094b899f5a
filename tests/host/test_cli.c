/* SPDX-License-Identifier: MIT */
/* The shared table-driven command line (lib/host/c4gh_cli.c). */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdlib.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>
#include "c4gh_textfile.h"
#include "c4gh_cli.h"

typedef struct cfg {
    int verbose;
    char host[16];
    long long count;
    unsigned port;
    double gain;
    int calls;
    char last[32];
} cfg_t;

static int on_call(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    cfg_t *c = ctx;
    (void)row;
    if (strcmp(v, "bad") == 0) {
        snprintf(why, wl, "not today");
        return -1;
    }
    c->calls++;
    snprintf(c->last, sizeof c->last, "%s", v);
    return 0;
}

static cfg_t G;
static const c4gh_cli_opt_t rows[] = {
    {"verbose", 'v', C4GH_CLI_FLAG, NULL, "say more", &G.verbose, 0, 0, 0, NULL, 0},
    {"host", 'H', C4GH_CLI_STRING, "ADDR", "address", G.host, sizeof G.host, 0, 0, NULL, 0},
    {"count", 0, C4GH_CLI_INT, "N", "how many", &G.count, 0, -5, 5, NULL, 0},
    {"port", 'p', C4GH_CLI_UINT, "PORT", "port", &G.port, 0, 1, 65535, NULL, 0},
    {"gain", 0, C4GH_CLI_DOUBLE, "G", "gain", &G.gain, 0, 0.0, 10.0, NULL, 0},
    {"call", 'c', C4GH_CLI_CALL, "X", "handler", NULL, 0, 0, 0, on_call, 0},
};
static const char *const ex[] = {"tool -v", NULL};
static const c4gh_cli_spec_t spec = {"tool", NULL, "Usage: tool [OPTIONS] [FILE]\n", rows,
                                sizeof rows / sizeof rows[0], ex, NULL, 0, 1, 0, NULL};

static c4gh_cli_result_t run(int argc, const char *const *argv_in, int *first)
{
    char *argv[16];
    int i;
    for (i = 0; i < argc; i++) {
        argv[i] = (char *)argv_in[i];
    }
    argv[argc] = NULL;
    memset(&G, 0, sizeof G);
    return c4gh_cli_parse(&spec, &G, argc, argv, first);
}

static void test_values(void **st)
{
    const char *a[] = {"tool", "-v", "--host", "1.2.3.4", "--count=-5", "-p", "31000",
                       "--gain", "2.5", "-c", "x", "--call", "y", "file"};
    int first = 0;
    (void)st;
    assert_int_equal(run(14, a, &first), C4GH_CLI_RUN);
    assert_int_equal(G.verbose, 1);
    assert_string_equal(G.host, "1.2.3.4");
    assert_int_equal(G.count, -5);
    assert_int_equal(G.port, 31000);
    assert_true(G.gain > 2.49 && G.gain < 2.51);
    assert_int_equal(G.calls, 2);
    assert_string_equal(G.last, "y");
    assert_int_equal(first, 13);
}

static void test_refusals(void **st)
{
    const char *range[] = {"tool", "--count", "6"};
    const char *frac[] = {"tool", "-p", "1.5"};
    const char *nan[] = {"tool", "--gain", "nan"};
    const char *longs[] = {"tool", "--host", "0123456789abcdef"};
    const char *unk[] = {"tool", "--nope"};
    const char *miss[] = {"tool", "--host"};
    const char *call[] = {"tool", "-c", "bad"};
    const char *extra[] = {"tool", "a", "b"};
    (void)st;
    assert_int_equal(run(3, range, NULL), C4GH_CLI_BAD);
    assert_int_equal(run(3, frac, NULL), C4GH_CLI_BAD);
    assert_int_equal(G.port, 0);
    assert_int_equal(run(3, nan, NULL), C4GH_CLI_BAD);
    assert_int_equal(run(3, longs, NULL), C4GH_CLI_BAD);
    assert_int_equal(run(2, unk, NULL), C4GH_CLI_BAD);
    assert_int_equal(run(2, miss, NULL), C4GH_CLI_BAD);
    assert_int_equal(run(3, call, NULL), C4GH_CLI_BAD);
    assert_int_equal(run(3, extra, NULL), C4GH_CLI_BAD);
}

static void test_help_version(void **st)
{
    const char *h[] = {"tool", "--help"};
    const char *v[] = {"tool", "-V"};
    char buf[4096];
    FILE *f = fmemopen(buf, sizeof buf, "w");
    (void)st;
    assert_non_null(f);
    c4gh_cli_usage(&spec, f);
    fclose(f);
    assert_non_null(strstr(buf, "-H, --host ADDR"));
    assert_non_null(strstr(buf, "--gain G"));
    assert_non_null(strstr(buf, "Examples:\n  tool -v\n"));
    assert_int_equal(run(2, h, NULL), C4GH_CLI_DONE);
    assert_int_equal(run(2, v, NULL), C4GH_CLI_DONE);
}

/* Output files checked at start-up, and paths as messages show them. */
static void test_outputs(void **st)
{
    char buf[64];
    char dir[] = "/tmp/test_cli_XXXXXX";
    char file[128];
    FILE *f;
    (void)st;
    assert_non_null(mkdtemp(dir));
    snprintf(file, sizeof file, "%s/out.json", dir);
    assert_int_equal(c4gh_cli_output_writable("-"), 0);
    assert_int_equal(c4gh_cli_output_writable(file), 0);     /* a new file in a writable directory */
    assert_int_equal(c4gh_cli_output_writable("/nonexistent-dir/x.json"), -1);
    assert_int_equal(errno, ENOENT);
    assert_int_equal(c4gh_cli_output_writable(dir), -1);      /* a directory */
    assert_int_equal(errno, EISDIR);
    f = fopen(file, "w");
    assert_non_null(f);
    fclose(f);
    assert_int_equal(c4gh_cli_output_writable(file), 0);     /* an existing writable file */
    snprintf(file + strlen(file), sizeof file - strlen(file), "/below");
    assert_int_equal(c4gh_cli_output_writable(file), -1);     /* below a regular file */
    assert_int_equal(errno, ENOTDIR);
    assert_int_equal(c4gh_cli_output_writable(""), -1);
    assert_string_equal(c4gh_cli_path_text("a\001b\nc", buf, sizeof buf), "a\\x01b\\x0ac");
    assert_null(c4gh_cli_open_output("tool", "--json", "/nonexistent-dir/x.json", "w"));
    assert_ptr_equal(c4gh_cli_open_output("tool", "--json", "-", "w"), stdout);
    snprintf(file, sizeof file, "%s/out.json", dir);
    assert_int_equal(remove(file), 0);
    assert_int_equal(rmdir(dir), 0);
}

/* INI keys as long option names; the -c / --config value found before parsing. */
static void test_apply_and_config(void **st)
{
    char why[128];
    char *argv1[] = {"tool", "-v", "--config", "x.ini", "--", "-c", "y.ini"};
    char *argv2[] = {"tool", "--config=z.ini"};
    char *argv3[] = {"tool", "--", "--config", "q.ini"};
    (void)st;
    memset(&G, 0, sizeof G);
    assert_int_equal(c4gh_cli_apply(&spec, &G, "host", "h1", why, sizeof why), 0);
    assert_string_equal(G.host, "h1");
    assert_int_equal(c4gh_cli_apply(&spec, &G, "verbose", "true", why, sizeof why), 0);
    assert_int_equal(G.verbose, 1);
    assert_int_equal(c4gh_cli_apply(&spec, &G, "verbose", "maybe", why, sizeof why), -1);
    assert_int_equal(c4gh_cli_apply(&spec, &G, "count", "99", why, sizeof why), -1);
    assert_int_equal(c4gh_cli_apply(&spec, &G, "nope", "1", why, sizeof why), 1);
    assert_string_equal(c4gh_cli_find_config(7, argv1), "x.ini");
    assert_string_equal(c4gh_cli_find_config(2, argv2), "z.ini");
    assert_null(c4gh_cli_find_config(4, argv3));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_values),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_help_version),
        cmocka_unit_test(test_outputs),
        cmocka_unit_test(test_apply_and_config),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
