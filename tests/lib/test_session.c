/* SPDX-License-Identifier: MIT */
/* Session engine: field facts handshake, NUM policies, counters, timing, special modes. */
#define TH_FIG10_1
#include "test_helpers.h"

#define MS 1000000ULL


typedef struct {
    c4g_session_t s;
    c4g_rx_result_t r;
    uint8_t out[1300];
    size_t out_len;
    uint64_t t;
} fx_t;

static c4g_rx_kind_t feed(fx_t *f, const uint8_t *buf, size_t len)
{
    f->t += 2 * MS;
    assert_int_equal(c4g_session_rx(&f->s, buf, len, f->t, &f->r), C4G_OK);
    return f->r.kind;
}

static void sync_packet(uint8_t *b, int32_t num)
{
    memset(b, 0, 732);
    th_put_u32(b, (uint32_t)num);
    b[20] = 0x5A;   /* something to echo */
}

/* Cold start: 9 syncs, init (NUM 10), 2 syncs; returns with the session in CYCLIC. */
static void cold_start(fx_t *f, c4g_num_policy_t pol)
{
    c4g_session_config_t cfg;
    uint8_t b[732];
    int32_t num;
    assert_int_equal(c4g_session_config_default(&cfg), C4G_OK);
    cfg.num_policy = pol;
    assert_int_equal(c4g_session_init(&f->s, &cfg), C4G_OK);
    f->t = 1000 * MS;
    for (num = 1; num <= 9; num++) {
        sync_packet(b, num);
        assert_int_equal(feed(f, b, sizeof b), C4G_RX_SYNC);
        assert_int_equal(f->s.phase, C4G_PHASE_WAIT_INIT);
        assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
        assert_int_equal(f->out_len, 732);
        assert_int_equal((int32_t)th_get_u32(f->out), c4g_reply_num(num, pol));
        assert_int_equal(f->out[20], 0x5A);
        assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_ERR_STATE);
    }
    assert_int_equal(feed(f, th_fig, sizeof th_fig), C4G_RX_INIT);
    assert_true(f->r.events & C4G_EV_INIT);
    assert_int_equal(f->s.phase, C4G_PHASE_POST_SYNC);
    assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
    assert_int_equal(f->out_len, 1200);
    assert_int_equal(th_get_u32(f->out), pol == C4G_NUM_PLUS_ONE ? 11 : 10);
    assert_memory_equal(&f->out[4], &th_fig[4], 1196);
    sync_packet(b, 10); /* a post-init sync repeating a NUM is dropped like any stale packet */
    assert_int_equal(feed(f, b, sizeof b), C4G_RX_DROPPED);
    assert_true(f->r.events & C4G_EV_DUPLICATE);
    sync_packet(b, 9);
    assert_int_equal(feed(f, b, sizeof b), C4G_RX_DROPPED);
    assert_true(f->r.events & C4G_EV_OUT_OF_ORDER);
    f->s.counters.duplicates = f->s.counters.out_of_order = 0;
    for (num = 11; num <= 12; num++) {
        sync_packet(b, num);
        assert_int_equal(feed(f, b, sizeof b), C4G_RX_SYNC);
        assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
        assert_int_equal(f->out_len, 732);
        assert_int_equal((int32_t)th_get_u32(f->out), c4g_reply_num(num, pol));
    }
    assert_int_equal(f->s.phase, C4G_PHASE_CYCLIC);
    assert_int_equal(f->s.counters.sync, 11);
    assert_int_equal(f->s.counters.init, 1);
    assert_int_equal(f->s.map.n_axes, 6);
}

static void cyclic(fx_t *f, int32_t num, int32_t mode)
{
    uint8_t b[732];
    c4g_pc_packet_t tx;
    size_t len = th_ctrl_bytes(b, sizeof b, num, 6, mode);
    assert_int_equal(feed(f, b, len), C4G_RX_CYCLIC);
    assert_non_null(f->r.pkt);
    assert_int_equal(f->r.pkt->num, num);
    assert_int_equal(c4g_pc_reply_neutral(f->r.pkt, &tx), C4G_OK);
    assert_int_equal(c4g_session_reply(&f->s, &tx, f->out, sizeof f->out, &f->out_len), C4G_OK);
    assert_int_equal(f->out_len, 228);
    assert_int_equal(c4g_session_sent(&f->s, f->t + 100000), C4G_OK);
}


/* Feeds @p p to two sessions in the same state; one answers with c4g_session_reply_neutral,
 * the other with c4g_pc_reply_neutral + c4g_session_reply: the same bytes and state. */
static void neutral_both(fx_t *a, fx_t *b, const c4g_ctrl_packet_t *p)
{
    uint8_t buf[732];
    size_t len = 0;
    c4g_pc_packet_t tx;
    assert_int_equal(c4g_ctrl_encode(p, buf, sizeof buf, &len), C4G_OK);
    assert_int_equal(feed(a, buf, len), C4G_RX_CYCLIC);
    assert_int_equal(feed(b, buf, len), C4G_RX_CYCLIC);
    assert_int_equal(a->r.events, b->r.events);
    memset(a->out, 0xA5, sizeof a->out);
    memset(b->out, 0x5A, sizeof b->out);
    assert_int_equal(c4g_session_reply_neutral(&a->s, a->out, sizeof a->out, &a->out_len), C4G_OK);
    assert_int_equal(c4g_pc_reply_neutral(b->r.pkt, &tx), C4G_OK);
    assert_int_equal(c4g_session_reply(&b->s, &tx, b->out, sizeof b->out, &b->out_len), C4G_OK);
    assert_int_equal(a->out_len, C4G_CYCLIC_SIZE(p->n_axes));
    assert_int_equal(a->out_len, b->out_len);
    assert_memory_equal(a->out, b->out, a->out_len);
    assert_int_equal(a->s.priv.frozen_active, b->s.priv.frozen_active);
    assert_int_equal(a->s.counters.tx, b->s.counters.tx);
    assert_int_equal(c4g_session_sent(&a->s, a->t + 100000), C4G_OK);
    assert_int_equal(c4g_session_sent(&b->s, b->t + 100000), C4G_OK);
}

/* The neutral reply holds: the reported reference in an absolute mode, the controller's own
 * current within AzLim where the PC closes the loops, zero additions (was: D1 = 0, "go to 0",
 * and D5 = 0 in modes 1 and 2). */
static void test_session_neutral_holds(void **state)
{
    fx_t a;
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t tx;
    uint8_t buf[732];
    size_t len = 0;
    uint32_t i;
    (void)state;
    assert_int_equal(c4g_session_init(&a.s, NULL), C4G_OK);
    th_ctrl_packet(&p, 13, 6, C4G_MODE_1);
    assert_int_equal(c4g_session_neutral(&a.s, &p, &tx), C4G_ERR_STATE); /* no init yet */
    assert_int_equal(c4g_session_neutral(NULL, &p, &tx), C4G_ERR_NULL);
    cold_start(&a, C4G_NUM_PLUS_ONE);
    for (i = 0; i < 6; i++) {
        p.ax[i].current_ref = (i % 2U == 0U) ? 100.0f : -100.0f; /* beyond AzLim */
    }
    assert_int_equal(c4g_ctrl_encode(&p, buf, sizeof buf, &len), C4G_OK);
    assert_int_equal(feed(&a, buf, len), C4G_RX_CYCLIC);
    assert_int_equal(c4g_session_neutral(&a.s, a.r.pkt, &tx), C4G_OK);
    for (i = 0; i < 6; i++) {
        const float az = a.s.init.az_lim[0][i];
        assert_int_equal(tx.ax[i].mode, C4G_MODE_1);
        assert_true(tx.ax[i].target_pos == 1.0f + (float)i);
        assert_true(tx.ax[i].target_vel == 0.0f);
        assert_true(tx.ax[i].vel_add == 0.0f);
        assert_true(tx.ax[i].current_add == ((i % 2U == 0U) ? az : -az));
    }
    /* the wire bytes of c4g_session_reply_neutral say the same */
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, sizeof a.out, &a.out_len), C4G_OK);
    assert_int_equal(th_get_u32(&a.out[12 + 4]), 0x3F800000U);
    {
        c4g_pc_packet_t w;
        assert_int_equal(c4g_pc_decode(a.out, a.out_len, 6U, &w, NULL), C4G_OK);
        assert_true(w.ax[0].current_add == a.s.init.az_lim[0][0]);
    }
    p.n_axes = 5;
    assert_int_equal(c4g_session_neutral(&a.s, &p, &tx), C4G_ERR_AXES);
    /* mode 9: the delta is zero */
    th_ctrl_packet(&p, 14, 6, C4G_MODE_9);
    assert_int_equal(c4g_session_neutral(&a.s, &p, &tx), C4G_OK);
    assert_true(tx.ax[3].current_add == 0.0f);
    assert_true(tx.ax[3].target_pos == 0.0f);
}

static void test_reply_neutral_direct(void **state)
{
    fx_t a, b;
    c4g_ctrl_packet_t p;
    uint8_t sync[732];
    size_t n = 0;
    (void)state;
    /* a sync is echoed as by c4g_session_reply */
    assert_int_equal(c4g_session_init(&a.s, NULL), C4G_OK);
    a.t = 1000 * MS;
    sync_packet(sync, 1);
    assert_int_equal(feed(&a, sync, sizeof sync), C4G_RX_SYNC);
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, sizeof a.out, &a.out_len), C4G_OK);
    assert_int_equal(a.out_len, 732);
    assert_int_equal(a.out[20], 0x5A);

    cold_start(&a, C4G_NUM_PLUS_ONE);
    cold_start(&b, C4G_NUM_PLUS_ONE);
    th_ctrl_packet(&p, 13, 6, C4G_MODE_4);          /* mode 4: D1 holds the reference */
    neutral_both(&a, &b, &p);
    assert_int_equal(th_get_u32(&a.out[12]), C4G_MODE_4);
    assert_int_equal(th_get_u32(&a.out[12 + 4]), 0x3F800000U);          /* 1.0f, not 0 */
    assert_int_equal(th_get_u32(&a.out[12 + 8]), 0);                     /* D2: none */
    th_ctrl_packet(&p, 14, 6, C4G_MODE_0_DEBUG);    /* 0': D1..D5 copied back */
    neutral_both(&a, &b, &p);
    assert_int_equal(th_get_u32(&a.out[12 + 5 * 36 + 4]), 0x40C00000U); /* 6.0f */
    th_ctrl_packet(&p, 15, 6, C4G_MODE_0);           /* several modes, one of them 0' */
    p.ax[2].mode = C4G_MODE_0_DEBUG;
    p.ax[4].mode = C4G_MODE_4;
    neutral_both(&a, &b, &p);
    assert_int_equal(th_get_u32(&a.out[12 + 4 * 36]), C4G_MODE_4);
    assert_int_equal(th_get_u32(&a.out[12 + 2 * 36 + 12]), 0x40500000U); /* D3 = 3.25f */
    th_ctrl_packet(&p, 16, 6, C4G_MODE_0);           /* 500 on one axis: active freezing */
    p.ax[5].mode = C4G_MODE_FREEZING_A;
    neutral_both(&a, &b, &p);
    assert_int_equal(a.s.priv.frozen_active, 1);
    a.s.priv.frozen_active = b.s.priv.frozen_active = 0U;
    th_ctrl_packet(&p, 17, 6, C4G_MODE_FREEZING_A);  /* 500 on every axis */
    neutral_both(&a, &b, &p);
    assert_int_equal(a.s.priv.frozen_active, 1);

    /* refusals: nothing pending, too small, no arguments */
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, sizeof a.out, &n), C4G_ERR_STATE);
    th_ctrl_packet(&p, 18, 6, C4G_MODE_0);
    assert_int_equal(c4g_ctrl_encode(&p, sync, sizeof sync, &n), C4G_OK);
    assert_int_equal(feed(&a, sync, n), C4G_RX_CYCLIC);
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, 227, &n), C4G_ERR_CAPACITY);
    assert_int_equal(n, 0);
    a.s.priv.rx_mixed_modes = 1U; /* the path of several modes refuses a short buffer too */
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, 227, &n), C4G_ERR_CAPACITY);
    assert_int_equal(n, 0);
    a.s.priv.rx_mixed_modes = 0U;
    assert_int_equal(c4g_session_reply_neutral(NULL, a.out, sizeof a.out, &n), C4G_ERR_NULL);
    assert_int_equal(c4g_session_reply_neutral(&a.s, NULL, sizeof a.out, &n), C4G_ERR_NULL);
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, sizeof a.out, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, 228, &n), C4G_OK);
    assert_int_equal(n, 228);
    assert_int_equal(c4g_session_reply_neutral(&a.s, a.out, 228, &n), C4G_ERR_STATE);
}

/* Session-level modes on one axis of several: the scan must not stop at the first axis. */
static void test_special_mode_on_one_axis(void **state)
{
    fx_t f;
    c4g_ctrl_packet_t p;
    uint8_t b[732];
    size_t len = 0;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    th_ctrl_packet(&p, 13, 6, C4G_MODE_0);
    p.ax[3].mode = C4G_MODE_FREEZING_P_IN;
    assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
    assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
    assert_true(f.r.events & C4G_EV_FREEZE_IN);
    assert_int_equal(f.s.priv.frozen, 1);
    assert_int_equal(f.s.priv.rx_mixed_modes, 1);
    assert_int_equal(c4g_session_reply_neutral(&f.s, f.out, sizeof f.out, &f.out_len), C4G_OK);
    th_ctrl_packet(&p, 14, 6, C4G_MODE_0);
    p.ax[5].mode = C4G_MODE_EXIT_OPEN;
    assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
    assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
    assert_true(f.r.events & C4G_EV_END);
    assert_int_equal(f.s.phase, C4G_PHASE_ENDED);
}

/* A cyclic packet decodes into the session's buffers without touching the axes past the
 * session's count: a new start-up with fewer axes must not leave the old ones there (the
 * bulk check reads a few words past the axes). */
static void test_fewer_axes_after_restart(void **state)
{
    fx_t f;
    c4g_init_t in;
    c4g_ctrl_packet_t p;
    uint8_t init[C4G_INIT_SIZE], b[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;
    uint32_t i, k;
    (void)state;
    assert_int_equal(c4g_init_decode(th_fig, sizeof th_fig, &in, NULL), C4G_OK);
    in.n_ax_open = 20;
    for (i = 0; i < 20; i++) {
        in.open_ax[i / 10][i % 10] = (int32_t)i;
        in.az_lim[i / 10][i % 10] = 10.0f;
        in.tx_rate[i / 10][i % 10] = 50.0f;
        in.follow_error[i / 10][i % 10] = 5.0f;
    }
    assert_int_equal(c4g_init_encode(&in, init, sizeof init, &len), C4G_OK);
    assert_int_equal(c4g_session_init(&f.s, NULL), C4G_OK);
    f.t = 1000 * MS;
    assert_int_equal(feed(&f, init, len), C4G_RX_INIT);
    assert_int_equal(f.s.map.n_axes, 20);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    for (k = 0; k < 2; k++) { /* both buffers of the double buffer hold 20 axes */
        th_ctrl_packet(&p, 11 + (int32_t)k, 20, C4G_MODE_0);
        assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
        assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
        assert_int_equal(c4g_session_reply_neutral(&f.s, f.out, sizeof f.out, &f.out_len), C4G_OK);
        assert_int_equal(f.out_len, C4G_CYCLIC_SIZE(20));
    }
    th_ctrl_packet(&p, 13, 20, C4G_MODE_SVR_RESTART);
    assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
    assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
    assert_int_equal(c4g_session_reply_neutral(&f.s, f.out, sizeof f.out, &f.out_len), C4G_OK);
    /* after 506 only the session's own init is taken: a 6-axis one refuses the session */
    assert_int_equal(feed(&f, th_fig, sizeof th_fig), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_INIT_CONFLICT);
    assert_int_equal(f.s.phase, C4G_PHASE_REFUSED);
    assert_int_equal(f.s.map.n_axes, 20);
    /* the controller gives up; its cold restart with 6 axes is a new start-up */
    {
        uint32_t ev = 0U;
        assert_int_equal(c4g_session_poll(&f.s, f.t + 1001 * MS, &ev), C4G_OK);
        assert_int_equal(ev, C4G_EV_LOST);
    }
    f.t += 1001 * MS;
    th_ctrl_packet(&p, 1, 6, C4G_MODE_0);
    assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
    assert_int_equal(feed(&f, b, len), C4G_RX_SYNC);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    assert_int_equal(feed(&f, th_fig, sizeof th_fig), C4G_RX_INIT); /* 6 axes */
    assert_int_equal(f.s.map.n_axes, 6);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    for (k = 0; k < 2; k++) { /* the post-init syncs */
        th_ctrl_packet(&p, 11 + (int32_t)k, 6, C4G_MODE_0);
        assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
        assert_int_equal(feed(&f, b, len), C4G_RX_SYNC);
        assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    }
    for (k = 2; k < 4; k++) {
        static const uint8_t zero[14 * sizeof(c4g_ctrl_axis_t)];
        th_ctrl_packet(&p, 11 + (int32_t)k, 6, C4G_MODE_0);
        assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
        assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
        assert_memory_equal(&f.r.pkt->ax[6], zero, sizeof zero);
        assert_int_equal(c4g_session_reply_neutral(&f.s, f.out, sizeof f.out, &f.out_len), C4G_OK);
        assert_int_equal(f.out_len, 228);
    }
}

static void test_handshake_plus_one(void **state)
{
    fx_t f;
    int32_t num;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    for (num = 13; num < 1013; num++) {
        cyclic(&f, num, 0);
        assert_int_equal(th_get_u32(f.out), (uint32_t)num + 1);
        assert_int_equal(th_get_u32(&f.out[4]), 0);     /* INFPAR 0 */
        assert_int_equal(th_get_u32(&f.out[12]), 0);    /* mode echoed */
    }
    assert_true(f.r.events == 0);
    assert_int_equal(f.s.counters.cyclic, 1000);
    assert_int_equal(f.s.counters.tx, 9 + 1 + 2 + 1000);
    assert_int_equal(f.s.counters.rx, 9 + 1 + 2 + 2 + 1000); /* + the 2 stale syncs */
    assert_int_equal(f.s.counters.gaps, 0);
    assert_int_equal(f.s.counters.malformed_total, 0);
}

static void test_handshake_echo(void **state)
{
    fx_t f;
    (void)state;
    cold_start(&f, C4G_NUM_ECHO);
    cyclic(&f, 13, 10);
    assert_int_equal(th_get_u32(f.out), 13);
    assert_int_equal(th_get_u32(&f.out[12]), 10);
    /* mode 10: D1 copied back (1.0f for axis 0) */
    assert_memory_equal(&f.out[16], "\x00\x00\x80\x3f", 4);
}

static void test_num_wrap(void **state)
{
    fx_t f;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    f.s.priv.last_num = 0x7FFD;
    cyclic(&f, 0x7FFE, 0);
    assert_int_equal(th_get_u32(f.out), 0x7FFF);
    cyclic(&f, 0x7FFF, 0);
    assert_int_equal(th_get_u32(f.out), 1);          /* field library: wraps to 1 */
    cyclic(&f, 0, 0);                                 /* SMP+ wraps to 0: no gap */
    assert_int_equal(th_get_u32(f.out), 1);
    assert_int_equal(f.s.counters.gaps, 0);
    assert_int_equal(f.s.counters.out_of_order, 0);
}

static void test_gaps_duplicates_reorder(void **state)
{
    fx_t f;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, 0);
    cyclic(&f, 16, 0);                     /* 14, 15 never seen */
    assert_true(f.r.events & C4G_EV_GAP);
    assert_int_equal(f.s.counters.gaps, 1);
    assert_int_equal(f.s.counters.missed, 2);
    {   /* a copy and an older packet: counted, never delivered, never answered */
        uint8_t b[732];
        size_t len = th_ctrl_bytes(b, sizeof b, 16, 6, 0);
        assert_int_equal(feed(&f, b, len), C4G_RX_DROPPED);
        assert_true(f.r.events & C4G_EV_DUPLICATE);
        assert_null(f.r.pkt);
        assert_int_equal(f.s.counters.duplicates, 1);
        assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len),
                         C4G_ERR_STATE);
        len = th_ctrl_bytes(b, sizeof b, 15, 6, C4G_MODE_FOLLOW_ERROR);
        assert_int_equal(feed(&f, b, len), C4G_RX_DROPPED);
        assert_true(f.r.events & C4G_EV_OUT_OF_ORDER);
        assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len),
                         C4G_ERR_STATE);
        assert_int_equal(f.s.priv.last_num, 16);
        assert_int_equal(f.s.priv.rx[f.s.priv.cur].num, 16); /* the newest packet stays the current one */
    }
    cyclic(&f, 17, 0);
    assert_int_equal(f.r.events, 0);
    assert_int_equal(f.s.counters.out_of_order, 1);
}

static void test_malformed_counted_not_answered(void **state)
{
    fx_t f;
    uint8_t b[732];
    size_t len;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, 0);
    len = th_ctrl_bytes(b, sizeof b, 14, 6, 0);
    assert_int_equal(feed(&f, b, len - 1), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_MALFORMED);
    assert_int_equal(f.r.diag.field, C4G_FIELD_LENGTH);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_ERR_STATE);
    len = th_ctrl_bytes(b, sizeof b, 14, 5, 0);     /* valid packet, wrong axis count */
    assert_int_equal(feed(&f, b, len), C4G_RX_DROPPED);
    len = th_ctrl_bytes(b, sizeof b, 14, 6, 0);
    th_put_u32(&b[12 + 36], 4242);
    assert_int_equal(feed(&f, b, len), C4G_RX_DROPPED);
    assert_int_equal(f.r.diag.axis, 1);
    th_put_u32(&b[12 + 36], 0);
    th_put_u32(&b[12 + 36 + 8], 0x7FC00000u);
    assert_int_equal(feed(&f, b, len), C4G_RX_DROPPED);
    th_put_u32(&b[12 + 36 + 8], 0);
    th_put_u32(b, 0x9000);
    assert_int_equal(feed(&f, b, len), C4G_RX_DROPPED);
    assert_int_equal(feed(&f, b, 0), C4G_RX_DROPPED);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_LENGTH], 3);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_MODE], 1);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_NONFINITE], 1);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_NUM], 1);
    assert_int_equal(f.s.counters.malformed_total, 6);
    cyclic(&f, 14, 0);                        /* the session goes on */
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);
}

static void test_bad_init_rejected(void **state)
{
    fx_t f;
    uint8_t b[1200];
    (void)state;
    assert_int_equal(c4g_session_init(&f.s, NULL), C4G_OK);
    f.t = 0;
    memcpy(b, th_fig, sizeof b);
    th_put_u32(b, 9);   /* init whose NUM is not 10 */
    assert_int_equal(feed(&f, b, sizeof b), C4G_RX_DROPPED);
    assert_int_equal(f.r.diag.field, C4G_FIELD_NUM);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_NUM], 1);
    memcpy(b, th_fig, sizeof b);
    th_put_u32(&b[12], 0);
    assert_int_equal(feed(&f, b, sizeof b), C4G_RX_DROPPED);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_INIT], 1);
    assert_int_equal(f.s.phase, C4G_PHASE_WAIT_INIT);
    /* short sync packets */
    assert_int_equal(feed(&f, b, 3), C4G_RX_DROPPED);
    th_put_u32(b, 0x8000);
    assert_int_equal(feed(&f, b, 48), C4G_RX_DROPPED);
    th_put_u32(b, 0xFFFFFFFFu);
    assert_int_equal(feed(&f, b, 48), C4G_RX_DROPPED);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_NUM], 3);
    /* a sync packet has a cyclic packet's shape: no other size, no NaN echoed, no unknown
     * mode, and never a 732-byte answer to a few bytes */
    memset(b, 0, sizeof b);
    th_put_u32(b, 3);
    assert_int_equal(feed(&f, b, 1000), C4G_RX_DROPPED);
    assert_int_equal(feed(&f, b, 4), C4G_RX_DROPPED);
    assert_int_equal(feed(&f, b, 47), C4G_RX_DROPPED);
    th_put_u32(&b[16], 0x7FC00000u);
    assert_int_equal(feed(&f, b, 48), C4G_RX_DROPPED);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_NONFINITE], 1);
    th_put_u32(&b[16], 0);
    th_put_u32(&b[12], 4242);
    assert_int_equal(feed(&f, b, 48), C4G_RX_DROPPED);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_MODE], 1);
    th_put_u32(&b[12], 0);
    th_put_u32(&b[20], 0x11111111u);
    assert_int_equal(feed(&f, b, 732), C4G_RX_SYNC);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, 731, &f.out_len), C4G_ERR_CAPACITY);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    assert_int_equal(f.out_len, 732);
    assert_int_equal(th_get_u32(&f.out[20]), 0x11111111u);
}

static void test_restart_506(void **state)
{
    fx_t f;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, 0);
    cyclic(&f, 14, C4G_MODE_SVR_RESTART);
    assert_true(f.r.events & C4G_EV_RESTART);
    /* client restart: the init packet comes first, no sync before or after */
    assert_int_equal(feed(&f, th_fig, sizeof th_fig), C4G_RX_INIT);
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    assert_int_equal(th_get_u32(f.out), 11);
    cyclic(&f, 11, 0);
    assert_int_equal(f.s.counters.init, 2);
    assert_int_equal(f.s.counters.gaps, 0);
}

static void test_restart_then_cold_sync(void **state)
{
    fx_t f;
    uint8_t b[732];
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, C4G_MODE_SVR_RESTART);
    /* ... but the controller went silent and was then cold-restarted: a new start-up,
     * with its post-init syncs (the pending 506 belonged to the old session) */
    {
        uint32_t ev = 0;
        assert_int_equal(c4g_session_poll(&f.s, f.t + 1001 * MS, &ev), C4G_OK);
        assert_int_equal(ev, C4G_EV_LOST);
        f.t += 1001 * MS;
    }
    sync_packet(b, 1);
    assert_int_equal(feed(&f, b, sizeof b), C4G_RX_SYNC);
    assert_int_equal(feed(&f, th_fig, sizeof th_fig), C4G_RX_INIT);
    assert_int_equal(f.s.phase, C4G_PHASE_POST_SYNC); /* a cold start: the 506 is forgotten */
}

static void test_other_special_modes_pass(void **state)
{
    fx_t f;
    static const int32_t modes[] = {C4G_MODE_FREEZING_A, C4G_MODE_DRIVING_ON, C4G_MODE_DRIVE_OFF,
                                    C4G_MODE_FOLLOW_ERROR};
    unsigned i;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    for (i = 0; i < 4; i++) {
        cyclic(&f, 13 + (int32_t)i, modes[i]);
        assert_int_equal(f.r.events & (C4G_EV_END | C4G_EV_RESTART | C4G_EV_FREEZE_IN), 0);
        assert_int_equal(th_get_u32(&f.out[12]), (uint32_t)modes[i]);   /* echoed */
    }
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);
}

static void test_init_without_sync(void **state)
{
    fx_t f;
    (void)state;
    assert_int_equal(c4g_session_init(&f.s, NULL), C4G_OK);
    f.t = 0;
    assert_int_equal(feed(&f, th_fig, sizeof th_fig), C4G_RX_INIT);
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, 1199, &f.out_len), C4G_ERR_CAPACITY);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    cyclic(&f, 11, 0);
    assert_true(f.r.events & C4G_EV_CYCLIC_START);
}

static void test_end_504(void **state)
{
    fx_t f;
    uint8_t b[732];
    size_t len;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, C4G_MODE_EXIT_OPEN);       /* the 504 packet itself is answered */
    assert_true(f.r.events & C4G_EV_END);
    assert_int_equal(f.s.phase, C4G_PHASE_ENDED);
    len = th_ctrl_bytes(b, sizeof b, 14, 6, 0);
    assert_int_equal(c4g_session_rx(&f.s, b, len, f.t, &f.r), C4G_ERR_ENDED);
}

/* A silence is an event, not the end: past 10 periods it is reported once, the session
 * goes on, and the next packet reports how long it lasted. Past 1 s the controller is lost. */
static void test_silence_lost_and_passive_freezing(void **state)
{
    fx_t f;
    uint32_t ev = 0;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, 0);
    assert_int_equal(f.s.silence_ns, 20 * MS);        /* 10 periods of 2 ms */
    assert_int_equal(f.s.lost_timeout_ns, 1000 * MS); /* the field library's 1 s */
    assert_int_equal(c4g_session_poll(&f.s, f.t + 20 * MS, &ev), C4G_OK);
    assert_int_equal(ev, 0);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 20 * MS + 1, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_SILENCE);
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);    /* the session goes on */
    assert_int_equal(c4g_session_poll(&f.s, f.t + 500 * MS, &ev), C4G_OK);
    assert_int_equal(ev, 0);                          /* reported once */
    f.t += 998 * MS;                                  /* feed() adds 2 ms: 1000 ms of silence */
    cyclic(&f, 14, 0);                                /* the controller came back */
    assert_true(f.r.events & C4G_EV_RESUMED);
    assert_int_equal(f.r.silence_ns, 1000 * MS);
    assert_int_equal(f.s.counters.silences, 1);
    assert_int_equal(f.s.counters.longest_silence_ns, 1000 * MS);
    assert_int_equal(f.s.counters.lost_events, 0);
    cyclic(&f, 15, 0);
    assert_int_equal(f.r.events & C4G_EV_RESUMED, 0);
    /* past the loss timeout the session is over, reported once */
    assert_int_equal(c4g_session_poll(&f.s, f.t + 1000 * MS + 1, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_LOST);
    assert_int_equal(f.s.phase, C4G_PHASE_LOST);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 2000 * MS, &ev), C4G_OK);
    assert_int_equal(ev, 0);
    f.t += 3000 * MS;
    cyclic(&f, 16, 0);                                /* the same controller, NUM goes on */
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);
    assert_true(f.r.events & C4G_EV_RESUMED);
    assert_int_equal(f.s.counters.lost_events, 1);
    /* passive freezing suspends the checks */
    cyclic(&f, 17, C4G_MODE_FREEZING_P_IN);
    assert_true(f.r.events & C4G_EV_FREEZE_IN);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 5000 * MS, &ev), C4G_OK);
    assert_int_equal(ev, 0);
    f.t += 5000 * MS;
    cyclic(&f, 18, C4G_MODE_FREEZING_P_OUT);
    assert_true(f.r.events & C4G_EV_FREEZE_OUT);
    assert_int_equal(f.r.events & (C4G_EV_LOST | C4G_EV_RESUMED), 0);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 21 * MS, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_SILENCE);
}

static void test_active_freezing(void **state)
{
    fx_t f;
    uint8_t b[732];
    c4g_pc_packet_t tx;
    uint32_t ev = 0;
    size_t len;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, 0);
    len = th_ctrl_bytes(b, sizeof b, 14, 6, 0);
    assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
    assert_int_equal(c4g_pc_reply_neutral(f.r.pkt, &tx), C4G_OK);
    tx.ax[0].mode = C4G_MODE_FREEZING_A;           /* the PC freezes (manual 15.1) */
    assert_int_equal(c4g_session_reply(&f.s, &tx, f.out, sizeof f.out, &f.out_len), C4G_OK);
    assert_int_equal(f.s.priv.frozen_active, 1);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 3000 * MS, &ev), C4G_OK);
    assert_int_equal(ev, 0);                        /* a long non-real-time pause is fine */
    f.t += 3000 * MS;
    len = th_ctrl_bytes(b, sizeof b, 15, 6, 0);
    assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
    assert_int_equal(f.r.events & C4G_EV_LOST, 0);
    assert_int_equal(c4g_pc_reply_neutral(f.r.pkt, &tx), C4G_OK);
    tx.infpar = c4g_arm_byte_set(0, 0, C4G_EXIT_FROM_OPEN);
    assert_int_equal(c4g_session_reply(&f.s, &tx, f.out, sizeof f.out, &f.out_len), C4G_OK);
    assert_int_equal(f.s.priv.frozen_active, 0);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 21 * MS, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_SILENCE);           /* the check is back on */
}

static void test_lost_then_cold_restart(void **state)
{
    fx_t f;
    uint8_t b[732];
    uint32_t ev;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    cyclic(&f, 13, 0);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 1001 * MS, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_LOST);
    f.t += 1001 * MS;
    sync_packet(b, 1);                                /* NUM 1 does not go on from 13 */
    assert_int_equal(feed(&f, b, sizeof b), C4G_RX_SYNC);
    assert_int_equal(f.s.phase, C4G_PHASE_WAIT_INIT);
    assert_int_equal(feed(&f, th_fig, sizeof th_fig), C4G_RX_INIT);
    assert_int_equal(f.s.phase, C4G_PHASE_POST_SYNC);
}

static void test_drives_event(void **state)
{
    fx_t f;
    uint8_t b[732];
    size_t len;
    (void)state;
    cold_start(&f, C4G_NUM_PLUS_ONE);
    len = th_ctrl_bytes(b, sizeof b, 13, 6, 0);
    th_put_u32(&b[4], 0x00000005u);
    assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
    assert_true(f.r.events & C4G_EV_DRIVES);
    assert_int_equal(f.s.drives, 1);
    th_put_u32(b, 14);
    assert_int_equal(feed(&f, b, len), C4G_RX_CYCLIC);
    assert_int_equal(f.r.events & C4G_EV_DRIVES, 0);
}

static void test_timing(void **state)
{
    c4g_session_t s;
    c4g_rx_result_t r;
    c4g_timing_t t;
    uint8_t b[732], out[732];
    size_t len, n;
    c4g_pc_packet_t tx;
    static const uint64_t gaps_us[] = {2000, 1900, 2300, 2000};
    uint64_t now = 5 * MS;
    unsigned i;
    (void)state;
    assert_int_equal(c4g_session_init(&s, NULL), C4G_OK);
    assert_int_equal(c4g_session_rx(&s, th_fig, sizeof th_fig, now, &r), C4G_OK);
    assert_int_equal(c4g_session_reply(&s, NULL, out, sizeof out + 0, &n), C4G_ERR_CAPACITY);
    for (i = 0; i < 5; i++) {
        if (i > 0) {
            now += gaps_us[i - 1] * 1000;
        }
        len = th_ctrl_bytes(b, sizeof b, 11 + (int32_t)i, 6, 0);
        assert_int_equal(c4g_session_rx(&s, b, len, now, &r), C4G_OK);
        assert_int_equal(c4g_session_sent(&s, now), C4G_ERR_STATE);   /* not answered yet */
        assert_int_equal(c4g_pc_reply_neutral(r.pkt, &tx), C4G_OK);
        assert_int_equal(c4g_session_reply(&s, &tx, out, sizeof out, &n), C4G_OK);
        assert_int_equal(c4g_session_sent(&s, now + 50000 + 10000 * i), C4G_OK);
        assert_int_equal(c4g_session_sent(&s, now), C4G_ERR_STATE);
    }
    assert_int_equal(c4g_session_timing(&s, &t), C4G_OK);
    assert_int_equal(t.nominal_period_ns, 2000000);
    assert_int_equal(t.samples_inter, 4);
    assert_int_equal(t.samples_cycle, 5);
    assert_int_equal(t.min_inter_ns, 1900000);
    assert_int_equal(t.max_inter_ns, 2300000);
    assert_int_equal(t.min_jitter_ns, -100000);
    assert_int_equal(t.max_jitter_ns, 300000);
    assert_float_equal(t.min_jitter_pct, -5.0, 1e-9);
    assert_float_equal(t.max_jitter_pct, 15.0, 1e-9);
    assert_int_equal(t.worst_cycle_ns, 90000);
    assert_int_equal(t.last_cycle_ns, 90000);
}

static void test_api_misuse(void **state)
{
    c4g_session_t s;
    c4g_session_config_t cfg;
    c4g_rx_result_t r;
    c4g_pc_packet_t tx;
    uint8_t out[732], b[732];
    size_t n, len;
    uint32_t ev;
    c4g_timing_t t;
    (void)state;
    assert_int_equal(c4g_session_config_default(NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_session_init(NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_session_config_default(&cfg), C4G_OK);
    cfg.num_policy = (c4g_num_policy_t)7;
    assert_int_equal(c4g_session_init(&s, &cfg), C4G_ERR_ARG);
    cfg.num_policy = C4G_NUM_ECHO;
    cfg.post_init_sync = 1000;
    assert_int_equal(c4g_session_init(&s, &cfg), C4G_ERR_ARG);
    cfg.post_init_sync = 0;
    cfg.lost_timeout_ns = 5 * MS;
    assert_int_equal(c4g_session_init(&s, &cfg), C4G_OK);
    assert_int_equal(c4g_session_rx(NULL, b, 1, 0, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_session_rx(&s, NULL, 1, 0, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_session_rx(&s, b, 1, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_session_reply(NULL, NULL, out, sizeof out, &n), C4G_ERR_NULL);
    assert_int_equal(c4g_session_reply(&s, NULL, NULL, sizeof out, &n), C4G_ERR_NULL);
    assert_int_equal(c4g_session_reply(&s, NULL, out, sizeof out, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_session_sent(NULL, 0), C4G_ERR_NULL);
    assert_int_equal(c4g_session_poll(NULL, 0, &ev), C4G_ERR_NULL);
    assert_int_equal(c4g_session_poll(&s, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_session_timing(NULL, &t), C4G_ERR_NULL);
    assert_int_equal(c4g_session_timing(&s, &t), C4G_OK);       /* before any init */
    assert_int_equal(t.nominal_period_ns, 0);
    assert_int_equal(t.max_jitter_ns, 0);
    assert_int_equal(c4g_session_rx(&s, NULL, 0, 0, &r), C4G_OK);   /* empty datagram */
    assert_int_equal(r.kind, C4G_RX_DROPPED);
    assert_int_equal(c4g_session_timing(&s, NULL), C4G_ERR_NULL);
    /* init with post_init_sync = 0 even after syncs; explicit loss timeout */
    sync_packet(b, 1);
    assert_int_equal(c4g_session_rx(&s, b, sizeof b, 0, &r), C4G_OK);
    assert_int_equal(c4g_session_reply(&s, NULL, out, sizeof out, &n), C4G_OK);
    assert_int_equal(c4g_session_rx(&s, th_fig, sizeof th_fig, 1, &r), C4G_OK);
    assert_int_equal(s.phase, C4G_PHASE_CYCLIC);
    assert_int_equal(s.lost_timeout_ns, 5 * MS);
    len = th_ctrl_bytes(b, sizeof b, 11, 6, 0);
    assert_int_equal(c4g_session_rx(&s, b, len, 2, &r), C4G_OK);
    assert_int_equal(c4g_session_reply(&s, NULL, out, sizeof out, &n), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_reply_neutral(r.pkt, &tx), C4G_OK);
    tx.n_axes = 5;
    assert_int_equal(c4g_session_reply(&s, &tx, out, sizeof out, &n), C4G_ERR_AXES);
    tx.n_axes = 6;
    tx.ax[0].target_pos = 0.0f / 0.0f;
    assert_int_equal(c4g_session_reply(&s, &tx, out, sizeof out, &n), C4G_ERR_NONFINITE);
    tx.ax[0].target_pos = 0.0f;
    assert_int_equal(c4g_session_reply(&s, &tx, out, sizeof out, &n), C4G_OK);
    assert_int_equal(th_get_u32(out), 11);          /* echo policy */
    assert_int_equal(c4g_session_reply(&s, &tx, out, sizeof out, &n), C4G_ERR_STATE);
    /* timing with no samples: zeros */
    assert_int_equal(c4g_session_timing(&s, &t), C4G_OK);
    assert_int_equal(t.samples_inter, 0);
    assert_int_equal(t.min_jitter_ns, 0);
    /* loss detected inside rx when poll was never called */
    len = th_ctrl_bytes(b, sizeof b, 12, 6, 0);
    assert_int_equal(c4g_session_rx(&s, b, len, 2 + 6 * MS, &r), C4G_OK);
    assert_true(r.events & C4G_EV_LOST);
    assert_int_equal(r.kind, C4G_RX_CYCLIC);
    /* time going backwards never declares a loss */
    assert_int_equal(c4g_session_poll(&s, 0, &ev), C4G_OK);
    assert_int_equal(ev, 0);
}


/* ---------------------------------------------------------------- trust: endpoints */

static c4g_endpoint_t ep(uint8_t last, uint16_t port)
{
    c4g_endpoint_t e;
    memset(&e, 0, sizeof e);
    e.addr[0] = 127;
    e.addr[3] = last;
    e.addr_len = 4;
    e.port = port;
    return e;
}

static c4g_rx_kind_t feed_from(fx_t *f, const uint8_t *buf, size_t len, const c4g_endpoint_t *e)
{
    f->t += 2 * MS;
    assert_int_equal(c4g_session_rx_from(&f->s, buf, len, f->t, e, &f->r), C4G_OK);
    return f->r.kind;
}

/* Cold start from endpoint @p e. */
static void cold_start_from(fx_t *f, const c4g_endpoint_t *e)
{
    uint8_t b[732];
    int32_t num;
    assert_int_equal(c4g_session_init(&f->s, NULL), C4G_OK);
    f->t = 1000 * MS;
    for (num = 1; num <= 9; num++) {
        sync_packet(b, num);
        assert_int_equal(feed_from(f, b, sizeof b, e), C4G_RX_SYNC);
        assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
    }
    assert_int_equal(feed_from(f, th_fig, sizeof th_fig, e), C4G_RX_INIT);
    assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
    for (num = 11; num <= 12; num++) {
        sync_packet(b, num);
        assert_int_equal(feed_from(f, b, sizeof b, e), C4G_RX_SYNC);
        assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
    }
    assert_int_equal(f->s.phase, C4G_PHASE_CYCLIC);
}

/* The controller's cold start into an existing (lost) session. */
static void cold_start_from_keep(fx_t *f, const c4g_endpoint_t *e)
{
    uint8_t b[732];
    int32_t num;
    for (num = 1; num <= 9; num++) {
        sync_packet(b, num);
        assert_int_equal(feed_from(f, b, sizeof b, e), C4G_RX_SYNC);
        assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
    }
    assert_int_equal(feed_from(f, th_fig, sizeof th_fig, e), C4G_RX_INIT);
    for (num = 11; num <= 12; num++) {
        sync_packet(b, num);
        assert_int_equal(feed_from(f, b, sizeof b, e), C4G_RX_SYNC);
    }
    assert_int_equal(f->s.phase, C4G_PHASE_CYCLIC);
}

static void cyclic_from(fx_t *f, int32_t num, int32_t mode, const c4g_endpoint_t *e)
{
    uint8_t b[732];
    size_t len = th_ctrl_bytes(b, sizeof b, num, 6, mode);
    assert_int_equal(feed_from(f, b, len, e), C4G_RX_CYCLIC);
}

static void expect_foreign(fx_t *f, const uint8_t *b, size_t len, const c4g_endpoint_t *e,
                           c4g_foreign_t shape)
{
    const uint64_t before = f->s.counters.foreign[shape];
    const c4g_phase_t phase = f->s.phase;
    assert_int_equal(feed_from(f, b, len, e), C4G_RX_DROPPED);
    assert_true(f->r.events & C4G_EV_FOREIGN);
    assert_null(f->r.pkt);
    assert_int_equal(f->s.counters.foreign[shape], before + 1);
    assert_int_equal(f->s.phase, phase);
    assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len),
                     C4G_ERR_STATE); /* never answered */
}

static void test_endpoint_lock(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600), other_port = ep(1, 3601), other_addr = ep(2, 3600);
    c4g_endpoint_t bad = ctl;
    uint8_t b[1200];
    size_t len;
    (void)state;
    assert_int_equal(c4g_session_init(&f.s, NULL), C4G_OK);
    assert_int_equal(c4g_session_is_peer(&f.s, &other_port), 1); /* nobody locked yet */
    cold_start_from(&f, &ctl);
    assert_int_equal(f.s.peer_locked, 1);
    assert_int_equal(c4g_session_is_peer(&f.s, &ctl), 1);
    assert_int_equal(c4g_session_is_peer(&f.s, &other_port), 0);
    assert_int_equal(c4g_session_is_peer(&f.s, &other_addr), 0);
    assert_int_equal(c4g_session_is_peer(&f.s, NULL), 0);
    assert_int_equal(c4g_session_is_peer(NULL, &ctl), 0);
    cyclic_from(&f, 13, 0, &ctl);
    /* forged init (AzLim 1e6, FollowError 0), 504, 508, unknown mode, zero flood, 4 bytes */
    memcpy(b, th_fig, sizeof b);
    th_put_u32(&b[548], 0x49742400u); /* 1e6 */
    th_put_u32(&b[1040], 0);
    expect_foreign(&f, b, sizeof b, &other_port, C4G_FOREIGN_INIT);
    assert_true(f.s.init.az_lim[0][0] < 100.0f);
    len = th_ctrl_bytes(b, sizeof b, 14, 6, C4G_MODE_EXIT_OPEN);
    expect_foreign(&f, b, len, &other_port, C4G_FOREIGN_CYCLIC);
    len = th_ctrl_bytes(b, sizeof b, 9, 6, C4G_MODE_FOLLOW_ERROR);
    expect_foreign(&f, b, len, &other_addr, C4G_FOREIGN_CYCLIC);
    len = th_ctrl_bytes(b, sizeof b, 14, 6, 0);
    th_put_u32(&b[12], 4242); /* an unknown mode */
    expect_foreign(&f, b, len, &other_port, C4G_FOREIGN_CYCLIC);
    memset(b, 0, 228);
    expect_foreign(&f, b, 228, &other_port, C4G_FOREIGN_CYCLIC);
    expect_foreign(&f, b, 4, &other_port, C4G_FOREIGN_OTHER);
    assert_int_equal(f.s.counters.foreign_total, 6);
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);
    cyclic_from(&f, 14, 0, &ctl); /* the controller's session goes on */
    assert_int_equal(f.s.counters.init, 1);
    /* an endpoint with an impossible address length is a caller error */
    bad.addr_len = 17;
    assert_int_equal(c4g_session_rx_from(&f.s, b, 4, f.t, &bad, &f.r), C4G_ERR_ARG);
    assert_int_equal(c4g_session_is_peer(&f.s, &bad), 0);
}

static void test_init_only_at_start_up(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600);
    uint8_t b[1200];
    (void)state;
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, 0, &ctl);
    /* from the controller's own endpoint, mid-session: refused, reported, not answered */
    memcpy(b, th_fig, sizeof b);
    th_put_u32(&b[548], 0x49742400u);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_MALFORMED);
    assert_int_equal(f.r.diag.status, C4G_ERR_STATE);
    assert_int_equal(f.r.diag.value, 10);
    assert_int_equal(f.s.counters.malformed[C4G_MAL_PHASE], 1);
    assert_true(f.s.init.az_lim[0][0] < 100.0f);
    /* ... and in the post-init synchronization phase too */
    {
        fx_t g;
        uint8_t s1[732];
        int32_t num;
        assert_int_equal(c4g_session_init(&g.s, NULL), C4G_OK);
        g.t = 0;
        for (num = 1; num <= 9; num++) {
            sync_packet(s1, num);
            assert_int_equal(feed_from(&g, s1, sizeof s1, &ctl), C4G_RX_SYNC);
        }
        assert_int_equal(feed_from(&g, th_fig, sizeof th_fig, &ctl), C4G_RX_INIT);
        /* the same bytes again: a duplicate, not answered (a different one: see
         * test_second_init_conflict) */
        assert_int_equal(feed_from(&g, th_fig, sizeof th_fig, &ctl), C4G_RX_DROPPED);
        assert_true(g.r.events & C4G_EV_DUPLICATE);
        assert_int_equal(g.s.counters.duplicates, 1);
        assert_int_equal(g.s.phase, C4G_PHASE_POST_SYNC);
    }
    /* after 506 the new init is taken */
    cyclic_from(&f, 14, C4G_MODE_SVR_RESTART, &ctl);
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &ctl), C4G_RX_INIT);
    assert_int_equal(f.s.counters.init, 2);
}

/* A lost controller: a new start-up is served from its first synchronization packet, from
 * whatever endpoint, and the session locks to it; the old endpoint is then foreign. */
static void test_lost_restart_new_endpoint(void **state)
{
    fx_t f;
    const c4g_endpoint_t old = ep(1, 3600), neu = ep(1, 40000);
    uint8_t b[732];
    size_t len;
    uint32_t ev = 0;
    (void)state;
    cold_start_from(&f, &old);
    cyclic_from(&f, 13, 0, &old);
    /* silent, but not lost yet: another endpoint's start-up is foreign */
    sync_packet(b, 1);
    f.t += 500 * MS;
    expect_foreign(&f, b, sizeof b, &neu, C4G_FOREIGN_CYCLIC);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 1000 * MS, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_LOST);
    f.t += 1000 * MS;
    /* after the loss: an init first from the new endpoint is still foreign */
    expect_foreign(&f, th_fig, sizeof th_fig, &neu, C4G_FOREIGN_INIT);
    /* a malformed start-up from a stranger does not end the lost state and is foreign */
    memset(b, 0, sizeof b);
    th_put_u32(&b[16], 0x7F800000u);
    {
        const uint64_t mal = f.s.counters.malformed_total;
        expect_foreign(&f, b, 48, &neu, C4G_FOREIGN_CYCLIC);
        assert_int_equal(f.s.phase, C4G_PHASE_LOST);
        assert_int_equal(f.s.counters.malformed_total, mal);
        /* the same bytes from the lost controller itself are its malformed datagram */
        assert_int_equal(feed_from(&f, b, 48, &old), C4G_RX_DROPPED);
        assert_int_equal(f.s.counters.malformed_total, mal + 1U);
        assert_int_equal(f.s.phase, C4G_PHASE_LOST);
    }
    cold_start_from_keep(&f, &neu);
    assert_true(f.s.peer.port == 40000);
    len = th_ctrl_bytes(b, sizeof b, 13, 6, 0);
    expect_foreign(&f, b, len, &old, C4G_FOREIGN_CYCLIC);
    cyclic_from(&f, 13, 0, &neu);
}

/* After a loss, the same controller continuing its NUM sequence is taken back. */
static void test_lost_resume_same_endpoint(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600);
    uint32_t ev = 0;
    (void)state;
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, 0, &ctl);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 1001 * MS, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_LOST);
    f.t += 2000 * MS;
    cyclic_from(&f, 20, 0, &ctl);
    assert_true(f.r.events & C4G_EV_RESUMED);
    assert_int_equal(f.s.phase, C4G_PHASE_CYCLIC);
    assert_int_equal(f.s.counters.longest_silence_ns, 2002 * MS);
}


static void cyclic_from_kind(fx_t *f, int32_t num, const c4g_endpoint_t *e, c4g_rx_kind_t want)
{
    uint8_t b[732];
    size_t len = th_ctrl_bytes(b, sizeof b, num, 6, C4G_MODE_0);
    assert_int_equal(feed_from(f, b, len, e), want);
}

/* Bits of a float as the diagnostics carry them. */
static int64_t f_bits(float f)
{
    uint8_t b[4];
    th_put_f32(b, f);
    return (int64_t)th_get_u32(b);
}

/* The figure 10.1 init with one float of a per-axis block (arm 1) replaced. */
static void init_with(uint8_t *b, uint32_t block, uint32_t axis, float v)
{
    memcpy(b, th_fig, C4G_INIT_SIZE);
    th_put_f32(&b[block + 4U * axis], v);
}

/* 9 syncs from @p e into a fresh session (answered). */
static void nine_syncs(fx_t *f, const c4g_endpoint_t *e)
{
    uint8_t b[732];
    int32_t num;
    assert_int_equal(c4g_session_init(&f->s, NULL), C4G_OK);
    f->t = 1000 * MS;
    for (num = 1; num <= 9; num++) {
        sync_packet(b, num);
        assert_int_equal(feed_from(f, b, sizeof b, e), C4G_RX_SYNC);
        assert_int_equal(c4g_session_reply(&f->s, NULL, f->out, sizeof f->out, &f->out_len), C4G_OK);
    }
}

/* The PC's ceilings: an init packet above them is refused, naming the field, the axis and
 * the value; the configuration itself is checked. */
static void test_init_ceilings(void **state)
{
    fx_t f;
    c4g_session_config_t cfg;
    const c4g_endpoint_t ctl = ep(1, 3600);
    uint8_t b[C4G_INIT_SIZE];
    static const float bad[] = {0.0f, -1.0f};
    uint32_t k;
    (void)state;
    assert_int_equal(c4g_session_config_default(&cfg), C4G_OK);
    assert_true(cfg.az_lim_max == C4G_AZLIM_MAX_DEFAULT);
    assert_true(cfg.follow_error_max == C4G_FOLLOW_ERROR_MAX_DEFAULT);
    for (k = 0; k < 2U; k++) {
        cfg.az_lim_max = bad[k];
        assert_int_equal(c4g_session_init(&f.s, &cfg), C4G_ERR_ARG);
        cfg.az_lim_max = C4G_AZLIM_MAX_DEFAULT;
        cfg.follow_error_max = bad[k];
        assert_int_equal(c4g_session_init(&f.s, &cfg), C4G_ERR_ARG);
        cfg.follow_error_max = C4G_FOLLOW_ERROR_MAX_DEFAULT;
    }
    th_put_u32((uint8_t *)&cfg.az_lim_max, 0x7FC00000u); /* NaN */
    assert_int_equal(c4g_session_init(&f.s, &cfg), C4G_ERR_ARG);
    th_put_u32((uint8_t *)&cfg.az_lim_max, 0x7F800000u); /* inf */
    assert_int_equal(c4g_session_init(&f.s, &cfg), C4G_ERR_ARG);
    /* AzLim 1e6 on axis 3 (the attack's value): refused, the session still waits */
    nine_syncs(&f, &ctl);
    init_with(b, C4G_INIT_OFF_AZLIM, 2, 1e6f);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_MALFORMED);
    assert_int_equal(f.r.diag.status, C4G_ERR_RANGE);
    assert_int_equal(f.r.diag.field, C4G_FIELD_AZLIM);
    assert_int_equal(f.r.diag.arm, 0);
    assert_int_equal(f.r.diag.axis, 2);
    assert_int_equal(f.r.diag.offset, C4G_INIT_OFF_AZLIM + 8U);
    assert_int_equal(f.r.diag.value, f_bits(1e6f));
    assert_int_equal(f.s.counters.malformed[C4G_MAL_CEILING], 1);
    assert_int_equal(f.s.counters.init, 0);
    assert_int_equal(f.s.phase, C4G_PHASE_WAIT_INIT);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_ERR_STATE);
    /* FollowError 60 turns on axis 5 */
    init_with(b, C4G_INIT_OFF_FOLLOWERROR, 4, 60.0f);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
    assert_int_equal(f.r.diag.field, C4G_FIELD_FOLLOWERROR);
    assert_int_equal(f.r.diag.axis, 4);
    assert_int_equal(f.r.diag.value, f_bits(60.0f));
    assert_int_equal(f.s.counters.malformed[C4G_MAL_CEILING], 2);
    /* a value on an axis that is not open is not the controller's limit: accepted */
    init_with(b, C4G_INIT_OFF_AZLIM, 8, 1e6f);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_INIT);
    /* a cell whose ceiling is under figure 10.1's 24.5 A refuses that packet */
    assert_int_equal(c4g_session_config_default(&cfg), C4G_OK);
    cfg.az_lim_max = 20.0f;
    assert_int_equal(c4g_session_init(&f.s, &cfg), C4G_OK);
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &ctl), C4G_RX_DROPPED);
    assert_int_equal(f.r.diag.field, C4G_FIELD_AZLIM);
    assert_int_equal(f.r.diag.axis, 0);
    assert_int_equal(f.r.diag.value, f_bits(24.5f));
    /* FollowError 0 (figure 10.1's axis 6) stays "no threshold": accepted under any ceiling */
    cfg.az_lim_max = 24.5f;
    cfg.follow_error_max = 7.5f;
    assert_int_equal(c4g_session_init(&f.s, &cfg), C4G_OK);
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &ctl), C4G_RX_INIT);
}

/* A ceiling refusal on an arm after axes that are not open: the diagnostic names the arm
 * and the logical axis of the first axis over the ceiling in the packet's order (the
 * session checks the open axes through its axis maps first, then names the refusal). */
static void test_init_ceiling_on_second_arm(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600);
    c4g_init_t in;
    uint8_t b[C4G_INIT_SIZE];
    size_t n = 0;
    uint32_t x;
    (void)state;
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    for (x = 0; x < 10U; x++) {
        in.open_ax[0][x] = C4G_OPEN_AX_NONE;
        in.open_ax[1][x] = (x < 6U) ? (int32_t)x : C4G_OPEN_AX_NONE;
        in.open_mask[1][x] = 0;
        in.az_lim[1][x] = 10.0f;
        in.follow_error[1][x] = 1.0f;
    }
    in.az_lim[1][5] = 1e6f;        /* over the default ceiling, and */
    in.follow_error[1][3] = 60.0f; /* before it in the packet: FollowError comes later */
    in.az_lim[0][0] = 1e6f;        /* not open: no limit of the controller's */
    assert_int_equal(c4g_init_encode(&in, b, sizeof b, &n), C4G_OK);
    memset(&f, 0, sizeof f);
    assert_int_equal(c4g_session_init(&f.s, NULL), C4G_OK);
    f.t = 1000 * MS;
    nine_syncs(&f, &ctl);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
    assert_int_equal(f.r.diag.status, C4G_ERR_RANGE);
    assert_int_equal(f.r.diag.field, C4G_FIELD_FOLLOWERROR);
    assert_int_equal(f.r.diag.arm, 1);
    assert_int_equal(f.r.diag.axis, 3);
    assert_int_equal(f.r.diag.offset, C4G_INIT_OFF_FOLLOWERROR + 40U + 12U);
    assert_int_equal(f.r.diag.value, f_bits(60.0f));
    assert_int_equal(f.s.counters.malformed[C4G_MAL_CEILING], 1);
    /* the FollowError within its ceiling: the AzLim of axis 5 is named */
    in.follow_error[1][3] = 1.0f;
    assert_int_equal(c4g_init_encode(&in, b, sizeof b, &n), C4G_OK);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
    assert_int_equal(f.r.diag.field, C4G_FIELD_AZLIM);
    assert_int_equal(f.r.diag.arm, 1);
    assert_int_equal(f.r.diag.axis, 5);
    assert_int_equal(f.r.diag.offset, C4G_INIT_OFF_AZLIM + 40U + 20U);
    /* within every ceiling: accepted, the maps on arm 1 */
    in.az_lim[1][5] = 10.0f;
    assert_int_equal(c4g_init_encode(&in, b, sizeof b, &n), C4G_OK);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_INIT);
    assert_int_equal(f.s.map.n_axes, 6);
    assert_int_equal(f.s.map.arm_of[5], 1);
    assert_int_equal(f.s.map.logical_of[5], 5);
}

/* An init packet injected between the controller's last sync and its own init (a sender
 * that spoofs the controller's address and port): the real one differs, and both are
 * refused. Either order. Then nothing is answered until the controller gives up. */
static void test_second_init_conflict(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600);
    uint8_t forged[C4G_INIT_SIZE], b[732];
    uint32_t order, ev = 0;
    (void)state;
    init_with(forged, C4G_INIT_OFF_AZLIM, 1, 150.0f); /* under the default ceiling */
    for (order = 0; order < 2U; order++) {
        const uint8_t *first = (order == 0U) ? forged : th_fig;
        const uint8_t *second = (order == 0U) ? th_fig : forged;
        nine_syncs(&f, &ctl);
        assert_int_equal(feed_from(&f, first, C4G_INIT_SIZE, &ctl), C4G_RX_INIT);
        assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
        assert_int_equal(feed_from(&f, second, C4G_INIT_SIZE, &ctl), C4G_RX_DROPPED);
        assert_true(f.r.events & C4G_EV_INIT_CONFLICT);
        assert_int_equal(f.r.diag.field, C4G_FIELD_AZLIM);
        assert_int_equal(f.r.diag.arm, 0);
        assert_int_equal(f.r.diag.axis, 1);
        assert_int_equal(f.r.diag.offset, C4G_INIT_OFF_AZLIM + 4U);
        assert_int_equal(f.r.diag.value, f_bits(order == 0U ? 24.5f : 150.0f));
        assert_int_equal(f.s.counters.init_conflicts, 1);
        assert_int_equal(f.s.phase, C4G_PHASE_REFUSED);
        assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len),
                         C4G_ERR_STATE);
        /* the controller's post-init syncs and cyclic packets: dropped, never answered */
        sync_packet(b, 11);
        assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
        assert_true(f.r.events & C4G_EV_REFUSED);
        assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len),
                         C4G_ERR_STATE);
        cyclic_from_kind(&f, 13, &ctl, C4G_RX_DROPPED);
        assert_int_equal(f.s.counters.refused, 2);
        assert_int_equal(f.s.counters.cyclic, 0);
        /* silent for the loss timeout: the phase is LOST, a new start-up is served */
        assert_int_equal(c4g_session_poll(&f.s, f.t + 500 * MS, &ev), C4G_OK);
        assert_int_equal(ev, 0U);
        assert_int_equal(c4g_session_poll(&f.s, f.t + 1001 * MS, &ev), C4G_OK);
        assert_int_equal(ev, C4G_EV_LOST);
        f.t += 1001 * MS;
        /* a cyclic packet continuing the NUM does not resume the refused session's init:
         * it can only open a new start-up (a sync, answered as such) */
        cyclic_from_kind(&f, 14, &ctl, C4G_RX_SYNC);
        assert_int_equal(f.s.phase, C4G_PHASE_WAIT_INIT);
        assert_int_equal(f.s.counters.cyclic, 0);
        assert_int_equal(f.s.priv.startup_only, 0);
        sync_packet(b, 1);
        assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_SYNC);
        assert_int_equal(f.s.phase, C4G_PHASE_WAIT_INIT);
    }
}

/* After 506 only the session's own init packet is taken; a different one (a spoofed 506
 * and init) refuses the session and leaves its limits as they were. */
static void test_restart_init_must_match(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600);
    uint8_t b[C4G_INIT_SIZE];
    (void)state;
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, 0, &ctl);
    cyclic_from(&f, 14, C4G_MODE_SVR_RESTART, &ctl);
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &ctl), C4G_RX_INIT);
    assert_int_equal(f.s.counters.init, 2);
    cyclic_from(&f, 11, 0, &ctl);
    cyclic_from(&f, 12, C4G_MODE_SVR_RESTART, &ctl);
    init_with(b, C4G_INIT_OFF_FOLLOWERROR, 0, 0.0f); /* the following-error check off */
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_INIT_CONFLICT);
    assert_int_equal(f.r.diag.field, C4G_FIELD_FOLLOWERROR);
    assert_int_equal(f.r.diag.axis, 0);
    assert_int_equal(f.r.diag.value, 0);
    assert_int_equal(f.s.phase, C4G_PHASE_REFUSED);
    assert_true(f.s.init.follow_error[0][0] == 7.5f);
    assert_int_equal(f.s.counters.init, 2);
    /* nor is the genuine one taken afterwards: the session stays refused */
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &ctl), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_REFUSED);
}

/* Sync replies: the field's 732 bytes for the handshake's syncs (9, each may come twice);
 * more are not answered
 * (no amplification of a stream of small datagrams, and no reply the controller could read
 * as a cyclic reply echoing its own data). A start-up silent for the loss timeout starts
 * afresh. */
static void test_sync_reply_bounded(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600);
    uint8_t b[732];
    int32_t num;
    (void)state;
    assert_int_equal(c4g_session_init(&f.s, NULL), C4G_OK);
    f.t = 1000 * MS;
    for (num = 1; num <= 30; num++) {
        const size_t len = th_ctrl_bytes(b, sizeof b, num, 1, C4G_MODE_0); /* 48 bytes */
        assert_int_equal(len, 48U);
        if (num <= (int32_t)C4G_SYNC_REPLY_BUDGET) {
            assert_int_equal(feed_from(&f, b, len, &ctl), C4G_RX_SYNC);
            assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
            assert_int_equal(f.out_len, 732U);
            assert_int_equal((int32_t)th_get_u32(f.out), num + 1);
            assert_memory_equal(&f.out[4], &b[4], 44U);
        } else {
            assert_int_equal(feed_from(&f, b, len, &ctl), C4G_RX_DROPPED);
            assert_true(f.r.events & C4G_EV_SYNC_EXCESS);
            assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len),
                             C4G_ERR_STATE);
        }
    }
    assert_int_equal(f.s.counters.sync_excess, 12);
    assert_int_equal(f.s.counters.sync, 18);
    /* another endpoint cannot take the start-up meanwhile; after the loss timeout without an
     * accepted packet the start-up starts afresh, from whatever endpoint */
    {
        const c4g_endpoint_t other = ep(1, 3700);
        size_t len = th_ctrl_bytes(b, sizeof b, 1, 6, C4G_MODE_0);
        assert_int_equal(f.s.peer_locked, 1);
        f.t += 1001 * MS;
        assert_int_equal(feed_from(&f, b, len, &other), C4G_RX_SYNC);
        assert_int_equal(f.s.peer.port, 3700);
        assert_int_equal(f.s.priv.sync_seen, 1);
        f.t += 1001 * MS;
        assert_int_equal(feed_from(&f, b, len, &ctl), C4G_RX_SYNC);
        assert_int_equal(f.s.peer.port, 3600);
    }
    /* the init and the post-init syncs of the field handshake are as before */
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &ctl), C4G_RX_INIT);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    assert_int_equal(f.out_len, 1200U);
    for (num = 11; num <= 12; num++) {
        const size_t len = th_ctrl_bytes(b, sizeof b, num, 6, C4G_MODE_0);
        assert_int_equal(feed_from(&f, b, len, &ctl), C4G_RX_SYNC);
        assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
        assert_int_equal(f.out_len, 732U);
    }
}

/* With no address filter, a forged sync before the controller's first locks the session;
 * the controller's start-up from another endpoint then contends for it: both refused. */
static void test_contended_startup(void **state)
{
    fx_t f;
    const c4g_endpoint_t forger = ep(9, 3600), ctl = ep(1, 3600);
    uint8_t b[732];
    (void)state;
    assert_int_equal(c4g_session_init(&f.s, NULL), C4G_OK);
    f.t = 1000 * MS;
    sync_packet(b, 1);
    assert_int_equal(feed_from(&f, b, sizeof b, &forger), C4G_RX_SYNC);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_OK);
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_CONTENDED);
    assert_true(f.r.events & C4G_EV_FOREIGN);
    assert_int_equal(f.s.counters.contended, 1);
    assert_int_equal(f.s.phase, C4G_PHASE_REFUSED);
    sync_packet(b, 2);
    assert_int_equal(feed_from(&f, b, sizeof b, &forger), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_REFUSED);
    assert_int_equal(c4g_session_reply(&f.s, NULL, f.out, sizeof f.out, &f.out_len), C4G_ERR_STATE);
    /* an init from the other endpoint during the post-init syncs contends too */
    nine_syncs(&f, &ctl);
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &ctl), C4G_RX_INIT);
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &forger), C4G_RX_DROPPED);
    assert_true(f.r.events & C4G_EV_CONTENDED);
    /* a 4-byte datagram is no start-up packet: foreign, nothing more */
    nine_syncs(&f, &ctl);
    expect_foreign(&f, b, 4, &forger, C4G_FOREIGN_OTHER);
    assert_int_equal(f.s.counters.contended, 0);
    /* once cyclic, another endpoint's sync is foreign only */
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, 0, &ctl);
    sync_packet(b, 1);
    expect_foreign(&f, b, sizeof b, &forger, C4G_FOREIGN_CYCLIC);
    assert_int_equal(f.s.counters.contended, 0);
}

/* A valid start-up from another endpoint after the controller's stall: served, reported. */
static void test_new_peer_after_stall(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600), other = ep(1, 3700);
    uint8_t b[732];
    uint32_t ev = 0;
    (void)state;
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, 0, &ctl);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 1001 * MS, &ev), C4G_OK);
    assert_int_equal(ev, C4G_EV_LOST);
    f.t += 1001 * MS;
    sync_packet(b, 1);
    assert_int_equal(feed_from(&f, b, sizeof b, &other), C4G_RX_SYNC);
    assert_true(f.r.events & C4G_EV_NEW_PEER);
    assert_int_equal(f.s.counters.new_peers, 1);
    assert_int_equal(f.s.peer.port, 3700);
    /* the same endpoint restarting cold is no new peer */
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, 0, &ctl);
    assert_int_equal(c4g_session_poll(&f.s, f.t + 1001 * MS, &ev), C4G_OK);
    f.t += 1001 * MS;
    assert_int_equal(feed_from(&f, b, sizeof b, &ctl), C4G_RX_SYNC);
    assert_false(f.r.events & C4G_EV_NEW_PEER);
    assert_int_equal(f.s.counters.new_peers, 0);
}

/* 504 ends the session either way; in the middle of an operating mode it is reported. */
static void test_end_unexpected(void **state)
{
    fx_t f;
    const c4g_endpoint_t ctl = ep(1, 3600);
    (void)state;
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, C4G_MODE_0, &ctl);
    cyclic_from(&f, 14, C4G_MODE_EXIT_OPEN, &ctl);
    assert_true(f.r.events & C4G_EV_END);
    assert_false(f.r.events & C4G_EV_END_UNEXPECTED);
    assert_int_equal(f.s.phase, C4G_PHASE_ENDED);
    cold_start_from(&f, &ctl);
    cyclic_from(&f, 13, C4G_MODE_0, &ctl);
    cyclic_from(&f, 14, C4G_MODE_9, &ctl);
    cyclic_from(&f, 15, C4G_MODE_EXIT_OPEN, &ctl);
    assert_true(f.r.events & C4G_EV_END);
    assert_true(f.r.events & C4G_EV_END_UNEXPECTED);
    assert_int_equal(f.r.diag.field, C4G_FIELD_SM);
    assert_int_equal(f.r.diag.axis, 0);
    assert_int_equal(f.r.diag.value, C4G_MODE_9);
    assert_int_equal(f.s.counters.end_unexpected, 1);
    assert_int_equal(f.s.phase, C4G_PHASE_ENDED);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_handshake_plus_one),
        cmocka_unit_test(test_handshake_echo),
        cmocka_unit_test(test_num_wrap),
        cmocka_unit_test(test_gaps_duplicates_reorder),
        cmocka_unit_test(test_malformed_counted_not_answered),
        cmocka_unit_test(test_bad_init_rejected),
        cmocka_unit_test(test_restart_506),
        cmocka_unit_test(test_restart_then_cold_sync),
        cmocka_unit_test(test_other_special_modes_pass),
        cmocka_unit_test(test_init_without_sync),
        cmocka_unit_test(test_end_504),
        cmocka_unit_test(test_silence_lost_and_passive_freezing),
        cmocka_unit_test(test_active_freezing),
        cmocka_unit_test(test_lost_then_cold_restart),
        cmocka_unit_test(test_drives_event),
        cmocka_unit_test(test_timing),
        cmocka_unit_test(test_api_misuse),
        cmocka_unit_test(test_endpoint_lock),
        cmocka_unit_test(test_init_only_at_start_up),
        cmocka_unit_test(test_lost_restart_new_endpoint),
        cmocka_unit_test(test_lost_resume_same_endpoint),
        cmocka_unit_test(test_reply_neutral_direct),
        cmocka_unit_test(test_session_neutral_holds),
        cmocka_unit_test(test_special_mode_on_one_axis),
        cmocka_unit_test(test_fewer_axes_after_restart),
        cmocka_unit_test(test_init_ceilings),
        cmocka_unit_test(test_second_init_conflict),
        cmocka_unit_test(test_init_ceiling_on_second_arm),
        cmocka_unit_test(test_restart_init_must_match),
        cmocka_unit_test(test_sync_reply_bounded),
        cmocka_unit_test(test_contended_startup),
        cmocka_unit_test(test_new_peer_after_stall),
        cmocka_unit_test(test_end_unexpected),
    };
    return cmocka_run_group_tests_name("session", tests, th_load_fig, NULL);
}
