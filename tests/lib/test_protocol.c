/* SPDX-License-Identifier: MIT */
/* The in-process protocol suite: the library's controller end (c4g_ctrl) and its PC end
 * (c4g_session) talk to each other in memory, on a simulated clock, deterministically. A
 * "world" carries each datagram from one end to the other and can drop, duplicate, hold
 * back (reorder) or delay it; a stall is a jump of the clock. Each case asserts the
 * counters and verdicts of both ends. No sockets, no threads, no sleeping. */
#include "test_helpers.h"

#define N_AX 6U             /* the figure 10.1 init packet: 6 axes of arm 1, 2 ms */
#define PERIOD (2U * MS)
#define MS 1000000ULL
#define US 1000ULL
#define PC_DELAY (100U * US)   /* controller packet -> PC */
#define PC_WORK (50U * US)     /* the PC's reply time */

/* Faults of one tick (bit mask). */
#define F_DROP_CTRL 0x01U   /* the controller's packet is lost on the way */
#define F_DUP_CTRL 0x02U    /* ... arrives twice */
#define F_HOLD_CTRL 0x04U   /* ... arrives after the next one (reorder) */
#define F_DROP_REPLY 0x08U  /* the PC's reply is lost */
#define F_DUP_REPLY 0x10U   /* ... arrives twice */
#define F_SILENT 0x20U      /* the controller sends nothing this tick (passive freezing) */
#define F_PC_STALL 0x40U    /* the PC does not run: packets wait in its socket */

typedef struct msg {
    uint8_t b[C4G_INIT_SIZE];
    size_t len;
} msg_t;

typedef struct world {
    c4g_ctrl_t ctrl;
    c4g_session_t pc;
    uint8_t init_raw[C4G_INIT_SIZE];
    uint64_t now;            /* the controller's next tick */
    int32_t mode;            /* the mode of every axis in the next cyclic packet */
    int frozen_a;            /* controller: a reply carried 500 (its checks are suspended) */
    /* the PC's behaviour */
    int32_t pc_mode;         /* 0: neutral replies; else this mode on every axis */
    uint32_t pc_infpar;      /* INFPAR of its replies */
    /* what happened */
    unsigned verdicts[4];    /* by c4g_ctrl_verdict_t */
    unsigned rx[C4G_CTRL_RX_DUPLICATE + 1]; /* by c4g_ctrl_rx_t */
    uint32_t pc_events;      /* OR of every c4g_session_rx / poll event */
    unsigned pc_ended;       /* packets refused with C4G_ERR_ENDED */
    uint64_t last_silence_ns;/* with C4G_EV_RESUMED */
    msg_t held;              /* F_HOLD_CTRL */
    int have_held;
    msg_t queue[32];         /* F_PC_STALL: the PC's socket */
    uint64_t queue_at[32];
    unsigned n_queue;
} world_t;

static void world_init(world_t *w, c4g_num_policy_t ctrl_policy, c4g_num_policy_t pc_policy)
{
    c4g_ctrl_config_t cc;
    c4g_session_config_t sc;
    c4g_init_t init;
    size_t len = 0U;
    memset(w, 0, sizeof *w);
    memset(&cc, 0, sizeof cc);
    cc.policy = ctrl_policy;
    cc.n_axes = N_AX;
    cc.t_cycle1_ns = 500U * US;
    cc.tol_ns = 500U * US;
    cc.max_miss = 10U;
    cc.sync_before = 9U;
    cc.sync_after = 2U;
    assert_int_equal(c4g_ctrl_init(&w->ctrl, &cc), C4G_OK);
    assert_int_equal(c4g_session_config_default(&sc), C4G_OK);
    sc.num_policy = pc_policy;
    assert_int_equal(c4g_session_init(&w->pc, &sc), C4G_OK);
    assert_int_equal(c4gsim_fig10_1(&init), C4G_OK);
    assert_int_equal(c4g_init_encode(&init, w->init_raw, sizeof w->init_raw, &len), C4G_OK);
    w->now = 10U * MS;
}

/* The controller end receives the PC's reply. */
static void to_ctrl(world_t *w, const uint8_t *b, size_t len, uint64_t at)
{
    c4g_ctrl_rx_t r = C4G_CTRL_RX_ACCEPTED;
    assert_int_equal(c4g_ctrl_reply(&w->ctrl, b, len, at, &r), C4G_OK);
    w->rx[r]++;
}

/* The PC's reply to a cyclic packet: neutral, or with the PC's request. */
static size_t pc_cyclic_reply(world_t *w, const c4g_ctrl_packet_t *rx, uint8_t *out, size_t cap)
{
    size_t len = 0U;
    if (w->pc_mode == 0 && w->pc_infpar == 0U) {
        assert_int_equal(c4g_session_reply_neutral(&w->pc, out, cap, &len), C4G_OK);
    } else {
        c4g_pc_packet_t tx;
        uint32_t i;
        assert_int_equal(c4g_session_neutral(&w->pc, rx, &tx), C4G_OK);
        for (i = 0U; i < tx.n_axes && w->pc_mode != 0; i++) {
            tx.ax[i].mode = w->pc_mode;
        }
        tx.infpar = w->pc_infpar;
        assert_int_equal(c4g_session_reply(&w->pc, &tx, out, cap, &len), C4G_OK);
    }
    return len;
}

/* The PC end receives a datagram at @p at and answers it (faults @p f on the reply). */
static void to_pc(world_t *w, const uint8_t *b, size_t len, uint64_t at, unsigned f)
{
    c4g_rx_result_t res;
    uint8_t out[C4G_INIT_SIZE];
    size_t n;
    const c4g_status_t st = c4g_session_rx(&w->pc, b, len, at, &res);
    if (st == C4G_ERR_ENDED) {
        w->pc_ended++;
        return;
    }
    assert_int_equal(st, C4G_OK);
    w->pc_events |= res.events;
    if ((res.events & C4G_EV_RESUMED) != 0U) {
        w->last_silence_ns = res.silence_ns;
    }
    if (res.kind == C4G_RX_DROPPED) {
        return;
    }
    if (res.kind == C4G_RX_CYCLIC) {
        n = pc_cyclic_reply(w, res.pkt, out, sizeof out);
        /* cycle time statistics: cyclic replies only */
        assert_int_equal(c4g_session_sent(&w->pc, at + PC_WORK), C4G_OK);
    } else {
        assert_int_equal(c4g_session_reply(&w->pc, NULL, out, sizeof out, &n), C4G_OK);
    }
    if ((f & F_DROP_REPLY) == 0U) {
        to_ctrl(w, out, n, at + PC_WORK);
    }
    if ((f & F_DUP_REPLY) != 0U) {
        to_ctrl(w, out, n, at + PC_WORK + 10U * US);
    }
}

/* The PC runs again after a stall at @p at: it answers what waited in its socket. */
static void pc_wakes(world_t *w, uint64_t at)
{
    unsigned i;
    for (i = 0U; i < w->n_queue; i++) {
        to_pc(w, w->queue[i].b, w->queue[i].len, at, 0U);
    }
    w->n_queue = 0U;
}

static void pc_poll(world_t *w, uint64_t at)
{
    uint32_t ev = 0U;
    assert_int_equal(c4g_session_poll(&w->pc, at, &ev), C4G_OK);
    w->pc_events |= ev;
}

/* The controller's tick at w->now, woken @p late ns after it: judge the outstanding packet
 * (its deadline was this tick), take the PC's requests, send the next packet. */
static void tick(world_t *w, unsigned f, uint64_t late)
{
    const uint64_t t = w->now + late;
    c4g_ctrl_verdict_t v = C4G_CTRL_J_NONE;
    const c4g_pc_packet_t *rep = NULL;
    msg_t m;
    c4g_pkt_kind_t kind;
    int32_t num;
    assert_int_equal(c4g_ctrl_judge(&w->ctrl, t, w->frozen_a != 0, &v), C4G_OK);
    w->verdicts[v]++;
    if (c4g_ctrl_take_reply(&w->ctrl, &rep) == C4G_OK) {
        /* the controller applies the PC's requests: 500 from mode 0 freezes it actively,
         * EXIT_FROM_OPEN ends that */
        if (rep->ax[0].mode == C4G_MODE_FREEZING_A) {
            w->frozen_a = 1;
        }
        if (c4g_arm_byte(rep->infpar, 0U) == C4G_EXIT_FROM_OPEN) {
            w->frozen_a = 0;
        }
    }
    if ((f & F_SILENT) != 0U) {
        pc_poll(w, t + PC_DELAY);
        w->now += PERIOD;
        return;
    }
    kind = c4g_ctrl_next_kind(&w->ctrl);
    num = c4g_ctrl_next_num(&w->ctrl);
    if (kind == C4G_PKT_INIT) {
        memcpy(m.b, w->init_raw, C4G_INIT_SIZE);
        m.len = C4G_INIT_SIZE;
    } else {
        m.len = th_ctrl_bytes(m.b, sizeof m.b, num, N_AX, (kind == C4G_PKT_SYNC) ? C4G_MODE_0 : w->mode);
    }
    /* the controller does not check the reply to 504 */
    assert_int_equal(c4g_ctrl_emit(&w->ctrl, kind, num, m.b, m.len,
                                   !(kind == C4G_PKT_CYCLIC && w->mode == C4G_MODE_EXIT_OPEN), t),
                     C4G_OK);
    assert_int_equal(c4g_ctrl_advance(&w->ctrl), C4G_OK);
    if (kind == C4G_PKT_CYCLIC && w->mode == C4G_MODE_SVR_RESTART) {
        assert_int_equal(c4g_ctrl_restart(&w->ctrl), C4G_OK);
        w->mode = C4G_MODE_0;
    }
    assert_int_equal(c4g_ctrl_set_deadline(&w->ctrl, w->now + PERIOD), C4G_OK);
    if ((f & F_PC_STALL) != 0U) {
        assert_true(w->n_queue < 32U);
        w->queue[w->n_queue] = m;
        w->queue_at[w->n_queue] = t + PC_DELAY;
        w->n_queue++;
    } else if ((f & F_HOLD_CTRL) != 0U) {
        w->held = m;
        w->have_held = 1;
    } else if ((f & F_DROP_CTRL) == 0U) {
        to_pc(w, m.b, m.len, t + PC_DELAY, f);
        if ((f & F_DUP_CTRL) != 0U) {
            to_pc(w, m.b, m.len, t + PC_DELAY + 20U * US, f);
        }
        if (w->have_held) {
            w->have_held = 0;
            to_pc(w, w->held.b, w->held.len, t + PC_DELAY + 30U * US, f);
        }
    }
    w->now += PERIOD;
}

static void ticks(world_t *w, unsigned n, unsigned f)
{
    unsigned i;
    for (i = 0U; i < n; i++) {
        tick(w, f, 0U);
    }
}

/* 9 sync, init, 2 sync, and @p cyclic cyclic packets; the last one judged. */
static void start(world_t *w, unsigned cyclic)
{
    ticks(w, 12U + cyclic, 0U);
    tick(w, F_SILENT, 0U);
}

static void assert_clean_pc(const world_t *w)
{
    const c4g_counters_t *k = &w->pc.counters;
    assert_int_equal(k->gaps, 0);
    assert_int_equal(k->duplicates, 0);
    assert_int_equal(k->out_of_order, 0);
    assert_int_equal(k->malformed_total, 0);
    assert_int_equal(k->foreign_total, 0);
}

/* ---- handshake and NUM policies ---- */

static void test_handshake(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 20U);
    /* controller: every packet answered in time */
    assert_int_equal(w.ctrl.n.sync_sent, 11);
    assert_int_equal(w.ctrl.n.init_sent, 1);
    assert_int_equal(w.ctrl.n.cyclic_sent, 20);
    assert_int_equal(w.ctrl.n.replies_ok, 32);
    assert_int_equal(w.verdicts[C4G_CTRL_J_OK], 32);
    assert_int_equal(w.ctrl.n.missing + w.ctrl.n.late + w.ctrl.n.wrong_num + w.ctrl.n.malformed, 0);
    assert_int_equal(w.ctrl.n.lat_max, PC_DELAY + PC_WORK);
    assert_int_equal(w.ctrl.last_lat_ns, PC_DELAY + PC_WORK);
    assert_int_equal(w.ctrl.phase, C4G_CTRL_PH_CYCLIC);
    /* PC: the same packets, each answered */
    assert_int_equal(w.pc.counters.sync, 11);
    assert_int_equal(w.pc.counters.init, 1);
    assert_int_equal(w.pc.counters.cyclic, 20);
    assert_int_equal(w.pc.counters.tx, 32);
    assert_int_equal(w.pc.phase, C4G_PHASE_CYCLIC);
    assert_true((w.pc_events & (C4G_EV_INIT | C4G_EV_CYCLIC_START)) == (C4G_EV_INIT | C4G_EV_CYCLIC_START));
    assert_clean_pc(&w);
}

static void test_num_policies(void **st)
{
    static const struct {
        c4g_num_policy_t ctrl, pc;
        int ok;
        int detected;
    } rows[] = {
        {C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE, 1, -1},
        {C4G_NUM_ECHO, C4G_NUM_ECHO, 1, -1},
        {C4G_NUM_EITHER, C4G_NUM_PLUS_ONE, 1, C4G_NUM_PLUS_ONE},
        {C4G_NUM_EITHER, C4G_NUM_ECHO, 1, C4G_NUM_ECHO},
        {C4G_NUM_PLUS_ONE, C4G_NUM_ECHO, 0, -1},
        {C4G_NUM_ECHO, C4G_NUM_PLUS_ONE, 0, -1},
    };
    size_t i;
    (void)st;
    for (i = 0U; i < sizeof rows / sizeof rows[0]; i++) {
        world_t w;
        world_init(&w, rows[i].ctrl, rows[i].pc);
        start(&w, 20U);
        assert_int_equal(w.ctrl.detected, rows[i].detected);
        /* the PC end sees a clean conversation either way: the refusal is the controller's */
        assert_int_equal(w.pc.counters.tx, 32);
        assert_clean_pc(&w);
        if (rows[i].ok) {
            assert_int_equal(w.ctrl.n.replies_ok, 32);
            assert_int_equal(w.ctrl.n.wrong_num, 0);
            assert_int_equal(w.ctrl.fatal, 0);
        } else {
            /* every reply is refused; the 10th packet in a row without one is fatal */
            assert_int_equal(w.ctrl.n.replies_ok, 0);
            assert_int_equal(w.ctrl.n.wrong_num + w.ctrl.n.stale, 32);
            assert_int_equal(w.ctrl.n.missing, 32);
            assert_int_equal(w.ctrl.n.max_consecutive, 32);
            assert_int_equal(w.verdicts[C4G_CTRL_J_MISSING], 32);
        }
    }
    /* the 10th miss in a row is reported fatal at its judgement */
    {
        world_t w;
        world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_ECHO);
        ticks(&w, 10U, 0U);
        assert_int_equal(w.ctrl.fatal, 0);
        tick(&w, F_SILENT, 0U);
        assert_int_equal(w.ctrl.fatal, 1);
        assert_int_equal(w.ctrl.n.consecutive, 10);
    }
}

/* Across the 15-bit wrap: the controller counts 0x7FFF, 0, 1; a plus-one PC answers 0x7FFF
 * with 1 (never 0). Both ends see no gap, no duplicate, no wrong NUM. */
static void test_num_wrap(void **st)
{
    static const c4g_num_policy_t pol[2] = {C4G_NUM_PLUS_ONE, C4G_NUM_ECHO};
    size_t i;
    (void)st;
    for (i = 0U; i < 2U; i++) {
        world_t w;
        unsigned n = 0U;
        world_init(&w, C4G_NUM_EITHER, pol[i]);
        ticks(&w, 12U, 0U);
        while (c4g_ctrl_next_num(&w.ctrl) != 2) {
            tick(&w, 0U, 0U);
            n++;
        }
        tick(&w, F_SILENT, 0U);
        assert_int_equal(n, 0x8000 - 13 + 2); /* NUM 13 .. 0x7FFF, 0, 1 */
        assert_int_equal(w.ctrl.n.replies_ok, 12U + n);
        assert_int_equal(w.ctrl.n.wrong_num + w.ctrl.n.stale + w.ctrl.n.missing, 0);
        assert_int_equal(w.pc.counters.cyclic, n);
        assert_int_equal(w.pc.priv.last_num, 1);
        assert_clean_pc(&w);
    }
}

/* ---- end and restart ---- */

static void test_exit_504(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 5U);
    w.mode = C4G_MODE_EXIT_OPEN;
    tick(&w, 0U, 0U);
    /* the PC ends the session and still answers the 504, which the controller does not
     * check: its reply is unexpected and the packet is not judged */
    assert_int_equal(w.pc.phase, C4G_PHASE_ENDED);
    assert_true((w.pc_events & C4G_EV_END) != 0U);
    assert_true((w.pc_events & C4G_EV_END_UNEXPECTED) == 0U);
    assert_int_equal(w.rx[C4G_CTRL_RX_UNEXPECTED], 1);
    assert_int_equal(w.ctrl.n.unexpected, 1);
    tick(&w, F_SILENT, 0U);
    /* nothing to judge at the first tick of all and after start's silent tick; the 504
     * itself is not judged */
    assert_int_equal(w.verdicts[C4G_CTRL_J_NONE], 3);
    assert_int_equal(w.ctrl.n.missing, 0);
    assert_int_equal(w.ctrl.n.replies_ok, 17);
    /* nothing after 504 reaches the PC's session */
    w.mode = C4G_MODE_0;
    tick(&w, 0U, 0U);
    assert_int_equal(w.pc_ended, 1);
}

static void test_restart_506(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_EITHER, C4G_NUM_ECHO);
    start(&w, 5U);
    w.mode = C4G_MODE_SVR_RESTART;
    tick(&w, 0U, 0U);
    /* the init packet follows at once, without sync packets, then cyclic packets */
    assert_int_equal(c4g_ctrl_next_kind(&w.ctrl), C4G_PKT_INIT);
    ticks(&w, 6U, 0U);
    tick(&w, F_SILENT, 0U);
    assert_int_equal(w.ctrl.n.init_sent, 2);
    assert_int_equal(w.ctrl.n.sync_sent, 11);
    assert_int_equal(w.ctrl.n.cyclic_sent, 11);
    assert_int_equal(w.ctrl.n.replies_ok, 24);
    assert_int_equal(w.ctrl.n.missing + w.ctrl.n.wrong_num + w.ctrl.n.malformed, 0);
    assert_int_equal(w.ctrl.detected, C4G_NUM_ECHO);
    assert_true((w.pc_events & C4G_EV_RESTART) != 0U);
    assert_int_equal(w.pc.counters.init, 2);
    assert_int_equal(w.pc.counters.cyclic, 11);
    assert_int_equal(w.pc.phase, C4G_PHASE_CYCLIC);
    assert_clean_pc(&w);
}

/* ---- freezing ---- */

/* Active: the PC's reply carries 500; the controller stops checking until a reply carries
 * EXIT_FROM_OPEN. Replies lost meanwhile are neither missing nor fatal. */
static void test_active_freezing(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 5U);
    w.pc_mode = C4G_MODE_FREEZING_A;
    tick(&w, 0U, 0U);
    tick(&w, 0U, 0U); /* the reply with 500 is judged and applied here */
    assert_int_equal(w.frozen_a, 1);
    assert_int_equal(w.pc.priv.frozen_active, 1);
    ticks(&w, 30U, F_DROP_REPLY);
    assert_int_equal(w.ctrl.n.missing, 0);
    assert_int_equal(w.ctrl.fatal, 0);
    /* the 30 suspended judgements, and the two ticks with nothing outstanding (the first
     * of all, the one after start's silent tick) */
    assert_int_equal(w.verdicts[C4G_CTRL_J_NONE], 30 + 2);
    /* the PC leaves: EXIT_FROM_OPEN on arm 1 */
    w.pc_mode = 0;
    w.pc_infpar = C4G_EXIT_FROM_OPEN;
    tick(&w, 0U, 0U);
    tick(&w, 0U, 0U);
    assert_int_equal(w.frozen_a, 0);
    assert_int_equal(w.pc.priv.frozen_active, 0);
    w.pc_infpar = 0U;
    /* checked again: a lost reply is missing */
    tick(&w, F_DROP_REPLY, 0U);
    tick(&w, F_SILENT, 0U);
    assert_int_equal(w.ctrl.n.missing, 1);
    assert_clean_pc(&w);
}

/* Passive: the controller sends 502, is silent for 3 s, then sends 503. The PC neither
 * reports a silence nor loses the controller; the controller has nothing to judge. The
 * same silence without 502 loses the controller. */
static void test_passive_freezing(void **st)
{
    world_t w;
    unsigned k;
    (void)st;
    for (k = 0U; k < 2U; k++) {
        world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
        start(&w, 5U);
        w.mode = (k == 0U) ? C4G_MODE_FREEZING_P_IN : C4G_MODE_0;
        tick(&w, 0U, 0U);
        ticks(&w, 1500U, F_SILENT);
        if (k == 1U) {
            assert_true((w.pc_events & C4G_EV_LOST) != 0U);
            assert_int_equal(w.pc.phase, C4G_PHASE_LOST);
            continue;
        }
        assert_int_equal(w.pc.priv.frozen, 1);
        assert_true((w.pc_events & (C4G_EV_FREEZE_IN)) != 0U);
        assert_true((w.pc_events & (C4G_EV_SILENCE | C4G_EV_LOST)) == 0U);
        w.mode = C4G_MODE_FREEZING_P_OUT;
        tick(&w, 0U, 0U);
        w.mode = C4G_MODE_0;
        ticks(&w, 5U, 0U);
        tick(&w, F_SILENT, 0U);
        assert_true((w.pc_events & C4G_EV_FREEZE_OUT) != 0U);
        assert_int_equal(w.pc.priv.frozen, 0);
        assert_int_equal(w.pc.phase, C4G_PHASE_CYCLIC);
        assert_int_equal(w.ctrl.n.replies_ok, 17 + 1 + 6);
        assert_int_equal(w.ctrl.n.missing, 0);
        /* every silent tick but the first (which judges the 502) has nothing to judge, nor
         * have the first tick of all, the 502's and the 503's (each after a silent one) */
        assert_int_equal(w.verdicts[C4G_CTRL_J_NONE], 1499 + 3);
        assert_clean_pc(&w);
    }
}

/* ---- the path ---- */

static void test_dropped(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 5U);
    /* a controller packet lost: the controller misses its reply, the PC sees a gap */
    tick(&w, F_DROP_CTRL, 0U);
    /* a reply lost: the controller misses it, the PC saw nothing wrong */
    tick(&w, 0U, 0U);
    tick(&w, F_DROP_REPLY, 0U);
    ticks(&w, 3U, 0U);
    tick(&w, F_SILENT, 0U);
    assert_int_equal(w.ctrl.n.missing, 2);
    assert_int_equal(w.ctrl.n.max_consecutive, 1);
    assert_int_equal(w.ctrl.n.replies_ok, 17 + 4);
    assert_int_equal(w.pc.counters.gaps, 1);
    assert_int_equal(w.pc.counters.missed, 1);
    assert_true((w.pc_events & C4G_EV_GAP) != 0U);
    assert_int_equal(w.pc.counters.duplicates + w.pc.counters.out_of_order, 0);
}

static void test_duplicated(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 5U);
    /* a controller packet twice: the PC answers once and drops the copy */
    tick(&w, F_DUP_CTRL, 0U);
    /* a reply twice: the controller keeps the first and counts the second */
    tick(&w, F_DUP_REPLY, 0U);
    tick(&w, F_SILENT, 0U);
    assert_int_equal(w.pc.counters.duplicates, 1);
    assert_true((w.pc_events & C4G_EV_DUPLICATE) != 0U);
    assert_int_equal(w.pc.counters.tx, 17 + 2);
    assert_int_equal(w.ctrl.n.duplicates, 1);
    assert_int_equal(w.rx[C4G_CTRL_RX_DUPLICATE], 1);
    assert_int_equal(w.ctrl.n.replies_ok, 17 + 2);
    assert_int_equal(w.ctrl.n.missing, 0);
}

static void test_reordered(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 5U);
    /* packet k arrives after packet k + 1: the PC answers k + 1 (a gap of one) and drops k
     * (out of order, its moment passed); the controller misses k's reply only */
    tick(&w, F_HOLD_CTRL, 0U);
    tick(&w, 0U, 0U);
    ticks(&w, 2U, 0U);
    tick(&w, F_SILENT, 0U);
    assert_int_equal(w.pc.counters.gaps, 1);
    assert_int_equal(w.pc.counters.out_of_order, 1);
    assert_true((w.pc_events & C4G_EV_OUT_OF_ORDER) != 0U);
    assert_int_equal(w.ctrl.n.missing, 1);
    assert_int_equal(w.ctrl.n.replies_ok, 17 + 3);
    assert_int_equal(w.ctrl.n.wrong_num + w.ctrl.n.stale, 0);
}

/* ---- stalls: jumps of either end's clock ---- */

/* The PC stops for 3 periods and runs again within the third: the controller misses the
 * replies to the first two and counts them stale when they come (their NUMs are behind),
 * the third is in time; the PC answers the backlog without a gap. */
static void test_pc_stall(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 5U);
    ticks(&w, 3U, F_PC_STALL);
    pc_wakes(&w, w.now - PERIOD + 500U * US);
    ticks(&w, 2U, 0U);
    tick(&w, F_SILENT, 0U);
    assert_int_equal(w.ctrl.n.missing, 2);
    assert_int_equal(w.ctrl.n.max_consecutive, 2);
    assert_int_equal(w.ctrl.n.stale, 2);
    assert_int_equal(w.rx[C4G_CTRL_RX_STALE], 2);
    assert_int_equal(w.ctrl.n.replies_ok, 17 + 3);
    assert_int_equal(w.ctrl.fatal, 0);
    assert_int_equal(w.pc.counters.cyclic, 5 + 5);
    assert_clean_pc(&w);
}

/* The controller wakes 30 ms late: a reply that was there counts, a lost one is unjudged
 * (the controller's own fault), and the PC reports the silence and its end. */
static void test_ctrl_stall(void **st)
{
    world_t w;
    (void)st;
    world_init(&w, C4G_NUM_PLUS_ONE, C4G_NUM_PLUS_ONE);
    start(&w, 5U);
    tick(&w, 0U, 0U);
    pc_poll(&w, w.now + 25U * MS);
    tick(&w, F_DROP_REPLY, 30U * MS);
    assert_int_equal(w.verdicts[C4G_CTRL_J_OK], 17 + 1);
    pc_poll(&w, w.now + 30U * MS);
    tick(&w, F_SILENT, 30U * MS);
    assert_int_equal(w.verdicts[C4G_CTRL_J_UNJUDGED], 1);
    assert_int_equal(w.ctrl.n.unjudged, 1);
    assert_int_equal(w.ctrl.n.missing, 0);
    assert_true((w.pc_events & (C4G_EV_SILENCE | C4G_EV_RESUMED)) == (C4G_EV_SILENCE | C4G_EV_RESUMED));
    assert_int_equal(w.last_silence_ns, 32U * MS);
    assert_int_equal(w.pc.counters.silences, 1);
    assert_clean_pc(&w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_handshake),
        cmocka_unit_test(test_num_policies),
        cmocka_unit_test(test_num_wrap),
        cmocka_unit_test(test_exit_504),
        cmocka_unit_test(test_restart_506),
        cmocka_unit_test(test_active_freezing),
        cmocka_unit_test(test_passive_freezing),
        cmocka_unit_test(test_dropped),
        cmocka_unit_test(test_duplicated),
        cmocka_unit_test(test_reordered),
        cmocka_unit_test(test_pc_stall),
        cmocka_unit_test(test_ctrl_stall),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
