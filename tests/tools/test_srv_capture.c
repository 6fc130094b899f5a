/* SPDX-License-Identifier: MIT */
/* c4g-server's host loop over its datagram sources (tools/c4g-server/host.c) and the capture
 * source (capture.c, c4g-server --capture): a scripted source shows the loop's decisions
 * (the address filter, the drain after active freezing, the deadline checked at the next
 * datagram's time); real captures of fixtures/replay show the capture source's (recorded
 * times, the drain over what was recorded during the pause, a fresh server where the
 * recorded one stopped, a synthetic start-up) and the comparison's figures. c4g-replay
 * rerun's front end asks c4g-server for what its own options say. */
#define TH_FIG10_1
#include "test_helpers.h"

#include "replay.h"
#include "srv_capture.h"

#define MS 1000000ULL
#define N_AX 6U
#define FX FIXTURES_DIR "/replay/"

/* ---- a scripted source ----------------------------------------------------------- */

#define FK_MAX 64U

typedef struct fk_dgram {
    uint8_t b[C4G_INIT_SIZE];
    size_t len;
    c4g_endpoint_t from;
    uint64_t t;
    int32_t num;
} fk_dgram_t;

typedef struct fake {
    fk_dgram_t d[FK_MAX];
    unsigned n, next;
    uint64_t clock, last_tx;
    /* what the loop did */
    int32_t replied[FK_MAX];  /* NUM of the datagrams answered */
    uint64_t replied_t[FK_MAX];
    unsigned n_replied;
    int32_t dropped[FK_MAX];  /* NUM of the datagrams dropped unanswered */
    unsigned n_dropped, n_accepted, pauses;
    uint8_t last_out[C4G_INIT_SIZE];
    size_t last_len;
} fake_t;

static fake_t g_fk;
static srv_host_t g_host;

static uint64_t fk_now(void *ctx)
{
    return ((fake_t *)ctx)->clock;
}

static void fk_take(fake_t *F, uint64_t t, srv_dgram_t *d)
{
    const fk_dgram_t *x = &F->d[F->next];
    d->size = x->len;
    d->len = x->len;
    memcpy(d->buf, x->b, x->len);
    d->from = x->from;
    d->t_rx = t;
    d->t_cap = t;
    d->ref = F->next++;
}

/* as the capture source: the clock jumps to the next datagram */
static int fk_next(void *ctx, uint64_t due, srv_dgram_t *d)
{
    fake_t *F = ctx;
    if (F->next >= F->n) {
        return SRV_SRC_END;
    }
    if (F->d[F->next].t >= due && F->d[F->next].t > F->clock) {
        F->clock = F->d[F->next].t;
        return SRV_SRC_NONE;
    }
    if (F->d[F->next].t > F->clock) {
        F->clock = F->d[F->next].t;
    }
    fk_take(F, F->clock, d);
    return SRV_SRC_HAVE;
}

static int fk_queued(void *ctx, srv_dgram_t *d)
{
    fake_t *F = ctx;
    if (F->next >= F->n || F->d[F->next].t >= F->clock) {
        return SRV_SRC_NONE;
    }
    fk_take(F, F->clock, d);
    return SRV_SRC_HAVE;
}

static uint64_t fk_reply(void *ctx, const srv_dgram_t *d, const uint8_t *out, size_t len,
                         const srv_verdict_t *v)
{
    fake_t *F = ctx;
    (void)v;
    if (out == NULL) {
        return 0U;
    }
    F->replied[F->n_replied] = F->d[d->ref].num;
    F->replied_t[F->n_replied++] = d->t_rx;
    memcpy(F->last_out, out, len);
    F->last_len = len;
    F->last_tx = d->t_rx + 100000U;
    return F->last_tx;
}

static void fk_pause(void *ctx, double ms)
{
    fake_t *F = ctx;
    F->pauses++;
    F->clock = F->last_tx + (uint64_t)(ms * 1e6);
}

static void fk_accepted(void *ctx, const srv_dgram_t *d)
{
    (void)d;
    ((fake_t *)ctx)->n_accepted++;
}

static void fk_dropped(void *ctx, const srv_dgram_t *d)
{
    fake_t *F = ctx;
    F->dropped[F->n_dropped++] = F->d[d->ref].num;
}

static srv_source_t fk_source(void)
{
    srv_source_t s;
    memset(&s, 0, sizeof s);
    s.ctx = &g_fk;
    s.now = fk_now;
    s.next = fk_next;
    s.queued = fk_queued;
    s.reply = fk_reply;
    s.pause = fk_pause;
    s.accepted = fk_accepted;
    s.dropped = fk_dropped;
    return s;
}

static void ep(c4g_endpoint_t *e, uint8_t last, uint16_t port)
{
    srv_endpoint(0x7F000000U | last, port, e);
}

/* A controller's datagram NUM @p num at @p t from 127.0.0.@p last: the figure-10.1 init packet
 * at NUM 10, else a 6-axis packet in mode 0 (a synchronization packet before it). */
static void fk_add(int32_t num, uint64_t t, uint8_t last)
{
    fk_dgram_t *x = &g_fk.d[g_fk.n++];
    assert_true(g_fk.n <= FK_MAX);
    if (num == C4G_INIT_NUM) {
        memcpy(x->b, th_fig, C4G_INIT_SIZE);
        x->len = C4G_INIT_SIZE;
    } else {
        x->len = th_ctrl_bytes(x->b, sizeof x->b, num, N_AX, 0);
    }
    x->num = num;
    x->t = t;
    ep(&x->from, last, 3600U);
}

/* The start-up and cyclic NUM 13 .. @p last_num, 2 ms apart from 1 s. */
static uint64_t fk_session(int32_t last_num)
{
    int32_t k;
    memset(&g_fk, 0, sizeof g_fk);
    for (k = 1; k <= last_num; k++) {
        fk_add(k, 1000U * MS + (uint64_t)k * 2U * MS, 1U);
    }
    return 1000U * MS + (uint64_t)last_num * 2U * MS;
}

static void host_config(srv_config_t *cfg, const char *freeze)
{
    char err[256];
    srv_config_default(cfg);
    (void)snprintf(cfg->ctrl_addr, sizeof cfg->ctrl_addr, "any");
    if (freeze != NULL) {
        assert_int_equal(srv_config_apply(cfg, "freeze", freeze, 0, err, sizeof err), 0);
    }
    memset(&g_host, 0, sizeof g_host);
    assert_int_equal(srv_init(&g_host.s, cfg, NULL, NULL), C4G_OK);
}

/* After the pause only the controller's newest queued datagram is answered, at the pause's
 * end; the older ones of the controller are dropped without the session seeing them, another
 * endpoint's goes to the session as foreign. */
static void test_host_drain_after_freezing(void **state)
{
    static srv_config_t cfg;
    const srv_source_t src = fk_source();
    uint64_t t;
    uint64_t rx_before;
    (void)state;
    host_config(&cfg, "5,9"); /* the reply to cyclic packet 5 (NUM 17) freezes for 9 ms */
    t = fk_session(17);       /* NUM 17 at t */
    /* during the pause (t + 0.1 ms .. t + 9.1 ms): NUM 18, 19, another endpoint's, NUM 20 */
    fk_add(18, t + 2U * MS, 1U);
    fk_add(19, t + 4U * MS, 1U);
    fk_add(99, t + 5U * MS, 2U);
    fk_add(20, t + 6U * MS, 1U);
    fk_add(21, t + 10U * MS, 1U); /* after it: answered as usual */
    assert_int_equal(srv_serve(&g_host, &src), SRV_SOURCE_END);
    assert_int_equal(g_fk.pauses, 1);
    assert_int_equal(g_fk.n_dropped, 3);
    assert_int_equal(g_fk.dropped[0], 18);
    assert_int_equal(g_fk.dropped[1], 99);
    assert_int_equal(g_fk.dropped[2], 19);
    assert_int_equal(g_fk.n_accepted, 17U + 2U);
    assert_int_equal(g_fk.n_replied, 17U + 2U);
    assert_int_equal(g_fk.replied[17], 20);
    assert_int_equal(g_fk.replied_t[17], t + 100000U + 9U * MS); /* at the pause's end */
    assert_int_equal(g_fk.replied[18], 21);
    rx_before = srv_counters(&g_host.s)->rx;
    /* the session saw the 17 + 2 answered and the other endpoint's, not NUM 18 and 19 */
    assert_int_equal(rx_before, 17U + 2U + 1U);
    assert_int_equal(srv_counters(&g_host.s)->foreign_total, 1U);
}

/* -c ADDR: another address's datagram never reaches the core. */
static void test_host_address_filter(void **state)
{
    static srv_config_t cfg;
    const srv_source_t src = fk_source();
    (void)state;
    host_config(&cfg, NULL);
    g_host.ctrl.sin_addr.s_addr = htonl(0x7F000001U);
    (void)fk_session(14);
    fk_add(15, 1000U * MS + 29U * MS, 9U); /* 127.0.0.9 */
    assert_int_equal(srv_serve(&g_host, &src), SRV_SOURCE_END);
    assert_int_equal(g_host.s.stats.foreign, 1U);
    assert_int_equal(g_fk.n_dropped, 1);
    assert_int_equal(g_fk.dropped[0], 15);
    assert_int_equal(g_fk.n_accepted, 14);
    assert_int_equal(srv_counters(&g_host.s)->rx, 14U);
}

/* A deadline that passed between two datagrams is checked at the next one's time: a silence
 * longer than the loss timeout ends the run there (exit 3), the datagram still unread. */
static void test_host_deadline_at_next_datagram(void **state)
{
    static srv_config_t cfg;
    const srv_source_t src = fk_source();
    uint64_t t;
    (void)state;
    host_config(&cfg, NULL);
    t = fk_session(20);
    fk_add(21, t + 1500U * MS, 1U); /* the loss timeout is 1 s */
    assert_int_equal(srv_serve(&g_host, &src), EXIT_LOST);
    assert_int_equal(g_fk.next, 20);
    assert_int_equal(g_fk.clock, t + 1500U * MS);
}

/* ---- the capture source on real captures --------------------------------------------- */

static srv_cap_t g_cap;

/* c4g-server's command line (its whole option table) into @p cfg. */
static void parse(srv_config_t *cfg, const char *const *args)
{
    char *argv[32];
    int n = 0;
    char err[400];
    argv[n++] = (char *)(uintptr_t)"c4g-server";
    while (args[n - 1] != NULL) {
        argv[n] = (char *)(uintptr_t)args[n - 1];
        n++;
    }
    argv[n] = NULL;
    srv_config_default(cfg);
    assert_int_equal(srv_config_cli(cfg, "c4g-server", NULL, SRV_CLI_ALL, n, argv), C4GH_CLI_RUN);
    assert_int_equal(srv_load_files(cfg, err, sizeof err), 0);
}

static void run(const char *const *args, int want_rc)
{
    static srv_config_t cfg;
    parse(&cfg, args);
    cfg.cap.no_progress = 1;
    assert_int_equal(srv_capture_run(&g_cap, &cfg), want_rc);
}

/* c4g-server's own capture with the options it ran with: every reply the same. */
static void test_capture_equal(void **state)
{
    static const char *const a[] = {"--capture", FX "mode4.pcap", "--sine", "0.25,1,0.5", NULL};
    (void)state;
    run(a, 0);
    assert_int_equal(g_cap.compared, 403U);
    assert_int_equal(g_cap.divergent, 0U);
    assert_int_equal(g_cap.server_starts, 1U);
    assert_int_equal(g_cap.n_sess, 1U);
    assert_int_equal(g_cap.sess[0].fed[C4G_PKT_SYNC], 11U);
    assert_int_equal(g_cap.sess[0].fed[C4G_PKT_INIT], 1U);
    assert_int_equal(g_cap.sess[0].fed[C4G_PKT_CYCLIC], 391U);
}

/* Another amplitude: the first divergence where the mode-4 motion starts, D1 and D2 only. */
static void test_capture_divergence(void **state)
{
    static const char *const a[] = {"--capture", FX "mode4.pcap", "--sine", "0.3,1,0.5", NULL};
    (void)state;
    run(a, 0);
    assert_int_equal(g_cap.divergent, 250U);
    assert_true(g_cap.have_first);
    assert_int_equal(g_cap.first.field, CAP_F_D1);
    assert_int_equal(g_cap.first.tick, 114U);
    assert_int_equal(g_cap.first.num, 126);
    assert_int_equal(g_cap.first.arm, 1);
    assert_int_equal(g_cap.first.logical, 1);
    assert_int_equal(g_cap.fields[CAP_F_D1].count, 1500U);
    assert_int_equal(g_cap.fields[CAP_F_D2].count, 1500U);
    assert_int_equal(g_cap.words_divergent, 3000U);
}

/* The server's active freezing (--freeze 120,100) over the controller's capture: the packets
 * recorded during the pause are the queue the drain empties; the newest is answered as the
 * recorded server answered it. */
static void test_capture_freeze_drain(void **state)
{
    static const char *const a[] = {"--capture", FX "special-freeze-active.pcap", "--freeze", "120,100", NULL};
    (void)state;
    run(a, 0);
    assert_int_equal(g_cap.compared, 263U);
    assert_int_equal(g_cap.divergent, 0U);
    assert_int_equal(g_cap.sess[0].held_dropped, 48U);
    assert_int_equal(g_cap.sess[0].recorded_missing, 48U);
}

/* A pause past the capture's end: the newest queued packet is the 504, answered (as by the
 * socket server) with the reply that ends active freezing, mode 500 on both axes, which the
 * recording's 504 echo does not carry. The older queued ones are not shown to the session:
 * a rerun that fed them to it found no divergence here. */
static void test_capture_long_pause(void **state)
{
    static const char *const a[] = {"--capture", FX "special-freeze-active.pcap", "--freeze", "120,1000", NULL};
    (void)state;
    run(a, 0);
    assert_int_equal(g_cap.fields[CAP_F_MODE].count, 2U);
    assert_int_equal(g_cap.fields[CAP_F_MODE].first.tick, 251U);
    assert_string_equal(g_cap.fields[CAP_F_MODE].first.produced, "500");
    assert_int_equal(g_cap.sess[0].held_dropped, 130U);
}

/* A 10 s hole: the server would have lost the controller; a fresh one takes the rest. */
static void test_capture_new_run_after_loss(void **state)
{
    static const char *const a[] = {"--capture", FX "field/hole-10s.pcap", NULL};
    (void)state;
    run(a, 0);
    assert_int_equal(g_cap.server_starts, 2U);
    assert_int_equal(g_cap.compared, 403U);
}

/* A capture that starts mid-session: a synthetic start-up first, then every reply equal. */
static void test_capture_synthetic_startup(void **state)
{
    static const char *const a[] = {"--capture", FX "field/midsession-mode4.pcap", "--sine", "0.25,1,0.5", NULL};
    (void)state;
    run(a, 0);
    assert_true(g_cap.sess[0].primed);
    assert_int_equal(g_cap.sess[0].primed_axes, 6U);
    assert_int_equal(g_cap.compared, 353U);
    assert_int_equal(g_cap.divergent, 0U);
}

/* Two controllers in one file: the first one's sessions, or the one --session names. */
static void test_capture_session(void **state)
{
    static const char *const a[] = {"--capture", FX "two-controllers.pcap", NULL};
    static const char *const b[] = {"--capture", FX "two-controllers.pcap", "--session", "2", NULL};
    (void)state;
    run(a, 0);
    assert_int_equal(g_cap.n_other, 1U);
    assert_int_equal(g_cap.other_sessions[0], 2U);
    assert_int_equal(g_cap.divergent, 0U);
    run(b, 0);
    assert_int_equal(g_cap.n_other, 1U);
    assert_int_equal(g_cap.other_sessions[0], 1U);
    assert_int_equal(g_cap.sess[0].id, 2U);
    assert_int_equal(g_cap.divergent, 0U);
}

static void test_capture_unreadable(void **state)
{
    static const char *const a[] = {"--capture", FX "no-such-file.pcap", NULL};
    (void)state;
    run(a, 2);
    assert_int_equal(g_cap.compared, 0U);
}

/* The capture's options without --capture: refused, named. */
static void test_capture_options_need_capture(void **state)
{
    static srv_config_t cfg;
    static const char *const a[] = {"--tolerance", "0.5", NULL};
    static const char *const b[] = {"--sine", "0.2,1", NULL};
    (void)state;
    parse(&cfg, a);
    assert_int_equal(srv_capture_misplaced(&cfg.cap), 1);
    parse(&cfg, b);
    assert_int_equal(srv_capture_misplaced(&cfg.cap), 0);
}

/* ---- c4g-replay rerun's front end ------------------------------------------------ */

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

static void test_rerun_argv_defaults(void **state)
{
    rp_rerun_t R;
    char *argv[RP_RERUN_ARGS];
    char num[RP_RERUN_NUMS][RP_LIVE_NUM];
    static const char *const want[] = {"c4g-server", "--replay-rerun", "--capture", "f.pcap", "--", NULL};
    (void)state;
    memset(&R, 0, sizeof R);
    R.path = "f.pcap";
    expect_argv(argv, rp_rerun_argv(&R, "c4g-server", argv, RP_RERUN_ARGS, num), want);
}

/* Every option, and c4g-server reads them back as they were given. */
static void test_rerun_argv_every_option(void **state)
{
    static srv_config_t cfg;
    rp_rerun_t R;
    char *argv[RP_RERUN_ARGS];
    char num[RP_RERUN_NUMS][RP_LIVE_NUM];
    char *srv[] = {(char *)(uintptr_t)"--sine", (char *)(uintptr_t)"0.2,1"};
    static const char *const want[] = {
        "c4g-server", "--replay-rerun", "--capture", "a b.pcap", "--session", "3", "--behaviour", "echo",
        "--tolerance", "9.9999999999999995e-07", "--list", "1000000000", "--capture-ports", "46104,1000",
        "--json-out", "-", "--no-progress", "--", "--sine", "0.2,1", NULL};
    int n;
    (void)state;
    memset(&R, 0, sizeof R);
    R.path = "a b.pcap";
    R.session = 3U;
    R.echo = 1;
    R.tolerance = 1e-6;
    R.list = 1000000000LL;
    R.ports = "46104,1000";
    R.json = 1;
    R.no_progress = 1;
    R.srv_argv = srv;
    R.srv_argc = 2;
    n = rp_rerun_argv(&R, "c4g-server", argv, RP_RERUN_ARGS, num);
    expect_argv(argv, n, want);
    srv_config_default(&cfg);
    assert_int_equal(srv_config_cli(&cfg, "c4g-server", NULL, SRV_CLI_CAPTURE, n - 3, argv), C4GH_CLI_RUN);
    assert_string_equal(cfg.cap.path, "a b.pcap");
    assert_int_equal(cfg.cap.session, 3U);
    assert_int_equal(cfg.cap.echo, 1);
    assert_true(cfg.cap.tolerance == 1e-6);
    assert_int_equal(cfg.cap.list, 1000000000U);
    assert_string_equal(cfg.cap.ports, "46104,1000");
    assert_string_equal(cfg.json_path, "-");
    assert_int_equal(cfg.cap.no_progress, 1);
    assert_int_equal(cfg.cap.rerun, 1);
    /* the user's c4g-server options are not among these: the server's own rows read them */
    assert_int_equal(srv_config_cli(&cfg, "c4g-server", NULL, SRV_CLI_CAPTURE, n, argv), C4GH_CLI_BAD);
}

static void test_rerun_argv_too_small(void **state)
{
    rp_rerun_t R;
    char *argv[4];
    char num[RP_RERUN_NUMS][RP_LIVE_NUM];
    (void)state;
    memset(&R, 0, sizeof R);
    R.path = "f.pcap";
    assert_int_equal(rp_rerun_argv(&R, "c4g-server", argv, 4U, num), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_host_drain_after_freezing),
        cmocka_unit_test(test_host_address_filter),
        cmocka_unit_test(test_host_deadline_at_next_datagram),
        cmocka_unit_test(test_capture_equal),
        cmocka_unit_test(test_capture_divergence),
        cmocka_unit_test(test_capture_freeze_drain),
        cmocka_unit_test(test_capture_long_pause),
        cmocka_unit_test(test_capture_new_run_after_loss),
        cmocka_unit_test(test_capture_synthetic_startup),
        cmocka_unit_test(test_capture_session),
        cmocka_unit_test(test_capture_unreadable),
        cmocka_unit_test(test_capture_options_need_capture),
        cmocka_unit_test(test_rerun_argv_defaults),
        cmocka_unit_test(test_rerun_argv_every_option),
        cmocka_unit_test(test_rerun_argv_too_small),
    };
    return cmocka_run_group_tests(tests, th_load_fig, NULL);
}
