/* SPDX-License-Identifier: MIT */
/* The identified mode-9 feedforward model: the INI parameter file c4g-ident writes
 * (docs/c4g-server.md, "Mode-9 parameter files"), its FNV-1a checksum and the model
 * itself. Per logical axis, motor side, in A:
 *   i = Ja a + Fv v + (Fc + (Fs - Fc) exp(-(v/vs)^2)) tanh(v/eps) + off + ga cos q + gb sin q
 * v [motor turns/s], a [motor turns/s^2], q the axis's link angle [rad].
 * Plain C99. c4g_ffmodel.c (checksum, evaluation) has no dependency but libm and allocates
 * nothing; c4g_ffmodel_load.c (the parser) reads through inih and c4g_textfile. C++
 * callers (c4g-ident) include this header as is. */
#ifndef C4GH_FFMODEL_H
#define C4GH_FFMODEL_H

#include <stddef.h>
#include <stdint.h>

#include "c4gh_kinfile.h"
#include "c4gopen_engine.h"

#ifdef __cplusplus
extern "C" {
#endif

#define C4GH_FFM_FNV_BASIS 0xcbf29ce484222325ULL /* FNV-1a 64-bit offset basis */
#define C4GH_FFM_FNV_PRIME 0x100000001b3ULL
#define C4GH_FFM_FORMAT "c4g-ident 1"            /* [model] format this reader takes */
#define C4GH_FFM_MODEL "motor-current-1"         /* [model] model: the formula above */
#define C4GH_FFM_MODEL_RIGID "rigid-body-1"      /* [model] model: the rigid-body model below */
#define C4GH_FFM_ARMS 4U
#define C4GH_FFM_AXES 10U                        /* logical axes per arm */
#define C4GH_FFM_MAX_BYTES (1U << 20)            /* file size cap */
#define C4GH_FFM_VALUE_MAX 1e6                   /* |every number| */

/* One logical axis ([axis N]). Units: ja A/(turn/s^2), fv A/(turn/s), fc fs off ga gb A,
 * vs eps turn/s, delay ticks (informational), v_max turn/s, a_max turn/s^2 (the range
 * the fit holds in; 0 = no range). */
typedef struct c4gh_ffm_axis {
    int set;                /* 1: the file has [axis N] */
    int line;               /* the line of that header */
    double ja, fv, fc, fs, vs, off, ga, gb, eps, delay, v_max, a_max;
    /* model = ctrl: i = k1 (EXT1 - in) + k2 in + friction + off, in = ks EXT2 2 pi a the
     * inertial part of EXT1 (no Ja, no gravity): a correction of the controller's own model,
     * k1 of its gravity and Coriolis part, k2 of its inertia (both 1 when it is right). ks
     * [A/(N m)] turns EXT2's torque into current (the controller's 1/Kt as c4g-ident found
     * it in EXT1). */
    int ctrl;               /* 1: model = ctrl; 0: model = axis (the formula above) */
    double k1, k2, ks;
    char variant[24];       /* coulomb, coulomb+gravity, stribeck, stribeck+gravity; "" */
} c4gh_ffm_axis_t;

/* A parameter file: one arm. model = rigid-body-1 (rigid = 1) adds the arm's kinematics
 * ([kinematics] and the DH keys of [joint N], read by c4gh_kin_on_key) and per joint the
 * link's ten parameters about its frame origin (c4gopen_dyn.h order: m, mx, my, mz, Ixx,
 * Ixy, Ixz, Iyy, Iyz, Izz), the rotor inertia ia and the fitted range; [axis N] then holds
 * motor N's friction and offset only (Fv, Fc, Fs, vs, off, eps; no Ja, ga, gb, k1, k2, ks),
 * for every motor 1..n of the chain and no other:
 *   i_k = (Kr^-T (rnea(q, qd, qdd; pi) + ia qdd))_k / kt_k + friction_k(vm_k) + off_k. */
typedef struct c4gh_ffm_file {
    int rigid;              /* 1: model = rigid-body-1 */
    unsigned arm;           /* 1..4 */
    double period_ms;       /* the controller period the model was identified at */
    uint64_t checksum;      /* as verified */
    int model_line;         /* line of [model] */
    char source[200];       /* informational keys, as written */
    char created_by[200];
    c4gh_ffm_axis_t ax[C4GH_FFM_AXES];
    /* model = rigid-body-1 only (zero otherwise) */
    int consistent;         /* [model] consistent: 1 physically consistent fit, 0 not, -1 not said */
    unsigned base_params;   /* [model] base_params (informational), 0 = not said */
    c4gh_kinfile_t kin;     /* the chain (kin.n joints) and each motor's kt */
    double pi[C4G_DYN_MAX_LINKS * C4G_DYN_PARAMS]; /* link j's row at j * C4G_DYN_PARAMS */
    double ia[C4G_DYN_MAX_LINKS];                  /* [kg m^2] */
    double q_min[C4G_DYN_MAX_LINKS], q_max[C4G_DYN_MAX_LINKS]; /* fitted range [rad] */
    double qd_max[C4G_DYN_MAX_LINKS];              /* [rad/s] */
    double qdd_max[C4G_DYN_MAX_LINKS];             /* [rad/s^2] */
    unsigned joint_line[C4G_DYN_MAX_LINKS];        /* line of [joint N] */
} c4gh_ffm_file_t;

/* FNV-1a 64-bit of @p len bytes continuing the running hash @p h (start: C4GH_FFM_FNV_BASIS).
 * c4gh_ffm_fnv1a64("", 0, C4GH_FFM_FNV_BASIS) = C4GH_FFM_FNV_BASIS, ("a") = 0xaf63dc4c8601ec8c. */
uint64_t c4gh_ffm_fnv1a64(const void *data, size_t len, uint64_t h);

/* The byte span of the checksum line: the first line whose first non-blank text is
 * "checksum" followed by optional blanks and '=' or ':', from the line's first byte
 * through its LF (or the end of the text). 0 with [*start, *end), or -1: no such line. */
int c4gh_ffm_checksum_span(const char *text, size_t len, size_t *start, size_t *end);

/* FNV-1a 64 over every byte of @p text except its checksum line. 0, or -1 when the text
 * has no checksum line (*sum is then the hash of the whole text). A writer hashes the
 * file with a placeholder checksum line of the final length, then fills it in. */
int c4gh_ffm_checksum_text(const char *text, size_t len, uint64_t *sum);

/* "fnv1a64:" + 16 lowercase hex digits of @p sum into @p out (at least 25 bytes). */
void c4gh_ffm_checksum_format(uint64_t sum, char out[25]);

/* The model's current [A] at velocity @p v [turn/s], acceleration @p a [turn/s^2] and
 * link angle @p q [rad]; the gravity terms only when @p have_q. vs <= 0: no Stribeck
 * term; eps <= 0: sign(v) instead of tanh(v/eps). No range clamp (the caller's). */
double c4gh_ffm_current(const c4gh_ffm_axis_t *p, double v, double a, double q, int have_q);

/* model = ctrl: k1 (EXT1 - in) + k2 in + friction + off, in = ks EXT2 2 pi a [A], from the
 * controller's packet of the tick: @p ext1 [A],
 * @p ext2 [kg m^2], and @p v, @p a as above. No range clamp (the caller's). */
double c4gh_ffm_current_ctrl(const c4gh_ffm_axis_t *p, double v, double a, double ext1, double ext2);

/* Parse a parameter file held in memory (@p name for messages). 0, or -1 with
 * "NAME:LINE:COL: [section] key: why" in @p err (the whole file checked, the checksum
 * last). */
int c4gh_ffm_parse_text(const char *name, const char *text, size_t len, c4gh_ffm_file_t *out, char *err,
                   size_t errlen);

/* Read and parse the file at @p path (at most C4GH_FFM_MAX_BYTES). Same result as above. */
int c4gh_ffm_load(const char *path, c4gh_ffm_file_t *out, char *err, size_t errlen);

/* ---- model = rigid-body-1's evaluation (c4gh_ffrigid.c): no allocation, no I/O, loops
 * bounded by the chain's joints. */

/* What the rigid model needs besides its file: the arm's transmission, from the
 * controller's kinematics (c4g_kin_from_init). Built once per init packet. */
typedef struct c4gh_ffr {
    const c4gh_ffm_file_t *m;   /* the file (the caller keeps it) */
    c4g_kin_t kin;              /* the arm's kinematics as given */
    uint32_t n;                 /* joints = motors 1..n */
    double kr[C4G_DYN_MAX_LINKS][C4G_DYN_MAX_LINKS];   /* motor rad per joint rad, [motor][joint] */
    double kinv[C4G_DYN_MAX_LINKS][C4G_DYN_MAX_LINKS]; /* joint rad per motor rad, [joint][motor] */
    c4g_dyn_model_t dyn;        /* the file's chain and parameters, checked once */
} c4gh_ffr_t;

/* What was clamped on a joint (c4gh_ffr_out_t.clamped). */
#define C4GH_FFR_Q 1U   /* the angle, to [q_min, q_max] */
#define C4GH_FFR_QD 2U  /* the velocity, to +-qd_max */
#define C4GH_FFR_QDD 4U /* the acceleration, to +-qdd_max */

typedef struct c4gh_ffr_out {
    double cur[C4G_DYN_MAX_LINKS];     /* motor k's current [A] */
    double tau[C4G_DYN_MAX_LINKS];     /* joint torques (rigid body + ia qdd) [N m], clamped state */
    unsigned clamped[C4G_DYN_MAX_LINKS]; /* C4GH_FFR_* per joint */
    double q[C4G_DYN_MAX_LINKS], qd[C4G_DYN_MAX_LINKS], qdd[C4G_DYN_MAX_LINKS]; /* before the clamp */
} c4gh_ffr_out_t;

/* Prepare @p r for the rigid file @p m (m->rigid) on the arm of kinematics @p kin: Kr and
 * its inverse for motors 1..n through the library's velocity conversions, and the file's
 * link parameters checked once (c4g_dyn_model_init: not again on every tick). 0, or -1
 * (not a rigid file, a period <= 0, a transmission that is singular or not finite,
 * parameters not finite). */
int c4gh_ffr_setup(c4gh_ffr_t *r, const c4gh_ffm_file_t *m, const c4g_kin_t *kin);

/* The currents of motors 1..n for motor positions @p qm [turns, with the calibration
 * offset, as D1], velocities @p vm [turns/s] and accelerations @p am [turns/s^2] (n each):
 * link state q = c4g_kin_motor_to_link(qm), qd = Kr^-1 2 pi vm, qdd = Kr^-1 2 pi am, each
 * clamped to the fitted range, tau = rnea(q, qd, qdd; pi) + ia qdd, and
 *   cur_k = (Kr^-T tau)_k / kt_k + Fv vm_k + level(vm_k) tanh(vm_k / eps) + off_k
 * with vm the motor velocities of the clamped qd. 0, or -1 (an input or the result not
 * finite, the angles not convertible): @p o's currents are then 0. */
int c4gh_ffr_current(const c4gh_ffr_t *r, const double *qm, const double *vm, const double *am,
                     c4gh_ffr_out_t *o);

#ifdef __cplusplus
}
#endif

#endif /* C4GH_FFMODEL_H */
