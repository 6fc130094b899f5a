/* SPDX-License-Identifier: MIT */
/* PC-side safety (14.17.2, 15.7): every pure check at and around its boundaries, then the
 * filter inside c4g_safety_filter mode by mode: following error -> 508, current saturation,
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
    assert_int_equal(c4g_sf_stroke(50.0f, 3.0f, 1.0f, &o), C4G_SF_BAD_LIMIT); /* not off */
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
    float ref[6]; /* the reference the controller applied, as it reports it in D1 */
} filt_t;

static void f_init(filt_t *f)
{
    c4g_init_t in;
    uint32_t i;
    memset(f, 0, sizeof *f);
    for (i = 0; i < 6; i++) f->ref[i] = 10.0f;
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_engine_init(&f->ctl, &in, NULL), C4G_OK);
}

/* One tick in @p mode; axis 0 gets d1, d2, d4, d5, the others hold. */
static int f_tick(filt_t *f, int32_t mode, float d1, float d2, float d4, float d5)
{
    uint32_t i;
    int st;
    const int abs_mode = (mode == 1 || mode == 11 || mode == 4);
    f->num++;
    mk_rx(&f->rx, f->num, mode);
    for (i = 0; i < 6; i++) f->rx.ax[i].target_pos = f->ref[i];
    assert_int_equal(c4g_engine_step(&f->ctl, &f->rx, (uint64_t)f->num, &f->tx, &f->rep), C4G_OK);
    for (i = 0; i < 6; i++) {
        f->tx.ax[i].target_pos = (i == 0) ? d1 : (abs_mode ? f->ref[i] : 0.0f);
        f->tx.ax[i].target_vel = (i == 0) ? d2 : 0.0f;
        f->tx.ax[i].vel_add = (i == 0) ? d4 : 0.0f;
        f->tx.ax[i].current_add = (i == 0) ? d5 : 0.0f;
    }
    st = c4g_safety_filter(&f->ctl, &f->rx, &f->tx, &f->rep);
    for (i = 0; i < 6; i++) { /* the controller applies an absolute reply of its mode */
        if (abs_mode && f->tx.ax[i].mode == mode) f->ref[i] = f->tx.ax[i].target_pos;
    }
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
            assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
            assert_int_equal(f.tx.ax[0].mode, rows[r].mode);
            f.num++;
            mk_rx(&f.rx, f.num, rows[r].mode);
            f.rx.ax[0].actual_pos = 2.49f;
            assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
            memset(f.tx.ax, 0, sizeof f.tx.ax);
            { uint32_t i; for (i = 0; i < 6; i++) f.tx.ax[i].mode = rows[r].mode; }
            assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
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
        assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
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
        assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
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
        assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[5].mode, 508);
        /* the 508 stays until the drives are off */
        f.num++;
        mk_rx(&f.rx, f.num, 2);
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[5].mode, 508);
        assert_int_equal(f.tx.ax[4].mode, 2);
        memset(f.tx.ax, 0, sizeof f.tx.ax);
        { uint32_t i; for (i = 0; i < 6; i++) f.tx.ax[i].mode = 2; }
        assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        assert_int_equal(f.tx.ax[5].mode, 508);
        f.num++;
        mk_rx(&f.rx, f.num, 0);
        f.rx.infpar = 0;
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        assert_true(f.rep.events & C4G_CEV_LATCH_CLEARED);
        assert_int_equal(f.tx.ax[5].mode, 0);
        assert_int_equal(f.ctl.priv.fe_latch[5], 0);
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
    /* mode 1 after mode 4: from the reference the controller reports (11.5), not from
     * where the axis stood in mode 0 (10) */
    assert_int_equal(f_tick(&f, 1, 10.6f, 0, 0.3f, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == 11.0f);
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
        assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_ERR_NONFINITE);
        assert_int_equal(f.tx.ax[0].mode, 505);
    }
}

/* One tick of the joint tests: the controller reports @p at (motor turns) in @p modes per
 * axis, the PC asks @p to. */
static int j_tick(filt_t *f, const int32_t modes[6], const double at[6], const double to[6])
{
    uint32_t i;
    f->num++;
    mk_rx(&f->rx, f->num, 4);
    for (i = 0; i < 6; i++) {
        f->rx.ax[i].mode = modes[i];
        f->rx.ax[i].target_pos = (float)at[i];
        f->rx.ax[i].actual_pos = (float)at[i];
    }
    assert_int_equal(c4g_engine_step(&f->ctl, &f->rx, 0, &f->tx, &f->rep), C4G_OK);
    for (i = 0; i < 6; i++) {
        if (modes[i] == 4) {
            f->tx.ax[i].target_pos = (float)to[i];
            f->tx.ax[i].target_vel = 0.0f;
        }
    }
    return c4g_safety_filter(&f->ctl, &f->rx, &f->tx, &f->rep);
}

static void test_filter_joint_stroke(void **state)
{
    static const int32_t all4[6] = {4, 4, 4, 4, 4, 4};
    filt_t f;
    c4g_axis_limits_t l;
    c4g_kin_t k;
    c4g_init_t in;
    double q[6] = {0, 0, 0, 0, 0.3, 0}, at[6], qm[6], back[6];
    uint32_t i;
    (void)state;
    f_init(&f);
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_OK);
    memset(&l, 0, sizeof l);
    l.joint_min = -0.4f;
    l.joint_max = 0.4f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 4, &l), C4G_OK); /* joint 5 */
    assert_int_equal(f.ctl.priv.n_joint[0], 6);
    assert_int_equal(f.ctl.priv.joint_on[0], 1);
    /* mode 4 from joint 5 = 0.3 rad to 0.5 rad: shrunk to the end, 0.4 rad */
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, at), C4G_OK);
    q[4] = 0.5;
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, qm), C4G_OK);
    assert_int_equal(j_tick(&f, all4, at, qm), C4G_OK);
    assert_true(f.rep.axis_flags[4] & C4G_SF_STROKE_JOINT);
    for (i = 0; i < 6; i++) qm[i] = f.tx.ax[i].target_pos;
    assert_int_equal(c4g_kin_motor_to_link(&k, qm, 6, back), C4G_OK);
    assert_true(fabs(back[4] - 0.4) < 1e-5);
    assert_true(fabs(back[3]) < 1e-5);
    for (i = 0; i < 6; i++) assert_int_equal(f.tx.ax[i].mode, 505); /* and the arm stops */
    /* drives off clears the stop */
    f.rx.ax[4].target_pos = -100.0f;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    for (i = 0; i < 6; i++) f.tx.ax[i].target_pos = f.tx.ax[i].target_vel = 0.0f;
    f.tx.ax[4].target_pos = -100.0f;
    assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
    assert_int_equal(f.tx.ax[4].mode, 508); /* its following error wins over the stop */
    /* integrating modes towards the lower end (7 adds D1, 5 integrates D2, 8 integrates
     * D4): the addition shrinks to a third, on every axis that moved */
    {
        static const int32_t imodes[3] = {7, 5, 8};
        int mi;
        for (mi = 0; mi < 3; mi++) {
            filt_t g;
            double lo[6] = {0, 0, 0, 0, -0.3, 0}, m0[6], m1[6];
            f_init(&g);
            assert_int_equal(c4g_engine_set_limits(&g.ctl, 0, 4, &l), C4G_OK);
            assert_int_equal(c4g_kin_link_to_motor(&k, lo, 6, m0), C4G_OK);
            lo[4] = -0.6;
            assert_int_equal(c4g_kin_link_to_motor(&k, lo, 6, m1), C4G_OK);
            g.num++;
            mk_rx(&g.rx, g.num, imodes[mi]);
            for (i = 0; i < 6; i++) {
                g.rx.ax[i].target_pos = (float)m0[i];
                g.rx.ax[i].actual_pos = (float)m0[i];
            }
            assert_int_equal(c4g_engine_step(&g.ctl, &g.rx, 0, &g.tx, &g.rep), C4G_OK);
            for (i = 0; i < 6; i++) {
                float *fld = (imodes[mi] == 7) ? &g.tx.ax[i].target_pos
                           : (imodes[mi] == 5) ? &g.tx.ax[i].target_vel : &g.tx.ax[i].vel_add;
                g.tx.ax[i].target_pos = g.tx.ax[i].target_vel = g.tx.ax[i].vel_add = 0.0f;
                *fld = (float)(m1[i] - m0[i]);
            }
            assert_int_equal(c4g_safety_filter(&g.ctl, &g.rx, &g.tx, &g.rep), C4G_OK);
            assert_true(g.rep.axis_flags[4] & C4G_SF_STROKE_JOINT);
            for (i = 0; i < 6; i++) {
                const float v = (imodes[mi] == 7) ? g.tx.ax[i].target_pos
                              : (imodes[mi] == 5) ? g.tx.ax[i].target_vel : g.tx.ax[i].vel_add;
                qm[i] = m0[i] + (double)v;
                assert_true(fabs((double)v - (m1[i] - m0[i]) / 3.0) < 1e-5);
            }
            assert_int_equal(c4g_kin_motor_to_link(&k, qm, 6, back), C4G_OK);
            assert_true(fabs(back[4] + 0.4) < 1e-5);
        }
    }
}

/* An arm with mixed modes (PDL2 opened axes 1-4 and 6 in mode 4 and left axis 5 to SMP+),
 * axis 5 beyond its joint stroke: its stroke is not the PC's to enforce, and the coupled
 * PC axes are never rewritten for it (was: -0.100 turns per tick on them, unflagged). */
static void test_joint_stroke_mixed_modes(void **state)
{
    static const int32_t mixed[6] = {4, 4, 4, 4, 0, 4};
    filt_t f;
    c4g_axis_limits_t l;
    c4g_kin_t k;
    c4g_init_t in;
    double q[6] = {0, 0, 0, 0.1, 0.6, 0.2}, at[6], to[6];
    uint32_t i;
    int t;
    (void)state;
    f_init(&f);
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_kin_from_init(&in, 0, &k), C4G_OK);
    memset(&l, 0, sizeof l);
    l.max_step = 0.01f;
    for (i = 0; i < 6; i++) assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, i, &l), C4G_OK);
    l.joint_min = -0.4f;
    l.joint_max = 0.4f;
    for (i = 0; i < 6; i++) assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, i, &l), C4G_OK);
    assert_int_equal(c4g_kin_link_to_motor(&k, q, 6, at), C4G_OK);
    for (t = 0; t < 5; t++) { /* the PC holds: the wire carries exactly that */
        assert_int_equal(j_tick(&f, mixed, at, at), C4G_OK);
        for (i = 0; i < 6; i++) {
            if (mixed[i] == 4) {
                assert_true(f.tx.ax[i].target_pos == (float)at[i]);
                assert_int_equal(f.tx.ax[i].mode, 4);
            }
            assert_int_equal(f.rep.axis_flags[i], 0);
        }
    }
    /* axis 4 moves: through the wrist coupling that moves joint 5 too; the direction that
     * drives joint 5 further out is refused (and flagged), the other one is not */
    {
        int flagged = 0;
        double sign;
        for (sign = -1.0; sign < 2.0; sign += 2.0) {
            double qreq[6];
            filt_t g;
            f_init(&g);
            l.joint_min = l.joint_max = 0.0f;
            for (i = 0; i < 6; i++) assert_int_equal(c4g_engine_set_limits(&g.ctl, 0, i, &l), C4G_OK);
            l.joint_min = -0.4f;
            l.joint_max = 0.4f;
            assert_int_equal(c4g_engine_set_limits(&g.ctl, 0, 4, &l), C4G_OK);
            for (i = 0; i < 6; i++) to[i] = at[i];
            to[3] = at[3] + sign * 0.01;
            assert_int_equal(c4g_kin_motor_to_link(&k, to, 6, qreq), C4G_OK);
            assert_int_equal(j_tick(&g, mixed, at, to), C4G_OK);
            for (i = 0; i < 6; i++) {
                if (i != 3 && mixed[i] == 4) assert_true(g.tx.ax[i].target_pos == (float)at[i]);
            }
            if (qreq[4] > q[4]) { /* further out: held, flagged, the arm stops */
                assert_true(g.rep.axis_flags[3] & C4G_SF_STROKE_JOINT);
                assert_true(g.tx.ax[3].target_pos == (float)at[3]);
                assert_int_equal(g.tx.ax[3].mode, 505);
                flagged++;
            } else {
                assert_int_equal(g.rep.axis_flags[3], 0);
                assert_true(g.tx.ax[3].target_pos == (float)to[3]);
            }
        }
        assert_int_equal(flagged, 1);
    }
}

/* The anchor is where the axis's current mode began; every step of an absolute target is
 * measured from the reference the controller reports, whatever came before: the exit of
 * mode 1 (1 -> 11), a passive freezing (4 -> 502 -> 503 -> 4), 4 -> 14 -> 4. */
static void test_step_base_is_the_applied_reference(void **state)
{
    filt_t f;
    c4g_axis_limits_t l;
    float a = -1.0f;
    int t;
    (void)state;
    f_init(&f);
    assert_int_equal(c4g_engine_anchor(NULL, 0, &a), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 6, &a), C4G_ERR_ARG);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, &a), C4G_ERR_STATE); /* no packet yet */
    memset(&l, 0, sizeof l);
    l.max_step = 0.005f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    assert_int_equal(f_tick(&f, 0, 0, 0, 0, 0), C4G_OK); /* mode 0, SMP+ reference 10 */
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, &a), C4G_OK);
    assert_true(a == 10.0f);
    /* mode 1 ramps the axis up by 0.004 per tick to 10.2 */
    for (t = 1; t <= 50; t++) {
        assert_int_equal(f_tick(&f, 1, 10.0f + 0.004f * (float)t, 0, 0, 0), C4G_OK);
        assert_int_equal(f.rep.axis_flags[0] & C4G_SF_STEP, 0);
    }
    /* 1 -> 11: the PC holds where it is (was: rate-limited towards 10, 39x the limit) */
    assert_int_equal(f_tick(&f, 11, f.ref[0], 0, 0, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == f.ref[0]);
    assert_int_equal(f.rep.axis_flags[0], 0);
    assert_true(f.ref[0] > 10.19f);
    /* 4 -> 502 -> 503 -> 4: the mode begins again where the axis stands */
    assert_int_equal(f_tick(&f, 0, 0, 0, 0, 0), C4G_OK);
    assert_int_equal(f_tick(&f, 4, f.ref[0] + 0.004f, 0, 0, 0), C4G_OK);
    assert_int_equal(f_tick(&f, 502, 0, 0, 0, 0), C4G_OK);
    assert_int_equal(f_tick(&f, 503, 0, 0, 0, 0), C4G_OK);
    assert_int_equal(f_tick(&f, 4, f.ref[0], 0, 0, 0), C4G_OK);
    assert_int_equal(c4g_engine_anchor(&f.ctl, 0, &a), C4G_OK);
    assert_true(a == f.ref[0]);
    assert_true(a > 10.19f);
    assert_int_equal(f.rep.axis_flags[0], 0);
    /* a PC restarting from mode 0's reference (10) is held to one step */
    assert_int_equal(f_tick(&f, 4, 10.0f, 0, 0, 0), C4G_OK);
    assert_true(f.rep.axis_flags[0] & C4G_SF_STEP);
    assert_true(fabsf(f.tx.ax[0].target_pos - (a - 0.005f)) < 1e-6f);
    /* 4 -> 14 -> 4 */
    assert_int_equal(f_tick(&f, 14, 0, 0, 0, 0), C4G_OK);
    assert_int_equal(f_tick(&f, 4, f.ref[0] + 0.004f, 0, 0, 0), C4G_OK);
    assert_int_equal(f.rep.axis_flags[0], 0);
}

/* While an overlay goes out (here 505 after a drive-off request) the axis holds what the
 * controller applied: D1 its reference, never a value from before, never the PC's. */
static void test_overlay_holds_the_applied_reference(void **state)
{
    filt_t f;
    c4g_axis_limits_t l;
    (void)state;
    f_init(&f);
    memset(&l, 0, sizeof l);
    l.max_step = 0.5f;
    l.motor_min = 9.0f;
    l.motor_max = 11.0f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    f.ref[0] = 9.5f;
    assert_int_equal(f_tick(&f, 4, 9.6f, 0, 0, 0), C4G_OK);
    assert_int_equal(c4g_engine_request_drive_off(&f.ctl, 0), C4G_OK);
    assert_int_equal(f_tick(&f, 4, 1e30f, 0, 0, 0), C4G_OK);
    assert_int_equal(f.tx.ax[0].mode, 505);
    assert_true(f.tx.ax[0].target_pos <= 10.1f); /* one step at most: was 1e30 */
    assert_true(f.tx.ax[0].target_pos >= 9.6f - 1e-6f);
    /* the prepared reply under the overlay holds the reported reference */
    f.num++;
    mk_rx(&f.rx, f.num, 4);
    f.rx.ax[0].target_pos = 9.7f;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    assert_int_equal(f.tx.ax[0].mode, 505);
    assert_true(f.tx.ax[0].target_pos == 9.7f);
    assert_true(f.tx.ax[0].target_vel == 0.0f);
    /* mode 0' under an overlay: the copy back is its hold */
    f.num++;
    mk_rx(&f.rx, f.num, C4G_MODE_0_DEBUG);
    f.rx.ax[0].target_vel = 0.125f;
    assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
    assert_int_equal(f.tx.ax[0].mode, 505);
    assert_true(f.tx.ax[0].target_pos == 10.0f);
    assert_true(f.tx.ax[0].target_vel == 0.125f);
}

/* Modes the C4G does not have (3, 6, 1xx, 201, 202): no field goes out, the arm gets 505
 * (was: D5 = 1e30 A in mode 3). */
static void test_mode_without_rules(void **state)
{
    static const int32_t modes[] = {3, 6, 101, 102, 103, 201, 202};
    size_t m;
    (void)state;
    for (m = 0; m < sizeof modes / sizeof modes[0]; m++) {
        filt_t f;
        uint32_t i;
        f_init(&f);
        f.num++;
        mk_rx(&f.rx, f.num, modes[m]);
        assert_int_equal(c4g_engine_step(&f.ctl, &f.rx, 0, &f.tx, &f.rep), C4G_OK);
        for (i = 0; i < 6; i++) { /* nothing is required in such a mode */
            assert_false(c4g_is_unset(f.tx.ax[i].current_add));
            assert_false(c4g_is_unset(f.tx.ax[i].measure));
            f.tx.ax[i].current_add = 1e30f;
            f.tx.ax[i].target_pos = 5.0f;
            f.tx.ax[i].target_vel = 1.0f;
            f.tx.ax[i].measure = 7.0f;
            f.tx.ax[i].vel_add = 2.0f;
        }
        assert_int_equal(c4g_safety_filter(&f.ctl, &f.rx, &f.tx, &f.rep), C4G_OK);
        for (i = 0; i < 6; i++) {
            assert_true(f.tx.ax[i].current_add == 0.0f);
            assert_true(f.tx.ax[i].target_pos == 0.0f);
            assert_true(f.tx.ax[i].target_vel == 0.0f);
            assert_true(f.tx.ax[i].measure == 0.0f);
            assert_true(f.tx.ax[i].vel_add == 0.0f);
            assert_int_equal(f.tx.ax[i].mode, 505);
            assert_true(f.rep.axis_flags[i] & C4G_SF_NO_RULE);
        }
    }
}

/* A stroke that is not an interval is refused, never taken as "off" (was: [1, -1] taken,
 * the check off, D1 5.0 out unflagged). */
static void test_reversed_stroke_refused(void **state)
{
    filt_t f;
    c4g_axis_limits_t l;
    (void)state;
    f_init(&f);
    memset(&l, 0, sizeof l);
    l.motor_min = 1.0f;
    l.motor_max = -1.0f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_LIMITS);
    l.motor_min = 1.0f;
    l.motor_max = 1.0f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_LIMITS);
    l.motor_min = 0.0f;
    l.motor_max = 0.0f;
    l.joint_min = 0.5f;
    l.joint_max = -0.5f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_ERR_LIMITS);
    l.joint_min = -0.0f; /* both ends 0: off */
    l.joint_max = 0.0f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    l.motor_min = -1.0f;
    l.motor_max = 1.0f;
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 0, &l), C4G_OK);
    f.ref[0] = 0.9f;
    assert_int_equal(f_tick(&f, 4, 5.0f, 0, 0, 0), C4G_OK);
    assert_true(f.tx.ax[0].target_pos == 1.0f);
    assert_true(f.rep.axis_flags[0] & C4G_SF_STROKE);
    /* the checked single rule: reversed is a bad limit, 0, 0 is off */
    {
        float o;
        assert_int_equal(c4g_sf_stroke(5.0f, 1.0f, -1.0f, &o), C4G_SF_BAD_LIMIT);
        assert_int_equal(c4g_sf_stroke(5.0f, 0.0f, 0.0f, &o), 0);
    }
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
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    in.open_ax[0][2] = 0xFF;
    in.open_ax[0][5] = 2;
    in.open_ax[0][6] = 5;
    in.az_lim[0][6] = 5.0f;
    in.tx_rate[0][6] = 3.0f;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    l.joint_min = -1.0f;
    l.joint_max = 1.0f;
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_ERR_NOT_OPEN);
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    in.tx_rate[0][2] = 0.0f;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_ERR_SINGULAR);
    ctl.kin_ok[0] = 0;
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_ERR_SINGULAR);
    /* clearing joint limits turns the joint check off */
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 1, &l), C4G_OK);
    assert_int_equal(f.ctl.priv.joint_on[0], 1);
    memset(&l, 0, sizeof l);
    assert_int_equal(c4g_engine_set_limits(&f.ctl, 0, 1, &l), C4G_OK);
    assert_int_equal(f.ctl.priv.joint_on[0], 0);
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
        cmocka_unit_test(test_step_base_is_the_applied_reference),
        cmocka_unit_test(test_joint_stroke_mixed_modes),
        cmocka_unit_test(test_overlay_holds_the_applied_reference),
        cmocka_unit_test(test_mode_without_rules),
        cmocka_unit_test(test_reversed_stroke_refused),
        cmocka_unit_test(test_set_limits_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
