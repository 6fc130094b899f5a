/* SPDX-License-Identifier: MIT */
/* c4g-replay live: see live.h. Pass 1 reads the whole file through the analysis to find the
 * session and check that it has its start-up; each pass after it reads the file again and
 * plays the session from inside the analysis callback. The callback hands over a controller
 * packet once the next one is read, which is ahead of real time: the player sleeps in it
 * until the packet is due, so memory stays bounded whatever the capture's length. */
#include "live.h"

#include "c4gh_textfile.h"
#include "c4gh_udp.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netdb.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#define LV_LEAD_NS 1000000U  /* the first packet is due this long after the pass starts */
#define LV_GUARD_NS 150000U  /* stop polling the socket this long before a packet is due */
#define LV_DGRAM 2048U

static volatile sig_atomic_t g_stop;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

/* ---- options ------------------------------------------------------------- */

static int opt_to(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    lv_t *L = ctx;
    const char *colon = strrchr(v, ':');
    char host[256];
    long long port = 0;
    struct addrinfo hints, *res = NULL;
    int rc;
    (void)row;
    if (colon == NULL || colon == v || (size_t)(colon - v) >= sizeof host ||
        c4gh_tf_parse_int(colon + 1, 1, 65535, &port) != C4GH_TF_NUM_OK) {
        (void)snprintf(why, whylen, "want HOST:PORT");
        return -1;
    }
    memcpy(host, v, (size_t)(colon - v));
    host[colon - v] = '\0';
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    rc = getaddrinfo(host, NULL, &hints, &res);
    if (rc != 0 || res == NULL) {
        (void)snprintf(why, whylen, "want HOST:PORT; %s: %s", host, gai_strerror(rc));
        return -1;
    }
    memcpy(&L->to, res->ai_addr, sizeof L->to);
    freeaddrinfo(res);
    L->to.sin_port = htons((uint16_t)port);
    (void)snprintf(L->to_text, sizeof L->to_text, "%s", v);
    L->have_to = 1;
    return 0;
}

static int opt_policy(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    lv_t *L = ctx;
    (void)row;
    if (c4g_num_policy_parse(v, &L->policy) != C4G_OK) {
        (void)snprintf(why, whylen, "want plus-one, echo or either");
        return -1;
    }
    return 0;
}

static int opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_port(&((lv_t *)ctx)->c, row, v, why, whylen);
}

static int opt_tcycle1(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_tcycle1(&((lv_t *)ctx)->c, row, v, why, whylen);
}

/* ---- pass 1: which session, and can it be played -------------------------- */

static void on_scan(void *ctx, const c4gh_an_exchange_t *x)
{
    lv_t *L = ctx;
    lv_scan_t *sc;
    uint64_t last;
    if (x->s->id == 0U || x->s->id > C4GH_AN_MAX_SESSIONS) {
        return;
    }
    sc = &L->scan[x->s->id - 1U];
    if (x->s->id > L->n_scan) {
        L->n_scan = x->s->id;
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
static int choose(lv_t *L)
{
    unsigned i;
    const lv_scan_t *sc;
    if (L->session == 0U) {
        for (i = 0U; i < L->n_scan && L->chosen == 0U; i++) {
            if (L->scan[i].init > 0U) {
                L->chosen = i + 1U;
            }
        }
        if (L->chosen == 0U) {
            fprintf(stderr, RP_TOOL ": live: %s: no session with its start-up (%s): a PC server "
                    "cannot take a session up in the middle; 'c4g-replay rerun' replays it through "
                    "c4g-server's code without the handshake\n", L->path,
                    L->n_scan == 0U ? "no C4G Open packets found" : "the initialization packet is "
                    "not in the capture");
            return RP_EXIT_UNREADABLE;
        }
        return 0;
    }
    if (L->session > L->n_scan || L->scan[L->session - 1U].exchanges == 0U) {
        fprintf(stderr, RP_TOOL ": live: --session %u: %s has %u session%s\n", L->session, L->path,
                L->n_scan, L->n_scan == 1U ? "" : "s");
        return C4GH_CLI_EXIT_USAGE;
    }
    sc = &L->scan[L->session - 1U];
    if (sc->init == 0U) {
        fprintf(stderr, RP_TOOL ": live: --session %u: the session starts at a %s packet without "
                "its start-up (no initialization packet): a PC server cannot take it up in the "
                "middle; 'c4g-replay rerun' replays it through c4g-server's code\n", L->session,
                sc->first_kind == C4G_PKT_SYNC ? "synchronization" : "cyclic");
        return RP_EXIT_UNREADABLE;
    }
    L->chosen = L->session;
    return 0;
}

/* ---- the socket ------------------------------------------------------------ */

static int net_open(lv_t *L)
{
    struct sockaddr_in la;
    memset(&la, 0, sizeof la);
    la.sin_family = AF_INET;
    L->fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (L->fd < 0 || bind(L->fd, (struct sockaddr *)&la, sizeof la) != 0) {
        fprintf(stderr, RP_TOOL ": live: socket: %s\n", strerror(errno));
        return -1;
    }
    L->kstamp = c4gh_udp_enable(L->fd);
    return 0;
}

/* Everything that arrived, each datagram with its kernel arrival time; then the kernel send
 * time of our last packet. */
static void drain(lv_t *L)
{
    const uint64_t off = L->kstamp ? c4gh_udp_real_minus_mono() : 0U;
    uint8_t buf[LV_DGRAM];
    c4gh_udp_msg_t m;
    ssize_t n;
    while ((n = c4gh_udp_recv(L->fd, 0, off, buf, sizeof buf, &m)) >= 0) {
        const uint64_t now = c4gh_udp_now_ns();
        const uint64_t t = (m.stamp_ns != 0U && m.stamp_ns <= now) ? m.stamp_ns : now;
        if (m.from.sin_addr.s_addr != L->to.sin_addr.s_addr || m.from.sin_port != L->to.sin_port) {
            (void)c4g_ctrl_foreign(&L->cs);
            continue;
        }
        c4g_ctrl_rx_t r;
        (void)c4g_ctrl_reply(&L->cs, buf, (size_t)n, t, &r); /* never NULL: C4G_OK */
        if (r == C4G_CTRL_RX_ACCEPTED) {
            L->live_len = ((size_t)n <= sizeof L->live_raw) ? (size_t)n : sizeof L->live_raw;
            memcpy(L->live_raw, buf, L->live_len);
        }
    }
    while (L->kstamp && c4gh_udp_recv(L->fd, 1, off, buf, sizeof buf, &m) >= 0) {
        if (m.has_key && L->has_key && m.key == L->tx_key) {
            (void)c4g_ctrl_sent_stamp(&L->cs, m.stamp_ns, c4gh_udp_now_ns());
        }
    }
}

/* Wait for the socket at most until @p until (0 when the time has come). */
static void poll_until(lv_t *L, uint64_t until)
{
    const uint64_t now = c4gh_udp_now_ns();
    fd_set rf;
    struct timespec ts;
    if (now >= until) {
        return;
    }
    ts.tv_sec = (time_t)((until - now) / 1000000000U);
    ts.tv_nsec = (long)((until - now) % 1000000000U);
    FD_ZERO(&rf);
    FD_SET(L->fd, &rf);
    /* readable also when a send stamp waits in the error queue */
    if (pselect(L->fd + 1, &rf, NULL, NULL, &ts, NULL) > 0) {
        drain(L);
    }
}

/* Receive until @p t, then sleep to it on the absolute clock: the socket is polled only up to
 * a guard before it, so the wake-up that sends a packet is the precise one. */
static void wait_until(lv_t *L, uint64_t t)
{
    const uint64_t guard = LV_GUARD_NS + L->spin_ns;
    while (!g_stop) {
        const uint64_t now = c4gh_udp_now_ns();
        if (now + guard >= t) {
            break;
        }
        poll_until(L, t - guard);
    }
    if (!g_stop) {
        c4gh_udp_sleep_until(t - L->spin_ns, &g_stop);
    }
    /* A sleeping process wakes tens of us late (timer slack, CPU idle states, a virtual
     * machine's timer): the last stretch is a busy wait on the clock. */
    if (L->spin_ns > 0U) {
        drain(L);
        while (!g_stop && c4gh_udp_now_ns() < t) {
        }
    }
    drain(L);
}

/* --topspeed: until the reply came (or none is awaited), or until @p deadline. */
static void wait_reply(lv_t *L, uint64_t deadline)
{
    for (;;) {
        drain(L);
        if (!L->pend.check || L->pend.suspended || L->cs.out.got || g_stop ||
            c4gh_udp_now_ns() >= deadline) {
            return;
        }
        poll_until(L, deadline);
    }
}

/* ---- comparing a reply with the recorded one ------------------------------ */

static void divergence(lv_t *L, unsigned *nd, lv_field_t f, unsigned axis, const char *rec,
                       const char *got)
{
    const lv_pending_t *P = &L->pend;
    lv_first_t *F = &L->first;
    L->field[f]++;
    (*nd)++;
    if (F->set) {
        return;
    }
    F->set = 1;
    F->pass = L->pass;
    F->kind = P->kind;
    F->tick = P->tick;
    F->num = P->num;
    F->axis = axis;
    F->mode = (axis > 0U && axis <= P->n_modes) ? P->modes[axis - 1U] : -1;
    F->field = f;
    (void)snprintf(F->recorded, sizeof F->recorded, "%s", rec);
    (void)snprintf(F->received, sizeof F->received, "%s", got);
}

static void cmp_int(lv_t *L, unsigned *nd, lv_field_t f, unsigned axis, int64_t rec, int64_t got,
                    int hex)
{
    char a[24], b[24];
    if (rec == got) {
        return;
    }
    (void)snprintf(a, sizeof a, hex ? "0x%08llx" : "%lld", (long long)rec);
    (void)snprintf(b, sizeof b, hex ? "0x%08llx" : "%lld", (long long)got);
    divergence(L, nd, f, axis, a, b);
}

/* Exact: the same bits (so -0 differs from 0); with --tolerance: |difference| <= it. */
static void cmp_float(lv_t *L, unsigned *nd, lv_field_t f, unsigned axis, float rec, float got)
{
    char a[24], b[24];
    uint32_t ua, ub;
    memcpy(&ua, &rec, sizeof ua);
    memcpy(&ub, &got, sizeof ub);
    if (L->tolerance > 0.0 ? fabs((double)rec - (double)got) <= L->tolerance : ua == ub) {
        return;
    }
    (void)snprintf(a, sizeof a, "%.9g", (double)rec);
    (void)snprintf(b, sizeof b, "%.9g", (double)got);
    divergence(L, nd, f, axis, a, b);
}

/* The pending packet's reply was judged ok: @p live is its decoded form (cyclic). */
static void compare(lv_t *L, const c4g_pc_packet_t *live)
{
    const lv_pending_t *P = &L->pend;
    unsigned nd = 0U, i;
    L->compared++;
    if (!P->has_rec) {
        divergence(L, &nd, LV_F_REPLY, 0U, "none", "a valid reply");
    } else if (P->kind != C4G_PKT_CYCLIC) {
        cmp_int(L, &nd, LV_F_NUM, 0U, c4g_le_i32(P->rec_raw), c4g_le_i32(L->live_raw), 0);
        if (P->rec_len != L->live_len || memcmp(P->rec_raw + 4, L->live_raw + 4, P->rec_len - 4U) != 0) {
            char a[24], b[24];
            (void)snprintf(a, sizeof a, "%u bytes", (unsigned)P->rec_len);
            (void)snprintf(b, sizeof b, "%u bytes, other", (unsigned)L->live_len);
            divergence(L, &nd, LV_F_BODY, 0U, a, b);
        }
    } else if (!P->rec_decoded || live == NULL) {
        divergence(L, &nd, LV_F_REPLY, 0U, "not decodable", "a valid reply");
    } else {
        const c4g_pc_packet_t *r = &P->rec;
        cmp_int(L, &nd, LV_F_NUM, 0U, r->num, live->num, 0);
        cmp_int(L, &nd, LV_F_INFPAR, 0U, r->infpar, live->infpar, 1);
        cmp_int(L, &nd, LV_F_CMD, 0U, r->cmd, live->cmd, 1);
        for (i = 0U; i < r->n_axes && i < live->n_axes; i++) {
            const c4g_pc_axis_t *a = &r->ax[i], *b = &live->ax[i];
            unsigned k;
            cmp_int(L, &nd, LV_F_MODE, i + 1U, a->mode, b->mode, 0);
            cmp_float(L, &nd, LV_F_D1, i + 1U, a->target_pos, b->target_pos);
            cmp_float(L, &nd, LV_F_D2, i + 1U, a->target_vel, b->target_vel);
            cmp_float(L, &nd, LV_F_D3, i + 1U, a->measure, b->measure);
            cmp_float(L, &nd, LV_F_D4, i + 1U, a->vel_add, b->vel_add);
            cmp_float(L, &nd, LV_F_D5, i + 1U, a->current_add, b->current_add);
            for (k = 0U; k < 3U; k++) {
                cmp_float(L, &nd, (lv_field_t)(LV_F_EXT1 + k), i + 1U, a->ext[k], b->ext[k]);
            }
        }
    }
    if (nd > 0U) {
        L->differing++;
    } else if (P->rec_late) {
        L->timing_only++; /* the recording's reply came after the next packet; this one in time */
    }
}

/* The recorded reply to the pending packet came after the next controller packet (the
 * controller counted it missing): it is still what the recorded PC answered, so a reply
 * judged ok now is compared with it (a timing difference, not a divergence, when equal). */
static void on_late_rec(void *ctx, const c4gh_an_session_t *s, const uint8_t *d, size_t len, int64_t ns,
                        uint64_t frame)
{
    lv_t *L = ctx;
    lv_pending_t *P = &L->pend;
    const int32_t num = (len >= 4U) ? c4g_le_i32(d) : -1;
    const c4g_num_policy_t pol = (s->cs.detected >= 0) ? (c4g_num_policy_t)s->cs.detected : C4G_NUM_PLUS_ONE;
    (void)ns;
    (void)frame;
    if (!P->active || P->has_rec || len > sizeof P->rec_raw ||
        c4g_reply_num(P->num, pol) != num) {
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
static void judge(lv_t *L, uint64_t deadline, int own_short)
{
    lv_pending_t *P = &L->pend;
    c4g_ctrl_verdict_t v;
    uint64_t woke = c4gh_udp_now_ns();
    /* We sent the packet so late that the PC had less than its period: judged as our own
     * lateness (c4g_ctrl_judge): a reply that is there counts, none is unjudged, not missing. */
    if (own_short && woke <= deadline + L->tol_ns) {
        woke = deadline + L->tol_ns + 1U;
    }
    (void)c4g_ctrl_set_deadline(&L->cs, deadline); /* C4G_ERR_STATE: nothing outstanding */
    (void)c4g_ctrl_judge(&L->cs, woke, P->suspended != 0, &v); /* C4G_OK */
    if (!L->topspeed) {
        /* the kernel's send time when it came back, else the clock read before sendto */
        const uint64_t sent = L->cs.out.sent_ns;
        c4gh_hist_add(&L->err, (int64_t)(sent - P->sched_ns));
        L->drift_ns = (int64_t)(sent - P->sched_ns);
    }
    if (v == C4G_CTRL_J_OK) {
        const c4g_pc_packet_t *rep = NULL;
        c4gh_hist_add(&L->pass_lat, (int64_t)L->cs.last_lat_ns);
        (void)c4g_ctrl_take_reply(&L->cs, &rep); /* C4G_ERR_STATE: not cyclic, rep NULL */
        compare(L, rep);
    }
    P->active = 0;
}

/* The pending packet's window: up to the next packet (@p next_sched, due then; with
 * --topspeed its capture time @p next_rec_ns) or, when the capture shows a silence, one
 * period after it, as the controller judges at its next tick. */
static void close_pending(lv_t *L, uint64_t next_sched, int64_t next_rec_ns)
{
    lv_pending_t *P = &L->pend;
    uint64_t deadline;
    int own_short;
    if (L->topspeed) {
        uint64_t gap = (next_rec_ns > P->rec_ns) ? (uint64_t)(next_rec_ns - P->rec_ns) : 0U;
        if (gap > L->period_ns + L->period_ns / 2U) {
            gap = L->period_ns;
        }
        deadline = P->sent_ns + gap;
        wait_reply(L, deadline);
        judge(L, deadline, 0);
        return;
    }
    deadline = next_sched;
    if (next_sched > P->sched_ns + L->period_ns + L->period_ns / 2U) {
        deadline = P->sched_ns + L->period_ns;
    }
    /* Sent later than c4g-sim's margin (the host stalled us), the packet is not given a full
     * period (the packets behind catch up with the fixed schedule) but at least t-cycle1 for
     * its reply, and our lateness is not charged to the PC. */
    own_short = deadline < P->sent_ns + L->period_ns - L->tol_ns;
    if (deadline < P->sent_ns + L->window_ns) {
        deadline = P->sent_ns + L->window_ns;
    }
    wait_until(L, deadline);
    judge(L, deadline, own_short);
}

static void send_packet(lv_t *L, const c4gh_an_exchange_t *x, uint64_t sched)
{
    lv_pending_t *P = &L->pend;
    int check = 1;
    uint32_t i;
    uint64_t t;
    ssize_t n;
    const int32_t num = c4g_le_i32(x->ctrl);
    /* the controller does not wait for the reply to 504 (the analysis' rule) */
    for (i = 0U; x->rx != NULL && i < x->rx->n_axes; i++) {
        if (x->rx->ax[i].mode == C4G_MODE_EXIT_OPEN) {
            check = 0;
        }
    }
    L->live_len = 0U;
    t = c4gh_udp_now_ns();
    (void)c4g_ctrl_emit(&L->cs, x->kind, num, x->ctrl, x->ctrl_len, check != 0, t); /* a known kind */
    n = sendto(L->fd, x->ctrl, x->ctrl_len, 0, (const struct sockaddr *)&L->to, sizeof L->to);
    L->has_key = (n >= 0);
    if (n >= 0) {
        L->tx_key = L->tx_seq++; /* the kernel numbers every datagram sent, from 0 */
    } else if (L->send_errors++ == 0U) {
        (void)snprintf(L->send_error, sizeof L->send_error, "sendto: %s", strerror(errno));
    }
    L->sent++;
    L->sent_kind[x->kind]++;
    /* More than the margin late (the host stalled us): counted. The schedule stays on its
     * origin (no drift), so the packets behind catch up (close_pending). */
    if (!L->topspeed && t > sched && t - sched > L->tol_ns) {
        L->overruns++;
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

static void on_play(void *ctx, const c4gh_an_exchange_t *x)
{
    lv_t *L = ctx;
    uint64_t rel, sched;
    if (x->s->id != L->chosen || L->pass_done || g_stop) {
        return;
    }
    if (!L->started) {
        L->started = 1;
        L->first_rec_ns = x->ctrl_ns;
        L->origin_ns = c4gh_udp_now_ns() + LV_LEAD_NS;
        L->last_rel_ns = 0U;
    }
    rel = (x->ctrl_ns > L->first_rec_ns)
              ? (uint64_t)((double)(x->ctrl_ns - L->first_rec_ns) / L->speed) : 0U;
    if (rel < L->last_rel_ns) {
        rel = L->last_rel_ns; /* a capture clock that stepped back: never earlier than before */
    }
    L->last_rel_ns = rel;
    sched = L->origin_ns + rel;
    if (L->pend.active) {
        close_pending(L, sched, x->ctrl_ns);
    } else if (!L->topspeed) {
        wait_until(L, sched);
    }
    if (g_stop) {
        return;
    }
    if (!L->topspeed && sched > c4gh_udp_now_ns()) {
        wait_until(L, sched); /* the window closed at a deadline before the packet is due */
    }
    send_packet(L, x, sched);
}

/* One pass over the file: 0, or -1 when it could not be read. */
static int play_pass(lv_t *L)
{
    const lv_scan_t *sc = &L->scan[L->chosen - 1U];
    c4gh_an_options_t o = L->c.an;
    c4g_ctrl_config_t cfg;
    char err[390];
    c4gh_an_t a;
    c4gh_cap_t *c;
    c4gh_cap_pkt_t p;
    int ended = 0;
    memset(&cfg, 0, sizeof cfg);
    cfg.policy = L->policy;
    cfg.n_axes = sc->n_axes;
    cfg.t_cycle1_ns = L->c.an.t_cycle1_ns;
    cfg.tol_ns = L->tol_ns;
    cfg.max_miss = 10U;
    cfg.sync_before = 9U;
    cfg.sync_after = 2U;
    (void)c4g_ctrl_init(&L->cs, &cfg); /* n_axes from the analysis (<= 20): C4G_OK */
    memset(&L->pass_lat, 0, sizeof L->pass_lat);
    L->started = 0;
    L->pass_done = 0;
    L->pend.active = 0;
    o.on_exchange = on_play;
    o.on_late = on_late_rec;
    o.ctx = L;
    if (c4gh_an_init(&a, &o) != 0) {
        fprintf(stderr, RP_TOOL ": out of memory\n");
        return -1;
    }
    c = c4gh_cap_open(L->path, err, sizeof err);
    if (c == NULL) {
        fprintf(stderr, RP_TOOL ": %s\n", err);
        c4gh_an_free(&a);
        return -1;
    }
    while (!g_stop && !ended) {
        const c4gh_cap_res_t r = c4gh_cap_next(c, &p, err, sizeof err);
        if (r == C4GH_CAP_END || r == C4GH_CAP_FATAL) {
            break;
        }
        if (r == C4GH_CAP_DATAGRAM) {
            c4gh_an_datagram(&a, L->path, &p);
            /* the session's last packet and its reply are in: close it now rather than read
             * the rest of the file (other sessions) with the packet still waiting */
            ended = p.frame >= sc->stop_frame;
        }
    }
    if (!g_stop) {
        c4gh_an_file_end(&a, L->path);
    }
    if (L->pend.active && !g_stop) {
        const uint64_t settle = L->pend.sent_ns + L->period_ns;
        if (L->topspeed) {
            close_pending(L, 0U, L->pend.rec_ns + (int64_t)L->period_ns);
        } else {
            close_pending(L, L->pend.sched_ns + L->period_ns, 0);
        }
        /* the reply to an unchecked last packet (504) is counted in this pass, not taken
         * for a wrong reply to the next pass's first packet */
        while (!g_stop && c4gh_udp_now_ns() < settle) {
            poll_until(L, settle);
        }
        drain(L);
    }
    L->pass_done = 1;
    c4gh_cap_close(c);
    c4gh_an_free(&a);
    return 0;
}

/* Add one pass's counters to the totals. */
static void add_counters(c4g_ctrl_counters_t *t, const c4g_ctrl_counters_t *n, c4gh_hist_t *t_lat,
                         const c4gh_hist_t *n_lat)
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
    c4gh_hist_merge(t_lat, n_lat);
}

static int play(lv_t *L)
{
    const lv_scan_t *sc = &L->scan[L->chosen - 1U];
    const uint64_t b = L->c.an.t_cycle1_ns;
    const uint64_t start = c4gh_udp_now_ns();
    struct sigaction sa;
    L->period_ns = (uint64_t)((double)(sc->period_ms > 0 ? sc->period_ms : 2) * 1e6 /
                              (L->topspeed ? 1.0 : L->speed));
    /* a send later than min(t-cycle1, period - t-cycle1) could make a PC that answers within
     * t-cycle1 miss the next tick: c4g-sim's overrun margin */
    L->tol_ns = (b < L->period_ns) ? ((b < L->period_ns - b) ? b : L->period_ns - b)
                                   : L->period_ns / 2U;
    L->window_ns = (b < L->period_ns) ? b : L->period_ns;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    /* a normal process's timer slack (50 us) would be most of the send-time budget */
    (void)prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    if (net_open(L) != 0) {
        return -1;
    }
    fprintf(stderr, RP_TOOL ": live: session %u of %s (%llu packets, %.3f s) to %s, %u pass%s\n",
            L->chosen, L->path, (unsigned long long)sc->exchanges,
            (double)(sc->last_ns - sc->first_ns) * 1e-9, L->to_text, L->loops,
            L->loops == 1U ? "" : "es");
    for (L->pass = 1U; L->pass <= L->loops && !g_stop; L->pass++) {
        if (L->pass > 1U && L->gap_ms > 0U) {
            c4gh_udp_sleep_until(c4gh_udp_now_ns() + (uint64_t)L->gap_ms * 1000000U, &g_stop);
        }
        if (play_pass(L) != 0) {
            L->read_failed = 1;
            break;
        }
        add_counters(&L->n, &L->cs.n, &L->lat, &L->pass_lat);
        if (!g_stop) {
            L->passes_done++;
        }
    }
    L->interrupted = g_stop != 0;
    L->elapsed_ns = c4gh_udp_now_ns() - start;
    close(L->fd);
    return 0;
}

/* ---- the command -------------------------------------------------------------- */

static const char *const live_examples[] = {
    RP_TOOL " live field.pcap --to 127.0.0.1:1000",
    RP_TOOL " live field.pcap --to 10.2.12.1:1000 --speed 2 --json",
    RP_TOOL " live field.pcap --to 127.0.0.1:31000 --topspeed --loop 100 --tolerance 1e-6",
    NULL};

static const char live_epilogue[] =
    "Every datagram the controller sent in the session (synchronization, initialization,\n"
    "cyclic packets, with their recorded bytes) leaves at its recorded time after the first\n"
    "one, on an absolute clock; each reply is judged as the controller judges it (by its\n"
    "kernel arrival time, deadline the next packet's time) and, when ok, compared field by\n"
    "field with the recorded reply. Each pass is a full start-up: with --loop the server must\n"
    "accept a restarted controller (c4g-server --persist; a capture that does not end with\n"
    "504 also needs --loop-gap longer than the server's loss timeout).\n"
    "Exit status: 0 every reply ok and equal to the recorded one, 1 findings or divergences\n"
    "(or a socket error, or interrupted), 2 bad usage, an unreadable file or a session\n"
    "without its start-up.\n";

int rp_cmd_live(int argc, char **argv)
{
    lv_t *L;
    c4gh_cli_spec_t spec;
    c4gh_cli_result_t r;
    rp_file_t info;
    c4gh_an_t a;
    c4gh_an_options_t o;
    int first = 0, rc;
    L = calloc(1, sizeof *L);
    if (L == NULL) {
        fprintf(stderr, RP_TOOL ": out of memory\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    {
        const c4gh_cli_opt_t rows[] = {
            {"to", 't', C4GH_CLI_CALL, "HOST:PORT", "the PC server (required)", NULL, 0, 0, 0, opt_to, 0},
            {"speed", 0, C4GH_CLI_DOUBLE, "X", "time scale: 2 plays twice as fast (default 1)", &L->speed, 0,
             0.01, 1000, NULL, 0},
            {"topspeed", 0, C4GH_CLI_FLAG, NULL, "each packet as soon as the previous one's reply came",
             &L->topspeed, 0, 0, 0, NULL, 0},
            {"loop", 0, C4GH_CLI_UINT, "N", "play the session N times, each a full start-up (default 1)",
             &L->loops, 0, 1, 1000000, NULL, 0},
            {"loop-gap", 0, C4GH_CLI_UINT, "MS", "silence between two passes (default 0)", &L->gap_ms, 0, 0,
             3600000, NULL, 0},
            {"session", 's', C4GH_CLI_UINT, "N", "the session to play (default: the first with its start-up)",
             &L->session, 0, 1, C4GH_AN_MAX_SESSIONS, NULL, 0},
            {"t-cycle1", 0, C4GH_CLI_CALL, "US", "replies later than this count as late (default 500)", NULL,
             0, 0, 0, opt_tcycle1, 0},
            {"num-policy", 0, C4GH_CLI_CALL, "P", "reply NUM accepted: plus-one, echo, either (default)", NULL,
             0, 0, 0, opt_policy, 0},
            {"spin-us", 0, C4GH_CLI_UINT, "US", "busy-wait this long before each packet (default 100)",
             &L->spin_us, 0, 0, 100000, NULL, 0},
            {"tolerance", 0, C4GH_CLI_DOUBLE, "X", "floats equal within X (default 0: the same bits)",
             &L->tolerance, 0, 0, 1e30, NULL, 0},
            {"port", 'p', C4GH_CLI_CALL, "LIST", "PC ports of C4G Open flows in the file (default 1000,1001)",
             NULL, 0, 0, 0, opt_port, 0},
            {"json", 'j', C4GH_CLI_FLAG, NULL, "the report as one JSON object", &L->c.json, 0, 0, 0, NULL, 0},
        };
        rp_common_default(&L->c);
        L->policy = C4G_NUM_EITHER;
        L->loops = 1U;
        L->spin_us = 100U;
        L->fd = -1;
        memset(&spec, 0, sizeof spec);
        spec.tool = RP_TOOL;
        spec.command = "live";
        spec.usage = "Usage: " RP_TOOL " live FILE --to HOST:PORT [OPTIONS]\n"
                     "Play the controller's side of a recorded session to a running PC server over\n"
                     "UDP, check its replies as the controller would, compare them with the\n"
                     "recorded ones, and report the timing achieved.\n";
        spec.opts = rows;
        spec.n_opts = sizeof rows / sizeof rows[0];
        spec.examples = live_examples;
        spec.epilogue = live_epilogue;
        spec.operands_min = 1;
        spec.operands_max = 1;
        spec.permute = 1;
        r = c4gh_cli_parse(&spec, L, argc, argv, &first);
    }
    if (r != C4GH_CLI_RUN) {
        free(L);
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    if (!L->have_to) {
        fprintf(stderr, RP_TOOL ": live: --to HOST:PORT is required (the PC server to play to)\n");
        free(L);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (L->topspeed && L->speed > 0.0) {
        fprintf(stderr, RP_TOOL ": live: --speed and --topspeed exclude each other\n");
        free(L);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (L->speed <= 0.0) {
        L->speed = 1.0;
    }
    L->spin_ns = (uint64_t)L->spin_us * 1000U;
    L->path = argv[first];
    if (strcmp(L->path, "-") == 0) {
        fprintf(stderr, RP_TOOL ": live: reads the file once per pass: give a file, not - (standard input)\n");
        free(L);
        return C4GH_CLI_EXIT_USAGE;
    }
    o = L->c.an;
    o.on_exchange = on_scan;
    o.ctx = L;
    if (c4gh_an_init(&a, &o) != 0) {
        fprintf(stderr, RP_TOOL ": out of memory\n");
        free(L);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    rc = rp_read(&a, L->path, &info, 1);
    c4gh_an_free(&a);
    if (rc == 2) {
        free(L);
        return RP_EXIT_UNREADABLE;
    }
    rc = choose(L);
    if (rc == 0 && play(L) != 0) {
        rc = C4GH_CLI_EXIT_RUNTIME;
    } else if (rc == 0) {
        if (L->c.json) {
            lv_report_json(stdout, L);
        } else {
            lv_report_text(stdout, L);
        }
        rc = (lv_findings(L) > 0) ? RP_EXIT_FINDINGS : C4GH_CLI_EXIT_OK;
    }
    free(L);
    return rc;
}
