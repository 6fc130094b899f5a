/* SPDX-License-Identifier: MIT */
/* cell-sim: the micro-manipulation cell's robot, orientation platform and
 * conditioning controllers as TCP servers (one process, one poll() loop).
 * See docs/cell-sim.md. */
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include <jansson.h>

#include "c4gopen.h"
#include "c4gh_cli.h"
#include "c4gh_textfile.h"
#include "c4gh_cell.h"
#include "sim_device.h"
#include "sim_canopen.h"

#define OUT_CAP 4096        /* per-client reply buffer; reading pauses when it fills */
/* Error lines one client's input may cause per second; the rest are counted and summed
 * up in one line when the burst ends or the client leaves. Without it 200 kB of newlines
 * made 30 MB of log. State-changing commands stay logged one by one (an audit trail). */
#define LOG_PER_SEC 5U
#define LOG_WINDOW_NS 1000000000ULL

enum { EXIT_OK = 0, EXIT_USAGE = 2, EXIT_SOCKET = 3 };

typedef struct client {
    int fd;                 /* -1: free slot */
    int dev;
    int closing;            /* flush then close (CLO) */
    char peer[64];
    char line_buf[C4G_CELL_LINE_MAX];
    c4g_cell_splitter_t sp;
    char out[OUT_CAP];
    size_t out_len;
    uint64_t last_ns;
    uint64_t lines;
    uint64_t log_win_ns;    /* start of the current one-second log window */
    unsigned log_in_win;    /* lines logged in it */
    uint64_t log_last_ns;   /* last error line this client caused, logged or not */
    uint64_t sup_err;       /* error lines suppressed since the last summary */
    /* A platform instruction on the CANopen bus whose reply waits (SRVON / SRVOF for the
     * drives, or any while another one waits): the client's next lines wait too, so that
     * its replies keep their order; the event loop goes on for everyone else. */
    int waiting;            /* 0 none, 1 held (not started), 2 started, reply to come */
    char held[C4G_CELL_LINE_MAX];
    size_t held_len;
    char stash[4096];       /* bytes read after the waiting line, fed once it is answered */
    size_t stash_len;
} client_t;

static volatile sig_atomic_t g_stop;
static unsigned long g_sup_clients; /* clients with suppressed lines not yet summed up */
static int g_json;
static sim_co_t g_co;       /* the platform's CANopen bus, when --canopen is given */
static int g_co_on;
static int g_verbose = 1; /* 0 quiet (errors only), 1 normal, 2 every request */
static client_t *g_servo_client; /* the client whose SRVON / SRVOF waits for the drives */

static void on_signal(int sig)
{
    g_stop = sig;
}

static void logf_(int level, const char *dev, const char *peer, const char *event,
                  const char *fmt, ...)
{
    char msg[512];
    char ts[40];
    struct timespec now;
    struct tm tm;
    va_list ap;
    if (level > g_verbose) {
        return;
    }
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    clock_gettime(CLOCK_REALTIME, &now);
    gmtime_r(&now.tv_sec, &tm);
    strftime(ts, sizeof ts, "%Y-%m-%dT%H:%M:%S", &tm);
    if (g_json) {
        /* jansson escapes; a message with bytes that are not UTF-8 keeps them as \xNN text */
        char stamp[48];
        json_t *o;
        snprintf(stamp, sizeof stamp, "%.30s.%03dZ", ts, (int)(now.tv_nsec / 1000000L) % 1000);
        o = json_pack("{s:s, s:s, s:s, s:s}", "time", stamp, "device", dev, "peer", peer, "event",
                      event);
        if (o != NULL) {
            json_t *m = json_string(msg);
            if (m == NULL) {
                char safe[1100];
                c4gh_tf_escape(msg, strlen(msg), safe, sizeof safe);
                m = json_string(safe);
            }
            json_object_set_new(o, "msg", m);
            json_dumpf(o, stderr, JSON_COMPACT | JSON_PRESERVE_ORDER);
            fputc('\n', stderr);
            json_decref(o);
        }
    } else {
        fprintf(stderr, "%s.%03ldZ cell-sim: %s %s %s: %s\n", ts, now.tv_nsec / 1000000L, dev,
                peer, event, msg);
    }
}

/* Printable copy of a line for the log (CR LF and control bytes as \xNN). */
static void printable(const char *s, size_t n, char *out, size_t cap)
{
    size_t o = 0;
    for (size_t i = 0; i < n && o + 5 < cap; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c >= 0x20 && c < 0x7F && c != '\\') {
            out[o++] = (char)c;
        } else {
            o += (size_t)snprintf(out + o, cap - o, "\\x%02x", c);
        }
    }
    out[o] = '\0';
}

/* May this client's input cause one more error line? */
static int client_log_ok(client_t *c)
{
    const uint64_t now = c4gh_now_ns();
    c->log_last_ns = now;
    if (now - c->log_win_ns >= LOG_WINDOW_NS) {
        c->log_win_ns = now;
        c->log_in_win = 0;
    }
    if (c->log_in_win < LOG_PER_SEC) {
        c->log_in_win++;
        return 1;
    }
    if (c->sup_err++ == 0) {
        g_sup_clients++;
    }
    return 0;
}

/* One summary line for what was suppressed (at the end of a burst or a connection). */
static void client_log_summary(client_t *c, const char *when)
{
    if (c->sup_err == 0) {
        return;
    }
    logf_(0, c4gh_cell_dev_name(c->dev), c->peer, "suppressed",
          "%llu more error lines not logged (at most %u per second per client), %s",
          (unsigned long long)c->sup_err, LOG_PER_SEC, when);
    c->sup_err = 0;
    g_sup_clients--;
}

static void client_close(client_t *c, const char *why)
{
    client_log_summary(c, "connection closing");
    logf_(1, c4gh_cell_dev_name(c->dev), c->peer, "disconnect", "%s (%llu lines)", why,
          (unsigned long long)c->lines);
    close(c->fd);
    c->fd = -1;
    c->waiting = 0;
    if (g_servo_client == c) {
        g_servo_client = NULL; /* the drives go on; the reply has nobody to go to */
    }
}

static void queue(client_t *c, const char *s, size_t n)
{
    /* client_read's read budget guarantees this fits. */
    if (c->out_len + n <= OUT_CAP) {
        memcpy(c->out + c->out_len, s, n);
        c->out_len += n;
    }
}

static void queue_er(client_t *c, int32_t code)
{
    c4g_cell_reply_t r;
    char b[16];
    size_t n = 0;
    memset(&r, 0, sizeof r);
    r.kind = C4G_CELL_REPLY_ER;
    r.error = code;
    if (c4g_cell_reply_encode(&r, b, sizeof b, &n) == C4G_OK) {
        queue(c, b, n);
    }
}

/* The reply to a line: queued and logged. */
static void reply_line(client_t *c, const char *line, size_t len, c4g_cell_cmd_t cmd,
                       c4g_cell_reply_t *rep, const char *note, int close_after)
{
    char pr[160];
    char out[C4G_CELL_LINE_MAX];
    size_t n = 0;
    const char *dev = c4gh_cell_dev_name(c->dev);
    if (c4g_cell_reply_encode(rep, out, sizeof out, &n) != C4G_OK) {
        rep->kind = C4G_CELL_REPLY_ER;
        rep->error = C4G_CELL_E_GENERIC;
        (void)c4g_cell_reply_encode(rep, out, sizeof out, &n);
    }
    queue(c, out, n);
    if (rep->kind == C4G_CELL_REPLY_ER) {
        if (client_log_ok(c)) {
            printable(line, len - 2, pr, sizeof pr);
            logf_(0, dev, c->peer, "error", "ER+%05d for %s: %s", (int)rep->error, pr, note);
        }
    } else if (g_verbose >= 2) {
        char po[80];
        printable(line, len - 2, pr, sizeof pr);
        printable(out, n - 2, po, sizeof po);
        logf_(2, dev, c->peer, "request", "%s -> %s (%s)", pr, po, note);
    } else if (cmd != C4G_CELL_CMD_STA) {
        printable(line, len - 2, pr, sizeof pr);
        logf_(1, dev, c->peer, "command", "%s: %s", pr, note);
    }
    if (close_after) {
        c->closing = 1;
    }
}

static void handle_line(client_t *c, sim_device_t *devs, const char *line, size_t len)
{
    c4g_cell_instr_t in;
    c4g_cell_diag_t d;
    c4g_cell_reply_t rep;
    char pr[160];
    int close_after = 0;
    const char *note;
    const char *dev = c4gh_cell_dev_name(c->dev);
    c4g_status_t st = c4g_cell_instr_decode(line, len, &in, &d);
    c->lines++;
    if (st != C4G_OK) {
        int32_t code = (st == C4G_ERR_CELL_HEAD) ? C4G_CELL_E_UNKNOWN_CMD
                       : (st == C4G_ERR_RANGE) ? C4G_CELL_E_RANGE
                                                    : C4G_CELL_E_MALFORMED;
        if (client_log_ok(c)) {
            printable(line, len, pr, sizeof pr);
            logf_(0, dev, c->peer, "error", "ER+%05d for \"%s\": %s at column %u", (int)code, pr,
                  c4g_strerror(st), (unsigned)d.column);
        }
        queue_er(c, code);
        return;
    }
    if (g_co_on && c->dev == C4GH_CELL_DEV_PLATFORM) {
        int deferred = 0;
        if (sim_co_servo_busy(&g_co)) {
            c->waiting = 1; /* run when the one waiting for the drives is answered */
            memmove(c->held, line, len); /* line may be c->held itself */
            c->held_len = len;
            c->lines--;     /* counted when it runs */
            return;
        }
        note = sim_co_exec(&g_co, &devs[c->dev], &in, c4gh_now_ns(), &rep, &close_after,
                           &deferred);
        if (deferred) {
            c->waiting = 2;
            memmove(c->held, line, len); /* line may be c->held itself */
            c->held_len = len;
            g_servo_client = c;
            return;
        }
    } else {
        note = sim_device_exec(&devs[c->dev], &in, c4gh_now_ns(), &rep, &close_after);
    }
    reply_line(c, line, len, in.cmd, &rep, note, close_after);
}

/* Replies are at most 10 bytes per byte read ("\n" -> "ER+00102\r\n", "STA\r\n" -> 50
 * bytes) plus one reply for a line already buffered, so reading at most
 * (room - 50) / 10 bytes can never overflow the reply buffer: a client that does
 * not read its replies is simply not read from (backpressure), and only it stalls. */
#define REPLY_MAX 50U
#define REPLY_RATIO 10U
#define READ_MIN_ROOM (REPLY_MAX + 16U * REPLY_RATIO)

/* The lines complete in the splitter, until one has to wait. */
static void client_lines(client_t *c, sim_device_t *devs)
{
    for (;;) {
        c4g_cell_split_event_t ev;
        const char *line = NULL;
        size_t len = 0;
        if (c->closing || c->waiting) {
            break;
        }
        (void)c4g_cell_split_next(&c->sp, &ev, &line, &len);
        if (ev == C4G_CELL_SPLIT_NONE) {
            break;
        }
        if (ev == C4G_CELL_SPLIT_OVERLONG) {
            c->lines++;
            if (client_log_ok(c)) {
                logf_(0, c4gh_cell_dev_name(c->dev), c->peer, "error",
                      "ER+%05d: line longer than %u bytes dropped", C4G_CELL_E_MALFORMED,
                      (unsigned)C4G_CELL_LINE_MAX);
            }
            queue_er(c, C4G_CELL_E_MALFORMED);
        } else {
            handle_line(c, devs, line, len);
        }
    }
}

/* Bytes of a client through the splitter and its lines; returns how many were taken (all,
 * unless a line has to wait). */
static size_t client_feed(client_t *c, sim_device_t *devs, const char *b, size_t n)
{
    size_t off = 0;
    client_lines(c, devs);
    while (off < n && !c->closing && !c->waiting) {
        size_t used = 0;
        (void)c4g_cell_split_push(&c->sp, b + off, n - off, &used);
        off += used;
        client_lines(c, devs);
        if (used == 0) {
            break;
        }
    }
    return off;
}

/* What a waiting client read meanwhile keeps for later. */
static void client_stash(client_t *c, const char *b, size_t n)
{
    if (c->waiting && c->stash_len + n <= sizeof c->stash) {
        memmove(c->stash + c->stash_len, b, n);
        c->stash_len += n;
    }
}

/* Its waiting line answered: the lines after it. */
static void client_resume(client_t *c, sim_device_t *devs)
{
    char tmp[sizeof c->stash];
    const size_t n = c->stash_len;
    size_t off;
    memcpy(tmp, c->stash, n);
    c->stash_len = 0;
    off = client_feed(c, devs, tmp, n);
    client_stash(c, tmp + off, n - off);
}

static void client_read(client_t *c, sim_device_t *devs)
{
    char buf[4096];
    size_t room = OUT_CAP - c->out_len;
    size_t want = (room > REPLY_MAX) ? (room - REPLY_MAX) / REPLY_RATIO : 0;
    size_t off;
    if (want == 0 || c->waiting) {
        return;
    }
    if (want > sizeof buf) {
        want = sizeof buf;
    }
    ssize_t r = recv(c->fd, buf, want, 0);
    if (r == 0) {
        client_close(c, "peer closed");
        return;
    }
    if (r < 0) {
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
            client_close(c, strerror(errno));
        }
        return;
    }
    c->last_ns = c4gh_now_ns();
    off = client_feed(c, devs, buf, (size_t)r);
    client_stash(c, buf + off, (size_t)r - off);
}

static void client_write(client_t *c)
{
    ssize_t w = send(c->fd, c->out, c->out_len, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (w < 0) {
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
            client_close(c, strerror(errno));
        }
        return;
    }
    memmove(c->out, c->out + w, c->out_len - (size_t)w);
    c->out_len -= (size_t)w;
    if (c->out_len == 0 && c->closing) {
        client_close(c, "CLO");
    }
}

/* ------------------------------------------------------------------ command line */

#define MAX_WS 32

typedef struct ws_limit {
    int dev, axis;
    double lo, hi;
} ws_limit_t;

/* What the options say (defaults set in main before parsing). */
typedef struct sim_opts {
    char bind[64];
    unsigned ports[C4GH_CELL_DEVICES];
    double speed;
    unsigned cameras, max_clients, idle_s;
    ws_limit_t ws[MAX_WS];
    int n_ws;
    double home[C4GH_CELL_DEVICES][4];
    int home_set[C4GH_CELL_DEVICES];
    int fault[C4GH_CELL_DEVICES];
    char canopen[512];      /* the platform on CANopen: channel INI (docs/canopen.md) */
    char can_if[32];        /* SocketCAN interface; empty: in-process virtual bus */
    char can_log[512];      /* candump log of the bus */
    char can_pcap[512];     /* pcap (DLT_CAN_SOCKETCAN) of the bus */
    unsigned canopen_port;  /* CANopen diagnostic shell port, 0: none */
    char config[1024];
} sim_opts_t;

static sim_opts_t g_opt = {.bind = "127.0.0.1", .speed = 1.0, .cameras = 2, .max_clients = 2048};

/* Largest magnitude a STA field can show: lengths 999.999 mm, angles 99.9999 rad. */
static double axis_field_max(int dev, int axis)
{
    return (dev == C4GH_CELL_DEV_ROBOT && axis < 3) ? 999.999 : 99.9999;
}

/* "DEV:" prefix of arg: the motion device it names, -1 if none; *rest after the colon. */
static int motion_dev_prefix(const char *arg, const char **rest)
{
    char tmp[32];
    const char *colon = strchr(arg, ':');
    int dev;
    if (colon == NULL || (size_t)(colon - arg) >= sizeof tmp) {
        return -1;
    }
    memcpy(tmp, arg, (size_t)(colon - arg));
    tmp[colon - arg] = '\0';
    dev = c4gh_cell_dev_parse(tmp);
    *rest = colon + 1;
    return dev == C4GH_CELL_DEV_CONDITIONING ? -1 : dev;
}

static int on_port_base(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_opts_t *o = ctx;
    long long x = 0;
    c4gh_tf_num_t st = c4gh_tf_parse_int(v, 1, 65533, &x);
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, v, row->lo, row->hi, why, wl);
        return -1;
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        o->ports[d] = (unsigned)x + (unsigned)d;
    }
    return 0;
}

static int on_speed(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_opts_t *o = ctx;
    double x = 0.0;
    (void)row;
    if (c4gh_tf_parse_double(v, 0.0, 1e6, &x) != C4GH_TF_NUM_OK || !(x > 0.0)) {
        snprintf(why, wl, "need a number > 0 and <= 1e6");
        return -1;
    }
    o->speed = x;
    return 0;
}

/* DEV:AXIS:MIN:MAX, within the STA field range. */
static int on_workspace(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_opts_t *o = ctx;
    char tmp[128];
    char *f[4];
    int n = 0;
    ws_limit_t w = {-1, -1, 0.0, 0.0};
    (void)row;
    snprintf(why, wl, "expected DEV:AXIS:MIN:MAX within the field range "
                      "(robot x,y,z,c; platform a,b), at most %d", MAX_WS);
    if (o->n_ws >= MAX_WS || strlen(v) >= sizeof tmp) {
        return -1;
    }
    strcpy(tmp, v);
    for (char *p = strtok(tmp, ":"); p != NULL && n < 4; p = strtok(NULL, ":")) {
        f[n++] = p;
    }
    if (n != 4 || (w.dev = c4gh_cell_dev_parse(f[0])) < 0 || w.dev == C4GH_CELL_DEV_CONDITIONING) {
        return -1;
    }
    for (int a = 0; a < 4; a++) {
        if (strcmp(f[1], sim_axis_name(w.dev, a)) == 0) {
            w.axis = a;
        }
    }
    if (w.axis < 0 || c4gh_cell_parse_double(f[2], &w.lo) != 0 ||
        c4gh_cell_parse_double(f[3], &w.hi) != 0 || w.lo > w.hi ||
        w.lo < -axis_field_max(w.dev, w.axis) || w.hi > axis_field_max(w.dev, w.axis)) {
        return -1;
    }
    o->ws[o->n_ws++] = w;
    return 0;
}

/* DEV:V1,V2[,V3,V4]: the robot takes 4 numbers, the platform 2. */
static int on_home(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_opts_t *o = ctx;
    const char *rest = NULL;
    char tmp[128];
    int n = 0;
    int dev = motion_dev_prefix(v, &rest);
    (void)row;
    if (dev < 0 || strlen(rest) >= sizeof tmp) {
        snprintf(why, wl, "expected DEV:V1,V2[,V3,V4] with DEV robot or platform");
        return -1;
    }
    strcpy(tmp, rest);
    for (char *p = strtok(tmp, ","); p != NULL; p = strtok(NULL, ",")) {
        if (n >= 4 || c4gh_cell_parse_double(p, &o->home[dev][n]) != 0) {
            n = 99;
            break;
        }
        n++;
    }
    if (n != (dev == C4GH_CELL_DEV_ROBOT ? 4 : 2)) {
        snprintf(why, wl, "the %s needs %d numbers", c4gh_cell_dev_name(dev),
                 dev == C4GH_CELL_DEV_ROBOT ? 4 : 2);
        return -1;
    }
    o->home_set[dev] = 1;
    return 0;
}

/* DEV:1 or DEV:2, DEV robot or platform. */
static int on_fault(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_opts_t *o = ctx;
    const char *rest = NULL;
    unsigned long u = 0;
    int dev = motion_dev_prefix(v, &rest);
    (void)row;
    if (dev < 0 || c4gh_cell_parse_uint(rest, 2, &u) != 0 || u == 0) {
        snprintf(why, wl, "expected DEV:1 or DEV:2 with DEV robot or platform");
        return -1;
    }
    o->fault[dev] = (int)u;
    return 0;
}

static int on_verbosity(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    (void)ctx;
    (void)v;
    (void)why;
    (void)wl;
    g_verbose = row->key;
    return 0;
}

static const c4gh_cli_opt_t k_opts[] = {
    {"config", 'c', C4GH_CLI_STRING, "FILE", "INI file read before the options (see below)",
     g_opt.config, sizeof g_opt.config, 0, 0, NULL, 0},
    {"bind", 'b', C4GH_CLI_STRING, "ADDR", "IPv4 address to listen on (default 127.0.0.1)", g_opt.bind,
     sizeof g_opt.bind, 0, 0, NULL, 0},
    {"port-base", 'p', C4GH_CLI_CALL, "N", "robot on N, platform N+1, conditioning N+2", NULL, 0, 1,
     65533, on_port_base, 0},
    {"robot-port", 0, C4GH_CLI_UINT, "N", "robot port (default 2001)", &g_opt.ports[C4GH_CELL_DEV_ROBOT], 0,
     1, 65535, NULL, 0},
    {"platform-port", 0, C4GH_CLI_UINT, "N", "platform port (default 2002)",
     &g_opt.ports[C4GH_CELL_DEV_PLATFORM], 0, 1, 65535, NULL, 0},
    {"conditioning-port", 0, C4GH_CLI_UINT, "N", "conditioning port (default 2003)",
     &g_opt.ports[C4GH_CELL_DEV_CONDITIONING], 0, 1, 65535, NULL, 0},
    {"speed-factor", 's', C4GH_CLI_CALL, "F", "multiply every axis speed by F (default 1)", NULL, 0, 0,
     0, on_speed, 0},
    {"workspace", 'w', C4GH_CLI_CALL, "DEV:AXIS:MIN:MAX", "workspace limit, e.g. robot:x:-50:50", NULL,
     0, 0, 0, on_workspace, 0},
    {"home", 0, C4GH_CLI_CALL, "DEV:V1,V2[,V3,V4]", "home pose used by RST (mm / rad)", NULL, 0, 0, 0,
     on_home, 0},
    {"servo-fault", 0, C4GH_CLI_CALL, "DEV:N", "SRVON on DEV fails with error +0000(N+1), N = 1 or 2",
     NULL, 0, 0, 0, on_fault, 0},
    {"cameras", 0, C4GH_CLI_UINT, "N", "camera ids 1..N accepted by ACQ (default 2)", &g_opt.cameras,
     0, 0, 99999, NULL, 0},
    {"max-clients", 0, C4GH_CLI_UINT, "N", "concurrent connections (default 2048)",
     &g_opt.max_clients, 0, 1, 100000, NULL, 0},
    {"idle-timeout", 0, C4GH_CLI_UINT, "SEC", "close connections silent that long (default 0: never)",
     &g_opt.idle_s, 0, 0, 86400, NULL, 0},
    {"canopen", 0, C4GH_CLI_STRING, "FILE", "platform drives on a CANopen bus configured by FILE (INI)",
     g_opt.canopen, sizeof g_opt.canopen, 0, 0, NULL, 0},
    {"can-if", 0, C4GH_CLI_STRING, "IF", "SocketCAN interface for --canopen (default: virtual bus)",
     g_opt.can_if, sizeof g_opt.can_if, 0, 0, NULL, 0},
    {"can-log", 0, C4GH_CLI_STRING, "FILE", "candump log of the CANopen bus", g_opt.can_log,
     sizeof g_opt.can_log, 0, 0, NULL, 0},
    {"can-pcap", 0, C4GH_CLI_STRING, "FILE", "pcap (SocketCAN link type) of the CANopen bus",
     g_opt.can_pcap, sizeof g_opt.can_pcap, 0, 0, NULL, 0},
    {"canopen-port", 0, C4GH_CLI_UINT, "N", "CANopen diagnostic shell port (default: platform port + 10)",
     &g_opt.canopen_port, 0, 1, 65535, NULL, 0},
    {"json", 'j', C4GH_CLI_FLAG, NULL, "log as JSON lines", &g_json, 0, 0, 0, NULL, 0},
    {"verbose", 'v', C4GH_CLI_CALL, NULL, "log every request and reply", NULL, 0, 0, 0, on_verbosity,
     2},
    {"quiet", 'q', C4GH_CLI_CALL, NULL, "log errors only", NULL, 0, 0, 0, on_verbosity, 0},
};

static const char *const k_examples[] = {
    "cell-sim                                  spec ports on 127.0.0.1",
    "cell-sim -p 21001 -s 10 -v                test ports, 10x faster motion",
    "cell-sim -w robot:z:-20:80 --home robot:0,0,50,0",
    "cell-sim --servo-fault platform:2         platform SRVON replies ER+00003",
    "cell-sim --canopen fixtures/canopen/platform.ini --can-pcap bus.pcap\n"
    "                                          platform drives on a virtual CANopen bus,\n"
    "                                          diagnostic shell on 2012 (cell-cli canopen ...)",
    "cell-sim -c fixtures/cell/cell-sim.ini     the settings of an INI file",
    NULL};

static const c4gh_cli_spec_t k_spec = {
    "cell-sim", NULL,
    "Usage: cell-sim [options]\n"
    "Simulates the cell's robot (port 2001), orientation platform (2002) and\n"
    "conditioning controller (2003) speaking the cell protocol over TCP.\n",
    k_opts, sizeof k_opts / sizeof k_opts[0], k_examples,
    "Logs go to stderr, one line per connection, disconnection and error, with the peer.\n"
    "Errors: at most 5 lines per second per client, then one line\n"
    "\"suppressed: N more error lines\" when the burst is over or the client leaves.\n"
    "\n"
    "Config file (-c FILE): [cell-sim] takes every long option but --config as a key\n"
    "(speed_factor = 10, workspace = robot:z:-20:80, verbose = true); [robot], [platform]\n"
    "and [conditioning] take port, workspace = AXIS:MIN:MAX, home = V1,V2[,V3,V4] and\n"
    "servo_fault = N for that device. Options on the command line win over the file.\n"
    "\n"
    "Exit status: 0 after SIGTERM, 130 after SIGINT, 2 usage or config file error, 3 cannot\n"
    "listen.\n",
    0, 0, 0, NULL};

/* One INI line: [cell-sim] KEY = any long option; [DEVICE] port, workspace, home and
 * servo_fault for that device (as the options DEVICE-port, workspace DEVICE:..., ...). */
static c4gh_tf_ini_rc_t on_ini(void *user, const char *section, const char *name, const char *value,
                          char *msg, size_t msglen)
{
    char key[64], val[256], why[300], shown[80];
    int dev = -1, rc;
    (void)user;
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        if (strcmp(section, c4gh_cell_dev_name(d)) == 0) {
            dev = d;
        }
    }
    if (dev < 0 && strcmp(section, "cell-sim") != 0) {
        c4gh_tf_escape(section, strlen(section), shown, sizeof shown);
        snprintf(msg, msglen, "unknown section [%s] (want [cell-sim], [robot], [platform] or "
                              "[conditioning])", shown);
        return C4GH_TF_INI_BAD_SECTION;
    }
    snprintf(key, sizeof key, "%s", name);
    snprintf(val, sizeof val, "%s", value);
    if (dev >= 0) {
        if (strcmp(name, "port") == 0) {
            snprintf(key, sizeof key, "%s-port", c4gh_cell_dev_name(dev));
        } else if (strcmp(name, "workspace") == 0 || strcmp(name, "home") == 0 ||
                   strcmp(name, "servo_fault") == 0 || strcmp(name, "servo-fault") == 0) {
            snprintf(val, sizeof val, "%s:%.200s", c4gh_cell_dev_name(dev), value);
        } else {
            key[0] = '\0';
        }
    }
    rc = (key[0] == '\0' || strcmp(key, "config") == 0)
             ? 1 : c4gh_cli_apply(&k_spec, &g_opt, key, val, why, sizeof why);
    if (rc > 0) {
        c4gh_tf_escape(name, strlen(name), shown, sizeof shown);
        snprintf(msg, msglen, "[%s] unknown key '%s'", section, shown);
        return C4GH_TF_INI_BAD_KEY;
    }
    if (rc < 0) {
        c4gh_tf_escape(value, strlen(value), shown, sizeof shown);
        snprintf(msg, msglen, "[%s] %s: bad value '%s' (%s)", section, name, shown, why);
        return C4GH_TF_INI_BAD_VALUE;
    }
    return C4GH_TF_INI_OK;
}

/* The INI file named by -c, read before the command line so that the options win. */
static int load_config(const char *path)
{
    c4gh_tf_file_t f;
    char err[700];
    int rc;
    if (c4gh_tf_load(&f, path, C4GH_TF_MAX_INI, err, sizeof err) != 0) {
        fprintf(stderr, "cell-sim: config file %s\n", err);
        return -1;
    }
    rc = c4gh_tf_ini_parse(&f, on_ini, &g_opt, err, sizeof err);
    c4gh_tf_free(&f);
    if (rc != 0) {
        fprintf(stderr, "cell-sim: config file %s\n", err);
        return -1;
    }
    return 0;
}

/* The devices as the options configure them; -1 when a home is outside its workspace. */
static int devices_setup(sim_device_t *devs)
{
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        sim_device_init(&devs[d], d, g_opt.speed);
        devs[d].servo_fault = g_opt.fault[d];
        devs[d].cameras = (int)g_opt.cameras;
        devs[d].last_ns = c4gh_now_ns();
    }
    for (int i = 0; i < g_opt.n_ws; i++) {
        devs[g_opt.ws[i].dev].lo[g_opt.ws[i].axis] = g_opt.ws[i].lo;
        devs[g_opt.ws[i].dev].hi[g_opt.ws[i].axis] = g_opt.ws[i].hi;
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        if (g_opt.home_set[d]) {
            memcpy(devs[d].home, g_opt.home[d], sizeof g_opt.home[d]);
        }
        for (int a = 0; a < devs[d].n_axes; a++) {
            if (devs[d].home[a] < devs[d].lo[a] || devs[d].home[a] > devs[d].hi[a]) {
                fprintf(stderr, "cell-sim: %s home %s=%g is outside the workspace\n",
                        c4gh_cell_dev_name(d), sim_axis_name(d, a), devs[d].home[a]);
                return -1;
            }
        }
        memcpy(devs[d].pos, devs[d].home, sizeof devs[d].pos); /* start at home */
    }
    return 0;
}

/* Descriptors for 1000+ clients, SIGPIPE ignored, SIGINT/SIGTERM stop the loop. */
static void process_setup(void)
{
    struct rlimit rl;
    struct sigaction sa;
    /* 1000+ clients need more descriptors than the usual soft limit of 1024. */
    if (getrlimit(RLIMIT_NOFILE, &rl) == 0 && rl.rlim_cur < rl.rlim_max) {
        rl.rlim_cur = rl.rlim_max;
        (void)setrlimit(RLIMIT_NOFILE, &rl);
    }
    signal(SIGPIPE, SIG_IGN);
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

/* ------------------------------------------------------------------ the server */

typedef struct server {
    int lfd[C4GH_CELL_DEVICES];
    client_t *cl;
    struct pollfd *pf;
    int *map;               /* pf index -> client slot, or -1 - device for a listener */
    unsigned long max_clients;
    size_t free_hint;
} server_t;

static int server_open(server_t *s)
{
    memset(s, 0, sizeof *s);
    s->max_clients = g_opt.max_clients;
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        char where[96];
        s->lfd[d] = c4gh_cell_tcp_listen(g_opt.bind, g_opt.ports[d], 512);
        if (s->lfd[d] < 0) {
            fprintf(stderr, "cell-sim: cannot listen on %s:%u for the %s: %s\n", g_opt.bind,
                    g_opt.ports[d], c4gh_cell_dev_name(d), strerror(errno));
            return -1;
        }
        snprintf(where, sizeof where, "%s:%u", g_opt.bind, g_opt.ports[d]);
        logf_(1, c4gh_cell_dev_name(d), where, "listen", "ready");
    }
    s->cl = calloc(s->max_clients, sizeof *s->cl);
    s->pf = calloc(s->max_clients + C4GH_CELL_DEVICES, sizeof *s->pf);
    s->map = calloc(s->max_clients + C4GH_CELL_DEVICES, sizeof *s->map);
    if (s->cl == NULL || s->pf == NULL || s->map == NULL) {
        fprintf(stderr, "cell-sim: out of memory for %lu clients\n", s->max_clients);
        return -1;
    }
    for (unsigned long i = 0; i < s->max_clients; i++) {
        s->cl[i].fd = -1;
    }
    return 0;
}

static void server_close(server_t *s)
{
    for (unsigned long i = 0; i < s->max_clients; i++) {
        if (s->cl[i].fd >= 0) {
            client_close(&s->cl[i], "shutting down");
        }
    }
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        close(s->lfd[d]);
    }
    free(s->cl);
    free(s->pf);
    free(s->map);
}

/* The poll set: the listeners, then every client with what it waits for. */
static nfds_t poll_set(server_t *s)
{
    nfds_t n = 0;
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        s->pf[n].fd = s->lfd[d];
        s->pf[n].events = POLLIN;
        s->map[n] = -1 - d;
        n++;
    }
    for (unsigned long i = 0; i < s->max_clients; i++) {
        const client_t *c = &s->cl[i];
        if (c->fd < 0) {
            continue;
        }
        s->pf[n].fd = c->fd;
        s->pf[n].events = 0;
        /* Backpressure: stop reading from a client whose replies pile up. */
        if (!c->closing && !c->waiting && OUT_CAP - c->out_len >= READ_MIN_ROOM) {
            s->pf[n].events |= POLLIN;
        }
        if (c->waiting && c->out_len == 0) {
            s->pf[n].fd = -1; /* a hang-up is seen once it is answered (no busy poll) */
        }
        if (c->out_len > 0) {
            s->pf[n].events |= POLLOUT;
        }
        s->map[n] = (int)i;
        n++;
    }
    return n;
}

static unsigned long free_slot(server_t *s)
{
    for (unsigned long j = 0; j < s->max_clients; j++) {
        unsigned long slot = (s->free_hint + j) % s->max_clients;
        if (s->cl[slot].fd < 0) {
            return slot;
        }
    }
    return s->max_clients;
}

static void client_start(client_t *c, int fd, int dev, const char *peer, uint64_t now)
{
    int one = 1;
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    c->fd = fd;
    c->dev = dev;
    c->closing = 0;
    c->out_len = 0;
    c->lines = 0;
    c->last_ns = now;
    c->log_win_ns = now;
    c->log_in_win = 0;
    c->log_last_ns = now;
    c->sup_err = 0;
    c->waiting = 0;
    c->stash_len = 0;
    snprintf(c->peer, sizeof c->peer, "%s", peer);
    (void)c4g_cell_split_init(&c->sp, c->line_buf, sizeof c->line_buf);
    logf_(1, c4gh_cell_dev_name(dev), c->peer, "connect", "connection accepted");
}

/* Accept every pending connection of device d's listener. */
static void accept_all(server_t *s, int d, uint64_t now)
{
    for (;;) {
        struct sockaddr_in peer;
        socklen_t pl = sizeof peer;
        char ps[64];
        unsigned long slot;
        int fd = accept(s->lfd[d], (struct sockaddr *)&peer, &pl);
        if (fd < 0) {
            if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR &&
                errno != ECONNABORTED) {
                logf_(0, c4gh_cell_dev_name(d), "-", "error", "accept: %s", strerror(errno));
            }
            return;
        }
        slot = free_slot(s);
        c4gh_cell_peer_string(fd, ps, sizeof ps);
        if (slot == s->max_clients) {
            logf_(0, c4gh_cell_dev_name(d), ps, "error", "refused: %lu connections already open",
                  s->max_clients);
            close(fd);
            continue;
        }
        s->free_hint = slot + 1;
        client_start(&s->cl[slot], fd, d, ps, now);
    }
}

static void client_event(client_t *c, short revents, sim_device_t *devs)
{
    if (c->fd < 0) {
        return;
    }
    if (revents & (POLLERR | POLLNVAL)) {
        client_close(c, "socket error");
        return;
    }
    if (revents & (POLLIN | POLLHUP)) {
        client_read(c, devs);
    }
    if (c->fd >= 0 && (revents & POLLOUT || c->out_len > 0)) {
        client_write(c);
    }
}

/* Summaries of bursts that are over, idle timeouts. */
static void housekeeping(server_t *s)
{
    /* Reads stamped clients after the poll returned: compare with a fresh clock, never a
     * difference that wraps around. */
    const uint64_t now = c4gh_now_ns();
    for (unsigned long i = 0; i < s->max_clients; i++) {
        client_t *c = &s->cl[i];
        /* a burst is over once its client caused no log line for a second */
        if (g_sup_clients > 0 && c->fd >= 0 && c->sup_err > 0 &&
            now >= c->log_last_ns + LOG_WINDOW_NS) {
            client_log_summary(c, "burst over");
        }
        if (g_opt.idle_s > 0 && c->fd >= 0 &&
            now > c->last_ns + (uint64_t)g_opt.idle_s * 1000000000ULL) {
            client_close(c, "idle timeout");
        }
    }
}

/* The platform's SRVON / SRVOF that waited for the drives: its reply once they are there,
 * then the lines its client sent meanwhile; then the instructions held while it waited. */
static void servo_replies(server_t *s, sim_device_t *devs)
{
    c4g_cell_reply_t rep;
    const char *note = NULL;
    int close_after = 0;
    if (sim_co_servo_poll(&g_co, &devs[C4GH_CELL_DEV_PLATFORM], c4gh_now_ns(), &rep, &note,
                          &close_after)) {
        client_t *c = g_servo_client;
        g_servo_client = NULL;
        if (c != NULL && c->fd >= 0 && c->waiting == 2) {
            c->waiting = 0;
            reply_line(c, c->held, c->held_len, g_co.servo.in.cmd, &rep, note, close_after);
            client_resume(c, devs);
            client_write(c);
        }
    }
    for (unsigned long i = 0; i < s->max_clients && !sim_co_servo_busy(&g_co); i++) {
        client_t *c = &s->cl[i];
        if (c->fd >= 0 && c->waiting == 1) {
            c->waiting = 0;
            handle_line(c, devs, c->held, c->held_len);
            if (c->waiting == 0) {
                client_resume(c, devs);
            }
            if (c->fd >= 0) {
                client_write(c);
            }
        }
    }
}

static void server_loop(server_t *s, sim_device_t *devs)
{
    while (!g_stop) {
        nfds_t n = poll_set(s);
        int rc = poll(s->pf, n, g_co_on ? 2 : 1000);
        uint64_t now;
        if (rc < 0) {
            if (errno == EINTR) {
                continue;
            }
            fprintf(stderr, "cell-sim: poll: %s\n", strerror(errno));
            return;
        }
        now = c4gh_now_ns();
        for (nfds_t k = 0; k < n && rc > 0; k++) {
            if (s->pf[k].revents == 0) {
                continue;
            }
            if (s->map[k] < 0) {
                accept_all(s, -1 - s->map[k], now);
            } else {
                client_event(&s->cl[s->map[k]], s->pf[k].revents, devs);
            }
        }
        housekeeping(s);
        if (g_co_on) {
            sim_co_step(&g_co, c4gh_now_ns(), &devs[C4GH_CELL_DEV_PLATFORM]);
            servo_replies(s, devs);
        }
    }
}

int main(int argc, char **argv)
{
    sim_device_t devs[C4GH_CELL_DEVICES];
    server_t srv;
    c4gh_cli_result_t pr;
    for (int d = 0; d < C4GH_CELL_DEVICES; d++) {
        g_opt.ports[d] = c4gh_cell_dev_default_port(d);
    }
    if (c4gh_cli_find_config(argc, argv) != NULL && load_config(c4gh_cli_find_config(argc, argv)) != 0) {
        return EXIT_USAGE;
    }
    pr = c4gh_cli_parse(&k_spec, &g_opt, argc, argv, NULL);
    if (pr != C4GH_CLI_RUN) {
        return pr == C4GH_CLI_DONE ? EXIT_OK : EXIT_USAGE;
    }
    if (devices_setup(devs) != 0) {
        return EXIT_USAGE;
    }
    process_setup();
    if (server_open(&srv) != 0) {
        return EXIT_SOCKET;
    }
    if (g_opt.canopen[0] != '\0') {
        char err[512];
        if (g_opt.canopen_port == 0) {
            g_opt.canopen_port = g_opt.ports[C4GH_CELL_DEV_PLATFORM] + 10U;
        }
        if (sim_co_open(&g_co, g_opt.canopen, g_opt.can_if[0] ? g_opt.can_if : NULL,
                        g_opt.can_log[0] ? g_opt.can_log : NULL,
                        g_opt.can_pcap[0] ? g_opt.can_pcap : NULL, g_opt.bind,
                        g_opt.canopen_port, err, sizeof err) != 0) {
            fprintf(stderr, "cell-sim: %s\n", err);
            server_close(&srv);
            return EXIT_USAGE;
        }
        g_co.verbose = g_verbose >= 2;
        g_co_on = 1;
        logf_(1, "platform", "-", "canopen", "CANopen channel %u: %u nodes on %s, shell on port %u",
              g_co.cfg.net.channel, g_co.cfg.net.n_nodes,
              g_opt.can_if[0] ? g_opt.can_if : "the virtual bus", g_opt.canopen_port);
    }
    server_loop(&srv, devs);
    if (g_co_on) {
        sim_co_close(&g_co);
    }
    server_close(&srv);
    logf_(1, "-", "-", "exit", "stopped by %s", g_stop == SIGINT ? "SIGINT" : "SIGTERM");
    /* SIGTERM: a service asked to stop; SIGINT: as a shell reports an interrupted command */
    return g_stop == SIGINT ? C4GH_CLI_EXIT_SIGINT : EXIT_OK;
}
