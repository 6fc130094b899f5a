/* SPDX-License-Identifier: MIT */
/* c4g-sim's arm plant: the mechanics of one 6-axis arm simulated by MuJoCo (an MJCF file,
 * fixtures/sim/smart-six.xml), the motor side ours: each motor's current from the DSA
 * (c4gsim_dsa_current) becomes a torque through Kt, the motors reach the joints through the
 * init packet's transmission and wrist coupling (the library's c4g_kin_*), each axis's
 * friction acts at its motor. It also holds the controller's own dynamic model (EXT1, EXT2):
 * a copy of the arm with masses and inertias off by configured fractions, no friction, and
 * the payload the controller was told of. MuJoCo allocates: this lives in the tool, never in
 * lib/sim. docs/c4g-sim.md "The arm plant". */
#ifndef SIM_PLANT_ARM_H
#define SIM_PLANT_ARM_H

#include <stddef.h>

#include "c4gopen.h"
#include "c4gsim_model.h"

#define PLANT_AXES 6
/* Coulomb and Stribeck friction are smooth: level * v / sqrt(v^2 + eps^2), eps in motor
 * turns/s. A stiff sign would need a step far below the DSA's to stay stable. */
#define PLANT_FRICTION_EPS 0.05

/** The arm plant's configuration (command line and INI [plant]). */
typedef struct plant_cfg {
    char path[256];                      /* MJCF file; "" = the decoupled plant */
    double payload;                      /* [kg] at the flange */
    double payload_com[3];               /* its centre [m], flange frame */
    int ctrl_payload_set;                /* 0: the controller knows the true payload */
    double ctrl_payload;                 /* the payload configured in the controller [kg] */
    double ctrl_payload_com[3];
    double ctrl_mass_err[PLANT_AXES];    /* controller model: link mass off by this fraction */
    double ctrl_inertia_err[PLANT_AXES]; /* and its inertia tensor */
} plant_cfg_t;

/** No file, no payload, the default model errors (docs/c4g-sim.md). */
void plant_cfg_default(plant_cfg_t *c);
/** Scale every model error by @p k (0: the controller's model is the plant's). */
void plant_cfg_scale_errors(plant_cfg_t *c, double k);

typedef struct plant_arm plant_arm_t;

/**
 * Load cfg->path and build the plant of logical axes 1..6 of arm @p arm of @p init (the
 * init packet c4g-sim sends: its TxRate, AxInfo and CalData), motors @p p (rotor inertia j,
 * kt, friction, torque noise), DSA step @p dt [s]. The model must have six hinge joints, one
 * dof each, and a body named "payload"; its custom numeric c4g_tx_rate, when present, must
 * match TxRate. Returns 0, or -1 with "FILE: why" in @p err.
 */
int plant_arm_open(plant_arm_t **out, const plant_cfg_t *cfg, const c4g_init_t *init, unsigned arm,
                   const c4gsim_axis_params_t *const p[PLANT_AXES], double dt, char *err, size_t errlen);
void plant_arm_close(plant_arm_t *pa);
/** The plant's MuJoCo model as c4g-sim integrates it (each joint's armature and the payload
 * set): for what derives the arm's exact parameters from it (tests/e2e/helpers/arm_exact.c). */
struct mjModel_;
const struct mjModel_ *plant_arm_mjmodel(const plant_arm_t *pa);

/** At rest at motor positions @p qm [turns]. 0, or -1 (not convertible). */
int plant_arm_reset(plant_arm_t *pa, const double qm[PLANT_AXES]);
/**
 * One DSA step after c4gsim_dsa_current set each motor's current ax[i]->cur: drive on, the
 * torques act and MuJoCo steps; drive off (ax[0]->drive_on false), the brakes hold. Sets
 * each ax[i]->pos and ->vel (motor turns, turns/s); the encoder is the caller's
 * (c4gsim_axis_measure). Draws @p rng for each motor with torque_noise > 0. 0, or -1 when
 * the integration failed (MuJoCo found a bad acceleration): the caller faults the drives.
 */
int plant_arm_step(plant_arm_t *pa, c4gsim_axis_t *const ax[PLANT_AXES], c4gsim_rng_t *rng);
/**
 * The controller's dynamic model at motor positions @p qm [turns], velocities @p vm
 * [turns/s] and accelerations @p am [turns/s^2]: into @p cur the current [A] each motor needs
 * (inverse dynamics of the controller's arm, rotors included, no friction, reflected to the
 * motors and divided by Kt) and into @p inertia the diagonal inertia [kg m^2] each motor sees
 * (the diagonal of Kr^-T M Kr^-1, M the controller's joint-space inertia with the rotors).
 * 0, or -1 (not convertible).
 */
int plant_arm_model(plant_arm_t *pa, const double qm[PLANT_AXES], const double vm[PLANT_AXES],
                    const double am[PLANT_AXES], double cur[PLANT_AXES], double inertia[PLANT_AXES]);

/* For tests and the bench. */
/** Joint positions [rad] and velocities [rad/s] of the plant. */
void plant_arm_joints(const plant_arm_t *pa, double q[PLANT_AXES], double qd[PLANT_AXES]);
/** Kinetic + potential energy of the plant [J] (MuJoCo's, rotors included). */
double plant_arm_energy(plant_arm_t *pa);
/** The plant's (@p controller 0) or the controller model's MuJoCo model and data. */
void plant_arm_mujoco(const plant_arm_t *pa, int controller, const void **model, void **data);
/** Kr (motor rad per joint rad) and its inverse, [motor][joint] and [joint][motor]. */
void plant_arm_gear(const plant_arm_t *pa, double kr[PLANT_AXES][PLANT_AXES],
                    double kinv[PLANT_AXES][PLANT_AXES]);

#endif
