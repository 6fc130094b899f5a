/* SPDX-License-Identifier: MIT */
/* Unit tests of lib/sim/c4gsim_model.c: the random generator, one axis with its DSA loop,
 * the interpolation, the trapezoidal profile and the controller's reference per mode. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "c4gsim_model.h"

#define TWO_PI 6.283185307179586
#define RNG_MUL 0x2545F4914F6CDD1DULL

/* ---- random numbers --------------------------------------------------------- */

static void test_rng_repeatable(void **state)
{
    c4gsim_rng_t a;
    c4gsim_rng_t b;
    uint64_t x = 0;
    uint64_t y = 0;
    int i;
    (void)state;
    assert_int_equal(c4gsim_rng_seed(&a, 42), C4G_OK);
    assert_int_equal(c4gsim_rng_seed(&b, 42), C4G_OK);
    for (i = 0; i < 1000; i++) {
        assert_int_equal(c4gsim_rng_next(&a, &x), C4G_OK);
        assert_int_equal(c4gsim_rng_next(&b, &y), C4G_OK);
        assert_true(x == y);
    }
    assert_int_equal(c4gsim_rng_seed(&b, 43), C4G_OK);
    assert_int_equal(c4gsim_rng_next(&a, &x), C4G_OK);
    assert_int_equal(c4gsim_rng_next(&b, &y), C4G_OK);
    assert_false(x == y);
}

/* xorshift64* by hand: the first value of seed 0 */
static void test_rng_values(void **state)
{
    c4gsim_rng_t r;
    uint64_t s = 0x9E3779B97F4A7C15ULL;
    uint64_t x = 0;
    double u = -1.0;
    (void)state;
    assert_int_equal(c4gsim_rng_seed(&r, 0), C4G_OK);
    assert_true(r.s == s);
    s ^= s >> 12;
    s ^= s << 25;
    s ^= s >> 27;
    assert_int_equal(c4gsim_rng_next(&r, &x), C4G_OK);
    assert_true(x == s * RNG_MUL);
    assert_true(r.s == s);
    assert_int_equal(c4gsim_rng_uniform(&r, &u), C4G_OK);
    assert_true(u >= 0.0 && u < 1.0);
    /* the seed that would make the state 0 gets a fixed non-zero state instead */
    assert_int_equal(c4gsim_rng_seed(&r, 0x9E3779B97F4A7C15ULL), C4G_OK);
    assert_true(r.s == RNG_MUL);
    assert_false(r.have_spare);
}

/* Inverse of x ^= x >> k (k > 0) and of x ^= x << k on 64 bits. */
static uint64_t unxor_right(uint64_t y, unsigned k)
{
    uint64_t x = y;
    unsigned i;
    for (i = 0; i < 64U / k + 1U; i++) {
        x = y ^ (x >> k);
    }
    return x;
}

static uint64_t unxor_left(uint64_t y, unsigned k)
{
    uint64_t x = y;
    unsigned i;
    for (i = 0; i < 64U / k + 1U; i++) {
        x = y ^ (x << k);
    }
    return x;
}

/* The state whose next output is @p out. */
static uint64_t state_before(uint64_t out)
{
    uint64_t inv = RNG_MUL; /* Newton: inverse of the odd multiplier mod 2^64 */
    uint64_t x;
    int i;
    for (i = 0; i < 6; i++) {
        inv *= 2U - RNG_MUL * inv;
    }
    x = out * inv;
    return unxor_right(unxor_left(unxor_right(x, 27), 25), 12);
}

static void test_rng_gauss(void **state)
{
    c4gsim_rng_t r;
    c4gsim_rng_t q;
    double g1 = 0.0;
    double g2 = 0.0;
    double u1 = 0.0;
    double u2 = 0.0;
    double m;
    (void)state;
    assert_int_equal(c4gsim_rng_seed(&r, 5), C4G_OK);
    q = r;
    assert_int_equal(c4gsim_rng_gauss(&r, &g1), C4G_OK);
    assert_true(r.have_spare);
    assert_int_equal(c4gsim_rng_gauss(&r, &g2), C4G_OK);
    assert_false(r.have_spare);
    /* Box-Muller of two uniforms: cosine first, the sine kept for the next call */
    assert_int_equal(c4gsim_rng_uniform(&q, &u1), C4G_OK);
    assert_int_equal(c4gsim_rng_uniform(&q, &u2), C4G_OK);
    m = sqrt(-2.0 * log(u1));
    assert_true(g1 == m * cos(TWO_PI * u2));
    assert_true(g2 == m * sin(TWO_PI * u2));
    /* a uniform of exactly 0 cannot go into log(): it is drawn again */
    assert_true(state_before(5U) != 0U);
    r.s = state_before(5U); /* next output 5: 5 >> 11 = 0 */
    q = r;
    assert_int_equal(c4gsim_rng_uniform(&q, &u1), C4G_OK);
    assert_true(u1 == 0.0);
    q = r;
    assert_int_equal(c4gsim_rng_uniform(&q, &u1), C4G_OK);
    assert_int_equal(c4gsim_rng_uniform(&q, &u1), C4G_OK); /* the redraw */
    assert_int_equal(c4gsim_rng_uniform(&q, &u2), C4G_OK);
    assert_int_equal(c4gsim_rng_gauss(&r, &g1), C4G_OK);
    assert_true(g1 == sqrt(-2.0 * log(u1)) * cos(TWO_PI * u2));
}

static void test_rng_null(void **state)
{
    c4gsim_rng_t r;
    uint64_t x;
    double d;
    (void)state;
    assert_int_equal(c4gsim_rng_seed(NULL, 1), C4G_ERR_NULL);
    assert_int_equal(c4gsim_rng_seed(&r, 1), C4G_OK);
    assert_int_equal(c4gsim_rng_next(NULL, &x), C4G_ERR_NULL);
    assert_int_equal(c4gsim_rng_next(&r, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_rng_uniform(NULL, &d), C4G_ERR_NULL);
    assert_int_equal(c4gsim_rng_uniform(&r, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_rng_gauss(NULL, &d), C4G_ERR_NULL);
    assert_int_equal(c4gsim_rng_gauss(&r, NULL), C4G_ERR_NULL);
}

/* ---- parameters --------------------------------------------------------------- */

static void test_params_default(void **state)
{
    c4gsim_axis_params_t p;
    (void)state;
    assert_int_equal(c4gsim_axis_params_default(NULL, 0), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_params_default(&p, 1), C4G_OK);
    assert_true(p.j == 4e-4 && p.kt == 0.8 && p.fc == 0.15 && p.gravity == 6.0);
    assert_true(p.kv == 150.0 * TWO_PI * 4e-4 / 0.8 && p.ki == p.kv * 40.0);
    assert_true(p.tx_rate == 159.260864 && p.az_lim == 24.5 && p.follow_error == 7.5);
    assert_int_equal(c4gsim_axis_params_check(&p), C4G_OK);
    assert_int_equal(c4gsim_axis_params_default(&p, 2), C4G_OK);
    assert_true(p.gravity == 3.0);
    assert_int_equal(c4gsim_axis_params_default(&p, 11), C4G_OK); /* axis 6's values again */
    assert_true(p.kt == 0.5 && p.fc == 0.05 && p.j == 8e-5 && p.tx_rate == -50.0 && p.gravity == 0.0);
    assert_true(p.follow_error == 0.0);
}

static void test_params_check(void **state)
{
    static const size_t positive[] = {offsetof(c4gsim_axis_params_t, j), offsetof(c4gsim_axis_params_t, kt)};
    static const size_t non_negative[] = {
        offsetof(c4gsim_axis_params_t, vs),     offsetof(c4gsim_axis_params_t, cur_noise),
        offsetof(c4gsim_axis_params_t, torque_noise), offsetof(c4gsim_axis_params_t, az_lim),
        offsetof(c4gsim_axis_params_t, counts), offsetof(c4gsim_axis_params_t, noise),
        offsetof(c4gsim_axis_params_t, vel_filter)};
    c4gsim_axis_params_t p;
    size_t off;
    size_t i;
    (void)state;
    assert_int_equal(c4gsim_axis_params_check(NULL), C4G_ERR_NULL);
    /* every double: NaN and infinity are refused */
    for (off = 0; off < offsetof(c4gsim_axis_params_t, startup_mode); off += sizeof(double)) {
        assert_int_equal(c4gsim_axis_params_default(&p, 0), C4G_OK);
        *(double *)(void *)((char *)&p + off) = NAN;
        assert_int_equal(c4gsim_axis_params_check(&p), C4G_ERR_NONFINITE);
        *(double *)(void *)((char *)&p + off) = -INFINITY;
        assert_int_equal(c4gsim_axis_params_check(&p), C4G_ERR_NONFINITE);
    }
    for (i = 0; i < sizeof positive / sizeof positive[0]; i++) {
        assert_int_equal(c4gsim_axis_params_default(&p, 0), C4G_OK);
        *(double *)(void *)((char *)&p + positive[i]) = 0.0;
        assert_int_equal(c4gsim_axis_params_check(&p), C4G_ERR_RANGE);
    }
    for (i = 0; i < sizeof non_negative / sizeof non_negative[0]; i++) {
        assert_int_equal(c4gsim_axis_params_default(&p, 0), C4G_OK);
        *(double *)(void *)((char *)&p + non_negative[i]) = 0.0;
        assert_int_equal(c4gsim_axis_params_check(&p), C4G_OK);
        *(double *)(void *)((char *)&p + non_negative[i]) = -1e-9;
        assert_int_equal(c4gsim_axis_params_check(&p), C4G_ERR_RANGE);
    }
    assert_int_equal(c4gsim_axis_params_default(&p, 0), C4G_OK);
    p.vel_filter = 1.0;
    assert_int_equal(c4gsim_axis_params_check(&p), C4G_OK);
    p.vel_filter = 1.0 + 1e-12;
    assert_int_equal(c4gsim_axis_params_check(&p), C4G_ERR_RANGE);
}

/* ---- one axis ------------------------------------------------------------------ */

/* Noise-free axis 1 with an ideal encoder, reset at 0. */
static void quiet_axis(c4gsim_axis_params_t *p, c4gsim_axis_t *a, c4gsim_rng_t *r)
{
    assert_int_equal(c4gsim_axis_params_default(p, 0), C4G_OK);
    p->noise = 0.0;
    p->counts = 0.0;
    assert_int_equal(c4gsim_rng_seed(r, 1), C4G_OK);
    assert_int_equal(c4gsim_axis_reset(a, p, r), C4G_OK);
}

static void test_axis_reset(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    (void)state;
    assert_int_equal(c4gsim_axis_params_default(&p, 0), C4G_OK);
    p.pos0 = 0.3;
    assert_int_equal(c4gsim_rng_seed(&r, 1), C4G_OK);
    assert_int_equal(c4gsim_axis_reset(NULL, &p, &r), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_reset(&a, NULL, &r), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_reset(&a, &p, NULL), C4G_ERR_NULL);
    p.kt = -1.0;
    assert_int_equal(c4gsim_axis_reset(&a, &p, &r), C4G_ERR_RANGE);
    p.kt = 0.8;
    assert_int_equal(c4gsim_axis_reset(&a, &p, &r), C4G_OK);
    /* the encoder: 16384 counts per turn, one noise draw */
    assert_true(fabs(a.meas_pos - 0.3) <= 0.5 / 16384.0 + 1e-4);
    assert_true(a.meas_pos * 16384.0 == floor(a.meas_pos * 16384.0));
    assert_true(a.prev_meas == a.meas_pos && a.pos == 0.3 && a.vel == 0.0);
    assert_false(a.drive_on);
    p.counts = 0.0;
    p.noise = 0.0;
    assert_int_equal(c4gsim_axis_reset(&a, &p, &r), C4G_OK);
    assert_true(a.meas_pos == 0.3); /* no quantization, no noise */
}

static void test_friction_gravity(void **state)
{
    c4gsim_axis_params_t p;
    (void)state;
    assert_int_equal(c4gsim_axis_params_default(&p, 1), C4G_OK);
    assert_true(c4gsim_axis_friction_level(&p, 3.0) == p.fc);
    p.vs = 2.0;
    p.fs = 0.3;
    assert_true(c4gsim_axis_friction_level(&p, 0.0) == 0.3);
    assert_true(c4gsim_axis_friction_level(&p, 2.0) == 0.15 + 0.15 * exp(-1.0));
    /* a quarter of a link turn: full gravity */
    assert_true(fabs(c4gsim_axis_gravity(&p, p.tx_rate / 4.0) - 6.0) < 1e-12);
    p.tx_rate = 0.0; /* no ratio: the motor angle itself */
    assert_true(fabs(c4gsim_axis_gravity(&p, 0.25) - 6.0) < 1e-12);
}

static void test_axis_step_errors(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_axis_t before;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    double *field[6];
    size_t i;
    (void)state;
    memset(&a, 0, sizeof a); /* the padding too: compared byte by byte below */
    quiet_axis(&p, &a, &r);
    memset(&in, 0, sizeof in);
    assert_int_equal(c4gsim_axis_step(NULL, &p, &in, 1e-3, &r), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_step(&a, NULL, &in, 1e-3, &r), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_step(&a, &p, NULL, 1e-3, &r), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 1e-3, NULL), C4G_ERR_NULL);
    p.j = 0.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 1e-3, &r), C4G_ERR_RANGE);
    p.j = 4e-4;
    memcpy(&before, &a, sizeof before);
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, NAN, &r), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0, &r), C4G_ERR_RANGE);
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, -1e-3, &r), C4G_ERR_RANGE);
    field[0] = &in.pos_ref;
    field[1] = &in.vel_ff;
    field[2] = &in.vel_add;
    field[3] = &in.cur_add;
    field[4] = &in.cur_pc;
    field[5] = &in.pc_share;
    for (i = 0; i < 6U; i++) {
        *field[i] = INFINITY;
        assert_int_equal(c4gsim_axis_step(&a, &p, &in, 1e-3, &r), C4G_ERR_NONFINITE);
        *field[i] = 0.0;
    }
    assert_memory_equal(&a, &before, sizeof a); /* refused: nothing changed */
}

/* The split: c4gsim_dsa_current is the loops of c4gsim_axis_step without the plant, and
 * c4gsim_axis_measure its encoder; the same inputs give the same current and reading. */
static void test_dsa_current_split(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_axis_t b;
    c4gsim_axis_t before;
    c4gsim_rng_t r;
    c4gsim_rng_t rb;
    c4gsim_dsa_in_t in;
    int k;
    (void)state;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    assert_int_equal(c4gsim_axis_params_default(&p, 1), C4G_OK);
    assert_int_equal(c4gsim_rng_seed(&r, 3), C4G_OK);
    assert_int_equal(c4gsim_axis_reset(&a, &p, &r), C4G_OK);
    a.drive_on = true;
    memcpy(&b, &a, sizeof b);
    memcpy(&rb, &r, sizeof rb);
    memset(&in, 0, sizeof in);
    in.pos_ref = 0.5;
    in.vel_ff = 2.0;
    in.cur_add = 0.3;
    for (k = 0; k < 50; k++) {
        assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
        /* b: the loops, then the same true motion, then the encoder */
        assert_int_equal(c4gsim_dsa_current(&b, &p, &in, 0.0005), C4G_OK);
        assert_true(b.cur == a.cur && b.integ == a.integ && b.ff_vel == a.ff_vel);
        b.pos = a.pos;
        b.vel = a.vel;
        assert_int_equal(c4gsim_axis_measure(&b, &p, 0.0005, &rb), C4G_OK);
        assert_true(b.meas_pos == a.meas_pos && b.meas_vel == a.meas_vel);
    }
    assert_true(a.pos > 0.0); /* it moved */
    /* refusals leave the axis as it was */
    memcpy(&before, &b, sizeof before);
    assert_int_equal(c4gsim_dsa_current(NULL, &p, &in, 0.0005), C4G_ERR_NULL);
    assert_int_equal(c4gsim_dsa_current(&b, NULL, &in, 0.0005), C4G_ERR_NULL);
    assert_int_equal(c4gsim_dsa_current(&b, &p, NULL, 0.0005), C4G_ERR_NULL);
    assert_int_equal(c4gsim_dsa_current(&b, &p, &in, NAN), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_dsa_current(&b, &p, &in, 0.0), C4G_ERR_RANGE);
    in.cur_add = NAN;
    assert_int_equal(c4gsim_dsa_current(&b, &p, &in, 0.0005), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_axis_measure(NULL, &p, 0.0005, &rb), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_measure(&b, &p, 0.0005, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_measure(&b, NULL, 0.0005, &rb), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_measure(&b, &p, INFINITY, &rb), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_axis_measure(&b, &p, -1.0, &rb), C4G_ERR_RANGE);
    b.pos = NAN;
    assert_int_equal(c4gsim_axis_measure(&b, &p, 0.0005, &rb), C4G_ERR_NONFINITE);
    b.pos = before.pos;
    assert_memory_equal(&b, &before, sizeof b);
    /* drive off: brakes, no current */
    in.cur_add = 0.3;
    b.drive_on = false;
    assert_int_equal(c4gsim_dsa_current(&b, &p, &in, 0.0005), C4G_OK);
    assert_true(b.cur == 0.0 && b.integ == 0.0 && b.vel == 0.0);
}

/* Drive off: the brakes hold, no current, the feedforward filter still runs. */
static void test_drive_off_brakes(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    int k;
    (void)state;
    assert_int_equal(c4gsim_axis_params_default(&p, 1), C4G_OK);
    p.pos0 = 3.0;
    assert_int_equal(c4gsim_rng_seed(&r, 1), C4G_OK);
    assert_int_equal(c4gsim_axis_reset(&a, &p, &r), C4G_OK);
    a.vel = 1.0;
    a.integ = 2.0;
    memset(&in, 0, sizeof in);
    in.pos_ref = 10.0;
    in.vel_ff = 4.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.ff_vel == 0.25 * 0.5 * 4.0 && a.prev_ff == 4.0);
    for (k = 0; k < 99; k++) {
        assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    }
    assert_true(a.pos == 3.0 && a.cur == 0.0 && a.vel == 0.0 && a.integ == 0.0);
    assert_int_equal(a.cur_n, 100);
    assert_false(a.saturated);
}

/* One step by hand: P and PI loops, the plant's midpoint rule and the encoder. */
static void test_axis_step_values(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    const double dt = 0.0005;
    double e;
    double cur;
    double torque;
    double net;
    double v_mid;
    double vel;
    (void)state;
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    memset(&in, 0, sizeof in);
    in.pos_ref = 0.01;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, dt, &r), C4G_OK);
    e = p.kp * 0.01;
    cur = p.kv * e + p.ki * e * dt;
    assert_true(a.integ == p.ki * e * dt);
    assert_true(a.cur == cur && a.cur_sum == cur && a.cur_n == 1U);
    assert_false(a.saturated);
    /* from rest: the torque beats Coulomb friction (gravity 0 on axis 1) */
    torque = p.kt * cur;
    assert_true(torque > p.fc);
    net = torque - p.fc;
    vel = net / (p.j * TWO_PI) * dt;
    assert_true(a.vel == vel);
    assert_true(a.pos == 0.5 * vel * dt);
    assert_true(a.meas_pos == a.pos && a.meas_vel == 0.25 * (a.pos / dt));
    /* moving on: friction at the mid velocity of the step */
    {
        const c4gsim_axis_t b = a;
        const double v_old = b.vel;
        const double vel_cmd = p.kp * (0.01 - b.meas_pos) + b.ff_vel;
        double i2;
        double integ = b.integ;
        e = vel_cmd - b.meas_vel;
        integ += p.ki * e * dt;
        i2 = p.kv * e + integ;
        assert_int_equal(c4gsim_axis_step(&a, &p, &in, dt, &r), C4G_OK);
        assert_true(a.cur == i2);
        net = p.kt * i2 - p.fv * TWO_PI * v_old - p.fc;
        v_mid = v_old + 0.5 * dt * net / (p.j * TWO_PI);
        net = p.kt * i2 - p.fv * TWO_PI * v_mid - p.fc;
        assert_true(a.vel == v_old + net / (p.j * TWO_PI) * dt);
        assert_true(a.pos == b.pos + 0.5 * (v_old + a.vel) * dt);
    }
}

/* Current saturation, the integrator's anti-windup and the PC's share (chapter 12). */
static void test_axis_saturation_share(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    (void)state;
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    memset(&in, 0, sizeof in);
    in.pos_ref = 100.0; /* far away: the regulator saturates */
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    /* the regulator is clamped to AzLim itself; "saturated" is a total beyond it */
    assert_true(a.cur == p.az_lim && !a.saturated);
    assert_true(a.integ == 0.0); /* at its limit in the error's direction: no integration */
    /* a full PC share: the regulator is limited to 0, the PC's current passes */
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    in.pos_ref = 0.0;
    in.pc_share = 2.0; /* clamped to 1 */
    in.cur_pc = 0.5;
    in.cur_add = 0.25;
    a.integ = 3.0; /* clamped to rho * AzLim = 0 */
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.integ == 0.0 && a.cur == 0.75);
    /* a negative share is none: the PC's current is ignored */
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    in.pc_share = -1.0;
    in.cur_add = 0.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.cur == 0.0 && a.vel == 0.0);
    /* beyond AzLim by the PC's own current: saturated, clamped to -AzLim */
    in.pc_share = 1.0;
    in.cur_pc = -100.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.cur == -p.az_lim && a.saturated);
}

/* Sticking: Coulomb and Stribeck static friction hold an axis at rest; the disturbance torque
 * and the load enter the torque. */
static void test_axis_sticks(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    (void)state;
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    memset(&in, 0, sizeof in);
    in.cur_add = 0.1; /* 0.08 Nm < fc 0.15 */
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel == 0.0 && a.pos == 0.0 && a.cur == 0.1);
    p.vs = 1.0;
    p.fs = 0.3;
    in.cur_add = 0.3; /* 0.24 Nm: beats fc, not fs */
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel == 0.0);
    p.fs = 0.1; /* fs <= fc: fc decides */
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel > 0.0);
    /* the load pulls the other way */
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    p.load = 1.0;
    in.cur_add = 0.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel < 0.0);
    /* a disturbance torque draws from the generator */
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    p.torque_noise = 1.0;
    {
        c4gsim_rng_t q = r;
        double g = 0.0;
        assert_int_equal(c4gsim_rng_gauss(&q, &g), C4G_OK);
        assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
        assert_true(r.s == q.s);
        assert_true((a.vel > 0.0) == (g > 0.0));
    }
}

/* Friction cannot reverse the motion within a step: the axis stops instead. */
static void test_axis_no_reversal(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    (void)state;
    quiet_axis(&p, &a, &r);
    a.drive_on = true;
    p.kp = 0.0;
    p.kv = 0.0;
    p.ki = 0.0;
    memset(&in, 0, sizeof in);
    a.vel = 1e-3; /* slow: one step of friction alone stops it */
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel == 0.0);
    assert_true(a.pos == 0.5 * 1e-3 * 0.0005);
    a.vel = -1e-3;
    a.pos = 0.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel == 0.0);
    /* a torque that beats friction reverses it */
    a.vel = -1e-3;
    in.cur_add = 10.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel > 0.0);
    /* fast: the midpoint friction, still moving the same way */
    a.vel = 5.0;
    in.cur_add = 0.0;
    assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
    assert_true(a.vel > 0.0 && a.vel < 5.0);
}

/* Closed loop: the DSA brings an axis with gravity to a step reference. */
static void test_axis_reaches_reference(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    c4gsim_dsa_in_t in;
    int k;
    (void)state;
    assert_int_equal(c4gsim_axis_params_default(&p, 1), C4G_OK); /* axis 2: gravity */
    assert_int_equal(c4gsim_rng_seed(&r, 1), C4G_OK);
    assert_int_equal(c4gsim_axis_reset(&a, &p, &r), C4G_OK);
    a.drive_on = true;
    memset(&in, 0, sizeof in);
    in.pos_ref = 0.5;
    for (k = 0; k < 4000; k++) { /* 2 s at 2 kHz */
        assert_int_equal(c4gsim_axis_step(&a, &p, &in, 0.0005, &r), C4G_OK);
        assert_true(fabs(a.cur) <= p.az_lim + 1e-9);
    }
    assert_true(fabs(a.pos - 0.5) < 0.01);
}

static void test_report_current(void **state)
{
    c4gsim_axis_params_t p;
    c4gsim_axis_t a;
    c4gsim_rng_t r;
    double cur = -1.0;
    (void)state;
    quiet_axis(&p, &a, &r);
    assert_int_equal(c4gsim_axis_report_current(NULL, &p, &r, &cur), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_report_current(&a, &p, NULL, &cur), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_report_current(&a, &p, &r, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_axis_report_current(&a, NULL, &r, &cur), C4G_ERR_NULL);
    /* no step in the period: the last current */
    a.cur = 1.5;
    assert_int_equal(c4gsim_axis_report_current(&a, &p, &r, &cur), C4G_OK);
    assert_true(cur == 1.5 && a.cur_report == 1.5);
    /* the mean of the period's steps, then a new period */
    a.cur_sum = 3.0;
    a.cur_n = 4U;
    assert_int_equal(c4gsim_axis_report_current(&a, &p, &r, &cur), C4G_OK);
    assert_true(cur == 0.75 && a.cur_sum == 0.0 && a.cur_n == 0U);
    /* sensor noise on the report alone */
    p.cur_noise = 0.5;
    {
        c4gsim_rng_t q = r;
        double g = 0.0;
        assert_int_equal(c4gsim_rng_gauss(&q, &g), C4G_OK);
        assert_int_equal(c4gsim_axis_report_current(&a, &p, &r, &cur), C4G_OK);
        assert_true(cur == 1.5 + 0.5 * g && a.cur == 1.5);
    }
}

/* ---- interpolation and trajectory --------------------------------------------- */

static void test_dsa_interp(void **state)
{
    double pos = 0.0;
    double vel = 0.0;
    (void)state;
    assert_int_equal(c4gsim_dsa_interp(1.0, 2.0, 3.0, 4.0, 0.0, 0.002, &pos, &vel), C4G_OK);
    assert_true(pos == 1.0 && vel == 2.0);
    assert_int_equal(c4gsim_dsa_interp(1.0, 2.0, 3.0, 4.0, 1.0, 0.002, &pos, &vel), C4G_OK);
    assert_true(pos == 3.0 && fabs(vel - 4.0) < 1e-9);
    /* constant acceleration 100 from v0 = 2 over 0.002 s: exact at the middle */
    assert_int_equal(c4gsim_dsa_interp(0.0, 2.0, 2.0 * 0.002 + 50.0 * 0.002 * 0.002, 2.2, 0.5, 0.002, &pos,
                                       &vel), C4G_OK);
    assert_true(fabs(pos - (2.0 * 0.001 + 50.0 * 0.001 * 0.001)) < 1e-15);
    assert_true(fabs(vel - 2.1) < 1e-9);
    assert_int_equal(c4gsim_dsa_interp(0.0, 0.0, 0.0, 0.0, 0.5, 0.002, NULL, &vel), C4G_ERR_NULL);
    assert_int_equal(c4gsim_dsa_interp(0.0, 0.0, 0.0, 0.0, 0.5, 0.002, &pos, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_dsa_interp(NAN, 0.0, 0.0, 0.0, 0.5, 0.002, &pos, &vel), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_dsa_interp(0.0, 0.0, 0.0, 0.0, INFINITY, 0.002, &pos, &vel), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_dsa_interp(0.0, 0.0, 0.0, 0.0, 0.5, NAN, &pos, &vel), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_dsa_interp(0.0, 0.0, 0.0, 0.0, 0.5, 0.0, &pos, &vel), C4G_ERR_RANGE);
}

static void test_trap_min_time(void **state)
{
    (void)state;
    assert_true(c4gsim_trap_min_time(0.0, 20.0, 200.0) == 0.0);
    /* velocity bound: 30 / (20 * 0.75) = 2 s; acceleration bound sqrt(30 / 37.5) < 1 s */
    assert_true(c4gsim_trap_min_time(-30.0, 20.0, 200.0) == 30.0 / (20.0 * 0.75));
    /* acceleration bound: sqrt(0.1 / (200 * 0.1875)) */
    assert_true(c4gsim_trap_min_time(0.1, 20.0, 200.0) == sqrt(0.1 / (200.0 * 0.25 * 0.75)));
    assert_true(c4gsim_trap_min_time(0.1, 0.0, 200.0) == sqrt(0.1 / (200.0 * 0.25 * 0.75)));
    assert_true(c4gsim_trap_min_time(30.0, 20.0, 0.0) == 2.0);
    assert_true(c4gsim_trap_min_time(30.0, 0.0, 0.0) == 0.0);
}

static void test_trap_profile(void **state)
{
    c4gsim_trap_t t;
    double p = 0.0;
    double v = 0.0;
    (void)state;
    assert_int_equal(c4gsim_trap_plan(&t, 1.0, 3.0, 2.0), C4G_OK);
    assert_true(t.p0 == 1.0 && t.d == 2.0 && t.t_total == 2.0 && t.t_acc == 0.5);
    assert_int_equal(c4gsim_trap_eval(&t, -1.0, &p, &v), C4G_OK); /* before: the start */
    assert_true(p == 1.0 && v == 0.0);
    /* vp = 1 / 1.5, a = vp / 0.5: accelerating, cruising, decelerating */
    assert_int_equal(c4gsim_trap_eval(&t, 0.25, &p, &v), C4G_OK);
    assert_true(p == 1.0 + 2.0 * (0.5 * (4.0 / 3.0) * 0.0625) && v == 2.0 * (4.0 / 3.0) * 0.25);
    assert_int_equal(c4gsim_trap_eval(&t, 1.0, &p, &v), C4G_OK);
    assert_true(fabs(p - 2.0) < 1e-15 && v == 2.0 / 1.5);
    assert_int_equal(c4gsim_trap_eval(&t, 1.75, &p, &v), C4G_OK);
    assert_true(fabs(p - (1.0 + 2.0 * (1.0 - 0.5 * (4.0 / 3.0) * 0.0625))) < 1e-15);
    assert_true(fabs(v - 2.0 * (4.0 / 3.0) * 0.25) < 1e-15);
    assert_int_equal(c4gsim_trap_eval(&t, 2.0, &p, &v), C4G_OK);
    assert_true(p == 3.0 && v == 0.0);
    assert_int_equal(c4gsim_trap_plan(&t, 1.0, 3.0, -1.0), C4G_OK); /* at once */
    assert_true(t.t_total == 0.0 && t.t_acc == 0.0);
    assert_int_equal(c4gsim_trap_eval(&t, 0.0, &p, &v), C4G_OK);
    assert_true(p == 3.0 && v == 0.0);
}

static void test_trap_errors(void **state)
{
    c4gsim_trap_t t;
    double p = 0.0;
    double v = 0.0;
    (void)state;
    assert_int_equal(c4gsim_trap_plan(NULL, 0.0, 1.0, 1.0), C4G_ERR_NULL);
    assert_int_equal(c4gsim_trap_plan(&t, NAN, 1.0, 1.0), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_trap_plan(&t, 0.0, INFINITY, 1.0), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_trap_plan(&t, 0.0, 1.0, NAN), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_trap_plan(&t, 0.0, 1.0, 1.0), C4G_OK);
    assert_int_equal(c4gsim_trap_eval(NULL, 0.5, &p, &v), C4G_ERR_NULL);
    assert_int_equal(c4gsim_trap_eval(&t, 0.5, NULL, &v), C4G_ERR_NULL);
    assert_int_equal(c4gsim_trap_eval(&t, 0.5, &p, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_trap_eval(&t, NAN, &p, &v), C4G_ERR_NONFINITE);
    t.d = NAN;
    assert_int_equal(c4gsim_trap_eval(&t, 0.5, &p, &v), C4G_ERR_NONFINITE);
}

/* ---- the controller's reference per mode ------------------------------------ */

static c4g_pc_axis_t pc_axis(void)
{
    c4g_pc_axis_t pc;
    memset(&pc, 0, sizeof pc);
    pc.target_pos = 0.5F;
    pc.target_vel = 0.25F;
    pc.vel_add = 0.125F;
    pc.current_add = 2.0F;
    return pc;
}

static void ref(c4gsim_ref_t *r, int mode, const c4g_pc_axis_t *pc, c4gsim_dsa_in_t *in)
{
    memset(in, 0x55, sizeof *in);
    assert_int_equal(c4gsim_ref_step(r, mode, pc, 10.0, 3.0, 0.5, 0.002, in), C4G_OK);
    assert_true(r->pos_ref == in->pos_ref);
}

static void test_ref_modes(void **state)
{
    const c4g_pc_axis_t pc = pc_axis();
    c4gsim_ref_t r;
    c4gsim_dsa_in_t in;
    (void)state;
    memset(&r, 0, sizeof r);
    r.pos_ref = 7.0;
    /* mode 1: the PC's position, velocity, velocity addition and current */
    ref(&r, C4G_MODE_1, &pc, &in);
    assert_true(in.pos_ref == 0.5 && in.vel_ff == 0.25 / 0.002 && in.vel_add == 0.125 / 0.002);
    assert_true(in.cur_pc == 2.0 && in.cur_add == 0.0);
    r.pos_ref = 7.0;
    ref(&r, C4G_MODE_1_STANDBY, NULL, &in); /* no reply: the reference holds */
    assert_true(in.pos_ref == 7.0 && in.vel_ff == 0.0 && in.vel_add == 0.0 && in.cur_pc == 0.0);
    /* mode 2: the SMP+ trajectory plus the PC's velocity addition and current */
    ref(&r, C4G_MODE_2, &pc, &in);
    assert_true(in.pos_ref == 10.0 && in.vel_ff == 3.0 && in.vel_add == 0.125 / 0.002 && in.cur_pc == 2.0);
    ref(&r, C4G_MODE_2_STANDBY, NULL, &in);
    assert_true(in.pos_ref == 10.0 && in.vel_add == 0.0 && in.cur_pc == 0.0);
    /* mode 4: absolute D1 */
    ref(&r, C4G_MODE_4, &pc, &in);
    assert_true(in.pos_ref == 0.5 && in.vel_ff == 0.25 / 0.002);
    ref(&r, C4G_MODE_4, NULL, &in);
    assert_true(in.pos_ref == 0.5 && in.vel_ff == 0.0);
    /* mode 9: the PC's current addition */
    ref(&r, C4G_MODE_9, &pc, &in);
    assert_true(in.pos_ref == 10.0 && in.vel_ff == 3.0 && in.cur_add == 2.0 && in.cur_pc == 0.0);
    ref(&r, C4G_MODE_9, NULL, &in);
    assert_true(in.cur_add == 0.0);
    /* any other mode: the SMP+ trajectory alone */
    ref(&r, C4G_MODE_0, &pc, &in);
    assert_true(in.pos_ref == 10.0 && in.vel_ff == 3.0 && in.vel_add == 0.0 && in.cur_add == 0.0);
}

static void test_ref_integrating(void **state)
{
    const c4g_pc_axis_t pc = pc_axis();
    c4gsim_ref_t r;
    c4gsim_dsa_in_t in;
    (void)state;
    memset(&r, 0, sizeof r);
    /* mode 5: pos_k += vel_i T + override D2 */
    r.pos_k = 1.0;
    ref(&r, C4G_MODE_5, &pc, &in);
    assert_true(r.pos_k == 1.0 + (3.0 * 0.002 + 0.5 * 0.25));
    assert_true(in.pos_ref == r.pos_k && in.vel_ff == 3.0 + 0.125 / 0.002);
    ref(&r, C4G_MODE_5, NULL, &in);
    assert_true(r.pos_k == 1.0 + (3.0 * 0.002 + 0.5 * 0.25) + 3.0 * 0.002 && in.vel_ff == 3.0);
    /* mode 7: D1 adds to the offset */
    ref(&r, C4G_MODE_7, &pc, &in);
    ref(&r, C4G_MODE_7, &pc, &in);
    ref(&r, C4G_MODE_7, NULL, &in);
    assert_true(r.offset == 1.0 && in.pos_ref == 11.0 && in.vel_ff == 3.0);
    /* mode 8: D4 integrates into the offset */
    r.offset = 0.0;
    ref(&r, C4G_MODE_8, &pc, &in);
    assert_true(r.offset == 0.125 && in.pos_ref == 10.125 && in.vel_ff == 3.0 + 0.125 / 0.002);
    ref(&r, C4G_MODE_8, NULL, &in);
    assert_true(r.offset == 0.125 && in.vel_ff == 3.0);
}

static void test_ref_errors(void **state)
{
    c4g_pc_axis_t pc = pc_axis();
    c4gsim_ref_t r;
    c4gsim_ref_t before;
    c4gsim_dsa_in_t in;
    float *field[4];
    size_t i;
    (void)state;
    memset(&r, 0, sizeof r);
    assert_int_equal(c4gsim_ref_step(NULL, C4G_MODE_4, &pc, 0.0, 0.0, 1.0, 0.002, &in), C4G_ERR_NULL);
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_4, &pc, 0.0, 0.0, 1.0, 0.002, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_4, &pc, NAN, 0.0, 1.0, 0.002, &in), C4G_ERR_NONFINITE);
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_4, &pc, 0.0, 0.0, 1.0, 0.0, &in), C4G_ERR_RANGE);
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_4, &pc, 0.0, 0.0, 1.0, -0.002, &in), C4G_ERR_RANGE);
    field[0] = &pc.target_pos;
    field[1] = &pc.target_vel;
    field[2] = &pc.vel_add;
    field[3] = &pc.current_add;
    for (i = 0; i < 4U; i++) {
        *field[i] = NAN;
        assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_5, &pc, 0.0, 0.0, 1.0, 0.002, &in), C4G_ERR_NONFINITE);
        *field[i] = 0.0F;
    }
    r.offset = INFINITY; /* a state that went bad is not integrated further */
    before = r;
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_8, &pc, 0.0, 0.0, 1.0, 0.002, &in), C4G_ERR_NONFINITE);
    assert_memory_equal(&r, &before, sizeof r);
    r.offset = 0.0;
    r.pos_k = NAN;
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_4, &pc, 0.0, 0.0, 1.0, 0.002, &in), C4G_ERR_NONFINITE);
    r.pos_k = 0.0;
    r.pos_ref = -INFINITY;
    assert_int_equal(c4gsim_ref_step(&r, C4G_MODE_4, &pc, 0.0, 0.0, 1.0, 0.002, &in), C4G_ERR_NONFINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rng_repeatable),
        cmocka_unit_test(test_rng_values),
        cmocka_unit_test(test_rng_gauss),
        cmocka_unit_test(test_rng_null),
        cmocka_unit_test(test_params_default),
        cmocka_unit_test(test_params_check),
        cmocka_unit_test(test_axis_reset),
        cmocka_unit_test(test_friction_gravity),
        cmocka_unit_test(test_axis_step_errors),
        cmocka_unit_test(test_drive_off_brakes),
        cmocka_unit_test(test_axis_step_values),
        cmocka_unit_test(test_axis_saturation_share),
        cmocka_unit_test(test_axis_sticks),
        cmocka_unit_test(test_axis_no_reversal),
        cmocka_unit_test(test_axis_reaches_reference),
        cmocka_unit_test(test_report_current),
        cmocka_unit_test(test_dsa_interp),
        cmocka_unit_test(test_trap_min_time),
        cmocka_unit_test(test_trap_profile),
        cmocka_unit_test(test_trap_errors),
        cmocka_unit_test(test_ref_modes),
        cmocka_unit_test(test_ref_integrating),
        cmocka_unit_test(test_ref_errors),
        cmocka_unit_test(test_dsa_current_split),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
