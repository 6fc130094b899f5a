/* SPDX-License-Identifier: MIT */
/* c4g-sim: a C4G controller (SMP+ UDP client + DSA + robot + PDL2 program) for testing
 * C4G Open PC servers without a robot. See docs/c4g-sim.md. */
#include <arpa/inet.h>
#include <errno.h>
#include <getopt.h>
#include <linux/errqueue.h>
#include <linux/net_tstamp.h>
#include <math.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "c4g_pcap.h"
#include "c4g_textfile.h"
#include "sim.h"

#define EXIT_OK 0
#define EXIT_RUNTIME 1
#define EXIT_USAGE 2
#define EXIT_EXPECT 3
#define EXIT_OUTPUT 4

#define MAX_PENDING 8
#define MAX_DGRAM 2048

enum fault { F_DROP = 0, F_DELAY, F_DUP, F_REORDER, F_CORRUPT, F_TRUNCATE, F_COUNT };
static const char *const fault_names[F_COUNT] = {"drop", "delay", "duplicate", "reorder",
                                                 "corrupt", "truncate"};

typedef struct pending {
    int used;
    uint64_t due_ns;
    size_t len;
    uint8_t buf[C4G_INIT_SIZE];
} pending_t;

typedef enum out_kind { OK_SYNC = 0, OK_INIT, OK_CYCLIC } out_kind_t;

typedef struct outstanding {
    int active;
    int check;               /* 0: no reply is checked (504) */
    out_kind_t kind;
    int32_t num;
    uint64_t sent_ns;        /* when it left (the kernel's send timestamp when there is one) */
    uint64_t deadline_ns;    /* the tick by which its reply must have arrived */
    int has_key;             /* tx_key: SO_TIMESTAMPING id of its sendto */
    uint32_t tx_key;
    int got;                 /* a valid reply arrived (the first one is kept) */
    uint64_t got_ns;         /* its kernel arrival time */
    int answered;            /* judged: the reply arrived in time */
    size_t len;
    uint8_t raw[C4G_INIT_SIZE];
    c4g_pc_packet_t reply;
} outstanding_t;

#define LAT_BINS 20001

typedef struct stats {
    unsigned long sent, sync_sent, init_sent, cyclic_sent;
    unsigned long replies_ok, missing, late, wrong_num, malformed, foreign, duplicates, stale;
    unsigned long unexpected, consecutive, max_consecutive, overruns, rx_total, unjudged;
    uint64_t overrun_max;
    unsigned long fault[F_COUNT];
    unsigned long paused_ticks;
    uint64_t lat_min, lat_max, lat_sum;
    uint32_t lat_hist[LAT_BINS]; /* 1 us bins; the last one collects everything above */
} stats_t;

typedef struct app {
    sim_t sim;
    scn_t scn;
    int fd;
    struct sockaddr_in srv;
    uint32_t local_ip;
    uint16_t local_port;
    int verbose;
    int json;
    FILE *csv;
    c4g_pcap_t *pcap;
    int out_error;
    stats_t st;
    outstanding_t out;
    pending_t pend[MAX_PENDING];
    pending_t held;          /* reorder: sent after the next packet */
    double fault_frac[F_COUNT];
    unsigned delay_us;
    unsigned long pause_at, pause_len;
    int entry_fault;         /* --entry-fault: 0 none, 1 drop, 2 truncate */
    int32_t sent_modes[C4G_MAX_AXES]; /* modes of the last cyclic packet sent */
    sim_rng_t frng;
    int32_t prev_num;        /* NUM of the packet before the outstanding one */
    int kstamp;              /* kernel send/receive timestamps (SO_TIMESTAMPING) are on */
    uint32_t tx_seq;         /* SO_TIMESTAMPING id of the next sendto */
    uint64_t tol_ns;         /* own lateness beyond which a tick is an overrun */
    int detected;            /* policy "either": the one the PC showed first, -1 none yet */
} app_t;

static volatile sig_atomic_t g_stop;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}

static void usage(FILE *f)
{
    fprintf(f,
"Usage: c4g-sim [OPTIONS]\n"
"Simulates a Comau C4G controller running C4G Open: the SMP+ UDP client (start-up\n"
"handshake, cyclic packets, reply checking, table 17.1 errors), the DSA loops and a\n"
"robot model, and a PDL2-like scenario. The PC server under test must be running.\n"
"\n"
"Network and timing:\n"
"  -s, --server ADDR       PC server IPv4 address (default 127.0.0.1)\n"
"  -p, --port N            PC server UDP port (default 1000)\n"
"      --bind ADDR         local address to bind (default 0.0.0.0)\n"
"      --local-port N      local UDP port (default 0: any)\n"
"  -T, --period MS         SMP+ period, 1 or 2 ms (default 2, as figure 10.1)\n"
"      --t-cycle1 US       reply budget; later replies count as late (default 500)\n"
"      --num-policy P      accepted reply NUM: plus-one, echo or either (default either)\n"
"      --max-miss N        consecutive missing/wrong replies raising ERR_C4GOPEN_UDP (10)\n"
"Robot:\n"
"  -c, --config FILE       INI file (sections [sim] [model] [arm N] [axis A.L])\n"
"      --axes LIST         open axes per arm, e.g. 6 or 6,4 (default 6: figure 10.1)\n"
"      --startup-mode M    start-up mode of every open axis (default 0)\n"
"      --seed N            random seed for noise and faults (default 1)\n"
"      --no-follow-check   disable the controller's following-error check\n"
"Run:\n"
"  -S, --scenario FILE     PDL2-like scenario (fixtures/scenarios/*.scn)\n"
"  -n, --ticks N           stop after N cyclic ticks (default: when the scenario ends)\n"
"      --hold              keep running after the scenario ends (until --ticks or signal)\n"
"Fault injection on the simulator's own packets (F = fraction 0..1):\n"
"      --drop F  --duplicate F  --reorder F  --corrupt F  --truncate F\n"
"      --delay F[:US]      delay a fraction of packets by US microseconds (default 300)\n"
"      --pause TICK:N      stall: send nothing for N ticks from cyclic tick TICK\n"
"      --entry-fault drop|truncate  lose or cut the packet that opens each new mode\n"
"Outputs:\n"
"      --csv FILE          per-tick records (moni-style)\n"
"      --pcap FILE         every datagram in both directions (Ethernet/IPv4/UDP)\n"
"  -j, --json              end-of-run summary as JSON on stdout\n"
"  -v, --verbose           log events on stderr;  -q, --quiet: no summary\n"
"  -h, --help  -V, --version\n"
"\n"
"Exit status: 0 ok; 1 a table 17.1 error was raised (e.g. ERR_C4GOPEN_UDP) or a\n"
"socket failed; 2 usage, configuration or scenario error; 3 a scenario EXPECT failed\n"
"or WAIT PC timed out; 4 an output file could not be written.\n"
"\n"
"Examples:\n"
"  c4g-sim -p 41000 -S fixtures/scenarios/mode0.scn --json\n"
"  c4g-sim -p 41000 -T 1 --num-policy plus-one -n 5000 --pcap run.pcap --csv run.csv\n"
"  c4g-sim -p 41000 -c fixtures/sim/two-arms.ini --drop 0.01 --seed 7 -n 2000\n");
}

static int parse_frac(const char *s, double *out, unsigned *extra)
{
    char *end;
    double d;
    errno = 0;
    d = strtod(s, &end);
    if (end == s || errno != 0 || !(d >= 0.0 && d <= 1.0)) {
        return -1;
    }
    if (*end == ':' && extra != NULL) {
        char *e2;
        unsigned long v = strtoul(end + 1, &e2, 10);
        if (e2 == end + 1 || *e2 != '\0' || v > 10000000UL) {
            return -1;
        }
        *extra = (unsigned)v;
        end = e2;
    }
    if (*end != '\0') {
        return -1;
    }
    *out = d;
    return 0;
}

static int parse_ulong(const char *s, unsigned long lo, unsigned long hi, unsigned long *out)
{
    char *end;
    unsigned long v;
    if (s[0] == '-') {
        return -1;
    }
    errno = 0;
    v = strtoul(s, &end, 0);
    if (end == s || *end != '\0' || errno != 0 || v < lo || v > hi) {
        return -1;
    }
    *out = v;
    return 0;
}

/* ---- output -------------------------------------------------------------- */

static void pcap_record(app_t *a, int outgoing, const struct sockaddr_in *peer,
                        const uint8_t *buf, size_t len)
{
    struct timespec ts;
    uint32_t pip;
    uint16_t pport;
    if (a->pcap == NULL) {
        return;
    }
    clock_gettime(CLOCK_REALTIME, &ts);
    pip = ntohl(peer->sin_addr.s_addr);
    pport = ntohs(peer->sin_port);
    if ((outgoing ? c4g_pcap_write_udp(a->pcap, &ts, a->local_ip, a->local_port, pip, pport, buf, len)
                  : c4g_pcap_write_udp(a->pcap, &ts, pip, pport, a->local_ip, a->local_port, buf, len)) != 0) {
        a->out_error = 1;
    }
}

/* Returns 1 and the SO_TIMESTAMPING id of the datagram in @p key if it went out. */
static int raw_send(app_t *a, const uint8_t *buf, size_t len, uint32_t *key)
{
    ssize_t n = sendto(a->fd, buf, len, 0, (const struct sockaddr *)&a->srv, sizeof a->srv);
    if (n < 0 && errno != ECONNREFUSED) {
        if (!a->sim.fatal) {
            fprintf(stderr, "c4g-sim: sendto: %s\n", strerror(errno));
            sim_raise(&a->sim, C4G_CERR_TX_UDP, 0, 0);
            sim_all_drive_off(&a->sim);
            a->sim.fatal = 1;
        }
        return 0;
    }
    pcap_record(a, 1, &a->srv, buf, len);
    if (n < 0) {
        return 0;
    }
    if (key != NULL) {
        *key = a->tx_seq;
    }
    a->tx_seq++; /* the kernel numbers every datagram sent, from 0 */
    return 1;
}

static int roll(app_t *a, enum fault f)
{
    return a->fault_frac[f] > 0.0 && sim_rng_uniform(&a->frng) < a->fault_frac[f];
}

static void queue_pending(app_t *a, const uint8_t *buf, size_t len, uint64_t due)
{
    int i;
    for (i = 0; i < MAX_PENDING; i++) {
        if (!a->pend[i].used) {
            a->pend[i].used = 1;
            a->pend[i].due_ns = due;
            a->pend[i].len = len;
            memcpy(a->pend[i].buf, buf, len);
            return;
        }
    }
    (void)raw_send(a, buf, len, NULL); /* queue full: send now */
}

static int32_t get_num(const uint8_t *b);

/* 1 if this cyclic packet is the first to carry a new mode on some axis. */
static int mode_entry(app_t *a, const uint8_t *pkt, size_t len)
{
    int entry = 0;
    size_t i;
    for (i = 0; i < C4G_MAX_AXES && C4G_CYCLIC_SIZE(i + 1U) <= len; i++) {
        const int32_t m = get_num(&pkt[C4G_HEADER_SIZE + C4G_AXIS_SIZE * i]);
        if (m != a->sent_modes[i]) {
            entry = 1;
            a->sent_modes[i] = m;
        }
    }
    return entry;
}

/* Send one of our packets through fault injection. Returns 1 (and the datagram's
 * SO_TIMESTAMPING id in @p key) if it went out now, unaltered in time. */
static int send_packet(app_t *a, const uint8_t *pkt, size_t len, uint32_t *key)
{
    uint8_t buf[C4G_INIT_SIZE];
    int held_now = 0;
    int now = 0;
    memcpy(buf, pkt, len);
    a->st.sent++;
    if (a->out.kind == OK_CYCLIC && mode_entry(a, pkt, len) && a->entry_fault != 0) {
        /* the packet that opens a mode is lost or cut: the PC must not anchor on it */
        if (a->entry_fault == 1) {
            a->st.fault[F_DROP]++;
            goto flush_held;
        }
        len = len / 2U;
        a->st.fault[F_TRUNCATE]++;
    }
    if (roll(a, F_DROP)) {
        a->st.fault[F_DROP]++;
        goto flush_held;
    }
    if (roll(a, F_CORRUPT)) {
        const size_t at = (size_t)(sim_rng_next(&a->frng) % len);
        buf[at] ^= (uint8_t)(1U + sim_rng_next(&a->frng) % 255U);
        a->st.fault[F_CORRUPT]++;
    }
    if (roll(a, F_TRUNCATE)) {
        len = (size_t)(sim_rng_next(&a->frng) % len);
        a->st.fault[F_TRUNCATE]++;
    }
    if (roll(a, F_REORDER) && !a->held.used) {
        a->held.used = 1;
        a->held.len = len;
        memcpy(a->held.buf, buf, len);
        a->st.fault[F_REORDER]++;
        held_now = 1;
    } else if (roll(a, F_DELAY)) {
        queue_pending(a, buf, len, now_ns() + (uint64_t)a->delay_us * 1000U);
        a->st.fault[F_DELAY]++;
    } else {
        now = raw_send(a, buf, len, key);
        if (roll(a, F_DUP)) {
            (void)raw_send(a, buf, len, NULL);
            a->st.fault[F_DUP]++;
        }
    }
flush_held:
    if (a->held.used && !held_now) {
        (void)raw_send(a, a->held.buf, a->held.len, NULL);
        a->held.used = 0;
    }
    return now;
}

/* ---- replies ------------------------------------------------------------- */

static int32_t get_num(const uint8_t *b)
{
    return (int32_t)((uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) |
                     ((uint32_t)b[3] << 24));
}

static int num_ok(const app_t *a, int32_t sent, int32_t got)
{
    const int32_t plus = c4g_reply_num(sent, C4G_NUM_PLUS_ONE);
    switch (a->sim.cfg.policy) {
    case SIM_NUM_PLUS_ONE:
        return got == plus;
    case SIM_NUM_ECHO:
        return got == sent;
    default:
        /* "either": the PC may use one or the other, but consistently; its echo of the
         * init packet decides (otherwise a late plus-one reply would pass as the next echo). */
        if (a->detected == SIM_NUM_PLUS_ONE) {
            return got == plus;
        }
        if (a->detected == SIM_NUM_ECHO) {
            return got == sent;
        }
        return got == plus || got == sent;
    }
}

/* A reply to one of the STALE_WINDOW packets before the outstanding one: it came too late.
 * Wide enough for a PC that a busy host stopped for a second and that then answers the
 * backlog (NUM counts to 0x7FFF, so a wrong NUM is still told apart). */
#define STALE_WINDOW 512
static int is_stale(const app_t *a, int32_t cur, int32_t got)
{
    int p;
    for (p = 0; p < 2; p++) {
        int32_t d;
        const int32_t sent = (p == 0) ? got : got - 1;
        const int use = (a->sim.cfg.policy == SIM_NUM_EITHER) ? a->detected : (int)a->sim.cfg.policy;
        if ((p == 0 && use == SIM_NUM_PLUS_ONE) || (p == 1 && use == SIM_NUM_ECHO)) {
            continue;
        }
        d = (cur - sent + 0x8000) % 0x8000;
        if (d >= 1 && d <= STALE_WINDOW) {
            return 1;
        }
    }
    return 0;
}

static void handle_rx(app_t *a, const uint8_t *buf, size_t len, const struct sockaddr_in *from,
                      uint64_t t)
{
    outstanding_t *o = &a->out;
    int32_t num;
    c4g_diag_t diag;
    c4g_pc_packet_t pkt;
    a->st.rx_total++;
    pcap_record(a, 0, from, buf, len);
    if (from->sin_addr.s_addr != a->srv.sin_addr.s_addr || from->sin_port != a->srv.sin_port) {
        a->st.foreign++;
        if (a->verbose) {
            char ip[INET_ADDRSTRLEN];
            inet_ntop(AF_INET, &from->sin_addr, ip, sizeof ip);
            fprintf(stderr, "c4g-sim: ignored a datagram from foreign %s:%u\n", ip, ntohs(from->sin_port));
        }
        return;
    }
    if (!o->active || !o->check) {
        a->st.unexpected++;
        return;
    }
    if (len < 4U) {
        a->st.malformed++;
        return;
    }
    num = get_num(buf);
    if (!num_ok(a, o->num, num)) {
        if (is_stale(a, o->num, num)) {
            a->st.stale++;
        } else {
            a->st.wrong_num++;
            if (a->verbose) {
                fprintf(stderr, "c4g-sim: reply NUM %d to packet NUM %d violates the %s policy\n", num,
                        o->num, a->sim.cfg.policy == SIM_NUM_ECHO ? "echo"
                        : a->sim.cfg.policy == SIM_NUM_PLUS_ONE ? "plus-one" : "either");
            }
        }
        return;
    }
    switch (o->kind) {
    case OK_SYNC:
        if (len != C4G_SYNC_REPLY_SIZE) {
            a->st.malformed++;
            return;
        }
        break;
    case OK_INIT:
        if (len != C4G_INIT_SIZE || memcmp(&buf[4], &o->raw[4], C4G_INIT_SIZE - 4U) != 0) {
            a->st.malformed++;
            return;
        }
        break;
    default:
        if (c4g_pc_decode(buf, len, (uint32_t)a->sim.n_axes, &pkt, &diag) != C4G_OK) {
            a->st.malformed++;
            if (a->verbose) {
                fprintf(stderr, "c4g-sim: bad reply (%u bytes): %s, field %s, axis %d, value %lld\n",
                        (unsigned)len, c4g_strerror(diag.status), c4g_field_name(diag.field),
                        diag.axis, (long long)diag.value);
            }
            return;
        }
        break;
    }
    if (o->got) {
        a->st.duplicates++;
        return;
    }
    /* Judged at the next tick against the packet's deadline (evaluate), by arrival time. */
    o->got = 1;
    o->got_ns = t;
    /* "either" locks on the init echo: its 1200 bytes cannot be confused with a late
     * reply to a sync packet, so its NUM (11 or 10) shows the PC's policy. */
    if (o->kind == OK_INIT && a->sim.cfg.policy == SIM_NUM_EITHER) {
        a->detected = (num == o->num) ? SIM_NUM_ECHO : SIM_NUM_PLUS_ONE;
    }
    if (o->kind == OK_CYCLIC) {
        o->reply = pkt;
    }
}

static uint64_t ts_ns(const struct timespec *ts)
{
    return (uint64_t)ts->tv_sec * 1000000000ULL + (uint64_t)ts->tv_nsec;
}

/* CLOCK_REALTIME minus CLOCK_MONOTONIC: kernel timestamps are real time, the tick grid is
 * monotonic. The real-time read sits between two monotonic reads; the narrowest of three
 * brackets wins, so a preemption between the reads does not shift the offset. */
static uint64_t real_minus_mono(void)
{
    uint64_t best = 0, width = UINT64_MAX;
    int i;
    for (i = 0; i < 3 && width > 2000U; i++) {
        struct timespec r;
        const uint64_t m1 = now_ns();
        uint64_t m2;
        clock_gettime(CLOCK_REALTIME, &r);
        m2 = now_ns();
        if (m2 - m1 < width) {
            width = m2 - m1;
            best = ts_ns(&r) - (m1 + (m2 - m1) / 2U);
        }
    }
    return best;
}

/* The software timestamp of a received or error-queue message, on the monotonic clock;
 * 0 if there is none. Sets @p key for a send timestamp from the error queue. */
static uint64_t msg_stamp(struct msghdr *m, uint64_t off, int *has_key, uint32_t *key)
{
    struct cmsghdr *c;
    uint64_t t = 0;
    for (c = CMSG_FIRSTHDR(m); c != NULL; c = CMSG_NXTHDR(m, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPING) {
            struct scm_timestamping st;
            memcpy(&st, CMSG_DATA(c), sizeof st);
            t = ts_ns(&st.ts[0]);
        } else if (has_key != NULL && c->cmsg_level == IPPROTO_IP && c->cmsg_type == IP_RECVERR) {
            struct sock_extended_err e;
            memcpy(&e, CMSG_DATA(c), sizeof e);
            if (e.ee_origin == SO_EE_ORIGIN_TIMESTAMPING) {
                *has_key = 1;
                *key = e.ee_data;
            }
        }
    }
    return (t > off) ? t - off : 0U;
}

/* Read everything that has arrived, each datagram with its kernel arrival time, so a reply
 * that waited in the socket while the simulator was descheduled keeps its real time; then
 * the send timestamps of our own datagrams. */
static void drain(app_t *a)
{
    const uint64_t off = a->kstamp ? real_minus_mono() : 0U;
    int errq;
    for (errq = 0; errq < 2; errq++) {
        for (;;) {
            uint8_t buf[MAX_DGRAM];
            union { char c[256]; struct cmsghdr align; } ctl;
            struct sockaddr_in from;
            struct iovec iov;
            struct msghdr m;
            ssize_t n;
            uint64_t t, now;
            int has_key = 0;
            uint32_t key = 0;
            memset(&m, 0, sizeof m);
            memset(&from, 0, sizeof from);
            iov.iov_base = buf;
            iov.iov_len = sizeof buf;
            m.msg_name = &from;
            m.msg_namelen = sizeof from;
            m.msg_iov = &iov;
            m.msg_iovlen = 1;
            m.msg_control = ctl.c;
            m.msg_controllen = sizeof ctl.c;
            n = recvmsg(a->fd, &m, MSG_DONTWAIT | (errq ? MSG_ERRQUEUE : 0));
            if (n < 0) {
                break;
            }
            t = a->kstamp ? msg_stamp(&m, off, errq ? &has_key : NULL, &key) : 0U;
            now = now_ns();
            if (errq) {
                outstanding_t *o = &a->out;
                /* the send happened after the clock read in emit and before now */
                if (has_key && o->active && o->has_key && key == o->tx_key && t != 0U &&
                    t + 200000U >= o->sent_ns && t <= now) {
                    o->sent_ns = t;
                }
                continue;
            }
            handle_rx(a, buf, (size_t)n, &from, (t != 0U && t <= now) ? t : now);
        }
        if (!a->kstamp) {
            break;
        }
    }
}

/* Receive (and release delayed packets) until @p until. */
static void window(app_t *a, uint64_t until)
{
    for (;;) {
        uint64_t t = now_ns();
        uint64_t wake = until;
        int i;
        fd_set rf;
        struct timeval tv;
        for (i = 0; i < MAX_PENDING; i++) {
            if (a->pend[i].used && a->pend[i].due_ns <= t) {
                (void)raw_send(a, a->pend[i].buf, a->pend[i].len, NULL);
                a->pend[i].used = 0;
            } else if (a->pend[i].used && a->pend[i].due_ns < wake) {
                wake = a->pend[i].due_ns;
            }
        }
        if (t >= until || g_stop) {
            break;
        }
        FD_ZERO(&rf);
        FD_SET(a->fd, &rf);
        tv.tv_sec = (time_t)((wake - t) / 1000000000U);
        tv.tv_usec = (suseconds_t)(((wake - t) % 1000000000U) / 1000U);
        if (select(a->fd + 1, &rf, NULL, NULL, &tv) > 0) {
            drain(a);
        }
    }
}

/* At a tick boundary (the simulator woke at @p woke, everything that arrived is read):
 * did the reply to the outstanding packet arrive by its deadline? */
static void evaluate(app_t *a, uint64_t woke)
{
    outstanding_t *o = &a->out;
    int own_late;
    if (!o->active) {
        return;
    }
    o->active = 0;
    a->prev_num = o->num;
    if (!o->check || sim_checks_suspended(&a->sim)) {
        return;
    }
    /* Woken past the deadline, the simulator could not see it pass: a reply that was there
     * when it looked counts, and no reply is not the PC's fault alone (the whole host may
     * have stalled). */
    own_late = woke > o->deadline_ns && woke - o->deadline_ns > a->tol_ns;
    if (o->got && o->got_ns <= (own_late ? woke : o->deadline_ns)) {
        const uint64_t lat = (o->got_ns > o->sent_ns) ? o->got_ns - o->sent_ns : 0U;
        o->answered = 1;
        a->st.consecutive = 0;
        if (lat > (uint64_t)a->sim.cfg.t_cycle1_us * 1000U) {
            a->st.late++;
        }
        if (a->st.replies_ok == 0U || lat < a->st.lat_min) {
            a->st.lat_min = lat;
        }
        if (lat > a->st.lat_max) {
            a->st.lat_max = lat;
        }
        a->st.lat_sum += lat;
        a->st.lat_hist[(lat / 1000U < LAT_BINS - 1U) ? lat / 1000U : LAT_BINS - 1U]++;
        a->st.replies_ok++;
        return;
    }
    if (o->got) {
        a->st.stale++; /* it came, after its deadline */
    }
    /* Unjudged or missing, it is a packet without a reply: both extend the run that ends
     * in ERR_C4GOPEN_UDP; only a missing one is the PC's fault (ERR_C4GOPEN_UDP_DEBUG). */
    a->st.consecutive++;
    if (own_late) {
        a->st.unjudged++;
        if (a->verbose) {
            fprintf(stderr, "c4g-sim: no reply to NUM %d by a deadline the simulator overran "
                            "itself (%.1f ms late; %lu in a row)\n", o->num,
                    (double)(woke - o->deadline_ns) / 1e6, a->st.consecutive);
        }
    } else {
        a->st.missing++;
        a->sim.udp_debug++;
        if (a->verbose) {
            fprintf(stderr, "c4g-sim: %s: %s (NUM %d, %lu in a row; ", c4g_ctrl_error_name(C4G_CERR_UDP_DEBUG),
                    c4g_ctrl_error_message(C4G_CERR_UDP_DEBUG), o->num, a->st.consecutive);
            if (o->got) {
                fprintf(stderr, "the reply came %.1f us after the packet, %.1f us after the deadline)\n",
                        (double)(o->got_ns - o->sent_ns) / 1e3, (double)(o->got_ns - o->deadline_ns) / 1e3);
            } else {
                fprintf(stderr, "no reply %.1f us after the packet)\n", (double)(woke - o->sent_ns) / 1e3);
            }
        }
    }
    if (a->st.consecutive > a->st.max_consecutive) {
        a->st.max_consecutive = a->st.consecutive;
    }
    if (a->st.consecutive >= a->sim.cfg.max_miss) {
        sim_raise(&a->sim, C4G_CERR_UDP, 0, 0);
        sim_all_drive_off(&a->sim);
        a->sim.fatal = 1;
    }
}

static void emit(app_t *a, out_kind_t kind, int32_t num, const uint8_t *buf, size_t len, int check)
{
    outstanding_t *o = &a->out;
    o->active = 1;
    o->check = check;
    o->kind = kind;
    o->num = num;
    o->answered = 0;
    o->got = 0;
    o->deadline_ns = UINT64_MAX; /* set by the tick loop once the next tick is known */
    o->len = len;
    memcpy(o->raw, buf, len);
    o->sent_ns = now_ns();
    if (kind == OK_SYNC) {
        a->st.sync_sent++;
    } else if (kind == OK_INIT) {
        a->st.init_sent++;
    } else {
        a->st.cyclic_sent++;
    }
    o->has_key = send_packet(a, buf, len, &o->tx_key);
}

static void csv_header(app_t *a)
{
    int i;
    if (a->csv == NULL) {
        return;
    }
    fprintf(a->csv, "tick,time_s,num,sent,infpar,cmd,reply_ok");
    for (i = 0; i < a->sim.n_axes; i++) {
        fprintf(a->csv, ",a%d_mode,a%d_tpos,a%d_tvel,a%d_apos,a%d_avel,a%d_cur,a%d_rmode,a%d_rd1,"
                        "a%d_rd2,a%d_rd4,a%d_rd5", i, i, i, i, i, i, i, i, i, i, i);
    }
    fputc('\n', a->csv);
}

static void csv_row(app_t *a, const c4g_ctrl_packet_t *p, int sent, int reply_ok)
{
    int i;
    if (a->csv == NULL) {
        return;
    }
    fprintf(a->csv, "%lu,%.4f,%d,%d,0x%08x,0x%08x,%d", a->sim.tick,
            (double)a->sim.tick * a->sim.period, p->num, sent, (unsigned)p->infpar, (unsigned)p->cmd,
            reply_ok);
    for (i = 0; i < a->sim.n_axes; i++) {
        const c4g_ctrl_axis_t *x = &p->ax[i];
        const c4g_pc_axis_t *r = &a->sim.ax[i].rx;
        fprintf(a->csv, ",%d,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%.9g,%.9g,%.9g,%.9g", (int)x->mode,
                (double)x->target_pos, (double)x->target_vel, (double)x->actual_pos,
                (double)x->actual_vel, (double)x->current_ref, (int)r->mode, (double)r->target_pos,
                (double)r->target_vel, (double)r->vel_add, (double)r->current_add);
    }
    fputc('\n', a->csv);
}

static int32_t next_num(int32_t n)
{
    return (n >= C4G_NUM_MAX) ? 0 : n + 1;
}

/* ---- summary ------------------------------------------------------------- */

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s != '\0'; s++) {
        if (*s == '"' || *s == '\\') {
            fputc('\\', f);
        }
        if ((unsigned char)*s < 0x20U) {
            fprintf(f, "\\u%04x", (unsigned)*s);
        } else {
            fputc(*s, f);
        }
    }
    fputc('"', f);
}

/* Percentile of the reply latency in us, from the 1 us histogram (upper bin edge). */
static double lat_percentile(const stats_t *st, double q)
{
    uint64_t total = 0, need, acc = 0;
    int i;
    for (i = 0; i < LAT_BINS; i++) {
        total += st->lat_hist[i];
    }
    if (total == 0U) {
        return 0.0;
    }
    need = (uint64_t)(q * (double)total + 0.999999);
    for (i = 0; i < LAT_BINS; i++) {
        acc += st->lat_hist[i];
        if (acc >= need) {
            const double edge = (double)(i + 1), max_us = (double)st->lat_max / 1000.0;
            return (edge < max_us) ? edge : max_us;
        }
    }
    return (double)LAT_BINS;
}

static void summary(app_t *a, int code, const char *result, double cpu_s)
{
    const sim_t *s = &a->sim;
    const stats_t *st = &a->st;
    const double per_tick = (st->sent > 0U) ? cpu_s * 1e9 / (double)st->sent : 0.0;
    const double lat_avg = (st->replies_ok > 0U) ? (double)st->lat_sum / (double)st->replies_ok / 1000.0 : 0.0;
    const double p50 = lat_percentile(st, 0.5), p99 = lat_percentile(st, 0.99), p999 = lat_percentile(st, 0.999);
    int i;
    if (a->json) {
        FILE *f = stdout;
        fprintf(f, "{\"tool\":\"c4g-sim\",\"version\":\"%s\",\"result\":\"%s\",\"exit_code\":%d,",
                C4G_VERSION_STRING, result, code);
        fprintf(f, "\"period_ms\":%d,\"axes\":%d,\"ticks\":%lu,\"packets\":{\"sent\":%lu,\"sync\":%lu,"
                   "\"init\":%lu,\"cyclic\":%lu},", s->cfg.period_ms, s->n_axes, s->tick, st->sent,
                st->sync_sent, st->init_sent, st->cyclic_sent);
        fprintf(f, "\"replies\":{\"ok\":%lu,\"missing\":%lu,\"late\":%lu,\"unjudged\":%lu,\"wrong_num\":%lu,"
                   "\"malformed\":%lu,\"foreign\":%lu,\"duplicates\":%lu,\"stale\":%lu,\"unexpected\":%lu,"
                   "\"max_consecutive_missing\":%lu,\"latency_us\":{\"min\":%.1f,\"avg\":%.1f,\"p50\":%.0f,"
                   "\"p99\":%.0f,\"p999\":%.0f,\"max\":%.1f}},",
                st->replies_ok, st->missing, st->late, st->unjudged, st->wrong_num, st->malformed, st->foreign,
                st->duplicates, st->stale, st->unexpected, st->max_consecutive,
                (double)st->lat_min / 1000.0, lat_avg, p50, p99, p999, (double)st->lat_max / 1000.0);
        fprintf(f, "\"num_policy\":\"%s\",\"pc_policy\":\"%s\",\"udp_debug\":%lu,\"overruns\":%lu,"
                   "\"overrun_max_us\":%.1f,\"timestamps\":\"%s\",\"paused_ticks\":%lu,"
                   "\"mode_rejected\":%lu,\"mode_mismatch\":%lu,\"faults\":{",
                s->cfg.policy == SIM_NUM_ECHO ? "echo" : s->cfg.policy == SIM_NUM_PLUS_ONE ? "plus-one" : "either",
                a->detected == SIM_NUM_ECHO ? "echo" : a->detected == SIM_NUM_PLUS_ONE ? "plus-one" : "unknown",
                s->udp_debug, st->overruns, (double)st->overrun_max / 1000.0, a->kstamp ? "kernel" : "user",
                st->paused_ticks, s->mode_rejected, s->mode_mismatch);
        for (i = 0; i < F_COUNT; i++) {
            fprintf(f, "%s\"%s\":%lu", i ? "," : "", fault_names[i], st->fault[i]);
        }
        fprintf(f, "},\"errors\":[");
        for (i = 0; i < s->n_err; i++) {
            fprintf(f, "%s{\"name\":\"%s\",\"message\":", i ? "," : "", c4g_ctrl_error_name(s->err[i].code));
            json_str(f, s->err[i].text);
            fprintf(f, ",\"tick\":%lu}", s->err[i].tick);
        }
        fprintf(f, "],\"scenario\":{\"loaded\":%s,\"done\":%s,\"aborted\":%s,\"commands_run\":%d,"
                   "\"expect_passed\":%d,\"expect_failed\":%d,\"wait_pc_timeout\":%s},",
                s->scn ? "true" : "false", s->scn_done ? "true" : "false",
                s->scn_aborted ? "true" : "false", s->pc, s->expect_passed, s->expect_failed,
                s->scn_timeout ? "true" : "false");
        fprintf(f, "\"robot\":[");
        for (i = 0; i < s->n_axes; i++) {
            const sim_ax_t *x = &s->ax[i];
            fprintf(f, "%s{\"arm\":%d,\"axis\":%d,\"mode\":%d,\"drive_on\":%s,\"pos\":%.6f,\"target\":%.6f,"
                       "\"current\":%.4f}", i ? "," : "", x->arm + 1, x->logical + 1, x->mode,
                    x->m.drive_on ? "true" : "false", x->m.meas_pos, x->pos_ref, x->m.cur);
        }
        fprintf(f, "],\"cpu\":{\"seconds\":%.6f,\"ns_per_packet\":%.0f}}\n", cpu_s, per_tick);
        return;
    }
    printf("c4g-sim %s: %s (exit %d)\n", C4G_VERSION_STRING, result, code);
    printf("  ticks %lu, period %d ms, %d open axes\n", s->tick, s->cfg.period_ms, s->n_axes);
    printf("  sent %lu (sync %lu, init %lu, cyclic %lu)\n", st->sent, st->sync_sent, st->init_sent,
           st->cyclic_sent);
    printf("  replies ok %lu, missing %lu, late %lu, unjudged %lu, wrong NUM %lu, malformed %lu, "
           "foreign %lu, duplicates %lu, stale %lu\n", st->replies_ok, st->missing, st->late,
           st->unjudged, st->wrong_num, st->malformed, st->foreign, st->duplicates, st->stale);
    printf("  own overruns %lu (worst %.1f us after the tick), %s timestamps\n", st->overruns,
           (double)st->overrun_max / 1000.0, a->kstamp ? "kernel" : "user-space");
    printf("  reply latency us: min %.1f avg %.1f p50 %.0f p99 %.0f p99.9 %.0f max %.1f; max consecutive missing %lu\n",
           (double)st->lat_min / 1000.0, lat_avg, p50, p99, p999, (double)st->lat_max / 1000.0,
           st->max_consecutive);
    printf("  faults:");
    for (i = 0; i < F_COUNT; i++) {
        printf(" %s %lu", fault_names[i], st->fault[i]);
    }
    printf("; paused ticks %lu\n", st->paused_ticks);
    for (i = 0; i < s->n_err; i++) {
        printf("  error at tick %lu: %s: %s\n", s->err[i].tick, c4g_ctrl_error_name(s->err[i].code),
               s->err[i].text);
    }
    if (s->scn != NULL) {
        printf("  scenario: %s, %d commands, expectations %d passed %d failed\n",
               s->scn_aborted ? "aborted" : (s->scn_done ? "done" : "running"), s->pc, s->expect_passed,
               s->expect_failed);
    }
    for (i = 0; i < s->n_axes; i++) {
        const sim_ax_t *x = &s->ax[i];
        printf("  arm %d axis %d: mode %d, pos %.6f turns, target %.6f, current %.3f A\n", x->arm + 1,
               x->logical + 1, x->mode, x->m.meas_pos, x->pos_ref, x->m.cur);
    }
    printf("  cpu %.3f s, %.0f ns per packet\n", cpu_s, per_tick);
}

/* ---- main ---------------------------------------------------------------- */

static app_t g_app;

int main(int argc, char **argv)
{
    enum { O_BIND = 256, O_LPORT, O_TC1, O_POLICY, O_MAXMISS, O_AXES, O_SMODE, O_SEED, O_NOFOLLOW,
           O_HOLD, O_DROP, O_DELAY, O_DUP, O_REORDER, O_CORRUPT, O_TRUNC, O_PAUSE, O_CSV, O_PCAP,
           O_ENTRY };
    static const struct option opts[] = {
        {"server", required_argument, NULL, 's'}, {"port", required_argument, NULL, 'p'},
        {"bind", required_argument, NULL, O_BIND}, {"local-port", required_argument, NULL, O_LPORT},
        {"period", required_argument, NULL, 'T'}, {"t-cycle1", required_argument, NULL, O_TC1},
        {"num-policy", required_argument, NULL, O_POLICY}, {"max-miss", required_argument, NULL, O_MAXMISS},
        {"config", required_argument, NULL, 'c'}, {"axes", required_argument, NULL, O_AXES},
        {"startup-mode", required_argument, NULL, O_SMODE}, {"seed", required_argument, NULL, O_SEED},
        {"no-follow-check", no_argument, NULL, O_NOFOLLOW}, {"scenario", required_argument, NULL, 'S'},
        {"ticks", required_argument, NULL, 'n'}, {"hold", no_argument, NULL, O_HOLD},
        {"drop", required_argument, NULL, O_DROP}, {"delay", required_argument, NULL, O_DELAY},
        {"duplicate", required_argument, NULL, O_DUP}, {"reorder", required_argument, NULL, O_REORDER},
        {"corrupt", required_argument, NULL, O_CORRUPT}, {"truncate", required_argument, NULL, O_TRUNC},
        {"pause", required_argument, NULL, O_PAUSE}, {"csv", required_argument, NULL, O_CSV},
        {"entry-fault", required_argument, NULL, O_ENTRY},
        {"pcap", required_argument, NULL, O_PCAP}, {"json", no_argument, NULL, 'j'},
        {"verbose", no_argument, NULL, 'v'}, {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'}, {"version", no_argument, NULL, 'V'}, {NULL, 0, NULL, 0}};
    app_t *a = &g_app;
    sim_config_t cfg;
    const char *config_path = NULL;
    const char *scenario_path = NULL;
    const char *csv_path = NULL;
    const char *pcap_path = NULL;
    int quiet = 0;
    int opt;
    int code = EXIT_OK;
    int phase;
    int cold = 1;
    unsigned handshake_left;
    int32_t num = 1;
    uint64_t t0;
    uint64_t deadline;
    unsigned long cyclic_ticks = 0;
    unsigned long pause_left = 0;
    long freeze_left = 0;
    int have_reply = 0;
    int ended = 0;
    char err[512];
    struct rusage ru;
    double cpu_s;
    const char *result;
    struct sockaddr_in la;
    socklen_t ll = sizeof la;

    memset(a, 0, sizeof *a);
    a->fd = -1;
    a->delay_us = 300U;
    a->prev_num = -1;
    a->detected = -1;
    sim_config_default(&cfg);

    /* Pass 1: the configuration file, so command-line options override it. */
    opterr = 0;
    while ((opt = getopt_long(argc, argv, "s:p:T:c:S:n:jvqhV", opts, NULL)) != -1) {
        if (opt == 'c') {
            config_path = optarg;
        } else if (opt == 'h') {
            usage(stdout);
            return EXIT_OK;
        } else if (opt == 'V') {
            printf("c4g-sim %s (libc4gopen %s, %s)\n", C4G_VERSION_STRING, C4G_VERSION_STRING,
                   C4G_PCAP_ANCHOR());
            return EXIT_OK;
        }
    }
    if (config_path != NULL && sim_config_load(&cfg, config_path, err, sizeof err) != 0) {
        fprintf(stderr, "c4g-sim: %s\n", err);
        return EXIT_USAGE;
    }
    optind = 1;
    opterr = 1;
    while ((opt = getopt_long(argc, argv, "s:p:T:c:S:n:jvqhV", opts, NULL)) != -1) {
        unsigned long v;
        switch (opt) {
        case 's':
        case O_BIND:
            if (strlen(optarg) >= sizeof cfg.server) {
                fprintf(stderr, "c4g-sim: --%s: address too long\n", opt == 's' ? "server" : "bind");
                return EXIT_USAGE;
            }
            strcpy(opt == 's' ? cfg.server : cfg.bind_addr, optarg);
            break;
        case 'p':
        case O_LPORT:
            if (parse_ulong(optarg, opt == 'p' ? 1 : 0, 65535, &v) != 0) {
                fprintf(stderr, "c4g-sim: --%s: '%s' is not a UDP port\n", opt == 'p' ? "port" : "local-port", optarg);
                return EXIT_USAGE;
            }
            *(opt == 'p' ? &cfg.port : &cfg.local_port) = (unsigned)v;
            break;
        case 'T':
            if (parse_ulong(optarg, 1, 2, &v) != 0) {
                fprintf(stderr, "c4g-sim: --period: '%s' must be 1 or 2 (ms)\n", optarg);
                return EXIT_USAGE;
            }
            cfg.period_ms = (int)v;
            break;
        case O_TC1:
            if (parse_ulong(optarg, 1, 1000000, &v) != 0) {
                fprintf(stderr, "c4g-sim: --t-cycle1: '%s' is not 1..1000000 us\n", optarg);
                return EXIT_USAGE;
            }
            cfg.t_cycle1_us = (unsigned)v;
            break;
        case O_POLICY:
            if (strcmp(optarg, "plus-one") == 0) {
                cfg.policy = SIM_NUM_PLUS_ONE;
            } else if (strcmp(optarg, "echo") == 0) {
                cfg.policy = SIM_NUM_ECHO;
            } else if (strcmp(optarg, "either") == 0) {
                cfg.policy = SIM_NUM_EITHER;
            } else {
                fprintf(stderr, "c4g-sim: --num-policy: '%s' is not plus-one, echo or either\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case O_MAXMISS:
            if (parse_ulong(optarg, 1, 1000000, &v) != 0) {
                fprintf(stderr, "c4g-sim: --max-miss: '%s' is not 1..1000000\n", optarg);
                return EXIT_USAGE;
            }
            cfg.max_miss = (unsigned)v;
            break;
        case O_AXES: {
            const char *p = optarg;
            int arms = 0;
            while (*p != '\0') {
                char *end;
                long n = strtol(p, &end, 10);
                if (end == p || n < 1 || n > 10 || arms >= (int)C4G_ARMS || (*end != ',' && *end != '\0')) {
                    fprintf(stderr, "c4g-sim: --axes: '%s' must be 1..4 counts of 1..10, e.g. 6,4\n", optarg);
                    return EXIT_USAGE;
                }
                cfg.open_mask[arms++] = (1U << n) - 1U;
                p = (*end == ',') ? end + 1 : end;
            }
            cfg.n_arms = arms;
            if (sim_config_axes(&cfg) < 0) {
                fprintf(stderr, "c4g-sim: --axes: '%s': ERR_C4GOPEN: %s (more than 20 axes)\n", optarg,
                        c4g_ctrl_error_message(C4G_CERR_CONFIG));
                return EXIT_USAGE;
            }
            break;
        }
        case O_SMODE: {
            unsigned aa;
            unsigned l;
            if (parse_ulong(optarg, 0, 1000, &v) != 0 || !c4g_mode_is_known((int32_t)v)) {
                fprintf(stderr, "c4g-sim: --startup-mode: '%s' is not a mode code\n", optarg);
                return EXIT_USAGE;
            }
            for (aa = 0; aa < C4G_ARMS; aa++) {
                for (l = 0; l < C4G_AXES_PER_ARM; l++) {
                    cfg.ax[aa][l].startup_mode = (int)v;
                }
            }
            break;
        }
        case O_SEED:
            if (parse_ulong(optarg, 0, ~0UL, &v) != 0) {
                fprintf(stderr, "c4g-sim: --seed: '%s' is not a number\n", optarg);
                return EXIT_USAGE;
            }
            cfg.seed = v;
            break;
        case O_NOFOLLOW:
            cfg.check_follow = 0;
            break;
        case 'S':
            scenario_path = optarg;
            break;
        case 'n':
            if (parse_ulong(optarg, 1, ~0UL, &v) != 0) {
                fprintf(stderr, "c4g-sim: --ticks: '%s' is not a positive number\n", optarg);
                return EXIT_USAGE;
            }
            cfg.ticks = v;
            break;
        case O_HOLD:
            cfg.hold = 1;
            break;
        case O_DROP: case O_DELAY: case O_DUP: case O_REORDER: case O_CORRUPT: case O_TRUNC: {
            const enum fault f = (opt == O_DROP) ? F_DROP : (opt == O_DELAY) ? F_DELAY : (opt == O_DUP) ? F_DUP
                               : (opt == O_REORDER) ? F_REORDER : (opt == O_CORRUPT) ? F_CORRUPT : F_TRUNCATE;
            if (parse_frac(optarg, &a->fault_frac[f], f == F_DELAY ? &a->delay_us : NULL) != 0) {
                fprintf(stderr, "c4g-sim: --%s: '%s' is not a fraction 0..1%s\n", fault_names[f], optarg,
                        f == F_DELAY ? " (optionally :US)" : "");
                return EXIT_USAGE;
            }
            break;
        }
        case O_PAUSE: {
            char *end;
            a->pause_at = strtoul(optarg, &end, 10);
            if (end == optarg || *end != ':' || optarg[0] == '-' ||
                parse_ulong(end + 1, 1, 1000000, &a->pause_len) != 0) {
                fprintf(stderr, "c4g-sim: --pause: '%s' must be TICK:N\n", optarg);
                return EXIT_USAGE;
            }
            break;
        }
        case O_ENTRY:
            if (strcmp(optarg, "drop") == 0) {
                a->entry_fault = 1;
            } else if (strcmp(optarg, "truncate") == 0) {
                a->entry_fault = 2;
            } else {
                fprintf(stderr, "c4g-sim: --entry-fault: '%s' must be drop or truncate\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case O_CSV:
            csv_path = optarg;
            break;
        case O_PCAP:
            pcap_path = optarg;
            break;
        case 'j':
            a->json = 1;
            break;
        case 'v':
            a->verbose = 1;
            break;
        case 'q':
            quiet = 1;
            break;
        case 'c':
            break;
        default:
            fprintf(stderr, "Try 'c4g-sim --help'.\n");
            return EXIT_USAGE;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "c4g-sim: unexpected argument '%s'\nTry 'c4g-sim --help'.\n", argv[optind]);
        return EXIT_USAGE;
    }
    memset(&a->srv, 0, sizeof a->srv);
    a->srv.sin_family = AF_INET;
    a->srv.sin_port = htons((uint16_t)cfg.port);
    if (inet_pton(AF_INET, cfg.server, &a->srv.sin_addr) != 1) {
        fprintf(stderr, "c4g-sim: server address '%s' is not an IPv4 address\n", cfg.server);
        return EXIT_USAGE;
    }
    memset(&la, 0, sizeof la);
    la.sin_family = AF_INET;
    la.sin_port = htons((uint16_t)cfg.local_port);
    if (inet_pton(AF_INET, cfg.bind_addr, &la.sin_addr) != 1) {
        fprintf(stderr, "c4g-sim: bind address '%s' is not an IPv4 address\n", cfg.bind_addr);
        return EXIT_USAGE;
    }
    if (scenario_path != NULL) {
        tf_file_t f;
        int bad;
        if (tf_load(&f, scenario_path, TF_MAX_SCENARIO, err, sizeof err) != 0) {
            fprintf(stderr, "c4g-sim: %s\n", err);
            return EXIT_USAGE;
        }
        bad = scn_parse(scenario_path, f.data, f.len, &a->scn, err, sizeof err);
        tf_free(&f);
        if (bad != 0) {
            fprintf(stderr, "c4g-sim: %s\n", err);
            return EXIT_USAGE;
        }
    }
    if (sim_init(&a->sim, &cfg, scenario_path ? &a->scn : NULL, a->verbose ? stderr : NULL) != 0) {
        fprintf(stderr, "c4g-sim: %s: %s\n", c4g_ctrl_error_name(a->sim.err[0].code), a->sim.err[0].text);
        return EXIT_USAGE;
    }
    sim_rng_seed(&a->frng, cfg.seed + 0x5EEDU);

    /* Socket (ERR_C4GOPEN_SKT_UDP on failure). */
    a->fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (a->fd < 0 || bind(a->fd, (struct sockaddr *)&la, sizeof la) != 0 ||
        getsockname(a->fd, (struct sockaddr *)&la, &ll) != 0) {
        fprintf(stderr, "c4g-sim: %s:%u: %s\n", cfg.bind_addr, cfg.local_port, strerror(errno));
        sim_raise(&a->sim, C4G_CERR_SKT_UDP, 0, 0);
        fprintf(stderr, "c4g-sim: %s: %s\n", c4g_ctrl_error_name(C4G_CERR_SKT_UDP), a->sim.err[0].text);
        if (!quiet) {
            summary(a, EXIT_RUNTIME, "error", 0.0);
        }
        return EXIT_RUNTIME;
    }
    a->local_port = ntohs(la.sin_port);
    a->local_ip = ntohl(la.sin_addr.s_addr);
    {
        /* Replies are judged by their kernel arrival time and our packets by their kernel
         * send time, so the simulator's own scheduling delays are not charged to the PC.
         * If the kernel refuses them: clock reads in user space. */
        const unsigned ts = SOF_TIMESTAMPING_RX_SOFTWARE | SOF_TIMESTAMPING_TX_SOFTWARE |
                            SOF_TIMESTAMPING_SOFTWARE | SOF_TIMESTAMPING_OPT_ID |
                            SOF_TIMESTAMPING_OPT_TSONLY;
        const uint64_t p = (uint64_t)cfg.period_ms * 1000000U;
        const uint64_t b = (uint64_t)cfg.t_cycle1_us * 1000U;
        a->kstamp = setsockopt(a->fd, SOL_SOCKET, SO_TIMESTAMPING, &ts, sizeof ts) == 0;
        if (!a->kstamp && a->verbose) {
            fprintf(stderr, "c4g-sim: no kernel timestamps (%s): reply times from user space\n",
                    strerror(errno));
        }
        /* a late start up to min(t-cycle1, period - t-cycle1) still leaves a PC that answers
         * within t-cycle1 before the next tick */
        a->tol_ns = (b < p) ? ((b < p - b) ? b : p - b) : p / 2U;
    }
    if (a->local_ip == 0U) {
        /* Bound to any: the source address the kernel picks towards the server. */
        int t = socket(AF_INET, SOCK_DGRAM, 0);
        struct sockaddr_in r;
        socklen_t rl = sizeof r;
        if (t >= 0 && connect(t, (struct sockaddr *)&a->srv, sizeof a->srv) == 0 &&
            getsockname(t, (struct sockaddr *)&r, &rl) == 0) {
            a->local_ip = ntohl(r.sin_addr.s_addr);
        }
        if (t >= 0) {
            close(t);
        }
    }
    if (csv_path != NULL) {
        a->csv = fopen(csv_path, "w");
        if (a->csv == NULL) {
            fprintf(stderr, "c4g-sim: --csv %s: %s\n", csv_path, strerror(errno));
            close(a->fd);
            return EXIT_OUTPUT;
        }
        csv_header(a);
    }
    if (pcap_path != NULL) {
        a->pcap = c4g_pcap_open(pcap_path, err, sizeof err);
        if (a->pcap == NULL) {
            fprintf(stderr, "c4g-sim: --pcap: %s\n", err);
            close(a->fd);
            return EXIT_OUTPUT;
        }
    }
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGPIPE, SIG_IGN);

    phase = (cfg.sync_before > 0U) ? PH_SYNC_PRE : PH_INIT;
    handshake_left = cfg.sync_before;
    t0 = now_ns();
    deadline = t0;
    while (!ended && !g_stop) {
        uint8_t buf[C4G_INIT_SIZE];
        size_t len = 0;
        c4g_ctrl_packet_t pkt;
        const uint64_t woke = now_ns();
        drain(a);
        evaluate(a, woke);
        if (a->sim.fatal) {
            break;
        }
        if (a->out.kind == OK_CYCLIC) {
            have_reply = a->out.answered;
        }
        switch (phase) {
        case PH_SYNC_PRE:
        case PH_SYNC_POST:
            memset(&pkt, 0, sizeof pkt);
            pkt.num = num;
            pkt.n_axes = (uint32_t)a->sim.n_axes;
            (void)c4g_ctrl_encode(&pkt, buf, sizeof buf, &len);
            emit(a, OK_SYNC, num, buf, len, 1);
            num = next_num(num);
            if (--handshake_left == 0U) {
                phase = (phase == PH_SYNC_PRE) ? PH_INIT : PH_CYCLIC;
            }
            break;
        case PH_INIT:
            a->sim.init.num = C4G_INIT_NUM;
            (void)c4g_init_encode(&a->sim.init, buf, sizeof buf, &len);
            emit(a, OK_INIT, C4G_INIT_NUM, buf, len, 1);
            num = C4G_INIT_NUM + 1;
            a->sim.restart_req = 0;
            handshake_left = cfg.sync_after;
            phase = (cold && cfg.sync_after > 0U) ? PH_SYNC_POST : PH_CYCLIC;
            have_reply = 0;
            cold = 0;
            break;
        default: {
            const c4g_pc_packet_t *rep = have_reply ? &a->out.reply : NULL;
            int send = 1;
            have_reply = 0;
            a->out.answered = 0;
            if (a->pause_len > 0U && cyclic_ticks == a->pause_at) {
                pause_left = a->pause_len;
                a->pause_len = 0;
            }
            if (freeze_left > 0 && freeze_left == 1) {
                a->sim.special_out = C4G_MODE_FREEZING_P_OUT;
            }
            sim_tick(&a->sim, rep, &pkt);
            cyclic_ticks++;
            if (freeze_left > 0) {
                freeze_left--;
                a->sim.freeze_ticks = freeze_left;
                send = (freeze_left == 0);
            } else if (a->sim.freeze_ticks > 0) {
                freeze_left = a->sim.freeze_ticks; /* 502 goes out now, then silence */
            }
            if (pause_left > 0U) {
                pause_left--;
                a->st.paused_ticks++;
                send = 0;
            }
            pkt.num = num;
            if (send) {
                if (c4g_ctrl_encode(&pkt, buf, sizeof buf, &len) != C4G_OK) {
                    fprintf(stderr, "c4g-sim: internal: packet not encodable\n");
                    send = 0;
                } else {
                    emit(a, OK_CYCLIC, num, buf, len, !a->sim.exit_open_req);
                    num = next_num(num);
                }
            }
            csv_row(a, &pkt, send, rep != NULL);
            if (a->sim.exit_open_req) {
                ended = 1; /* 504 sent: end of communication */
            } else if (a->sim.restart_req && send) {
                phase = PH_INIT; /* 506 sent: the init packet follows, no sync packets */
            } else if (cfg.ticks != 0U && cyclic_ticks >= cfg.ticks) {
                ended = 1;
            } else if (a->sim.scn != NULL && (a->sim.scn_done || a->sim.scn_aborted) && !cfg.hold &&
                       freeze_left == 0) {
                ended = 1;
            }
            break;
        }
        }
        {
            /* The simulator's own overrun: its packet left so late that a PC answering within
             * t-cycle1 could miss the next tick. No burst to catch up: the grid restarts at
             * the send, so the PC always gets its period. */
            const uint64_t t = now_ns();
            if (t > deadline && t - deadline > a->tol_ns) {
                a->st.overruns++;
                if (t - deadline > a->st.overrun_max) {
                    a->st.overrun_max = t - deadline;
                }
                deadline = t;
            }
        }
        deadline += (uint64_t)cfg.period_ms * 1000000U;
        if (a->out.active) {
            a->out.deadline_ns = deadline;
        }
        window(a, deadline);
        {
            struct timespec ts;
            ts.tv_sec = (time_t)(deadline / 1000000000U);
            ts.tv_nsec = (long)(deadline % 1000000000U);
            while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR && !g_stop) {
            }
        }
    }
    if (!a->sim.fatal) {
        const uint64_t woke = now_ns();
        drain(a); /* what arrived before the end (or the signal) is counted */
        if (!g_stop) {
            evaluate(a, woke); /* the last packet had its window */
        }
    }
    if (a->sim.fatal) {
        sim_all_drive_off(&a->sim);
    }
    if (a->csv != NULL && fclose(a->csv) != 0) {
        a->out_error = 1;
    }
    if (a->pcap != NULL && c4g_pcap_close(a->pcap) != 0) {
        a->out_error = 1;
    }
    close(a->fd);
    getrusage(RUSAGE_SELF, &ru);
    cpu_s = (double)ru.ru_utime.tv_sec + (double)ru.ru_utime.tv_usec / 1e6 +
            (double)ru.ru_stime.tv_sec + (double)ru.ru_stime.tv_usec / 1e6;
    if (a->sim.n_err > 0) {
        code = EXIT_RUNTIME;
        result = "error";
    } else if (a->sim.expect_failed > 0 || a->sim.scn_timeout || a->sim.scn_aborted) {
        code = EXIT_EXPECT;
        result = "scenario-failed";
    } else if (a->out_error) {
        code = EXIT_OUTPUT;
        result = "output-error";
    } else {
        result = g_stop ? "interrupted" : "ok";
    }
    if (!quiet || a->json) {
        summary(a, code, result, cpu_s);
    }
    return code;
}
