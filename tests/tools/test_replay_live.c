/* SPDX-License-Identifier: MIT */
/* c4g-replay live is a front end of c4g-sim --capture: its options map one to one onto
 * c4g-sim's (docs/c4g-replay.md, "live"), and c4g-sim reads them back as they were given. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "app.h"
#include "replay.h"

/* app_t holds the scenario and the histograms: too big for the stack */
static app_t g_app;

static void expect_argv(char **got, int n, const char *const *want)
{
    int i;
    for (i = 0; want[i] != NULL; i++) {
        assert_true(i < n);
        assert_string_equal(got[i], want[i]);
    }
    assert_int_equal(n, i);
    assert_null(got[n]);
}

static void test_live_argv_defaults(void **state)
{
    rp_live_t L;
    char *argv[RP_LIVE_ARGS];
    char num[RP_LIVE_NUMS][RP_LIVE_NUM];
    static const char *const want[] = {"c4g-sim", "--capture", "f.pcap", "--replay-live", "--server",
                                       "127.0.0.1", "--port", "31000", "--spin-us", "100", NULL};
    (void)state;
    memset(&L, 0, sizeof L);
    L.path = "f.pcap";
    (void)snprintf(L.host, sizeof L.host, "127.0.0.1");
    L.port = 31000U;
    L.spin_us = 100U;
    expect_argv(argv, rp_live_argv(&L, "c4g-sim", argv, RP_LIVE_ARGS, num), want);
}

static void test_live_argv_every_option(void **state)
{
    rp_live_t L;
    char *argv[RP_LIVE_ARGS];
    char num[RP_LIVE_NUMS][RP_LIVE_NUM];
    static const char *const want[] = {
        "/x/c4g-sim", "--capture", "a b.pcap", "--replay-live", "--server", "localhost", "--port", "1",
        "--spin-us", "0", "--speed", "0.10000000000000001", "--loop", "1000000", "--loop-gap", "3600000",
        "--session", "3", "--tolerance", "9.9999999999999995e-07", "--t-cycle1", "400",
        "--num-policy", "plus-one", "--capture-ports", "46104,1000", "--json", NULL};
    (void)state;
    memset(&L, 0, sizeof L);
    L.path = "a b.pcap";
    (void)snprintf(L.host, sizeof L.host, "localhost");
    L.port = 1U;
    L.spin_us = 0U;
    L.speed = 0.1;
    L.loops = 1000000U;
    L.gap_ms = 3600000U;
    L.session = 3U;
    L.tolerance = 1e-6;
    L.t_cycle1 = "400";
    L.policy = "plus-one";
    L.ports = "46104,1000";
    L.json = 1;
    expect_argv(argv, rp_live_argv(&L, "/x/c4g-sim", argv, RP_LIVE_ARGS, num), want);
    /* --topspeed instead of --speed */
    L.speed = 0.0;
    L.topspeed = 1;
    assert_true(rp_live_argv(&L, "c4g-sim", argv, RP_LIVE_ARGS, num) > 0);
    assert_string_equal(argv[10], "--topspeed");
}

/* c4g-sim reads every option back as c4g-replay live was given it. */
static void test_live_argv_read_back_by_c4g_sim(void **state)
{
    rp_live_t L;
    char *argv[RP_LIVE_ARGS];
    char num[RP_LIVE_NUMS][RP_LIVE_NUM];
    int n, done = 1;
    (void)state;
    memset(&L, 0, sizeof L);
    L.path = "a b.pcap";
    (void)snprintf(L.host, sizeof L.host, "localhost");
    L.port = 65535U;
    L.spin_us = 7U;
    L.speed = 0.1;
    L.loops = 5U;
    L.gap_ms = 20U;
    L.session = 3U;
    L.tolerance = 1e-6;
    L.t_cycle1 = "400";
    L.policy = "echo";
    L.ports = "46104,1000";
    L.json = 1;
    n = rp_live_argv(&L, "c4g-sim", argv, RP_LIVE_ARGS, num);
    memset(&g_app, 0, sizeof g_app);
    g_app.fd = -1;
    assert_int_equal(app_options(&g_app, n, argv, &done), EXIT_OK);
    assert_int_equal(done, 0);
    assert_string_equal(g_app.o.cap.path, "a b.pcap");
    assert_true(g_app.o.cap.as_replay_live);
    assert_string_equal(g_app.cfg.server, "localhost");
    assert_int_equal(g_app.cfg.port, 65535);
    assert_int_equal(g_app.o.cap.spin_us, 7);
    assert_true(g_app.o.cap.speed == 0.1); /* the same double */
    assert_false(g_app.o.cap.topspeed);
    assert_int_equal(g_app.o.cap.loops, 5);
    assert_int_equal(g_app.o.cap.gap_ms, 20);
    assert_int_equal(g_app.o.cap.session, 3);
    assert_true(g_app.o.cap.tolerance == 1e-6);
    assert_int_equal(g_app.cfg.t_cycle1_us, 400);
    assert_int_equal(g_app.cfg.policy, C4G_NUM_ECHO);
    assert_int_equal(g_app.o.cap.n_ports, 2);
    assert_int_equal(g_app.o.cap.ports[0], 46104);
    assert_int_equal(g_app.o.cap.ports[1], 1000);
    assert_true(g_app.o.json);
}

/* An argv that does not fit is refused, never written past its end. */
static void test_live_argv_too_small(void **state)
{
    rp_live_t L;
    char *argv[RP_LIVE_ARGS];
    char num[RP_LIVE_NUMS][RP_LIVE_NUM];
    (void)state;
    memset(&L, 0, sizeof L);
    L.path = "f.pcap";
    L.port = 1000U;
    argv[6] = (char *)(uintptr_t)"untouched";
    assert_int_equal(rp_live_argv(&L, "c4g-sim", argv, 6U, num), -1);
    assert_null(argv[5]);
    assert_string_equal(argv[6], "untouched");
    assert_int_equal(rp_live_argv(&L, "c4g-sim", argv, 0U, num), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_live_argv_defaults),
        cmocka_unit_test(test_live_argv_every_option),
        cmocka_unit_test(test_live_argv_read_back_by_c4g_sim),
        cmocka_unit_test(test_live_argv_too_small),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
