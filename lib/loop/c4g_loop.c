/* SPDX-License-Identifier: MIT */
/* The PC-side loop object: session + control engine, so that the safety filter and the
 * neutral fallback are on the only path a reply can take. */
#include "../c4g_internal.h"

#include <string.h>

c4g_status_t c4g_loop_init(c4g_loop_t *lp, const c4g_loop_config_t *cfg)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (lp != NULL) {
        (void)memset(lp, 0, sizeof *lp);
        if (cfg != NULL) {
            lp->priv.engine_cfg = cfg->engine;
            /* an engine configuration refused now, not at every init packet (which would
             * leave every reply to the fallback) */
            st = c4g_engine_config_check(&cfg->engine);
            if (st == C4G_OK) {
                st = c4g_session_init(&lp->session, &cfg->session);
            }
        } else {
            (void)c4g_engine_config_default(&lp->priv.engine_cfg);
            st = c4g_session_init(&lp->session, NULL);
        }
    }
    return st;
}

/* The reply when the safety filter cannot be run on one (no engine for the packet, a reply
 * the caller broke, an encoder refusal): every axis holds (c4g_session_neutral), and every
 * arm with an axis in a mode where the PC moves it gets 505, the PC's right at any time. */
static void loop_fallback(c4g_loop_t *lp)
{
    const uint32_t pc_moves = C4G_MR_ABS | C4G_MR_INT_D1 | C4G_MR_INT_D2 | C4G_MR_INT_D4 |
                              C4G_MR_VADD | C4G_MR_CUR | C4G_MR_DCUR;
    uint32_t stop = 0U;
    uint32_t i;
    lp->counters.neutral_replies++;
    /* cannot fail: the session decoded rx for its own axis map */
    (void)c4g_session_neutral(&lp->session, lp->priv.rx, &lp->priv.tx);
    for (i = 0U; (i < lp->priv.tx.n_axes) && (i < C4G_MAX_AXES); i++) {
        if ((c4g_mode_rules(lp->priv.tx.ax[i].mode) & pc_moves) != 0U) {
            stop |= 1U << (lp->session.map.arm_of[i] & 3U);
        }
    }
    if (stop != 0U) {
        lp->counters.fallback_drive_off++;
        for (i = 0U; (i < lp->priv.tx.n_axes) && (i < C4G_MAX_AXES); i++) {
            if (((stop >> (lp->session.map.arm_of[i] & 3U)) & 1U) != 0U) {
                lp->priv.tx.ax[i].mode = C4G_MODE_DRIVE_OFF;
            }
        }
    }
}

/* A cyclic packet through the control engine: its reply prepared, or the fallback. */
static void loop_step(c4g_loop_t *lp, const c4g_ctrl_packet_t *pkt, uint64_t now_ns,
                      c4g_loop_event_t *ev)
{
    c4g_status_t st = C4G_ERR_STATE;
    lp->priv.rx = pkt;
    lp->priv.prepared = 0U;
    if (lp->engine_ready != 0U) {
        /* clears report; pkt comes from the session's decoder, which checked it */
        st = c4g_engine_step_decoded(&lp->engine, pkt, now_ns, &lp->priv.tx, &lp->report);
    }
    if (st == C4G_OK) {
        lp->priv.prepared = 1U;
        ev->cmd = &lp->priv.tx;
        ev->engine_events = lp->report.events;
    } else {
        /* no engine for this packet: only the fallback is safe */
        (void)memset(&lp->report, 0, sizeof lp->report);
        loop_fallback(lp);
    }
}

/* The user limits kept by the loop, on a freshly started engine: 0 if one of an open
 * axis was refused. */
static uint32_t apply_user_limits(c4g_loop_t *lp)
{
    uint32_t ok = 1U;
    uint32_t a;
    uint32_t j;
    for (a = 0U; a < C4G_ARMS; a++) {
        for (j = 0U; j < C4G_AXES_PER_ARM; j++) {
            if ((((lp->priv.user_set[a] >> j) & 1U) != 0U) &&
                (lp->engine.map.open_of[a][j] != 0xFFU) &&
                (c4g_engine_set_limits(&lp->engine, a, j, &lp->priv.user_lim[a][j]) != C4G_OK)) {
                ok = 0U;
            }
        }
    }
    return ok;
}

/* An accepted init packet (re)starts the control engine with the user's limits. */
static void loop_engine_init(c4g_loop_t *lp)
{
    lp->engine_ready = 0U;
    if (c4g_engine_init(&lp->engine, &lp->session.init, &lp->priv.engine_cfg) != C4G_OK) {
        lp->counters.engine_init_refused++;
    } else if (apply_user_limits(lp) == 0U) {
        lp->counters.limits_refused++;
    } else {
        lp->engine_ready = 1U;
    }
}

c4g_status_t c4g_loop_set_limits(c4g_loop_t *lp, uint32_t arm, uint32_t axis,
                                 const c4g_axis_limits_t *lim)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (lim != NULL)) {
        st = C4G_ERR_ARG;
        if ((arm < C4G_ARMS) && (axis < C4G_AXES_PER_ARM)) {
            st = C4G_OK;
            if ((lp->engine_ready != 0U) && (lp->engine.map.open_of[arm][axis] != 0xFFU)) {
                st = c4g_engine_set_limits(&lp->engine, arm, axis, lim);
            }
        }
        if (st == C4G_OK) {
            lp->priv.user_lim[arm][axis] = *lim;
            lp->priv.user_set[arm] |= (uint32_t)1U << axis;
        }
    }
    return st;
}

c4g_status_t c4g_loop_rx(c4g_loop_t *lp, const uint8_t *buf, size_t len, uint64_t now_ns,
                         const c4g_endpoint_t *from, c4g_loop_event_t *ev)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (ev != NULL)) {
        c4g_rx_result_t res;
        (void)memset(ev, 0, sizeof *ev);
        lp->priv.due = 0U;
        lp->priv.rx = NULL;
        st = c4g_session_rx_from(&lp->session, buf, len, now_ns, from, &res);
        if (st == C4G_OK) {
            ev->kind = res.kind;
            ev->events = res.events;
            ev->pkt = res.pkt;
            ev->diag = res.diag;
            ev->silence_ns = res.silence_ns;
            if (res.kind == C4G_RX_INIT) {
                loop_engine_init(lp);
            }
            if (res.kind == C4G_RX_CYCLIC) {
                loop_step(lp, res.pkt, now_ns, ev);
            }
            if (res.kind != C4G_RX_DROPPED) {
                lp->priv.due = 1U;
            }
        }
    }
    return st;
}

/* The cyclic reply: the safety filter, then the encoder; neutral when nothing was prepared,
 * when the engine refused the packet, or when the encoder refuses what the caller wrote. */
static c4g_status_t loop_cyclic_reply(c4g_loop_t *lp, uint8_t *buf, size_t cap, size_t *out_len)
{
    c4g_status_t st;
    lp->finish_status = C4G_OK;
    if (lp->priv.prepared != 0U) {
        /* after any other status the filtered reply is safe and must be sent (an arm may
         * carry 505): only a refused call (the caller changed the reply's axis count or
         * header) falls back */
        lp->finish_status = c4g_safety_filter(&lp->engine, lp->priv.rx, &lp->priv.tx, &lp->report);
        if (lp->finish_status == C4G_ERR_STATE) {
            loop_fallback(lp);
        }
        lp->priv.prepared = 0U;
    } /* else the fallback was prepared with the packet */
    st = c4g_session_reply(&lp->session, &lp->priv.tx, buf, cap, out_len);
    if ((st != C4G_OK) && (st != C4G_ERR_CAPACITY)) {
        /* the encoder refused the reply: not reached after the filter, kept as a guard */
        lp->counters.encode_refused++;
        loop_fallback(lp);
        st = c4g_session_reply(&lp->session, &lp->priv.tx, buf, cap, out_len);
    }
    return st;
}

c4g_status_t c4g_loop_reply(c4g_loop_t *lp, uint8_t *buf, size_t cap, size_t *out_len,
                            c4g_engine_report_t *rep)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (buf != NULL) && (out_len != NULL)) {
        if (lp->priv.due == 0U) {
            st = C4G_ERR_STATE;
        } else if (lp->priv.rx == NULL) {
            st = c4g_session_reply(&lp->session, NULL, buf, cap, out_len);
        } else {
            st = loop_cyclic_reply(lp, buf, cap, out_len);
            if (rep != NULL) {
                *rep = lp->report;
            }
        }
        if (st == C4G_OK) {
            lp->priv.due = 0U;
            lp->priv.timed = c4g_flag(lp->priv.rx != NULL);
        }
    }
    return st;
}

c4g_status_t c4g_loop_sent(c4g_loop_t *lp, uint64_t now_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (lp != NULL) {
        st = C4G_OK;
        if (lp->priv.timed != 0U) {
            lp->priv.timed = 0U;
            st = c4g_session_sent(&lp->session, now_ns);
        }
    }
    return st;
}

/* t + d + 1 without wrapping: the session's checks fire once the gap EXCEEDS d */
static uint64_t after(uint64_t t, uint64_t d)
{
    const uint64_t room = C4G_NO_DEADLINE - t;
    return (d < room) ? ((t + d) + 1U) : C4G_NO_DEADLINE;
}

/* The first instant at which the session's silence/loss check (c4g_session_poll) changes
 * something, from the same conditions; C4G_NO_DEADLINE when only a datagram can. */
static uint64_t session_deadline(const c4g_session_t *s)
{
    uint64_t next = C4G_NO_DEADLINE;
    if ((s->phase == C4G_PHASE_REFUSED) ||
        ((s->phase == C4G_PHASE_WAIT_INIT) && (s->priv.sync_seen > 0U))) {
        next = after(s->priv.last_rx_ns, s->lost_timeout_ns);
    } else if (((s->phase == C4G_PHASE_CYCLIC) || (s->phase == C4G_PHASE_POST_SYNC)) &&
               (s->priv.frozen == 0U) && (s->priv.frozen_active == 0U)) {
        next = after(s->priv.last_rx_ns, s->lost_timeout_ns);
        if ((s->priv.silent == 0U) && (s->silence_ns < s->lost_timeout_ns)) {
            next = after(s->priv.last_rx_ns, s->silence_ns);
        }
    } else {
        /* no silence check in this phase */
    }
    return next;
}

c4g_status_t c4g_loop_deadline(const c4g_loop_t *lp, uint64_t *next_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (next_ns != NULL)) {
        *next_ns = session_deadline(&lp->session);
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_loop_poll(c4g_loop_t *lp, uint64_t now_ns, uint32_t *events, uint64_t *next_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (next_ns != NULL)) {
        st = c4g_session_poll(&lp->session, now_ns, events);
        *next_ns = session_deadline(&lp->session);
    }
    return st;
}

c4g_status_t c4g_loop_init_packet(const c4g_loop_t *lp, const c4g_init_t **out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        *out = &lp->session.init;
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_loop_axis_map(const c4g_loop_t *lp, const c4g_axis_map_t **out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        *out = &lp->session.map;
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_loop_counters(const c4g_loop_t *lp, const c4g_counters_t **session,
                               const c4g_loop_counters_t **loop)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && ((session != NULL) || (loop != NULL))) {
        if (session != NULL) {
            *session = &lp->session.counters;
        }
        if (loop != NULL) {
            *loop = &lp->counters;
        }
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_loop_timing(const c4g_loop_t *lp, c4g_timing_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (lp != NULL) {
        st = c4g_session_timing(&lp->session, out);
    }
    return st;
}

c4g_status_t c4g_loop_state(const c4g_loop_t *lp, c4g_loop_state_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        const c4g_session_t *s = &lp->session;
        out->phase = s->phase;
        out->locked = (s->peer_locked != 0U);
        out->peer = s->peer;
        out->last_num = s->priv.last_num;
        out->drives = s->drives;
        out->silence_ns = s->silence_ns;
        out->lost_timeout_ns = s->lost_timeout_ns;
        out->engine_ready = (lp->engine_ready != 0U);
        out->finish_status = lp->finish_status;
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_loop_engine_view(const c4g_loop_t *lp, const c4g_engine_t **out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        *out = &lp->engine;
        st = (lp->engine_ready != 0U) ? C4G_OK : C4G_ERR_STATE;
    }
    return st;
}

c4g_status_t c4g_loop_reply_packet(const c4g_loop_t *lp, const c4g_pc_packet_t **out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        *out = &lp->priv.tx;
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_loop_is_peer(const c4g_loop_t *lp, const c4g_endpoint_t *from, bool *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (from != NULL) && (out != NULL)) {
        *out = c4g_session_is_peer(&lp->session, from);
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_loop_engine(c4g_loop_t *lp, c4g_engine_t **out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        *out = &lp->engine;
        st = (lp->engine_ready != 0U) ? C4G_OK : C4G_ERR_STATE;
    }
    return st;
}

c4g_status_t c4g_loop_exit_pending(const c4g_loop_t *lp, uint32_t arm, bool *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        *out = false;
        if (arm >= C4G_ARMS) {
            st = C4G_ERR_ARG;
        } else if (lp->engine_ready == 0U) {
            st = C4G_ERR_STATE;
        } else {
            const c4g_arm_sm_t *sm = &lp->engine.arm[arm];
            *out = (sm->exit_req != 0U) || (sm->leaving != 0U);
            st = C4G_OK;
        }
    }
    return st;
}

c4g_status_t c4g_loop_limits(const c4g_loop_t *lp, uint32_t axis, c4g_axis_limits_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((lp != NULL) && (out != NULL)) {
        if (lp->engine_ready == 0U) {
            st = C4G_ERR_STATE;
        } else if (axis >= lp->engine.map.n_axes) {
            st = C4G_ERR_ARG;
        } else {
            *out = lp->engine.lim[axis];
            st = C4G_OK;
        }
    }
    return st;
}
