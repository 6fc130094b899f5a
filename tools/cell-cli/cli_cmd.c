/* SPDX-License-Identifier: MIT */
/* cell-cli command language (see cli_cmd.h and docs/cell-cli.md). The device commands are
 * the rows of the library's command table; nothing here names one of them. */
#include "cli_cmd.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "c4gh_cell.h"

#define MAX_WORDS 12
#define WORD_MAX 32 /* longest command word of the table, NUL included */

/* One row of C4G_CELL_COMMANDS as the command language needs it. */
typedef struct cmd_row {
    c4g_cell_cmd_t cmd;
    c4g_cell_args_t args;
    int32_t lo, hi;
    unsigned devices;
    const char *words; /* "stp|stop", "srvon|servo on" */
    const char *arg;   /* usage placeholder of the integer argument */
    const char *what;  /* its name in messages */
    const char *help;
} cmd_row_t;

#define CLI_X_ROW(cmd, head, args, lo, hi, reply, devices, words, arg, what, help) \
    {(cmd), (args), (lo), (hi), (devices), (words), (arg), (what), (help)},
static const cmd_row_t k_rows[] = {C4G_CELL_COMMANDS(CLI_X_ROW)};
#undef CLI_X_ROW
#define N_ROWS (sizeof k_rows / sizeof k_rows[0])

/* The commands of the tool itself (after the device commands in the help). */
static const struct {
    const char *topic;
    const char *text;
} k_tool_help[] = {
    {"raw", "raw DEV TEXT       send TEXT + CR LF unchanged, e.g. raw robot OVR+00050"},
    {"wait", "wait DEV stopped [TIMEOUT]  poll STA until the device has stopped (default 60 s)"},
    {"sleep", "sleep SECONDS      pause (scripts)"},
    {"clear", "clear              clear the screen (REPL)"},
    {"connect", "connect HOST [PORT]  talk to the devices on HOST: robot PORT, platform PORT+1,\n"
                "                   conditioning PORT+2 (no PORT: the ports in use);\n"
                "connect DEV HOST[:PORT]  one device elsewhere"},
    {"N", "N COMMAND          run COMMAND N times (1.." "100000), stopping at the first failure,\n"
          "                   e.g. 5 robot sta"},
    {"quit", "quit | exit        leave the REPL"},
};
#define N_TOOL_HELP (sizeof k_tool_help / sizeof k_tool_help[0])

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

/* ------------------------------------------------------------------ the table's words */

/* One alternative of a row's words: first word and optional second word. */
typedef struct alt {
    char first[WORD_MAX];
    char second[WORD_MAX];
} alt_t;

/* The k-th alternative of words into a; 0 when there is none. */
static int alt_get(const char *words, int k, alt_t *a)
{
    const char *p = words;
    size_t n, sp;
    for (int i = 0; i < k; i++) {
        p = strchr(p, '|');
        if (p == NULL) {
            return 0;
        }
        p++;
    }
    n = strcspn(p, "|");
    sp = strcspn(p, " |");
    snprintf(a->first, sizeof a->first, "%.*s", (int)sp, p);
    a->second[0] = '\0';
    if (sp < n) {
        snprintf(a->second, sizeof a->second, "%.*s", (int)(n - sp - 1), p + sp + 1);
    }
    return 1;
}

/* The primary (first) word of a row. */
static const char *primary(const cmd_row_t *r, char *buf, size_t cap)
{
    snprintf(buf, cap, "%.*s", (int)strcspn(r->words, "|"), r->words);
    return buf;
}

/* The row for verb [next]: *used 1 or 2 words. *partial is set when verb starts a
 * two-word alternative whose second word does not follow. */
static const cmd_row_t *row_find(const char *verb, const char *next, int *used, int *partial)
{
    alt_t a;
    *partial = 0;
    for (size_t i = 0; i < N_ROWS; i++) {
        for (int k = 0; alt_get(k_rows[i].words, k, &a); k++) {
            if (strcasecmp(a.first, verb) != 0) {
                continue;
            }
            if (a.second[0] == '\0') {
                *used = 1;
                return &k_rows[i];
            }
            *partial = 1;
            if (next != NULL && strcasecmp(a.second, next) == 0) {
                *used = 2;
                return &k_rows[i];
            }
        }
    }
    return NULL;
}

/* "servo on|off": verb and the second words of its two-word alternatives. */
static void two_word_usage(const char *verb, char *buf, size_t cap)
{
    alt_t a;
    size_t o = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < N_ROWS && o < cap; i++) {
        for (int k = 0; alt_get(k_rows[i].words, k, &a) && o < cap; k++) {
            if (a.second[0] != '\0' && strcasecmp(a.first, verb) == 0) {
                if (o == 0) {
                    o = (size_t)snprintf(buf, cap, "%s %s", a.first, a.second);
                } else {
                    o += (size_t)snprintf(buf + o, cap - o, "|%s", a.second);
                }
            }
        }
    }
}

/* Is w the first word of one of the row's alternatives? */
static int row_has_word(const cmd_row_t *r, const char *w)
{
    alt_t a;
    for (int k = 0; alt_get(r->words, k, &a); k++) {
        if (strcasecmp(a.first, w) == 0) {
            return 1;
        }
    }
    return 0;
}

/* ------------------------------------------------------------------ arguments */

static int parse_value(const char *s, c4g_cell_unit_t unit, int32_t *out, const char *what,
                       char *err, size_t cap)
{
    c4g_status_t st = c4g_cell_from_text(s, strlen(s), unit, out);
    if (st == C4G_ERR_RANGE) {
        return errf(err, cap, "%s=%s is out of range (%s)", what, s,
                    unit == C4G_CELL_UNIT_MM ? "+-999.999 mm"
                    : unit == C4G_CELL_UNIT_RAD ? "+-99.9999 rad" : "+-99999");
    }
    if (st != C4G_OK) {
        return errf(err, cap, "%s: not a number: '%s'", what, s);
    }
    return 0;
}

/* Pose keys: robot x y z c (and clear, the PNP clearance, as index 4); platform a b. */
static const char *pose_key(int dev, int j)
{
    static const char *const rk[5] = {"x", "y", "z", "c", "clear"};
    static const char *const pk[2] = {"a", "b"};
    return dev == C4GH_CELL_DEV_ROBOT ? rk[j] : pk[j];
}

/* Index of key k, -1 if the device (with or without a clearance) has none. */
static int pose_key_index(int dev, int clear, const char *k)
{
    int nk = dev == C4GH_CELL_DEV_ROBOT ? 4 + clear : 2;
    for (int j = 0; j < nk; j++) {
        if (strcasecmp(k, pose_key(dev, j)) == 0) {
            return j;
        }
    }
    return -1;
}

/* One key=value of a pose; seen[] marks the keys given. */
static int parse_pose_word(int dev, int clear, char *word, int *seen, c4g_cell_instr_t *in,
                           char *err, size_t cap)
{
    char *eq = strchr(word, '=');
    int k;
    if (eq == NULL) {
        return errf(err, cap, "expected key=value, got '%s'", word);
    }
    *eq = '\0';
    k = pose_key_index(dev, clear, word);
    if (k < 0) {
        return errf(err, cap, "unknown axis '%s' for the %s (use %s)", word, c4gh_cell_dev_name(dev),
                    dev == C4GH_CELL_DEV_ROBOT ? (clear ? "clear, x, y, z, c" : "x, y, z, c")
                                          : "a, b");
    }
    if (seen[k]) {
        return errf(err, cap, "axis '%s' given twice", word);
    }
    seen[k] = 1;
    c4g_cell_unit_t u = (dev == C4GH_CELL_DEV_ROBOT && k != 3) ? C4G_CELL_UNIT_MM : C4G_CELL_UNIT_RAD;
    return parse_value(eq + 1, u, k == 4 ? &in->clearance : &in->pose.v[k], word, err, cap);
}

/* key=value pose for a device; absolute moves need every axis. */
static int parse_pose(int dev, int clear, char **w, int n, int need_all, c4g_cell_instr_t *in,
                      char *err, size_t cap)
{
    int seen[5] = {0};
    int nk = dev == C4GH_CELL_DEV_ROBOT ? 4 : 2;
    in->pose.n_axes = (uint32_t)nk;
    for (int i = 0; i < n; i++) {
        if (parse_pose_word(dev, clear, w[i], seen, in, err, cap) != 0) {
            return -1;
        }
    }
    for (int j = 0; need_all && j < nk + clear; j++) {
        if (!seen[j]) {
            return errf(err, cap, "missing %s= (absolute targets need every axis)",
                        pose_key(dev, j));
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

/* The arguments w[first..n) of a row's layout. */
static int parse_args(const cmd_row_t *r, int dev, char **w, int n, int first,
                      c4g_cell_instr_t *in, char *err, size_t cap)
{
    char pw[WORD_MAX];
    switch (r->args) {
    case C4G_CELL_ARGS_INT:
        if (n > first + 1) {
            return errf(err, cap, "usage: %s %s %s", w[0], primary(r, pw, sizeof pw), r->arg);
        }
        return parse_int_arg(n > first ? w[first] : NULL, r->lo, r->hi, r->what, &in->value, err,
                             cap);
    case C4G_CELL_ARGS_INT_ACTION:
        if (n != first + 2 ||
            (strcasecmp(w[first + 1], "open") != 0 && strcasecmp(w[first + 1], "close") != 0)) {
            return errf(err, cap, "usage: %s %s %s open|close", w[0], primary(r, pw, sizeof pw),
                        r->arg);
        }
        in->open = strcasecmp(w[first + 1], "open") == 0;
        return parse_int_arg(w[first], r->lo, r->hi, r->what, &in->value, err, cap);
    case C4G_CELL_ARGS_MODE_POSE:
        if (dev == C4GH_CELL_DEV_CONDITIONING) {
            return errf(err, cap, "the conditioning controller has no axes");
        }
        if (n <= first ||
            (strcasecmp(w[first], "abs") != 0 && strcasecmp(w[first], "rel") != 0)) {
            return errf(err, cap, "usage: %s %s abs|rel %s", w[0], primary(r, pw, sizeof pw),
                        dev == C4GH_CELL_DEV_ROBOT ? "x=MM y=MM z=MM c=RAD" : "a=RAD b=RAD");
        }
        in->relative = strcasecmp(w[first], "rel") == 0;
        return parse_pose(dev, 0, w + first + 1, n - first - 1, !in->relative, in, err, cap);
    case C4G_CELL_ARGS_CLEAR_POSE:
        if (dev != C4GH_CELL_DEV_ROBOT) {
            return errf(err, cap, "%s is a robot command", primary(r, pw, sizeof pw));
        }
        return parse_pose(dev, 1, w + first, n - first, 1, in, err, cap);
    case C4G_CELL_ARGS_NONE:
    default:
        if (n > first) {
            return errf(err, cap, "'%s' takes no arguments", w[1]);
        }
        return 0;
    }
}

static int parse_device_cmd(int dev, char **w, int n, cli_cmd_t *out, char *err, size_t cap)
{
    c4g_cell_instr_t *in = &out->instr;
    const cmd_row_t *r;
    int used = 1, partial = 0;
    char usage[96];
    memset(in, 0, sizeof *in);
    if (n < 2) {
        return errf(err, cap, "missing command after '%s' (try: help)", w[0]);
    }
    out->kind = CMD_SEND;
    out->dev = dev;
    r = row_find(w[1], n > 2 ? w[2] : NULL, &used, &partial);
    if ((r == NULL && partial) || (r != NULL && used == 2 && n != 3)) {
        two_word_usage(w[1], usage, sizeof usage);
        return errf(err, cap, "usage: %s %s", w[0], usage);
    }
    if (r == NULL) {
        return errf(err, cap, "unknown command '%s' for the %s (try: help)", w[1],
                    c4gh_cell_dev_name(dev));
    }
    in->cmd = r->cmd;
    return parse_args(r, dev, w, n, 1 + used, in, err, cap);
}

/* ------------------------------------------------------------------ the tool's commands */

/* "raw DEV TEXT": the text after the device verbatim (spaces included); 1 if not raw. */
static int parse_raw(const char *text, cli_cmd_t *out, char *err, size_t cap)
{
    const char *p = text;
    char devw[32];
    size_t dl = 0, tl;
    while (isspace((unsigned char)*p)) {
        p++;
    }
    if (strncasecmp(p, "raw", 3) != 0 || (p[3] != '\0' && !isspace((unsigned char)p[3]))) {
        return 1;
    }
    p += 3;
    while (isspace((unsigned char)*p)) {
        p++;
    }
    while (p[dl] != '\0' && !isspace((unsigned char)p[dl]) && dl < sizeof devw - 1) {
        devw[dl] = p[dl];
        dl++;
    }
    devw[dl] = '\0';
    out->dev = c4gh_cell_dev_parse(devw);
    if (out->dev < 0) {
        return errf(err, cap, "usage: raw robot|platform|conditioning TEXT");
    }
    p += dl;
    if (isspace((unsigned char)*p)) {
        p++;
    }
    tl = strlen(p);
    while (tl > 0 && (p[tl - 1] == '\n' || p[tl - 1] == '\r')) {
        tl--;
    }
    if (tl + 2 > sizeof out->line) {
        return errf(err, cap, "raw text too long");
    }
    memcpy(out->line, p, tl);
    out->line[tl] = '\r';
    out->line[tl + 1] = '\n';
    out->len = tl + 2;
    out->kind = CMD_RAW;
    return 0;
}

/* connect HOST [PORT] | connect DEV HOST[:PORT] */
static int parse_connect(char **w, int n, cli_cmd_t *out, char *err, size_t cap)
{
    static const char usage[] = "usage: connect HOST [PORT] | connect robot|platform|conditioning "
                                "HOST[:PORT]";
    int dev = n == 3 ? c4gh_cell_dev_parse(w[1]) : -1;
    out->kind = CMD_CONNECT;
    out->dev = -1;
    out->port = 0;
    if (n < 2 || n > 3) {
        return errf(err, cap, usage);
    }
    if (dev >= 0) {
        out->dev = dev;
        if (c4gh_cell_parse_hostport(w[2], out->host, sizeof out->host, &out->port) != 0) {
            return errf(err, cap, "connect: bad address '%s' (HOST or HOST:PORT)", w[2]);
        }
        return 0;
    }
    if (strlen(w[1]) >= sizeof out->host || strchr(w[1], ':') != NULL) {
        return errf(err, cap, "%s", usage);
    }
    snprintf(out->host, sizeof out->host, "%s", w[1]);
    if (n == 3) {
        int32_t p;
        if (parse_int_arg(w[2], 1, 65533, "PORT", &p, err, cap) != 0) {
            return -1;
        }
        out->port = (unsigned)p;
    }
    return 0;
}

/* quit, help, sleep, wait, connect: 1 if w[0] is none of them. */
static int parse_tool_cmd(char **w, int n, cli_cmd_t *out, char *err, size_t cap)
{
    if (strcasecmp(w[0], "quit") == 0 || strcasecmp(w[0], "exit") == 0) {
        out->kind = CMD_QUIT;
        return 0;
    }
    if (strcasecmp(w[0], "clear") == 0) {
        out->kind = CMD_CLEAR;
        return n == 1 ? 0 : errf(err, cap, "usage: clear");
    }
    if (strcasecmp(w[0], "help") == 0 || strcmp(w[0], "?") == 0) {
        out->kind = CMD_HELP;
        snprintf(out->topic, sizeof out->topic, "%s", n > 1 ? w[1] : "");
        return 0;
    }
    if (strcasecmp(w[0], "connect") == 0) {
        return parse_connect(w, n, out, err, cap);
    }
    if (strcasecmp(w[0], "sleep") == 0) {
        out->kind = CMD_SLEEP;
        if (n != 2 || c4gh_cell_parse_double(w[1], &out->seconds) != 0 || out->seconds < 0 ||
            out->seconds > 3600) {
            return errf(err, cap, "usage: sleep SECONDS (0..3600)");
        }
        return 0;
    }
    if (strcasecmp(w[0], "wait") == 0) {
        out->kind = CMD_WAIT;
        out->seconds = 60.0;
        if (n < 3 || n > 4 || (out->dev = c4gh_cell_dev_parse(w[1])) < 0 ||
            out->dev == C4GH_CELL_DEV_CONDITIONING || strcasecmp(w[2], "stopped") != 0 ||
            (n == 4 && (c4gh_cell_parse_double(w[3], &out->seconds) != 0 || out->seconds <= 0))) {
            return errf(err, cap, "usage: wait robot|platform stopped [TIMEOUT_SECONDS]");
        }
        return 0;
    }
    return 1;
}

/* "N CMD": the count and where the command starts; 0 when the line has no count. */
static int repeat_prefix(const char *text, long *count, const char **rest)
{
    const char *p = text;
    long v = 0;
    while (isspace((unsigned char)*p)) {
        p++;
    }
    if (!isdigit((unsigned char)*p)) {
        return 0;
    }
    while (isdigit((unsigned char)*p)) {
        v = v > CLI_REPEAT_MAX ? v : v * 10 + (*p - '0');
        p++;
    }
    if (*p != '\0' && !isspace((unsigned char)*p)) {
        return 0; /* "2001x": not a count, reported as an unknown word */
    }
    *count = v;
    *rest = p;
    return 1;
}

static int cmd_parse_one(const char *text, cli_cmd_t *out, char *err, size_t err_cap);

int cli_cmd_parse(const char *text, cli_cmd_t *out, char *err, size_t err_cap)
{
    long count = 1;
    const char *rest = text;
    if (repeat_prefix(text, &count, &rest)) {
        if (count < 1 || count > CLI_REPEAT_MAX) {
            memset(out, 0, sizeof *out);
            return errf(err, err_cap, "N COMMAND: N must be 1..%ld", CLI_REPEAT_MAX);
        }
        if (cmd_parse_one(rest, out, err, err_cap) != 0) {
            return -1;
        }
        if (out->kind == CMD_EMPTY || out->kind == CMD_QUIT || out->kind == CMD_CONNECT ||
            out->kind == CMD_HELP || out->kind == CMD_CLEAR) {
            return errf(err, err_cap, "N COMMAND: repeats a device command, wait or sleep");
        }
        out->repeat = count;
        return 0;
    }
    return cmd_parse_one(text, out, err, err_cap);
}

static int cmd_parse_one(const char *text, cli_cmd_t *out, char *err, size_t err_cap)
{
    char buf[512];
    char *w[MAX_WORDS];
    int n, rc, dev;
    memset(out, 0, sizeof *out);
    out->dev = -1;
    out->repeat = 1;
    if (strlen(text) >= sizeof buf) {
        return errf(err, err_cap, "command too long");
    }
    strcpy(buf, text);
    rc = parse_raw(text, out, err, err_cap);
    if (rc <= 0) {
        return rc;
    }
    n = split_words(buf, w, MAX_WORDS);
    if (n < 0) {
        return errf(err, err_cap, "too many words");
    }
    if (n == 0) {
        out->kind = CMD_EMPTY;
        return 0;
    }
    rc = parse_tool_cmd(w, n, out, err, err_cap);
    if (rc <= 0) {
        return rc;
    }
    dev = c4gh_cell_dev_parse(w[0]);
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

/* ------------------------------------------------------------------ help, completion */

/* text with every line indented by two spaces (the table's help rows span lines) */
static size_t append_indented(char *out, size_t cap, size_t o, const char *text)
{
    const char *p = text;
    while (*p != '\0' && o < cap) {
        size_t n = strcspn(p, "\n");
        o += (size_t)snprintf(out + o, cap - o, "  %.*s\n", (int)n, p);
        p += n;
        if (*p == '\n') {
            p++;
        }
    }
    return o;
}

static int help_overview(const char *const addr[], char *out, size_t cap)
{
    size_t o;
    if (addr != NULL) {
        o = (size_t)snprintf(out, cap, "Devices: robot (%s), platform (%s), conditioning (%s);\n",
                             addr[C4GH_CELL_DEV_ROBOT], addr[C4GH_CELL_DEV_PLATFORM],
                             addr[C4GH_CELL_DEV_CONDITIONING]);
    } else {
        o = (size_t)snprintf(out, cap, "Devices: robot (port 2001), platform (2002), conditioning "
                                       "(2003);\n");
    }
    o += (size_t)snprintf(out + o, o < cap ? cap - o : 0, "any unique prefix works (r, p, c). "
                                                          "Commands:\n");
    for (size_t i = 0; i < N_ROWS && o < cap; i++) {
        o = append_indented(out, cap, o, k_rows[i].help);
    }
    for (size_t i = 0; i < N_TOOL_HELP && o < cap; i++) {
        o = append_indented(out, cap, o, k_tool_help[i].text);
    }
    if (o < cap) {
        snprintf(out + o, cap - o, "help COMMAND shows one command, help DEVICE its commands; "
                                   "replies ER+nnnnn are\nexplained with the spec's meaning.\n");
    }
    return 0;
}

/* The device whose full name starts a help line ("platform mov ..."), -1 for none ("DEV"). */
static int line_device(const char *p, size_t n)
{
    size_t w = strcspn(p, " \n");
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        const char *name = c4gh_cell_dev_name(d);
        if (w <= n && w == strlen(name) && strncmp(p, name, w) == 0) {
            return d;
        }
    }
    return -1;
}

/* The help rows of the commands device dev takes, DEV replaced by its name and the lines
 * of another device's form left out ("platform mov ..." under robot). */
static int help_device(int dev, char *out, size_t cap)
{
    const char *name = c4gh_cell_dev_name(dev);
    size_t o = (size_t)snprintf(out, cap, "Commands of the %s:\n", name);
    for (size_t i = 0; i < N_ROWS && o < cap; i++) {
        const char *p = k_rows[i].help;
        int keep = 0;
        if ((k_rows[i].devices & (1U << dev)) == 0U) {
            continue;
        }
        while (*p != '\0' && o < cap) {
            size_t n = strcspn(p, "\n");
            int other = line_device(p, n);
            if (n > 0 && p[0] != ' ') {
                keep = other < 0 || other == dev; /* a line of its own form, or of every device */
            }
            if (keep) {
                o += (size_t)snprintf(out + o, cap - o, "  ");
                for (size_t k = 0; k < n && o < cap; k++) {
                    if (n - k >= 4 && strncmp(p + k, "DEV ", 4) == 0) {
                        o += (size_t)snprintf(out + o, cap - o, "%s ", name);
                        k += 3;
                    } else {
                        out[o++] = p[k];
                    }
                }
                o += (size_t)snprintf(out + o, o < cap ? cap - o : 0, "\n");
            }
            p += n + (p[n] == '\n' ? 1 : 0);
        }
    }
    if (o >= cap && cap > 0) {
        out[cap - 1] = '\0';
    }
    return 0;
}

int cli_cmd_help_at(const char *topic, const char *const addr[], char *out, size_t cap)
{
    size_t o = 0;
    int dev;
    if (topic == NULL || topic[0] == '\0') {
        return help_overview(addr, out, cap);
    }
    out[0] = '\0';
    /* every row the word names: "servo" is the first word of "servo on" and "servo off" */
    for (size_t i = 0; i < N_ROWS && o < cap; i++) {
        if (row_has_word(&k_rows[i], topic)) {
            o += (size_t)snprintf(out + o, cap - o, "%s\n", k_rows[i].help);
        }
    }
    if (o > 0) {
        return 0;
    }
    for (size_t i = 0; i < N_TOOL_HELP; i++) {
        if (strcasecmp(topic, k_tool_help[i].topic) == 0) {
            snprintf(out, cap, "%s\n", k_tool_help[i].text);
            return 0;
        }
    }
    dev = c4gh_cell_dev_parse(topic);
    if (dev >= 0) {
        return help_device(dev, out, cap);
    }
    snprintf(out, cap, "no help for '%s' (try: help)\n", topic);
    return -1;
}

int cli_cmd_help(const char *topic, char *out, size_t cap)
{
    return cli_cmd_help_at(topic, NULL, out, cap);
}

/* Completion lists built once from the table: the primary words per device, and the
 * help topics (every primary word, then the tool's commands). */
static char g_primary[N_ROWS][WORD_MAX];
static const char *g_dev_cmds[C4GH_CELL_DEVICES][N_ROWS + 1];
static const char *g_topics[N_ROWS + N_TOOL_HELP + 1];

static void words_init(void)
{
    size_t nd[C4GH_CELL_DEVICES] = {0, 0, 0};
    size_t nt = 0;
    if (g_topics[0] != NULL) {
        return;
    }
    for (size_t i = 0; i < N_ROWS; i++) {
        primary(&k_rows[i], g_primary[i], sizeof g_primary[i]);
        for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
            if ((k_rows[i].devices & (1U << d)) != 0U) {
                g_dev_cmds[d][nd[d]++] = g_primary[i];
            }
        }
        g_topics[nt++] = g_primary[i];
    }
    for (size_t i = 0; i < N_TOOL_HELP; i++) {
        g_topics[nt++] = k_tool_help[i].topic;
    }
}

/* Words after "DEV VERB": from the layout of VERB's row. */
static const char *const *arg_words(int word, int dev, const char *second)
{
    static const char *const absrel[] = {"abs", "rel", NULL};
    static const char *const robot_keys[] = {"x=", "y=", "z=", "c=", NULL};
    static const char *const pnp_keys[] = {"clear=", "x=", "y=", "z=", "c=", NULL};
    static const char *const plat_keys[] = {"a=", "b=", NULL};
    static const char *const openclose[] = {"open", "close", NULL};
    int used = 1, partial = 0;
    const cmd_row_t *r = second != NULL ? row_find(second, NULL, &used, &partial) : NULL;
    if (r == NULL) {
        return NULL;
    }
    switch (r->args) {
    case C4G_CELL_ARGS_MODE_POSE:
        return word == 2 ? absrel : dev == C4GH_CELL_DEV_ROBOT ? robot_keys : plat_keys;
    case C4G_CELL_ARGS_CLEAR_POSE:
        return dev == C4GH_CELL_DEV_ROBOT ? pnp_keys : NULL;
    case C4G_CELL_ARGS_INT_ACTION:
        return word == 3 ? openclose : NULL;
    case C4G_CELL_ARGS_INT:
    case C4G_CELL_ARGS_NONE:
    default:
        return NULL;
    }
}

const char *const *cli_cmd_words(int word, const char *first, const char *second)
{
    static const char *const w0[] = {"robot", "platform", "conditioning", "raw", "wait",
                                     "sleep", "connect", "help", "clear", "quit", NULL};
    static const char *const devs[] = {"robot", "platform", "conditioning", NULL};
    static const char *const motion_devs[] = {"robot", "platform", NULL};
    static const char *const stopped[] = {"stopped", NULL};
    int dev;
    words_init();
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
        return word == 1 ? g_topics : NULL;
    }
    if (strcasecmp(first, "connect") == 0) {
        return word == 1 ? devs : NULL;
    }
    dev = c4gh_cell_dev_parse(first);
    if (dev < 0) {
        return NULL;
    }
    if (word == 1) {
        return g_dev_cmds[dev];
    }
    return arg_words(word, dev, second);
}

/* ------------------------------------------------------------------ hints as you type */

static size_t hint_of(const char *line, char *out, size_t cap);

/* A hint template is the arguments of a command, space-separated: a word of lower-case
 * choices ("abs|rel", "robot|platform"), a placeholder in capitals ("PERCENT", "[TIMEOUT]")
 * or a key ("x=MM", "[a=RAD]"). Choices and placeholders come in order; keys in any order. */
#define HINT_TOKENS 8
#define HINT_TOKEN_MAX 128 /* a device's command list is one token */

typedef struct hint_tpl {
    char tok[HINT_TOKENS][HINT_TOKEN_MAX];
    int n;
} hint_tpl_t;

static void tpl_set(hint_tpl_t *t, const char *text)
{
    char buf[256];
    char *w[HINT_TOKENS];
    snprintf(buf, sizeof buf, "%s", text);
    t->n = split_words(buf, w, HINT_TOKENS);
    if (t->n < 0) {
        t->n = 0;
    }
    for (int i = 0; i < t->n; i++) {
        snprintf(t->tok[i], sizeof t->tok[i], "%s", w[i]);
    }
}

static void tpl_drop(hint_tpl_t *t, int i)
{
    for (int j = i; j + 1 < t->n; j++) {
        memcpy(t->tok[j], t->tok[j + 1], sizeof t->tok[j]);
    }
    t->n--;
}

/* The key of a key token ("x" of "x=MM" and "[x=MM]"), or "" for another token. */
static void tok_key(const char *tok, char *key, size_t cap)
{
    const char *p = tok[0] == '[' ? tok + 1 : tok;
    size_t n = strcspn(p, "=");
    key[0] = '\0';
    if (p[n] == '=' && n > 0 && !isupper((unsigned char)p[0])) {
        snprintf(key, cap, "%.*s", (int)n, p);
    }
}

/* Does word fill a choice token? Device names may be shortened as everywhere else. */
static int choice_match(const char *tok, const char *word)
{
    const char *p = tok;
    int dev = c4gh_cell_dev_parse(word);
    while (*p != '\0') {
        size_t n = strcspn(p, "|");
        if ((strlen(word) == n && strncasecmp(p, word, n) == 0) ||
            (dev >= 0 && strlen(c4gh_cell_dev_name(dev)) == n && strncmp(p, c4gh_cell_dev_name(dev), n) == 0)) {
            return 1;
        }
        p += n + (p[n] == '|' ? 1 : 0);
    }
    return 0;
}

/* Takes away the token word fills: 0, or -1 when the word fits nowhere (no hint then).
 * A key word still being typed without its '=' fills nothing yet. */
static int tpl_take(hint_tpl_t *t, const char *word)
{
    char key[WORD_MAX];
    const char *eq = strchr(word, '=');
    if (t->n == 0) {
        return -1;
    }
    tok_key(t->tok[0], key, sizeof key);
    if (key[0] != '\0') {
        if (eq == NULL) {
            return -1;
        }
        for (int i = 0; i < t->n; i++) {
            tok_key(t->tok[i], key, sizeof key);
            if (strlen(key) == (size_t)(eq - word) && strncasecmp(key, word, strlen(key)) == 0) {
                tpl_drop(t, i);
                return 0;
            }
        }
        return -1;
    }
    if (islower((unsigned char)t->tok[0][0]) && !choice_match(t->tok[0], word)) {
        return -1;
    }
    tpl_drop(t, 0);
    return 0;
}

/* The template of a device command (w[0] a device, n >= 2 words); *k: the words that name
 * the command. -1 when w[1] names no command of the device, or only starts one. */
static int device_tpl(int dev, char **w, int n, int typing, hint_tpl_t *t, int *k)
{
    int used = 1, partial = 0;
    const cmd_row_t *r = row_find(w[1], n > 2 ? w[2] : NULL, &used, &partial);
    char buf[96];
    if (r == NULL && partial && (n > 3 || (n == 3 && !typing))) {
        return -1; /* "servo up" */
    }
    if (r == NULL && partial) {
        if (n == 3) {
            return -1; /* "servo o": the second word is being typed */
        }
        two_word_usage(w[1], buf, sizeof buf);
        *k = 2;
        tpl_set(t, buf + strcspn(buf, " ")); /* "on|off" */
        return 0;
    }
    if (r == NULL || (r->devices & (1U << dev)) == 0U) {
        return -1;
    }
    *k = 1 + used;
    switch (r->args) {
    case C4G_CELL_ARGS_INT:
        tpl_set(t, r->arg);
        break;
    case C4G_CELL_ARGS_INT_ACTION:
        snprintf(buf, sizeof buf, "%s open|close", r->arg);
        tpl_set(t, buf);
        break;
    case C4G_CELL_ARGS_MODE_POSE: {
        int rel = n > *k && strcasecmp(w[*k], "rel") == 0;
        const char *keys = dev == C4GH_CELL_DEV_ROBOT
                               ? (rel ? "[x=MM] [y=MM] [z=MM] [c=RAD]" : "x=MM y=MM z=MM c=RAD")
                               : (rel ? "[a=RAD] [b=RAD]" : "a=RAD b=RAD");
        snprintf(buf, sizeof buf, "abs|rel %s", keys);
        tpl_set(t, buf);
        break;
    }
    case C4G_CELL_ARGS_CLEAR_POSE:
        tpl_set(t, "clear=MM x=MM y=MM z=MM c=RAD");
        break;
    case C4G_CELL_ARGS_NONE:
    default:
        t->n = 0;
        break;
    }
    return 0;
}

/* The template of the command in w[0..n); -1 for an unknown command. */
static int command_tpl(char **w, int n, int typing, hint_tpl_t *t, int *k)
{
    static const struct {
        const char *word, *args;
    } tool[] = {{"help", "[COMMAND]"}, {"?", "[COMMAND]"}, {"sleep", "SECONDS"},
                {"wait", "robot|platform stopped [TIMEOUT]"},
                {"raw", "robot|platform|conditioning TEXT"}, {"connect", "HOST [PORT]"},
                {"clear", ""}, {"quit", ""},
                {"exit", ""}};
    int dev = c4gh_cell_dev_parse(w[0]);
    *k = 1;
    t->n = 0;
    for (size_t i = 0; i < sizeof tool / sizeof tool[0]; i++) {
        if (strcasecmp(w[0], tool[i].word) == 0) {
            tpl_set(t, tool[i].args);
            return 0;
        }
    }
    if (dev < 0) {
        return -1;
    }
    if (n >= 2) {
        return device_tpl(dev, w, n, typing, t, k);
    }
    /* a device alone: its commands, once the word is the device's whole name (or ended) */
    if (typing && strcasecmp(w[0], c4gh_cell_dev_name(dev)) != 0) {
        return -1;
    }
    {
        char *list = t->tok[0];
        size_t o = 0;
        const char *const *c = cli_cmd_words(1, c4gh_cell_dev_name(dev), NULL);
        list[0] = '\0';
        for (; c != NULL && *c != NULL && o < sizeof t->tok[0]; c++) {
            o += (size_t)snprintf(list + o, sizeof t->tok[0] - o, "%s%s", o > 0 ? "|" : "", *c);
        }
        if (o >= sizeof t->tok[0]) {
            strcpy(list, "COMMAND");
        }
        t->n = 1;
    }
    return 0;
}

size_t cli_cmd_hint(const char *line, char *out, size_t cap)
{
    long count;
    const char *rest;
    if (repeat_prefix(line, &count, &rest) && *rest != '\0') {
        return cli_cmd_hint(rest + 1, out, cap); /* "3 robot mov ": the command's hint */
    }
    return hint_of(line, out, cap);
}

static size_t hint_of(const char *line, char *out, size_t cap)
{
    char buf[512];
    char *w[MAX_WORDS];
    hint_tpl_t t;
    size_t len = strlen(line);
    size_t o = 0;
    int n, k = 1;
    int typing = len > 0 && !isspace((unsigned char)line[len - 1]); /* the last word goes on */
    if (cap == 0) {
        return 0;
    }
    out[0] = '\0';
    if (len >= sizeof buf || strchr(line, '#') != NULL) {
        return 0;
    }
    strcpy(buf, line);
    n = split_words(buf, w, MAX_WORDS);
    if (n <= 0 || command_tpl(w, n, typing, &t, &k) != 0 || n < k) {
        return 0;
    }
    for (int i = k; i < n; i++) {
        if (tpl_take(&t, w[i]) != 0) {
            return 0;
        }
    }
    for (int i = 0; i < t.n && o < cap; i++) {
        o += (size_t)snprintf(out + o, cap - o, "%s%s", (i > 0 || typing) ? " " : "", t.tok[i]);
    }
    if (o >= cap) {
        o = cap - 1;
    }
    return t.n > 0 ? o : 0;
}
