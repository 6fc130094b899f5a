/* SPDX-License-Identifier: MIT */
/* c4g-sim scenario parser. Grammar (one command per line, '#' starts a comment,
 * keywords case-insensitive) is documented in docs/c4g-sim.md. */
#include "scenario.h"

#include "c4gh_textfile.h"

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
    c4gh_tf_file_t *f;
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
    return c4gh_tf_error(L->f, col_of(L, k), L->err, L->errlen, "%s", msg);
}

/* Word k as a finite number in lo..hi; what names the value in the message. */
static int get_num(const scn_line_t *L, int k, double lo, double hi, double *out, const char *what)
{
    char why[160];
    const c4gh_tf_num_t st = c4gh_tf_parse_double(L->t[k], lo, hi, out);
    if (st == C4GH_TF_NUM_OK) {
        return 0;
    }
    c4gh_tf_num_explain(st, L->t[k], lo, hi, why, sizeof why);
    return scn_fail(L, k, "%s: %s: %s", L->t[0], what, why);
}

static int get_int(const scn_line_t *L, int k, long lo, long hi, int *out, const char *what)
{
    char why[160];
    long long v = 0;
    const c4gh_tf_num_t st = c4gh_tf_parse_int(L->t[k], lo, hi, &v);
    if (st == C4GH_TF_NUM_OK) {
        *out = (int)v;
        return 0;
    }
    c4gh_tf_num_explain(st, L->t[k], (double)lo, (double)hi, why, sizeof why);
    return scn_fail(L, k, "%s: %s: %s", L->t[0], what, why);
}

/* Limits: positions in motor turns, times in ms (an hour), so every later conversion
 * (ticks as unsigned long, positions as float) stays in range. */
#define POS_MAX 1e6
#define MS_MAX 3.6e6

/* ---- one parser per command --------------------------------------------
 * Each gets the line with c->op set from its table row and returns the index of the
 * first word it did not use (the caller refuses leftovers), or -1 after an error. */

/* Word k must be there. */
static int need(const scn_line_t *L, int k, const char *what)
{
    if (L->nt <= k) {
        return scn_fail(L, -1, "%s: missing %s", L->t[0], what);
    }
    return 0;
}

static int get_arm(const scn_line_t *L, int k, scn_cmd_t *c)
{
    if (need(L, k, "arm") != 0) {
        return -1;
    }
    return get_int(L, k, 1, 4, &c->arm, "arm");
}

/* RESTART, END */
static int p_bare(const scn_line_t *L, scn_cmd_t *c)
{
    (void)L;
    (void)c;
    return 1;
}

/* EXIT OPEN */
static int p_two_words(const scn_line_t *L, scn_cmd_t *c)
{
    (void)L;
    (void)c;
    return 2;
}

/* DRIVE ON|OFF [[ARM] a] */
static int p_drive(const scn_line_t *L, scn_cmd_t *c)
{
    int i = 2;
    if (L->nt > 2) {
        if (kw(L->t[2], "ARM")) {
            i = 3;
        }
        if (get_arm(L, i, c) != 0) {
            return -1;
        }
        i++;
    }
    return i;
}

/* MOVE|MOVEREL a p1 .. pn [NOWAIT] */
static int p_move(const scn_line_t *L, scn_cmd_t *c)
{
    int i;
    if (get_arm(L, 1, c) != 0) {
        return -1;
    }
    for (i = 2; i < L->nt && !c->nowait; i++) {
        char what[32];
        if (kw(L->t[i], "NOWAIT")) {
            c->nowait = 1; /* the loop ends past it */
            continue;
        }
        if (c->n >= SCN_MAX_VALUES) {
            return scn_fail(L, i, "%s: more than %d targets", L->t[0], SCN_MAX_VALUES);
        }
        snprintf(what, sizeof what, "target %d [turns]", c->n + 1);
        if (get_num(L, i, -POS_MAX, POS_MAX, &c->v[c->n], what) != 0) {
            return -1;
        }
        c->n++;
    }
    if (c->n == 0) {
        return scn_fail(L, -1, "%s: no targets", L->t[0]);
    }
    return i;
}

/* WAIT MOVE a */
static int p_wait_move(const scn_line_t *L, scn_cmd_t *c)
{
    return (get_arm(L, 2, c) != 0) ? -1 : 3;
}

/* WAIT [FOR] PC a [TIMEOUT ms] */
static int p_wait_pc(const scn_line_t *L, scn_cmd_t *c)
{
    int i = kw(L->t[1], "FOR") ? 2 : 1;
    if (!kw(L->nt > i ? L->t[i] : NULL, "PC")) {
        return scn_fail(L, i, "WAIT: expected MOVE, PC or FOR PC");
    }
    i++;
    if (get_arm(L, i, c) != 0) {
        return -1;
    }
    i++;
    if (L->nt > i && kw(L->t[i], "TIMEOUT")) {
        if (need(L, i + 1, "timeout [ms]") != 0 ||
            get_num(L, i + 1, 0.0, MS_MAX, &c->ms, "timeout [ms]") != 0) {
            return -1;
        }
        i += 2;
    }
    return i;
}

/* DELAY ms, FREEZE ms */
static int p_time(const scn_line_t *L, scn_cmd_t *c)
{
    if (need(L, 1, "time [ms]") != 0 || get_num(L, 1, 0.0, MS_MAX, &c->ms, "time [ms]") != 0) {
        return -1;
    }
    return 2;
}

/* MODE a m [AXES l ..] */
static int p_mode(const scn_line_t *L, scn_cmd_t *c)
{
    int i;
    if (get_arm(L, 1, c) != 0 || need(L, 2, "mode") != 0 ||
        get_int(L, 2, 0, 1000, &c->iv, "mode") != 0) {
        return -1;
    }
    if (L->nt <= 3 || !kw(L->t[3], "AXES")) {
        return 3;
    }
    for (i = 4; i < L->nt; i++) {
        int ax;
        if (get_int(L, i, 1, 10, &ax, "axis") != 0) {
            return -1;
        }
        c->axes_mask |= 1U << (ax - 1);
    }
    if (c->axes_mask == 0U) {
        return scn_fail(L, 3, "MODE: AXES without axes");
    }
    return i;
}

/* CMD a v */
static int p_cmd(const scn_line_t *L, scn_cmd_t *c)
{
    if (get_arm(L, 1, c) != 0 || need(L, 2, "value") != 0 ||
        get_int(L, 2, 0, 255, &c->iv, "value") != 0) {
        return -1;
    }
    return 3;
}

/* OVERRIDE pct */
static int p_override(const scn_line_t *L, scn_cmd_t *c)
{
    if (need(L, 1, "percent") != 0 || get_num(L, 1, 0.0, 100.0, &c->ms, "percent") != 0) {
        return -1;
    }
    return 2;
}

/* SELECTOR AUTO|PROG */
static int p_selector(const scn_line_t *L, scn_cmd_t *c)
{
    if (need(L, 1, "AUTO or PROG") != 0) {
        return -1;
    }
    if (!kw(L->t[1], "AUTO") && !kw(L->t[1], "PROG")) {
        return scn_fail(L, 1, "SELECTOR: expected AUTO or PROG, got '%s'", L->t[1]);
    }
    c->iv = kw(L->t[1], "PROG");
    return 2;
}

/* EXPECT POS|MODE a l ...: the arm, the axis and that a value follows. */
static int expect_axis(const scn_line_t *L, scn_cmd_t *c)
{
    if (get_arm(L, 2, c) != 0 || need(L, 3, "axis") != 0 ||
        get_int(L, 3, 1, 10, &c->iv, "axis") != 0 || need(L, 4, "value") != 0) {
        return -1;
    }
    return 0;
}

/* EXPECT POS a l value tol */
static int p_expect_pos(const scn_line_t *L, scn_cmd_t *c)
{
    if (expect_axis(L, c) != 0 ||
        get_num(L, 4, -POS_MAX, POS_MAX, &c->v[0], "position [turns]") != 0 ||
        need(L, 5, "tolerance") != 0 ||
        get_num(L, 5, 0.0, POS_MAX, &c->v[1], "tolerance [turns]") != 0) {
        return -1;
    }
    c->n = 2;
    return 6;
}

/* EXPECT MODE a l mode: a mode code, compared as an integer with the packet's mode */
static int p_expect_mode(const scn_line_t *L, scn_cmd_t *c)
{
    int m;
    if (expect_axis(L, c) != 0 || get_int(L, 4, 0, 1000, &m, "mode") != 0) {
        return -1;
    }
    c->v[0] = m;
    c->n = 1;
    return 5;
}

/* EXPECT ERROR NAME|NONE */
static int p_expect_error(const scn_line_t *L, scn_cmd_t *c)
{
    if (need(L, 2, "error name (or NONE)") != 0) {
        return -1;
    }
    if (strlen(L->t[2]) >= sizeof c->name) {
        return scn_fail(L, 2, "EXPECT ERROR: name longer than %d characters", (int)sizeof c->name - 1);
    }
    strcpy(c->name, L->t[2]);
    return 3;
}

/* ---- the command table ----------------------------------------------------- */

typedef struct scn_row {
    const char *word;   /* first keyword */
    const char *word2;  /* second keyword, NULL for one-word commands */
    scn_op_t op;
    int (*parse)(const scn_line_t *L, scn_cmd_t *c);
} scn_row_t;

/* One row per command (WAIT PC twice: "WAIT PC" and "WAIT FOR PC"). */
static const scn_row_t scn_rows[] = {
    {"DRIVE", "ON", SCN_DRIVE_ON, p_drive},
    {"DRIVE", "OFF", SCN_DRIVE_OFF, p_drive},
    {"MOVE", NULL, SCN_MOVE, p_move},
    {"MOVEREL", NULL, SCN_MOVE_REL, p_move},
    {"WAIT", "MOVE", SCN_WAIT_MOVE, p_wait_move},
    {"WAIT", "PC", SCN_WAIT_PC, p_wait_pc},
    {"WAIT", "FOR", SCN_WAIT_PC, p_wait_pc},
    {"DELAY", NULL, SCN_DELAY, p_time},
    {"MODE", NULL, SCN_MODE, p_mode},
    {"CMD", NULL, SCN_CMD, p_cmd},
    {"FREEZE", NULL, SCN_FREEZE, p_time},
    {"RESTART", NULL, SCN_RESTART, p_bare},
    {"EXIT", "OPEN", SCN_EXIT_OPEN, p_two_words},
    {"OVERRIDE", NULL, SCN_OVERRIDE, p_override},
    {"SELECTOR", NULL, SCN_SELECTOR, p_selector},
    {"EXPECT", "POS", SCN_EXPECT_POS, p_expect_pos},
    {"EXPECT", "MODE", SCN_EXPECT_MODE, p_expect_mode},
    {"EXPECT", "ERROR", SCN_EXPECT_ERROR, p_expect_error},
    {"END", NULL, SCN_END, p_bare},
};

/* Two-word commands whose second word is missing or unknown. */
typedef struct scn_family {
    const char *word;
    const char *missing;  /* "missing ..." */
    const char *expected; /* "expected ...", may name the word found ('%s') */
} scn_family_t;

static const scn_family_t scn_families[] = {
    {"DRIVE", "ON or OFF", "DRIVE: expected ON or OFF, got '%s'"},
    {"WAIT", "MOVE or PC", "WAIT: expected MOVE, PC or FOR PC"},
    {"EXIT", "OPEN", "EXIT: expected OPEN"},
    {"EXPECT", "POS, MODE or ERROR", "EXPECT: expected POS, MODE or ERROR, got '%s'"},
};

static const scn_row_t *find_row(const scn_line_t *L)
{
    size_t r;
    for (r = 0; r < sizeof scn_rows / sizeof scn_rows[0]; r++) {
        const scn_row_t *row = &scn_rows[r];
        if (kw(L->t[0], row->word) && (row->word2 == NULL || (L->nt > 1 && kw(L->t[1], row->word2)))) {
            return row;
        }
    }
    return NULL;
}

/* No row: a family with a wrong or missing second word, or an unknown command. */
static int no_row(const scn_line_t *L)
{
    size_t r;
    for (r = 0; r < sizeof scn_families / sizeof scn_families[0]; r++) {
        const scn_family_t *f = &scn_families[r];
        if (kw(L->t[0], f->word)) {
            if (L->nt <= 1) {
                return scn_fail(L, -1, "%s: missing %s", L->t[0], f->missing);
            }
            return scn_fail(L, 1, f->expected, L->t[1]);
        }
    }
    return scn_fail(L, 0, "unknown command '%s'", L->t[0]);
}

/* Parse one tokenised line into c. */
static int parse_line(const scn_line_t *L, scn_cmd_t *c)
{
    const scn_row_t *row = find_row(L);
    int i;
    memset(c, 0, sizeof *c);
    c->line = (int)L->f->line;
    if (row == NULL) {
        return no_row(L);
    }
    c->op = row->op;
    i = row->parse(L, c);
    if (i < 0) {
        return -1;
    }
    if (i < L->nt) {
        return scn_fail(L, i, "%s: unexpected '%s'", scn_op_name(c->op), L->t[i]);
    }
    return 0;
}

int scn_parse(const char *path, const char *text, size_t len, scn_t *out, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    char buf[MAX_LINE];
    int r;
    out->n = 0;
    if (err != NULL && errlen > 0U) {
        err[0] = '\0';
    }
    c4gh_tf_open_mem(&f, path, text, len);
    while ((r = c4gh_tf_next_line(&f, buf, sizeof buf, err, errlen)) > 0) {
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
                return c4gh_tf_error(&f, (size_t)(p - buf) + 1U, err, errlen, "more than %d words", MAX_TOK);
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
            return c4gh_tf_error(&f, 1U, err, errlen, "more than %d commands", SCN_MAX_CMDS);
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
