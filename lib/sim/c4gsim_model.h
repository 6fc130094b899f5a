/* SPDX-License-Identifier: MIT */
/* c4g-sim robot model: one motor-side axis with its DSA position/velocity loop. Pure like
 * the core library: no heap, no I/O; every function returns a status (C4G_ERR_NULL for a NULL
 * pointer, C4G_ERR_NONFINITE for a NaN or infinite input, C4G_ERR_RANGE for a value outside
 * its documented range, the state untouched) or is a computation on its arguments alone. */
#ifndef C4GSIM_MODEL_H
#define C4GSIM_MODEL_H

#include <stdbool.h>
#include <stdint.h>

#include "c4gopen.h"

/** Deterministic PRNG (xorshift64*), Gaussian by Box-Muller. */
typedef struct c4gsim_rng {
    uint64_t s;
    bool have_spare;
    double spare;
} c4gsim_rng_t;

C4G_NODISCARD c4g_status_t c4gsim_rng_seed(c4gsim_rng_t *r, uint64_t seed);
/** The next 64 random bits into @p out. */
C4G_NODISCARD c4g_status_t c4gsim_rng_next(c4gsim_rng_t *r, uint64_t *out);
/** Uniform in [0, 1) into @p out. */
C4G_NODISCARD c4g_status_t c4gsim_rng_uniform(c4gsim_rng_t *r, double *out);
/** N(0, 1) into @p out. */
C4G_NODISCARD c4g_status_t c4gsim_rng_gauss(c4gsim_rng_t *r, double *out);

/** Axis parameters (motor side). Positions in motor turns, velocities in turns/s. */
typedef struct c4gsim_axis_params {
    double j;            /* inertia seen by the motor [kg m^2] */
    double kt;           /* torque constant [Nm/A] */
    double fv;           /* viscous friction [Nm/(rad/s)] */
    double fc;           /* Coulomb friction [Nm] */
    double fs;           /* Stribeck static friction [Nm] (used when vs > 0) */
    double vs;           /* Stribeck velocity [turns/s], 0 = no Stribeck term */
    double load;         /* constant load torque [Nm] (a current offset load/kt) */
    double cur_noise;    /* sigma of the noise on the reported current D5 [A] */
    double torque_noise; /* sigma of a white disturbance torque, per DSA step [Nm] */
    double gravity;      /* gravity torque amplitude at the motor [Nm] (axes 2 and 3) */
    double kp;           /* DSA position gain [1/s] */
    double kv;           /* DSA velocity gain [A/(turn/s)] */
    double ki;           /* DSA velocity integral gain [A/turn] */
    double az_lim;       /* current saturation [A] */
    double tx_rate;      /* motor turns per joint turn (sign = direction) */
    double cal;          /* calibration constant [turns] (init packet) */
    double ax_info;      /* kinematic influence coefficient (init packet) */
    double follow_error; /* following-error threshold [turns], 0 = off */
    double counts;       /* encoder counts per motor turn */
    double noise;        /* position measurement noise, sigma [turns] */
    double vel_filter;   /* velocity measurement low-pass, 0 < a <= 1 (1 = none) */
    double vmax;         /* trajectory velocity limit [turns/s] */
    double amax;         /* trajectory acceleration limit [turns/s^2] */
    double pos0;         /* start position [turns] */
    int startup_mode;    /* start-up mode (init packet OpenMask) */
} c4gsim_axis_params_t;

/** Parameters the model can run with: every value finite (C4G_ERR_NONFINITE), j > 0, kt > 0,
 * vs, cur_noise, torque_noise, az_lim, counts, noise >= 0 and 0 <= vel_filter <= 1
 * (C4G_ERR_RANGE). Every function taking parameters checks them. */
C4G_NODISCARD c4g_status_t c4gsim_axis_params_check(const c4gsim_axis_params_t *p);

/** What the SMP+ hands the DSA for one period. */
typedef struct c4gsim_dsa_in {
    double pos_ref;      /* position reference [turns] */
    double vel_ff;       /* velocity feed-forward [turns/s] */
    double vel_add;      /* mode 8: velocity addition [turns/s] */
    double cur_add;      /* mode 9: current addition [A] */
    double cur_pc;       /* modes 1, 2: PC current [A] */
    double pc_share;     /* control switching share 0 (DSA) .. 1 (PC) */
} c4gsim_dsa_in_t;

/** What the controller keeps per axis to build its position reference from the PC's fields. */
typedef struct c4gsim_ref {
    double pos_k;        /* mode 5: global reference integrator [turns] */
    double offset;       /* modes 7 and 8: accumulated PC offset [turns] */
    double pos_ref;      /* the reference of the last tick [turns] */
} c4gsim_ref_t;

/**
 * One tick of the controller's reference for an axis in @p mode (manual chapter 14): mode 4
 * follows D1 (absolute); mode 5 integrates pos_k += vel_i T + override D2 (fig. 14.1; D1 is
 * ignored); mode 7 adds D1 to its offset; mode 8 integrates the velocity addition D4 into the
 * offset; modes 1 and 2 take the PC's current; mode 9 adds D5. @p pc is the PC's data for this
 * tick, or NULL when no reply of this mode arrived: the reference then holds (no PC
 * contribution), never a stale value of another mode. Positions in turns, @p vel_i in turns/s,
 * @p T the period [s] (finite, > 0). Fills @p in (pos_ref, vel_ff, vel_add, cur_add, cur_pc).
 */
C4G_NODISCARD c4g_status_t c4gsim_ref_step(c4gsim_ref_t *r, int mode, const c4g_pc_axis_t *pc,
                                           double pos_i, double vel_i, double override, double T,
                                           c4gsim_dsa_in_t *in);

/** Axis state. */
typedef struct c4gsim_axis {
    double pos;          /* true position [turns] */
    double vel;          /* true velocity [turns/s] */
    double integ;        /* velocity loop integrator [A] */
    double cur;          /* current command after saturation [A] */
    double cur_report;   /* the current the controller reports (D5) [A] */
    double cur_sum;      /* sum of the DSA steps' currents since the last report */
    unsigned cur_n;
    double meas_pos;     /* encoder position (quantized, noisy) [turns] */
    double meas_vel;     /* measured velocity [turns/s] */
    double prev_meas;
    double ff_vel;       /* velocity feedforward through the measurement's filter [turns/s] */
    double prev_ff;
    bool saturated;      /* last step hit AzLim */
    bool drive_on;
} c4gsim_axis_t;

/** Default parameters for logical axis @p logical (0-based) of figure 10.1 style arms. */
C4G_NODISCARD c4g_status_t c4gsim_axis_params_default(c4gsim_axis_params_t *p, unsigned logical);
/** The axis at rest at pos0, drive off, its encoder read once (one draw of @p rng). */
C4G_NODISCARD c4g_status_t c4gsim_axis_reset(c4gsim_axis_t *a, const c4gsim_axis_params_t *p,
                                             c4gsim_rng_t *rng);
/** Friction torque [Nm] of a motor moving at @p vel turns/s (Coulomb, Stribeck, viscous),
 * without the sign of the motion: magnitude of the Coulomb/Stribeck part. @p p must be
 * non-NULL and checked (c4gsim_axis_params_check). */
double c4gsim_axis_friction_level(const c4gsim_axis_params_t *p, double vel);
/** Gravity torque at the motor [Nm] for @p pos (@p p non-NULL and checked). */
double c4gsim_axis_gravity(const c4gsim_axis_params_t *p, double pos);
/** One DSA step of @p dt seconds (finite, > 0; loop + plant). Drive off: brakes hold the
 * axis. Every field of @p in must be finite. */
C4G_NODISCARD c4g_status_t c4gsim_axis_step(c4gsim_axis_t *a, const c4gsim_axis_params_t *p,
                                            const c4gsim_dsa_in_t *in, double dt, c4gsim_rng_t *rng);

/** The DSA's loops alone for one step of @p dt seconds (finite, > 0): the current command
 * a->cur (saturated at AzLim; drive off: brakes, no current) from the axis's last encoder
 * reading and @p in, without moving the axis. A plant other than the decoupled one
 * (c4g-sim's arm) turns that current into motion and then calls c4gsim_axis_measure;
 * c4gsim_axis_step is this, the decoupled integration, then the encoder. Every field of @p in
 * must be finite. */
C4G_NODISCARD c4g_status_t c4gsim_dsa_current(c4gsim_axis_t *a, const c4gsim_axis_params_t *p,
                                              const c4gsim_dsa_in_t *in, double dt);
/** The encoder read at the end of a step of @p dt seconds (finite, > 0): a->meas_pos
 * (quantised, noisy: one draw of @p rng when noise > 0) and the filtered a->meas_vel, from
 * the true position a->pos (finite) that a plant has set. */
C4G_NODISCARD c4g_status_t c4gsim_axis_measure(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, double dt,
                                               c4gsim_rng_t *rng);

/** The DSA's reference at fraction @p w (0..1) of an SMP+ period of @p period seconds, from
 * (@p p0, @p v0) at its start to (@p p1, @p v1) at its end: one cubic (Hermite) through both
 * ends, so the velocity feedforward is the derivative of the position reference and a
 * trajectory of constant acceleration is reproduced exactly. */
C4G_NODISCARD c4g_status_t c4gsim_dsa_interp(double p0, double v0, double p1, double v1, double w,
                                             double period, double *pos, double *vel);

/** The current reported for the SMP+ period that just ended: the mean of its DSA steps'
 * currents (the mean current is what moved the axis over the period, whatever ripple the
 * reference steps cause inside it), plus the sensor noise cur_noise, into @p current (also
 * kept in cur_report). Starts a new period. */
C4G_NODISCARD c4g_status_t c4gsim_axis_report_current(c4gsim_axis_t *a, const c4gsim_axis_params_t *p,
                                                      c4gsim_rng_t *rng, double *current);

/** Trapezoidal profile (synchronised multi-axis moves share one duration). */
typedef struct c4gsim_trap {
    double p0;           /* start [turns] */
    double d;            /* signed distance [turns] */
    double t_total;      /* duration [s] */
    double t_acc;        /* accelerating (and decelerating) time [s] */
} c4gsim_trap_t;

/** Shortest duration of a move of |d| under vmax/amax with the accel fraction used (a limit
 * <= 0 does not bound it; 0 for d = 0). */
double c4gsim_trap_min_time(double d, double vmax, double amax);
/** A move from @p p0 to @p p1 in @p duration seconds (<= 0: at once). */
C4G_NODISCARD c4g_status_t c4gsim_trap_plan(c4gsim_trap_t *t, double p0, double p1, double duration);
/** Position and velocity at time @p t into the move (clamped to [0, t_total]). */
C4G_NODISCARD c4g_status_t c4gsim_trap_eval(const c4gsim_trap_t *t, double time, double *pos, double *vel);

#endif
