/* SPDX-License-Identifier: MIT */
/* c4g-server: the PC side of C4G Open. Binds the UDP port, accepts packets only from
 * the controller's address, runs the libc4gopen loop object (session + control engine)
 * and answers every packet with a per-arm behaviour passed through the PC-side safety
 * filter.
 *
 * The real-time loop: recvfrom -> c4g_loop_rx (session, control step) -> controllers
 * (behave.c, tools/common/c4g_controllers.c) -> c4g_loop_reply (safety filter, encoding,
 * neutral fallback) -> sendto -> c4g_loop_sent. Nothing on that path allocates or does
 * file I/O: logs, pcap and moni rows go through a lock-free ring
 * (tools/common/c4g_rtlog.h) to a writer thread. */
#include "srv.h"
#include "c4g_pcap.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

void srv_report(srv_t *S, FILE *out, const char *why, int code);
int srv_json(srv_t *S, const char *path, const char *why, int code);
void srv_sink(void *ctx, const c4g_rtlog_rec_t *rec);
int srv_outputs_open(srv_t *S);
void srv_outputs_close(srv_t *S);

static srv_t g_srv; /* static: large, and locked by mlockall */
static volatile sig_atomic_t g_stop;

static void on_signal(int sig)
{
    g_stop = sig;
}

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}

void srv_log(srv_t *S, uint64_t t_ns, const char *fmt, ...)
{
    va_list ap;
    c4g_rtlog_rec_t *rec;
    int n;
    if (S->cfg.quiet && !S->log_fp) {
        return;
    }
    rec = c4g_rtlog_reserve(&S->log);
    if (rec == NULL) {
        return; /* counted as dropped */
    }
    va_start(ap, fmt);
    n = vsnprintf((char *)rec->data, C4G_RTLOG_SLOT_BYTES, fmt, ap);
    va_end(ap);
    if (n < 0) {
        n = 0;
    } else if ((size_t)n >= C4G_RTLOG_SLOT_BYTES) {
        n = (int)C4G_RTLOG_SLOT_BYTES - 1;
    }
    rec->kind = LOG_TEXT;
    rec->t_ns = t_ns;
    rec->len = (uint32_t)n;
    c4g_rtlog_commit(&S->log);
}

static int load_files(srv_config_t *cfg)
{
    char err[600];
    uint32_t a;
    for (a = 0U; a < C4G_ARMS; a++) {
        const srv_arm_cfg_t *A = &cfg->arm[a];
        uint32_t b;
        int shared = 0;
        if (A->src != SRC_FILE) {
            continue;
        }
        for (b = 0U; b < a; b++) { /* same file as an earlier arm: copy, don't re-read */
            if (cfg->arm[b].src == SRC_FILE && strcmp(cfg->arm[b].traj_path, A->traj_path) == 0) {
                memcpy(&srv_traj[a], &srv_traj[b], sizeof srv_traj[a]);
                shared = 1;
                break;
            }
        }
        if (!shared && srv_load_traj(A->traj_path, &srv_traj[a], err, sizeof err) != 0) {
            fprintf(stderr, "c4g-server: trajectory: %s\n", err);
            return -1;
        }
    }
    if (cfg->arm[0].ff_path[0] != '\0' &&
        srv_load_ff(cfg->arm[0].ff_path, cfg->ff, err, sizeof err) != 0) {
        fprintf(stderr, "c4g-server: feedforward: %s\n", err);
        return -1;
    }
    return 0;
}

static int open_socket(srv_t *S)
{
    struct sockaddr_in sa;
    int fd, rcv = 1 << 20;
    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)S->cfg.port);
    if (inet_pton(AF_INET, S->cfg.bind_addr, &sa.sin_addr) != 1) {
        fprintf(stderr, "c4g-server: --bind: '%s' is not an IPv4 address\n", S->cfg.bind_addr);
        return -1;
    }
    memset(&S->ctrl, 0, sizeof S->ctrl);
    if (strcmp(S->cfg.ctrl_addr, "any") != 0 &&
        inet_pton(AF_INET, S->cfg.ctrl_addr, &S->ctrl.sin_addr) != 1) {
        fprintf(stderr, "c4g-server: --controller: '%s' is not an IPv4 address or 'any'\n",
                S->cfg.ctrl_addr);
        return -1;
    }
    fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) {
        fprintf(stderr, "c4g-server: socket: %s\n", strerror(errno));
        return -2;
    }
    (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcv, sizeof rcv);
    {
        struct timeval tv;
        tv.tv_sec = 0;
        tv.tv_usec = 1000; /* the blocking wait wakes every 1 ms for the loss check */
        (void)setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    }
    if (bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0) {
        const int e = errno;
        fprintf(stderr, "c4g-server: bind %s:%u: %s%s\n", S->cfg.bind_addr, S->cfg.port, strerror(e),
                (e == EACCES && S->cfg.port < 1024U)
                    ? " (ports below 1024 need root or CAP_NET_BIND_SERVICE)" : "");
        close(fd);
        return -2;
    }
    return fd;
}

/* Wait until the socket is readable or timeout_ns passed; 1 readable, 0 timeout. */
static int wait_readable(const srv_t *S, int fd, uint64_t timeout_ns)
{
    if (S->cfg.spin || S->cfg.poll_us > 0U) {
        const uint64_t end = now_ns() + timeout_ns;
        struct timespec next;
        char b;
        clock_gettime(CLOCK_MONOTONIC, &next);
        for (;;) {
            const ssize_t n = recv(fd, &b, 1, MSG_PEEK | MSG_DONTWAIT);
            if (n >= 0) {
                return 1;
            }
            if (g_stop || now_ns() >= end) {
                return 0;
            }
            if (S->cfg.poll_us > 0U) {
                next.tv_nsec += (long)S->cfg.poll_us * 1000L;
                while (next.tv_nsec >= 1000000000L) {
                    next.tv_nsec -= 1000000000L;
                    next.tv_sec++;
                }
                (void)clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
            }
        }
    } else {
        struct pollfd p;
        int ms = (int)(timeout_ns / 1000000ULL);
        p.fd = fd;
        p.events = POLLIN;
        p.revents = 0;
        if (ms < 1) {
            ms = 1;
        }
        return (poll(&p, 1, ms) > 0) ? 1 : 0;
    }
}

static void pause_ms(double ms)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(ms / 1000.0);
    ts.tv_nsec = (long)((ms - (double)ts.tv_sec * 1000.0) * 1e6);
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR && !g_stop) {
    }
}

static void hist_add(srv_stats_t *st, int64_t ns)
{
    uint64_t us = (ns > 0) ? (uint64_t)ns / 1000U : 0U;
    if (us > SRV_HIST_US) {
        us = SRV_HIST_US;
    }
    st->hist[us]++;
    st->hist_n++;
    st->cycle_sum_us += (double)ns / 1000.0;
    if (ns > st->cycle_max_ns) {
        st->cycle_max_ns = ns;
    }
}

static void log_datagram(srv_t *S, uint32_t kind, uint64_t t, const uint8_t *buf, size_t n,
                         const struct sockaddr_in *peer)
{
    c4g_rtlog_rec_t *rec;
    if (S->pcap == NULL) {
        return;
    }
    rec = c4g_rtlog_reserve(&S->log);
    if (rec == NULL) {
        return;
    }
    if (n > C4G_RTLOG_SLOT_BYTES - 8U) {
        n = C4G_RTLOG_SLOT_BYTES - 8U;
    }
    rec->kind = kind;
    rec->t_ns = t;
    memcpy(rec->data, &peer->sin_addr.s_addr, 4U);
    memcpy(rec->data + 4, &peer->sin_port, 2U);
    memcpy(rec->data + 6, &S->local_port, 2U);
    memcpy(rec->data + 8, buf, n);
    rec->len = (uint32_t)(n + 8U);
    c4g_rtlog_commit(&S->log);
}

static void log_moni(srv_t *S, uint64_t t, const c4g_ctrl_packet_t *rx, const c4g_pc_packet_t *tx)
{
    c4g_rtlog_rec_t *rec;
    if (S->moni_fp == NULL) {
        return;
    }
    rec = c4g_rtlog_reserve(&S->log);
    if (rec == NULL) {
        return;
    }
    rec->kind = LOG_MONI;
    rec->t_ns = t;
    memcpy(rec->data, rx, sizeof *rx);
    memcpy(rec->data + sizeof *rx, tx, sizeof *tx);
    rec->len = (uint32_t)(sizeof *rx + sizeof *tx);
    c4g_rtlog_commit(&S->log);
}

/* Silence and loss events of the session, whether c4g_loop_poll found them or
 * c4g_loop_rx did before it classified a datagram (a stream of refused datagrams
 * keeps the socket busy: the loss must not wait for a quiet moment). Exit code, or -1. */
static int time_events(srv_t *S, uint32_t ev, uint64_t t)
{
    const c4g_session_t *s = &S->loop.session;
    if ((ev & C4G_EV_SILENCE) != 0U) {
        srv_log(S, t, "controller silent for more than %.1f ms: session kept",
                (double)s->silence_ns * 1e-6);
    }
    if ((ev & C4G_EV_LOST) != 0U) {
        srv_log(S, t, "controller lost: no packet for %.1f ms", (double)s->lost_timeout_ns * 1e-6);
        if (!S->cfg.persist) {
            return EXIT_LOST;
        }
        srv_log(S, t, "waiting for the controller's next start-up");
    }
    return -1;
}

/* No datagram for a while: silence, lost-controller and idle checks. Exit code, or -1. */
static int on_idle(srv_t *S, uint64_t start)
{
    uint32_t ev = 0U;
    const uint64_t t = now_ns();
    const c4g_session_t *s = &S->loop.session;
    int code;
    (void)c4g_loop_poll(&S->loop, t, &ev);
    code = time_events(S, ev, t);
    if (code >= 0) {
        return code;
    }
    if (s->counters.rx == 0U && S->cfg.idle_timeout > 0.0 &&
        (double)(t - start) * 1e-9 >= S->cfg.idle_timeout) {
        return EXIT_TIMEOUT;
    }
    return -1;
}

static void endpoint_of(const struct sockaddr_in *a, c4g_endpoint_t *e)
{
    memset(e, 0, sizeof *e);
    memcpy(e->addr, &a->sin_addr.s_addr, 4U);
    e->addr_len = 4U;
    e->port = ntohs(a->sin_port);
}

/* A datagram from another address than the controller's (-c): counted, logged at first. */
static int foreign_address(srv_t *S, const struct sockaddr_in *peer, ssize_t n, uint64_t t)
{
    if (S->ctrl.sin_addr.s_addr == 0U || peer->sin_addr.s_addr == S->ctrl.sin_addr.s_addr) {
        return 0;
    }
    S->stats.foreign++;
    if (S->stats.foreign <= 10U || S->cfg.verbose) {
        char a[INET_ADDRSTRLEN];
        inet_ntop(AF_INET, &peer->sin_addr, a, sizeof a);
        srv_log(S, t, "dropped %zd-byte datagram from foreign source %s:%u", n, a,
                (unsigned)ntohs(peer->sin_port));
    }
    return 1;
}

static void log_foreign(srv_t *S, const c4g_session_t *s, const struct sockaddr_in *peer,
                        size_t len, uint64_t t)
{
    if (s->counters.foreign_total <= 10U || S->cfg.verbose) {
        char a[INET_ADDRSTRLEN];
        inet_ntop(AF_INET, &peer->sin_addr, a, sizeof a);
        srv_log(S, t, "dropped %zu-byte datagram from %s:%u: not the controller's endpoint", len, a,
                (unsigned)ntohs(peer->sin_port));
    }
}

/* Active freezing is over: drop what queued from the controller during the pause and answer
 * the newest; whatever else queued goes through the same trust checks as any datagram. The
 * datagram already in @p in counts too: if it is not the controller's and a newer one of the
 * controller's replaces it, the session sees it first (counted as foreign); if none does, it
 * stays in @p in and the caller's path counts it. */
static void drain_queue(srv_t *S, int fd, uint8_t *in, size_t cap, size_t *len,
                        struct sockaddr_in *peer)
{
    static uint8_t other[2048];
    ssize_t m;
    struct sockaddr_in p2;
    socklen_t l2 = sizeof p2;
    c4g_endpoint_t e;
    c4g_loop_event_t ev;
    unsigned n_ctrl = 0U, n_foreign = 0U, k_guard = 0U;
    int have;
    endpoint_of(peer, &e);
    have = c4g_session_is_peer(&S->loop.session, &e);
    while (k_guard++ < 100000U && (m = recvfrom(fd, other, sizeof other, MSG_DONTWAIT | MSG_TRUNC,
                                                (struct sockaddr *)&p2, &l2)) >= 0) {
        const uint64_t t = now_ns();
        const size_t k = ((size_t)m > sizeof other) ? sizeof other : (size_t)m;
        endpoint_of(&p2, &e);
        l2 = sizeof p2;
        if (foreign_address(S, &p2, m, t)) {
            n_foreign++;
            continue;
        }
        if (!c4g_session_is_peer(&S->loop.session, &e)) {
            (void)c4g_loop_rx(&S->loop, other, k, t, &e, &ev); /* counted */
            log_foreign(S, &S->loop.session, &p2, k, t);
            n_foreign++;
            continue;
        }
        if (!have) { /* the first datagram was another endpoint's: count it before it goes */
            c4g_endpoint_t e0;
            endpoint_of(peer, &e0);
            (void)c4g_loop_rx(&S->loop, in, *len, t, &e0, &ev);
            log_foreign(S, &S->loop.session, peer, *len, t);
            n_foreign++;
            have = 1;
        }
        n_ctrl++;
        memcpy(in, other, (k > cap) ? cap : k);
        *len = (k > cap) ? cap : k;
        *peer = p2;
    }
    srv_log(S, now_ns(), "active freezing over: %u more datagrams queued (%u of the controller's, "
            "%u foreign); answering the controller's newest", n_ctrl + n_foreign, n_ctrl, n_foreign);
}

/* One received datagram of the controller's address. */
typedef struct dgram {
    size_t len;
    struct sockaddr_in peer;
    socklen_t plen;
    uint64_t t_rx;
} dgram_t;

enum { SRV_NEXT = -1, SRV_HAVE = -2 }; /* besides exit codes: go on / a datagram is in */

static uint8_t g_in[2048];
static uint8_t g_out[C4G_INIT_SIZE];

/* Wait for one datagram of the controller's address into g_in. SRV_HAVE, SRV_NEXT (nothing
 * came, or another address's), or an exit code. */
static int receive(srv_t *S, int fd, uint64_t start, int thaw, dgram_t *d)
{
    ssize_t n;
    int code;
    if (g_stop) {
        return EXIT_SIGNAL;
    }
    if (S->cfg.max_seconds > 0.0 && (double)(now_ns() - start) * 1e-9 >= S->cfg.max_seconds) {
        return EXIT_TIMEOUT;
    }
    d->plen = sizeof d->peer;
    if ((S->cfg.spin || S->cfg.poll_us > 0U) && !wait_readable(S, fd, 1000000ULL)) {
        n = -1;
        errno = EAGAIN;
    } else {
        /* default: one blocking recvfrom, woken by the packet (SO_RCVTIMEO 1 ms) */
        n = recvfrom(fd, g_in, sizeof g_in, MSG_TRUNC, (struct sockaddr *)&d->peer, &d->plen);
    }
    d->t_rx = now_ns();
    if (n < 0) {
        /* a timeout runs the idle checks; EINTR or a transient error: go on */
        code = (errno == EAGAIN || errno == EWOULDBLOCK) ? on_idle(S, start) : SRV_NEXT;
        return (code >= 0) ? code : SRV_NEXT;
    }
    if (foreign_address(S, &d->peer, n, d->t_rx)) {
        /* a stream from another address keeps recvfrom from timing out: the silence
         * and loss checks must not wait for a quiet socket */
        code = on_idle(S, start);
        return (code >= 0) ? code : SRV_NEXT;
    }
    if ((size_t)n > sizeof g_in) {
        S->stats.oversize++;
        d->len = sizeof g_in;
    } else {
        d->len = (size_t)n;
    }
    if (thaw) {
        drain_queue(S, fd, g_in, sizeof g_in, &d->len, &d->peer);
        d->t_rx = now_ns();
    }
    return SRV_HAVE;
}

/* Datagrams the session refused or that need no answer: logged. 1 when nothing is due. */
static int refused(srv_t *S, const dgram_t *d, const c4g_loop_event_t *ev)
{
    const uint32_t e = ev->events;
    if ((e & C4G_EV_FOREIGN) != 0U) {
        log_foreign(S, &S->loop.session, &d->peer, d->len, d->t_rx);
        return 1;
    }
    if ((e & C4G_EV_RESUMED) != 0U) {
        srv_log(S, d->t_rx, "controller back after %.1f ms of silence", (double)ev->silence_ns * 1e-6);
    }
    if ((e & (C4G_EV_DUPLICATE | C4G_EV_OUT_OF_ORDER)) != 0U && ev->kind == C4G_RX_DROPPED) {
        srv_log(S, d->t_rx, "dropped %s packet NUM %d (newest %d): not answered",
                (e & C4G_EV_DUPLICATE) ? "duplicate" : "stale",
                (int)((uint32_t)g_in[0] | (uint32_t)g_in[1] << 8 | (uint32_t)g_in[2] << 16 |
                      (uint32_t)g_in[3] << 24),
                (int)S->loop.session.last_num);
        return 1;
    }
    if ((e & C4G_EV_MALFORMED) != 0U && ev->diag.status == C4G_ERR_STATE) {
        srv_log(S, d->t_rx, "refused a %zu-byte initialization packet mid-session (NUM %lld): "
                "accepted only at start-up or after 506", d->len, (long long)ev->diag.value);
        return 1;
    }
    if ((e & C4G_EV_MALFORMED) != 0U) {
        srv_log(S, d->t_rx, "dropped malformed %zu-byte datagram: %s (field %s, offset %u, axis %d, value %lld)",
                d->len, c4g_strerror(ev->diag.status), c4g_field_name(ev->diag.field),
                (unsigned)ev->diag.offset, (int)ev->diag.axis, (long long)ev->diag.value);
        return 1;
    }
    return 0;
}

/* The session's events on a datagram that is answered. */
static void session_events(srv_t *S, const dgram_t *d, const c4g_loop_event_t *ev)
{
    const c4g_session_t *s = &S->loop.session;
    const uint32_t e = ev->events;
    const uint64_t t = d->t_rx;
    if ((e & C4G_EV_LOST) != 0U && ev->kind == C4G_RX_CYCLIC) {
        S->stats.long_gaps++; /* a packet did come: a long gap, not a lost controller */
        srv_log(S, t, "long gap: more than %.1f ms without a packet",
                (double)s->lost_timeout_ns * 1e-6);
    }
    if ((e & C4G_EV_INIT) != 0U) {
        S->stats.inits++;
        srv_behave_init(S, t);
        srv_log(S, t, "init packet: %u open axes, period %d ms, version %d.%d.%d",
                (unsigned)s->map.n_axes, (int)s->init.period_ms, (int)s->init.version_major,
                (int)s->init.version_minor, (int)s->init.version_build);
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
        srv_log(S, t, "drives: INFPAR MOVING mask now 0x%x", (unsigned)s->drives);
    }
    if ((e & C4G_EV_CYCLIC_START) != 0U) {
        srv_log(S, t, "cyclic communication started");
    }
}

/* The reply to a cyclic packet: the controllers fill what the loop prepared, the loop
 * filters and encodes it (neutral when it cannot). A reply --skip-replies holds back is
 * still finished, so that the control engine sees every tick as the controller does, but
 * not encoded (zero capacity). 1 when g_out holds a reply to send. */
static int reply_cyclic(srv_t *S, const c4g_loop_event_t *ev, uint64_t t_rx, int *thaw,
                        size_t *olen)
{
    const uint64_t k = S->loop.session.counters.cyclic;
    const uint64_t neutral0 = S->loop.counters.neutral_replies;
    const int skip = S->cfg.skip_at > 0U && k >= S->cfg.skip_at &&
                     k < S->cfg.skip_at + S->cfg.skip_count;
    c4g_engine_report_t rep;
    c4g_status_t st;
    S->cyc_k = k;
    S->thaw = *thaw;
    *thaw = 0;
    if (ev->cmd != NULL) {
        srv_behave(S, ev, t_rx);
    }
    st = c4g_loop_reply(&S->loop, g_out, skip ? 0U : sizeof g_out, olen, &rep);
    S->stats.encode_errors += S->loop.counters.neutral_replies - neutral0;
    if (ev->cmd != NULL) {
        srv_behave_done(S, &rep, t_rx);
    }
    if (skip) {
        S->stats.skipped++;
        return 0;
    }
    return st == C4G_OK;
}

/* Answer the datagram (sync/init echo or cyclic reply), then the active-freezing pause. */
static void answer(srv_t *S, int fd, const dgram_t *d, const c4g_loop_event_t *ev, int *thaw)
{
    size_t olen = 0U;
    int send_it = 0;
    if (ev->kind == C4G_RX_SYNC || ev->kind == C4G_RX_INIT) {
        send_it = (c4g_loop_reply(&S->loop, g_out, sizeof g_out, &olen, NULL) == C4G_OK);
    } else if (ev->kind == C4G_RX_CYCLIC) {
        send_it = reply_cyclic(S, ev, d->t_rx, thaw, &olen);
    }
    if (send_it) {
        uint64_t t_tx;
        if (sendto(fd, g_out, olen, 0, (const struct sockaddr *)&d->peer, d->plen) != (ssize_t)olen) {
            S->stats.send_errors++;
        }
        t_tx = now_ns();
        if (ev->kind == C4G_RX_CYCLIC) {
            const int64_t cyc = (int64_t)(t_tx - d->t_rx);
            (void)c4g_loop_sent(&S->loop, t_tx);
            hist_add(&S->stats, cyc);
            if (cyc > (int64_t)S->cfg.late_us * 1000) {
                S->stats.late++;
            }
            log_moni(S, d->t_rx, ev->pkt, &S->loop.tx);
        }
        log_datagram(S, LOG_PCAP_TX, t_tx, g_out, olen, &d->peer);
    }
    if (ev->kind == C4G_RX_CYCLIC && S->cfg.freeze_at == S->loop.session.counters.cyclic &&
        S->loop.tx.ax[0].mode == C4G_MODE_FREEZING_A) {
        S->stats.freezes++;
        srv_log(S, now_ns(), "active freezing: pausing %.0f ms", S->cfg.freeze_ms);
        pause_ms(S->cfg.freeze_ms);
        *thaw = 1;
    }
}

/* One datagram through the loop. An exit code, or SRV_NEXT. */
static int handle(srv_t *S, int fd, const dgram_t *d, int *thaw)
{
    c4g_endpoint_t from;
    c4g_loop_event_t ev;
    int was_lost;
    endpoint_of(&d->peer, &from);
    log_datagram(S, LOG_PCAP_RX, d->t_rx, g_in, d->len, &d->peer);
    was_lost = (S->loop.session.phase == C4G_PHASE_LOST);
    if (c4g_loop_rx(&S->loop, g_in, d->len, d->t_rx, &from, &ev) != C4G_OK) {
        return SRV_NEXT;
    }
    if (ev.kind != C4G_RX_CYCLIC) {
        /* the session checks the clock before it classifies a datagram: a loss it found
         * there ends the session (without --persist) whether the datagram was refused or
         * opens a new start-up, which is then not answered. A cyclic packet of the
         * controller after the loss timeout is a long gap (session_events). */
        const int code = time_events(S, ev.events, d->t_rx);
        if (code >= 0) {
            return code;
        }
        if (ev.kind == C4G_RX_SYNC && (was_lost || (ev.events & C4G_EV_LOST) != 0U)) {
            char a[INET_ADDRSTRLEN];
            inet_ntop(AF_INET, &d->peer.sin_addr, a, sizeof a);
            srv_log(S, d->t_rx, "new start-up from %s:%u: a new session", a,
                    (unsigned)ntohs(d->peer.sin_port));
        }
    } else if ((ev.events & C4G_EV_SILENCE) != 0U) {
        (void)time_events(S, C4G_EV_SILENCE, d->t_rx);
    }
    if (refused(S, d, &ev)) {
        return SRV_NEXT;
    }
    session_events(S, d, &ev);
    answer(S, fd, d, &ev, thaw);
    if ((ev.events & C4G_EV_END) != 0U) {
        srv_log(S, d->t_rx, "504: end of communication");
        if (!S->cfg.persist) {
            return EXIT_END;
        }
        srv_counters_add(&S->done, &S->loop.session.counters); /* the exit report adds every session */
        (void)c4g_loop_init(&S->loop, &S->loop_cfg);
    }
    return SRV_NEXT;
}

/* The per-packet loop. Returns the exit code. */
static int serve(srv_t *S, int fd)
{
    const uint64_t start = now_ns();
    int thaw = 0;
    for (;;) {
        dgram_t d;
        int code = receive(S, fd, start, thaw, &d);
        if (code == SRV_HAVE) {
            code = handle(S, fd, &d, &thaw);
        }
        if (code >= 0) {
            return code;
        }
    }
}

/* The configuration: command line, INI file, input files, the loop. SRV_NEXT to go on,
 * else the exit code (0 after --help / --version). */
static int configure(srv_t *S, int argc, char **argv)
{
    srv_config_default(&S->cfg);
    switch (srv_config_cli(&S->cfg, C4G_PCAP_ANCHOR(), argc, argv)) {
    case CLI_RUN: break;
    case CLI_DONE: return 0; /* --help, --version */
    default: return EXIT_USAGE;
    }
    if (load_files(&S->cfg) != 0) {
        return EXIT_USAGE;
    }
    (void)c4g_session_config_default(&S->loop_cfg.session);
    (void)c4g_engine_config_default(&S->loop_cfg.engine);
    S->loop_cfg.session.num_policy = S->cfg.num_policy;
    S->loop_cfg.session.lost_timeout_ns = S->cfg.lost_timeout_ns;
    S->loop_cfg.engine.start_ns = (uint64_t)(S->cfg.arm[0].scs * 1e9);
    if (c4g_loop_init(&S->loop, &S->loop_cfg) != C4G_OK) {
        fprintf(stderr, "c4g-server: session configuration refused\n");
        return EXIT_USAGE;
    }
    srv_behave_reset(S);
    return SRV_NEXT;
}

/* Socket, outputs, the log writer thread, signals, real time. SRV_NEXT with the socket in
 * *fd, else the exit code. */
static int start(srv_t *S, int *fd)
{
    struct sigaction sa;
    *fd = open_socket(S);
    if (*fd < 0) {
        return (*fd == -1) ? EXIT_USAGE : EXIT_SETUP;
    }
    S->local_port = htons((uint16_t)S->cfg.port);
    if (srv_outputs_open(S) != 0) {
        close(*fd);
        return EXIT_SETUP;
    }
    c4g_rtlog_init(&S->log, srv_sink, S);
    if (c4g_rtlog_start(&S->log) != 0) {
        fprintf(stderr, "c4g-server: cannot start the log writer thread\n");
        close(*fd);
        return EXIT_SETUP;
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    /* RT settings last: the writer thread stays SCHED_OTHER; memory is locked from here */
    if (srv_rt_setup(&S->cfg, stderr) != 0) {
        c4g_rtlog_stop(&S->log);
        close(*fd);
        return EXIT_SETUP;
    }
    if (!S->cfg.quiet) {
        fprintf(stderr, "c4g-server: listening on %s:%u, controller %s, NUM policy %s\n",
                S->cfg.bind_addr, S->cfg.port, S->cfg.ctrl_addr,
                S->cfg.num_policy == C4G_NUM_ECHO ? "echo" : "plus1");
    }
    return SRV_NEXT;
}

/* The report and the JSON summary at exit. Returns the exit code. */
static int finish(srv_t *S, int code)
{
    const char *why;
    switch (code) {
    case EXIT_END: why = "504 from the controller (end of communication)"; break;
    case EXIT_LOST: why = "controller lost (no packet within the loss timeout)"; break;
    case EXIT_TIMEOUT: why = (S->loop.session.counters.rx == 0U) ? "idle timeout: no controller"
                                                                 : "--max-seconds reached"; break;
    case EXIT_SIGNAL: why = "stopped by a signal"; break;
    default: why = "?"; break;
    }
    if (!S->cfg.quiet) {
        srv_report(S, stdout, why, code);
    }
    if (S->cfg.json_path[0] != '\0' && srv_json(S, S->cfg.json_path, why, code) != 0) {
        code = EXIT_SETUP;
    }
    srv_outputs_close(S);
    return code;
}

int main(int argc, char **argv)
{
    srv_t *S = &g_srv;
    int fd = -1;
    int code = configure(S, argc, argv);
    if (code == SRV_NEXT) {
        code = start(S, &fd);
    }
    if (code != SRV_NEXT) {
        return code;
    }
    S->t0_ns = now_ns();
    code = serve(S, fd);
    c4g_rtlog_stop(&S->log);
    close(fd);
    return finish(S, code);
}
