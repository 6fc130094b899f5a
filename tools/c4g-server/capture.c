/* SPDX-License-Identifier: MIT */
/* c4g-server --capture: see srv_capture.h. The capture is read through the analysis
 * (lib/host/c4gh_analyze.h) on demand: the host loop asks the source for its next datagram,
 * the source reads frames until the analysis hands over the next controller packet of the
 * controller being run (with its recorded reply, or a recorded reply that came late), so
 * memory stays bounded whatever the capture's length.
 *
 * The source's clock is the recorded reception time of the datagram handed over: there is
 * no time between two datagrams, so the core's deadlines that passed are checked at the
 * next datagram's time; an active-freezing pause moves the clock to its end (the reply's
 * recorded send time plus the pause), and the datagrams recorded before it are what queued
 * meanwhile: the host loop's drain answers the newest. A run stops where the server's would
 * (504 without --persist, the controller lost): a fresh server takes the next datagram. */
#include "srv_capture.h"

#include "c4gsim_fixtures.h"
#include "c4gh_textfile.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CAP_PROGRESS_MIN_BYTES (16U << 20) /* smaller files are read in a blink */

#if SRV_CAPTURE_MAX_PORTS != C4GH_AN_MAX_PORTS || SRV_CAPTURE_MAX_SESSIONS != C4GH_AN_MAX_SESSIONS
#error "srv_core.h's capture limits must be the analysis' (c4gh_analyze.h)"
#endif

static srv_host_t g_cap_host; /* large: static storage, like the socket's */
static c4gh_an_t g_an;

/* ---- comparing one reply ------------------------------------------------- */

static srv_cap_sess_t *sess_of(srv_cap_t *C, const c4gh_an_session_t *s)
{
    unsigned i;
    for (i = 0U; i < C->n_sess; i++) {
        if (C->sess[i].id == s->id) {
            return &C->sess[i];
        }
    }
    if (C->n_sess >= C4GH_AN_MAX_SESSIONS) {
        return NULL;
    }
    C->sess[C->n_sess].id = s->id;
    C->sess[C->n_sess].ctrl = s->ctrl;
    C->sess[C->n_sess].pc = s->pc;
    return &C->sess[C->n_sess++];
}

static void word_text(char *buf, size_t cap, srv_cap_field_t f, uint32_t u)
{
    if (f >= CAP_F_D1) {
        (void)snprintf(buf, cap, "%.9g", (double)c4gh_an_f32_bits(u));
    } else if (f == CAP_F_NUM || f == CAP_F_MODE) {
        (void)snprintf(buf, cap, "%d", (int)(int32_t)u);
    } else {
        (void)snprintf(buf, cap, "0x%08x", (unsigned)u);
    }
}

static void div_where(srv_cap_div_t *d, const srv_cap_pkt_t *p)
{
    memset(d, 0, sizeof *d);
    d->session = p->session;
    d->tick = p->tick;
    d->kind = p->kind;
    d->num = (p->ctrl_len >= 4U) ? (int32_t)c4g_le_u32(p->ctrl) : -1;
    d->frame = p->ctrl_frame;
    d->t_s = (double)(p->ctrl_ns - p->s->first_ns) * 1e-9;
}

/* Divergences of a packet whose recorded reply came late are found after later ones: the
 * first is the first in the capture. */
static int before(const srv_cap_div_t *a, const srv_cap_div_t *b)
{
    return a->session < b->session || (a->session == b->session && a->frame < b->frame);
}

static void count_div(srv_cap_t *C, const srv_cap_div_t *d)
{
    srv_cap_field_count_t *fc = &C->fields[d->field];
    if (fc->count++ == 0U || before(d, &fc->first)) {
        fc->first = *d;
    }
    C->words_divergent++;
    if (!C->have_first || before(d, &C->first)) {
        C->first = *d;
        C->have_first = 1;
    }
    if (C->listed < (long long)C->cfg.cap.list) {
        C->listed++;
        fputs("divergence: ", stdout);
        srv_cap_print_div(stdout, d);
    }
}

static int float_equal(const srv_cap_t *C, uint32_t a, uint32_t b)
{
    const double x = (double)c4gh_an_f32_bits(a), y = (double)c4gh_an_f32_bits(b);
    if (a == b) {
        return 1;
    }
    return C->cfg.cap.tolerance > 0.0 && isfinite(x) && isfinite(y) && fabs(x - y) <= C->cfg.cap.tolerance;
}

/* The field a word of a cyclic reply carries; *axis the OPEN index (0-based) or -1. */
static srv_cap_field_t cyclic_field(unsigned w, int *axis)
{
    static const srv_cap_field_t head[3] = {CAP_F_NUM, CAP_F_INFPAR, CAP_F_CMD};
    static const srv_cap_field_t per_axis[9] = {CAP_F_MODE, CAP_F_D1,   CAP_F_D2,   CAP_F_D3,  CAP_F_D4,
                                                CAP_F_D5,   CAP_F_EXT1, CAP_F_EXT2, CAP_F_EXT3};
    if (w < 3U) {
        *axis = -1;
        return head[w];
    }
    *axis = (int)((w - 3U) / 9U);
    return per_axis[(w - 3U) % 9U];
}

/* Compare the words both replies have; 1 if any differs. */
static int compare_words(srv_cap_t *C, const srv_cap_pkt_t *p, const uint8_t *rec, const uint8_t *out, size_t n)
{
    const c4gh_an_session_t *s = p->s;
    unsigned w;
    int diverged = 0;
    for (w = 0U; w < (unsigned)(n / 4U); w++) {
        const uint32_t a = c4g_le_u32(rec + 4U * w), b = c4g_le_u32(out + 4U * w);
        srv_cap_div_t d;
        int axis = -1;
        srv_cap_field_t f;
        if (a == b) {
            continue;
        }
        if (p->kind == C4G_PKT_CYCLIC) {
            f = cyclic_field(w, &axis);
            if (f >= CAP_F_D1 && float_equal(C, a, b)) {
                continue;
            }
        } else {
            f = (p->kind == C4G_PKT_SYNC) ? CAP_F_SYNC : CAP_F_INIT;
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
        count_div(C, &d);
        diverged = 1;
    }
    return diverged;
}

static void diverged_packet(srv_cap_t *C, srv_cap_sess_t *ss, const srv_cap_pkt_t *p)
{
    C->divergent++;
    ss->divergent++;
    if (!ss->any_div || p->tick < ss->first_div_tick) {
        ss->any_div = 1;
        ss->first_div_tick = p->tick;
    }
}

/* A pending packet without its late recorded reply: recorded none, produced a reply. */
static void pending_expire(srv_cap_t *C, srv_cap_pending_t *e)
{
    srv_cap_sess_t *ss = sess_of(C, e->p.s);
    srv_cap_div_t d;
    e->used = 0;
    if (ss == NULL) {
        return;
    }
    ss->recorded_missing++;
    div_where(&d, &e->p);
    d.field = CAP_F_REPLY;
    (void)snprintf(d.recorded, sizeof d.recorded, "none");
    (void)snprintf(d.produced, sizeof d.produced, "a reply");
    count_div(C, &d);
    diverged_packet(C, ss, &e->p);
}

static void pending_add(srv_cap_t *C, const srv_cap_pkt_t *p, const uint8_t *out, size_t out_len)
{
    srv_cap_pending_t *e = &C->pending[C->pend_next];
    C->pend_next = (C->pend_next + 1U) % CAP_PENDING;
    if (e->used) {
        pending_expire(C, e);
    }
    e->used = 1;
    e->p = *p;
    memcpy(e->ctrl, p->ctrl, p->ctrl_len);
    e->p.ctrl = e->ctrl;
    e->p.rec = NULL;
    memcpy(e->out, out, out_len);
    e->out_len = out_len;
}

static void pending_flush(srv_cap_t *C)
{
    unsigned k;
    for (k = 0U; k < CAP_PENDING; k++) {
        srv_cap_pending_t *e = &C->pending[(C->pend_next + k) % CAP_PENDING];
        if (e->used) {
            pending_expire(C, e);
        }
    }
}

static void compare(srv_cap_t *C, const srv_cap_pkt_t *p, const uint8_t *out, size_t out_len)
{
    srv_cap_sess_t *ss = sess_of(C, p->s);
    int diverged = 0;
    srv_cap_div_t d;
    if (ss == NULL) {
        return;
    }
    ss->compared++;
    C->compared++;
    if (p->rec == NULL && out != NULL && out_len <= C4G_INIT_SIZE && p->ctrl_len <= CAP_DGRAM) {
        pending_add(C, p, out, out_len); /* its recorded reply may still come, late */
        return;
    }
    if (p->rec == NULL) {
        ss->recorded_missing++;
    }
    if ((p->rec == NULL) != (out == NULL)) {
        div_where(&d, p);
        d.field = CAP_F_REPLY;
        (void)snprintf(d.recorded, sizeof d.recorded, "%s", (p->rec != NULL) ? "a reply" : "none");
        (void)snprintf(d.produced, sizeof d.produced, "%s", (out != NULL) ? "a reply" : "none");
        count_div(C, &d);
        diverged = 1;
    } else if (p->rec != NULL) {
        const size_t n = (p->rec_len < out_len) ? p->rec_len : out_len;
        if (p->rec_len != out_len) {
            div_where(&d, p);
            d.field = CAP_F_LENGTH;
            (void)snprintf(d.recorded, sizeof d.recorded, "%zu bytes", p->rec_len);
            (void)snprintf(d.produced, sizeof d.produced, "%zu bytes", out_len);
            count_div(C, &d);
            diverged = 1;
        }
        diverged |= compare_words(C, p, p->rec, out, n);
    }
    if (diverged) {
        diverged_packet(C, ss, p);
    }
}

/* A recorded reply that came after its packet's deadline: the reply the server produced for
 * that packet is compared with it; equal content is a timing difference only. */
static void late_reply(srv_cap_t *C, const srv_cap_item_t *it)
{
    const c4gh_an_session_t *s = it->p.s;
    const uint8_t *d = it->rec;
    const size_t len = it->p.rec_len;
    const int32_t num = (len >= 4U) ? (int32_t)c4g_le_u32(d) : -1;
    unsigned k;
    for (k = 0U; k < CAP_PENDING; k++) {
        srv_cap_pending_t *e = &C->pending[(C->pend_next + CAP_PENDING - 1U - k) % CAP_PENDING];
        const int32_t sent = (e->p.ctrl_len >= 4U) ? (int32_t)c4g_le_u32(e->p.ctrl) : -1;
        srv_cap_sess_t *ss;
        int diverged = 0;
        if (!e->used || e->p.s != s ||
            c4g_reply_num(sent, it->policy == C4G_NUM_ECHO ? C4G_NUM_ECHO : C4G_NUM_PLUS_ONE) != num) {
            continue;
        }
        e->used = 0;
        ss = sess_of(C, s);
        if (ss == NULL) {
            return;
        }
        if (len != e->out_len) {
            srv_cap_div_t dv;
            div_where(&dv, &e->p);
            dv.field = CAP_F_LENGTH;
            (void)snprintf(dv.recorded, sizeof dv.recorded, "%zu bytes", len);
            (void)snprintf(dv.produced, sizeof dv.produced, "%zu bytes", e->out_len);
            count_div(C, &dv);
            diverged = 1;
        }
        diverged |= compare_words(C, &e->p, d, e->out, (len < e->out_len) ? len : e->out_len);
        if (diverged) {
            diverged_packet(C, ss, &e->p);
        } else {
            ss->timing_only++;
            C->timing_only++;
        }
        return;
    }
}

/* ---- the reading ------------------------------------------------------------ */

static int selected(srv_cap_t *C, const c4gh_an_exchange_t *x)
{
    if (C->cfg.cap.session != 0U) {
        return x->s->id == C->cfg.cap.session;
    }
    if (!C->have_ctrl) {
        C->have_ctrl = 1;
        C->ctrl = x->s->ctrl;
    }
    return x->s->ctrl.ip == C->ctrl.ip && x->s->ctrl.port == C->ctrl.port;
}

static void note_other(srv_cap_t *C, unsigned id)
{
    unsigned i;
    C->other_ctrl_exchanges++;
    for (i = 0U; i < C->n_other; i++) {
        if (C->other_sessions[i] == id) {
            return;
        }
    }
    if (C->n_other < C4GH_AN_MAX_SESSIONS) {
        C->other_sessions[C->n_other++] = id;
    }
}

static srv_cap_item_t *push(srv_cap_t *C)
{
    srv_cap_item_t *it;
    if (C->q_n >= CAP_QUEUE) {
        C->overflow = 1;
        return NULL;
    }
    it = &C->q[(C->q_head + C->q_n++) % CAP_QUEUE];
    memset(it, 0, offsetof(srv_cap_item_t, ctrl));
    return it;
}

static void on_exchange(void *ctx, const c4gh_an_exchange_t *x)
{
    srv_cap_t *C = ctx;
    srv_cap_item_t *it;
    const uint8_t *rec = NULL;
    size_t rec_len = 0U;
    int64_t rec_ns = 0;
    if (C->init_error) {
        return; /* read to the end for its messages only */
    }
    if (!selected(C, x)) {
        note_other(C, x->s->id);
        return;
    }
    it = push(C);
    if (it == NULL) {
        return;
    }
    it->p.session = x->s->id;
    it->p.s = x->s;
    it->p.kind = (int)x->kind;
    it->p.tick = x->tick;
    it->p.ctrl_len = x->ctrl_len;
    it->p.ctrl_frame = x->ctrl_frame;
    it->p.ctrl_ns = x->ctrl_ns;
    memcpy(it->ctrl, x->ctrl, (x->ctrl_len < CAP_DGRAM) ? x->ctrl_len : CAP_DGRAM);
    it->p.ctrl = it->ctrl;
    if (x->reply != NULL) {
        rec = x->reply;
        rec_len = x->reply_len;
        rec_ns = x->reply_ns;
    } else if (x->other != NULL) {
        rec = x->other;
        rec_len = x->other_len;
        rec_ns = x->other_ns;
    }
    if (rec != NULL) {
        memcpy(it->rec, rec, (rec_len < sizeof it->rec) ? rec_len : sizeof it->rec);
        it->p.rec = it->rec;
        it->p.rec_len = rec_len;
        it->p.rec_ns = rec_ns;
    }
    it->from = x->s->ctrl;
    it->have_init = x->s->have_init;
    it->next_ns = x->next_ns;
}

static void on_late(void *ctx, const c4gh_an_session_t *s, const uint8_t *d, size_t len, int64_t ns,
                    uint64_t frame)
{
    srv_cap_t *C = ctx;
    srv_cap_item_t *it;
    (void)ns;
    (void)frame;
    if (C->init_error) {
        return;
    }
    it = push(C);
    if (it == NULL) {
        return;
    }
    it->late = 1;
    it->p.s = s;
    /* the rule as the analysis knows it now, not when the item is taken */
    it->policy = (s->cs.detected >= 0) ? s->cs.detected
                                        : ((C->an.num_policy == C4G_NUM_ECHO) ? C4G_NUM_ECHO
                                                                              : C4G_NUM_PLUS_ONE);
    memcpy(it->rec, d, (len < sizeof it->rec) ? len : sizeof it->rec);
    it->p.rec = it->rec;
    it->p.rec_len = len;
}

static void progress(const srv_cap_t *C, int final)
{
    const c4gh_cap_t *c = C->file;
    const uint64_t size = c4gh_cap_size(c), pos = c4gh_cap_pos(c);
    const unsigned pct = (size > 0U) ? (unsigned)((pos * 100U) / size) : 0U;
    if (final) {
        fprintf(stderr, "\r%-72s\r", "");
    } else {
        fprintf(stderr, "\r%s: %.40s %3u%% (%.1f of %.1f MB)", C->tool, c4gh_cap_path(c), pct,
                (double)pos / 1e6, (double)size / 1e6);
    }
    fflush(stderr);
}

/* Frames into the analysis until it hands over an item or the file ends. */
static void read_more(srv_cap_t *C)
{
    char err[390];
    c4gh_cap_pkt_t p;
    const char *path = C->cfg.cap.path;
    while (!C->eof && C->q_n == 0U) {
        const c4gh_cap_res_t r = c4gh_cap_next(C->file, &p, err, sizeof err);
        if (r == C4GH_CAP_FATAL) {
            fprintf(stderr, "%s: %s\n", C->tool, err);
            C->read_rc = 1;
        }
        if (r == C4GH_CAP_END || r == C4GH_CAP_FATAL) {
            if (C->progress) {
                progress(C, 1);
            }
            if (c4gh_cap_counts(C->file)->bad > 10U) {
                fprintf(stderr, "%s: %s: %llu damaged frames in all (the first 10 shown)\n", C->tool, path,
                        (unsigned long long)c4gh_cap_counts(C->file)->bad);
            }
            c4gh_an_file_end(C->a, path);
            C->eof = 1;
            break;
        }
        if (r == C4GH_CAP_BAD) {
            if (c4gh_cap_counts(C->file)->bad <= 10U) {
                fprintf(stderr, "%s: %s\n", C->tool, err);
            }
            continue;
        }
        if (r == C4GH_CAP_DATAGRAM) {
            c4gh_an_datagram(C->a, path, &p);
        }
        if (C->progress && (c4gh_cap_counts(C->file)->frames & 0xFFFFU) == 0U) {
            progress(C, 0);
        }
    }
}

/* The next item to take (a synthetic start-up first), the late replies before it judged on
 * the way; NULL at the end of the capture. */
static srv_cap_item_t *head(srv_cap_t *C)
{
    for (;;) {
        srv_cap_item_t *it;
        if (C->synth_n > 0U) {
            return &C->synth[C->synth_head];
        }
        if (C->q_n == 0U) {
            if (C->eof) {
                return NULL;
            }
            read_more(C);
            continue;
        }
        it = &C->q[C->q_head];
        if (!it->late) {
            return it;
        }
        late_reply(C, it);
        C->q_head = (C->q_head + 1U) % CAP_QUEUE;
        C->q_n--;
    }
}

static void pop(srv_cap_t *C)
{
    if (C->synth_n > 0U) {
        C->synth_head++;
        C->synth_n--;
    } else {
        C->q_head = (C->q_head + 1U) % CAP_QUEUE;
        C->q_n--;
    }
}

/* A session the capture shows without its start-up (it begins after the initialization
 * packet): the server is first taken through one, as a controller starts (9 synchronization
 * packets, the initialization packet, 2 synchronization packets, one period apart, ending one
 * period before the first recorded packet). The init packet is the manual's figure 10.1 for
 * the recorded axis count (axes 1-10 on arm 1, 11-20 on arm 2, as the analysis takes them)
 * and the recorded period. Its replies are not compared. */
static void prime(srv_cap_t *C, srv_cap_item_t *x)
{
    srv_cap_sess_t *ss;
    c4g_init_t init;
    const uint32_t n = (uint32_t)((x->p.ctrl_len - C4G_HEADER_SIZE) / C4G_AXIS_SIZE);
    uint64_t per_ns = 2000000U;
    uint32_t i;
    int32_t k;
    x->synthetic = -1; /* checked: never primed twice */
    if (x->have_init || x->p.kind != C4G_PKT_CYCLIC || x->p.ctrl_len < C4G_CYCLIC_SIZE(1U) ||
        x->p.ctrl_len > C4G_CYCLIC_SIZE(C4G_MAX_AXES)) {
        return;
    }
    ss = sess_of(C, x->p.s);
    if (ss == NULL || ss->fed[C4G_PKT_SYNC] + ss->fed[C4G_PKT_INIT] + ss->fed[C4G_PKT_CYCLIC] != 0U) {
        return;
    }
    if (x->next_ns > x->p.ctrl_ns && x->next_ns - x->p.ctrl_ns < 1500000) {
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
    C->synth_head = 0U;
    C->synth_n = 0U;
    for (k = 1; k <= (int32_t)CAP_SYNTH; k++) {
        srv_cap_item_t *s = &C->synth[C->synth_n];
        size_t len = C4G_CYCLIC_SIZE((size_t)n);
        memset(s, 0, offsetof(srv_cap_item_t, ctrl));
        memset(s->ctrl, 0, sizeof s->ctrl);
        if (k == C4G_INIT_NUM) {
            if (c4g_init_encode(&init, s->ctrl, C4G_INIT_SIZE, &len) != C4G_OK) {
                C->synth_n = 0U;
                return;
            }
        } else {
            s->ctrl[0] = (uint8_t)k;
        }
        s->synthetic = 1;
        s->p = x->p;
        s->p.ctrl = s->ctrl;
        s->p.ctrl_len = len;
        s->p.ctrl_ns = x->p.ctrl_ns - (int64_t)((uint64_t)(13 - k) * per_ns);
        s->p.rec = NULL;
        s->from = x->from;
        C->synth_n++;
    }
    ss->primed = 1;
    ss->primed_axes = n;
    ss->primed_period_ms = (unsigned)(per_ns / 1000000U);
}

/* The next item, with a synthetic start-up before a session's first packet when the capture
 * lacks one. */
static srv_cap_item_t *head_primed(srv_cap_t *C)
{
    srv_cap_item_t *it = head(C);
    if (it != NULL && it->synthetic == 0) {
        prime(C, it);
        it = head(C);
    }
    return it;
}

/* ---- the capture as the host loop's source (srv.h) ---------------------------- */

static uint64_t item_ns(const srv_cap_item_t *it)
{
    return (it->p.ctrl_ns > 0) ? (uint64_t)it->p.ctrl_ns : 0U;
}

static const srv_cap_item_t *taken(const srv_cap_t *C, const srv_dgram_t *d)
{
    return &C->taken[d->ref % CAP_TAKEN];
}

/* The head item into @p d, received at @p t. */
static void take(srv_cap_t *C, srv_cap_item_t *it, uint64_t t, srv_dgram_t *d)
{
    srv_cap_item_t *slot;
    d->ref = C->next_ref++;
    slot = &C->taken[d->ref % CAP_TAKEN];
    *slot = *it;
    slot->p.ctrl = slot->ctrl;
    slot->p.rec = (it->p.rec != NULL) ? slot->rec : NULL;
    d->size = it->p.ctrl_len;
    d->len = (d->size > d->cap) ? d->cap : d->size;
    memcpy(d->buf, it->ctrl, d->len);
    srv_endpoint(it->from.ip, it->from.port, &d->from);
    d->t_rx = t;
    d->t_cap = t;
    pop(C);
}

static uint64_t cap_now(void *ctx)
{
    return ((const srv_cap_t *)ctx)->clock;
}

/* The next recorded packet. Recorded at or after @p due: the clock moves to it and the
 * caller's deadline checks run there first. */
static int cap_next(void *ctx, uint64_t due, srv_dgram_t *d)
{
    srv_cap_t *C = ctx;
    srv_cap_item_t *it = head_primed(C);
    uint64_t t;
    if (it == NULL) {
        return SRV_SRC_END;
    }
    t = item_ns(it);
    if (t >= due && t > C->clock) {
        C->clock = t;
        return SRV_SRC_NONE;
    }
    if (t > C->clock) {
        C->clock = t;
    }
    take(C, it, C->clock, d);
    return SRV_SRC_HAVE;
}

/* A packet recorded before the clock: queued while the server paused. */
static int cap_queued(void *ctx, srv_dgram_t *d)
{
    srv_cap_t *C = ctx;
    srv_cap_item_t *it = head(C);
    if (it == NULL || item_ns(it) >= C->clock) {
        return SRV_SRC_NONE;
    }
    take(C, it, C->clock, d);
    return SRV_SRC_HAVE;
}

static void cap_accepted(void *ctx, const srv_dgram_t *d)
{
    srv_cap_t *C = ctx;
    const srv_cap_item_t *it = taken(C, d);
    srv_cap_sess_t *ss;
    if (it->synthetic > 0) {
        return;
    }
    ss = sess_of(C, it->p.s);
    if (ss != NULL && it->p.kind >= C4G_PKT_SYNC && it->p.kind <= C4G_PKT_CYCLIC) {
        ss->fed[it->p.kind]++;
    }
}

/* The reply compared with the recorded one; sent when the recording sent it (else when its
 * packet came). */
static uint64_t cap_reply(void *ctx, const srv_dgram_t *d, const uint8_t *out, size_t len,
                          const srv_verdict_t *v)
{
    srv_cap_t *C = ctx;
    const srv_cap_item_t *it = taken(C, d);
    const srv_cap_pkt_t *p = &it->p;
    (void)v;
    if (it->synthetic > 0) {
        C->last_tx = d->t_rx;
        return d->t_rx;
    }
    compare(C, p, out, len);
    C->last_tx = (p->rec != NULL && p->rec_ns >= 0 && (uint64_t)p->rec_ns >= d->t_rx) ? (uint64_t)p->rec_ns
                                                                                      : d->t_rx;
    return C->last_tx;
}

/* Active freezing: the clock moves to the pause's end; what was recorded before it queued. */
static void cap_pause(void *ctx, double ms)
{
    srv_cap_t *C = ctx;
    C->clock = C->last_tx + (uint64_t)(ms * 1e6);
}

/* Dropped unanswered after a pause: counted as fed, compared with no reply. */
static void cap_dropped(void *ctx, const srv_dgram_t *d)
{
    srv_cap_t *C = ctx;
    const srv_cap_item_t *it = taken(C, d);
    srv_cap_sess_t *ss;
    if (it->synthetic > 0) {
        return;
    }
    ss = sess_of(C, it->p.s);
    if (ss != NULL) {
        ss->held_dropped++;
        if (it->p.kind >= C4G_PKT_SYNC && it->p.kind <= C4G_PKT_CYCLIC) {
            ss->fed[it->p.kind]++;
        }
    }
    compare(C, &it->p, NULL, 0U);
}

/* ---- the run -------------------------------------------------------------------- */

int srv_capture_misplaced(const srv_capture_opts_t *o)
{
    if (o->path[0] == '\0' && (o->session != 0U || o->ports[0] != '\0' || o->tolerance > 0.0 ||
                               o->list != 0U || o->echo || o->no_progress || o->rerun)) {
        fprintf(stderr, "c4g-server: --session, --capture-ports, --behaviour, --tolerance, --list, "
                "--no-progress and --replay-rerun need --capture FILE\n");
        return 1;
    }
    return 0;
}

/* What only the live server does: none of it changes a reply. */
static void capture_config(srv_cap_t *C, const srv_config_t *cfg)
{
    unsigned arm;
    C->cfg = *cfg;
    C->cfg.pcap_path[0] = '\0';
    C->cfg.moni_path[0] = '\0';
    C->cfg.log_path[0] = '\0';
    C->cfg.quiet = 1;
    C->cfg.verbose = 0;
    C->cfg.idle_timeout = 0.0;
    C->cfg.max_seconds = 0.0;
    (void)snprintf(C->cfg.ctrl_addr, sizeof C->cfg.ctrl_addr, "any");
    if (C->cfg.cap.echo) {
        for (arm = 0U; arm < C4G_ARMS; arm++) {
            C->cfg.arm[arm].axes = 0U;
        }
    }
}

/* The analysis' options: its callbacks, the PC ports. */
static void capture_analysis(srv_cap_t *C)
{
    const char *p = C->cfg.cap.ports;
    c4gh_an_options_default(&C->an);
    if (p[0] != '\0') {
        C->an.n_ports = 0U;
        while (*p != '\0' && C->an.n_ports < C4GH_AN_MAX_PORTS) {
            C->an.ports[C->an.n_ports++] = (uint16_t)strtoul(p, NULL, 10); /* checked by the option */
            p += strcspn(p, ",");
            p += (*p == ',') ? 1 : 0;
        }
    }
    C->an.on_exchange = on_exchange;
    C->an.on_late = on_late;
    C->an.ctx = C;
}

int srv_capture_run(srv_cap_t *C, const srv_config_t *cfg)
{
    srv_host_t *H = &g_cap_host;
    srv_source_t src;
    char err[390];
    const char *tool = cfg->cap.rerun ? "c4g-replay" : "c4g-server";
    memset(C, 0, sizeof *C);
    C->tool = tool;
    C->cmd = cfg->cap.rerun ? "rerun" : "capture";
    capture_config(C, cfg);
    capture_analysis(C);
    C->file = c4gh_cap_open(C->cfg.cap.path, err, sizeof err);
    if (C->file == NULL) {
        fprintf(stderr, "%s: %s\n", tool, err);
        C->read_rc = 2;
        return 2;
    }
    if (c4gh_an_init(&g_an, &C->an) != 0) {
        c4gh_cap_close(C->file);
        return -1;
    }
    C->a = &g_an;
    C->progress = !C->cfg.cap.no_progress && isatty(2) && c4gh_cap_size(C->file) >= CAP_PROGRESS_MIN_BYTES;
    memset(&src, 0, sizeof src);
    src.ctx = C;
    src.now = cap_now;
    src.next = cap_next;
    src.queued = cap_queued;
    src.reply = cap_reply;
    src.pause = cap_pause;
    src.accepted = cap_accepted;
    src.dropped = cap_dropped;
    memset(H, 0, sizeof *H); /* no controller address: the capture holds one controller's packets */
    for (;;) {
        /* a fresh server where the recorded one would have stopped, at its next datagram */
        const srv_cap_item_t *it = head_primed(C);
        if (it == NULL) {
            break;
        }
        if (srv_init(&H->s, &C->cfg, NULL, NULL) != C4G_OK) {
            C->init_error = 1;
            (void)snprintf(C->init_why, sizeof C->init_why, "the server core refused the configuration");
            C->q_n = 0U;
            C->synth_n = 0U;
            while (!C->eof) {
                read_more(C); /* to the end, for the messages a damaged file gives */
            }
            break;
        }
        C->server_starts++;
        H->s.t0_ns = item_ns(it);
        if (srv_serve(H, &src) == SRV_SOURCE_END) {
            break;
        }
    }
    pending_flush(C);
    c4gh_an_free(&g_an);
    C->a = NULL;
    c4gh_cap_close(C->file);
    C->file = NULL;
    return C->read_rc;
}

/* The report: text on stdout, JSON on stdout (--json, --json-out -) or into a file besides. 0, or -1. */
static int report(const srv_cap_t *C, const srv_config_t *cfg)
{
    const char *json = cfg->json_path;
    const char *path = cfg->cap.path;
    FILE *f;
    int rc = 0;
    if (strcmp(json, "-") == 0) {
        return (srv_cap_report_json(stdout, C, path) != 0 || fflush(stdout) != 0) ? -1 : 0;
    }
    srv_cap_report_text(stdout, C, path);
    if (fflush(stdout) != 0) {
        return -1;
    }
    if (json[0] == '\0') {
        return 0;
    }
    f = fopen(json, "w");
    if (f == NULL) {
        return -1;
    }
    rc = srv_cap_report_json(f, C, path);
    if (fclose(f) != 0) {
        rc = -1;
    }
    return rc;
}

static srv_cap_t g_cap; /* large: static storage */

static int capture_exit(srv_cap_t *C, const srv_config_t *cfg, int rc)
{
    if (rc < 0) {
        fprintf(stderr, "%s: out of memory\n", C->tool);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (rc == 2) {
        return C4GH_CLI_EXIT_USAGE;
    }
    if (C->init_error) {
        fprintf(stderr, "%s: %s: %s\n", C->tool, C->cmd, C->init_why);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (C->overflow) {
        fprintf(stderr, "%s: %s: internal: the reading ran more than %u items ahead\n", C->tool, C->cmd,
                CAP_QUEUE);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (C->compared == 0U) {
        fprintf(stderr, "%s: %s: no controller packet to %s%s\n", C->tool, cfg->cap.path,
                cfg->cap.rerun ? "rerun" : "run", (cfg->cap.session != 0U) ? " in that session" : "");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (report(C, cfg) != 0) {
        fprintf(stderr, "%s: writing the report failed\n", C->tool);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (rc == 1) {
        return C4GH_CLI_EXIT_USAGE;
    }
    return (C->divergent > 0U) ? C4GH_CLI_EXIT_RUNTIME : C4GH_CLI_EXIT_OK;
}

int srv_capture_main(const srv_config_t *cfg, int argc, char **argv)
{
    srv_cap_t *C = &g_cap;
    const int rc = srv_capture_run(C, cfg);
    C->srv_argv = argv;
    C->srv_argc = argc;
    return capture_exit(C, cfg, rc);
}

int srv_capture_rerun_main(int argc, char **argv)
{
    static srv_config_t cfg, front;
    static char *argv2[256];
    const char *tool = "c4g-replay rerun (c4g-server options)";
    char err[700];
    int k, dash = argc;
    for (k = 1; k < argc; k++) {
        if (strcmp(argv[k], "--") == 0) {
            dash = k;
            break;
        }
    }
    /* the front end's own request: it checked it */
    srv_config_default(&front);
    if (srv_config_cli(&front, "c4g-server", NULL, SRV_CLI_CAPTURE, dash, argv) != C4GH_CLI_RUN) {
        return C4GH_CLI_EXIT_USAGE;
    }
    /* the user's c4g-server options, as c4g-replay rerun's */
    if (argc - dash > (int)(sizeof argv2 / sizeof argv2[0]) - 1) {
        fprintf(stderr, "c4g-replay: at most %u c4g-server options\n",
                (unsigned)(sizeof argv2 / sizeof argv2[0]) - 2U);
        return C4GH_CLI_EXIT_USAGE;
    }
    argv2[0] = (char *)(uintptr_t)tool; /* getopt's argv is never written through */
    for (k = dash + 1; k < argc; k++) {
        argv2[k - dash] = argv[k];
    }
    argv2[(argc > dash) ? argc - dash : 1] = NULL;
    srv_config_default(&cfg);
    switch (srv_config_cli(&cfg, tool, NULL, SRV_CLI_SERVER, (argc > dash) ? argc - dash : 1, argv2)) {
    case C4GH_CLI_RUN:
        break;
    case C4GH_CLI_DONE:
        return C4GH_CLI_EXIT_OK;
    default:
        return C4GH_CLI_EXIT_USAGE;
    }
    if (srv_load_files(&cfg, err, sizeof err) != 0) {
        fprintf(stderr, "c4g-replay: %s\n", err);
        return C4GH_CLI_EXIT_USAGE;
    }
    cfg.cap = front.cap;
    cfg.cap.rerun = 1;
    (void)snprintf(cfg.json_path, sizeof cfg.json_path, "%s", front.json_path);
    return srv_capture_main(&cfg, (argc > dash) ? argc - dash - 1 : 0, argv + dash + 1);
}
