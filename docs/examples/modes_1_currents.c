/* SPDX-License-Identifier: MIT */
/* Mode 1 (docs/modes.md): the PC generates the trajectory and closes the loops. The
 * controller (PDL2) sets mode 1; during START the PC ramps its current in with the soft
 * control switching gain eta (chapter 12), then moves axis 1 by a small trajectory, sends
 * EXIT_FROM_OPEN, holds the robot in 1 stand-by (11) while ramping out with rho, and the
 * controller returns to mode 0. Exit status 0 only if every expectation holds. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdio.h>
#include <string.h>

#define CHECK(c) do { if (!(c)) { fprintf(stderr, "%s:%d: %s\n", __FILE__, __LINE__, #c); return 1; } } while (0)
#define PERIOD_NS 2000000u
#define SWITCH_NS 20000000u /* T1 + T2 + T3 of the SMP+ switching counter (site value) */

static float pos[6];        /* the "robot": follows the last target exactly */

static void controller_packet(c4g_ctrl_packet_t *rx, int32_t num, int32_t mode)
{
    uint32_t i;
    memset(rx, 0, sizeof *rx);
    rx->num = num;
    rx->n_axes = 6;
    rx->infpar = C4G_STS_MOVING;
    for (i = 0; i < 6; i++) {
        rx->ax[i].mode = mode;
        rx->ax[i].target_pos = pos[i];
        rx->ax[i].actual_pos = pos[i];
        rx->ax[i].current_ref = 3.0f;
    }
}

/* The PC's position loop (a stand-in for a real controller with anti-windup). */
static float pd_current(float target, float actual)
{
    return 3.0f + 40.0f * (target - actual);
}

int main(void)
{
    c4g_init_t init;
    c4g_engine_config_t cfg;
    c4g_engine_t ctl;
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    uint8_t out[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;
    int32_t num = 0;
    uint64_t t = 0;
    int k, cruise_ticks = 0, standby_ticks = 0;
    uint32_t i;
    float target = 0.0f;

    CHECK(c4gsim_fig10_1(&init) == C4G_OK);
    CHECK(c4g_engine_config_default(&cfg) == C4G_OK);
    cfg.start_ns = SWITCH_NS;
    CHECK(c4g_engine_init(&ctl, &init, &cfg) == C4G_OK);

    for (k = 0; k < 80; k++, t += PERIOD_NS) {
        const c4g_arm_sm_t *sm = &ctl.arm[0];
        int32_t mode = C4G_MODE_1;
        c4g_scs_t scs;
        if (sm->leaving && sm->mode == C4G_MODE_1_STANDBY) {
            /* the controller ends 1 stand-by after its counter ran down */
            mode = (standby_ticks++ < 10) ? C4G_MODE_1_STANDBY : C4G_MODE_0;
        } else if (sm->leaving || (sm->exit_req && sm->exit_ticks > 0)) {
            mode = C4G_MODE_1_STANDBY;
        } else if (k > 0 && sm->mode == C4G_MODE_0) {
            mode = C4G_MODE_0;
        }
        controller_packet(&rx, ++num, mode);
        CHECK(c4g_engine_step(&ctl, &rx, t, &tx, &rep) == C4G_OK);
        if (tx.ax[0].mode == C4G_MODE_1 || tx.ax[0].mode == C4G_MODE_1_STANDBY) {
            /* mode 1 needs D1, D2, D4, D5 in every packet, the first one included */
            CHECK(c4g_is_unset(tx.ax[0].current_add));
            CHECK(c4g_scs_linear(t, sm->phase_since_ns, sm->phase_since_ns + SWITCH_NS,
                                 &scs) == C4G_OK);
            if (sm->phase == C4G_MPH_CRUISE && cruise_ticks < 20) {
                target += 0.002f;       /* motor turns per tick, axis 1 */
                cruise_ticks++;
            } else if (sm->phase == C4G_MPH_CRUISE) {
                CHECK(c4g_engine_request_exit(&ctl, 0) == C4G_OK);
            }
            for (i = 0; i < 6; i++) {
                const float goal = (i == 0) ? target : pos[i];
                float cur = pd_current(goal, pos[i]);
                /* START: ramp in with eta; END (stand-by): ramp out with rho */
                CHECK(c4g_scs_reduce(sm->phase == C4G_MPH_END ? scs.rho
                                     : (sm->phase == C4G_MPH_START ? scs.eta : 1.0f),
                                     cur, &cur) == C4G_OK);
                tx.ax[i].target_pos = goal;
                tx.ax[i].target_vel = (i == 0 && sm->phase == C4G_MPH_CRUISE) ? 0.002f : 0.0f;
                tx.ax[i].vel_add = 0.0f;
                tx.ax[i].current_add = cur;
            }
        }
        CHECK(c4g_safety_filter(&ctl, &rx, &tx, &rep) == C4G_OK);
        CHECK(rep.n_filtered == 0);                      /* no safety action needed */
        CHECK(c4g_pc_encode(&tx, out, sizeof out, &len) == C4G_OK);
        for (i = 0; i < 6; i++) {
            pos[i] = (tx.ax[i].mode == C4G_MODE_0) ? pos[i] : tx.ax[i].target_pos;
        }
        if ((rep.events & C4G_CEV_EXIT_DONE) != 0) {
            break;
        }
    }
    CHECK(ctl.arm[0].mode == C4G_MODE_0 && ctl.arm[0].phase == C4G_MPH_NONE);
    CHECK(cruise_ticks == 20 && standby_ticks > 0);
    CHECK(pos[0] > 0.039f && pos[0] < 0.041f);
    printf("mode 1: moved axis 1 by %.3f turns, exit through 1 stand-by in %d ticks\n",
           (double)pos[0], standby_ticks);
    return 0;
}
