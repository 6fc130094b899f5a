/* SPDX-License-Identifier: MIT */
/* The kinematics file (c4gh_kinfile.h): every key known and given once, every number
 * finite and in range, joints 1..n without a gap, and the chain built by the library,
 * whose own checks are reported against the joint that failed them. */
#include "c4gh_kinfile.h"

#include "c4gh_textfile.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define KIN_PI 3.141592653589793

enum { KA_CONVENTION, KA_ANGLES, KA_GRAVITY, KA_N };
static const char *const kin_arm_keys[KA_N] = {"convention", "angles", "gravity"};

enum { KJ_A, KJ_ALPHA, KJ_D, KJ_THETA0, KJ_KT, KJ_N };
static const char *const kin_joint_keys[KJ_N] = {"a", "alpha", "d", "theta0", "kt"};

static int kin_bad(char *msg, size_t msglen, int rc, const char *section, const char *name, const char *why)
{
    char n[80];
    c4gh_tf_escape(name, strlen(name), n, sizeof n);
    snprintf(msg, msglen, "[%s] %s: %s", section, n, why);
    return rc;
}

static int kin_once(unsigned *seen, unsigned line, char *msg, size_t msglen, const char *section, const char *name)
{
    char why[80];
    if (*seen != 0U) {
        snprintf(why, sizeof why, "set twice (first on line %u)", *seen);
        return kin_bad(msg, msglen, C4GH_TF_INI_BAD_KEY, section, name, why);
    }
    *seen = line;
    return C4GH_TF_INI_OK;
}

static int kin_number(const char *section, const char *name, const char *value, double lo, double hi, double *out,
                      char *msg, size_t msglen)
{
    char why[200];
    const c4gh_tf_num_t st = c4gh_tf_parse_double(value, lo, hi, out);
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, value, lo, hi, why, sizeof why);
        return kin_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name, why);
    }
    return C4GH_TF_INI_OK;
}

static int kin_word(const char *section, const char *name, const char *value, const char *a, const char *b,
                    int *which, char *msg, size_t msglen)
{
    char v[80];
    char why[200];
    if (strcmp(value, a) == 0 || strcmp(value, b) == 0) {
        *which = (strcmp(value, b) == 0) ? 1 : 0;
        return C4GH_TF_INI_OK;
    }
    c4gh_tf_escape(value, strlen(value), v, sizeof v);
    snprintf(why, sizeof why, "'%s' is not %s or %s", v, a, b);
    return kin_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name, why);
}

/* "x y z": three numbers, each within +-100 m/s^2 */
static int kin_gravity(const char *section, const char *name, const char *value, double g[3], char *msg,
                       size_t msglen)
{
    char buf[128];
    char *save = NULL;
    char *tok;
    int k = 0;
    const size_t n = strlen(value);
    if (n >= sizeof buf) {
        return kin_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name, "too long (want three numbers)");
    }
    memcpy(buf, value, n + 1U);
    for (tok = strtok_r(buf, " \t", &save); tok != NULL; tok = strtok_r(NULL, " \t", &save)) {
        if (k == 3) {
            return kin_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name,
                           "more than three numbers (want x y z in the base frame)");
        }
        if (kin_number(section, name, tok, -100.0, 100.0, &g[k], msg, msglen) != C4GH_TF_INI_OK) {
            return C4GH_TF_INI_BAD_VALUE;
        }
        k++;
    }
    if (k != 3) {
        return kin_bad(msg, msglen, C4GH_TF_INI_BAD_VALUE, section, name,
                       "fewer than three numbers (want x y z in the base frame)");
    }
    return C4GH_TF_INI_OK;
}

void c4gh_kin_begin(c4gh_kin_ctx_t *x, c4gh_kinfile_t *out, const char *arm_section)
{
    memset(x, 0, sizeof *x);
    memset(out, 0, sizeof *out);
    x->out = out;
    x->arm_section = arm_section;
}

/* "joint N": N - 1 when 1..C4G_DYN_MAX_LINKS, -2 for another N, -1 when not a joint section */
static int kin_section_joint(const char *s)
{
    long long v = 0;
    if (strncmp(s, "joint ", 6U) != 0) {
        return -1;
    }
    if (c4gh_tf_parse_int(s + 6, 1, (long long)C4G_DYN_MAX_LINKS, &v) != C4GH_TF_NUM_OK) {
        return -2;
    }
    return (int)v - 1;
}

static int kin_arm_key(c4gh_kin_ctx_t *x, const char *section, const char *name, const char *value, unsigned line,
                       char *msg, size_t msglen)
{
    c4gh_kinfile_t *o = x->out;
    int k;
    for (k = 0; k < KA_N; k++) {
        if (strcmp(name, kin_arm_keys[k]) == 0) {
            int rc = kin_once(&x->arm_line[k], line, msg, msglen, section, name);
            int which = 0;
            if (rc != C4GH_TF_INI_OK) {
                return rc;
            }
            if (k == KA_CONVENTION) {
                rc = kin_word(section, name, value, "standard", "modified", &which, msg, msglen);
                o->conv = (which != 0) ? C4G_DYN_DH_MODIFIED : C4G_DYN_DH_STANDARD;
            } else if (k == KA_ANGLES) {
                rc = kin_word(section, name, value, "rad", "deg", &which, msg, msglen);
                o->deg = which;
            } else {
                rc = kin_gravity(section, name, value, o->gravity, msg, msglen);
            }
            return rc;
        }
    }
    return -1;
}

int c4gh_kin_on_key(c4gh_kin_ctx_t *x, const char *section, const char *name, const char *value, unsigned line,
                    char *msg, size_t msglen)
{
    const int j = kin_section_joint(section);
    int k;
    if (strcmp(section, x->arm_section) == 0) {
        return kin_arm_key(x, section, name, value, line, msg, msglen);
    }
    if (j == -2) {
        char s[80];
        char why[120];
        c4gh_tf_escape(section, strlen(section), s, sizeof s);
        snprintf(why, sizeof why, "joint number out of 1..%u", C4G_DYN_MAX_LINKS);
        snprintf(msg, msglen, "[%s]: %s", s, why);
        return C4GH_TF_INI_BAD_SECTION;
    }
    if (j < 0) {
        return -1;
    }
    for (k = 0; k < KJ_N; k++) {
        if (strcmp(name, kin_joint_keys[k]) == 0) {
            c4gh_kin_joint_t *p = &x->out->j[j];
            double *dst[KJ_N];
            /* lengths within the library's limit; angles within one turn either way; kt > 0 */
            const double lo[KJ_N] = {-C4G_DYN_LENGTH_MAX, -360.0, -C4G_DYN_LENGTH_MAX, -360.0, 1e-6};
            const double hi[KJ_N] = {C4G_DYN_LENGTH_MAX, 360.0, C4G_DYN_LENGTH_MAX, 360.0, 1e4};
            int rc = kin_once(&x->joint_line[j][k], line, msg, msglen, section, name);
            if (rc != C4GH_TF_INI_OK) {
                return rc;
            }
            dst[KJ_A] = &p->a;
            dst[KJ_ALPHA] = &p->alpha;
            dst[KJ_D] = &p->d;
            dst[KJ_THETA0] = &p->theta0;
            dst[KJ_KT] = &p->kt;
            if (p->line == 0U) {
                p->line = line;
            }
            return kin_number(section, name, value, lo[k], hi[k], dst[k], msg, msglen);
        }
    }
    return -1;
}

int c4gh_kin_end(c4gh_kin_ctx_t *x, const char *name, char *err, size_t errlen)
{
    c4gh_kinfile_t *o = x->out;
    double a[C4G_DYN_MAX_LINKS];
    double al[C4G_DYN_MAX_LINKS];
    double d[C4G_DYN_MAX_LINKS];
    double th[C4G_DYN_MAX_LINKS];
    const double unit = (o->deg != 0) ? (KIN_PI / 180.0) : 1.0;
    uint32_t n = 0U;
    uint32_t i;
    int k;
    c4g_status_t st;
    for (k = 0; k < KA_N; k++) {
        if (x->arm_line[k] == 0U) {
            snprintf(err, errlen, "%s: [%s] %s: missing (convention, angles and gravity are required)", name,
                     x->arm_section, kin_arm_keys[k]);
            return -1;
        }
    }
    while (n < C4G_DYN_MAX_LINKS && o->j[n].line != 0U) {
        n++;
    }
    if (n == 0U) {
        snprintf(err, errlen, "%s: no [joint 1] section: the file describes no joint", name);
        return -1;
    }
    for (i = n; i < C4G_DYN_MAX_LINKS; i++) {
        if (o->j[i].line != 0U) {
            snprintf(err, errlen, "%s:%u:1: [joint %u]: joint %u is missing (joints are numbered 1..n "
                     "without a gap)", name, o->j[i].line, i + 1U, n + 1U);
            return -1;
        }
    }
    for (i = 0U; i < n; i++) {
        for (k = 0; k < KJ_N; k++) {
            if (x->joint_line[i][k] == 0U) {
                snprintf(err, errlen, "%s:%u:1: [joint %u] %s: missing (a, alpha, d, theta0 and kt are "
                         "required)", name, o->j[i].line, i + 1U, kin_joint_keys[k]);
                return -1;
            }
        }
        a[i] = o->j[i].a;
        d[i] = o->j[i].d;
        al[i] = o->j[i].alpha * unit;
        th[i] = o->j[i].theta0 * unit;
    }
    if (o->deg == 0) {
        for (i = 0U; i < n; i++) {
            if (fabs(al[i]) > 2.0 * KIN_PI || fabs(th[i]) > 2.0 * KIN_PI) {
                snprintf(err, errlen, "%s:%u:1: [joint %u]: an angle over 2 pi rad (angles = rad: was "
                         "it written in degrees?)", name, o->j[i].line, i + 1U);
                return -1;
            }
        }
    }
    o->n = n;
    st = c4g_dyn_chain_dh(&o->chain, n, o->conv, a, al, d, th, o->gravity);
    if (st != C4G_OK) {
        snprintf(err, errlen, "%s: the chain is refused: %s", name, c4g_strerror(st));
        return -1;
    }
    return 0;
}

typedef struct kin_file_ctx {
    c4gh_kin_ctx_t k;
    const c4gh_tf_file_t *f;
} kin_file_ctx_t;

static c4gh_tf_ini_rc_t kin_file_key(void *user, const char *section, const char *name, const char *value,
                                     char *msg, size_t msglen)
{
    kin_file_ctx_t *x = user;
    const int rc = c4gh_kin_on_key(&x->k, section, name, value, x->f->line, msg, msglen);
    char s[80];
    if (rc >= 0) {
        return (c4gh_tf_ini_rc_t)rc;
    }
    if (section[0] == '\0') {
        c4gh_tf_escape(name, strlen(name), s, sizeof s);
        snprintf(msg, msglen, "%s: a key before the first section (want [arm] first)", s);
        return C4GH_TF_INI_BAD_KEY;
    }
    if (strcmp(section, "arm") == 0 || kin_section_joint(section) >= 0) {
        return (c4gh_tf_ini_rc_t)kin_bad(msg, msglen, C4GH_TF_INI_BAD_KEY, section, name,
                                         (strcmp(section, "arm") == 0)
                                             ? "unknown key (want convention, angles, gravity)"
                                             : "unknown key (want a, alpha, d, theta0, kt)");
    }
    c4gh_tf_escape(section, strlen(section), s, sizeof s);
    snprintf(msg, msglen, "unknown section [%s] (want [arm] or [joint 1]..[joint %u])", s, C4G_DYN_MAX_LINKS);
    return C4GH_TF_INI_BAD_SECTION;
}

static int kin_parse(c4gh_tf_file_t *f, c4gh_kinfile_t *out, char *err, size_t errlen)
{
    kin_file_ctx_t x;
    c4gh_kin_begin(&x.k, out, "arm");
    x.f = f;
    if (c4gh_tf_ini_parse(f, kin_file_key, &x, err, errlen) != 0) {
        return -1;
    }
    return c4gh_kin_end(&x.k, f->path, err, errlen);
}

int c4gh_kin_parse_text(const char *name, const char *text, size_t len, c4gh_kinfile_t *out, char *err,
                        size_t errlen)
{
    c4gh_tf_file_t f;
    c4gh_tf_open_mem(&f, name, text, len);
    return kin_parse(&f, out, err, errlen);
}

int c4gh_kin_load(const char *path, c4gh_kinfile_t *out, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    memset(out, 0, sizeof *out);
    if (c4gh_tf_load(&f, path, C4GH_KIN_MAX_BYTES, err, errlen) != 0) {
        return -1;
    }
    rc = kin_parse(&f, out, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}
