/* SPDX-License-Identifier: MIT */
/* cell-cli: terminal client for the cell's robot, platform and conditioning
 * controllers (REPL with libedit, one-shot, scripts, --json). See docs/cell-cli.md. */
#include <errno.h>
#include <getopt.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#include <editline/readline.h>

#include "c4gopen.h"
#include "cell_common.h"
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
static int g_json;
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

static void json_str(FILE *f, const char *s, size_t n)
{
    fputc('"', f);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '"' || c == '\\') {
            fprintf(f, "\\%c", c);
        } else if (c < 0x20 || c >= 0x7F) {
            fprintf(f, "\\u%04x", c);
        } else {
            fputc(c, f);
        }
    }
    fputc('"', f);
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

/* Show a reply; returns the exit class it implies. */
static int show_reply(int dev, const char *req, size_t req_len, const char *line, size_t len)
{
    c4g_cell_reply_t r;
    c4g_cell_diag_t d;
    c4g_status_t st = c4g_cell_reply_decode(line, len, &r, &d);
    size_t rl = (req_len >= 2) ? req_len - 2 : req_len;
    size_t ll = (len >= 2 && line[len - 1] == '\n') ? len - 2 : len;
    if (st != C4G_OK) {
        if (g_json) {
            printf("{\"device\":\"%s\",\"request\":", cell_dev_name(dev));
            json_str(stdout, req, rl);
            printf(",\"reply\":\"invalid\",\"raw\":");
            json_str(stdout, line, len);
            printf(",\"problem\":\"%s\",\"column\":%u}\n", c4g_strerror(st), (unsigned)d.column);
        } else {
            printf("%s: invalid reply \"%.*s\": %s at column %u\n", cell_dev_name(dev), (int)ll,
                   line, c4g_strerror(st), (unsigned)d.column);
        }
        return EXIT_PROTOCOL;
    }
    int project = 0;
    const char *etext = c4g_cell_error_text(r.error, &project);
    if (g_json) {
        printf("{\"device\":\"%s\",\"request\":", cell_dev_name(dev));
        json_str(stdout, req, rl);
        printf(",\"raw\":");
        json_str(stdout, line, ll);
        if (r.kind == C4G_CELL_REPLY_ER) {
            printf(",\"reply\":\"ER\",\"error\":%d,\"error_text\":\"%s\",\"project_code\":%s}\n",
                   (int)r.error, etext, project ? "true" : "false");
        } else if (r.kind == C4G_CELL_REPLY_OK) {
            printf(",\"reply\":\"OK\"}\n");
        } else {
            printf(",\"reply\":\"OK\",\"moving\":%s,\"servo\":%s,\"override\":%d,\"error\":%d,"
                   "\"error_text\":\"%s\",\"position\":{",
                   r.moving ? "true" : "false", r.servo_on ? "true" : "false",
                   (int)r.override_pct, (int)r.error, etext);
            for (uint32_t a = 0; a < r.pose.n_axes; a++) {
                double v = 0;
                (void)c4g_cell_to_double(r.pose.v[a], axis_unit(dev, (int)a), &v);
                printf("%s\"%s\":%.*f", a ? "," : "", axis_label(dev, (int)a),
                       axis_unit(dev, (int)a) == C4G_CELL_UNIT_MM ? 3 : 4, v);
            }
            printf("}}\n");
        }
    } else if (r.kind == C4G_CELL_REPLY_ER) {
        printf("%s: ER %+06d  %s (%s)\n", cell_dev_name(dev), (int)r.error, etext,
               project ? "project code" : "spec");
    } else if (r.kind == C4G_CELL_REPLY_OK) {
        printf("%s: OK\n", cell_dev_name(dev));
    } else {
        printf("%s: %s, servo %s, override %d %%, error %+06d (%s)\n", cell_dev_name(dev),
               r.moving ? "MOVING" : "stopped", r.servo_on ? "ON" : "off", (int)r.override_pct,
               (int)r.error, etext);
        for (uint32_t a = 0; a < r.pose.n_axes; a++) {
            char h[16];
            snprintf(h, sizeof h, "%s [%s]", axis_label(dev, (int)a),
                     axis_unit(dev, (int)a) == C4G_CELL_UNIT_MM ? "mm" : "rad");
            printf("  %10s", h);
        }
        printf("\n");
        for (uint32_t a = 0; a < r.pose.n_axes; a++) {
            double v = 0;
            (void)c4g_cell_to_double(r.pose.v[a], axis_unit(dev, (int)a), &v);
            printf("  %10.*f", axis_unit(dev, (int)a) == C4G_CELL_UNIT_MM ? 3 : 4, v);
        }
        printf("\n");
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
            if (g_json) {
                printf("{\"device\":\"%s\",\"wait\":\"stopped\",\"result\":\"ok\"}\n",
                       cell_dev_name(dev));
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
    case CLI_EMPTY:
    case CLI_QUIT:
        return EXIT_OK;
    case CLI_HELP:
        rc = cli_help(cmd->topic, help, sizeof help);
        fputs(help, stdout);
        return rc == 0 ? EXIT_OK : EXIT_USAGE;
    case CLI_SLEEP:
        sleep_s(cmd->seconds);
        return EXIT_OK;
    case CLI_WAIT:
        return wait_stopped(cmd->dev, cmd->seconds);
    case CLI_SEND:
    case CLI_RAW:
        rc = transact(cmd->dev, cmd->line, cmd->len, reply, sizeof reply, &n);
        if (rc != 0) {
            return rc;
        }
        rc = show_reply(cmd->dev, cmd->line, cmd->len, reply, n);
        if (cmd->kind == CLI_SEND && cmd->instr.cmd == C4G_CELL_CMD_CLO && rc == EXIT_OK) {
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
        if (cli_parse(line, &cmd, err, sizeof err) != 0) {
            fprintf(stderr, "cell-cli: %s:%d: %s\n", name, lineno, err);
            return EXIT_USAGE;
        }
        if (cmd.kind == CLI_EMPTY) {
            continue;
        }
        if (cmd.kind == CLI_QUIT) {
            break;
        }
        if (g_echo && !g_json) {
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

static char *complete_gen(const char *text, int state)
{
    static const char *const *list;
    static int idx;
    static size_t tl;
    if (state == 0) {
        /* which word is being completed, and the words before it */
        char buf[512];
        char *w[4] = {NULL, NULL, NULL, NULL};
        int n = 0;
        size_t pl = (size_t)rl_point < sizeof buf ? (size_t)rl_point : sizeof buf - 1;
        memcpy(buf, rl_line_buffer, pl);
        buf[pl] = '\0';
        for (char *p = strtok(buf, " \t"); p != NULL && n < 4; p = strtok(NULL, " \t")) {
            w[n++] = p;
        }
        int word = n;
        if (pl > 0 && buf[pl - 1] != ' ' && buf[pl - 1] != '\t' && n > 0) {
            word = n - 1; /* completing the last, unfinished word */
        }
        list = cli_words(word, w[0] ? w[0] : "", word >= 2 ? w[1] : NULL);
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
    (void)start;
    (void)end;
    rl_attempted_completion_over = 1; /* no file name completion */
    return rl_completion_matches(text, complete_gen);
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
        char *line = readline("cell> ");
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
        if (cli_parse(line, &cmd, err, sizeof err) != 0) {
            printf("error: %s\n", err);
        } else if (cmd.kind == CLI_QUIT) {
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

static void usage(FILE *f)
{
    fprintf(f,
"Usage: cell-cli [options] [DEVICE COMMAND [ARGS...]]\n"
"Terminal client of the cell protocol (robot 2001, platform 2002, conditioning 2003).\n"
"No command: interactive REPL (libedit: history in ~/.cell_cli_history, TAB completion);\n"
"with stdin not a terminal, or -f FILE, commands are read as a script.\n"
"\n"
"Options:\n"
"  -H, --host HOST            host of all three devices (default 127.0.0.1)\n"
"  -p, --port-base N          robot on N, platform N+1, conditioning N+2\n"
"      --robot HOST[:PORT]    robot address (also --platform, --conditioning)\n"
"      --platform HOST[:PORT]\n"
"      --conditioning HOST[:PORT]\n"
"  -c, --config FILE          INI file: [robot] host= port=, [platform], [conditioning],\n"
"                             [cli] connect_timeout_ms= reply_timeout_ms=\n"
"                             (default: $CELL_CLI_CONFIG or ~/.config/cell-cli.ini if present)\n"
"      --connect-timeout MS   connect timeout (default 2000)\n"
"  -t, --timeout MS           reply timeout (default 2000)\n"
"  -f, --file FILE            run a script ('-' = stdin)\n"
"  -k, --keep-going           scripts: do not stop at the first ER reply\n"
"  -e, --echo                 scripts: print each command before running it\n"
"  -r, --repeat N             one-shot: run the command N times (-1: forever)\n"
"  -i, --interval SEC         one-shot: pause between repeats (default 0)\n"
"  -j, --json                 one JSON object per reply\n"
"      --no-history           REPL: do not read or write the history file\n"
"  -h, --help                 this help (commands: cell-cli help)\n"
"  -V, --version              print the version\n"
"\n"
"Commands (see 'cell-cli help'): DEV sta | srvon | srvof | ovr N | stp | itr | rst | clo,\n"
"  robot mov abs|rel x= y= z= c=, platform mov abs|rel a= b=, robot pnp clear= x= y= z= c=,\n"
"  conditioning acq N, conditioning hnd N open|close, raw DEV TEXT,\n"
"  wait DEV stopped [TIMEOUT], sleep SEC.\n"
"\n"
"Exit status: 0 ok, 1 a device replied ER, 2 usage or script error, 3 connection\n"
"failure or reply timeout, 4 invalid reply, 5 wait timed out.\n"
"\n"
"Examples:\n"
"  cell-cli robot sta\n"
"  cell-cli robot mov abs x=10 y=-2 z=5.999 c=-1.2322\n"
"  cell-cli --json -r 10 -i 0.5 platform sta        monitor the platform\n"
"  cell-cli -p 21001 -f fixtures/cell/pick_and_place.cell\n"
"  cell-cli raw robot OVR+00050\n");
}

int main(int argc, char **argv)
{
    static const struct option opts[] = {
        {"host", required_argument, NULL, 'H'},
        {"port-base", required_argument, NULL, 'p'},
        {"robot", required_argument, NULL, 1000},
        {"platform", required_argument, NULL, 1001},
        {"conditioning", required_argument, NULL, 1002},
        {"config", required_argument, NULL, 'c'},
        {"connect-timeout", required_argument, NULL, 1003},
        {"timeout", required_argument, NULL, 't'},
        {"file", required_argument, NULL, 'f'},
        {"keep-going", no_argument, NULL, 'k'},
        {"echo", no_argument, NULL, 'e'},
        {"repeat", required_argument, NULL, 'r'},
        {"interval", required_argument, NULL, 'i'},
        {"json", no_argument, NULL, 'j'},
        {"no-history", no_argument, NULL, 1004},
        {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, 'V'},
        {NULL, 0, NULL, 0}};
    const char *config = NULL;
    const char *script = NULL;
    const char *host_all = NULL;
    const char *dev_addr[CELL_DEVICES] = {NULL, NULL, NULL};
    long port_base = -1;
    long connect_ms = -1, reply_ms = -1;
    long repeat = 1;
    double interval = 0.0;
    int keep_going = 0, use_history = 1;
    int ch;

    for (int d = 0; d < CELL_DEVICES; d++) {
        strcpy(g_conn[d].host, "127.0.0.1");
        g_conn[d].port = cell_dev_default_port(d);
        g_conn[d].fd = -1;
    }
    /* "+" stops at the first non-option: command words like "mov" pass through */
    while ((ch = getopt_long(argc, argv, "+H:p:c:t:f:ker:i:jhV", opts, NULL)) != -1) {
        unsigned long u;
        switch (ch) {
        case 'H':
            host_all = optarg;
            break;
        case 'p':
            if (cell_parse_uint(optarg, 65533UL, &u) != 0 || u == 0) {
                fprintf(stderr, "cell-cli: --port-base: not a port: %s\n", optarg);
                return EXIT_USAGE;
            }
            port_base = (long)u;
            break;
        case 1000:
        case 1001:
        case 1002:
            dev_addr[ch - 1000] = optarg;
            break;
        case 'c':
            config = optarg;
            break;
        case 1003:
        case 't':
            if (cell_parse_uint(optarg, 600000UL, &u) != 0 || u == 0) {
                fprintf(stderr, "cell-cli: timeout: milliseconds 1..600000: %s\n", optarg);
                return EXIT_USAGE;
            }
            if (ch == 't') {
                reply_ms = (long)u;
            } else {
                connect_ms = (long)u;
            }
            break;
        case 'f':
            script = optarg;
            break;
        case 'k':
            keep_going = 1;
            break;
        case 'e':
            g_echo = 1;
            break;
        case 'r':
            if (strcmp(optarg, "-1") == 0) {
                repeat = -1;
            } else if (cell_parse_uint(optarg, 100000000UL, &u) != 0 || u == 0) {
                fprintf(stderr, "cell-cli: --repeat: a count >= 1, or -1: %s\n", optarg);
                return EXIT_USAGE;
            } else {
                repeat = (long)u;
            }
            break;
        case 'i':
            if (cell_parse_double(optarg, &interval) != 0 || interval < 0 || interval > 86400) {
                fprintf(stderr, "cell-cli: --interval: seconds 0..86400: %s\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case 'j':
            g_json = 1;
            break;
        case 1004:
            use_history = 0;
            break;
        case 'h':
            usage(stdout);
            return EXIT_OK;
        case 'V':
            printf("cell-cli %s\n", C4G_VERSION_STRING);
            return EXIT_OK;
        default:
            usage(stderr);
            return EXIT_USAGE;
        }
    }

    /* precedence: defaults < config file < options */
    if (config == NULL) {
        const char *env = getenv("CELL_CLI_CONFIG");
        static char def[1024];
        const char *home = getenv("HOME");
        if (env != NULL) {
            config = env;
        } else if (home != NULL) {
            snprintf(def, sizeof def, "%s/.config/cell-cli.ini", home);
            if (access(def, R_OK) == 0) {
                config = def;
            }
        }
    }
    if (config != NULL) {
        cli_config_t cc;
        char err[600];
        cli_config_default(&cc);
        for (int d = 0; d < CELL_DEVICES; d++) {
            strcpy(cc.host[d], g_conn[d].host);
            cc.port[d] = g_conn[d].port;
        }
        cc.connect_ms = g_connect_ms;
        cc.reply_ms = g_reply_ms;
        if (cli_config_load(&cc, config, err, sizeof err) != 0) {
            fprintf(stderr, "cell-cli: config file %s\n", err);
            return EXIT_USAGE;
        }
        for (int d = 0; d < CELL_DEVICES; d++) {
            strcpy(g_conn[d].host, cc.host[d]);
            g_conn[d].port = cc.port[d];
        }
        g_connect_ms = cc.connect_ms;
        g_reply_ms = cc.reply_ms;
    }
    if (connect_ms > 0) {
        g_connect_ms = (int)connect_ms;
    }
    if (reply_ms > 0) {
        g_reply_ms = (int)reply_ms;
    }
    for (int d = 0; d < CELL_DEVICES; d++) {
        if (host_all != NULL) {
            if (strlen(host_all) >= sizeof g_conn[d].host) {
                fprintf(stderr, "cell-cli: --host too long\n");
                return EXIT_USAGE;
            }
            strcpy(g_conn[d].host, host_all);
        }
        if (port_base > 0) {
            g_conn[d].port = (unsigned)port_base + (unsigned)d;
        }
        if (dev_addr[d] != NULL &&
            cell_parse_hostport(dev_addr[d], g_conn[d].host, sizeof g_conn[d].host,
                                &g_conn[d].port) != 0) {
            fprintf(stderr, "cell-cli: --%s: expected HOST[:PORT]: %s\n", cell_dev_name(d),
                    dev_addr[d]);
            return EXIT_USAGE;
        }
    }

    int rc;
    if (script != NULL) {
        if (optind < argc) {
            fprintf(stderr, "cell-cli: -f and a command cannot be combined\n");
            return EXIT_USAGE;
        }
        FILE *f = strcmp(script, "-") == 0 ? stdin : fopen(script, "r");
        if (f == NULL) {
            fprintf(stderr, "cell-cli: cannot open script %s: %s\n", script, strerror(errno));
            return EXIT_USAGE;
        }
        rc = run_script(f, strcmp(script, "-") == 0 ? "stdin" : script, keep_going);
        if (f != stdin) {
            fclose(f);
        }
    } else if (optind < argc) {
        char text[1024] = "";
        size_t o = 0;
        cli_cmd_t cmd;
        char err[256];
        for (int i = optind; i < argc; i++) {
            int w = snprintf(text + o, sizeof text - o, "%s%s", i > optind ? " " : "", argv[i]);
            if (w < 0 || (size_t)w >= sizeof text - o) {
                fprintf(stderr, "cell-cli: command too long\n");
                return EXIT_USAGE;
            }
            o += (size_t)w;
        }
        if (cli_parse(text, &cmd, err, sizeof err) != 0) {
            fprintf(stderr, "cell-cli: %s\n", err);
            return EXIT_USAGE;
        }
        rc = EXIT_OK;
        for (long k = 0; repeat < 0 || k < repeat; k++) {
            if (k > 0 && interval > 0) {
                sleep_s(interval);
            }
            rc = run_cmd(&cmd);
            if (rc != EXIT_OK && rc != EXIT_DEVICE_ER) {
                break;
            }
        }
    } else if (isatty(STDIN_FILENO)) {
        rc = run_repl(use_history);
    } else {
        rc = run_script(stdin, "stdin", keep_going);
    }
    for (int d = 0; d < CELL_DEVICES; d++) {
        conn_drop(d);
    }
    return rc;
}
