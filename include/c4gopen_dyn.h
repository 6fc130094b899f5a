/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_dyn.h
 * @brief Rigid-body dynamics of a serial arm of revolute joints: inverse dynamics by a
 *        recursive Newton-Euler pass, and its regressor (the same pass, linear in the
 *        link parameters), for identification and for the mode-9 current feedforward.
 *
 * Frames. Link i (0-based, i < n) has a frame fixed to it; its joint turns it about its
 * own z axis. With T(p, R) the homogeneous transform of origin p and rotation R:
 *     base -> link 0 -> ... -> link n-1,
 *     T_{i-1,i}(q_i) = T(pos_i, rot_i) Rz(q_i + theta0_i)
 * (link -1 is the base). c4g_dyn_chain_dh builds pos/rot from DH parameters in either
 * convention:
 *   - modified (Craig): T_{i-1,i} = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i); the
 *     arrays are indexed by i, so a[i], alpha[i] are Craig's a_{i-1}, alpha_{i-1}.
 *   - standard: T_{i-1,i} = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i). Rewritten so every
 *     frame sits on its joint's axis: link i's frame is the standard frame i-1 turned by
 *     theta_i and moved by d_i; the a_i, alpha_i of the last link only place the flange,
 *     which the dynamics does not need.
 * Link parameters (the standard 10 per link, in the link's frame, about its origin):
 *     pi = { m, m cx, m cy, m cz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz }
 * with I the inertia tensor about the frame's origin (not the centre of mass):
 * I_origin = I_com + m (|c|^2 E - c c^T). Joint torques are linear in pi, which is what
 * the regressor returns. A rotor inertia (armature) ia_i adds ia_i qdd_i to joint i.
 *
 * Units: rad, rad/s, rad/s^2, m, kg, kg m^2, N m, m/s^2. Pure C99: no allocation, no I/O,
 * loops bounded by C4G_DYN_MAX_LINKS. Not recursive: the passes are loops.
 */
#ifndef C4GOPEN_DYN_H
#define C4GOPEN_DYN_H

#include <stdint.h>
#include "c4gopen_base.h"

#ifdef __cplusplus
extern "C" {
#endif

#define C4G_DYN_MAX_LINKS 7U   /**< links (joints) per chain */
#define C4G_DYN_PARAMS 10U     /**< standard parameters per link */
#define C4G_DYN_LENGTH_MAX 100.0 /**< |a|, |d|, |pos| limit [m] */

/** One joint: where its frame sits on its parent at q = 0, and the angle offset. */
typedef struct c4g_dyn_joint {
    double rot[3][3]; /**< parent -> this frame rotation (columns: this frame's axes) */
    double pos[3];    /**< this frame's origin in the parent frame [m] */
    double theta0;    /**< added to q before turning [rad] */
} c4g_dyn_joint_t;

/** A chain of n revolute joints and the gravity acting on it. */
typedef struct c4g_dyn_chain {
    uint32_t n;
    c4g_dyn_joint_t j[C4G_DYN_MAX_LINKS];
    double gravity[3]; /**< gravity acceleration in the base frame [m/s^2], e.g. {0,0,-9.81} */
} c4g_dyn_chain_t;

/** DH convention of c4g_dyn_chain_dh. */
typedef enum c4g_dyn_convention {
    C4G_DYN_DH_STANDARD = 0,
    C4G_DYN_DH_MODIFIED = 1
} c4g_dyn_convention_t;

/**
 * Build @p ch from n sets of DH parameters (arrays of @p n) and the base-frame gravity.
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_ARG (n outside 1..C4G_DYN_MAX_LINKS, unknown
 * convention); C4G_ERR_NONFINITE; C4G_ERR_RANGE (|a|, |d| over C4G_DYN_LENGTH_MAX,
 * |angle| over 2 pi, |gravity| over 100).
 */
C4G_NODISCARD c4g_status_t c4g_dyn_chain_dh(c4g_dyn_chain_t *ch, uint32_t n, c4g_dyn_convention_t conv,
                                            const double *a, const double *alpha, const double *d,
                                            const double *theta0, const double gravity[3]);

/**
 * Joint torques @p tau (n) of the chain at @p q, @p qd, @p qdd (n each) for the link
 * parameters @p pi (n x C4G_DYN_PARAMS, row per link) and rotor inertias @p ia (n, or
 * NULL for none). O(n), no allocation.
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_ARG (chain n out of range); C4G_ERR_NONFINITE
 * (an input or the result).
 */
C4G_NODISCARD c4g_status_t c4g_dyn_rnea(const c4g_dyn_chain_t *ch, const double *q, const double *qd,
                                        const double *qdd, const double *pi, const double *ia, double *tau);

/** c4g_dyn_model_t.checked once c4g_dyn_model_init accepted the model. */
#define C4G_DYN_CHECKED 0x44594e31U

/**
 * A chain with its link parameters and rotor inertias, checked once by c4g_dyn_model_init
 * for c4g_dyn_model_rnea: parameters that are constant after a file is loaded are not
 * checked again on every tick (c4g_dyn_rnea checks its 10 n + n values on each call).
 * Members are read-only: a change after c4g_dyn_model_init voids its check.
 */
typedef struct c4g_dyn_model {
    c4g_dyn_chain_t chain;
    double pi[C4G_DYN_MAX_LINKS * C4G_DYN_PARAMS]; /**< n x C4G_DYN_PARAMS, row per link */
    double ia[C4G_DYN_MAX_LINKS];                  /**< rotor inertias, 0 for none */
    uint32_t checked;                              /**< C4G_DYN_CHECKED once checked */
} c4g_dyn_model_t;

/**
 * Check @p ch, the link parameters @p pi (ch->n x C4G_DYN_PARAMS) and the rotor inertias
 * @p ia (ch->n, or NULL for none) once, and copy them into @p m.
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_ARG (chain n out of range); C4G_ERR_NONFINITE
 * (a parameter, a rotor inertia or the gravity). On an error @p m is not usable
 * (checked is 0).
 */
C4G_NODISCARD c4g_status_t c4g_dyn_model_init(c4g_dyn_model_t *m, const c4g_dyn_chain_t *ch, const double *pi,
                                              const double *ia);

/**
 * c4g_dyn_rnea on a model c4g_dyn_model_init checked: only the motion is checked. The
 * same torques.
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_STATE (@p m not checked by c4g_dyn_model_init);
 * C4G_ERR_NONFINITE (an input or the result).
 */
C4G_NODISCARD c4g_status_t c4g_dyn_model_rnea(const c4g_dyn_model_t *m, const double *q, const double *qd,
                                              const double *qdd, double *tau);

/**
 * The regressor: @p y (n rows x n*C4G_DYN_PARAMS columns, row-major, row stride
 * n*C4G_DYN_PARAMS, @p cap entries at least n*n*C4G_DYN_PARAMS) with
 * tau = y pi for every pi (rotor inertias not included: add ia_i qdd_i to row i).
 * Entries of links beyond a row's own subtree (j < i) are 0. O(n^2).
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_ARG; C4G_ERR_CAPACITY; C4G_ERR_NONFINITE.
 */
C4G_NODISCARD c4g_status_t c4g_dyn_regressor(const c4g_dyn_chain_t *ch, const double *q, const double *qd,
                                             const double *qdd, double *y, uint32_t cap);

/**
 * Link parameters about the frame origin from mass @p m, centre @p c (link frame) and the
 * inertia tensor about the centre @p icom {Ixx, Ixy, Ixz, Iyy, Iyz, Izz} (link frame).
 * Writes 10 values.
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_NONFINITE; C4G_ERR_RANGE (m < 0).
 */
C4G_NODISCARD c4g_status_t c4g_dyn_params_from_com(double m, const double c[3], const double icom[6],
                                                   double pi[10]);

#ifdef __cplusplus
}
#endif

#endif /* C4GOPEN_DYN_H */
