/* SPDX-License-Identifier: MIT */
/* Unit tests for the library's controller end (lib/wire/c4g_ctrl.c): handshake driver,
 * NUM policies, reply checks and the reply deadline. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "c4gopen.h"
#include "c4gsim_fixtures.h"

#define MS 1000000ULL
#define US 1000ULL

/* The calls with their status checked: every case below passes valid arguments. */
static void cs_init(c4g_ctrl_t *c, const c4g_ctrl_config_t *cfg)
{
    assert_int_equal(c4g_ctrl_init(c, cfg), C4G_OK);
}
static void cs_advance(c4g_ctrl_t *c)
{
    assert_int_equal(c4g_ctrl_advance(c), C4G_OK);
}
static void cs_restart(c4g_ctrl_t *c)
{
    assert_int_equal(c4g_ctrl_restart(c), C4G_OK);
}
static void cs_emit(c4g_ctrl_t *c, c4g_pkt_kind_t kind, int32_t num, const uint8_t *b, size_t len, int check,
                    uint64_t sent)
{
    assert_int_equal(c4g_ctrl_emit(c, kind, num, b, len, check != 0, sent), C4G_OK);
}
static void cs_set_deadline(c4g_ctrl_t *c, uint64_t d)
{
    assert_int_equal(c4g_ctrl_set_deadline(c, d), C4G_OK);
}
static int cs_sent_stamp(c4g_ctrl_t *c, uint64_t stamp, uint64_t now)
{
    return c4g_ctrl_sent_stamp(c, stamp, now) == C4G_OK;
}
static c4g_ctrl_rx_t cs_reply(c4g_ctrl_t *c, const uint8_t *b, size_t len, uint64_t at)
{
    c4g_ctrl_rx_t r = C4G_CTRL_RX_ACCEPTED;
    assert_int_equal(c4g_ctrl_reply(c, b, len, at, &r), C4G_OK);
    return r;
}
static void cs_foreign(c4g_ctrl_t *c)
{
    assert_int_equal(c4g_ctrl_foreign(c), C4G_OK);
}
static int cs_num_ok(const c4g_ctrl_t *c, int32_t sent, int32_t got)
{
    return c4g_num_accepts(c4g_ctrl_policy(c), sent, got);
}
static int cs_is_stale(const c4g_ctrl_t *c, int32_t cur, int32_t got)
{
    return c4g_num_answers_recent(c4g_ctrl_policy(c), cur, got, C4G_CTRL_STALE_WINDOW);
}
static c4g_ctrl_verdict_t cs_judge(c4g_ctrl_t *c, uint64_t woke, int suspended)
{
    c4g_ctrl_verdict_t v = C4G_CTRL_J_NONE;
    assert_int_equal(c4g_ctrl_judge(c, woke, suspended != 0, &v), C4G_OK);
    return v;
}
static const c4g_pc_packet_t *cs_take_reply(c4g_ctrl_t *c)
{
    const c4g_pc_packet_t *r = NULL;
    const c4g_status_t st = c4g_ctrl_take_reply(c, &r);
    assert_int_equal(st, (r != NULL) ? C4G_OK : C4G_ERR_STATE);
    return r;
}

static c4g_ctrl_config_t config(c4g_num_policy_t policy)
{
    c4g_ctrl_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.policy = policy;
    cfg.n_axes = 2;
    cfg.t_cycle1_ns = 500 * US;
    cfg.tol_ns = 500 * US;
    cfg.max_miss = 3;
    cfg.sync_before = 9;
    cfg.sync_after = 2;
    return cfg;
}

static void put_num(uint8_t *b, int32_t num)
{
    const uint32_t u = (uint32_t)num;
    b[0] = (uint8_t)u;
    b[1] = (uint8_t)(u >> 8);
    b[2] = (uint8_t)(u >> 16);
    b[3] = (uint8_t)(u >> 24);
}

/* A datagram of len bytes: NUM, then a fixed pattern. */
static void dgram(uint8_t *b, size_t len, int32_t num)
{
    size_t i;
    for (i = 0; i < len; i++) {
        b[i] = (uint8_t)(i * 7U + 3U);
    }
    put_num(b, num);
}

/* A valid cyclic PC reply for 2 axes in mode 0. */
static size_t pc_reply(uint8_t *b, size_t cap, int32_t num)
{
    c4g_pc_packet_t p;
    size_t len = 0;
    memset(&p, 0, sizeof p);
    p.num = num;
    p.n_axes = 2;
    p.ax[0].target_pos = 1.5f;
    assert_int_equal(c4g_pc_encode(&p, b, cap, &len), C4G_OK);
    assert_int_equal(len, C4G_CYCLIC_SIZE(2U));
    return len;
}

/* Send one packet of kind/num at sent with its deadline. */
static void emit_pkt(c4g_ctrl_t *c, c4g_pkt_kind_t kind, int32_t num, uint64_t sent, uint64_t deadline)
{
    uint8_t b[C4G_INIT_SIZE];
    const size_t len = (kind == C4G_PKT_INIT) ? C4G_INIT_SIZE : C4G_CYCLIC_SIZE(2U);
    dgram(b, len, num);
    cs_emit(c, kind, num, b, len, 1, sent);
    cs_set_deadline(c, deadline);
}

/* ---- handshake driver ---- */

static void test_handshake_start_and_restart(void **st)
{
    const c4g_ctrl_config_t cfg = config(C4G_NUM_EITHER);
    c4g_ctrl_t c;
    int i;
    (void)st;
    cs_init(&c, &cfg);
    /* 9 sync packets NUM 1..9, the init packet NUM 10, 2 syncs NUM 11, 12, cyclic from 13 */
    for (i = 1; i <= 9; i++) {
        assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_SYNC);
        assert_int_equal(c4g_ctrl_next_num(&c), i);
        cs_advance(&c);
    }
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_INIT);
    assert_int_equal(c4g_ctrl_next_num(&c), 10);
    cs_advance(&c);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_SYNC);
    assert_int_equal(c4g_ctrl_next_num(&c), 11);
    cs_advance(&c);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_SYNC);
    assert_int_equal(c4g_ctrl_next_num(&c), 12);
    cs_advance(&c);
    assert_int_equal(c.phase, C4G_CTRL_PH_CYCLIC);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_CYCLIC);
    assert_int_equal(c4g_ctrl_next_num(&c), 13);
    /* a cyclic packet not sent (pause, freeze) keeps its NUM */
    assert_int_equal(c4g_ctrl_next_num(&c), 13);
    cs_advance(&c);
    assert_int_equal(c4g_ctrl_next_num(&c), 14);
    /* 506: the init packet again (NUM 10), then cyclic from 11 without sync packets */
    cs_restart(&c);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_INIT);
    assert_int_equal(c4g_ctrl_next_num(&c), 10);
    cs_advance(&c);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_CYCLIC);
    assert_int_equal(c4g_ctrl_next_num(&c), 11);
}

static void test_handshake_no_syncs_and_wrap(void **st)
{
    c4g_ctrl_config_t cfg = config(C4G_NUM_ECHO);
    c4g_ctrl_t c;
    (void)st;
    cfg.sync_before = 0;
    cfg.sync_after = 0;
    cs_init(&c, &cfg);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_INIT);
    cs_advance(&c);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_CYCLIC);
    assert_int_equal(c4g_ctrl_next_num(&c), 11);
    c.num = C4G_NUM_MAX;
    cs_advance(&c);
    assert_int_equal(c4g_ctrl_next_num(&c), 0); /* 0x7FFF wraps to 0 */
    assert_int_equal(c4g_num_next(5), 6);
}

/* ---- NUM policies ---- */

static void test_num_policies(void **st)
{
    c4g_ctrl_config_t cfg;
    c4g_ctrl_t c;
    (void)st;
    cfg = config(C4G_NUM_PLUS_ONE);
    cs_init(&c, &cfg);
    assert_true(cs_num_ok(&c, 5, 6));
    assert_false(cs_num_ok(&c, 5, 5));
    assert_false(cs_num_ok(&c, 5, 7));
    assert_true(cs_num_ok(&c, C4G_NUM_MAX, 1)); /* plus-one wraps 0x7FFF to 1 */
    assert_false(cs_num_ok(&c, C4G_NUM_MAX, 0));

    cfg = config(C4G_NUM_ECHO);
    cs_init(&c, &cfg);
    assert_true(cs_num_ok(&c, 5, 5));
    assert_false(cs_num_ok(&c, 5, 6));

    cfg = config(C4G_NUM_EITHER);
    cs_init(&c, &cfg);
    assert_true(cs_num_ok(&c, 5, 5));
    assert_true(cs_num_ok(&c, 5, 6));
    assert_false(cs_num_ok(&c, 5, 7));
    c.detected = C4G_NUM_ECHO; /* locked on what the init echo showed */
    assert_true(cs_num_ok(&c, 5, 5));
    assert_false(cs_num_ok(&c, 5, 6));
    c.detected = C4G_NUM_PLUS_ONE;
    assert_true(cs_num_ok(&c, 5, 6));
    assert_false(cs_num_ok(&c, 5, 5));
}

static void test_stale_window(void **st)
{
    c4g_ctrl_config_t cfg;
    c4g_ctrl_t c;
    (void)st;
    cfg = config(C4G_NUM_PLUS_ONE);
    cs_init(&c, &cfg);
    assert_true(cs_is_stale(&c, 1000, 1000));     /* plus-one reply to 999 */
    assert_true(cs_is_stale(&c, 1000, 489));      /* to 488: 512 back */
    assert_false(cs_is_stale(&c, 1000, 488));     /* to 487: 513 back */
    assert_false(cs_is_stale(&c, 1000, 1001));    /* the right reply is not stale */
    cfg = config(C4G_NUM_ECHO);
    cs_init(&c, &cfg);
    assert_true(cs_is_stale(&c, 1000, 999));
    assert_true(cs_is_stale(&c, 1000, 488));
    assert_false(cs_is_stale(&c, 1000, 487));
    assert_true(cs_is_stale(&c, 5, C4G_NUM_MAX)); /* across the wrap */
    assert_false(cs_is_stale(&c, 1000, 1000));
}

/* ---- reply checks ---- */

static void test_sync_reply_checks(void **st)
{
    const c4g_ctrl_config_t cfg = config(C4G_NUM_PLUS_ONE);
    uint8_t b[C4G_INIT_SIZE];
    c4g_ctrl_t c;
    (void)st;
    cs_init(&c, &cfg);
    dgram(b, C4G_SYNC_REPLY_SIZE, 4);
    assert_int_equal(cs_reply(&c, b, C4G_SYNC_REPLY_SIZE, 10), C4G_CTRL_RX_UNEXPECTED); /* none sent */
    emit_pkt(&c, C4G_PKT_SYNC, 3, 0, 2 * MS);
    assert_int_equal(cs_reply(&c, b, 3, 10), C4G_CTRL_RX_SHORT);
    assert_int_equal(cs_reply(&c, b, C4G_SYNC_REPLY_SIZE - 1U, 10), C4G_CTRL_RX_BAD_LENGTH);
    assert_int_equal(cs_reply(&c, b, C4G_SYNC_REPLY_SIZE + 1U, 10), C4G_CTRL_RX_BAD_LENGTH);
    dgram(b, C4G_SYNC_REPLY_SIZE, 100);
    assert_int_equal(cs_reply(&c, b, C4G_SYNC_REPLY_SIZE, 10), C4G_CTRL_RX_WRONG_NUM);
    assert_int_equal(c.last_num, 100);
    dgram(b, C4G_SYNC_REPLY_SIZE, 3); /* plus-one reply to packet 2 */
    assert_int_equal(cs_reply(&c, b, C4G_SYNC_REPLY_SIZE, 10), C4G_CTRL_RX_STALE);
    dgram(b, C4G_SYNC_REPLY_SIZE, 4);
    assert_int_equal(cs_reply(&c, b, C4G_SYNC_REPLY_SIZE, 10), C4G_CTRL_RX_ACCEPTED);
    assert_int_equal(cs_reply(&c, b, C4G_SYNC_REPLY_SIZE, 20), C4G_CTRL_RX_DUPLICATE);
    assert_int_equal(c.out.got_ns, 10); /* the first one is kept */
    assert_int_equal(c.n.rx_total, 8);
    assert_int_equal(c.n.unexpected, 1);
    assert_int_equal(c.n.malformed, 3);
    assert_int_equal(c.n.wrong_num, 1);
    assert_int_equal(c.n.stale, 1);
    assert_int_equal(c.n.duplicates, 1);
    assert_int_equal(c.n.sync_sent, 1);
    cs_foreign(&c);
    assert_int_equal(c.n.foreign, 1);
    assert_int_equal(c.n.rx_total, 9);
}

static void test_init_echo_and_either_lock(void **st)
{
    const c4g_ctrl_config_t cfg = config(C4G_NUM_EITHER);
    uint8_t b[C4G_INIT_SIZE];
    c4g_ctrl_t c;
    (void)st;
    cs_init(&c, &cfg);
    emit_pkt(&c, C4G_PKT_INIT, 10, 0, 2 * MS);
    dgram(b, C4G_INIT_SIZE, 11);
    b[600] ^= 1U; /* one byte of the echo differs */
    assert_int_equal(cs_reply(&c, b, C4G_INIT_SIZE, 10), C4G_CTRL_RX_BAD_INIT);
    b[600] ^= 1U;
    assert_int_equal(cs_reply(&c, b, C4G_INIT_SIZE - 1U, 10), C4G_CTRL_RX_BAD_INIT);
    assert_int_equal(c.detected, -1);
    assert_int_equal(cs_reply(&c, b, C4G_INIT_SIZE, 10), C4G_CTRL_RX_ACCEPTED);
    assert_int_equal(c.detected, C4G_NUM_PLUS_ONE); /* NUM 11 for the init packet's 10 */
    assert_string_equal(c4g_num_policy_name(c.detected), "plus-one");
    /* from now on an echo is wrong (or stale) */
    emit_pkt(&c, C4G_PKT_CYCLIC, 13, 2 * MS, 4 * MS);
    assert_false(cs_num_ok(&c, 13, 13));

    cs_init(&c, &cfg);
    emit_pkt(&c, C4G_PKT_INIT, 10, 0, 2 * MS);
    dgram(b, C4G_INIT_SIZE, 10);
    assert_int_equal(cs_reply(&c, b, C4G_INIT_SIZE, 10), C4G_CTRL_RX_ACCEPTED);
    assert_int_equal(c.detected, C4G_NUM_ECHO);
    assert_string_equal(c4g_num_policy_name(-1), "unknown");
}

static void test_cyclic_reply_decode(void **st)
{
    const c4g_ctrl_config_t cfg = config(C4G_NUM_PLUS_ONE);
    uint8_t b[256];
    size_t len;
    c4g_ctrl_t c;
    (void)st;
    cs_init(&c, &cfg);
    emit_pkt(&c, C4G_PKT_CYCLIC, 20, 0, 2 * MS);
    len = pc_reply(b, sizeof b, 21);
    /* one axis short: the length refused */
    assert_int_equal(cs_reply(&c, b, C4G_CYCLIC_SIZE(1U), 10), C4G_CTRL_RX_BAD_DECODE);
    assert_int_equal(c.last_diag.status, C4G_ERR_LENGTH);
    /* an unknown mode on axis 1 */
    put_num(&b[C4G_HEADER_SIZE + C4G_AXIS_SIZE], 12345);
    assert_int_equal(cs_reply(&c, b, len, 10), C4G_CTRL_RX_BAD_DECODE);
    assert_int_equal(c.last_diag.status, C4G_ERR_MODE);
    assert_int_equal(c.last_diag.field, C4G_FIELD_SM);
    assert_int_equal(c.last_diag.axis, 1);
    assert_int_equal(c.n.malformed, 2);
    len = pc_reply(b, sizeof b, 21);
    assert_int_equal(cs_reply(&c, b, len, 300 * US), C4G_CTRL_RX_ACCEPTED);
    /* the decoded reply goes to the next tick once judged, and only once */
    assert_null(cs_take_reply(&c));
    assert_int_equal(cs_judge(&c, 2 * MS, 0), C4G_CTRL_J_OK);
    {
        const c4g_pc_packet_t *r = cs_take_reply(&c);
        assert_non_null(r);
        assert_int_equal(r->num, 21);
        assert_true(r->ax[0].target_pos > 1.49f && r->ax[0].target_pos < 1.51f);
    }
    assert_null(cs_take_reply(&c));
}

/* ---- the reply deadline ---- */

/* Send at 1 ms, deadline 3 ms; reply at `at` (0: none); judge at `woke`. */
static c4g_ctrl_verdict_t one(c4g_ctrl_t *c, uint64_t at, uint64_t woke)
{
    uint8_t b[256];
    const int32_t num = c4g_ctrl_next_num(c);
    size_t len;
    emit_pkt(c, C4G_PKT_CYCLIC, num, 1 * MS, 3 * MS);
    cs_advance(c);
    if (at != 0U) {
        len = pc_reply(b, sizeof b, num);
        assert_int_equal(cs_reply(c, b, len, at), C4G_CTRL_RX_ACCEPTED);
    }
    return cs_judge(c, woke, 0);
}

static void test_deadline_boundaries(void **st)
{
    c4g_ctrl_config_t cfg = config(C4G_NUM_ECHO);
    c4g_ctrl_t c;
    (void)st;
    cfg.max_miss = 100;
    cs_init(&c, &cfg);
    c.phase = C4G_CTRL_PH_CYCLIC;
    c.num = 100;
    /* latency exactly t-cycle1: on time; 1 ns more: late; at the deadline: still ok */
    assert_int_equal(one(&c, 1 * MS + 500 * US, 3 * MS), C4G_CTRL_J_OK);
    assert_int_equal(c.last_late, 0);
    assert_int_equal(one(&c, 1 * MS + 500 * US + 1, 3 * MS), C4G_CTRL_J_OK);
    assert_int_equal(c.last_late, 1);
    assert_int_equal(one(&c, 3 * MS, 3 * MS + 10 * US), C4G_CTRL_J_OK);
    assert_int_equal(c.n.replies_ok, 3);
    assert_int_equal(c.n.late, 2);
    /* 1 ns after the deadline: missing, and the reply counts as stale */
    assert_int_equal(one(&c, 3 * MS + 1, 3 * MS + 10 * US), C4G_CTRL_J_MISSING);
    assert_int_equal(c.last_stale, 1);
    assert_int_equal(c.n.stale, 1);
    /* no reply, woken within the tolerance: missing; beyond it: unjudged */
    assert_int_equal(one(&c, 0, 3 * MS + 500 * US), C4G_CTRL_J_MISSING);
    assert_int_equal(one(&c, 0, 3 * MS + 500 * US + 1), C4G_CTRL_J_UNJUDGED);
    assert_int_equal(c.n.missing, 2);
    assert_int_equal(c.n.unjudged, 1);
    assert_int_equal(c.n.consecutive, 3);
    assert_int_equal(c.n.max_consecutive, 3);
    /* woken late itself: a reply that was there when it looked counts */
    assert_int_equal(one(&c, 3 * MS + 100 * US, 3 * MS + 600 * US), C4G_CTRL_J_OK);
    assert_int_equal(c.n.consecutive, 0);
    assert_int_equal(c.n.max_consecutive, 3);
    /* latencies: 500 us, 500.001 us, 2000 us, 2100 us */
    assert_int_equal(c.n.lat_min, 500 * US);
    assert_int_equal(c.n.lat_max, 2100 * US);
    assert_int_equal(c.n.lat_sum, (500 + 500 + 2000 + 2100) * US + 1U);
    /* the last reply judged ok is reported for the caller's histogram */
    assert_int_equal(c.last_lat_ns, 2100 * US);
}

static void test_not_judged(void **st)
{
    const c4g_ctrl_config_t cfg = config(C4G_NUM_ECHO);
    uint8_t b[256];
    size_t len;
    c4g_ctrl_t c;
    (void)st;
    cs_init(&c, &cfg);
    assert_int_equal(cs_judge(&c, 1 * MS, 0), C4G_CTRL_J_NONE); /* nothing sent */
    /* active freezing: the packet is closed without a verdict */
    emit_pkt(&c, C4G_PKT_CYCLIC, 50, 0, 2 * MS);
    assert_int_equal(cs_judge(&c, 9 * MS, 1), C4G_CTRL_J_NONE);
    assert_int_equal(c.n.missing + c.n.unjudged + c.n.replies_ok, 0);
    assert_null(cs_take_reply(&c));
    /* a reply that came while suspended is not counted, yet handed over: the PC's
     * EXIT_FROM_OPEN that ends the freezing is in one (before: never handed over, so a
     * controller taking its requests from c4g_ctrl_take_reply stayed frozen) */
    len = pc_reply(b, sizeof b, 52);
    emit_pkt(&c, C4G_PKT_CYCLIC, 52, 0, 2 * MS);
    assert_int_equal(cs_reply(&c, b, len, 8 * MS), C4G_CTRL_RX_ACCEPTED);
    assert_int_equal(cs_judge(&c, 9 * MS, 1), C4G_CTRL_J_NONE);
    assert_int_equal(c.n.missing + c.n.unjudged + c.n.replies_ok + c.n.late + c.n.stale, 0);
    assert_non_null(cs_take_reply(&c));
    assert_null(cs_take_reply(&c)); /* once */
    /* 504: no reply is checked */
    len = pc_reply(b, sizeof b, 51);
    cs_emit(&c, C4G_PKT_CYCLIC, 51, b, len, 0, 2 * MS);
    assert_int_equal(cs_reply(&c, b, len, 2 * MS + 1), C4G_CTRL_RX_UNEXPECTED);
    assert_int_equal(cs_judge(&c, 9 * MS, 0), C4G_CTRL_J_NONE);
    assert_int_equal(c.n.missing, 0);
    assert_int_equal(c.n.cyclic_sent, 3);
}

static void test_max_miss_is_fatal(void **st)
{
    const c4g_ctrl_config_t cfg = config(C4G_NUM_ECHO); /* max_miss 3 */
    c4g_ctrl_t c;
    (void)st;
    cs_init(&c, &cfg);
    c.phase = C4G_CTRL_PH_CYCLIC;
    assert_int_equal(one(&c, 0, 3 * MS), C4G_CTRL_J_MISSING);
    assert_int_equal(one(&c, 0, 3 * MS), C4G_CTRL_J_MISSING);
    assert_int_equal(c.fatal, 0);
    assert_int_equal(one(&c, 0, 3 * MS), C4G_CTRL_J_MISSING);
    assert_int_equal(c.fatal, 1);
    /* a reply in time ends the run of misses */
    assert_int_equal(one(&c, 2 * MS, 3 * MS), C4G_CTRL_J_OK);
    assert_int_equal(c.fatal, 0);
    assert_int_equal(c.n.consecutive, 0);
}

static void test_send_stamp(void **st)
{
    const c4g_ctrl_config_t cfg = config(C4G_NUM_ECHO);
    c4g_ctrl_t c;
    (void)st;
    cs_init(&c, &cfg);
    assert_int_equal(cs_sent_stamp(&c, 1 * MS, 2 * MS), 0); /* nothing outstanding */
    emit_pkt(&c, C4G_PKT_CYCLIC, 7, 1 * MS, 3 * MS);
    assert_int_equal(cs_sent_stamp(&c, 0, 2 * MS), 0);               /* no stamp */
    assert_int_equal(cs_sent_stamp(&c, 1 * MS + 50 * US, 1 * MS), 0); /* after now */
    assert_int_equal(cs_sent_stamp(&c, 800 * US - 1, 2 * MS), 0);     /* too early */
    assert_int_equal(c.out.sent_ns, 1 * MS);
    assert_int_equal(cs_sent_stamp(&c, 800 * US, 2 * MS), 1);
    assert_int_equal(c.out.sent_ns, 800 * US);
}

/* ---- argument checks ---- */

static void test_ctrl_arguments(void **st)
{
    c4g_ctrl_config_t cfg = config(C4G_NUM_EITHER);
    c4g_ctrl_t c;
    c4g_ctrl_rx_t r;
    c4g_ctrl_verdict_t v;
    const c4g_pc_packet_t *p = NULL;
    uint8_t b[8] = {0};
    (void)st;
    assert_int_equal(c4g_ctrl_init(NULL, &cfg), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_init(&c, NULL), C4G_ERR_NULL);
    cfg.n_axes = C4G_MAX_AXES + 1U;
    assert_int_equal(c4g_ctrl_init(&c, &cfg), C4G_ERR_ARG);
    cfg.n_axes = 2U;
    cfg.policy = (c4g_num_policy_t)3;
    assert_int_equal(c4g_ctrl_init(&c, &cfg), C4G_ERR_ARG);
    cfg.policy = C4G_NUM_EITHER;
    cfg.sync_before = 0U; /* no sync packets: the init packet comes first */
    cs_init(&c, &cfg);
    assert_int_equal(c4g_ctrl_next_kind(&c), C4G_PKT_INIT);
    assert_int_equal(c4g_ctrl_advance(NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_restart(NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_emit(NULL, C4G_PKT_SYNC, 1, b, 8U, true, 0U), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_emit(&c, C4G_PKT_SYNC, 1, NULL, 8U, true, 0U), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_emit(&c, C4G_PKT_FOREIGN, 1, b, 8U, true, 0U), C4G_ERR_ARG);
    assert_int_equal(c.out.active, 0);
    assert_int_equal(c4g_ctrl_set_deadline(NULL, 1U), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_set_deadline(&c, 1U), C4G_ERR_STATE); /* nothing outstanding */
    assert_int_equal(c4g_ctrl_sent_stamp(NULL, 1U, 1U), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_sent_stamp(&c, 1U, 1U), C4G_ERR_STATE);
    assert_int_equal(c4g_ctrl_emit(&c, C4G_PKT_SYNC, 1, b, 0U, true, 5U), C4G_OK); /* no bytes */
    assert_int_equal(c.out.len, 0);
    assert_int_equal(c4g_ctrl_reply(&c, NULL, 0U, 6U, &r), C4G_OK);
    assert_int_equal(r, C4G_CTRL_RX_SHORT);
    assert_int_equal(c4g_ctrl_reply(NULL, b, 8U, 0U, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_reply(&c, b, 8U, 0U, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_reply(&c, NULL, 8U, 0U, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_foreign(NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_judge(NULL, 0U, false, &v), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_judge(&c, 0U, false, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_take_reply(NULL, &p), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_take_reply(&c, NULL), C4G_ERR_NULL);
    assert_int_equal(c.n.rx_total, 1);
}

/* ---- NUM arithmetic and policy names ---- */

static void test_num_module(void **st)
{
    c4g_num_policy_t p = C4G_NUM_ECHO;
    (void)st;
    assert_int_equal(c4g_num_next(C4G_NUM_MAX), 0);
    assert_int_equal(c4g_num_next(-1), 0);
    assert_int_equal(c4g_num_delta(C4G_NUM_MAX, 0), 1);
    assert_int_equal(c4g_num_delta(0, C4G_NUM_MAX), C4G_NUM_MAX); /* one behind */
    assert_int_equal(c4g_num_delta(5, 5), 0);
    assert_int_equal(c4g_num_delta(INT32_MIN, INT32_MAX), C4G_NUM_MAX); /* raw fields */
    assert_int_equal(c4g_reply_num(C4G_NUM_MAX, C4G_NUM_PLUS_ONE), 1);
    assert_int_equal(c4g_reply_num(-3, C4G_NUM_PLUS_ONE), 1);
    assert_int_equal(c4g_reply_num(7, C4G_NUM_ECHO), 7);
    assert_int_equal(c4g_reply_num(7, C4G_NUM_EITHER), 7);
    assert_true(c4g_num_accepts(C4G_NUM_PLUS_ONE, C4G_NUM_MAX, 1));
    assert_false(c4g_num_accepts(C4G_NUM_PLUS_ONE, C4G_NUM_MAX, 0));
    assert_true(c4g_num_accepts(C4G_NUM_EITHER, 9, 9));
    assert_true(c4g_num_accepts(C4G_NUM_EITHER, 9, 10));
    assert_false(c4g_num_accepts(C4G_NUM_EITHER, 9, 11));
    /* a reply to the packet before, under each policy; across the wrap */
    assert_true(c4g_num_answers_recent(C4G_NUM_ECHO, 0, C4G_NUM_MAX, 1));
    assert_false(c4g_num_answers_recent(C4G_NUM_PLUS_ONE, 0, C4G_NUM_MAX, 1));
    assert_true(c4g_num_answers_recent(C4G_NUM_PLUS_ONE, 1, 1, 1));
    assert_false(c4g_num_answers_recent(C4G_NUM_ECHO, 1, 1, 1));
    assert_true(c4g_num_answers_recent(C4G_NUM_EITHER, 1, 1, 1));
    assert_false(c4g_num_answers_recent(C4G_NUM_EITHER, 100, 50, 10));
    assert_string_equal(c4g_num_policy_name(C4G_NUM_EITHER), "either");
    assert_string_equal(c4g_num_policy_name(3), "unknown");
    assert_int_equal(c4g_num_policy_parse("plus-one", &p), C4G_OK);
    assert_int_equal(p, C4G_NUM_PLUS_ONE);
    assert_int_equal(c4g_num_policy_parse("either", &p), C4G_OK);
    assert_int_equal(p, C4G_NUM_EITHER);
    assert_int_equal(c4g_num_policy_parse("echoes", &p), C4G_ERR_ARG);
    assert_int_equal(c4g_num_policy_parse("ech", &p), C4G_ERR_ARG);
    assert_int_equal(c4g_num_policy_parse("", &p), C4G_ERR_ARG);
    assert_int_equal(p, C4G_NUM_EITHER);
    assert_int_equal(c4g_num_policy_parse(NULL, &p), C4G_ERR_NULL);
    assert_int_equal(c4g_num_policy_parse("echo", NULL), C4G_ERR_NULL);
}

/* ---- the datagram classifier ---- */

static void test_peek(void **st)
{
    uint8_t b[C4G_INIT_SIZE];
    c4g_peek_t k;
    c4g_init_t init;
    size_t len = 0U;
    (void)st;
    assert_int_equal(c4gsim_fig10_1(&init), C4G_OK);
    assert_int_equal(c4g_init_encode(&init, b, sizeof b, &len), C4G_OK);
    assert_int_equal(c4g_peek(b, len, false, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_INIT);
    assert_int_equal(k.num, C4G_INIT_NUM);
    assert_int_equal(k.n_axes, 0);
    b[4] = 4U; /* nFieldPck 4: 1200 bytes, not an init packet, not a cyclic size */
    assert_int_equal(c4g_peek(b, len, true, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_FOREIGN);
    b[4] = 3U;
    b[8] = 8U; /* nFieldAx */
    assert_int_equal(c4g_peek(b, len, true, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_FOREIGN);
    dgram(b, C4G_CYCLIC_SIZE(6U), 77);
    assert_int_equal(c4g_peek(b, C4G_CYCLIC_SIZE(6U), true, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_SYNC);
    assert_int_equal(k.n_axes, 6);
    assert_int_equal(k.num, 77);
    assert_int_equal(c4g_peek(b, C4G_CYCLIC_SIZE(20U), false, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_CYCLIC);
    assert_int_equal(k.n_axes, 20);
    assert_int_equal(c4g_peek(b, C4G_CYCLIC_SIZE(6U) + 1U, false, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_FOREIGN);
    assert_int_equal(c4g_peek(b, C4G_HEADER_SIZE, false, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_FOREIGN);
    assert_int_equal(c4g_peek(b, C4G_CYCLIC_SIZE(21U), false, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_FOREIGN);
    assert_int_equal(c4g_peek(b, 3U, false, &k), C4G_OK);
    assert_int_equal(k.num, -1);
    assert_int_equal(c4g_peek(NULL, 0U, false, &k), C4G_OK);
    assert_int_equal(k.kind, C4G_PKT_FOREIGN);
    assert_int_equal(c4g_peek(NULL, 4U, false, &k), C4G_ERR_NULL);
    assert_int_equal(c4g_peek(b, 4U, false, NULL), C4G_ERR_NULL);
    /* the wire's words, as the tools read them */
    b[0] = 0x78U;
    b[1] = 0x56U;
    b[2] = 0x34U;
    b[3] = 0x92U;
    assert_int_equal(c4g_le_u32(b), 0x92345678U);
    assert_int_equal(c4g_le_i32(b), (int32_t)0x92345678U);
    b[0] = 0x00U;
    b[1] = 0x00U;
    b[2] = 0xC0U;
    b[3] = 0x3FU;
    assert_true(c4g_le_f32(b) == 1.5F);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ctrl_arguments),
        cmocka_unit_test(test_num_module),
        cmocka_unit_test(test_peek),
        cmocka_unit_test(test_handshake_start_and_restart),
        cmocka_unit_test(test_handshake_no_syncs_and_wrap),
        cmocka_unit_test(test_num_policies),
        cmocka_unit_test(test_stale_window),
        cmocka_unit_test(test_sync_reply_checks),
        cmocka_unit_test(test_init_echo_and_either_lock),
        cmocka_unit_test(test_cyclic_reply_decode),
        cmocka_unit_test(test_deadline_boundaries),
        cmocka_unit_test(test_not_judged),
        cmocka_unit_test(test_max_miss_is_fatal),
        cmocka_unit_test(test_send_stamp),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
