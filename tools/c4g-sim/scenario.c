/* SPDX-License-Identifier: MIT */
/* c4g-sim scenario parser. Grammar (one command per line, '#' starts a comment,
 * keywords case-insensitive) is documented in docs/c4g-sim.md. */
#include "scenario.h"

#include "c4g_textfile.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_LINE 512
#define MAX_TOK 32

static const char *const op_names[] = {
    "?", "DRIVE ON", "DRIVE OFF", "MOVE", "MOVEREL", "WAIT MOVE", "DELAY", "MODE", "CMD",
    "WAIT PC", "FREEZE", "RESTART", "EXIT OPEN", "OVERRIDE", "SELECTOR", "EXPECT POS",
    "EXPECT MODE", "EXPECT ERROR", "END"};

const char *scn_op_name(scn_op_t op)
{
    return ((int)op >= 1 && (int)op <= (int)SCN_END) ? op_names[op] : "?";
}

static int kw(const char *tok, const char *word)
{
    return tok != NULL && strcasecmp(tok, word) == 0;
}

/* Where the words of the current line start (1-based columns, for messages). */
typedef struct scn_line {
    tf_file_t *f;
    char *buf;
    char **t;
    int nt;
    char *err;
    size_t errlen;
} scn_line_t;

static size_t col_of(const scn_line_t *L, int k)
{
    return (k >= 0 && k < L->nt) ? (size_t)(L->t[k] - L->buf) + 1U : 0U;
}

/* Error at word k of the line (k < 0 or past the end: no column). */
static int scn_fail(const scn_line_t *L, int k, const char *fmt, ...)
{
    va_list ap;
    char msg[384];
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return tf_error(L->f, col_of(L, k), L->err, L->errlen, "%s", msg);
}

/* Word k as a finite number in lo..hi; what names the value in the message. */
static int get_num(const scn_line_t *L, int k, double lo, double hi, double *out, const char *what)
{
    char why[160];
    const tf_num_t st = tf_parse_double(L->t[k], lo, hi, out);
    if (st == TF_NUM_OK) {
        return 0;
    }
    tf_num_explain(st, L->t[k], lo, hi, why, sizeof why);
    return scn_fail(L, k, "%s: %s: %s", L->t[0], what, why);
}

static int get_int(const scn_line_t *L, int k, long lo, long hi, int *out, const char *what)
{
    char why[160];
    long long v = 0;
    const tf_num_t st = tf_parse_int(L->t[k], lo, hi, &v);
    if (st == TF_NUM_OK) {
        *out = (int)v;
        return 0;
    }
    tf_num_explain(st, L->t[k], (double)lo, (double)hi, why, sizeof why);
    return scn_fail(L, k, "%s: %s: %s", L->t[0], what, why);
}

/* Limits: positions in motor turns, times in ms (an hour), so every later conversion
 * (ticks as unsigned long, positions as float) stays in range. */
#define POS_MAX 1e6
#define MS_MAX 3.6e6

/* Parse one tokenised line into c. */
static int parse_line(const scn_line_t *L, scn_cmd_t *c)
{
    char *const *t = L->t;
    const int nt = L->nt;
    int i = 1;
    memset(c, 0, sizeof *c);
    c->line = (int)L->f->line;
#define NEED(k, what) do { if (nt <= (k)) return scn_fail(L, -1, "%s: missing %s", t[0], what); } while (0)
#define ARM(k) do { NEED(k, "arm"); if (get_int(L, k, 1, 4, &c->arm, "arm") != 0) return -1; } while (0)
    if (kw(t[0], "DRIVE")) {
        NEED(1, "ON or OFF");
        if (kw(t[1], "ON")) {
            c->op = SCN_DRIVE_ON;
        } else if (kw(t[1], "OFF")) {
            c->op = SCN_DRIVE_OFF;
        } else {
            return scn_fail(L, 1, "DRIVE: expected ON or OFF, got '%s'", t[1]);
        }
        i = 2;
        if (nt > 2) {
            if (kw(t[2], "ARM")) {
                i = 3;
            }
            ARM(i);
            i++;
        }
    } else if (kw(t[0], "MOVE") || kw(t[0], "MOVEREL")) {
        c->op = kw(t[0], "MOVE") ? SCN_MOVE : SCN_MOVE_REL;
        ARM(1);
        for (i = 2; i < nt; i++) {
            char what[32];
            if (kw(t[i], "NOWAIT")) {
                c->nowait = 1;
                i++;
                break;
            }
            if (c->n >= SCN_MAX_VALUES) {
                return scn_fail(L, i, "%s: more than %d targets", t[0], SCN_MAX_VALUES);
            }
            snprintf(what, sizeof what, "target %d [turns]", c->n + 1);
            if (get_num(L, i, -POS_MAX, POS_MAX, &c->v[c->n], what) != 0) {
                return -1;
            }
            c->n++;
        }
        if (c->n == 0) {
            return scn_fail(L, -1, "%s: no targets", t[0]);
        }
    } else if (kw(t[0], "WAIT")) {
        NEED(1, "MOVE or PC");
        if (kw(t[1], "MOVE")) {
            c->op = SCN_WAIT_MOVE;
            ARM(2);
            i = 3;
        } else {
            i = 1;
            if (kw(t[i], "FOR")) {
                i++;
            }
            if (!kw(nt > i ? t[i] : NULL, "PC")) {
                return scn_fail(L, i, "WAIT: expected MOVE, PC or FOR PC");
            }
            c->op = SCN_WAIT_PC;
            i++;
            ARM(i);
            i++;
            if (nt > i && kw(t[i], "TIMEOUT")) {
                NEED(i + 1, "timeout [ms]");
                if (get_num(L, i + 1, 0.0, MS_MAX, &c->ms, "timeout [ms]") != 0) {
                    return -1;
                }
                i += 2;
            }
        }
    } else if (kw(t[0], "DELAY") || kw(t[0], "FREEZE")) {
        c->op = kw(t[0], "DELAY") ? SCN_DELAY : SCN_FREEZE;
        NEED(1, "time [ms]");
        if (get_num(L, 1, 0.0, MS_MAX, &c->ms, "time [ms]") != 0) {
            return -1;
        }
        i = 2;
    } else if (kw(t[0], "MODE")) {
        c->op = SCN_MODE;
        ARM(1);
        NEED(2, "mode");
        if (get_int(L, 2, 0, 1000, &c->iv, "mode") != 0) {
            return -1;
        }
        i = 3;
        if (nt > 3 && kw(t[3], "AXES")) {
            for (i = 4; i < nt; i++) {
                int ax;
                if (get_int(L, i, 1, 10, &ax, "axis") != 0) {
                    return -1;
                }
                c->axes_mask |= 1U << (ax - 1);
            }
            if (c->axes_mask == 0U) {
                return scn_fail(L, 3, "MODE: AXES without axes");
            }
        }
    } else if (kw(t[0], "CMD")) {
        c->op = SCN_CMD;
        ARM(1);
        NEED(2, "value");
        if (get_int(L, 2, 0, 255, &c->iv, "value") != 0) {
            return -1;
        }
        i = 3;
    } else if (kw(t[0], "RESTART")) {
        c->op = SCN_RESTART;
    } else if (kw(t[0], "EXIT")) {
        NEED(1, "OPEN");
        if (!kw(t[1], "OPEN")) {
            return scn_fail(L, 1, "EXIT: expected OPEN");
        }
        c->op = SCN_EXIT_OPEN;
        i = 2;
    } else if (kw(t[0], "OVERRIDE")) {
        c->op = SCN_OVERRIDE;
        NEED(1, "percent");
        if (get_num(L, 1, 0.0, 100.0, &c->ms, "percent") != 0) {
            return -1;
        }
        i = 2;
    } else if (kw(t[0], "SELECTOR")) {
        c->op = SCN_SELECTOR;
        NEED(1, "AUTO or PROG");
        if (kw(t[1], "AUTO")) {
            c->iv = 0;
        } else if (kw(t[1], "PROG")) {
            c->iv = 1;
        } else {
            return scn_fail(L, 1, "SELECTOR: expected AUTO or PROG, got '%s'", t[1]);
        }
        i = 2;
    } else if (kw(t[0], "EXPECT")) {
        NEED(1, "POS, MODE or ERROR");
        if (kw(t[1], "POS") || kw(t[1], "MODE")) {
            const int pos = kw(t[1], "POS");
            c->op = pos ? SCN_EXPECT_POS : SCN_EXPECT_MODE;
            ARM(2);
            NEED(3, "axis");
            if (get_int(L, 3, 1, 10, &c->iv, "axis") != 0) {
                return -1;
            }
            NEED(4, "value");
            if (pos) {
                if (get_num(L, 4, -POS_MAX, POS_MAX, &c->v[0], "position [turns]") != 0) {
                    return -1;
                }
                NEED(5, "tolerance");
                if (get_num(L, 5, 0.0, POS_MAX, &c->v[1], "tolerance [turns]") != 0) {
                    return -1;
                }
                c->n = 2;
                i = 6;
            } else {
                int m;
                /* a mode code: compared as an integer with the packet's mode */
                if (get_int(L, 4, 0, 1000, &m, "mode") != 0) {
                    return -1;
                }
                c->v[0] = m;
                c->n = 1;
                i = 5;
            }
        } else if (kw(t[1], "ERROR")) {
            c->op = SCN_EXPECT_ERROR;
            NEED(2, "error name (or NONE)");
            if (strlen(t[2]) >= sizeof c->name) {
                return scn_fail(L, 2, "EXPECT ERROR: name longer than %d characters",
                                (int)sizeof c->name - 1);
            }
            strcpy(c->name, t[2]);
            i = 3;
        } else {
            return scn_fail(L, 1, "EXPECT: expected POS, MODE or ERROR, got '%s'", t[1]);
        }
    } else if (kw(t[0], "END")) {
        c->op = SCN_END;
    } else {
        return scn_fail(L, 0, "unknown command '%s'", t[0]);
    }
    if (i < nt) {
        return scn_fail(L, i, "%s: unexpected '%s'", scn_op_name(c->op), t[i]);
    }
#undef NEED
#undef ARM
    return 0;
}

int scn_parse(const char *path, const char *text, size_t len, scn_t *out, char *err, size_t errlen)
{
    tf_file_t f;
    char buf[MAX_LINE];
    int r;
    out->n = 0;
    if (err != NULL && errlen > 0U) {
        err[0] = '\0';
    }
    tf_open_mem(&f, path, text, len);
    while ((r = tf_next_line(&f, buf, sizeof buf, err, errlen)) > 0) {
        char *tok[MAX_TOK];
        scn_line_t L;
        int nt = 0;
        char *p = strchr(buf, '#');
        if (p != NULL) {
            *p = '\0';
        }
        p = buf;
        for (;;) {
            while (*p == ' ' || *p == '\t') {
                p++;
            }
            if (*p == '\0') {
                break;
            }
            if (nt >= MAX_TOK) {
                return tf_error(&f, (size_t)(p - buf) + 1U, err, errlen, "more than %d words", MAX_TOK);
            }
            tok[nt++] = p;
            while (*p != '\0' && *p != ' ' && *p != '\t') {
                p++;
            }
            if (*p != '\0') {
                *p++ = '\0';
            }
        }
        if (nt == 0) {
            continue;
        }
        if (out->n >= SCN_MAX_CMDS) {
            return tf_error(&f, 1U, err, errlen, "more than %d commands", SCN_MAX_CMDS);
        }
        L.f = &f;
        L.buf = buf;
        L.t = tok;
        L.nt = nt;
        L.err = err;
        L.errlen = errlen;
        if (parse_line(&L, &out->cmd[out->n]) != 0) {
            return -1;
        }
        out->n++;
    }
    return (r < 0) ? -1 : 0;
}
