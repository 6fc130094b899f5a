/* SPDX-License-Identifier: MIT */
/* The controller end of C4G Open without I/O: see c4gopen_ctrl.h. */
#include "../c4g_internal.h"

c4g_status_t c4g_ctrl_init(c4g_ctrl_t *c, const c4g_ctrl_config_t *cfg)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((c != NULL) && (cfg != NULL)) {
        if ((cfg->policy > C4G_NUM_EITHER) || (cfg->n_axes > C4G_MAX_AXES)) {
            st = C4G_ERR_ARG;
        } else {
            (void)memset(c, 0, sizeof *c);
            c->cfg = *cfg;
            c->phase = (cfg->sync_before > 0U) ? C4G_CTRL_PH_SYNC_PRE : C4G_CTRL_PH_INIT;
            c->left = cfg->sync_before;
            c->cold = 1U;
            c->num = 1;
            c->detected = -1;
            c->out.deadline_ns = UINT64_MAX;
            st = C4G_OK;
        }
    }
    return st;
}

/* ---- handshake driver ---------------------------------------------------- */

c4g_pkt_kind_t c4g_ctrl_next_kind(const c4g_ctrl_t *c)
{
    c4g_pkt_kind_t k = C4G_PKT_CYCLIC;
    if ((c->phase == C4G_CTRL_PH_SYNC_PRE) || (c->phase == C4G_CTRL_PH_SYNC_POST)) {
        k = C4G_PKT_SYNC;
    } else if (c->phase == C4G_CTRL_PH_INIT) {
        k = C4G_PKT_INIT;
    } else {
        /* cyclic */
    }
    return k;
}

int32_t c4g_ctrl_next_num(const c4g_ctrl_t *c)
{
    return (c->phase == C4G_CTRL_PH_INIT) ? C4G_INIT_NUM : c->num;
}

c4g_status_t c4g_ctrl_advance(c4g_ctrl_t *c)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (c != NULL) {
        st = C4G_OK;
        if ((c->phase == C4G_CTRL_PH_SYNC_PRE) || (c->phase == C4G_CTRL_PH_SYNC_POST)) {
            c->num = c4g_num_next(c->num);
            if (c->left > 0U) {
                c->left--;
            }
            if (c->left == 0U) {
                c->phase = (c->phase == C4G_CTRL_PH_SYNC_PRE) ? C4G_CTRL_PH_INIT : C4G_CTRL_PH_CYCLIC;
            }
        } else if (c->phase == C4G_CTRL_PH_INIT) {
            /* the syncs after the init packet belong to the first start only (a restart
             * goes straight to cyclic packets) */
            c->num = C4G_INIT_NUM + 1;
            c->left = c->cfg.sync_after;
            c->phase = ((c->cold != 0U) && (c->cfg.sync_after > 0U)) ? C4G_CTRL_PH_SYNC_POST
                                                                      : C4G_CTRL_PH_CYCLIC;
            c->cold = 0U;
        } else {
            c->num = c4g_num_next(c->num);
        }
    }
    return st;
}

c4g_status_t c4g_ctrl_restart(c4g_ctrl_t *c)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (c != NULL) {
        c->phase = C4G_CTRL_PH_INIT;
        st = C4G_OK;
    }
    return st;
}

/* ---- NUM policy ---------------------------------------------------------- */

c4g_num_policy_t c4g_ctrl_policy(const c4g_ctrl_t *c)
{
    /* "either": the PC may use one or the other, but consistently; its echo of the init
     * packet decides (otherwise a late plus-one reply would pass as the next echo) */
    c4g_num_policy_t p = c->cfg.policy;
    if ((p == C4G_NUM_EITHER) && (c->detected == (int32_t)C4G_NUM_ECHO)) {
        p = C4G_NUM_ECHO;
    } else if ((p == C4G_NUM_EITHER) && (c->detected == (int32_t)C4G_NUM_PLUS_ONE)) {
        p = C4G_NUM_PLUS_ONE;
    } else {
        /* as configured */
    }
    return p;
}

/* ---- replies ------------------------------------------------------------- */

c4g_status_t c4g_ctrl_emit(c4g_ctrl_t *c, c4g_pkt_kind_t kind, int32_t num, const uint8_t *buf,
                           size_t len, bool check, uint64_t sent_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((c != NULL) && (buf != NULL)) {
        c4g_ctrl_outstanding_t *o = &c->out;
        st = C4G_OK;
        if (kind == C4G_PKT_SYNC) {
            c->n.sync_sent++;
        } else if (kind == C4G_PKT_INIT) {
            c->n.init_sent++;
        } else if (kind == C4G_PKT_CYCLIC) {
            c->n.cyclic_sent++;
        } else {
            st = C4G_ERR_ARG;
        }
        if (st == C4G_OK) {
            o->active = 1U;
            o->check = c4g_flag(check);
            o->kind = kind;
            o->num = num;
            o->answered = 0U;
            o->got = 0U;
            o->deadline_ns = UINT64_MAX; /* the caller sets it once the next tick is known */
            o->len = (len <= sizeof o->raw) ? len : sizeof o->raw;
            (void)memcpy(o->raw, buf, o->len);
            o->sent_ns = sent_ns;
        }
    }
    return st;
}

c4g_status_t c4g_ctrl_set_deadline(c4g_ctrl_t *c, uint64_t deadline_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (c != NULL) {
        st = C4G_ERR_STATE;
        if (c->out.active != 0U) {
            c->out.deadline_ns = deadline_ns;
            st = C4G_OK;
        }
    }
    return st;
}

c4g_status_t c4g_ctrl_sent_stamp(c4g_ctrl_t *c, uint64_t stamp_ns, uint64_t now_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (c != NULL) {
        c4g_ctrl_outstanding_t *o = &c->out;
        if (o->active == 0U) {
            st = C4G_ERR_STATE;
        } else if ((stamp_ns != 0U) && ((stamp_ns + C4G_CTRL_STAMP_SLACK_NS) >= o->sent_ns) &&
                   (stamp_ns <= now_ns)) {
            /* the send happened after the caller's clock read before it, and before now */
            o->sent_ns = stamp_ns;
            st = C4G_OK;
        } else {
            st = C4G_ERR_ARG;
        }
    }
    return st;
}

c4g_status_t c4g_ctrl_foreign(c4g_ctrl_t *c)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (c != NULL) {
        c->n.rx_total++;
        c->n.foreign++;
        st = C4G_OK;
    }
    return st;
}

/* The per-kind check of a reply whose NUM is right; C4G_CTRL_RX_ACCEPTED or why not. */
static c4g_ctrl_rx_t check_body(c4g_ctrl_t *c, const uint8_t *buf, size_t len, c4g_pc_packet_t *pkt)
{
    const c4g_ctrl_outstanding_t *o = &c->out;
    c4g_ctrl_rx_t r = C4G_CTRL_RX_ACCEPTED;
    if (o->kind == C4G_PKT_SYNC) {
        if (len != C4G_SYNC_REPLY_SIZE) {
            r = C4G_CTRL_RX_BAD_LENGTH;
        }
    } else if (o->kind == C4G_PKT_INIT) {
        /* the init packet echoed: only NUM may differ */
        if ((len != C4G_INIT_SIZE) || (o->len != C4G_INIT_SIZE) ||
            (memcmp(&buf[4], &o->raw[4], C4G_INIT_SIZE - 4U) != 0)) {
            r = C4G_CTRL_RX_BAD_INIT;
        }
    } else {
        if (c4g_pc_decode(buf, len, c->cfg.n_axes, pkt, &c->last_diag) != C4G_OK) {
            r = C4G_CTRL_RX_BAD_DECODE;
        }
    }
    return r;
}

/* A reply with the right NUM and body: the first one is kept for the judgement. */
static c4g_ctrl_rx_t take_valid(c4g_ctrl_t *c, const c4g_pc_packet_t *pkt, uint64_t at_ns)
{
    c4g_ctrl_outstanding_t *o = &c->out;
    c4g_ctrl_rx_t r = C4G_CTRL_RX_ACCEPTED;
    if (o->got != 0U) {
        c->n.duplicates++;
        r = C4G_CTRL_RX_DUPLICATE;
    } else {
        /* judged at the next tick against the packet's deadline, by arrival time */
        o->got = 1U;
        o->got_ns = at_ns;
        /* "either" locks on the init echo: its 1200 bytes cannot be confused with a late
         * reply to a sync packet, so its NUM (11 or 10) shows the PC's policy */
        if ((o->kind == C4G_PKT_INIT) && (c->cfg.policy == C4G_NUM_EITHER)) {
            c->detected = (c->last_num == o->num) ? (int32_t)C4G_NUM_ECHO : (int32_t)C4G_NUM_PLUS_ONE;
        }
        if (o->kind == C4G_PKT_CYCLIC) {
            o->reply = *pkt;
        }
    }
    return r;
}

static c4g_ctrl_rx_t judge_reply(c4g_ctrl_t *c, const uint8_t *buf, size_t len, uint64_t at_ns)
{
    const c4g_ctrl_outstanding_t *o = &c->out;
    c4g_ctrl_rx_t r;
    if ((o->active == 0U) || (o->check == 0U)) {
        c->n.unexpected++;
        r = C4G_CTRL_RX_UNEXPECTED;
    } else if (len < 4U) {
        c->n.malformed++;
        r = C4G_CTRL_RX_SHORT;
    } else {
        const c4g_num_policy_t pol = c4g_ctrl_policy(c);
        c->last_num = c4g_get_i32le(buf);
        if (!c4g_num_accepts(pol, o->num, c->last_num)) {
            if (c4g_num_answers_recent(pol, o->num, c->last_num, C4G_CTRL_STALE_WINDOW)) {
                c->n.stale++;
                r = C4G_CTRL_RX_STALE;
            } else {
                c->n.wrong_num++;
                r = C4G_CTRL_RX_WRONG_NUM;
            }
        } else {
            c4g_pc_packet_t pkt;
            r = check_body(c, buf, len, &pkt);
            if (r != C4G_CTRL_RX_ACCEPTED) {
                c->n.malformed++;
            } else {
                r = take_valid(c, &pkt, at_ns);
            }
        }
    }
    return r;
}

c4g_status_t c4g_ctrl_reply(c4g_ctrl_t *c, const uint8_t *buf, size_t len, uint64_t at_ns,
                            c4g_ctrl_rx_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((c != NULL) && (out != NULL) && ((buf != NULL) || (len == 0U))) {
        c->n.rx_total++;
        *out = judge_reply(c, buf, len, at_ns);
        st = C4G_OK;
    }
    return st;
}

/* ---- deadlines ----------------------------------------------------------- */

static void count_ok(c4g_ctrl_t *c, uint64_t lat)
{
    c4g_ctrl_counters_t *n = &c->n;
    c->out.answered = 1U;
    n->consecutive = 0U;
    if (lat > c->cfg.t_cycle1_ns) {
        n->late++;
        c->last_late = 1U;
    }
    if ((n->replies_ok == 0U) || (lat < n->lat_min)) {
        n->lat_min = lat;
    }
    if (lat > n->lat_max) {
        n->lat_max = lat;
    }
    n->lat_sum += lat;
    n->replies_ok++;
    c->last_lat_ns = lat;
}

/* Unjudged or missing, it is a packet without a reply: both extend the run that ends in
 * ERR_C4GOPEN_UDP; only a missing one is the PC's fault. */
static c4g_ctrl_verdict_t count_none(c4g_ctrl_t *c, bool own_late)
{
    c4g_ctrl_counters_t *n = &c->n;
    c4g_ctrl_verdict_t v = C4G_CTRL_J_MISSING;
    if (c->out.got != 0U) {
        n->stale++; /* it came, after its deadline */
        c->last_stale = 1U;
    }
    n->consecutive++;
    if (own_late) {
        n->unjudged++;
        v = C4G_CTRL_J_UNJUDGED;
    } else {
        n->missing++;
    }
    if (n->consecutive > n->max_consecutive) {
        n->max_consecutive = n->consecutive;
    }
    c->fatal = c4g_flag(n->consecutive >= (uint64_t)c->cfg.max_miss);
    return v;
}

static c4g_ctrl_verdict_t judge(c4g_ctrl_t *c, uint64_t woke_ns, bool suspended)
{
    c4g_ctrl_outstanding_t *o = &c->out;
    c4g_ctrl_verdict_t v = C4G_CTRL_J_NONE;
    if (o->active != 0U) {
        o->active = 0U;
        if (suspended && (o->got != 0U)) {
            /* not checked, not counted, yet handed over: the reply that ends an active
             * freezing (EXIT_FROM_OPEN) comes while the checks are suspended */
            o->answered = 1U;
        } else if ((o->check != 0U) && !suspended) {
            /* Woken past the deadline, the caller could not see it pass: a reply that was
             * there when it looked counts, and no reply is not the PC's fault alone (the
             * whole host may have stalled). */
            const bool own_late = (woke_ns > o->deadline_ns) && ((woke_ns - o->deadline_ns) > c->cfg.tol_ns);
            const uint64_t limit = own_late ? woke_ns : o->deadline_ns;
            if ((o->got != 0U) && (o->got_ns <= limit)) {
                count_ok(c, (o->got_ns > o->sent_ns) ? (o->got_ns - o->sent_ns) : 0U);
                v = C4G_CTRL_J_OK;
            } else {
                v = count_none(c, own_late);
            }
        } else {
            /* not checked (504), or suspended without a reply */
        }
    }
    return v;
}

c4g_status_t c4g_ctrl_judge(c4g_ctrl_t *c, uint64_t woke_ns, bool suspended, c4g_ctrl_verdict_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((c != NULL) && (out != NULL)) {
        c->last_late = 0U;
        c->last_stale = 0U;
        c->fatal = 0U;
        *out = judge(c, woke_ns, suspended);
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_ctrl_take_reply(c4g_ctrl_t *c, const c4g_pc_packet_t **reply)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((c != NULL) && (reply != NULL)) {
        const bool ok = (c->out.kind == C4G_PKT_CYCLIC) && (c->out.answered != 0U);
        c->out.answered = 0U;
        *reply = ok ? &c->out.reply : NULL;
        st = ok ? C4G_OK : C4G_ERR_STATE;
    }
    return st;
}
