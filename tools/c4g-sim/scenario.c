/* SPDX-License-Identifier: MIT */
/* c4g-sim scenario parser. Grammar (one command per line, '#' starts a comment,
 * keywords case-insensitive) is documented in docs/c4g-sim.md. */
#include "scenario.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
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

static int scn_fail(char *err, size_t errlen, int line, const char *fmt, ...)
{
    va_list ap;
    char msg[256];
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (err != NULL && errlen > 0U) {
        snprintf(err, errlen, "line %d: %s", line, msg);
    }
    return -1;
}

static int kw(const char *tok, const char *word)
{
    return tok != NULL && strcasecmp(tok, word) == 0;
}

static int parse_num(const char *s, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(v)) {
        return -1;
    }
    *out = v;
    return 0;
}

static int parse_int(const char *s, long lo, long hi, int *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 0);
    if (end == s || *end != '\0' || errno != 0 || v < lo || v > hi) {
        return -1;
    }
    *out = (int)v;
    return 0;
}

/* Parse one tokenised line into c. */
static int parse_line(char **t, int nt, scn_cmd_t *c, int line, char *err, size_t errlen)
{
    int i = 1;
    memset(c, 0, sizeof *c);
    c->line = line;
#define NEED(k, what) do { if (nt <= (k)) return scn_fail(err, errlen, line, "%s: missing %s", t[0], what); } while (0)
#define ARM(k) do { NEED(k, "arm"); if (parse_int(t[k], 1, 4, &c->arm) != 0) \
        return scn_fail(err, errlen, line, "arm '%s' is not 1..4", t[k]); } while (0)
    if (kw(t[0], "DRIVE")) {
        NEED(1, "ON or OFF");
        if (kw(t[1], "ON")) {
            c->op = SCN_DRIVE_ON;
        } else if (kw(t[1], "OFF")) {
            c->op = SCN_DRIVE_OFF;
        } else {
            return scn_fail(err, errlen, line, "DRIVE: expected ON or OFF, got '%s'", t[1]);
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
            if (kw(t[i], "NOWAIT")) {
                c->nowait = 1;
                i++;
                break;
            }
            if (c->n >= SCN_MAX_VALUES) {
                return scn_fail(err, errlen, line, "%s: more than %d targets", t[0], SCN_MAX_VALUES);
            }
            if (parse_num(t[i], &c->v[c->n]) != 0) {
                return scn_fail(err, errlen, line, "%s: target %d '%s' is not a number", t[0], c->n + 1, t[i]);
            }
            c->n++;
        }
        if (c->n == 0) {
            return scn_fail(err, errlen, line, "%s: no targets", t[0]);
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
                return scn_fail(err, errlen, line, "WAIT: expected MOVE, PC or FOR PC");
            }
            c->op = SCN_WAIT_PC;
            i++;
            ARM(i);
            i++;
            if (nt > i && kw(t[i], "TIMEOUT")) {
                NEED(i + 1, "timeout [ms]");
                if (parse_num(t[i + 1], &c->ms) != 0 || c->ms < 0.0) {
                    return scn_fail(err, errlen, line, "WAIT PC: bad timeout '%s'", t[i + 1]);
                }
                i += 2;
            }
        }
    } else if (kw(t[0], "DELAY") || kw(t[0], "FREEZE")) {
        c->op = kw(t[0], "DELAY") ? SCN_DELAY : SCN_FREEZE;
        NEED(1, "time [ms]");
        if (parse_num(t[1], &c->ms) != 0 || c->ms < 0.0 || c->ms > 3.6e6) {
            return scn_fail(err, errlen, line, "%s: bad time '%s' (ms, 0..3600000)", t[0], t[1]);
        }
        i = 2;
    } else if (kw(t[0], "MODE")) {
        c->op = SCN_MODE;
        ARM(1);
        NEED(2, "mode");
        if (parse_int(t[2], 0, 1000, &c->iv) != 0) {
            return scn_fail(err, errlen, line, "MODE: bad mode '%s'", t[2]);
        }
        i = 3;
        if (nt > 3 && kw(t[3], "AXES")) {
            for (i = 4; i < nt; i++) {
                int ax;
                if (parse_int(t[i], 1, 10, &ax) != 0) {
                    return scn_fail(err, errlen, line, "MODE: axis '%s' is not 1..10", t[i]);
                }
                c->axes_mask |= 1U << (ax - 1);
            }
            if (c->axes_mask == 0U) {
                return scn_fail(err, errlen, line, "MODE: AXES without axes");
            }
        }
    } else if (kw(t[0], "CMD")) {
        c->op = SCN_CMD;
        ARM(1);
        NEED(2, "value");
        if (parse_int(t[2], 0, 255, &c->iv) != 0) {
            return scn_fail(err, errlen, line, "CMD: value '%s' is not 0..255", t[2]);
        }
        i = 3;
    } else if (kw(t[0], "RESTART")) {
        c->op = SCN_RESTART;
    } else if (kw(t[0], "EXIT")) {
        NEED(1, "OPEN");
        if (!kw(t[1], "OPEN")) {
            return scn_fail(err, errlen, line, "EXIT: expected OPEN");
        }
        c->op = SCN_EXIT_OPEN;
        i = 2;
    } else if (kw(t[0], "OVERRIDE")) {
        c->op = SCN_OVERRIDE;
        NEED(1, "percent");
        if (parse_num(t[1], &c->ms) != 0 || c->ms < 0.0 || c->ms > 100.0) {
            return scn_fail(err, errlen, line, "OVERRIDE: '%s' is not 0..100", t[1]);
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
            return scn_fail(err, errlen, line, "SELECTOR: expected AUTO or PROG, got '%s'", t[1]);
        }
        i = 2;
    } else if (kw(t[0], "EXPECT")) {
        NEED(1, "POS, MODE or ERROR");
        if (kw(t[1], "POS") || kw(t[1], "MODE")) {
            const int pos = kw(t[1], "POS");
            c->op = pos ? SCN_EXPECT_POS : SCN_EXPECT_MODE;
            ARM(2);
            NEED(3, "axis");
            if (parse_int(t[3], 1, 10, &c->iv) != 0) {
                return scn_fail(err, errlen, line, "EXPECT: axis '%s' is not 1..10", t[3]);
            }
            NEED(4, "value");
            if (parse_num(t[4], &c->v[0]) != 0) {
                return scn_fail(err, errlen, line, "EXPECT: value '%s' is not a number", t[4]);
            }
            c->n = 1;
            i = 5;
            if (pos) {
                NEED(5, "tolerance");
                if (parse_num(t[5], &c->v[1]) != 0 || c->v[1] < 0.0) {
                    return scn_fail(err, errlen, line, "EXPECT POS: bad tolerance '%s'", t[5]);
                }
                c->n = 2;
                i = 6;
            }
        } else if (kw(t[1], "ERROR")) {
            c->op = SCN_EXPECT_ERROR;
            NEED(2, "error name (or NONE)");
            if (strlen(t[2]) >= sizeof c->name) {
                return scn_fail(err, errlen, line, "EXPECT ERROR: name too long");
            }
            strcpy(c->name, t[2]);
            i = 3;
        } else {
            return scn_fail(err, errlen, line, "EXPECT: expected POS, MODE or ERROR, got '%s'", t[1]);
        }
    } else if (kw(t[0], "END")) {
        c->op = SCN_END;
    } else {
        return scn_fail(err, errlen, line, "unknown command '%s'", t[0]);
    }
    if (i < nt) {
        return scn_fail(err, errlen, line, "%s: unexpected '%s'", scn_op_name(c->op), t[i]);
    }
#undef NEED
#undef ARM
    return 0;
}

int scn_parse(const char *text, size_t len, scn_t *out, char *err, size_t errlen)
{
    size_t pos = 0;
    int line = 0;
    out->n = 0;
    if (err != NULL && errlen > 0U) {
        err[0] = '\0';
    }
    while (pos < len) {
        char buf[MAX_LINE];
        char *tok[MAX_TOK];
        int nt = 0;
        size_t k = 0;
        char *p;
        line++;
        while (pos < len && text[pos] != '\n') {
            if (text[pos] == '\0') {
                return scn_fail(err, errlen, line, "NUL byte in the scenario");
            }
            if (k + 1U >= sizeof buf) {
                return scn_fail(err, errlen, line, "line longer than %d characters", MAX_LINE - 1);
            }
            buf[k++] = text[pos++];
        }
        pos++; /* the newline */
        buf[k] = '\0';
        p = strchr(buf, '#');
        if (p != NULL) {
            *p = '\0';
        }
        p = buf;
        for (;;) {
            while (*p != '\0' && isspace((unsigned char)*p)) {
                p++;
            }
            if (*p == '\0') {
                break;
            }
            if (nt >= MAX_TOK) {
                return scn_fail(err, errlen, line, "more than %d words", MAX_TOK);
            }
            tok[nt++] = p;
            while (*p != '\0' && !isspace((unsigned char)*p)) {
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
            return scn_fail(err, errlen, line, "more than %d commands", SCN_MAX_CMDS);
        }
        if (parse_line(tok, nt, &out->cmd[out->n], line, err, errlen) != 0) {
            return -1;
        }
        out->n++;
    }
    return 0;
}
