/* SPDX-License-Identifier: MIT */
/* libFuzzer target: arbitrary bytes drive a sequence of controller packets, PC requests,
   user limits and caller-filled replies through c4g_engine_step / c4g_safety_filter.
   Invariants (abort on violation): every finished reply encodes (no NaN, no unknown mode);
   each axis carries its echo or a safety / freezing mode (500, 505, 508), never a mode of
   the PC's; INFPAR bytes are 0 or EXIT_FROM_OPEN; currents in modes 1/2 stay within the
   limit; in mode 9 the delta only shrinks towards 0 and SMP+ current + delta stays within
   the limit unless SMP+ alone is beyond it; in modes 5, 7 and 8 the position the controller
   integrates to stays inside the stroke; finish returns only its documented statuses; moni
   rows always fit C4GH_MONI_ROW_MAX. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c4gopen.h"
#include "c4gh_csv.h"
#include "c4gsim_fixtures.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const int32_t modes[] = {0, 10, 1, 11, 2, 12, 3, 4, 14, 5, 15, 6, 7, 17, 170, 8, 9,
                                101, 102, 103, 201, 202, 500, 501, 502, 503, 504, 505, 506, 508};
#define N_MODES (sizeof modes / sizeof modes[0])

typedef struct cur {
    const uint8_t *p;
    size_t n;
} cur_t;

static int take(cur_t *c, uint8_t *b)
{
    if (c->n == 0) {
        return 0;
    }
    *b = *c->p;
    c->p++;
    c->n--;
    return 1;
}

static uint8_t byte(cur_t *c)
{
    uint8_t b = 0;
    (void)take(c, &b);
    return b;
}

static float small(cur_t *c)
{
    const int16_t v = (int16_t)(uint16_t)((uint16_t)byte(c) | ((uint16_t)byte(c) << 8));
    return (float)v / 64.0f;
}

/* A value the caller writes: mostly ordinary, sometimes hostile. */
static void fill_value(cur_t *c, float *f)
{
    const uint8_t b = byte(c);
    uint32_t u;
    switch (b) {
    case 0xFF: break;                                  /* leave it (maybe unset) */
    case 0xFE: u = 0x7FC00000u; memcpy(f, &u, 4); break; /* NaN */
    case 0xFD: u = 0x7F800000u; memcpy(f, &u, 4); break; /* +inf */
    case 0xFC: *f = 3.0e38f; break;
    case 0xFB: *f = -3.0e38f; break;
    default: *f = (float)(int8_t)b / 4.0f; break;
    }
}

static void check_at(int cond, int line)
{
    if (!cond) {
        fprintf(stderr, "fuzz_control: invariant at line %d broken\n", line);
        abort();
    }
}
#define check(cond) check_at((cond), __LINE__)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cur_t c = {data, size};
    c4g_init_t in;
    c4g_engine_t ctl;
    c4g_engine_config_t cfg;
    uint32_t n_axes, tick;
    int32_t num = 0;
    const uint8_t setup = byte(&c);

    (void)c4gsim_fig10_1(&in);
    if (setup & 1u) { /* a second arm with two axes */
        in.n_ax_open = 8;
        in.open_ax[1][0] = 6;
        in.open_ax[1][1] = 7;
        in.az_lim[1][0] = 5.0f;
        in.az_lim[1][1] = 2.0f;
        in.tx_rate[1][0] = 10.0f;
        in.tx_rate[1][1] = -20.0f;
        in.follow_error[1][1] = 0.5f;
    }
    n_axes = (uint32_t)in.n_ax_open;
    (void)c4g_engine_config_default(&cfg);
    cfg.request_timeout_ticks = 1u + (setup >> 4);
    cfg.start_ns = (uint64_t)((setup >> 1) & 7u) * 1000000u;
    check(c4g_engine_init(&ctl, &in, &cfg) == C4G_OK);

    for (tick = 0; tick < 64 && c.n > 0; tick++) {
        c4g_ctrl_packet_t rx;
        c4g_pc_packet_t tx;
        c4g_engine_report_t rep;
        int32_t arm_mode[C4G_ARMS];
        uint32_t i, a;
        const uint8_t op = byte(&c);
        const uint32_t arm = (op >> 3) & 3u;
        c4g_status_t st;

        switch (op & 7u) {
        case 1: check(c4g_engine_request_mode(&ctl, arm, modes[byte(&c) % N_MODES]) != C4G_OK); break;
        case 2: (void)c4g_engine_request_exit(&ctl, arm); break;
        case 3: (void)c4g_engine_request_drive_off(&ctl, arm); break;
        case 4: (void)c4g_engine_request_follow_error(&ctl, arm); break;
        case 5: (void)c4g_engine_request_freeze(&ctl, arm); break;
        case 7: {
            c4g_axis_limits_t l;
            memset(&l, 0, sizeof l);
            l.follow_error = (float)(byte(&c) & 15u) / 2.0f;
            l.current_max = (float)(byte(&c) & 31u);
            l.max_step = (float)(byte(&c) & 7u) / 4.0f;
            l.max_vel = (float)(byte(&c) & 7u) / 8.0f;
            l.motor_min = small(&c);
            l.motor_max = small(&c);
            l.joint_min = small(&c) / 8.0f;
            l.joint_max = small(&c) / 8.0f;
            (void)c4g_engine_set_limits(&ctl, arm, byte(&c) % 10u, &l);
            break;
        }
        default: break;
        }

        memset(&rx, 0, sizeof rx);
        num = (num >= C4G_NUM_MAX) ? 0 : num + 1;
        rx.num = num;
        rx.n_axes = n_axes;
        rx.cmd = byte(&c);
        for (a = 0; a < C4G_ARMS; a++) {
            const uint8_t b = byte(&c);
            rx.infpar = c4g_arm_byte_set(rx.infpar, a, (b & 1u) ? (uint8_t)C4G_STS_MOVING : 0u);
            arm_mode[a] = modes[(b >> 1) % N_MODES];
        }
        for (i = 0; i < n_axes; i++) {
            const uint8_t b = byte(&c);
            rx.ax[i].mode = (b < 224u) ? arm_mode[ctl.map.arm_of[i]] : modes[b % N_MODES];
            rx.ax[i].target_pos = small(&c);
            rx.ax[i].actual_pos = rx.ax[i].target_pos + (float)(int8_t)byte(&c) / 8.0f;
            rx.ax[i].target_vel = (float)(int8_t)byte(&c) / 128.0f;
            rx.ax[i].current_ref = (float)(int8_t)byte(&c) / 4.0f;
        }
        st = c4g_engine_step(&ctl, &rx, (uint64_t)tick * 2000000u, &tx, &rep);
        check(st == C4G_OK);
        for (i = 0; i < n_axes; i++) {
            fill_value(&c, &tx.ax[i].target_pos);
            fill_value(&c, &tx.ax[i].target_vel);
            fill_value(&c, &tx.ax[i].measure);
            fill_value(&c, &tx.ax[i].vel_add);
            fill_value(&c, &tx.ax[i].current_add);
            if (byte(&c) == 0xAAu) {
                tx.ax[i].mode = modes[byte(&c) % N_MODES]; /* a forbidden write */
            }
        }
        c4g_pc_packet_t req = tx; /* what the caller asked, before the filter */
        st = c4g_safety_filter(&ctl, &rx, &tx, &rep);
        check(st == C4G_OK || st == (c4g_status_t)C4G_ERR_MISSING_DATA ||
              st == C4G_ERR_NONFINITE || st == (c4g_status_t)C4G_ERR_MODE_RESTORED);
        {
            uint8_t buf[C4G_MAX_CYCLIC_SIZE];
            size_t len = 0;
            check(c4g_pc_encode(&tx, buf, sizeof buf, &len) == C4G_OK);
            check(len == C4G_CYCLIC_SIZE(n_axes));
        }
        for (a = 0; a < C4G_ARMS; a++) {
            const uint8_t b = c4g_arm_byte(tx.infpar, a);
            check(b == 0u || b == (uint8_t)C4G_EXIT_FROM_OPEN);
        }
        for (i = 0; i < n_axes; i++) {
            const int32_t m = tx.ax[i].mode;
            const int32_t p = ctl.priv.prep_mode[i];
            const c4g_arm_sm_t *sm = &ctl.arm[ctl.map.arm_of[i]];
            const float lim = ctl.lim[i].current_max;
            const int held = (rep.axis_flags[i] & C4G_SF_HELD) != 0;
            /* the PC echoes the controller's mode, or asks 500 / 505 / 508: never a mode */
            check(m == rx.ax[i].mode || m == 500 || m == 505 || m == 508);
            check(p == rx.ax[i].mode);
            (void)sm;
            if ((p == 1 || p == 2 || p == 11 || p == 12) && !(rep.axis_flags[i] & C4G_SF_HELD)) {
                check(tx.ax[i].current_add <= lim && tx.ax[i].current_add >= -lim);
            }
            if (p == 9 && !held) {
                /* shrink towards 0 only: never created, never reversed; within the limit
                 * unless SMP+ alone is already beyond it */
                const float out = tx.ax[i].current_add, in = req.ax[i].current_add;
                const float s = rx.ax[i].current_ref + out;
                const float smp = rx.ax[i].current_ref;
                const float bound = (smp > lim || smp < -lim) ? (smp < 0 ? -smp : smp) : lim;
                check(out * in >= 0.0f && (out < 0 ? -out : out) <= (in < 0 ? -in : in));
                check(s <= bound * 1.0001f + 1e-3f && s >= -bound * 1.0001f - 1e-3f);
            }
            if ((p == 5 || p == 7 || p == 8) && m == p && !held && ctl.lim[i].motor_min < ctl.lim[i].motor_max &&
                !(rep.axis_flags[i] & C4G_SF_NONFINITE)) {
                /* the position the controller integrates to stays in the stroke it was in:
                 * from its reference advanced by its own target velocity (fig. 14.1) */
                const float base = rx.ax[i].target_pos + rx.ax[i].target_vel;
                const float d = (p == 5) ? tx.ax[i].target_vel
                                : (p == 7) ? tx.ax[i].target_pos : tx.ax[i].vel_add;
                const float lo = ctl.lim[i].motor_min, hi = ctl.lim[i].motor_max;
                const float tol = 1e-5f * (1.0f + (base < 0 ? -base : base));
                if (base >= lo && base <= hi && !(rep.axis_flags[i] & C4G_SF_STROKE_JOINT)) {
                    check(base + d <= hi + tol && base + d >= lo - tol);
                }
            }
            if (rep.axis_flags[i] & (C4G_SF_MISSING | C4G_SF_NONFINITE)) {
                check(m == 505 || m == 508);
            }
            {
                c4g_moni_rec_t r;
                char row[C4GH_MONI_ROW_MAX];
                size_t len = 0;
                check(c4g_moni_record(19u + (tick % 6u), &rx, &tx, i, &r) == C4G_OK);
                check(c4gh_moni_csv_row(&r, row, sizeof row, &len) == C4G_OK);
            }
        }
    }
    return 0;
}
