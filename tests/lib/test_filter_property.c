/* SPDX-License-Identifier: MIT */
/* Property test, mode by mode: random PC requests go through the safety filter
 * (c4g_engine_step / c4g_safety_filter) and then through c4g-sim's model of what the controller
 * does with the fields (c4gsim_ref_step, the code c4g-sim runs). Whatever the PC asks, the
 * reference the controller integrates never leaves the stroke and never steps more than the
 * continuity limit; currents never exceed the limit and a mode-9 delta only ever shrinks.
 * The simulator source is included directly: it is not part of the library. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "c4gsim_model.h"
#include "c4gsim_fixtures.h"

#define N_AX 6U
#define TICKS 400
#define SEEDS 150
#define T_S 0.002
#define MAX_STEP 0.01f
#define MAX_VEL 0.008f
#define LO (-0.5f)
#define HI 0.5f

typedef struct world {
    c4g_engine_t ctl;
    c4gsim_ref_t ref[N_AX];
    double pos_i[N_AX];
    float last_d2[N_AX]; /* what the controller reports as its target velocity */
    float cur[N_AX];     /* its own current */
    int32_t num;
} world_t;

static double uniform(c4gsim_rng_t *r)
{
    double u = 0.0;
    assert_int_equal(c4gsim_rng_uniform(r, &u), C4G_OK);
    return u;
}

static float uni(c4gsim_rng_t *r, float a, float b)
{
    return a + (b - a) * (float)uniform(r);
}

/* A request that is sometimes tame, sometimes absurd. */
static float wild(c4gsim_rng_t *r, float tame)
{
    const double u = uniform(r);
    if (u < 0.6) {
        return uni(r, -tame, tame);
    }
    if (u < 0.9) {
        return uni(r, -20.0f * tame, 20.0f * tame);
    }
    return uni(r, -2.0f, 2.0f);
}

static void world_init(world_t *w, c4gsim_rng_t *rng)
{
    c4g_init_t in;
    c4g_axis_limits_t l;
    uint32_t i;
    memset(w, 0, sizeof *w);
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_engine_init(&w->ctl, &in, NULL), C4G_OK);
    memset(&l, 0, sizeof l);
    l.max_step = MAX_STEP;
    l.max_vel = MAX_VEL;
    l.motor_min = LO;
    l.motor_max = HI;
    l.current_max = 10.0f;
    for (i = 0; i < N_AX; i++) {
        assert_int_equal(c4g_engine_set_limits(&w->ctl, 0, i, &l), C4G_OK);
        w->pos_i[i] = uni(rng, 0.9f * LO, 0.9f * HI);
        w->ref[i].pos_k = w->pos_i[i];
        w->ref[i].pos_ref = w->pos_i[i];
        w->cur[i] = uni(rng, -12.0f, 12.0f);
    }
}

/* One controller packet in @p mode, as the controller reports its own state. */
static void controller_packet(const world_t *w, int32_t mode, c4g_ctrl_packet_t *rx)
{
    uint32_t i;
    memset(rx, 0, sizeof *rx);
    rx->num = w->num;
    rx->n_axes = N_AX;
    rx->infpar = C4G_STS_MOVING;
    for (i = 0; i < N_AX; i++) {
        rx->ax[i].mode = mode;
        rx->ax[i].target_pos = (float)w->ref[i].pos_ref;
        rx->ax[i].target_vel = w->last_d2[i];
        rx->ax[i].actual_pos = (float)w->ref[i].pos_ref; /* the robot follows */
        rx->ax[i].current_ref = w->cur[i];
    }
}

static void fill_request(c4gsim_rng_t *r, int32_t mode, const c4g_ctrl_axis_t *rx, c4g_pc_axis_t *a)
{
    a->target_pos = wild(r, MAX_STEP);
    if (mode == C4G_MODE_4 || mode == C4G_MODE_1) {
        a->target_pos = rx->target_pos + wild(r, MAX_STEP); /* absolute */
    }
    a->target_vel = wild(r, MAX_STEP);
    a->measure = 0.0f;
    a->vel_add = wild(r, MAX_STEP);
    a->current_add = uni(r, -40.0f, 40.0f);
}

static long ticks_run;

static int run_mode(int32_t mode, uint64_t seed)
{
    world_t w;
    c4gsim_rng_t rng;
    int tick;
    assert_int_equal(c4gsim_rng_seed(&rng, seed), C4G_OK);
    world_init(&w, &rng);
    for (tick = 0; tick < TICKS; tick++) {
        const int32_t m = (tick < 3) ? C4G_MODE_0 : mode; /* the robot stands in mode 0 first */
        c4g_ctrl_packet_t rx;
        c4g_pc_packet_t tx;
        c4g_pc_packet_t asked;
        c4g_engine_report_t rep;
        uint32_t i;
        int stopped = 0;
        w.num++;
        controller_packet(&w, m, &rx);
        assert_int_equal(c4g_engine_step(&w.ctl, &rx, (uint64_t)tick * 2000000U, &tx, &rep), C4G_OK);
        for (i = 0; i < N_AX; i++) {
            fill_request(&rng, m, &rx.ax[i], &tx.ax[i]);
        }
        asked = tx;
        (void)c4g_safety_filter(&w.ctl, &rx, &tx, &rep);
        for (i = 0; i < N_AX; i++) {
            if (tx.ax[i].mode == C4G_MODE_DRIVE_OFF || tx.ax[i].mode == C4G_MODE_FOLLOW_ERROR) {
                stopped = 1; /* the controller takes the drives off: nothing moves any more */
            }
        }
        if (stopped) {
            break;
        }
        ticks_run++;
        for (i = 0; i < N_AX; i++) {
            const double before = w.ref[i].pos_ref;
            const c4g_pc_axis_t *a = &tx.ax[i];
            c4gsim_dsa_in_t in;
            double step;
            assert_int_equal(c4gsim_ref_step(&w.ref[i], m, a, w.pos_i[i], 0.0, 1.0, T_S, &in), C4G_OK);
            step = in.pos_ref - before;
            if (m == C4G_MODE_1 || m == C4G_MODE_2 || m == C4G_MODE_1_STANDBY) {
                if (a->current_add > 10.0f || a->current_add < -10.0f) {
                    fail_msg("mode %d seed %llu tick %d axis %u: current %g past 10 A", (int)m,
                             (unsigned long long)seed, tick, i, (double)a->current_add);
                }
            }
            if (m == C4G_MODE_9) {
                const float out = a->current_add, req = asked.ax[i].current_add;
                if (out * req < 0.0f || (out < 0 ? -out : out) > (req < 0 ? -req : req)) {
                    fail_msg("mode 9 seed %llu tick %d axis %u: asked %g, sent %g",
                             (unsigned long long)seed, tick, i, (double)req, (double)out);
                }
            }
            if (in.pos_ref > (double)HI + 1e-6 || in.pos_ref < (double)LO - 1e-6) {
                fail_msg("mode %d seed %llu tick %d axis %u: reference %.9f out of [%g, %g]",
                         (int)m, (unsigned long long)seed, tick, i, in.pos_ref, (double)LO,
                         (double)HI);
            }
            if (step > (double)MAX_STEP + 1e-6 || step < -(double)MAX_STEP - 1e-6) {
                fail_msg("mode %d seed %llu tick %d axis %u: reference stepped %.9f", (int)m,
                         (unsigned long long)seed, tick, i, step);
            }
            /* what the controller reports as its target velocity next tick */
            w.last_d2[i] = (float)(in.vel_ff * T_S);
        }
    }
    return tick;
}

static void test_property_modes(void **state)
{
    static const int32_t modes[] = {C4G_MODE_1, C4G_MODE_2, C4G_MODE_4, C4G_MODE_5,
                                    C4G_MODE_7, C4G_MODE_8, C4G_MODE_9};
    size_t k;
    uint64_t seed;
    (void)state;
    for (k = 0; k < sizeof modes / sizeof modes[0]; k++) {
        long stops = 0;
        ticks_run = 0;
        for (seed = 1; seed <= SEEDS; seed++) {
            stops += (run_mode(modes[k], seed * 7919U + (uint64_t)modes[k]) < TICKS) ? 1 : 0;
        }
        print_message("mode %d: %ld ticks checked, %ld of %d runs ended in a safety stop\n",
                      (int)modes[k], ticks_run, stops, SEEDS);
        /* the runs must go on long enough to mean something */
        assert_true(ticks_run > (long)SEEDS * 50);
    }
}

/* Without the filter, the same requests leave the stroke: the property can fail. */
static void test_property_needs_the_filter(void **state)
{
    c4gsim_ref_t r = {0.0, 0.0, 0.0};
    c4g_pc_axis_t a;
    c4gsim_dsa_in_t in;
    int k;
    (void)state;
    memset(&a, 0, sizeof a);
    a.target_vel = 0.25f; /* mode 5: 0.25 turns a tick, integrated */
    for (k = 0; k < 10; k++) {
        assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_5, &a, 0.0, 0.0, 1.0, T_S, &in), C4G_OK);
    }
    assert_true(in.pos_ref > 2.0);
    memset(&r, 0, sizeof r);
    a.target_vel = 0.0f;
    a.vel_add = 0.5f; /* mode 8: D4 integrated into the reference */
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_8, &a, 0.0, 0.0, 1.0, T_S, &in), C4G_OK);
    assert_true(in.pos_ref > 0.49);
    /* no reply of the mode: the reference holds */
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_8, NULL, 0.0, 0.0, 1.0, T_S, &in), C4G_OK);
    assert_true(in.pos_ref > 0.49 && in.pos_ref < 0.51);
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_4, NULL, 0.0, 0.0, 1.0, T_S, &in), C4G_OK);
    assert_true(in.pos_ref > 0.49 && in.pos_ref < 0.51);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_property_modes),
        cmocka_unit_test(test_property_needs_the_filter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
