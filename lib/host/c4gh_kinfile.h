/* SPDX-License-Identifier: MIT */
/* An arm's kinematics as a user writes it for the rigid-body model (c4g-ident --kin,
 * docs/c4g-ident.md "The kinematics file"): DH parameters in a named convention, the
 * gravity, and each motor's torque constant. The transmission and the wrist coupling are
 * not here: they come from the capture's initialization packet (c4g_kin_from_init).
 *
 *   [arm]
 *   convention = modified      ; modified (Craig) or standard
 *   angles = deg               ; unit of alpha and theta0: deg or rad
 *   gravity = 0 0 -9.81        ; in the base frame [m/s^2]
 *   [joint 1]                  ; joints 1..n, n <= C4G_DYN_MAX_LINKS, none missing
 *   a = 0                      ; [m]
 *   alpha = 0
 *   d = 0.45                   ; [m]
 *   theta0 = 0                 ; added to the joint angle
 *   kt = 0.8                   ; motor N's torque constant [N m/A]
 *
 * Files that embed a kinematics (c4g-ident's rigid parameter file) feed their keys through
 * c4gh_kin_on_key with their own name for the [arm] section, and handle the keys it
 * leaves. C99, reads through c4gh_textfile; C++ callers include this header as is. */
#ifndef C4GH_KINFILE_H
#define C4GH_KINFILE_H

#include <stddef.h>
#include <stdint.h>

#include "c4gopen_dyn.h"

#ifdef __cplusplus
extern "C" {
#endif

#define C4GH_KIN_MAX_BYTES (1U << 16) /* file size cap */

/* One joint's keys as written (angles in the file's unit). */
typedef struct c4gh_kin_joint {
    double a, alpha, d, theta0, kt;
    unsigned line; /* the line of its first key, 0: not given */
} c4gh_kin_joint_t;

typedef struct c4gh_kinfile {
    uint32_t n;                 /* joints */
    c4g_dyn_convention_t conv;
    int deg;                    /* 1: alpha, theta0 in degrees */
    double gravity[3];
    c4gh_kin_joint_t j[C4G_DYN_MAX_LINKS];
    c4g_dyn_chain_t chain;      /* built from the above (angles in rad) */
} c4gh_kinfile_t;

/* Parser state for one file. */
typedef struct c4gh_kin_ctx {
    c4gh_kinfile_t *out;
    const char *arm_section;    /* "arm" in a kinematics file */
    unsigned arm_line[3];       /* line each [arm] key was on; 0 = not yet */
    unsigned joint_line[C4G_DYN_MAX_LINKS][5];
} c4gh_kin_ctx_t;

/* Start parsing into @p out (zeroed); @p arm_section names the section holding
 * convention, angles and gravity. */
void c4gh_kin_begin(c4gh_kin_ctx_t *x, c4gh_kinfile_t *out, const char *arm_section);

/* One key=value on line @p line. -1: neither the arm section nor a [joint N] key this
 * module knows (the caller's key; "[joint N]" sections with N out of range are refused
 * here); otherwise a c4gh_tf_ini_rc_t (0 = taken) with "[section] key: why" in @p msg. */
int c4gh_kin_on_key(c4gh_kin_ctx_t *x, const char *section, const char *name, const char *value,
                    unsigned line, char *msg, size_t msglen);

/* After the last key: every required key there, joints 1..n without a gap, the chain
 * built. 0, or -1 with "NAME: why" in @p err. */
int c4gh_kin_end(c4gh_kin_ctx_t *x, const char *name, char *err, size_t errlen);

/* A whole kinematics file in memory / on disk. 0, or -1 with "NAME:LINE:COL: ..." or
 * "NAME: ..." in @p err. */
int c4gh_kin_parse_text(const char *name, const char *text, size_t len, c4gh_kinfile_t *out, char *err,
                        size_t errlen);
int c4gh_kin_load(const char *path, c4gh_kinfile_t *out, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* C4GH_KINFILE_H */
