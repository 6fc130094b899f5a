/* SPDX-License-Identifier: MIT */
/* c4g-server's controllers: what produces the per-tick request of one axis from the
 * configuration and the controller's measured state (PD(+I) loop of modes 1/2, the
 * trajectory / raised-cosine / offset / velocity sources of modes 1, 4, 5, 7, 8, the
 * mode-9 current feedforward). Pure: no sockets, no clock, no stdio, no globals; every
 * state lives in the caller's ctlr_axis_t, so a capture can be re-run through the same
 * code (see docs/controllers.md). Units: positions in motor turns, velocities in delta
 * motor turns per tick, currents in A, times in s. */
#ifndef C4G_CONTROLLERS_H
#define C4G_CONTROLLERS_H

#include "c4gopen.h"
#include "c4gh_ffmodel.h"

#include <stdint.h>

#define CTLR_MAX_TRAJ_ROWS 20000U /* trajectory rows (caller's storage) */

/* Trajectory source of modes 1, 4, 5. */
enum { CTLR_SRC_NONE = 0, CTLR_SRC_SINE = 1, CTLR_SRC_FILE = 2 };

/* Kinds of mode-9 feedforward (ctlr_ff_t.kind). */
enum { CTLR_FF_LEGACY = 0, CTLR_FF_MODEL = 1, CTLR_FF_RIGID = 2 };

/* Mode-9 feedforward parameters of one axis, of one of three kinds:
 * CTLR_FF_LEGACY, the line format: I = c0 + cv v + cc sign(v) + ca dv + gs sin(gscale pos + gphase);
 * CTLR_FF_MODEL, a model c4g-ident identified (c4g_ffmodel.h), in turns/s and turns/s^2;
 * CTLR_FF_RIGID, motor `model.line`'s share of its arm's rigid-body model (c4gh_ffr_*): the
 * caller evaluates the whole arm once per tick and hands each axis its current
 * (ctlr_in_t.ff_cur). */
typedef struct ctlr_ff {
    int set;                /* 0, or the line of the parameter file that set it */
    int kind;               /* CTLR_FF_* */
    unsigned file;          /* which parameter file (the caller's index), for messages */
    double c0, cv, cc, ca, gs, gscale, gphase;
    double period_ms;       /* CTLR_FF_MODEL: the period the model was identified at */
    c4gh_ffm_axis_t model;       /* CTLR_FF_MODEL */
} ctlr_ff_t;

/* Per-arm configuration of the controllers (and the server's per-arm settings). */
typedef struct ctlr_arm_cfg {
    uint32_t axes;          /* logical axes driven (bit 0 = axis 1); default all */
    int src;                /* CTLR_SRC_* (modes 1, 4, 5) */
    double sine_amp;        /* raised-cosine amplitude [turns] */
    double sine_freq;       /* [Hz] */
    double sine_cycles;     /* cycles before exit from open */
    char traj_path[512];
    double offset_amp;      /* mode 7 offset step [turns] */
    double offset_ramp;     /* mode 7 ramp time [s] */
    double offset_hold;     /* mode 7 hold time before exit [s] */
    double vel_amp;         /* mode 8 velocity delta amplitude [delta turns/tick] */
    double vel_freq;        /* mode 8 [Hz] */
    double vel_cycles;      /* mode 8 full cycles (zero mean) */
    double duration;        /* modes 1 (with no trajectory), 2, 9: time before exit [s] */
    int ff_ext1;            /* mode 9: add the controller's dynamic-model current (EXT1) */
    double kp, kd, ki;      /* modes 1, 2: PD(+I) gains [A/turn], [A/(turn/tick)], [A/(turn s)] */
    double i_max;           /* integrator limit [A] (anti-windup); 0 = AzLim */
    double scs;             /* soft control switching ramp time [s] (mode 1/2 entry) */
    int exit_open;          /* send EXIT_FROM_OPEN when the behaviour is done */
    double max_step;        /* continuity limit on PC position refs [turns/tick]; 0 = off */
    double pos_min[C4G_AXES_PER_ARM], pos_max[C4G_AXES_PER_ARM]; /* stroke ends */
    int have_stroke;
    double fe_limit;        /* following-error limit override [turns]; 0 = init packet */
} ctlr_arm_cfg_t;

/* A trajectory: t[s] (strictly increasing) plus up to 10 offset columns (logical axes). */
typedef struct ctlr_traj {
    uint32_t rows, cols;
    double t[CTLR_MAX_TRAJ_ROWS];
    float q[CTLR_MAX_TRAJ_ROWS][C4G_AXES_PER_ARM];
} ctlr_traj_t;

/* Per-axis controller state. */
typedef struct ctlr_axis {
    int32_t mode;           /* mode seen on the previous packet, -1 none */
    uint32_t ticks;         /* packets in the current mode */
    double start;           /* reference at mode entry */
    double q_prev;          /* previous generator offset */
    double integ;           /* integrator state [A] */
    double v_prev;          /* previous target velocity (mode 9 acceleration) */
    int done;               /* behaviour finished (the caller's flag) */
    unsigned ff_flags;      /* CTLR_FFF_* of this tick (mode 9) */
} ctlr_axis_t;

/* What a mode-9 tick did (ctlr_axis_t.ff_flags), for the caller's counters. */
#define CTLR_FFF_MODEL 1U   /* the current came from an identified model */
#define CTLR_FFF_CLAMPED 2U /* v or a was outside the model's range: clamped to it */

/* What one axis's controller sees on a tick besides its state and the packet. */
typedef struct ctlr_in {
    const ctlr_arm_cfg_t *cfg;  /* the axis's arm */
    const ctlr_traj_t *traj;    /* the arm's trajectory (CTLR_SRC_FILE), may be NULL */
    const ctlr_ff_t *ff;        /* the axis's mode-9 parameters, may be NULL */
    uint32_t lax;               /* logical axis in the arm (0..9) */
    double dt;                  /* controller period [s] */
    double az_lim;              /* AzLim of the axis [A]; <= 0: none */
    int driven;                 /* the axis is in cfg->axes */
    double q_link;              /* mode 9, CTLR_FF_MODEL: the axis's link angle one tick
                                   ahead [rad] (kinematics of D1 + D2), when have_q */
    int have_q;
    double ff_cur;              /* mode 9, CTLR_FF_RIGID: the arm's rigid model's current of
                                   this axis for the tick [A], when ff_cur_ok */
    int ff_cur_ok;
    int ff_cur_clamped;         /* the arm's state was clamped to the model's range */
} ctlr_in_t;

/* Raised cosine: 0 at t = 0 with zero slope, amp at half a period. */
double ctlr_raised_cos(double amp, double f, double t);

/* Trajectory offset of logical axis lax at time t (binary search, linear interpolation);
 * *done past the last row (the last row is held), or with no rows / no such column. */
double ctlr_traj_at(const ctlr_traj_t *tr, uint32_t lax, double t, int *done);

/* Generator offset of modes 1, 4, 5 at time t from the arm's source: raised cosine
 * (done after sine_cycles), trajectory, or none (0, done after duration). */
double ctlr_gen_offset(const ctlr_arm_cfg_t *A, const ctlr_traj_t *tr, uint32_t lax, double t,
                       int *done);

/* Mode 7: smooth 0 -> offset_amp step (half cosine) over offset_ramp s; done after
 * offset_ramp + offset_hold. */
double ctlr_offset_profile(const ctlr_arm_cfg_t *A, double t, int *done);

/* Mode 8: zero-mean velocity addition vel_amp sin(2 pi f t) for vel_cycles; 0 and done
 * after. */
double ctlr_vel_add(const ctlr_arm_cfg_t *A, double t, int *done);

/* Mode 9: feedforward current for SMP+ target velocity v, acceleration acc (delta of v per
 * tick) and target position pos. Saturated to the float range (NaN stays NaN). */
float ctlr_ff_current(const ctlr_ff_t *p, double v, double acc, double pos);

/* Mode 9 with an identified model (p->kind CTLR_FF_MODEL): the current for the tick the
 * reply is applied on, one after the packet's. From the SMP+ target velocities d2 and
 * d2_prev [delta turns/tick] and the period dt [s]: a = (d2 - d2_prev) / dt^2,
 * v = d2 / dt + a dt; |v| and |a| clamped to the model's v_max / a_max (when > 0; *clamped
 * then set to 1), gravity on link angle q when have_q. Saturated to the float range. */
float ctlr_ff_model_current(const ctlr_ff_t *p, double d2, double d2_prev, double dt, double q,
                            int have_q, int *clamped);

/* The same for a model = ctrl file (p->model.ctrl): k1 (EXT1 - in) + k2 in + friction + off,
 * in = ks EXT2 2 pi a (c4gh_ffm_current_ctrl), from the controller's packet of the tick (@p ext1 [A], @p ext2 [kg m^2]) and v, a
 * as above (clamped alike). A non-finite EXT1 or EXT2 gives 0 A (nothing to correct). */
float ctlr_ff_ctrl_current(const ctlr_ff_t *p, double d2, double d2_prev, double dt, double ext1,
                           double ext2, int *clamped);

/* PD(+I) joint controller with anti-windup (clamped integrator plus back-calculation) and
 * the soft-control-switching limiter (the limit ramps 0 -> AzLim over cfg->scs s).
 * Updates X->integ; returns the current [A]. */
double ctlr_pd(ctlr_axis_t *X, const ctlr_in_t *in, double ref, double vref,
               const c4g_ctrl_axis_t *r, double t);

/* 1 for the open modes with a behaviour (1, 2, 4, 5, 7, 8, 9). */
int ctlr_is_open_mode(int32_t mode);

/* State before any packet (mode -1). */
void ctlr_axis_reset(ctlr_axis_t *X);

/* The axis reports @p mode, another than X->mode: start its regulator from @p anchor (where
 * the axis stood before the mode) and the packet's current and velocity. Stand-by modes
 * continue the regulator of their main mode (1 -> 11, 2 <-> 12). Returns 1 when the
 * regulator was restarted. */
int ctlr_axis_enter(ctlr_axis_t *X, int32_t mode, double anchor, const c4g_ctrl_axis_t *r);

/* One tick of one axis: fill the fields prepared mode @p pm requires into @p o (modes 1,
 * 11, 2, 12, 4, 5, 7, 8, 9; other modes are left as prepared) at t = X->ticks * dt, then
 * count the tick. Returns 1 when the axis's behaviour is done. */
int ctlr_step(ctlr_axis_t *X, const ctlr_in_t *in, int32_t pm, const c4g_ctrl_axis_t *r,
              c4g_pc_axis_t *o);

#endif
