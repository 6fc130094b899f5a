/* SPDX-License-Identifier: MIT */
/* cell-cli: terminal client for the cell's robot, platform and conditioning
 * controllers (REPL with libedit, one-shot, scripts, --json). See docs/cell-cli.md. */
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#include <editline/readline.h>
#include <jansson.h>

#include "c4gopen.h"
#include "c4g_cli.h"
#include "c4g_textfile.h"
#include "cell_common.h"
#include "cli_canopen.h"
#include "cli_cmd.h"
#include "cli_config.h"

enum {
    EXIT_OK = 0,
    EXIT_DEVICE_ER = 1,   /* a device replied ER */
    EXIT_USAGE = 2,       /* bad option, bad command, script syntax */
    EXIT_CONNECT = 3,     /* connection refused / lost / reply timeout */
    EXIT_PROTOCOL = 4,    /* a reply that does not parse */
    EXIT_WAIT = 5         /* wait ... stopped timed out */
};

typedef struct conn {
    char host[256];
    unsigned port;
    int fd;
    char buf[C4G_CELL_LINE_MAX];
    c4g_cell_splitter_t sp;
} conn_t;

static conn_t g_conn[CELL_DEVICES];
static int g_connect_ms = 2000;
static int g_reply_ms = 2000;
/* How replies are shown: the human text on a terminal, the reply line as the device sent
 * it when stdout is not one (as redis-cli does), one JSON object or one CSV row each. */
typedef enum out_fmt { OUT_AUTO = 0, OUT_TEXT, OUT_RAW, OUT_JSON, OUT_CSV } out_fmt_t;
static out_fmt_t g_fmt;
static int g_json, g_csv, g_raw, g_no_raw;
static int g_stamp;     /* JSON/CSV rows carry the wall-clock time (-r / -i) */
static int g_csv_head;  /* the CSV header was printed */
static int g_last_dev = -1; /* the device of the last command (the prompt shows it) */
static int g_echo;

/* ------------------------------------------------------------------ transport */

static void conn_drop(int dev)
{
    if (g_conn[dev].fd >= 0) {
        close(g_conn[dev].fd);
        g_conn[dev].fd = -1;
    }
}

static int conn_get(int dev)
{
    conn_t *c = &g_conn[dev];
    const char *err = NULL;
    if (c->fd >= 0) {
        return 0;
    }
    c->fd = cell_tcp_connect(c->host, c->port, g_connect_ms, &err);
    if (c->fd < 0) {
        fprintf(stderr, "cell-cli: %s at %s:%u: %s\n", cell_dev_name(dev), c->host, c->port, err);
        return EXIT_CONNECT;
    }
    (void)c4g_cell_split_init(&c->sp, c->buf, sizeof c->buf);
    return 0;
}

/* Send one line, read one reply line (CR LF included) into reply. */
static int transact(int dev, const char *line, size_t len, char *reply, size_t cap,
                    size_t *rlen)
{
    conn_t *c = &g_conn[dev];
    int rc = conn_get(dev);
    size_t off = 0;
    uint64_t deadline;
    if (rc != 0) {
        return rc;
    }
    while (off < len) {
        ssize_t w = send(c->fd, line + off, len - off, MSG_NOSIGNAL);
        if (w < 0) {
            if (errno == EINTR) {
                continue;
            }
            fprintf(stderr, "cell-cli: %s: send failed: %s\n", cell_dev_name(dev), strerror(errno));
            conn_drop(dev);
            return EXIT_CONNECT;
        }
        off += (size_t)w;
    }
    deadline = cell_now_ns() + (uint64_t)g_reply_ms * 1000000ULL;
    for (;;) {
        c4g_cell_split_event_t ev;
        const char *l = NULL;
        size_t n = 0;
        (void)c4g_cell_split_next(&c->sp, &ev, &l, &n);
        if (ev == C4G_CELL_SPLIT_LINE) {
            if (n > cap) {
                n = cap;
            }
            memcpy(reply, l, n);
            *rlen = n;
            return 0;
        }
        if (ev == C4G_CELL_SPLIT_OVERLONG) {
            fprintf(stderr, "cell-cli: %s: reply longer than %u bytes\n", cell_dev_name(dev),
                    (unsigned)C4G_CELL_LINE_MAX);
            conn_drop(dev);
            return EXIT_PROTOCOL;
        }
        uint64_t now = cell_now_ns();
        if (now >= deadline) {
            fprintf(stderr, "cell-cli: %s: no reply within %d ms\n", cell_dev_name(dev), g_reply_ms);
            conn_drop(dev); /* a late reply would desynchronise the next request */
            return EXIT_CONNECT;
        }
        struct pollfd p = {c->fd, POLLIN, 0};
        int pr = poll(&p, 1, (int)((deadline - now) / 1000000ULL) + 1);
        if (pr < 0 && errno == EINTR) {
            continue;
        }
        if (pr <= 0) {
            continue; /* the deadline check above reports the timeout */
        }
        char tmp[C4G_CELL_LINE_MAX];
        size_t used = 0;
        ssize_t r = recv(c->fd, tmp, sizeof tmp, 0);
        if (r <= 0) {
            fprintf(stderr, "cell-cli: %s: connection closed by the device\n", cell_dev_name(dev));
            conn_drop(dev);
            return EXIT_CONNECT;
        }
        /* one read never exceeds the splitter capacity; consume what it takes */
        for (size_t o = 0; o < (size_t)r; o += used) {
            (void)c4g_cell_split_push(&c->sp, tmp + o, (size_t)r - o, &used);
            if (used == 0) {
                break;
            }
        }
    }
}

/* ------------------------------------------------------------------ output */

/* A JSON string from n bytes of the wire: bytes that are not UTF-8 become \u00NN. */
static json_t *json_bytes(const char *s, size_t n)
{
    char buf[C4G_CELL_LINE_MAX * 6 + 1];
    size_t o = 0;
    for (size_t i = 0; i < n && o + 7 < sizeof buf; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c < 0x80) {
            buf[o++] = (char)c;
        } else { /* Latin-1 reading: always valid UTF-8, every byte kept */
            buf[o++] = (char)(0xC0 | (c >> 6));
            buf[o++] = (char)(0x80 | (c & 0x3F));
        }
    }
    return json_stringn(buf, o);
}

/* The wall-clock time as ISO 8601 UTC with milliseconds. */
static void stamp_text(char *out, size_t cap)
{
    struct timespec ts;
    struct tm tm;
    clock_gettime(CLOCK_REALTIME, &ts);
    gmtime_r(&ts.tv_sec, &tm);
    char day[40];
    strftime(day, sizeof day, "%Y-%m-%dT%H:%M:%S", &tm);
    snprintf(out, cap, "%.19s.%03dZ", day, (int)(ts.tv_nsec / 1000000L) % 1000);
}

/* One JSON object per line: {"time":...} first when stamped, then the fields. */
static json_t *json_head(int dev)
{
    json_t *o = json_object();
    if (g_stamp) {
        char t[40];
        stamp_text(t, sizeof t);
        json_object_set_new(o, "time", json_string(t));
    }
    json_object_set_new(o, "device", json_string(cell_dev_name(dev)));
    return o;
}

static void json_emit(json_t *o)
{
    json_dumpf(o, stdout, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(10));
    fputc('\n', stdout);
    json_decref(o);
}

/* A CSV field: quoted when it holds a comma, a quote or a byte that is not printable. */
static void csv_field(const char *s, size_t n)
{
    int quote = 0;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == ',' || c == '"' || c < 0x20 || c >= 0x7F) {
            quote = 1;
        }
    }
    if (!quote) {
        fwrite(s, 1, n, stdout);
        return;
    }
    fputc('"', stdout);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '"') {
            fputs("\"\"", stdout);
        } else if (c < 0x20 || c >= 0x7F) {
            printf("\\x%02x", c);
        } else {
            fputc(c, stdout);
        }
    }
    fputc('"', stdout);
}

static const char *axis_label(int dev, int a)
{
    static const char *const r[4] = {"x", "y", "z", "c"};
    static const char *const p[2] = {"a", "b"};
    return dev == CELL_DEV_ROBOT ? r[a] : p[a];
}

static c4g_cell_unit_t axis_unit(int dev, int a)
{
    return (dev == CELL_DEV_ROBOT && a < 3) ? C4G_CELL_UNIT_MM : C4G_CELL_UNIT_RAD;
}

static int axis_places(int dev, int a)
{
    return axis_unit(dev, a) == C4G_CELL_UNIT_MM ? 3 : 4;
}

static double axis_value(int dev, const c4g_cell_reply_t *r, uint32_t a)
{
    double v = 0;
    (void)c4g_cell_to_double(r->pose.v[a], axis_unit(dev, (int)a), &v);
    return v;
}

static void csv_row(int dev, const char *req, size_t rl, const char *line, size_t ll,
                    const c4g_cell_reply_t *r);

/* A reply that does not decode. */
static int show_invalid(int dev, const char *req, size_t rl, const char *line, size_t len,
                        c4g_status_t st, const c4g_cell_diag_t *d)
{
    size_t ll = (len >= 2 && line[len - 1] == '\n') ? len - 2 : len;
    if (g_fmt == OUT_JSON) {
        json_t *o = json_head(dev);
        json_object_set_new(o, "request", json_bytes(req, rl));
        json_object_set_new(o, "reply", json_string("invalid"));
        json_object_set_new(o, "raw", json_bytes(line, len));
        json_object_set_new(o, "problem", json_string(c4g_strerror(st)));
        json_object_set_new(o, "column", json_integer((json_int_t)d->column));
        json_emit(o);
    } else if (g_fmt == OUT_CSV) {
        csv_row(dev, req, rl, line, ll, NULL);
    } else if (g_fmt == OUT_RAW) {
        fwrite(line, 1, ll, stdout);
        fputc('\n', stdout);
    } else {
        printf("%s: invalid reply \"%.*s\": %s at column %u\n", cell_dev_name(dev), (int)ll, line,
               c4g_strerror(st), (unsigned)d->column);
    }
    return EXIT_PROTOCOL;
}

static void show_json(int dev, const char *req, size_t rl, const char *line, size_t ll,
                      const c4g_cell_reply_t *r)
{
    int project = 0;
    const char *etext = c4g_cell_error_text(r->error, &project);
    json_t *o = json_head(dev);
    json_object_set_new(o, "request", json_bytes(req, rl));
    json_object_set_new(o, "raw", json_bytes(line, ll));
    json_object_set_new(o, "reply", json_string(r->kind == C4G_CELL_REPLY_ER ? "ER" : "OK"));
    if (r->kind == C4G_CELL_REPLY_ER) {
        json_object_set_new(o, "error", json_integer(r->error));
        json_object_set_new(o, "error_text", json_string(etext));
        json_object_set_new(o, "project_code", json_boolean(project));
    } else if (r->kind == C4G_CELL_REPLY_STA) {
        json_t *pos = json_object();
        json_object_set_new(o, "moving", json_boolean(r->moving));
        json_object_set_new(o, "servo", json_boolean(r->servo_on));
        json_object_set_new(o, "override", json_integer(r->override_pct));
        json_object_set_new(o, "error", json_integer(r->error));
        json_object_set_new(o, "error_text", json_string(etext));
        for (uint32_t a = 0; a < r->pose.n_axes; a++) {
            json_object_set_new(pos, axis_label(dev, (int)a), json_real(axis_value(dev, r, a)));
        }
        json_object_set_new(o, "position", pos);
    }
    json_emit(o);
}

/* One CSV row: time (with -r/-i), device, request, reply, then the STA fields; the header
 * first. r NULL: a reply that does not decode. */
static void csv_row(int dev, const char *req, size_t rl, const char *line, size_t ll,
                    const c4g_cell_reply_t *r)
{
    char t[40];
    if (!g_csv_head) {
        printf("%sdevice,request,reply,raw,moving,servo,override,error,p1,p2,p3,p4\n",
               g_stamp ? "time," : "");
        g_csv_head = 1;
    }
    if (g_stamp) {
        stamp_text(t, sizeof t);
        printf("%s,", t);
    }
    printf("%s,", cell_dev_name(dev));
    csv_field(req, rl);
    printf(",%s,", r == NULL ? "invalid" : r->kind == C4G_CELL_REPLY_ER ? "ER" : "OK");
    csv_field(line, ll);
    if (r != NULL && r->kind == C4G_CELL_REPLY_STA) {
        printf(",%d,%d,%d,%d", r->moving ? 1 : 0, r->servo_on ? 1 : 0, (int)r->override_pct,
               (int)r->error);
        for (uint32_t a = 0; a < 4U; a++) {
            if (a < r->pose.n_axes) {
                printf(",%.*f", axis_places(dev, (int)a), axis_value(dev, r, a));
            } else {
                fputc(',', stdout);
            }
        }
    } else if (r != NULL && r->kind == C4G_CELL_REPLY_ER) {
        printf(",,,,%d,,,,", (int)r->error);
    } else {
        fputs(",,,,,,,,", stdout);
    }
    fputc('\n', stdout);
}

static void show_text(int dev, const c4g_cell_reply_t *r)
{
    int project = 0;
    const char *etext = c4g_cell_error_text(r->error, &project);
    if (r->kind == C4G_CELL_REPLY_ER) {
        printf("%s: ER %+06d  %s (%s)\n", cell_dev_name(dev), (int)r->error, etext,
               project ? "project code" : "spec");
        return;
    }
    if (r->kind == C4G_CELL_REPLY_OK) {
        printf("%s: OK\n", cell_dev_name(dev));
        return;
    }
    printf("%s: %s, servo %s, override %d %%, error %+06d (%s)\n", cell_dev_name(dev),
           r->moving ? "MOVING" : "stopped", r->servo_on ? "ON" : "off", (int)r->override_pct,
           (int)r->error, etext);
    for (uint32_t a = 0; a < r->pose.n_axes; a++) {
        char h[16];
        snprintf(h, sizeof h, "%s [%s]", axis_label(dev, (int)a),
                 axis_unit(dev, (int)a) == C4G_CELL_UNIT_MM ? "mm" : "rad");
        printf("  %10s", h);
    }
    printf("\n");
    for (uint32_t a = 0; a < r->pose.n_axes; a++) {
        printf("  %10.*f", axis_places(dev, (int)a), axis_value(dev, r, a));
    }
    printf("\n");
}

/* Show a reply; returns the exit class it implies. */
static int show_reply(int dev, const char *req, size_t req_len, const char *line, size_t len)
{
    c4g_cell_reply_t r;
    c4g_cell_diag_t d;
    c4g_status_t st = c4g_cell_reply_decode(line, len, &r, &d);
    size_t rl = (req_len >= 2) ? req_len - 2 : req_len;
    size_t ll = (len >= 2 && line[len - 1] == '\n') ? len - 2 : len;
    if (st != C4G_OK) {
        return show_invalid(dev, req, rl, line, len, st, &d);
    }
    if (g_fmt == OUT_JSON) {
        show_json(dev, req, rl, line, ll, &r);
    } else if (g_fmt == OUT_CSV) {
        csv_row(dev, req, rl, line, ll, &r);
    } else if (g_fmt == OUT_RAW) {
        fwrite(line, 1, ll, stdout);
        fputc('\n', stdout);
    } else {
        show_text(dev, &r);
    }
    fflush(stdout);
    return r.kind == C4G_CELL_REPLY_ER ? EXIT_DEVICE_ER : EXIT_OK;
}

static void sleep_s(double s)
{
    struct timespec ts;
    ts.tv_sec = (time_t)s;
    ts.tv_nsec = (long)((s - (double)ts.tv_sec) * 1e9);
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

/* Poll STA every 50 ms until the device reports 'F' (stopped). */
static int wait_stopped(int dev, double timeout_s)
{
    uint64_t deadline = cell_now_ns() + (uint64_t)(timeout_s * 1e9);
    for (;;) {
        char reply[C4G_CELL_LINE_MAX];
        size_t n = 0;
        c4g_cell_reply_t r;
        int rc = transact(dev, "STA\r\n", 5, reply, sizeof reply, &n);
        if (rc != 0) {
            return rc;
        }
        if (c4g_cell_reply_decode(reply, n, &r, NULL) != C4G_OK) {
            return show_reply(dev, "STA\r\n", 5, reply, n);
        }
        if (r.kind == C4G_CELL_REPLY_ER) {
            return show_reply(dev, "STA\r\n", 5, reply, n);
        }
        if (r.kind == C4G_CELL_REPLY_STA && !r.moving) {
            if (g_fmt == OUT_JSON) {
                json_t *o = json_head(dev);
                json_object_set_new(o, "wait", json_string("stopped"));
                json_object_set_new(o, "result", json_string("ok"));
                json_emit(o);
            } else if (g_fmt == OUT_RAW || g_fmt == OUT_CSV) {
                (void)show_reply(dev, "STA\r\n", 5, reply, n); /* the reply that ended it */
            } else {
                printf("%s: stopped\n", cell_dev_name(dev));
            }
            fflush(stdout);
            return EXIT_OK;
        }
        if (cell_now_ns() >= deadline) {
            fprintf(stderr, "cell-cli: wait %s stopped: still moving after %g s\n",
                    cell_dev_name(dev), timeout_s);
            return EXIT_WAIT;
        }
        sleep_s(0.05);
    }
}

/* Execute one command. */
static int run_cmd(const cli_cmd_t *cmd)
{
    char reply[C4G_CELL_LINE_MAX];
    char help[4096];
    size_t n = 0;
    int rc;
    switch (cmd->kind) {
    case CMD_EMPTY:
    case CMD_QUIT:
        return EXIT_OK;
    case CMD_CLEAR:
        if (isatty(STDOUT_FILENO)) {
            fputs("\033[H\033[2J", stdout); /* home, erase the screen */
        }
        return EXIT_OK;
    case CMD_HELP:
        rc = cli_cmd_help(cmd->topic, help, sizeof help);
        fputs(help, stdout);
        return rc == 0 ? EXIT_OK : EXIT_USAGE;
    case CMD_SLEEP:
        sleep_s(cmd->seconds);
        return EXIT_OK;
    case CMD_WAIT:
        g_last_dev = cmd->dev;
        return wait_stopped(cmd->dev, cmd->seconds);
    case CMD_SEND:
    case CMD_RAW:
        g_last_dev = cmd->dev;
        rc = transact(cmd->dev, cmd->line, cmd->len, reply, sizeof reply, &n);
        if (rc != 0) {
            return rc;
        }
        rc = show_reply(cmd->dev, cmd->line, cmd->len, reply, n);
        if (cmd->kind == CMD_SEND && cmd->instr.cmd == C4G_CELL_CMD_CLO && rc == EXIT_OK) {
            conn_drop(cmd->dev); /* the device closes after OK */
        }
        return rc;
    }
    return EXIT_USAGE;
}

/* ------------------------------------------------------------------ modes */

/* One script line (streamed: stdin may be a pipe fed over time). 1 a line, 0 end, -1 an
 * error in err: a line over cap - 1 bytes (fgets split it silently), a NUL or other
 * control byte (fgets made /dev/zero an endless run of empty lines). */
static int script_line(FILE *f, char *line, size_t cap, char *err, size_t errlen)
{
    size_t n = 0;
    int c;
    while ((c = getc(f)) != EOF && c != '\n') {
        if (c == '\r') {
            int d = getc(f);
            if (d == '\n' || d == EOF) {
                break;
            }
            ungetc(d, f);
        }
        if ((c < 0x20 && c != '\t') || c == 0x7F) {
            snprintf(err, errlen, "column %zu: control byte \\x%02x: binary content is not accepted",
                     n + 1, (unsigned)c);
            return -1;
        }
        if (n + 1 >= cap) {
            snprintf(err, errlen, "line longer than %zu bytes", cap - 1);
            return -1;
        }
        line[n++] = (char)c;
    }
    line[n] = '\0';
    return (c == EOF && n == 0) ? 0 : 1;
}

static int run_script(FILE *f, const char *name, int keep_going)
{
    char line[1024];
    char lerr[128];
    int lineno = 0;
    int worst = EXIT_OK;
    int r;
    while ((r = script_line(f, line, sizeof line, lerr, sizeof lerr)) != 0) {
        cli_cmd_t cmd;
        char err[256];
        lineno++;
        if (r < 0) {
            fprintf(stderr, "cell-cli: %s:%d: %s\n", name, lineno, lerr);
            return EXIT_USAGE;
        }
        if (cli_cmd_parse(line, &cmd, err, sizeof err) != 0) {
            fprintf(stderr, "cell-cli: %s:%d: %s\n", name, lineno, err);
            return EXIT_USAGE;
        }
        if (cmd.kind == CMD_EMPTY) {
            continue;
        }
        if (cmd.kind == CMD_QUIT) {
            break;
        }
        if (g_echo && (g_fmt == OUT_TEXT || g_fmt == OUT_RAW)) {
            printf("> %s\n", line);
        }
        int rc = run_cmd(&cmd);
        if (rc == EXIT_DEVICE_ER && keep_going) {
            worst = rc;
            continue;
        }
        if (rc != EXIT_OK) {
            fprintf(stderr, "cell-cli: %s:%d: stopped at '%s'\n", name, lineno, line);
            return rc;
        }
    }
    return worst;
}

/* Where the word being completed starts in rl_line_buffer: the completion callback's start.
 * (libedit does not update rl_point before completing, so rl_point cannot tell whether the
 * cursor follows a space, i.e. whether the word being completed is an empty one.) */
static int g_comp_start;
static char g_hint[512];

static char *complete_gen(const char *text, int state)
{
    static const char *const *list;
    static int idx;
    static size_t tl;
    if (state == 0) {
        /* the words before the one being completed */
        char buf[512];
        char *w[4] = {NULL, NULL, NULL, NULL};
        int n = 0;
        size_t pl = g_comp_start > 0 ? (size_t)g_comp_start : 0U;
        if (pl >= sizeof buf) {
            pl = sizeof buf - 1U;
        }
        memcpy(buf, rl_line_buffer, pl);
        buf[pl] = '\0';
        for (char *p = strtok(buf, " \t"); p != NULL; p = strtok(NULL, " \t")) {
            if (n < 4) {
                w[n] = p;
            }
            n++;
        }
        list = cli_cmd_words(n, w[0] ? w[0] : "", n >= 2 ? w[1] : NULL);
        /* the hint when nothing can be offered: the help of the command being typed */
        g_hint[0] = '\0';
        if (list == NULL && n >= 1) {
            const char *topic = (cell_dev_parse(w[0]) >= 0 && n >= 2) ? w[1] : w[0];
            if (cli_cmd_help(topic, g_hint, sizeof g_hint) != 0) {
                g_hint[0] = '\0';
            }
        }
        idx = 0;
        tl = strlen(text);
    }
    while (list != NULL && list[idx] != NULL) {
        const char *c = list[idx++];
        if (strncasecmp(c, text, tl) == 0) {
            return strdup(c);
        }
    }
    return NULL;
}

static char **complete(const char *text, int start, int end)
{
    (void)end;
    char **m;
    g_comp_start = start;
    rl_attempted_completion_over = 1; /* no file name completion */
    m = rl_completion_matches(text, complete_gen);
    if (m == NULL && g_hint[0] != '\0') {
        /* libedit has no hook that runs as each key is typed (redis-cli's hints come from
         * linenoise's): the argument hint is shown on TAB, below the line, which is redrawn */
        fprintf(stdout, "\n%s", g_hint);
        fflush(stdout);
        rl_on_new_line();
        rl_forced_update_display();
    }
    return m;
}

static int run_repl(int use_history)
{
    char hist[1024] = "";
    const char *hf = getenv("CELL_CLI_HISTFILE");
    const char *home = getenv("HOME");
    if (hf != NULL) {
        snprintf(hist, sizeof hist, "%s", hf);
    } else if (home != NULL) {
        snprintf(hist, sizeof hist, "%s/.cell_cli_history", home);
    }
    rl_readline_name = "cell-cli";
    rl_attempted_completion_function = complete;
    using_history();
    if (use_history && hist[0] != '\0') {
        (void)read_history(hist);
    }
    printf("cell-cli %s: robot %s:%u, platform %s:%u, conditioning %s:%u. Type help.\n",
           C4G_VERSION_STRING, g_conn[0].host, g_conn[0].port, g_conn[1].host, g_conn[1].port,
           g_conn[2].host, g_conn[2].port);
    for (;;) {
        char prompt[sizeof g_conn[0].host + 64];
        char *line;
        /* the device of the last command and its address while its connection is open */
        if (g_last_dev >= 0 && g_conn[g_last_dev].fd >= 0) {
            snprintf(prompt, sizeof prompt, "cell %s@%s:%u> ", cell_dev_name(g_last_dev),
                     g_conn[g_last_dev].host, g_conn[g_last_dev].port);
        } else {
            snprintf(prompt, sizeof prompt, "cell not connected> ");
        }
        line = readline(prompt);
        cli_cmd_t cmd;
        char err[256];
        if (line == NULL) {
            printf("\n");
            break;
        }
        if (line[0] != '\0') {
            add_history(line);
            if (use_history && hist[0] != '\0') {
                (void)write_history(hist);
                (void)history_truncate_file(hist, 1000);
            }
        }
        if (cli_cmd_parse(line, &cmd, err, sizeof err) != 0) {
            printf("error: %s\n", err);
        } else if (cmd.kind == CMD_QUIT) {
            free(line);
            break;
        } else {
            (void)run_cmd(&cmd); /* the REPL shows errors and carries on */
        }
        fflush(stdout);
        free(line);
    }
    return EXIT_OK;
}

/* ------------------------------------------------------------------ command line */

#define HOST_CAP sizeof g_conn[0].host

/* What the options say; 0 / "" for "not given" (defaults < config file < options). */
typedef struct opts {
    char config[1024];
    char script[1024];
    char host_all[HOST_CAP];
    char dev_addr[CELL_DEVICES][HOST_CAP + 8];
    unsigned port_base;
    unsigned connect_ms, reply_ms;
    long long repeat;
    double interval;
    int keep_going, no_history;
} opts_t;

static opts_t g_opt = {.repeat = 1};

/* --robot / --platform / --conditioning HOST[:PORT]: checked now, applied after the file. */
static int on_addr(void *ctx, const cli_opt_t *row, const char *v, char *why, size_t wl)
{
    opts_t *o = ctx;
    char host[HOST_CAP];
    unsigned port = 0;
    if (strlen(v) >= sizeof o->dev_addr[0] || cell_parse_hostport(v, host, sizeof host, &port) != 0) {
        snprintf(why, wl, "expected HOST[:PORT]");
        return -1;
    }
    snprintf(o->dev_addr[row->key], sizeof o->dev_addr[0], "%s", v);
    return 0;
}

static int on_repeat(void *ctx, const cli_opt_t *row, const char *v, char *why, size_t wl)
{
    opts_t *o = ctx;
    long long x = 0;
    (void)row;
    if (tf_parse_int(v, -1, 100000000LL, &x) != TF_NUM_OK || x == 0) {
        snprintf(why, wl, "a count 1..100000000, or -1 for forever");
        return -1;
    }
    o->repeat = x;
    return 0;
}

static const cli_opt_t k_opts[] = {
    {"host", 'H', CLI_STRING, "HOST", "host of all three devices (default 127.0.0.1)",
     g_opt.host_all, sizeof g_opt.host_all, 0, 0, NULL, 0},
    {"port-base", 'p', CLI_UINT, "N", "robot on N, platform N+1, conditioning N+2",
     &g_opt.port_base, 0, 1, 65533, NULL, 0},
    {"robot", 0, CLI_CALL, "HOST[:PORT]", "robot address", NULL, 0, 0, 0, on_addr,
     CELL_DEV_ROBOT},
    {"platform", 0, CLI_CALL, "HOST[:PORT]", "platform address", NULL, 0, 0, 0, on_addr,
     CELL_DEV_PLATFORM},
    {"conditioning", 0, CLI_CALL, "HOST[:PORT]", "conditioning controller address", NULL, 0, 0,
     0, on_addr, CELL_DEV_CONDITIONING},
    {"config", 'c', CLI_STRING, "FILE", "INI file (see below)", g_opt.config,
     sizeof g_opt.config, 0, 0, NULL, 0},
    {"connect-timeout", 0, CLI_UINT, "MS", "connect timeout 1..600000 (default 2000)",
     &g_opt.connect_ms, 0, 1, 600000, NULL, 0},
    {"timeout", 't', CLI_UINT, "MS", "reply timeout 1..600000 (default 2000)", &g_opt.reply_ms,
     0, 1, 600000, NULL, 0},
    {"file", 'f', CLI_STRING, "FILE", "run a script ('-' = stdin)", g_opt.script,
     sizeof g_opt.script, 0, 0, NULL, 0},
    {"keep-going", 'k', CLI_FLAG, NULL, "scripts: do not stop at the first ER reply",
     &g_opt.keep_going, 0, 0, 0, NULL, 0},
    {"echo", 'e', CLI_FLAG, NULL, "scripts: print each command before running it", &g_echo, 0,
     0, 0, NULL, 0},
    {"repeat", 'r', CLI_CALL, "N", "one-shot: run the command N times (-1: forever)", NULL, 0,
     0, 0, on_repeat, 0},
    {"interval", 'i', CLI_DOUBLE, "SEC", "one-shot: pause between repeats 0..86400 (default 0)",
     &g_opt.interval, 0, 0, 86400, NULL, 0},
    {"json", 'j', CLI_FLAG, NULL, "one JSON object per reply", &g_json, 0, 0, 0, NULL, 0},
    {"csv", 0, CLI_FLAG, NULL, "one CSV row per reply, after a header line", &g_csv, 0, 0, 0,
     NULL, 0},
    {"raw", 0, CLI_FLAG, NULL, "replies as the device sent them (default when stdout is not a "
     "terminal)", &g_raw, 0, 0, 0, NULL, 0},
    {"no-raw", 0, CLI_FLAG, NULL, "the human format even when stdout is not a terminal",
     &g_no_raw, 0, 0, 0, NULL, 0},
    {"no-history", 0, CLI_FLAG, NULL, "REPL: do not read or write the history file",
     &g_opt.no_history, 0, 0, 0, NULL, 0},
};

static const char *const k_examples[] = {
    "cell-cli robot sta",
    "cell-cli robot mov abs x=10 y=-2 z=5.999 c=-1.2322",
    "cell-cli --json -r 10 -i 0.5 platform sta        monitor the platform",
    "cell-cli --csv -r -1 -i 1 robot sta > robot.csv  log the robot once a second",
    "cell-cli -p 21001 -f fixtures/cell/pick_and_place.cell",
    "cell-cli raw robot OVR+00050",
    NULL};

static const cli_spec_t k_spec = {
    "cell-cli", NULL,
    "Usage: cell-cli [options] [DEVICE COMMAND [ARGS...]]\n"
    "Terminal client of the cell protocol (robot 2001, platform 2002, conditioning 2003).\n"
    "No command: interactive REPL (libedit: history in ~/.cell_cli_history, TAB completion);\n"
    "with stdin not a terminal, or -f FILE, commands are read as a script.\n",
    k_opts, sizeof k_opts / sizeof k_opts[0], k_examples,
    "Config file (-c FILE, default: $CELL_CLI_CONFIG or ~/.config/cell-cli.ini if present):\n"
    "  [robot] host= port=, [platform], [conditioning], [cli] connect_timeout_ms=\n"
    "  reply_timeout_ms=; options win over the file.\n"
    "\n"
    "Commands (see 'cell-cli help'): DEV sta | srvon | srvof | ovr N | stp | itr | rst | clo,\n"
    "  robot mov abs|rel x= y= z= c=, platform mov abs|rel a= b=, robot pnp clear= x= y= z= c=,\n"
    "  conditioning acq N, conditioning hnd N open|close, raw DEV TEXT,\n"
    "  wait DEV stopped [TIMEOUT], sleep SEC.\n"
    "\n"
    "Exit status: 0 ok, 1 a device replied ER, 2 usage or script error, 3 connection\n"
    "failure or reply timeout, 4 invalid reply, 5 wait timed out.\n",
    0, -1, 0, NULL};

/* The config file: -c, else $CELL_CLI_CONFIG, else ~/.config/cell-cli.ini if present. */
static const char *config_path(void)
{
    static char def[1024];
    const char *env = getenv("CELL_CLI_CONFIG");
    const char *home = getenv("HOME");
    if (g_opt.config[0] != '\0') {
        return g_opt.config;
    }
    if (env != NULL) {
        return env;
    }
    if (home != NULL) {
        snprintf(def, sizeof def, "%s/.config/cell-cli.ini", home);
        if (access(def, R_OK) == 0) {
            return def;
        }
    }
    return NULL;
}

static int load_config(const char *path)
{
    cli_config_t cc;
    char err[600];
    cli_config_default(&cc);
    for (int d = 0; d < CELL_DEVICES; d++) {
        strcpy(cc.host[d], g_conn[d].host);
        cc.port[d] = g_conn[d].port;
    }
    cc.connect_ms = g_connect_ms;
    cc.reply_ms = g_reply_ms;
    if (cli_config_load(&cc, path, err, sizeof err) != 0) {
        fprintf(stderr, "cell-cli: config file %s\n", err);
        return EXIT_USAGE;
    }
    for (int d = 0; d < CELL_DEVICES; d++) {
        strcpy(g_conn[d].host, cc.host[d]);
        g_conn[d].port = cc.port[d];
    }
    g_connect_ms = cc.connect_ms;
    g_reply_ms = cc.reply_ms;
    return EXIT_OK;
}

/* Defaults, then the config file, then the options. */
static int configure(void)
{
    const char *config = config_path();
    for (int d = 0; d < CELL_DEVICES; d++) {
        strcpy(g_conn[d].host, "127.0.0.1");
        g_conn[d].port = cell_dev_default_port(d);
        g_conn[d].fd = -1;
    }
    if (config != NULL && load_config(config) != EXIT_OK) {
        return EXIT_USAGE;
    }
    if (g_opt.connect_ms > 0) {
        g_connect_ms = (int)g_opt.connect_ms;
    }
    if (g_opt.reply_ms > 0) {
        g_reply_ms = (int)g_opt.reply_ms;
    }
    for (int d = 0; d < CELL_DEVICES; d++) {
        if (g_opt.host_all[0] != '\0') {
            strcpy(g_conn[d].host, g_opt.host_all);
        }
        if (g_opt.port_base > 0) {
            g_conn[d].port = g_opt.port_base + (unsigned)d;
        }
        if (g_opt.dev_addr[d][0] != '\0') {
            (void)cell_parse_hostport(g_opt.dev_addr[d], g_conn[d].host, sizeof g_conn[d].host,
                                      &g_conn[d].port); /* checked by on_addr */
        }
    }
    return EXIT_OK;
}

static int run_script_file(const char *script)
{
    int is_stdin = strcmp(script, "-") == 0;
    FILE *f = is_stdin ? stdin : fopen(script, "r");
    int rc;
    if (f == NULL) {
        fprintf(stderr, "cell-cli: cannot open script %s: %s\n", script, strerror(errno));
        return EXIT_USAGE;
    }
    rc = run_script(f, is_stdin ? "stdin" : script, g_opt.keep_going);
    if (!is_stdin) {
        fclose(f);
    }
    return rc;
}

/* One-shot: the operands are one command, run --repeat times. */
static int run_oneshot(int n, char **words)
{
    char text[1024] = "";
    size_t o = 0;
    cli_cmd_t cmd;
    char err[256];
    int rc = EXIT_OK;
    for (int i = 0; i < n; i++) {
        int w = snprintf(text + o, sizeof text - o, "%s%s", i > 0 ? " " : "", words[i]);
        if (w < 0 || (size_t)w >= sizeof text - o) {
            fprintf(stderr, "cell-cli: command too long\n");
            return EXIT_USAGE;
        }
        o += (size_t)w;
    }
    if (cli_cmd_parse(text, &cmd, err, sizeof err) != 0) {
        fprintf(stderr, "cell-cli: %s\n", err);
        return EXIT_USAGE;
    }
    for (long long k = 0; g_opt.repeat < 0 || k < g_opt.repeat; k++) {
        if (k > 0 && g_opt.interval > 0) {
            sleep_s(g_opt.interval);
        }
        rc = run_cmd(&cmd);
        if (rc != EXIT_OK && rc != EXIT_DEVICE_ER) {
            break;
        }
    }
    return rc;
}

int main(int argc, char **argv)
{
    int first = 0;
    int rc;
    cli_result_t pr = cli_parse(&k_spec, &g_opt, argc, argv, &first);
    if (pr != CLI_RUN) {
        return pr == CLI_DONE ? EXIT_OK : EXIT_USAGE;
    }
    if (g_json + g_csv > 1 || g_raw + g_no_raw > 1) {
        cli_error(&k_spec, "--json and --csv, or --raw and --no-raw, exclude each other (see "
                  "cell-cli --help)");
        return EXIT_USAGE;
    }
    g_fmt = g_json ? OUT_JSON : g_csv ? OUT_CSV : g_raw ? OUT_RAW : g_no_raw ? OUT_TEXT
            : isatty(STDOUT_FILENO) ? OUT_TEXT : OUT_RAW;
    g_stamp = g_opt.repeat != 1 || g_opt.interval > 0;
    rc = configure();
    if (rc != EXIT_OK) {
        return rc;
    }
    if (g_opt.script[0] != '\0') {
        if (first < argc) {
            fprintf(stderr, "cell-cli: -f and a command cannot be combined\n");
            return EXIT_USAGE;
        }
        rc = run_script_file(g_opt.script);
    } else if (first < argc && strcmp(argv[first], "canopen") == 0) {
        rc = cli_canopen_run(g_conn[CELL_DEV_PLATFORM].host, g_conn[CELL_DEV_PLATFORM].port + 10U,
                             argc - first - 1, argv + first + 1, g_reply_ms);
    } else if (first < argc) {
        rc = run_oneshot(argc - first, argv + first);
    } else if (isatty(STDIN_FILENO)) {
        rc = run_repl(!g_opt.no_history);
    } else {
        rc = run_script(stdin, "stdin", g_opt.keep_going);
    }
    for (int d = 0; d < CELL_DEVICES; d++) {
        conn_drop(d);
    }
    return rc;
}
