/* SPDX-License-Identifier: MIT */
/* Unit tests of c4g-replay's capture reader and session analysis (the tool sources are
 * included: tools are not in the library). Captures are written with libpcap itself
 * (pcap_open_dead + pcap_dump) for every link type, and sessions are built with the
 * library's encoders. */
#define _GNU_SOURCE /* capture.c, included below, reads pipes through fopencookie */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#define TH_FIG10_1
#include "test_helpers.h"

#include "c4gh_hist.h"
#include "c4gh_hist.h"
#include "c4gh_analyze.h"
/* intrusive: the link-type table (LT_*) is private to the capture reader */
#include "../../lib/host/c4gh_capture.c"

#define IP_CTRL 0x0A020C96U /* 10.2.12.150 */
#define IP_PC 0x0A020C01U

/* ---- writing captures ------------------------------------------------------ */

typedef struct frame_opt {
    int link;            /* LT_* */
    int vlan;            /* Ethernet: one 802.1Q tag */
    int null_be;         /* NULL: AF in big-endian order */
    uint16_t ethertype;  /* 0: IPv4 */
    uint8_t proto;       /* 0: UDP */
    uint16_t frag;       /* IPv4 flags/fragment offset field */
    int ip_len_extra;    /* added to the IPv4 total length */
    int udp_len_extra;   /* added to the UDP length */
} frame_opt_t;

static size_t put16(uint8_t *b, uint16_t v)
{
    b[0] = (uint8_t)(v >> 8);
    b[1] = (uint8_t)v;
    return 2U;
}

static size_t put32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)(v >> 24);
    b[1] = (uint8_t)(v >> 16);
    b[2] = (uint8_t)(v >> 8);
    b[3] = (uint8_t)v;
    return 4U;
}

/* One frame of link type o->link carrying a UDP datagram; returns its length. */
static size_t build(uint8_t *f, const frame_opt_t *o, uint32_t src, uint16_t sport, uint32_t dst,
                    uint16_t dport, const uint8_t *pl, size_t n)
{
    size_t k = 0U, ip;
    const uint16_t et = o->ethertype != 0U ? o->ethertype : 0x0800U;
    switch (o->link) {
    case LT_EN10MB:
        memset(f, 0x02, 12);
        k = 12U;
        if (o->vlan) {
            k += put16(f + k, 0x8100U);
            k += put16(f + k, 7U);
        }
        k += put16(f + k, et);
        break;
    case LT_SLL:
        memset(f, 0, 14);
        k = 14U;
        k += put16(f + k, et);
        break;
    case LT_SLL2:
        k += put16(f, et);
        memset(f + 2, 0, 18);
        k = 20U;
        break;
    case LT_NULL:
        if (o->null_be) {
            k += put32(f, 2U);
        } else {
            f[0] = 2U;
            f[1] = f[2] = f[3] = 0U;
            k = 4U;
        }
        break;
    default:
        break;
    }
    ip = k;
    memset(f + ip, 0, 20);
    f[ip] = 0x45U;
    (void)put16(f + ip + 2, (uint16_t)(28U + n + (size_t)o->ip_len_extra));
    (void)put16(f + ip + 6, o->frag);
    f[ip + 8] = 64U;
    f[ip + 9] = o->proto != 0U ? o->proto : 17U;
    (void)put32(f + ip + 12, src);
    (void)put32(f + ip + 16, dst);
    k = ip + 20U;
    k += put16(f + k, sport);
    k += put16(f + k, dport);
    k += put16(f + k, (uint16_t)(8U + n + (size_t)o->udp_len_extra));
    k += put16(f + k, 0U);
    memcpy(f + k, pl, n);
    return k + n;
}

typedef struct writer {
    pcap_t *dead;
    pcap_dumper_t *d;
    char path[64];
} writer_t;

static void w_open(writer_t *w, int link)
{
    int fd;
    strcpy(w->path, "/tmp/test_replay_XXXXXX");
    fd = mkstemp(w->path);
    assert_true(fd >= 0);
    close(fd);
    w->dead = pcap_open_dead(link, 65535);
    assert_non_null(w->dead);
    w->d = pcap_dump_open(w->dead, w->path);
    assert_non_null(w->d);
}

/* caplen < len: the snapshot length cut the frame */
static void w_frame(writer_t *w, int64_t t_ns, const uint8_t *f, size_t len, size_t caplen)
{
    struct pcap_pkthdr h;
    memset(&h, 0, sizeof h);
    h.ts.tv_sec = (time_t)(t_ns / 1000000000LL);
    h.ts.tv_usec = (suseconds_t)((t_ns % 1000000000LL) / 1000LL);
    h.len = (bpf_u_int32)len;
    h.caplen = (bpf_u_int32)caplen;
    pcap_dump((u_char *)w->d, &h, f);
}

static void w_close(writer_t *w)
{
    pcap_dump_close(w->d);
    pcap_close(w->dead);
}

static void w_udp(writer_t *w, const frame_opt_t *o, int64_t t, uint32_t src, uint16_t sp, uint32_t dst,
                  uint16_t dp, const uint8_t *pl, size_t n)
{
    uint8_t f[2000];
    const size_t len = build(f, o, src, sp, dst, dp, pl, n);
    w_frame(w, t, f, len, len);
}

/* ---- the reader -------------------------------------------------------------- */

static void one_link(int link, int vlan, int null_be)
{
    writer_t w;
    frame_opt_t o;
    const uint8_t pl[5] = {1, 2, 3, 4, 5};
    char err[400];
    c4gh_cap_pkt_t p;
    c4gh_cap_t *c;
    memset(&o, 0, sizeof o);
    o.link = link;
    o.vlan = vlan;
    o.null_be = null_be;
    w_open(&w, link);
    w_udp(&w, &o, 1500000000123456000LL, IP_CTRL, 3600, IP_PC, 1000, pl, sizeof pl);
    w_close(&w);
    c = c4gh_cap_open(w.path, err, sizeof err);
    assert_non_null(c);
    assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), C4GH_CAP_DATAGRAM);
    assert_int_equal(p.src_ip, IP_CTRL);
    assert_int_equal(p.dst_ip, IP_PC);
    assert_int_equal(p.src_port, 3600);
    assert_int_equal(p.dst_port, 1000);
    assert_int_equal(p.len, 5);
    assert_memory_equal(p.payload, pl, 5);
    assert_int_equal(p.frame, 1);
    assert_int_equal(p.offset, 24);
    assert_true(p.ts_ns == 1500000000123456000LL);
    assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), C4GH_CAP_END);
    assert_int_equal(c4gh_cap_counts(c)->udp, 1);
    c4gh_cap_close(c);
    unlink(w.path);
}

static void test_link_types(void **state)
{
    (void)state;
    one_link(LT_EN10MB, 0, 0);
    one_link(LT_EN10MB, 1, 0);
    one_link(LT_SLL, 0, 0);
    one_link(LT_SLL2, 0, 0);
    one_link(LT_NULL, 0, 0);
    one_link(LT_NULL, 0, 1);
    one_link(LT_RAW_OLD, 0, 0); /* DLT_RAW as libpcap reports LINKTYPE_RAW on Linux */
    one_link(LT_IPV4, 0, 0);
}

/* Each damaged or foreign frame, then one good one: the reader names the problem and goes on. */
static void test_damaged_frames(void **state)
{
    static const struct { frame_opt_t o; c4gh_cap_res_t want; const char *msg; } cases[] = {
        {{LT_EN10MB, 0, 0, 0x86DDU, 0, 0, 0, 0}, C4GH_CAP_IGNORED, NULL},
        {{LT_EN10MB, 0, 0, 0, 6U, 0, 0, 0}, C4GH_CAP_IGNORED, NULL},
        {{LT_EN10MB, 0, 0, 0, 0, 0x2000U, 0, 0}, C4GH_CAP_BAD, "fragment (id 0x0000, offset 0, more follow)"},
        {{LT_EN10MB, 0, 0, 0, 0, 0x0010U, 0, 0}, C4GH_CAP_BAD, "offset 128, last"},
        {{LT_EN10MB, 0, 0, 0, 0, 0, 40, 0}, C4GH_CAP_BAD, "IPv4 total length 73 exceeds the frame"},
        {{LT_EN10MB, 0, 0, 0, 0, 0, 0, 9}, C4GH_CAP_BAD, "UDP length 22 does not fit"},
        {{LT_EN10MB, 0, 0, 0, 0, 0, -30, 0}, C4GH_CAP_BAD, "below its header length"},
    };
    const uint8_t pl[5] = {1, 2, 3, 4, 5};
    char err[400];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        writer_t w;
        frame_opt_t good;
        c4gh_cap_pkt_t p;
        c4gh_cap_t *c;
        memset(&good, 0, sizeof good);
        good.link = LT_EN10MB;
        w_open(&w, LT_EN10MB);
        w_udp(&w, &cases[i].o, 1000, IP_CTRL, 3600, IP_PC, 1000, pl, sizeof pl);
        w_udp(&w, &good, 2000, IP_CTRL, 3600, IP_PC, 1000, pl, sizeof pl);
        w_close(&w);
        c = c4gh_cap_open(w.path, err, sizeof err);
        assert_non_null(c);
        err[0] = '\0';
        assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), cases[i].want);
        if (cases[i].msg != NULL) {
            assert_non_null(strstr(err, cases[i].msg));
            assert_non_null(strstr(err, "packet 1 (offset 24)"));
            assert_non_null(strstr(err, w.path));
        }
        assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), C4GH_CAP_DATAGRAM);
        assert_int_equal(p.frame, 2);
        c4gh_cap_close(c);
        unlink(w.path);
    }
}

static void test_snaplen_and_truncation(void **state)
{
    writer_t w;
    frame_opt_t o;
    uint8_t pl[300], f[400];
    char err[400];
    c4gh_cap_pkt_t p;
    c4gh_cap_t *c;
    size_t len;
    FILE *fp;
    long size;
    (void)state;
    memset(pl, 7, sizeof pl);
    memset(&o, 0, sizeof o);
    o.link = LT_EN10MB;
    w_open(&w, LT_EN10MB);
    len = build(f, &o, IP_CTRL, 3600, IP_PC, 1000, pl, sizeof pl);
    w_frame(&w, 1000, f, len, 64U);
    w_frame(&w, 2000, f, len, len);
    w_close(&w);
    c = c4gh_cap_open(w.path, err, sizeof err);
    assert_non_null(c);
    assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), C4GH_CAP_BAD);
    assert_non_null(strstr(err, "snapshot length cut the datagram: 50 of 328 IP bytes captured"));
    assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), C4GH_CAP_DATAGRAM);
    assert_int_equal(c4gh_cap_counts(c)->cut, 1);
    c4gh_cap_close(c);
    /* cut the file inside the second record */
    fp = fopen(w.path, "rb+");
    assert_non_null(fp);
    assert_int_equal(fseek(fp, 0, SEEK_END), 0);
    size = ftell(fp);
    fclose(fp);
    assert_int_equal(truncate(w.path, size - 100), 0);
    c = c4gh_cap_open(w.path, err, sizeof err);
    assert_non_null(c);
    assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), C4GH_CAP_BAD);
    assert_int_equal(c4gh_cap_next(c, &p, err, sizeof err), C4GH_CAP_FATAL);
    assert_non_null(strstr(err, "packet 2 (offset 104)"));
    c4gh_cap_close(c);
    unlink(w.path);
}

static void test_not_captures(void **state)
{
    char err[400], path[] = "/tmp/test_replay_XXXXXX";
    int fd;
    (void)state;
    assert_null(c4gh_cap_open("/tmp", err, sizeof err));
    assert_non_null(strstr(err, "is a directory"));
    assert_null(c4gh_cap_open("/nonexistent/x.pcap", err, sizeof err));
    assert_non_null(strstr(err, "No such file"));
    fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_null(c4gh_cap_open(path, err, sizeof err));
    assert_non_null(strstr(err, "empty file"));
    assert_int_equal(write(fd, "hello world\n", 12), 12);
    close(fd);
    assert_null(c4gh_cap_open(path, err, sizeof err));
    assert_non_null(strstr(err, "not a pcap or pcapng file (starts with 68 65 6c 6c)"));
    unlink(path);
}

/* ---- the analysis -------------------------------------------------------------- */

typedef struct sess_plan {
    int handshake;        /* 9 sync, init, 2 sync */
    unsigned ticks;
    unsigned skip_from, skip_n; /* replies not sent */
    unsigned wrong_num_at;
    unsigned late_at;     /* reply 600 us after */
    unsigned fe_at;       /* axis 2: D1 - D3 over FollowError */
    unsigned cur_at;      /* reply in mode 2 with D5 over AzLim */
    uint16_t pc_port;
    int64_t t0;
} sess_plan_t;

static size_t ctrl_packet(int32_t num, unsigned tick, const sess_plan_t *pl, uint8_t *buf, int32_t mode)
{
    c4g_ctrl_packet_t k;
    size_t len = 0U;
    uint32_t i;
    memset(&k, 0, sizeof k);
    k.num = num;
    k.n_axes = 6U;
    k.infpar = 5U;
    for (i = 0U; i < 6U; i++) {
        k.ax[i].mode = mode;
        k.ax[i].target_pos = 1.0f + 0.001f * (float)tick;
        k.ax[i].actual_pos = k.ax[i].target_pos - 0.0005f;
    }
    if (tick == pl->fe_at) {
        k.ax[1].actual_pos = k.ax[1].target_pos - 100.0f;
    }
    assert_int_equal(c4g_ctrl_encode(&k, buf, C4G_MAX_CYCLIC_SIZE, &len), C4G_OK);
    return len;
}

static size_t pc_packet(const uint8_t *ctrl, size_t n, int32_t num, unsigned tick, const sess_plan_t *pl,
                        uint8_t *buf)
{
    c4g_ctrl_packet_t k;
    c4g_pc_packet_t r;
    size_t len = 0U;
    assert_int_equal(c4g_ctrl_decode(ctrl, n, 6U, &k, NULL), C4G_OK);
    assert_int_equal(c4g_pc_reply_neutral(&k, &r), C4G_OK);
    r.num = num;
    if (tick == pl->cur_at) {
        r.ax[0].current_add = 99.0f; /* mode 2: the current itself, over AzLim */
    }
    assert_int_equal(c4g_pc_encode(&r, buf, C4G_MAX_CYCLIC_SIZE, &len), C4G_OK);
    return len;
}

static void write_session(writer_t *w, const sess_plan_t *pl, int32_t mode, int restart_at_end)
{
    frame_opt_t o;
    uint8_t b[C4G_INIT_SIZE], r[C4G_INIT_SIZE];
    int64_t t = pl->t0;
    int32_t num = 1;
    unsigned k;
    size_t n;
    memset(&o, 0, sizeof o);
    o.link = LT_EN10MB;
    if (pl->handshake) {
        for (k = 0U; k < 11U; k++) {
            if (k == 9U) {
                memcpy(b, th_fig, C4G_INIT_SIZE);
                w_udp(w, &o, t, IP_CTRL, 3600, IP_PC, pl->pc_port, b, C4G_INIT_SIZE);
                memcpy(r, b, C4G_INIT_SIZE);
                r[0] = 11U;
                w_udp(w, &o, t + 100000, IP_PC, pl->pc_port, IP_CTRL, 3600, r, C4G_INIT_SIZE);
                num = 11;
                t += 2000000;
            }
            memset(b, 0, sizeof b);
            b[0] = (uint8_t)num;
            w_udp(w, &o, t, IP_CTRL, 3600, IP_PC, pl->pc_port, b, C4G_CYCLIC_SIZE(6U));
            memset(r, 0, sizeof r);
            r[0] = (uint8_t)(num + 1);
            w_udp(w, &o, t + 100000, IP_PC, pl->pc_port, IP_CTRL, 3600, r, C4G_SYNC_REPLY_SIZE);
            num++;
            t += 2000000;
        }
    }
    for (k = 0U; k < pl->ticks; k++) {
        const int32_t m = (restart_at_end && k + 1U == pl->ticks) ? C4G_MODE_SVR_RESTART : mode;
        n = ctrl_packet(num, k, pl, b, m);
        w_udp(w, &o, t, IP_CTRL, 3600, IP_PC, pl->pc_port, b, n);
        if (!(k >= pl->skip_from && k < pl->skip_from + pl->skip_n)) {
            const int32_t rn = (k == pl->wrong_num_at) ? num + 5 : c4g_num_next(num);
            const size_t rl = pc_packet(b, n, rn, k, pl, r);
            w_udp(w, &o, t + (k == pl->late_at ? 600000 : 200000), IP_PC, pl->pc_port, IP_CTRL, 3600, r, rl);
        }
        num = c4g_num_next(num);
        t += 2000000;
    }
}

typedef struct collect {
    unsigned cyclic, with_reply;
} collect_t;

static void on_x(void *ctx, const c4gh_an_exchange_t *x)
{
    collect_t *c = ctx;
    if (x->kind == C4G_PKT_CYCLIC) {
        c->cyclic++;
        if (x->reply != NULL && x->tx != NULL) {
            c->with_reply++;
        }
    }
}

static void analyse(const char *path, c4gh_an_t *a, collect_t *col)
{
    c4gh_an_options_t o;
    char err[400];
    c4gh_cap_pkt_t p;
    c4gh_cap_t *c;
    c4gh_cap_res_t r;
    c4gh_an_options_default(&o);
    o.on_exchange = on_x;
    o.ctx = col;
    assert_int_equal(c4gh_an_init(a, &o), 0);
    c = c4gh_cap_open(path, err, sizeof err);
    assert_non_null(c);
    while ((r = c4gh_cap_next(c, &p, err, sizeof err)) != C4GH_CAP_END) {
        assert_int_equal(r, C4GH_CAP_DATAGRAM);
        c4gh_an_datagram(a, path, &p);
    }
    c4gh_an_file_end(a, path);
    c4gh_cap_close(c);
}

static void test_session_findings(void **state)
{
    sess_plan_t pl;
    writer_t w;
    c4gh_an_t a;
    collect_t col = {0U, 0U};
    const c4gh_an_session_t *s;
    (void)state;
    memset(&pl, 0, sizeof pl);
    pl.handshake = 1;
    pl.ticks = 100U;
    pl.skip_from = 20U;
    pl.skip_n = 12U;
    pl.wrong_num_at = 40U;
    pl.late_at = 45U;
    pl.fe_at = 10U;
    pl.cur_at = 60U;
    pl.pc_port = 31000U; /* not a default port: found by its init packet */
    pl.t0 = 1000000000000LL;
    w_open(&w, LT_EN10MB);
    write_session(&w, &pl, 2, 0);
    w_close(&w);
    analyse(w.path, &a, &col);
    assert_int_equal(a.n_sess, 1);
    s = &a.sess[0];
    assert_int_equal(s->ctrl.ip, IP_CTRL);
    assert_int_equal(s->pc.port, 31000);
    assert_int_equal(s->ctrl_sync, 11);
    assert_int_equal(s->pc_sync, 11);
    assert_int_equal(s->ctrl_init, 1);
    assert_int_equal(s->pc_init, 1);
    assert_int_equal(s->ctrl_cyclic, 100);
    assert_int_equal(s->policy, C4G_NUM_PLUS_ONE);
    assert_true(s->have_init);
    assert_int_equal(s->n_axes, 6);
    /* 12 skipped + the wrong NUM one: 13 missing, the longest run 12 from tick 20 */
    assert_int_equal(s->cs.n.missing, 13);
    assert_int_equal(s->run_longest, 12);
    assert_int_equal(s->f[AN_K_MISSING_RUN].count, 1);
    assert_int_equal(s->f[AN_K_NUM].count, 1);
    assert_int_equal(s->f[AN_K_LATE].count, 1);
    assert_int_equal(s->f[AN_K_FOLLOW_ERROR].count, 1);
    assert_non_null(strstr(s->f[AN_K_FOLLOW_ERROR].first, "axis 2 (arm 1 axis 2)"));
    assert_int_equal(s->f[AN_K_CURRENT].count, 1);
    assert_non_null(strstr(s->f[AN_K_CURRENT].first, "current D5 99 A over AzLim"));
    assert_int_equal(s->f[AN_K_CTRL_GAP].count, 0);
    assert_int_equal(s->cs.n.late, 1);
    /* every cyclic tick handed over; the last one's reply is judged at the end */
    assert_int_equal(col.cyclic, 100);
    assert_int_equal(col.with_reply, 100 - 13);
    assert_int_equal(s->n_tl[0], 1);
    assert_int_equal(s->tl[0][0].to, 2);
    c4gh_an_free(&a);
    unlink(w.path);
}

/* A capture that starts in the cyclic phase, on the default port: the controller is the
 * side whose packets the other answers within a fraction of the period. */
static void test_direction_midsession(void **state)
{
    sess_plan_t pl;
    writer_t w;
    c4gh_an_t a;
    collect_t col = {0U, 0U};
    (void)state;
    memset(&pl, 0, sizeof pl);
    pl.ticks = 50U;
    pl.skip_from = 1000U;
    pl.wrong_num_at = 1000U;
    pl.late_at = 1000U;
    pl.fe_at = 1000U;
    pl.cur_at = 1000U;
    pl.pc_port = 1000U;
    pl.t0 = 5000000000LL;
    w_open(&w, LT_EN10MB);
    write_session(&w, &pl, 4, 0);
    w_close(&w);
    analyse(w.path, &a, &col);
    assert_int_equal(a.n_sess, 1);
    assert_int_equal(a.sess[0].ctrl.port, 3600);
    assert_int_equal(a.sess[0].pc.port, 1000);
    assert_false(a.sess[0].have_init);
    assert_true(a.sess[0].synthetic_map);
    assert_int_equal(a.sess[0].ctrl_cyclic, 50);
    assert_int_equal(a.sess[0].cs.n.missing, 0);
    assert_int_equal(a.sess[0].cs.n.replies_ok, 50);
    c4gh_an_free(&a);
    unlink(w.path);
}

/* 506 then a new init packet: two sessions, the first ended by the restart. */
static void test_restart_two_sessions(void **state)
{
    sess_plan_t pl;
    writer_t w;
    c4gh_an_t a;
    collect_t col = {0U, 0U};
    (void)state;
    memset(&pl, 0, sizeof pl);
    pl.handshake = 1;
    pl.ticks = 30U;
    pl.skip_from = 1000U;
    pl.wrong_num_at = 1000U;
    pl.late_at = 1000U;
    pl.fe_at = 1000U;
    pl.cur_at = 1000U;
    pl.pc_port = 1000U;
    pl.t0 = 5000000000LL;
    w_open(&w, LT_EN10MB);
    write_session(&w, &pl, 0, 1);
    pl.t0 += 200000000LL;
    write_session(&w, &pl, 0, 0);
    w_close(&w);
    analyse(w.path, &a, &col);
    assert_int_equal(a.n_sess, 2);
    assert_string_equal(a.sess[0].end, "506 restart");
    assert_int_equal(a.sess[0].special_seen[6], 1);
    assert_int_equal(a.sess[1].ctrl_cyclic, 30);
    assert_int_equal(a.sess[1].cs.n.missing, 0);
    c4gh_an_free(&a);
    unlink(w.path);
}

/* One datagram straight into the analysis (no file). */
static void feed_dgram(c4gh_an_t *a, uint64_t frame, int64_t ts, int from_ctrl, const uint8_t *d, size_t n)
{
    c4gh_cap_pkt_t p;
    memset(&p, 0, sizeof p);
    p.frame = frame;
    p.ts_ns = ts;
    p.src_ip = from_ctrl ? IP_CTRL : IP_PC;
    p.dst_ip = from_ctrl ? IP_PC : IP_CTRL;
    p.src_port = from_ctrl ? 3600 : 1000;
    p.dst_port = from_ctrl ? 1000 : 3600;
    p.payload = d;
    p.len = n;
    c4gh_an_datagram(a, "mem", &p);
}

typedef struct times {
    int64_t last;
    int back;
    unsigned n;
} times_t;

static void on_time(void *ctx, const c4gh_an_exchange_t *x)
{
    times_t *t = ctx;
    if (x->kind == C4G_PKT_CYCLIC) {
        t->back |= (t->n > 0U && x->ctrl_ns < t->last);
        t->last = x->ctrl_ns;
        t->n++;
    }
}

/* What a capture made outside the project does: the clock steps back 1 s at tick 10, tick 5
 * is captured twice, a datagram with NUM 0x7FFFF000 comes after tick 15. Each is reported
 * once; no tick is lost or taken out of order. */
static void test_capture_artefacts(void **state)
{
    sess_plan_t pl;
    c4gh_an_options_t o;
    c4gh_an_t a;
    times_t tm;
    uint8_t b[C4G_INIT_SIZE], r[C4G_INIT_SIZE];
    const c4gh_an_session_t *s;
    int64_t t = 1700000000000000000LL;
    uint64_t frame = 0U;
    unsigned k;
    (void)state;
    memset(&pl, 0, sizeof pl);
    memset(&tm, 0, sizeof tm);
    c4gh_an_options_default(&o);
    o.on_exchange = on_time;
    o.ctx = &tm;
    assert_int_equal(c4gh_an_init(&a, &o), 0);
    for (k = 0U; k < 20U; k++) {
        const int32_t num = (int32_t)(100U + k);
        const size_t n = ctrl_packet(num, k, &pl, b, 0);
        const size_t rl = pc_packet(b, n, num + 1, k, &pl, r);
        if (k == 10U) {
            t -= 1000000000LL; /* the clock steps back */
        }
        feed_dgram(&a, ++frame, t, 1, b, n);
        if (k == 5U) {
            feed_dgram(&a, ++frame, t, 1, b, n); /* the same frame again */
        }
        feed_dgram(&a, ++frame, t + 200000, 0, r, rl);
        if (k == 15U) {
            b[0] = 0x00U; /* 0x7FFFF000: not a stale NUM */
            b[1] = 0xF0U;
            b[2] = 0xFFU;
            b[3] = 0x7FU;
            feed_dgram(&a, ++frame, t + 300000, 1, b, n);
        }
        t += 2000000;
    }
    c4gh_an_file_end(&a, "mem");
    assert_int_equal(a.n_sess, 1);
    s = &a.sess[0];
    assert_int_equal(a.doubled, 1);
    assert_int_equal(s->ctrl_cyclic, 20);
    assert_int_equal(tm.n, 20);
    assert_false(tm.back);
    assert_int_equal(s->cs.n.missing, 0);
    assert_int_equal(s->f[AN_K_CLOCK_STEP].count, 1);
    assert_int_equal(s->f[AN_K_CLOCK_STEP].frame, 22); /* tick 10's packet */
    assert_true(fabs(s->f[AN_K_CLOCK_STEP].worst - 0.9982) < 1e-6);
    assert_int_equal(s->f[AN_K_MALFORMED].count, 1);
    assert_non_null(strstr(s->f[AN_K_MALFORMED].first, "NUM 2147479552 outside 0..32767"));
    assert_int_equal(s->f[AN_K_REORDER].count, 0);
    assert_int_equal(s->f[AN_K_CTRL_GAP].count, 0);
    assert_true(s->last_ns - s->first_ns > 0);
    c4gh_an_free(&a);
}

static void test_kind_names(void **state)
{
    (void)state;
    assert_int_equal(c4gh_an_kind_find("missing-run"), AN_K_MISSING_RUN);
    assert_int_equal(c4gh_an_kind_find("nope"), -1);
    assert_string_equal(c4gh_an_kind_name(AN_K_POS_STEP), "position-step");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_link_types),
        cmocka_unit_test(test_damaged_frames),
        cmocka_unit_test(test_snaplen_and_truncation),
        cmocka_unit_test(test_not_captures),
        cmocka_unit_test(test_session_findings),
        cmocka_unit_test(test_direction_midsession),
        cmocka_unit_test(test_restart_two_sessions),
        cmocka_unit_test(test_capture_artefacts),
        cmocka_unit_test(test_kind_names),
    };
    return cmocka_run_group_tests(tests, th_load_fig, NULL);
}
