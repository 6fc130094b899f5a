/* SPDX-License-Identifier: MIT */
/* A C4G Open session as a capture file, for the c4g-replay benchmarks: the start-up
 * (9 synchronization packets and their 732-byte replies, the initialization packet of
 * figure 10.1 with the period given and its echo, 2 synchronization packets), then cyclic
 * ticks: the controller in mode 0 for 2 s, then in mode 4 following the smooth motion the
 * PC commands, drives on (INFPAR 5); the PC answering each packet with NUM + 1, 150 to
 * 300 us later. Every packet goes through the library's encoders, so the capture is what a
 * conforming pair would put on the wire. The same arguments give the same bytes (a fixed
 * start time and a fixed pseudo-random sequence), so runs and machines compare.
 * With --dynamics, D5 is the current of a known axis model (inertia, viscous, Coulomb and
 * Stribeck friction, offset, Gaussian noise) for the motion D3/D4 report, so c4g-ident
 * has something real to fit (the c4g-ident benchmark).
 *   gen_capture [--minutes M | --seconds S] [--axes N] [--period-ms P] [--dynamics] FILE */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include "c4gh_pcap.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CTRL_IP 0xC0A8000AU /* 192.168.0.10 */
#define CTRL_PORT 10000U
#define PC_IP 0xC0A80014U   /* 192.168.0.20 */
#define PC_PORT 1000U
#define START_S 1700000000LL
#define MODE0_MS 2000U
#define TWO_PI 6.283185307179586

typedef struct gen {
    c4gh_pcap_t *w;
    uint64_t rng;
    int64_t period_ns;
    uint64_t tick;       /* controller packets so far: the time grid */
    int32_t num;         /* NUM of the next controller packet */
    uint32_t n_axes;
    c4g_init_t init;
    unsigned long bad;   /* encoder or writer failures */
    int dynamics;        /* D5 from the axis model below */
} gen_t;

/* The --dynamics axis model, in c4g-ident's units: i = JA acc + FV vel + (FC + (FS - FC)
 * exp(-(vel/VS)^2)) sign(vel) + OFF + noise [A, turns/s, turns/s^2]. */
#define DYN_JA 0.0031
#define DYN_FV 0.0079
#define DYN_FC 0.19
#define DYN_FS 0.30
#define DYN_VS 0.6
#define DYN_OFF 0.02
#define DYN_NOISE 0.01

/* One axis of the motion: the PC's reference q(t) = hold + amp (1 - cos w t), which
 * leaves the hold position with zero velocity, so mode 4 starts without a step. */
typedef struct axis_motion {
    double hold, amp;
    double c, s, dc, ds; /* cos and sin of w t, advanced by a rotation each tick */
    double w, t;         /* rad/s; time of cmd [s] */
    double cmd, cmd_prev, cmd_prev2;
} axis_motion_t;

static uint64_t next_rand(gen_t *g)
{
    uint64_t z = (g->rng += 0x9E3779B97F4A7C15ULL); /* splitmix64 */
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

static int64_t uniform(gen_t *g, int64_t lo, int64_t hi)
{
    return lo + (int64_t)(next_rand(g) % (uint64_t)(hi - lo + 1));
}

static void put_i32le(uint8_t *b, int32_t v)
{
    const uint32_t u = (uint32_t)v;
    b[0] = (uint8_t)u;
    b[1] = (uint8_t)(u >> 8);
    b[2] = (uint8_t)(u >> 16);
    b[3] = (uint8_t)(u >> 24);
}

static void write_at(gen_t *g, int64_t t_ns, int from_ctrl, const uint8_t *buf, size_t len)
{
    struct timespec ts;
    int rc;
    ts.tv_sec = (time_t)(t_ns / 1000000000LL);
    ts.tv_nsec = (long)(t_ns % 1000000000LL);
    if (from_ctrl) {
        rc = c4gh_pcap_write_udp(g->w, &ts, CTRL_IP, CTRL_PORT, PC_IP, PC_PORT, buf, len);
    } else {
        rc = c4gh_pcap_write_udp(g->w, &ts, PC_IP, PC_PORT, CTRL_IP, CTRL_PORT, buf, len);
    }
    if (rc != 0) {
        g->bad++;
    }
}

/* The controller's packet goes out on its period grid with a little jitter; the PC
 * answers 150..300 us later. Returns the time of the controller's packet. */
static int64_t ctrl_time(gen_t *g)
{
    const int64_t t = START_S * 1000000000LL + (int64_t)g->tick * g->period_ns +
                      uniform(g, -15, 15) * 1000LL;
    g->tick++;
    return t;
}

static int64_t reply_time(gen_t *g, int64_t t_ctrl)
{
    return t_ctrl + uniform(g, 150, 300) * 1000LL;
}

static int32_t num_after(int32_t n)
{
    return (n >= C4G_NUM_MAX) ? 0 : n + 1;
}

/* A synchronization packet (a cyclic packet of zeros but NUM) and its 732-byte reply. */
static void sync_pair(gen_t *g)
{
    c4g_ctrl_packet_t pkt;
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    uint8_t rep[C4G_SYNC_REPLY_SIZE];
    size_t len = 0U;
    int64_t t;
    memset(&pkt, 0, sizeof pkt);
    pkt.num = g->num;
    pkt.n_axes = g->n_axes;
    if (c4g_ctrl_encode(&pkt, buf, sizeof buf, &len) != C4G_OK) {
        g->bad++;
        return;
    }
    t = ctrl_time(g);
    write_at(g, t, 1, buf, len);
    memset(rep, 0, sizeof rep);
    memcpy(rep, buf, len);
    put_i32le(rep, c4g_reply_num(g->num, C4G_NUM_PLUS_ONE));
    write_at(g, reply_time(g, t), 0, rep, sizeof rep);
    g->num = num_after(g->num);
}

static void init_pair(gen_t *g)
{
    uint8_t buf[C4G_INIT_SIZE];
    size_t len = 0U;
    int64_t t;
    if (c4g_init_encode(&g->init, buf, sizeof buf, &len) != C4G_OK) {
        g->bad++;
        return;
    }
    t = ctrl_time(g);
    write_at(g, t, 1, buf, len);
    put_i32le(buf, c4g_reply_num(C4G_INIT_NUM, C4G_NUM_PLUS_ONE)); /* the echo, NUM 11 */
    write_at(g, reply_time(g, t), 0, buf, len);
    g->num = C4G_INIT_NUM + 1;
}

/* Figure 10.1 with @p axes open axes (10 per arm) and the period given; axes past the
 * figure's 6 repeat its values. */
static int make_init(c4g_init_t *in, uint32_t axes, int32_t period_ms)
{
    uint32_t i;
    if (c4gsim_fig10_1(in) != C4G_OK) {
        return -1;
    }
    in->n_ax_open = (int32_t)axes;
    in->period_ms = period_ms;
    for (i = 0U; i < C4G_ARMS * C4G_AXES_PER_ARM; i++) {
        const uint32_t arm = i / C4G_AXES_PER_ARM, lax = i % C4G_AXES_PER_ARM, f = i % 6U;
        in->open_ax[arm][lax] = (i < axes) ? (int32_t)i : (int32_t)C4G_OPEN_AX_NONE;
        if (i < axes && i >= 6U) {
            in->cal_data[arm][lax] = in->cal_data[0][f];
            in->az_lim[arm][lax] = in->az_lim[0][f];
            in->ax_info[arm][lax] = in->ax_info[0][f];
            in->tx_rate[arm][lax] = in->tx_rate[0][f];
            in->follow_error[arm][lax] = in->follow_error[0][f];
        }
    }
    return (c4g_init_validate(in, NULL) == C4G_OK) ? 0 : -1;
}

static void motion_init(axis_motion_t *m, uint32_t n, double period_s)
{
    uint32_t i;
    for (i = 0U; i < n; i++) {
        const double w = TWO_PI * (0.1 + 0.03 * (double)i); /* rad/s */
        m[i].w = w;
        m[i].t = 0.0;
        m[i].hold = 0.5 * (double)(i + 1U) - 2.0;
        m[i].amp = 2.0 + 0.5 * (double)i;
        m[i].c = 1.0;
        m[i].s = 0.0;
        m[i].dc = cos(w * period_s);
        m[i].ds = sin(w * period_s);
        m[i].cmd = m[i].hold;
        m[i].cmd_prev = m[i].hold;
        m[i].cmd_prev2 = m[i].hold;
    }
}

/* The next reference: one tick further along the motion. */
static void motion_step(axis_motion_t *m)
{
    const double c = m->c * m->dc - m->s * m->ds;
    m->s = m->s * m->dc + m->c * m->ds;
    m->c = c;
    m->cmd_prev2 = m->cmd_prev;
    m->cmd_prev = m->cmd;
    m->cmd = m->hold + m->amp * (1.0 - c);
}

/* The controller's packet: in mode 0 it holds the arm still; in mode 4 its target is the
 * PC's last reference and the arm follows one tick behind. */
static double gauss(gen_t *g)
{
    /* Box-Muller on two uniforms in (0, 1] */
    const double u1 = ((double)(next_rand(g) >> 11) + 1.0) / 9007199254740992.0;
    const double u2 = (double)(next_rand(g) >> 11) / 9007199254740992.0;
    return sqrt(-2.0 * log(u1)) * cos(TWO_PI * u2);
}

/* The model current of the interval D4 reports (the arm is one tick behind the reference,
 * so that interval ends one tick before m->t): the mean over it, by its midpoint. */
static double dyn_current(gen_t *g, const axis_motion_t *m, double period)
{
    const double tm = m->t - 1.5 * period;
    const double vel = m->amp * m->w * sin(m->w * tm);
    const double acc = m->amp * m->w * m->w * cos(m->w * tm);
    const double r = vel / DYN_VS;
    const double fr = DYN_FC + (DYN_FS - DYN_FC) * exp(-r * r);
    const double sgn = (vel > 0.0) ? 1.0 : ((vel < 0.0) ? -1.0 : 0.0);
    if (m->t <= 0.0) {
        return DYN_OFF + DYN_NOISE * gauss(g);
    }
    return DYN_JA * acc + DYN_FV * vel + fr * sgn + DYN_OFF + DYN_NOISE * gauss(g);
}

static void ctrl_packet(gen_t *g, const axis_motion_t *m, int mode4, c4g_ctrl_packet_t *p)
{
    uint32_t i;
    memset(p, 0, sizeof *p);
    p->num = g->num;
    p->n_axes = g->n_axes;
    for (i = 0U; i < g->n_axes; i++) {
        const uint32_t arm = i / C4G_AXES_PER_ARM, lax = i % C4G_AXES_PER_ARM;
        const double az = (double)g->init.az_lim[arm][lax];
        c4g_ctrl_axis_t *x = &p->ax[i];
        p->infpar = c4g_arm_byte_set(p->infpar, arm, (uint8_t)C4G_STS_MOVING);
        x->mode = mode4 ? C4G_MODE_4 : C4G_MODE_0;
        x->target_pos = (float)m[i].cmd;
        x->target_vel = (float)(m[i].cmd - m[i].cmd_prev);
        x->actual_pos = (float)m[i].cmd_prev;
        x->actual_vel = (float)(m[i].cmd_prev - m[i].cmd_prev2);
        x->current_ref = g->dynamics ? (float)dyn_current(g, &m[i], (double)g->period_ns * 1e-9)
                                     : (float)(az * (0.1 + 0.2 * m[i].s));
    }
}

static void pc_reply(const c4g_ctrl_packet_t *rx, const axis_motion_t *m, int mode4,
                     c4g_pc_packet_t *tx)
{
    uint32_t i;
    if (c4g_pc_reply_neutral(rx, tx) != C4G_OK) {
        memset(tx, 0, sizeof *tx);
    }
    tx->num = c4g_reply_num(rx->num, C4G_NUM_PLUS_ONE);
    for (i = 0U; mode4 && i < rx->n_axes; i++) {
        tx->ax[i].target_pos = (float)m[i].cmd;
        tx->ax[i].target_vel = (float)(m[i].cmd - m[i].cmd_prev);
    }
}

static void cyclic(gen_t *g, uint64_t ticks)
{
    axis_motion_t m[C4G_MAX_AXES];
    const uint64_t mode0 = MODE0_MS / (uint64_t)(g->period_ns / 1000000LL);
    uint64_t k;
    motion_init(m, g->n_axes, (double)g->period_ns * 1e-9);
    for (k = 0U; k < ticks; k++) {
        const int mode4 = (k >= mode0);
        c4g_ctrl_packet_t rx;
        c4g_pc_packet_t tx;
        uint8_t buf[C4G_MAX_CYCLIC_SIZE];
        size_t len = 0U;
        int64_t t;
        uint32_t i;
        ctrl_packet(g, m, mode4, &rx);
        if (c4g_ctrl_encode(&rx, buf, sizeof buf, &len) != C4G_OK) {
            g->bad++;
            return;
        }
        t = ctrl_time(g);
        write_at(g, t, 1, buf, len);
        for (i = 0U; mode4 && i < g->n_axes; i++) {
            motion_step(&m[i]);
            m[i].t += (double)g->period_ns * 1e-9;
        }
        pc_reply(&rx, m, mode4, &tx);
        if (c4g_pc_encode(&tx, buf, sizeof buf, &len) != C4G_OK) {
            g->bad++;
            return;
        }
        write_at(g, reply_time(g, t), 0, buf, len);
        g->num = num_after(g->num);
    }
}

static int usage(void)
{
    fprintf(stderr, "usage: gen_capture [--minutes M | --seconds S] [--axes N] [--period-ms P] [--dynamics] FILE\n"
                    "  a deterministic C4G Open session (default 10 minutes, 6 axes, 1 ms)\n");
    return 2;
}

int main(int argc, char **argv)
{
    double seconds = 600.0;
    long axes = 6, period_ms = 1;
    int dynamics = 0;
    const char *path = NULL;
    char err[256];
    gen_t g;
    uint64_t ticks;
    int i;
    for (i = 1; i < argc; i++) {
        const int more = i + 1 < argc;
        if (strcmp(argv[i], "--minutes") == 0 && more) {
            seconds = 60.0 * atof(argv[++i]);
        } else if (strcmp(argv[i], "--seconds") == 0 && more) {
            seconds = atof(argv[++i]);
        } else if (strcmp(argv[i], "--axes") == 0 && more) {
            axes = atol(argv[++i]);
        } else if (strcmp(argv[i], "--dynamics") == 0) {
            dynamics = 1;
        } else if (strcmp(argv[i], "--period-ms") == 0 && more) {
            period_ms = atol(argv[++i]);
        } else if (argv[i][0] != '-' && path == NULL) {
            path = argv[i];
        } else {
            return usage();
        }
    }
    if (path == NULL || !(seconds > 0.0) || axes < 1 || axes > (long)C4G_MAX_AXES || period_ms < 1 ||
        period_ms > 1000) {
        return usage();
    }
    memset(&g, 0, sizeof g);
    g.rng = 0xC46C0DE5EEDULL;
    g.period_ns = period_ms * 1000000L;
    g.n_axes = (uint32_t)axes;
    g.dynamics = dynamics;
    g.num = 1;
    if (make_init(&g.init, g.n_axes, (int32_t)period_ms) != 0) {
        fprintf(stderr, "gen_capture: the initialization packet does not validate\n");
        return 1;
    }
    g.w = c4gh_pcap_open(path, err, sizeof err);
    if (g.w == NULL) {
        fprintf(stderr, "gen_capture: %s\n", err);
        return 1;
    }
    ticks = (uint64_t)(seconds * 1000.0 / (double)period_ms + 0.5);
    for (i = 0; i < 9; i++) {
        sync_pair(&g);
    }
    init_pair(&g);
    for (i = 0; i < 2; i++) {
        sync_pair(&g);
    }
    cyclic(&g, ticks);
    if (c4gh_pcap_close(g.w) != 0 || g.bad != 0U) {
        fprintf(stderr, "gen_capture: %s: %lu packets not written\n", path, g.bad);
        return 1;
    }
    return 0;
}
