/* SPDX-License-Identifier: MIT */
/* libFuzzer target: the library's adversarial property fuzzer. A controller model written
 * from the manual (not from the filter) talks to the PC-side loop object through real
 * datagrams: the start-up handshake, cyclic packets, restarts (506 with the session's init,
 * 506 with another one, cold restarts after a loss with new init packets whose limits span
 * the representable range), lost packets (NUM gaps). The arbitrary PC
 * fills every reply with what the input says; the invariants are checked on the reply BYTES
 * the loop encodes, against what the model will do with them:
 *  - every float on the wire is finite;
 *  - no current over the limit (AzLim, or the user's tighter one) in a current mode (1, 11,
 *    2, 12), nor controller current + delta in mode 9 (unless SMP+ alone is beyond it, and
 *    then the delta only brings it back);
 *  - absolute modes (1, 11, 4): no step over max_step from the reference the controller
 *    applied last, no target outside the stroke (unless the axis stands outside it and the
 *    target brings it back);
 *  - integrating modes (5, 7, 8): the PC's addition to the integrated reference never
 *    steps more than max_step and never leaves the stroke;
 *  - a reply the filter could not run on (the loop's fallback) holds: the reported
 *    reference, the controller's current within AzLim, nothing added;
 *  - a mode without rules (3, 6, 1xx, 201, 202) never carries a non-zero field.
 * Worlds: the first input byte chooses how honest the controller is. Honest: legal mode
 * transitions only (chapter 24), D1 is the reference it applied. Then illegal transitions,
 * modes the C4G does not have, mixed modes on an arm, and reports of arbitrary finite values
 * (the invariants then hold against what the controller reports, all the PC can know). User
 * limits are kept by the loop (c4g_loop_set_limits) across restarts.
 * Written from the manual: modes 1/11/4 follow D1 (tables 14.3, 14.6), mode 5 integrates D2
 * on its own trajectory (fig. 14.1), mode 7 adds D1, mode 8 integrates D4, modes 1/2 take D5
 * as the current, mode 9 adds D5 (14.12); a reply that did not arrive changes nothing. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c4gopen.h"
#include "c4gsim_fixtures.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define N_AX 6U
#define TICKS_MAX 600U
/* The float resolution around a reference: base + d is rounded to a float on the wire. */
static double tol_at(double x)
{
    return fabs(x) * 2.4e-7 + 1e-9;
}

typedef struct cur {
    const uint8_t *p;
    size_t n;
} cur_t;

static uint8_t u8(cur_t *c)
{
    uint8_t b = 0U;
    if (c->n > 0U) {
        b = *c->p;
        c->p++;
        c->n--;
    }
    return b;
}

static uint32_t u32(cur_t *c)
{
    uint32_t v = 0U;
    int k;
    for (k = 0; k < 4; k++) {
        v = (v << 8) | u8(c);
    }
    return v;
}

/* A float the PC might write: small and smooth, large, absurd, or any bit pattern. */
static float pc_value(cur_t *c, float around, float scale)
{
    const uint8_t k = u8(c);
    const float x = ((float)(int8_t)u8(c)) / 127.0f;
    float f;
    uint32_t bits;
    switch (k & 7U) {
    case 0: case 1: case 2: return around + x * scale;
    case 3: return around + x * scale * 50.0f;
    case 4: return x * 1e30f;
    case 5:
        bits = u32(c);
        memcpy(&f, &bits, sizeof f);
        return f;
    case 6: return around;
    default: return c4g_unset();
    }
}

/* A finite value a lying controller might report. */
static float wild_finite(cur_t *c)
{
    uint32_t bits = u32(c);
    float f;
    if ((bits & 0x7F800000U) == 0x7F800000U) {
        bits &= 0xFF7FFFFFU;
    }
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* ---------------------------------------------------------------- the controller model */

enum { W_HONEST = 0, W_ILLEGAL = 1, W_LIAR = 2 };

typedef struct ax {
    int32_t mode;      /* SMax reported */
    int32_t resume;    /* mode a passive freezing returns to */
    double ref;        /* the position reference the DSA is given (motor turns) */
    double vel_i;      /* SMP+ trajectory velocity, turns per tick */
    double cur;        /* the current applied (A) */
    double own_cur;    /* the controller's own current (mode 9 adds to it) */
} ax_t;

typedef struct world {
    int kind;
    c4g_init_t init;
    ax_t ax[N_AX];
    int32_t num;
    uint32_t drives_on;
    c4g_axis_limits_t user;   /* the PC's limits, applied after every init */
    /* what the checks need from the last reply */
    c4g_pc_packet_t sent;     /* decoded reply to the last packet */
    int have_sent;
    c4g_ctrl_packet_t pkt;    /* the last packet sent (its reports) */
} world_t;

static int is_abs(int32_t m) { return m == 1 || m == 11 || m == 4; }
static int is_cur(int32_t m) { return m == 1 || m == 11 || m == 2 || m == 12; }
static int no_rule(int32_t m) { return m == 3 || m == 6 || (m >= 101 && m <= 103) || m == 201 || m == 202; }

/* Chapter 24: from mode 0 PDL2 opens 0', 1, 2, 4, 5, 7, 8, 9; each operating mode ends
 * through its stand-by (1 -> 11, 2 -> 12, 4 -> 14, 5 -> 15, 7 -> 17 -> 170) or is forced
 * back to 0; a passive freezing (502 .. 503) returns to the mode it interrupted. */
static int32_t next_mode_honest(cur_t *c, const ax_t *a)
{
    static const int32_t opens[] = {10, 1, 2, 4, 5, 7, 8, 9};
    const uint8_t k = u8(c);
    int32_t m = a->mode;
    if ((k & 0xC0U) != 0U) {
        return m; /* most ticks: stay */
    }
    switch (a->mode) {
    case 0: m = opens[k % 8U]; break;
    case 1: m = (k & 1U) ? 11 : 502; break;
    case 2: m = (k & 1U) ? 12 : 502; break;
    case 4: m = (k & 1U) ? 14 : 502; break;
    case 5: m = (k & 1U) ? 15 : 502; break;
    case 7: m = (k & 1U) ? 17 : 502; break;
    case 17: m = 170; break;
    case 502: m = 503; break;
    case 503: m = a->resume; break;
    case 14: m = (k & 1U) ? 4 : 0; break;
    default: m = 0; break;
    }
    return m;
}

static int32_t next_mode_any(cur_t *c)
{
    static const int32_t modes[] = {0, 10, 1, 11, 2, 12, 3, 4, 14, 5, 15, 6, 7, 17, 170, 8,
                                    9, 101, 102, 103, 201, 202, 500, 501, 502, 503, 505, 508};
    return modes[u8(c) % (sizeof modes / sizeof modes[0])];
}

/* The controller applies the reply to its previous packet (if it arrived, for the mode it
 * answered), then moves its own trajectory. */
static void apply_reply(world_t *w, int arrived)
{
    uint32_t i;
    for (i = 0; i < N_AX; i++) {
        ax_t *a = &w->ax[i];
        const c4g_pc_axis_t *r = &w->sent.ax[i];
        const int ok = arrived && w->have_sent && r->mode == a->mode;
        if (w->have_sent && arrived && (r->mode == C4G_MODE_DRIVE_OFF || r->mode == C4G_MODE_FOLLOW_ERROR)) {
            w->drives_on = 0U; /* the controller honours 505 / 508: drives off */
        }
        switch (a->mode) {
        case 1: case 11: case 4:
            if (ok) { a->ref = r->target_pos; }
            if (is_cur(a->mode) && ok) { a->cur = r->current_add; }
            break;
        case 2: case 12:
            a->ref += a->vel_i;
            if (ok) { a->cur = r->current_add; }
            break;
        case 5: a->ref += a->vel_i + (ok ? r->target_vel : 0.0); break;
        case 7: a->ref += a->vel_i + (ok ? r->target_pos : 0.0); break;
        case 8: a->ref += a->vel_i + (ok ? r->vel_add : 0.0); break;
        case 9: a->ref += a->vel_i; a->cur = a->own_cur + (ok ? r->current_add : 0.0); break;
        case 0: case 10: a->ref += a->vel_i; break;
        default: break; /* stand-by, special: the reference holds */
        }
    }
}

static void report(world_t *w, cur_t *c, c4g_ctrl_packet_t *p)
{
    uint32_t i;
    memset(p, 0, sizeof *p);
    p->num = w->num;
    p->n_axes = N_AX;
    p->infpar = w->drives_on ? C4G_STS_MOVING : 0U;
    for (i = 0; i < N_AX; i++) {
        const ax_t *a = &w->ax[i];
        c4g_ctrl_axis_t *o = &p->ax[i];
        o->mode = a->mode;
        o->target_pos = (float)a->ref;
        o->target_vel = (float)a->vel_i;
        o->actual_pos = (float)a->ref;
        o->actual_vel = (float)a->vel_i;
        o->current_ref = (float)((a->mode == 9) ? a->own_cur : a->cur);
        o->ext[0] = 0.5f;
        o->ext[1] = 1e-3f;
        if (w->kind == W_LIAR && (u8(c) & 3U) == 0U) {
            o->target_pos = wild_finite(c);
            o->target_vel = wild_finite(c);
            o->actual_pos = wild_finite(c);
            o->current_ref = wild_finite(c);
        }
    }
}

/* ---------------------------------------------------------------- checks */

static void fail(const char *what, uint32_t i, double a, double b)
{
    fprintf(stderr, "safety invariant broken: %s (axis %u: %.9g vs %.9g)\n", what, i + 1U, a, b);
    abort();
}

static void check_finite_bytes(const uint8_t *b, size_t n)
{
    size_t off;
    for (off = 12U; off + 36U <= n; off += 36U) {
        size_t k;
        for (k = 4U; k < 36U; k += 4U) {
            const uint32_t v = (uint32_t)b[off + k] | ((uint32_t)b[off + k + 1U] << 8) |
                               ((uint32_t)b[off + k + 2U] << 16) | ((uint32_t)b[off + k + 3U] << 24);
            if ((v & 0x7F800000U) == 0x7F800000U) {
                fail("non-finite on the wire", (uint32_t)((off - 12U) / 36U), (double)v, 0.0);
            }
        }
    }
}

/* The limits the loop applies to axis i (the user's, tightened by the init's). */
static void limits(const c4g_loop_t *lp, uint32_t i, c4g_axis_limits_t *l)
{
    if (c4g_loop_limits(lp, i, l) != C4G_OK) {
        memset(l, 0, sizeof *l);
        l->current_max = lp->session.init.az_lim[0][i];
    }
}

static void check_stroke(uint32_t i, const char *what, double base, double next, const c4g_axis_limits_t *l)
{
    const double lo = l->motor_min, hi = l->motor_max;
    if (!(l->motor_min < l->motor_max)) {
        return;
    }
    const double tol = tol_at(base) + tol_at(next);
    if (next > hi + tol && next > base + tol) {
        fail(what, i, next, hi);
    }
    if (next < lo - tol && next < base - tol) {
        fail(what, i, next, lo);
    }
}

static void check_step(uint32_t i, const char *what, double base, double d, const c4g_axis_limits_t *l)
{
    if (l->max_step > 0.0f && fabs(d) > (double)l->max_step * (1.0 + 1e-5) + 2.0 * tol_at(base)) {
        fail(what, i, d, l->max_step);
    }
}

/* The reply @p r to packet @p p (whose reports the PC saw), against what the controller
 * will do with it. @p truth: the model's state before it applies the reply. */
static void check_reply(const c4g_loop_t *lp, const world_t *w, const c4g_ctrl_packet_t *p,
                        const c4g_pc_packet_t *r, int fallback)
{
    uint32_t i;
    for (i = 0; i < N_AX; i++) {
        const c4g_ctrl_axis_t *in = &p->ax[i];
        const c4g_pc_axis_t *o = &r->ax[i];
        const ax_t *a = &w->ax[i];
        const int honest = (w->kind != W_LIAR) ||
                           (in->target_pos == (float)a->ref && in->target_vel == (float)a->vel_i &&
                            in->current_ref == (float)((a->mode == 9) ? a->own_cur : a->cur));
        /* what the controller applied, as far as the PC can know it */
        const double ref = honest ? a->ref : (double)in->target_pos;
        const double vel = honest ? a->vel_i : (double)in->target_vel;
        const double own = honest ? ((a->mode == 9) ? a->own_cur : a->cur) : (double)in->current_ref;
        c4g_axis_limits_t l;
        limits(lp, i, &l);
        if (o->mode != in->mode) {
            /* only a safety or freezing request replaces the echo */
            if (o->mode != C4G_MODE_DRIVE_OFF && o->mode != C4G_MODE_FOLLOW_ERROR &&
                o->mode != C4G_MODE_FREEZING_A) {
                fail("mode neither echoed nor a safety request", i, o->mode, in->mode);
            }
        }
        if (no_rule(in->mode) || no_rule(o->mode)) {
            if (o->target_pos != 0.0f || o->target_vel != 0.0f || o->measure != 0.0f ||
                o->vel_add != 0.0f || o->current_add != 0.0f) {
                fail("a mode without rules carries data", i, o->current_add, 0.0);
            }
        }
        if (o->mode != in->mode) {
            /* the controller ignores data of another mode (it stops for 505/508) */
        } else if (is_abs(in->mode)) {
            check_step(i, "absolute step from the applied reference", ref, (double)o->target_pos - ref, &l);
            check_stroke(i, "absolute target outside the stroke", ref, (double)o->target_pos, &l);
            if (l.max_vel > 0.0f && fabsf(o->target_vel) > l.max_vel * 1.00001f) {
                fail("target velocity over the limit", i, o->target_vel, l.max_vel);
            }
        } else if (in->mode == 5) {
            check_step(i, "mode 5 addition", 0.0, (double)o->target_vel, &l);
            check_stroke(i, "mode 5 integrated reference", ref + vel, ref + vel + (double)o->target_vel, &l);
        } else if (in->mode == 7) {
            check_step(i, "mode 7 addition", 0.0, (double)o->target_pos, &l);
            check_stroke(i, "mode 7 integrated reference", ref + vel, ref + vel + (double)o->target_pos, &l);
        } else if (in->mode == 8) {
            check_step(i, "mode 8 addition", 0.0, (double)o->vel_add, &l);
            check_stroke(i, "mode 8 integrated reference", ref + vel, ref + vel + (double)o->vel_add, &l);
        } else {
            /* no position rule */
        }
        if (o->mode == in->mode && is_cur(in->mode)) {
            if (fabs((double)o->current_add) > (double)l.current_max * (1.0 + 1e-6)) {
                fail("current over the limit", i, o->current_add, l.current_max);
            }
        }
        if (o->mode == in->mode && in->mode == 9) {
            const double tot = own + (double)o->current_add;
            const double lim = (double)l.current_max * (1.0 + 1e-6) + 1e-6;
            if (fabs(tot) > lim && (fabs(tot) > fabs(own) + 1e-6 || tot * own < 0.0)) {
                fail("mode 9 total current over the limit", i, tot, l.current_max);
            }
        }
        if (fallback && o->mode == in->mode && in->mode != C4G_MODE_0_DEBUG) {
            /* the fallback holds: the reported reference, nothing added */
            if (o->target_vel != 0.0f || o->vel_add != 0.0f || o->measure != 0.0f) {
                fail("fallback adds something", i, o->target_vel, 0.0);
            }
            if (is_abs(in->mode) && o->target_pos != in->target_pos) {
                fail("fallback moves an absolute axis", i, o->target_pos, in->target_pos);
            }
            if (!is_abs(in->mode) && in->mode != 10 && o->target_pos != 0.0f) {
                fail("fallback adds a position", i, o->target_pos, 0.0);
            }
            if (in->mode == 9 && o->current_add != 0.0f) {
                fail("fallback adds a current", i, o->current_add, 0.0);
            }
        }
    }
}

/* The neutral reply to every packet holds: the reported reference of an absolute mode, the
 * controller's current within AzLim where the PC closes the loops, nothing else. */
static void check_neutral(const c4g_loop_t *lp, const c4g_ctrl_packet_t *p)
{
    c4g_pc_packet_t n;
    uint32_t i;
    if (lp->session.map.n_axes != N_AX || c4g_session_neutral(&lp->session, p, &n) != C4G_OK) {
        return;
    }
    for (i = 0; i < N_AX; i++) {
        const c4g_pc_axis_t *o = &n.ax[i];
        const int32_t m = p->ax[i].mode;
        const double az = lp->session.init.az_lim[0][i];
        if (o->mode != m) {
            fail("neutral reply changes the mode", i, o->mode, m);
        }
        if (m == C4G_MODE_0_DEBUG) {
            continue;
        }
        if (o->target_pos != (is_abs(m) ? p->ax[i].target_pos : 0.0f) || o->target_vel != 0.0f ||
            o->measure != 0.0f || o->vel_add != 0.0f) {
            fail("neutral reply moves an axis", i, o->target_pos, p->ax[i].target_pos);
        }
        if (is_cur(m) ? (fabs((double)o->current_add) > az) : (o->current_add != 0.0f)) {
            fail("neutral reply adds a current", i, o->current_add, az);
        }
    }
}

/* ---------------------------------------------------------------- the run */

static void make_init(cur_t *c, c4g_init_t *in, int wide)
{
    uint32_t i;
    (void)c4gsim_fig10_1(in);
    for (i = 0; i < N_AX && wide; i++) {
        /* limits across the representable range (finite, >= 0) */
        const uint32_t e = u8(c);
        in->az_lim[0][i] = (float)ldexp((double)(u8(c) + 1U) / 256.0, (int)(e % 140U) - 20);
        in->follow_error[0][i] = (u8(c) & 1U) ? 0.0f : (float)ldexp(1.0, (int)(u8(c) % 60U) - 20);
    }
}

static void user_limits(cur_t *c, c4g_axis_limits_t *l)
{
    const uint8_t k = u8(c);
    memset(l, 0, sizeof *l);
    l->max_step = (k & 1U) ? (float)(u8(c) + 1U) * 1e-4f : 0.0f;
    l->max_vel = (k & 2U) ? (float)(u8(c) + 1U) * 1e-4f : 0.0f;
    l->current_max = (k & 4U) ? (float)(u8(c) + 1U) * 0.1f : 0.0f;
    if (k & 8U) {
        l->motor_min = -(float)(u8(c) + 1U) * 0.01f;
        l->motor_max = (float)(u8(c) + 1U) * 0.01f;
    }
}

/* The user's limits on every axis, kept by the loop across restarts (a refused set keeps
 * the previous ones, which the checks read back from the loop). */
static void set_user_limits(c4g_loop_t *lp, const c4g_axis_limits_t *l)
{
    uint32_t i;
    for (i = 0; i < N_AX; i++) {
        (void)c4g_loop_set_limits(lp, 0, i, l);
    }
}

static int send_ctrl(c4g_loop_t *lp, const uint8_t *b, size_t n, uint64_t t, c4g_loop_event_t *ev)
{
    static const c4g_endpoint_t ctl = {{127, 0, 0, 1}, 4, 3600};
    return c4g_loop_rx(lp, b, n, t, &ctl, ev) == C4G_OK;
}

static void handshake(c4g_loop_t *lp, world_t *w, int restart, uint64_t *t)
{
    uint8_t b[C4G_INIT_SIZE];
    uint8_t out[C4G_INIT_SIZE];
    size_t len = 0;
    c4g_loop_event_t ev;
    int k;
    for (k = 0; k < (restart ? 0 : 9); k++) { /* 9 syncs, NUM 1..9 */
        memset(b, 0, 48);
        b[0] = (uint8_t)(k + 1);
        *t += 2000000U;
        (void)send_ctrl(lp, b, 48, *t, &ev);
        (void)c4g_loop_reply(lp, out, sizeof out, &len, NULL);
    }
    w->init.num = 10;
    if (c4g_init_encode(&w->init, b, sizeof b, &len) != C4G_OK) {
        abort();
    }
    *t += 2000000U;
    (void)send_ctrl(lp, b, len, *t, &ev);
    (void)c4g_loop_reply(lp, out, sizeof out, &len, NULL);
    (void)ev; /* the loop applies the user's limits kept by c4g_loop_set_limits */
    for (k = 0; k < (restart ? 0 : 2); k++) { /* 2 more syncs */
        memset(b, 0, 48);
        b[0] = (uint8_t)(11 + k);
        *t += 2000000U;
        (void)send_ctrl(lp, b, 48, *t, &ev);
        (void)c4g_loop_reply(lp, out, sizeof out, &len, NULL);
    }
    w->num = restart ? 11 : 13;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static c4g_loop_t lp;
    static world_t w;
    cur_t c = {data, size};
    uint64_t t = 1000000000U;
    uint32_t tick;
    uint32_t i;
    memset(&w, 0, sizeof w);
    w.kind = u8(&c) % 3;
    if (c4g_loop_init(&lp, NULL) != C4G_OK) {
        abort();
    }
    user_limits(&c, &w.user);
    set_user_limits(&lp, &w.user);
    make_init(&c, &w.init, (u8(&c) & 1U) != 0U);
    for (i = 0; i < N_AX; i++) {
        w.ax[i].ref = ((double)(int8_t)u8(&c)) / 64.0;
        w.ax[i].cur = ((double)(int8_t)u8(&c)) / 4.0;
        w.ax[i].own_cur = w.ax[i].cur;
    }
    w.drives_on = 1U;
    handshake(&lp, &w, 0, &t);
    for (tick = 0; tick < TICKS_MAX && c.n > 0U; tick++) {
        const uint8_t op = u8(&c);
        uint8_t b[C4G_MAX_CYCLIC_SIZE];
        uint8_t out[C4G_INIT_SIZE];
        size_t len = 0;
        c4g_loop_event_t ev;
        c4g_ctrl_packet_t p;
        uint64_t before;
        const int lost_rx = (op & 0x0FU) == 1U;   /* the packet never reaches the PC */
        const int lost_tx = (op & 0x0FU) == 2U;   /* the reply never reaches the controller */
        if ((op & 0x3FU) == 3U) {
            /* a restart: 506 and the session's own init packet; 506 and another one (an
             * attack, or a changed controller: the session is refused); or a cold restart
             * (silence past the loss timeout, a new start-up) with a new init packet */
            const uint8_t how = u8(&c) % 3U;
            if (how != 0U) {
                make_init(&c, &w.init, 1);
                user_limits(&c, &w.user);
                set_user_limits(&lp, &w.user);
            }
            if (how == 2U) {
                t += 1500000000U;
                for (i = 0; i < N_AX; i++) {
                    w.ax[i].mode = 0;
                }
                w.have_sent = 0;
                handshake(&lp, &w, 0, &t);
                continue;
            }
            for (i = 0; i < N_AX; i++) {
                w.ax[i].mode = 506;
            }
            report(&w, &c, &p);
            p.num = w.num;
            if (c4g_ctrl_encode(&p, b, sizeof b, &len) == C4G_OK) {
                t += 2000000U;
                (void)send_ctrl(&lp, b, len, t, &ev);
                (void)c4g_loop_reply(&lp, out, sizeof out, &len, NULL);
            }
            for (i = 0; i < N_AX; i++) {
                w.ax[i].mode = 0;
            }
            w.have_sent = 0;
            handshake(&lp, &w, 1, &t);
            continue;
        }
        /* the controller's tick: the mode PDL2 sets, its own trajectory */
        {
            int32_t arm_mode = (w.kind == W_HONEST) ? next_mode_honest(&c, &w.ax[0]) : next_mode_any(&c);
            const uint8_t mixed = (w.kind == W_HONEST) ? 0U : u8(&c);
            for (i = 0; i < N_AX; i++) {
                ax_t *a = &w.ax[i];
                const int32_t m = ((mixed >> i) & 1U) ? a->mode : arm_mode;
                if (m == 502 && a->mode != 502) {
                    a->resume = a->mode;
                }
                a->mode = m;
                a->vel_i = (a->mode == 0 || a->mode == 2 || a->mode == 5 || a->mode == 7 ||
                            a->mode == 8 || a->mode == 9 || a->mode == 10)
                               ? ((double)(int8_t)u8(&c)) * 1e-4 : 0.0;
                if (a->mode == 9) {
                    a->own_cur = ((double)(int8_t)u8(&c)) / 4.0;
                }
            }
        }
        w.num = (w.num >= 0x7FFF) ? 0 : w.num + 1;
        report(&w, &c, &p);
        w.pkt = p;
        if (lost_rx) {
            apply_reply(&w, 0);
            w.have_sent = 0;
            continue;
        }
        if (c4g_ctrl_encode(&p, b, sizeof b, &len) != C4G_OK) {
            abort();
        }
        t += 2000000U;
        before = lp.counters.neutral_replies;
        if (!send_ctrl(&lp, b, len, t, &ev)) {
            break;
        }
        check_neutral(&lp, &p);
        if (ev.cmd != NULL) {
            for (i = 0; i < ev.cmd->n_axes && i < N_AX; i++) {
                c4g_pc_axis_t *a = &ev.cmd->ax[i];
                const float here = p.ax[i].target_pos;
                if ((u8(&c) & 7U) == 0U) {
                    continue; /* leave the prepared reply as it is */
                }
                a->target_pos = pc_value(&c, is_abs(p.ax[i].mode) ? here : 0.0f, 0.01f);
                a->target_vel = pc_value(&c, 0.0f, 0.01f);
                a->measure = pc_value(&c, 0.0f, 1.0f);
                a->vel_add = pc_value(&c, 0.0f, 0.01f);
                a->current_add = pc_value(&c, 0.0f, 10.0f);
                if ((u8(&c) & 0x1FU) == 0U) {
                    a->mode = next_mode_any(&c); /* a mode of the PC's own */
                }
            }
            if ((u8(&c) & 0x3FU) == 0U) {
                ev.cmd->n_axes = u8(&c) % 21U; /* a broken reply: the fallback */
            }
            switch (u8(&c) & 0x1FU) {
            case 0: (void)c4g_engine_request_exit(&lp.engine, 0); break;
            case 1: (void)c4g_engine_request_drive_off(&lp.engine, 0); break;
            case 2: (void)c4g_engine_request_freeze(&lp.engine, 0); break;
            case 3: (void)c4g_engine_request_follow_error(&lp.engine, 0); break;
            default: break;
            }
        }
        {
            if (c4g_loop_reply(&lp, out, sizeof out, &len, NULL) == C4G_OK && ev.kind == C4G_RX_CYCLIC) {
                c4g_pc_packet_t r;
                check_finite_bytes(out, len);
                if (c4g_pc_decode(out, len, N_AX, &r, NULL) != C4G_OK) {
                    fail("reply does not decode", 0, (double)len, 0.0);
                }
                check_reply(&lp, &w, &p, &r, lp.counters.neutral_replies != before);
                w.sent = r;
                w.have_sent = 1;
            } else {
                w.have_sent = 0;
            }
        }
        /* next tick the controller applies what arrived */
        apply_reply(&w, !lost_tx);
        if (!w.drives_on && (u8(&c) & 3U) == 0U) {
            w.drives_on = 1U;
        }
    }
    return 0;
}
