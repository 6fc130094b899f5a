/* SPDX-License-Identifier: MIT */
/* The controller side of C4G Open without I/O: see c4g_ctrlside.h. */
#include "c4gh_ctrlside.h"

#include <string.h>

void c4gh_cs_init(c4gh_cs_t *c, const c4gh_cs_config_t *cfg)
{
    memset(c, 0, sizeof *c);
    c->cfg = *cfg;
    c->phase = (cfg->sync_before > 0U) ? C4GH_CS_PH_SYNC_PRE : C4GH_CS_PH_INIT;
    c->left = cfg->sync_before;
    c->cold = 1;
    c->num = 1;
    c->detected = -1;
    c->out.deadline_ns = UINT64_MAX;
}

/* ---- handshake driver ---------------------------------------------------- */

int32_t c4gh_cs_num_after(int32_t n)
{
    return (n >= C4G_NUM_MAX) ? 0 : n + 1;
}

c4gh_cs_kind_t c4gh_cs_next_kind(const c4gh_cs_t *c)
{
    switch (c->phase) {
    case C4GH_CS_PH_SYNC_PRE:
    case C4GH_CS_PH_SYNC_POST:
        return C4GH_CS_SYNC;
    case C4GH_CS_PH_INIT:
        return C4GH_CS_INIT;
    case C4GH_CS_PH_CYCLIC:
    default:
        return C4GH_CS_CYCLIC;
    }
}

int32_t c4gh_cs_next_num(const c4gh_cs_t *c)
{
    return (c->phase == C4GH_CS_PH_INIT) ? C4G_INIT_NUM : c->num;
}

void c4gh_cs_advance(c4gh_cs_t *c)
{
    switch (c->phase) {
    case C4GH_CS_PH_SYNC_PRE:
    case C4GH_CS_PH_SYNC_POST:
        c->num = c4gh_cs_num_after(c->num);
        if (c->left > 0U) {
            c->left--;
        }
        if (c->left == 0U) {
            c->phase = (c->phase == C4GH_CS_PH_SYNC_PRE) ? C4GH_CS_PH_INIT : C4GH_CS_PH_CYCLIC;
        }
        break;
    case C4GH_CS_PH_INIT:
        /* the syncs after the init packet belong to the first start only (a restart
         * goes straight to cyclic packets) */
        c->num = C4G_INIT_NUM + 1;
        c->left = c->cfg.sync_after;
        c->phase = (c->cold && c->cfg.sync_after > 0U) ? C4GH_CS_PH_SYNC_POST : C4GH_CS_PH_CYCLIC;
        c->cold = 0;
        break;
    case C4GH_CS_PH_CYCLIC:
    default:
        c->num = c4gh_cs_num_after(c->num);
        break;
    }
}

void c4gh_cs_restart(c4gh_cs_t *c)
{
    c->phase = C4GH_CS_PH_INIT;
}

/* ---- NUM policy ---------------------------------------------------------- */

/* The policy in force: "either" is the one the PC showed, or still both (-1). */
static int cs_policy_in_force(const c4gh_cs_t *c)
{
    return (c->cfg.policy == C4GH_CS_NUM_EITHER) ? c->detected : (int)c->cfg.policy;
}

int c4gh_cs_num_ok(const c4gh_cs_t *c, int32_t sent, int32_t got)
{
    const int32_t plus = c4g_reply_num(sent, C4G_NUM_PLUS_ONE);
    /* "either": the PC may use one or the other, but consistently; its echo of the init
     * packet decides (otherwise a late plus-one reply would pass as the next echo). */
    switch (cs_policy_in_force(c)) {
    case C4GH_CS_NUM_PLUS_ONE:
        return got == plus;
    case C4GH_CS_NUM_ECHO:
        return got == sent;
    default:
        return got == plus || got == sent;
    }
}

int c4gh_cs_is_stale(const c4gh_cs_t *c, int32_t cur, int32_t got)
{
    const int use = cs_policy_in_force(c);
    int p;
    for (p = 0; p < 2; p++) {
        /* p 0: got echoes packet got; p 1: got is plus-one of packet got - 1 */
        /* in 64 bits: a hostile reply's NUM may be anything an int32 holds */
        const int64_t sent = (p == 0) ? (int64_t)got : (int64_t)got - 1;
        int64_t d;
        if ((p == 0 && use == C4GH_CS_NUM_PLUS_ONE) || (p == 1 && use == C4GH_CS_NUM_ECHO)) {
            continue;
        }
        d = ((int64_t)cur - sent) % 0x8000;
        if (d < 0) {
            d += 0x8000;
        }
        if (d >= 1 && d <= C4GH_CS_STALE_WINDOW) {
            return 1;
        }
    }
    return 0;
}

/* ---- replies ------------------------------------------------------------- */

void c4gh_cs_emit(c4gh_cs_t *c, c4gh_cs_kind_t kind, int32_t num, const uint8_t *buf, size_t len, int check,
             uint64_t sent_ns)
{
    c4gh_cs_outstanding_t *o = &c->out;
    o->active = 1;
    o->check = check;
    o->kind = kind;
    o->num = num;
    o->answered = 0;
    o->got = 0;
    o->deadline_ns = UINT64_MAX; /* the caller sets it once the next tick is known */
    o->len = (len <= sizeof o->raw) ? len : sizeof o->raw;
    memcpy(o->raw, buf, o->len);
    o->sent_ns = sent_ns;
    if (kind == C4GH_CS_SYNC) {
        c->n.sync_sent++;
    } else if (kind == C4GH_CS_INIT) {
        c->n.init_sent++;
    } else {
        c->n.cyclic_sent++;
    }
}

void c4gh_cs_set_deadline(c4gh_cs_t *c, uint64_t deadline_ns)
{
    if (c->out.active) {
        c->out.deadline_ns = deadline_ns;
    }
}

int c4gh_cs_sent_stamp(c4gh_cs_t *c, uint64_t stamp_ns, uint64_t now_ns)
{
    c4gh_cs_outstanding_t *o = &c->out;
    /* the send happened after the caller's clock read before it, and before now */
    if (o->active && stamp_ns != 0U && stamp_ns + 200000U >= o->sent_ns && stamp_ns <= now_ns) {
        o->sent_ns = stamp_ns;
        return 1;
    }
    return 0;
}

void c4gh_cs_foreign(c4gh_cs_t *c)
{
    c->n.rx_total++;
    c->n.foreign++;
}

static int32_t cs_get_num(const uint8_t *b)
{
    return (int32_t)((uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) |
                     ((uint32_t)b[3] << 24));
}

/* The per-kind check of a reply whose NUM is right; C4GH_CS_RX_ACCEPTED or why not. */
static c4gh_cs_rx_t cs_check_body(c4gh_cs_t *c, const uint8_t *buf, size_t len, c4g_pc_packet_t *pkt)
{
    const c4gh_cs_outstanding_t *o = &c->out;
    switch (o->kind) {
    case C4GH_CS_SYNC:
        return (len == C4G_SYNC_REPLY_SIZE) ? C4GH_CS_RX_ACCEPTED : C4GH_CS_RX_BAD_LENGTH;
    case C4GH_CS_INIT:
        /* the init packet echoed: only NUM may differ */
        return (len == C4G_INIT_SIZE && o->len == C4G_INIT_SIZE &&
                memcmp(&buf[4], &o->raw[4], C4G_INIT_SIZE - 4U) == 0)
                   ? C4GH_CS_RX_ACCEPTED
                   : C4GH_CS_RX_BAD_INIT;
    case C4GH_CS_CYCLIC:
    default:
        return (c4g_pc_decode(buf, len, c->cfg.n_axes, pkt, &c->last_diag) == C4G_OK)
                   ? C4GH_CS_RX_ACCEPTED
                   : C4GH_CS_RX_BAD_DECODE;
    }
}

c4gh_cs_rx_t c4gh_cs_reply(c4gh_cs_t *c, const uint8_t *buf, size_t len, uint64_t at_ns)
{
    c4gh_cs_outstanding_t *o = &c->out;
    c4g_pc_packet_t pkt;
    c4gh_cs_rx_t r;
    c->n.rx_total++;
    if (!o->active || !o->check) {
        c->n.unexpected++;
        return C4GH_CS_RX_UNEXPECTED;
    }
    if (len < 4U) {
        c->n.malformed++;
        return C4GH_CS_RX_SHORT;
    }
    c->last_num = cs_get_num(buf);
    if (!c4gh_cs_num_ok(c, o->num, c->last_num)) {
        if (c4gh_cs_is_stale(c, o->num, c->last_num)) {
            c->n.stale++;
            return C4GH_CS_RX_STALE;
        }
        c->n.wrong_num++;
        return C4GH_CS_RX_WRONG_NUM;
    }
    r = cs_check_body(c, buf, len, &pkt);
    if (r != C4GH_CS_RX_ACCEPTED) {
        c->n.malformed++;
        return r;
    }
    if (o->got) {
        c->n.duplicates++;
        return C4GH_CS_RX_DUPLICATE;
    }
    /* judged at the next tick against the packet's deadline (c4gh_cs_judge), by arrival time */
    o->got = 1;
    o->got_ns = at_ns;
    /* "either" locks on the init echo: its 1200 bytes cannot be confused with a late
     * reply to a sync packet, so its NUM (11 or 10) shows the PC's policy */
    if (o->kind == C4GH_CS_INIT && c->cfg.policy == C4GH_CS_NUM_EITHER) {
        c->detected = (c->last_num == o->num) ? C4GH_CS_NUM_ECHO : C4GH_CS_NUM_PLUS_ONE;
    }
    if (o->kind == C4GH_CS_CYCLIC) {
        o->reply = pkt;
    }
    return C4GH_CS_RX_ACCEPTED;
}

/* ---- deadlines ----------------------------------------------------------- */

static void cs_count_latency(c4gh_cs_counters_t *n, uint64_t lat)
{
    if (n->replies_ok == 0U || lat < n->lat_min) {
        n->lat_min = lat;
    }
    if (lat > n->lat_max) {
        n->lat_max = lat;
    }
    n->lat_sum += lat;
    c4gh_hist_add(&n->lat, (int64_t)lat);
    n->replies_ok++;
}

c4gh_cs_verdict_t c4gh_cs_judge(c4gh_cs_t *c, uint64_t woke_ns, int suspended)
{
    c4gh_cs_outstanding_t *o = &c->out;
    int own_late;
    c4gh_cs_verdict_t v;
    c->last_late = 0;
    c->last_stale = 0;
    c->fatal = 0;
    if (!o->active) {
        return C4GH_CS_J_NONE;
    }
    o->active = 0;
    if (!o->check || suspended) {
        return C4GH_CS_J_NONE;
    }
    /* Woken past the deadline, the caller could not see it pass: a reply that was there
     * when it looked counts, and no reply is not the PC's fault alone (the whole host may
     * have stalled). */
    own_late = woke_ns > o->deadline_ns && woke_ns - o->deadline_ns > c->cfg.tol_ns;
    if (o->got && o->got_ns <= (own_late ? woke_ns : o->deadline_ns)) {
        const uint64_t lat = (o->got_ns > o->sent_ns) ? o->got_ns - o->sent_ns : 0U;
        o->answered = 1;
        c->n.consecutive = 0;
        if (lat > c->cfg.t_cycle1_ns) {
            c->n.late++;
            c->last_late = 1;
        }
        cs_count_latency(&c->n, lat);
        return C4GH_CS_J_OK;
    }
    if (o->got) {
        c->n.stale++; /* it came, after its deadline */
        c->last_stale = 1;
    }
    /* Unjudged or missing, it is a packet without a reply: both extend the run that ends
     * in ERR_C4GOPEN_UDP; only a missing one is the PC's fault. */
    c->n.consecutive++;
    if (own_late) {
        c->n.unjudged++;
        v = C4GH_CS_J_UNJUDGED;
    } else {
        c->n.missing++;
        v = C4GH_CS_J_MISSING;
    }
    if (c->n.consecutive > c->n.max_consecutive) {
        c->n.max_consecutive = c->n.consecutive;
    }
    c->fatal = c->n.consecutive >= c->cfg.max_miss;
    return v;
}

const c4g_pc_packet_t *c4gh_cs_take_reply(c4gh_cs_t *c)
{
    const int ok = c->out.kind == C4GH_CS_CYCLIC && c->out.answered;
    c->out.answered = 0;
    return ok ? &c->out.reply : NULL;
}

/* ---- reporting ----------------------------------------------------------- */

double c4gh_cs_lat_percentile(const c4gh_cs_counters_t *n, double q)
{
    return c4gh_hist_us(&n->lat, q);
}

const char *c4gh_cs_policy_name(int policy)
{
    switch (policy) {
    case C4GH_CS_NUM_PLUS_ONE:
        return "plus-one";
    case C4GH_CS_NUM_ECHO:
        return "echo";
    case C4GH_CS_NUM_EITHER:
        return "either";
    default:
        return "unknown";
    }
}
