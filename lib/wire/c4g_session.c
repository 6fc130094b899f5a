/* SPDX-License-Identifier: MIT */
/* PC-side session engine: start-up handshake (field facts), NUM policy, counters and
 * the chapter 22 timing statistics. I/O-free: the caller passes datagrams and times. */
#include "../c4g_internal.h"
#include "c4g_wire_hot.h"

#define DEFAULT_POST_INIT_SYNC 2U
#define SILENCE_PERIODS 10U         /* the controller itself gives up after 10 missed replies */
#define LOST_DEFAULT_NS 1000000000U /* the field library's real-time wait in the cyclic phase */
#define NS_PER_MS 1000000U
#define NUM_HALF 0x4000
#define MAX_POST_INIT_SYNC 100U
#define INIT_BLOCKS 14U /* the init packet's fields and blocks of 40, in their order */

c4g_status_t c4g_session_config_default(c4g_session_config_t *cfg)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (cfg != NULL) {
        cfg->num_policy = C4G_NUM_PLUS_ONE;
        cfg->lost_timeout_ns = 0U;
        cfg->silence_ns = 0U;
        cfg->post_init_sync = DEFAULT_POST_INIT_SYNC;
        cfg->az_lim_max = C4G_AZLIM_MAX_DEFAULT;
        cfg->follow_error_max = C4G_FOLLOW_ERROR_MAX_DEFAULT;
        st = C4G_OK;
    }
    return st;
}

/* A ceiling is a finite positive number. */
static int ceiling_ok(float v)
{
    return ((c4g_f32_finite(v) != 0) && (v > 0.0F)) ? 1 : 0;
}

c4g_status_t c4g_session_init(c4g_session_t *s, const c4g_session_config_t *cfg)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (s != NULL) {
        c4g_session_config_t c;
        st = C4G_OK;
        if (cfg != NULL) {
            c = *cfg;
        } else {
            (void)c4g_session_config_default(&c);
        }
        if (((c.num_policy != C4G_NUM_PLUS_ONE) && (c.num_policy != C4G_NUM_ECHO)) ||
            (c.post_init_sync > MAX_POST_INIT_SYNC) || (ceiling_ok(c.az_lim_max) == 0) ||
            (ceiling_ok(c.follow_error_max) == 0)) {
            st = C4G_ERR_ARG;
        } else {
            (void)memset(s, 0, sizeof *s);
            s->cfg = c;
            s->phase = C4G_PHASE_WAIT_INIT;
            s->priv.last_num = -1;
            s->priv.pending_num = -1;
            s->priv.pending_kind = C4G_RX_DROPPED;
            /* effective from the start: a REFUSED start-up ends on it too */
            s->lost_timeout_ns =
                (c.lost_timeout_ns != 0U) ? c.lost_timeout_ns : (uint64_t)LOST_DEFAULT_NS;
        }
    }
    return st;
}

static void count_malformed(c4g_session_t *s, c4g_status_t st, c4g_rx_result_t *res)
{
    c4g_malformed_t why = C4G_MAL_LENGTH;
    if (st == C4G_ERR_NUM) {
        why = C4G_MAL_NUM;
    } else if (st == C4G_ERR_MODE) {
        why = C4G_MAL_MODE;
    } else if (st == C4G_ERR_NONFINITE) {
        why = C4G_MAL_NONFINITE;
    } else if (st != C4G_ERR_LENGTH) {
        why = C4G_MAL_INIT; /* every other reason comes from the init validator */
    } else {
        /* length: the default */
    }
    s->counters.malformed[why]++;
    s->counters.malformed_total++;
    res->kind = C4G_RX_DROPPED;
    res->events |= C4G_EV_MALFORMED;
}

/* How far @p num is ahead of the newest NUM, modulo the SMP+ counter (0: the same). */
static int32_t num_delta(const c4g_session_t *s, int32_t num)
{
    return c4g_num_wrap_delta(s->priv.last_num, num);
}

/* A duplicate (delta 0) or an older NUM (delta in the back half of the counter) is
 * counted and dropped: answered already, or its moment has passed, and acting on it would
 * move the engine back in time. Returns 1 when the packet is dropped. */
static int drop_stale(c4g_session_t *s, int32_t num, c4g_rx_result_t *res)
{
    const int32_t delta = num_delta(s, num);
    int r = 1;
    if (delta == 0) {
        s->counters.duplicates++;
        res->events |= C4G_EV_DUPLICATE;
    } else if (delta >= NUM_HALF) {
        s->counters.out_of_order++;
        res->events |= C4G_EV_OUT_OF_ORDER;
    } else {
        r = 0;
    }
    return r;
}

/* NUM bookkeeping of an accepted packet (SMP+ counts 0..0x7FFF and wraps to 0). */
static void track_num(c4g_session_t *s, int32_t num, c4g_rx_result_t *res)
{
    const int32_t delta = num_delta(s, num);
    if (delta > 1) {
        s->counters.gaps++;
        s->counters.missed += (uint64_t)delta - 1U;
        res->events |= C4G_EV_GAP;
    }
    s->priv.last_num = num;
}

static void arm_reply(c4g_session_t *s, c4g_rx_kind_t kind, int32_t num, const uint8_t *buf,
                      size_t len, uint64_t now_ns)
{
    s->priv.pending_kind = kind;
    s->priv.pending_num = num;
    s->priv.pending_rx_ns = now_ns;
    s->priv.pending_len = 0U;
    if ((kind != C4G_RX_CYCLIC) && (buf != NULL)) { /* (a decoded datagram has bytes) */
        /* Sync replies echo at most 732 bytes; the init echo is the full 1200, from
         * init_raw (which holds the accepted packet's bytes). */
        const size_t keep = (kind == C4G_RX_INIT) ? C4G_INIT_SIZE
                            : ((len < C4G_SYNC_REPLY_SIZE) ? len : C4G_SYNC_REPLY_SIZE);
        if (kind != C4G_RX_INIT) {
            (void)memcpy(s->priv.pending_raw, buf, keep);
        }
        s->priv.pending_len = (uint32_t)keep;
        s->priv.pending_reply_len = (kind == C4G_RX_INIT) ? (uint32_t)C4G_INIT_SIZE
                                                     : (uint32_t)C4G_SYNC_REPLY_SIZE;
    }
}

/* Where byte @p off of an initialization packet lies: the field, and for the per-axis
 * blocks the arm and logical axis (-1 otherwise). */
static c4g_field_t init_field_at(uint32_t off, int32_t *arm, int32_t *axis)
{
    static const uint32_t base[INIT_BLOCKS] = {0U, 4U, 8U, 12U, C4G_INIT_OFF_OPENMASK, C4G_INIT_OFF_TYPES,
                                    C4G_INIT_OFF_PERIOD, C4G_INIT_OFF_OPENAX,
                                    C4G_INIT_OFF_CALDATA, C4G_INIT_OFF_AZLIM,
                                    C4G_INIT_OFF_VERSION, C4G_INIT_OFF_AXINFO,
                                    C4G_INIT_OFF_TXRATE, C4G_INIT_OFF_FOLLOWERROR};
    static const c4g_field_t field[INIT_BLOCKS] = {C4G_FIELD_NUM, C4G_FIELD_NFIELDPCK, C4G_FIELD_NFIELDAX,
                                        C4G_FIELD_NAXOPEN, C4G_FIELD_OPENMASK, C4G_FIELD_TYPES,
                                        C4G_FIELD_PERIOD, C4G_FIELD_OPENAX, C4G_FIELD_CALDATA,
                                        C4G_FIELD_AZLIM, C4G_FIELD_VERSION, C4G_FIELD_AXINFO,
                                        C4G_FIELD_TXRATE, C4G_FIELD_FOLLOWERROR};
    /* the blocks of 40 values, one per arm and logical axis */
    static const uint8_t per_axis[INIT_BLOCKS] = {0U, 0U, 0U, 0U, 1U, 0U, 0U, 1U, 1U, 1U, 0U, 1U, 1U, 1U};
    uint32_t k = 0U;
    uint32_t i;
    for (i = 1U; i < INIT_BLOCKS; i++) {
        if (off >= base[i]) {
            k = i;
        }
    }
    *arm = -1;
    *axis = -1;
    if (per_axis[k] != 0U) {
        const uint32_t v = (off - base[k]) / 4U;
        const uint32_t a = v / C4G_AXES_PER_ARM;
        const uint32_t x = v % C4G_AXES_PER_ARM;
        *arm = (int32_t)a;
        *axis = (int32_t)x;
    }
    return field[k];
}

/* The PC's ceilings on the limits an initialization packet may set (open axes only; a
 * FollowError of 0 is the controller's "no threshold" and stays accepted). */
static c4g_status_t check_ceilings(const c4g_session_t *s, const c4g_init_t *in,
                                   const c4g_axis_map_t *map, c4g_diag_t *diag)
{
    c4g_status_t st = C4G_OK;
    uint32_t over = 0U;
    uint32_t arm;
    uint32_t ax;
    uint32_t i;
    /* the open axes through the map first: the ordered pass below only names a refusal */
    for (i = 0U; i < map->n_axes; i++) {
        const uint32_t a = map->arm_of[i] & 3U;
        const uint32_t x = map->logical_of[i] % C4G_AXES_PER_ARM;
        over |= c4g_flag((in->az_lim[a][x] > s->cfg.az_lim_max) ||
                         (in->follow_error[a][x] > s->cfg.follow_error_max));
    }
    for (arm = 0U; (over != 0U) && (arm < C4G_ARMS) && (st == C4G_OK); arm++) {
        for (ax = 0U; (ax < C4G_AXES_PER_ARM) && (st == C4G_OK); ax++) {
            const uint32_t at = (arm * C4G_AXES_PER_ARM * 4U) + (ax * 4U);
            const float a = in->az_lim[arm][ax];
            const float f = in->follow_error[arm][ax];
            if (in->open_ax[arm][ax] == C4G_OPEN_AX_NONE) {
                continue;
            }
            if (a > s->cfg.az_lim_max) {
                st = C4G_ERR_RANGE;
                c4g_diag_set(diag, st, C4G_FIELD_AZLIM, C4G_INIT_OFF_AZLIM + at, (int32_t)arm,
                             (int32_t)ax, (int64_t)c4g_f32_bits(a));
            } else if (f > s->cfg.follow_error_max) {
                st = C4G_ERR_RANGE;
                c4g_diag_set(diag, st, C4G_FIELD_FOLLOWERROR, C4G_INIT_OFF_FOLLOWERROR + at,
                             (int32_t)arm, (int32_t)ax, (int64_t)c4g_f32_bits(f));
            } else {
                /* within the ceilings */
            }
        }
    }
    return st;
}

/* Nothing is accepted or answered any more until the controller falls silent for the loss
 * timeout (check_lost): the fail-safe when the session cannot tell the controller's
 * packets from another sender's. */
static void refuse(c4g_session_t *s, uint64_t now_ns, c4g_rx_result_t *res)
{
    s->phase = C4G_PHASE_REFUSED;
    s->priv.pending_num = -1;
    s->priv.startup_init = 0U;
    s->priv.restart_pending = 0U;
    s->priv.frozen = 0U;
    s->priv.frozen_active = 0U;
    s->priv.last_rx_ns = now_ns;
    res->kind = C4G_RX_DROPPED;
}

/* A second initialization packet while one is held for this start-up (or after 506):
 * the same bytes are a duplicate (after 506: the restart); different bytes are refused
 * with the first one. Returns 1 when @p buf was handled here. */
static int second_init(c4g_session_t *s, const uint8_t *buf, uint64_t now_ns,
                       c4g_rx_result_t *res)
{
    uint32_t off = C4G_INIT_SIZE;
    int r = 0;
    /* from NUM on: the decoder has checked NUM (10) already; the first differing byte */
    if (memcmp(&buf[4], &s->priv.init_raw[4], (size_t)C4G_INIT_SIZE - 4U) != 0) {
        uint32_t i;
        for (i = 4U; (i < C4G_INIT_SIZE) && (off == C4G_INIT_SIZE); i++) {
            if (buf[i] != s->priv.init_raw[i]) {
                off = i;
            }
        }
    }
    if (off < C4G_INIT_SIZE) {
        int32_t arm;
        int32_t axis;
        const uint32_t at = off & ~3U;
        const c4g_field_t fld = init_field_at(at, &arm, &axis);
        c4g_diag_set(&res->diag, C4G_ERR_STATE, fld, at, arm, axis,
                     (int64_t)c4g_get_u32le(&buf[at]));
        s->counters.init_conflicts++;
        res->events |= C4G_EV_INIT_CONFLICT;
        refuse(s, now_ns, res);
        r = 1;
    } else if (s->priv.startup_init != 0U) {
        s->counters.duplicates++;
        res->events |= C4G_EV_DUPLICATE;
        res->kind = C4G_RX_DROPPED;
        r = 1;
    } else {
        /* after 506: the session's own init again, the restart goes on */
    }
    return r;
}

static void on_init(c4g_session_t *s, const uint8_t *buf, size_t len, uint64_t now_ns,
                    c4g_rx_result_t *res)
{
    c4g_init_t init;
    c4g_axis_map_t map;
    c4g_status_t st = C4G_OK;
    if ((s->phase != C4G_PHASE_WAIT_INIT) && (s->priv.restart_pending == 0U) &&
        (s->priv.startup_init == 0U)) {
        /* mid-session: new limits and thresholds are never taken from a datagram */
        c4g_diag_set(&res->diag, C4G_ERR_STATE, C4G_FIELD_NUM, 0U, -1, -1,
                     (int64_t)c4g_get_i32le(buf));
        s->counters.malformed[C4G_MAL_PHASE]++;
        s->counters.malformed_total++;
        res->kind = C4G_RX_DROPPED;
        res->events |= C4G_EV_MALFORMED;
        st = C4G_ERR_STATE;
    }
    if (st == C4G_OK) {
        st = c4g_init_decode_map(buf, len, &init, &map, &res->diag);
        if (st != C4G_OK) {
            count_malformed(s, st, res);
        }
    }
    if (st == C4G_OK) {
        st = check_ceilings(s, &init, &map, &res->diag);
        if (st != C4G_OK) {
            s->counters.malformed[C4G_MAL_CEILING]++;
            s->counters.malformed_total++;
            res->kind = C4G_RX_DROPPED;
            res->events |= C4G_EV_MALFORMED;
        }
    }
    if ((st == C4G_OK) && ((s->priv.startup_init != 0U) || (s->priv.restart_pending != 0U)) &&
        (second_init(s, buf, now_ns, res) != 0)) {
        st = C4G_ERR_STATE;
    }
    if (st == C4G_OK) {
        s->init = init;
        s->map = map;
        (void)memcpy(s->priv.init_raw, buf, C4G_INIT_SIZE);
        s->priv.startup_init = 1U;
        /* the cyclic decode writes map.n_axes axes only: the rest stay zero from here */
        (void)memset(s->priv.rx, 0, sizeof s->priv.rx);
        s->priv.rx_mixed_modes = 0U;
        s->counters.init++;
        /* After a cold restart 2 syncs follow the init; after 506 none do. */
        s->priv.post_sync_left = ((s->priv.sync_seen > 0U) && (s->priv.restart_pending == 0U))
                                ? s->cfg.post_init_sync : 0U;
        s->phase = (s->priv.post_sync_left > 0U) ? C4G_PHASE_POST_SYNC : C4G_PHASE_CYCLIC;
        s->priv.sync_seen = 0U;
        s->priv.restart_pending = 0U;
        s->priv.frozen = 0U;
        s->priv.frozen_active = 0U;
        s->priv.have_cyclic_time = 0U;
        s->priv.last_num = C4G_INIT_NUM;
        s->silence_ns = (s->cfg.silence_ns != 0U)
                            ? s->cfg.silence_ns
                            : ((uint64_t)SILENCE_PERIODS * (uint64_t)init.period_ms * NS_PER_MS);
        s->priv.silent = 0U;
        s->timing.nominal_period_ns = (int64_t)init.period_ms * (int64_t)NS_PER_MS;
        res->kind = C4G_RX_INIT;
        res->events |= C4G_EV_INIT;
        arm_reply(s, C4G_RX_INIT, C4G_INIT_NUM, buf, len, now_ns);
    }
}

/* A synchronization packet has the shape of a cyclic packet (the controller sends one of its
 * own size): decoding it bounds the reply's size to the datagram's and keeps NaN, infinity
 * and unknown modes out of the echo. The spare decode buffer is the scratch space. */
static void on_sync(c4g_session_t *s, const uint8_t *buf, size_t len, uint64_t now_ns,
                    c4g_rx_result_t *res)
{
    const c4g_status_t st = c4g_ctrl_decode(buf, len, 0U, &s->priv.rx[s->priv.cur ^ 1U], &res->diag);
    const int32_t num = s->priv.rx[s->priv.cur ^ 1U].num; /* 0 when the decode failed */
    if (st != C4G_OK) {
        count_malformed(s, st, res);
    } else if ((s->phase == C4G_PHASE_POST_SYNC) && (drop_stale(s, num, res) != 0)) {
        /* counted */
    } else if ((s->phase == C4G_PHASE_WAIT_INIT) && (s->priv.sync_seen >= C4G_SYNC_REPLY_BUDGET)) {
        /* The field answers the handshake's 9 syncs with 732 bytes (twice as many allowed:
         * duplicates on the path). More are no handshake: not answered (no amplification;
         * and a reply of the datagram's own size would read as a cyclic reply echoing the
         * controller's own data). */
        s->counters.sync_excess++;
        res->kind = C4G_RX_DROPPED;
        res->events |= C4G_EV_SYNC_EXCESS;
    } else {
        {
            s->counters.sync++;
            if (s->phase == C4G_PHASE_POST_SYNC) {
                s->priv.post_sync_left--;
                if (s->priv.post_sync_left == 0U) {
                    s->phase = C4G_PHASE_CYCLIC;
                }
                track_num(s, num, res);
            } else {
                s->priv.sync_seen++;
                s->phase = C4G_PHASE_WAIT_INIT;
            }
            res->kind = C4G_RX_SYNC;
            arm_reply(s, C4G_RX_SYNC, num, buf, len, now_ns);
        }
    }
}

/* Bit a set when arm a's INFPAR byte reports C4G_STS_MOVING (the bytes by constant shifts:
 * this runs on every packet). */
static uint32_t drive_mask(uint32_t infpar)
{
    return c4g_flag((infpar & 0xFFU) == C4G_STS_MOVING) |
           (c4g_flag(((infpar >> 8U) & 0xFFU) == C4G_STS_MOVING) << 1U) |
           (c4g_flag(((infpar >> 16U) & 0xFFU) == C4G_STS_MOVING) << 2U) |
           (c4g_flag((infpar >> 24U) == C4G_STS_MOVING) << 3U);
}

/* Session-level modes (>= 500) of an accepted packet: their events, which are also added
 * to @p res. One mode on every axis, the usual case, is one comparison; a packet without
 * such a mode changes nothing. */
static uint32_t scan_special_modes(c4g_session_t *s, const c4g_ctrl_packet_t *p, c4g_rx_result_t *res)
{
    const uint32_t n = (s->priv.rx_mixed_modes != 0U) ? p->n_axes : 1U;
    uint32_t ev = 0U;
    uint32_t i;
    for (i = 0U; i < n; i++) {
        if (p->ax[i].mode < C4G_MODE_FREEZING_A) {
            continue; /* hot path: no special mode */
        }
        switch (p->ax[i].mode) {
        case C4G_MODE_EXIT_OPEN:
            ev |= C4G_EV_END;
            break;
        case C4G_MODE_SVR_RESTART:
            ev |= C4G_EV_RESTART;
            break;
        case C4G_MODE_FREEZING_P_IN:
            ev |= C4G_EV_FREEZE_IN;
            break;
        case C4G_MODE_FREEZING_P_OUT:
            ev |= C4G_EV_FREEZE_OUT;
            break;
        default:
            /* not a session-level mode */
            break;
        }
    }
    if (ev != 0U) {
        res->events |= ev;
        if ((ev & C4G_EV_FREEZE_IN) != 0U) {
            s->priv.frozen = 1U;
        }
        if ((ev & C4G_EV_FREEZE_OUT) != 0U) {
            s->priv.frozen = 0U;
        }
        if ((ev & C4G_EV_RESTART) != 0U) {
            s->priv.restart_pending = 1U;
        }
        if ((ev & C4G_EV_END) != 0U) {
            s->phase = C4G_PHASE_ENDED;
        }
    }
    return ev;
}

/* Manual 15.4: 504 is sent with the system preset to mode 0. A 504 whose previous packet
 * had an axis in an operating mode is reported (the session ends all the same: the PC
 * stops answering, and a controller that did not send it turns its drives off after 10
 * missing replies). diag names the axis and its mode. */
static void end_in_procedure(c4g_session_t *s, const c4g_ctrl_packet_t *prev,
                             c4g_rx_result_t *res)
{
    uint32_t i;
    uint32_t found = 0U;
    for (i = 0U; (i < prev->n_axes) && (i < C4G_MAX_AXES) && (found == 0U); i++) {
        const int32_t m = prev->ax[i].mode;
        if ((m != C4G_MODE_0) && (m != C4G_MODE_0_DEBUG) && (m < C4G_MODE_FREEZING_A)) {
            found = 1U;
            c4g_diag_set(&res->diag, C4G_ERR_STATE, C4G_FIELD_SM,
                         C4G_HEADER_SIZE + (i * C4G_AXIS_SIZE), -1, (int32_t)i, (int64_t)m);
        }
    }
    if (found != 0U) {
        s->counters.end_unexpected++;
        res->events |= C4G_EV_END_UNEXPECTED;
    }
}

static void on_cyclic(c4g_session_t *s, const uint8_t *buf, size_t len, uint64_t now_ns,
                      c4g_rx_result_t *res)
{
    const uint32_t next = s->priv.cur ^ 1U;
    c4g_ctrl_packet_t *p = &s->priv.rx[next];
    uint32_t mixed = 1U;
    c4g_status_t st = C4G_OK;
    if (c4g_cyclic_decode_hot(buf, len, s->map.n_axes, p, &mixed) == 0U) {
        mixed = 1U;
        st = c4g_ctrl_decode(buf, len, s->map.n_axes, p, &res->diag); /* names the fault */
    }
    if (st != C4G_OK) {
        count_malformed(s, st, res);
    } else if (drop_stale(s, p->num, res) != 0) {
        /* counted */
    } else {
        const uint32_t drives = drive_mask(p->infpar);
        const uint32_t prev = s->priv.cur;
        s->priv.startup_init = 0U; /* the start-up is over */
        s->priv.cur = next;
        s->priv.rx_mixed_modes = mixed;
        s->counters.cyclic++;
        if (s->counters.cyclic == 1U) {
            res->events |= C4G_EV_CYCLIC_START;
        }
        if (s->phase == C4G_PHASE_LOST) {
            s->phase = C4G_PHASE_CYCLIC;
        }
        if (drives != s->drives) {
            s->drives = drives;
            res->events |= C4G_EV_DRIVES;
        }
        track_num(s, p->num, res);
        if (s->priv.have_cyclic_time != 0U) {
            const uint64_t elapsed = now_ns - s->priv.last_cyclic_ns;
            const int64_t inter = (int64_t)elapsed;
            c4g_timing_t *t = &s->timing;
            if ((t->samples_inter == 0U) || (inter < t->min_inter_ns)) {
                t->min_inter_ns = inter;
            }
            if ((t->samples_inter == 0U) || (inter > t->max_inter_ns)) {
                t->max_inter_ns = inter;
            }
            t->samples_inter++;
        }
        s->priv.last_cyclic_ns = now_ns;
        s->priv.have_cyclic_time = 1U;
        if (((scan_special_modes(s, p, res) & C4G_EV_END) != 0U) && (s->counters.cyclic > 1U)) {
            end_in_procedure(s, &s->priv.rx[prev], res);
        }
        res->kind = C4G_RX_CYCLIC;
        res->pkt = p;
        arm_reply(s, C4G_RX_CYCLIC, p->num, buf, len, now_ns);
    }
}

/* Silence check shared by rx and poll; freezing suspends it. A silence is reported once,
 * past the silence threshold; the session ends past the loss timeout. */
static inline uint32_t check_lost(c4g_session_t *s, uint64_t now_ns)
{
    uint32_t ev = 0U;
    if ((s->phase == C4G_PHASE_REFUSED) && (now_ns > s->priv.last_rx_ns) &&
        ((now_ns - s->priv.last_rx_ns) > s->lost_timeout_ns)) {
        /* the refused controller gave up: a new start-up may be served, and nothing resumes
         * the refused session's init packet */
        s->phase = C4G_PHASE_LOST;
        s->priv.startup_only = 1U;
        s->counters.lost_events++;
        ev = C4G_EV_LOST;
    } else if ((s->phase == C4G_PHASE_WAIT_INIT) && (s->priv.sync_seen > 0U) &&
               (now_ns > s->priv.last_rx_ns) && ((now_ns - s->priv.last_rx_ns) > s->lost_timeout_ns)) {
        /* a start-up that stopped before its init: the next one starts afresh (a cold
         * restart of the controller takes far longer than the loss timeout) */
        s->priv.sync_seen = 0U;
        s->peer_locked = 0U;
    } else if (((s->phase == C4G_PHASE_CYCLIC) || (s->phase == C4G_PHASE_POST_SYNC)) &&
        (s->priv.frozen == 0U) && (s->priv.frozen_active == 0U) && (now_ns > s->priv.last_rx_ns)) {
        const uint64_t gap = now_ns - s->priv.last_rx_ns;
        if (gap > s->lost_timeout_ns) {
            s->phase = C4G_PHASE_LOST;
            s->counters.lost_events++;
            s->priv.pending_num = -1;
            ev = C4G_EV_LOST;
        } else if ((gap > s->silence_ns) && (s->priv.silent == 0U)) {
            s->priv.silent = 1U;
            s->counters.silences++;
            ev = C4G_EV_SILENCE;
        } else {
            /* in time */
        }
    } else {
        /* no silence check in this phase */
    }
    return ev;
}

static int same_endpoint(const c4g_endpoint_t *a, const c4g_endpoint_t *b)
{
    return ((a->addr_len == b->addr_len) && (a->port == b->port) &&
            (memcmp(a->addr, b->addr, a->addr_len) == 0))
               ? 1
               : 0;
}

bool c4g_session_is_peer(const c4g_session_t *s, const c4g_endpoint_t *from)
{
    bool r = false;
    if ((s != NULL) && (from != NULL) && (from->addr_len <= 16U)) {
        r = (s->peer_locked == 0U) || (same_endpoint(from, &s->peer) != 0);
    }
    return r;
}

/* Another endpoint than the controller's: counted by shape, nothing else. */
static c4g_foreign_t on_foreign(c4g_session_t *s, size_t len, c4g_rx_result_t *res)
{
    c4g_foreign_t shape = C4G_FOREIGN_OTHER;
    if (len == C4G_INIT_SIZE) {
        shape = C4G_FOREIGN_INIT;
    } else if ((len >= C4G_CYCLIC_SIZE(1U)) && (len <= C4G_MAX_CYCLIC_SIZE) &&
               (((len - C4G_HEADER_SIZE) % C4G_AXIS_SIZE) == 0U)) {
        shape = C4G_FOREIGN_CYCLIC;
    } else {
        /* anything else */
    }
    s->counters.foreign[shape]++;
    s->counters.foreign_total++;
    res->kind = C4G_RX_DROPPED;
    res->events |= C4G_EV_FOREIGN;
    return shape;
}

/* The session's start-up runs: the synchronization packets before and after the init
 * packet, and from a 506 to the new init packet. */
static int in_startup(const c4g_session_t *s)
{
    return ((s->phase == C4G_PHASE_WAIT_INIT) || (s->phase == C4G_PHASE_POST_SYNC) ||
            (s->priv.restart_pending != 0U))
               ? 1
               : 0;
}

/* After a lost controller, a datagram that does not continue its NUM sequence, or that comes
 * from another endpoint, is a new start-up: the controller restarted cold. */
static int new_startup(const c4g_session_t *s, const uint8_t *buf, size_t len, int other)
{
    int r = 0;
    if ((s->phase == C4G_PHASE_LOST) && (len != C4G_INIT_SIZE)) {
        const int32_t d = (len >= 4U) ? num_delta(s, c4g_get_i32le(buf)) : 0;
        if ((other != 0) || (d == 0) || (d >= NUM_HALF) || (s->priv.startup_only != 0U)) {
            r = 1;
        }
    }
    return r;
}

static void dispatch(c4g_session_t *s, const uint8_t *buf, size_t len, uint64_t now_ns,
                     c4g_rx_result_t *res)
{
    if (len == C4G_INIT_SIZE) {
        on_init(s, buf, len, now_ns, res);
    } else if ((s->phase == C4G_PHASE_WAIT_INIT) || (s->phase == C4G_PHASE_POST_SYNC)) {
        on_sync(s, buf, len, now_ns, res);
    } else {
        on_cyclic(s, buf, len, now_ns, res);
    }
}

/* An accepted datagram: the end of a silence, the lock on the controller's endpoint. */
static void accepted(c4g_session_t *s, uint64_t now_ns, uint32_t was_silent,
                     const c4g_endpoint_t *from, c4g_rx_result_t *res)
{
    if ((was_silent != 0U) && (now_ns > s->priv.last_rx_ns)) {
        res->silence_ns = now_ns - s->priv.last_rx_ns;
        res->events |= C4G_EV_RESUMED;
        if (res->silence_ns > s->counters.longest_silence_ns) {
            s->counters.longest_silence_ns = res->silence_ns;
        }
    }
    s->priv.silent = 0U;
    s->priv.last_rx_ns = now_ns;
    if ((from != NULL) && (s->peer_locked == 0U)) {
        s->peer = *from;
        s->peer_locked = 1U;
    }
}

static void result_reset(c4g_rx_result_t *res)
{
    (void)memset(res, 0, sizeof *res);
    res->diag.arm = -1;
    res->diag.axis = -1;
}

/* A start-up packet (sync or init) while a session runs: the old session is over, a new
 * handshake starts, locked to whoever starts it. */
static void restart_from(c4g_session_t *s, const uint8_t *buf, size_t len, uint64_t now_ns,
                         int other, const c4g_counters_t *before, uint32_t lost_ev,
                         c4g_rx_result_t *res)
{
    s->phase = C4G_PHASE_WAIT_INIT;
    s->priv.sync_seen = 0U;
    s->priv.restart_pending = 0U;
    s->priv.startup_init = 0U;
    s->priv.frozen = 0U;
    s->priv.frozen_active = 0U;
    on_sync(s, buf, len, now_ns, res);
    if (res->kind != C4G_RX_DROPPED) {
        s->priv.startup_only = 0U;
        s->peer_locked = 0U; /* accepted() locks to its sender */
        if (other != 0) {
            /* served (a cold restart may come from a new port), but never silently */
            s->counters.new_peers++;
            res->events |= C4G_EV_NEW_PEER;
        }
    } else {
        s->phase = C4G_PHASE_LOST; /* not a start-up after all */
        if (other != 0) {
            /* from a stranger it is foreign, not the controller's malformed datagram */
            s->counters = *before;
            result_reset(res);
            res->events |= lost_ev;
            (void)on_foreign(s, len, res);
        }
    }
}

/* One datagram of a session that has not ended. */
static void session_datagram(c4g_session_t *s, const uint8_t *buf, size_t len, uint64_t now_ns,
                             const c4g_endpoint_t *from, c4g_rx_result_t *res)
{
    int other = 0;
    uint32_t was_silent;
    uint32_t lost_ev;
    c4g_counters_t before;
    s->counters.rx++;
    s->priv.pending_num = -1;
    res->events |= check_lost(s, now_ns); /* (may unlock a start-up that stopped) */
    if ((from != NULL) && (s->peer_locked != 0U) && (same_endpoint(from, &s->peer) == 0)) {
        other = 1;
    }
    was_silent = c4g_flag((s->priv.silent != 0U) || (s->phase == C4G_PHASE_LOST));
    lost_ev = res->events;
    if (new_startup(s, buf, len, other) != 0) {
        before = s->counters; /* restored if a stranger's datagram was no start-up */
        restart_from(s, buf, len, now_ns, other, &before, lost_ev, res);
    } else if (other != 0) {
        if ((on_foreign(s, len, res) != C4G_FOREIGN_OTHER) && (in_startup(s) != 0)) {
            /* two endpoints start one session: neither can be told to be the controller */
            s->counters.contended++;
            res->events |= C4G_EV_CONTENDED;
            refuse(s, s->priv.last_rx_ns, res);
        }
    } else if (s->phase == C4G_PHASE_REFUSED) {
        s->counters.refused++;
        s->priv.last_rx_ns = now_ns; /* the refused controller is still sending */
        res->kind = C4G_RX_DROPPED;
        res->events |= C4G_EV_REFUSED;
    } else {
        dispatch(s, buf, len, now_ns, res);
    }
    if (res->kind != C4G_RX_DROPPED) {
        accepted(s, now_ns, was_silent, from, res);
    }
}

c4g_status_t c4g_session_rx_from(c4g_session_t *s, const uint8_t *buf, size_t len,
                                 uint64_t now_ns, const c4g_endpoint_t *from,
                                 c4g_rx_result_t *res)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (res != NULL) && ((buf != NULL) || (len == 0U))) {
        result_reset(res);
        st = C4G_OK;
        if ((from != NULL) && (from->addr_len > 16U)) {
            st = C4G_ERR_ARG;
        } else if (s->phase == C4G_PHASE_ENDED) {
            st = C4G_ERR_ENDED;
        } else {
            session_datagram(s, buf, len, now_ns, from, res);
        }
    }
    return st;
}

c4g_status_t c4g_session_rx(c4g_session_t *s, const uint8_t *buf, size_t len, uint64_t now_ns,
                            c4g_rx_result_t *res)
{
    return c4g_session_rx_from(s, buf, len, now_ns, NULL, res);
}

/* Active freezing is the PC's own request: 500 in a reply starts it (only mode 0 may
 * enter it, which the engine enforces), EXIT_FROM_OPEN on any arm ends it. */
static void track_active_freezing(c4g_session_t *s, const c4g_pc_packet_t *tx)
{
    const uint32_t w = tx->infpar;
    uint32_t i;
    for (i = 0U; i < tx->n_axes; i++) {
        if (tx->ax[i].mode == C4G_MODE_FREEZING_A) {
            s->priv.frozen_active = 1U;
        }
    }
    /* the arms' bytes by constant shifts: this runs on every reply */
    if (((w & 0xFFU) == C4G_EXIT_FROM_OPEN) || (((w >> 8U) & 0xFFU) == C4G_EXIT_FROM_OPEN) ||
        (((w >> 16U) & 0xFFU) == C4G_EXIT_FROM_OPEN) || ((w >> 24U) == C4G_EXIT_FROM_OPEN)) {
        s->priv.frozen_active = 0U;
    }
}

/* Whether the neutral reply of @p mode carries data (held reference or current, copy back):
 * then it cannot come from the zero-data template. */
static uint32_t neutral_has_data(int32_t mode)
{
    return c4g_flag((c4g_mode_rules(mode) & (C4G_MR_ABS | C4G_MR_CUR | C4G_MR_COPY)) != 0U);
}

/* The wire bytes of @p axes axes carrying @p mode and zero data. */
static void neutral_template(c4g_session_t *s, uint32_t axes, int32_t mode)
{
    uint32_t i;
    (void)memset(s->priv.neutral_axes, 0, sizeof s->priv.neutral_axes);
    for (i = 0U; i < axes; i++) {
        c4g_put_i32le(&s->priv.neutral_axes[(size_t)i * C4G_AXIS_SIZE], mode);
    }
    s->priv.neutral_n = axes;
    s->priv.neutral_mode = mode;
    s->priv.neutral_data = neutral_has_data(mode);
}

/* The current a hold keeps in a mode where the PC closes the loops, within +-AzLim of the
 * axis (AzLim is validated finite and >= 0 with the init packet). */
static void neutral_current(const c4g_session_t *s, uint32_t i, c4g_pc_axis_t *a)
{
    const float lim = s->init.az_lim[s->map.arm_of[i] & 3U][s->map.logical_of[i] % C4G_AXES_PER_ARM];
    if ((c4g_mode_rules(a->mode) & C4G_MR_CUR) != 0U) {
        if (a->current_add > lim) {
            a->current_add = lim;
        } else if (a->current_add < -lim) {
            a->current_add = -lim;
        } else {
            /* within the limit */
        }
    }
}

c4g_status_t c4g_session_neutral(const c4g_session_t *s, const c4g_ctrl_packet_t *rx,
                                 c4g_pc_packet_t *tx)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (rx != NULL) && (tx != NULL)) {
        st = C4G_ERR_STATE;
        if (s->map.n_axes > 0U) {
            st = (rx->n_axes == s->map.n_axes) ? c4g_pc_reply_neutral(rx, tx) : C4G_ERR_AXES;
        }
        if (st == C4G_OK) {
            uint32_t i;
            for (i = 0U; (i < tx->n_axes) && (i < C4G_MAX_AXES); i++) {
                neutral_current(s, i, &tx->ax[i]);
            }
        }
    }
    return st;
}


/* The neutral reply to @p p built as a PC packet and encoded (the packet of several modes,
 * or of a mode whose hold carries data: off the common path, and its 740-byte packet off
 * the common stack frame). */
static c4g_status_t neutral_encoded(c4g_session_t *s, const c4g_ctrl_packet_t *p, uint8_t *buf,
                                    size_t cap, size_t *n)
{
    c4g_pc_packet_t tx;
    c4g_status_t st = c4g_session_neutral(s, p, &tx);
    if (st == C4G_OK) {
        st = c4g_pc_encode(&tx, buf, cap, n);
    }
    if (st == C4G_OK) {
        track_active_freezing(s, &tx);
    }
    return st;
}

/* The neutral reply to the pending cyclic packet rx[cur]. One mode whose hold is zero data
 * on every axis (the usual case): written to the wire directly from the session's template,
 * no PC packet and no second check (the decoder checked the modes it echoes). Several modes,
 * or a mode whose hold carries data: built and encoded as c4g_session_neutral +
 * c4g_pc_encode. */
static c4g_status_t neutral_bytes(c4g_session_t *s, uint8_t *buf, size_t cap, size_t *n)
{
    const c4g_ctrl_packet_t *p = &s->priv.rx[s->priv.cur];
    const uint32_t axes = p->n_axes;
    const int32_t first = p->ax[0].mode;
    c4g_status_t st;
    if ((s->priv.rx_mixed_modes == 0U) &&
        ((s->priv.neutral_n != axes) || (s->priv.neutral_mode != first))) {
        neutral_template(s, axes, first);
    }
    if ((s->priv.rx_mixed_modes == 0U) && (s->priv.neutral_data == 0U)) {
        st = C4G_ERR_CAPACITY;
        if (cap >= C4G_CYCLIC_SIZE(axes)) {
            c4g_put_u32le(&buf[4], 0U);
            c4g_put_u32le(&buf[8], 0U);
            (void)memcpy(&buf[C4G_HEADER_SIZE], s->priv.neutral_axes, (size_t)axes * C4G_AXIS_SIZE);
            if (first == C4G_MODE_FREEZING_A) {
                s->priv.frozen_active = 1U;
            }
            *n = C4G_CYCLIC_SIZE((size_t)axes);
            st = C4G_OK;
        }
    } else {
        st = neutral_encoded(s, p, buf, cap, n);
    }
    return st;
}

/* The bytes of the reply to what is pending: the encoded cyclic reply (neutral when
 * @p tx is NULL and @p neutral set), or the echo of the start-up packet padded to its reply
 * size. */
static c4g_status_t reply_bytes(c4g_session_t *s, const c4g_pc_packet_t *tx, uint32_t neutral,
                                uint8_t *buf, size_t cap, size_t *n)
{
    c4g_status_t st;
    if (s->priv.pending_kind == C4G_RX_CYCLIC) {
        if (neutral != 0U) {
            st = neutral_bytes(s, buf, cap, n);
        } else if (tx == NULL) {
            st = C4G_ERR_NULL;
        } else if (tx->n_axes != s->map.n_axes) {
            st = C4G_ERR_AXES;
        } else {
            st = c4g_pc_encode(tx, buf, cap, n);
            if (st == C4G_OK) {
                track_active_freezing(s, tx);
            }
        }
    } else {
        *n = s->priv.pending_reply_len;
        st = C4G_ERR_CAPACITY;
        if (cap >= *n) {
            const uint8_t *raw = (s->priv.pending_kind == C4G_RX_INIT) ? s->priv.init_raw
                                                                        : s->priv.pending_raw;
            (void)memcpy(buf, raw, s->priv.pending_len);
            (void)memset(&buf[s->priv.pending_len], 0, *n - s->priv.pending_len);
            st = C4G_OK;
        }
    }
    return st;
}

static c4g_status_t session_reply(c4g_session_t *s, const c4g_pc_packet_t *tx, uint32_t neutral,
                                  uint8_t *buf, size_t cap, size_t *out_len)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (buf != NULL) && (out_len != NULL)) {
        size_t n = 0U;
        *out_len = 0U;
        st = C4G_ERR_STATE; /* nothing received to answer, or answered already */
        if ((s->priv.pending_num >= 0) && (s->priv.pending_kind != C4G_RX_DROPPED)) {
            st = reply_bytes(s, tx, neutral, buf, cap, &n);
        }
        if (st == C4G_OK) {
            c4g_put_i32le(buf, c4g_reply_num_inline(s->priv.pending_num, s->cfg.num_policy));
            *out_len = n;
            s->counters.tx++;
            if (s->priv.pending_kind != C4G_RX_CYCLIC) {
                s->priv.pending_num = -1;
            } else {
                s->priv.pending_kind = C4G_RX_DROPPED; /* marks "answered, cycle time pending" */
            }
        }
    }
    return st;
}

c4g_status_t c4g_session_reply(c4g_session_t *s, const c4g_pc_packet_t *tx, uint8_t *buf,
                               size_t cap, size_t *out_len)
{
    return session_reply(s, tx, 0U, buf, cap, out_len);
}

/* The usual neutral reply in one step: a cyclic packet pending, of one mode whose hold is
 * zero data and whose template is built (not 500, which starts active freezing), the
 * buffer large enough. What session_reply and
 * neutral_bytes do for it, without their dispatch; 0 (nothing written) when another case. */
static uint32_t neutral_fast(c4g_session_t *s, uint8_t *buf, size_t cap, size_t *out_len)
{
    const c4g_ctrl_packet_t *p = &s->priv.rx[s->priv.cur];
    const uint32_t axes = p->n_axes;
    const int32_t first = p->ax[0].mode;
    uint32_t done = 0U;
    if ((s->priv.pending_kind == C4G_RX_CYCLIC) && (s->priv.pending_num >= 0) &&
        (s->priv.rx_mixed_modes == 0U) && (s->priv.neutral_data == 0U) &&
        (s->priv.neutral_n == axes) && (s->priv.neutral_mode == first) &&
        (first != C4G_MODE_FREEZING_A) && (cap >= C4G_CYCLIC_SIZE(axes))) {
        c4g_put_i32le(buf, c4g_reply_num_inline(s->priv.pending_num, s->cfg.num_policy));
        c4g_put_u32le(&buf[4], 0U);
        c4g_put_u32le(&buf[8], 0U);
        (void)memcpy(&buf[C4G_HEADER_SIZE], s->priv.neutral_axes, (size_t)axes * C4G_AXIS_SIZE);
        *out_len = C4G_CYCLIC_SIZE((size_t)axes);
        s->counters.tx++;
        s->priv.pending_kind = C4G_RX_DROPPED; /* answered, cycle time pending */
        done = 1U;
    }
    return done;
}

c4g_status_t c4g_session_reply_neutral(c4g_session_t *s, uint8_t *buf, size_t cap,
                                       size_t *out_len)
{
    c4g_status_t st = C4G_OK;
    if ((s == NULL) || (buf == NULL) || (out_len == NULL) ||
        (neutral_fast(s, buf, cap, out_len) == 0U)) {
        st = session_reply(s, NULL, 1U, buf, cap, out_len);
    }
    return st;
}

c4g_status_t c4g_session_sent(c4g_session_t *s, uint64_t now_ns)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (s != NULL) {
        st = C4G_ERR_STATE;
        if ((s->priv.pending_num >= 0) && (s->priv.pending_kind == C4G_RX_DROPPED)) {
            c4g_timing_t *t = &s->timing;
            const uint64_t elapsed = now_ns - s->priv.pending_rx_ns;
            const int64_t cyc = (int64_t)elapsed;
            t->last_cycle_ns = cyc;
            if ((t->samples_cycle == 0U) || (cyc > t->worst_cycle_ns)) {
                t->worst_cycle_ns = cyc;
            }
            t->samples_cycle++;
            s->priv.pending_num = -1;
            st = C4G_OK;
        }
    }
    return st;
}

c4g_status_t c4g_session_poll(c4g_session_t *s, uint64_t now_ns, uint32_t *events)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (events != NULL)) {
        *events = check_lost(s, now_ns);
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4g_session_timing(const c4g_session_t *s, c4g_timing_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((s != NULL) && (out != NULL)) {
        *out = s->timing;
        if ((out->nominal_period_ns > 0) && (out->samples_inter > 0U)) {
            out->min_jitter_ns = out->min_inter_ns - out->nominal_period_ns;
            out->max_jitter_ns = out->max_inter_ns - out->nominal_period_ns;
            out->min_jitter_pct = ((double)out->min_jitter_ns * 100.0) / (double)out->nominal_period_ns;
            out->max_jitter_pct = ((double)out->max_jitter_ns * 100.0) / (double)out->nominal_period_ns;
        }
        st = C4G_OK;
    }
    return st;
}
