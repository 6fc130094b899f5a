/* SPDX-License-Identifier: MIT */
/* The server's per-datagram step, the same on the socket and over a capture (--capture,
 * which c4g-replay rerun runs), so a capture is answered with exactly the code the server ran:
 * c4g_loop_rx (session trust checks, control step) -> refusals and session events ->
 * behaviours (c4g_srv_behave.c) -> c4g_loop_reply (safety filter, encoding) -> counters.
 * Time comes only from the caller's timestamps and log lines go to the caller's logger,
 * so the same datagrams at the same times give the same replies. */
#include "srv_core.h"

#include <stdio.h>
#include <string.h>

void srv_log(srv_t *S, uint64_t t_ns, const char *fmt, ...)
{
    va_list ap;
    if (S->log_fn == NULL) {
        return;
    }
    va_start(ap, fmt);
    S->log_fn(S->log_ctx, t_ns, fmt, ap);
    va_end(ap);
}

c4g_status_t srv_init(srv_t *S, const srv_config_t *cfg, srv_log_fn log_fn, void *log_ctx)
{
    c4g_status_t st;
    if (S == NULL || cfg == NULL) {
        return C4G_ERR_NULL;
    }
    if (cfg == &S->cfg) {
        return C4G_ERR_ARG; /* cleared below before it is copied */
    }
    memset(S, 0, sizeof *S);
    S->cfg = *cfg;
    S->log_fn = log_fn;
    S->log_ctx = log_ctx;
    (void)c4g_session_config_default(&S->loop_cfg.session);
    (void)c4g_engine_config_default(&S->loop_cfg.engine);
    S->loop_cfg.session.num_policy = S->cfg.num_policy;
    S->loop_cfg.session.lost_timeout_ns = S->cfg.lost_timeout_ns;
    S->loop_cfg.session.az_lim_max = (float)S->cfg.az_lim_max;
    S->loop_cfg.session.follow_error_max = (float)S->cfg.fe_max;
    S->loop_cfg.engine.start_ns = (uint64_t)(S->cfg.arm[0].scs * 1e9);
    st = c4g_loop_init(&S->loop, &S->loop_cfg);
    if (st == C4G_OK) {
        srv_behave_reset(S);
    }
    return st;
}

void srv_counters_add(c4g_counters_t *sum, const c4g_counters_t *c)
{
    uint32_t k;
    sum->rx += c->rx;
    sum->tx += c->tx;
    sum->sync += c->sync;
    sum->init += c->init;
    sum->cyclic += c->cyclic;
    sum->gaps += c->gaps;
    sum->missed += c->missed;
    sum->duplicates += c->duplicates;
    sum->out_of_order += c->out_of_order;
    sum->malformed_total += c->malformed_total;
    for (k = 0U; k < C4G_MAL_COUNT_; k++) {
        sum->malformed[k] += c->malformed[k];
    }
    sum->lost_events += c->lost_events;
    sum->foreign_total += c->foreign_total;
    for (k = 0U; k < C4G_FOREIGN_COUNT_; k++) {
        sum->foreign[k] += c->foreign[k];
    }
    sum->silences += c->silences;
    sum->init_conflicts += c->init_conflicts;
    sum->contended += c->contended;
    sum->new_peers += c->new_peers;
    sum->end_unexpected += c->end_unexpected;
    sum->refused += c->refused;
    sum->sync_excess += c->sync_excess;
    if (c->longest_silence_ns > sum->longest_silence_ns) {
        sum->longest_silence_ns = c->longest_silence_ns;
    }
}

/* A session --persist ended with 504 gives way to a new one once its reply is out (the
 * caller's moni row and send time still read the ended session). */
static void settle(srv_t *S)
{
    if (S->restart_due) {
        S->restart_due = 0;
        srv_counters_add(&S->done, srv_counters(S)); /* the exit report adds every session */
        (void)c4g_loop_init(&S->loop, &S->loop_cfg);
    }
}

/* "a.b.c.d:port" (or "[ipv6]:port"): the sender in log lines. */
static void endpoint_text(const c4g_endpoint_t *e, char *buf, size_t cap)
{
    if (e == NULL) {
        (void)snprintf(buf, cap, "?");
    } else if (e->addr_len == 4U) {
        (void)snprintf(buf, cap, "%u.%u.%u.%u:%u", (unsigned)e->addr[0], (unsigned)e->addr[1],
                       (unsigned)e->addr[2], (unsigned)e->addr[3], (unsigned)e->port);
    } else {
        size_t n = 0U;
        uint32_t k;
        (void)snprintf(buf, cap, "[");
        for (k = 0U; k + 1U < 16U && k + 1U < e->addr_len; k += 2U) {
            n = strlen(buf);
            (void)snprintf(buf + n, cap - n, "%s%x", k ? ":" : "",
                           (unsigned)e->addr[k] << 8 | (unsigned)e->addr[k + 1U]);
        }
        n = strlen(buf);
        (void)snprintf(buf + n, cap - n, "]:%u", (unsigned)e->port);
    }
}

static void log_foreign(srv_t *S, const c4g_endpoint_t *from, size_t len, uint64_t t)
{
    if (srv_counters(S)->foreign_total <= 10U || S->cfg.verbose) {
        char a[64];
        endpoint_text(from, a, sizeof a);
        srv_log(S, t, "dropped %zu-byte datagram from %s: not the controller's endpoint", len, a);
    }
}

void srv_drop(srv_t *S, const uint8_t *in, size_t len, const c4g_endpoint_t *from, uint64_t t_ns)
{
    c4g_loop_event_t ev;
    settle(S);
    (void)c4g_loop_rx(&S->loop, in, len, t_ns, from, &ev); /* counted */
    log_foreign(S, from, len, t_ns);
}

/* Silence and loss events of the session, whether c4g_loop_poll found them or
 * c4g_loop_rx did before it classified a datagram (a stream of refused datagrams
 * keeps the socket busy: the loss must not wait for a quiet moment). */
static srv_stop_t time_events(srv_t *S, uint32_t ev, uint64_t t)
{
    const c4g_loop_state_t s = srv_state(S);
    if ((ev & C4G_EV_SILENCE) != 0U) {
        srv_log(S, t, "controller silent for more than %.1f ms: session kept",
                (double)s.silence_ns * 1e-6);
    }
    if ((ev & C4G_EV_LOST) != 0U) {
        srv_log(S, t, "controller lost: no packet for %.1f ms", (double)s.lost_timeout_ns * 1e-6);
        if (!S->cfg.persist) {
            return SRV_STOP_LOST;
        }
        srv_log(S, t, "waiting for the controller's next start-up");
    }
    return SRV_STOP_NONE;
}

srv_stop_t srv_idle(srv_t *S, uint64_t t_ns)
{
    uint32_t ev = 0U;
    uint64_t next;
    settle(S);
    (void)c4g_loop_poll(&S->loop, t_ns, &ev, &next);
    return time_events(S, ev, t_ns);
}

uint64_t srv_deadline(const srv_t *S)
{
    uint64_t next = C4G_NO_DEADLINE;
    if (S->restart_due) {
        return 0U; /* settle() is due: poll now */
    }
    (void)c4g_loop_deadline(&S->loop, &next);
    return next;
}

/* A diagnostic's raw value as text: the float of a float field, else the integer. */
static void diag_value(const c4g_diag_t *d, char *buf, size_t cap)
{
    switch (d->field) {
    case C4G_FIELD_CALDATA:
    case C4G_FIELD_AZLIM:
    case C4G_FIELD_AXINFO:
    case C4G_FIELD_TXRATE:
    case C4G_FIELD_FOLLOWERROR: {
        const uint32_t u = (uint32_t)d->value;
        float f;
        memcpy(&f, &u, sizeof f);
        (void)snprintf(buf, cap, "%g", (double)f);
        break;
    }
    default:
        (void)snprintf(buf, cap, "%lld", (long long)d->value);
        break;
    }
}

/* "arm A axis L" of an init diagnostic (1-based), or "" for a field of the header. */
static void diag_axis(const c4g_diag_t *d, char *buf, size_t cap)
{
    if (d->arm >= 0 && d->axis >= 0) {
        (void)snprintf(buf, cap, " of arm %d axis %d", (int)d->arm + 1, (int)d->axis + 1);
    } else {
        buf[0] = '\0';
    }
}

/* The events that refuse the session, or an init packet above the ceilings: logged. 1 when
 * the datagram was one of them. */
static int refusals(srv_t *S, size_t len, const c4g_endpoint_t *from, uint64_t t,
                    const c4g_loop_event_t *ev, bool ceiling)
{
    const uint32_t e = ev->events;
    const c4g_counters_t *c;
    c4g_loop_state_t s;
    char v[48], ax[40], a[64], p[64];
    /* every answered packet comes here: nothing is formatted or copied unless one is due */
    if (!ceiling && (e & (C4G_EV_INIT_CONFLICT | C4G_EV_CONTENDED | C4G_EV_SYNC_EXCESS |
                          C4G_EV_REFUSED)) == 0U) {
        return 0;
    }
    s = srv_state(S);
    c = srv_counters(S);
    diag_value(&ev->diag, v, sizeof v);
    diag_axis(&ev->diag, ax, sizeof ax);
    if (ceiling) {
        const bool az = ev->diag.field == C4G_FIELD_AZLIM;
        srv_log(S, t, "refused the initialization packet: %s%s is %s %s, above this cell's "
                "ceiling %g %s (--%s)", c4g_field_name(ev->diag.field), ax, v, az ? "A" : "turns",
                az ? S->cfg.az_lim_max : S->cfg.fe_max, az ? "A" : "turns",
                az ? "az-lim-max" : "fe-max");
        return 1;
    }
    if ((e & C4G_EV_INIT_CONFLICT) != 0U) {
        srv_log(S, t, "ATTACK? init conflict: a second initialization packet differs from the "
                "one accepted (%s%s: %s, offset %u): both refused; no reply until the "
                "controller is silent for %.0f ms", c4g_field_name(ev->diag.field), ax, v,
                (unsigned)ev->diag.offset, (double)s.lost_timeout_ns * 1e-6);
        return 1;
    }
    if ((e & C4G_EV_CONTENDED) != 0U) {
        endpoint_text(from, a, sizeof a);
        endpoint_text(&s.peer, p, sizeof p);
        srv_log(S, t, "ATTACK? start-up contended: a %zu-byte start-up packet from %s while "
                "%s's start-up runs: both refused; no reply until the controller is silent "
                "for %.0f ms", len, a, p, (double)s.lost_timeout_ns * 1e-6);
        return 1;
    }
    if ((e & C4G_EV_SYNC_EXCESS) != 0U) {
        if (c->sync_excess <= 10U || S->cfg.verbose) {
            srv_log(S, t, "dropped a %zu-byte sync: more than %u before an init packet, not "
                    "answered", len, (unsigned)C4G_SYNC_REPLY_BUDGET);
        }
        return 1;
    }
    if ((e & C4G_EV_REFUSED) != 0U) {
        if (c->refused <= 10U || S->cfg.verbose) {
            srv_log(S, t, "dropped a %zu-byte datagram: the session is refused", len);
        }
        return 1;
    }
    return 0;
}

/* Datagrams the session refused or that need no answer: logged. 1 when nothing is due. */
static int refused(srv_t *S, const uint8_t *in, size_t len, const c4g_endpoint_t *from,
                   uint64_t t, const c4g_loop_event_t *ev, bool ceiling)
{
    const uint32_t e = ev->events;
    if (refusals(S, len, from, t, ev, ceiling)) {
        return 1;
    }
    if ((e & C4G_EV_FOREIGN) != 0U) {
        log_foreign(S, from, len, t);
        return 1;
    }
    if ((e & C4G_EV_RESUMED) != 0U) {
        srv_log(S, t, "controller back after %.1f ms of silence", (double)ev->silence_ns * 1e-6);
    }
    if ((e & (C4G_EV_DUPLICATE | C4G_EV_OUT_OF_ORDER)) != 0U && ev->kind == C4G_RX_DROPPED) {
        c4g_peek_t pk;
        if (c4g_peek(in, len, false, &pk) != C4G_OK) {
            pk.num = -1;
        }
        srv_log(S, t, "dropped %s packet NUM %d (newest %d): not answered",
                (e & C4G_EV_DUPLICATE) ? "duplicate" : "stale", (int)pk.num,
                (int)srv_state(S).last_num);
        return 1;
    }
    if ((e & C4G_EV_MALFORMED) != 0U && ev->diag.status == C4G_ERR_STATE) {
        srv_log(S, t, "refused a %zu-byte initialization packet mid-session (NUM %lld): "
                "accepted only at start-up or after 506", len, (long long)ev->diag.value);
        return 1;
    }
    if ((e & C4G_EV_MALFORMED) != 0U) {
        srv_log(S, t, "dropped malformed %zu-byte datagram: %s (field %s, offset %u, axis %d, value %lld)",
                len, c4g_strerror(ev->diag.status), c4g_field_name(ev->diag.field),
                (unsigned)ev->diag.offset, (int)ev->diag.axis, (long long)ev->diag.value);
        return 1;
    }
    return 0;
}

/* The session's events on a datagram that is answered. */
static void session_events(srv_t *S, const c4g_loop_event_t *ev, uint64_t t)
{
    const c4g_loop_state_t s = srv_state(S);
    const c4g_init_t *init = srv_init_packet(S);
    const uint32_t e = ev->events;
    if ((e & C4G_EV_LOST) != 0U && ev->kind == C4G_RX_CYCLIC) {
        S->stats.long_gaps++; /* a packet did come: a long gap, not a lost controller */
        srv_log(S, t, "long gap: more than %.1f ms without a packet",
                (double)s.lost_timeout_ns * 1e-6);
    }
    if ((e & C4G_EV_INIT) != 0U) {
        S->stats.inits++;
        srv_behave_init(S, t);
        srv_log(S, t, "init packet: %u open axes, period %d ms, version %d.%d.%d",
                (unsigned)srv_map(S)->n_axes, (int)init->period_ms, (int)init->version_major,
                (int)init->version_minor, (int)init->version_build);
    }
    if ((e & C4G_EV_RESTART) != 0U) {
        S->stats.restarts++;
        srv_log(S, t, "506: client restart, a new init packet follows");
    }
    if ((e & C4G_EV_FREEZE_IN) != 0U) {
        S->stats.frozen_passive++;
        srv_log(S, t, "502: passive freezing (loss check suspended)");
    }
    if ((e & C4G_EV_FREEZE_OUT) != 0U) {
        srv_log(S, t, "503: passive freezing over");
    }
    if ((e & C4G_EV_DRIVES) != 0U) {
        srv_log(S, t, "drives: INFPAR MOVING mask now 0x%x", (unsigned)s.drives);
    }
    if ((e & C4G_EV_CYCLIC_START) != 0U) {
        srv_log(S, t, "cyclic communication started");
    }
}

/* The reply to a cyclic packet: the controllers fill what the loop prepared, the loop
 * filters and encodes it (neutral when it cannot). A reply --skip-replies holds back is
 * still finished, so that the control engine sees every tick as the controller does, but
 * not encoded (zero capacity). True when out holds a reply to send. */
static bool reply_cyclic(srv_t *S, const c4g_loop_event_t *ev, uint64_t t_rx, uint8_t *out,
                         size_t cap, size_t *olen, srv_verdict_t *v)
{
    const uint64_t k = srv_counters(S)->cyclic;
    const bool skip = S->cfg.skip_at > 0U && k >= S->cfg.skip_at &&
                      k < S->cfg.skip_at + S->cfg.skip_count;
    c4g_engine_report_t rep;
    c4g_status_t st;
    S->cyc_k = k;
    S->thaw = S->thaw_due;
    S->thaw_due = 0;
    if (ev->cmd != NULL) {
        srv_behave(S, ev, t_rx);
    }
    st = c4g_loop_reply(&S->loop, out, skip ? 0U : cap, olen, &rep);
    if (ev->cmd != NULL) {
        srv_behave_done(S, &rep, t_rx);
    }
    if (skip) {
        S->stats.skipped++;
        v->skipped = true;
        return false;
    }
    return st == C4G_OK;
}

/* The reply due (sync/init echo or cyclic reply), and whether active freezing pauses. */
static void answer(srv_t *S, const c4g_loop_event_t *ev, uint64_t t_rx, uint8_t *out,
                   size_t cap, size_t *olen, srv_verdict_t *v)
{
    if (ev->kind == C4G_RX_SYNC || ev->kind == C4G_RX_INIT) {
        v->send = (c4g_loop_reply(&S->loop, out, cap, olen, NULL) == C4G_OK);
    } else if (ev->kind == C4G_RX_CYCLIC) {
        v->send = reply_cyclic(S, ev, t_rx, out, cap, olen, v);
        v->pkt = ev->pkt;
        if (S->cfg.freeze_at == srv_counters(S)->cyclic &&
            srv_reply_packet(S)->ax[0].mode == C4G_MODE_FREEZING_A) {
            S->stats.freezes++;
            S->thaw_due = 1;
            v->freeze = true;
            v->pause_ms = S->cfg.freeze_ms;
        }
    }
}

/* The session's clock events on the datagram. SRV_STOP_LOST ends the run before any
 * answer. */
static srv_stop_t rx_time_events(srv_t *S, const c4g_loop_event_t *ev, int was_lost,
                                 const c4g_endpoint_t *from, const c4g_endpoint_t *old_peer,
                                 uint64_t t)
{
    if (ev->kind != C4G_RX_CYCLIC) {
        /* the session checks the clock before it classifies a datagram: a loss it found
         * there ends the session (without --persist) whether the datagram was refused or
         * opens a new start-up, which is then not answered. A cyclic packet of the
         * controller after the loss timeout is a long gap (session_events). */
        if (time_events(S, ev->events, t) != SRV_STOP_NONE) {
            return SRV_STOP_LOST;
        }
        if (ev->kind == C4G_RX_SYNC && (was_lost || (ev->events & C4G_EV_LOST) != 0U)) {
            char a[64];
            endpoint_text(from, a, sizeof a);
            srv_log(S, t, "new start-up from %s: a new session", a);
        }
        if ((ev->events & C4G_EV_NEW_PEER) != 0U) {
            char a[64], o[64];
            endpoint_text(from, a, sizeof a);
            endpoint_text(old_peer, o, sizeof o);
            srv_log(S, t, "new peer: the session is now locked to %s, not to the lost "
                    "controller %s (a cold restart from a new port, or another sender)", a, o);
        }
    } else if ((ev->events & C4G_EV_SILENCE) != 0U) {
        (void)time_events(S, C4G_EV_SILENCE, t);
    }
    return SRV_STOP_NONE;
}

c4g_status_t srv_process(srv_t *S, const uint8_t *in, size_t len, const c4g_endpoint_t *from,
                         uint64_t t_rx_ns, uint8_t *out, size_t cap, size_t *out_len,
                         srv_verdict_t *v)
{
    c4g_loop_event_t ev;
    c4g_status_t st;
    c4g_endpoint_t old_peer;
    uint64_t ceil0, neutral0, refused0;
    int was_lost;
    if (S == NULL || out_len == NULL || v == NULL) {
        return C4G_ERR_NULL;
    }
    memset(v, 0, sizeof *v);
    *out_len = 0U;
    settle(S);
    S->last_kind = C4G_RX_DROPPED;
    /* the loop prepares a fallback at c4g_loop_rx (no engine for the packet) or at
     * c4g_loop_reply (the encoder refused): both count */
    neutral0 = srv_loop_counters(S)->neutral_replies;
    refused0 = srv_loop_counters(S)->encode_refused;
    was_lost = (srv_state(S).phase == C4G_PHASE_LOST);
    old_peer = srv_state(S).peer;
    ceil0 = srv_counters(S)->malformed[C4G_MAL_CEILING];
    st = c4g_loop_rx(&S->loop, in, len, t_rx_ns, from, &ev);
    if (st != C4G_OK) {
        return st;
    }
    v->kind = ev.kind;
    v->events = ev.events;
    v->stop = rx_time_events(S, &ev, was_lost, from, &old_peer, t_rx_ns);
    if (v->stop != SRV_STOP_NONE ||
        refused(S, in, len, from, t_rx_ns, &ev,
                srv_counters(S)->malformed[C4G_MAL_CEILING] != ceil0)) {
        return C4G_OK;
    }
    session_events(S, &ev, t_rx_ns);
    answer(S, &ev, t_rx_ns, out, cap, out_len, v);
    S->stats.neutral_replies += srv_loop_counters(S)->neutral_replies - neutral0;
    S->stats.encode_errors += srv_loop_counters(S)->encode_refused - refused0;
    if (!v->send) {
        *out_len = 0U;
    }
    if ((ev.events & C4G_EV_END) != 0U) {
        v->ended = true;
        if ((ev.events & C4G_EV_END_UNEXPECTED) != 0U) {
            srv_log(S, t_rx_ns, "ATTACK? 504 out of procedure: OPEN axis %d was in mode %lld "
                    "(the manual presets mode 0 before 504): forged, or the controller left "
                    "abruptly; the session ends and the PC stops answering (a controller that "
                    "did not send it turns its drives off after 10 missing replies)",
                    (int)ev.diag.axis + 1, (long long)ev.diag.value);
        }
        srv_log(S, t_rx_ns, "504: end of communication");
        if (!S->cfg.persist) {
            v->stop = SRV_STOP_END;
        } else {
            S->restart_due = 1;
        }
    }
    if (v->send) {
        S->last_kind = ev.kind;
        S->last_rx_ns = t_rx_ns;
    } else {
        settle(S); /* nothing goes out: the next session starts now */
    }
    return C4G_OK;
}

void srv_sent(srv_t *S, uint64_t t_ns)
{
    if (S->last_kind == C4G_RX_CYCLIC) {
        const int64_t cyc = (int64_t)(t_ns - S->last_rx_ns);
        (void)c4g_loop_sent(&S->loop, t_ns);
        c4gh_hist_add(&S->stats.cycle, cyc);
        if (cyc > (int64_t)S->cfg.late_us * 1000) {
            S->stats.late++;
        }
    }
    S->last_kind = C4G_RX_DROPPED;
    settle(S);
}
