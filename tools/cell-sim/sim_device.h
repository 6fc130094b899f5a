/* SPDX-License-Identifier: MIT */
/* cell-sim device model: state machine and velocity-limited motion of the robot,
 * the orientation platform and the conditioning controller (docs/cell-sim.md). */
#ifndef SIM_DEVICE_H
#define SIM_DEVICE_H

#include <stdint.h>
#include "c4gopen.h"

#define SIM_MAX_SEGS 3
#define SIM_GRIPPERS 2 /* id 0 vacuum, id 1 blow */

typedef struct sim_device {
    int kind;                   /* CELL_DEV_* */
    int n_axes;                 /* 4 robot, 2 platform, 0 conditioning */
    double pos[4];              /* mm / rad */
    double home[4];
    double lo[4], hi[4];        /* workspace limits */
    double vmax[4];             /* per axis at 100 % override, after --speed-factor */
    int moving;
    int servo;
    int32_t ovr;
    int32_t error;              /* latched device error (STA), cleared by RST */
    int servo_fault;            /* 0 none, 1 or 2: SRVON fails with +00002 / +00003 */
    int nseg, seg_i;
    double seg[SIM_MAX_SEGS][4];
    uint64_t last_ns;
    int cameras;                /* conditioning: camera ids 1..cameras */
    int valve[SIM_GRIPPERS];    /* conditioning: gripper valves */
    uint64_t acquisitions;
} sim_device_t;

/* Defaults for a device kind (limits, speeds, home). */
void sim_device_init(sim_device_t *d, int kind, double speed_factor);
/* Advance the motion model to now_ns. */
void sim_device_update(sim_device_t *d, uint64_t now_ns);
/* Execute one decoded instruction: fills the reply; *close_after for CLO. Returns a
 * short note for the log (what happened), never NULL. */
const char *sim_device_exec(sim_device_t *d, const c4g_cell_instr_t *in, uint64_t now_ns,
                            c4g_cell_reply_t *rep, int *close_after);
/* Axis names of a device kind: "x","y","z","c" / "a","b". */
const char *sim_axis_name(int kind, int axis);

#endif /* SIM_DEVICE_H */
