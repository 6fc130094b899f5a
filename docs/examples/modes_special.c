/* SPDX-License-Identifier: MIT */
/* Special modes (docs/modes.md): DRIVING ON (501) and its end, requests refused with a
 * clear status, active freezing (500) from mode 0 left with EXIT_FROM_OPEN, a following
 * error found by the safety filter (508 on the offending axis), a NaN never sent (505 on
 * every axis of the arm), and the drive-off latch that ends when the drives are off.
 * Exit status 0 only if every expectation holds. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include <stdio.h>
#include <string.h>

#define CHECK(c) do { if (!(c)) { fprintf(stderr, "%s:%d: %s\n", __FILE__, __LINE__, #c); return 1; } } while (0)

static c4g_engine_t ctl;
static c4g_ctrl_packet_t rx;
static c4g_pc_packet_t tx;
static c4g_engine_report_t rep;
static int32_t num;

static int tick(int32_t mode, uint8_t drives, float actual0, float d1_0)
{
    uint8_t out[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;
    uint32_t i;
    int st;
    memset(&rx, 0, sizeof rx);
    rx.num = ++num;
    rx.n_axes = 6;
    rx.infpar = drives;
    for (i = 0; i < 6; i++) {
        rx.ax[i].mode = mode;
        rx.ax[i].target_pos = 1.0f;
        rx.ax[i].actual_pos = (i == 0) ? actual0 : 1.0f;
    }
    if (c4g_engine_step(&ctl, &rx, (uint64_t)num * 2000000u, &tx, &rep) != C4G_OK) {
        return -1;
    }
    for (i = 0; i < 6; i++) {       /* mode 4 data; ignored where not required */
        tx.ax[i].target_pos = (i == 0) ? d1_0 : 1.0f;
        tx.ax[i].target_vel = 0.0f;
    }
    st = c4g_safety_filter(&ctl, &rx, &tx, &rep);
    if (c4g_pc_encode(&tx, out, sizeof out, &len) != C4G_OK) {
        st = -1;                    /* never happens: nothing unsendable leaves finish */
    }
    return st;
}

int main(void)
{
    c4g_init_t init;
    CHECK(c4gsim_fig10_1(&init) == C4G_OK);
    CHECK(c4g_engine_init(&ctl, &init, NULL) == C4G_OK);

    /* DRIVE ON: the controller forces 501; requests are refused meanwhile */
    CHECK(tick(C4G_MODE_DRIVING_ON, 0, 1.0f, 1.0f) == C4G_OK);
    CHECK(tick(C4G_MODE_DRIVING_ON, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK(c4g_engine_request_freeze(&ctl, 0) == C4G_ERR_DRIVING_ON);
    CHECK(tick(C4G_MODE_0, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK((rep.events & C4G_CEV_DRIVING_ON_END) != 0);  /* first tick SMax left 501 */
    printf("driving on over; refused example: %s\n", c4g_strerror(C4G_ERR_DRIVING_ON));

    /* other refusals */
    CHECK(c4g_engine_request_mode(&ctl, 0, C4G_MODE_4) == C4G_ERR_PDL_ONLY); /* 24.2 */
    CHECK(c4g_engine_request_exit(&ctl, 0) == C4G_ERR_NOT_IN_OPEN);

    /* active freezing: only from mode 0; every axis carries 500 until the exit */
    CHECK(c4g_engine_request_freeze(&ctl, 0) == C4G_OK);
    CHECK(tick(C4G_MODE_0, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK(tx.ax[0].mode == C4G_MODE_FREEZING_A && tx.ax[5].mode == C4G_MODE_FREEZING_A);
    /* ... long non-real-time work here: the controller does not check the PC ... */
    CHECK(c4g_engine_request_exit(&ctl, 0) == C4G_OK);
    CHECK(tick(C4G_MODE_0, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK(c4g_arm_byte(tx.infpar, 0) == C4G_EXIT_FROM_OPEN);
    CHECK(tick(C4G_MODE_0, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK((rep.events & C4G_CEV_FREEZE_A_END) != 0 && tx.ax[0].mode == C4G_MODE_0);

    /* following error in mode 4: |D1 - D3| = 8 turns > FollowError 7.5 of axis 1 */
    CHECK(tick(C4G_MODE_4, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK(tick(C4G_MODE_4, C4G_STS_MOVING, -7.0f, 1.0f) == C4G_OK);
    CHECK(tx.ax[0].mode == C4G_MODE_FOLLOW_ERROR && tx.ax[1].mode == C4G_MODE_4);
    CHECK(rep.follow_err[0] == 8.0f);
    /* the controller drives off after 508: the latch clears */
    CHECK(tick(C4G_MODE_0, 0, 1.0f, 1.0f) == C4G_OK);
    CHECK((rep.events & C4G_CEV_LATCH_CLEARED) != 0 && tx.ax[0].mode == C4G_MODE_0);

    /* a NaN is never sent: the axis holds what the controller applied, the arm carries 505 */
    CHECK(tick(C4G_MODE_4, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK(tick(C4G_MODE_4, C4G_STS_MOVING, 1.0f, 0.0f / 0.0f) == C4G_ERR_NONFINITE);
    CHECK(tx.ax[0].target_pos == 1.0f && tx.ax[3].mode == C4G_MODE_DRIVE_OFF);
    CHECK(tick(C4G_MODE_4, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK(tx.ax[0].mode == C4G_MODE_DRIVE_OFF);         /* latched while drives are on */
    CHECK(tick(C4G_MODE_0, 0, 1.0f, 1.0f) == C4G_OK && tx.ax[0].mode == C4G_MODE_0);

    /* an explicit drive-off request is never refused */
    CHECK(c4g_engine_request_drive_off(&ctl, 0) == C4G_OK);
    CHECK(tick(C4G_MODE_0, C4G_STS_MOVING, 1.0f, 1.0f) == C4G_OK);
    CHECK(tx.ax[2].mode == C4G_MODE_DRIVE_OFF);
    printf("special modes: ok\n");
    return 0;
}
