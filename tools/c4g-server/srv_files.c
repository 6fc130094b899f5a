/* SPDX-License-Identifier: MIT */
/* The server's input files: trajectory CSV (modes 1, 4, 5) and the mode-9 feedforward
 * parameter files (the line format, or c4g-ident's INI through c4g_ffmodel). Loaded once
 * at start-up into static storage; every error names the file, the line, the column, the
 * field and the value (lib/host/c4gh_textfile.h). */
#include "srv_core.h"

#include "c4gh_ffmodel.h"
#include "c4gh_textfile.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bounds that keep every later conversion defined: offsets are stored as float and
 * times are compared with the mode's elapsed seconds. */
#define TRAJ_T_MAX 1e7     /* s */
#define TRAJ_Q_MAX 1e6     /* motor turns */
#define FF_COEF_MAX 1e6
#define TRAJ_LINE 4096
#define FF_LINE 1024

srv_traj_t srv_traj[C4G_ARMS]; /* static: large */

/* Split s in place into at most max fields. Blanks separate fields, and so does one
 * ',' or ';' with optional blanks around it; an empty field ("1,,2", a leading or
 * trailing comma) is an error, never a silently shifted column. Returns the count, -1
 * for an empty field, -2 for too many fields; *bad is then the column. */
static int split_fields(char *s, char **tok, size_t *col, int max, size_t *bad)
{
    size_t i = 0U;
    int n = 0;
    int need = 0; /* a separator was seen: a field must follow */
    for (;;) {
        while (s[i] == ' ' || s[i] == '\t') {
            i++;
        }
        if (s[i] == '\0') {
            if (need) {
                *bad = i + 1U;
                return -1;
            }
            return n;
        }
        if (s[i] == ',' || s[i] == ';') {
            if (need || n == 0) {
                *bad = i + 1U;
                return -1;
            }
            need = 1;
            i++;
            continue;
        }
        if (n == max) {
            *bad = i + 1U;
            return -2;
        }
        tok[n] = s + i;
        col[n] = i + 1U;
        n++;
        need = 0;
        while (s[i] != '\0' && s[i] != ' ' && s[i] != '\t' && s[i] != ',' && s[i] != ';') {
            i++;
        }
        if (s[i] == '\0') {
            return n;
        }
        if (s[i] == ',' || s[i] == ';') {
            need = 1;
        }
        s[i++] = '\0';
    }
}

static int blank_or_comment(const char *s)
{
    s += strspn(s, " \t");
    return *s == '\0' || *s == '#';
}

/* The header line allowed before the first row: its first field cannot start a number. */
static int is_header(const char *tok0)
{
    double d;
    const c4gh_tf_num_t st = c4gh_tf_parse_double(tok0, -1e308, 1e308, &d);
    return st == C4GH_TF_NUM_SYNTAX && !(tok0[0] == '-' || tok0[0] == '+' || tok0[0] == '.' ||
                                    (tok0[0] >= '0' && tok0[0] <= '9'));
}

/* The n fields of a row: t in [0, TRAJ_T_MAX], offsets within +-TRAJ_Q_MAX. 0, or -1. */
static int traj_values(c4gh_tf_file_t *f, char *const *tok, const size_t *col, int n, double *vals,
                       char *err, size_t errlen)
{
    int k;
    for (k = 0; k < n; k++) {
        const double lim = (k == 0) ? TRAJ_T_MAX : TRAJ_Q_MAX;
        const c4gh_tf_num_t st = c4gh_tf_parse_double(tok[k], (k == 0) ? 0.0 : -lim, lim, &vals[k]);
        if (st != C4GH_TF_NUM_OK) {
            char why[200];
            c4gh_tf_num_explain(st, tok[k], (k == 0) ? 0.0 : -lim, lim, why, sizeof why);
            return c4gh_tf_error(f, col[k], err, errlen, "column %d (%s): %s", k + 1,
                            k == 0 ? "t [s]" : "axis offset [turns]", why);
        }
    }
    return 0;
}

/* Append a row of n values (t and n - 1 offsets); col0 is the column of its time. */
static int traj_add(c4gh_tf_file_t *f, srv_traj_t *tr, const double *vals, int n, size_t col0,
                    char *err, size_t errlen)
{
    int k;
    if (n < 2) {
        return c4gh_tf_error(f, 0U, err, errlen, "need t and at least one axis column, got %d value(s)", n);
    }
    if (tr->rows == 0U) {
        tr->cols = (uint32_t)n - 1U;
    } else if ((uint32_t)n - 1U != tr->cols) {
        return c4gh_tf_error(f, 0U, err, errlen, "%d axis columns, the first row has %u", n - 1,
                        tr->cols);
    }
    if (tr->rows >= SRV_MAX_TRAJ_ROWS) {
        return c4gh_tf_error(f, 0U, err, errlen, "more than %u rows", SRV_MAX_TRAJ_ROWS);
    }
    if (tr->rows > 0U && vals[0] <= tr->t[tr->rows - 1U]) {
        return c4gh_tf_error(f, col0, err, errlen,
                        "column 1 (t [s]): %g is not after the previous row's time %g", vals[0],
                        tr->t[tr->rows - 1U]);
    }
    tr->t[tr->rows] = vals[0];
    for (k = 0; k < (int)C4G_AXES_PER_ARM; k++) {
        tr->q[tr->rows][k] = ((uint32_t)k < tr->cols) ? (float)vals[k + 1] : 0.0f;
    }
    tr->rows++;
    return 0;
}

int srv_parse_traj(c4gh_tf_file_t *f, srv_traj_t *tr, char *err, size_t errlen)
{
    char line[TRAJ_LINE];
    int header_seen = 0;
    int r;
    tr->rows = 0U;
    tr->cols = 0U;
    while ((r = c4gh_tf_next_line(f, line, sizeof line, err, errlen)) > 0) {
        char *tok[C4G_AXES_PER_ARM + 1U];
        size_t col[C4G_AXES_PER_ARM + 1U];
        double vals[C4G_AXES_PER_ARM + 1U];
        size_t bad = 0U;
        int n;
        if (blank_or_comment(line)) {
            continue;
        }
        n = split_fields(line, tok, col, (int)C4G_AXES_PER_ARM + 1, &bad);
        if (n == -2) {
            return c4gh_tf_error(f, bad, err, errlen, "more than %u axis columns", C4G_AXES_PER_ARM);
        }
        if (n < 0) {
            return c4gh_tf_error(f, bad, err, errlen, "empty field");
        }
        /* One header line before the first row. */
        if (tr->rows == 0U && !header_seen && is_header(tok[0])) {
            header_seen = 1;
            continue;
        }
        if (traj_values(f, tok, col, n, vals, err, errlen) != 0 ||
            traj_add(f, tr, vals, n, col[0], err, errlen) != 0) {
            return -1;
        }
    }
    if (r < 0) {
        return -1;
    }
    if (tr->rows == 0U) {
        snprintf(err, errlen, "%s: no data rows", f->path);
        return -1;
    }
    return 0;
}

int srv_parse_ff(c4gh_tf_file_t *f, srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err, size_t errlen)
{
    static const char *const names[9] = {"arm", "axis", "c0", "cv", "cc", "ca", "gs", "gscale",
                                         "gphase"};
    char line[FF_LINE];
    unsigned n = 0U;
    int r;
    while ((r = c4gh_tf_next_line(f, line, sizeof line, err, errlen)) > 0) {
        char *tok[9];
        size_t col[9];
        double v[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        long long arm = 0;
        long long ax = 0;
        size_t bad = 0U;
        char why[200];
        c4gh_tf_num_t st;
        int nf;
        int k;
        if (blank_or_comment(line)) {
            continue;
        }
        nf = split_fields(line, tok, col, 9, &bad);
        if (nf == -2) {
            return c4gh_tf_error(f, bad, err, errlen, "more than 9 fields");
        }
        if (nf < 0) {
            return c4gh_tf_error(f, bad, err, errlen, "empty field");
        }
        if (nf < 3) {
            return c4gh_tf_error(f, 0U, err, errlen, "need at least arm, axis, c0 (got %d fields)", nf);
        }
        st = c4gh_tf_parse_int(tok[0], 1, (long long)C4G_ARMS, &arm);
        if (st != C4GH_TF_NUM_OK) {
            c4gh_tf_num_explain(st, tok[0], 1.0, (double)C4G_ARMS, why, sizeof why);
            return c4gh_tf_error(f, col[0], err, errlen, "field 1 (arm): %s", why);
        }
        st = c4gh_tf_parse_int(tok[1], 1, (long long)C4G_AXES_PER_ARM, &ax);
        if (st != C4GH_TF_NUM_OK) {
            c4gh_tf_num_explain(st, tok[1], 1.0, (double)C4G_AXES_PER_ARM, why, sizeof why);
            return c4gh_tf_error(f, col[1], err, errlen, "field 2 (axis): %s", why);
        }
        for (k = 2; k < nf; k++) {
            st = c4gh_tf_parse_double(tok[k], -FF_COEF_MAX, FF_COEF_MAX, &v[k]);
            if (st != C4GH_TF_NUM_OK) {
                c4gh_tf_num_explain(st, tok[k], -FF_COEF_MAX, FF_COEF_MAX, why, sizeof why);
                return c4gh_tf_error(f, col[k], err, errlen, "field %d (%s): %s", k + 1, names[k], why);
            }
        }
        {
            srv_ff_t *p = &ff[arm - 1][ax - 1];
            if (p->set != 0) {
                /* a second line would silently replace the first one's parameters */
                return c4gh_tf_error(f, col[0], err, errlen, "arm %lld axis %lld is already set on line %d",
                                arm, ax, p->set);
            }
            p->set = (int)f->line;
            p->c0 = v[2]; p->cv = v[3]; p->cc = v[4]; p->ca = v[5];
            p->gs = v[6]; p->gscale = v[7]; p->gphase = v[8];
        }
        n++;
    }
    if (r < 0) {
        return -1;
    }
    if (n == 0U) {
        snprintf(err, errlen, "%s: no parameter lines", f->path);
        return -1;
    }
    return 0;
}

int srv_load_traj(const char *path, srv_traj_t *tr, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    if (c4gh_tf_load(&f, path, SRV_MAX_TRAJ_BYTES, err, errlen) != 0) {
        return -1;
    }
    rc = srv_parse_traj(&f, tr, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}

int srv_load_ff(const char *path, srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err,
                size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    if (c4gh_tf_load(&f, path, SRV_MAX_FF_BYTES, err, errlen) != 0) {
        return -1;
    }
    rc = srv_parse_ff(&f, ff, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}

int srv_ff_is_ini(const char *text, size_t len)
{
    size_t i = 0U;
    if (len >= 3U && memcmp(text, "\xef\xbb\xbf", 3U) == 0) {
        i = 3U; /* a UTF-8 byte order mark, as inih skips it */
    }
    while (i < len) {
        while (i < len && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) {
            i++;
        }
        if (i < len && text[i] != '\n' && text[i] != '#' && text[i] != ';') {
            return text[i] == '[';
        }
        while (i < len && text[i] != '\n') {
            i++;
        }
        i++;
    }
    return 0;
}

/* An axis two files set: which one applies would depend on the order of the options. */
static int ff_taken(const srv_ff_t *p, const char *path, int line, unsigned arm, unsigned ax,
                    const char *const *paths, char *err, size_t errlen)
{
    if (p->set == 0) {
        return 0;
    }
    snprintf(err, errlen, "%s:%d:1: arm %u axis %u is already set by %s:%d", path, line, arm + 1U,
             ax + 1U, paths[p->file], p->set);
    return 1;
}

static int ff_merge_model(const c4gh_tf_file_t *f, unsigned file, const char *const *paths,
                          srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], c4gh_ffm_file_t rigid[C4G_ARMS],
                          char *err, size_t errlen)
{
    static c4gh_ffm_file_t m; /* large; the tool is single-threaded here (startup) */
    unsigned l;
    if (c4gh_ffm_parse_text(f->path, f->data, f->len, &m, err, errlen) != 0) {
        return -1;
    }
    if (m.rigid && rigid == NULL) {
        snprintf(err, errlen, "%s:%d:1: a rigid-body model has no place here", f->path, m.model_line);
        return -1;
    }
    for (l = 0U; l < C4G_AXES_PER_ARM; l++) {
        srv_ff_t *p = &ff[m.arm - 1U][l];
        if (!m.ax[l].set) {
            continue;
        }
        if (ff_taken(p, f->path, m.ax[l].line, m.arm - 1U, l, paths, err, errlen)) {
            return -1;
        }
        memset(p, 0, sizeof *p);
        p->set = m.ax[l].line;
        p->kind = m.rigid ? CTLR_FF_RIGID : CTLR_FF_MODEL;
        p->file = file;
        p->period_ms = m.period_ms;
        p->model = m.ax[l];
    }
    if (m.rigid) {
        /* the arm's axes 1..n are each set once (above): so is its rigid model */
        rigid[m.arm - 1U] = m;
    }
    return 0;
}

static int ff_merge_legacy(c4gh_tf_file_t *f, unsigned file, const char *const *paths,
                           srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err, size_t errlen)
{
    srv_ff_t tmp[C4G_ARMS][C4G_AXES_PER_ARM];
    unsigned a, l;
    memset(tmp, 0, sizeof tmp);
    if (srv_parse_ff(f, tmp, err, errlen) != 0) {
        return -1;
    }
    for (a = 0U; a < C4G_ARMS; a++) {
        for (l = 0U; l < C4G_AXES_PER_ARM; l++) {
            if (tmp[a][l].set == 0) {
                continue;
            }
            if (ff_taken(&ff[a][l], f->path, tmp[a][l].set, a, l, paths, err, errlen)) {
                return -1;
            }
            ff[a][l] = tmp[a][l];
            ff[a][l].file = file;
        }
    }
    return 0;
}

int srv_load_ff_any(const char *path, unsigned file, const char *const *paths,
                    srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], c4gh_ffm_file_t rigid[C4G_ARMS],
                    char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    if (c4gh_tf_load(&f, path, SRV_MAX_FF_BYTES, err, errlen) != 0) {
        return -1;
    }
    if (srv_ff_is_ini(f.data, f.len)) {
        rc = ff_merge_model(&f, file, paths, ff, rigid, err, errlen);
    } else {
        rc = ff_merge_legacy(&f, file, paths, ff, err, errlen);
    }
    c4gh_tf_free(&f);
    return rc;
}

/* Every arm's trajectory (into srv_traj; an arm naming an earlier arm's file shares its
 * rows) and the feedforward parameters of every --ff file (into cfg->ff). */
int srv_load_files(srv_config_t *cfg, char *err, size_t errlen)
{
    char why[600];
    uint32_t a;
    for (a = 0U; a < C4G_ARMS; a++) {
        const srv_arm_cfg_t *A = &cfg->arm[a];
        uint32_t b;
        int shared = 0;
        if (A->src != SRC_FILE) {
            continue;
        }
        for (b = 0U; b < a; b++) { /* same file as an earlier arm: copy, don't re-read */
            if (cfg->arm[b].src == SRC_FILE && strcmp(cfg->arm[b].traj_path, A->traj_path) == 0) {
                memcpy(&srv_traj[a], &srv_traj[b], sizeof srv_traj[a]);
                shared = 1;
                break;
            }
        }
        if (!shared && srv_load_traj(A->traj_path, &srv_traj[a], why, sizeof why) != 0) {
            snprintf(err, errlen, "trajectory: %s", why);
            return -1;
        }
    }
    {
        const char *paths[SRV_MAX_FF_FILES];
        unsigned k;
        memset(cfg->ff, 0, sizeof cfg->ff);
        memset(cfg->rigid, 0, sizeof cfg->rigid);
        for (k = 0U; k < SRV_MAX_FF_FILES; k++) {
            paths[k] = cfg->ff_path[k];
        }
        for (k = 0U; k < cfg->n_ff && k < SRV_MAX_FF_FILES; k++) {
            if (srv_load_ff_any(cfg->ff_path[k], k, paths, cfg->ff, cfg->rigid, why, sizeof why) != 0) {
                snprintf(err, errlen, "feedforward: %s", why);
                return -1;
            }
            for (a = 0U; a < C4G_ARMS; a++) {
                if (cfg->rigid[a].rigid && cfg->ff[a][0].file == k && cfg->ff[a][0].kind == CTLR_FF_RIGID) {
                    cfg->rigid_file[a] = k;
                }
            }
        }
    }
    return 0;
}
