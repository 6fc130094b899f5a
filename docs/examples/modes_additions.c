/* SPDX-License-Identifier: MIT */
/* Modes 2, 5, 7, 8 and 9 (docs/modes.md): the controller's trajectory with PC
 * contributions. Mode 2: the PC closes the loops (D4, D5) and PDL2 ends it with 12.
 * Mode 5: relative targets (D1, D2). Mode 7: position deltas (D1), left through 17 and 170.
 * Mode 8: velocity additions (D4). Mode 9: current additions (D5), clamped so that the
 * SMP+ current plus the delta stays within AzLim. Moni type 23 rows are written as CSV.
 * Exit status 0 only if every expectation holds. */
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
#include "c4gh_csv.h"
#include <stdio.h>
#include <string.h>

#define CHECK(c) do { if (!(c)) { fprintf(stderr, "%s:%d: %s\n", __FILE__, __LINE__, #c); return 1; } } while (0)

typedef struct pc {
    c4g_engine_t ctl;
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_engine_report_t rep;
    int32_t num;
} pc_t;

/* One controller packet (every axis of ARM 1 in @p mode) up to c4g_engine_step. */
static int step(pc_t *p, int32_t mode)
{
    uint32_t i;
    memset(&p->rx, 0, sizeof p->rx);
    p->rx.num = ++p->num;
    p->rx.n_axes = 6;
    p->rx.infpar = C4G_STS_MOVING;
    for (i = 0; i < 6; i++) {
        p->rx.ax[i].mode = mode;
        p->rx.ax[i].target_pos = 2.0f;
        p->rx.ax[i].target_vel = 0.01f;  /* SMP+ is moving: OPEN TYPE B */
        p->rx.ax[i].actual_pos = 2.0f;
        p->rx.ax[i].current_ref = 20.0f;
        p->rx.ax[i].ext[0] = 1.5f;       /* EXT1: dynamic model current */
        p->rx.ax[i].ext[1] = 0.02f;      /* EXT2: diagonal inertia */
    }
    return c4g_engine_step(&p->ctl, &p->rx, (uint64_t)p->num * 2000000u, &p->tx, &p->rep);
}

static int finish(pc_t *p)
{
    uint8_t out[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0;
    int st = c4g_safety_filter(&p->ctl, &p->rx, &p->tx, &p->rep);
    if (c4g_pc_encode(&p->tx, out, sizeof out, &len) != C4G_OK) {
        st = -1;
    }
    return st;
}

int main(void)
{
    static pc_t p;
    c4g_init_t init;
    c4g_moni_rec_t rec;
    char row[C4GH_MONI_ROW_MAX];
    size_t len = 0;
    uint32_t i;

    CHECK(c4gsim_fig10_1(&init) == C4G_OK);
    CHECK(c4g_engine_init(&p.ctl, &init, NULL) == C4G_OK);

    /* mode 2: PC loops, SMP+ trajectory; EXIT_FROM_OPEN is refused, PDL2 sets 12 */
    CHECK(step(&p, C4G_MODE_2) == C4G_OK);
    CHECK(c4g_mode_pc_fields(C4G_MODE_2) == (C4G_PCF_D4 | C4G_PCF_D5));
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].vel_add = 0.0f;
        p.tx.ax[i].current_add = 30.0f;  /* above AzLim: saturated */
    }
    CHECK(finish(&p) == C4G_OK);
    CHECK(p.tx.ax[0].current_add == 24.5f && p.tx.ax[3].current_add == 9.5f);
    CHECK(c4g_engine_request_exit(&p.ctl, 0) == C4G_ERR_FORBIDDEN);
    CHECK(step(&p, C4G_MODE_2_STANDBY) == C4G_OK && p.ctl.arm[0].phase == C4G_MPH_END);
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].vel_add = 0.0f;
        p.tx.ax[i].current_add = 20.0f;
    }
    CHECK(finish(&p) == C4G_OK);
    CHECK(step(&p, C4G_MODE_0) == C4G_OK && finish(&p) == C4G_OK);

    /* mode 5: relative targets */
    CHECK(step(&p, C4G_MODE_5) == C4G_OK);
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].target_pos = 0.001f;
        p.tx.ax[i].target_vel = 0.001f;
    }
    CHECK(finish(&p) == C4G_OK);
    CHECK(c4g_moni_record(21, &p.rx, &p.tx, 0, &rec) == C4G_OK); /* moni 21: mode 5 */
    CHECK(c4g_engine_request_exit(&p.ctl, 0) == C4G_OK);
    CHECK(step(&p, C4G_MODE_5) == C4G_OK);
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].target_pos = 0.0f;
        p.tx.ax[i].target_vel = 0.0f;
    }
    CHECK(finish(&p) == C4G_OK && c4g_arm_byte(p.tx.infpar, 0) == C4G_EXIT_FROM_OPEN);
    CHECK(step(&p, C4G_MODE_0) == C4G_OK && (p.rep.events & C4G_CEV_EXIT_DONE) != 0);
    CHECK(finish(&p) == C4G_OK);

    /* mode 7: position deltas; the exit goes through 17 (SMP+ still moving) and 170 */
    CHECK(step(&p, C4G_MODE_7) == C4G_OK && p.ctl.arm[0].fsm == C4G_FSM_S11);
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].target_pos = 0.0005f;
    }
    CHECK(finish(&p) == C4G_OK);
    CHECK(c4g_engine_request_exit(&p.ctl, 0) == C4G_OK);
    CHECK(step(&p, C4G_MODE_7) == C4G_OK);
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].target_pos = 0.0f;    /* null delta from now on */
    }
    CHECK(finish(&p) == C4G_OK);
    CHECK(step(&p, C4G_MODE_7_STANDBY) == C4G_OK && finish(&p) == C4G_OK); /* no data */
    CHECK(step(&p, C4G_MODE_7_STANDBY_EXIT) == C4G_OK && finish(&p) == C4G_OK);
    CHECK(step(&p, C4G_MODE_0) == C4G_OK && (p.rep.events & C4G_CEV_EXIT_DONE) != 0);
    CHECK(finish(&p) == C4G_OK);

    /* mode 8: velocity additions */
    CHECK(step(&p, C4G_MODE_8) == C4G_OK);
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].vel_add = 0.0002f;
    }
    CHECK(finish(&p) == C4G_OK);
    CHECK(c4g_engine_request_exit(&p.ctl, 0) == C4G_OK);
    CHECK(step(&p, C4G_MODE_0) == C4G_OK && finish(&p) == C4G_OK);

    /* mode 9: current additions; SMP+ sends 20 A, AzLim of axis 1 is 24.5 A */
    CHECK(step(&p, C4G_MODE_9) == C4G_OK);
    for (i = 0; i < 6; i++) {
        p.tx.ax[i].current_add = 6.0f;
    }
    CHECK(finish(&p) == C4G_OK);
    CHECK(p.tx.ax[0].current_add == 4.5f);              /* 20 + 4.5 = AzLim */
    CHECK((p.rep.axis_flags[0] & C4G_SF_DCURRENT) != 0);
    CHECK(c4gh_moni_csv_header(23, row, sizeof row, &len) == C4G_OK);
    fputs(row, stdout);
    for (i = 0; i < 6; i++) {
        CHECK(c4g_moni_record(23, &p.rx, &p.tx, i, &rec) == C4G_OK);
        CHECK(c4gh_moni_csv_row(&rec, row, sizeof row, &len) == C4G_OK);
        fputs(row, stdout);
    }
    return 0;
}
