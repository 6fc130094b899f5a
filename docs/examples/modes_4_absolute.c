/* SPDX-License-Identifier: MIT */
/* Mode 4 (docs/modes.md): the PC generates absolute position targets, SMP+ closes the
 * loops. The controller's PDL2 program sets mode 4 (the PC cannot: manual 24.2); the PC
 * plans in joint space (rad) from where the robot stood (c4g_engine_anchor) and converts to
 * motor turns with the chapter 19 kinematics; the safety filter limits the step per tick
 * and stops the arm (505) before joint 5 crosses its stroke end. Exit status 0 only if
 * every expectation holds. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdio.h>
#include <string.h>

#define CHECK(c) do { if (!(c)) { fprintf(stderr, "%s:%d: %s\n", __FILE__, __LINE__, #c); return 1; } } while (0)

static double qm_now[6]; /* motor positions of the simulated robot */

static void controller_packet(c4g_ctrl_packet_t *rx, int32_t num, int32_t mode)
{
    uint32_t i;
    memset(rx, 0, sizeof *rx);
    rx->num = num;
    rx->n_axes = 6;
    rx->infpar = C4G_STS_MOVING;
    for (i = 0; i < 6; i++) {
        rx->ax[i].mode = mode;
        rx->ax[i].target_pos = (float)qm_now[i];
        rx->ax[i].actual_pos = (float)qm_now[i];
    }
}

int main(void)
{
    c4g_init_t init;
    c4g_engine_t ctl;
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    c4g_axis_limits_t lim;
    uint8_t out[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;
    double q[6] = {0.0, 0.1, -0.1, 0.0, 0.2, 0.0}; /* joint positions [rad] */
    int32_t num = 0, mode = C4G_MODE_0;
    int k, clamped = 0, stopped = 0;
    uint32_t i;

    CHECK(c4gsim_fig10_1(&init) == C4G_OK);
    CHECK(c4g_engine_init(&ctl, &init, NULL) == C4G_OK);
    CHECK(c4g_kin_link_to_motor(&ctl.kin[0], q, 6, qm_now) == C4G_OK);

    /* user limits: at most 0.05 motor turns per tick on every axis, joint 5 within +-0.3 rad */
    memset(&lim, 0, sizeof lim);
    lim.max_step = 0.05f;
    for (i = 0; i < 6; i++) {
        CHECK(c4g_engine_set_limits(&ctl, 0, i, &lim) == C4G_OK);
    }
    lim.joint_min = -0.3f;
    lim.joint_max = 0.3f;
    CHECK(c4g_engine_set_limits(&ctl, 0, 4, &lim) == C4G_OK);

    for (k = 0; k < 200; k++) {
        controller_packet(&rx, ++num, mode);
        CHECK(c4g_engine_step(&ctl, &rx, (uint64_t)k * 2000000u, &tx, &rep) == C4G_OK);
        if (k == 1) {
            /* only the PDL2 program starts a mode */
            CHECK(c4g_engine_request_mode(&ctl, 0, C4G_MODE_4) == C4G_ERR_PDL_ONLY);
            mode = C4G_MODE_4; /* ... which it does: the next packet carries mode 4 */
        }
        if (tx.ax[0].mode == C4G_MODE_4) {
            double qm[6];
            q[4] += 0.002;                      /* joint 5 towards (and past) its limit */
            CHECK(c4g_kin_link_to_motor(&ctl.kin[0], q, 6, qm) == C4G_OK);
            for (i = 0; i < 6; i++) {
                tx.ax[i].target_pos = (float)qm[i];   /* D1: absolute target */
                tx.ax[i].target_vel = (float)(qm[i] - qm_now[i]); /* D2 */
            }
        }
        CHECK(c4g_safety_filter(&ctl, &rx, &tx, &rep) == C4G_OK);
        CHECK(c4g_pc_encode(&tx, out, sizeof out, &len) == C4G_OK);
        clamped += (rep.axis_flags[4] & C4G_SF_STROKE_JOINT) ? 1 : 0;
        /* the simulated controller: 505 takes the drives off, the robot stops */
        if (tx.ax[0].mode == C4G_MODE_DRIVE_OFF) {
            stopped = 1;
            break;
        }
        if (tx.ax[0].mode == C4G_MODE_4) {
            for (i = 0; i < 6; i++) {
                qm_now[i] = (double)tx.ax[i].target_pos;
            }
        }
        if (c4g_arm_byte(tx.infpar, 0) == C4G_EXIT_FROM_OPEN) {
            mode = C4G_MODE_0;                  /* mode 4 ends at once (24.2.5) */
        }
        if (mode == C4G_MODE_4 && ctl.arm[0].phase == C4G_MPH_CRUISE && q[4] > 0.35) {
            CHECK(c4g_engine_request_exit(&ctl, 0) == C4G_OK);
        }
        if ((rep.events & C4G_CEV_EXIT_DONE) != 0) {
            break;
        }
    }
    CHECK(stopped == 1 && clamped == 1);
    CHECK((ctl.arm[0].latch & C4G_LATCH_STROKE) != 0);
    CHECK(c4g_kin_motor_to_link(&ctl.kin[0], qm_now, 6, q) == C4G_OK);
    CHECK(q[4] <= 0.3 + 1e-5 && q[4] >= 0.29);
    printf("mode 4: joint 5 stopped at %.4f rad (soft limit 0.3): the arm got 505\n", q[4]);
    return 0;
}
