/* SPDX-License-Identifier: MIT */
/* Capture analysis: see analyze.h. */
#include "c4gh_analyze.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define AN_KIND_NAME(id, name, text) name,
#define AN_KIND_TEXT(id, name, text) text,
static const char *const kind_names[AN_K_COUNT] = {C4GH_AN_KINDS(AN_KIND_NAME)};
static const char *const kind_texts[AN_K_COUNT] = {C4GH_AN_KINDS(AN_KIND_TEXT)};

const char *c4gh_an_kind_name(c4gh_an_kind_t k) { return (k < AN_K_COUNT) ? kind_names[k] : "?"; }
const char *c4gh_an_kind_text(c4gh_an_kind_t k) { return (k < AN_K_COUNT) ? kind_texts[k] : "?"; }

int c4gh_an_kind_find(const char *name)
{
    unsigned k;
    for (k = 0U; k < (unsigned)AN_K_COUNT; k++) {
        if (strcmp(kind_names[k], name) == 0) {
            return (int)k;
        }
    }
    return -1;
}

/* A datagram held while its flow's direction is undecided. */
struct an_held {
    c4gh_cap_pkt_t p;
    uint8_t data[C4G_INIT_SIZE + 4U];
    int used;
};
typedef struct an_held an_held_t;

struct an_flow {
    c4gh_an_endpoint_t a, b;   /* a: the first sender seen */
    int ctrl_is_a;        /* 1, 0, or -1 undecided */
    int sess;             /* current session index, -1 none */
    an_held_t held[C4GH_AN_PENDING];
    unsigned n_held;
};

void c4gh_an_options_default(c4gh_an_options_t *o)
{
    memset(o, 0, sizeof *o);
    o->ports[0] = 1000U;
    o->ports[1] = 1001U;
    o->n_ports = 2U;
    o->t_cycle1_ns = 500000U;
    o->num_policy = C4G_NUM_EITHER;
}

int c4gh_an_init(c4gh_an_t *a, const c4gh_an_options_t *o)
{
    memset(a, 0, sizeof *a);
    a->opt = *o;
    a->sess = calloc(C4GH_AN_MAX_SESSIONS, sizeof *a->sess);
    a->flows = calloc(C4GH_AN_MAX_FLOWS, sizeof *a->flows);
    a->recent = calloc(C4GH_AN_RECENT, sizeof *a->recent);
    if (a->sess == NULL || a->flows == NULL || a->recent == NULL) {
        c4gh_an_free(a);
        return -1;
    }
    return 0;
}

void c4gh_an_free(c4gh_an_t *a)
{
    free(a->sess);
    free(a->flows);
    free(a->recent);
    a->sess = NULL;
    a->flows = NULL;
    a->recent = NULL;
}

/* ---- helpers ------------------------------------------------------------- */

/* The shape of a datagram, by the library's classifier. */
static c4g_peek_t peek(const uint8_t *d, size_t len)
{
    c4g_peek_t k;
    if (c4g_peek(d, len, false, &k) != C4G_OK) {
        k.kind = C4G_PKT_FOREIGN; /* no bytes */
        k.num = -1;
        k.n_axes = 0U;
    }
    return k;
}

static int is_cyclic_size(const uint8_t *d, size_t len)
{
    return peek(d, len).kind == C4G_PKT_CYCLIC;
}

/* An initialization packet (NUM 10) or its echo (11). */
static int looks_init(const uint8_t *d, size_t len)
{
    const c4g_peek_t k = peek(d, len);
    return k.kind == C4G_PKT_INIT && (k.num == C4G_INIT_NUM || k.num == C4G_INIT_NUM + 1);
}

static int zero_body(const uint8_t *d, size_t len)
{
    size_t i;
    for (i = 4U; i < len; i++) {
        if (d[i] != 0U) {
            return 0;
        }
    }
    return 1;
}

static int port_listed(const c4gh_an_t *a, uint16_t port)
{
    unsigned i;
    for (i = 0U; i < a->opt.n_ports; i++) {
        if (a->opt.ports[i] == port) {
            return 1;
        }
    }
    return 0;
}

static int64_t rel(const c4gh_an_session_t *s, int64_t t) { return t - s->first_ns; }

static void finding(c4gh_an_session_t *s, c4gh_an_kind_t k, const c4gh_cap_pkt_t *p, int32_t num, double value,
                    const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;
static void finding(c4gh_an_session_t *s, c4gh_an_kind_t k, const c4gh_cap_pkt_t *p, int32_t num, double value,
                    const char *fmt, ...)
{
    c4gh_an_finding_t *f = &s->f[k];
    if (f->count == 0U || value > f->worst) {
        f->worst = value;
    }
    if (f->count++ == 0U) {
        va_list ap;
        f->frame = p->frame;
        f->t_ns = rel(s, p->ts_ns);
        f->num = num;
        va_start(ap, fmt);
        (void)vsnprintf(f->first, sizeof f->first, fmt, ap);
        va_end(ap);
    }
}

static void event(c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, int32_t num, uint32_t arm, const char *what)
{
    c4gh_an_event_t *e;
    if (s->n_ev >= C4GH_AN_EVENTS) {
        s->ev_more++;
        return;
    }
    e = &s->ev[s->n_ev++];
    e->t_ns = rel(s, p->ts_ns);
    e->num = num;
    e->frame = p->frame;
    e->arm = arm;
    (void)snprintf(e->what, sizeof e->what, "%s", what);
}

/* ---- sessions ------------------------------------------------------------ */

static void cs_setup(c4gh_an_t *a, c4gh_an_session_t *s, uint32_t n_axes)
{
    c4g_ctrl_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.policy = a->opt.num_policy;
    cfg.n_axes = n_axes;
    cfg.t_cycle1_ns = a->opt.t_cycle1_ns;
    cfg.tol_ns = UINT64_MAX; /* the capture is the controller's clock: never late itself */
    cfg.max_miss = 10U;
    cfg.sync_before = 9U;
    cfg.sync_after = 2U;
    memset(&s->lat, 0, sizeof s->lat);
    (void)c4g_ctrl_init(&s->cs, &cfg); /* n_axes <= 20 and a known policy: always C4G_OK */
}

/* Arms from the packet length when the capture has no init packet: 10 axes per arm. */
static void synthetic_map(c4gh_an_session_t *s, uint32_t n)
{
    uint32_t i;
    memset(&s->map, 0xFF, sizeof s->map);
    s->map.n_axes = n;
    memset(s->map.n_axes_arm, 0, sizeof s->map.n_axes_arm);
    for (i = 0U; i < n; i++) {
        const uint32_t arm = i / C4G_AXES_PER_ARM, lax = i % C4G_AXES_PER_ARM;
        s->map.arm_of[i] = (uint8_t)arm;
        s->map.logical_of[i] = (uint8_t)lax;
        s->map.open_of[arm][lax] = (uint8_t)i;
        s->map.n_axes_arm[arm]++;
    }
    s->synthetic_map = 1;
}

static void arms_setup(c4gh_an_session_t *s)
{
    uint32_t arm;
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        (void)c4g_arm_sm_init(&s->sm[arm], s->map.n_axes_arm[arm]);
    }
}

static c4gh_an_session_t *session_new(c4gh_an_t *a, c4gh_an_flow_t *fl, const char *file, const c4gh_cap_pkt_t *p)
{
    c4gh_an_session_t *s;
    unsigned i;
    if (a->n_sess >= C4GH_AN_MAX_SESSIONS) {
        a->sess_dropped++;
        fl->sess = -1;
        return NULL;
    }
    s = &a->sess[a->n_sess];
    memset(s, 0, sizeof *s);
    /* numbered per file: the numbers summary, export and rerun give the file alone */
    s->id = 1U;
    for (i = 0U; i < a->n_sess; i++) {
        s->id += (a->sess[i].file == file) ? 1U : 0U;
    }
    s->file = file;
    s->ctrl = (fl->ctrl_is_a == 1) ? fl->a : fl->b;
    s->pc = (fl->ctrl_is_a == 1) ? fl->b : fl->a;
    s->first_ns = p->ts_ns;
    s->last_ns = p->ts_ns;
    s->first_frame = p->frame;
    s->end = "capture end";
    s->policy = -1;
    s->ctrl_num = -1;
    cs_setup(a, s, 0U);
    fl->sess = (int)a->n_sess;
    a->n_sess++;
    return s;
}

static void deliver(c4gh_an_t *a, c4gh_an_session_t *s, c4g_ctrl_verdict_t v, int64_t next_ns)
{
    c4gh_an_exchange_t x;
    if (a->opt.on_exchange == NULL) {
        return;
    }
    memset(&x, 0, sizeof x);
    x.s = s;
    x.kind = s->cs.out.kind;
    x.tick = s->ctrl_cyclic;
    x.ctrl = s->ctrl_raw;
    x.ctrl_len = s->ctrl_len;
    x.ctrl_frame = s->ctrl_frame;
    x.ctrl_ns = s->ctrl_ns;
    x.rx = (x.kind == C4G_PKT_CYCLIC && s->rx_ok) ? &s->rx : NULL;
    if (s->reply_len > 0U) {
        x.reply = s->reply_raw;
        x.reply_len = s->reply_len;
        x.reply_frame = s->reply_frame;
        x.reply_ns = s->reply_ns;
        x.tx = (x.kind == C4G_PKT_CYCLIC && s->cs.out.got) ? &s->cs.out.reply : NULL;
    }
    if (s->other_len > 0U) {
        x.other = s->other_raw;
        x.other_len = s->other_len;
        x.other_frame = s->other_frame;
        x.other_ns = s->other_ns;
    }
    x.verdict = v;
    x.late = s->cs.last_late;
    x.next_ns = next_ns;
    a->opt.on_exchange(a->opt.ctx, &x);
}

/* The outstanding packet is judged at the controller's next tick: @p t_next, or its own
 * time plus one period when the next packet came much later (lost ones in between). */
static void judge(c4gh_an_t *a, c4gh_an_session_t *s, int64_t t_next, const c4gh_cap_pkt_t *p, int at_end)
{
    c4g_ctrl_outstanding_t *o = &s->cs.out;
    uint64_t deadline = (uint64_t)t_next;
    c4g_ctrl_verdict_t v;
    if (!o->active) {
        return;
    }
    if (s->have_init) {
        const uint64_t per = (uint64_t)s->init.period_ms * 1000000U;
        if (deadline > o->sent_ns + per + per / 2U) {
            deadline = o->sent_ns + per;
        }
    }
    if (at_end && !o->got) {
        o->active = 0; /* the capture ended before its deadline was seen */
        deliver(a, s, C4G_CTRL_J_NONE, 0);
        return;
    }
    (void)c4g_ctrl_set_deadline(&s->cs, deadline); /* o->active: C4G_OK */
    (void)c4g_ctrl_judge(&s->cs, deadline, s->frozen != 0, &v);
    s->prev_in_time = (v == C4G_CTRL_J_OK && o->kind == C4G_PKT_CYCLIC);
    if (v == C4G_CTRL_J_OK) {
        c4gh_hist_add(&s->lat, (int64_t)s->cs.last_lat_ns);
        s->run = 0U;
        if (s->cs.last_late) {
            finding(s, AN_K_LATE, p, o->num, (double)(o->got_ns - o->sent_ns) * 1e-3,
                    "reply to NUM %d came %.0f us after the packet (T_CYCLE1 %.0f us)", (int)o->num,
                    (double)(o->got_ns - o->sent_ns) * 1e-3, (double)a->opt.t_cycle1_ns * 1e-3);
        }
        if (o->kind == C4G_PKT_CYCLIC && a->opt.max_step > 0.0) {
            s->last_tx = o->reply; /* only the step rule reads it: a 750-byte copy a tick */
            s->have_last_tx = 1;
        }
    } else if (v == C4G_CTRL_J_MISSING) {
        if (s->run++ == 0U) {
            s->run_start_ns = rel(s, (int64_t)o->sent_ns);
            s->run_start_num = o->num;
        }
        if (s->run > s->run_longest) {
            s->run_longest = s->run;
            s->longest_start_ns = s->run_start_ns;
            s->longest_start_num = s->run_start_num;
        }
        finding(s, AN_K_MISSING, p, o->num, 1.0, "no reply to NUM %d by the next tick%s", (int)o->num,
                s->cs.last_stale ? " (it came later)" : "");
        if (s->run == 10U) {
            finding(s, AN_K_MISSING_RUN, p, s->run_start_num, 10.0,
                    "10 replies missing in a row from NUM %d: the controller raises ERR_C4GOPEN_UDP",
                    (int)s->run_start_num);
        }
        if (s->run >= 10U && (double)s->run > s->f[AN_K_MISSING_RUN].worst) {
            s->f[AN_K_MISSING_RUN].worst = (double)s->run;
        }
    } else {
        /* not judged (frozen, or a packet whose reply is not checked) */
    }
    deliver(a, s, v, t_next);
}

/* ---- controller packets ------------------------------------------------- */

static int32_t arm_mode(const c4gh_an_session_t *s, const c4g_ctrl_packet_t *rx, uint32_t arm,
                        uint32_t *mixed, uint32_t *moving)
{
    int32_t best = 0, first = -1, last = 0;
    bool best_sp = c4g_mode_is_special(0), last_sp = best_sp;
    uint32_t i;
    *mixed = 0U;
    *moving = 0U;
    for (i = 0U; i < rx->n_axes; i++) {
        const int32_t m = rx->ax[i].mode;
        bool sp;
        if (s->map.arm_of[i] != arm) {
            continue;
        }
        if (first < 0) {
            first = m;
        } else if (m != first) {
            *mixed = 1U;
        }
        if (rx->ax[i].target_vel != 0.0f) {
            *moving = 1U;
        }
        if (m != last) { /* an arm's axes mostly share one mode: look it up once */
            last = m;
            last_sp = c4g_mode_is_special(m);
        }
        sp = last_sp;
        if (sp || (best < C4G_MODE_FREEZING_A && m != 0)) {
            if (!(best_sp && !sp)) {
                best = m;
                best_sp = sp;
            }
        }
    }
    return best;
}

static void timeline(c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, int32_t num, uint32_t arm, int32_t from,
                     int32_t to, uint32_t mixed)
{
    c4gh_an_transition_t *t;
    if (s->n_tl[arm] >= C4GH_AN_TIMELINE) {
        s->tl_more[arm]++;
        return;
    }
    t = &s->tl[arm][s->n_tl[arm]++];
    t->t_ns = rel(s, p->ts_ns);
    t->num = num;
    t->frame = p->frame;
    t->from = from;
    t->to = to;
    t->mixed = mixed;
}

static void arms_update(c4gh_an_session_t *s, const c4g_ctrl_packet_t *rx, const c4gh_cap_pkt_t *p)
{
    c4g_engine_config_t ecfg;
    uint32_t arm;
    (void)c4g_engine_config_default(&ecfg);
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        c4g_arm_sm_t *sm = &s->sm[arm];
        const int32_t before = sm->started ? sm->mode : -1;
        uint32_t mixed, moving, ev = 0U;
        int32_t m;
        if (s->map.n_axes_arm[arm] == 0U) {
            continue;
        }
        m = arm_mode(s, rx, arm, &mixed, &moving);
        if (c4g_arm_sm_update(sm, &ecfg, m, mixed, c4g_arm_byte(rx->infpar, arm), moving,
                              (uint64_t)p->ts_ns, &ev) != C4G_OK) {
            continue;
        }
        if (before != m) {
            timeline(s, p, rx->num, arm, before, m, mixed);
        }
        if ((ev & C4G_CEV_UNEXPECTED) != 0U) {
            finding(s, AN_K_TRANSITION, p, rx->num, 1.0, "arm %u: mode %d -> %d is not allowed",
                    (unsigned)arm + 1U, (int)before, (int)m);
        }
        if ((ev & C4G_CEV_DRIVE_ON) != 0U) {
            event(s, p, rx->num, arm, "drive on");
        }
        if ((ev & C4G_CEV_DRIVE_OFF) != 0U) {
            event(s, p, rx->num, arm, "drive off");
        }
        if ((ev & (C4G_CEV_FREEZE_P_IN | C4G_CEV_FREEZE_A)) != 0U) {
            s->frozen = 1;
        }
        if ((ev & (C4G_CEV_FREEZE_P_OUT | C4G_CEV_FREEZE_A_END)) != 0U) {
            s->frozen = 0;
        }
        if ((ev & C4G_CEV_END_COMM) != 0U) {
            s->end = "504 end of communication";
        }
        if ((ev & C4G_CEV_RESTART) != 0U) {
            s->end = "506 restart";
        }
    }
}

/* Following error in the controller's own data: |D1 - D3| over FollowError. */
static void ctrl_data(c4gh_an_session_t *s, const c4g_ctrl_packet_t *rx, const c4gh_cap_pkt_t *p)
{
    uint32_t i, seen = 0U;
    for (i = 0U; i < rx->n_axes; i++) {
        const uint32_t arm = s->map.arm_of[i], lax = s->map.logical_of[i];
        const c4g_ctrl_axis_t *x = &rx->ax[i];
        float thr, err;
        if (x->mode >= C4G_MODE_FREEZING_A && x->mode <= C4G_MODE_FOLLOW_ERROR) {
            const uint32_t bit = 1U << (uint32_t)(x->mode - C4G_MODE_FREEZING_A);
            if ((seen & bit) == 0U) {
                s->special_seen[x->mode - C4G_MODE_FREEZING_A]++; /* packets, not axes */
                seen |= bit;
            }
            continue;
        }
        if (!s->have_init || arm >= C4G_ARMS || lax >= C4G_AXES_PER_ARM) {
            continue;
        }
        thr = s->init.follow_error[arm][lax];
        if ((c4g_sf_follow_error(x->target_pos, x->actual_pos, thr, &err) & C4G_SF_FOLLOW_ERROR) != 0U) {
            finding(s, AN_K_FOLLOW_ERROR, p, rx->num, (double)err,
                    "axis %u (arm %u axis %u) NUM %d: |D1 - D3| = %.6g > FollowError %.6g turns",
                    (unsigned)i + 1U, (unsigned)arm + 1U, (unsigned)lax + 1U, (int)rx->num, (double)err,
                    (double)thr);
        }
    }
}

static void diag_finding(c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, const char *who, c4g_status_t st,
                         const c4g_diag_t *d)
{
    const int32_t num = (p->len >= 4U) ? c4g_le_i32(p->payload) : -1;
    c4gh_an_kind_t k = AN_K_MALFORMED;
    char axis[32] = "";
    if (st == C4G_ERR_NONFINITE) {
        k = AN_K_NONFINITE;
    } else if (st == C4G_ERR_MODE) {
        k = AN_K_UNKNOWN_MODE;
    } else {
        /* length, axes, NUM range: the datagram's layout */
    }
    if (d->axis >= 0) {
        (void)snprintf(axis, sizeof axis, " axis %d", (int)d->axis + 1);
    }
    finding(s, k, p, num, 1.0, "%s datagram of %u bytes, NUM %d: %s: %s%s at offset %u (value %lld)",
            who, (unsigned)p->len, (int)num, c4g_strerror(st), c4g_field_name(d->field), axis,
            (unsigned)d->offset, (long long)d->value);
}

static void new_controller_tick(c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, c4g_pkt_kind_t kind,
                                int check)
{
    const int32_t num = (p->len >= 4U) ? c4g_le_i32(p->payload) : -1;
    const size_t n = (p->len <= sizeof s->ctrl_raw) ? p->len : sizeof s->ctrl_raw;
    memcpy(s->ctrl_raw, p->payload, n);
    s->ctrl_len = n;
    s->ctrl_frame = p->frame;
    s->ctrl_ns = p->ts_ns;
    s->reply_len = 0U;
    s->other_len = 0U;
    (void)c4g_ctrl_emit(&s->cs, kind, num, p->payload, n, check != 0, (uint64_t)p->ts_ns);
}

static void ctrl_num_seq(c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, int32_t num, int *repeat)
{
    *repeat = 0;
    if (s->ctrl_num >= 0 && num >= 0) {
        const int32_t want = c4g_num_next(s->ctrl_num);
        if (num == s->ctrl_num || c4g_num_answers_recent(c4g_ctrl_policy(&s->cs), s->ctrl_num, num, C4G_CTRL_STALE_WINDOW)) {
            *repeat = 1;
            if (num == s->ctrl_num) {
                s->ctrl_dups++;
            } else {
                s->ctrl_older++;
            }
            finding(s, AN_K_REORDER, p, num, 1.0, "controller NUM %d after NUM %d (%s)", (int)num,
                    (int)s->ctrl_num, num == s->ctrl_num ? "repeated" : "out of order");
            return;
        }
        if (num != want) {
            const int32_t skipped = c4g_num_delta(want, num);
            s->ctrl_gaps++;
            s->ctrl_skipped += (uint64_t)skipped;
            finding(s, AN_K_CTRL_GAP, p, num, (double)skipped,
                    "controller NUM %d after NUM %d: %d packet(s) missing from the capture or never sent",
                    (int)num, (int)s->ctrl_num, (int)skipped);
        }
    }
    s->ctrl_num = num;
}

static void ctrl_cyclic(c4gh_an_t *a, c4gh_an_session_t *s, const c4gh_cap_pkt_t *p)
{
    c4g_diag_t d;
    c4g_status_t st;
    const int32_t num = c4g_le_i32(p->payload);
    int repeat;
    ctrl_num_seq(s, p, num, &repeat);
    if (repeat) {
        return; /* not a new tick: the outstanding packet stays */
    }
    /* over c4g-server's default loss timeout without a packet, not frozen: a pause of the
     * controller, or the capture's clock stepped forward (the NUMs tell if packets were lost) */
    if (s->ctrl_len > 0U && !s->frozen && p->ts_ns - s->ctrl_ns > 1000000000LL) {
        finding(s, AN_K_SILENCE, p, num, (double)(p->ts_ns - s->ctrl_ns) * 1e-9,
                "no controller packet for %.3f s before NUM %d (after NUM %d, frame %llu)",
                (double)(p->ts_ns - s->ctrl_ns) * 1e-9, (int)num,
                (s->ctrl_len >= 4U) ? (int)c4g_le_i32(s->ctrl_raw) : -1, (unsigned long long)s->ctrl_frame);
    }
    judge(a, s, p->ts_ns, p, 0);
    s->ctrl_cyclic++;
    s->cyclic_started = 1;
    if (s->n_axes == 0U) {
        s->n_axes = peek(p->payload, p->len).n_axes;
        synthetic_map(s, s->n_axes);
        arms_setup(s);
        s->cs.cfg.n_axes = s->n_axes;
    }
    memset(&d, 0, sizeof d);
    st = c4g_ctrl_decode(p->payload, p->len, s->n_axes, &s->rx, &d);
    s->rx_ok = (st == C4G_OK);
    if (st != C4G_OK) {
        diag_finding(s, p, "controller", st, &d);
    } else {
        arms_update(s, &s->rx, p);
        ctrl_data(s, &s->rx, p);
    }
    {
        int check = 1;
        uint32_t i;
        for (i = 0U; s->rx_ok && i < s->rx.n_axes; i++) {
            if (s->rx.ax[i].mode == C4G_MODE_EXIT_OPEN) {
                check = 0; /* the controller does not wait for the reply to 504 */
            }
        }
        new_controller_tick(s, p, C4G_PKT_CYCLIC, check);
    }
}

static void ctrl_init(c4gh_an_t *a, c4gh_an_session_t *s, const c4gh_cap_pkt_t *p)
{
    c4g_diag_t d;
    c4g_status_t st;
    judge(a, s, p->ts_ns, p, 0);
    s->ctrl_init++;
    memset(&d, 0, sizeof d);
    st = c4g_init_decode(p->payload, p->len, &s->init, &d);
    if (st != C4G_OK) {
        diag_finding(s, p, "controller init", st, &d);
    } else {
        s->have_init = 1;
        (void)c4g_axis_map_build(&s->init, &s->map, NULL);
        s->n_axes = s->map.n_axes;
        s->synthetic_map = 0;
        s->cs.cfg.n_axes = s->n_axes;
        arms_setup(s);
    }
    s->post_sync = s->cold ? 2U : 0U;
    s->ctrl_num = C4G_INIT_NUM;
    new_controller_tick(s, p, C4G_PKT_INIT, 1);
}

static void ctrl_sync(c4gh_an_t *a, c4gh_an_session_t *s, const c4gh_cap_pkt_t *p)
{
    judge(a, s, p->ts_ns, p, 0);
    s->ctrl_sync++;
    s->cold = 1;
    if (s->post_sync > 0U) {
        s->post_sync--;
    }
    s->ctrl_num = c4g_le_i32(p->payload);
    new_controller_tick(s, p, C4G_PKT_SYNC, 1);
}

static void session_close(c4gh_an_t *a, c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, const char *why)
{
    judge(a, s, s->last_ns, p, 1);
    if (why != NULL && strcmp(s->end, "capture end") == 0) {
        s->end = why;
    }
    (void)a;
}

static void from_controller(c4gh_an_t *a, c4gh_an_flow_t *fl, const char *file, const c4gh_cap_pkt_t *p)
{
    c4gh_an_session_t *s = (fl->sess >= 0) ? &a->sess[fl->sess] : NULL;
    const int init = (p->len == C4G_INIT_SIZE);
    const int cyc = is_cyclic_size(p->payload, p->len);
    const int sync = cyc && zero_body(p->payload, p->len);
    const int32_t num = (p->len >= 4U) ? c4g_le_i32(p->payload) : -1;
    /* the controller counts NUM 0..0x7FFF: anything else is not a packet of the session
     * (no tick, no restart, no NUM arithmetic on it) */
    const int num_bad = (init || cyc) && (num < 0 || num > 0x7FFF);
    if (s != NULL && !num_bad) {
        /* a new start: an init packet after the session had one (506 restart) or cyclic
         * packets, or a synchronization packet after cyclic ones (cold restart) */
        if (init && (s->have_init || s->cyclic_started)) {
            session_close(a, s, p, s->cyclic_started ? "506 restart" : "init repeated");
            s = NULL;
        } else if (sync && s->cyclic_started && c4g_le_i32(p->payload) <= 9) {
            session_close(a, s, p, "cold restart");
            s = NULL;
        } else {
            /* same session */
        }
    }
    if (s == NULL) {
        s = session_new(a, fl, file, p);
        if (s == NULL) {
            return;
        }
    }
    s->last_ns = p->ts_ns;
    s->last_frame = p->frame;
    if (num_bad) {
        s->ctrl_other++;
        finding(s, AN_K_MALFORMED, p, num, (double)p->len,
                "controller datagram of %u bytes: NUM %d outside 0..32767", (unsigned)p->len, (int)num);
    } else if (init) {
        ctrl_init(a, s, p);
    } else if (sync && (!s->cyclic_started || s->post_sync > 0U)) {
        ctrl_sync(a, s, p);
    } else if (cyc) {
        ctrl_cyclic(a, s, p);
    } else {
        s->ctrl_other++;
        finding(s, AN_K_MALFORMED, p, (p->len >= 4U) ? c4g_le_i32(p->payload) : -1, (double)p->len,
                "controller datagram of %u bytes: not 12 + 36 n, not 1200", (unsigned)p->len);
    }
}

/* ---- PC packets ---------------------------------------------------------- */

static void pc_requests(c4gh_an_session_t *s, const c4g_pc_packet_t *tx, const c4gh_cap_pkt_t *p)
{
    static const struct { int32_t mode; uint8_t bit; const char *what; } reqs[] = {
        {C4G_MODE_DRIVE_OFF, 1U, "PC requests 505 drive off"},
        {C4G_MODE_FOLLOW_ERROR, 2U, "PC requests 508 following error"},
        {C4G_MODE_FREEZING_A, 4U, "PC requests 500 active freezing"},
    };
    uint8_t now[C4G_ARMS] = {0, 0, 0, 0};
    uint32_t i, arm, r;
    for (i = 0U; i < tx->n_axes && i < s->rx.n_axes; i++) {
        arm = s->map.arm_of[i];
        for (r = 0U; r < 3U && arm < C4G_ARMS; r++) {
            if (tx->ax[i].mode == reqs[r].mode && s->rx.ax[i].mode != reqs[r].mode) {
                now[arm] |= reqs[r].bit;
            }
        }
    }
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        if (c4g_arm_byte(tx->infpar, arm) == C4G_EXIT_FROM_OPEN) {
            now[arm] |= 8U;
        }
        for (r = 0U; r < 3U; r++) {
            if ((now[arm] & reqs[r].bit) != 0U && (s->req[arm] & reqs[r].bit) == 0U) {
                event(s, p, tx->num, arm, reqs[r].what);
            }
        }
        if ((now[arm] & 8U) != 0U && (s->req[arm] & 8U) == 0U) {
            event(s, p, tx->num, arm, "PC requests EXIT_FROM_OPEN");
        }
        s->req[arm] = now[arm];
    }
}

/* What the controller would do with the reply's fields (the mode table's rules). */
static void pc_data(c4gh_an_t *a, c4gh_an_session_t *s, const c4g_pc_packet_t *tx, const c4gh_cap_pkt_t *p)
{
    uint32_t i;
    for (i = 0U; i < tx->n_axes && i < s->rx.n_axes; i++) {
        const uint32_t arm = s->map.arm_of[i], lax = s->map.logical_of[i];
        const c4g_pc_axis_t *o = &tx->ax[i];
        const c4g_ctrl_axis_t *r = &s->rx.ax[i];
        const uint32_t rules = c4g_mode_rules(o->mode);
        float az, fe, err;
        if (!s->have_init || arm >= C4G_ARMS || lax >= C4G_AXES_PER_ARM) {
            continue;
        }
        az = s->init.az_lim[arm][lax];
        fe = s->init.follow_error[arm][lax];
        if ((rules & C4G_MR_CUR) != 0U && fabsf(o->current_add) > az) {
            finding(s, AN_K_CURRENT, p, tx->num, (double)fabsf(o->current_add),
                    "reply NUM %d axis %u (arm %u axis %u) mode %d: current D5 %.6g A over AzLim %.6g A",
                    (int)tx->num, (unsigned)i + 1U, (unsigned)arm + 1U, (unsigned)lax + 1U,
                    (int)o->mode, (double)o->current_add, (double)az);
        }
        if ((rules & C4G_MR_DCUR) != 0U && fabsf(r->current_ref + o->current_add) > az &&
            fabsf(r->current_ref + o->current_add) > fabsf(r->current_ref)) {
            finding(s, AN_K_CURRENT, p, tx->num, (double)fabsf(r->current_ref + o->current_add),
                    "reply NUM %d axis %u (arm %u axis %u) mode 9: controller current %.6g + D5 %.6g A "
                    "over AzLim %.6g A", (int)tx->num, (unsigned)i + 1U, (unsigned)arm + 1U,
                    (unsigned)lax + 1U, (double)r->current_ref, (double)o->current_add, (double)az);
        }
        if ((rules & C4G_MR_ABS) != 0U &&
            (c4g_sf_follow_error(o->target_pos, r->actual_pos, fe, &err) & C4G_SF_FOLLOW_ERROR) != 0U) {
            finding(s, AN_K_POS_STEP, p, tx->num, (double)err,
                    "reply NUM %d axis %u (arm %u axis %u) mode %d: target D1 %.6g is %.6g turns from the "
                    "actual position, over FollowError %.6g", (int)tx->num, (unsigned)i + 1U,
                    (unsigned)arm + 1U, (unsigned)lax + 1U, (int)o->mode, (double)o->target_pos,
                    (double)err, (double)fe);
        }
        if ((rules & C4G_MR_ABS) != 0U && a->opt.max_step > 0.0 && s->have_last_tx &&
            s->last_tx.ax[i].mode == o->mode &&
            fabs((double)o->target_pos - (double)s->last_tx.ax[i].target_pos) > a->opt.max_step) {
            const double step = fabs((double)o->target_pos - (double)s->last_tx.ax[i].target_pos);
            finding(s, AN_K_POS_STEP, p, tx->num, step,
                    "reply NUM %d axis %u mode %d: target D1 moved %.6g turns in one tick (--max-step %.6g)",
                    (int)tx->num, (unsigned)i + 1U, (int)o->mode, step, a->opt.max_step);
        }
    }
}

/* The reply to 504 is not checked by the controller (c4g_ctrl_reply: unexpected), yet the PC sends
 * it: the tick's reply if its NUM answers under the policy and it decodes, so the export
 * shows it like any other (the counters do not change). */
static void keep_unchecked_reply(c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, int32_t num)
{
    c4g_pc_packet_t pkt;
    if (s->reply_len != 0U || p->len > sizeof s->reply_raw ||
        !c4g_num_accepts(c4g_ctrl_policy(&s->cs), s->cs.out.num, num) ||
        c4g_pc_decode(p->payload, p->len, s->cs.cfg.n_axes, &pkt, NULL) != C4G_OK) {
        return;
    }
    memcpy(s->reply_raw, p->payload, p->len);
    s->reply_len = p->len;
    s->reply_ns = p->ts_ns;
    s->reply_frame = p->frame;
    if (s->other_len != 0U && s->other_frame == p->frame) {
        s->other_len = 0U; /* a reply, not another datagram */
    }
}

/* A cyclic reply whose NUM answers the packet after the outstanding one under the policy in
 * force (either one while it is unknown). */
static int answers_unseen(const c4gh_an_session_t *s, int32_t num)
{
    if (s->cs.out.kind != C4G_PKT_CYCLIC || !s->cs.out.active) {
        return 0;
    }
    return c4g_num_accepts(c4g_ctrl_policy(&s->cs), c4g_num_next(s->cs.out.num), num);
}

/* Policy "either" without an init echo in time (a late echo, a capture started mid-session):
 * learnt from the cyclic replies, so that a late plus-one reply is not taken for the echo of
 * the next packet. NUM + 1 can only be plus-one; NUM itself is an echo only when the packet
 * before had its reply in time (else it may be that packet's late plus-one reply). */
static void learn_policy(const c4gh_an_t *a, c4gh_an_session_t *s, int32_t num)
{
    const c4g_ctrl_outstanding_t *o = &s->cs.out;
    if (a->opt.num_policy != C4G_NUM_EITHER || s->cs.detected >= 0 || !o->active || !o->check ||
        o->kind != C4G_PKT_CYCLIC || o->got) {
        return;
    }
    if (num == c4g_reply_num(o->num, C4G_NUM_PLUS_ONE) && num != o->num) {
        s->cs.detected = C4G_NUM_PLUS_ONE;
    } else if (num == o->num && s->prev_in_time) {
        s->cs.detected = C4G_NUM_ECHO;
    } else {
        return;
    }
    s->policy = s->cs.detected;
    s->policy_from_cyclic = 1;
}

/* A reply the conversation accepted: kept, counted by kind, its requests and data judged. */
static void pc_accepted(c4gh_an_t *a, c4gh_an_session_t *s, const c4gh_cap_pkt_t *p, int32_t num)
{
    const c4g_ctrl_outstanding_t *o = &s->cs.out;
    const size_t n = (p->len <= sizeof s->reply_raw) ? p->len : sizeof s->reply_raw;
    memcpy(s->reply_raw, p->payload, n);
    s->reply_len = n;
    s->reply_ns = p->ts_ns;
    s->reply_frame = p->frame;
    if (o->kind == C4G_PKT_SYNC) {
        s->pc_sync++;
    } else if (o->kind == C4G_PKT_INIT) {
        s->pc_init++;
        s->policy = s->cs.detected;
    } else {
        s->pc_cyclic++;
        if (num == o->num) {
            s->policy_echo++;
        } else {
            s->policy_plus++;
        }
        if (s->rx_ok) {
            pc_requests(s, &o->reply, p);
            pc_data(a, s, &o->reply, p);
        }
    }
}

static void from_pc(c4gh_an_t *a, c4gh_an_flow_t *fl, const char *file, const c4gh_cap_pkt_t *p)
{
    c4gh_an_session_t *s = (fl->sess >= 0) ? &a->sess[fl->sess] : NULL;
    c4g_ctrl_rx_t r;
    const int32_t num = (p->len >= 4U) ? c4g_le_i32(p->payload) : -1;
    if (s == NULL) {
        s = session_new(a, fl, file, p);
        if (s == NULL) {
            return;
        }
    }
    s->last_ns = p->ts_ns;
    s->last_frame = p->frame;
    learn_policy(a, s, num);
    (void)c4g_ctrl_reply(&s->cs, p->payload, p->len, (uint64_t)p->ts_ns, &r); /* never NULL */
    if (r != C4G_CTRL_RX_ACCEPTED && r != C4G_CTRL_RX_STALE && r != C4G_CTRL_RX_DUPLICATE && s->reply_len == 0U &&
        s->other_len == 0U && p->len > 0U) {
        const size_t n = (p->len <= sizeof s->other_raw) ? p->len : sizeof s->other_raw;
        memcpy(s->other_raw, p->payload, n);
        s->other_len = n;
        s->other_ns = p->ts_ns;
        s->other_frame = p->frame;
    }
    switch (r) {
    case C4G_CTRL_RX_ACCEPTED:
        pc_accepted(a, s, p, num);
        break;
    case C4G_CTRL_RX_WRONG_NUM:
        s->pc_other++;
        if (looks_init(p->payload, p->len) && num == C4G_INIT_NUM + 1 && s->cs.out.kind != C4G_PKT_INIT) {
            finding(s, AN_K_CTRL_GAP, p, num, 1.0,
                    "an initialization echo (NUM %d) with no initialization packet before it: the "
                    "controller's packet is missing from the capture", (int)num);
            break;
        }
        if (answers_unseen(s, num)) {
            /* the reply to the controller's next packet, which the capture lost (not the
             * wire: the PC answered it): the ctrl-gap at the next packet explains it */
            s->pc_unseen++;
            if (s->cs.n.wrong_num > 0U) {
                s->cs.n.wrong_num--; /* a right reply, to a packet the capture does not show */
            }
            break;
        }
        finding(s, AN_K_NUM, p, num, 1.0, "reply NUM %d to controller NUM %d breaks the NUM policy",
                (int)num, (int)s->cs.out.num);
        break;
    case C4G_CTRL_RX_DUPLICATE:
        s->pc_other++;
        finding(s, AN_K_DUPLICATE, p, num, 1.0, "a second reply (NUM %d) to controller NUM %d",
                (int)num, (int)s->cs.out.num);
        break;
    case C4G_CTRL_RX_STALE:
        s->pc_other++; /* counted at the judgement of its packet (missing, it came later) */
        if (a->opt.on_late != NULL) {
            a->opt.on_late(a->opt.ctx, s, p->payload, p->len, p->ts_ns, p->frame);
        }
        break;
    case C4G_CTRL_RX_BAD_DECODE:
        s->pc_other++;
        diag_finding(s, p, "PC", s->cs.last_diag.status, &s->cs.last_diag);
        break;
    case C4G_CTRL_RX_UNEXPECTED:
        if (s->cs.out.active && !s->cs.out.check) {
            s->pc_cyclic++; /* the reply to 504, which the controller does not check */
            keep_unchecked_reply(s, p, num);
            break;
        }
        s->pc_other++;
        {
            finding(s, AN_K_MALFORMED, p, num, (double)p->len,
                    "PC datagram of %u bytes (NUM %d) with no controller packet awaiting a reply",
                    (unsigned)p->len, (int)num);
        }
        break;
    default: /* short, bad length, bad init echo */
        s->pc_other++;
        finding(s, AN_K_MALFORMED, p, num, (double)p->len,
                "PC datagram of %u bytes (NUM %d) is not a valid reply to a %s packet", (unsigned)p->len,
                (int)num, s->cs.out.kind == C4G_PKT_SYNC ? "sync" : (s->cs.out.kind == C4G_PKT_INIT ? "init" : "cyclic"));
        break;
    }
}

/* ---- flows ---------------------------------------------------------------- */

static int same_ep(const c4gh_an_endpoint_t *e, uint32_t ip, uint16_t port)
{
    return e->ip == ip && e->port == port;
}

static c4gh_an_flow_t *flow_find(c4gh_an_t *a, const c4gh_cap_pkt_t *p, int *from_a)
{
    unsigned i;
    for (i = 0U; i < a->n_flows; i++) {
        c4gh_an_flow_t *f = &a->flows[i];
        if (same_ep(&f->a, p->src_ip, p->src_port) && same_ep(&f->b, p->dst_ip, p->dst_port)) {
            *from_a = 1;
            return f;
        }
        if (same_ep(&f->b, p->src_ip, p->src_port) && same_ep(&f->a, p->dst_ip, p->dst_port)) {
            *from_a = 0;
            return f;
        }
    }
    return NULL;
}

static void dispatch(c4gh_an_t *a, c4gh_an_flow_t *fl, const char *file, const c4gh_cap_pkt_t *p, int from_a)
{
    if ((from_a != 0) == (fl->ctrl_is_a == 1)) {
        from_controller(a, fl, file, p);
    } else {
        from_pc(a, fl, file, p);
    }
    if (a->step_pending && fl->sess >= 0) {
        c4gh_an_session_t *s = &a->sess[fl->sess];
        c4gh_cap_pkt_t q = *p;
        a->step_pending = 0;
        q.frame = a->step_frame;
        finding(s, AN_K_CLOCK_STEP, &q, (p->len >= 4U) ? c4g_le_i32(p->payload) : -1,
                (double)a->step_ns * 1e-9,
                "frame %llu is stamped %.6f s before the frame ahead of it (the capture's clock "
                "went back): analysed in capture order, its time and every later one moved %.6f s "
                "on", (unsigned long long)a->step_frame, (double)a->step_ns * 1e-9,
                (double)a->step_ns * 1e-9);
    }
}

/* Median (lower) of up to C4GH_AN_PENDING values. */
static int64_t median(int64_t *v, unsigned n)
{
    unsigned i, j;
    for (i = 1U; i < n; i++) {
        const int64_t x = v[i];
        for (j = i; j > 0U && v[j - 1U] > x; j--) {
            v[j] = v[j - 1U];
        }
        v[j] = x;
    }
    return v[(n - 1U) / 2U];
}

/* Who is the controller, from the held datagrams: 1 (a), 0 (b), -1 not yet. @p final:
 * the file ended or the buffer is full, so decide with what there is. */
static int decide(const c4gh_an_t *a, const c4gh_an_flow_t *fl, int final)
{
    int64_t gap[2][C4GH_AN_PENDING];
    unsigned ng[2] = {0U, 0U}, i;
    int64_t last[2] = {-1, -1};
    int pa, pb;
    for (i = 0U; i < fl->n_held; i++) {
        const an_held_t *h = &fl->held[i];
        const int side = same_ep(&fl->a, h->p.src_ip, h->p.src_port) ? 0 : 1;
        /* the initialization packet (NUM 10) comes from the controller; its plus-one echo
         * (NUM 11) from the PC */
        if (looks_init(h->data, h->p.len)) {
            const int from_ctrl = (c4g_le_i32(h->data) == C4G_INIT_NUM);
            return (side == 0) == from_ctrl ? 1 : 0;
        }
        /* a 732-byte answer to a shorter cyclic-shaped packet is the PC's sync reply */
        if (h->p.len == C4G_SYNC_REPLY_SIZE && i > 0U && last[1 - side] >= 0 &&
            fl->held[i - 1U].p.len < C4G_SYNC_REPLY_SIZE && is_cyclic_size(fl->held[i - 1U].data, fl->held[i - 1U].p.len)) {
            return side == 0 ? 0 : 1;
        }
        if (last[1 - side] >= 0) {
            gap[side][ng[side]++] = h->p.ts_ns - last[1 - side];
        }
        last[side] = h->p.ts_ns;
    }
    if (!final) {
        return -1;
    }
    /* cyclic phase: the PC answers a fraction of a period after the controller's packet,
     * the controller's next packet comes the rest of the period after the reply */
    if (ng[0] >= 2U && ng[1] >= 2U) {
        const int64_t m0 = median(gap[0], ng[0]), m1 = median(gap[1], ng[1]);
        if (m0 != m1) {
            return (m0 < m1) ? 0 : 1;
        }
    }
    /* one direction only, or no telling: the PC is the side on a C4G Open port */
    pa = port_listed(a, fl->a.port);
    pb = port_listed(a, fl->b.port);
    if (pa != pb) {
        return pa ? 0 : 1;
    }
    return 1; /* the first sender */
}

static void release(c4gh_an_t *a, c4gh_an_flow_t *fl, const char *file, int ctrl_is_a)
{
    unsigned i;
    fl->ctrl_is_a = ctrl_is_a;
    for (i = 0U; i < fl->n_held; i++) {
        c4gh_cap_pkt_t q = fl->held[i].p;
        q.payload = fl->held[i].data;
        dispatch(a, fl, file, &q, same_ep(&fl->a, q.src_ip, q.src_port));
    }
    fl->n_held = 0U;
}

static void remember(c4gh_an_t *a, const c4gh_cap_pkt_t *p)
{
    an_held_t *h = &a->recent[a->recent_head];
    a->recent_head = (a->recent_head + 1U) % C4GH_AN_RECENT;
    if (a->n_recent < C4GH_AN_RECENT) {
        a->n_recent++;
    }
    h->p = *p;
    h->p.len = (p->len <= sizeof h->data) ? p->len : sizeof h->data;
    memcpy(h->data, p->payload, h->p.len);
    h->p.payload = h->data;
    h->used = 0;
}

/* One datagram of a known flow: analysed, or held while the flow's direction is undecided. */
static void feed_flow(c4gh_an_t *a, c4gh_an_flow_t *fl, const char *file, const c4gh_cap_pkt_t *p, int from_a)
{
    an_held_t *h;
    int d;
    if (fl->ctrl_is_a >= 0) {
        dispatch(a, fl, file, p, from_a);
        return;
    }
    h = &fl->held[fl->n_held++];
    h->p = *p;
    h->p.len = (p->len <= sizeof h->data) ? p->len : sizeof h->data;
    memcpy(h->data, p->payload, h->p.len);
    h->p.payload = h->data;
    d = decide(a, fl, fl->n_held == C4GH_AN_PENDING);
    if (d >= 0) {
        release(a, fl, file, d);
    }
}

/* A flow found by its init packet: the datagrams of its endpoints seen just before (the
 * synchronization packets and their replies) go first, in order. */
static void take_recent(c4gh_an_t *a, c4gh_an_flow_t *fl, const char *file)
{
    unsigned k;
    for (k = 0U; k < a->n_recent; k++) {
        an_held_t *h = &a->recent[(a->recent_head + C4GH_AN_RECENT - a->n_recent + k) % C4GH_AN_RECENT];
        const int fwd = same_ep(&fl->a, h->p.src_ip, h->p.src_port) &&
                        same_ep(&fl->b, h->p.dst_ip, h->p.dst_port);
        const int back = same_ep(&fl->b, h->p.src_ip, h->p.src_port) &&
                         same_ep(&fl->a, h->p.dst_ip, h->p.dst_port);
        if (h->used || (!fwd && !back)) {
            continue;
        }
        h->used = 1;
        a->other_udp--;
        a->c4g_datagrams++;
        feed_flow(a, fl, file, &h->p, fwd);
    }
}

/* A capture that starts mid-session on ports not listed: the datagrams of one UDP
 * conversation have the C4G Open shape when the last AN_SHAPE_MIN of them (in the ring of
 * recent datagrams) go both ways, each 12 + 36 n bytes (n the same both ways; 732 for a
 * synchronization reply), with NUMs 0..0x7FFF, and one side counts its NUM up by one from
 * datagram to datagram. */
#define AN_SHAPE_MIN 8U
static int c4g_shaped(const c4gh_an_t *a, const c4gh_cap_pkt_t *p)
{
    unsigned k, n = 0U, steps = 0U, dirs = 0U;
    int32_t last_num[2] = {-1, -1};
    size_t len[2] = {0U, 0U};
    for (k = 0U; k < a->n_recent && n < AN_SHAPE_MIN; k++) {
        const an_held_t *h = &a->recent[(a->recent_head + C4GH_AN_RECENT - 1U - k) % C4GH_AN_RECENT];
        const int fwd = h->p.src_ip == p->src_ip && h->p.src_port == p->src_port &&
                        h->p.dst_ip == p->dst_ip && h->p.dst_port == p->dst_port;
        const int back = h->p.src_ip == p->dst_ip && h->p.src_port == p->dst_port &&
                         h->p.dst_ip == p->src_ip && h->p.dst_port == p->src_port;
        const int side = fwd ? 0 : 1;
        int32_t num;
        if (h->used || (!fwd && !back)) {
            continue;
        }
        if (!is_cyclic_size(h->data, h->p.len) && h->p.len != C4G_SYNC_REPLY_SIZE) {
            return 0;
        }
        num = c4g_le_i32(h->data);
        if (num < 0 || num > 0x7FFF) {
            return 0;
        }
        if (h->p.len != C4G_SYNC_REPLY_SIZE) {
            if (len[side] != 0U && len[side] != h->p.len) {
                return 0;
            }
            len[side] = h->p.len;
        }
        /* newest first: the side's previous datagram carries NUM - 1 */
        if (last_num[side] >= 0 && c4g_num_next(num) == last_num[side]) {
            steps++;
        }
        last_num[side] = num;
        dirs |= 1U << (unsigned)side;
        n++;
    }
    return n >= AN_SHAPE_MIN && dirs == 3U && len[0] == len[1] && steps >= AN_SHAPE_MIN / 2U - 1U;
}

/* A new flow from packet @p p's endpoints (a the sender), its controller side unknown. */
static c4gh_an_flow_t *flow_new(c4gh_an_t *a, const c4gh_cap_pkt_t *p)
{
    c4gh_an_flow_t *fl = &a->flows[a->n_flows++];
    memset(fl, 0, sizeof *fl);
    fl->a.ip = p->src_ip;
    fl->a.port = p->src_port;
    fl->b.ip = p->dst_ip;
    fl->b.port = p->dst_port;
    fl->ctrl_is_a = -1;
    fl->sess = -1;
    return fl;
}

static void datagram(c4gh_an_t *a, const char *file, const c4gh_cap_pkt_t *p)
{
    int from_a = 1;
    c4gh_an_flow_t *fl;
    a->datagrams++;
    a->file = file;
    fl = flow_find(a, p, &from_a);
    if (fl == NULL) {
        const int init = looks_init(p->payload, p->len);
        if (!port_listed(a, p->src_port) && !port_listed(a, p->dst_port) && !init) {
            a->other_udp++;
            remember(a, p);
            if (!is_cyclic_size(p->payload, p->len) || !c4g_shaped(a, p) || a->n_flows >= C4GH_AN_MAX_FLOWS) {
                return;
            }
            /* found by its shape: the datagrams in the ring (this one the last) are its start */
            fl = flow_new(a, p);
            take_recent(a, fl, file);
            return;
        }
        if (a->n_flows >= C4GH_AN_MAX_FLOWS) {
            a->flows_dropped++;
            return;
        }
        fl = flow_new(a, p);
        if (init) {
            /* the initialization packet comes from the controller; a first one carrying
             * NUM 11 is the PC's plus-one echo of an init packet the capture lost (a
             * fragment, a drop): its receiver is the controller */
            fl->ctrl_is_a = (c4g_le_i32(p->payload) == C4G_INIT_NUM) ? 1 : 0;
            take_recent(a, fl, file);
        }
    }
    a->c4g_datagrams++;
    feed_flow(a, fl, file, p, from_a);
}

/* An identical datagram (endpoints, bytes) at the same time as the one before: the same
 * frame captured twice (two interfaces merged, a file merged with itself). */
static int doubled(c4gh_an_t *a, const c4gh_cap_pkt_t *p)
{
    const int same = a->have_prev && a->prev.ts_ns == p->ts_ns && a->prev.src_ip == p->src_ip &&
                     a->prev.dst_ip == p->dst_ip && a->prev.src_port == p->src_port &&
                     a->prev.dst_port == p->dst_port && a->prev.len == p->len &&
                     p->len <= sizeof a->prev_data && memcmp(a->prev_data, p->payload, p->len) == 0;
    if (same) {
        a->doubled++;
        a->have_prev = 0; /* a third copy is a datagram again */
        return 1;
    }
    a->prev = *p;
    a->have_prev = p->len <= sizeof a->prev_data;
    if (a->have_prev) {
        memcpy(a->prev_data, p->payload, p->len);
    }
    return 0;
}

void c4gh_an_datagram(c4gh_an_t *a, const char *file, const c4gh_cap_pkt_t *p)
{
    c4gh_cap_pkt_t q = *p;
    if (doubled(a, p)) {
        return;
    }
    /* a clock step back (NTP, a merged file): capture order is the order of events, so the
     * later times move by the step and nothing is taken out of order */
    q.ts_ns = p->ts_ns + a->clock_shift;
    if (a->have_ts && q.ts_ns < a->last_ts) {
        const int64_t step = a->last_ts - q.ts_ns;
        if (!a->step_pending) {
            a->step_ns = step;
            a->step_frame = p->frame;
            a->step_pending = 1;
        }
        a->clock_shift += step;
        q.ts_ns = a->last_ts;
    }
    a->have_ts = 1;
    a->last_ts = q.ts_ns;
    datagram(a, file, &q);
}

void c4gh_an_file_end(c4gh_an_t *a, const char *file)
{
    unsigned i;
    for (i = 0U; i < a->n_flows; i++) {
        c4gh_an_flow_t *fl = &a->flows[i];
        if (fl->ctrl_is_a < 0 && fl->n_held > 0U) {
            release(a, fl, file, decide(a, fl, 1));
        }
        if (fl->sess >= 0) {
            c4gh_an_session_t *s = &a->sess[fl->sess];
            c4gh_cap_pkt_t q;
            memset(&q, 0, sizeof q);
            q.frame = s->last_frame;
            q.ts_ns = s->last_ns;
            session_close(a, s, &q, NULL);
        }
    }
    a->n_flows = 0U;
    a->n_recent = 0U;
    a->recent_head = 0U;
    a->have_ts = 0;
    a->clock_shift = 0;
    a->step_pending = 0;
    a->have_prev = 0;
}

double c4gh_an_latency_us(const c4gh_an_session_t *s, double q)
{
    return c4gh_hist_us(&s->lat, q);
}

unsigned c4gh_an_findings(const c4gh_an_session_t *s, uint32_t allow)
{
    unsigned k, n = 0U;
    for (k = 0U; k < (unsigned)AN_K_COUNT; k++) {
        if (s->f[k].count > 0U && (allow & (1U << k)) == 0U) {
            n++;
        }
    }
    return n;
}
