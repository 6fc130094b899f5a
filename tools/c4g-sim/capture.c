/* SPDX-License-Identifier: MIT */
/* c4g-sim --capture: see capture.h. The first reading goes through the whole file with the
 * analysis to find the session and check that it has its start-up; each pass after it reads
 * the file again and plays the session from inside the analysis callback. The callback
 * hands over a controller packet once the next one is read, which is ahead of real time:
 * the player sleeps in it until the packet is due, so memory stays bounded whatever the
 * capture's length. Sending, receiving, the foreign filter and the kernel timestamps are
 * c4g-sim's (net.c, handle_rx); the judgement is the library's controller end (c4g_ctrl_*). */
#include "capture.h"

#include "c4gh_cli.h"

#include "c4gh_udp.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/select.h>
#include <unistd.h>

#define CAP_LEAD_NS 1000000U  /* the first packet is due this long after the pass starts */
#define CAP_GUARD_NS 150000U  /* stop polling the socket this long before a packet is due */

static void cap_on_signal(int sig)
{
    g_stop = sig;
}

/* ---- the first reading: which session, and can it be played ------------------ */

static void on_scan(void *ctx, const c4gh_an_exchange_t *x)
{
    cap_t *C = ctx;
    cap_scan_t *sc;
    uint64_t last;
    if (x->s->id == 0U || x->s->id > C4GH_AN_MAX_SESSIONS) {
        return;
    }
    sc = &C->scan[x->s->id - 1U];
    if (x->s->id > C->n_scan) {
        C->n_scan = x->s->id;
    }
    if (sc->exchanges++ == 0U) {
        sc->first_kind = (int)x->kind;
        sc->first_ns = x->ctrl_ns;
    }
    sc->sync += (x->kind == C4G_PKT_SYNC);
    sc->init += (x->kind == C4G_PKT_INIT);
    sc->cyclic += (x->kind == C4G_PKT_CYCLIC);
    sc->last_ns = x->ctrl_ns;
    last = x->ctrl_frame;
    if (x->reply != NULL && x->reply_frame > last) {
        last = x->reply_frame;
    }
    sc->stop_frame = last;
    sc->n_axes = x->s->n_axes;
    sc->period_ms = x->s->have_init ? x->s->init.period_ms : 0;
}

/* 0, or the exit code after the error. */
static int choose(cap_t *C)
{
    unsigned i;
    const cap_scan_t *sc;
    if (C->o.session == 0U) {
        for (i = 0U; i < C->n_scan && C->chosen == 0U; i++) {
            if (C->scan[i].init > 0U) {
                C->chosen = i + 1U;
            }
        }
        if (C->chosen == 0U) {
            fprintf(stderr, "%s: %s: %s: no session with its start-up (%s): a PC server "
                    "cannot take a session up in the middle; 'c4g-replay rerun' replays it through "
                    "c4g-server's code without the handshake\n", C->tool, C->cmd, C->o.path,
                    C->n_scan == 0U ? "no C4G Open packets found" : "the initialization packet is "
                    "not in the capture");
            return EXIT_USAGE;
        }
        return 0;
    }
    if (C->o.session > C->n_scan || C->scan[C->o.session - 1U].exchanges == 0U) {
        fprintf(stderr, "%s: %s: --session %u: %s has %u session%s\n", C->tool, C->cmd, C->o.session,
                C->o.path,
                C->n_scan, C->n_scan == 1U ? "" : "s");
        return EXIT_USAGE;
    }
    sc = &C->scan[C->o.session - 1U];
    if (sc->init == 0U) {
        fprintf(stderr, "%s: %s: --session %u: the session starts at a %s packet without "
                "its start-up (no initialization packet): a PC server cannot take it up in the "
                "middle; 'c4g-replay rerun' replays it through c4g-server's code\n", C->tool, C->cmd,
                C->o.session,
                sc->first_kind == C4G_PKT_SYNC ? "synchronization" : "cyclic");
        return EXIT_USAGE;
    }
    C->chosen = C->o.session;
    return 0;
}

/* ---- waiting: c4g-sim's socket (net.c), its own clock ----------------------- */

/* Wait for the socket at most until @p until (0 when the time has come). */
static void poll_until(cap_t *C, uint64_t until)
{
    const uint64_t now = c4gh_now_ns();
    fd_set rf;
    struct timespec ts;
    if (now >= until) {
        return;
    }
    ts.tv_sec = (time_t)((until - now) / 1000000000U);
    ts.tv_nsec = (long)((until - now) % 1000000000U);
    FD_ZERO(&rf);
    FD_SET(C->app->fd, &rf);
    /* readable also when a send stamp waits in the error queue */
    if (pselect(C->app->fd + 1, &rf, NULL, NULL, &ts, NULL) > 0) {
        drain(C->app);
    }
}

/* Receive until @p t, then sleep to it on the absolute clock: the socket is polled only up to
 * a guard before it, so the wake-up that sends a packet is the precise one. */
static void wait_until(cap_t *C, uint64_t t)
{
    const uint64_t guard = CAP_GUARD_NS + C->spin_ns;
    while (!g_stop) {
        const uint64_t now = c4gh_now_ns();
        if (now + guard >= t) {
            break;
        }
        poll_until(C, t - guard);
    }
    if (!g_stop) {
        c4gh_udp_sleep_until(t - C->spin_ns, &g_stop);
    }
    /* A sleeping process wakes tens of us late (timer slack, CPU idle states, a virtual
     * machine's timer): the last stretch is a busy wait on the clock. */
    if (C->spin_ns > 0U) {
        drain(C->app);
        while (!g_stop && c4gh_now_ns() < t) {
        }
    }
    drain(C->app);
}

/* --topspeed: until the reply came (or none is awaited), or until @p deadline. */
static void wait_reply(cap_t *C, uint64_t deadline)
{
    for (;;) {
        drain(C->app);
        if (!C->pend.check || C->pend.suspended || C->app->cs.out.got || g_stop ||
            c4gh_now_ns() >= deadline) {
            return;
        }
        poll_until(C, deadline);
    }
}

/* ---- comparing a reply with the recorded one ------------------------------ */

static void divergence(cap_t *C, unsigned *nd, cap_field_t f, unsigned axis, const char *rec,
                       const char *got)
{
    const cap_pending_t *P = &C->pend;
    cap_first_t *F = &C->first;
    C->field[f]++;
    (*nd)++;
    if (F->set) {
        return;
    }
    F->set = 1;
    F->pass = C->pass;
    F->kind = P->kind;
    F->tick = P->tick;
    F->num = P->num;
    F->axis = axis;
    F->mode = (axis > 0U && axis <= P->n_modes) ? P->modes[axis - 1U] : -1;
    F->field = f;
    (void)snprintf(F->recorded, sizeof F->recorded, "%s", rec);
    (void)snprintf(F->received, sizeof F->received, "%s", got);
}

static void cmp_int(cap_t *C, unsigned *nd, cap_field_t f, unsigned axis, int64_t rec, int64_t got,
                    int hex)
{
    char a[24], b[24];
    if (rec == got) {
        return;
    }
    (void)snprintf(a, sizeof a, hex ? "0x%08llx" : "%lld", (long long)rec);
    (void)snprintf(b, sizeof b, hex ? "0x%08llx" : "%lld", (long long)got);
    divergence(C, nd, f, axis, a, b);
}

/* Exact: the same bits (so -0 differs from 0); with --tolerance: |difference| <= it. */
static void cmp_float(cap_t *C, unsigned *nd, cap_field_t f, unsigned axis, float rec, float got)
{
    char a[24], b[24];
    uint32_t ua, ub;
    memcpy(&ua, &rec, sizeof ua);
    memcpy(&ub, &got, sizeof ub);
    if (C->o.tolerance > 0.0 ? fabs((double)rec - (double)got) <= C->o.tolerance : ua == ub) {
        return;
    }
    (void)snprintf(a, sizeof a, "%.9g", (double)rec);
    (void)snprintf(b, sizeof b, "%.9g", (double)got);
    divergence(C, nd, f, axis, a, b);
}

/* The pending packet's reply was judged ok: @p live is its decoded form (cyclic). */
static void compare(cap_t *C, const c4g_pc_packet_t *live)
{
    const cap_pending_t *P = &C->pend;
    unsigned nd = 0U, i;
    C->compared++;
    if (!P->has_rec) {
        divergence(C, &nd, CAP_F_REPLY, 0U, "none", "a valid reply");
    } else if (P->kind != C4G_PKT_CYCLIC) {
        cmp_int(C, &nd, CAP_F_NUM, 0U, c4g_le_i32(P->rec_raw), c4g_le_i32(C->app->rx_raw), 0);
        if (P->rec_len != C->app->rx_len || memcmp(P->rec_raw + 4, C->app->rx_raw + 4, P->rec_len - 4U) != 0) {
            char a[24], b[24];
            (void)snprintf(a, sizeof a, "%u bytes", (unsigned)P->rec_len);
            (void)snprintf(b, sizeof b, "%u bytes, other", (unsigned)C->app->rx_len);
            divergence(C, &nd, CAP_F_BODY, 0U, a, b);
        }
    } else if (!P->rec_decoded || live == NULL) {
        divergence(C, &nd, CAP_F_REPLY, 0U, "not decodable", "a valid reply");
    } else {
        const c4g_pc_packet_t *r = &P->rec;
        cmp_int(C, &nd, CAP_F_NUM, 0U, r->num, live->num, 0);
        cmp_int(C, &nd, CAP_F_INFPAR, 0U, r->infpar, live->infpar, 1);
        cmp_int(C, &nd, CAP_F_CMD, 0U, r->cmd, live->cmd, 1);
        for (i = 0U; i < r->n_axes && i < live->n_axes; i++) {
            const c4g_pc_axis_t *a = &r->ax[i], *b = &live->ax[i];
            unsigned k;
            cmp_int(C, &nd, CAP_F_MODE, i + 1U, a->mode, b->mode, 0);
            cmp_float(C, &nd, CAP_F_D1, i + 1U, a->target_pos, b->target_pos);
            cmp_float(C, &nd, CAP_F_D2, i + 1U, a->target_vel, b->target_vel);
            cmp_float(C, &nd, CAP_F_D3, i + 1U, a->measure, b->measure);
            cmp_float(C, &nd, CAP_F_D4, i + 1U, a->vel_add, b->vel_add);
            cmp_float(C, &nd, CAP_F_D5, i + 1U, a->current_add, b->current_add);
            for (k = 0U; k < 3U; k++) {
                cmp_float(C, &nd, (cap_field_t)(CAP_F_EXT1 + k), i + 1U, a->ext[k], b->ext[k]);
            }
        }
    }
    if (nd > 0U) {
        C->differing++;
    } else if (P->rec_late) {
        C->timing_only++; /* the recording's reply came after the next packet; this one in time */
    }
}

/* The recorded reply to the pending packet came after the next controller packet (the
 * controller counted it missing): it is still what the recorded PC answered, so a reply
 * judged ok now is compared with it (a timing difference, not a divergence, when equal). */
static void on_late_rec(void *ctx, const c4gh_an_session_t *s, const uint8_t *d, size_t len, int64_t ns,
                        uint64_t frame)
{
    cap_t *C = ctx;
    cap_pending_t *P = &C->pend;
    const int32_t num = (len >= 4U) ? c4g_le_i32(d) : -1;
    const int pol = (s->cs.detected >= 0) ? s->cs.detected : C4G_NUM_PLUS_ONE;
    (void)ns;
    (void)frame;
    if (!P->active || P->has_rec || len > sizeof P->rec_raw ||
        c4g_reply_num(P->num, pol == C4G_NUM_ECHO ? C4G_NUM_ECHO : C4G_NUM_PLUS_ONE) != num) {
        return;
    }
    P->has_rec = 1;
    P->rec_late = 1;
    P->rec_len = len;
    memcpy(P->rec_raw, d, len);
    if (P->kind == C4G_PKT_CYCLIC) {
        P->rec_decoded = (c4g_pc_decode(d, len, s->cs.cfg.n_axes, &P->rec, NULL) == C4G_OK);
    }
}

/* ---- playing ---------------------------------------------------------------- */

/* Judge the pending packet at @p deadline and record its timing. */
static void cap_judge(cap_t *C, uint64_t deadline, int own_short)
{
    cap_pending_t *P = &C->pend;
    c4g_ctrl_verdict_t v;
    uint64_t woke = c4gh_now_ns();
    /* We sent the packet so late that the PC had less than its period: judged as our own
     * lateness (c4g_ctrl_judge): a reply that is there counts, none is unjudged, not missing. */
    if (own_short && woke <= deadline + C->tol_ns) {
        woke = deadline + C->tol_ns + 1U;
    }
    (void)c4g_ctrl_set_deadline(&C->app->cs, deadline);
    (void)c4g_ctrl_judge(&C->app->cs, woke, P->suspended != 0, &v);
    if (!C->o.topspeed) {
        /* the kernel's send time when it came back, else the clock read before sendto */
        const uint64_t sent = C->app->cs.out.sent_ns;
        c4gh_hist_add(&C->err, (int64_t)(sent - P->sched_ns));
        C->drift_ns = (int64_t)(sent - P->sched_ns);
    }
    if (v == C4G_CTRL_J_OK) {
        const c4g_pc_packet_t *reply = NULL;
        c4gh_hist_add(&C->app->lat, (int64_t)C->app->cs.last_lat_ns);
        (void)c4g_ctrl_take_reply(&C->app->cs, &reply);
        compare(C, reply);
    }
    P->active = 0;
}

/* The pending packet's window: up to the next packet (@p next_sched, due then; with
 * --topspeed its capture time @p next_rec_ns) or, when the capture shows a silence, one
 * period after it, as the controller judges at its next tick. */
static void close_pending(cap_t *C, uint64_t next_sched, int64_t next_rec_ns)
{
    cap_pending_t *P = &C->pend;
    uint64_t deadline;
    int own_short;
    if (C->o.topspeed) {
        uint64_t gap = (next_rec_ns > P->rec_ns) ? (uint64_t)(next_rec_ns - P->rec_ns) : 0U;
        if (gap > C->period_ns + C->period_ns / 2U) {
            gap = C->period_ns;
        }
        deadline = P->sent_ns + gap;
        wait_reply(C, deadline);
        cap_judge(C, deadline, 0);
        return;
    }
    deadline = next_sched;
    if (next_sched > P->sched_ns + C->period_ns + C->period_ns / 2U) {
        deadline = P->sched_ns + C->period_ns;
    }
    /* Sent later than c4g-sim's margin (the host stalled us), the packet is not given a full
     * period (the packets behind catch up with the fixed schedule) but at least t-cycle1 for
     * its reply, and our lateness is not charged to the PC. */
    own_short = deadline < P->sent_ns + C->period_ns - C->tol_ns;
    if (deadline < P->sent_ns + C->window_ns) {
        deadline = P->sent_ns + C->window_ns;
    }
    wait_until(C, deadline);
    cap_judge(C, deadline, own_short);
}

static void cap_send(cap_t *C, const c4gh_an_exchange_t *x, uint64_t sched)
{
    cap_pending_t *P = &C->pend;
    int check = 1;
    uint32_t i;
    uint64_t t;
    long n;
    const int32_t num = c4g_le_i32(x->ctrl);
    /* the controller does not wait for the reply to 504 (the analysis' rule) */
    for (i = 0U; x->rx != NULL && i < x->rx->n_axes; i++) {
        if (x->rx->ax[i].mode == C4G_MODE_EXIT_OPEN) {
            check = 0;
        }
    }
    C->app->rx_len = 0U;
    t = c4gh_now_ns();
    (void)c4g_ctrl_emit(&C->app->cs, x->kind, num, x->ctrl, x->ctrl_len, check != 0, t);
    n = net_sendto(C->app, x->ctrl, x->ctrl_len, &C->app->tx_key);
    C->app->has_key = (n >= 0);
    if (n < 0 && C->send_errors++ == 0U) {
        (void)snprintf(C->send_error, sizeof C->send_error, "sendto: %s", strerror(errno));
    }
    C->sent++;
    C->sent_kind[x->kind]++;
    /* More than the margin late (the host stalled us): counted. The schedule stays on its
     * origin (no drift), so the packets behind catch up (close_pending). */
    if (!C->o.topspeed && t > sched && t - sched > C->tol_ns) {
        C->overruns++;
    }
    memset(P, 0, sizeof *P);
    P->active = 1;
    P->kind = x->kind;
    P->tick = x->tick;
    P->num = num;
    P->check = check;
    P->suspended = x->s->frozen; /* what the analysis judged the recorded reply with */
    P->rec_ns = x->ctrl_ns;
    P->sched_ns = sched;
    P->sent_ns = t;
    if (x->reply != NULL && x->reply_len >= 4U) {
        P->has_rec = 1;
        P->rec_len = (x->reply_len <= sizeof P->rec_raw) ? x->reply_len : sizeof P->rec_raw;
        memcpy(P->rec_raw, x->reply, P->rec_len);
    }
    if (x->tx != NULL) {
        P->rec = *x->tx;
        P->rec_decoded = 1;
    }
    if (x->rx != NULL) {
        P->n_modes = x->rx->n_axes;
        for (i = 0U; i < x->rx->n_axes; i++) {
            P->modes[i] = x->rx->ax[i].mode;
        }
    }
}

/* This pass sent CAP_DEAD_PACKETS packets, all judged, and the target sent nothing back
 * (the counters are the pass's: c4g_ctrl_init at its start). */
static int nothing_answered(const cap_t *C)
{
    const c4g_ctrl_counters_t *n = &C->app->cs.n;
    return n->sync_sent + n->init_sent + n->cyclic_sent >= CAP_DEAD_PACKETS &&
           n->rx_total == n->foreign && !C->pend.active;
}

static void on_play(void *ctx, const c4gh_an_exchange_t *x)
{
    cap_t *C = ctx;
    uint64_t rel, sched;
    if (x->s->id != C->chosen || C->pass_done || g_stop) {
        return;
    }
    if (!C->started) {
        C->started = 1;
        C->first_rec_ns = x->ctrl_ns;
        C->origin_ns = c4gh_now_ns() + CAP_LEAD_NS;
        C->last_rel_ns = 0U;
    }
    rel = (x->ctrl_ns > C->first_rec_ns)
              ? (uint64_t)((double)(x->ctrl_ns - C->first_rec_ns) / C->o.speed) : 0U;
    if (rel < C->last_rel_ns) {
        rel = C->last_rel_ns; /* a capture clock that stepped back: never earlier than before */
    }
    C->last_rel_ns = rel;
    sched = C->origin_ns + rel;
    if (C->pend.active) {
        close_pending(C, sched, x->ctrl_ns);
    } else if (!C->o.topspeed) {
        wait_until(C, sched);
    }
    if (g_stop) {
        return;
    }
    if (nothing_answered(C)) {
        C->dead = 1;
        C->dead_ns = c4gh_now_ns() - C->origin_ns;
        C->pass_done = 1;
        return;
    }
    if (!C->o.topspeed && sched > c4gh_now_ns()) {
        wait_until(C, sched); /* the window closed at a deadline before the packet is due */
    }
    cap_send(C, x, sched);
}

/* One pass over the file: 0, or -1 when it could not be read. */
static int play_pass(cap_t *C)
{
    const cap_scan_t *sc = &C->scan[C->chosen - 1U];
    c4gh_an_options_t o = C->an;
    c4g_ctrl_config_t cfg;
    char err[390];
    c4gh_an_t a;
    c4gh_cap_t *c;
    c4gh_cap_pkt_t p;
    int ended = 0;
    memset(&cfg, 0, sizeof cfg);
    cfg.policy = C->policy;
    cfg.n_axes = sc->n_axes;
    cfg.t_cycle1_ns = C->an.t_cycle1_ns;
    cfg.tol_ns = C->tol_ns;
    cfg.max_miss = 10U;
    cfg.sync_before = 9U;
    cfg.sync_after = 2U;
    (void)c4g_ctrl_init(&C->app->cs, &cfg);
    C->started = 0;
    C->pass_done = 0;
    C->pend.active = 0;
    o.on_exchange = on_play;
    o.on_late = on_late_rec;
    o.ctx = C;
    if (c4gh_an_init(&a, &o) != 0) {
        fprintf(stderr, "%s: out of memory\n", C->tool);
        return -1;
    }
    c = c4gh_cap_open(C->o.path, err, sizeof err);
    if (c == NULL) {
        fprintf(stderr, "%s: %s\n", C->tool, err);
        c4gh_an_free(&a);
        return -1;
    }
    while (!g_stop && !ended && !C->dead) {
        const c4gh_cap_res_t r = c4gh_cap_next(c, &p, err, sizeof err);
        if (r == C4GH_CAP_END || r == C4GH_CAP_FATAL) {
            break;
        }
        if (r == C4GH_CAP_DATAGRAM) {
            c4gh_an_datagram(&a, C->o.path, &p);
            /* the session's last packet and its reply are in: close it now rather than read
             * the rest of the file (other sessions) with the packet still waiting */
            ended = p.frame >= sc->stop_frame;
        }
    }
    if (!g_stop && !C->dead) {
        c4gh_an_file_end(&a, C->o.path);
    }
    if (C->pend.active && !g_stop && !C->dead) {
        const uint64_t settle = C->pend.sent_ns + C->period_ns;
        if (C->o.topspeed) {
            close_pending(C, 0U, C->pend.rec_ns + (int64_t)C->period_ns);
        } else {
            close_pending(C, C->pend.sched_ns + C->period_ns, 0);
        }
        /* the reply to an unchecked last packet (504) is counted in this pass, not taken
         * for a wrong reply to the next pass's first packet */
        while (!g_stop && c4gh_now_ns() < settle) {
            poll_until(C, settle);
        }
        drain(C->app);
    }
    C->pass_done = 1;
    c4gh_cap_close(c);
    c4gh_an_free(&a);
    return 0;
}

/* Add one pass's counters to the totals. */
static void add_counters(c4g_ctrl_counters_t *t, const c4g_ctrl_counters_t *n)
{
    if (n->replies_ok > 0U && (t->replies_ok == 0U || n->lat_min < t->lat_min)) {
        t->lat_min = n->lat_min;
    }
    if (n->lat_max > t->lat_max) {
        t->lat_max = n->lat_max;
    }
    if (n->max_consecutive > t->max_consecutive) {
        t->max_consecutive = n->max_consecutive;
    }
    t->sync_sent += n->sync_sent;
    t->init_sent += n->init_sent;
    t->cyclic_sent += n->cyclic_sent;
    t->rx_total += n->rx_total;
    t->replies_ok += n->replies_ok;
    t->missing += n->missing;
    t->late += n->late;
    t->unjudged += n->unjudged;
    t->wrong_num += n->wrong_num;
    t->malformed += n->malformed;
    t->foreign += n->foreign;
    t->duplicates += n->duplicates;
    t->stale += n->stale;
    t->unexpected += n->unexpected;
    t->lat_sum += n->lat_sum;
}

static void play(cap_t *C)
{
    const cap_scan_t *sc = &C->scan[C->chosen - 1U];
    const uint64_t b = C->an.t_cycle1_ns;
    const uint64_t start = c4gh_now_ns();
    struct sigaction sa;
    C->period_ns = (uint64_t)((double)(sc->period_ms > 0 ? sc->period_ms : 2) * 1e6 /
                              (C->o.topspeed ? 1.0 : C->o.speed));
    /* a send later than min(t-cycle1, period - t-cycle1) could make a PC that answers within
     * t-cycle1 miss the next tick: c4g-sim's overrun margin */
    C->tol_ns = (b < C->period_ns) ? ((b < C->period_ns - b) ? b : C->period_ns - b)
                                   : C->period_ns / 2U;
    C->window_ns = (b < C->period_ns) ? b : C->period_ns;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = cap_on_signal;
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    /* a normal process's timer slack (50 us) would be most of the send-time budget */
    (void)prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    fprintf(stderr, "%s: %s: session %u of %s (%llu packets, %.3f s) to %s, %u pass%s\n", C->tool,
            C->cmd, C->chosen, C->o.path, (unsigned long long)sc->exchanges,
            (double)(sc->last_ns - sc->first_ns) * 1e-9, C->to_text, C->o.loops,
            C->o.loops == 1U ? "" : "es");
    for (C->pass = 1U; C->pass <= C->o.loops && !g_stop; C->pass++) {
        if (C->pass > 1U && C->o.gap_ms > 0U) {
            c4gh_udp_sleep_until(c4gh_now_ns() + (uint64_t)C->o.gap_ms * 1000000U, &g_stop);
        }
        if (play_pass(C) != 0) {
            C->read_failed = 1;
            break;
        }
        add_counters(&C->n, &C->app->cs.n);
        if (C->dead) {
            C->dead_pass = C->pass;
            break;
        }
        if (!g_stop) {
            C->passes_done++;
        }
    }
    C->interrupted = g_stop != 0;
    C->elapsed_ns = c4gh_now_ns() - start;
}

/* ---- the run ------------------------------------------------------------------ */

/* Options of the model that a played capture has no use for: refused, not ignored. */
static int model_options_given(const app_t *a)
{
    const app_opts_t *o = &a->o;
    sim_config_t d;
    int i, given = o->config_path != NULL || o->scenario_path != NULL || o->csv_path != NULL ||
                   o->pause_len > 0U || o->entry_fault != 0;
    for (i = 0; i < F_COUNT; i++) {
        given = given || o->fault_frac[i] > 0.0;
    }
    /* the configuration as the defaults but for what --capture uses */
    sim_config_default(&d);
    memcpy(d.server, a->cfg.server, sizeof d.server);
    d.port = a->cfg.port;
    memcpy(d.bind_addr, a->cfg.bind_addr, sizeof d.bind_addr);
    d.local_port = a->cfg.local_port;
    d.t_cycle1_us = a->cfg.t_cycle1_us;
    d.policy = a->cfg.policy;
    return given || memcmp(&d, &a->cfg, sizeof d) != 0;
}

int capture_options_misplaced(const app_t *a)
{
    const cap_opts_t *c = &a->o.cap;
    if (c->speed > 0.0 || c->topspeed || c->loops > 0U || c->gap_ms > 0U || c->session > 0U ||
        c->tolerance > 0.0 || c->spin_us != CAP_SPIN_UNSET || c->n_ports > 0U || c->as_replay_live) {
        fprintf(stderr, "c4g-sim: --session, --speed, --topspeed, --loop, --loop-gap, --spin-us, "
                "--tolerance, --capture-ports and --replay-live need --capture FILE\n");
        return 1;
    }
    return 0;
}

/* The first reading: 0, or the exit code after the error. */
static int scan_file(cap_t *C)
{
    c4gh_an_options_t o = C->an;
    c4gh_an_t an;
    c4gh_cap_t *c;
    c4gh_cap_pkt_t p;
    char err[390];
    o.on_exchange = on_scan;
    o.ctx = C;
    if (c4gh_an_init(&an, &o) != 0) {
        fprintf(stderr, "%s: out of memory\n", C->tool);
        return EXIT_RUNTIME;
    }
    c = c4gh_cap_open(C->o.path, err, sizeof err);
    if (c == NULL) {
        fprintf(stderr, "%s: %s\n", C->tool, err);
        c4gh_an_free(&an);
        return EXIT_USAGE;
    }
    for (;;) {
        const c4gh_cap_res_t r = c4gh_cap_next(c, &p, err, sizeof err);
        if (r == C4GH_CAP_END) {
            break;
        }
        if (r == C4GH_CAP_FATAL) {
            fprintf(stderr, "%s: %s\n", C->tool, err); /* what was read before is played */
            break;
        }
        if (r == C4GH_CAP_BAD) {
            if (c4gh_cap_counts(c)->bad <= 10U) {
                fprintf(stderr, "%s: %s\n", C->tool, err);
            }
        } else if (r == C4GH_CAP_DATAGRAM) {
            c4gh_an_datagram(&an, C->o.path, &p);
        }
    }
    if (c4gh_cap_counts(c)->bad > 10U) {
        fprintf(stderr, "%s: %s: %llu damaged frames in all (the first 10 shown)\n", C->tool, C->o.path,
                (unsigned long long)c4gh_cap_counts(c)->bad);
    }
    c4gh_an_file_end(&an, C->o.path);
    c4gh_cap_close(c);
    c4gh_an_free(&an);
    return 0;
}

/* The options into the player: 0, or EXIT_USAGE after the error. */
static int cap_setup(cap_t *C, app_t *a)
{
    const sim_config_t *cfg = &a->cfg;
    unsigned i;
    C->app = a;
    C->o = a->o.cap;
    C->tool = C->o.as_replay_live ? "c4g-replay" : "c4g-sim";
    C->cmd = C->o.as_replay_live ? "live" : "capture";
    if (model_options_given(a)) {
        fprintf(stderr, "%s: --capture plays a recorded controller: the model's options (INI file, "
                "scenario, axes, period, ticks, faults, CSV...) do not apply\n", C->tool);
        return EXIT_USAGE;
    }
    if (C->o.topspeed && C->o.speed > 0.0) {
        fprintf(stderr, "%s: %s: --speed and --topspeed exclude each other\n", C->tool, C->cmd);
        return EXIT_USAGE;
    }
    if (strcmp(C->o.path, "-") == 0) {
        fprintf(stderr, "%s: %s: reads the file once per pass: give a file, not - (standard input)\n",
                C->tool, C->cmd);
        return EXIT_USAGE;
    }
    if (C->o.speed <= 0.0) {
        C->o.speed = 1.0;
    }
    if (C->o.loops == 0U) {
        C->o.loops = 1U;
    }
    if (C->o.spin_us == CAP_SPIN_UNSET) {
        C->o.spin_us = 100U;
    }
    C->spin_ns = (uint64_t)C->o.spin_us * 1000U;
    C->policy = cfg->policy;
    (void)snprintf(C->to_text, sizeof C->to_text, "%s:%u", cfg->server, cfg->port);
    c4gh_an_options_default(&C->an);
    if (C->o.n_ports > 0U) {
        for (i = 0U; i < C->o.n_ports; i++) {
            C->an.ports[i] = C->o.ports[i];
        }
        C->an.n_ports = C->o.n_ports;
    }
    C->an.t_cycle1_ns = (uint64_t)cfg->t_cycle1_us * 1000U;
    return app_addresses(a);
}

static int cap_run(cap_t *C, app_t *a)
{
    int rc = cap_setup(C, a);
    if (rc == 0) {
        rc = scan_file(C);
    }
    if (rc == 0) {
        rc = choose(C);
    }
    if (rc != 0) {
        return rc;
    }
    if (net_open(a) != 0) {
        fprintf(stderr, "%s: %s: socket: %s\n", C->tool, C->cmd, strerror(errno));
        if (a->fd >= 0) {
            close(a->fd);
        }
        return EXIT_RUNTIME;
    }
    rc = outputs_open(a);
    if (rc != EXIT_OK) {
        close(a->fd);
        return rc;
    }
    play(C);
    outputs_close(a);
    close(a->fd);
    if (C->dead) {
        /* an error, not a figure of the report: said on stderr, even with --quiet */
        fprintf(stderr, "%s: %s: nothing answered on %s (is c4g-server running there?): "
                "stopped after %u packets (%.3f s) of pass %u without a datagram back\n",
                C->tool, C->cmd, C->to_text, CAP_DEAD_PACKETS, (double)C->dead_ns * 1e-9,
                C->dead_pass);
    }
    if (a->o.json) {
        cap_report_json(stdout, C);
    } else if (!a->o.quiet) {
        cap_report_text(stdout, C);
    }
    if (C->interrupted) {
        return (g_stop == SIGTERM) ? C4GH_CLI_EXIT_SIGTERM : C4GH_CLI_EXIT_SIGINT;
    }
    if (C->dead) {
        return EXIT_NO_ANSWER;
    }
    return cap_findings(C) ? EXIT_RUNTIME : (a->out_error ? EXIT_OUTPUT : EXIT_OK);
}

int capture_main(app_t *a)
{
    int rc;
    /* the scan table and the histograms: too big for the stack */
    cap_t *C = calloc(1, sizeof *C);
    if (C == NULL) {
        fprintf(stderr, "c4g-sim: out of memory\n");
        return EXIT_RUNTIME;
    }
    a->cap = C;
    rc = cap_run(C, a);
    a->cap = NULL;
    free(C);
    return rc;
}
