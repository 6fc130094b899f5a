/* SPDX-License-Identifier: MIT */
/* Control context: init, step/finish flow, per-mode packet rules, mode-10 copy-back,
 * requests and their wire effects (exit, 500, 505, 508), latches, and a table-driven walk
 * of the PDL2 sequences of figure 24.4 through the state machine. */
#include "test_helpers.h"

static c4g_init_t fig(void)
{
    c4g_init_t in;
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    return in;
}

/* Figure 10.1 plus two axes on ARM 2 (OPEN 6, 7) with AzLim 5 A and no ratios. */
static c4g_init_t fig2(void)
{
    c4g_init_t in = fig();
    in.n_ax_open = 8;
    in.open_ax[1][0] = 6;
    in.open_ax[1][1] = 7;
    in.az_lim[1][0] = 5.0f;
    in.az_lim[1][1] = 5.0f;
    return in;
}

static void mk_rx(c4g_ctrl_packet_t *rx, int32_t num, uint32_t n, int32_t mode, uint8_t drive)
{
    uint32_t i;
    memset(rx, 0, sizeof *rx);
    rx->num = num;
    rx->n_axes = n;
    rx->infpar = c4g_arm_byte_set(0, 0, drive);
    rx->infpar = c4g_arm_byte_set(rx->infpar, 1, drive);
    for (i = 0; i < n; i++) {
        rx->ax[i].mode = mode;
        rx->ax[i].target_pos = 1.0f + (float)i;
        rx->ax[i].actual_pos = 1.0f + (float)i;
        rx->ax[i].current_ref = 2.0f;
        rx->ax[i].target_vel = 0.0f;
    }
}

/* Fill every unset field: hold position for absolute modes, zero otherwise. */
static void fill(const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx)
{
    uint32_t i;
    for (i = 0; i < tx->n_axes; i++) {
        c4g_pc_axis_t *a = &tx->ax[i];
        if (c4g_is_unset(a->target_pos)) {
            a->target_pos = (a->mode == 1 || a->mode == 11 || a->mode == 4) ? rx->ax[i].target_pos
                                                                            : 0.0f;
        }
        if (c4g_is_unset(a->target_vel)) a->target_vel = 0.0f;
        if (c4g_is_unset(a->measure)) a->measure = 0.0f;
        if (c4g_is_unset(a->vel_add)) a->vel_add = 0.0f;
        if (c4g_is_unset(a->current_add)) a->current_add = 1.0f;
    }
}

static int tick(c4g_engine_t *ctl, const c4g_ctrl_packet_t *rx, uint64_t t, c4g_pc_packet_t *tx,
                c4g_engine_report_t *rep)
{
    assert_int_equal(c4g_engine_step(ctl, rx, t, tx, rep), C4G_OK);
    fill(rx, tx);
    return c4g_safety_filter(ctl, rx, tx, rep);
}

static void encodes(const c4g_pc_packet_t *tx)
{
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;
    assert_int_equal(c4g_pc_encode(tx, buf, sizeof buf, &len), C4G_OK);
}

static void test_strerror_and_unset(void **state)
{
    int s;
    (void)state;
    for (s = -101; s >= -116; s--) {
        if (s == -103 || s == -106) {
            assert_string_equal(c4g_strerror(s), "unknown status"); /* retired codes */
        } else {
            assert_string_not_equal(c4g_strerror(s), "unknown status");
        }
    }
    assert_string_equal(c4g_strerror(-100), "unknown status");
    assert_string_equal(c4g_strerror(-117), "unknown status");
    assert_string_equal(c4g_strerror(-99), "unknown status");
    assert_string_equal(c4g_strerror(C4G_ERR_FORBIDDEN),
                        "mode change not allowed from the arm's current mode");
    assert_true(c4g_is_unset(c4g_unset()));
    assert_false(c4g_is_unset(0.0f));
    assert_true(c4g_unset() != c4g_unset()); /* a NaN */
}

static void test_init(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_engine_config_t c;
    (void)state;
    assert_int_equal(c4g_engine_init(NULL, &in, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_init(&ctl, NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(ctl.map.n_axes, 6);
    assert_int_equal(ctl.arm[0].n_axes, 6);
    assert_int_equal(ctl.arm[1].n_axes, 0);
    assert_int_equal(ctl.kin_ok[0], 1);
    assert_true(ctl.lim[3].current_max == 9.5f);
    assert_true(ctl.lim[5].follow_error == 0.0f);
    assert_int_equal(ctl.cfg.request_timeout_ticks, 100);
    assert_int_equal(c4g_engine_config_default(&c), C4G_OK);
    c.moving_eps = -1.0f;
    assert_int_equal(c4g_engine_init(&ctl, &in, &c), C4G_ERR_ARG);
    c.moving_eps = 0.5f;
    assert_int_equal(c4g_engine_init(&ctl, &in, &c), C4G_OK);
    assert_true(ctl.cfg.moving_eps == 0.5f);
    in.num = 9;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_ERR_NUM);
    in = fig();
    in.tx_rate[2][0] = 1.0f / 0.0f; /* validate catches non-finite floats anywhere */
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_ERR_NONFINITE);
    in = fig();
    in.open_ax[0][5] = 0; /* OPEN index used twice */
    assert_true(c4g_engine_init(&ctl, &in, NULL) != C4G_OK);
}

static void test_step_finish_args(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    mk_rx(&rx, 100, 6, 0, 5);
    assert_int_equal(c4g_engine_step(NULL, &rx, 0, &tx, &rep), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_step(&ctl, NULL, 0, &tx, &rep), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, NULL, &rep), C4G_ERR_NULL);
    assert_int_equal(c4g_safety_filter(NULL, &rx, &tx, &rep), C4G_ERR_NULL);
    assert_int_equal(c4g_safety_filter(&ctl, NULL, &tx, &rep), C4G_ERR_NULL);
    assert_int_equal(c4g_safety_filter(&ctl, &rx, NULL, &rep), C4G_ERR_NULL);
    /* finish without step */
    memset(&tx, 0, sizeof tx);
    tx.n_axes = 6;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_STATE);
    rx.n_axes = 5;
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_ERR_PACKET);
    mk_rx(&rx, 100, 6, 0, 5);
    rx.ax[2].mode = 13;
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_ERR_MODE);
    mk_rx(&rx, 100, 6, 0, 5);
    rx.ax[5].ext[2] = 0.0f / 0.0f;
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_ERR_NONFINITE);
    mk_rx(&rx, 100, 6, 0, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, NULL), C4G_OK);
    /* finish with another packet than the stepped one */
    rx.num = 101;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_STATE);
    rx.num = 100;
    tx.n_axes = 5;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_STATE);
    tx.n_axes = 6;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, NULL), C4G_OK);
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, NULL), C4G_ERR_STATE); /* once */
}

static void test_neutral_and_copy_back(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    uint32_t i;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    mk_rx(&rx, 7, 6, 0, 5);
    rx.cmd = 0x33;
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(tx.num, 7);
    assert_int_equal(tx.infpar, 0);
    assert_int_equal(tx.cmd, 0);
    for (i = 0; i < 6; i++) {
        assert_int_equal(tx.ax[i].mode, 0);
        assert_true(tx.ax[i].target_pos == 0.0f);
    }
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
    assert_int_equal(rep.n_filtered, 0);
    encodes(&tx);
    /* mode 10: the library copies D1..D5 back, whatever the caller wrote */
    mk_rx(&rx, 8, 6, 10, 5);
    rx.ax[1].target_vel = 0.25f;
    rx.ax[1].actual_vel = -0.5f;
    assert_int_equal(c4g_engine_step(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    assert_true(tx.ax[1].target_vel == 0.25f);
    tx.ax[1].target_pos = 99.0f;
    tx.ax[1].current_add = 99.0f;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
    assert_true(tx.ax[1].target_pos == rx.ax[1].target_pos);
    assert_true(tx.ax[1].target_vel == 0.25f);
    assert_true(tx.ax[1].measure == rx.ax[1].actual_pos);
    assert_true(tx.ax[1].vel_add == -0.5f);
    assert_true(tx.ax[1].current_add == 2.0f);
    assert_true(rep.axis_flags[1] & C4G_SF_COPY_BACK);
    assert_int_equal(rep.n_filtered, 0);
    encodes(&tx);
}

static void test_required_fields(void **state)
{
    static const struct { int32_t mode; uint32_t fields; } rows[] = {
        {1, C4G_PCF_D1 | C4G_PCF_D2 | C4G_PCF_D4 | C4G_PCF_D5},
        {11, C4G_PCF_D1 | C4G_PCF_D2 | C4G_PCF_D4 | C4G_PCF_D5},
        {2, C4G_PCF_D4 | C4G_PCF_D5}, {12, C4G_PCF_D4 | C4G_PCF_D5},
        {4, C4G_PCF_D1 | C4G_PCF_D2}, {5, C4G_PCF_D1 | C4G_PCF_D2}, {7, C4G_PCF_D1},
        {8, C4G_PCF_D4}, {9, C4G_PCF_D5}, {17, 0}, {170, 0}, {0, 0},
    };
    size_t r;
    (void)state;
    for (r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        uint32_t k;
        for (k = 0; k < 5; k++) {
            c4g_engine_t ctl;
            c4g_init_t in = fig();
            c4g_ctrl_packet_t rx;
            c4g_pc_packet_t tx;
            c4g_engine_report_t rep;
            const uint32_t bit = 1u << k;
            float *f;
            int st;
            assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
            mk_rx(&rx, 1, 6, rows[r].mode, 5);
            assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
            f = (k == 0) ? &tx.ax[2].target_pos : (k == 1) ? &tx.ax[2].target_vel
              : (k == 2) ? &tx.ax[2].measure : (k == 3) ? &tx.ax[2].vel_add
              : &tx.ax[2].current_add;
            assert_int_equal(c4g_is_unset(*f), (rows[r].fields & bit) != 0);
            /* fill everything except this one field of axis 2 */
            fill(&rx, &tx);
            if (rows[r].fields & bit) {
                *f = c4g_unset();
            }
            st = c4g_safety_filter(&ctl, &rx, &tx, &rep);
            if (rows[r].fields & bit) {
                assert_int_equal(st, C4G_ERR_MISSING_DATA);
                assert_true(rep.axis_flags[2] & C4G_SF_MISSING);
                assert_true(rep.axis_flags[2] & C4G_SF_HELD);
                uint32_t j;
                for (j = 0; j < 6; j++) {
                    assert_int_equal(tx.ax[j].mode, C4G_MODE_DRIVE_OFF);
                }
                assert_int_equal(ctl.arm[0].latch, C4G_LATCH_DRIVE_OFF);
            } else {
                assert_int_equal(st, C4G_OK);
                assert_int_equal(tx.ax[2].mode, rows[r].mode);
            }
            encodes(&tx);
        }
    }
}

static void test_nonfinite_holds(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    uint32_t i;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    /* first packet already bad: nothing safe yet, zeros go out with 505 */
    mk_rx(&rx, 1, 6, 4, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    fill(&rx, &tx);
    tx.ax[0].ext[1] = 1.0f / 0.0f;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_NONFINITE);
    assert_true(tx.ax[0].ext[1] == 0.0f);
    assert_int_equal(tx.ax[0].mode, 505);
    encodes(&tx);
    /* later: the axis holds its last safe value */
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    mk_rx(&rx, 1, 6, 4, 5);
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    mk_rx(&rx, 2, 6, 4, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    fill(&rx, &tx);
    tx.ax[3].target_pos = 0.0f / 0.0f;
    tx.ax[4].target_pos = 4.9f;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_NONFINITE);
    assert_true(tx.ax[3].target_pos == 4.0f); /* last safe (held position) */
    assert_true(rep.axis_flags[3] & C4G_SF_NONFINITE);
    for (i = 0; i < 6; i++) {
        assert_int_equal(tx.ax[i].mode, 505);
        assert_true(rep.axis_flags[i] & C4G_SF_DRIVE_OFF);
    }
    assert_true(tx.ax[4].target_pos == 4.9f); /* good axes keep their data */
    encodes(&tx);
    /* latched: 505 keeps going out, data held, no unset fields */
    mk_rx(&rx, 3, 6, 4, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 2, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 505);
    assert_false(c4g_is_unset(tx.ax[0].target_pos));
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 505);
    /* drives off: latch cleared, back to echo */
    mk_rx(&rx, 4, 6, 0, 0);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 3, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_LATCH_CLEARED);
    assert_int_equal(tx.ax[0].mode, 0);
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
}

static void test_mixed_arm(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    mk_rx(&rx, 1, 6, 0, 5);
    rx.ax[1].mode = 4;
    rx.ax[3].mode = 4;
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(ctl.arm[0].mode, 4);   /* an open mode wins over 0 */
    assert_int_equal(ctl.arm[0].mixed, 1);
    assert_true(rep.events & C4G_CEV_MIXED);
    assert_int_equal(tx.ax[0].mode, 0);     /* each axis echoes its own mode */
    assert_int_equal(tx.ax[1].mode, 4);
    assert_int_equal(c4g_engine_request_mode(&ctl, 0, 5), C4G_ERR_PDL_ONLY);
    mk_rx(&rx, 2, 6, 0, 5);
    rx.ax[1].mode = 4;
    rx.ax[2].mode = 502;                    /* a special mode wins over everything */
    rx.ax[4].mode = 503;
    assert_int_equal(tick(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    assert_int_equal(ctl.arm[0].mode, 502);
}

static void test_mode_restored(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    mk_rx(&rx, 1, 6, 0, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    tx.ax[1].mode = C4G_MODE_4; /* not through the request API */
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_MODE_RESTORED);
    assert_int_equal(tx.ax[1].mode, 0);
    assert_true(rep.axis_flags[1] & C4G_SF_MODE_RESTORED);
    /* a drive off asked between step and finish goes out at once */
    mk_rx(&rx, 2, 6, 0, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_engine_request_drive_off(&ctl, 0), C4G_OK);
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 505);
    /* caller may already write the overlay mode itself */
    mk_rx(&rx, 3, 6, 0, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 505);
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
}

/* ----------------------------------------------------------------- requests */

/* Operating modes are the PDL2 program's to start (manual 24.2): every request is refused,
 * the reply echoes what the controller reports, and the data of the new mode are required in
 * the very first packet that carries it. */
static void test_request_mode_refused(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    const int32_t modes[] = {0, 10, 1, 11, 2, 12, 3, 4, 14, 5, 15, 6, 7, 17, 170, 8, 9,
                             101, 102, 103, 201, 202, 500, 501, 502, 503, 504, 505, 506, 508};
    size_t k;
    uint32_t i;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(c4g_engine_request_mode(NULL, 0, 4), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_request_mode(&ctl, 4, 4), C4G_ERR_ARG);
    assert_int_equal(c4g_engine_request_mode(&ctl, 1, 4), C4G_ERR_NOT_OPEN);
    mk_rx(&rx, 1, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    for (k = 0; k < sizeof modes / sizeof modes[0]; k++) {
        assert_int_equal(c4g_engine_request_mode(&ctl, 0, modes[k]), C4G_ERR_PDL_ONLY);
    }
    assert_int_equal(c4g_engine_request_mode(&ctl, 0, 13), C4G_ERR_MODE);
    assert_string_equal(c4g_strerror(C4G_ERR_PDL_ONLY),
                        "only the controller's PDL2 program starts an operating mode");
    /* the next reply still echoes mode 0 */
    mk_rx(&rx, 2, 6, 0, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 0);
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
    /* PDL2 sets mode 4: the first packet carrying it needs the mode's data */
    mk_rx(&rx, 3, 6, 4, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 2, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_START);
    for (i = 0; i < 6; i++) {
        assert_int_equal(tx.ax[i].mode, 4);
        assert_true(c4g_is_unset(tx.ax[i].target_pos));
        assert_true(c4g_is_unset(tx.ax[i].target_vel));
    }
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_MISSING_DATA);
    assert_int_equal(tx.ax[0].mode, 505); /* never a mode without its data */
}

/* Two arms in different modes: the exits are separate INFPAR bytes. */
static void test_two_arm_exits(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig2();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(ctl.arm[1].n_axes, 2);
    mk_rx(&rx, 1, 8, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    mk_rx(&rx, 2, 8, 4, 5);
    rx.ax[0].mode = rx.ax[1].mode = rx.ax[2].mode = rx.ax[3].mode = rx.ax[4].mode =
        rx.ax[5].mode = 1;
    assert_int_equal(tick(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 1);
    assert_int_equal(tx.ax[6].mode, 4);
    assert_true(rep.arm_events[0] & C4G_CEV_START);
    assert_true(rep.arm_events[1] & C4G_CEV_START);
    assert_int_equal(c4g_engine_request_exit(&ctl, 1), C4G_OK);
    mk_rx(&rx, 3, 8, 4, 5);
    rx.ax[0].mode = rx.ax[1].mode = rx.ax[2].mode = rx.ax[3].mode = rx.ax[4].mode =
        rx.ax[5].mode = 1;
    assert_int_equal(tick(&ctl, &rx, 2, &tx, &rep), C4G_OK);
    assert_int_equal(tx.infpar, 0x0100u);
    /* the exit is not taken: it times out */
    ctl.cfg.request_timeout_ticks = 2;
    mk_rx(&rx, 4, 8, 4, 5);
    assert_int_equal(tick(&ctl, &rx, 3, &tx, &rep), C4G_OK);
    mk_rx(&rx, 5, 8, 4, 5);
    assert_int_equal(tick(&ctl, &rx, 4, &tx, &rep), C4G_OK);
    assert_true(rep.arm_events[1] & C4G_CEV_REQ_TIMEOUT);
}

static void test_exit_and_freeze(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(c4g_engine_request_exit(NULL, 0), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_request_freeze(&ctl, 7), C4G_ERR_ARG);
    mk_rx(&rx, 1, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_ERR_NOT_IN_OPEN);
    /* active freezing from mode 0: 500 on every axis until exit */
    assert_int_equal(c4g_engine_request_freeze(&ctl, 0), C4G_OK);
    assert_int_equal(c4g_engine_request_freeze(&ctl, 0), C4G_OK); /* idempotent */
    mk_rx(&rx, 2, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 500);
    assert_int_equal(tx.ax[5].mode, 500);
    mk_rx(&rx, 3, 6, 500, 5); /* the controller echoes 500 */
    assert_int_equal(tick(&ctl, &rx, 2, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_FREEZE_A);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);
    mk_rx(&rx, 4, 6, 500, 5);
    assert_int_equal(tick(&ctl, &rx, 3, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_arm_byte(tx.infpar, 0), 1);
    assert_int_equal(tx.ax[0].mode, 500);
    assert_false(rep.events & C4G_CEV_END); /* freezing is not a mode phase */
    mk_rx(&rx, 5, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 4, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_FREEZE_A_END);
    assert_int_equal(tx.ax[0].mode, 0);
    assert_int_equal(tx.infpar, 0);
    /* controller that never echoes 500 */
    assert_int_equal(c4g_engine_request_freeze(&ctl, 0), C4G_OK);
    mk_rx(&rx, 6, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 5, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);
    mk_rx(&rx, 7, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 6, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_arm_byte(tx.infpar, 0), 1);
    mk_rx(&rx, 8, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 7, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_FREEZE_A_END);
    assert_int_equal(tx.infpar, 0);
    assert_int_equal(tx.ax[0].mode, 0);
    /* echoes 500 forever: the exit times out, freezing given up */
    ctl.cfg.request_timeout_ticks = 2;
    assert_int_equal(c4g_engine_request_freeze(&ctl, 0), C4G_OK);
    mk_rx(&rx, 9, 6, 500, 5);
    assert_int_equal(tick(&ctl, &rx, 8, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);
    mk_rx(&rx, 10, 6, 500, 5);
    assert_int_equal(tick(&ctl, &rx, 9, &tx, &rep), C4G_OK);
    mk_rx(&rx, 11, 6, 500, 5);
    assert_int_equal(tick(&ctl, &rx, 10, &tx, &rep), C4G_OK);
    mk_rx(&rx, 12, 6, 500, 5);
    assert_int_equal(tick(&ctl, &rx, 11, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_FREEZE_A_END);
    assert_int_equal(ctl.arm[0].frozen, 0);
    /* exit in mode 4 that the controller ignores: timeout, back to CRUISE */
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    ctl.cfg.request_timeout_ticks = 2;
    mk_rx(&rx, 1, 6, 4, 5);
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);    /* idempotent */
    mk_rx(&rx, 2, 6, 4, 5);
    assert_int_equal(tick(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    mk_rx(&rx, 3, 6, 4, 5);
    assert_int_equal(tick(&ctl, &rx, 2, &tx, &rep), C4G_OK);
    mk_rx(&rx, 4, 6, 4, 5);
    assert_int_equal(tick(&ctl, &rx, 3, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_REQ_TIMEOUT);
    assert_int_equal(ctl.arm[0].phase, C4G_MPH_CRUISE);
    assert_int_equal(ctl.arm[0].exit_req, 0);
}

static void test_drive_off_follow_error_requests(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    uint32_t i;
    (void)state;
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(c4g_engine_request_drive_off(NULL, 0), C4G_ERR_NULL);
    assert_int_equal(c4g_engine_request_follow_error(&ctl, 5), C4G_ERR_ARG);
    mk_rx(&rx, 1, 6, 501, 5);
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    /* never refused, even while driving on */
    assert_int_equal(c4g_engine_request_follow_error(&ctl, 0), C4G_OK);
    mk_rx(&rx, 2, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    for (i = 0; i < 6; i++) {
        assert_int_equal(tx.ax[i].mode, 508);
        assert_true(rep.axis_flags[i] & C4G_SF_FE_SENT);
    }
    assert_int_equal(c4g_engine_request_freeze(&ctl, 0), C4G_ERR_LATCHED);
    mk_rx(&rx, 3, 6, 0, 0); /* drives off */
    assert_int_equal(tick(&ctl, &rx, 2, &tx, &rep), C4G_OK);
    assert_true(rep.events & C4G_CEV_LATCH_CLEARED);
    assert_true(rep.events & C4G_CEV_DRIVE_OFF);
    assert_int_equal(tx.ax[0].mode, 0);
    /* a drive off in mode 0 */
    mk_rx(&rx, 4, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 3, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_engine_request_drive_off(&ctl, 0), C4G_OK);
    mk_rx(&rx, 5, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 4, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 505);
    /* the latch stays while the drives are on */
    mk_rx(&rx, 6, 6, 0, 5);
    assert_int_equal(tick(&ctl, &rx, 5, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 505);
}

/* ----------------------------------------------------------------- figure 24.4 walk */

enum { NONE = 0, EXIT = 1 };

typedef struct walk_row {
    int32_t rx_mode;
    uint8_t drive;
    int moving;
    int pc;              /* action before the tick */
    int32_t unused;
    int32_t tx_mode;     /* mode the reply carries */
    uint8_t exit_byte;   /* INFPAR byte of the reply */
    c4g_mode_phase_t phase;
    c4g_fsm_state_t fsm;
    uint32_t events;     /* must all be raised */
} walk_row_t;

static void walk(const char *name, const walk_row_t *rows, size_t n, uint64_t start_ns)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_engine_config_t c;
    size_t k;
    assert_int_equal(c4g_engine_config_default(&c), C4G_OK);
    c.start_ns = start_ns;
    assert_int_equal(c4g_engine_init(&ctl, &in, &c), C4G_OK);
    for (k = 0; k < n; k++) {
        const walk_row_t *w = &rows[k];
        c4g_ctrl_packet_t rx;
        c4g_pc_packet_t tx;
        c4g_engine_report_t rep;
        uint32_t i;
        if (w->pc == EXIT) {
            assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);
        }
        mk_rx(&rx, (int32_t)k + 1, 6, w->rx_mode, w->drive);
        for (i = 0; i < 6; i++) {
            rx.ax[i].target_vel = w->moving ? 0.01f : 0.0f;
        }
        assert_int_equal(tick(&ctl, &rx, (uint64_t)k * 2000000u, &tx, &rep), C4G_OK);
        if (tx.ax[0].mode != w->tx_mode || c4g_arm_byte(tx.infpar, 0) != w->exit_byte ||
            ctl.arm[0].phase != w->phase || ctl.arm[0].fsm != w->fsm ||
            (rep.arm_events[0] & w->events) != w->events ||
            (rep.arm_events[0] & C4G_CEV_UNEXPECTED) != 0) {
            fail_msg("%s row %zu: tx mode %d exit %u phase %d fsm %d events 0x%x", name, k,
                     tx.ax[0].mode, c4g_arm_byte(tx.infpar, 0), ctl.arm[0].phase,
                     ctl.arm[0].fsm, rep.arm_events[0]);
        }
        encodes(&tx);
    }
}

#define ROWS(r) r, sizeof r / sizeof r[0]

static void test_fig24_4_pdl_sequences(void **state)
{
    const uint32_t MC = C4G_CEV_MODE_CHANGE;
    (void)state;
    {   /* Mode 0: setta_modalita(mod0), MOVE, DELAY */
        const walk_row_t r[] = {
            {501, 5, 0, NONE, 0, 501, 0, C4G_MPH_SPECIAL, C4G_FSM_UNKNOWN, C4G_CEV_DRIVING_ON},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_DRIVING_ON_END | MC},
            {0, 5, 1, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S10, 0},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, 0},
        };
        walk("mode 0", ROWS(r), 0);
    }
    {   /* Mode 0': setta_modalita(mod0p), MOVE, DELAY */
        const walk_row_t r[] = {
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, 0},
            {10, 5, 1, NONE, 0, 10, 0, C4G_MPH_NONE, C4G_FSM_S10, MC},
            {10, 5, 0, NONE, 0, 10, 0, C4G_MPH_NONE, C4G_FSM_S00, 0},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, MC},
        };
        walk("mode 0'", ROWS(r), 0);
    }
    {   /* Mode 1: setta_modalita(mod1); DELAYs while the PC runs; PC exits; 11; 0 */
        const walk_row_t r[] = {
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, 0},
            {1, 5, 0, NONE, 0, 1, 0, C4G_MPH_START, C4G_FSM_S01, C4G_CEV_START},
            {1, 5, 0, NONE, 0, 1, 0, C4G_MPH_START, C4G_FSM_S01, 0},
            {1, 5, 0, NONE, 0, 1, 0, C4G_MPH_CRUISE, C4G_FSM_S01, C4G_CEV_CRUISE},
            {1, 5, 0, EXIT, 0, 1, 1, C4G_MPH_END, C4G_FSM_S01, C4G_CEV_EXIT_SENT | C4G_CEV_END},
            {11, 5, 0, NONE, 0, 11, 0, C4G_MPH_END, C4G_FSM_S01, MC},
            {11, 5, 0, NONE, 0, 11, 0, C4G_MPH_END, C4G_FSM_S01, 0},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00,
             C4G_CEV_EXIT_DONE | C4G_CEV_MODE0},
        };
        walk("mode 1", ROWS(r), 3000000u);
    }
    {   /* Mode 2/2': setta_modalita(mod2), DELAYs, MOVE, setta_modalita(mod12), DELAYs */
        const walk_row_t r[] = {
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, 0},
            {2, 5, 0, NONE, 0, 2, 0, C4G_MPH_START, C4G_FSM_S01, C4G_CEV_START},
            {2, 5, 0, NONE, 0, 2, 0, C4G_MPH_CRUISE, C4G_FSM_S01, C4G_CEV_CRUISE},
            {2, 5, 1, NONE, 0, 2, 0, C4G_MPH_CRUISE, C4G_FSM_S11, 0},
            {12, 5, 0, NONE, 0, 12, 0, C4G_MPH_END, C4G_FSM_S01, C4G_CEV_END},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_MODE0},
        };
        walk("mode 2", ROWS(r), 0);
    }
    {   /* Mode 4: MOVE (approach), DELAY, setta_modalita(mod4), WAIT FOR segnale_go */
        const walk_row_t r[] = {
            {0, 5, 1, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S10, 0},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, 0},
            {4, 5, 0, NONE, 0, 4, 0, C4G_MPH_START, C4G_FSM_S01, C4G_CEV_START},
            {4, 5, 0, NONE, 0, 4, 0, C4G_MPH_CRUISE, C4G_FSM_S01, C4G_CEV_CRUISE},
            {4, 5, 0, EXIT, 0, 4, 1, C4G_MPH_END, C4G_FSM_S01, C4G_CEV_END},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_EXIT_DONE},
        };
        walk("mode 4", ROWS(r), 0);
    }
    {   /* Mode 5: C4GOPEN_CMD[1] := ind_stato, setta_modalita(mod5), WAIT */
        const walk_row_t r[] = {
            {5, 5, 0, NONE, 0, 5, 0, C4G_MPH_START, C4G_FSM_S01, C4G_CEV_START},
            {5, 5, 0, NONE, 0, 5, 0, C4G_MPH_CRUISE, C4G_FSM_S01, C4G_CEV_CRUISE},
            {5, 5, 0, EXIT, 0, 5, 1, C4G_MPH_END, C4G_FSM_S01, C4G_CEV_END},
            {5, 5, 0, NONE, 0, 5, 1, C4G_MPH_END, C4G_FSM_S01, 0}, /* sent until acted on */
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_EXIT_DONE},
        };
        walk("mode 5", ROWS(r), 0);
    }
    {   /* Mode 7: setta_modalita(mod7), MOVE (long): PC exits first -> 17 -> 170 -> 0 */
        const walk_row_t r[] = {
            {7, 5, 1, NONE, 0, 7, 0, C4G_MPH_START, C4G_FSM_S11, C4G_CEV_START},
            {7, 5, 1, NONE, 0, 7, 0, C4G_MPH_CRUISE, C4G_FSM_S11, C4G_CEV_CRUISE},
            {7, 5, 1, EXIT, 0, 7, 1, C4G_MPH_END, C4G_FSM_S11, C4G_CEV_END},
            {17, 5, 1, NONE, 0, 17, 0, C4G_MPH_END, C4G_FSM_S11, MC},
            {170, 5, 0, NONE, 0, 170, 0, C4G_MPH_END, C4G_FSM_S01, MC},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_EXIT_DONE},
        };
        walk("mode 7 long", ROWS(r), 0);
    }
    {   /* Mode 7, MOVE (short): SMP+ done first -> 170 -> 0 */
        const walk_row_t r[] = {
            {7, 5, 1, NONE, 0, 7, 0, C4G_MPH_START, C4G_FSM_S11, C4G_CEV_START},
            {7, 5, 0, NONE, 0, 7, 0, C4G_MPH_CRUISE, C4G_FSM_S01, C4G_CEV_CRUISE},
            {7, 5, 0, EXIT, 0, 7, 1, C4G_MPH_END, C4G_FSM_S01, C4G_CEV_END},
            {170, 5, 0, NONE, 0, 170, 0, C4G_MPH_END, C4G_FSM_S01, MC},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_EXIT_DONE},
        };
        walk("mode 7 short", ROWS(r), 0);
    }
    {   /* Modes 8 and 9: setta_modalita, MOVE (GENERIC), WAIT */
        const walk_row_t r8[] = {
            {8, 5, 1, NONE, 0, 8, 0, C4G_MPH_START, C4G_FSM_S11, C4G_CEV_START},
            {8, 5, 1, EXIT, 0, 8, 1, C4G_MPH_END, C4G_FSM_S11, C4G_CEV_END},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_EXIT_DONE},
        };
        const walk_row_t r9[] = {
            {9, 5, 1, NONE, 0, 9, 0, C4G_MPH_START, C4G_FSM_S11, C4G_CEV_START},
            {9, 5, 1, NONE, 0, 9, 0, C4G_MPH_CRUISE, C4G_FSM_S11, C4G_CEV_CRUISE},
            {9, 5, 0, EXIT, 0, 9, 1, C4G_MPH_END, C4G_FSM_S01, C4G_CEV_END},
            {0, 5, 0, NONE, 0, 0, 0, C4G_MPH_NONE, C4G_FSM_S00, C4G_CEV_EXIT_DONE},
        };
        walk("mode 8", ROWS(r8), 0);
        walk("mode 9", ROWS(r9), 0);
    }
}

static void test_more_paths(void **state)
{
    c4g_engine_t ctl;
    c4g_init_t in = fig();
    c4g_engine_config_t c;
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    c4g_axis_limits_t l;
    (void)state;
    assert_int_equal(c4g_engine_config_default(&c), C4G_OK);
    c.moving_eps = 0.0f / 0.0f;
    assert_int_equal(c4g_engine_init(&ctl, &in, &c), C4G_ERR_ARG);
    /* a drive off before anything was sent: 505 goes out holding the reported reference
     * (zero would mean "go to 0" in mode 4) */
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(c4g_engine_request_drive_off(&ctl, 0), C4G_OK);
    mk_rx(&rx, 1, 6, 4, 5);
    rx.ax[0].target_pos = 2.5f;
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(tx.ax[0].mode, 505);
    assert_true(tx.ax[0].target_pos == 2.5f);
    /* finish with a packet of another size than the context's */
    rx.n_axes = 5;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_STATE);
    /* a mode the C4G does not have (1xx): nothing required, nothing sent, 505 */
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    mk_rx(&rx, 2, 6, C4G_MODE_101, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_false(c4g_is_unset(tx.ax[0].measure));
    fill(&rx, &tx);
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_OK);
    assert_true(tx.ax[0].measure == 0.0f);
    assert_int_equal(tx.ax[0].mode, 505);
    assert_true(rep.axis_flags[0] & C4G_SF_NO_RULE);
    /* two bad axes: NONFINITE reported once */
    mk_rx(&rx, 3, 6, 4, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    fill(&rx, &tx);
    tx.ax[1].ext[0] = 1.0f / 0.0f;
    tx.ax[2].ext[0] = 1.0f / 0.0f;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_NONFINITE);
    /* exit asked again while leaving through the stand-by: accepted, nothing new */
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    mk_rx(&rx, 4, 6, 1, 5);
    assert_int_equal(tick(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);
    mk_rx(&rx, 5, 6, 1, 5);
    assert_int_equal(tick(&ctl, &rx, 1, &tx, &rep), C4G_OK);
    mk_rx(&rx, 6, 6, 11, 5);
    assert_int_equal(tick(&ctl, &rx, 2, &tx, &rep), C4G_OK);
    assert_int_equal(ctl.arm[0].leaving, 1);
    assert_int_equal(c4g_engine_request_exit(&ctl, 0), C4G_OK);
    assert_int_equal(ctl.arm[0].exit_req, 0);
    /* joint limits on ARM 1 with a second arm open, and a bad axis on the joint arm */
    in = fig2();
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    memset(&l, 0, sizeof l);
    l.joint_min = -1.0f;
    l.joint_max = 1.0f;
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_OK);
    mk_rx(&rx, 7, 8, 4, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    fill(&rx, &tx);
    tx.ax[2].vel_add = 0.0f / 0.0f;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_NONFINITE);
    assert_int_equal(tx.ax[0].mode, 505);
    assert_int_equal(tx.ax[6].mode, 4);
    /* a mode written by the caller on an arm with a joint check: restored, reported */
    assert_int_equal(c4g_engine_init(&ctl, &in, NULL), C4G_OK);
    assert_int_equal(c4g_engine_set_limits(&ctl, 0, 0, &l), C4G_OK);
    mk_rx(&rx, 8, 8, 0, 5);
    assert_int_equal(c4g_engine_step(&ctl, &rx, 0, &tx, &rep), C4G_OK);
    tx.ax[1].mode = C4G_MODE_4;
    assert_int_equal(c4g_safety_filter(&ctl, &rx, &tx, &rep), C4G_ERR_MODE_RESTORED);
    assert_int_equal(tx.ax[1].mode, 0);
    assert_true(rep.axis_flags[1] & C4G_SF_MODE_RESTORED);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_strerror_and_unset),
        cmocka_unit_test(test_init),
        cmocka_unit_test(test_step_finish_args),
        cmocka_unit_test(test_neutral_and_copy_back),
        cmocka_unit_test(test_required_fields),
        cmocka_unit_test(test_nonfinite_holds),
        cmocka_unit_test(test_mixed_arm),
        cmocka_unit_test(test_mode_restored),
        cmocka_unit_test(test_request_mode_refused),
        cmocka_unit_test(test_two_arm_exits),
        cmocka_unit_test(test_exit_and_freeze),
        cmocka_unit_test(test_drive_off_follow_error_requests),
        cmocka_unit_test(test_fig24_4_pdl_sequences),
        cmocka_unit_test(test_more_paths),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
