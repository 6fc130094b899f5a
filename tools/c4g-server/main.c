/* SPDX-License-Identifier: MIT */
/* c4g-server: the PC side of C4G Open. Binds the UDP port, accepts packets only from
 * the controller's address, runs the libc4gopen loop object (session + control engine)
 * and answers every packet with a per-arm behaviour passed through the PC-side safety
 * filter.
 *
 * The real-time loop: wait for the next datagram or the core's next deadline (silence,
 * loss, --idle-timeout, --max-seconds; no fixed timer) -> recvfrom -> srv_process (tools/c4g-server/srv_core.c: c4g_loop_rx,
 * controllers, c4g_loop_reply, counters; the same code c4g-replay rerun runs on a
 * capture) -> sendto -> srv_sent. This file holds only the I/O around it: socket,
 * clock, the active-freezing pause, outputs. Nothing on that path allocates or does file
 * I/O: logs, pcap and moni rows go through a lock-free ring (lib/host/c4gh_rtlog.h)
 * to a writer thread. */
#define _GNU_SOURCE /* ppoll: the wait that unblocks SIGINT/SIGTERM atomically */
#include "srv.h"
#include "c4gh_pcap.h"
#include "c4gh_udp.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

static srv_host_t g_host; /* static: large, and locked by mlockall */
static srv_config_t g_cfg;
static volatile sig_atomic_t g_stop;
/* The signal mask inside the blocking wait: SIGINT and SIGTERM are blocked everywhere else
 * (in every thread), so a signal that comes between the g_stop check and the wait still
 * ends the wait (ppoll unblocks them atomically) instead of waiting for the next deadline,
 * which may be none. */
static sigset_t g_waitmask;

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

/* The core's logger: one text record in the ring (RT-safe, formatted in place). */
static void host_log(void *ctx, uint64_t t_ns, const char *fmt, va_list ap)
{
    srv_host_t *H = (srv_host_t *)ctx;
    c4gh_rtlog_rec_t *rec;
    int n;
    if (H->s.cfg.quiet && !H->log_fp) {
        return;
    }
    rec = c4gh_rtlog_reserve(&H->log);
    if (rec == NULL) {
        return; /* counted as dropped */
    }
    n = vsnprintf((char *)rec->data, C4GH_RTLOG_SLOT_BYTES, fmt, ap);
    if (n < 0) {
        n = 0;
    } else if ((size_t)n >= C4GH_RTLOG_SLOT_BYTES) {
        n = (int)C4GH_RTLOG_SLOT_BYTES - 1;
    }
    rec->kind = LOG_TEXT;
    rec->t_ns = t_ns;
    rec->len = (uint32_t)n;
    c4gh_rtlog_commit(&H->log);
}

static int open_socket(srv_host_t *H)
{
    const srv_config_t *cfg = &H->s.cfg;
    struct sockaddr_in sa;
    int fd, rcv = 1 << 20;
    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)cfg->port);
    if (inet_pton(AF_INET, cfg->bind_addr, &sa.sin_addr) != 1) {
        fprintf(stderr, "c4g-server: --bind: '%s' is not an IPv4 address\n", cfg->bind_addr);
        return -1;
    }
    memset(&H->ctrl, 0, sizeof H->ctrl);
    if (strcmp(cfg->ctrl_addr, "any") != 0 &&
        inet_pton(AF_INET, cfg->ctrl_addr, &H->ctrl.sin_addr) != 1) {
        fprintf(stderr, "c4g-server: --controller: '%s' is not an IPv4 address or 'any'\n",
                cfg->ctrl_addr);
        return -1;
    }
    fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) {
        fprintf(stderr, "c4g-server: socket: %s\n", strerror(errno));
        return -2;
    }
    (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcv, sizeof rcv);
    if (bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0) {
        const int e = errno;
        fprintf(stderr, "c4g-server: bind %s:%u: %s%s\n", cfg->bind_addr, cfg->port, strerror(e),
                (e == EACCES && cfg->port < 1024U)
                    ? " (ports below 1024 need root or CAP_NET_BIND_SERVICE)" : "");
        close(fd);
        return -2;
    }
    return fd;
}

/* A relative timeout until @p due (C4G_NO_DEADLINE: NULL, no timeout). */
static struct timespec *until(uint64_t due, struct timespec *ts)
{
    uint64_t t, d;
    if (due == C4G_NO_DEADLINE) {
        return NULL;
    }
    t = now_ns();
    d = (due > t) ? due - t : 0U;
    ts->tv_sec = (time_t)(d / 1000000000ULL);
    ts->tv_nsec = (long)(d % 1000000000ULL);
    return ts;
}

/* Wait until the socket is readable or @p due (monotonic ns) came; 1 readable, 0 not (the
 * deadline, a signal). --spin and --poll-us poll the socket; else one ppoll, woken by the
 * datagram, the deadline or a signal. */
static int wait_readable(const srv_t *S, int fd, uint64_t due)
{
    if (S->cfg.spin || S->cfg.poll_us > 0U) {
        struct timespec next;
        char b;
        clock_gettime(CLOCK_MONOTONIC, &next);
        for (;;) {
            const ssize_t n = recv(fd, &b, 1, MSG_PEEK | MSG_DONTWAIT);
            if (n >= 0) {
                return 1;
            }
            if (g_stop || now_ns() >= due) {
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
        struct timespec ts;
        p.fd = fd;
        p.events = POLLIN;
        p.revents = 0;
        return (ppoll(&p, 1, until(due, &ts), &g_waitmask) > 0) ? 1 : 0;
    }
}

/* The active-freezing pause; a signal ends it. */
static void pause_ms(double ms)
{
    const uint64_t due = now_ns() + (uint64_t)(ms * 1e6);
    struct timespec ts;
    while (!g_stop && now_ns() < due) {
        (void)ppoll(NULL, 0, until(due, &ts), &g_waitmask);
    }
}

static void log_datagram(srv_host_t *H, uint32_t kind, uint64_t t, const uint8_t *buf, size_t n,
                         const struct sockaddr_in *peer)
{
    c4gh_rtlog_rec_t *rec;
    if (H->pcap == NULL) {
        return;
    }
    rec = c4gh_rtlog_reserve(&H->log);
    if (rec == NULL) {
        return;
    }
    if (n > C4GH_RTLOG_SLOT_BYTES - 8U) {
        n = C4GH_RTLOG_SLOT_BYTES - 8U;
    }
    rec->kind = kind;
    rec->t_ns = t;
    memcpy(rec->data, &peer->sin_addr.s_addr, 4U);
    memcpy(rec->data + 4, &peer->sin_port, 2U);
    memcpy(rec->data + 6, &H->local_port, 2U);
    memcpy(rec->data + 8, buf, n);
    rec->len = (uint32_t)(n + 8U);
    c4gh_rtlog_commit(&H->log);
}

static void log_moni(srv_host_t *H, uint64_t t, const c4g_ctrl_packet_t *rx, const c4g_pc_packet_t *tx)
{
    c4gh_rtlog_rec_t *rec;
    if (H->moni_fp == NULL) {
        return;
    }
    rec = c4gh_rtlog_reserve(&H->log);
    if (rec == NULL) {
        return;
    }
    rec->kind = LOG_MONI;
    rec->t_ns = t;
    memcpy(rec->data, rx, sizeof *rx);
    memcpy(rec->data + sizeof *rx, tx, sizeof *tx);
    rec->len = (uint32_t)(sizeof *rx + sizeof *tx);
    c4gh_rtlog_commit(&H->log);
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
static int on_idle(srv_t *S, uint64_t start)
{
    const uint64_t t = now_ns();
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

static void endpoint_of(const struct sockaddr_in *a, c4g_endpoint_t *e)
{
    memset(e, 0, sizeof *e);
    memcpy(e->addr, &a->sin_addr.s_addr, 4U);
    e->addr_len = 4U;
    e->port = ntohs(a->sin_port);
}

/* A datagram from another address than the controller's (-c): counted, logged at first. */
static int foreign_address(srv_host_t *H, const struct sockaddr_in *peer, ssize_t n, uint64_t t)
{
    srv_t *S = &H->s;
    if (H->ctrl.sin_addr.s_addr == 0U || peer->sin_addr.s_addr == H->ctrl.sin_addr.s_addr) {
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

/* Active freezing is over: drop what queued from the controller during the pause and answer
 * the newest; whatever else queued goes through the same trust checks as any datagram. The
 * datagram already in @p in counts too: if it is not the controller's and a newer one of the
 * controller's replaces it, the session sees it first (counted as foreign); if none does, it
 * stays in @p in and the caller's path counts it. */
static void drain_queue(srv_host_t *H, int fd, uint8_t *in, size_t cap, size_t *len,
                        struct sockaddr_in *peer)
{
    static uint8_t other[2048];
    ssize_t m;
    struct sockaddr_in p2;
    socklen_t l2 = sizeof p2;
    c4g_endpoint_t e;
    srv_t *S = &H->s;
    unsigned n_ctrl = 0U, n_foreign = 0U, k_guard = 0U;
    bool have = false, is_peer = false;
    endpoint_of(peer, &e);
    (void)c4g_loop_is_peer(&S->loop, &e, &have);
    while (k_guard++ < 100000U && (m = recvfrom(fd, other, sizeof other, MSG_DONTWAIT | MSG_TRUNC,
                                                (struct sockaddr *)&p2, &l2)) >= 0) {
        const uint64_t t = now_ns();
        const size_t k = ((size_t)m > sizeof other) ? sizeof other : (size_t)m;
        endpoint_of(&p2, &e);
        l2 = sizeof p2;
        if (foreign_address(H, &p2, m, t)) {
            n_foreign++;
            continue;
        }
        (void)c4g_loop_is_peer(&S->loop, &e, &is_peer);
        if (!is_peer) {
            srv_drop(S, other, k, &e, t); /* counted */
            n_foreign++;
            continue;
        }
        if (!have) { /* the first datagram was another endpoint's: count it before it goes */
            c4g_endpoint_t e0;
            endpoint_of(peer, &e0);
            srv_drop(S, in, *len, &e0, t);
            n_foreign++;
            have = true;
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
    uint64_t t_cap;       /* for --pcap: the kernel's receive time, else t_rx */
} dgram_t;

enum { SRV_NEXT = -1, SRV_HAVE = -2 }; /* besides exit codes: go on / a datagram is in */

static uint8_t g_in[2048];
static uint8_t g_out[C4G_INIT_SIZE];

/* recvfrom with the kernel's receive time of the datagram in d->t_cap (0: none). */
static ssize_t recv_stamped(srv_host_t *H, int fd, dgram_t *d)
{
    c4gh_udp_msg_t m;
    const ssize_t n = c4gh_udp_recv_flags(fd, MSG_TRUNC | MSG_DONTWAIT, H->kstamp_off, g_in, sizeof g_in, &m);
    if (n >= 0) {
        d->peer = m.from;
        d->plen = sizeof d->peer;
        d->t_cap = m.stamp_ns;
    }
    return n;
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

/* Wait for one datagram of the controller's address into g_in, or for the next deadline.
 * SRV_HAVE, SRV_NEXT (nothing came, or another address's), or an exit code. After an
 * active-freezing pause (the core's thaw_due) only the newest queued datagram is answered. */
static int receive(srv_host_t *H, int fd, uint64_t start, dgram_t *d)
{
    srv_t *S = &H->s;
    ssize_t n;
    uint64_t due;
    int code;
    if (g_stop) {
        return EXIT_SIGNAL;
    }
    if (S->cfg.max_seconds > 0.0 && (double)(now_ns() - start) * 1e-9 >= S->cfg.max_seconds) {
        return EXIT_TIMEOUT;
    }
    /* checked before every wait, not only when the socket is quiet: a stream from another
     * address must not hold off the silence and loss checks */
    due = next_due(S, start);
    if (now_ns() >= due) {
        code = on_idle(S, start);
        return (code >= 0) ? code : SRV_NEXT;
    }
    if (!wait_readable(S, fd, due)) {
        return SRV_NEXT; /* the deadline or a signal: checked above on the next call */
    }
    d->plen = sizeof d->peer;
    if (H->kstamp) {
        n = recv_stamped(H, fd, d);
    } else {
        n = recvfrom(fd, g_in, sizeof g_in, MSG_TRUNC | MSG_DONTWAIT, (struct sockaddr *)&d->peer,
                     &d->plen);
    }
    d->t_rx = now_ns();
    d->t_cap = (H->kstamp && d->t_cap != 0U && d->t_cap <= d->t_rx) ? d->t_cap : d->t_rx;
    if (n < 0) {
        return SRV_NEXT; /* EAGAIN, EINTR or a transient error: go on */
    }
    if (foreign_address(H, &d->peer, n, d->t_rx)) {
        return SRV_NEXT;
    }
    if ((size_t)n > sizeof g_in) {
        S->stats.oversize++;
        d->len = sizeof g_in;
    } else {
        d->len = (size_t)n;
    }
    if (S->thaw_due) {
        drain_queue(H, fd, g_in, sizeof g_in, &d->len, &d->peer);
        d->t_rx = now_ns();
        d->t_cap = d->t_rx;
    }
    return SRV_HAVE;
}

/* The send stamp of the datagram just sent, from the error queue (the clock read after
 * sendto when the kernel has none for it). */
static uint64_t sent_stamp(srv_host_t *H, int fd, uint64_t t_tx)
{
    static uint8_t buf[64];
    const uint32_t key = H->tx_key++;
    uint64_t t = 0U;
    c4gh_udp_msg_t m;
    unsigned guard = 0U;
    while (guard++ < 64U && c4gh_udp_recv(fd, 1, H->kstamp_off, buf, sizeof buf, &m) >= 0) {
        if (m.has_key && m.key == key && m.stamp_ns != 0U) {
            t = m.stamp_ns;
        }
    }
    return (t != 0U && t <= t_tx) ? t : t_tx;
}

/* Send the reply the core produced; the send time and the moni/pcap records. */
static void send_reply(srv_host_t *H, int fd, const dgram_t *d, const srv_verdict_t *v,
                       size_t olen)
{
    srv_t *S = &H->s;
    uint64_t t_tx;
    if (sendto(fd, g_out, olen, 0, (const struct sockaddr *)&d->peer, d->plen) != (ssize_t)olen) {
        S->stats.send_errors++;
    }
    t_tx = now_ns();
    if (v->kind == C4G_RX_CYCLIC) {
        log_moni(H, d->t_rx, v->pkt, srv_reply_packet(S)); /* before srv_sent: a 504 may end the session */
    }
    srv_sent(S, t_tx);
    log_datagram(H, LOG_PCAP_TX, H->kstamp ? sent_stamp(H, fd, t_tx) : t_tx, g_out, olen, &d->peer);
}

/* One datagram through the server core, the reply sent, then the active-freezing pause.
 * An exit code, or SRV_NEXT. */
static int handle(srv_host_t *H, int fd, const dgram_t *d)
{
    srv_t *S = &H->s;
    c4g_endpoint_t from;
    srv_verdict_t v;
    size_t olen = 0U;
    endpoint_of(&d->peer, &from);
    log_datagram(H, LOG_PCAP_RX, d->t_cap, g_in, d->len, &d->peer);
    if (srv_process(S, g_in, d->len, &from, d->t_rx, g_out, sizeof g_out, &olen, &v) != C4G_OK) {
        return SRV_NEXT;
    }
    if (v.send) {
        send_reply(H, fd, d, &v, olen);
    }
    if (v.freeze) {
        srv_log(S, now_ns(), "active freezing: pausing %.0f ms", v.pause_ms);
        pause_ms(v.pause_ms);
    }
    return (v.stop != SRV_STOP_NONE) ? stop_code(v.stop) : SRV_NEXT;
}

/* The kernel's address filter, and the only place that connects or disconnects the socket.
 * Once the session is in its cyclic phase the socket is connect()ed to the controller's
 * endpoint: datagrams of any other source no longer reach this loop (a flood from another
 * address costs the kernel, not the replies). During a start-up it stays open to every
 * source, because the session must see a second endpoint's start-up packets to refuse the
 * session (C4G_EV_CONTENDED); after a loss, a refusal or a new session it is open again, so
 * that the controller's next start-up is served from whatever port it uses. */
static void peer_filter(srv_host_t *H, int fd)
{
    const c4g_loop_state_t ls = srv_state(&H->s);
    const c4g_loop_state_t *s = &ls;
    const int want = s->locked && s->phase == C4G_PHASE_CYCLIC && s->peer.addr_len == 4U;
    char a[INET_ADDRSTRLEN];
    if (want && (!H->connected || memcmp(&H->conn_peer, &s->peer, sizeof s->peer) != 0)) {
        struct sockaddr_in to;
        memset(&to, 0, sizeof to);
        to.sin_family = AF_INET;
        memcpy(&to.sin_addr.s_addr, s->peer.addr, 4U);
        to.sin_port = htons(s->peer.port);
        inet_ntop(AF_INET, &to.sin_addr, a, sizeof a);
        if (connect(fd, (const struct sockaddr *)&to, sizeof to) == 0) {
            H->connected = 1;
            H->conn_peer = s->peer;
            srv_log(&H->s, now_ns(), "socket connected to the controller %s:%u: the kernel drops "
                    "every other source", a, (unsigned)s->peer.port);
        } else if (!H->connected) {
            H->connected = -1; /* said once; the user-space checks still hold */
            srv_log(&H->s, now_ns(), "connect to %s:%u: %s (other sources filtered in user space)",
                    a, (unsigned)s->peer.port, strerror(errno));
        }
    } else if (!want && H->connected > 0) {
        struct sockaddr none;
        memset(&none, 0, sizeof none);
        none.sa_family = AF_UNSPEC;
        (void)connect(fd, &none, sizeof none);
        H->connected = 0;
        srv_log(&H->s, now_ns(), "socket open to every source again (waiting for a start-up)");
    } else if (!want && H->connected < 0) {
        H->connected = 0;
    }
}

/* The per-packet loop. Returns the exit code. */
static int serve(srv_host_t *H, int fd)
{
    const uint64_t start = now_ns();
    for (;;) {
        dgram_t d;
        int code = receive(H, fd, start, &d);
        if (code == SRV_HAVE) {
            code = handle(H, fd, &d);
        }
        peer_filter(H, fd);
        if (code >= 0) {
            return code;
        }
    }
}

/* The configuration: command line, INI file, input files, the core. SRV_NEXT to go on,
 * else the exit code (0 after --help / --version). */
static int configure(srv_host_t *H, int argc, char **argv)
{
    char err[640];
    srv_config_default(&g_cfg);
    switch (srv_config_cli(&g_cfg, "c4g-server", C4GH_PCAP_ANCHOR(), argc, argv)) {
    case C4GH_CLI_RUN: break;
    case C4GH_CLI_DONE: return 0; /* --help, --version */
    default: return EXIT_USAGE;
    }
    if (srv_load_files(&g_cfg, err, sizeof err) != 0) {
        fprintf(stderr, "c4g-server: %s\n", err);
        return EXIT_USAGE;
    }
    if (srv_init(&H->s, &g_cfg, host_log, H) != C4G_OK) {
        fprintf(stderr, "c4g-server: session configuration refused\n");
        return EXIT_USAGE;
    }
    return SRV_NEXT;
}

/* Socket, outputs, the log writer thread, signals, real time. SRV_NEXT with the socket in
 * *fd, else the exit code. */
static int start(srv_host_t *H, int *fd)
{
    const srv_config_t *cfg = &H->s.cfg;
    struct sigaction sa;
    *fd = open_socket(H);
    if (*fd < 0) {
        return (*fd == -1) ? EXIT_USAGE : EXIT_SETUP;
    }
    H->local_port = htons((uint16_t)cfg->port);
    if (srv_outputs_open(H) != 0) {
        close(*fd);
        return EXIT_SETUP;
    }
    /* SIGINT and SIGTERM blocked from here in this thread and in the writer thread it
     * starts: only the wait (ppoll with g_waitmask) takes them, so none is lost between
     * the check of g_stop and the wait. --spin and --poll-us check g_stop as they poll. */
    if (!cfg->spin && cfg->poll_us == 0U) {
        sigset_t block;
        sigemptyset(&block);
        sigaddset(&block, SIGINT);
        sigaddset(&block, SIGTERM);
        (void)pthread_sigmask(SIG_BLOCK, &block, &g_waitmask);
    } else {
        (void)pthread_sigmask(SIG_BLOCK, NULL, &g_waitmask);
    }
    c4gh_rtlog_init(&H->log, srv_sink, H);
    if (c4gh_rtlog_start(&H->log) != 0) {
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
    if (srv_rt_setup(cfg, stderr) != 0) {
        c4gh_rtlog_stop(&H->log);
        close(*fd);
        return EXIT_SETUP;
    }
    if (!cfg->quiet) {
        fprintf(stderr, "c4g-server: listening on %s:%u, controller %s, NUM policy %s\n",
                cfg->bind_addr, cfg->port, cfg->ctrl_addr,
                cfg->num_policy == C4G_NUM_ECHO ? "echo" : "plus1");
    }
    return SRV_NEXT;
}

/* The report and the JSON summary at exit. Returns the exit code. */
static int finish(srv_host_t *H, int code)
{
    const srv_t *S = &H->s;
    const char *why;
    switch (code) {
    case EXIT_END: why = "504 from the controller (end of communication)"; break;
    case EXIT_LOST: why = "controller lost (no packet within the loss timeout)"; break;
    case EXIT_TIMEOUT: why = (srv_counters(S)->rx == 0U) ? "idle timeout: no controller"
                                                                 : "--max-seconds reached"; break;
    case EXIT_SIGNAL: why = "stopped by a signal"; break;
    default: why = "?"; break;
    }
    if (!S->cfg.quiet) {
        srv_report(H, stdout, why, code);
    }
    if (S->cfg.json_path[0] != '\0' && srv_json(H, S->cfg.json_path, why, code) != 0) {
        code = EXIT_SETUP;
    }
    srv_outputs_close(H);
    return code;
}

int main(int argc, char **argv)
{
    srv_host_t *H = &g_host;
    int fd = -1;
    int code = configure(H, argc, argv);
    if (code == SRV_NEXT) {
        code = start(H, &fd);
    }
    if (code != SRV_NEXT) {
        return code;
    }
    H->s.t0_ns = now_ns();
    /* --pcap records the kernel's receive and send times (as c4g-sim's does); without
     * kernel stamps, the clock reads around recvfrom and sendto */
    H->kstamp = (H->pcap != NULL) && c4gh_udp_enable(fd);
    H->kstamp_off = H->kstamp ? c4gh_udp_real_minus_mono() : 0U;
    code = serve(H, fd);
    c4gh_rtlog_stop(&H->log);
    close(fd);
    return finish(H, code);
}
