/* SPDX-License-Identifier: MIT */
/* ref_pc: a tiny reference C4G Open PC server for the c4g-sim end-to-end tests, built on
 * the library's session engine (recvfrom -> c4g_session_rx -> reply -> sendto). It can
 * misbehave on purpose (no reply, wrong NUM, stop after N, drop the Nth, request a mode)
 * and plays a minimal PC role in every supported mode so the scenarios can finish. It
 * counts its own slow replies (sent more than 1 ms after the packet's kernel arrival time;
 * with --slow-us each one is logged with its NUM), so a test can tell a late PC from a
 * simulator that blames the PC.
 *
 * Late on purpose: --late-us US[@N[,COUNT]] holds the replies to cyclic packets N..N+COUNT-1
 * (COUNT default 1; every cyclic packet without @N) until US microseconds after the packet's
 * kernel arrival time, and may be given up to 8 times; --wrong-num-at N[,COUNT] puts a wrong
 * NUM (+5) in the replies to those cyclic packets only (--wrong-num: in every reply). Both
 * make captures of a misbehaving PC. */
/* the kernel's receive stamp (SO_TIMESTAMPNS, SCM_TIMESTAMPNS) is not POSIX: the file asks
 * for it itself, so that docs/c4g-sim.md's plain cc line builds it too */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE 1
#endif
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "c4gopen.h"

static volatile sig_atomic_t stop_flag;
static void on_sig(int s) { (void)s; stop_flag = 1; }

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}

static void usage(void)
{
    fprintf(stderr,
            "usage: ref_pc -p PORT [--echo] [--no-reply] [--wrong-num] [--alter-init] [--stop-after N]\n"
            "              [--drop-nth N] [--exit-after K] [--request MODE@N] [--idle-ms MS]\n"
            "              [--max-s S] [--bind ADDR] [--slow-us US] [--late-us US[@N[,COUNT]]]\n"
            "              [--wrong-num-at N[,COUNT]]\n");
}

/* A range of cyclic packets (1-based, as counted by this PC) and a reply delay. */
typedef struct late_rule {
    long us;
    long from;
    long count;
} late_rule_t;

#define MAX_LATE 8

/* "US", "US@N" or "US@N,COUNT"; 0 on a malformed value. */
static int parse_late(const char *v, late_rule_t *r)
{
    char tail = '\0';
    r->from = 1;
    r->count = -1;
    if (sscanf(v, "%ld@%ld,%ld%c", &r->us, &r->from, &r->count, &tail) == 3) { /* N,COUNT */ }
    else if (sscanf(v, "%ld@%ld%c", &r->us, &r->from, &tail) == 2) { r->count = 1; }
    else if (sscanf(v, "%ld%c", &r->us, &tail) == 1) { r->from = 1; r->count = -1; }
    else { return 0; }
    return r->us >= 0 && r->us < 1000000 && r->from >= 1 && (r->count == -1 || r->count >= 1);
}

static int in_range(unsigned long k, long from, long count)
{
    return from >= 1 && (long)k >= from && (count < 0 || (long)k < from + count);
}

/* Wait until @p us after the kernel arrival time @p arrived (CLOCK_REALTIME), or @p us
 * from now when the arrival time is unknown. */
static void hold_reply(const struct timespec *arrived, long us)
{
    struct timespec due;
    if (arrived->tv_sec != 0) {
        due = *arrived;
        due.tv_nsec += us * 1000L;
        due.tv_sec += due.tv_nsec / 1000000000L;
        due.tv_nsec %= 1000000000L;
        while (clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &due, NULL) == EINTR && !stop_flag) {
        }
    } else {
        due.tv_sec = us / 1000000L;
        due.tv_nsec = (us % 1000000L) * 1000L;
        (void)nanosleep(&due, NULL);
    }
}

typedef struct axstate {
    int32_t last_mode;
    unsigned long entered;   /* cyclic count at entry */
    float hold;
    float integ;
    float acc;               /* accumulated PC contribution */
} axstate_t;

int main(int argc, char **argv)
{
    unsigned port = 0;
    const char *bind_addr = "127.0.0.1";
    c4g_session_config_t cfg;
    c4g_session_t s;
    int no_reply = 0;
    int wrong_num = 0;
    int alter_init = 0;
    long stop_after = -1;
    long drop_nth = -1;
    long exit_after = 600;
    long req_mode = -1;
    long req_at = -1;
    long idle_ms = 3000;
    long max_s = 55;
    long slow_us = 1000;
    int log_slow = 0;
    unsigned long slow = 0;
    uint64_t worst_ns = 0;
    const int on = 1;
    unsigned long rx_total = 0;
    unsigned long replied = 0;
    unsigned long cyclic = 0;
    unsigned long syncs = 0;
    unsigned long inits = 0;
    unsigned long dropped = 0;
    late_rule_t late[MAX_LATE];
    int n_late = 0;
    long wrong_from = -1;
    long wrong_count = 1;
    unsigned long held = 0;
    int ended = 0;
    int i;
    int fd;
    struct sockaddr_in a;
    uint64_t start;
    uint64_t last_rx;
    axstate_t ax[C4G_MAX_AXES];

    (void)c4g_session_config_default(&cfg);
    for (i = 1; i < argc; i++) {
        const char *o = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (strcmp(o, "-p") == 0 && v) { port = (unsigned)atoi(v); i++; }
        else if (strcmp(o, "--bind") == 0 && v) { bind_addr = v; i++; }
        else if (strcmp(o, "--echo") == 0) { cfg.num_policy = C4G_NUM_ECHO; }
        else if (strcmp(o, "--no-reply") == 0) { no_reply = 1; }
        else if (strcmp(o, "--wrong-num") == 0) { wrong_num = 1; }
        else if (strcmp(o, "--alter-init") == 0) { alter_init = 1; }
        else if (strcmp(o, "--stop-after") == 0 && v) { stop_after = atol(v); i++; }
        else if (strcmp(o, "--drop-nth") == 0 && v) { drop_nth = atol(v); i++; }
        else if (strcmp(o, "--exit-after") == 0 && v) { exit_after = atol(v); i++; }
        else if (strcmp(o, "--request") == 0 && v) {
            if (sscanf(v, "%ld@%ld", &req_mode, &req_at) != 2) { usage(); return 2; }
            i++;
        }
        else if (strcmp(o, "--idle-ms") == 0 && v) { idle_ms = atol(v); i++; }
        else if (strcmp(o, "--max-s") == 0 && v) { max_s = atol(v); i++; }
        else if (strcmp(o, "--slow-us") == 0 && v) { slow_us = atol(v); log_slow = 1; i++; }
        else if (strcmp(o, "--late-us") == 0 && v) {
            if (n_late >= MAX_LATE || !parse_late(v, &late[n_late])) { usage(); return 2; }
            n_late++;
            i++;
        }
        else if (strcmp(o, "--wrong-num-at") == 0 && v) {
            char tail = '\0';
            const int got = sscanf(v, "%ld,%ld%c", &wrong_from, &wrong_count, &tail);
            if ((got != 1 && got != 2) || wrong_from < 1 || wrong_count < 1) { usage(); return 2; }
            i++;
        }
        else { usage(); return 2; }
    }
    if (port == 0U) { usage(); return 2; }
    memset(ax, 0, sizeof ax);
    for (i = 0; i < (int)C4G_MAX_AXES; i++) { ax[i].last_mode = -1; }
    if (c4g_session_init(&s, &cfg) != C4G_OK) { return 2; }
    fd = socket(AF_INET, SOCK_DGRAM, 0);
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    if (inet_pton(AF_INET, bind_addr, &a.sin_addr) != 1 || fd < 0 ||
        bind(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        fprintf(stderr, "ref_pc: bind %s:%u: %s\n", bind_addr, port, strerror(errno));
        return 1;
    }
    (void)setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on);
    signal(SIGINT, on_sig);
    signal(SIGTERM, on_sig);
    /* the tests start the controller once this line is out: no datagram races the bind */
    fprintf(stderr, "ref_pc: listening on %s:%u\n", bind_addr, port);
    start = last_rx = now_ns();
    while (!stop_flag && !ended) {
        uint8_t buf[2048];
        uint8_t out[C4G_INIT_SIZE];
        size_t olen = 0;
        struct sockaddr_in from;
        socklen_t fl = sizeof from;
        struct timespec arrived = {0, 0};
        union { char c[128]; struct cmsghdr align; } ctl;
        struct iovec iov;
        struct msghdr m;
        struct cmsghdr *c;
        fd_set rf;
        struct timeval tv = {0, 100000};
        ssize_t n;
        c4g_rx_result_t res;
        uint64_t t = now_ns();
        if ((t - start) / 1000000000ULL >= (uint64_t)max_s ||
            (rx_total > 0U && (t - last_rx) / 1000000ULL >= (uint64_t)idle_ms)) {
            break;
        }
        FD_ZERO(&rf);
        FD_SET(fd, &rf);
        if (select(fd + 1, &rf, NULL, NULL, &tv) <= 0) { continue; }
        memset(&m, 0, sizeof m);
        iov.iov_base = buf;
        iov.iov_len = sizeof buf;
        m.msg_name = &from;
        m.msg_namelen = fl;
        m.msg_iov = &iov;
        m.msg_iovlen = 1;
        m.msg_control = ctl.c;
        m.msg_controllen = sizeof ctl.c;
        n = recvmsg(fd, &m, 0);
        if (n < 0) { continue; }
        fl = m.msg_namelen;
        for (c = CMSG_FIRSTHDR(&m); c != NULL; c = CMSG_NXTHDR(&m, c)) {
            if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
                memcpy(&arrived, CMSG_DATA(c), sizeof arrived);
            }
        }
        t = now_ns();
        last_rx = t;
        rx_total++;
        if (c4g_session_rx(&s, buf, (size_t)n, t, &res) != C4G_OK) { break; }
        if (res.kind == C4G_RX_DROPPED) { dropped++; continue; }
        if (res.kind == C4G_RX_SYNC) { syncs++; }
        if (res.kind == C4G_RX_INIT) { inits++; }
        if (res.kind == C4G_RX_CYCLIC) {
            const c4g_ctrl_packet_t *p = res.pkt;
            c4g_pc_packet_t tx;
            const float T = (float)s.init.period_ms / 1000.0F;
            cyclic++;
            if (cyclic == 1U) {
                fprintf(stderr, "ref_pc: cyclic from NUM %d\n", (int)p->num);
            }
            (void)c4g_pc_reply_neutral(p, &tx);
            for (i = 0; i < (int)p->n_axes; i++) {
                const c4g_ctrl_axis_t *x = &p->ax[i];
                axstate_t *st = &ax[i];
                const int arm = s.map.arm_of[i];
                const unsigned long k = cyclic - st->entered;
                float target;
                if (x->mode != st->last_mode) {
                    const int was_open = st->last_mode != 0 && st->last_mode != 501 && st->last_mode != -1;
                    if (!(was_open && (x->mode == 11 || x->mode == 12 || x->mode == 14 || x->mode == 15 ||
                                       x->mode == 17 || x->mode == 170))) {
                        st->entered = cyclic;
                        st->hold = x->actual_pos;
                        st->integ = 0.0F;
                        st->acc = 0.0F;
                    }
                    st->last_mode = x->mode;
                }
                switch (x->mode) {
                case 1: case 11: case 2: case 12: {
                    /* PD current loop + the SMP+ dynamic model (EXT1) as gravity feed-forward. */
                    const int m2 = (x->mode == 2 || x->mode == 12);
                    const float tvel = m2 ? x->target_vel / T : 0.0F;
                    const float e = (m2 ? x->target_pos : st->hold) - x->actual_pos;
                    target = m2 ? x->target_pos : st->hold;
                    tx.ax[i].target_pos = target;
                    tx.ax[i].target_vel = m2 ? x->target_vel : 0.0F;
                    tx.ax[i].current_add = x->ext[0] + 20.0F * e + 0.35F * (tvel - x->actual_vel / T);
                    if (tx.ax[i].current_add > 20.0F) tx.ax[i].current_add = 20.0F;
                    if (tx.ax[i].current_add < -20.0F) tx.ax[i].current_add = -20.0F;
                    if (x->mode == 2 && exit_after > 0 && (long)k >= exit_after) {
                        tx.ax[i].mode = 12; /* 2 stand-by: the PC ends mode 2 */
                    }
                    break;
                }
                case 4:
                    st->acc = (k < 500U) ? (float)k * 0.0005F : 0.25F;
                    tx.ax[i].target_pos = st->hold + st->acc;
                    tx.ax[i].target_vel = (k < 500U) ? 0.0005F : 0.0F;
                    break;
                case 5:
                    tx.ax[i].target_vel = (k < 500U) ? 0.0005F : 0.0F;
                    st->acc += tx.ax[i].target_vel;
                    tx.ax[i].target_pos = st->acc;
                    break;
                case 7:
                    tx.ax[i].target_pos = (k < 500U) ? 0.0002F : 0.0F;
                    break;
                case 8:
                    tx.ax[i].vel_add = (k < 250U) ? 0.0002F : ((k < 500U) ? -0.0002F : 0.0F);
                    break;
                case 9:
                    tx.ax[i].current_add = (k < 500U) ? 0.2F : 0.0F;
                    break;
                default:
                    break;
                }
                /* held until the controller leaves the mode (as the library's control
                 * layer does): one reply that comes too late must not lose the request */
                if ((x->mode == 1 || x->mode == 4 || x->mode == 5 || x->mode == 7 || x->mode == 8 ||
                     x->mode == 9) && exit_after > 0 && (long)k >= exit_after) {
                    tx.infpar = c4g_arm_byte_set(tx.infpar, (uint32_t)arm, C4G_EXIT_FROM_OPEN);
                }
                /* from packet N on, so one late reply does not lose the request */
                if (req_mode >= 0 && req_at >= 0 && (long)cyclic >= req_at) {
                    tx.ax[i].mode = (int32_t)req_mode;
                }
            }
            if ((res.events & C4G_EV_END) != 0U) { ended = 1; }
            if (no_reply || (stop_after >= 0 && (long)rx_total > stop_after) || (long)cyclic == drop_nth) {
                continue;
            }
            if (c4g_session_reply(&s, &tx, out, sizeof out, &olen) != C4G_OK) { continue; }
        } else {
            if (no_reply || (stop_after >= 0 && (long)rx_total > stop_after)) { continue; }
            if (c4g_session_reply(&s, NULL, out, sizeof out, &olen) != C4G_OK) { continue; }
        }
        if (alter_init && res.kind == C4G_RX_INIT) {
            out[C4G_INIT_OFF_AZLIM + 1U] ^= 0x01U; /* a PC holding other limits: AzLim axis 1 */
        }
        if (wrong_num || (res.kind == C4G_RX_CYCLIC && in_range(cyclic, wrong_from, wrong_count))) {
            const int32_t w = (int32_t)(out[0] | (out[1] << 8)) + 5;
            out[0] = (uint8_t)w;
            out[1] = (uint8_t)(w >> 8);
        }
        if (res.kind == C4G_RX_CYCLIC) {
            int r;
            for (r = 0; r < n_late; r++) {
                if (in_range(cyclic, late[r].from, late[r].count)) {
                    hold_reply(&arrived, late[r].us);
                    held++;
                    break;
                }
            }
        }
        if (sendto(fd, out, olen, 0, (struct sockaddr *)&from, fl) == (ssize_t)olen) {
            struct timespec sent;
            clock_gettime(CLOCK_REALTIME, &sent);
            if (arrived.tv_sec != 0) {
                const int64_t d = ((int64_t)sent.tv_sec - (int64_t)arrived.tv_sec) * 1000000000LL +
                                  ((int64_t)sent.tv_nsec - (int64_t)arrived.tv_nsec);
                if (d > slow_us * 1000LL) {
                    slow++;
                    if (log_slow) {
                        fprintf(stderr, "ref_pc: slow reply to NUM %d: %.1f us\n",
                                (int)(buf[0] | (buf[1] << 8)), (double)d / 1000.0);
                    }
                }
                if (d > 0 && (uint64_t)d > worst_ns) { worst_ns = (uint64_t)d; }
            }
            replied++;
            (void)c4g_session_sent(&s, now_ns());
        }
    }
    fprintf(stderr, "ref_pc: rx %lu sync %lu init %lu cyclic %lu replied %lu dropped %lu ended %d "
            "slow %lu worst %.1f us held %lu\n", rx_total, syncs, inits, cyclic, replied, dropped, ended,
            slow, (double)worst_ns / 1000.0, held);
    close(fd);
    return 0;
}
