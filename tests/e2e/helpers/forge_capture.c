/* SPDX-License-Identifier: MIT */
/* forge_capture: writes one complete, realistic C4G Open session into a pcap file, with
 * one defect injected that the real tools refuse to produce (c4g-server's safety filter
 * and the library's encoders never send it), so that a capture checker can be tested on it.
 *
 * The session (controller 127.0.0.1:CTRL_PORT, PC 127.0.0.1:PC_PORT, plus-one NUM policy):
 * 9 synchronization packets (NUM 1..9, zero data) each answered with the PC's 732-byte reply,
 * the manual's figure 10.1 initialization packet (NUM 10, cut to --axes open axes of arm 1)
 * and its echo (NUM 11), 2 synchronization packets (NUM 11, 12), then --ticks cyclic packets
 * from NUM 13 (cyclic tick k carries NUM 12 + k). Controller packets sit exactly on the
 * period grid from --start; every reply follows its packet by 150..300 us (a fixed
 * pseudo-random sequence from --seed). The same options give the same file, byte for byte.
 *
 * Cyclic timeline, N = --ticks:
 *   ticks 1..20      every axis 501 (driving on), INFPAR 0
 *   ticks 21..N-10   drives on (INFPAR byte 5 on arm 1), mode 0 outside the mode window
 *   ticks 31..N-20   the mode window (--mode): the reference moves one raised-cosine cycle
 *                    per axis and comes back; in mode 0, 2 and 9 the SMP+ moves it, in mode 4
 *                    the PC does (absolute targets in D1, steps in D2). The PC ends mode 4 and
 *                    9 with EXIT_FROM_OPEN at tick N-20 (mode 4 goes through 14 for one tick);
 *                    PDL2 ends mode 2 with 12 for 10 ticks
 *   ticks N-9..N-1   drives off, mode 0
 *   tick N           504 on every axis (end of communication), echoed by the PC
 * Controller data: D1 the reference, D2 its step, D3 the actual position (the reference of
 * the tick before plus 1e-5 turns of noise), D4 its step, D5 the current, EXT1 the gravity
 * current, EXT2 the inertia.
 *
 * Options:
 *   --out FILE         capture to write (required)
 *   --inject KIND      the defect (default none):
 *     none             a clean session
 *     follow-error     axis 2 (axis 1 with one axis): |D1 - D3| grows as 8 (j/20)^2 turns
 *                      over ticks AT-19..AT (j = 1..20): 7.22 at AT-1, 8.0 at AT, over
 *                      FollowError 7.5 at AT only (the current saturates at AzLim); the
 *                      controller drives the arm off from AT+1 (INFPAR 0, mode 0, D1 = D3).
 *                      With 6 axes, axis 6 (FollowError 0 = no threshold) deviates 1.25
 *                      times as much: never a finding
 *     current          mode 2: the PC's D5 on axis 1 is 30 A at AT (AzLim 24.5 A). Mode 9: the
 *                      PC's D5 on axis 1 is 30 A at AT, and (4 axes or more) on axis 4 it is
 *                      8.5 A at AT+10 while the SMP+ current D5 is 1.5 A: 10 A > AzLim 9.5 A
 *                      together, the PC's part alone within it
 *     nan-d3           the controller's D3 on axis 2 (axis 1 with one axis) is NaN at AT; that
 *                      packet is not answered (c4g-server refuses it)
 *     inf-d1           the PC's D1 on axis 1 is +infinity in its reply to AT
 *     step             mode 4: the PC's D1 on axis 1 jumps 8 turns in its reply to AT (past
 *                      FollowError 7.5 from the actual position); the controller drives the
 *                      arm off from AT+1
 *     truncate         the PC's reply to AT is cut to 20 bytes
 *     unknown-mode     the controller's packet AT carries mode 77 on axis 3 (the last axis
 *                      with fewer); not answered (c4g-server refuses it)
 *     unknown-mode-pc  the PC's reply to AT carries mode 77 on axis 3 (the last with fewer)
 *   --at TICK          cyclic tick of the defect (default 100)
 *   --ticks N          cyclic packets, the final 504 included (60..30000, default 200)
 *   --axes N           open axes, logical axes 1..N of arm 1 (1..6, default 6)
 *   --mode M           mode of the window: 0, 2, 4 or 9 (default: 9 for current, 4 for step,
 *                      else 0)
 *   --period MS        1 or 2 (default 2)
 *   --link TYPE        eth (default; the tools' own writer, lib/host/c4gh_pcap), vlan
 *                      (Ethernet with an 802.1Q tag, VLAN 100), raw (DLT_RAW, bare IPv4),
 *                      null (DLT_NULL, 4-byte host-order AF_INET), sll (Linux cooked, 16
 *                      bytes), sll2 (Linux cooked v2, 20 bytes); cooked headers as tcpdump
 *                      writes them for the loopback device
 *   --fragment-init    the controller's initialization packet as two IPv4 fragments
 *   --start SECONDS    time of the first packet (default 1700000000)
 *   --ctrl-port N, --pc-port N   UDP ports (default 45001, 45000)
 *   --seed N           reply latency sequence (default 1)
 *   --first-num N      the capture starts in the middle of a session, as a capture started
 *                      late does: no start-up, cyclic tick k carries NUM (N + k - 1) mod
 *                      0x8000, so the counter wraps from 0x7FFF to 0 within the file when N
 *                      is close to it (the reply to 0x7FFF carries 1, as does the reply to 0)
 * Exit status: 0 written, 1 write error, 2 usage. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include "c4gh_pcap.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

enum inj { INJ_NONE, INJ_FOLLOW, INJ_CURRENT, INJ_NAN_D3, INJ_INF_D1, INJ_STEP, INJ_TRUNCATE,
           INJ_MODE_CTRL, INJ_MODE_PC };
static const char *const inj_names[] = {"none", "follow-error", "current", "nan-d3", "inf-d1",
                                        "step", "truncate", "unknown-mode", "unknown-mode-pc"};
enum link { LINK_ETH, LINK_VLAN, LINK_RAW, LINK_NULL, LINK_SLL, LINK_SLL2 };
static const char *const link_names[] = {"eth", "vlan", "raw", "null", "sll", "sll2"};

#define DRIVE_TICKS 20L  /* 501 while driving on */
#define W0 31L           /* first tick of the mode window */
#define M2_STANDBY 10L   /* ticks of 12 at the end of mode 2 */
#define FE_TICKS 20L     /* ticks over which the following error grows */
#define IP_LEN 20U
#define UDP_LEN 8U
#define LINK_MAX 20U
#define LOCALHOST 0x7F000001U
#define VLAN_ID 100U

static struct {
    const char *out;
    enum inj inj;
    long at, ticks, start, first_num;
    int axes, mode, period_ms, frag_init;
    enum link link;
    unsigned ctrl_port, pc_port;
    unsigned long seed;
} o;

/* ---------------------------------------------------------------- capture file */

static c4gh_pcap_t *c4g_w;   /* plain Ethernet: the tools' writer */
static pcap_t *dead;        /* every other link type, and fragments */
static pcap_dumper_t *dump;
static uint16_t ip_id = 1U;
static unsigned long frames;
static uint8_t frame[LINK_MAX + IP_LEN + UDP_LEN + C4G_INIT_SIZE];

static void put16(uint8_t *b, uint32_t v) { b[0] = (uint8_t)(v >> 8); b[1] = (uint8_t)v; }
static void put32(uint8_t *b, uint32_t v) { put16(b, v >> 16); put16(&b[2], v & 0xFFFFU); }

static uint32_t csum_add(uint32_t sum, const uint8_t *b, size_t len)
{
    size_t i;
    for (i = 0; i + 1U < len; i += 2U) {
        sum += ((uint32_t)b[i] << 8) | b[i + 1U];
    }
    if ((len & 1U) != 0U) {
        sum += (uint32_t)b[len - 1U] << 8;
    }
    return sum;
}

static uint16_t csum_fold(uint32_t sum)
{
    while ((sum >> 16) != 0U) {
        sum = (sum & 0xFFFFU) + (sum >> 16);
    }
    return (uint16_t)(~sum & 0xFFFFU);
}

static int open_capture(void)
{
    static const int dlt[] = {DLT_EN10MB, DLT_EN10MB, DLT_RAW, DLT_NULL, DLT_LINUX_SLL,
                              DLT_LINUX_SLL2};
    char err[256];
    if (o.link == LINK_ETH && !o.frag_init) {
        c4g_w = c4gh_pcap_open(o.out, err, sizeof err);
        if (c4g_w == NULL) {
            fprintf(stderr, "forge_capture: %s: %s\n", o.out, err);
        }
        return c4g_w != NULL ? 0 : -1;
    }
    dead = pcap_open_dead(dlt[o.link], 65535);
    dump = (dead != NULL) ? pcap_dump_open(dead, o.out) : NULL;
    if (dump == NULL) {
        fprintf(stderr, "forge_capture: %s: %s\n", o.out, dead != NULL ? pcap_geterr(dead) : "pcap_open_dead");
        return -1;
    }
    return 0;
}

static int close_capture(void)
{
    int rc = 0;
    if (c4g_w != NULL) {
        frames = c4gh_pcap_frames(c4g_w);
        rc = c4gh_pcap_close(c4g_w);
    }
    if (dump != NULL) {
        rc = pcap_dump_flush(dump);
        pcap_dump_close(dump);
        pcap_close(dead);
    }
    return rc;
}

/* The link-layer header of o.link before an IPv4 packet; its length. */
static size_t link_header(uint8_t *f)
{
    static const uint8_t mac_dst[6] = {0x02, 0x00, 0x00, 0x00, 0x00, 0x02};
    static const uint8_t mac_src[6] = {0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
    const uint32_t af_inet = AF_INET;
    switch (o.link) {
    case LINK_ETH:
    case LINK_VLAN:
        /* same addresses as lib/host/c4gh_pcap.c, so the variants differ by the link only */
        memcpy(f, mac_dst, 6);
        memcpy(&f[6], mac_src, 6);
        if (o.link == LINK_ETH) {
            put16(&f[12], 0x0800U);
            return 14U;
        }
        put16(&f[12], 0x8100U);
        put16(&f[14], VLAN_ID); /* priority 0, DEI 0 */
        put16(&f[16], 0x0800U);
        return 18U;
    case LINK_NULL:
        memcpy(f, &af_inet, 4); /* host byte order, as BSD loopback captures are written */
        return 4U;
    case LINK_SLL:
        memset(f, 0, 16);
        put16(&f[0], 0U);        /* packet type: to us */
        put16(&f[2], 772U);      /* ARPHRD_LOOPBACK */
        put16(&f[4], 6U);        /* address length; the loopback address is zero */
        put16(&f[14], 0x0800U);
        return 16U;
    case LINK_SLL2:
        memset(f, 0, 20);
        put16(&f[0], 0x0800U);
        put32(&f[4], 1U);        /* interface index of lo */
        put16(&f[8], 772U);
        f[10] = 0U;              /* packet type: to us */
        f[11] = 6U;
        return 20U;
    case LINK_RAW:
    default:
        return 0U;
    }
}

static void ip_header(uint8_t *ip, uint32_t src, uint32_t dst, size_t payload, uint16_t id,
                      uint32_t flags_off)
{
    ip[0] = 0x45U;
    ip[1] = 0U;
    put16(&ip[2], (uint32_t)(IP_LEN + payload));
    put16(&ip[4], id);
    put16(&ip[6], flags_off);
    ip[8] = 64U;
    ip[9] = 17U;
    put16(&ip[10], 0U);
    put32(&ip[12], src);
    put32(&ip[16], dst);
    put16(&ip[10], csum_fold(csum_add(0U, ip, IP_LEN)));
}

static void dump_frame(uint64_t t_us, size_t len)
{
    struct pcap_pkthdr h;
    memset(&h, 0, sizeof h);
    h.ts.tv_sec = (time_t)(t_us / 1000000U);
    h.ts.tv_usec = (suseconds_t)(t_us % 1000000U);
    h.caplen = (bpf_u_int32)len;
    h.len = (bpf_u_int32)len;
    pcap_dump((u_char *)dump, &h, frame);
    frames++;
}

/* One UDP datagram at t_us; from_ctrl: controller -> PC. With frag, as two IPv4 fragments
 * (the first 8-byte aligned half of the UDP datagram, then the rest) at the same time. */
static int emit(uint64_t t_us, int from_ctrl, const uint8_t *p, size_t len, int frag)
{
    static uint8_t udp[UDP_LEN + C4G_INIT_SIZE];
    const uint32_t src = LOCALHOST, dst = LOCALHOST;
    const uint16_t sport = (uint16_t)(from_ctrl ? o.ctrl_port : o.pc_port);
    const uint16_t dport = (uint16_t)(from_ctrl ? o.pc_port : o.ctrl_port);
    const size_t ulen = UDP_LEN + len;
    uint8_t pseudo[12];
    uint16_t uc;
    size_t lh;
    if (c4g_w != NULL) {
        struct timespec ts;
        ts.tv_sec = (time_t)(t_us / 1000000U);
        ts.tv_nsec = (long)(t_us % 1000000U) * 1000L;
        return c4gh_pcap_write_udp(c4g_w, &ts, src, sport, dst, dport, p, len);
    }
    put16(&udp[0], sport);
    put16(&udp[2], dport);
    put16(&udp[4], (uint32_t)ulen);
    put16(&udp[6], 0U);
    memcpy(&udp[UDP_LEN], p, len);
    put32(pseudo, src);
    put32(&pseudo[4], dst);
    pseudo[8] = 0U;
    pseudo[9] = 17U;
    put16(&pseudo[10], (uint32_t)ulen);
    uc = csum_fold(csum_add(csum_add(0U, pseudo, sizeof pseudo), udp, ulen));
    put16(&udp[6], (uc == 0U) ? 0xFFFFU : uc);
    lh = link_header(frame);
    if (!frag) {
        ip_header(&frame[lh], src, dst, ulen, ip_id, 0x4000U); /* don't fragment */
        memcpy(&frame[lh + IP_LEN], udp, ulen);
        dump_frame(t_us, lh + IP_LEN + ulen);
    } else {
        const size_t first = ((ulen / 2U) + 7U) & ~(size_t)7U;
        ip_header(&frame[lh], src, dst, first, ip_id, 0x2000U); /* more fragments */
        memcpy(&frame[lh + IP_LEN], udp, first);
        dump_frame(t_us, lh + IP_LEN + first);
        lh = link_header(frame);
        ip_header(&frame[lh], src, dst, ulen - first, ip_id, (uint32_t)(first / 8U));
        memcpy(&frame[lh + IP_LEN], &udp[first], ulen - first);
        dump_frame(t_us, lh + IP_LEN + ulen - first);
    }
    ip_id = (uint16_t)(ip_id + 1U);
    return 0;
}

/* ---------------------------------------------------------------- session */

static const double pos0[6] = {0.15, -0.32, 0.48, 0.05, -0.12, 0.27};
static const double amp[6] = {0.40, -0.30, 0.25, 0.60, 0.50, -0.45};
static const double grav[6] = {0.0, 2.1, 1.3, 0.0, 0.0, 0.0};
static const double inertia[6] = {0.0012, 0.0015, 0.0009, 0.0004, 0.0003, 0.0002};

static unsigned long rng;
static unsigned long next_rand(void)
{
    rng = (rng * 1103515245UL + 12345UL) & 0x7FFFFFFFUL;
    return rng >> 8;
}
static uint64_t latency_us(void) { return 150U + (uint64_t)(next_rand() % 151U); }
static double noise(void) { return ((double)(next_rand() % 2001U) - 1000.0) * 1e-8; }

static void put_le32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    b[2] = (uint8_t)(v >> 16);
    b[3] = (uint8_t)(v >> 24);
}
/* byte offset of axis i's field f (0 = SM, 1..5 = D1..D5) in a cyclic packet */
static size_t field_at(int i, int f) { return C4G_HEADER_SIZE + C4G_AXIS_SIZE * (size_t)i + 4U * (size_t)f; }

/* one raised-cosine cycle over the mode window, 0 outside it */
static double profile(long k, long w1)
{
    if (k < W0 || k > w1) {
        return 0.0;
    }
    return 0.5 * (1.0 - cos(2.0 * 3.14159265358979323846 * (double)(k - W0) / (double)(w1 - W0)));
}

/* the DSA never commands more than AzLim */
static double saturate(double v, double lim) { return v > lim ? lim : (v < -lim ? -lim : v); }

static int in_mode_window(long k, long w1) { return k >= W0 && k <= w1; }

/* the controller's mode at tick k (before a drive-off) */
static int32_t ctrl_mode(long k, long w1, long off)
{
    if (k == o.ticks) return C4G_MODE_EXIT_OPEN;
    if (k <= DRIVE_TICKS) return C4G_MODE_DRIVING_ON;
    if (k >= off) return C4G_MODE_0;
    switch (o.mode) {
    case 4:
        if (in_mode_window(k, w1)) return C4G_MODE_4;
        return (k == w1 + 1) ? C4G_MODE_4_STANDBY : C4G_MODE_0;
    case 9:
        return in_mode_window(k, w1) ? C4G_MODE_9 : C4G_MODE_0;
    case 2:
        if (in_mode_window(k, w1 - 1)) return C4G_MODE_2;
        return (k >= w1 && k < w1 + M2_STANDBY) ? C4G_MODE_2_STANDBY : C4G_MODE_0;
    default:
        return C4G_MODE_0;
    }
}

static int run(void)
{
    const uint64_t P = (uint64_t)o.period_ms * 1000U;
    const uint64_t t0 = (uint64_t)o.start * 1000000U;
    const long w1 = o.ticks - 20L;
    const long off = o.ticks - 9L;
    const int n = o.axes;
    const int fe_ax = (n >= 2) ? 1 : 0;
    const int mode_ax = (n >= 3) ? 2 : n - 1;
    uint8_t buf[C4G_INIT_SIZE];
    uint8_t rep[C4G_INIT_SIZE];
    size_t len = 0;
    c4g_init_t init;
    double ref[6], ref_prev[6], act[6], act_prev[6], pc_target[6], pc_cur[6];
    long dropped_at = -1;  /* the arm went off at this tick (following error) */
    int exit_req = 0;
    long k;
    int i;
    uint64_t t;

    rng = o.seed;
    if (c4gsim_fig10_1(&init) != C4G_OK) return -1;
    init.n_ax_open = n;
    init.period_ms = o.period_ms;
    for (i = n; i < 6; i++) init.open_ax[0][i] = C4G_OPEN_AX_NONE;
    /* start-up: 9 sync, init, 2 sync; the PC answers each one */
    for (k = 1; k <= 12 && o.first_num < 0; k++) {
        t = t0 + (uint64_t)(k - 1) * P;
        if (k == C4G_INIT_NUM) {
            if (c4g_init_encode(&init, buf, sizeof buf, &len) != C4G_OK) return -1;
            if (emit(t, 1, buf, len, o.frag_init) != 0) return -1;
            put_le32(buf, (uint32_t)C4G_INIT_NUM + 1U);
            if (emit(t + latency_us(), 0, buf, len, 0) != 0) return -1;
            continue;
        }
        memset(buf, 0, sizeof buf);
        put_le32(buf, (uint32_t)k);
        if (emit(t, 1, buf, C4G_CYCLIC_SIZE((size_t)n), 0) != 0) return -1;
        memset(rep, 0, sizeof rep);
        put_le32(rep, (uint32_t)k + 1U);
        if (emit(t + latency_us(), 0, rep, C4G_SYNC_REPLY_SIZE, 0) != 0) return -1;
    }
    for (i = 0; i < n; i++) {
        ref[i] = ref_prev[i] = act[i] = act_prev[i] = pc_target[i] = pos0[i];
        pc_cur[i] = grav[i];
    }
    for (k = 1; k <= o.ticks; k++) {
        c4g_ctrl_packet_t c;
        c4g_pc_packet_t r;
        const int drives = k > DRIVE_TICKS && k < off && dropped_at < 0;
        int32_t m = ctrl_mode(k, w1, off);
        int answer = 1;
        size_t rlen = 0;
        if (dropped_at >= 0 && m != C4G_MODE_EXIT_OPEN) m = C4G_MODE_0;
        t = t0 + (uint64_t)(o.first_num < 0 ? 11 + k : k - 1) * P;
        memset(&c, 0, sizeof c);
        c.num = (o.first_num < 0) ? (int32_t)(12 + k) : (int32_t)((o.first_num + k - 1) % 0x8000);
        c.infpar = drives ? C4G_STS_MOVING : 0U;
        c.n_axes = (uint32_t)n;
        for (i = 0; i < n; i++) {
            ref_prev[i] = ref[i];
            act_prev[i] = act[i];
            if (!drives) {
                ref[i] = act[i]; /* brakes: the reference takes the measured position */
            } else if (m == C4G_MODE_4) {
                ref[i] = pc_target[i]; /* the PC's last target */
            } else if (o.mode != 4) {
                ref[i] = pos0[i] + amp[i] * profile(k, w1);
            }
            act[i] = drives ? ref_prev[i] + noise() : act[i];
        }
        if (o.inj == INJ_FOLLOW && k > o.at - FE_TICKS && k <= o.at) {
            /* the axis falls behind faster and faster: 7.22 turns at AT-1, 8.0 at AT */
            const double u = (double)(k - (o.at - FE_TICKS)) / (double)FE_TICKS;
            const double dev = 8.0 * u * u;
            act[fe_ax] = ref[fe_ax] - dev;
            if (n >= 6) {
                act[5] = ref[5] - 1.25 * dev;
            }
        }
        for (i = 0; i < n; i++) {
            c4g_ctrl_axis_t *x = &c.ax[i];
            x->mode = m;
            x->target_pos = (float)ref[i];
            x->target_vel = drives ? (float)(ref[i] - ref_prev[i]) : 0.0F;
            x->actual_pos = (float)act[i];
            x->actual_vel = (float)(act[i] - act_prev[i]);
            x->current_ref = drives ? (float)saturate((m == C4G_MODE_2 || m == C4G_MODE_2_STANDBY)
                                                           ? pc_cur[i] : grav[i] + 30.0 * (ref[i] - act[i]),
                                                       (double)init.az_lim[0][i])
                                    : 0.0F;
            x->ext[0] = (float)grav[i];
            x->ext[1] = (float)inertia[i];
        }
        if (o.inj == INJ_CURRENT && o.mode == 9 && n >= 4 && k == o.at + 10) {
            c.ax[3].current_ref = 1.5F;
        }
        if (c4g_ctrl_encode(&c, buf, sizeof buf, &len) != C4G_OK) {
            fprintf(stderr, "forge_capture: cannot encode the controller's tick %ld\n", k);
            return -1;
        }
        if (o.inj == INJ_NAN_D3 && k == o.at) {
            put_le32(&buf[field_at(fe_ax, 3)], 0x7FC00000U); /* quiet NaN */
            answer = 0;
        }
        if (o.inj == INJ_MODE_CTRL && k == o.at) {
            put_le32(&buf[field_at(mode_ax, 0)], 77U);
            answer = 0;
        }
        if (emit(t, 1, buf, len, 0) != 0) return -1;

        /* the PC's reply: mode echo, the data of the mode */
        memset(&r, 0, sizeof r);
        r.num = c4g_reply_num(c.num, C4G_NUM_PLUS_ONE);
        r.n_axes = c.n_axes;
        if ((m == C4G_MODE_4 || m == C4G_MODE_9) && k >= w1) exit_req = 1;
        if (m != C4G_MODE_4 && m != C4G_MODE_9) exit_req = 0;
        r.infpar = exit_req ? C4G_EXIT_FROM_OPEN : 0U;
        for (i = 0; i < n; i++) {
            c4g_pc_axis_t *y = &r.ax[i];
            y->mode = m;
            if (m == C4G_MODE_4) {
                const double prev = pc_target[i];
                pc_target[i] = pos0[i] + amp[i] * profile(k + 1, w1);
                y->target_pos = (float)pc_target[i];
                y->target_vel = (float)(pc_target[i] - prev);
            } else if (m == C4G_MODE_9) {
                y->current_add = (float)(0.2 * profile(k, w1));
            } else if (m == C4G_MODE_2 || m == C4G_MODE_2_STANDBY) {
                pc_cur[i] = grav[i] + 30.0 * (c.ax[i].target_pos - c.ax[i].actual_pos) +
                            0.35 * (c.ax[i].target_vel - c.ax[i].actual_vel);
                y->current_add = (float)pc_cur[i];
            }
        }
        if (o.inj == INJ_CURRENT && k == o.at) {
            r.ax[0].current_add = 30.0F;
            pc_cur[0] = (double)init.az_lim[0][0]; /* what the controller applies: saturated */
        }
        if (o.inj == INJ_CURRENT && o.mode == 9 && n >= 4 && k == o.at + 10) {
            r.ax[3].current_add = 8.5F;
        }
        if (o.inj == INJ_STEP && k == o.at) {
            pc_target[0] += 8.0;
            r.ax[0].target_pos = (float)pc_target[0];
            r.ax[0].target_vel = 8.0F;
        }
        if (c4g_pc_encode(&r, rep, sizeof rep, &rlen) != C4G_OK) {
            fprintf(stderr, "forge_capture: cannot encode the PC's reply to tick %ld\n", k);
            return -1;
        }
        if (o.inj == INJ_INF_D1 && k == o.at) {
            put_le32(&rep[field_at(0, 1)], 0x7F800000U); /* +infinity */
        }
        if (o.inj == INJ_MODE_PC && k == o.at) {
            put_le32(&rep[field_at(mode_ax, 0)], 77U);
        }
        if (o.inj == INJ_TRUNCATE && k == o.at) {
            rlen = 20U;
        }
        if (answer && emit(t + latency_us(), 0, rep, rlen, 0) != 0) return -1;
        /* a following error: the controller drives the arm off at the next tick */
        if ((o.inj == INJ_FOLLOW || o.inj == INJ_STEP) && k == o.at) {
            dropped_at = k;
        }
    }
    return 0;
}

/* ---------------------------------------------------------------- options */

static void usage(void)
{
    fprintf(stderr,
            "usage: forge_capture --out FILE [--inject none|follow-error|current|nan-d3|inf-d1|step|\n"
            "                     truncate|unknown-mode|unknown-mode-pc] [--at TICK] [--ticks N]\n"
            "                     [--axes N] [--mode 0|2|4|9] [--period 1|2]\n"
            "                     [--link eth|vlan|raw|null|sll|sll2] [--fragment-init]\n"
            "                     [--start SECONDS] [--ctrl-port N] [--pc-port N] [--seed N]\n"
            "                     [--first-num N]\n");
}

static int pick(const char *v, const char *const *names, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        if (strcmp(v, names[i]) == 0) return i;
    }
    return -1;
}

static int num_arg(const char *v, long lo, long hi, long *out)
{
    char *end = NULL;
    const long x = strtol(v, &end, 10);
    if (end == v || *end != '\0' || x < lo || x > hi) return 0;
    *out = x;
    return 1;
}

static int parse(int argc, char **argv)
{
    int i;
    long v;
    o.inj = INJ_NONE;
    o.at = 100;
    o.ticks = 200;
    o.axes = 6;
    o.mode = -1;
    o.period_ms = 2;
    o.link = LINK_ETH;
    o.start = 1700000000L;
    o.ctrl_port = 45001U;
    o.pc_port = 45000U;
    o.seed = 1UL;
    o.first_num = -1;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = (i + 1 < argc) ? argv[i + 1] : NULL;
        int k;
        if (strcmp(a, "--fragment-init") == 0) { o.frag_init = 1; continue; }
        if (val == NULL) { fprintf(stderr, "forge_capture: %s needs a value\n", a); return 0; }
        i++;
        if (strcmp(a, "--out") == 0) { o.out = val; }
        else if (strcmp(a, "--inject") == 0 && (k = pick(val, inj_names, 9)) >= 0) { o.inj = (enum inj)k; }
        else if (strcmp(a, "--link") == 0 && (k = pick(val, link_names, 6)) >= 0) { o.link = (enum link)k; }
        else if (strcmp(a, "--at") == 0 && num_arg(val, 1, 30000, &v)) { o.at = v; }
        else if (strcmp(a, "--ticks") == 0 && num_arg(val, 60, 30000, &v)) { o.ticks = v; }
        else if (strcmp(a, "--axes") == 0 && num_arg(val, 1, 6, &v)) { o.axes = (int)v; }
        else if (strcmp(a, "--mode") == 0 && num_arg(val, 0, 9, &v) && (v == 0 || v == 2 || v == 4 || v == 9)) { o.mode = (int)v; }
        else if (strcmp(a, "--period") == 0 && num_arg(val, 1, 2, &v)) { o.period_ms = (int)v; }
        else if (strcmp(a, "--start") == 0 && num_arg(val, 0, 2000000000L, &v)) { o.start = v; }
        else if (strcmp(a, "--ctrl-port") == 0 && num_arg(val, 1, 65535, &v)) { o.ctrl_port = (unsigned)v; }
        else if (strcmp(a, "--pc-port") == 0 && num_arg(val, 1, 65535, &v)) { o.pc_port = (unsigned)v; }
        else if (strcmp(a, "--seed") == 0 && num_arg(val, 0, 2147483647L, &v)) { o.seed = (unsigned long)v; }
        else if (strcmp(a, "--first-num") == 0 && num_arg(val, 0, C4G_NUM_MAX, &v)) { o.first_num = v; }
        else { fprintf(stderr, "forge_capture: bad option or value: %s %s\n", a, val); return 0; }
    }
    if (o.out == NULL) { fprintf(stderr, "forge_capture: --out is required\n"); return 0; }
    if (o.mode < 0) {
        o.mode = (o.inj == INJ_CURRENT) ? 9 : (o.inj == INJ_STEP) ? 4 : 0;
    }
    if ((o.inj == INJ_CURRENT && o.mode != 2 && o.mode != 9) || (o.inj == INJ_STEP && o.mode != 4)) {
        fprintf(stderr, "forge_capture: %s needs --mode %s\n", inj_names[o.inj],
                o.inj == INJ_STEP ? "4" : "2 or 9");
        return 0;
    }
    if (o.inj != INJ_NONE) {
        /* inside the mode window for the mode's defects, with drives on for the others */
        const long lo = (o.inj == INJ_CURRENT || o.inj == INJ_STEP) ? W0 + 2
                        : DRIVE_TICKS + 1 + (o.inj == INJ_FOLLOW ? FE_TICKS : 0L);
        const long hi = (o.inj == INJ_CURRENT || o.inj == INJ_STEP) ? o.ticks - 22 - (o.mode == 9 ? 10 : 0)
                                                                    : o.ticks - 10;
        if (o.at < lo || o.at > hi) {
            fprintf(stderr, "forge_capture: --at %ld: %s needs a tick in %ld..%ld with --ticks %ld\n",
                    o.at, inj_names[o.inj], lo, hi, o.ticks);
            return 0;
        }
    }
    if (o.ctrl_port == o.pc_port) { fprintf(stderr, "forge_capture: the two ports must differ\n"); return 0; }
    return 1;
}

int main(int argc, char **argv)
{
    int rc;
    if (!parse(argc, argv)) {
        usage();
        return 2;
    }
    if (open_capture() != 0) {
        return 1;
    }
    rc = run();
    if (close_capture() != 0 || rc != 0) {
        fprintf(stderr, "forge_capture: %s: not written completely\n", o.out);
        return 1;
    }
    printf("forge_capture: %s: %lu frames, %ld cyclic ticks, %d axes, mode %d, link %s%s, inject %s",
           o.out, frames, o.ticks, o.axes, o.mode, link_names[o.link],
           o.frag_init ? " (init fragmented)" : "", inj_names[o.inj]);
    if (o.inj != INJ_NONE) {
        printf(" at tick %ld (NUM %ld)", o.at, o.first_num < 0 ? 12 + o.at : (o.first_num + o.at - 1) % 0x8000);
    }
    printf("\n");
    return 0;
}
