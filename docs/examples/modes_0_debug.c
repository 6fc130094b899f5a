/* SPDX-License-Identifier: MIT */
/* Modes 0 and 0' (docs/modes.md): in mode 0 the reply is neutral (mode echoed, data zero);
 * in mode 0' (10, debug echo) the library copies D1..D5 back, whatever the caller wrote.
 * Exit status 0 only if every expectation holds. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdio.h>
#include <string.h>

#define CHECK(c) do { if (!(c)) { fprintf(stderr, "%s:%d: %s\n", __FILE__, __LINE__, #c); return 1; } } while (0)

/* The controller's cyclic packet: the 6 axes of ARM 1 in one mode, drives on. */
static void controller_packet(c4g_ctrl_packet_t *rx, int32_t num, int32_t mode)
{
    uint32_t i;
    memset(rx, 0, sizeof *rx);
    rx->num = num;
    rx->n_axes = 6;
    rx->infpar = C4G_STS_MOVING; /* byte 0: ARM 1 drives on */
    for (i = 0; i < 6; i++) {
        rx->ax[i].mode = mode;
        rx->ax[i].target_pos = 0.5f * (float)i;
        rx->ax[i].target_vel = 0.001f;
        rx->ax[i].actual_pos = 0.5f * (float)i;
        rx->ax[i].actual_vel = 0.001f;
        rx->ax[i].current_ref = 1.25f;
    }
}

int main(void)
{
    c4g_init_t init;
    c4g_engine_t ctl;
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    uint8_t out[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;

    CHECK(c4gsim_fig10_1(&init) == C4G_OK);      /* normally from c4g_session_rx */
    CHECK(c4g_engine_init(&ctl, &init, NULL) == C4G_OK);

    /* mode 0: nothing to fill */
    controller_packet(&rx, 100, C4G_MODE_0);
    CHECK(c4g_engine_step(&ctl, &rx, 0, &tx, &rep) == C4G_OK);
    CHECK(c4g_mode_pc_fields(C4G_MODE_0) == 0);
    CHECK(c4g_safety_filter(&ctl, &rx, &tx, &rep) == C4G_OK);
    CHECK(tx.ax[3].mode == C4G_MODE_0 && tx.ax[3].target_pos == 0.0f && tx.infpar == 0);
    CHECK(ctl.arm[0].fsm == C4G_FSM_S10);              /* SMP+ moving, CLOSED */
    CHECK(c4g_pc_encode(&tx, out, sizeof out, &len) == C4G_OK && len == C4G_CYCLIC_SIZE(6));

    /* mode 0': the copy-back is built by the library */
    controller_packet(&rx, 101, C4G_MODE_0_DEBUG);
    CHECK(c4g_engine_step(&ctl, &rx, 2000000, &tx, &rep) == C4G_OK);
    tx.ax[2].target_pos = 42.0f;                       /* ignored: mode 0' echoes */
    CHECK(c4g_safety_filter(&ctl, &rx, &tx, &rep) == C4G_OK);
    CHECK(tx.ax[2].target_pos == rx.ax[2].target_pos);
    CHECK(tx.ax[2].measure == rx.ax[2].actual_pos);
    CHECK(tx.ax[2].current_add == rx.ax[2].current_ref);
    CHECK((rep.axis_flags[2] & C4G_SF_COPY_BACK) != 0);
    CHECK(c4g_pc_encode(&tx, out, sizeof out, &len) == C4G_OK);
    printf("mode %s: %s\n", c4g_mode_name(C4G_MODE_0_DEBUG),
           c4g_mode_description(C4G_MODE_0_DEBUG));
    return 0;
}
