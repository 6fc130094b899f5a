/* SPDX-License-Identifier: MIT */
/* cell-cli: terminal client for the cell's robot, platform and conditioning
 * controllers (REPL with libedit, one-shot, scripts, --json). See docs/cell-cli.md. */
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include <wchar.h>
#include <histedit.h>
#include <jansson.h>

#include "c4gopen.h"
#include "c4gh_cli.h"
#include "c4gh_textfile.h"
#include "c4gh_cell.h"
#include "cli_canopen.h"
#include "cli_cmd.h"
#include "cli_config.h"

enum {
    EXIT_OK = 0,
    EXIT_DEVICE_ER = 1,   /* a device replied ER */
    EXIT_USAGE = 2,       /* bad option, bad command, script syntax */
    EXIT_CONNECT = 3,     /* connection refused / lost / reply timeout */
    EXIT_PROTOCOL = 4,    /* a reply that does not parse */
    EXIT_WAIT = 5,        /* wait ... stopped timed out */
    EXIT_INTR = 130       /* interrupted by ^C (SIGINT), as a shell reports it */
};

typedef struct conn {
    char host[256];
    unsigned port;
    int fd;
    int mid_line;   /* the last byte received ended no line: a line is partly in */
    int stale;      /* that part came before the request: its line is not the reply */
    char buf[C4G_CELL_LINE_MAX];
    c4g_cell_splitter_t sp;
} conn_t;

static conn_t g_conn[C4GH_CELL_DEVICES];
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
static int g_hints = 1; /* [cli] hints in the config file */
static int g_latency;   /* --latency: sample STA reply times (as redis-cli --latency) */
/* A motion this process started (MOV, PNP sent) that no STA has shown finished and no
 * STP stopped: what ^C stops. A monitor (-r robot sta) never stops a robot others move. */
static int g_moved[C4GH_CELL_DEVICES];

/* ^C: the handler only notes it and wakes poll() through a pipe (a flag alone could be set
 * just before a poll that then sleeps its whole timeout). */
static volatile sig_atomic_t g_sigint;
static volatile sig_atomic_t g_winch;
static int g_wake[2] = {-1, -1};
static int g_no_intr; /* set while the STP of an interrupt is sent: a second ^C waits */

static void on_signal(int sig)
{
    const int e = errno;
    if (sig == SIGINT) {
        g_sigint = 1;
    } else {
        g_winch = 1;
    }
    if (g_wake[1] >= 0) {
        (void)!write(g_wake[1], "x", 1);
    }
    errno = e;
}

static void wake_drain(void)
{
    char b[64];
    while (g_wake[0] >= 0 && read(g_wake[0], b, sizeof b) > 0) {
    }
}

static int interrupted(void)
{
    return g_sigint && !g_no_intr;
}

/* SIGINT (and SIGWINCH for the REPL) without SA_RESTART: a blocked read() returns. */
static void signals_setup(int repl)
{
    struct sigaction sa;
    if (pipe(g_wake) == 0) {
        for (int i = 0; i < 2; i++) {
            (void)fcntl(g_wake[i], F_SETFL, fcntl(g_wake[i], F_GETFL) | O_NONBLOCK);
            (void)fcntl(g_wake[i], F_SETFD, FD_CLOEXEC);
        }
    } else {
        g_wake[0] = g_wake[1] = -1;
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    (void)sigaction(SIGINT, &sa, NULL);
    if (repl) {
        (void)sigaction(SIGWINCH, &sa, NULL);
    }
}

/* Waits up to ms (-1: no limit) for fd (-1: none) to be readable or for ^C: 1 readable,
 * 0 time out, EXIT_INTR interrupted. */
static int wait_readable(int fd, int ms)
{
    for (;;) {
        struct pollfd p[2] = {{g_wake[0], POLLIN, 0}, {fd, POLLIN, 0}};
        int pr;
        if (interrupted()) {
            return EXIT_INTR;
        }
        pr = poll(p, 2, ms); /* a negative fd is not polled */
        if (pr < 0 && errno == EINTR) {
            continue;
        }
        if (pr > 0 && p[0].revents != 0) {
            wake_drain();
            if (!interrupted() && p[1].revents == 0) {
                continue;
            }
        }
        if (interrupted()) {
            return EXIT_INTR;
        }
        return pr > 0 ? 1 : 0;
    }
}

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
    c->fd = c4gh_cell_tcp_connect(c->host, c->port, g_connect_ms, &err);
    if (c->fd < 0) {
        fprintf(stderr, "cell-cli: %s at %s:%u: %s\n", c4gh_cell_dev_name(dev), c->host, c->port, err);
        return EXIT_CONNECT;
    }
    (void)c4g_cell_split_init(&c->sp, c->buf, sizeof c->buf);
    c->mid_line = 0;
    c->stale = 0;
    return 0;
}

/* Bytes received into the line splitter. */
static void conn_push(conn_t *c, const char *b, size_t n)
{
    size_t used = 0;
    /* one read never exceeds the splitter capacity; consume what it takes */
    for (size_t o = 0; o < n; o += used) {
        (void)c4g_cell_split_push(&c->sp, b + o, n - o, &used);
        if (used == 0) {
            break;
        }
    }
    if (n > 0) {
        c->mid_line = b[n - 1] != '\n';
    }
}

/* A line nobody asked for, shown escaped and dropped. */
static void unsolicited(int dev, const char *l, size_t n)
{
    char shown[C4G_CELL_LINE_MAX * 4 + 4];
    size_t ll = (n >= 2 && l[n - 2] == '\r') ? n - 2 : (n >= 1 && l[n - 1] == '\n') ? n - 1 : n;
    c4gh_tf_escape(l, ll, shown, sizeof shown);
    fprintf(stderr, "cell-cli: %s: unsolicited line dropped: \"%s\"\n", c4gh_cell_dev_name(dev), shown);
}

/* Before a request: what the device sent unasked (an alarm, a late or extra reply) is
 * read and dropped, so that it cannot pass for the reply. A line partly in is stale too. */
static void conn_drain(int dev)
{
    conn_t *c = &g_conn[dev];
    char tmp[C4G_CELL_LINE_MAX];
    ssize_t r;
    while ((r = recv(c->fd, tmp, sizeof tmp, MSG_DONTWAIT)) > 0) {
        conn_push(c, tmp, (size_t)r);
    }
    for (;;) {
        c4g_cell_split_event_t ev;
        const char *l = NULL;
        size_t n = 0;
        (void)c4g_cell_split_next(&c->sp, &ev, &l, &n);
        if (ev == C4G_CELL_SPLIT_LINE) {
            unsolicited(dev, l, n);
        } else if (ev == C4G_CELL_SPLIT_OVERLONG) {
            fprintf(stderr, "cell-cli: %s: unsolicited line longer than %u bytes dropped\n",
                    c4gh_cell_dev_name(dev), (unsigned)C4G_CELL_LINE_MAX);
        } else {
            break;
        }
    }
    c->stale = c->mid_line;
}

/* Send one line, read one reply line (CR LF included) into reply. */
static int transact(int dev, const char *line, size_t len, char *reply, size_t cap,
                    size_t *rlen)
{
    conn_t *c = &g_conn[dev];
    int rc;
    size_t off = 0;
    uint64_t deadline;
    if (interrupted()) {
        return EXIT_INTR;
    }
    rc = conn_get(dev);
    if (rc != 0) {
        return rc;
    }
    conn_drain(dev);
    while (off < len) {
        ssize_t w = send(c->fd, line + off, len - off, MSG_NOSIGNAL);
        if (w < 0) {
            if (errno == EINTR) {
                continue;
            }
            fprintf(stderr, "cell-cli: %s: send failed: %s\n", c4gh_cell_dev_name(dev), strerror(errno));
            conn_drop(dev);
            return EXIT_CONNECT;
        }
        off += (size_t)w;
    }
    deadline = c4gh_now_ns() + (uint64_t)g_reply_ms * 1000000ULL;
    for (;;) {
        c4g_cell_split_event_t ev;
        const char *l = NULL;
        size_t n = 0;
        (void)c4g_cell_split_next(&c->sp, &ev, &l, &n);
        if (ev == C4G_CELL_SPLIT_LINE && c->stale) {
            c->stale = 0; /* it began before the request */
            unsolicited(dev, l, n);
            continue;
        }
        if (ev == C4G_CELL_SPLIT_LINE) {
            if (n > cap) {
                n = cap;
            }
            memcpy(reply, l, n);
            *rlen = n;
            return 0;
        }
        if (ev == C4G_CELL_SPLIT_OVERLONG) {
            fprintf(stderr, "cell-cli: %s: reply longer than %u bytes\n", c4gh_cell_dev_name(dev),
                    (unsigned)C4G_CELL_LINE_MAX);
            conn_drop(dev);
            return EXIT_PROTOCOL;
        }
        uint64_t now = c4gh_now_ns();
        if (now >= deadline) {
            fprintf(stderr, "cell-cli: %s: no reply within %d ms\n", c4gh_cell_dev_name(dev), g_reply_ms);
            conn_drop(dev); /* a late reply would desynchronise the next request */
            return EXIT_CONNECT;
        }
        rc = wait_readable(c->fd, (int)((deadline - now) / 1000000ULL) + 1);
        if (rc == EXIT_INTR) {
            conn_drop(dev); /* the reply still due would desynchronise the next request */
            return EXIT_INTR;
        }
        if (rc == 0) {
            continue; /* the deadline check above reports the timeout */
        }
        char tmp[C4G_CELL_LINE_MAX];
        ssize_t r = recv(c->fd, tmp, sizeof tmp, 0);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r <= 0) {
            fprintf(stderr, "cell-cli: %s: connection closed by the device\n", c4gh_cell_dev_name(dev));
            conn_drop(dev);
            return EXIT_CONNECT;
        }
        conn_push(c, tmp, (size_t)r);
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
    json_object_set_new(o, "device", json_string(c4gh_cell_dev_name(dev)));
    return o;
}

/* Non-ASCII as \uNNNN (a device's 0x9B must not reach a terminal as the C1 CSI it is in
 * UTF-8), and DEL, which jansson leaves as it is, as \u007f. */
static void json_emit(json_t *o)
{
    char *t = json_dumps(o, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_ENSURE_ASCII |
                                JSON_REAL_PRECISION(10));
    for (const char *p = t; p != NULL && *p != '\0'; p++) {
        if (*p == 0x7F) {
            fputs("\\u007f", stdout);
        } else {
            fputc(*p, stdout);
        }
    }
    fputc('\n', stdout);
    free(t);
    json_decref(o);
}

/* A device's line for a terminal or a pipe: printable ASCII as it is, every other byte
 * (and the backslash) as \xNN, so that no escape sequence of a device reaches the screen. */
static void put_escaped(const char *s, size_t n)
{
    char shown[C4G_CELL_LINE_MAX * 4 + 4];
    c4gh_tf_escape(s, n, shown, sizeof shown);
    fputs(shown, stdout);
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
    return dev == C4GH_CELL_DEV_ROBOT ? r[a] : p[a];
}

static c4g_cell_unit_t axis_unit(int dev, int a)
{
    return (dev == C4GH_CELL_DEV_ROBOT && a < 3) ? C4G_CELL_UNIT_MM : C4G_CELL_UNIT_RAD;
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

/* A reply that does not decode, or does not fit the request (problem; column 0: none). */
static int show_invalid(int dev, const char *req, size_t rl, const char *line, size_t len,
                        const char *problem, size_t column)
{
    size_t ll = (len >= 2 && line[len - 1] == '\n') ? len - 2 : len;
    if (g_fmt == OUT_JSON) {
        json_t *o = json_head(dev);
        json_object_set_new(o, "request", json_bytes(req, rl));
        json_object_set_new(o, "reply", json_string("invalid"));
        json_object_set_new(o, "raw", json_bytes(line, len));
        json_object_set_new(o, "problem", json_string(problem));
        json_object_set_new(o, "column", json_integer((json_int_t)column));
        json_emit(o);
    } else if (g_fmt == OUT_CSV) {
        csv_row(dev, req, rl, line, ll, NULL);
    } else if (g_fmt == OUT_RAW) {
        put_escaped(line, ll);
        fputc('\n', stdout);
    } else {
        printf("%s: invalid reply \"", c4gh_cell_dev_name(dev));
        put_escaped(line, ll);
        printf("\" to ");
        put_escaped(req, rl);
        printf(": %s", problem);
        if (column > 0) {
            printf(" at column %zu", column);
        }
        printf("\n");
    }
    fflush(stdout);
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
    printf("%s,", c4gh_cell_dev_name(dev));
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
        printf("%s: ER %+06d  %s (%s)\n", c4gh_cell_dev_name(dev), (int)r->error, etext,
               project ? "project code" : "spec");
        return;
    }
    if (r->kind == C4G_CELL_REPLY_OK) {
        printf("%s: OK\n", c4gh_cell_dev_name(dev));
        return;
    }
    /* The error field is the last error, latched until RST: after an error the command that
     * fixed it (servo on) does not clear it, so it is shown as history, not as the state. */
    printf("%s: %s, servo %s, override %d %%, %s %+06d (%s)%s\n", c4gh_cell_dev_name(dev),
           r->moving ? "MOVING" : "stopped", r->servo_on ? "ON" : "off", (int)r->override_pct,
           r->error != 0 ? "last error" : "error", (int)r->error, etext,
           r->error != 0 ? ", latched until rst" : "");
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

/* The kind of reply a request line asks for; -1 for a line that is no instruction (raw
 * text), which any reply fits. */
static int reply_wanted(const char *req, size_t len)
{
    c4g_cell_instr_t in;
    c4g_cell_cmd_info_t info;
    if (c4g_cell_instr_decode(req, len, &in, NULL) != C4G_OK ||
        c4g_cell_cmd_info(in.cmd, &info) != C4G_OK) {
        return -1;
    }
    return (int)info.reply;
}

/* Why a reply that decodes does not answer the request (NULL: it does). ER answers any. */
static const char *reply_misfit(int dev, int want, const c4g_cell_reply_t *r)
{
    if (r->kind == C4G_CELL_REPLY_ER || want < 0) {
        return NULL;
    }
    if (want == C4G_CELL_REPLY_STA && r->kind != C4G_CELL_REPLY_STA) {
        return "a bare OK where a status reply (OK and the status fields) was expected";
    }
    if (want != C4G_CELL_REPLY_STA && r->kind == C4G_CELL_REPLY_STA) {
        return "a status reply where a bare OK was expected";
    }
    if (r->kind == C4G_CELL_REPLY_STA && dev == C4GH_CELL_DEV_ROBOT && r->pose.n_axes != 4U) {
        return "a status of 2 axes (a platform's) where the robot's 4 were expected";
    }
    if (r->kind == C4G_CELL_REPLY_STA && dev == C4GH_CELL_DEV_PLATFORM && r->pose.n_axes != 2U) {
        return "a status of 4 axes (a robot's) where the platform's 2 were expected";
    }
    return NULL;
}

/* Decodes a reply to req and checks its shape: 0 and *r, or the invalid reply shown. */
static int decode_reply(int dev, const char *req, size_t req_len, const char *line, size_t len,
                        c4g_cell_reply_t *r)
{
    c4g_cell_diag_t d;
    const char *misfit;
    size_t rl = (req_len >= 2) ? req_len - 2 : req_len;
    c4g_status_t st = c4g_cell_reply_decode(line, len, r, &d);
    if (st != C4G_OK) {
        return show_invalid(dev, req, rl, line, len, c4g_strerror(st), d.column);
    }
    misfit = reply_misfit(dev, reply_wanted(req, req_len), r);
    if (misfit != NULL) {
        return show_invalid(dev, req, rl, line, len, misfit, 0);
    }
    /* what ^C stops: a motion shown finished, or stopped, needs no STP */
    if (r->kind == C4G_CELL_REPLY_STA && !r->moving) {
        g_moved[dev] = 0;
    } else if (r->kind == C4G_CELL_REPLY_OK && reply_wanted(req, req_len) >= 0) {
        c4g_cell_instr_t in;
        (void)c4g_cell_instr_decode(req, req_len, &in, NULL);
        if (in.cmd == C4G_CELL_CMD_STP || in.cmd == C4G_CELL_CMD_ITR ||
            in.cmd == C4G_CELL_CMD_RST) {
            g_moved[dev] = 0;
        }
    }
    return 0;
}

/* Show a reply; returns the exit class it implies. */
static int show_reply(int dev, const char *req, size_t req_len, const char *line, size_t len)
{
    c4g_cell_reply_t r;
    size_t rl = (req_len >= 2) ? req_len - 2 : req_len;
    size_t ll = (len >= 2 && line[len - 1] == '\n') ? len - 2 : len;
    int rc = decode_reply(dev, req, req_len, line, len, &r);
    if (rc != 0) {
        return rc;
    }
    if (g_fmt == OUT_JSON) {
        show_json(dev, req, rl, line, ll, &r);
    } else if (g_fmt == OUT_CSV) {
        csv_row(dev, req, rl, line, ll, &r);
    } else if (g_fmt == OUT_RAW) {
        put_escaped(line, ll);
        fputc('\n', stdout);
    } else {
        show_text(dev, &r);
    }
    fflush(stdout);
    return r.kind == C4G_CELL_REPLY_ER ? EXIT_DEVICE_ER : EXIT_OK;
}

/* A pause that ^C ends: EXIT_OK, or EXIT_INTR. */
static int sleep_s(double s)
{
    const uint64_t end = c4gh_now_ns() + (uint64_t)(s * 1e9);
    for (;;) {
        const uint64_t now = c4gh_now_ns();
        if (now >= end) {
            return interrupted() ? EXIT_INTR : EXIT_OK;
        }
        if (wait_readable(-1, (int)((end - now + 999999ULL) / 1000000ULL)) == EXIT_INTR) {
            return EXIT_INTR;
        }
    }
}

/* Poll STA every 50 ms until the device reports 'F' (stopped). */
static int wait_stopped(int dev, double timeout_s)
{
    uint64_t deadline = c4gh_now_ns() + (uint64_t)(timeout_s * 1e9);
    for (;;) {
        char reply[C4G_CELL_LINE_MAX];
        size_t n = 0;
        c4g_cell_reply_t r;
        int rc = transact(dev, "STA\r\n", 5, reply, sizeof reply, &n);
        if (rc != 0) {
            return rc;
        }
        rc = decode_reply(dev, "STA\r\n", 5, reply, n, &r); /* a bare OK is no status */
        if (rc != 0) {
            return rc;
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
                printf("%s: stopped\n", c4gh_cell_dev_name(dev));
            }
            fflush(stdout);
            return EXIT_OK;
        }
        if (c4gh_now_ns() >= deadline) {
            fprintf(stderr, "cell-cli: wait %s stopped: still moving after %g s\n",
                    c4gh_cell_dev_name(dev), timeout_s);
            return EXIT_WAIT;
        }
        if (sleep_s(0.05) != EXIT_OK) {
            return EXIT_INTR;
        }
    }
}

/* After ^C: STP to each device whose motion this process started (and that no reply has
 * shown finished), its reply shown. A second ^C meanwhile does not cut the STP short. */
static void stop_after_interrupt(void)
{
    g_no_intr = 1;
    wake_drain();
    if (isatty(STDERR_FILENO)) {
        fputc('\n', stderr); /* after the "^C" the terminal echoed */
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        char reply[C4G_CELL_LINE_MAX];
        size_t n = 0;
        if (!g_moved[d]) {
            continue;
        }
        fprintf(stderr, "cell-cli: %s: interrupted: sending STP to stop the motion started here\n",
                c4gh_cell_dev_name(d));
        if (transact(d, "STP\r\n", 5, reply, sizeof reply, &n) == 0) {
            (void)show_reply(d, "STP\r\n", 5, reply, n);
        }
    }
    fprintf(stderr, "cell-cli: interrupted\n");
    fflush(stdout);
    g_sigint = 0;
    g_no_intr = 0;
    wake_drain();
}

/* A motion is about to start: ^C will stop it. */
static void note_motion(int dev, const char *line, size_t len)
{
    c4g_cell_instr_t in;
    if (c4g_cell_instr_decode(line, len, &in, NULL) == C4G_OK &&
        (in.cmd == C4G_CELL_CMD_MOV || in.cmd == C4G_CELL_CMD_PNP)) {
        g_moved[dev] = 1;
    }
}

/* "HOST:PORT" of each device, for help */
static void help_addresses(char addr[C4GH_CELL_DEVICES][sizeof g_conn[0].host + 8],
                           const char *ptr[C4GH_CELL_DEVICES])
{
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        snprintf(addr[d], sizeof addr[d], "%.255s:%u", g_conn[d].host, g_conn[d].port);
        ptr[d] = addr[d];
    }
}

/* connect: new addresses, the old connections closed, each new one opened at once so the
 * user learns now whether it answers (a device that does not is reported, not fatal). */
static int run_connect(const cli_cmd_t *cmd)
{
    int rc = EXIT_OK;
    /* a motion started here that no reply showed finished: leaving its connection would
     * leave it without the STP a ^C sends, so it is stopped or waited for first */
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        if ((cmd->dev < 0 || d == cmd->dev) && g_moved[d]) {
            fprintf(stderr, "cell-cli: %s: a motion started here is not seen finished: '%s stp' "
                            "or 'wait %s stopped' before connect\n", c4gh_cell_dev_name(d),
                    c4gh_cell_dev_name(d), c4gh_cell_dev_name(d));
            return EXIT_USAGE;
        }
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        if (cmd->dev >= 0 && d != cmd->dev) {
            continue;
        }
        conn_drop(d);
        snprintf(g_conn[d].host, sizeof g_conn[d].host, "%s", cmd->host);
        if (cmd->dev >= 0 && cmd->port > 0) {
            g_conn[d].port = cmd->port;
        } else if (cmd->dev < 0 && cmd->port > 0) {
            g_conn[d].port = cmd->port + (unsigned)d;
        }
        if (conn_get(d) == 0) {
            printf("%s: connected to %s:%u\n", c4gh_cell_dev_name(d), g_conn[d].host, g_conn[d].port);
            g_last_dev = d;
        } else {
            rc = EXIT_CONNECT;
        }
    }
    return rc;
}

static int run_once(const cli_cmd_t *cmd);

/* Execute one command, "N CMD" N times: it stops at the first failure (an ER reply
 * included: the next repeat would act on a device that refused) and at ^C. */
static int run_cmd(const cli_cmd_t *cmd)
{
    int rc = EXIT_OK;
    for (long k = 0; k < cmd->repeat || (k == 0 && cmd->repeat <= 0); k++) {
        rc = run_once(cmd);
        if (rc != EXIT_OK) {
            break;
        }
    }
    return rc;
}

static int run_once(const cli_cmd_t *cmd)
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
    case CMD_HELP: {
        char addr[C4GH_CELL_DEVICES][sizeof g_conn[0].host + 8];
        const char *ptr[C4GH_CELL_DEVICES];
        help_addresses(addr, ptr); /* the ones in use, not the defaults */
        rc = cli_cmd_help_at(cmd->topic, ptr, help, sizeof help);
        fputs(help, stdout);
        return rc == 0 ? EXIT_OK : EXIT_USAGE;
    }
    case CMD_CONNECT:
        rc = run_connect(cmd);
        break;
    case CMD_SLEEP:
        rc = sleep_s(cmd->seconds);
        break;
    case CMD_WAIT:
        g_last_dev = cmd->dev;
        rc = wait_stopped(cmd->dev, cmd->seconds);
        break;
    case CMD_SEND:
    case CMD_RAW:
        g_last_dev = cmd->dev;
        note_motion(cmd->dev, cmd->line, cmd->len);
        rc = transact(cmd->dev, cmd->line, cmd->len, reply, sizeof reply, &n);
        if (rc != 0) {
            break;
        }
        rc = show_reply(cmd->dev, cmd->line, cmd->len, reply, n);
        if (cmd->kind == CMD_SEND && cmd->instr.cmd == C4G_CELL_CMD_CLO && rc == EXIT_OK) {
            conn_drop(cmd->dev); /* the device closes after OK */
        }
        break;
    default:
        rc = EXIT_USAGE;
        break;
    }
    /* ^C during a part that does not wait for it (a connect): the same as during a wait */
    if (rc == EXIT_INTR || interrupted()) {
        stop_after_interrupt();
        rc = EXIT_INTR;
    }
    return rc;
}

/* ------------------------------------------------------------------ modes */

/* --latency: STA to one device every 10 ms, its reply time's min, max and average, shown
 * in place on a terminal and once a second otherwise, until ^C or -r N samples; a final
 * line either way. Only STA: it moves nothing. */
static void latency_line(int dev, const uint64_t st[3], unsigned long long n, int final)
{
    const int tty = isatty(STDOUT_FILENO);
    printf("%s%s %s:%u: min %.3f, max %.3f, avg %.3f ms (%llu samples)%s",
           tty && !final ? "\r\033[K" : "", c4gh_cell_dev_name(dev), g_conn[dev].host,
           g_conn[dev].port, (double)st[0] / 1e6, (double)st[1] / 1e6,
           n > 0 ? (double)st[2] / 1e6 / (double)n : 0.0, n, tty && !final ? "" : "\n");
    fflush(stdout);
}

static int run_latency(int n_words, char **words, long long samples)
{
    cli_cmd_t cmd;
    char err[256], text[64], reply[C4G_CELL_LINE_MAX];
    uint64_t st[3] = {UINT64_MAX, 0, 0}; /* min, max, sum [ns] */
    uint64_t last_line = c4gh_now_ns();
    unsigned long long n = 0;
    const int dev = n_words > 0 ? c4gh_cell_dev_parse(words[0]) : C4GH_CELL_DEV_ROBOT;
    int rc = EXIT_OK;
    if (n_words > 1 || dev < 0 || dev == C4GH_CELL_DEV_CONDITIONING) {
        fprintf(stderr, "cell-cli: --latency [robot|platform]: STA needs a device with axes\n");
        return EXIT_USAGE;
    }
    snprintf(text, sizeof text, "%s sta", c4gh_cell_dev_name(dev));
    if (cli_cmd_parse(text, &cmd, err, sizeof err) != 0) {
        fprintf(stderr, "cell-cli: %s\n", err);
        return EXIT_USAGE;
    }
    while (samples <= 1 || n < (unsigned long long)samples) {
        size_t len = 0;
        c4g_cell_reply_t r;
        const uint64_t t0 = c4gh_now_ns();
        uint64_t dt;
        rc = transact(dev, cmd.line, cmd.len, reply, sizeof reply, &len);
        if (rc == EXIT_OK) {
            rc = decode_reply(dev, cmd.line, cmd.len, reply, len, &r);
        }
        if (rc != EXIT_OK) {
            break;
        }
        dt = c4gh_now_ns() - t0;
        st[0] = dt < st[0] ? dt : st[0];
        st[1] = dt > st[1] ? dt : st[1];
        st[2] += dt;
        n++;
        if (isatty(STDOUT_FILENO) || c4gh_now_ns() - last_line >= 1000000000ULL) {
            latency_line(dev, st, n, 0);
            last_line = c4gh_now_ns();
        }
        if (sleep_s(0.01) == EXIT_INTR) {
            break;
        }
    }
    if (n == 0) {
        st[0] = 0;
    }
    if (isatty(STDOUT_FILENO)) {
        printf("\n");
    }
    latency_line(dev, st, n, 1);
    return rc == EXIT_INTR ? EXIT_OK : rc; /* ^C is how a latency run ends */
}

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
        if (interrupted()) {
            break; /* ^C while a line was read: it may be cut short, it does not run */
        }
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
    if (interrupted()) {
        stop_after_interrupt();
        return EXIT_INTR;
    }
    return worst;
}

/* The REPL runs on libedit's own interface (histedit.h): its readline emulation has no
 * hook that runs as each key is typed, which hints as you type need. */
typedef struct repl {
    char prompt[sizeof g_conn[0].host + 64];
    int hints;             /* show a hint after the line as it is typed */
    int hint_shown;        /* a hint is on the screen right of the cursor */
    unsigned long keys;    /* keys read so far (the first is key 1) */
    unsigned long tab_key; /* the number of the last TAB that left several choices; 0 none */
} repl_t;

static repl_t g_repl;

static char *repl_prompt(EditLine *el)
{
    (void)el;
    return g_repl.prompt;
}

static void hint_erase(void)
{
    if (g_repl.hint_shown) {
        fputs("\033[K", stdout); /* the hint is all that is right of the cursor */
        fflush(stdout);
        g_repl.hint_shown = 0;
    }
}

/* The hint in grey after the line, the cursor left where it was (redis-cli's look). Only
 * when the cursor ends a one-row line of printable ASCII with room for the hint, and no key
 * is waiting (a paste or an escape sequence is not interrupted): libedit knows nothing of
 * the hint, which hint_erase() takes away before libedit acts on the next key. */
static void hint_show(EditLine *el)
{
    const LineInfo *li = el_line(el);
    size_t len = (size_t)(li->lastchar - li->buffer);
    size_t col = strlen(g_repl.prompt) + len;
    char line[512], hint[256];
    int cols = 0;
    size_t hl;
    struct pollfd p = {STDIN_FILENO, POLLIN, 0};
    if (!g_repl.hints || li->cursor != li->lastchar || len >= sizeof line || poll(&p, 1, 0) > 0) {
        return;
    }
    for (size_t i = 0; i < len; i++) {
        if (li->buffer[i] < 0x20 || li->buffer[i] > 0x7E) {
            return;
        }
    }
    memcpy(line, li->buffer, len);
    line[len] = '\0';
    hl = cli_cmd_hint(line, hint, sizeof hint);
    if (hl == 0 || el_get(el, EL_GETTC, "co", &cols, NULL) != 0 || cols <= 0 ||
        col + 2 > (size_t)cols) {
        return;
    }
    if (hl > (size_t)cols - 1 - col) {
        hl = (size_t)cols - 1 - col; /* never wrap: the cursor must come back on this row */
    }
    printf("\033[90m%.*s\033[0m\033[%zuD", (int)hl, hint, hl);
    fflush(stdout);
    g_repl.hint_shown = 1;
}

/* libedit's read of one key, with the hint shown while it waits. */
static int repl_getc(EditLine *el, wchar_t *wc)
{
    char b[MB_LEN_MAX];
    size_t n = 0;
    hint_show(el);
    for (;;) {
        mbstate_t st;
        size_t k;
        ssize_t r;
        int w;
        if (g_winch) {
            g_winch = 0;
            el_resize(el);
        }
        w = wait_readable(STDIN_FILENO, -1);
        if (w == EXIT_INTR) {
            /* ^C: the key bound to repl_intr (the terminal turns a typed ^C into SIGINT,
             * so this key never comes from the keyboard) */
            g_sigint = 0;
            hint_erase();
            *wc = (wchar_t)3;
            g_repl.keys++;
            return 1;
        }
        if (w == 0) {
            continue; /* a window resize */
        }
        r = read(STDIN_FILENO, b + n, 1);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r <= 0) {
            hint_erase();
            *wc = L'\0';
            return r < 0 ? -1 : 0;
        }
        n++;
        memset(&st, 0, sizeof st);
        k = mbrtowc(wc, b, n, &st);
        if (k == (size_t)-2 && n < sizeof b) {
            continue; /* more bytes of one character */
        }
        if (k == (size_t)-1 || k == (size_t)-2) {
            n = 0; /* not a character: dropped, as libedit's own read does */
            continue;
        }
        break;
    }
    hint_erase();
    g_repl.keys++;
    return 1;
}

static int cmp_word(const void *a, const void *b)
{
    return strcasecmp(*(const char *const *)a, *(const char *const *)b);
}

/* The choices as readline lists them: sorted, in columns, down then across. */
static void list_choices(EditLine *el, const char **m, size_t n)
{
    size_t w = 0, ncol, nrow;
    int cols = 80;
    qsort(m, n, sizeof m[0], cmp_word);
    for (size_t i = 0; i < n; i++) {
        w = strlen(m[i]) > w ? strlen(m[i]) : w;
    }
    if (el_get(el, EL_GETTC, "co", &cols, NULL) != 0 || cols < 20) {
        cols = 80;
    }
    ncol = (size_t)cols / (w + 2) > 0 ? (size_t)cols / (w + 2) : 1;
    nrow = (n + ncol - 1) / ncol;
    fputc('\n', stdout);
    for (size_t r = 0; r < nrow; r++) {
        for (size_t c = 0; c < ncol && c * nrow + r < n; c++) {
            printf("%-*s", (int)(w + 2), m[c * nrow + r]);
        }
        fputc('\n', stdout);
    }
}

/* Replace the word before the cursor (wl bytes) with the first tl bytes of text. */
static void replace_word(EditLine *el, size_t wl, const char *text, size_t tl, int space)
{
    char ins[64];
    snprintf(ins, sizeof ins, "%.*s%s", (int)tl, text, space ? " " : "");
    el_deletestr(el, (int)wl);
    (void)el_insertstr(el, ins);
}

/* The words before the one being completed (at most 2 kept), their count in *n. */
static void words_before(const LineInfo *li, size_t start, char *buf, size_t cap, char **w,
                         int *n)
{
    size_t pl = start < cap ? start : cap - 1U;
    memcpy(buf, li->buffer, pl);
    buf[pl] = '\0';
    *n = 0;
    w[0] = w[1] = NULL;
    for (char *p = strtok(buf, " \t"); p != NULL; p = strtok(NULL, " \t")) {
        if (p == buf + strspn(buf, " \t") && strspn(p, "0123456789") == strlen(p)) {
            continue; /* the count of "N CMD": the command's words follow */
        }
        if (*n < 2) {
            w[*n] = p;
        }
        (*n)++;
    }
}

/* TAB: one choice completes the word (a space follows unless it ends in '='); several
 * complete their common part, and a second TAB in a row lists them; none: the usage of
 * the command being typed (cli_cmd_help), below the line. */
static unsigned char repl_complete(EditLine *el, int ch)
{
    const LineInfo *li = el_line(el);
    size_t end = (size_t)(li->cursor - li->buffer), start = end, wl, cl;
    char buf[512], help[512];
    char *w[2];
    const char *m[64];
    size_t nm = 0;
    int n = 0;
    const char *const *list;
    (void)ch;
    while (start > 0 && li->buffer[start - 1] != ' ' && li->buffer[start - 1] != '\t') {
        start--;
    }
    wl = end - start;
    words_before(li, start, buf, sizeof buf, w, &n);
    list = cli_cmd_words(n, w[0] ? w[0] : "", n >= 2 ? w[1] : NULL);
    for (size_t i = 0; list != NULL && list[i] != NULL && nm < 64; i++) {
        if (strlen(list[i]) >= wl && strncasecmp(list[i], li->buffer + start, wl) == 0) {
            m[nm++] = list[i];
        }
    }
    if (nm == 0) {
        const char *topic = (n >= 2 && c4gh_cell_dev_parse(w[0]) >= 0) ? w[1] : w[0];
        if (list != NULL || n == 0 || cli_cmd_help(topic, help, sizeof help) != 0) {
            return CC_ERROR;
        }
        printf("\n%s", help); /* nothing to complete: the usage, as a hint */
        return CC_REDISPLAY;
    }
    if (nm == 1) {
        cl = strlen(m[0]);
        replace_word(el, wl, m[0], cl, m[0][cl - 1] != '=');
        return CC_REFRESH;
    }
    cl = strlen(m[0]); /* the common part of the choices */
    for (size_t i = 1; i < nm; i++) {
        size_t j = 0;
        while (j < cl && tolower((unsigned char)m[i][j]) == tolower((unsigned char)m[0][j])) {
            j++;
        }
        cl = j;
    }
    if (cl > wl) {
        replace_word(el, wl, m[0], cl, 0);
        g_repl.tab_key = g_repl.keys;
        return CC_REFRESH_BEEP;
    }
    if (g_repl.tab_key != 0 && g_repl.tab_key + 1 == g_repl.keys) {
        list_choices(el, m, nm);
        return CC_REDISPLAY;
    }
    g_repl.tab_key = g_repl.keys;
    return CC_ERROR;
}

/* ^Z stops the process as in a shell (the terminal is in libedit's raw mode, which is
 * set again when the shell brings the REPL back). */
static unsigned char repl_tstp(EditLine *el, int ch)
{
    struct termios t;
    const int have = tcgetattr(STDIN_FILENO, &t) == 0;
    (void)el;
    (void)ch;
    (void)kill(0, SIGTSTP);
    if (have) {
        (void)tcsetattr(STDIN_FILENO, TCSADRAIN, &t);
    }
    return CC_REDISPLAY;
}

/* ^C at the prompt: the line is dropped as a shell drops it ("^C", a fresh prompt); the
 * REPL stays. An empty command ends el_gets (an empty line would read as end of input). */
static unsigned char repl_intr(EditLine *el, int ch)
{
    const LineInfo *li = el_line(el);
    (void)ch;
    el_cursor(el, (int)(li->lastchar - li->cursor));
    li = el_line(el);
    el_deletestr(el, (int)(li->cursor - li->buffer));
    fputs("^C\n", stdout);
    fflush(stdout);
    (void)el_insertstr(el, "\n");
    return CC_NEWLINE;
}

/* Emacs keys, TAB completion, readline's extra keys (Home, End, Delete, ^R, Ctrl+arrows),
 * then ~/.editrc (or $EDITRC), which may change any of them. */
static void repl_keys(EditLine *el)
{
    static const char *const bind[][2] = {
        {"^R", "em-inc-search-prev"},   {"\\e[1~", "ed-move-to-beg"},
        {"\\e[4~", "ed-move-to-end"},   {"\\e[7~", "ed-move-to-beg"},
        {"\\e[8~", "ed-move-to-end"},   {"\\e[H", "ed-move-to-beg"},
        {"\\e[F", "ed-move-to-end"},    {"\\e[3~", "ed-delete-next-char"},
        {"\\e[2~", "ed-quoted-insert"}, {"\\e[1;5C", "em-next-word"},
        {"\\e[1;5D", "ed-prev-word"},   {"\\e[5C", "em-next-word"},
        {"\\e[5D", "ed-prev-word"},     {"\\e\\e[C", "em-next-word"},
        {"\\e\\e[D", "ed-prev-word"}};
    el_set(el, EL_EDITOR, "emacs");
    /* the wide el_wset: the narrow el_set copies a new function's name and help, and those
     * copies are never freed */
    el_wset(el, EL_ADDFN, L"cell-complete", L"complete a cell-cli word", repl_complete);
    el_set(el, EL_BIND, "^I", "cell-complete", NULL);
    el_wset(el, EL_ADDFN, L"cell-tstp", L"suspend cell-cli", repl_tstp);
    el_set(el, EL_BIND, "^Z", "cell-tstp", NULL);
    el_wset(el, EL_ADDFN, L"cell-intr", L"drop the line (^C)", repl_intr);
    el_set(el, EL_BIND, "^C", "cell-intr", NULL);
    for (size_t i = 0; i < sizeof bind / sizeof bind[0]; i++) {
        el_set(el, EL_BIND, bind[i][0], bind[i][1], NULL);
    }
    (void)el_source(el, NULL);
}

/* Hints need a terminal that takes colours and cursor moves: not TERM=dumb (nor unset), as
 * linenoise decides for redis-cli. */
static int hints_possible(void)
{
    const char *term = getenv("TERM");
    return isatty(STDOUT_FILENO) && term != NULL && term[0] != '\0' &&
           strcmp(term, "dumb") != 0;
}

static void repl_set_prompt(void)
{
    /* the device of the last command and its address while its connection is open */
    if (g_last_dev >= 0 && g_conn[g_last_dev].fd >= 0) {
        snprintf(g_repl.prompt, sizeof g_repl.prompt, "cell %s@%s:%u> ",
                 c4gh_cell_dev_name(g_last_dev), g_conn[g_last_dev].host, g_conn[g_last_dev].port);
    } else {
        snprintf(g_repl.prompt, sizeof g_repl.prompt, "cell not connected> ");
    }
}

/* One line of the REPL; 1 to leave it. */
static int repl_line(const char *got, int n)
{
    char line[1024];
    cli_cmd_t cmd;
    char err[256];
    size_t len = n > 0 ? (size_t)n : 0U;
    while (len > 0 && (got[len - 1] == '\n' || got[len - 1] == '\r')) {
        len--;
    }
    if (len >= sizeof line) {
        printf("error: command too long\n");
        return 0;
    }
    memcpy(line, got, len);
    line[len] = '\0';
    if (cli_cmd_parse(line, &cmd, err, sizeof err) != 0) {
        printf("error: %s\n", err);
    } else if (cmd.kind == CMD_QUIT) {
        return 1;
    } else {
        (void)run_cmd(&cmd); /* the REPL shows errors and carries on */
    }
    fflush(stdout);
    return 0;
}

static int run_repl(int use_history, int hints)
{
    char hist[1024] = "";
    const char *hf = getenv("CELL_CLI_HISTFILE");
    const char *home = getenv("HOME");
    HistEvent ev;
    History *h = history_init();
    EditLine *el = el_init("cell-cli", stdin, stdout, stderr);
    if (h == NULL || el == NULL) {
        fprintf(stderr, "cell-cli: cannot start the line editor; reading commands as a script\n");
        if (h != NULL) {
            history_end(h);
        }
        return run_script(stdin, "stdin", 1);
    }
    if (hf != NULL) {
        snprintf(hist, sizeof hist, "%s", hf);
    } else if (home != NULL) {
        snprintf(hist, sizeof hist, "%s/.cell_cli_history", home);
    }
    use_history = use_history && hist[0] != '\0';
    (void)history(h, &ev, H_SETSIZE, 1000);
    (void)history(h, &ev, H_SETUNIQUE, 1); /* a command repeated is kept once */
    if (use_history) {
        (void)history(h, &ev, H_LOAD, hist); /* a missing file is an empty history */
    }
    g_repl.hints = hints && hints_possible();
    el_set(el, EL_HIST, history, h);
    el_set(el, EL_PROMPT, repl_prompt);
    /* no libedit signal handling: it would end the REPL on ^C; SIGINT is ours (on_signal),
     * and SIGWINCH too (repl_getc tells libedit) */
    el_set(el, EL_SIGNAL, 0);
    el_set(el, EL_GETCFN, repl_getc);
    repl_keys(el);
    printf("cell-cli %s: robot %s:%u, platform %s:%u, conditioning %s:%u. Type help.\n",
           C4G_VERSION_STRING, g_conn[0].host, g_conn[0].port, g_conn[1].host, g_conn[1].port,
           g_conn[2].host, g_conn[2].port);
    fflush(stdout);
    for (;;) {
        int n = 0;
        const char *got;
        repl_set_prompt();
        got = el_gets(el, &n);
        if (got == NULL || n <= 0) {
            printf("\n");
            break;
        }
        if (strspn(got, " \t\r\n") < (size_t)n) {
            char entry[1024];
            snprintf(entry, sizeof entry, "%.*s", (int)strcspn(got, "\r\n"), got);
            (void)history(h, &ev, H_ENTER, entry);
            if (use_history) {
                (void)history(h, &ev, H_SAVE, hist);
            }
        }
        if (repl_line(got, n)) {
            break;
        }
    }
    el_end(el);
    history_end(h);
    return EXIT_OK;
}

/* ------------------------------------------------------------------ command line */

#define HOST_CAP sizeof g_conn[0].host

/* What the options say; 0 / "" for "not given" (defaults < config file < options). */
typedef struct opts {
    char config[1024];
    char script[1024];
    char host_all[HOST_CAP];
    char dev_addr[C4GH_CELL_DEVICES][HOST_CAP + 8];
    unsigned port_base;
    unsigned connect_ms, reply_ms;
    long long repeat;
    double interval;
    int keep_going, no_history, no_hints;
} opts_t;

static opts_t g_opt = {.repeat = 1};

/* --robot / --platform / --conditioning HOST[:PORT]: checked now, applied after the file. */
static int on_addr(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    opts_t *o = ctx;
    char host[HOST_CAP];
    unsigned port = 0;
    if (strlen(v) >= sizeof o->dev_addr[0] || c4gh_cell_parse_hostport(v, host, sizeof host, &port) != 0) {
        snprintf(why, wl, "expected HOST[:PORT]");
        return -1;
    }
    snprintf(o->dev_addr[row->key], sizeof o->dev_addr[0], "%s", v);
    return 0;
}

static int on_repeat(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    opts_t *o = ctx;
    long long x = 0;
    (void)row;
    if (c4gh_tf_parse_int(v, -1, 100000000LL, &x) != C4GH_TF_NUM_OK || x == 0) {
        snprintf(why, wl, "a count 1..100000000, or -1 for forever");
        return -1;
    }
    o->repeat = x;
    return 0;
}

static const c4gh_cli_opt_t k_opts[] = {
    {"host", 'H', C4GH_CLI_STRING, "HOST", "host of all three devices (default 127.0.0.1)",
     g_opt.host_all, sizeof g_opt.host_all, 0, 0, NULL, 0},
    {"port-base", 'p', C4GH_CLI_UINT, "N", "robot on N, platform N+1, conditioning N+2",
     &g_opt.port_base, 0, 1, 65533, NULL, 0},
    {"robot", 0, C4GH_CLI_CALL, "HOST[:PORT]", "robot address", NULL, 0, 0, 0, on_addr,
     C4GH_CELL_DEV_ROBOT},
    {"platform", 0, C4GH_CLI_CALL, "HOST[:PORT]", "platform address", NULL, 0, 0, 0, on_addr,
     C4GH_CELL_DEV_PLATFORM},
    {"conditioning", 0, C4GH_CLI_CALL, "HOST[:PORT]", "conditioning controller address", NULL, 0, 0,
     0, on_addr, C4GH_CELL_DEV_CONDITIONING},
    {"config", 'c', C4GH_CLI_STRING, "FILE", "INI file (see below)", g_opt.config,
     sizeof g_opt.config, 0, 0, NULL, 0},
    {"connect-timeout", 0, C4GH_CLI_UINT, "MS", "connect timeout 1..600000 (default 2000)",
     &g_opt.connect_ms, 0, 1, 600000, NULL, 0},
    {"timeout", 't', C4GH_CLI_UINT, "MS", "reply timeout 1..600000 (default 2000)", &g_opt.reply_ms,
     0, 1, 600000, NULL, 0},
    {"file", 'f', C4GH_CLI_STRING, "FILE", "run a script ('-' = stdin)", g_opt.script,
     sizeof g_opt.script, 0, 0, NULL, 0},
    {"keep-going", 'k', C4GH_CLI_FLAG, NULL, "scripts: do not stop at the first ER reply",
     &g_opt.keep_going, 0, 0, 0, NULL, 0},
    {"echo", 'e', C4GH_CLI_FLAG, NULL, "scripts: print each command before running it", &g_echo, 0,
     0, 0, NULL, 0},
    {"repeat", 'r', C4GH_CLI_CALL, "N", "one-shot: run the command N times (-1: forever)", NULL, 0,
     0, 0, on_repeat, 0},
    {"interval", 'i', C4GH_CLI_DOUBLE, "SEC", "one-shot: pause between repeats 0..86400 (default 0)",
     &g_opt.interval, 0, 0, 86400, NULL, 0},
    {"json", 'j', C4GH_CLI_FLAG, NULL, "one JSON object per reply", &g_json, 0, 0, 0, NULL, 0},
    {"csv", 0, C4GH_CLI_FLAG, NULL, "one CSV row per reply, after a header line", &g_csv, 0, 0, 0,
     NULL, 0},
    {"raw", 0, C4GH_CLI_FLAG, NULL, "replies as the device sent them (default when stdout is not a "
     "terminal)", &g_raw, 0, 0, 0, NULL, 0},
    {"no-raw", 0, C4GH_CLI_FLAG, NULL, "the human format even when stdout is not a terminal",
     &g_no_raw, 0, 0, 0, NULL, 0},
    {"no-history", 0, C4GH_CLI_FLAG, NULL, "REPL: do not read or write the history file",
     &g_opt.no_history, 0, 0, 0, NULL, 0},
    {"no-hints", 0, C4GH_CLI_FLAG, NULL, "REPL: no argument hints as you type", &g_opt.no_hints, 0,
     0, 0, NULL, 0},
    {"latency", 0, C4GH_CLI_FLAG, NULL, "STA to the robot (or the DEVICE given) every 10 ms: reply "
     "time min, max, avg until ^C (or -r N samples)", &g_latency, 0, 0, 0, NULL, 0},
};

static const char *const k_examples[] = {
    "cell-cli robot sta",
    "cell-cli robot mov abs x=10 y=-2 z=5.999 c=-1.2322",
    "cell-cli --json -r 10 -i 0.5 platform sta        monitor the platform",
    "cell-cli --csv -r -1 -i 1 robot sta > robot.csv  log the robot once a second",
    "cell-cli -p 21001 -f fixtures/cell/pick_and_place.cell",
    "cell-cli raw robot OVR+00050",
    "cell-cli --latency platform                       reply times until ^C",
    NULL};

static const c4gh_cli_spec_t k_spec = {
    "cell-cli", NULL,
    "Usage: cell-cli [options] [DEVICE COMMAND [ARGS...]]\n"
    "Terminal client of the cell protocol (robot 2001, platform 2002, conditioning 2003).\n"
    "No command: interactive REPL (libedit: history in ~/.cell_cli_history, TAB completion,\n"
    "argument hints as you type unless TERM=dumb); with stdin not a terminal, or -f FILE,\n"
    "commands are read as a script.\n",
    k_opts, sizeof k_opts / sizeof k_opts[0], k_examples,
    "Config file (-c FILE, default: $CELL_CLI_CONFIG or ~/.config/cell-cli.ini if present):\n"
    "  [robot] host= port=, [platform], [conditioning], [cli] connect_timeout_ms=\n"
    "  reply_timeout_ms= hints=yes|no; options win over the file.\n"
    "\n"
    "Commands (see 'cell-cli help'): DEV sta | srvon | srvof | ovr N | stp | itr | rst | clo,\n"
    "  robot mov abs|rel x= y= z= c=, platform mov abs|rel a= b=, robot pnp clear= x= y= z= c=,\n"
    "  conditioning acq N, conditioning hnd N open|close, raw DEV TEXT,\n"
    "  wait DEV stopped [TIMEOUT], sleep SEC, connect HOST [PORT], N COMMAND (N times).\n"
    "\n"
    "Ctrl-C during a command: STP to each device whose motion this run started, then back\n"
    "to the prompt (scripts and one-shot: exit 130); at the prompt it drops the line.\n"
    "\n"
    "Exit status: 0 ok, 1 a device replied ER, 2 usage or script error, 3 connection\n"
    "failure or reply timeout, 4 invalid reply (or not the reply its request wants),\n"
    "5 wait timed out, 130 interrupted.\n",
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
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        strcpy(cc.host[d], g_conn[d].host);
        cc.port[d] = g_conn[d].port;
    }
    cc.connect_ms = g_connect_ms;
    cc.reply_ms = g_reply_ms;
    cc.hints = g_hints;
    if (cli_config_load(&cc, path, err, sizeof err) != 0) {
        fprintf(stderr, "cell-cli: config file %s\n", err);
        return EXIT_USAGE;
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        strcpy(g_conn[d].host, cc.host[d]);
        g_conn[d].port = cc.port[d];
    }
    g_connect_ms = cc.connect_ms;
    g_reply_ms = cc.reply_ms;
    g_hints = cc.hints;
    return EXIT_OK;
}

/* Defaults, then the config file, then the options. */
static int configure(void)
{
    const char *config = config_path();
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        strcpy(g_conn[d].host, "127.0.0.1");
        g_conn[d].port = c4gh_cell_dev_default_port(d);
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
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        if (g_opt.host_all[0] != '\0') {
            strcpy(g_conn[d].host, g_opt.host_all);
        }
        if (g_opt.port_base > 0) {
            g_conn[d].port = g_opt.port_base + (unsigned)d;
        }
        if (g_opt.dev_addr[d][0] != '\0') {
            (void)c4gh_cell_parse_hostport(g_opt.dev_addr[d], g_conn[d].host, sizeof g_conn[d].host,
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
        int one;
        if (k > 0 && g_opt.interval > 0 && sleep_s(g_opt.interval) == EXIT_INTR) {
            stop_after_interrupt();
            return EXIT_INTR;
        }
        one = run_cmd(&cmd);
        if (one != EXIT_OK && one != EXIT_DEVICE_ER) {
            return one;
        }
        if (one == EXIT_DEVICE_ER) {
            rc = one; /* an ER among the repeats is not hidden by a later OK */
        }
    }
    return rc;
}

int main(int argc, char **argv)
{
    int first = 0;
    int rc;
    c4gh_cli_result_t pr = c4gh_cli_parse(&k_spec, &g_opt, argc, argv, &first);
    if (pr != C4GH_CLI_RUN) {
        return pr == C4GH_CLI_DONE ? EXIT_OK : EXIT_USAGE;
    }
    if (g_json + g_csv > 1 || g_raw + g_no_raw > 1) {
        c4gh_cli_error(&k_spec, "--json and --csv, or --raw and --no-raw, exclude each other (see "
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
    if (!(first < argc && strcmp(argv[first], "canopen") == 0)) {
        signals_setup(!g_latency && g_opt.script[0] == '\0' && first >= argc && isatty(STDIN_FILENO));
    }
    if (g_opt.script[0] != '\0') {
        if (first < argc) {
            fprintf(stderr, "cell-cli: -f and a command cannot be combined\n");
            return EXIT_USAGE;
        }
        rc = run_script_file(g_opt.script);
    } else if (g_latency) {
        rc = run_latency(argc - first, argv + first, g_opt.repeat);
    } else if (first < argc && strcmp(argv[first], "canopen") == 0) {
        rc = cli_canopen_run(g_conn[C4GH_CELL_DEV_PLATFORM].host, g_conn[C4GH_CELL_DEV_PLATFORM].port + 10U,
                             argc - first - 1, argv + first + 1, g_reply_ms);
    } else if (first < argc) {
        rc = run_oneshot(argc - first, argv + first);
    } else if (isatty(STDIN_FILENO)) {
        rc = run_repl(!g_opt.no_history, g_hints && !g_opt.no_hints);
    } else {
        rc = run_script(stdin, "stdin", g_opt.keep_going);
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        conn_drop(d);
    }
    return rc;
}
