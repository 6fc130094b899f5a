/* SPDX-License-Identifier: MIT */
/* ctrl_stub: a test-only C4G controller (SMP+) for the c4g-server end-to-end tests.
 * Plays the field facts start-up handshake and cyclic packets with the library's
 * encoders, runs a tiny robot model per axis, checks every reply byte by byte and
 * prints a key=value summary. Not a simulator: c4g-sim is the real one. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#define MAXPH 32
typedef struct { int mode; long ticks; int until_exit; } phase_t;

static struct {
    char server[64]; unsigned port; char bind[64];
    int period_ms; unsigned arms_n[4]; int policy; /* 0 plus1 1 echo */
    phase_t ph[MAXPH]; int nph; int cold; int moving;
    long restart_at; long pfreeze_at; int pfreeze_ms; long garbage_every;
    long foreign_every; char foreign[64]; double fe_thr; long fe_push_at;
    double azlim; double dist; double gain; int reply_us; int quiet; long num_start;
} o;

static int fd, ffd = -1;
static struct sockaddr_in srv;
static uint8_t rbuf[2048];
static long bad, replies, missed, consec, max_consec, stale, n505, n508, n500, exits;
static long foreign_replies, sent_pkts, garbage_sent;
static int err_udp, drive_off, fe_err, frozen_a, freeze_survived;
static double rtt[200000]; static long nrtt;
static c4g_init_t ini; static c4g_axis_map_t map;
static double pos[20], vel[20], tgt[20], start[20], maxdev[20], maxcur[20], off7[20];
static int32_t num = 0;
static uint64_t next_ns;

static uint64_t now_ns(void)
{
    struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000ULL + (uint64_t)t.tv_nsec;
}
static void sleep_until(uint64_t t)
{
    struct timespec ts; ts.tv_sec = (time_t)(t / 1000000000ULL); ts.tv_nsec = (long)(t % 1000000000ULL);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {}
}
static void badf(const char *what, long a, long b)
{
    bad++;
    if (bad <= 10) fprintf(stderr, "ctrl_stub: BAD reply (NUM %d): %s (got %ld, want %ld)\n", (int)num, what, a, b);
}
/* field facts, written out here (not the library's c4g_reply_num): +1, 0x7FFF wraps to 1 */
static int32_t want_num(int32_t n) { return o.policy ? n : (n >= 0x7FFF ? 1 : n + 1); }
/* --num-start: NUM reaches the wrap in forward gaps shorter than half the range (a longer
 * jump reads as an older, stale packet to the PC) */
static int32_t jump_to = -1;
static int32_t next_num(void)
{
    if (jump_to >= 0) {
        const int32_t d = (jump_to - num + 0x8000) % 0x8000;
        if (d > 0x3000) { num = (num + 0x3000) % 0x8000; return num; }
        num = jump_to; jump_to = -1; return num;
    }
    num = (num >= C4G_NUM_MAX) ? 0 : num + 1;
    return num;
}

/* Wait for the reply to the datagram just sent; returns its length or -1. Past the
 * deadline the socket is still read without waiting: a stub descheduled by a busy host
 * must not call a reply missing that already waits in it. */
static ssize_t await(int32_t n, uint64_t t0, uint64_t deadline)
{
    for (;;) {
        uint64_t t = now_ns(); struct pollfd p; ssize_t k; int ms;
        ms = (t >= deadline) ? 0 : (int)((deadline - t + 999999) / 1000000); p.fd = fd; p.events = POLLIN;
        if (poll(&p, 1, ms) <= 0) { if (t >= deadline) return -1; continue; }
        k = recv(fd, rbuf, sizeof rbuf, 0);
        if (k < 4) { if (k >= 0) badf("short datagram", (long)k, 12); continue; }
        {
            int32_t rn = (int32_t)((uint32_t)rbuf[0] | (uint32_t)rbuf[1] << 8 | (uint32_t)rbuf[2] << 16 | (uint32_t)rbuf[3] << 24);
            if (rn != want_num(n)) { stale++; continue; }
        }
        if (nrtt < 200000) rtt[nrtt++] = (double)(now_ns() - t0) / 1000.0;
        return k;
    }
}

static void xsend(const uint8_t *b, size_t n)
{
    if (sendto(fd, b, n, 0, (struct sockaddr *)&srv, sizeof srv) < 0) perror("ctrl_stub: sendto");
    sent_pkts++;
}

static void check_raw_echo(const uint8_t *sent, size_t slen, size_t rlen, size_t want_len, int32_t n)
{
    size_t i;
    if (rlen != want_len) { badf("handshake reply length", (long)rlen, (long)want_len); return; }
    if ((int32_t)(rbuf[0] | rbuf[1] << 8 | rbuf[2] << 16 | (uint32_t)rbuf[3] << 24) != want_num(n)) badf("NUM", 0, 0);
    for (i = 4; i < rlen; i++) {
        uint8_t w = (i < slen) ? sent[i] : 0U;
        if (rbuf[i] != w) { badf("handshake echo byte", (long)i, (long)w); return; }
    }
}

static void handshake_sync(int count)
{
    int k;
    for (k = 0; k < count; k++) {
        uint8_t b[C4G_MAX_CYCLIC_SIZE]; size_t n = C4G_CYCLIC_SIZE(6); uint64_t t0; ssize_t r;
        memset(b, 0, sizeof b);
        next_num();
        b[0] = (uint8_t)num; b[1] = (uint8_t)(num >> 8); b[8] = (uint8_t)(0x10 + k); /* marker bytes */
        t0 = now_ns(); xsend(b, n);
        r = await(num, t0, t0 + 200000000ULL);
        if (r < 0) { missed++; badf("no sync reply", 0, 1); } else { replies++; check_raw_echo(b, n, (size_t)r, C4G_SYNC_REPLY_SIZE, num); }
        next_ns += (uint64_t)o.period_ms * 1000000ULL; sleep_until(next_ns);
    }
}

static void send_init(void)
{
    uint8_t b[C4G_INIT_SIZE]; size_t n; uint64_t t0; ssize_t r;
    num = C4G_INIT_NUM; ini.num = C4G_INIT_NUM;
    if (c4g_init_encode(&ini, b, sizeof b, &n) != C4G_OK) { fprintf(stderr, "ctrl_stub: init encode failed\n"); exit(1); }
    t0 = now_ns(); xsend(b, n);
    r = await(num, t0, t0 + 200000000ULL);
    if (r < 0) { missed++; badf("no init reply", 0, 1); } else { replies++; check_raw_echo(b, n, (size_t)r, C4G_INIT_SIZE, num); }
    next_ns += (uint64_t)o.period_ms * 1000000ULL; sleep_until(next_ns);
}

static void build_init(void)
{
    unsigned a, l, idx = 0;
    c4gsim_fig10_1(&ini);
    ini.period_ms = o.period_ms;
    for (a = 0; a < 4; a++) for (l = 0; l < 10; l++) {
        ini.open_ax[a][l] = (l < o.arms_n[a]) ? (int32_t)idx++ : C4G_OPEN_AX_NONE;
        ini.open_mask[a][l] = 0; ini.az_lim[a][l] = (float)o.azlim;
        ini.follow_error[a][l] = (float)o.fe_thr; ini.tx_rate[a][l] = 100.0f; ini.cal_data[a][l] = 0.0f;
    }
    ini.n_ax_open = (int32_t)idx;
    if (c4g_axis_map_build(&ini, &map, NULL) != C4G_OK) { fprintf(stderr, "ctrl_stub: bad arms\n"); exit(1); }
}

static int32_t cur_mode[20];
static void set_all(int m) { unsigned i; for (i = 0; i < map.n_axes; i++) cur_mode[i] = m; }

/* One cyclic exchange; returns 1 when the PC asked to exit from open on arm 1. */
static int cyclic(long tick)
{
    c4g_ctrl_packet_t p; c4g_pc_packet_t r; uint8_t b[C4G_MAX_CYCLIC_SIZE]; size_t n; unsigned i;
    uint64_t t0; ssize_t k; int exit_req = 0;
    memset(&p, 0, sizeof p);
    p.num = next_num(); p.n_axes = map.n_axes;
    for (i = 0; i < 4; i++) if (o.moving && o.arms_n[i] && !drive_off) p.infpar |= (uint32_t)C4G_STS_MOVING << (8 * i);
    for (i = 0; i < map.n_axes; i++) {
        c4g_ctrl_axis_t *a = &p.ax[i];
        a->mode = cur_mode[i];
        if (cur_mode[i] == 0 || cur_mode[i] == 10 || cur_mode[i] == 2 || cur_mode[i] == 12 || cur_mode[i] == 9)
            tgt[i] = start[i] + 0.05 * sin(2.0 * 3.14159265 * (double)tick * o.period_ms * 1e-3); /* SMP+ trajectory */
        a->target_pos = (float)tgt[i]; a->target_vel = 0.0f; a->actual_pos = (float)pos[i];
        a->actual_vel = (float)vel[i]; a->current_ref = (float)o.dist; a->ext[0] = 0.5f; a->ext[1] = 0.01f;
        if (o.fe_push_at > 0 && tick >= o.fe_push_at && (cur_mode[i] == 4 || cur_mode[i] == 1)) a->actual_pos = (float)(tgt[i] + 10.0 * o.fe_thr);
    }
    if (c4g_ctrl_encode(&p, b, sizeof b, &n) != C4G_OK) { fprintf(stderr, "ctrl_stub: encode failed\n"); exit(1); }
    t0 = now_ns(); xsend(b, n);
    if (o.foreign_every > 0 && ffd >= 0 && tick % o.foreign_every == 0) {
        if (sendto(ffd, b, n, 0, (struct sockaddr *)&srv, sizeof srv) < 0) perror("ctrl_stub: foreign sendto");
    }
    if (o.garbage_every > 0 && tick % o.garbage_every == 0) {
        uint8_t g[1500]; size_t gl = n; float nanf_ = NAN; int32_t badm = 77;
        memcpy(g, b, n);
        switch ((tick / o.garbage_every) % 7) {
        case 5: memset(g, 0xA5, sizeof g); gl = sizeof g; break;    /* oversize */
        case 6: memset(g, 0x5A, C4G_INIT_SIZE); g[0] = 10; g[1] = g[2] = g[3] = 0; gl = C4G_INIT_SIZE; break; /* bad init */
        case 0: gl = n - 5; break;                                  /* truncated */
        case 1: memcpy(g + 12 + 4, &nanf_, 4); break;               /* NaN in D1 */
        case 2: memcpy(g + 12, &badm, 4); break;                    /* unknown mode */
        case 3: gl = 7; break;                                      /* runt */
        default: g[0] = 0xFF; g[1] = 0xFF; g[2] = 0xFF; g[3] = 0x7F; break; /* NUM out of range */
        }
        sendto(fd, g, gl, 0, (struct sockaddr *)&srv, sizeof srv); garbage_sent++;
    }
    k = await(p.num, t0, t0 + (uint64_t)o.reply_us * 1000ULL);
    if (k < 0) {
        if (!frozen_a) { missed++; consec++; if (consec > max_consec) max_consec = consec;
            if (!o.quiet && missed <= 5) fprintf(stderr, "ctrl_stub: no reply to NUM %d (tick %ld, mode %d) within %d us\n", (int)p.num, tick, (int)p.ax[0].mode, o.reply_us); }
        if (consec >= 10 && !err_udp) { err_udp = 1; fprintf(stderr, "ctrl_stub: ERR_C4GOPEN_UDP after %ld missing replies\n", consec); }
        return 0;
    }
    consec = 0; replies++;
    if ((size_t)k != n) { badf("cyclic reply length", (long)k, (long)n); return 0; }
    if (c4g_pc_decode(rbuf, (size_t)k, map.n_axes, &r, NULL) != C4G_OK) { badf("reply does not decode", 0, 0); return 0; }
    if (r.cmd != 0U) badf("CMD", (long)r.cmd, 0);
    for (i = 0; i < 4; i++) {
        unsigned by = (r.infpar >> (8 * i)) & 0xFFU;
        if (by != 0U && by != C4G_EXIT_FROM_OPEN) badf("INFPAR byte", (long)by, 1);
        if (by == C4G_EXIT_FROM_OPEN && o.arms_n[i]) { exits++; if (i == 0) exit_req = 1; }
    }
    if (frozen_a && exit_req) { frozen_a = 0; freeze_survived = 1; set_all(0); return 0; }
    for (i = 0; i < map.n_axes; i++) {
        const c4g_pc_axis_t *x = &r.ax[i]; const c4g_ctrl_axis_t *a = &p.ax[i]; double ref, cur;
        if (x->mode == 505) { n505++; drive_off = 1; continue; }
        if (x->mode == 508) { n508++; fe_err = 1; drive_off = 1; continue; }
        if (x->mode == 500) { n500++; frozen_a = 1; continue; }
        if (x->mode != a->mode) { badf("mode echo", (long)x->mode, (long)a->mode); continue; }
        switch (a->mode) {
        case 0: case 501: case 502: case 503: case 504: case 506:
            if (x->target_pos != 0.0f || x->target_vel != 0.0f || x->vel_add != 0.0f || x->current_add != 0.0f) badf("mode 0 data not zero", 0, 0);
            pos[i] = tgt[i]; break;
        case 10:
            if (memcmp(&x->target_pos, &a->target_pos, 4) || memcmp(&x->target_vel, &a->target_vel, 4)) badf("mode 10 copy", 0, 0);
            pos[i] = x->target_pos; break;
        case 4: ref = x->target_pos; pos[i] = ref; tgt[i] = ref; break;
        case 5: ref = pos[i] + x->target_vel; pos[i] = ref; tgt[i] = ref; break;
        case 7: case 17: case 170: off7[i] += x->target_pos; pos[i] = tgt[i] + off7[i]; break;
        case 8: off7[i] += x->vel_add; pos[i] = tgt[i] + off7[i]; break;
        case 9: cur = a->current_ref + x->current_add; if (fabs(cur) > maxcur[i]) maxcur[i] = fabs(cur);
            if (fabs(cur) > o.azlim + 1e-4) badf("mode 9 current beyond AzLim (x1000)", (long)(cur * 1000), (long)(o.azlim * 1000));
            if (fabs(x->current_add) > 0) { off7[i] += 1; }
            pos[i] = tgt[i]; break;
        case 1: case 11: case 2: case 12:
            cur = x->current_add; if (fabs(cur) > maxcur[i]) maxcur[i] = fabs(cur);
            if (fabs(cur) > o.azlim + 1e-4) badf("current beyond AzLim (x1000)", (long)(cur * 1000), (long)(o.azlim * 1000));
            vel[i] += o.gain * (cur - o.dist); pos[i] += vel[i];
            if (a->mode == 1 || a->mode == 11) tgt[i] = x->target_pos;
            break;
        default: break;
        }
        if (fabs(pos[i] - start[i]) > maxdev[i]) maxdev[i] = fabs(pos[i] - start[i]);
    }
    return exit_req;
}

static void tick_wait(void) { next_ns += (uint64_t)o.period_ms * 1000000ULL; sleep_until(next_ns); }

static void parse_script(const char *s)
{
    char buf[512], *tok, *save = NULL;
    strncpy(buf, s, sizeof buf - 1);
    for (tok = strtok_r(buf, ",", &save); tok && o.nph < MAXPH; tok = strtok_r(NULL, ",", &save)) {
        phase_t *p = &o.ph[o.nph++]; char *c = strchr(tok, ':');
        p->mode = atoi(tok); p->ticks = 1; p->until_exit = 0;
        if (c) { if (strcmp(c + 1, "exit") == 0) { p->until_exit = 1; p->ticks = 20000; } else p->ticks = atol(c + 1); }
    }
}

static int cmpd(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }

int main(int argc, char **argv)
{
    int i; long tick = 0; unsigned a;
    memset(&o, 0, sizeof o);
    strcpy(o.server, "127.0.0.1"); strcpy(o.bind, "127.0.0.1"); o.port = 31000; o.period_ms = 2; o.arms_n[0] = 6;
    o.cold = 1; o.azlim = 10.0; o.gain = 1.3e-3; o.reply_us = 0; o.fe_thr = 0.0;
    for (i = 1; i < argc; i++) {
        const char *k = argv[i], *v = (i + 1 < argc) ? argv[i + 1] : "";
#define OPT(n) (strcmp(k, n) == 0 && (++i, 1))
        if (OPT("--port")) o.port = (unsigned)atoi(v);
        else if (OPT("--server")) strncpy(o.server, v, 63);
        else if (OPT("--bind")) strncpy(o.bind, v, 63);
        else if (OPT("--period-ms")) o.period_ms = atoi(v);
        else if (OPT("--arms")) { unsigned n[4] = {0, 0, 0, 0}; sscanf(v, "%u,%u,%u,%u", &n[0], &n[1], &n[2], &n[3]); memcpy(o.arms_n, n, sizeof n); }
        else if (OPT("--policy")) o.policy = strcmp(v, "echo") == 0;
        else if (OPT("--script")) parse_script(v);
        else if (strcmp(k, "--warm") == 0) o.cold = 0;
        else if (strcmp(k, "--moving") == 0) o.moving = 1;
        else if (strcmp(k, "--quiet") == 0) o.quiet = 1;
        else if (OPT("--restart-at")) o.restart_at = atol(v);
        else if (OPT("--passive-freeze")) sscanf(v, "%ld,%d", &o.pfreeze_at, &o.pfreeze_ms);
        else if (OPT("--garbage-every")) o.garbage_every = atol(v);
        else if (OPT("--foreign")) { sscanf(v, "%63[^,],%ld", o.foreign, &o.foreign_every); }
        else if (OPT("--fe")) o.fe_thr = atof(v);
        else if (OPT("--fe-push-at")) o.fe_push_at = atol(v);
        else if (OPT("--azlim")) o.azlim = atof(v);
        else if (OPT("--dist")) o.dist = atof(v);
        else if (OPT("--gain")) o.gain = atof(v);
        else if (OPT("--reply-us")) o.reply_us = atoi(v);
        else if (OPT("--num-start")) o.num_start = atol(v);
        else { fprintf(stderr, "ctrl_stub: unknown option %s\n", k); return 1; }
    }
    if (o.reply_us == 0) o.reply_us = o.period_ms * 900;
    if (o.nph == 0) parse_script("0:100,504:1");
    build_init();
    fd = socket(AF_INET, SOCK_DGRAM, 0);
    { struct sockaddr_in b; memset(&b, 0, sizeof b); b.sin_family = AF_INET; inet_pton(AF_INET, o.bind, &b.sin_addr);
      if (bind(fd, (struct sockaddr *)&b, sizeof b) != 0) { perror("ctrl_stub: bind"); return 1; } }
    memset(&srv, 0, sizeof srv); srv.sin_family = AF_INET; srv.sin_port = htons((uint16_t)o.port);
    inet_pton(AF_INET, o.server, &srv.sin_addr);
    if (o.foreign[0]) {
        struct sockaddr_in b; memset(&b, 0, sizeof b); b.sin_family = AF_INET; inet_pton(AF_INET, o.foreign, &b.sin_addr);
        ffd = socket(AF_INET, SOCK_DGRAM, 0);
        if (bind(ffd, (struct sockaddr *)&b, sizeof b) != 0) { perror("ctrl_stub: bind foreign"); return 1; }
    }
    for (i = 0; i < 20; i++) { start[i] = 1.0 + i; pos[i] = tgt[i] = start[i]; }
    next_ns = now_ns();
    if (o.cold) { handshake_sync(9); send_init(); handshake_sync(2); } else send_init();
    if (o.num_start > 0) jump_to = (int32_t)o.num_start; /* near the wrap (server sees gaps) */
    {
        int ph;
        for (ph = 0; ph < o.nph && !err_udp; ph++) {
            phase_t *P = &o.ph[ph]; long t; int got_exit = 0;
            if (drive_off && P->mode != 504) { set_all(0); } else set_all(P->mode);
            for (i = 0; i < (int)map.n_axes; i++) { start[i] = tgt[i]; off7[i] = 0; }
            for (t = 0; t < P->ticks && !err_udp; t++, tick++) {
                if (o.restart_at > 0 && tick == o.restart_at) {
                    set_all(506); cyclic(tick); tick_wait();
                    next_ns += 5ULL * (uint64_t)o.period_ms * 1000000ULL; sleep_until(next_ns);
                    send_init(); set_all(drive_off ? 0 : P->mode);
                }
                if (o.pfreeze_at > 0 && tick == o.pfreeze_at) {
                    set_all(502); cyclic(tick); 
                    sleep_until(now_ns() + (uint64_t)o.pfreeze_ms * 1000000ULL); next_ns = now_ns();
                    set_all(503); cyclic(tick); tick_wait(); set_all(P->mode); freeze_survived = 1;
                }
                if (drive_off && cur_mode[0] != 0 && P->mode != 504) set_all(0);
                if (cyclic(tick) && P->until_exit) got_exit = 1;
                if (err_udp) break;
                tick_wait();
                if (got_exit) {
                    if (P->mode == 1) { int j; set_all(11); for (j = 0; j < 50; j++, tick++) { cyclic(tick); tick_wait(); } }
                    if (P->mode == 7) { set_all(170); cyclic(tick++); tick_wait(); }
                    break;
                }
            }
            printf("ph%d_mode=%d\nph%d_exit=%d\nph%d_end=%.6f\nph%d_maxdev=%.6f\nph%d_off=%.6f\nph%d_maxcur=%.4f\n", ph, P->mode, ph, got_exit,
                   ph, pos[0] - start[0], ph, maxdev[0], ph, off7[0], ph, maxcur[0]);
            for (i = 0; i < 20; i++) { maxdev[i] = 0; maxcur[i] = 0; }
            if (P->until_exit && !got_exit && !drive_off) { fprintf(stderr, "ctrl_stub: phase %d (mode %d): no EXIT_FROM_OPEN\n", ph, P->mode); bad++; }
        }
    }
    printf("packets=%ld\nreplies=%ld\nbad=%ld\nmissed=%ld\nmax_consec_missed=%ld\nstale=%ld\n", sent_pkts, replies, bad, missed, max_consec, stale);
    printf("err=%s\n", err_udp ? "ERR_C4GOPEN_UDP" : fe_err ? "ERR_C4GOPEN_FOLLOW_ERROR" : drive_off ? "ERR_C4GOPEN_DRIVEOFF_SERVER" : "NONE");
    printf("n505=%ld\nn508=%ld\nn500=%ld\nexits=%ld\nfreeze_survived=%d\ngarbage=%ld\n", n505, n508, n500, exits, freeze_survived, garbage_sent);
    if (ffd >= 0) {
        struct pollfd p; p.fd = ffd; p.events = POLLIN;
        while (poll(&p, 1, 50) > 0) { if (recv(ffd, rbuf, sizeof rbuf, 0) >= 0) foreign_replies++; }
        printf("foreign_replies=%ld\n", foreign_replies);
    }
    for (a = 0; a < map.n_axes; a++)
        printf("ax%u_pos=%.6f\nax%u_dev=%.6f\nax%u_maxcur=%.4f\nax%u_off=%.6f\n", a + 1, pos[a] - start[a], a + 1, maxdev[a], a + 1, maxcur[a], a + 1, off7[a]);
    if (nrtt > 0) {
        qsort(rtt, (size_t)nrtt, sizeof rtt[0], cmpd);
        { long over = 0, j; for (j = 0; j < nrtt; j++) if (rtt[j] > 500.0) over++;
          printf("rtt_n=%ld\nrtt_p50_us=%.1f\nrtt_p99_us=%.1f\nrtt_p999_us=%.1f\nrtt_max_us=%.1f\nrtt_over500=%ld\n", nrtt,
                 rtt[nrtt / 2], rtt[(long)(nrtt * 0.99)], rtt[(long)(nrtt * 0.999)], rtt[nrtt - 1], over); }
    }
    return err_udp ? 3 : 0;
}
