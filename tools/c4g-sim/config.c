/* SPDX-License-Identifier: MIT */
/* c4g-sim configuration: defaults and the INI file (read with inih). */
#include "sim.h"

#include "c4gh_textfile.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void sim_config_default(sim_config_t *c)
{
    unsigned a;
    unsigned l;
    memset(c, 0, sizeof *c);
    strcpy(c->server, "127.0.0.1");
    c->port = C4G_DEFAULT_PORT;
    strcpy(c->bind_addr, "0.0.0.0");
    c->period_ms = 2;
    c->t_cycle1_us = 500U;
    c->policy = C4G_NUM_EITHER;
    c->max_miss = 10U;
    c->seed = 1U;
    c->sync_before = 9U;
    c->sync_after = 2U;
    c->drive_on_ms = 400.0;
    c->switch_ms = 200.0;
    c->check_follow = 1;
    c->n_arms = 1;
    c->open_mask[0] = 0x3FU;
    c->version[0] = 3;
    c->version[1] = 11;
    c->version[2] = 115;
    for (a = 0; a < C4G_ARMS; a++) {
        c->option_ok[a] = 1;
        for (l = 0; l < C4G_AXES_PER_ARM; l++) {
            (void)c4gsim_axis_params_default(&c->ax[a][l], l); /* cannot fail: non-NULL */
        }
    }
    plant_cfg_default(&c->plant);
}

int sim_config_axes(const sim_config_t *c)
{
    int a;
    int n = 0;
    if (c->n_arms < 1 || c->n_arms > (int)C4G_ARMS) {
        return -1;
    }
    for (a = 0; a < c->n_arms; a++) {
        unsigned m = c->open_mask[a] & 0x3FFU;
        if (m == 0U) {
            return -1;
        }
        while (m != 0U) {
            n += (int)(m & 1U);
            m >>= 1;
        }
    }
    return (n > (int)C4G_MAX_AXES) ? -1 : n;
}

/* Value checks: each writes "[section] key: why" into msg on failure. */
typedef struct kv {
    const char *section;
    const char *name;
    const char *value;
    char *msg;
    size_t msglen;
} kv_t;

static int bad_num(const kv_t *k, c4gh_tf_num_t st, double lo, double hi)
{
    char why[200];
    c4gh_tf_num_explain(st, k->value, lo, hi, why, sizeof why);
    snprintf(k->msg, k->msglen, "[%s] %s: %s", k->section, k->name, why);
    return -1;
}

static int dbl(const kv_t *k, double lo, double hi, double *out)
{
    const c4gh_tf_num_t st = c4gh_tf_parse_double(k->value, lo, hi, out);
    return (st == C4GH_TF_NUM_OK) ? 0 : bad_num(k, st, lo, hi);
}

static int uns(const kv_t *k, long long lo, long long hi, unsigned *out)
{
    long long v = 0;
    const c4gh_tf_num_t st = c4gh_tf_parse_int(k->value, lo, hi, &v);
    if (st != C4GH_TF_NUM_OK) {
        return bad_num(k, st, (double)lo, (double)hi);
    }
    *out = (unsigned)v;
    return 0;
}

static int sint(const kv_t *k, long long lo, long long hi, int *out)
{
    long long v = 0;
    const c4gh_tf_num_t st = c4gh_tf_parse_int(k->value, lo, hi, &v);
    if (st != C4GH_TF_NUM_OK) {
        return bad_num(k, st, (double)lo, (double)hi);
    }
    *out = (int)v;
    return 0;
}

static int bad_text(const kv_t *k, const char *want)
{
    char v[80];
    c4gh_tf_escape(k->value, strlen(k->value), v, sizeof v);
    snprintf(k->msg, k->msglen, "[%s] %s: '%s' is not %s", k->section, k->name, v, want);
    return -1;
}

/* Axis parameter by name; returns 0 ok, -1 bad value, -2 unknown key. */
static int axis_key(c4gsim_axis_params_t *p, const kv_t *k)
{
    static const struct {
        const char *name;
        size_t off;
        double lo, hi;
    } keys[] = {
#define K(n, lo, hi) {#n, offsetof(c4gsim_axis_params_t, n), lo, hi}
        K(j, 1e-9, 1e3), K(kt, 1e-6, 1e3), K(fv, 0.0, 1e3), K(fc, 0.0, 1e3), K(fs, 0.0, 1e3), K(vs, 0.0, 1e4),
        K(load, -1e4, 1e4), K(cur_noise, 0.0, 1e3), K(torque_noise, 0.0, 1e3), K(gravity, -1e4, 1e4),
        K(kp, 0.0, 1e5), K(kv, 0.0, 1e5), K(ki, 0.0, 1e7), K(az_lim, 0.0, 1e4),
        K(tx_rate, -1e5, 1e5), K(cal, -1e6, 1e6), K(ax_info, -1e3, 1e3), K(follow_error, 0.0, 1e6),
        K(counts, 0.0, 1e9), K(noise, 0.0, 1.0), K(vel_filter, 1e-6, 1.0), K(vmax, 1e-6, 1e5),
        K(amax, 1e-6, 1e7), K(pos0, -1e6, 1e6)
#undef K
    };
    size_t i;
    double d;
    if (strcmp(k->name, "startup_mode") == 0) {
        int m;
        if (sint(k, 0, 1000, &m) != 0) {
            return -1;
        }
        if (!c4g_mode_is_known((int32_t)m)) {
            return bad_text(k, "a mode code");
        }
        p->startup_mode = m;
        return 0;
    }
    for (i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        if (strcmp(k->name, keys[i].name) == 0) {
            if (dbl(k, keys[i].lo, keys[i].hi, &d) != 0) {
                return -1;
            }
            *(double *)((char *)p + keys[i].off) = d;
            return 0;
        }
    }
    return -2;
}

/* "arm N" (N = 1..4) and "axis A.L" (A = 1..4, L = 1..10): 1 if s is one of them. */
static int section_arm(const char *s, unsigned *a)
{
    long long v = 0;
    if (strncmp(s, "arm ", 4) != 0 || c4gh_tf_parse_int(s + 4, 1, (long long)C4G_ARMS, &v) != C4GH_TF_NUM_OK) {
        return 0;
    }
    *a = (unsigned)v;
    return 1;
}

static int section_axis(const char *s, unsigned *a, unsigned *l)
{
    char tmp[16];
    const char *dot;
    long long va = 0;
    long long vl = 0;
    if (strncmp(s, "axis ", 5) != 0 || (dot = strchr(s + 5, '.')) == NULL ||
        (size_t)(dot - (s + 5)) >= sizeof tmp) {
        return 0;
    }
    memcpy(tmp, s + 5, (size_t)(dot - (s + 5)));
    tmp[dot - (s + 5)] = '\0';
    if (c4gh_tf_parse_int(tmp, 1, (long long)C4G_ARMS, &va) != C4GH_TF_NUM_OK ||
        c4gh_tf_parse_int(dot + 1, 1, (long long)C4G_AXES_PER_ARM, &vl) != C4GH_TF_NUM_OK) {
        return 0;
    }
    *a = (unsigned)va;
    *l = (unsigned)vl;
    return 1;
}

/* [sim] seed: 0..2^64-1 */
static int seed_key(sim_config_t *c, const kv_t *k)
{
    const char *name = k->name;
    const char *value = k->value;
    unsigned long long v = 0;
    const c4gh_tf_num_t st = c4gh_tf_parse_uint(value, ~0ULL, &v);
    if (st == C4GH_TF_NUM_RANGE) {
        /* 2^64 - 1 as text: a double bound would print rounded */
        char v80[80];
        c4gh_tf_escape(value, strlen(value), v80, sizeof v80);
        snprintf(k->msg, k->msglen, "[%s] %s: '%s' is out of range 0..18446744073709551615",
                 k->section, name, v80);
        return -1;
    }
    if (st != C4GH_TF_NUM_OK) {
        return bad_num(k, st, 0.0, 0.0);
    }
    c->seed = (uint64_t)v;
    return 0;
}

/* [sim] num_policy */
static int policy_key(sim_config_t *c, const kv_t *k)
{
    if (c4g_num_policy_parse(k->value, &c->policy) != C4G_OK) {
        return bad_text(k, "plus-one, echo or either");
    }
    return 0;
}

/* [sim] version: MAJOR.MINOR.BUILD, each 0..65535 */
static int version_key(sim_config_t *c, const kv_t *k)
{
    const char *value = k->value;
    char tmp[64];
    char *part[3];
    char *p;
    int n = 0;
    int v[3];
    if (strlen(value) >= sizeof tmp) {
        return bad_text(k, "a version MAJOR.MINOR.BUILD");
    }
    strcpy(tmp, value);
    part[n++] = tmp;
    for (p = tmp; *p != '\0'; p++) {
        if (*p == '.') {
            if (n == 3) {
                return bad_text(k, "a version MAJOR.MINOR.BUILD");
            }
            *p = '\0';
            part[n++] = p + 1;
        }
    }
    for (int i = 0; i < n; i++) {
        long long x = 0;
        if (c4gh_tf_parse_int(part[i], 0, 65535, &x) != C4GH_TF_NUM_OK) {
            return bad_text(k, "a version MAJOR.MINOR.BUILD (each 0..65535)");
        }
        v[i] = (int)x;
    }
    if (n != 3) {
        return bad_text(k, "a version MAJOR.MINOR.BUILD");
    }
    memcpy(c->version, v, sizeof v);
    return 0;
}

static int sim_key(sim_config_t *c, const kv_t *k)
{
    const char *name = k->name;
    const char *value = k->value;
    if (strcmp(name, "server") == 0 || strcmp(name, "bind") == 0) {
        char *dst = (name[0] == 's') ? c->server : c->bind_addr;
        if (strlen(value) >= sizeof c->server) {
            return bad_text(k, "an address (under 64 bytes)");
        }
        strcpy(dst, value);
        return 0;
    }
    if (strcmp(name, "port") == 0) {
        return uns(k, 1, 65535, &c->port);
    }
    if (strcmp(name, "local_port") == 0) {
        return uns(k, 0, 65535, &c->local_port);
    }
    if (strcmp(name, "period_ms") == 0) {
        return sint(k, 1, 2, &c->period_ms);
    }
    if (strcmp(name, "t_cycle1_us") == 0) {
        return uns(k, 1, 1000000, &c->t_cycle1_us);
    }
    if (strcmp(name, "num_policy") == 0) {
        return policy_key(c, k);
    }
    if (strcmp(name, "max_miss") == 0) {
        return uns(k, 1, 1000000, &c->max_miss);
    }
    if (strcmp(name, "seed") == 0) {
        return seed_key(c, k);
    }
    if (strcmp(name, "drive_on_ms") == 0) {
        return dbl(k, 0, 1e5, &c->drive_on_ms);
    }
    if (strcmp(name, "switch_ms") == 0) {
        return dbl(k, 0, 1e5, &c->switch_ms);
    }
    if (strcmp(name, "follow_check") == 0) {
        return sint(k, 0, 1, &c->check_follow);
    }
    if (strcmp(name, "sync_before") == 0) {
        return uns(k, 0, 1000, &c->sync_before);
    }
    if (strcmp(name, "sync_after") == 0) {
        return uns(k, 0, 100, &c->sync_after);
    }
    if (strcmp(name, "version") == 0) {
        return version_key(c, k);
    }
    return -2;
}

static int arm_key(sim_config_t *c, unsigned a, const kv_t *k)
{
    unsigned l;
    int rc = 0;
    if ((int)a > c->n_arms) {
        unsigned n;
        for (n = (unsigned)c->n_arms; n < a; n++) {
            c->open_mask[n] = 0x3FU;
        }
        c->n_arms = (int)a;
    }
    if (strcmp(k->name, "open") == 0) {
        /* logical axes separated by blanks or commas, e.g. "1 2 3" */
        char tmp[128];
        char *tok;
        char *save = NULL;
        unsigned m = 0U;
        if (strlen(k->value) >= sizeof tmp) {
            return bad_text(k, "a list of logical axes 1..10");
        }
        strcpy(tmp, k->value);
        for (tok = strtok_r(tmp, " ,\t", &save); tok != NULL; tok = strtok_r(NULL, " ,\t", &save)) {
            long long v = 0;
            if (c4gh_tf_parse_int(tok, 1, 10, &v) != C4GH_TF_NUM_OK) {
                return bad_text(k, "a list of logical axes 1..10");
            }
            m |= 1U << (v - 1);
        }
        if (m == 0U) {
            return bad_text(k, "a list of logical axes 1..10");
        }
        c->open_mask[a - 1U] = m;
        return 0;
    }
    if (strcmp(k->name, "option") == 0) {
        return sint(k, 0, 1, &c->option_ok[a - 1U]);
    }
    for (l = 0; l < C4G_AXES_PER_ARM && rc == 0; l++) {
        rc = axis_key(&c->ax[a - 1U][l], k);
    }
    return rc;
}

/* "5,-8,12,-15,3,10": six percentages (-90..500) into fractions. */
static int percent_list(const kv_t *k, double out[PLANT_AXES])
{
    char tmp[160];
    char *tok;
    char *save = NULL;
    double v[PLANT_AXES];
    int n = 0;
    if (strlen(k->value) >= sizeof tmp) {
        return bad_text(k, "six percentages -90..500");
    }
    strcpy(tmp, k->value);
    for (tok = strtok_r(tmp, " ,\t", &save); tok != NULL; tok = strtok_r(NULL, " ,\t", &save)) {
        if (n == PLANT_AXES || c4gh_tf_parse_double(tok, -90.0, 500.0, &v[n]) != C4GH_TF_NUM_OK) {
            return bad_text(k, "six percentages -90..500");
        }
        n++;
    }
    if (n != PLANT_AXES) {
        return bad_text(k, "six percentages -90..500");
    }
    for (n = 0; n < PLANT_AXES; n++) {
        out[n] = v[n] / 100.0;
    }
    return 0;
}

/* [plant]: the arm plant and the controller's model of it. */
static int plant_key(sim_config_t *c, const kv_t *k)
{
    plant_cfg_t *p = &c->plant;
    char why[160];
    if (strcmp(k->name, "file") == 0) {
        if (strlen(k->value) >= sizeof p->path) {
            return bad_text(k, "a path under 256 bytes");
        }
        strcpy(p->path, k->value);
        return 0;
    }
    if (strcmp(k->name, "payload") == 0 || strcmp(k->name, "ctrl_payload") == 0) {
        const int ctrl = k->name[0] == 'c';
        if (sim_parse_payload(k->value, ctrl ? &p->ctrl_payload : &p->payload,
                              ctrl ? p->ctrl_payload_com : p->payload_com, why, sizeof why) != 0) {
            snprintf(k->msg, k->msglen, "[%s] %s: %s", k->section, k->name, why);
            return -1;
        }
        p->ctrl_payload_set |= ctrl;
        return 0;
    }
    if (strcmp(k->name, "ctrl_mass_error") == 0) {
        return percent_list(k, p->ctrl_mass_err);
    }
    if (strcmp(k->name, "ctrl_inertia_error") == 0) {
        return percent_list(k, p->ctrl_inertia_err);
    }
    return -2;
}

static c4gh_tf_ini_rc_t handler(void *user, const char *section, const char *name, const char *value,
                           char *msg, size_t msglen)
{
    sim_config_t *c = user;
    kv_t k;
    int rc;
    unsigned a;
    unsigned l;
    k.section = section;
    k.name = name;
    k.value = value;
    k.msg = msg;
    k.msglen = msglen;
    if (strcmp(section, "sim") == 0) {
        rc = sim_key(c, &k);
    } else if (strcmp(section, "plant") == 0) {
        rc = plant_key(c, &k);
    } else if (strcmp(section, "model") == 0) {
        rc = 0;
        for (a = 0; a < C4G_ARMS && rc == 0; a++) {
            for (l = 0; l < C4G_AXES_PER_ARM && rc == 0; l++) {
                rc = axis_key(&c->ax[a][l], &k);
            }
        }
    } else if (section_arm(section, &a)) {
        rc = arm_key(c, a, &k);
    } else if (section_axis(section, &a, &l)) {
        rc = axis_key(&c->ax[a - 1U][l - 1U], &k);
    } else {
        char s[80];
        c4gh_tf_escape(section, strlen(section), s, sizeof s);
        snprintf(msg, msglen, "unknown section [%s] (want [sim], [plant], [model], [arm 1..4] or [axis A.L])", s);
        return C4GH_TF_INI_BAD_SECTION;
    }
    if (rc == -2) {
        char n[80];
        c4gh_tf_escape(name, strlen(name), n, sizeof n);
        snprintf(msg, msglen, "[%s]: unknown key '%s'", section, n);
        return C4GH_TF_INI_BAD_KEY;
    }
    return (rc == 0) ? C4GH_TF_INI_OK : C4GH_TF_INI_BAD_VALUE;
}

int sim_config_parse(sim_config_t *c, c4gh_tf_file_t *f, char *err, size_t errlen)
{
    if (c4gh_tf_ini_parse(f, handler, c, err, errlen) != 0) {
        return -1;
    }
    if (sim_config_axes(c) < 0) {
        snprintf(err, errlen, "%s: more than 20 open axes, or an arm with none", f->path);
        return -1;
    }
    return 0;
}

int sim_config_load(sim_config_t *c, const char *path, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    if (c4gh_tf_load(&f, path, C4GH_TF_MAX_INI, err, errlen) != 0) {
        return -1;
    }
    rc = sim_config_parse(c, &f, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}
