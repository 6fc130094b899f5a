/* SPDX-License-Identifier: MIT */
/* The host loop around the server core, whatever the datagrams come from (srv.h: a source):
 * wait for the next datagram or the core's next deadline -> the controller-address filter ->
 * after active freezing, the drain -> srv_process -> the reply -> srv_sent -> the pause. The
 * socket (main.c) and a capture (capture.c) run this same code, so a capture run takes
 * every host decision the server takes on its socket. */
#include "srv.h"

#include <string.h>

enum { SRV_NEXT = -1, SRV_HAVE = -2 }; /* besides exit codes: go on / a datagram is in */

static uint8_t g_in[2048];
static uint8_t g_out[C4G_INIT_SIZE];

void srv_endpoint(uint32_t ip, uint16_t port, c4g_endpoint_t *e)
{
    memset(e, 0, sizeof *e);
    e->addr[0] = (uint8_t)(ip >> 24);
    e->addr[1] = (uint8_t)(ip >> 16);
    e->addr[2] = (uint8_t)(ip >> 8);
    e->addr[3] = (uint8_t)ip;
    e->addr_len = 4U;
    e->port = port;
}

int srv_foreign(srv_host_t *H, const c4g_endpoint_t *from, const uint8_t *buf, size_t len,
                size_t size, uint64_t t)
{
    srv_t *S = &H->s;
    c4g_peek_t pk;
    if (H->ctrl.sin_addr.s_addr == 0U ||
        (from->addr_len == 4U && memcmp(from->addr, &H->ctrl.sin_addr.s_addr, 4U) == 0)) {
        return 0;
    }
    S->stats.foreign++;
    if (S->stats.foreign <= 10U || S->cfg.verbose) {
        srv_log(S, t, "dropped %zu-byte datagram from foreign source %u.%u.%u.%u:%u", size,
                (unsigned)from->addr[0], (unsigned)from->addr[1], (unsigned)from->addr[2],
                (unsigned)from->addr[3], (unsigned)from->port);
    }
    /* A controller's start-up from another address while nothing came from -c's: most
     * likely -c names the wrong host. Said once; the datagrams stay dropped. */
    if (!H->ctrl_hinted && srv_counters(S)->rx == 0U && S->done.rx == 0U &&
        c4g_peek(buf, len, true, &pk) == C4G_OK && pk.kind != C4G_PKT_FOREIGN) {
        H->ctrl_hinted = 1;
        (void)snprintf(H->ctrl_seen, sizeof H->ctrl_seen, "%u.%u.%u.%u:%u",
                       (unsigned)from->addr[0], (unsigned)from->addr[1],
                       (unsigned)from->addr[2], (unsigned)from->addr[3], (unsigned)from->port);
        srv_log(S, t, "the controller's packets come from %s: is that your controller? "
                "(--controller gives %s)", H->ctrl_seen, S->cfg.ctrl_addr);
    }
    return 1;
}

static void dropped(const srv_source_t *src, const srv_dgram_t *d)
{
    if (src->dropped != NULL) {
        src->dropped(src->ctx, d);
    }
}

/* A stop the core reported, as the exit code; -1 to go on. */
static int stop_code(srv_stop_t stop)
{
    switch (stop) {
    case SRV_STOP_END: return EXIT_END;
    case SRV_STOP_LOST: return EXIT_LOST;
    case SRV_STOP_NONE:
    default: return -1;
    }
}

/* No datagram for a while: silence, lost-controller and idle checks. Exit code, or -1. */
static int on_idle(srv_t *S, uint64_t t, uint64_t start)
{
    const int code = stop_code(srv_idle(S, t));
    if (code >= 0) {
        return code;
    }
    if (srv_counters(S)->rx == 0U && S->cfg.idle_timeout > 0.0 &&
        (double)(t - start) * 1e-9 >= S->cfg.idle_timeout) {
        return EXIT_TIMEOUT;
    }
    return -1;
}

/* The next instant the run has something to do without a datagram: the core's silence or
 * loss check, --idle-timeout before the first datagram, --max-seconds. */
static uint64_t next_due(const srv_t *S, uint64_t start)
{
    uint64_t due = srv_deadline(S);
    if (srv_counters(S)->rx == 0U && S->cfg.idle_timeout > 0.0) {
        const uint64_t t = start + (uint64_t)(S->cfg.idle_timeout * 1e9);
        due = (t < due) ? t : due;
    }
    if (S->cfg.max_seconds > 0.0) {
        const uint64_t t = start + (uint64_t)(S->cfg.max_seconds * 1e9);
        due = (t < due) ? t : due;
    }
    return due;
}

/* Active freezing is over: drop what queued from the controller during the pause and answer
 * the newest; whatever else queued goes through the same trust checks as any datagram. The
 * datagram already in @p d counts too: if it is not the controller's and a newer one of the
 * controller's replaces it, the session sees it first (counted as foreign); if none does, it
 * stays in @p d and the caller's path counts it. */
static void drain(srv_host_t *H, const srv_source_t *src, srv_dgram_t *d)
{
    static uint8_t other[2048];
    srv_dgram_t o;
    srv_t *S = &H->s;
    unsigned n_ctrl = 0U, n_foreign = 0U, k_guard = 0U;
    bool have = false, is_peer = false;
    (void)c4g_loop_is_peer(&S->loop, &d->from, &have);
    memset(&o, 0, sizeof o);
    o.buf = other;
    o.cap = sizeof other;
    while (k_guard++ < 100000U && src->queued(src->ctx, &o) == SRV_SRC_HAVE) {
        const uint64_t t = src->now(src->ctx);
        if (srv_foreign(H, &o.from, o.buf, o.len, o.size, t)) {
            n_foreign++;
            dropped(src, &o);
            continue;
        }
        (void)c4g_loop_is_peer(&S->loop, &o.from, &is_peer);
        if (!is_peer) {
            srv_drop(S, o.buf, o.len, &o.from, t); /* counted */
            n_foreign++;
            dropped(src, &o);
            continue;
        }
        if (!have) { /* the first datagram was another endpoint's: count it before it goes */
            srv_drop(S, d->buf, d->len, &d->from, t);
            n_foreign++;
            have = true;
        }
        dropped(src, d); /* superseded by a newer one of the controller's */
        n_ctrl++;
        d->len = (o.len > d->cap) ? d->cap : o.len;
        memcpy(d->buf, o.buf, d->len);
        d->size = o.size;
        d->from = o.from;
        d->ref = o.ref;
    }
    srv_log(S, src->now(src->ctx), "active freezing over: %u more datagrams queued (%u of the "
            "controller's, %u foreign); answering the controller's newest", n_ctrl + n_foreign,
            n_ctrl, n_foreign);
    d->t_rx = src->now(src->ctx);
    d->t_cap = d->t_rx;
}

/* Wait for one datagram of the controller's address into @p d, or for the next deadline.
 * SRV_HAVE, SRV_NEXT (nothing came, or another address's), SRV_SOURCE_END, or an exit
 * code. After an active-freezing pause (the core's thaw_due) only the newest queued
 * datagram is answered. */
static int receive(srv_host_t *H, const srv_source_t *src, uint64_t start, srv_dgram_t *d)
{
    srv_t *S = &H->s;
    uint64_t due, now;
    int code;
    if (H->stop != NULL && *H->stop) {
        return EXIT_SIGNAL;
    }
    now = src->now(src->ctx);
    if (S->cfg.max_seconds > 0.0 && (double)(now - start) * 1e-9 >= S->cfg.max_seconds) {
        return EXIT_TIMEOUT;
    }
    /* checked before every wait, not only when the source is quiet: a stream from another
     * address must not hold off the silence and loss checks */
    due = next_due(S, start);
    if (now >= due) {
        code = on_idle(S, now, start);
        return (code >= 0) ? code : SRV_NEXT;
    }
    memset(d, 0, sizeof *d);
    d->buf = g_in;
    d->cap = sizeof g_in;
    switch (src->next(src->ctx, due, d)) {
    case SRV_SRC_HAVE: break;
    case SRV_SRC_END: return SRV_SOURCE_END;
    default: return SRV_NEXT; /* the deadline, a signal: checked above on the next call */
    }
    if (srv_foreign(H, &d->from, d->buf, d->len, d->size, d->t_rx)) {
        dropped(src, d);
        return SRV_NEXT;
    }
    if (d->size > d->cap) {
        S->stats.oversize++;
    }
    if (S->thaw_due) {
        drain(H, src, d);
    }
    return SRV_HAVE;
}

/* One datagram through the server core, the reply sent, then the active-freezing pause.
 * An exit code, or SRV_NEXT. */
static int handle(srv_host_t *H, const srv_source_t *src, const srv_dgram_t *d)
{
    srv_t *S = &H->s;
    srv_verdict_t v;
    size_t olen = 0U;
    uint64_t t_tx;
    if (src->accepted != NULL) {
        src->accepted(src->ctx, d);
    }
    if (srv_process(S, d->buf, d->len, &d->from, d->t_rx, g_out, sizeof g_out, &olen, &v) != C4G_OK) {
        memset(&v, 0, sizeof v);
        (void)src->reply(src->ctx, d, NULL, 0U, &v);
        return SRV_NEXT;
    }
    t_tx = src->reply(src->ctx, d, v.send ? g_out : NULL, v.send ? olen : 0U, &v);
    if (v.send) {
        srv_sent(S, t_tx);
    }
    if (v.freeze) {
        srv_log(S, src->now(src->ctx), "active freezing: pausing %.0f ms", v.pause_ms);
        src->pause(src->ctx, v.pause_ms);
    }
    return (v.stop != SRV_STOP_NONE) ? stop_code(v.stop) : SRV_NEXT;
}

int srv_serve(srv_host_t *H, const srv_source_t *src)
{
    const uint64_t start = src->now(src->ctx);
    for (;;) {
        srv_dgram_t d;
        int code = receive(H, src, start, &d);
        if (code == SRV_HAVE) {
            code = handle(H, src, &d);
        }
        if (src->after != NULL) {
            src->after(src->ctx);
        }
        if (code >= 0 || code == SRV_SOURCE_END) {
            return code;
        }
    }
}
