/* SPDX-License-Identifier: MIT */
/* c4g-sim's tick loop: at each tick, read what arrived, judge the previous packet's reply
 * (the library's controller end, lib/wire/c4g_ctrl.c), send the packet the handshake driver asks for, then
 * wait on an absolute grid for the next tick. */
#include <arpa/inet.h>
#include <string.h>

#include "app.h"
#include "c4gh_udp.h"
#include "c4gh_cli.h"

volatile sig_atomic_t g_stop;

/* ---- replies ------------------------------------------------------------- */

static void log_refused(const app_t *a, c4g_ctrl_rx_t r, size_t len)
{
    const c4g_ctrl_t *c = &a->cs;
    if (r == C4G_CTRL_RX_WRONG_NUM) {
        fprintf(stderr, "c4g-sim: reply NUM %d to packet NUM %d violates the %s policy\n",
                c->last_num, c->out.num, c4g_num_policy_name((int)c->cfg.policy));
    } else if (r == C4G_CTRL_RX_BAD_DECODE) {
        fprintf(stderr, "c4g-sim: bad reply (%u bytes): %s, field %s, axis %d, value %lld\n",
                (unsigned)len, c4g_strerror(c->last_diag.status), c4g_field_name(c->last_diag.field),
                c->last_diag.axis, (long long)c->last_diag.value);
    }
}

/* The init packet's field at byte offset @p off (its first 4-byte word), for the message. */
static const char *init_field_name(uint32_t off)
{
    static const struct {
        uint32_t at;
        c4g_field_t f;
    } map[] = {{0U, C4G_FIELD_NUM},
               {4U, C4G_FIELD_NFIELDPCK},
               {8U, C4G_FIELD_NFIELDAX},
               {12U, C4G_FIELD_NAXOPEN},
               {C4G_INIT_OFF_OPENMASK, C4G_FIELD_OPENMASK},
               {C4G_INIT_OFF_TYPES, C4G_FIELD_TYPES},
               {C4G_INIT_OFF_PERIOD, C4G_FIELD_PERIOD},
               {C4G_INIT_OFF_OPENAX, C4G_FIELD_OPENAX},
               {C4G_INIT_OFF_CALDATA, C4G_FIELD_CALDATA},
               {C4G_INIT_OFF_AZLIM, C4G_FIELD_AZLIM},
               {C4G_INIT_OFF_VERSION, C4G_FIELD_VERSION},
               {C4G_INIT_OFF_AXINFO, C4G_FIELD_AXINFO},
               {C4G_INIT_OFF_TXRATE, C4G_FIELD_TXRATE},
               {C4G_INIT_OFF_FOLLOWERROR, C4G_FIELD_FOLLOWERROR}};
    size_t k, best = 0;
    for (k = 0; k < sizeof map / sizeof map[0]; k++) {
        if (off >= map[k].at) {
            best = k;
        }
    }
    return c4g_field_name(map[best].f);
}

/* The PC echoed 1200 other bytes than the init packet sent: the limits the PC works with are
 * not the controller's (an injected or altered init packet). The session fails: nothing
 * the PC sends from here can be trusted to respect this controller's limits. */
static void bad_init_echo(app_t *a, const uint8_t *buf)
{
    const c4g_ctrl_outstanding_t *o = &a->cs.out;
    uint32_t off = 4U;
    while (off < C4G_INIT_SIZE && buf[off] == o->raw[off]) {
        off++;
    }
    {
        /* (off < 1200: c4g_ctrl_reply found a difference) */
        const uint32_t w = ((off < C4G_INIT_SIZE) ? off : C4G_INIT_SIZE - 1U) & ~3U;
        fprintf(stderr, "c4g-sim: the PC's init echo differs from the init packet sent at byte "
                "offset %u (field %s: sent 0x%02x%02x%02x%02x, echoed 0x%02x%02x%02x%02x, "
                "little-endian word): the PC holds other limits than this controller's; "
                "session failed\n", (unsigned)off, init_field_name(w), o->raw[w + 3U],
                o->raw[w + 2U], o->raw[w + 1U], o->raw[w], buf[w + 3U], buf[w + 2U],
                buf[w + 1U], buf[w]);
    }
    sim_raise(&a->sim, C4G_CERR_CONFIG, 0, 0);
    sim_all_drive_off(&a->sim);
    a->sim.fatal = 1;
}

void handle_rx(app_t *a, const uint8_t *buf, size_t len, const struct sockaddr_in *from,
               uint64_t t)
{
    c4g_ctrl_rx_t r;
    if (from->sin_addr.s_addr != a->srv.sin_addr.s_addr || from->sin_port != a->srv.sin_port) {
        (void)c4g_ctrl_foreign(&a->cs);
        if (a->o.verbose) {
            char ip[INET_ADDRSTRLEN];
            inet_ntop(AF_INET, &from->sin_addr, ip, sizeof ip);
            fprintf(stderr, "c4g-sim: ignored a datagram from foreign %s:%u\n", ip, ntohs(from->sin_port));
        }
        return;
    }
    (void)c4g_ctrl_reply(&a->cs, buf, len, t, &r); /* never NULL: C4G_OK */
    if (r == C4G_CTRL_RX_ACCEPTED) {
        /* --capture compares the reply's bytes with the recorded ones */
        a->rx_len = (len <= sizeof a->rx_raw) ? len : sizeof a->rx_raw;
        memcpy(a->rx_raw, buf, a->rx_len);
    }
    /* another length is a late or stray reply (a late sync reply passes the NUM check of
     * "either"): counted as malformed, as before; 1200 other bytes are the PC's limits (a
     * played capture's init packet is the recording's: an echo of other bytes is only a
     * malformed reply there, the model is not running) */
    if (r == C4G_CTRL_RX_BAD_INIT && len == C4G_INIT_SIZE && !a->sim.fatal && a->cap == NULL) {
        bad_init_echo(a, buf);
    }
    if (a->o.verbose) {
        log_refused(a, r, len);
    }
}

static void log_miss(const app_t *a, c4g_ctrl_verdict_t v, uint64_t woke)
{
    const c4g_ctrl_outstanding_t *o = &a->cs.out;
    const unsigned long row = a->cs.n.consecutive;
    if (v == C4G_CTRL_J_UNJUDGED) {
        fprintf(stderr, "c4g-sim: no reply to NUM %d by a deadline the simulator overran "
                        "itself (%.1f ms late; %lu in a row)\n", o->num,
                (double)(woke - o->deadline_ns) / 1e6, row);
        return;
    }
    fprintf(stderr, "c4g-sim: %s: %s (NUM %d, %lu in a row; ", c4g_ctrl_error_name(C4G_CERR_UDP_DEBUG),
            c4g_ctrl_error_message(C4G_CERR_UDP_DEBUG), o->num, row);
    if (o->got) {
        fprintf(stderr, "the reply came %.1f us after the packet, %.1f us after the deadline)\n",
                (double)(o->got_ns - o->sent_ns) / 1e3, (double)(o->got_ns - o->deadline_ns) / 1e3);
    } else {
        fprintf(stderr, "no reply %.1f us after the packet)\n", (double)(woke - o->sent_ns) / 1e3);
    }
}

/* At a tick boundary (woken at @p woke, everything that arrived is read): did the reply
 * to the outstanding packet arrive by its deadline? */
void judge(app_t *a, uint64_t woke)
{
    c4g_ctrl_verdict_t v;
    (void)c4g_ctrl_judge(&a->cs, woke, sim_checks_suspended(&a->sim) != 0, &v); /* C4G_OK */
    if (v == C4G_CTRL_J_OK) {
        c4gh_hist_add(&a->lat, (int64_t)a->cs.last_lat_ns);
    }
    if (v == C4G_CTRL_J_MISSING) {
        a->sim.udp_debug++; /* ERR_C4GOPEN_UDP_DEBUG: not fatal, not listed among the errors */
    }
    if ((v == C4G_CTRL_J_MISSING || v == C4G_CTRL_J_UNJUDGED) && a->o.verbose) {
        log_miss(a, v, woke);
    }
    if (a->cs.fatal) {
        sim_raise(&a->sim, C4G_CERR_UDP, 0, 0);
        sim_all_drive_off(&a->sim);
        a->sim.fatal = 1;
    }
}

static void emit(app_t *a, c4g_pkt_kind_t kind, int32_t num, const uint8_t *buf, size_t len, int check)
{
    (void)c4g_ctrl_emit(&a->cs, kind, num, buf, len, check != 0, now_ns()); /* kind is one of three */
    a->has_key = send_packet(a, buf, len, &a->tx_key);
}

/* ---- one tick per phase --------------------------------------------------- */

typedef struct loop {
    uint64_t deadline;
    unsigned long cyclic_ticks;
    unsigned long pause_left;
    long freeze_left;
    int ended;
} loop_t;

static void tick_sync(app_t *a)
{
    uint8_t buf[C4G_INIT_SIZE];
    size_t len = 0;
    c4g_ctrl_packet_t pkt;
    memset(&pkt, 0, sizeof pkt);
    pkt.num = c4g_ctrl_next_num(&a->cs);
    pkt.n_axes = (uint32_t)a->sim.n_axes;
    (void)c4g_ctrl_encode(&pkt, buf, sizeof buf, &len);
    emit(a, C4G_PKT_SYNC, pkt.num, buf, len, 1);
    (void)c4g_ctrl_advance(&a->cs);
}

static void tick_init(app_t *a)
{
    uint8_t buf[C4G_INIT_SIZE];
    size_t len = 0;
    a->sim.init.num = C4G_INIT_NUM;
    (void)c4g_init_encode(&a->sim.init, buf, sizeof buf, &len);
    emit(a, C4G_PKT_INIT, C4G_INIT_NUM, buf, len, 1);
    (void)c4g_ctrl_advance(&a->cs);
    a->sim.restart_req = 0;
}

/* Passive freezing (502, silence, 503) and --pause: 1 if this tick's packet goes out. */
static int tick_silence(app_t *a, loop_t *L)
{
    int send = 1;
    if (L->freeze_left > 0) {
        L->freeze_left--;
        a->sim.freeze_ticks = L->freeze_left;
        send = (L->freeze_left == 0);
    } else if (a->sim.freeze_ticks > 0) {
        L->freeze_left = a->sim.freeze_ticks; /* 502 goes out now, then silence */
    }
    if (L->pause_left > 0U) {
        L->pause_left--;
        a->st.paused_ticks++;
        send = 0;
    }
    return send;
}

static int tick_send(app_t *a, c4g_ctrl_packet_t *pkt)
{
    uint8_t buf[C4G_INIT_SIZE];
    size_t len = 0;
    if (c4g_ctrl_encode(pkt, buf, sizeof buf, &len) != C4G_OK) {
        fprintf(stderr, "c4g-sim: internal: packet not encodable\n");
        return 0;
    }
    emit(a, C4G_PKT_CYCLIC, pkt->num, buf, len, !a->sim.exit_open_req);
    (void)c4g_ctrl_advance(&a->cs);
    return 1;
}

/* After a cyclic tick: 1 if the run is over. */
static int run_over(const app_t *a, const loop_t *L)
{
    const sim_t *s = &a->sim;
    if (s->exit_open_req) {
        return 1; /* 504 sent: end of communication */
    }
    if (a->cfg.ticks != 0U && L->cyclic_ticks >= a->cfg.ticks) {
        return 1;
    }
    return s->scn != NULL && (s->scn_done || s->scn_aborted) && !a->cfg.hold && L->freeze_left == 0;
}

static void tick_cyclic(app_t *a, loop_t *L)
{
    const c4g_pc_packet_t *rep = NULL;
    c4g_ctrl_packet_t pkt;
    int send;
    (void)c4g_ctrl_take_reply(&a->cs, &rep); /* C4G_ERR_STATE: none, rep NULL */
    if (a->o.pause_len > 0U && L->cyclic_ticks == a->o.pause_at) {
        L->pause_left = a->o.pause_len;
        a->o.pause_len = 0;
    }
    if (L->freeze_left == 1) {
        a->sim.special_out = C4G_MODE_FREEZING_P_OUT;
    }
    sim_tick(&a->sim, rep, &pkt);
    L->cyclic_ticks++;
    send = tick_silence(a, L);
    pkt.num = c4g_ctrl_next_num(&a->cs);
    if (send) {
        send = tick_send(a, &pkt);
    }
    csv_row(a, &pkt, rep, send);
    if (!a->sim.exit_open_req && a->sim.restart_req && send) {
        (void)c4g_ctrl_restart(&a->cs); /* 506 sent: the init packet follows, no sync packets */
        return;
    }
    L->ended = run_over(a, L);
}

/* The simulator's own overrun: its packet left so late that a PC answering within
 * t-cycle1 could miss the next tick. No burst to catch up: the grid restarts at the
 * send, so the PC always gets its period. */
static void check_overrun(app_t *a, loop_t *L)
{
    const uint64_t t = now_ns();
    if (t > L->deadline && t - L->deadline > a->tol_ns) {
        a->st.overruns++;
        if (t - L->deadline > a->st.overrun_max) {
            a->st.overrun_max = t - L->deadline;
        }
        L->deadline = t;
    }
}

/* --lockstep: a packet whose reply is checked is outstanding (sync, init or cyclic: a
 * start-up reply the host delayed would cost a restart as surely as a cyclic one). */
static int lockstep_due(const app_t *a)
{
    const c4g_ctrl_outstanding_t *o = &a->cs.out;
    return a->o.lockstep && o->active && o->check;
}

/* --lockstep (a real C4G does not do this): the reply is awaited past the tick, up to
 * --lockstep-wait, and counts as on time; a reply that came after the tick sends the next
 * packet at once and the grid restarts there. Simulated time is one period per packet
 * whatever the wall clock did, so the plant sees the PC as always on time, and a model's
 * figures are apart from the host's scheduling. */
static void lockstep_wait(app_t *a, loop_t *L)
{
    const uint64_t bound = L->deadline + (uint64_t)a->o.lockstep_wait_ms * 1000000U;
    (void)c4g_ctrl_set_deadline(&a->cs, bound); /* lockstep_due: outstanding */
    window(a, L->deadline);
    if (!a->cs.out.got && !g_stop) {
        const int came = wait_own_reply(a, bound);
        const uint64_t t = now_ns();
        if (came) {
            a->st.lockstep_waits++;
            if (t - L->deadline > a->st.lockstep_wait_max) {
                a->st.lockstep_wait_max = t - L->deadline;
            }
        }
        L->deadline = t; /* never earlier than the period; after a wait, at once */
    }
}

/* Once a second on a terminal: where the run is (ticks of --ticks, replies, missing). */
static void progress(const app_t *a, const loop_t *L, unsigned long *shown)
{
    const unsigned long every = 1000UL / (unsigned long)a->cfg.period_ms;
    if (L->cyclic_ticks < *shown + every) {
        return;
    }
    *shown = L->cyclic_ticks;
    if (a->cfg.ticks != 0U) {
        c4gh_cli_progress("c4g-sim", "tick %lu of %lu (%.0f %%), replies ok %lu, missing %lu",
                     L->cyclic_ticks, a->cfg.ticks,
                     100.0 * (double)L->cyclic_ticks / (double)a->cfg.ticks, a->cs.n.replies_ok,
                     a->cs.n.missing);
    } else {
        c4gh_cli_progress("c4g-sim", "tick %lu (%.0f s), replies ok %lu, missing %lu", L->cyclic_ticks,
                     (double)L->cyclic_ticks * a->cfg.period_ms * 1e-3, a->cs.n.replies_ok,
                     a->cs.n.missing);
    }
}

void app_run(app_t *a)
{
    loop_t L;
    /* a progress line only for a person watching: stderr a terminal, no log lines on it */
    const int show = c4gh_cli_progress_wanted() && !a->o.quiet && !a->o.verbose;
    unsigned long shown = 0;
    memset(&L, 0, sizeof L);
    L.deadline = now_ns();
    while (!L.ended && !g_stop) {
        const uint64_t woke = now_ns();
        drain(a);
        judge(a, woke);
        if (a->sim.fatal) {
            break;
        }
        switch (c4g_ctrl_next_kind(&a->cs)) {
        case C4G_PKT_SYNC:
            tick_sync(a);
            break;
        case C4G_PKT_INIT:
            tick_init(a);
            break;
        case C4G_PKT_CYCLIC:
        default:
            tick_cyclic(a, &L);
            break;
        }
        check_overrun(a, &L);
        if (show) {
            progress(a, &L, &shown);
        }
        L.deadline += (uint64_t)a->cfg.period_ms * 1000000U;
        if (lockstep_due(a)) {
            lockstep_wait(a, &L);
        } else {
            (void)c4g_ctrl_set_deadline(&a->cs, L.deadline); /* C4G_ERR_STATE: nothing outstanding */
            window(a, L.deadline);
        }
        c4gh_udp_sleep_until(L.deadline, &g_stop);
    }
    if (show && shown > 0) {
        c4gh_cli_progress_end();
    }
    if (!a->sim.fatal) {
        const uint64_t woke = now_ns();
        drain(a); /* what arrived before the end (or the signal) is counted */
        if (!g_stop) {
            judge(a, woke); /* the last packet had its window */
        }
    }
}
