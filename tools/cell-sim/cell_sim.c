/* SPDX-License-Identifier: MIT */
/* cell-sim: the micro-manipulation cell's robot, orientation platform and
 * conditioning controllers as TCP servers (one process, one poll() loop).
 * See docs/cell-sim.md. */
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
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

#include "c4gopen.h"
#include "cell_common.h"
#include "sim_device.h"

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
} client_t;

static volatile sig_atomic_t g_stop;
static unsigned long g_sup_clients; /* clients with suppressed lines not yet summed up */
static int g_json;
static int g_verbose = 1; /* 0 quiet (errors only), 1 normal, 2 every request */

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
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
        /* messages are built from fixed texts and protocol-safe bytes; escape quotes anyway */
        char esc[1100];
        size_t o = 0;
        for (size_t i = 0; msg[i] != '\0' && o + 7 < sizeof esc; i++) {
            unsigned char c = (unsigned char)msg[i];
            if (c == '"' || c == '\\') {
                esc[o++] = '\\';
                esc[o++] = (char)c;
            } else if (c < 0x20 || c >= 0x7F) {
                o += (size_t)snprintf(esc + o, sizeof esc - o, "\\u%04x", c);
            } else {
                esc[o++] = (char)c;
            }
        }
        esc[o] = '\0';
        fprintf(stderr, "{\"time\":\"%s.%03ldZ\",\"device\":\"%s\",\"peer\":\"%s\",\"event\":\"%s\",\"msg\":\"%s\"}\n",
                ts, now.tv_nsec / 1000000L, dev, peer, event, esc);
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

static void usage(FILE *f)
{
    fprintf(f,
"Usage: cell-sim [options]\n"
"Simulates the cell's robot (port 2001), orientation platform (2002) and\n"
"conditioning controller (2003) speaking the cell protocol over TCP.\n"
"\n"
"Options:\n"
"  -b, --bind ADDR           IPv4 address to listen on (default 127.0.0.1)\n"
"  -p, --port-base N         robot on N, platform N+1, conditioning N+2\n"
"      --robot-port N        robot port (default 2001)\n"
"      --platform-port N     platform port (default 2002)\n"
"      --conditioning-port N conditioning port (default 2003)\n"
"  -s, --speed-factor F      multiply every axis speed by F (default 1)\n"
"  -w, --workspace DEV:AXIS:MIN:MAX   workspace limit, e.g. robot:x:-50:50\n"
"      --home DEV:V1,V2[,V3,V4]      home pose used by RST (mm / rad)\n"
"      --servo-fault DEV:N   SRVON on DEV fails with error +0000(N+1), N = 1 or 2\n"
"      --cameras N           camera ids 1..N accepted by ACQ (default 2)\n"
"      --max-clients N       concurrent connections (default 2048)\n"
"      --idle-timeout SEC    close connections silent that long (default 0: never)\n"
"  -j, --json                log as JSON lines\n"
"  -v, --verbose             log every request and reply\n"
"  -q, --quiet               log errors only\n"
"  -h, --help                this help\n"
"  -V, --version             print the version\n"
"\n"
"Logs go to stderr, one line per connection, disconnection and error, with the peer.\n"
"Errors: at most 5 lines per second per client, then one line\n"
"\"suppressed: N more error lines\" when the burst is over or the client leaves.\n"
"Exit status: 0 after SIGINT/SIGTERM, 2 usage error, 3 cannot listen.\n"
"\n"
"Examples:\n"
"  cell-sim                                  spec ports on 127.0.0.1\n"
"  cell-sim -p 21001 -s 10 -v                test ports, 10x faster motion\n"
"  cell-sim -w robot:z:-20:80 --home robot:0,0,50,0\n"
"  cell-sim --servo-fault platform:2         platform SRVON replies ER+00003\n");
}

static int listen_on(const char *addr, unsigned port)
{
    struct sockaddr_in sa;
    int one = 1;
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) {
        return -1;
    }
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)port);
    if (inet_pton(AF_INET, addr, &sa.sin_addr) != 1 ||
        bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0 || listen(fd, 512) != 0) {
        int e = errno;
        close(fd);
        errno = e;
        return -1;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    return fd;
}

/* May this client's input cause one more error line? */
static int client_log_ok(client_t *c)
{
    const uint64_t now = cell_now_ns();
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
    logf_(0, cell_dev_name(c->dev), c->peer, "suppressed",
          "%llu more error lines not logged (at most %u per second per client), %s",
          (unsigned long long)c->sup_err, LOG_PER_SEC, when);
    c->sup_err = 0;
    g_sup_clients--;
}

static void client_close(client_t *c, const char *why)
{
    client_log_summary(c, "connection closing");
    logf_(1, cell_dev_name(c->dev), c->peer, "disconnect", "%s (%llu lines)", why,
          (unsigned long long)c->lines);
    close(c->fd);
    c->fd = -1;
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

static void handle_line(client_t *c, sim_device_t *devs, const char *line, size_t len)
{
    c4g_cell_instr_t in;
    c4g_cell_diag_t d;
    c4g_cell_reply_t rep;
    char pr[160];
    char out[C4G_CELL_LINE_MAX];
    size_t n = 0;
    int close_after = 0;
    const char *dev = cell_dev_name(c->dev);
    c4g_status_t st = c4g_cell_instr_decode(line, len, &in, &d);
    c->lines++;
    if (st != C4G_OK) {
        int32_t code = (st == C4G_ERR_CELL_HEAD) ? C4G_CELL_E_UNKNOWN_CMD
                       : (st == C4G_ERR_CELL_RANGE) ? C4G_CELL_E_RANGE
                                                    : C4G_CELL_E_MALFORMED;
        if (client_log_ok(c)) {
            printable(line, len, pr, sizeof pr);
            logf_(0, dev, c->peer, "error", "ER+%05d for \"%s\": %s at column %u", (int)code, pr,
                  c4g_strerror(st), (unsigned)d.column);
        }
        queue_er(c, code);
        return;
    }
    const char *note = sim_device_exec(&devs[c->dev], &in, cell_now_ns(), &rep, &close_after);
    if (c4g_cell_reply_encode(&rep, out, sizeof out, &n) != C4G_OK) {
        rep.kind = C4G_CELL_REPLY_ER;
        rep.error = C4G_CELL_E_GENERIC;
        (void)c4g_cell_reply_encode(&rep, out, sizeof out, &n);
    }
    queue(c, out, n);
    if (rep.kind == C4G_CELL_REPLY_ER) {
        if (client_log_ok(c)) {
            printable(line, len - 2, pr, sizeof pr);
            logf_(0, dev, c->peer, "error", "ER+%05d for %s: %s", (int)rep.error, pr, note);
        }
    } else if (g_verbose >= 2) {
        char po[80];
        printable(line, len - 2, pr, sizeof pr);
        printable(out, n - 2, po, sizeof po);
        logf_(2, dev, c->peer, "request", "%s -> %s (%s)", pr, po, note);
    } else if (in.cmd != C4G_CELL_CMD_STA) {
        printable(line, len - 2, pr, sizeof pr);
        logf_(1, dev, c->peer, "command", "%s: %s", pr, note);
    }
    if (close_after) {
        c->closing = 1;
    }
}

/* Replies are at most 10 bytes per byte read ("\n" -> "ER+00102\r\n", "STA\r\n" -> 50
 * bytes) plus one reply for a line already buffered, so reading at most
 * (room - 50) / 10 bytes can never overflow the reply buffer: a client that does
 * not read its replies is simply not read from (backpressure), and only it stalls. */
#define REPLY_MAX 50U
#define REPLY_RATIO 10U
#define READ_MIN_ROOM (REPLY_MAX + 16U * REPLY_RATIO)

static void client_read(client_t *c, sim_device_t *devs)
{
    char buf[4096];
    size_t room = OUT_CAP - c->out_len;
    size_t want = (room > REPLY_MAX) ? (room - REPLY_MAX) / REPLY_RATIO : 0;
    if (want == 0) {
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
    c->last_ns = cell_now_ns();
    size_t off = 0;
    while (off < (size_t)r && !c->closing) {
        size_t used = 0;
        (void)c4g_cell_split_push(&c->sp, buf + off, (size_t)r - off, &used);
        off += used;
        for (;;) {
            c4g_cell_split_event_t ev;
            const char *line = NULL;
            size_t len = 0;
            (void)c4g_cell_split_next(&c->sp, &ev, &line, &len);
            if (ev == C4G_CELL_SPLIT_NONE || c->closing) {
                break;
            }
            if (ev == C4G_CELL_SPLIT_OVERLONG) {
                c->lines++;
                if (client_log_ok(c)) {
                    logf_(0, cell_dev_name(c->dev), c->peer, "error",
                          "ER+%05d: line longer than %u bytes dropped", C4G_CELL_E_MALFORMED,
                          (unsigned)C4G_CELL_LINE_MAX);
                }
                queue_er(c, C4G_CELL_E_MALFORMED);
            } else {
                handle_line(c, devs, line, len);
            }
        }
    }
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

static int parse_dev_axis(const char *arg, int *dev, int *axis, double *lo, double *hi)
{
    char tmp[128];
    char *f[4];
    int n = 0;
    if (strlen(arg) >= sizeof tmp) {
        return -1;
    }
    strcpy(tmp, arg);
    for (char *p = strtok(tmp, ":"); p != NULL && n < 4; p = strtok(NULL, ":")) {
        f[n++] = p;
    }
    if (n != 4 || (*dev = cell_dev_parse(f[0])) < 0 || *dev == CELL_DEV_CONDITIONING) {
        return -1;
    }
    *axis = -1;
    for (int a = 0; a < 4; a++) {
        if (strcmp(f[1], sim_axis_name(*dev, a)) == 0) {
            *axis = a;
        }
    }
    if (*axis < 0 || cell_parse_double(f[2], lo) != 0 || cell_parse_double(f[3], hi) != 0 ||
        *lo > *hi) {
        return -1;
    }
    return 0;
}

/* Largest magnitude a STA field can show: lengths 999.999 mm, angles 99.9999 rad. */
static double axis_field_max(int dev, int axis)
{
    return (dev == CELL_DEV_ROBOT && axis < 3) ? 999.999 : 99.9999;
}

int main(int argc, char **argv)
{
    static const struct option opts[] = {
        {"bind", required_argument, NULL, 'b'},
        {"port-base", required_argument, NULL, 'p'},
        {"robot-port", required_argument, NULL, 1001},
        {"platform-port", required_argument, NULL, 1002},
        {"conditioning-port", required_argument, NULL, 1003},
        {"speed-factor", required_argument, NULL, 's'},
        {"workspace", required_argument, NULL, 'w'},
        {"home", required_argument, NULL, 1004},
        {"servo-fault", required_argument, NULL, 1005},
        {"cameras", required_argument, NULL, 1006},
        {"max-clients", required_argument, NULL, 1007},
        {"idle-timeout", required_argument, NULL, 1008},
        {"json", no_argument, NULL, 'j'},
        {"verbose", no_argument, NULL, 'v'},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, 'V'},
        {NULL, 0, NULL, 0}};
    const char *bind_addr = "127.0.0.1";
    unsigned ports[CELL_DEVICES];
    double speed = 1.0;
    unsigned long max_clients = 2048, idle_s = 0, cameras = 2;
    struct {
        int dev, axis;
        double lo, hi;
    } ws[32];
    int n_ws = 0;
    double home[CELL_DEVICES][4] = {{0}};
    int home_set[CELL_DEVICES] = {0};
    int fault[CELL_DEVICES] = {0};
    sim_device_t devs[CELL_DEVICES];
    int lfd[CELL_DEVICES];
    int ch;

    for (int d = 0; d < CELL_DEVICES; d++) {
        ports[d] = cell_dev_default_port(d);
    }
    while ((ch = getopt_long(argc, argv, "b:p:s:w:jvqhV", opts, NULL)) != -1) {
        unsigned long u;
        switch (ch) {
        case 'b':
            bind_addr = optarg;
            break;
        case 'p':
            if (cell_parse_uint(optarg, 65533UL, &u) != 0 || u == 0) {
                fprintf(stderr, "cell-sim: --port-base: not a port: %s\n", optarg);
                return EXIT_USAGE;
            }
            for (int d = 0; d < CELL_DEVICES; d++) {
                ports[d] = (unsigned)u + (unsigned)d;
            }
            break;
        case 1001:
        case 1002:
        case 1003:
            if (cell_parse_uint(optarg, 65535UL, &u) != 0 || u == 0) {
                fprintf(stderr, "cell-sim: %s: not a port: %s\n", argv[optind - 1], optarg);
                return EXIT_USAGE;
            }
            ports[ch - 1001] = (unsigned)u;
            break;
        case 's':
            if (cell_parse_double(optarg, &speed) != 0 || !(speed > 0.0) || speed > 1e6) {
                fprintf(stderr, "cell-sim: --speed-factor: need a number > 0: %s\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case 'w': {
            int dev, axis;
            double lo, hi;
            if (n_ws >= 32 || parse_dev_axis(optarg, &dev, &axis, &lo, &hi) != 0 ||
                lo < -axis_field_max(dev, axis) || hi > axis_field_max(dev, axis)) {
                fprintf(stderr, "cell-sim: --workspace: expected DEV:AXIS:MIN:MAX within the "
                                "field range (robot x,y,z,c; platform a,b): %s\n", optarg);
                return EXIT_USAGE;
            }
            ws[n_ws].dev = dev;
            ws[n_ws].axis = axis;
            ws[n_ws].lo = lo;
            ws[n_ws].hi = hi;
            n_ws++;
            break;
        }
        case 1004: {
            char tmp[128];
            char *colon = strchr(optarg, ':');
            int dev, n = 0;
            if (colon == NULL || (size_t)(colon - optarg) >= sizeof tmp) {
                fprintf(stderr, "cell-sim: --home: expected DEV:V1,V2[,V3,V4]: %s\n", optarg);
                return EXIT_USAGE;
            }
            memcpy(tmp, optarg, (size_t)(colon - optarg));
            tmp[colon - optarg] = '\0';
            dev = cell_dev_parse(tmp);
            if (dev < 0 || dev == CELL_DEV_CONDITIONING || strlen(colon + 1) >= sizeof tmp) {
                fprintf(stderr, "cell-sim: --home: unknown device in %s\n", optarg);
                return EXIT_USAGE;
            }
            strcpy(tmp, colon + 1);
            for (char *p = strtok(tmp, ","); p != NULL; p = strtok(NULL, ",")) {
                if (n >= 4 || cell_parse_double(p, &home[dev][n]) != 0) {
                    n = 99;
                    break;
                }
                n++;
            }
            if (n != (dev == CELL_DEV_ROBOT ? 4 : 2)) {
                fprintf(stderr, "cell-sim: --home: %s needs %d numbers: %s\n",
                        cell_dev_name(dev), dev == CELL_DEV_ROBOT ? 4 : 2, optarg);
                return EXIT_USAGE;
            }
            home_set[dev] = 1;
            break;
        }
        case 1005: {
            char *colon = strchr(optarg, ':');
            char tmp[32];
            int dev;
            if (colon == NULL || (size_t)(colon - optarg) >= sizeof tmp ||
                cell_parse_uint(colon + 1, 2, &u) != 0 || u == 0) {
                fprintf(stderr, "cell-sim: --servo-fault: expected DEV:1 or DEV:2: %s\n", optarg);
                return EXIT_USAGE;
            }
            memcpy(tmp, optarg, (size_t)(colon - optarg));
            tmp[colon - optarg] = '\0';
            dev = cell_dev_parse(tmp);
            if (dev < 0 || dev == CELL_DEV_CONDITIONING) {
                fprintf(stderr, "cell-sim: --servo-fault: robot or platform: %s\n", optarg);
                return EXIT_USAGE;
            }
            fault[dev] = (int)u;
            break;
        }
        case 1006:
            if (cell_parse_uint(optarg, 99999UL, &cameras) != 0) {
                fprintf(stderr, "cell-sim: --cameras: not a number: %s\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case 1007:
            if (cell_parse_uint(optarg, 100000UL, &max_clients) != 0 || max_clients == 0) {
                fprintf(stderr, "cell-sim: --max-clients: need 1..100000: %s\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case 1008:
            if (cell_parse_uint(optarg, 86400UL, &idle_s) != 0) {
                fprintf(stderr, "cell-sim: --idle-timeout: seconds, 0..86400: %s\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case 'j':
            g_json = 1;
            break;
        case 'v':
            g_verbose = 2;
            break;
        case 'q':
            g_verbose = 0;
            break;
        case 'h':
            usage(stdout);
            return EXIT_OK;
        case 'V':
            printf("cell-sim %s\n", C4G_VERSION_STRING);
            return EXIT_OK;
        default:
            usage(stderr);
            return EXIT_USAGE;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "cell-sim: unexpected argument: %s\n", argv[optind]);
        return EXIT_USAGE;
    }

    for (int d = 0; d < CELL_DEVICES; d++) {
        sim_device_init(&devs[d], d, speed);
        devs[d].servo_fault = fault[d];
        devs[d].cameras = (int)cameras;
        devs[d].last_ns = cell_now_ns();
    }
    for (int i = 0; i < n_ws; i++) {
        devs[ws[i].dev].lo[ws[i].axis] = ws[i].lo;
        devs[ws[i].dev].hi[ws[i].axis] = ws[i].hi;
    }
    for (int d = 0; d < CELL_DEVICES; d++) {
        if (home_set[d]) {
            memcpy(devs[d].home, home[d], sizeof home[d]);
        }
        for (int a = 0; a < devs[d].n_axes; a++) {
            if (devs[d].home[a] < devs[d].lo[a] || devs[d].home[a] > devs[d].hi[a]) {
                fprintf(stderr, "cell-sim: %s home %s=%g is outside the workspace\n",
                        cell_dev_name(d), sim_axis_name(d, a), devs[d].home[a]);
                return EXIT_USAGE;
            }
        }
        memcpy(devs[d].pos, devs[d].home, sizeof devs[d].pos); /* start at home */
    }

    /* 1000+ clients need more descriptors than the usual soft limit of 1024. */
    struct rlimit rl;
    if (getrlimit(RLIMIT_NOFILE, &rl) == 0 && rl.rlim_cur < rl.rlim_max) {
        rl.rlim_cur = rl.rlim_max;
        (void)setrlimit(RLIMIT_NOFILE, &rl);
    }
    signal(SIGPIPE, SIG_IGN);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    for (int d = 0; d < CELL_DEVICES; d++) {
        lfd[d] = listen_on(bind_addr, ports[d]);
        if (lfd[d] < 0) {
            fprintf(stderr, "cell-sim: cannot listen on %s:%u for the %s: %s\n", bind_addr,
                    ports[d], cell_dev_name(d), strerror(errno));
            return EXIT_SOCKET;
        }
        char where[64];
        snprintf(where, sizeof where, "%s:%u", bind_addr, ports[d]);
        logf_(1, cell_dev_name(d), where, "listen", "ready");
    }

    client_t *cl = calloc(max_clients, sizeof *cl);
    struct pollfd *pf = calloc(max_clients + CELL_DEVICES, sizeof *pf);
    int *map = calloc(max_clients + CELL_DEVICES, sizeof *map);
    if (cl == NULL || pf == NULL || map == NULL) {
        fprintf(stderr, "cell-sim: out of memory for %lu clients\n", max_clients);
        return EXIT_SOCKET;
    }
    for (unsigned long i = 0; i < max_clients; i++) {
        cl[i].fd = -1;
    }
    size_t free_hint = 0;

    while (!g_stop) {
        nfds_t n = 0;
        for (int d = 0; d < CELL_DEVICES; d++) {
            pf[n].fd = lfd[d];
            pf[n].events = POLLIN;
            map[n] = -1 - d;
            n++;
        }
        for (unsigned long i = 0; i < max_clients; i++) {
            if (cl[i].fd < 0) {
                continue;
            }
            pf[n].fd = cl[i].fd;
            pf[n].events = 0;
            /* Backpressure: stop reading from a client whose replies pile up. */
            if (!cl[i].closing && OUT_CAP - cl[i].out_len >= READ_MIN_ROOM) {
                pf[n].events |= POLLIN;
            }
            if (cl[i].out_len > 0) {
                pf[n].events |= POLLOUT;
            }
            map[n] = (int)i;
            n++;
        }
        int rc = poll(pf, n, 1000);
        if (rc < 0) {
            if (errno == EINTR) {
                continue;
            }
            fprintf(stderr, "cell-sim: poll: %s\n", strerror(errno));
            break;
        }
        uint64_t now = cell_now_ns();
        for (nfds_t k = 0; k < n && rc > 0; k++) {
            if (pf[k].revents == 0) {
                continue;
            }
            if (map[k] < 0) {
                int d = -1 - map[k];
                for (;;) {
                    struct sockaddr_in peer;
                    socklen_t pl = sizeof peer;
                    int fd = accept(lfd[d], (struct sockaddr *)&peer, &pl);
                    if (fd < 0) {
                        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR &&
                            errno != ECONNABORTED) {
                            logf_(0, cell_dev_name(d), "-", "error", "accept: %s",
                                  strerror(errno));
                        }
                        break;
                    }
                    unsigned long slot = max_clients;
                    for (unsigned long j = 0; j < max_clients; j++) {
                        unsigned long s = (free_hint + j) % max_clients;
                        if (cl[s].fd < 0) {
                            slot = s;
                            break;
                        }
                    }
                    char ps[64];
                    cell_peer_string(fd, ps, sizeof ps);
                    if (slot == max_clients) {
                        logf_(0, cell_dev_name(d), ps, "error",
                              "refused: %lu connections already open", max_clients);
                        close(fd);
                        continue;
                    }
                    free_hint = slot + 1;
                    client_t *c = &cl[slot];
                    int one = 1;
                    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
                    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                    c->fd = fd;
                    c->dev = d;
                    c->closing = 0;
                    c->out_len = 0;
                    c->lines = 0;
                    c->last_ns = now;
                    c->log_win_ns = now;
                    c->log_in_win = 0;
                    c->log_last_ns = now;
                    c->sup_err = 0;
                    snprintf(c->peer, sizeof c->peer, "%s", ps);
                    (void)c4g_cell_split_init(&c->sp, c->line_buf, sizeof c->line_buf);
                    logf_(1, cell_dev_name(d), c->peer, "connect", "connection accepted");
                }
                continue;
            }
            client_t *c = &cl[map[k]];
            if (c->fd < 0) {
                continue;
            }
            if (pf[k].revents & (POLLERR | POLLNVAL)) {
                client_close(c, "socket error");
                continue;
            }
            if (pf[k].revents & (POLLIN | POLLHUP)) {
                client_read(c, devs);
            }
            if (c->fd >= 0 && (pf[k].revents & POLLOUT || c->out_len > 0)) {
                client_write(c);
            }
        }
        /* Reads above stamped clients after `now` was taken: compare with a fresh
         * clock, never a difference that wraps around. */
        now = cell_now_ns();
        if (g_sup_clients > 0) {
            /* a burst is over once its client caused no log line for a second */
            for (unsigned long i = 0; i < max_clients; i++) {
                if (cl[i].fd >= 0 && cl[i].sup_err > 0 &&
                    now >= cl[i].log_last_ns + LOG_WINDOW_NS) {
                    client_log_summary(&cl[i], "burst over");
                }
            }
        }
        if (idle_s > 0) {
            for (unsigned long i = 0; i < max_clients; i++) {
                if (cl[i].fd >= 0 && now > cl[i].last_ns + (uint64_t)idle_s * 1000000000ULL) {
                    client_close(&cl[i], "idle timeout");
                }
            }
        }
    }
    for (unsigned long i = 0; i < max_clients; i++) {
        if (cl[i].fd >= 0) {
            client_close(&cl[i], "shutting down");
        }
    }
    for (int d = 0; d < CELL_DEVICES; d++) {
        close(lfd[d]);
    }
    free(cl);
    free(pf);
    free(map);
    logf_(1, "-", "-", "exit", "stopped by signal");
    return EXIT_OK;
}
