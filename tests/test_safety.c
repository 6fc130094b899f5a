/* SPDX-License-Identifier: MIT */
/* PC-side safety (14.17.2, 15.7): every pure check at and around its boundaries, then the
 * filter inside c4g_engine_finish mode by mode: following error -> 508, current saturation,
 * delta current, continuity, stroke ends in motor turns and in joint units, user limits. */
#include "test_helpers.h"
#include <math.h>

/* ---------------------------------------------------------------- pure checks */

static void test_follow_error(void **state)
{
    float e = -1.0f;
    (void)state;
    assert_int_equal(c4g_sf_follow_error(10.0f, 9.0f, 1.0f, &e), 0);      /* == threshold */
    assert_true(e == 1.0f);
    assert_int_equal(c4g_sf_follow_error(10.0f, 8.99f, 1.0f, &e), C4G_SF_FOLLOW_ERROR);
    assert_int_equal(c4g_sf_follow_error(9.0f, 10.99f, 2.0f, &e), 0);
    assert_int_equal(c4g_sf_follow_error(9.0f, 11.01f, 2.0f, &e), C4G_SF_FOLLOW_ERROR);
    assert_int_equal(c4g_sf_follow_error(0.0f, 1000.0f, 0.0f, &e), 0);    /* 0 = no threshold */
    assert_int_equal(c4g_sf_follow_error(NAN, 0.0f, 1.0f, &e), C4G_SF_NONFINITE);
    assert_true(e == 0.0f);
    assert_int_equal(c4g_sf_follow_error(0.0f, INFINITY, 1.0f, NULL), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_follow_error(0.0f, 0.5f, -1.0f, NULL), C4G_SF_BAD_LIMIT);
    assert_int_equal(c4g_sf_follow_error(0.0f, 0.5f, NAN, NULL), C4G_SF_BAD_LIMIT);
    assert_int_equal(c4g_sf_follow_error(3e38f, -3e38f, 1.0f, &e), C4G_SF_FOLLOW_ERROR);
}

static void test_current(void **state)
{
    float o = 0.0f;
    (void)state;
    assert_int_equal(c4g_sf_current(24.5f, 24.5f, &o), 0);
    assert_true(o == 24.5f);
    assert_int_equal(c4g_sf_current(24.51f, 24.5f, &o), C4G_SF_CURRENT);
    assert_true(o == 24.5f);
    assert_int_equal(c4g_sf_current(-24.5f, 24.5f, &o), 0);
    assert_int_equal(c4g_sf_current(-24.51f, 24.5f, &o), C4G_SF_CURRENT);
    assert_true(o == -24.5f);
    assert_int_equal(c4g_sf_current(1.0f, 0.0f, &o), C4G_SF_CURRENT);
    assert_true(o == 0.0f);
    assert_int_equal(c4g_sf_current(NAN, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_current(1.0f, -1.0f, &o), C4G_SF_BAD_LIMIT);
    assert_true(o == 1.0f);
    assert_int_equal(c4g_sf_current(1.0f, 1.0f, NULL), C4G_SF_NONFINITE);
}

static void test_delta_current(void **state)
{
    float o = 0.0f;
    (void)state;
    /* smp 20 A, limit 24.5 A: delta in [-44.5, 4.5] */
    assert_int_equal(c4g_sf_delta_current(20.0f, 4.5f, 24.5f, &o), 0);
    assert_int_equal(c4g_sf_delta_current(20.0f, 4.6f, 24.5f, &o), C4G_SF_DCURRENT);
    assert_true(o == 4.5f);
    assert_int_equal(c4g_sf_delta_current(20.0f, -44.5f, 24.5f, &o), 0);
    assert_int_equal(c4g_sf_delta_current(20.0f, -44.6f, 24.5f, &o), C4G_SF_DCURRENT);
    assert_true(o == -44.5f);
    /* SMP+ already above the limit: the filter never creates a current to bring it back; a
     * request that pushes further becomes 0, one that brings it back is kept */
    assert_int_equal(c4g_sf_delta_current(30.0f, 0.0f, 24.5f, &o), 0);
    assert_true(o == 0.0f);
    assert_int_equal(c4g_sf_delta_current(30.0f, 3.0f, 24.5f, &o), C4G_SF_DCURRENT);
    assert_true(o == 0.0f);
    assert_int_equal(c4g_sf_delta_current(30.0f, -2.0f, 24.5f, &o), 0);
    assert_true(o == -2.0f);
    assert_int_equal(c4g_sf_delta_current(-30.0f, -1.0f, 24.5f, &o), C4G_SF_DCURRENT);
    assert_true(o == 0.0f);
    /* user limit 5 A below an SMP+ current of 20 A: a request of 0 stays 0 */
    assert_int_equal(c4g_sf_delta_current(20.0f, 0.0f, 5.0f, &o), 0);
    assert_true(o == 0.0f);
    assert_int_equal(c4g_sf_delta_current(20.0f, -30.0f, 5.0f, &o), C4G_SF_DCURRENT);
    assert_true(o == -25.0f);
    assert_int_equal(c4g_sf_delta_current(NAN, 0.0f, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_delta_current(0.0f, INFINITY, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_delta_current(0.0f, 0.0f, -1.0f, &o), C4G_SF_BAD_LIMIT);
    assert_int_equal(c4g_sf_delta_current(0.0f, 0.0f, 1.0f, NULL), C4G_SF_NONFINITE);
}

static void test_step_velocity_stroke(void **state)
{
    float o = 0.0f;
    (void)state;
    assert_int_equal(c4g_sf_step(1.0f, 1.5f, 0.5f, &o), 0);
    assert_int_equal(c4g_sf_step(1.0f, 1.51f, 0.5f, &o), C4G_SF_STEP);
    assert_true(o == 1.5f);
    assert_int_equal(c4g_sf_step(1.0f, 0.5f, 0.5f, &o), 0);
    assert_int_equal(c4g_sf_step(1.0f, 0.49f, 0.5f, &o), C4G_SF_STEP);
    assert_true(o == 0.5f);
    assert_int_equal(c4g_sf_step(1.0f, 100.0f, 0.0f, &o), 0);             /* off */
    assert_true(o == 100.0f);
    assert_int_equal(c4g_sf_step(NAN, 1.0f, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_step(1.0f, NAN, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_step(-3e38f, 3e38f, 1.0f, &o), C4G_SF_NONFINITE); /* overflow */
    assert_int_equal(c4g_sf_step(0.0f, 0.0f, NAN, &o), C4G_SF_BAD_LIMIT);
    assert_int_equal(c4g_sf_step(0.0f, 0.0f, 1.0f, NULL), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_velocity(0.2f, 0.2f, &o), 0);
    assert_int_equal(c4g_sf_velocity(-0.21f, 0.2f, &o), C4G_SF_VELOCITY);
    assert_true(o == -0.2f);
    assert_int_equal(c4g_sf_velocity(5.0f, 0.0f, &o), 0);
    assert_int_equal(c4g_sf_velocity(INFINITY, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_velocity(1.0f, -2.0f, &o), C4G_SF_BAD_LIMIT);
    assert_int_equal(c4g_sf_velocity(1.0f, 1.0f, NULL), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_stroke(2.0f, -1.0f, 2.0f, &o), 0);
    assert_int_equal(c4g_sf_stroke(2.01f, -1.0f, 2.0f, &o), C4G_SF_STROKE);
    assert_true(o == 2.0f);
    assert_int_equal(c4g_sf_stroke(-1.0f, -1.0f, 2.0f, &o), 0);
    assert_int_equal(c4g_sf_stroke(-1.01f, -1.0f, 2.0f, &o), C4G_SF_STROKE);
    assert_true(o == -1.0f);
    assert_int_equal(c4g_sf_stroke(50.0f, 0.0f, 0.0f, &o), 0);            /* off */
    assert_int_equal(c4g_sf_stroke(50.0f, 3.0f, 1.0f, &o), 0);            /* off */
    assert_int_equal(c4g_sf_stroke(NAN, 0.0f, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_stroke(0.0f, NAN, 1.0f, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_stroke(0.0f, 0.0f, INFINITY, &o), C4G_SF_NONFINITE);
    assert_int_equal(c4g_sf_stroke(0.0f, 0.0f, 1.0f, NULL), C4G_SF_NONFINITE);
}

/* ---------------------------------------------------------------- the filter */

static void mk_rx(c4g_ctrl_packet_t *rx, int32_t num, int32_t mode)
{
    uint32_t i;
    memset(rx, 0, sizeof *rx);
    rx->num = num;
    rx->n_axes = 6;
    rx->infpar = 5;
    for (i = 0; i < 6; i++) {
        rx->ax[i].mode = mode;
        rx->ax[i].target_pos = 10.0f;
        rx->ax[i].actual_pos = 10.0f;
        rx->ax[i].current_ref = 20.0f;
    }
}

typedef struct filt {
    c4g_engine_t ctl;
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    int32_t num;
} filt_t;

static void f_init(filt_t *f)
{
    c4g_init_t in;
    memset(f, 0, sizeof *f);
    assert_int_equal(c4g_init_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_engine_init(&f->ctl, &in, NULL), C4G_OK);
}

/* One tick in @p mode; axis 0 gets d1, d2, d4, d5, the others hold. */
static int f_tick(filt_t *f, int32_t mode, float d1, float d2, float d4, float d5)
{
    uint32_t i;
    int st;
    f->num++;
    mk_rx(&f->rx, f->num, mode);
    assert_int_equal(c4g_engine_step(&f->ctl, &f->rx, (uint64_t)f->num, &f->tx, &f->rep), C4G_OK);
    for (i = 0; i < 6; i++) {
        const int abs_mode = (mode == 1 || mode == 11 || mode == 4);
        f->tx.ax[i].target_pos = (i == 0) ? d1 : (abs_mode ? 10.0f : 0.0f);
        f->tx.ax[i].target_vel = (i == 0) ? d2 : 0.0f;
        f->tx.ax[i].vel_add = (i == 0) ? d4 : 0.0f;
        f->tx.ax[i].current_add = (i == 0) ? d5 : 0.0f;
    }
    st = c4g_engine_finish(&f->ctl, &f->rx, &f->tx, &f->rep);
    {
        uint8_t buf[C4G_MAX_CYCLIC_SIZE];
        size_t len;
        assert_int_equal(c4g_pc_encode(&f->tx, buf, sizeof buf, &len), C4G_OK);
    }
    return st;
}

static void test_filter_following_error(void **state)
{
    static const struct { int32_t mode; int uses_tx; } rows[] = {
        {1, 1}, {11, 1}, {4, 1}, {2, 0}, {12, 0}, {5, 0}, {7, 0}, {8, 0}, {9, 0},
    };
    size_t r;
    (void)state;
    for (r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        filt_t f;
        f_init(&f);
        /* FollowError of axis 1 is 7.5 turns in figure 10.1 */
        if (rows[r].uses_tx) {
            assert_int_equal(f_tick(&f, rows[r].mode, 17.5f, 0, 0, 0), C4G_OK);
            assert_int_equal(f.tx.ax[0].mode, rows[r].mode);
            assert_true(f.rep.follow_err[0] == 7.5f);
            assert_int_equal(f_tick(&f, rows[r].mode, 17.51f, 0, 0, 0), C4G_OK);
        } else {
            /* pos_ref is the SMP+ reference: move the measure instead */
            f.num++;
            mk_rx(&f.rx, f.num, rows[r].mode);
            f.rx.ax[0].actual_pos = 2.5f;
            assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
            memset(f.tx.ax, 0, sizeof f.tx.ax);
            { uint32_t i; for (i = 0; i < 6; i++) f.tx.ax[i].mode = rows[r].mode; }
            assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
            assert_int_equal(f.tx.ax[0].mode, rows[r].mode);
            f.num++;
            mk_rx(&f.rx, f.num, rows[r].mode);
            f.rx.ax[0].actual_pos = 2.49f;
            assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
            memset(f.tx.ax, 0, sizeof f.tx.ax);
            { uint32_t i; for (i = 0; i < 6; i++) f.tx.ax[i].mode = rows[r].mode; }
            assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        }
        assert_int_equal(f.tx.ax[0].mode, C4G_MODE_FOLLOW_ERROR);  /* offending axis only */
        assert_int_equal(f.tx.ax[1].mode, rows[r].mode);
        assert_true(f.rep.axis_flags[0] & C4G_SF_FOLLOW_ERROR);
        assert_true(f.rep.axis_flags[0] & C4G_SF_FE_SENT);
        assert_true(f.ctl.arm[0].latch & C4G_LATCH_AXIS_FE);
    }
    {   /* not checked where SMP+ alone moves the robot (0, 0') */
        filt_t f;
        f_init(&f);
        f.num++;
        mk_rx(&f.rx, f.num, 0);
        f.rx.ax[0].actual_pos = -100.0f;
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[0].mode, 0);
    }
    {   /* axis 6 has FollowError 0: no threshold unless the user sets one */
        filt_t f;
        c4g_axis_limits_t l;
        f_init(&f);
        f.num++;
        mk_rx(&f.rx, f.num, 2);
        f.rx.ax[5].actual_pos = -1000.0f;
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        memset(f.tx.ax, 0, sizeof f.tx.ax);
        { uint32_t i; for (i = 0; i < 6; i++) f.tx.ax[i].mode = 2; }
        assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[5].mode, 2);
        memset(&l, 0, sizeof l);
        l.follow_error = 1.0f;
        assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 5, &l), C4G_OK);
        assert_true(f.ctl.lim[5].follow_error == 1.0f);
        f.num++;
        mk_rx(&f.rx, f.num, 2);
        f.rx.ax[5].actual_pos = 8.9f;
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        memset(f.tx.ax, 0, sizeof f.tx.ax);
        { uint32_t i; for (i = 0; i < 6; i++) f.tx.ax[i].mode = 2; }
        assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[5].mode, 508);
        /* the 508 stays until the drives are off */
        f.num++;
        mk_rx(&f.rx, f.num, 2);
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[5].mode, 508);
        assert_int_equal(f.tx.ax[4].mode, 2);
        memset(f.tx.ax, 0, sizeof f.tx.ax);
        { uint32_t i; for (i = 0; i < 6; i++) f.tx.ax[i].mode = 2; }
        assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[5].mode, 508);
        f.num++;
        mk_rx(&f.rx, f.num, 0);
        f.rx.infpar = 0;
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        assert_true(f.rep.events & C4G_CEV_LATCH_CLEARED);
        assert_int_equal(f.tx.ax[5].mode, 0);
        assert_int_equal(f.ctl.fe_latch[5], 0);
    }
}

static void test_filter_currents(void **state)
{
    filt_t f;
    (void)state;
    f_init(&f);
    assert_int_equal(f_tick(&f, 1, 10.0f, 0, 0, 24.5f), C4G_OK);
    assert_true(f.tx.ax[0].current_add == 24.5f);
    assert_int_equal(f.rep.n_filtered, 0);
    assert_int_equal(f_tick(&f, 1, 10.0f, 0, 0, 30.0f), C4G_OK);
    assert_true(f.tx.ax[0].current_add == 24.5f);
    assert_true(f.rep.axis_flags[0] & C4G_SF_CURRENT);
    assert_true(f.rep.events & C4G_CEV_SAFETY);
    assert_int_equal(f.rep.n_filtered, 1);
    assert_int_equal(f_tick(&f, 2, 0, 0, 0, -24.6f), C4G_OK);
    assert_true(f.tx.ax[0].current_add == -24.5f);
    assert_int_equal(f_tick(&f, 12, 0, 0, 0, -24.6f), C4G_OK);
    assert_true(f.tx.ax[0].current_add == -24.5f);
    /* mode 9: SMP+ current 20 A, AzLim 24.5 A */
    assert_int_equal(f_tick(&f, 9, 0, 0, 0, 4.5f), C4G_OK);
    assert_true(f.tx.ax[0].current_add == 4.5f);
    assert_int_equal(f_tick(&f, 9, 0, 0, 0, 5.0f), C4G_OK);
    assert_true(f.tx.ax[0].current_add == 4.5f);
    assert_true(f.rep.axis_flags[0] & C4G_SF_DCURRENT);
    /* mode 4: no current from the PC, nothing saturated */
    assert_int_equal(f_tick(&f, 4, 10.0f, 0, 0, 100.0f), C4G_OK);
    assert_true(f.tx.ax[0].current_add == 100.0f);
    /* user limit tightens AzLim, never loosens it */
    {
        c4g_axis_limits_t l;
        memset(&l, 0, sizeof l);
        l.current_max = 10.0f;
        assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
        assert_int_equal(f_tick(&f, 1, 10.0f, 0, 0, 11.0f), C4G_OK);
        assert_true(f.tx.ax[0].current_add == 10.0f);
        l.current_max = 100.0f;
        assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
        assert_true(f.ctl.lim[0].current_max == 24.5f);
    }
}

static void test_filter_continuity(void **state)
{
    filt_t f;
    c4g_axis_limits_t l;
    (void)state;
    f_init(&f);
    memset(&l, 0, sizeof l);
    l.max_step = 0.5f;
    l.max_vel = 0.25f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    /* mode 4, first tick: the step is measured from where the axis stood (10) */
    assert_int_equal(f_tick(&f, 4, 10.5f, 0.25f, 0, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == 10.5f);
    assert_int_equal(f.rep.axis_flags[0], 0);
    /* next ticks: from the last value sent */
    assert_int_equal(f_tick(&f, 4, 11.0f, 0, 0, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == 11.0f);
    assert_int_equal(f_tick(&f, 4, 12.0f, 0.3f, 0, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == 11.5f);
    assert_true(f.tx.ax[0].target_vel == 0.25f);
    assert_true(f.rep.axis_flags[0] & C4G_SF_STEP);
    assert_true(f.rep.axis_flags[0] & C4G_SF_VELOCITY);
    /* mode 1 after mode 4: the step restarts from the anchor (10) */
    assert_int_equal(f_tick(&f, 1, 10.6f, 0, 0.3f, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == 10.5f);
    assert_true(f.tx.ax[0].vel_add == 0.25f); /* velocity contribution bounded too */
    /* mode 5: the controller integrates D2 (fig. 14.1); D1 is not what it acts on */
    assert_int_equal(f_tick(&f, 5, 3.0f, -0.25f, 0, 0), C4G_OK);
    assert_int_equal(f.rep.axis_flags[0], 0);
    assert_true(f.tx.ax[0].target_pos == 3.0f);
    assert_int_equal(f_tick(&f, 5, 0.0f, -0.6f, 0, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_vel == -0.25f); /* step 0.5 and velocity 0.25 */
    assert_true(f.rep.axis_flags[0] & C4G_SF_STEP);
    /* mode 7: the controller adds D1 */
    assert_int_equal(f_tick(&f, 7, 0.7f, 9.0f, 0, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == 0.5f);
    assert_true(f.tx.ax[0].target_vel == 9.0f); /* D2 not used in mode 7 */
    /* mode 8: the controller integrates the velocity addition D4 */
    assert_int_equal(f_tick(&f, 8, 0, 0, 0.5f, 0), C4G_OK);
    assert_true(f.tx.ax[0].vel_add == 0.25f);
    assert_true(f.rep.axis_flags[0] & C4G_SF_VELOCITY);
    /* mode 2: the PC sends no targets; its velocity contribution is bounded */
    assert_int_equal(f_tick(&f, 2, 99.0f, 9.0f, -0.3f, 0), C4G_OK);
    assert_false(f.rep.axis_flags[0] & C4G_SF_STEP);
    assert_true(f.tx.ax[0].vel_add == -0.25f);
}

/* The stroke ends bound the position the controller will hold next tick, and stop the arm
 * (505) before it gets there. */
static void test_filter_stroke(void **state)
{
    static const struct { int32_t mode; float d1, d2, d4; int field; } rows[] = {
        {4, 10.6f, 0, 0, 1},  /* absolute D1 */
        {1, 10.6f, 0, 0, 1},
        {5, 0.0f, 0.6f, 0, 2}, /* pos_k += D2 */
        {7, 0.6f, 0, 0, 1},    /* offset += D1 */
        {8, 0, 0, 0.6f, 4},    /* reference += D4 */
    };
    size_t r;
    (void)state;
    for (r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        filt_t f;
        c4g_axis_limits_t l;
        float sent;
        uint32_t i;
        f_init(&f);
        memset(&l, 0, sizeof l);
        l.motor_min = 9.0f;
        l.motor_max = 10.5f;
        assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
        assert_int_equal(f_tick(&f, 0, 0, 0, 0, 0), C4G_OK);
        assert_int_equal(f_tick(&f, rows[r].mode, rows[r].d1, rows[r].d2, rows[r].d4, 0),
                         C4G_OK);
        sent = (rows[r].field == 1) ? f.tx.ax[0].target_pos
               : (rows[r].field == 2) ? f.tx.ax[0].target_vel : f.tx.ax[0].vel_add;
        if (rows[r].mode == 4 || rows[r].mode == 1) {
            assert_true(sent == 10.5f);
        } else {
            assert_true(sent == 0.5f); /* base 10 + 0.5 = the stroke end */
        }
        assert_true(f.rep.axis_flags[0] & C4G_SF_STROKE);
        for (i = 0; i < 6; i++) {
            assert_int_equal(f.tx.ax[i].mode, 505); /* the whole arm stops, in this reply */
        }
        assert_true(f.ctl.arm[0].latch & C4G_LATCH_STROKE);
        /* the stop holds until the drives are off */
        assert_int_equal(f_tick(&f, rows[r].mode, rows[r].d1, rows[r].d2, rows[r].d4, 0),
                         C4G_OK);
        assert_int_equal(f.tx.ax[0].mode, 505);
    }
    {   /* outside the stroke already: going back is kept, going further out becomes 0 */
        filt_t f;
        c4g_axis_limits_t l;
        f_init(&f);
        memset(&l, 0, sizeof l);
        l.motor_min = 0.0f;
        l.motor_max = 5.0f;
        assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
        assert_int_equal(f_tick(&f, 7, -0.25f, 0, 0, 0), C4G_OK); /* SMP+ at 10 */
        assert_true(f.tx.ax[0].target_pos == -0.25f);
        assert_int_equal(f.rep.axis_flags[0] & C4G_SF_STROKE, 0);
        assert_int_equal(f_tick(&f, 7, 0.0f, 0, 0, 0), C4G_OK);
        assert_int_equal(f.rep.axis_flags[0] & C4G_SF_STROKE, 0);
        assert_int_equal(f_tick(&f, 7, 0.25f, 0, 0, 0), C4G_OK);
        assert_true(f.tx.ax[0].target_pos == 0.0f);
        assert_true(f.rep.axis_flags[0] & C4G_SF_STROKE);
    }
    {   /* an absurd delta overflows the absolute position: never sent */
        filt_t f;
        uint32_t i;
        f_init(&f);
        f.num++;
        mk_rx(&f.rx, f.num, 7);
        f.rx.ax[0].target_pos = 3.4e38f;
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        for (i = 0; i < 6; i++) f.tx.ax[i].target_pos = 0.0f;
        f.tx.ax[0].target_pos = 3.4e38f;
        assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_ERR_NONFINITE);
        assert_int_equal(f.tx.ax[0].mode, 505);
    }
}

static void test_filter_joint_stroke(void **state)
{
    filt_t f;
    c4g_axis_limits_t l;
    c4g_kin_t k;
    c4g_init_t in;
    double q[6] = {0, 0, 0, 0, 0.5, 0}, qm[6], back[6];
    uint32_t i;
    int st;
    (void)state;
    f_init(&f);
    assert_int_equal(c4g_init_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_OK);
    memset(&l, 0, sizeof l);
    l.joint_min = -0.4f;
    l.joint_max = 0.4f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 4, &l), C4G_OK); /* joint 5 */
    assert_int_equal(f.ctl.n_joint[0], 6);
    assert_int_equal(f.ctl.joint_on[0], 1);
    /* mode 4 target at joint 5 = 0.5 rad (axis 4 at 0): clamped to 0.4 rad */
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, qm), C4G_OK);
    f.num++;
    mk_rx(&f.rx, f.num, 4);
    for (i = 0; i < 6; i++) {
        f.rx.ax[i].target_pos = (float)qm[i];
        f.rx.ax[i].actual_pos = (float)qm[i];
    }
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    for (i = 0; i < 6; i++) {
        f.tx.ax[i].target_pos = (float)qm[i];
        f.tx.ax[i].target_vel = 0.0f;
    }
    st = c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep);
    assert_int_equal(st, C4G_OK);
    assert_true(f.rep.axis_flags[4] & C4G_SF_STROKE_JOINT);
    for (i = 0; i < 6; i++) qm[i] = f.tx.ax[i].target_pos;
    assert_int_equal(c4g_kin_motor_to_link(&k, qm, 6, back), C4G_OK);
    assert_true(fabs(back[4] - 0.4) < 1e-5);
    assert_true(fabs(back[3]) < 1e-5);
    for (i = 0; i < 6; i++) assert_int_equal(f.tx.ax[i].mode, 505); /* and the arm stops */
    /* drives off clears the stop */
    f.num++;
    mk_rx(&f.rx, f.num, 0);
    f.rx.infpar = 0;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    assert_true(f.rep.events & C4G_CEV_LATCH_CLEARED);
    assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    /* mode 7 (deltas): SMP+ at joint 5 = 0.3 rad, delta of +0.2 rad clamped to +0.1 */
    q[4] = 0.3;
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, qm), C4G_OK);
    q[4] = 0.5;
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, back), C4G_OK);
    f.num++;
    mk_rx(&f.rx, f.num, 7);
    for (i = 0; i < 6; i++) {
        f.rx.ax[i].target_pos = (float)qm[i];
    }
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    for (i = 0; i < 6; i++) {
        f.tx.ax[i].target_pos = (float)(back[i] - qm[i]);
    }
    assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    assert_true(f.rep.axis_flags[4] & C4G_SF_STROKE_JOINT);
    for (i = 0; i < 6; i++) back[i] = (double)f.rx.ax[i].target_pos + (double)f.tx.ax[i].target_pos;
    assert_int_equal(c4g_kin_motor_to_link(&k, back, 6, q), C4G_OK);
    assert_true(fabs(q[4] - 0.4) < 1e-5);
    f.num++;
    mk_rx(&f.rx, f.num, 0);
    f.rx.infpar = 0;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    assert_true(f.rep.events & C4G_CEV_LATCH_CLEARED);
    assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    /* below the lower limit in mode 0: SMP+ moves the axis, nothing of the PC's to stop */
    f.num++;
    mk_rx(&f.rx, f.num, 0);
    f.rx.ax[4].target_pos = -100.0f;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    assert_int_equal(f.rep.axis_flags[4] & C4G_SF_STROKE_JOINT, 0);
    assert_true(f.tx.ax[4].target_pos == 0.0f);
    assert_int_equal(f.tx.ax[4].mode, 0);
    /* inside: untouched; and no conversion when the SMP+ data overflow the kinematics */
    f.num++;
    mk_rx(&f.rx, f.num, 0);
    f.rx.ax[0].target_pos = 3e38f;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    /* mode 4 below the lower limit */
    f.num++;
    mk_rx(&f.rx, f.num, 4);
    f.rx.ax[4].target_pos = -100.0f;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    for (i = 0; i < 6; i++) f.tx.ax[i].target_pos = f.tx.ax[i].target_vel = 0.0f;
    f.tx.ax[4].target_pos = -100.0f;
    assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    assert_true(f.rep.axis_flags[4] & C4G_SF_STROKE_JOINT);
    assert_int_equal(f.tx.ax[4].mode, 508); /* its following error wins over the stop */
    assert_int_equal(f.tx.ax[5].mode, 505); /* no threshold on axis 6: the stop shows */
}


/* The packet that opens mode 4 is lost and the next one reports a stale target (0): the
 * first step is still measured from where the axis stood in mode 0. */
static void test_anchor_survives_lost_entry(void **state)
{
    filt_t f;
    c4g_axis_limits_t l;
    float a = -1.0f;
    (void)state;
    f_init(&f);
    assert_int_equal(c4g_engine_anchor(NULL, 0, &a), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 6, &a), C4G_ERR_ARG);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, &a), C4G_ERR_STATE); /* no packet yet */
    memset(&l, 0, sizeof l);
    l.max_step = 0.05f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    assert_int_equal(f_tick(&f, 0, 0, 0, 0, 0), C4G_OK);  /* mode 0, SMP+ target 10 */
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, &a), C4G_OK);
    assert_true(a == 10.0f);
    f.num++;
    mk_rx(&f.rx, f.num, 4);
    f.rx.ax[0].target_pos = 0.0f; /* stale: what the controller did without our reply */
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, &a), C4G_OK);
    assert_true(a == 10.0f); /* not moved by the mode-4 packet */
    {   /* a PC anchoring on the packet (0) is caught as a 10-turn step */
        uint32_t i;
        for (i = 0; i < 6; i++) {
            f.tx.ax[i].target_pos = 10.0f;
            f.tx.ax[i].target_vel = 0.0f;
        }
        f.tx.ax[0].target_pos = 0.0f;
    }
    assert_int_equal(c4g_engine_finish(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    assert_true(f.rep.axis_flags[0] & C4G_SF_STEP);
    assert_true(f.tx.ax[0].target_pos == 9.95f);
    /* a PC anchoring on c4g_engine_anchor moves smoothly */
    assert_int_equal(f_tick(&f, 4, 9.99f, 0, 0, 0), C4G_OK);
    assert_int_equal(f.rep.axis_flags[0] & C4G_SF_STEP, 0);
}

static void test_set_limits_errors(void **state)
{
    filt_t f;
    c4g_axis_limits_t l;
    c4g_init_t in;
    c4g_engine_t ctl;
    (void)state;
    f_init(&f);
    memset(&l, 0, sizeof l);
    assert_int_equal(c4g_engine_set_limits(NULL, 0, 0, &l), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 4, 0, &l), C4G_ERR_ARG);
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 10, &l), C4G_ERR_ARG);
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 6, &l), C4G_ERR_NOT_OPEN);
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 1, 0, &l), C4G_ERR_NOT_OPEN);
    l.max_vel = NAN;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_NONFINITE);
    l.max_vel = 0;
    l.joint_max = INFINITY;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_NONFINITE);
    l.joint_max = 0;
    l.follow_error = -1;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_LIMITS);
    l.follow_error = 0;
    l.current_max = -1;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_LIMITS);
    l.current_max = 0;
    l.max_step = -1;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_LIMITS);
    l.max_step = 0;
    l.max_vel = -1;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_LIMITS);
    l.max_vel = 0;
    /* joint limits need every axis up to the last open one, with ratios */
    assert_int_equal(c4g_init_fig10_1(&in), C4G_OK);
    in.open_ax[0][2] = 0xFF;
    in.open_ax[0][5] = 2;
    in.open_ax[0][6] = 5;
    in.az_lim[0][6] = 5.0f;
    in.tx_rate[0][6] = 3.0f;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    l.joint_min = -1.0f;
    l.joint_max = 1.0f;
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_ERR_NOT_OPEN);
    assert_int_equal(c4g_init_fig10_1(&in), C4G_OK);
    in.tx_rate[0][2] = 0.0f;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_ERR_SINGULAR);
    ctl.kin_ok[0] = 0;
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_ERR_SINGULAR);
    /* clearing joint limits turns the joint check off */
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 1, &l), C4G_OK);
    assert_int_equal(f.ctl.joint_on[0], 1);
    memset(&l, 0, sizeof l);
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 1, &l), C4G_OK);
    assert_int_equal(f.ctl.joint_on[0], 0);
    /* user FE tighter than the controller's; looser one ignored */
    l.follow_error = 1.0f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    assert_true(f.ctl.lim[0].follow_error == 1.0f);
    l.follow_error = 100.0f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    assert_true(f.ctl.lim[0].follow_error == 7.5f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_follow_error),
        cmocka_unit_test(test_current),
        cmocka_unit_test(test_delta_current),
        cmocka_unit_test(test_step_velocity_stroke),
        cmocka_unit_test(test_filter_following_error),
        cmocka_unit_test(test_filter_currents),
        cmocka_unit_test(test_filter_continuity),
        cmocka_unit_test(test_filter_stroke),
        cmocka_unit_test(test_filter_joint_stroke),
        cmocka_unit_test(test_anchor_survives_lost_entry),
        cmocka_unit_test(test_set_limits_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
