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

#ifdef __cplusplus
extern "C" {
#endif

#define C4GH_FFM_FNV_BASIS 0xcbf29ce484222325ULL /* FNV-1a 64-bit offset basis */
#define C4GH_FFM_FNV_PRIME 0x100000001b3ULL
#define C4GH_FFM_FORMAT "c4g-ident 1"            /* [model] format this reader takes */
#define C4GH_FFM_MODEL "motor-current-1"         /* [model] model: the formula above */
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

/* A parameter file: one arm. */
typedef struct c4gh_ffm_file {
    unsigned arm;           /* 1..4 */
    double period_ms;       /* the controller period the model was identified at */
    uint64_t checksum;      /* as verified */
    int model_line;         /* line of [model] */
    char source[200];       /* informational keys, as written */
    char created_by[200];
    c4gh_ffm_axis_t ax[C4GH_FFM_AXES];
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

#ifdef __cplusplus
}
#endif

#endif /* C4GH_FFMODEL_H */
