/* SPDX-License-Identifier: MIT */
/* c4g-ident's parameter file (c4g_ffmodel.h), read with inih through c4g_textfile: every
 * key known, every number finite and in range, every key once, the required ones there,
 * and the checksum right. Errors are "FILE:LINE:COL: [section] key: why". A rigid-body
 * file's kinematics keys go through c4gh_kin_on_key (c4gh_kinfile.h), the rest here. */
#include "c4gh_ffmodel.h"

#include "c4gh_textfile.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* [axis N] keys. The numbers are checked against [lo, hi]; `pos` asks for > lo too. */
enum {
    FFK_JA, FFK_FV, FFK_FC, FFK_FS, FFK_VS, FFK_OFF, FFK_GA, FFK_GB, FFK_EPS, FFK_DELAY,
    FFK_VMAX, FFK_AMAX, FFK_K1, FFK_K2, FFK_KS, FFK_VARIANT, FFK_MODEL, FFK_N
};

typedef struct ffm_key {
    const char *name;
    size_t off;             /* double in c4gh_ffm_axis_t */
    double lo, hi;
    int pos;                /* must be > lo */
    int required;           /* 1: by model = axis, 2: by model = ctrl, 3: by both */
} ffm_key_t;

#define FFM_VMAX C4GH_FFM_VALUE_MAX
static const ffm_key_t ffm_keys[FFK_VARIANT] = {
    {"Ja", offsetof(c4gh_ffm_axis_t, ja), 0.0, FFM_VMAX, 1, 1},
    {"Fv", offsetof(c4gh_ffm_axis_t, fv), 0.0, FFM_VMAX, 0, 3},
    {"Fc", offsetof(c4gh_ffm_axis_t, fc), 0.0, FFM_VMAX, 0, 3},
    {"Fs", offsetof(c4gh_ffm_axis_t, fs), 0.0, FFM_VMAX, 0, 0},
    {"vs", offsetof(c4gh_ffm_axis_t, vs), 0.0, FFM_VMAX, 0, 0},
    {"off", offsetof(c4gh_ffm_axis_t, off), -FFM_VMAX, FFM_VMAX, 0, 3},
    {"ga", offsetof(c4gh_ffm_axis_t, ga), -FFM_VMAX, FFM_VMAX, 0, 0},
    {"gb", offsetof(c4gh_ffm_axis_t, gb), -FFM_VMAX, FFM_VMAX, 0, 0},
    {"eps", offsetof(c4gh_ffm_axis_t, eps), 0.0, FFM_VMAX, 1, 3},
    {"delay", offsetof(c4gh_ffm_axis_t, delay), -FFM_VMAX, FFM_VMAX, 0, 0},
    {"v_max", offsetof(c4gh_ffm_axis_t, v_max), 0.0, FFM_VMAX, 0, 0},
    {"a_max", offsetof(c4gh_ffm_axis_t, a_max), 0.0, FFM_VMAX, 0, 0},
    {"k1", offsetof(c4gh_ffm_axis_t, k1), -FFM_VMAX, FFM_VMAX, 0, 2},
    {"k2", offsetof(c4gh_ffm_axis_t, k2), -FFM_VMAX, FFM_VMAX, 0, 2},
    {"ks", offsetof(c4gh_ffm_axis_t, ks), 0.0, FFM_VMAX, 1, 2},
};

/* Keys of one model only: Ja, ga, gb are model = axis's, k1, k2, ks model = ctrl's. */
static int ffm_key_of_ctrl_only(size_t k) { return k == FFK_K1 || k == FFK_K2 || k == FFK_KS; }
static int ffm_key_of_axis_only(size_t k) { return k == FFK_JA || k == FFK_GA || k == FFK_GB; }

static const char *const ffm_variants[] = {"coulomb", "coulomb+gravity", "stribeck",
                                           "stribeck+gravity", "ctrl+coulomb", "ctrl+stribeck"};

/* [model] keys; the last three are model = rigid-body-1's. */
enum { FFM_FORMAT_K, FFM_MODEL_K, FFM_ARM_K, FFM_PERIOD_K, FFM_SOURCE_K, FFM_CREATED_K,
       FFM_CHECKSUM_K, FFM_RANGE_K, FFM_CONSISTENT_K, FFM_BASE_K, FFM_MN };
static const char *const ffm_model_keys[FFM_MN] = {"format", "model", "arm", "period_ms",
                                                   "source", "created_by", "checksum", "range",
                                                   "consistent", "base_params"};
static const int ffm_model_required[FFM_MN] = {1, 1, 1, 1, 0, 0, 1, 0, 0, 0};

/* [joint N] keys of a rigid-body file besides the kinematics ones: the link's parameters
 * (c4gopen_dyn.h order), the rotor inertia, the fitted range. */
enum { FFJ_IA = C4G_DYN_PARAMS, FFJ_QMIN, FFJ_QMAX, FFJ_QDMAX, FFJ_QDDMAX, FFJ_N };
static const char *const ffm_joint_keys[FFJ_N] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz",
                                                  "Iyy", "Iyz", "Izz", "ia", "q_min", "q_max",
                                                  "qd_max", "qdd_max"};

typedef struct ffm_ctx {
    const c4gh_tf_file_t *f;
    c4gh_ffm_file_t *out;
    unsigned model_line[FFM_MN];            /* line each [model] key was on; 0 = not yet */
    unsigned axis_line[C4GH_FFM_AXES][FFK_N];    /* the same per axis */
    unsigned joint_line[C4G_DYN_MAX_LINKS][FFJ_N]; /* the same per joint (own keys) */
    unsigned kin_line;                      /* line of [kinematics] */
    c4gh_kin_ctx_t kx;                      /* the kinematics keys */
    uint64_t sum;                           /* the checksum the file states */
} ffm_ctx_t;

#define FFM_SECTIONS "(want [model], [kinematics], [joint 1]..[joint 7] or [axis 1]..[axis 10])"

/* "[section] key: " + why into msg; returns the tf_ini code. */
static c4gh_tf_ini_rc_t ffm_bad(char *msg, size_t msglen, c4gh_tf_ini_rc_t rc, const char *section,
                           const char *name, const char *why)
{
    char n[80];
    c4gh_tf_escape(name, strlen(name), n, sizeof n);
    snprintf(msg, msglen, "[%s] %s: %s", section, n, why);
    return rc;
}

static c4gh_tf_ini_rc_t ffm_bad_text(char *msg, size_t msglen, const char *section, const char *name,
                                const char *value, const char *want)
{
    char v[80];
    char why[200];
    c4gh_tf_escape(value, strlen(value), v, sizeof v);
    snprintf(why, sizeof why, "'%s' is not %s", v, want);
    return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name, why);
}

/* A key seen a second time in its section (inih would let the last one win). */
static c4gh_tf_ini_rc_t ffm_once(const ffm_ctx_t *x, unsigned *line, char *msg, size_t msglen,
                            const char *section, const char *name)
{
    char why[80];
    if (*line != 0U) {
        snprintf(why, sizeof why, "set twice (first on line %u)", *line);
        return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_KEY, section, name, why);
    }
    *line = x->f->line;
    return C4GH_TF_INI_OK;
}

static c4gh_tf_ini_rc_t ffm_number(const char *section, const char *name, const char *value, double lo,
                              double hi, int pos, double *out, char *msg, size_t msglen)
{
    char why[200];
    const c4gh_tf_num_t st = c4gh_tf_parse_double(value, lo, hi, out);
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, value, lo, hi, why, sizeof why);
        return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name, why);
    }
    if (pos && !(*out > lo)) {
        char v[80];
        c4gh_tf_escape(value, strlen(value), v, sizeof v);
        snprintf(why, sizeof why, "'%s' must be > %g", v, lo);
        return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name, why);
    }
    return C4GH_TF_INI_OK;
}

/* "fnv1a64:" + exactly 16 lowercase hex digits. */
static int ffm_parse_sum(const char *s, uint64_t *out)
{
    uint64_t v = 0U;
    size_t i;
    if (strncmp(s, "fnv1a64:", 8U) != 0 || strlen(s) != 24U) {
        return -1;
    }
    for (i = 8U; i < 24U; i++) {
        const char c = s[i];
        unsigned d;
        if (c >= '0' && c <= '9') {
            d = (unsigned)(c - '0');
        } else if (c >= 'a' && c <= 'f') {
            d = (unsigned)(c - 'a') + 10U;
        } else {
            return -1;
        }
        v = (v << 4) | (uint64_t)d;
    }
    *out = v;
    return 0;
}

static c4gh_tf_ini_rc_t ffm_model_value(ffm_ctx_t *x, int k, const char *name, const char *value,
                                   char *msg, size_t msglen)
{
    c4gh_ffm_file_t *o = x->out;
    c4gh_tf_ini_rc_t rc = C4GH_TF_INI_OK;
    switch (k) {
    case FFM_FORMAT_K:
        if (strcmp(value, C4GH_FFM_FORMAT) != 0) {
            rc = ffm_bad_text(msg, msglen, "model", name, value,
                              "'" C4GH_FFM_FORMAT "' (the only format this reader knows)");
        }
        break;
    case FFM_MODEL_K:
        if (strcmp(value, C4GH_FFM_MODEL_RIGID) == 0) {
            o->rigid = 1;
        } else if (strcmp(value, C4GH_FFM_MODEL) != 0) {
            rc = ffm_bad_text(msg, msglen, "model", name, value,
                              "'" C4GH_FFM_MODEL "' or '" C4GH_FFM_MODEL_RIGID
                              "' (the models this reader evaluates)");
        }
        break;
    case FFM_RANGE_K:
        if (strcmp(value, "clamp") != 0) {
            rc = ffm_bad_text(msg, msglen, "model", name, value,
                              "'clamp' (the only range policy this reader knows)");
        }
        break;
    case FFM_CONSISTENT_K:
    case FFM_BASE_K: {
        long long v = 0;
        const long long hi = (k == FFM_BASE_K) ? (long long)(C4G_DYN_MAX_LINKS * (C4G_DYN_PARAMS + 1U)) : 1;
        const c4gh_tf_num_t st = c4gh_tf_parse_int(value, (k == FFM_BASE_K) ? 1 : 0, hi, &v);
        if (st != C4GH_TF_NUM_OK) {
            char why[200];
            c4gh_tf_num_explain(st, value, (k == FFM_BASE_K) ? 1.0 : 0.0, (double)hi, why, sizeof why);
            rc = ffm_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, "model", name, why);
        } else if (k == FFM_BASE_K) {
            o->base_params = (unsigned)v;
        } else {
            o->consistent = (int)v;
        }
        break;
    }
    case FFM_ARM_K: {
        long long v = 0;
        const c4gh_tf_num_t st = c4gh_tf_parse_int(value, 1, (long long)C4GH_FFM_ARMS, &v);
        if (st != C4GH_TF_NUM_OK) {
            char why[200];
            c4gh_tf_num_explain(st, value, 1.0, (double)C4GH_FFM_ARMS, why, sizeof why);
            rc = ffm_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, "model", name, why);
        }
        o->arm = (unsigned)v;
        break;
    }
    case FFM_PERIOD_K:
        rc = ffm_number("model", name, value, 0.0, 1000.0, 1, &o->period_ms, msg, msglen);
        break;
    case FFM_SOURCE_K:
    case FFM_CREATED_K: {
        char *dst = (k == FFM_SOURCE_K) ? o->source : o->created_by;
        const size_t n = strlen(value);
        memcpy(dst, value, (n < sizeof o->source) ? n : sizeof o->source - 1U);
        break;
    }
    case FFM_CHECKSUM_K:
    default:
        if (ffm_parse_sum(value, &x->sum) != 0) {
            rc = ffm_bad_text(msg, msglen, "model", name, value,
                              "'fnv1a64:' and 16 lowercase hex digits");
        }
        break;
    }
    return rc;
}

static c4gh_tf_ini_rc_t ffm_model_key(ffm_ctx_t *x, const char *name, const char *value, char *msg,
                                 size_t msglen)
{
    int k;
    for (k = 0; k < FFM_MN; k++) {
        if (strcmp(name, ffm_model_keys[k]) == 0) {
            const c4gh_tf_ini_rc_t rc = ffm_once(x, &x->model_line[k], msg, msglen, "model", name);
            return (rc != C4GH_TF_INI_OK) ? rc : ffm_model_value(x, k, name, value, msg, msglen);
        }
    }
    return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_KEY, "model", name,
                   "unknown key (want format, model, arm, period_ms, source, created_by, "
                   "checksum, range, consistent, base_params)");
}

static c4gh_tf_ini_rc_t ffm_axis_key(ffm_ctx_t *x, const char *section, unsigned ax, const char *name,
                                const char *value, char *msg, size_t msglen)
{
    c4gh_ffm_axis_t *p = &x->out->ax[ax];
    size_t k;
    c4gh_tf_ini_rc_t rc;
    if (strcmp(name, "model") == 0) {
        rc = ffm_once(x, &x->axis_line[ax][FFK_MODEL], msg, msglen, section, name);
        if (rc != C4GH_TF_INI_OK) {
            return rc;
        }
        if (strcmp(value, "axis") == 0 || strcmp(value, "ctrl") == 0) {
            p->ctrl = (value[0] == 'c') ? 1 : 0;
            return C4GH_TF_INI_OK;
        }
        return ffm_bad_text(msg, msglen, section, name, value, "axis or ctrl");
    }
    if (strcmp(name, "variant") == 0) {
        rc = ffm_once(x, &x->axis_line[ax][FFK_VARIANT], msg, msglen, section, name);
        for (k = 0U; rc == C4GH_TF_INI_OK && k < sizeof ffm_variants / sizeof ffm_variants[0]; k++) {
            if (strcmp(value, ffm_variants[k]) == 0) {
                strcpy(p->variant, ffm_variants[k]);
                return C4GH_TF_INI_OK;
            }
        }
        return (rc != C4GH_TF_INI_OK) ? rc
                                 : ffm_bad_text(msg, msglen, section, name, value,
                                                "coulomb, coulomb+gravity, stribeck, "
                                                "stribeck+gravity, ctrl+coulomb or "
                                                "ctrl+stribeck");
    }
    for (k = 0U; k < (size_t)FFK_VARIANT; k++) {
        const ffm_key_t *d = &ffm_keys[k];
        if (strcmp(name, d->name) == 0) {
            rc = ffm_once(x, &x->axis_line[ax][k], msg, msglen, section, name);
            return (rc != C4GH_TF_INI_OK)
                       ? rc
                       : ffm_number(section, name, value, d->lo, d->hi, d->pos,
                                    (double *)(void *)((char *)p + d->off), msg, msglen);
        }
    }
    return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_KEY, section, name,
                   "unknown key (want model, variant, Ja, Fv, Fc, Fs, vs, off, ga, gb, eps, "
                   "delay, v_max, a_max, k1, k2, ks)");
}

/* "axis N", N = 1..10: the 0-based axis, or -1. */
static int ffm_section_axis(const char *s)
{
    long long v = 0;
    if (strncmp(s, "axis ", 5U) != 0 ||
        c4gh_tf_parse_int(s + 5, 1, (long long)C4GH_FFM_AXES, &v) != C4GH_TF_NUM_OK) {
        return -1;
    }
    return (int)v - 1;
}

/* "joint N", N = 1..C4G_DYN_MAX_LINKS: the 0-based joint, or -1. */
static int ffm_section_joint(const char *s)
{
    long long v = 0;
    if (strncmp(s, "joint ", 6U) != 0 ||
        c4gh_tf_parse_int(s + 6, 1, (long long)C4G_DYN_MAX_LINKS, &v) != C4GH_TF_NUM_OK) {
        return -1;
    }
    return (int)v - 1;
}

/* A rigid-body file's [joint N] key that the kinematics left: the link's parameters, ia
 * and the range. The signs of the parameters are free (a base-parameter solution). */
static c4gh_tf_ini_rc_t ffm_joint_key(ffm_ctx_t *x, const char *section, unsigned j, const char *name,
                                      const char *value, char *msg, size_t msglen)
{
    c4gh_ffm_file_t *o = x->out;
    size_t k;
    for (k = 0U; k < (size_t)FFJ_N; k++) {
        if (strcmp(name, ffm_joint_keys[k]) == 0) {
            const int pos = (k == (size_t)FFJ_QDMAX || k == (size_t)FFJ_QDDMAX) ? 1 : 0;
            double *dst;
            const c4gh_tf_ini_rc_t rc = ffm_once(x, &x->joint_line[j][k], msg, msglen, section, name);
            if (rc != C4GH_TF_INI_OK) {
                return rc;
            }
            switch (k) {
            case FFJ_IA: dst = &o->ia[j]; break;
            case FFJ_QMIN: dst = &o->q_min[j]; break;
            case FFJ_QMAX: dst = &o->q_max[j]; break;
            case FFJ_QDMAX: dst = &o->qd_max[j]; break;
            case FFJ_QDDMAX: dst = &o->qdd_max[j]; break;
            default: dst = &o->pi[(j * C4G_DYN_PARAMS) + k]; break;
            }
            return ffm_number(section, name, value, pos ? 0.0 : -FFM_VMAX, FFM_VMAX, pos, dst, msg, msglen);
        }
    }
    return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_KEY, section, name,
                   "unknown key (want a, alpha, d, theta0, kt, m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, "
                   "Iyz, Izz, ia, q_min, q_max, qd_max, qdd_max)");
}

static c4gh_tf_ini_rc_t ffm_on_key(void *user, const char *section, const char *name,
                              const char *value, char *msg, size_t msglen)
{
    ffm_ctx_t *x = user;
    int ax;
    char s[80];
    if (strcmp(section, "model") == 0) {
        return ffm_model_key(x, name, value, msg, msglen);
    }
    ax = ffm_section_axis(section);
    if (ax >= 0) {
        return ffm_axis_key(x, section, (unsigned)ax, name, value, msg, msglen);
    }
    ax = ffm_section_joint(section);
    if (ax >= 0 || strcmp(section, "kinematics") == 0) {
        const int rc = c4gh_kin_on_key(&x->kx, section, name, value, x->f->line, msg, msglen);
        if (rc >= 0) {
            return (c4gh_tf_ini_rc_t)rc;
        }
        if (ax >= 0) {
            return ffm_joint_key(x, section, (unsigned)ax, name, value, msg, msglen);
        }
        return ffm_bad(msg, msglen, C4GH_TF_INI_BAD_KEY, section, name,
                       "unknown key (want convention, angles, gravity)");
    }
    if (section[0] == '\0') {
        c4gh_tf_escape(name, strlen(name), s, sizeof s);
        snprintf(msg, msglen, "%s: a key before the first section (want [model] first)", s);
        return C4GH_TF_INI_BAD_KEY;
    }
    c4gh_tf_escape(section, strlen(section), s, sizeof s);
    snprintf(msg, msglen, "unknown section [%s] " FFM_SECTIONS, s);
    return C4GH_TF_INI_BAD_SECTION;
}

/* ---- the section headers (before inih: its handler never sees a section without keys,
 * nor a section that comes back), then the required keys and the checksum */

/* A complete header line: the name as inih takes it, from '[' to the first ']'. One
 * without its ']' is left to inih's syntax error. */
static int ffm_header(const char *line, size_t n, size_t *col, char *name, size_t cap)
{
    size_t i = 0U;
    size_t e;
    while (i < n && (line[i] == ' ' || line[i] == '\t')) {
        i++;
    }
    if (i == n || line[i] != '[') {
        return 0;
    }
    *col = i + 1U;
    e = i + 1U;
    while (e < n && line[e] != ']') {
        e++;
    }
    if (e == n) {
        return 0;
    }
    n = e - (i + 1U);
    if (n >= cap) {
        n = cap - 1U;
    }
    memcpy(name, line + i + 1U, n);
    name[n] = '\0';
    return 1;
}

/* One section header at line @p ln: a known name, given once. */
static int ffm_one_header(ffm_ctx_t *x, const char *name, unsigned ln, size_t col, char *err,
                          size_t errlen)
{
    const char *path = x->f->path;
    int *line;
    unsigned *uline = NULL;
    int dummy = 0;
    const int ax = ffm_section_axis(name);
    const int jt = ffm_section_joint(name);
    if (strcmp(name, "model") == 0) {
        line = &x->out->model_line;
    } else if (ax >= 0) {
        line = &x->out->ax[ax].line;
    } else if (jt >= 0 || strcmp(name, "kinematics") == 0) {
        uline = (jt >= 0) ? &x->out->joint_line[jt] : &x->kin_line;
        dummy = (int)*uline;
        line = &dummy;
    } else {
        char s[80];
        c4gh_tf_escape(name, strlen(name), s, sizeof s);
        snprintf(err, errlen, "%s:%u:%zu: unknown section [%s] " FFM_SECTIONS, path, ln, col, s);
        return -1;
    }
    if (*line != 0) {
        snprintf(err, errlen, "%s:%u:%zu: [%s]: section given twice (first on line %d)", path, ln,
                 col, name, *line);
        return -1;
    }
    *line = (int)ln;
    if (uline != NULL) {
        *uline = ln;
    }
    if (ax >= 0) {
        x->out->ax[ax].set = 1;
    }
    return 0;
}

static int ffm_scan_sections(ffm_ctx_t *x, char *err, size_t errlen)
{
    const char *d = x->f->data;
    const size_t len = x->f->len;
    size_t b = 0U;
    unsigned ln = 1U;
    if (len >= 3U && memcmp(d, "\xef\xbb\xbf", 3U) == 0) {
        b = 3U; /* inih skips a UTF-8 byte order mark */
    }
    for (; b < len; ln++) {
        const char *nl = memchr(d + b, '\n', len - b);
        const size_t e = (nl != NULL) ? (size_t)(nl - d) : len;
        char name[64];
        size_t col = 0U;
        if (ffm_header(d + b, e - b, &col, name, sizeof name) &&
            ffm_one_header(x, name, ln, col, err, errlen) != 0) {
            return -1;
        }
        b = e + 1U;
    }
    return 0;
}

/* The keys and sections of the other model family. */
static int ffm_family(const ffm_ctx_t *x, char *err, size_t errlen)
{
    const c4gh_ffm_file_t *o = x->out;
    unsigned j;
    int k;
    if (o->rigid) {
        return 0;
    }
    for (k = FFM_RANGE_K; k < FFM_MN; k++) {
        if (x->model_line[k] != 0U) {
            snprintf(err, errlen, "%s:%u:1: [model] %s: not a key of model = " C4GH_FFM_MODEL
                     " (only of " C4GH_FFM_MODEL_RIGID ")", x->f->path, x->model_line[k],
                     ffm_model_keys[k]);
            return -1;
        }
    }
    for (j = 0U; j < C4G_DYN_MAX_LINKS; j++) {
        if (x->kin_line != 0U || o->joint_line[j] != 0U) {
            snprintf(err, errlen, "%s:%u:1: [%s%.0u]: a section of model = " C4GH_FFM_MODEL_RIGID
                     " only (this file is model = " C4GH_FFM_MODEL ")", x->f->path,
                     (x->kin_line != 0U) ? x->kin_line : o->joint_line[j],
                     (x->kin_line != 0U) ? "kinematics" : "joint ", (x->kin_line != 0U) ? 0U : j + 1U);
            return -1;
        }
    }
    return 0;
}

/* An [axis N] of a rigid-body file: motor N of the chain, friction and offset only. */
static int ffm_rigid_axis(const ffm_ctx_t *x, unsigned a, char *err, size_t errlen)
{
    const c4gh_ffm_file_t *o = x->out;
    const c4gh_ffm_axis_t *p = &o->ax[a];
    size_t j;
    if (p->set && a >= o->kin.n) {
        snprintf(err, errlen, "%s:%d:1: [axis %u]: the chain has %u joints: a rigid-body file "
                 "sets motors 1..%u only", x->f->path, p->line, a + 1U, (unsigned)o->kin.n,
                 (unsigned)o->kin.n);
        return -1;
    }
    if (!p->set && a < o->kin.n) {
        snprintf(err, errlen, "%s:%d:1: [axis %u]: missing (motor %u's friction and offset: "
                 "every joint of the chain needs its [axis N])", x->f->path, o->model_line,
                 a + 1U, a + 1U);
        return -1;
    }
    for (j = 0U; p->set && j < (size_t)FFK_VARIANT; j++) {
        const int wrong = ffm_key_of_axis_only(j) || ffm_key_of_ctrl_only(j);
        if ((ffm_keys[j].required & 1) != 0 && !wrong && x->axis_line[a][j] == 0U) {
            snprintf(err, errlen, "%s:%d:1: [axis %u] %s: missing (model = " C4GH_FFM_MODEL_RIGID
                     " needs Fv, Fc, off and eps)", x->f->path, p->line, a + 1U, ffm_keys[j].name);
            return -1;
        }
        if (wrong && x->axis_line[a][j] != 0U) {
            snprintf(err, errlen, "%s:%u:1: [axis %u] %s: not a key of model = " C4GH_FFM_MODEL_RIGID
                     " (the rigid-body part holds the inertia and the gravity)", x->f->path,
                     x->axis_line[a][j], a + 1U, ffm_keys[j].name);
            return -1;
        }
    }
    if (p->set && (x->axis_line[a][FFK_MODEL] != 0U ||
                   (p->variant[0] != '\0' && strcmp(p->variant, "coulomb") != 0 &&
                    strcmp(p->variant, "stribeck") != 0))) {
        const int m = (x->axis_line[a][FFK_MODEL] != 0U);
        snprintf(err, errlen, "%s:%u:1: [axis %u] %s: %s", x->f->path,
                 x->axis_line[a][m ? FFK_MODEL : FFK_VARIANT], a + 1U, m ? "model" : "variant",
                 m ? "not a key of model = " C4GH_FFM_MODEL_RIGID " (its axes are rigid-body)"
                   : "a rigid-body file's variant is coulomb or stribeck");
        return -1;
    }
    return 0;
}

/* model = rigid-body-1: the chain, every joint's own keys, every motor's [axis N]. */
static int ffm_rigid(ffm_ctx_t *x, char *err, size_t errlen)
{
    c4gh_ffm_file_t *o = x->out;
    unsigned j;
    size_t k;
    if (!o->rigid) {
        return 0;
    }
    if (x->kin_line == 0U) {
        snprintf(err, errlen, "%s:%d:1: [kinematics]: missing (model = " C4GH_FFM_MODEL_RIGID
                 " needs the arm's convention, angles and gravity)", x->f->path, o->model_line);
        return -1;
    }
    if (c4gh_kin_end(&x->kx, x->f->path, err, errlen) != 0) {
        return -1;
    }
    for (j = 0U; j < o->kin.n; j++) {
        for (k = 0U; k < (size_t)FFJ_N; k++) {
            if (x->joint_line[j][k] == 0U) {
                snprintf(err, errlen, "%s:%u:1: [joint %u] %s: missing (a rigid-body joint needs "
                         "m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz, ia, q_min, q_max, qd_max, "
                         "qdd_max)", x->f->path, o->joint_line[j], j + 1U, ffm_joint_keys[k]);
                return -1;
            }
        }
        if (!(o->q_min[j] < o->q_max[j])) {
            snprintf(err, errlen, "%s:%u:1: [joint %u] q_max: %.17g is not above q_min %.17g",
                     x->f->path, x->joint_line[j][FFJ_QMAX], j + 1U, o->q_max[j], o->q_min[j]);
            return -1;
        }
    }
    for (j = 0U; j < C4GH_FFM_AXES; j++) {
        if (ffm_rigid_axis(x, j, err, errlen) != 0) {
            return -1;
        }
    }
    if (x->model_line[FFM_CONSISTENT_K] == 0U) {
        o->consistent = -1;
    }
    return 0;
}

static int ffm_required(ffm_ctx_t *x, char *err, size_t errlen)
{
    const c4gh_ffm_file_t *o = x->out;
    unsigned a;
    int k;
    int any = 0;
    if (o->model_line == 0) {
        snprintf(err, errlen, "%s: no [model] section (not a c4g-ident parameter file?)",
                 x->f->path);
        return -1;
    }
    for (k = 0; k < FFM_MN; k++) {
        if (ffm_model_required[k] && x->model_line[k] == 0U) {
            snprintf(err, errlen, "%s:%d:1: [model] %s: missing%s", x->f->path, o->model_line,
                     ffm_model_keys[k],
                     (k == FFM_CHECKSUM_K) ? " (c4g-ident writes one: was the file written by hand?)"
                                           : "");
            return -1;
        }
    }
    if (ffm_family(x, err, errlen) != 0) {
        return -1;
    }
    if (o->rigid) {
        return ffm_rigid(x, err, errlen);
    }
    for (a = 0U; a < C4GH_FFM_AXES; a++) {
        const c4gh_ffm_axis_t *p = &o->ax[a];
        const int need = p->ctrl ? 2 : 1;
        size_t j;
        for (j = 0U; p->set && j < (size_t)FFK_VARIANT; j++) {
            const int wrong = p->ctrl ? ffm_key_of_axis_only(j) : ffm_key_of_ctrl_only(j);
            if ((ffm_keys[j].required & need) != 0 && x->axis_line[a][j] == 0U) {
                snprintf(err, errlen, "%s:%d:1: [axis %u] %s: missing (%s)", x->f->path, p->line,
                         a + 1U, ffm_keys[j].name,
                         p->ctrl ? "model = ctrl needs k1, k2, ks, Fv, Fc, off and eps"
                                 : "Ja, Fv, Fc, off and eps are required");
                return -1;
            }
            if (wrong && x->axis_line[a][j] != 0U) {
                snprintf(err, errlen, "%s:%u:1: [axis %u] %s: not a key of model = %s", x->f->path,
                         x->axis_line[a][j], a + 1U, ffm_keys[j].name, p->ctrl ? "ctrl" : "axis");
                return -1;
            }
        }
        if (p->set && p->variant[0] != '\0' &&
            (strncmp(p->variant, "ctrl+", 5U) == 0) != (p->ctrl != 0)) {
            snprintf(err, errlen, "%s:%u:1: [axis %u] variant: '%s' is not a variant of model = %s",
                     x->f->path, x->axis_line[a][FFK_VARIANT], a + 1U, p->variant,
                     p->ctrl ? "ctrl" : "axis");
            return -1;
        }
        any |= p->set;
    }
    if (!any) {
        snprintf(err, errlen, "%s: no [axis N] section: the file sets no axis", x->f->path);
        return -1;
    }
    return 0;
}

/* The stated checksum against the text's. */
static int ffm_verify_sum(ffm_ctx_t *x, char *err, size_t errlen)
{
    const char *d = x->f->data;
    size_t s = 0U;
    size_t e = 0U;
    size_t i;
    size_t col;
    unsigned ln = 1U;
    uint64_t sum = 0U;
    char want[25];
    char got[25];
    if (c4gh_ffm_checksum_text(d, x->f->len, &sum) != 0 ||
        c4gh_ffm_checksum_span(d, x->f->len, &s, &e) != 0) {
        snprintf(err, errlen, "%s: [model] checksum: no checksum line", x->f->path);
        return -1;
    }
    for (i = 0U; i < s; i++) {
        ln += (d[i] == '\n') ? 1U : 0U;
    }
    if (ln != x->model_line[FFM_CHECKSUM_K]) {
        /* only a hand-made file gets here: the key inih read is another line */
        snprintf(err, errlen, "%s:%u:1: [model] checksum: this line is not the checksum key "
                 "(line %u is)", x->f->path, ln, x->model_line[FFM_CHECKSUM_K]);
        return -1;
    }
    x->out->checksum = sum;
    if (sum == x->sum) {
        return 0;
    }
    /* the value's column, as tf_ini reports values: past the separator and blanks */
    col = s;
    while (col < e && d[col] != '=' && d[col] != ':') {
        col++;
    }
    col++;
    while (col < e && (d[col] == ' ' || d[col] == '\t')) {
        col++;
    }
    c4gh_ffm_checksum_format(x->sum, want);
    c4gh_ffm_checksum_format(sum, got);
    snprintf(err, errlen, "%s:%u:%zu: [model] checksum: checksum mismatch: the file was edited "
             "after c4g-ident wrote it (expected %s, computed %s)", x->f->path, ln, col - s + 1U,
             want, got);
    return -1;
}

int c4gh_ffm_parse_text(const char *name, const char *text, size_t len, c4gh_ffm_file_t *out, char *err,
                   size_t errlen)
{
    c4gh_tf_file_t f;
    ffm_ctx_t x;
    memset(out, 0, sizeof *out);
    memset(&x, 0, sizeof x);
    c4gh_tf_open_mem(&f, name, text, len);
    x.f = &f;
    x.out = out;
    c4gh_kin_begin(&x.kx, &out->kin, "kinematics");
    if (ffm_scan_sections(&x, err, errlen) != 0 ||
        c4gh_tf_ini_parse(&f, ffm_on_key, &x, err, errlen) != 0 || ffm_required(&x, err, errlen) != 0 ||
        ffm_verify_sum(&x, err, errlen) != 0) {
        return -1;
    }
    return 0;
}

int c4gh_ffm_load(const char *path, c4gh_ffm_file_t *out, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    memset(out, 0, sizeof *out);
    if (c4gh_tf_load(&f, path, C4GH_FFM_MAX_BYTES, err, errlen) != 0) {
        return -1;
    }
    rc = c4gh_ffm_parse_text(path, f.data, f.len, out, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}
