/* SPDX-License-Identifier: MIT */
/* c4g-server input files: trajectory CSV (modes 1, 4, 5) and the mode-9 feedforward
 * parameter file. Loaded once at start-up into static storage; every error names the
 * file, the line, the field and the value. */
#include "srv.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    e = s + strlen(s);
    while (e > s && (e[-1] == '\n' || e[-1] == '\r' || e[-1] == ' ' || e[-1] == '\t')) {
        *--e = '\0';
    }
    return s;
}

static int parse_num(const char *tok, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(tok, &end);
    if (end == tok || errno != 0 || !isfinite(v)) {
        return -1;
    }
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    if (*end != '\0') {
        return -1;
    }
    *out = v;
    return 0;
}

int srv_load_traj(const char *path, srv_traj_t *tr, char *err, size_t errlen)
{
    FILE *fp = fopen(path, "r");
    char line[4096];
    unsigned lineno = 0U;
    tr->rows = 0U;
    tr->cols = 0U;
    if (fp == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    while (fgets(line, sizeof line, fp) != NULL) {
        char *s = trim(line), *tok, *save = NULL;
        uint32_t col = 0U;
        double vals[C4G_AXES_PER_ARM + 1U];
        lineno++;
        if (*s == '\0' || *s == '#') {
            continue;
        }
        if (tr->rows == 0U && tr->cols == 0U && !(*s == '-' || *s == '+' || *s == '.' ||
                                                  (*s >= '0' && *s <= '9'))) {
            continue; /* header line */
        }
        for (tok = strtok_r(s, ",; \t", &save); tok != NULL; tok = strtok_r(NULL, ",; \t", &save)) {
            if (col > C4G_AXES_PER_ARM) {
                snprintf(err, errlen, "%s:%u: more than %u axis columns", path, lineno,
                         C4G_AXES_PER_ARM);
                fclose(fp);
                return -1;
            }
            if (parse_num(tok, &vals[col]) != 0) {
                snprintf(err, errlen, "%s:%u: column %u (%s): not a finite number: '%s'", path,
                         lineno, col + 1U, col == 0U ? "t" : "axis offset", tok);
                fclose(fp);
                return -1;
            }
            col++;
        }
        if (col < 2U) {
            snprintf(err, errlen, "%s:%u: need t and at least one axis column, got %u value(s)",
                     path, lineno, col);
            fclose(fp);
            return -1;
        }
        if (tr->rows == 0U) {
            tr->cols = col - 1U;
        } else if (col - 1U != tr->cols) {
            snprintf(err, errlen, "%s:%u: %u axis columns, the first row has %u", path, lineno,
                     col - 1U, tr->cols);
            fclose(fp);
            return -1;
        }
        if (tr->rows >= SRV_MAX_TRAJ_ROWS) {
            snprintf(err, errlen, "%s:%u: more than %u rows", path, lineno, SRV_MAX_TRAJ_ROWS);
            fclose(fp);
            return -1;
        }
        if (vals[0] < 0.0 || (tr->rows > 0U && vals[0] <= tr->t[tr->rows - 1U])) {
            snprintf(err, errlen, "%s:%u: column 1 (t): %g is not after the previous row's time",
                     path, lineno, vals[0]);
            fclose(fp);
            return -1;
        }
        tr->t[tr->rows] = vals[0];
        {
            uint32_t k;
            for (k = 0U; k < C4G_AXES_PER_ARM; k++) {
                tr->q[tr->rows][k] = (k < tr->cols) ? (float)vals[k + 1U] : 0.0f;
            }
        }
        tr->rows++;
    }
    fclose(fp);
    if (tr->rows == 0U) {
        snprintf(err, errlen, "%s: no data rows", path);
        return -1;
    }
    return 0;
}

int srv_load_ff(const char *path, srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err,
                size_t errlen)
{
    static const char *const names[9] = {"arm", "axis", "c0", "cv", "cc", "ca", "gs", "gscale",
                                         "gphase"};
    FILE *fp = fopen(path, "r");
    char line[1024];
    unsigned lineno = 0U, n = 0U;
    if (fp == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    while (fgets(line, sizeof line, fp) != NULL) {
        char *s = trim(line), *tok, *save = NULL;
        double v[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        unsigned col = 0U;
        long arm, ax;
        lineno++;
        if (*s == '\0' || *s == '#') {
            continue;
        }
        for (tok = strtok_r(s, " \t,", &save); tok != NULL; tok = strtok_r(NULL, " \t,", &save)) {
            if (col >= 9U) {
                snprintf(err, errlen, "%s:%u: more than 9 fields", path, lineno);
                fclose(fp);
                return -1;
            }
            if (parse_num(tok, &v[col]) != 0) {
                snprintf(err, errlen, "%s:%u: field %u (%s): not a finite number: '%s'", path,
                         lineno, col + 1U, names[col], tok);
                fclose(fp);
                return -1;
            }
            col++;
        }
        if (col < 3U) {
            snprintf(err, errlen, "%s:%u: need at least arm, axis, c0 (got %u fields)", path,
                     lineno, col);
            fclose(fp);
            return -1;
        }
        arm = (long)v[0];
        ax = (long)v[1];
        if ((double)arm != v[0] || arm < 1 || arm > (long)C4G_ARMS) {
            snprintf(err, errlen, "%s:%u: field 1 (arm): %g is not 1..4", path, lineno, v[0]);
            fclose(fp);
            return -1;
        }
        if ((double)ax != v[1] || ax < 1 || ax > (long)C4G_AXES_PER_ARM) {
            snprintf(err, errlen, "%s:%u: field 2 (axis): %g is not 1..10", path, lineno, v[1]);
            fclose(fp);
            return -1;
        }
        {
            srv_ff_t *p = &ff[arm - 1][ax - 1];
            p->set = 1;
            p->c0 = v[2]; p->cv = v[3]; p->cc = v[4]; p->ca = v[5];
            p->gs = v[6]; p->gscale = v[7]; p->gphase = v[8];
        }
        n++;
    }
    fclose(fp);
    if (n == 0U) {
        snprintf(err, errlen, "%s: no parameter lines", path);
        return -1;
    }
    return 0;
}
