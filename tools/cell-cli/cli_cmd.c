/* SPDX-License-Identifier: MIT */
/* cell-cli command language (see cli_cmd.h and docs/cell-cli.md). */
#include "cli_cmd.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "cell_common.h"

#define MAX_WORDS 12

static int errf(char *err, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, cap, fmt, ap);
    va_end(ap);
    return -1;
}

static int split_words(char *s, char **w, int max)
{
    int n = 0;
    char *p = s;
    while (*p != '\0') {
        while (*p != '\0' && isspace((unsigned char)*p)) {
            p++;
        }
        if (*p == '\0' || *p == '#') {
            break;
        }
        if (n == max) {
            return -1;
        }
        w[n++] = p;
        while (*p != '\0' && !isspace((unsigned char)*p)) {
            p++;
        }
        if (*p != '\0') {
            *p++ = '\0';
        }
    }
    return n;
}

static const struct {
    const char *word;
    c4g_cell_cmd_t cmd;
} k_simple[] = {
    {"sta", C4G_CELL_CMD_STA},   {"status", C4G_CELL_CMD_STA}, {"srvon", C4G_CELL_CMD_SRVON},
    {"srvof", C4G_CELL_CMD_SRVOF}, {"srvoff", C4G_CELL_CMD_SRVOF}, {"stp", C4G_CELL_CMD_STP},
    {"stop", C4G_CELL_CMD_STP},  {"rst", C4G_CELL_CMD_RST},    {"reset", C4G_CELL_CMD_RST},
    {"clo", C4G_CELL_CMD_CLO},   {"close", C4G_CELL_CMD_CLO},  {"itr", C4G_CELL_CMD_ITR},
};

static int parse_value(const char *s, c4g_cell_unit_t unit, int32_t *out, const char *what,
                       char *err, size_t cap)
{
    c4g_status_t st = c4g_cell_from_text(s, strlen(s), unit, out);
    if (st == C4G_ERR_CELL_RANGE) {
        return errf(err, cap, "%s=%s is out of range (%s)", what, s,
                    unit == C4G_CELL_UNIT_MM ? "+-999.999 mm"
                    : unit == C4G_CELL_UNIT_RAD ? "+-99.9999 rad" : "+-99999");
    }
    if (st != C4G_OK) {
        return errf(err, cap, "%s: not a number: '%s'", what, s);
    }
    return 0;
}

/* key=value pose for a device; absolute moves need every axis. */
static int parse_pose(int dev, char **w, int n, int need_all, c4g_cell_instr_t *in, char *err,
                      size_t cap)
{
    static const char *const rk[5] = {"x", "y", "z", "c", "clear"};
    static const char *const pk[2] = {"a", "b"};
    int seen[5] = {0};
    int nk = dev == CELL_DEV_ROBOT ? 4 : 2;
    int allow_clear = in->cmd == C4G_CELL_CMD_PNP;
    in->pose.n_axes = (uint32_t)nk;
    for (int i = 0; i < n; i++) {
        char *eq = strchr(w[i], '=');
        int k = -1;
        if (eq == NULL) {
            return errf(err, cap, "expected key=value, got '%s'", w[i]);
        }
        *eq = '\0';
        for (int j = 0; j < (dev == CELL_DEV_ROBOT ? 4 + allow_clear : 2); j++) {
            if (strcasecmp(w[i], dev == CELL_DEV_ROBOT ? rk[j] : pk[j]) == 0) {
                k = j;
            }
        }
        if (k < 0) {
            return errf(err, cap, "unknown axis '%s' for the %s (use %s)", w[i],
                        cell_dev_name(dev),
                        dev == CELL_DEV_ROBOT ? (allow_clear ? "clear, x, y, z, c" : "x, y, z, c")
                                              : "a, b");
        }
        if (seen[k]) {
            return errf(err, cap, "axis '%s' given twice", w[i]);
        }
        seen[k] = 1;
        c4g_cell_unit_t u = (dev == CELL_DEV_ROBOT && k != 3) ? C4G_CELL_UNIT_MM : C4G_CELL_UNIT_RAD;
        int32_t *dst = k == 4 ? &in->clearance : &in->pose.v[k];
        if (parse_value(eq + 1, u, dst, w[i], err, cap) != 0) {
            return -1;
        }
    }
    if (need_all) {
        for (int j = 0; j < nk + allow_clear; j++) {
            if (!seen[j]) {
                return errf(err, cap, "missing %s= (absolute targets need every axis)",
                            dev == CELL_DEV_ROBOT ? rk[j] : pk[j]);
            }
        }
    }
    return 0;
}

static int parse_int_arg(const char *s, int32_t lo, int32_t hi, const char *what, int32_t *out,
                         char *err, size_t cap)
{
    int32_t v;
    if (s == NULL) {
        return errf(err, cap, "missing %s", what);
    }
    if (c4g_cell_from_text(s, strlen(s), C4G_CELL_UNIT_INT, &v) != C4G_OK ||
        strchr(s, '.') != NULL || v < lo || v > hi) {
        return errf(err, cap, "%s must be an integer %d..%d, got '%s'", what, (int)lo, (int)hi, s);
    }
    *out = v;
    return 0;
}

static int parse_device_cmd(int dev, char **w, int n, cli_cmd_t *out, char *err, size_t cap)
{
    c4g_cell_instr_t *in = &out->instr;
    const char *verb = n > 1 ? w[1] : NULL;
    memset(in, 0, sizeof *in);
    if (verb == NULL) {
        return errf(err, cap, "missing command after '%s' (try: help)", w[0]);
    }
    out->kind = CLI_SEND;
    out->dev = dev;
    for (size_t i = 0; i < sizeof k_simple / sizeof k_simple[0]; i++) {
        if (strcasecmp(verb, k_simple[i].word) == 0) {
            if (n > 2) {
                return errf(err, cap, "'%s' takes no arguments", verb);
            }
            in->cmd = k_simple[i].cmd;
            return 0;
        }
    }
    if (strcasecmp(verb, "servo") == 0) {
        if (n != 3 || (strcasecmp(w[2], "on") != 0 && strcasecmp(w[2], "off") != 0)) {
            return errf(err, cap, "usage: %s servo on|off", w[0]);
        }
        in->cmd = strcasecmp(w[2], "on") == 0 ? C4G_CELL_CMD_SRVON : C4G_CELL_CMD_SRVOF;
        return 0;
    }
    if (strcasecmp(verb, "ovr") == 0 || strcasecmp(verb, "override") == 0) {
        in->cmd = C4G_CELL_CMD_OVR;
        if (n > 3) {
            return errf(err, cap, "usage: %s ovr PERCENT", w[0]);
        }
        return parse_int_arg(n > 2 ? w[2] : NULL, 0, 100, "override (percent)", &in->value, err,
                             cap);
    }
    if (strcasecmp(verb, "acq") == 0) {
        in->cmd = C4G_CELL_CMD_ACQ;
        if (n > 3) {
            return errf(err, cap, "usage: %s acq CAMERA", w[0]);
        }
        return parse_int_arg(n > 2 ? w[2] : NULL, 0, 99999, "camera id", &in->value, err, cap);
    }
    if (strcasecmp(verb, "hnd") == 0 || strcasecmp(verb, "gripper") == 0) {
        in->cmd = C4G_CELL_CMD_HND;
        if (n != 4 || (strcasecmp(w[3], "open") != 0 && strcasecmp(w[3], "close") != 0)) {
            return errf(err, cap, "usage: %s hnd GRIPPER open|close", w[0]);
        }
        in->open = strcasecmp(w[3], "open") == 0;
        return parse_int_arg(w[2], 0, 99999, "gripper id", &in->value, err, cap);
    }
    if (strcasecmp(verb, "mov") == 0 || strcasecmp(verb, "move") == 0) {
        in->cmd = C4G_CELL_CMD_MOV;
        if (dev == CELL_DEV_CONDITIONING) {
            return errf(err, cap, "the conditioning controller has no axes");
        }
        if (n < 3 || (strcasecmp(w[2], "abs") != 0 && strcasecmp(w[2], "rel") != 0)) {
            return errf(err, cap, "usage: %s mov abs|rel %s", w[0],
                        dev == CELL_DEV_ROBOT ? "x=MM y=MM z=MM c=RAD" : "a=RAD b=RAD");
        }
        in->relative = strcasecmp(w[2], "rel") == 0;
        return parse_pose(dev, w + 3, n - 3, !in->relative, in, err, cap);
    }
    if (strcasecmp(verb, "pnp") == 0) {
        in->cmd = C4G_CELL_CMD_PNP;
        if (dev != CELL_DEV_ROBOT) {
            return errf(err, cap, "pnp is a robot command");
        }
        return parse_pose(dev, w + 2, n - 2, 1, in, err, cap);
    }
    return errf(err, cap, "unknown command '%s' for the %s (try: help)", verb, cell_dev_name(dev));
}

int cli_parse(const char *text, cli_cmd_t *out, char *err, size_t err_cap)
{
    char buf[512];
    char *w[MAX_WORDS];
    int n;
    memset(out, 0, sizeof *out);
    out->dev = -1;
    if (strlen(text) >= sizeof buf) {
        return errf(err, err_cap, "command too long");
    }
    strcpy(buf, text);
    /* raw keeps the text after the device verbatim (spaces included) */
    {
        const char *p = text;
        while (isspace((unsigned char)*p)) {
            p++;
        }
        if (strncasecmp(p, "raw", 3) == 0 && (p[3] == '\0' || isspace((unsigned char)p[3]))) {
            char devw[32];
            size_t dl = 0;
            p += 3;
            while (isspace((unsigned char)*p)) {
                p++;
            }
            while (p[dl] != '\0' && !isspace((unsigned char)p[dl]) && dl < sizeof devw - 1) {
                devw[dl] = p[dl];
                dl++;
            }
            devw[dl] = '\0';
            out->dev = cell_dev_parse(devw);
            if (out->dev < 0) {
                return errf(err, err_cap, "usage: raw robot|platform|conditioning TEXT");
            }
            p += dl;
            if (isspace((unsigned char)*p)) {
                p++;
            }
            size_t tl = strlen(p);
            while (tl > 0 && (p[tl - 1] == '\n' || p[tl - 1] == '\r')) {
                tl--;
            }
            if (tl + 2 > sizeof out->line) {
                return errf(err, err_cap, "raw text too long");
            }
            memcpy(out->line, p, tl);
            out->line[tl] = '\r';
            out->line[tl + 1] = '\n';
            out->len = tl + 2;
            out->kind = CLI_RAW;
            return 0;
        }
    }
    n = split_words(buf, w, MAX_WORDS);
    if (n < 0) {
        return errf(err, err_cap, "too many words");
    }
    if (n == 0) {
        out->kind = CLI_EMPTY;
        return 0;
    }
    if (strcasecmp(w[0], "quit") == 0 || strcasecmp(w[0], "exit") == 0) {
        out->kind = CLI_QUIT;
        return 0;
    }
    if (strcasecmp(w[0], "help") == 0 || strcmp(w[0], "?") == 0) {
        out->kind = CLI_HELP;
        snprintf(out->topic, sizeof out->topic, "%s", n > 1 ? w[1] : "");
        return 0;
    }
    if (strcasecmp(w[0], "sleep") == 0) {
        out->kind = CLI_SLEEP;
        if (n != 2 || cell_parse_double(w[1], &out->seconds) != 0 || out->seconds < 0 ||
            out->seconds > 3600) {
            return errf(err, err_cap, "usage: sleep SECONDS (0..3600)");
        }
        return 0;
    }
    if (strcasecmp(w[0], "wait") == 0) {
        out->kind = CLI_WAIT;
        out->seconds = 60.0;
        if (n < 3 || n > 4 || (out->dev = cell_dev_parse(w[1])) < 0 ||
            out->dev == CELL_DEV_CONDITIONING || strcasecmp(w[2], "stopped") != 0 ||
            (n == 4 && (cell_parse_double(w[3], &out->seconds) != 0 || out->seconds <= 0))) {
            return errf(err, err_cap, "usage: wait robot|platform stopped [TIMEOUT_SECONDS]");
        }
        return 0;
    }
    int dev = cell_dev_parse(w[0]);
    if (dev < 0) {
        return errf(err, err_cap, "unknown device or command '%s' (try: help)", w[0]);
    }
    if (parse_device_cmd(dev, w, n, out, err, err_cap) != 0) {
        return -1;
    }
    c4g_status_t st = c4g_cell_instr_encode(&out->instr, out->line, sizeof out->line,
                                                 &out->len);
    if (st != C4G_OK) {
        return errf(err, err_cap, "cannot encode: %s", c4g_strerror(st));
    }
    return 0;
}

static const struct {
    const char *topic;
    const char *text;
} k_help[] = {
    {"sta", "DEV sta            status: moving flag, position, servo, override, error (STA)"},
    {"srvon", "DEV srvon | DEV servo on     switch the servo motors on (SRVON)"},
    {"srvof", "DEV srvof | DEV servo off    switch the servo motors off (SRVOF)"},
    {"ovr", "DEV ovr PERCENT    set the override 0..100 % (OVR), e.g. robot ovr 50"},
    {"mov", "robot mov abs|rel x=MM y=MM z=MM c=RAD    point-to-point motion (MOVA/MOVR)\n"
            "platform mov abs|rel a=RAD b=RAD          absolute needs every axis;\n"
            "                                          relative axes default to 0"},
    {"pnp", "robot pnp clear=MM x=MM y=MM z=MM c=RAD  pick-and-place (project extension PNP):\n"
            "                                          lift to Z=clear, travel, descend"},
    {"stp", "DEV stp            stop the motion (STP)"},
    {"itr", "DEV itr            interrupt the motion (project extension ITR, as STP)"},
    {"rst", "DEV rst            reset: stop, clear the error, home if the servo is on (RST)"},
    {"clo", "DEV clo            ask the device to close the connection (CLO)"},
    {"acq", "conditioning acq CAMERA         acquire an image (ACQ), cameras 1..2 on cell-sim"},
    {"hnd", "conditioning hnd ID open|close  gripper valve (HND): 0 vacuum, 1 blow"},
    {"raw", "raw DEV TEXT       send TEXT + CR LF unchanged, e.g. raw robot OVR+00050"},
    {"wait", "wait DEV stopped [TIMEOUT]  poll STA until the device has stopped (default 60 s)"},
    {"sleep", "sleep SECONDS      pause (scripts)"},
    {"quit", "quit | exit        leave the REPL"},
};

int cli_help(const char *topic, char *out, size_t cap)
{
    size_t o = 0;
    if (topic == NULL || topic[0] == '\0') {
        o += (size_t)snprintf(out + o, cap - o,
                              "Devices: robot (port 2001), platform (2002), conditioning (2003);\n"
                              "any unique prefix works (r, p, c). Commands:\n");
        for (size_t i = 0; i < sizeof k_help / sizeof k_help[0] && o < cap; i++) {
            o += (size_t)snprintf(out + o, cap - o, "  %s\n", k_help[i].text);
        }
        if (o < cap) {
            snprintf(out + o, cap - o, "help COMMAND shows one command; replies ER+nnnnn are "
                                       "explained with the spec's meaning.\n");
        }
        return 0;
    }
    for (size_t i = 0; i < sizeof k_help / sizeof k_help[0]; i++) {
        if (strcasecmp(topic, k_help[i].topic) == 0 ||
            (strcasecmp(topic, "srvoff") == 0 && strcmp(k_help[i].topic, "srvof") == 0) ||
            (strcasecmp(topic, "servo") == 0 && strcmp(k_help[i].topic, "srvon") == 0)) {
            snprintf(out, cap, "%s\n", k_help[i].text);
            return 0;
        }
    }
    snprintf(out, cap, "no help for '%s' (try: help)\n", topic);
    return -1;
}

const char *const *cli_words(int word, const char *first, const char *second)
{
    static const char *const w0[] = {"robot", "platform", "conditioning", "raw", "wait",
                                     "sleep", "help", "quit", NULL};
    static const char *const devs[] = {"robot", "platform", "conditioning", NULL};
    static const char *const motion_devs[] = {"robot", "platform", NULL};
    static const char *const robot_cmds[] = {"sta", "srvon", "srvof", "ovr", "mov", "pnp", "stp",
                                             "itr", "rst", "clo", NULL};
    static const char *const plat_cmds[] = {"sta", "srvon", "srvof", "ovr", "mov", "stp", "itr",
                                            "rst", "clo", NULL};
    static const char *const cond_cmds[] = {"acq", "hnd", "rst", "clo", NULL};
    static const char *const absrel[] = {"abs", "rel", NULL};
    static const char *const stopped[] = {"stopped", NULL};
    static const char *const topics[] = {"sta", "srvon", "srvof", "ovr", "mov", "pnp", "stp",
                                         "itr", "rst", "clo", "acq", "hnd", "raw", "wait",
                                         "sleep", "quit", NULL};
    static const char *const robot_keys[] = {"x=", "y=", "z=", "c=", NULL};
    static const char *const pnp_keys[] = {"clear=", "x=", "y=", "z=", "c=", NULL};
    static const char *const plat_keys[] = {"a=", "b=", NULL};
    static const char *const openclose[] = {"open", "close", NULL};
    int dev;
    if (word == 0) {
        return w0;
    }
    if (strcasecmp(first, "raw") == 0) {
        return word == 1 ? devs : NULL;
    }
    if (strcasecmp(first, "wait") == 0) {
        return word == 1 ? motion_devs : word == 2 ? stopped : NULL;
    }
    if (strcasecmp(first, "help") == 0) {
        return word == 1 ? topics : NULL;
    }
    dev = cell_dev_parse(first);
    if (dev < 0) {
        return NULL;
    }
    if (word == 1) {
        return dev == CELL_DEV_ROBOT ? robot_cmds : dev == CELL_DEV_PLATFORM ? plat_cmds : cond_cmds;
    }
    if (second != NULL && strcasecmp(second, "mov") == 0) {
        return word == 2 ? absrel : dev == CELL_DEV_ROBOT ? robot_keys : plat_keys;
    }
    if (second != NULL && strcasecmp(second, "pnp") == 0 && dev == CELL_DEV_ROBOT) {
        return pnp_keys;
    }
    if (second != NULL && strcasecmp(second, "hnd") == 0 && word == 3) {
        return openclose;
    }
    return NULL;
}
