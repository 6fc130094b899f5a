/* SPDX-License-Identifier: MIT */
/* The PC-side loop object: handshake, control engine, the safety filter and the neutral
 * fallback on the only reply path. */
#define TH_FIG10_1
#include "test_helpers.h"

#define MS 1000000ULL


typedef struct {
    c4g_loop_t lp;
    c4g_loop_event_t ev;
    uint8_t out[1300];
    size_t out_len;
    uint64_t t;
    c4g_endpoint_t ctl;
} fx_t;

static c4g_rx_kind_t feed_from(fx_t *f, const uint8_t *b, size_t len, const c4g_endpoint_t *e)
{
    f->t += 2 * MS;
    assert_int_equal(c4g_loop_rx(&f->lp, b, len, f->t, e, &f->ev), C4G_OK);
    return f->ev.kind;
}

static void answer(fx_t *f, size_t want_len)
{
    assert_int_equal(c4g_loop_reply(&f->lp, f->out, sizeof f->out, &f->out_len, NULL), C4G_OK);
    assert_int_equal(f->out_len, want_len);
    assert_int_equal(c4g_loop_sent(&f->lp, f->t + 50000U), C4G_OK);
    /* one reply per datagram */
    assert_int_equal(c4g_loop_reply(&f->lp, f->out, sizeof f->out, &f->out_len, NULL), C4G_ERR_STATE);
}

static void cold_start(fx_t *f)
{
    uint8_t b[732];
    int32_t num;
    memset(f, 0, sizeof *f);
    f->ctl.addr_len = 4U;
    f->ctl.addr[0] = 127U;
    f->ctl.addr[3] = 1U;
    f->ctl.port = 3600U;
    assert_int_equal(c4g_loop_init(&f->lp, NULL), C4G_OK);
    f->t = 1000 * MS;
    for (num = 1; num <= 12; num++) {
        if (num == 10) {
            assert_int_equal(feed_from(f, th_fig, sizeof th_fig, &f->ctl), C4G_RX_INIT);
            assert_int_equal(f->lp.engine_ready, 1U);
            answer(f, 1200U);
            continue;
        }
        memset(b, 0, sizeof b);
        th_put_u32(b, (uint32_t)num);
        assert_int_equal(feed_from(f, b, C4G_CYCLIC_SIZE(6U), &f->ctl), C4G_RX_SYNC);
        assert_null(f->ev.cmd);
        answer(f, 732U);
    }
    assert_int_equal(f->lp.session.phase, C4G_PHASE_CYCLIC);
}

/* One cyclic packet, every axis in @p mode, SMP+ target = measured position = @p pos. */
static void cyclic(fx_t *f, int32_t num, int32_t mode, float pos)
{
    uint8_t b[732];
    c4g_ctrl_packet_t p;
    size_t len = 0;
    uint32_t i;
    th_ctrl_packet(&p, num, 6U, mode);
    for (i = 0; i < 6U; i++) {
        p.ax[i].target_pos = pos;
        p.ax[i].actual_pos = pos;
        p.ax[i].target_vel = 0.0f;
    }
    assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
    assert_int_equal(feed_from(f, b, len, &f->ctl), C4G_RX_CYCLIC);
    assert_non_null(f->ev.pkt);
}

static void decode_reply(const fx_t *f, c4g_pc_packet_t *pc)
{
    c4g_diag_t d;
    assert_int_equal(c4g_pc_decode(f->out, f->out_len, 6U, pc, &d), C4G_OK);
}

static void test_handshake_and_mode0(void **state)
{
    fx_t f;
    c4g_pc_packet_t pc;
    (void)state;
    cold_start(&f);
    cyclic(&f, 13, C4G_MODE_0, 1.0f);
    assert_non_null(f.ev.cmd);
    answer(&f, C4G_CYCLIC_SIZE(6U));
    decode_reply(&f, &pc);
    assert_int_equal(pc.num, 14);
    assert_int_equal(pc.ax[0].mode, C4G_MODE_0);
    assert_int_equal(f.lp.counters.neutral_replies, 0U);
}

/* A target past the stroke end: the loop's reply is filtered, whatever the caller wrote. */
static void test_reply_is_filtered(void **state)
{
    fx_t f;
    c4g_pc_packet_t pc;
    c4g_axis_limits_t lim;
    c4g_engine_report_t rep;
    uint32_t i;
    (void)state;
    cold_start(&f);
    memset(&lim, 0, sizeof lim);
    lim.motor_min = 0.9f;
    lim.motor_max = 1.1f;
    assert_int_equal(c4g_engine_set_limits(&f.lp.engine, f.lp.session.map.arm_of[0],
                                        f.lp.session.map.logical_of[0], &lim), C4G_OK);
    cyclic(&f, 13, C4G_MODE_0, 1.0f);
    answer(&f, C4G_CYCLIC_SIZE(6U));
    cyclic(&f, 14, C4G_MODE_4, 1.0f);
    assert_non_null(f.ev.cmd);
    for (i = 0; i < 6U; i++) {
        f.ev.cmd->ax[i].target_pos = 1.0f;
        f.ev.cmd->ax[i].target_vel = 0.0f;
    }
    f.ev.cmd->ax[0].target_pos = 1.5f; /* 0.4 turns past the end */
    assert_int_equal(c4g_loop_reply(&f.lp, f.out, sizeof f.out, &f.out_len, &rep), C4G_OK);
    assert_true(rep.axis_flags[0] & C4G_SF_STROKE);
    decode_reply(&f, &pc);
    assert_true(pc.ax[0].target_pos <= 1.1f);  /* shrunk to the stroke end */
    assert_int_equal(pc.ax[0].mode, C4G_MODE_DRIVE_OFF); /* and the arm stopped */
}

/* No engine for a packet (its init refused by the engine): the fallback holds the
 * reference the controller reports (never 0) and stops the arm the PC moves. */
static void test_neutral_without_engine(void **state)
{
    fx_t f;
    c4g_pc_packet_t pc;
    uint32_t i;
    (void)state;
    cold_start(&f);
    f.lp.engine_ready = 0U;
    cyclic(&f, 13, C4G_MODE_4, 2.5f);
    assert_null(f.ev.cmd);
    answer(&f, C4G_CYCLIC_SIZE(6U));
    decode_reply(&f, &pc);
    assert_int_equal(f.lp.counters.neutral_replies, 1U);
    assert_int_equal(f.lp.counters.fallback_drive_off, 1U);
    for (i = 0; i < 6U; i++) {
        assert_int_equal(pc.ax[i].mode, C4G_MODE_DRIVE_OFF);
        assert_true(pc.ax[i].target_pos == 2.5f); /* was 0.000: "go to 0" */
        assert_true(pc.ax[i].target_vel == 0.0f);
    }
    /* in mode 0 the PC moves nothing: the echo alone, no 505 */
    cyclic(&f, 14, C4G_MODE_0, 2.5f);
    answer(&f, C4G_CYCLIC_SIZE(6U));
    decode_reply(&f, &pc);
    assert_int_equal(f.lp.counters.neutral_replies, 2U);
    assert_int_equal(f.lp.counters.fallback_drive_off, 1U);
    assert_int_equal(pc.ax[0].mode, C4G_MODE_0);
    assert_true(pc.ax[0].target_pos == 0.0f);
}

/* An engine configuration the engine would refuse at every init is refused at once. */
static void test_loop_refuses_bad_engine_config(void **state)
{
    c4g_loop_t lp;
    c4g_loop_config_t cfg;
    (void)state;
    assert_int_equal(c4g_session_config_default(&cfg.session), C4G_OK);
    assert_int_equal(c4g_engine_config_default(&cfg.engine), C4G_OK);
    cfg.engine.moving_eps = -1.0f;
    assert_int_equal(c4g_loop_init(&lp, &cfg), C4G_ERR_ARG);
    assert_int_equal(c4g_engine_config_check(NULL), C4G_ERR_NULL);
    cfg.engine.moving_eps = 0.5f;
    assert_int_equal(c4g_loop_init(&lp, &cfg), C4G_OK);
}

/* The encoder refuses what reached it (here: finish skipped, a NaN left): neutral. */
static void test_neutral_when_encoder_refuses(void **state)
{
    fx_t f;
    c4g_pc_packet_t pc;
    (void)state;
    cold_start(&f);
    cyclic(&f, 13, C4G_MODE_0, 1.0f);
    f.lp.priv.prepared = 0U;
    {
        const uint32_t qnan = 0x7FC00000U;
        memcpy(&f.lp.priv.tx.ax[0].target_pos, &qnan, sizeof qnan);
    }
    answer(&f, C4G_CYCLIC_SIZE(6U));
    decode_reply(&f, &pc);
    assert_int_equal(f.lp.counters.encode_refused, 1U);
    assert_int_equal(f.lp.counters.neutral_replies, 1U);
    /* a finish refused (no matching step): the fallback too */
    cyclic(&f, 14, C4G_MODE_0, 1.0f);
    f.lp.engine.priv.stepped = 0U;
    answer(&f, C4G_CYCLIC_SIZE(6U));
    assert_int_equal(f.lp.finish_status, C4G_ERR_STATE);
    assert_int_equal(f.lp.counters.neutral_replies, 2U);
    /* mode 4, the caller changed the axis count: the arm holds at 1.0 and gets 505 */
    cyclic(&f, 15, C4G_MODE_4, 1.0f);
    assert_non_null(f.ev.cmd);
    f.ev.cmd->n_axes = 5U;
    answer(&f, C4G_CYCLIC_SIZE(6U));
    decode_reply(&f, &pc);
    assert_int_equal(f.lp.finish_status, C4G_ERR_STATE);
    assert_int_equal(pc.ax[5].mode, C4G_MODE_DRIVE_OFF);
    assert_true(pc.ax[5].target_pos == 1.0f);
}

static void test_foreign_and_misuse(void **state)
{
    fx_t f;
    c4g_endpoint_t other;
    uint8_t b[732];
    size_t len;
    uint32_t ev = 0;
    uint64_t next = 0U;
    c4g_loop_config_t cfg;
    (void)state;
    cold_start(&f);
    other = f.ctl;
    other.port = 3601U;
    len = th_ctrl_bytes(b, sizeof b, 13, 6, C4G_MODE_0);
    assert_int_equal(feed_from(&f, b, len, &other), C4G_RX_DROPPED);
    assert_true(f.ev.events & C4G_EV_FOREIGN);
    assert_int_equal(c4g_loop_reply(&f.lp, f.out, sizeof f.out, &f.out_len, NULL), C4G_ERR_STATE);
    /* too small a buffer: the reply stays due */
    cyclic(&f, 13, C4G_MODE_0, 1.0f);
    assert_int_equal(c4g_loop_reply(&f.lp, f.out, 10U, &f.out_len, NULL), C4G_ERR_CAPACITY);
    answer(&f, C4G_CYCLIC_SIZE(6U));
    assert_int_equal(c4g_loop_poll(&f.lp, f.t + 1, &ev, &next), C4G_OK);
    assert_int_equal(ev, 0U);
    assert_int_equal(c4g_loop_poll(&f.lp, f.t + 2000 * MS, &ev, &next), C4G_OK);
    assert_true(ev & C4G_EV_LOST);
    assert_true(next == C4G_NO_DEADLINE);
    /* NULL arguments */
    assert_int_equal(c4g_loop_init(NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_rx(NULL, b, len, 0, NULL, &f.ev), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_rx(&f.lp, b, len, 0, NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_reply(NULL, f.out, sizeof f.out, &f.out_len, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_reply(&f.lp, NULL, sizeof f.out, &f.out_len, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_reply(&f.lp, f.out, sizeof f.out, NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_sent(NULL, 0), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_poll(NULL, 0, &ev, &next), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_poll(&f.lp, 0, &ev, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_deadline(NULL, &next), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_deadline(&f.lp, NULL), C4G_ERR_NULL);
    /* an explicit configuration */
    assert_int_equal(c4g_session_config_default(&cfg.session), C4G_OK);
    assert_int_equal(c4g_engine_config_default(&cfg.engine), C4G_OK);
    cfg.session.num_policy = C4G_NUM_ECHO;
    assert_int_equal(c4g_loop_init(&f.lp, &cfg), C4G_OK);
    assert_int_equal(f.lp.session.cfg.num_policy, C4G_NUM_ECHO);
    /* a sender address longer than 16 bytes is refused outright */
    other.addr_len = 17U;
    assert_int_equal(c4g_loop_rx(&f.lp, b, len, 0, &other, &f.ev), C4G_ERR_ARG);
}

/* A control configuration the engine refuses: every cyclic reply is neutral. */
static void test_engine_refused(void **state)
{
    fx_t f;
    c4g_pc_packet_t pc;
    (void)state;
    memset(&f, 0, sizeof f);
    cold_start(&f);
    f.lp.priv.engine_cfg.moving_eps = -1.0f;
    f.lp.engine_ready = 0U;
    /* a 506 restart brings a new init packet, which the engine now refuses */
    {
        uint8_t b[732];
        c4g_ctrl_packet_t p;
        size_t len = 0;
        th_ctrl_packet(&p, 13, 6U, C4G_MODE_SVR_RESTART);
        assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
        assert_int_equal(feed_from(&f, b, len, &f.ctl), C4G_RX_CYCLIC);
        answer(&f, C4G_CYCLIC_SIZE(6U));
        th_put_u32(th_fig, 10U);
        assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &f.ctl), C4G_RX_INIT);
        answer(&f, 1200U);
    }
    assert_int_equal(f.lp.counters.engine_init_refused, 1U);
    assert_int_equal(f.lp.engine_ready, 0U);
    cyclic(&f, 11, C4G_MODE_0, 1.0f);
    assert_null(f.ev.cmd);
    answer(&f, C4G_CYCLIC_SIZE(6U));
    decode_reply(&f, &pc);
    assert_int_equal(pc.ax[0].mode, C4G_MODE_0);
    assert_true(f.lp.counters.neutral_replies >= 2U);
}

/* A 506 restart with a new init packet: the user limits kept by the loop hold again at once;
 * an init on which an open axis's limits cannot be applied leaves the engine off. */
static void restart_with(fx_t *f, const uint8_t *init)
{
    uint8_t b[732];
    c4g_ctrl_packet_t p;
    size_t len = 0;
    th_ctrl_packet(&p, 13, 6U, C4G_MODE_SVR_RESTART);
    assert_int_equal(c4g_ctrl_encode(&p, b, sizeof b, &len), C4G_OK);
    assert_int_equal(feed_from(f, b, len, &f->ctl), C4G_RX_CYCLIC);
    answer(f, C4G_CYCLIC_SIZE(6U));
    assert_int_equal(feed_from(f, init, C4G_INIT_SIZE, &f->ctl), C4G_RX_INIT);
    answer(f, 1200U);
}

static void test_user_limits_survive_restart(void **state)
{
    fx_t f;
    c4g_axis_limits_t lim, got;
    c4g_init_t in;
    uint8_t other[C4G_INIT_SIZE];
    size_t len = 0;
    c4g_pc_packet_t pc;
    (void)state;
    memset(&lim, 0, sizeof lim);
    lim.max_step = 0.01f;
    lim.joint_min = -1.0f;
    lim.joint_max = 1.0f;
    cold_start(&f);
    assert_int_equal(c4g_loop_set_limits(NULL, 0, 0, &lim), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_set_limits(&f.lp, 4, 0, &lim), C4G_ERR_ARG);
    assert_int_equal(c4g_loop_set_limits(&f.lp, 0, 10, &lim), C4G_ERR_ARG);
    assert_int_equal(c4g_loop_set_limits(&f.lp, 0, 0, &lim), C4G_OK);
    assert_int_equal(c4g_loop_set_limits(&f.lp, 0, 8, &lim), C4G_OK); /* not open: kept */
    lim.max_step = -1.0f;
    assert_int_equal(c4g_loop_set_limits(&f.lp, 0, 1, &lim), C4G_ERR_LIMITS); /* not kept */
    assert_int_equal(c4g_loop_limits(&f.lp, 0, &got), C4G_OK);
    assert_true(got.max_step == 0.01f);
    th_put_u32(th_fig, 10U);
    restart_with(&f, th_fig);
    assert_int_equal(f.lp.engine_ready, 1U);
    assert_int_equal(c4g_loop_limits(&f.lp, 0, &got), C4G_OK);
    assert_true(got.max_step == 0.01f); /* was: 0, off, after every restart */
    assert_int_equal(c4g_loop_limits(&f.lp, 1, &got), C4G_OK);
    assert_true(got.max_step == 0.0f);
    /* a cold restart (the session lost, then a new start-up) with an init whose axis 1 has
     * no transmission ratio: its joint limits cannot be kept */
    assert_int_equal(c4g_init_decode(th_fig, sizeof th_fig, &in, NULL), C4G_OK);
    in.tx_rate[0][0] = 0.0f;
    assert_int_equal(c4g_init_encode(&in, other, sizeof other, &len), C4G_OK);
    f.t += 3000 * MS;
    {
        uint8_t b[732];
        int32_t num;
        for (num = 1; num <= 12; num++) {
            if (num == 10) {
                assert_int_equal(feed_from(&f, other, sizeof other, &f.ctl), C4G_RX_INIT);
                answer(&f, 1200U);
                continue;
            }
            memset(b, 0, sizeof b);
            th_put_u32(b, (uint32_t)num);
            assert_int_equal(feed_from(&f, b, C4G_CYCLIC_SIZE(6U), &f.ctl), C4G_RX_SYNC);
            answer(&f, 732U);
        }
    }
    assert_int_equal(f.lp.counters.limits_refused, 1U);
    assert_int_equal(f.lp.engine_ready, 0U);
    cyclic(&f, 13, C4G_MODE_4, 0.5f);
    answer(&f, C4G_CYCLIC_SIZE(6U));
    decode_reply(&f, &pc);
    assert_int_equal(pc.ax[0].mode, C4G_MODE_DRIVE_OFF); /* the fallback: hold, 505 */
    assert_true(pc.ax[0].target_pos == 0.5f);
}

/* The queries: an exit under way (requested, or accepted and leaving), effective limits. */
static void test_queries(void **state)
{
    fx_t f;
    c4g_axis_limits_t lim, got;
    bool pend = true;
    (void)state;
    cold_start(&f);
    cyclic(&f, 13, C4G_MODE_4, 1.0f);
    assert_int_equal(c4g_loop_exit_pending(&f.lp, 0U, &pend), C4G_OK);
    assert_false(pend);
    assert_int_equal(c4g_engine_request_exit(&f.lp.engine, 0U), C4G_OK);
    assert_int_equal(c4g_loop_exit_pending(&f.lp, 0U, &pend), C4G_OK);
    assert_true(pend);
    f.lp.engine.arm[0].exit_req = 0U;
    f.lp.engine.arm[0].leaving = 1U;
    pend = false;
    assert_int_equal(c4g_loop_exit_pending(&f.lp, 0U, &pend), C4G_OK);
    assert_true(pend);
    assert_int_equal(c4g_loop_exit_pending(&f.lp, C4G_ARMS, &pend), C4G_ERR_ARG);
    assert_false(pend);
    assert_int_equal(c4g_loop_exit_pending(NULL, 0U, &pend), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_exit_pending(&f.lp, 0U, NULL), C4G_ERR_NULL);
    /* limits: the user's stroke ends, the init packet's following error */
    memset(&lim, 0, sizeof lim);
    lim.motor_min = -2.0f;
    lim.motor_max = 3.0f;
    assert_int_equal(c4g_engine_set_limits(&f.lp.engine, f.lp.session.map.arm_of[1],
                                        f.lp.session.map.logical_of[1], &lim), C4G_OK);
    assert_int_equal(c4g_loop_limits(&f.lp, 1U, &got), C4G_OK);
    assert_true(got.motor_min == -2.0f);
    assert_true(got.motor_max == 3.0f);
    assert_true(got.follow_error == f.lp.engine.ctrl_fe[1]);
    assert_int_equal(c4g_loop_limits(&f.lp, 6U, &got), C4G_ERR_ARG);
    assert_int_equal(c4g_loop_limits(NULL, 0U, &got), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_limits(&f.lp, 0U, NULL), C4G_ERR_NULL);
    /* no engine: nothing to ask */
    f.lp.engine_ready = 0U;
    assert_int_equal(c4g_loop_limits(&f.lp, 0U, &got), C4G_ERR_STATE);
    assert_int_equal(c4g_loop_exit_pending(&f.lp, 0U, &pend), C4G_ERR_STATE);
}


/* An init packet injected from the controller's own endpoint between its last sync and its
 * own init: the loop takes neither. The controller's init conflicts, nothing is answered any
 * more (no reply, no control step), and the loop's limits never come from the forged one
 * into a reply. */
static void test_injected_init_refused(void **state)
{
    fx_t f;
    uint8_t b[732], forged[C4G_INIT_SIZE];
    size_t len;
    int32_t num;
    uint32_t k;
    (void)state;
    memset(&f, 0, sizeof f);
    f.ctl.addr_len = 4U;
    f.ctl.addr[0] = 127U;
    f.ctl.addr[3] = 1U;
    f.ctl.port = 3600U;
    assert_int_equal(c4g_loop_init(&f.lp, NULL), C4G_OK);
    f.t = 1000 * MS;
    for (num = 1; num <= 9; num++) {
        memset(b, 0, sizeof b);
        th_put_u32(b, (uint32_t)num);
        assert_int_equal(feed_from(&f, b, sizeof b, &f.ctl), C4G_RX_SYNC);
        answer(&f, 732U);
    }
    memcpy(forged, th_fig, sizeof forged);
    for (k = 0; k < 6U; k++) {
        th_put_f32(&forged[C4G_INIT_OFF_AZLIM + 4U * k], 150.0f); /* under the ceiling */
    }
    assert_int_equal(feed_from(&f, forged, sizeof forged, &f.ctl), C4G_RX_INIT);
    answer(&f, 1200U);
    assert_int_equal(feed_from(&f, th_fig, sizeof th_fig, &f.ctl), C4G_RX_DROPPED);
    assert_true(f.ev.events & C4G_EV_INIT_CONFLICT);
    assert_int_equal(f.ev.diag.field, C4G_FIELD_AZLIM);
    assert_int_equal(c4g_loop_reply(&f.lp, f.out, sizeof f.out, &f.out_len, NULL), C4G_ERR_STATE);
    for (num = 11; num <= 20; num++) {
        len = th_ctrl_bytes(b, sizeof b, num, 6, C4G_MODE_0);
        assert_int_equal(feed_from(&f, b, len, &f.ctl), C4G_RX_DROPPED);
        assert_true(f.ev.events & C4G_EV_REFUSED);
        assert_null(f.ev.cmd);
        assert_int_equal(c4g_loop_reply(&f.lp, f.out, sizeof f.out, &f.out_len, NULL),
                         C4G_ERR_STATE);
    }
    assert_int_equal(f.lp.session.phase, C4G_PHASE_REFUSED);
    assert_int_equal(f.lp.session.counters.tx, 10U); /* 9 syncs and the forged echo only */
    /* refused: the next check is the loss timeout, after which a new start-up is served */
    {
        uint64_t next = 0U;
        uint32_t ev = 0U;
        assert_int_equal(c4g_loop_deadline(&f.lp, &next), C4G_OK);
        assert_true(next == f.t + f.lp.session.lost_timeout_ns + 1U);
        assert_int_equal(c4g_loop_poll(&f.lp, next - 1U, &ev, &next), C4G_OK);
        assert_int_equal(ev, 0U);
        assert_int_equal(c4g_loop_poll(&f.lp, next, &ev, &next), C4G_OK);
        assert_true(ev & C4G_EV_LOST);
        assert_true(next == C4G_NO_DEADLINE);
    }
}

/* c4g_loop_poll's next deadline is the first instant the silence or loss check has work:
 * one ns earlier it finds nothing, at it the event comes; no deadline while only a datagram
 * can change anything. */
static void test_poll_deadline(void **state)
{
    fx_t f;
    uint8_t b[732];
    uint64_t next = 0U, t_last;
    uint32_t ev = 0U;
    c4g_loop_state_t ls;
    (void)state;
    memset(&f, 0, sizeof f);
    f.ctl.addr_len = 4U;
    f.ctl.addr[0] = 127U;
    f.ctl.port = 3600U;
    assert_int_equal(c4g_loop_init(&f.lp, NULL), C4G_OK);
    /* nothing received: nothing can time out */
    assert_int_equal(c4g_loop_poll(&f.lp, 5000 * MS, &ev, &next), C4G_OK);
    assert_int_equal(ev, 0U);
    assert_true(next == C4G_NO_DEADLINE);
    /* a start-up under way: the loss timeout forgets it */
    f.t = 1000 * MS;
    memset(b, 0, sizeof b);
    th_put_u32(b, 1U);
    assert_int_equal(feed_from(&f, b, C4G_CYCLIC_SIZE(6U), &f.ctl), C4G_RX_SYNC);
    answer(&f, 732U);
    assert_int_equal(c4g_loop_state(&f.lp, &ls), C4G_OK);
    assert_int_equal(c4g_loop_deadline(&f.lp, &next), C4G_OK);
    assert_true(next == f.t + ls.lost_timeout_ns + 1U);
    /* cyclic: silence first, then the loss */
    cold_start(&f);
    t_last = f.t;
    assert_int_equal(c4g_loop_state(&f.lp, &ls), C4G_OK);
    assert_true(ls.silence_ns < ls.lost_timeout_ns);
    assert_int_equal(c4g_loop_deadline(&f.lp, &next), C4G_OK);
    assert_true(next == t_last + ls.silence_ns + 1U);
    assert_int_equal(c4g_loop_poll(&f.lp, next - 1U, &ev, &next), C4G_OK);
    assert_int_equal(ev, 0U);
    assert_true(next == t_last + ls.silence_ns + 1U);
    assert_int_equal(c4g_loop_poll(&f.lp, next, &ev, &next), C4G_OK);
    assert_int_equal(ev, C4G_EV_SILENCE);
    assert_true(next == t_last + ls.lost_timeout_ns + 1U);
    assert_int_equal(c4g_loop_poll(&f.lp, next - 1U, &ev, &next), C4G_OK);
    assert_int_equal(ev, 0U);
    assert_int_equal(c4g_loop_poll(&f.lp, next, &ev, &next), C4G_OK);
    assert_int_equal(ev, C4G_EV_LOST);
    assert_true(next == C4G_NO_DEADLINE);
    /* a deadline past the end of the clock saturates instead of wrapping */
    cold_start(&f);
    f.lp.session.priv.last_rx_ns = C4G_NO_DEADLINE - 10U;
    assert_int_equal(c4g_loop_deadline(&f.lp, &next), C4G_OK);
    assert_true(next == C4G_NO_DEADLINE);
    /* passive freezing suspends the checks */
    cold_start(&f);
    f.lp.session.priv.frozen = 1U;
    assert_int_equal(c4g_loop_deadline(&f.lp, &next), C4G_OK);
    assert_true(next == C4G_NO_DEADLINE);
}

/* The read accessors show the session and engine the loop holds. */
static void test_accessors(void **state)
{
    fx_t f;
    const c4g_init_t *ip = NULL;
    const c4g_axis_map_t *m = NULL;
    const c4g_counters_t *sc = NULL;
    const c4g_loop_counters_t *lc = NULL;
    const c4g_pc_packet_t *tx = NULL;
    c4g_engine_t *e = NULL;
    const c4g_engine_t *ev_ = NULL;
    c4g_timing_t tm;
    c4g_loop_state_t ls;
    bool is = false;
    c4g_endpoint_t other;
    (void)state;
    assert_int_equal(c4g_loop_init(&f.lp, NULL), C4G_OK);
    assert_int_equal(c4g_loop_engine(&f.lp, &e), C4G_ERR_STATE);
    assert_ptr_equal(e, &f.lp.engine);
    assert_int_equal(c4g_loop_engine_view(&f.lp, &ev_), C4G_ERR_STATE);
    assert_int_equal(c4g_loop_axis_map(&f.lp, &m), C4G_OK);
    assert_int_equal(m->n_axes, 0U);
    cold_start(&f);
    assert_int_equal(c4g_loop_init_packet(&f.lp, &ip), C4G_OK);
    assert_ptr_equal(ip, &f.lp.session.init);
    assert_true(ip->period_ms > 0);
    assert_int_equal(c4g_loop_axis_map(&f.lp, &m), C4G_OK);
    assert_int_equal(m->n_axes, 6U);
    assert_int_equal(c4g_loop_counters(&f.lp, &sc, &lc), C4G_OK);
    assert_int_equal(sc->sync, 11U);
    assert_int_equal(sc->init, 1U);
    assert_int_equal(lc->neutral_replies, 0U);
    sc = NULL;
    assert_int_equal(c4g_loop_counters(&f.lp, &sc, NULL), C4G_OK);
    assert_non_null(sc);
    assert_int_equal(c4g_loop_counters(&f.lp, NULL, &lc), C4G_OK);
    assert_int_equal(c4g_loop_timing(&f.lp, &tm), C4G_OK);
    assert_true(tm.nominal_period_ns == (int64_t)ip->period_ms * 1000000);
    assert_int_equal(c4g_loop_state(&f.lp, &ls), C4G_OK);
    assert_int_equal(ls.phase, C4G_PHASE_CYCLIC);
    assert_true(ls.locked);
    assert_int_equal(ls.peer.port, 3600U);
    assert_int_equal(ls.last_num, 12);
    assert_true(ls.engine_ready);
    assert_int_equal(ls.finish_status, C4G_OK);
    assert_int_equal(c4g_loop_is_peer(&f.lp, &f.ctl, &is), C4G_OK);
    assert_true(is);
    other = f.ctl;
    other.port = 3601U;
    assert_int_equal(c4g_loop_is_peer(&f.lp, &other, &is), C4G_OK);
    assert_false(is);
    assert_int_equal(c4g_loop_engine(&f.lp, &e), C4G_OK);
    assert_ptr_equal(e, &f.lp.engine);
    assert_int_equal(c4g_loop_engine_view(&f.lp, &ev_), C4G_OK);
    assert_ptr_equal(ev_, &f.lp.engine);
    assert_int_equal(c4g_loop_reply_packet(&f.lp, &tx), C4G_OK);
    assert_ptr_equal(tx, &f.lp.priv.tx);
    /* NULL arguments */
    assert_int_equal(c4g_loop_init_packet(NULL, &ip), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_init_packet(&f.lp, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_axis_map(NULL, &m), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_axis_map(&f.lp, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_counters(NULL, &sc, &lc), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_counters(&f.lp, NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_timing(NULL, &tm), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_timing(&f.lp, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_state(NULL, &ls), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_state(&f.lp, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_is_peer(NULL, &other, &is), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_is_peer(&f.lp, NULL, &is), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_is_peer(&f.lp, &other, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_engine(NULL, &e), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_engine(&f.lp, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_reply_packet(NULL, &tx), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_engine_view(NULL, &ev_), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_engine_view(&f.lp, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_loop_reply_packet(&f.lp, NULL), C4G_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_handshake_and_mode0),
        cmocka_unit_test(test_reply_is_filtered),
        cmocka_unit_test(test_neutral_without_engine),
        cmocka_unit_test(test_loop_refuses_bad_engine_config),
        cmocka_unit_test(test_user_limits_survive_restart),
        cmocka_unit_test(test_neutral_when_encoder_refuses),
        cmocka_unit_test(test_foreign_and_misuse),
        cmocka_unit_test(test_engine_refused),
        cmocka_unit_test(test_queries),
        cmocka_unit_test(test_injected_init_refused),
        cmocka_unit_test(test_poll_deadline),
        cmocka_unit_test(test_accessors),
    };
    return cmocka_run_group_tests_name("loop", tests, th_load_fig, NULL);
}
