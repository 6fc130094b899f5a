/* SPDX-License-Identifier: MIT */
/* c4g-server's controllers (tools/c4g-server/controllers.c): PD(+I) output for known
 * errors and gains, the sources at given times, trajectory interpolation, feedforward. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdlib.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "controllers.h"
#include "c4gh_ffmodel.h"

#define EPS 1e-9
#define near(a, b) assert_true(fabs((double)(a) - (double)(b)) < EPS)
#define nearf(a, b) assert_true(fabs((double)(a) - (double)(b)) < 1e-6)

static ctlr_arm_cfg_t A;
static ctlr_traj_t TR;
static ctlr_ff_t FF;

static void cfg_default(void)
{
    memset(&A, 0, sizeof A);
    A.axes = 0x3FFU;
    A.src = CTLR_SRC_SINE;
    A.sine_amp = 0.2;
    A.sine_freq = 0.5;
    A.sine_cycles = 1.0;
    A.offset_amp = 0.05;
    A.offset_ramp = 0.5;
    A.offset_hold = 0.5;
    A.vel_amp = 0.0005;
    A.vel_freq = 1.0;
    A.vel_cycles = 1.0;
    A.duration = 2.0;
    A.kp = 30.0;
    A.kd = 200.0;
    A.ki = 0.0;
}

static ctlr_in_t in_default(void)
{
    ctlr_in_t in;
    memset(&in, 0, sizeof in);
    in.cfg = &A;
    in.traj = &TR;
    in.ff = &FF;
    in.lax = 0U;
    in.dt = 0.002;
    in.az_lim = 10.0;
    in.driven = 1;
    return in;
}

static c4g_ctrl_axis_t meas(float pos, float vel)
{
    c4g_ctrl_axis_t r;
    memset(&r, 0, sizeof r);
    r.actual_pos = pos;
    r.actual_vel = vel;
    r.target_pos = pos;
    return r;
}

/* PD: u = kp e + kd (vref - vel) + integral, the integral clamped, the output saturated to
 * AzLim (back-calculation), and ramped by soft control switching. */
static void test_pd(void **st)
{
    ctlr_axis_t X;
    ctlr_in_t in;
    c4g_ctrl_axis_t r = meas(1.0f, 0.0f);
    (void)st;
    cfg_default();
    in = in_default();
    ctlr_axis_reset(&X);
    /* e = 0.1, vref = 0.001: 30 * 0.1 + 200 * 0.001 = 3.2 */
    near(ctlr_pd(&X, &in, 1.1, 0.001, &r, 1.0), 3.2);
    near(X.integ, 0.0);
    /* with KI = 300: integral 300 * 0.1 * 0.002 = 0.06 */
    A.ki = 300.0;
    near(ctlr_pd(&X, &in, 1.1, 0.001, &r, 1.0), 3.26);
    near(X.integ, 0.06);
    /* saturated to AzLim = 2: the integrator gives back the excess 1.26 */
    in.az_lim = 2.0;
    X.integ = 0.0;
    near(ctlr_pd(&X, &in, 1.1, 0.001, &r, 1.0), 2.0);
    near(X.integ, 0.06 - 1.26);
    /* negative error, saturated to -2 */
    X.integ = 0.0;
    near(ctlr_pd(&X, &in, 0.9, -0.001, &r, 1.0), -2.0);
    near(X.integ, -0.06 + 1.26);
    /* the integrator limit --i-max */
    A.i_max = 0.01;
    X.integ = 0.0;
    near(ctlr_pd(&X, &in, 1.0, 0.0, &r, 1.0), 0.0 + 0.0 + 0.0);
    X.integ = 5.0;
    (void)ctlr_pd(&X, &in, 1.0, 0.0, &r, 1.0);
    near(X.integ, 0.01);
    X.integ = -5.0;
    (void)ctlr_pd(&X, &in, 1.0, 0.0, &r, 1.0);
    near(X.integ, -0.01);
    /* no AzLim: the integrator limit is the "no limit" 1e9; SCS ramps the limit: at
     * t = 0.25 of 1 s the limit is 0.25 * AzLim */
    A.i_max = 0.0;
    A.ki = 0.0;
    A.scs = 1.0;
    in.az_lim = 10.0;
    X.integ = 0.0;
    near(ctlr_pd(&X, &in, 1.1, 0.001, &r, 0.25), 2.5);
    X.integ = 0.0;
    near(ctlr_pd(&X, &in, 1.1, 0.001, &r, 1.0), 3.2);
    in.az_lim = 0.0;
    A.scs = 0.0;
    X.integ = 0.0;
    near(ctlr_pd(&X, &in, 101.0, 0.0, &r, 0.0), 3000.0);
}

static void test_sources(void **st)
{
    int done = -1;
    (void)st;
    cfg_default();
    /* raised cosine 0.2 turns at 0.5 Hz: 0 at 0, half at a quarter period, peak at half */
    near(ctlr_raised_cos(0.2, 0.5, 0.0), 0.0);
    near(ctlr_gen_offset(&A, NULL, 0U, 0.5, &done), 0.1);
    assert_int_equal(done, 0);
    near(ctlr_gen_offset(&A, NULL, 0U, 1.0, &done), 0.2);
    near(ctlr_gen_offset(&A, NULL, 0U, 3.0, &done), 0.0); /* past 1 cycle: held at the end */
    assert_int_equal(done, 1);
    A.sine_freq = 0.0; /* 1 Hz */
    near(ctlr_gen_offset(&A, NULL, 0U, 0.5, &done), 0.2);
    /* hold: no offset, done after duration */
    A.src = CTLR_SRC_NONE;
    near(ctlr_gen_offset(&A, NULL, 0U, 1.0, &done), 0.0);
    assert_int_equal(done, 0);
    (void)ctlr_gen_offset(&A, NULL, 0U, 2.0, &done);
    assert_int_equal(done, 1);
    /* mode 7: half-cosine step 0.05 over 0.5 s, held 0.5 s */
    near(ctlr_offset_profile(&A, 0.25, &done), 0.025);
    assert_int_equal(done, 0);
    near(ctlr_offset_profile(&A, 0.6, &done), 0.05);
    assert_int_equal(done, 0);
    near(ctlr_offset_profile(&A, 1.0, &done), 0.05);
    assert_int_equal(done, 1);
    A.offset_ramp = 0.0;
    near(ctlr_offset_profile(&A, 0.0, &done), 0.05);
    /* mode 8: 0.0005 sin(2 pi t) for one cycle */
    near(ctlr_vel_add(&A, 0.25, &done), 0.0005);
    assert_int_equal(done, 0);
    near(ctlr_vel_add(&A, 0.75, &done), -0.0005);
    near(ctlr_vel_add(&A, 1.0, &done), 0.0);
    assert_int_equal(done, 1);
    A.vel_freq = 0.0; /* 1 Hz */
    near(ctlr_vel_add(&A, 0.25, &done), 0.0005);
}

static void test_trajectory(void **st)
{
    int done = -1;
    (void)st;
    cfg_default();
    memset(&TR, 0, sizeof TR);
    TR.rows = 3U;
    TR.cols = 2U;
    TR.t[0] = 0.0;
    TR.t[1] = 1.0;
    TR.t[2] = 2.0;
    TR.q[0][0] = 0.0f;
    TR.q[1][0] = 1.0f;
    TR.q[2][0] = 3.0f;
    TR.q[0][1] = -1.0f;
    TR.q[1][1] = -1.0f;
    TR.q[2][1] = 1.0f;
    near(ctlr_traj_at(&TR, 0U, 0.5, &done), 0.5);
    assert_int_equal(done, 0);
    near(ctlr_traj_at(&TR, 0U, 1.5, &done), 2.0);
    near(ctlr_traj_at(&TR, 1U, 1.75, &done), 0.5);
    near(ctlr_traj_at(&TR, 0U, 1.0, &done), 1.0);
    near(ctlr_traj_at(&TR, 0U, -1.0, &done), 0.0); /* before the first row: the first */
    near(ctlr_traj_at(&TR, 0U, 2.5, &done), 3.0);  /* past the last: held, done */
    assert_int_equal(done, 1);
    near(ctlr_traj_at(&TR, 2U, 0.5, &done), 0.0);  /* no such column */
    assert_int_equal(done, 1);
    near(ctlr_traj_at(NULL, 0U, 0.5, &done), 0.0);
    assert_int_equal(done, 1);
    A.src = CTLR_SRC_FILE;
    near(ctlr_gen_offset(&A, &TR, 0U, 0.25, &done), 0.25);
    assert_int_equal(done, 0);
}

static void test_feedforward(void **st)
{
    (void)st;
    memset(&FF, 0, sizeof FF);
    FF.set = 1;
    FF.c0 = 0.1;
    FF.cv = 2.0;
    FF.cc = 0.3;
    FF.ca = 5.0;
    FF.gs = 0.5;
    FF.gscale = 0.0;
    FF.gphase = M_PI / 2.0;
    /* 0.1 + 2 * 0.01 + 0.3 + 5 * 0.002 + 0.5 = 0.93 */
    nearf(ctlr_ff_current(&FF, 0.01, 0.002, 7.0), 0.93);
    nearf(ctlr_ff_current(&FF, -0.01, 0.0, 7.0), 0.1 - 0.02 - 0.3 + 0.5);
    nearf(ctlr_ff_current(&FF, 0.0, 0.0, 7.0), 0.6);
    FF.gscale = 2.0;
    FF.gphase = 0.0;
    nearf(ctlr_ff_current(&FF, 0.0, 0.0, M_PI / 4.0), 0.1 + 0.5);
    FF.c0 = 1e300;
    assert_true(ctlr_ff_current(&FF, 0.0, 0.0, 0.0) == FLT_MAX);
    FF.c0 = -1e300;
    assert_true(ctlr_ff_current(&FF, 0.0, 0.0, 0.0) == -FLT_MAX);
}

/* An identified model (CTLR_FF_MODEL): per-second units, one tick ahead, range clamps. */
static void test_feedforward_model(void **st)
{
    const double dt = 0.002;
    int clamped = -1;
    (void)st;
    memset(&FF, 0, sizeof FF);
    FF.set = 1;
    FF.kind = CTLR_FF_MODEL;
    FF.model.ja = 0.01;
    FF.model.fv = 0.1;
    FF.model.eps = 0.01;
    /* d2 0.0038 -> 0.004 turns/tick: v = 2 turns/s, a = 0.0002 / dt^2 = 50 turns/s^2, and
     * the next tick's v = 2 + 50 dt = 2.1: 0.01 * 50 + 0.1 * 2.1 */
    nearf(ctlr_ff_model_current(&FF, 0.004, 0.0038, dt, 0.0, 0, &clamped), 0.5 + 0.21);
    assert_int_equal(clamped, 0);
    /* outside the fit's range: v to v_max, a to a_max, each sign kept */
    FF.model.v_max = 1.0;
    FF.model.a_max = 20.0;
    nearf(ctlr_ff_model_current(&FF, 0.004, 0.0038, dt, 0.0, 0, &clamped), 0.2 + 0.1);
    assert_int_equal(clamped, 1);
    nearf(ctlr_ff_model_current(&FF, -0.004, -0.0038, dt, 0.0, 0, &clamped), -0.2 - 0.1);
    assert_int_equal(clamped, 1);
    nearf(ctlr_ff_model_current(&FF, 0.001, 0.001, dt, 0.0, 0, &clamped), 0.1 * 0.5);
    assert_int_equal(clamped, 0);
    /* gravity on the link angle given */
    FF.model.gb = 2.0;
    nearf(ctlr_ff_model_current(&FF, 0.0, 0.0, dt, M_PI / 2.0, 1, &clamped), 2.0);
    nearf(ctlr_ff_model_current(&FF, 0.0, 0.0, dt, M_PI / 2.0, 0, &clamped), 0.0);
    /* saturated to the float range like the line format */
    FF.model.off = 1e300;
    assert_true(ctlr_ff_model_current(&FF, 0.0, 0.0, dt, 0.0, 0, &clamped) == FLT_MAX);
}

/* Mode 9 through ctlr_step with a model: no acceleration on the mode's first packet,
 * then D2's change per tick; the flags say what the tick did. */
static void test_step_model(void **st)
{
    ctlr_axis_t X;
    ctlr_in_t in;
    c4g_pc_axis_t o;
    c4g_ctrl_axis_t r = meas(5.0f, 0.0f);
    (void)st;
    cfg_default();
    in = in_default();
    memset(&FF, 0, sizeof FF);
    FF.set = 1;
    FF.kind = CTLR_FF_MODEL;
    FF.model.ja = 0.01;
    FF.model.ga = 1.0;
    FF.model.eps = 0.01;
    FF.model.a_max = 100.0;
    in.q_link = 0.0;
    in.have_q = 1;
    r.target_vel = 0.004f;
    ctlr_axis_reset(&X);
    X.v_prev = 0.0; /* whatever came before the mode */
    (void)ctlr_axis_enter(&X, C4G_MODE_9, 5.0, &r);
    X.v_prev = 0.0;
    memset(&o, 0, sizeof o);
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 1.0); /* a = 0: only ga cos 0 */
    assert_int_equal(X.ff_flags, CTLR_FFF_MODEL);
    /* next tick: a = (0.0042 - 0.004) / dt^2 = 50 */
    r.target_vel = 0.0042f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 1.0 + 0.01 * ((double)0.0042f - (double)0.004f) / (0.002 * 0.002));
    assert_int_equal(X.ff_flags, CTLR_FFF_MODEL);
    /* a jump of 0.001 turns/tick: 250 turns/s^2, clamped to 100 */
    r.target_vel = 0.0052f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 1.0 + 0.01 * 100.0);
    assert_int_equal(X.ff_flags, CTLR_FFF_MODEL | CTLR_FFF_CLAMPED);
    /* other modes clear the flags */
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_8, &r, &o), 0);
    assert_int_equal(X.ff_flags, 0U);
    /* not driven: nothing, no flag */
    in.driven = 0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 0.0f);
    assert_int_equal(X.ff_flags, 0U);
}

/* Mode 9 with a model = ctrl axis: k1 (EXT1 - in) + k2 in + friction + off from the
 * packet's EXT1, EXT2 and D2's change, a and v clamped as the axis model's; --ff-ext1 not
 * added on top (the model holds EXT1); a non-finite EXT1 or EXT2 adds nothing. */
static void test_step_ctrl_model(void **st)
{
    const double dt = 0.002;
    const double two_pi = 6.283185307179586;
    ctlr_axis_t X;
    ctlr_in_t in;
    c4g_pc_axis_t o;
    c4g_ctrl_axis_t r = meas(5.0f, 0.0f);
    int clamped = 0;
    double a, in_a;
    (void)st;
    cfg_default();
    in = in_default();
    memset(&FF, 0, sizeof FF);
    FF.set = 1;
    FF.kind = CTLR_FF_MODEL;
    FF.model.ctrl = 1;
    FF.model.k1 = 0.9;
    FF.model.k2 = 1.1;
    FF.model.ks = 1.25;
    FF.model.fv = 0.1;
    FF.model.off = 0.02;
    FF.model.eps = 0.01;
    FF.model.a_max = 100.0;
    /* the function: d2 0.0038 -> 0.004: a = 50, v = 2.1; in = 1.25 * 4e-4 * 2 pi * 50 */
    in_a = 1.25 * 4e-4 * two_pi * 50.0;
    nearf(ctlr_ff_ctrl_current(&FF, 0.004, 0.0038, dt, 1.5, 4e-4, &clamped),
          0.9 * (1.5 - in_a) + 1.1 * in_a + 0.1 * 2.1 + 0.02);
    assert_int_equal(clamped, 0);
    nearf(ctlr_ff_ctrl_current(&FF, 0.004, 0.0038, dt, NAN, 4e-4, &clamped), 0.0);
    nearf(ctlr_ff_ctrl_current(&FF, 0.004, 0.0038, dt, 1.5, INFINITY, &clamped), 0.0);
    /* through ctlr_step, --ff-ext1 on: the packet's EXT1, EXT2, not EXT1 twice */
    A.ff_ext1 = 1;
    r.ext[0] = 1.5f;
    r.ext[1] = 4e-4f;
    r.target_vel = 0.004f;
    ctlr_axis_reset(&X);
    (void)ctlr_axis_enter(&X, C4G_MODE_9, 5.0, &r);
    X.v_prev = 0.0;
    memset(&o, 0, sizeof o);
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    /* first packet: a = 0, v = 2 */
    nearf(o.current_add, 0.9 * (double)1.5f + 0.1 * ((double)0.004f / dt) + 0.02);
    assert_int_equal(X.ff_flags, CTLR_FFF_MODEL);
    /* 0.004 -> 0.0052: a = 300 clamped to 100 (v predicted with the unclamped a) */
    r.target_vel = 0.0052f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    a = ((double)0.0052f - (double)0.004f) / (dt * dt);
    in_a = 1.25 * (double)4e-4f * two_pi * 100.0;
    nearf(o.current_add, 0.9 * ((double)1.5f - in_a) + 1.1 * in_a + 0.1 * ((double)0.0052f / dt + a * dt) + 0.02);
    assert_int_equal(X.ff_flags, CTLR_FFF_MODEL | CTLR_FFF_CLAMPED);
    /* an axis model file with --ff-ext1 still gets EXT1 added */
    FF.model.ctrl = 0;
    FF.model.ja = 0.0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, (double)1.5f + 0.1 * ((double)0.0052f / dt) + 0.02);
    A.ff_ext1 = 0;
}

/* Mode 9 with a rigid-body file (CTLR_FF_RIGID): the arm's current the caller evaluated
 * (ctlr_in_t.ff_cur) is the axis's addition, its clamp flag counted; --ff-ext1 not added
 * (the model replaces EXT1); no evaluation (ff_cur_ok 0): 0 A, not a stale value. */
static void test_step_rigid(void **st)
{
    ctlr_axis_t X;
    ctlr_in_t in;
    c4g_pc_axis_t o;
    c4g_ctrl_axis_t r = meas(5.0f, 0.0f);
    (void)st;
    cfg_default();
    in = in_default();
    memset(&FF, 0, sizeof FF);
    FF.set = 1;
    FF.kind = CTLR_FF_RIGID;
    A.ff_ext1 = 1;
    r.ext[0] = 1.5f;
    r.target_vel = 0.004f;
    ctlr_axis_reset(&X);
    (void)ctlr_axis_enter(&X, C4G_MODE_9, 5.0, &r);
    in.ff_cur = 2.25;
    in.ff_cur_ok = 1;
    memset(&o, 0, sizeof o);
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 2.25);
    assert_int_equal(X.ff_flags, CTLR_FFF_MODEL);
    in.ff_cur_clamped = 1;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 2.25);
    assert_int_equal(X.ff_flags, CTLR_FFF_MODEL | CTLR_FFF_CLAMPED);
    in.ff_cur_ok = 0;
    in.ff_cur_clamped = 0;
    o.current_add = 7.0f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 0.0);
    /* beyond the range of float: saturated (the safety filter then clamps it to AzLim) */
    in.ff_cur_ok = 1;
    in.ff_cur = 1e300;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    assert_true(o.current_add == FLT_MAX);
    A.ff_ext1 = 0;
}

static void test_enter(void **st)
{
    ctlr_axis_t X;
    c4g_ctrl_axis_t r = meas(1.0f, 0.0f);
    (void)st;
    r.current_ref = 1.5f;
    r.target_vel = 0.25f;
    ctlr_axis_reset(&X);
    assert_int_equal(X.mode, -1);
    assert_int_equal(ctlr_axis_enter(&X, C4G_MODE_1, 4.0, &r), 1);
    near(X.start, 4.0);
    near(X.integ, 1.5);
    near(X.v_prev, 0.25);
    X.ticks = 9U;
    X.q_prev = 0.3;
    /* 1 -> 11, 2 -> 12, 12 -> 2 continue the regulator */
    assert_int_equal(ctlr_axis_enter(&X, C4G_MODE_1_STANDBY, 0.0, &r), 0);
    assert_int_equal(X.mode, C4G_MODE_1_STANDBY);
    assert_int_equal(X.ticks, 9U);
    near(X.q_prev, 0.3);
    X.mode = C4G_MODE_2;
    assert_int_equal(ctlr_axis_enter(&X, C4G_MODE_2_STANDBY, 0.0, &r), 0);
    assert_int_equal(ctlr_axis_enter(&X, C4G_MODE_2, 0.0, &r), 0);
    assert_int_equal(ctlr_axis_enter(&X, C4G_MODE_0, 2.0, &r), 1);
    assert_int_equal(X.ticks, 0U);
    near(X.q_prev, 0.0);
    assert_int_equal(ctlr_is_open_mode(C4G_MODE_9), 1);
    assert_int_equal(ctlr_is_open_mode(C4G_MODE_1_STANDBY), 0);
    assert_int_equal(ctlr_is_open_mode(C4G_MODE_0), 0);
}

/* One tick per mode through ctlr_step: the fields the mode needs, at t = ticks * dt. */
static void test_step_modes(void **st)
{
    ctlr_axis_t X;
    ctlr_in_t in;
    c4g_pc_axis_t o;
    c4g_ctrl_axis_t r = meas(5.0f, 0.0f);
    (void)st;
    cfg_default();
    in = in_default();
    ctlr_axis_reset(&X);
    (void)ctlr_axis_enter(&X, C4G_MODE_4, 5.0, &r);
    /* mode 4 at t = 0.5 s (250 ticks of 2 ms): 5 + 0.1 absolute, dq since q_prev 0.05 */
    X.ticks = 250U;
    X.q_prev = 0.05;
    memset(&o, 0, sizeof o);
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_4, &r, &o), 0);
    nearf(o.target_pos, 5.1f);
    nearf(o.target_vel, 0.05f);
    near(X.q_prev, 0.1);
    assert_int_equal(X.ticks, 251U);
    /* mode 5: the step itself */
    X.ticks = 500U; /* t = 1: q = 0.2 */
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_5, &r, &o), 0);
    nearf(o.target_pos, 0.1f);
    nearf(o.target_vel, 0.1f);
    /* not driven: no offset, done */
    in.driven = 0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_5, &r, &o), 1);
    nearf(o.target_pos, -0.2f);
    /* mode 7 at t = 0.25: offset 0.025, the addition since the previous offset */
    in.driven = 1;
    X.q_prev = 0.02;
    X.ticks = 125U;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_7, &r, &o), 0);
    nearf(o.target_pos, 0.005f);
    in.driven = 0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_7, &r, &o), 1);
    nearf(o.target_pos, -0.025f);
    /* mode 8 at t = 0.25 */
    in.driven = 1;
    X.ticks = 125U;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_8, &r, &o), 0);
    nearf(o.vel_add, 0.0005f);
    in.driven = 0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_8, &r, &o), 1);
    nearf(o.vel_add, 0.0f);
    /* mode 9: feedforward on the SMP+ velocity; acceleration from the previous one */
    in.driven = 1;
    memset(&FF, 0, sizeof FF);
    FF.set = 1;
    FF.cv = 100.0;
    FF.ca = 1000.0;
    r.target_vel = 0.01f;
    X.v_prev = 0.008;
    X.ticks = 0U;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 100.0 * (double)0.01f + 1000.0 * ((double)0.01f - 0.008));
    near(X.v_prev, (double)0.01f);
    FF.set = 0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 0.0f);
    X.ticks = 1000U; /* t = 2 = duration */
    FF.set = 1;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 1);
    nearf(o.current_add, 0.0f);
    in.ff = NULL;
    X.ticks = 0U;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 0.0f);
    /* --ff-ext1: the controller's model current (EXT1) passed back, alone or on the file's;
     * a non-finite EXT1 adds nothing; after the duration nothing either */
    A.ff_ext1 = 1;
    r.ext[0] = 1.25f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 1.25f);
    in.ff = &FF;
    X.v_prev = 0.008;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 1.25 + 100.0 * (double)0.01f + 1000.0 * ((double)0.01f - 0.008));
    r.ext[0] = NAN;
    X.v_prev = (double)0.01f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 0);
    nearf(o.current_add, 100.0 * (double)0.01f);
    r.ext[0] = 1.25f;
    X.ticks = 1000U;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_9, &r, &o), 1);
    nearf(o.current_add, 0.0f);
    A.ff_ext1 = 0;
    r.ext[0] = 0.0f;
    in.ff = NULL;
    X.ticks = 0U;
    r.target_vel = 0.0f;
    /* mode 1, hold (no source): target = start, PD on it, done after duration */
    A.src = CTLR_SRC_NONE;
    (void)ctlr_axis_enter(&X, C4G_MODE_1, 5.0, &r);
    r.actual_pos = 4.9f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_1, &r, &o), 0);
    nearf(o.target_pos, 5.0f);
    nearf(o.target_vel, 0.0f);
    nearf(o.current_add, 30.0 * (5.0 - (double)4.9f));
    /* mode 1 with the sine: at least `duration` even when the sine is over */
    A.src = CTLR_SRC_SINE;
    X.ticks = 750U; /* t = 1.5, past the 1 s cycle... */
    A.sine_freq = 1.0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_1, &r, &o), 0);
    nearf(o.target_pos, 5.0f);
    X.ticks = 1000U; /* ... done at 2 s */
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_1, &r, &o), 1);
    /* 11: the trajectory stays where it was, the PD runs on */
    X.q_prev = 0.01;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_1_STANDBY, &r, &o), 1);
    nearf(o.target_pos, 5.01f);
    nearf(o.target_vel, 0.0f);
    /* mode 2: PD on the SMP+ target; never done by the PC */
    r.target_pos = 5.0f;
    r.target_vel = 0.0f;
    X.integ = 0.0;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_2, &r, &o), 0);
    nearf(o.current_add, 30.0 * (5.0 - (double)4.9f));
    nearf(o.vel_add, 0.0f);
    /* mode 0 and other modes: the prepared reply is left as it is */
    o.target_pos = 42.0f;
    assert_int_equal(ctlr_step(&X, &in, C4G_MODE_0, &r, &o), 1);
    nearf(o.target_pos, 42.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pd),
        cmocka_unit_test(test_sources),
        cmocka_unit_test(test_trajectory),
        cmocka_unit_test(test_feedforward),
        cmocka_unit_test(test_feedforward_model),
        cmocka_unit_test(test_step_model),
        cmocka_unit_test(test_step_ctrl_model),
        cmocka_unit_test(test_step_rigid),
        cmocka_unit_test(test_enter),
        cmocka_unit_test(test_step_modes),
    };
    return cmocka_run_group_tests_name("controllers", tests, NULL, NULL);
}
