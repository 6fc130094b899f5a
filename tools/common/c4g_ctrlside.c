/* SPDX-License-Identifier: MIT */
/* The controller side of C4G Open without I/O: see c4g_ctrlside.h. */
#include "c4g_ctrlside.h"

#include <string.h>

void cs_init(cs_t *c, const cs_config_t *cfg)
{
    memset(c, 0, sizeof *c);
    c->cfg = *cfg;
    c->phase = (cfg->sync_before > 0U) ? CS_PH_SYNC_PRE : CS_PH_INIT;
    c->left = cfg->sync_before;
    c->cold = 1;
    c->num = 1;
    c->detected = -1;
    c->out.deadline_ns = UINT64_MAX;
}

/* ---- handshake driver ---------------------------------------------------- */

int32_t cs_num_after(int32_t n)
{
    return (n >= C4G_NUM_MAX) ? 0 : n + 1;
}

cs_kind_t cs_next_kind(const cs_t *c)
{
    switch (c->phase) {
    case CS_PH_SYNC_PRE:
    case CS_PH_SYNC_POST:
        return CS_SYNC;
    case CS_PH_INIT:
        return CS_INIT;
    case CS_PH_CYCLIC:
    default:
        return CS_CYCLIC;
    }
}

int32_t cs_next_num(const cs_t *c)
{
    return (c->phase == CS_PH_INIT) ? C4G_INIT_NUM : c->num;
}

void cs_advance(cs_t *c)
{
    switch (c->phase) {
    case CS_PH_SYNC_PRE:
    case CS_PH_SYNC_POST:
        c->num = cs_num_after(c->num);
        if (c->left > 0U) {
            c->left--;
        }
        if (c->left == 0U) {
            c->phase = (c->phase == CS_PH_SYNC_PRE) ? CS_PH_INIT : CS_PH_CYCLIC;
        }
        break;
    case CS_PH_INIT:
        /* the syncs after the init packet belong to the first start only (a restart
         * goes straight to cyclic packets) */
        c->num = C4G_INIT_NUM + 1;
        c->left = c->cfg.sync_after;
        c->phase = (c->cold && c->cfg.sync_after > 0U) ? CS_PH_SYNC_POST : CS_PH_CYCLIC;
        c->cold = 0;
        break;
    case CS_PH_CYCLIC:
    default:
        c->num = cs_num_after(c->num);
        break;
    }
}

void cs_restart(cs_t *c)
{
    c->phase = CS_PH_INIT;
}

/* ---- NUM policy ---------------------------------------------------------- */

/* The policy in force: "either" is the one the PC showed, or still both (-1). */
static int cs_policy_in_force(const cs_t *c)
{
    return (c->cfg.policy == CS_NUM_EITHER) ? c->detected : (int)c->cfg.policy;
}

int cs_num_ok(const cs_t *c, int32_t sent, int32_t got)
{
    const int32_t plus = c4g_reply_num(sent, C4G_NUM_PLUS_ONE);
    /* "either": the PC may use one or the other, but consistently; its echo of the init
     * packet decides (otherwise a late plus-one reply would pass as the next echo). */
    switch (cs_policy_in_force(c)) {
    case CS_NUM_PLUS_ONE:
        return got == plus;
    case CS_NUM_ECHO:
        return got == sent;
    default:
        return got == plus || got == sent;
    }
}

int cs_is_stale(const cs_t *c, int32_t cur, int32_t got)
{
    const int use = cs_policy_in_force(c);
    int p;
    for (p = 0; p < 2; p++) {
        /* p 0: got echoes packet got; p 1: got is plus-one of packet got - 1 */
        /* in 64 bits: a hostile reply's NUM may be anything an int32 holds */
        const int64_t sent = (p == 0) ? (int64_t)got : (int64_t)got - 1;
        int64_t d;
        if ((p == 0 && use == CS_NUM_PLUS_ONE) || (p == 1 && use == CS_NUM_ECHO)) {
            continue;
        }
        d = ((int64_t)cur - sent) % 0x8000;
        if (d < 0) {
            d += 0x8000;
        }
        if (d >= 1 && d <= CS_STALE_WINDOW) {
            return 1;
        }
    }
    return 0;
}

/* ---- replies ------------------------------------------------------------- */

void cs_emit(cs_t *c, cs_kind_t kind, int32_t num, const uint8_t *buf, size_t len, int check,
             uint64_t sent_ns)
{
    cs_outstanding_t *o = &c->out;
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
    if (kind == CS_SYNC) {
        c->n.sync_sent++;
    } else if (kind == CS_INIT) {
        c->n.init_sent++;
    } else {
        c->n.cyclic_sent++;
    }
}

void cs_set_deadline(cs_t *c, uint64_t deadline_ns)
{
    if (c->out.active) {
        c->out.deadline_ns = deadline_ns;
    }
}

int cs_sent_stamp(cs_t *c, uint64_t stamp_ns, uint64_t now_ns)
{
    cs_outstanding_t *o = &c->out;
    /* the send happened after the caller's clock read before it, and before now */
    if (o->active && stamp_ns != 0U && stamp_ns + 200000U >= o->sent_ns && stamp_ns <= now_ns) {
        o->sent_ns = stamp_ns;
        return 1;
    }
    return 0;
}

void cs_foreign(cs_t *c)
{
    c->n.rx_total++;
    c->n.foreign++;
}

static int32_t cs_get_num(const uint8_t *b)
{
    return (int32_t)((uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) |
                     ((uint32_t)b[3] << 24));
}

/* The per-kind check of a reply whose NUM is right; CS_RX_ACCEPTED or why not. */
static cs_rx_t cs_check_body(cs_t *c, const uint8_t *buf, size_t len, c4g_pc_packet_t *pkt)
{
    const cs_outstanding_t *o = &c->out;
    switch (o->kind) {
    case CS_SYNC:
        return (len == C4G_SYNC_REPLY_SIZE) ? CS_RX_ACCEPTED : CS_RX_BAD_LENGTH;
    case CS_INIT:
        /* the init packet echoed: only NUM may differ */
        return (len == C4G_INIT_SIZE && o->len == C4G_INIT_SIZE &&
                memcmp(&buf[4], &o->raw[4], C4G_INIT_SIZE - 4U) == 0)
                   ? CS_RX_ACCEPTED
                   : CS_RX_BAD_INIT;
    case CS_CYCLIC:
    default:
        return (c4g_pc_decode(buf, len, c->cfg.n_axes, pkt, &c->last_diag) == C4G_OK)
                   ? CS_RX_ACCEPTED
                   : CS_RX_BAD_DECODE;
    }
}

cs_rx_t cs_reply(cs_t *c, const uint8_t *buf, size_t len, uint64_t at_ns)
{
    cs_outstanding_t *o = &c->out;
    c4g_pc_packet_t pkt;
    cs_rx_t r;
    c->n.rx_total++;
    if (!o->active || !o->check) {
        c->n.unexpected++;
        return CS_RX_UNEXPECTED;
    }
    if (len < 4U) {
        c->n.malformed++;
        return CS_RX_SHORT;
    }
    c->last_num = cs_get_num(buf);
    if (!cs_num_ok(c, o->num, c->last_num)) {
        if (cs_is_stale(c, o->num, c->last_num)) {
            c->n.stale++;
            return CS_RX_STALE;
        }
        c->n.wrong_num++;
        return CS_RX_WRONG_NUM;
    }
    r = cs_check_body(c, buf, len, &pkt);
    if (r != CS_RX_ACCEPTED) {
        c->n.malformed++;
        return r;
    }
    if (o->got) {
        c->n.duplicates++;
        return CS_RX_DUPLICATE;
    }
    /* judged at the next tick against the packet's deadline (cs_judge), by arrival time */
    o->got = 1;
    o->got_ns = at_ns;
    /* "either" locks on the init echo: its 1200 bytes cannot be confused with a late
     * reply to a sync packet, so its NUM (11 or 10) shows the PC's policy */
    if (o->kind == CS_INIT && c->cfg.policy == CS_NUM_EITHER) {
        c->detected = (c->last_num == o->num) ? CS_NUM_ECHO : CS_NUM_PLUS_ONE;
    }
    if (o->kind == CS_CYCLIC) {
        o->reply = pkt;
    }
    return CS_RX_ACCEPTED;
}

/* ---- deadlines ----------------------------------------------------------- */

static void cs_count_latency(cs_counters_t *n, uint64_t lat)
{
    if (n->replies_ok == 0U || lat < n->lat_min) {
        n->lat_min = lat;
    }
    if (lat > n->lat_max) {
        n->lat_max = lat;
    }
    n->lat_sum += lat;
    c4g_hist_add(&n->lat, (int64_t)lat);
    n->replies_ok++;
}

cs_verdict_t cs_judge(cs_t *c, uint64_t woke_ns, int suspended)
{
    cs_outstanding_t *o = &c->out;
    int own_late;
    cs_verdict_t v;
    c->last_late = 0;
    c->last_stale = 0;
    c->fatal = 0;
    if (!o->active) {
        return CS_J_NONE;
    }
    o->active = 0;
    if (!o->check || suspended) {
        return CS_J_NONE;
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
        return CS_J_OK;
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
        v = CS_J_UNJUDGED;
    } else {
        c->n.missing++;
        v = CS_J_MISSING;
    }
    if (c->n.consecutive > c->n.max_consecutive) {
        c->n.max_consecutive = c->n.consecutive;
    }
    c->fatal = c->n.consecutive >= c->cfg.max_miss;
    return v;
}

const c4g_pc_packet_t *cs_take_reply(cs_t *c)
{
    const int ok = c->out.kind == CS_CYCLIC && c->out.answered;
    c->out.answered = 0;
    return ok ? &c->out.reply : NULL;
}

/* ---- reporting ----------------------------------------------------------- */

double cs_lat_percentile(const cs_counters_t *n, double q)
{
    return c4g_hist_us(&n->lat, q);
}

const char *cs_policy_name(int policy)
{
    switch (policy) {
    case CS_NUM_PLUS_ONE:
        return "plus-one";
    case CS_NUM_ECHO:
        return "echo";
    case CS_NUM_EITHER:
        return "either";
    default:
        return "unknown";
    }
}
