/* SPDX-License-Identifier: MIT */
/* The wire layer's observable behaviour, recorded: one line per call of the decoders,
 * encoders, the neutral reply and the session over inputs, so that two builds of the
 * library can be compared line by line (bench/wire_diff.sh: a tree's archive against the
 * one a git revision builds). A change that is meant to make lib/wire cheaper must leave
 * every line unchanged: same status codes, diagnostics, decoded values, encoded bytes and
 * session state.
 *
 * The inputs: every file named on the command line, each run
 *   - as a raw datagram through c4g_init_decode, c4g_ctrl_decode and c4g_pc_decode (axis
 *     count 0 and one taken from the first byte), their outputs encoded again, and through
 *     c4g_pc_reply_neutral;
 *   - laid over the figure 10.1 initialization packet (as fuzz_init_decode does), then
 *     c4g_init_validate, c4g_axis_map_build, c4g_init_encode, and a session started on it;
 *   - as fuzz_session's datagram stream through a session, replies alternating between
 *     c4g_session_reply_neutral, c4g_session_neutral + c4g_session_reply and
 *     c4g_pc_reply_neutral + c4g_session_reply (the session's whole public state and the
 *     reply bytes after each datagram);
 * and then MUTATIONS variants of each (a seeded generator: byte flips, and 4-byte words at
 * 4-aligned offsets set to NaN, infinities, modes, axis counts, limits and NUMs).
 * A hash (FNV-1a 64) stands for long byte strings.
 *   Usage: wire_record MUTATIONS FILE... */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include "../tests/fuzz/fuzz_stream.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; i++) {
        h = (h ^ b[i]) * 0x100000001b3ULL;
    }
    return h;
}
#define H0 0xcbf29ce484222325ULL
#define HV(h, v) fnv((h), &(v), sizeof(v))

static void pr_diag(const char *what, const c4g_diag_t *d)
{
    printf(" %s[%d %d %u %d %d %lld]", what, (int)d->status, (int)d->field, (unsigned)d->offset,
           (int)d->arm, (int)d->axis, (long long)d->value);
}

static uint64_t h_init(const c4g_init_t *in)
{
    return fnv(H0, in, sizeof *in); /* every member is 4 bytes: no padding */
}

static uint64_t h_map(const c4g_axis_map_t *m)
{
    uint64_t h = H0;
    h = HV(h, m->n_axes);
    h = fnv(h, m->arm_of, sizeof m->arm_of);
    h = fnv(h, m->logical_of, sizeof m->logical_of);
    h = fnv(h, m->open_of, sizeof m->open_of);
    h = fnv(h, m->n_axes_arm, sizeof m->n_axes_arm);
    return h;
}

/* A packet's members (the axes are 4-byte members: no padding). */
static uint64_t h_ctrl(const c4g_ctrl_packet_t *p)
{
    uint64_t h = H0;
    h = HV(h, p->num);
    h = HV(h, p->infpar);
    h = HV(h, p->cmd);
    h = HV(h, p->n_axes);
    return fnv(h, p->ax, sizeof p->ax);
}

static uint64_t h_pc(const c4g_pc_packet_t *p)
{
    uint64_t h = H0;
    h = HV(h, p->num);
    h = HV(h, p->infpar);
    h = HV(h, p->cmd);
    h = HV(h, p->n_axes);
    return fnv(h, p->ax, sizeof p->ax);
}

/* The session's public state and the private members that decide its behaviour. */
static uint64_t h_session(const c4g_session_t *s)
{
    const c4g_session_priv_t *p = &s->priv;
    uint64_t h = H0;
    h = HV(h, s->phase);
    h = HV(h, s->init.num);
    h = fnv(h, &s->init, sizeof s->init);
    h = (h ^ h_map(&s->map)) * 0x100000001b3ULL;
    h = fnv(h, &s->counters, sizeof s->counters); /* all uint64_t */
    h = HV(h, s->timing.samples_cycle);
    h = HV(h, s->timing.samples_inter);
    h = HV(h, s->timing.nominal_period_ns);
    h = HV(h, s->timing.last_cycle_ns);
    h = HV(h, s->timing.worst_cycle_ns);
    h = HV(h, s->timing.min_inter_ns);
    h = HV(h, s->timing.max_inter_ns);
    h = HV(h, s->drives);
    h = HV(h, s->lost_timeout_ns);
    h = HV(h, s->silence_ns);
    h = HV(h, s->peer_locked);
    h = fnv(h, s->peer.addr, sizeof s->peer.addr);
    h = HV(h, s->peer.port);
    h = HV(h, s->peer.addr_len);
    h = (h ^ h_ctrl(&p->rx[p->cur])) * 0x100000001b3ULL;
    h = HV(h, p->rx_mixed_modes);
    h = HV(h, p->last_num);
    h = HV(h, p->pending_num);
    h = HV(h, p->pending_kind);
    h = HV(h, p->startup_init);
    h = HV(h, p->startup_only);
    h = HV(h, p->sync_seen);
    h = HV(h, p->post_sync_left);
    h = HV(h, p->restart_pending);
    h = HV(h, p->frozen);
    h = HV(h, p->frozen_active);
    h = HV(h, p->last_rx_ns);
    h = HV(h, p->last_cyclic_ns);
    h = HV(h, p->pending_rx_ns);
    h = HV(h, p->have_cyclic_time);
    h = HV(h, p->silent);
    h = fnv(h, p->init_raw, sizeof p->init_raw);
    return h;
}

/* ---------------------------------------------------------------- the calls */

static void raw_decoders(const uint8_t *d, size_t n)
{
    static c4g_ctrl_packet_t p;
    static c4g_pc_packet_t q, t;
    c4g_init_t in;
    c4g_diag_t dg;
    uint8_t out[C4G_INIT_SIZE];
    size_t len;
    uint32_t axes[2];
    int k;
    c4g_status_t st;
    memset(&dg, 0x5A, sizeof dg);
    st = c4g_init_decode(d, n, &in, &dg);
    printf("init_decode %d", (int)st);
    pr_diag("d", &dg);
    printf(" %016llx\n", (unsigned long long)h_init(&in));
    axes[0] = 0U;
    axes[1] = (n > 0U) ? (uint32_t)(d[0] % 22U) : 1U;
    for (k = 0; k < 2; k++) {
        memset(&p, 0xA5, sizeof p);
        memset(&dg, 0x5A, sizeof dg);
        st = c4g_ctrl_decode(d, n, axes[k], &p, &dg);
        printf("ctrl_decode %u %d", (unsigned)axes[k], (int)st);
        pr_diag("d", &dg);
        printf(" %016llx", (unsigned long long)h_ctrl(&p));
        if (st == C4G_OK) {
            len = 7U;
            memset(out, 0x11, sizeof out);
            st = c4g_ctrl_encode(&p, out, sizeof out, &len);
            printf(" enc %d %zu %016llx", (int)st, len, (unsigned long long)fnv(H0, out, C4G_MAX_CYCLIC_SIZE));
            memset(&t, 0x3C, sizeof t);
            st = c4g_pc_reply_neutral(&p, &t);
            printf(" neutral %d %016llx", (int)st, (unsigned long long)h_pc(&t));
            if (st == C4G_OK) {
                len = 7U;
                memset(out, 0x11, sizeof out);
                st = c4g_pc_encode(&t, out, sizeof out, &len);
                printf(" nenc %d %zu %016llx", (int)st, len, (unsigned long long)fnv(H0, out, C4G_MAX_CYCLIC_SIZE));
            }
            /* a short buffer */
            len = 7U;
            st = c4g_ctrl_encode(&p, out, (n > 13U) ? n - 1U : 0U, &len);
            printf(" short %d %zu", (int)st, len);
        }
        printf("\n");
        memset(&q, 0xA5, sizeof q);
        memset(&dg, 0x5A, sizeof dg);
        st = c4g_pc_decode(d, n, axes[k], &q, &dg);
        printf("pc_decode %u %d", (unsigned)axes[k], (int)st);
        pr_diag("d", &dg);
        printf(" %016llx", (unsigned long long)h_pc(&q));
        if (st == C4G_OK) {
            len = 7U;
            memset(out, 0x11, sizeof out);
            st = c4g_pc_encode(&q, out, sizeof out, &len);
            printf(" enc %d %zu %016llx", (int)st, len, (unsigned long long)fnv(H0, out, C4G_MAX_CYCLIC_SIZE));
        }
        printf("\n");
    }
}

/* The raw bytes laid as a packet struct and encoded: the encoders' own checks. */
static void raw_encoders(const uint8_t *d, size_t n)
{
    static c4g_ctrl_packet_t p;
    static c4g_pc_packet_t q;
    uint8_t out[C4G_MAX_CYCLIC_SIZE];
    size_t len = 7U;
    size_t m = (n < sizeof p.ax) ? n : sizeof p.ax;
    c4g_status_t st;
    memset(&p, 0, sizeof p);
    memcpy(p.ax, d, m);
    p.num = (n > 1U) ? (int32_t)(((uint32_t)d[0] << 8U) | d[1]) - 1000 : 5;
    p.n_axes = (n > 2U) ? (uint32_t)(d[2] % 23U) : 1U;
    p.infpar = 0x01020304U;
    memset(out, 0x11, sizeof out);
    st = c4g_ctrl_encode(&p, out, sizeof out, &len);
    printf("ctrl_encode %d %zu %016llx\n", (int)st, len, (unsigned long long)fnv(H0, out, sizeof out));
    memset(&q, 0, sizeof q);
    memcpy(q.ax, d, m);
    q.num = p.num;
    q.n_axes = p.n_axes;
    len = 7U;
    memset(out, 0x11, sizeof out);
    st = c4g_pc_encode(&q, out, sizeof out, &len);
    printf("pc_encode %d %zu %016llx\n", (int)st, len, (unsigned long long)fnv(H0, out, sizeof out));
}

static void session_line(const char *what, c4g_status_t st, const c4g_rx_result_t *r,
                         const c4g_session_t *s)
{
    printf("%s %d kind %d ev %08x", what, (int)st, (int)r->kind, (unsigned)r->events);
    pr_diag("d", &r->diag);
    printf(" sil %llu pkt %s %016llx\n", (unsigned long long)r->silence_ns,
           (r->pkt == NULL) ? "-" : "p", (unsigned long long)h_session(s));
}

/* One reply to what the session holds, in one of three ways. */
static void session_answer(c4g_session_t *s, const c4g_rx_result_t *r, unsigned way, uint64_t t)
{
    static c4g_pc_packet_t tx;
    uint8_t out[C4G_INIT_SIZE];
    size_t n = 7U;
    c4g_status_t st;
    c4g_status_t st2 = C4G_OK;
    memset(out, 0x11, sizeof out);
    memset(&tx, 0x3C, sizeof tx);
    if (way == 0U) {
        st = c4g_session_reply_neutral(s, out, sizeof out, &n);
    } else if ((way == 1U) && (r->pkt != NULL)) {
        st2 = c4g_session_neutral(s, r->pkt, &tx);
        st = c4g_session_reply(s, (st2 == C4G_OK) ? &tx : NULL, out, sizeof out, &n);
    } else if (r->pkt != NULL) {
        st2 = c4g_pc_reply_neutral(r->pkt, &tx);
        st = c4g_session_reply(s, &tx, out, sizeof out, &n);
    } else {
        st = c4g_session_reply(s, NULL, out, sizeof out, &n);
    }
    printf("reply %u %d %d %zu %016llx %016llx", way, (int)st2, (int)st, n,
           (unsigned long long)fnv(H0, out, sizeof out), (unsigned long long)h_session(s));
    if (way == 1U) {
        printf(" tx %016llx", (unsigned long long)h_pc(&tx));
    }
    /* a second reply: refused (answered already) */
    n = 7U;
    st = c4g_session_reply_neutral(s, out, sizeof out, &n);
    printf(" again %d %zu", (int)st, n);
    st = c4g_session_sent(s, t + 1000U);
    printf(" sent %d\n", (int)st);
    /* too small a buffer */
}

/* fuzz_session's stream through a session; @p cfgk picks the configuration. */
static void session_stream(const uint8_t *d, size_t n, unsigned cfgk)
{
    static c4g_session_t s;
    static fuzz_stream_t fs;
    c4g_session_config_t cfg;
    const uint8_t *dg;
    size_t dl;
    const c4g_endpoint_t *from;
    unsigned k = 0U;
    (void)c4g_session_config_default(&cfg);
    if (cfgk == 1U) {
        cfg.num_policy = C4G_NUM_ECHO;
        cfg.az_lim_max = 5.0F;
        cfg.follow_error_max = 2.0F;
        cfg.post_init_sync = 0U;
    }
    fuzz_stream_start(&fs, d, n);
    if (c4g_session_init(&s, &cfg) != C4G_OK) {
        abort();
    }
    while (fuzz_stream_next(&fs, &dg, &dl, &from)) {
        c4g_rx_result_t r;
        c4g_status_t st;
        memset(&r, 0x77, sizeof r);
        st = c4g_session_rx_from(&s, dg, dl, fs.t, from, &r);
        session_line("rx", st, &r, &s);
        if (st == C4G_ERR_ENDED) {
            (void)c4g_session_init(&s, &cfg);
            continue;
        }
        if (st == C4G_OK) {
            if ((k % 7U) == 3U) {
                /* a reply into too small a buffer first */
                uint8_t small[64];
                size_t sn = 7U;
                st = c4g_session_reply_neutral(&s, small, sizeof small, &sn);
                printf("small %d %zu\n", (int)st, sn);
            }
            session_answer(&s, &r, k % 3U, fs.t);
        }
        k++;
    }
}

/* The bytes laid over the figure 10.1 initialization packet (first two bytes: the offset),
 * the validators, and a session started on the packet with cyclic packets after it. */
static void init_checks(const uint8_t *buf)
{
    static c4g_session_t s;
    c4g_init_t in;
    c4g_axis_map_t m;
    c4g_diag_t dg;
    uint8_t out[C4G_INIT_SIZE];
    size_t len = 0U;
    c4g_status_t st;
    unsigned cfgk;
    memset(&dg, 0x5A, sizeof dg);
    memset(&in, 0x3C, sizeof in);
    st = c4g_init_decode(buf, C4G_INIT_SIZE, &in, &dg);
    printf("overlay %d", (int)st);
    pr_diag("d", &dg);
    printf(" %016llx", (unsigned long long)h_init(&in));
    memset(&dg, 0x5A, sizeof dg);
    st = c4g_init_validate(&in, &dg);
    printf(" validate %d", (int)st);
    pr_diag("d", &dg);
    memset(&m, 0x3C, sizeof m);
    memset(&dg, 0x5A, sizeof dg);
    st = c4g_axis_map_build(&in, &m, &dg);
    printf(" map %d", (int)st);
    pr_diag("d", &dg);
    printf(" %016llx", (unsigned long long)h_map(&m));
    len = 7U;
    memset(out, 0x11, sizeof out);
    st = c4g_init_encode(&in, out, sizeof out, &len);
    printf(" encode %d %zu %016llx\n", (int)st, len, (unsigned long long)fnv(H0, out, sizeof out));
    for (cfgk = 0U; cfgk < 2U; cfgk++) {
        c4g_session_config_t cfg;
        c4g_rx_result_t r;
        c4g_ctrl_packet_t p;
        uint8_t cy[C4G_MAX_CYCLIC_SIZE];
        uint8_t rep[C4G_INIT_SIZE];
        size_t cl = 0U;
        size_t rn = 7U;
        memset(rep, 0x11, sizeof rep);
        uint32_t i;
        int j;
        (void)c4g_session_config_default(&cfg);
        cfg.post_init_sync = 0U;
        if (cfgk == 1U) {
            cfg.az_lim_max = 5.0F;
            cfg.follow_error_max = 2.0F;
        }
        (void)c4g_session_init(&s, &cfg);
        memset(&r, 0x77, sizeof r);
        st = c4g_session_rx(&s, buf, C4G_INIT_SIZE, 1000000U, &r);
        session_line("overlay_rx", st, &r, &s);
        st = c4g_session_reply(&s, NULL, rep, sizeof rep, &rn);
        printf("overlay_reply %d %zu %016llx\n", (int)st, rn, (unsigned long long)fnv(H0, rep, sizeof rep));
        if (s.map.n_axes == 0U) {
            continue;
        }
        /* the same init again (a duplicate) */
        memset(&r, 0x77, sizeof r);
        st = c4g_session_rx(&s, buf, C4G_INIT_SIZE, 2000000U, &r);
        session_line("overlay_rx2", st, &r, &s);
        memset(&p, 0, sizeof p);
        p.n_axes = s.map.n_axes;
        for (j = 0; j < 3; j++) {
            p.num = 11 + j;
            for (i = 0U; i < p.n_axes; i++) {
                static const int32_t modes[3] = {C4G_MODE_0, 1, 2};
                p.ax[i].mode = modes[j];
                p.ax[i].target_pos = 1.0F + (float)i;
                p.ax[i].current_ref = 3.0F * (float)(i + 1U) - 20.0F;
            }
            if (c4g_ctrl_encode(&p, cy, sizeof cy, &cl) != C4G_OK) {
                abort();
            }
            memset(&r, 0x77, sizeof r);
            st = c4g_session_rx(&s, cy, cl, 3000000U + 2000000U * (uint64_t)j, &r);
            session_line("overlay_cy", st, &r, &s);
            if (st == C4G_OK) {
                session_answer(&s, &r, (unsigned)j % 3U, 3000000U + 2000000U * (uint64_t)j);
            }
        }
    }
}

static void init_overlay(const uint8_t *d, size_t n)
{
    c4g_init_t in;
    uint8_t buf[C4G_INIT_SIZE];
    size_t len = 0U;
    (void)c4gsim_fig10_1(&in);
    (void)c4g_init_encode(&in, buf, sizeof buf, &len);
    if (n >= 2U) {
        size_t off = (((size_t)d[0] << 8U) | d[1]) % C4G_INIT_SIZE;
        size_t k = n - 2U;
        if (k > C4G_INIT_SIZE - off) {
            k = C4G_INIT_SIZE - off;
        }
        memcpy(&buf[off], &d[2], k);
    }
    init_checks(buf);
}

/* ---------------------------------------------------------------- mutations */

static uint64_t g_rng = 0x9E3779B97F4A7C15ULL;

static uint32_t rnd(void)
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 7;
    g_rng ^= g_rng << 17;
    return (uint32_t)(g_rng >> 16);
}

static const uint32_t specials[] = {
    0x7FC00000U, 0xFFC00001U, 0x7F800000U, 0xFF800000U, 0x7F7FFFFFU, 0x00000001U,
    0x80000000U, 0xBF800000U, 0x3F800000U, 0x41200000U, 0x47000000U, 0U, 1U, 2U, 3U,
    4U, 5U, 9U, 10U, 11U, 12U, 17U, 18U, 19U, 20U, 21U, 39U, 40U, 0xFFU, 0xFEU,
    0xFFFFFFFFU, 500U, 501U, 502U, 503U, 504U, 505U, 506U, 507U, 999U, 1000U, 1001U,
    0x7FFFU, 0x8000U, 0x7FFEU, 0x05050505U, 0x06060606U, 0x01000000U, 0x40A00000U,
    0x41A00000U, 0x00800000U, 0x807FFFFFU, 0x7F7FFFFFU, 0x3F000000U, 13U, 16U};

static uint32_t special(void)
{
    return specials[rnd() % (sizeof specials / sizeof specials[0])];
}

/* One variant of @p d (length @p n) into @p m; returns its length. */
static size_t mutate(const uint8_t *d, size_t n, uint8_t *m, size_t cap)
{
    size_t len = (n < cap) ? n : cap;
    uint32_t edits = 1U + (rnd() % 4U);
    uint32_t e;
    memcpy(m, d, len);
    if ((rnd() % 8U) == 0U) {
        /* another length: one axis more or less, or a byte */
        static const int delta[] = {-36, 36, -1, 1, -4};
        const int dl = delta[rnd() % 5U];
        if ((dl > 0) && (len + (size_t)dl <= cap)) {
            memset(&m[len], (int)(rnd() & 0xFFU), (size_t)dl);
            len += (size_t)dl;
        } else if ((dl < 0) && (len >= (size_t)(-dl))) {
            len -= (size_t)(-dl);
        }
    }
    for (e = 0U; (e < edits) && (len > 0U); e++) {
        const uint32_t how = rnd() % 3U;
        if ((how == 0U) || (len < 4U)) {
            m[rnd() % len] ^= (uint8_t)(1U << (rnd() % 8U));
        } else {
            const size_t at = (rnd() % (len / 4U)) * 4U + ((how == 2U) ? 2U : 0U);
            const uint32_t v = special();
            size_t b;
            for (b = 0U; (b < 4U) && (at + b < len); b++) {
                m[at + b] = (uint8_t)(v >> (8U * b));
            }
        }
    }
    return len;
}

static void one(const uint8_t *d, size_t n)
{
    if (n == C4G_INIT_SIZE) {
        init_checks(d);
    }
    raw_decoders(d, n);
    raw_encoders(d, n);
    init_overlay(d, n);
    session_stream(d, n, 0U);
    session_stream(d, n, 1U);
}

/* Initialization packets of @p axes open axes (bench/tick.c's), arms filled in turn or
 * (@p spread) one axis per arm first. */
static size_t init_packet(uint32_t axes, int spread, uint8_t *buf)
{
    c4g_init_t in;
    size_t n = 0U;
    uint32_t i;
    (void)c4gsim_fig10_1(&in);
    in.n_ax_open = (int32_t)axes;
    for (i = 0; i < 40U; i++) {
        const uint32_t a = spread ? (i % 4U) : (i / 10U);
        const uint32_t x = spread ? (i / 4U) : (i % 10U);
        in.open_ax[a][x] = (i < axes) ? (int32_t)i : C4G_OPEN_AX_NONE;
        if (i < axes) {
            in.az_lim[a][x] = 10.0f;
            in.tx_rate[a][x] = 50.0f + (float)x;
            in.follow_error[a][x] = 5.0f;
            in.open_mask[a][x] = ((i % 3U) == 0U) ? C4G_OPEN_AX_NONE : (int32_t)(i % 5U);
        }
    }
    if (c4g_init_encode(&in, buf, C4G_INIT_SIZE, &n) != C4G_OK) {
        abort();
    }
    return n;
}

int main(int argc, char **argv)
{
    static uint8_t data[1U << 16];
    static uint8_t mut[(1U << 16) + 64U];
    const int mutations = (argc > 1) ? atoi(argv[1]) : 0;
    int a;
    for (a = 2; a < argc; a++) {
        size_t n;
        int k;
        if (strncmp(argv[a], "@init", 5) == 0) {
            /* @initN / @initNs: a generated initialization packet */
            n = init_packet((uint32_t)atoi(&argv[a][5]), strchr(argv[a], 's') != NULL, data);
        } else {
            FILE *f = fopen(argv[a], "rb");
            if (f == NULL) {
                fprintf(stderr, "wire_record: cannot read %s\n", argv[a]);
                return 1;
            }
            n = fread(data, 1U, sizeof data, f);
            fclose(f);
        }
        printf("== %s\n", argv[a]);
        one(data, n);
        if (n == C4G_INIT_SIZE) {
            /* every word of an initialization packet set to every special value in turn */
            static uint8_t b[C4G_INIT_SIZE];
            size_t off;
            for (off = 0U; off < C4G_INIT_SIZE; off += 4U) {
                size_t v;
                for (v = 0U; v < sizeof specials / sizeof specials[0]; v++) {
                    memcpy(b, data, sizeof b);
                    b[off] = (uint8_t)specials[v];
                    b[off + 1U] = (uint8_t)(specials[v] >> 8U);
                    b[off + 2U] = (uint8_t)(specials[v] >> 16U);
                    b[off + 3U] = (uint8_t)(specials[v] >> 24U);
                    printf("== %s @%zu=%08x\n", argv[a], off, (unsigned)specials[v]);
                    init_checks(b);
                }
            }
        }
        for (k = 0; k < mutations; k++) {
            const size_t m = mutate(data, n, mut, sizeof mut);
            printf("== %s ~%d\n", argv[a], k);
            one(mut, m);
        }
    }
    return 0;
}
