/* SPDX-License-Identifier: MIT */
/* c4g-replay rerun: the recorded controller packets of a capture through c4g-server's own
 * per-datagram core (tools/c4g-server/srv_core: libc4gopen's loop and the server's controllers,
 * the code c4g-server runs), at top speed with the recorded reception times. Every reply
 * produced is compared with the reply recorded for the same controller packet, word by word,
 * each word named by its field; the first divergence and the count per field are reported.
 *
 * What the server would have seen is rebuilt from the capture: one server per controller
 * endpoint, a fresh one where the recorded run would have stopped (504 without --persist, a
 * lost controller), the silence before each packet (srv_idle), and during an active-freezing
 * pause only the newest packet answered once the pause is over. */
#include "replay.h"

#include "c4gsim_fixtures.h"
#include "srv_core.h"
#include "c4gh_textfile.h"

#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RR_MAX_SERVER_ARGS 128
#define RR_PENDING 8U  /* produced replies awaiting a late recorded one (packets) */

/* Fields a divergence is counted under: reply (sent on one side only), length, a word of a
 * sync reply or of the init echo, then the cyclic reply's words. */
#define RR_FIELDS(X)                    \
    X(REPLY, "reply")           \
    X(LENGTH, "length")         \
    X(SYNC, "sync")             \
    X(INIT, "init")             \
    X(NUM, "num")               \
    X(INFPAR, "infpar")         \
    X(CMD, "cmd")               \
    X(MODE, "mode")             \
    X(D1, "d1")                 \
    X(D2, "d2")                 \
    X(D3, "d3")                 \
    X(D4, "d4")                 \
    X(D5, "d5")                 \
    X(EXT1, "ext1")             \
    X(EXT2, "ext2")             \
    X(EXT3, "ext3")

#define RR_FIELD_ENUM(id, name) RR_F_##id,
typedef enum rr_field { RR_FIELDS(RR_FIELD_ENUM) RR_F_COUNT } rr_field_t;
#undef RR_FIELD_ENUM

#define RR_FIELD_NAME(id, name) name,
static const char *const k_field_names[RR_F_COUNT] = {RR_FIELDS(RR_FIELD_NAME)};
#undef RR_FIELD_NAME

typedef enum rr_behaviour { RR_SERVER = 0, RR_ECHO } rr_behaviour_t;

/* One divergence: where, which field, both values. */
typedef struct rr_div {
    unsigned session;
    uint64_t tick;           /* the cyclic packet's number in its session (1 = the first) */
    int kind;                /* C4G_PKT_SYNC / C4G_PKT_INIT / C4G_PKT_CYCLIC */
    int32_t num;             /* the controller packet's NUM */
    uint64_t frame;          /* its frame in the capture */
    double t_s;              /* since the session's first packet */
    int open;                /* OPEN index 1..20, 0: not an axis field */
    int arm, logical;        /* 1-based, 0 unknown */
    unsigned word;           /* 32-bit word of the reply */
    rr_field_t field;
    char recorded[40], produced[40];
} rr_div_t;

typedef struct rr_field_count {
    uint64_t count;
    rr_div_t first;
} rr_field_count_t;

typedef struct rr_sess {
    unsigned id;
    c4gh_an_endpoint_t ctrl, pc;
    uint64_t fed[3];         /* sync, init, cyclic packets fed */
    uint64_t compared, divergent;
    uint64_t recorded_missing;  /* controller packets the recording has no reply to */
    uint64_t held_dropped;      /* packets the server drops after an active-freezing pause */
    uint64_t first_div_tick;
    int any_div;
    uint64_t timing_only;       /* recorded after the next packet, produced in time, equal */
    int primed;                 /* no start-up in the capture: a synthetic one was fed */
    unsigned primed_axes, primed_period_ms;
} rr_sess_t;

/* A controller packet and the recorded reply, as rerun needs them (held across a pause). */
typedef struct rr_pkt {
    unsigned session;
    const c4gh_an_session_t *s;
    int kind;
    uint64_t tick;
    const uint8_t *ctrl;
    size_t ctrl_len;
    uint64_t ctrl_frame;
    int64_t ctrl_ns;
    const uint8_t *rec;      /* NULL: nothing recorded */
    size_t rec_len;
    int64_t rec_ns;
} rr_pkt_t;

/* A reply produced for a packet the recording shows no reply to by its deadline: judged
 * once the recorded reply turns up late (a timing difference, its content compared) or
 * RR_PENDING packets later (a divergence: recorded none). */
typedef struct rr_pending {
    int used;
    rr_pkt_t p;
    uint8_t ctrl[C4G_INIT_SIZE];
    uint8_t out[C4G_INIT_SIZE];
    size_t out_len;
} rr_pending_t;

typedef struct rr {
    rp_common_t c;
    rr_behaviour_t behaviour;
    unsigned only_session;   /* 0: every session of the first controller */
    double tolerance;        /* absolute, on the float fields; 0: bit-exact */
    long long max_lines;     /* divergences printed one per line (--list) */
    srv_config_t cfg;
    char **srv_argv;
    int srv_argc;
    /* the run */
    int have_ctrl;
    c4gh_an_endpoint_t ctrl;      /* the controller being rerun */
    int server_live;         /* a server is running (fresh after a stop) */
    int server_stopped;      /* the last packet ended the server's run */
    uint64_t server_starts;
    int64_t t_last;
    int frozen;
    int64_t freeze_until;
    int have_held;
    rr_pkt_t held;
    uint8_t held_ctrl[C4G_INIT_SIZE], held_rec[C4G_INIT_SIZE];
    uint64_t other_ctrl_exchanges;  /* packets of sessions not rerun */
    unsigned other_sessions[C4GH_AN_MAX_SESSIONS];
    unsigned n_other;
    rr_sess_t sess[C4GH_AN_MAX_SESSIONS];
    unsigned n_sess;
    uint64_t compared, divergent, words_divergent;
    int have_first;
    rr_div_t first;
    rr_field_count_t fields[RR_F_COUNT];
    long long listed;
    rr_pending_t pending[RR_PENDING];
    unsigned pend_next;
    uint64_t timing_only;
    int init_error;
    char init_why[200];
} rr_t;

static srv_t g_srv;          /* large: static storage, like c4g-server's */
static rr_t g_rr;

/* ---- comparing one reply ------------------------------------------------- */

static rr_sess_t *sess_of(rr_t *R, const c4gh_an_session_t *s)
{
    unsigned i;
    for (i = 0U; i < R->n_sess; i++) {
        if (R->sess[i].id == s->id) {
            return &R->sess[i];
        }
    }
    if (R->n_sess >= C4GH_AN_MAX_SESSIONS) {
        return NULL;
    }
    R->sess[R->n_sess].id = s->id;
    R->sess[R->n_sess].ctrl = s->ctrl;
    R->sess[R->n_sess].pc = s->pc;
    return &R->sess[R->n_sess++];
}

static void word_text(char *buf, size_t cap, rr_field_t f, uint32_t u)
{
    if (f >= RR_F_D1) {
        (void)snprintf(buf, cap, "%.9g", (double)c4gh_an_f32_bits(u));
    } else if (f == RR_F_NUM || f == RR_F_MODE) {
        (void)snprintf(buf, cap, "%d", (int)(int32_t)u);
    } else {
        (void)snprintf(buf, cap, "0x%08x", (unsigned)u);
    }
}

static void div_where(rr_div_t *d, const rr_pkt_t *p)
{
    memset(d, 0, sizeof *d);
    d->session = p->session;
    d->tick = p->tick;
    d->kind = p->kind;
    d->num = (p->ctrl_len >= 4U) ? (int32_t)c4g_le_u32(p->ctrl) : -1;
    d->frame = p->ctrl_frame;
    d->t_s = (double)(p->ctrl_ns - p->s->first_ns) * 1e-9;
}

static const char *kind_name(int kind)
{
    return (kind == C4G_PKT_SYNC) ? "sync" : ((kind == C4G_PKT_INIT) ? "init" : "cyclic");
}

static void print_div(FILE *out, const rr_div_t *d)
{
    fprintf(out, "session %u ", d->session);
    if (d->kind == C4G_PKT_CYCLIC) {
        fprintf(out, "tick %llu", (unsigned long long)d->tick);
    } else {
        fprintf(out, "%s packet", kind_name(d->kind));
    }
    fprintf(out, " (controller NUM %d, frame %llu, %.6f s): ", (int)d->num, (unsigned long long)d->frame,
            d->t_s);
    if (d->open > 0) {
        if (d->arm > 0) {
            fprintf(out, "arm %d axis %d (OPEN %d) ", d->arm, d->logical, d->open);
        } else {
            fprintf(out, "OPEN axis %d ", d->open);
        }
    }
    if (d->field == RR_F_SYNC || d->field == RR_F_INIT) {
        fprintf(out, "%s word %u", k_field_names[d->field], d->word);
    } else {
        fprintf(out, "%s", k_field_names[d->field]);
    }
    fprintf(out, ": recorded %s, produced %s\n", d->recorded, d->produced);
}

/* Divergences of a packet whose recorded reply came late are found after later ones: the
 * first is the first in the capture. */
static int before(const rr_div_t *a, const rr_div_t *b)
{
    return a->session < b->session || (a->session == b->session && a->frame < b->frame);
}

static void count_div(rr_t *R, const rr_div_t *d)
{
    rr_field_count_t *fc = &R->fields[d->field];
    if (fc->count++ == 0U || before(d, &fc->first)) {
        fc->first = *d;
    }
    R->words_divergent++;
    if (!R->have_first || before(d, &R->first)) {
        R->first = *d;
        R->have_first = 1;
    }
    if (R->listed < R->max_lines) {
        R->listed++;
        fputs("divergence: ", stdout);
        print_div(stdout, d);
    }
}

static int float_equal(const rr_t *R, uint32_t a, uint32_t b)
{
    const double x = (double)c4gh_an_f32_bits(a), y = (double)c4gh_an_f32_bits(b);
    if (a == b) {
        return 1;
    }
    return R->tolerance > 0.0 && isfinite(x) && isfinite(y) && fabs(x - y) <= R->tolerance;
}

/* The field a word of a cyclic reply carries; *axis the OPEN index (0-based) or -1. */
static rr_field_t cyclic_field(unsigned w, int *axis)
{
    static const rr_field_t head[3] = {RR_F_NUM, RR_F_INFPAR, RR_F_CMD};
    static const rr_field_t per_axis[9] = {RR_F_MODE, RR_F_D1,   RR_F_D2,   RR_F_D3,  RR_F_D4,
                                           RR_F_D5,   RR_F_EXT1, RR_F_EXT2, RR_F_EXT3};
    if (w < 3U) {
        *axis = -1;
        return head[w];
    }
    *axis = (int)((w - 3U) / 9U);
    return per_axis[(w - 3U) % 9U];
}

/* Compare the words both replies have; 1 if any differs. */
static int compare_words(rr_t *R, const rr_pkt_t *p, const uint8_t *rec, const uint8_t *out, size_t n)
{
    const c4gh_an_session_t *s = p->s;
    unsigned w;
    int diverged = 0;
    for (w = 0U; w < (unsigned)(n / 4U); w++) {
        const uint32_t a = c4g_le_u32(rec + 4U * w), b = c4g_le_u32(out + 4U * w);
        rr_div_t d;
        int axis = -1;
        rr_field_t f;
        if (a == b) {
            continue;
        }
        if (p->kind == C4G_PKT_CYCLIC) {
            f = cyclic_field(w, &axis);
            if (f >= RR_F_D1 && float_equal(R, a, b)) {
                continue;
            }
        } else {
            f = (p->kind == C4G_PKT_SYNC) ? RR_F_SYNC : RR_F_INIT;
        }
        div_where(&d, p);
        d.field = f;
        d.word = w;
        if (axis >= 0) {
            d.open = axis + 1;
            if (axis < (int)s->map.n_axes) {
                d.arm = (int)s->map.arm_of[axis] + 1;
                d.logical = (int)s->map.logical_of[axis] + 1;
            }
        }
        word_text(d.recorded, sizeof d.recorded, f, a);
        word_text(d.produced, sizeof d.produced, f, b);
        count_div(R, &d);
        diverged = 1;
    }
    return diverged;
}

static void diverged_packet(rr_t *R, rr_sess_t *ss, const rr_pkt_t *p)
{
    R->divergent++;
    ss->divergent++;
    if (!ss->any_div || p->tick < ss->first_div_tick) {
        ss->any_div = 1;
        ss->first_div_tick = p->tick;
    }
}

/* A pending packet without its late recorded reply: recorded none, produced a reply. */
static void pending_expire(rr_t *R, rr_pending_t *e)
{
    rr_sess_t *ss = sess_of(R, e->p.s);
    rr_div_t d;
    e->used = 0;
    if (ss == NULL) {
        return;
    }
    ss->recorded_missing++;
    div_where(&d, &e->p);
    d.field = RR_F_REPLY;
    (void)snprintf(d.recorded, sizeof d.recorded, "none");
    (void)snprintf(d.produced, sizeof d.produced, "a reply");
    count_div(R, &d);
    diverged_packet(R, ss, &e->p);
}

static void pending_add(rr_t *R, const rr_pkt_t *p, const uint8_t *out, size_t out_len)
{
    rr_pending_t *e = &R->pending[R->pend_next];
    R->pend_next = (R->pend_next + 1U) % RR_PENDING;
    if (e->used) {
        pending_expire(R, e);
    }
    e->used = 1;
    e->p = *p;
    memcpy(e->ctrl, p->ctrl, p->ctrl_len);
    e->p.ctrl = e->ctrl;
    e->p.rec = NULL;
    memcpy(e->out, out, out_len);
    e->out_len = out_len;
}

static void pending_flush(rr_t *R)
{
    unsigned k;
    for (k = 0U; k < RR_PENDING; k++) {
        rr_pending_t *e = &R->pending[(R->pend_next + k) % RR_PENDING];
        if (e->used) {
            pending_expire(R, e);
        }
    }
}

static void compare(rr_t *R, const rr_pkt_t *p, const uint8_t *out, size_t out_len)
{
    rr_sess_t *ss = sess_of(R, p->s);
    int diverged = 0;
    rr_div_t d;
    if (ss == NULL) {
        return;
    }
    ss->compared++;
    R->compared++;
    if (p->rec == NULL && out != NULL && out_len <= C4G_INIT_SIZE && p->ctrl_len <= C4G_INIT_SIZE) {
        pending_add(R, p, out, out_len); /* its recorded reply may still come, late */
        return;
    }
    if (p->rec == NULL) {
        ss->recorded_missing++;
    }
    if ((p->rec == NULL) != (out == NULL)) {
        div_where(&d, p);
        d.field = RR_F_REPLY;
        (void)snprintf(d.recorded, sizeof d.recorded, "%s", (p->rec != NULL) ? "a reply" : "none");
        (void)snprintf(d.produced, sizeof d.produced, "%s", (out != NULL) ? "a reply" : "none");
        count_div(R, &d);
        diverged = 1;
    } else if (p->rec != NULL) {
        const size_t n = (p->rec_len < out_len) ? p->rec_len : out_len;
        if (p->rec_len != out_len) {
            div_where(&d, p);
            d.field = RR_F_LENGTH;
            (void)snprintf(d.recorded, sizeof d.recorded, "%zu bytes", p->rec_len);
            (void)snprintf(d.produced, sizeof d.produced, "%zu bytes", out_len);
            count_div(R, &d);
            diverged = 1;
        }
        diverged |= compare_words(R, p, p->rec, out, n);
    }
    if (diverged) {
        diverged_packet(R, ss, p);
    }
}

/* A recorded reply that came after its packet's deadline: the reply the server produced for
 * that packet is compared with it; equal content is a timing difference only. */
static void on_late(void *ctx, const c4gh_an_session_t *s, const uint8_t *d, size_t len, int64_t ns,
                    uint64_t frame)
{
    rr_t *R = ctx;
    const int32_t num = (len >= 4U) ? (int32_t)c4g_le_u32(d) : -1;
    const int policy = (s->cs.detected >= 0) ? s->cs.detected
                                              : ((R->c.an.num_policy == C4G_NUM_ECHO) ? C4G_NUM_ECHO
                                                                                      : C4G_NUM_PLUS_ONE);
    unsigned k;
    (void)ns;
    (void)frame;
    for (k = 0U; k < RR_PENDING; k++) {
        rr_pending_t *e = &R->pending[(R->pend_next + RR_PENDING - 1U - k) % RR_PENDING];
        const int32_t sent = (e->p.ctrl_len >= 4U) ? (int32_t)c4g_le_u32(e->p.ctrl) : -1;
        rr_sess_t *ss;
        int diverged = 0;
        if (!e->used || e->p.s != s ||
            c4g_reply_num(sent, policy == C4G_NUM_ECHO ? C4G_NUM_ECHO : C4G_NUM_PLUS_ONE) != num) {
            continue;
        }
        e->used = 0;
        ss = sess_of(R, s);
        if (ss == NULL) {
            return;
        }
        if (len != e->out_len) {
            rr_div_t dv;
            div_where(&dv, &e->p);
            dv.field = RR_F_LENGTH;
            (void)snprintf(dv.recorded, sizeof dv.recorded, "%zu bytes", len);
            (void)snprintf(dv.produced, sizeof dv.produced, "%zu bytes", e->out_len);
            count_div(R, &dv);
            diverged = 1;
        }
        diverged |= compare_words(R, &e->p, d, e->out, (len < e->out_len) ? len : e->out_len);
        if (diverged) {
            diverged_packet(R, ss, &e->p);
        } else {
            ss->timing_only++;
            R->timing_only++;
        }
        return;
    }
}

/* ---- the server ----------------------------------------------------------- */

static int server_start(rr_t *R)
{
    if (srv_init(&g_srv, &R->cfg, NULL, NULL) != C4G_OK) {
        R->init_error = 1;
        (void)snprintf(R->init_why, sizeof R->init_why, "the server core refused the configuration");
        return -1;
    }
    R->server_live = 1;
    R->server_stopped = 0;
    R->server_starts++;
    return 0;
}

static void endpoint_of(const c4gh_an_endpoint_t *a, c4g_endpoint_t *e)
{
    memset(e, 0, sizeof *e);
    e->addr[0] = (uint8_t)(a->ip >> 24);
    e->addr[1] = (uint8_t)(a->ip >> 16);
    e->addr[2] = (uint8_t)(a->ip >> 8);
    e->addr[3] = (uint8_t)a->ip;
    e->addr_len = 4U;
    e->port = a->port;
}

/* One controller packet into the server at @p t_rx; the reply compared. */
static void feed(rr_t *R, const rr_pkt_t *p, uint64_t t_rx, int after_pause)
{
    static uint8_t out[C4G_INIT_SIZE + 64U];
    rr_sess_t *ss = sess_of(R, p->s);
    c4g_endpoint_t from;
    srv_verdict_t v;
    size_t olen = 0U;
    c4g_status_t st;
    if (R->init_error) {
        return;
    }
    if (!R->server_live || R->server_stopped) {
        if (server_start(R) != 0) {
            return;
        }
        g_srv.t0_ns = t_rx;
    } else if (!after_pause && srv_idle(&g_srv, t_rx) != SRV_STOP_NONE) {
        /* the server lost the controller before this packet and stopped: run a new one */
        if (server_start(R) != 0) {
            return;
        }
        g_srv.t0_ns = t_rx;
    }
    if (ss != NULL && p->kind >= C4G_PKT_SYNC && p->kind <= C4G_PKT_CYCLIC) {
        ss->fed[p->kind]++;
    }
    endpoint_of(&p->s->ctrl, &from);
    memset(&v, 0, sizeof v);
    st = srv_process(&g_srv, p->ctrl, p->ctrl_len, &from, t_rx, out, sizeof out, &olen, &v);
    compare(R, p, (st == C4G_OK && v.send) ? out : NULL, olen);
    if (st == C4G_OK && v.send) {
        const uint64_t t_tx = (p->rec != NULL && p->rec_ns >= (int64_t)t_rx) ? (uint64_t)p->rec_ns : t_rx;
        srv_sent(&g_srv, t_tx);
        if (v.freeze) {
            R->frozen = 1;
            R->freeze_until = (int64_t)t_tx + (int64_t)(v.pause_ms * 1e6);
        }
    }
    if (st == C4G_OK && v.stop != SRV_STOP_NONE) {
        R->server_stopped = 1;
    }
    R->t_last = (int64_t)t_rx;
}

/* A session the capture shows without its start-up (it begins after the initialization
 * packet): the server is first taken through one, as a controller starts (9 synchronization
 * packets, the initialization packet, 2 synchronization packets, one period apart, ending one
 * period before the first recorded packet). The init packet is the manual's figure 10.1 for
 * the recorded axis count (axes 1-10 on arm 1, 11-20 on arm 2, as the analysis takes them)
 * and the recorded period. Its replies are not compared. */
static void prime(rr_t *R, rr_sess_t *ss, const c4gh_an_exchange_t *x)
{
    static uint8_t out[C4G_INIT_SIZE + 64U];
    uint8_t pkt[C4G_INIT_SIZE];
    c4g_init_t init;
    c4g_endpoint_t from;
    const uint32_t n = (uint32_t)((x->ctrl_len - C4G_HEADER_SIZE) / C4G_AXIS_SIZE);
    uint64_t per_ns = 2000000U;
    uint32_t i;
    int32_t k;
    if (x->next_ns > x->ctrl_ns && x->next_ns - x->ctrl_ns < 1500000) {
        per_ns = 1000000U;
    }
    if (c4gsim_fig10_1(&init) != C4G_OK) {
        return;
    }
    init.n_ax_open = (int32_t)n;
    init.period_ms = (int32_t)(per_ns / 1000000U);
    for (i = 0U; i < n && i < C4G_MAX_AXES; i++) {
        const uint32_t arm = i / C4G_AXES_PER_ARM, lax = i % C4G_AXES_PER_ARM, src = i % 6U;
        init.open_ax[arm][lax] = (int32_t)i;
        init.cal_data[arm][lax] = init.cal_data[0][src];
        init.az_lim[arm][lax] = init.az_lim[0][src];
        init.ax_info[arm][lax] = init.ax_info[0][src];
        init.tx_rate[arm][lax] = init.tx_rate[0][src];
        init.follow_error[arm][lax] = init.follow_error[0][src];
    }
    for (i = n; i < 6U; i++) {
        init.open_ax[0][i] = C4G_OPEN_AX_NONE;
    }
    if (!R->server_live || R->server_stopped) {
        if (server_start(R) != 0) {
            return;
        }
        g_srv.t0_ns = (uint64_t)x->ctrl_ns - 12U * per_ns;
    }
    endpoint_of(&x->s->ctrl, &from);
    for (k = 1; k <= 12; k++) {
        const uint64_t t = (uint64_t)x->ctrl_ns - (uint64_t)(13 - k) * per_ns;
        size_t len = C4G_CYCLIC_SIZE((size_t)n), olen = 0U;
        srv_verdict_t v;
        memset(pkt, 0, sizeof pkt);
        if (k == C4G_INIT_NUM) {
            if (c4g_init_encode(&init, pkt, sizeof pkt, &len) != C4G_OK) {
                return;
            }
        } else {
            pkt[0] = (uint8_t)k;
        }
        memset(&v, 0, sizeof v);
        if (srv_process(&g_srv, pkt, len, &from, t, out, sizeof out, &olen, &v) == C4G_OK && v.send) {
            srv_sent(&g_srv, t);
        }
    }
    ss->primed = 1;
    ss->primed_axes = n;
    ss->primed_period_ms = (unsigned)(per_ns / 1000000U);
}

static void hold(rr_t *R, const rr_pkt_t *p)
{
    R->held = *p;
    memcpy(R->held_ctrl, p->ctrl, p->ctrl_len);
    R->held.ctrl = R->held_ctrl;
    if (p->rec != NULL) {
        memcpy(R->held_rec, p->rec, p->rec_len);
        R->held.rec = R->held_rec;
    }
    R->have_held = 1;
}

/* The pause is over: the newest packet queued during it is answered. */
static void release(rr_t *R)
{
    R->frozen = 0;
    if (R->have_held) {
        R->have_held = 0;
        feed(R, &R->held, (uint64_t)R->freeze_until, 1);
    }
}

/* A packet queued during the pause and superseded by a newer one: dropped unanswered. */
static void drop_held(rr_t *R)
{
    rr_sess_t *ss = sess_of(R, R->held.s);
    c4g_endpoint_t from;
    endpoint_of(&R->held.s->ctrl, &from);
    srv_drop(&g_srv, R->held.ctrl, R->held.ctrl_len, &from, (uint64_t)R->freeze_until);
    if (ss != NULL) {
        ss->held_dropped++;
        if (R->held.kind >= C4G_PKT_SYNC && R->held.kind <= C4G_PKT_CYCLIC) {
            ss->fed[R->held.kind]++;
        }
    }
    compare(R, &R->held, NULL, 0U);
    R->have_held = 0;
}

static int selected(rr_t *R, const c4gh_an_exchange_t *x)
{
    if (R->only_session != 0U) {
        return x->s->id == R->only_session;
    }
    if (!R->have_ctrl) {
        R->have_ctrl = 1;
        R->ctrl = x->s->ctrl;
    }
    return x->s->ctrl.ip == R->ctrl.ip && x->s->ctrl.port == R->ctrl.port;
}

static void note_other(rr_t *R, unsigned id)
{
    unsigned i;
    R->other_ctrl_exchanges++;
    for (i = 0U; i < R->n_other; i++) {
        if (R->other_sessions[i] == id) {
            return;
        }
    }
    if (R->n_other < C4GH_AN_MAX_SESSIONS) {
        R->other_sessions[R->n_other++] = id;
    }
}

static void on_exchange(void *ctx, const c4gh_an_exchange_t *x)
{
    rr_t *R = ctx;
    rr_pkt_t p;
    if (!selected(R, x)) {
        note_other(R, x->s->id);
        return;
    }
    memset(&p, 0, sizeof p);
    p.session = x->s->id;
    p.s = x->s;
    p.kind = (int)x->kind;
    p.tick = x->tick;
    p.ctrl = x->ctrl;
    p.ctrl_len = x->ctrl_len;
    p.ctrl_frame = x->ctrl_frame;
    p.ctrl_ns = x->ctrl_ns;
    if (x->reply != NULL) {
        p.rec = x->reply;
        p.rec_len = x->reply_len;
        p.rec_ns = x->reply_ns;
    } else if (x->other != NULL) {
        p.rec = x->other;
        p.rec_len = x->other_len;
        p.rec_ns = x->other_ns;
    }
    if (!x->s->have_init && x->kind == C4G_PKT_CYCLIC && x->ctrl_len >= C4G_CYCLIC_SIZE(1U)) {
        rr_sess_t *ss = sess_of(R, x->s);
        if (ss != NULL && ss->fed[C4G_PKT_SYNC] + ss->fed[C4G_PKT_INIT] + ss->fed[C4G_PKT_CYCLIC] == 0U) {
            prime(R, ss, x);
        }
    }
    if (R->frozen && p.ctrl_ns < R->freeze_until) {
        if (R->have_held) {
            drop_held(R);
        }
        hold(R, &p);
        return;
    }
    if (R->frozen) {
        release(R);
    }
    feed(R, &p, (uint64_t)p.ctrl_ns, 0);
}

/* ---- reports -------------------------------------------------------------- */

static const char *ep_text(const c4gh_an_endpoint_t *e, char *buf, size_t cap)
{
    char ip[16];
    (void)snprintf(buf, cap, "%s:%u", c4gh_cap_ip_str(e->ip, ip), (unsigned)e->port);
    return buf;
}

static const char *behaviour_name(const rr_t *R)
{
    return (R->behaviour == RR_ECHO) ? "echo" : "server";
}

static void report_text(const rr_t *R, const char *path)
{
    unsigned i;
    int k;
    printf("%s: behaviour %s", path, behaviour_name(R));
    if (R->srv_argc > 0) {
        printf(", c4g-server options:");
        for (k = 0; k < R->srv_argc; k++) {
            printf(" %s", R->srv_argv[k]);
        }
    }
    printf("\n");
    for (i = 0U; i < R->n_sess; i++) {
        const rr_sess_t *s = &R->sess[i];
        char a[32], b[32];
        printf("session %u  controller %s  PC %s\n", s->id, ep_text(&s->ctrl, a, sizeof a),
               ep_text(&s->pc, b, sizeof b));
        printf("  fed %llu sync, %llu init, %llu cyclic packets", (unsigned long long)s->fed[C4G_PKT_SYNC],
               (unsigned long long)s->fed[C4G_PKT_INIT], (unsigned long long)s->fed[C4G_PKT_CYCLIC]);
        if (s->held_dropped > 0U) {
            printf(" (%llu dropped unanswered after an active-freezing pause)",
                   (unsigned long long)s->held_dropped);
        }
        printf("\n  replies: %llu compared, %llu equal, %llu divergent",
               (unsigned long long)s->compared, (unsigned long long)(s->compared - s->divergent),
               (unsigned long long)s->divergent);
        if (s->any_div) {
            printf(" (the first at tick %llu)", (unsigned long long)s->first_div_tick);
        }
        printf("\n");
        if (s->recorded_missing > 0U) {
            printf("  %llu controller packets have no reply in the capture\n",
                   (unsigned long long)s->recorded_missing);
        }
        if (s->timing_only > 0U) {
            printf("  timing: %llu recorded replies came after the controller's next packet, the server's "
                   "in time with the same content (not divergences)\n", (unsigned long long)s->timing_only);
        }
        if (s->primed) {
            printf("  no start-up in the capture: the server was first taken through one (9 sync, the "
                   "figure 10.1 init packet for %u axes, %u ms, 2 sync), not compared\n", s->primed_axes,
                   s->primed_period_ms);
        }
    }
    if (R->server_starts > 1U) {
        printf("server runs: %llu (a new run where the recorded one would have stopped)\n",
               (unsigned long long)R->server_starts);
    }
    if (R->n_other > 0U) {
        printf("not rerun: %u session(s) of another controller (", R->n_other);
        for (i = 0U; i < R->n_other; i++) {
            printf("%s%u", (i > 0U) ? ", " : "", R->other_sessions[i]);
        }
        printf("): take one with --session N\n");
    }
    if (R->have_first) {
        printf("first divergence: ");
        print_div(stdout, &R->first);
        printf("divergences per field:\n");
        for (k = 0; k < (int)RR_F_COUNT; k++) {
            const rr_field_count_t *f = &R->fields[k];
            if (f->count == 0U) {
                continue;
            }
            printf("  %-7s %10llu  first: ", k_field_names[k], (unsigned long long)f->count);
            print_div(stdout, &f->first);
        }
    }
    if (R->divergent == 0U) {
        printf("verdict: 0 divergences in %llu replies: the server gives the recorded replies\n",
               (unsigned long long)R->compared);
    } else {
        printf("verdict: %llu of %llu replies diverge\n", (unsigned long long)R->divergent,
               (unsigned long long)R->compared);
    }
}

static json_t *div_json(const rr_div_t *d)
{
    json_t *o = json_pack("{s:i, s:s, s:I, s:i, s:I, s:f, s:s, s:s, s:s}", "session", (json_int_t)d->session,
                          "packet", kind_name(d->kind), "tick", (json_int_t)d->tick, "num", (json_int_t)d->num, "frame", (json_int_t)d->frame,
                          "time", d->t_s, "field", k_field_names[d->field], "recorded", d->recorded,
                          "produced", d->produced);
    if (o == NULL) {
        return NULL;
    }
    if (d->open > 0) {
        (void)json_object_set_new(o, "open", json_integer(d->open));
        if (d->arm > 0) {
            (void)json_object_set_new(o, "arm", json_integer(d->arm));
            (void)json_object_set_new(o, "axis", json_integer(d->logical));
        }
    }
    if (d->field == RR_F_SYNC || d->field == RR_F_INIT) {
        (void)json_object_set_new(o, "word", json_integer((json_int_t)d->word));
    }
    return o;
}

static int report_json(const rr_t *R, const char *path)
{
    json_t *root = json_object(), *sessions = json_array(), *fields = json_object(), *opts = json_array();
    unsigned i;
    int k, rc;
    char a[32], b[32];
    if (root == NULL || sessions == NULL || fields == NULL || opts == NULL) {
        return -1;
    }
    for (k = 0; k < R->srv_argc; k++) {
        (void)json_array_append_new(opts, json_string(R->srv_argv[k]));
    }
    for (i = 0U; i < R->n_sess; i++) {
        const rr_sess_t *s = &R->sess[i];
        (void)json_array_append_new(
            sessions,
            json_pack("{s:i, s:s, s:s, s:{s:I, s:I, s:I}, s:I, s:I, s:I, s:I, s:I}", "id", (json_int_t)s->id,
                      "controller", ep_text(&s->ctrl, a, sizeof a), "pc", ep_text(&s->pc, b, sizeof b), "fed",
                      "sync", (json_int_t)s->fed[C4G_PKT_SYNC], "init", (json_int_t)s->fed[C4G_PKT_INIT], "cyclic",
                      (json_int_t)s->fed[C4G_PKT_CYCLIC], "compared", (json_int_t)s->compared, "equal",
                      (json_int_t)(s->compared - s->divergent), "divergent", (json_int_t)s->divergent,
                      "recorded_missing", (json_int_t)s->recorded_missing, "dropped_after_pause",
                      (json_int_t)s->held_dropped));
        (void)json_object_set_new(json_array_get(sessions, json_array_size(sessions) - 1U), "timing_only",
                                  json_integer((json_int_t)s->timing_only));
        (void)json_object_set_new(json_array_get(sessions, json_array_size(sessions) - 1U), "synthetic_startup",
                                  json_boolean(s->primed));
    }
    for (k = 0; k < (int)RR_F_COUNT; k++) {
        if (R->fields[k].count > 0U) {
            (void)json_object_set_new(fields, k_field_names[k],
                                      json_pack("{s:I, s:o}", "count", (json_int_t)R->fields[k].count,
                                                "first", div_json(&R->fields[k].first)));
        }
    }
    (void)json_object_set_new(root, "tool", json_string(RP_TOOL " rerun"));
    (void)json_object_set_new(root, "file", json_string(path));
    (void)json_object_set_new(root, "behaviour", json_string(behaviour_name(R)));
    (void)json_object_set_new(root, "server_options", opts);
    (void)json_object_set_new(root, "tolerance", json_real(R->tolerance));
    (void)json_object_set_new(root, "sessions", sessions);
    (void)json_object_set_new(root, "server_runs", json_integer((json_int_t)R->server_starts));
    (void)json_object_set_new(root, "sessions_not_rerun", json_integer((json_int_t)R->n_other));
    (void)json_object_set_new(root, "compared", json_integer((json_int_t)R->compared));
    (void)json_object_set_new(root, "divergent", json_integer((json_int_t)R->divergent));
    (void)json_object_set_new(root, "timing_only", json_integer((json_int_t)R->timing_only));
    (void)json_object_set_new(root, "first", R->have_first ? div_json(&R->first) : json_null());
    (void)json_object_set_new(root, "fields", fields);
    rc = json_dumpf(root, stdout, JSON_INDENT(2) | JSON_PRESERVE_ORDER);
    json_decref(root);
    fputc('\n', stdout);
    return rc;
}

/* ---- the command ---------------------------------------------------------- */

static int opt_behaviour(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rr_t *R = ctx;
    (void)row;
    if (strcmp(v, "server") == 0) {
        R->behaviour = RR_SERVER;
    } else if (strcmp(v, "echo") == 0) {
        R->behaviour = RR_ECHO;
    } else {
        (void)snprintf(why, whylen, "want server or echo");
        return -1;
    }
    return 0;
}

static int opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_port(&((rr_t *)ctx)->c, row, v, why, whylen);
}

static const char *const examples[] = {
    RP_TOOL " rerun fixtures/replay/mode4.pcap",
    RP_TOOL " rerun field.pcap -- --arm 1 --axes 1,2 --sine 0.2,0.5,2",
    RP_TOOL " rerun field.pcap -- --config my-server.ini",
    RP_TOOL " rerun --json field.pcap -- --gains 40,0.5 | jq '.fields'",
    RP_TOOL " rerun --behaviour echo --session 2 field.pcap",
    NULL};

static const char epilogue[] =
    "Everything after \"--\" is c4g-server's own options (--config INI, --arm N, --sine,\n"
    "--traj, --gains, --persist, --num-policy, ...), read by c4g-server's option table;\n"
    "socket, real-time and output options are accepted and have no effect. Behaviours:\n"
    "server (default) runs c4g-server's per-arm behaviours as configured; echo drives no\n"
    "axis (NUM, mode echo and the library's neutral reply only).\n"
    "Fields compared: reply (sent on one side only), length, sync and init words, num,\n"
    "infpar, cmd and per OPEN axis mode, d1..d5, ext1..ext3. A recorded reply that came\n"
    "after the next controller packet is compared with the one produced: equal content is\n"
    "a timing difference (counted apart), not a divergence. A capture that starts after\n"
    "the init packet is rerun after a synthetic start-up (figure 10.1 init, its axis count).\n"
    "Exit status: 0 the replies produced equal the recorded ones, 1 some diverge, 2 bad\n"
    "usage or an unreadable capture.\n";

static int setup_server(rr_t *R, const c4gh_cli_spec_t *spec)
{
    static char *argv2[RR_MAX_SERVER_ARGS + 2];
    char err[700];
    int k;
    unsigned arm;
    const char *tool = RP_TOOL " rerun (c4g-server options)";
    srv_config_default(&R->cfg);
    if (R->srv_argc > RR_MAX_SERVER_ARGS) {
        c4gh_cli_error(spec, "at most %d c4g-server options", RR_MAX_SERVER_ARGS);
        return C4GH_CLI_EXIT_USAGE;
    }
    argv2[0] = (char *)tool;
    for (k = 0; k < R->srv_argc; k++) {
        argv2[k + 1] = R->srv_argv[k];
    }
    argv2[R->srv_argc + 1] = NULL;
    switch (srv_config_cli(&R->cfg, tool, NULL, R->srv_argc + 1, argv2)) {
    case C4GH_CLI_RUN:
        break;
    case C4GH_CLI_DONE:
        return -1;
    default:
        return C4GH_CLI_EXIT_USAGE;
    }
    if (srv_load_files(&R->cfg, err, sizeof err) != 0) {
        c4gh_cli_error(spec, "%s", err);
        return C4GH_CLI_EXIT_USAGE;
    }
    /* what only the live server does: none of it changes a reply */
    R->cfg.pcap_path[0] = '\0';
    R->cfg.moni_path[0] = '\0';
    R->cfg.json_path[0] = '\0';
    R->cfg.log_path[0] = '\0';
    R->cfg.quiet = 1;
    R->cfg.verbose = 0;
    (void)snprintf(R->cfg.ctrl_addr, sizeof R->cfg.ctrl_addr, "any");
    if (R->behaviour == RR_ECHO) {
        for (arm = 0U; arm < C4G_ARMS; arm++) {
            R->cfg.arm[arm].axes = 0U;
        }
    }
    return 0;
}

int rp_cmd_rerun(int argc, char **argv)
{
    rr_t *R = &g_rr;
    c4gh_cli_spec_t spec;
    c4gh_an_t a;
    rp_file_t file;
    int first = 0, rc;
    c4gh_cli_result_t r;
    const c4gh_cli_opt_t rows[] = {
        {"behaviour", 'b', C4GH_CLI_CALL, "NAME", "server (c4g-server's behaviours, default) or echo", NULL, 0, 0, 0,
         opt_behaviour, 0},
        {"session", 's', C4GH_CLI_UINT, "N", "only session N (default: every session of the first controller)",
         &R->only_session, 0, 1, C4GH_AN_MAX_SESSIONS, NULL, 0},
        {"tolerance", 't', C4GH_CLI_DOUBLE, "X", "float fields within X count as equal (default 0: bit-exact)",
         &R->tolerance, 0, 0, 1e9, NULL, 0},
        {"list", 'l', C4GH_CLI_INT, "N", "print the first N divergences, one per line", &R->max_lines, 0, 0, 1e9,
         NULL, 0},
        {"json", 'j', C4GH_CLI_FLAG, NULL, "the report as JSON on stdout", &R->c.json, 0, 0, 0, NULL, 0},
        {"port", 'p', C4GH_CLI_CALL, "LIST", "PC ports of C4G Open flows (default 1000,1001)", NULL, 0, 0, 0,
         opt_port, 0},
        {"no-progress", 0, C4GH_CLI_FLAG, NULL, "no progress bar on a terminal", &R->c.no_progress, 0, 0, 0, NULL, 0},
    };
    memset(R, 0, sizeof *R);
    rp_common_default(&R->c);
    memset(&spec, 0, sizeof spec);
    spec.tool = RP_TOOL;
    spec.command = "rerun";
    spec.usage = "Usage: " RP_TOOL " rerun [OPTIONS] FILE [-- C4G-SERVER-OPTIONS]\n"
                 "Feed the recorded controller packets through c4g-server's own core at top speed,\n"
                 "with their recorded times, and compare every reply produced with the recorded one,\n"
                 "field by field: the first divergence (tick, arm, axis, field, recorded vs produced)\n"
                 "and the count per field.\n";
    spec.opts = rows;
    spec.n_opts = sizeof rows / sizeof rows[0];
    spec.examples = examples;
    spec.epilogue = epilogue;
    spec.operands_min = 1;
    spec.operands_max = -1;
    spec.permute = 1;
    r = c4gh_cli_parse(&spec, R, argc, argv, &first);
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    R->srv_argv = argv + first + 1;
    R->srv_argc = argc - first - 1;
    rc = setup_server(R, &spec);
    if (rc != 0) {
        return (rc < 0) ? C4GH_CLI_EXIT_OK : rc;
    }
    R->c.an.on_exchange = on_exchange;
    R->c.an.on_late = on_late;
    R->c.an.ctx = R;
    if (c4gh_an_init(&a, &R->c.an) != 0) {
        fprintf(stderr, RP_TOOL ": out of memory\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    rc = rp_read(&a, argv[first], &file, !R->c.no_progress);
    if (R->frozen) {
        release(R);
    }
    pending_flush(R);
    c4gh_an_free(&a);
    if (rc == 2) {
        return RP_EXIT_UNREADABLE;
    }
    if (R->init_error) {
        fprintf(stderr, RP_TOOL ": rerun: %s\n", R->init_why);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (R->compared == 0U) {
        fprintf(stderr, RP_TOOL ": %s: no controller packet to rerun%s\n", argv[first],
                (R->only_session != 0U) ? " in that session" : "");
        return RP_EXIT_UNREADABLE;
    }
    if (R->c.json ? report_json(R, argv[first]) != 0 : (report_text(R, argv[first]), 0)) {
        fprintf(stderr, RP_TOOL ": writing the report failed\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (fflush(stdout) != 0) {
        fprintf(stderr, RP_TOOL ": writing the report failed\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (rc == 1) {
        return RP_EXIT_UNREADABLE;
    }
    return (R->divergent > 0U) ? RP_EXIT_FINDINGS : C4GH_CLI_EXIT_OK;
}
