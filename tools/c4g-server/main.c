/* SPDX-License-Identifier: MIT */
/* c4g-server: the PC side of C4G Open. Binds the UDP port, accepts packets only from
 * the controller's address, runs the libc4gopen loop object (session + control engine)
 * and answers every packet with a per-arm behaviour passed through the PC-side safety
 * filter. With --capture FILE the same core and host loop run over a recorded capture
 * instead of the socket (capture.c).
 *
 * The real-time loop (host.c, srv_serve): wait for the next datagram or the core's next
 * deadline (silence, loss, --idle-timeout, --max-seconds; no fixed timer) -> recvfrom ->
 * srv_process (tools/c4g-server/srv_core.c: c4g_loop_rx, controllers, c4g_loop_reply,
 * counters) -> sendto -> srv_sent. This file holds the socket source of that loop: the
 * socket, the clock, the wait, the active-freezing pause, the kernel's address filter and
 * the outputs. Nothing on that path allocates or does file I/O: logs, pcap and moni rows
 * go through a lock-free ring (lib/host/c4gh_rtlog.h) to a writer thread.
 *
 * The wait costs no system call of its own: the loop blocks in recvfrom itself, as a bare
 * echo loop does. The core's next deadline is a POSIX timer on the monotonic clock (a
 * high-resolution timer, not the socket's jiffy-grained SO_RCVTIMEO), armed only when the
 * deadline comes earlier than the armed one or after it fired: while datagrams keep coming,
 * the deadline moves later and the timer fires once per silence threshold, not per packet.
 * The timer's signal and SIGINT/SIGTERM interrupt recvfrom (no SA_RESTART); a signal that
 * lands between the loop's checks and the call is not lost either, because its handler
 * also switches the socket to O_NONBLOCK, so that recvfrom returns at once; the loop
 * switches it back after the failed read, before it checks again. */
#define _GNU_SOURCE /* ppoll: the active-freezing pause that unblocks SIGINT/SIGTERM atomically */
#include "srv.h"
#include "srv_capture.h"
#include "c4gh_cli.h"
#include "c4gh_pcap.h"
#include "c4gh_udp.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
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

enum { SRV_NEXT = -1, SRV_CAPTURE = -4 }; /* configure(): go on with the socket / a capture */

static srv_host_t g_host; /* static: large, and locked by mlockall */
static srv_config_t g_cfg;
static volatile sig_atomic_t g_stop;
/* The real-time thread's signal mask, SIGINT, SIGTERM and SIG_DEADLINE unblocked (the
 * writer thread runs with them blocked). */
static sigset_t g_waitmask;
/* The blocking wait (no --spin, no --poll-us): the socket and its blocking file flags for
 * the handlers, the deadline timer, the deadline it is armed for (0: none), and what the
 * handlers did (g_fired: the timer expired; g_nonblock: the socket is O_NONBLOCK). */
static int g_fd = -1;
static int g_fl;
static timer_t g_timer;
static volatile uint64_t g_armed;
static volatile sig_atomic_t g_fired;
static volatile sig_atomic_t g_nonblock;
/* The deadline the loop waits for, for the timer's handler (same thread: g_due_busy marks
 * a store in progress, which a 32-bit target splits in two). */
static volatile uint64_t g_due = C4G_NO_DEADLINE;
static volatile sig_atomic_t g_due_busy;
#define SIG_DEADLINE SIGRTMIN

/* Arm the deadline timer for @p due (monotonic ns; async-signal-safe). */
static void arm_timer(uint64_t due)
{
    struct itimerspec it;
    memset(&it, 0, sizeof it);
    it.it_value.tv_sec = (time_t)(due / 1000000000ULL);
    it.it_value.tv_nsec = (long)(due % 1000000000ULL);
    (void)timer_settime(g_timer, TIMER_ABSTIME, &it, NULL);
    g_armed = due;
}

/* Make a recvfrom that is about to start return at once (one that is blocked already
 * returns EINTR). fcntl is async-signal-safe; errno is kept for the interrupted code. */
static void wake_recv(void)
{
    const int e = errno;
    if (g_fd >= 0) {
        g_nonblock = 1;
        (void)fcntl(g_fd, F_SETFL, g_fl | O_NONBLOCK);
    }
    errno = e;
}

static void on_signal(int sig)
{
    g_stop = sig;
    wake_recv();
}

/* The deadline timer expired. Early (datagrams moved the deadline on since it was armed):
 * re-arm it for the deadline the loop published and let recvfrom go on (SA_RESTART), so a
 * steady stream costs one timer_settime per silence threshold and never a trip round the
 * loop. Due (or the deadline being published just now): wake the loop. */
static void on_deadline(int sig)
{
    const int e = errno;
    struct timespec ts;
    (void)sig;
    if (!g_due_busy) {
        const uint64_t due = g_due;
        if (due == C4G_NO_DEADLINE) {
            g_armed = 0U; /* nothing to wait for: stays disarmed */
            return;
        }
        clock_gettime(CLOCK_MONOTONIC, &ts);
        if ((uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec < due) {
            arm_timer(due);
            errno = e;
            return;
        }
    }
    errno = e;
    g_fired = 1;
    wake_recv();
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

/* --spin and --poll-us: poll the socket until it is readable (1) or @p due (monotonic ns)
 * came or a signal was taken (0). */
static int wait_readable(const srv_t *S, int fd, uint64_t due)
{
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
}

/* The active-freezing pause; a signal ends it. SIGINT and SIGTERM are blocked around the
 * check of g_stop and unblocked only inside ppoll, so one that comes in between ends the
 * pause too. */
static void pause_ms(double ms)
{
    const uint64_t due = now_ns() + (uint64_t)(ms * 1e6);
    struct timespec ts;
    sigset_t block, old;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    (void)pthread_sigmask(SIG_BLOCK, &block, &old);
    while (!g_stop && now_ns() < due) {
        (void)ppoll(NULL, 0, until(due, &ts), &old);
    }
    (void)pthread_sigmask(SIG_SETMASK, &old, NULL);
}

/* Publish @p due for the timer's handler and arm the timer when it must fire earlier than
 * it is armed for, or it fired. A later deadline (the usual case: every datagram moves the
 * silence check on) is armed only once the armed expiry is nearer than a quarter of the way
 * to it: at 1 kHz with the 10-period silence threshold one timer_settime every 7 or 8
 * packets, and the timer does not fire (no signal, no wake-up) while the stream goes on. If
 * no packet came in that quarter, it fires early and its handler re-arms it. */
static void arm_deadline(uint64_t due)
{
    uint64_t now;
    g_due_busy = 1;
    g_due = due;
    g_due_busy = 0;
    if (due == C4G_NO_DEADLINE) {
        g_fired = 0; /* one still armed fires and finds nothing due */
        return;
    }
    if (g_fired || g_armed == 0U || due < g_armed) {
        g_fired = 0;
        arm_timer(due);
        return;
    }
    now = now_ns();
    if (due > g_armed && g_armed > now && g_armed - now < (due - now) / 4U) {
        arm_timer(due);
    }
}

static void log_datagram(srv_host_t *H, uint32_t kind, uint64_t t, const uint8_t *buf, size_t n,
                         const c4g_endpoint_t *peer)
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
    const uint16_t port = htons(peer->port);
    memcpy(rec->data, peer->addr, 4U);
    memcpy(rec->data + 4, &port, 2U);
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

/* The send stamp of the datagram just sent, from the error queue (the clock read after
 * sendto when the kernel has none for it). The read stops at the stamp of this send: one
 * recvmsg a packet, not a second one to find the queue empty. Older stamps still queued
 * come out first; a stamp that comes after its read stays queued until the next send's
 * read (a queued stamp does not wake the blocking recvfrom, which waits for data only). */
static uint64_t sent_stamp(srv_host_t *H, int fd, uint64_t t_tx)
{
    static uint8_t buf[64];
    const uint32_t key = H->tx_key++;
    uint64_t t = 0U;
    c4gh_udp_msg_t m;
    unsigned guard = 0U;
    while (guard++ < 64U && c4gh_udp_recv(fd, 1, H->kstamp_off, buf, sizeof buf, &m) >= 0) {
        if (m.has_key && m.key == key) {
            t = m.stamp_ns;
            break;
        }
    }
    return (t != 0U && t <= t_tx) ? t : t_tx;
}

/* ---- the socket as the host loop's source (srv.h) */

typedef struct sock_src {
    srv_host_t *H;
    int fd;
} sock_src_t;

static uint64_t sock_now(void *ctx)
{
    (void)ctx;
    return now_ns();
}

/* One recvfrom into @p d (@p flags: MSG_DONTWAIT or 0, blocking; @p stamped: the kernel's
 * receive time in t_cap). */
static int sock_recv(sock_src_t *X, srv_dgram_t *d, int stamped, int flags)
{
    struct sockaddr_in peer;
    socklen_t plen = sizeof peer;
    ssize_t n;
    d->t_cap = 0U;
    if (stamped) {
        c4gh_udp_msg_t m;
        n = c4gh_udp_recv_flags(X->fd, MSG_TRUNC | flags, X->H->kstamp_off, d->buf, d->cap, &m);
        if (n >= 0) {
            peer = m.from;
            d->t_cap = m.stamp_ns;
        }
    } else {
        n = recvfrom(X->fd, d->buf, d->cap, MSG_TRUNC | flags, (struct sockaddr *)&peer, &plen);
    }
    d->t_rx = now_ns();
    d->t_cap = (stamped && d->t_cap != 0U && d->t_cap <= d->t_rx) ? d->t_cap : d->t_rx;
    if (n < 0) {
        return SRV_SRC_NONE; /* EAGAIN, EINTR or a transient error: go on */
    }
    d->size = (size_t)n;
    d->len = ((size_t)n > d->cap) ? d->cap : (size_t)n;
    srv_endpoint(ntohl(peer.sin_addr.s_addr), ntohs(peer.sin_port), &d->from);
    return SRV_SRC_HAVE;
}

/* The next datagram, or SRV_SRC_NONE at the deadline or a signal. Blocking: recvfrom
 * itself waits (see the top of the file); after a read that a handler cut short the socket
 * blocks again before the loop checks g_stop and the deadline, so no signal goes unseen. */
static int sock_next(void *ctx, uint64_t due, srv_dgram_t *d)
{
    sock_src_t *X = ctx;
    int r;
    if (g_fd < 0) { /* --spin, --poll-us */
        if (!wait_readable(&X->H->s, X->fd, due)) {
            return SRV_SRC_NONE;
        }
        return sock_recv(X, d, X->H->kstamp, MSG_DONTWAIT);
    }
    arm_deadline(due);
    r = sock_recv(X, d, X->H->kstamp, 0);
    if (r != SRV_SRC_HAVE && g_nonblock) {
        g_nonblock = 0;
        (void)fcntl(X->fd, F_SETFL, g_fl);
    }
    return r;
}

static int sock_queued(void *ctx, srv_dgram_t *d)
{
    return sock_recv((sock_src_t *)ctx, d, 0, MSG_DONTWAIT);
}

static void sock_accepted(void *ctx, const srv_dgram_t *d)
{
    sock_src_t *X = ctx;
    log_datagram(X->H, LOG_PCAP_RX, d->t_cap, d->buf, d->len, &d->from);
}

/* Send the reply the core produced; the send time and the moni/pcap records. */
static uint64_t sock_reply(void *ctx, const srv_dgram_t *d, const uint8_t *out, size_t olen,
                           const srv_verdict_t *v)
{
    sock_src_t *X = ctx;
    srv_host_t *H = X->H;
    struct sockaddr_in to;
    uint64_t t_tx;
    if (out == NULL) {
        return 0U;
    }
    memset(&to, 0, sizeof to);
    to.sin_family = AF_INET;
    memcpy(&to.sin_addr.s_addr, d->from.addr, 4U);
    to.sin_port = htons(d->from.port);
    if (sendto(X->fd, out, olen, 0, (const struct sockaddr *)&to, sizeof to) != (ssize_t)olen) {
        H->s.stats.send_errors++;
    }
    t_tx = now_ns();
    if (v->kind == C4G_RX_CYCLIC) {
        log_moni(H, d->t_rx, v->pkt, srv_reply_packet(&H->s)); /* before srv_sent: a 504 may end the session */
    }
    log_datagram(H, LOG_PCAP_TX, H->kstamp ? sent_stamp(H, X->fd, t_tx) : t_tx, out, olen, &d->from);
    return t_tx;
}

static void sock_pause(void *ctx, double ms)
{
    (void)ctx;
    pause_ms(ms);
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

static void sock_after(void *ctx)
{
    sock_src_t *X = ctx;
    peer_filter(X->H, X->fd);
}

/* The configuration: command line, INI file, input files, the core. SRV_NEXT to go on,
 * SRV_CAPTURE for a run over a capture, else the exit code (0 after --help / --version). */
static int configure(srv_host_t *H, int argc, char **argv)
{
    char err[640];
    srv_config_default(&g_cfg);
    switch (srv_config_cli(&g_cfg, "c4g-server", C4GH_PCAP_ANCHOR(), SRV_CLI_ALL, argc, argv)) {
    case C4GH_CLI_RUN: break;
    case C4GH_CLI_DONE: return 0; /* --help, --version */
    default: return EXIT_USAGE;
    }
    if (srv_capture_misplaced(&g_cfg.cap)) {
        return EXIT_USAGE;
    }
    if (srv_load_files(&g_cfg, err, sizeof err) != 0) {
        fprintf(stderr, "c4g-server: %s\n", err);
        return EXIT_USAGE;
    }
    if (g_cfg.cap.path[0] != '\0') {
        return SRV_CAPTURE;
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
    sigset_t block;
    *fd = open_socket(H);
    if (*fd < 0) {
        return (*fd == -1) ? EXIT_USAGE : EXIT_SETUP;
    }
    H->local_port = htons((uint16_t)cfg->port);
    if (srv_outputs_open(H) != 0) {
        close(*fd);
        return EXIT_SETUP;
    }
    /* SIGINT, SIGTERM and the deadline timer's signal blocked in the writer thread (it
     * inherits this mask) and unblocked again in this one below: they interrupt only the
     * real-time loop's recvfrom. --spin and --poll-us check g_stop as they poll. */
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    sigaddset(&block, SIG_DEADLINE);
    (void)pthread_sigmask(SIG_BLOCK, &block, &g_waitmask);
    c4gh_rtlog_init(&H->log, srv_sink, H);
    if (c4gh_rtlog_start(&H->log) != 0) {
        fprintf(stderr, "c4g-server: cannot start the log writer thread\n");
        close(*fd);
        return EXIT_SETUP;
    }
    memset(&sa, 0, sizeof sa); /* no SA_RESTART: a signal ends the blocked recvfrom */
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    if (!cfg->spin && cfg->poll_us == 0U) {
        struct sigevent ev;
        memset(&ev, 0, sizeof ev);
        ev.sigev_notify = SIGEV_SIGNAL;
        ev.sigev_signo = SIG_DEADLINE;
        sa.sa_handler = on_deadline;
        sa.sa_flags = SA_RESTART; /* an early expiry goes unnoticed by recvfrom */
        sigaction(SIG_DEADLINE, &sa, NULL);
        g_fl = fcntl(*fd, F_GETFL);
        if (g_fl < 0 || timer_create(CLOCK_MONOTONIC, &ev, &g_timer) != 0) {
            fprintf(stderr, "c4g-server: cannot create the deadline timer: %s\n", strerror(errno));
            c4gh_rtlog_stop(&H->log);
            close(*fd);
            return EXIT_SETUP;
        }
        g_fl &= ~O_NONBLOCK;
        g_fd = *fd;
    }
    (void)pthread_sigmask(SIG_SETMASK, &g_waitmask, NULL);
    /* RT settings last: the writer thread stays SCHED_OTHER; memory is locked from here */
    if (srv_rt_setup(cfg, stderr) != 0) {
        c4gh_rtlog_stop(&H->log);
        close(*fd);
        return EXIT_SETUP;
    }
    if (!cfg->quiet) {
        fprintf(stderr, "c4g-server: listening on %s:%u, controller %s, NUM policy %s\n",
                cfg->bind_addr, cfg->port, cfg->ctrl_addr,
                cfg->num_policy == C4G_NUM_ECHO ? "echo" : "plus-one");
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
    case EXIT_SIGNAL:
        /* SIGTERM is how a service manager stops the server: a normal end */
        why = (g_stop == SIGTERM) ? "stopped by SIGTERM" : "stopped by SIGINT";
        code = (g_stop == SIGTERM) ? 0 : C4GH_CLI_EXIT_SIGINT;
        break;
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
    sock_src_t X;
    srv_source_t src;
    int fd = -1;
    int code;
    if (argc > 1 && strcmp(argv[1], "--replay-rerun") == 0) {
        return srv_capture_rerun_main(argc, argv); /* c4g-replay rerun's two option sets */
    }
    code = configure(H, argc, argv);
    if (code == SRV_CAPTURE) {
        return srv_capture_main(&g_cfg, argc - 1, argv + 1);
    }
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
    X.H = H;
    X.fd = fd;
    memset(&src, 0, sizeof src);
    src.ctx = &X;
    src.now = sock_now;
    src.next = sock_next;
    src.queued = sock_queued;
    src.reply = sock_reply;
    src.pause = sock_pause;
    src.accepted = sock_accepted;
    src.after = sock_after;
    H->stop = &g_stop;
    code = srv_serve(H, &src);
    /* blocked again for the rest: a second Ctrl-C does not cut the files and the report
     * short (the loop is over, nothing waits for it any more) */
    {
        sigset_t block;
        sigemptyset(&block);
        sigaddset(&block, SIGINT);
        sigaddset(&block, SIGTERM);
        sigaddset(&block, SIG_DEADLINE);
        (void)pthread_sigmask(SIG_BLOCK, &block, NULL);
    }
    if (g_fd >= 0) {
        g_fd = -1;
        (void)timer_delete(g_timer);
    }
    c4gh_rtlog_stop(&H->log);
    close(fd);
    return finish(H, code);
}
