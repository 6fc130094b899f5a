/* SPDX-License-Identifier: MIT */
/* c4g-replay live: a front end of c4g-sim, the one controller host. c4g-sim --capture plays
 * a recorded session's controller packets to a PC server, judges the replies with the
 * library's controller end (c4g_ctrl_*) and compares them with the recorded ones (docs/c4g-sim.md).
 * This command keeps its own option table (its --help, its man page, its usage errors),
 * then runs c4g-sim with the same request: found beside this executable, then on PATH. */
#include "replay.h"

#include "c4gh_textfile.h"

#include <errno.h>
#include <limits.h>
#include <netdb.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

/* ---- options ------------------------------------------------------------- */

/* --target HOST:PORT: checked here (a host name must resolve), passed on as --server and --port. */
static int opt_to(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rp_live_t *L = ctx;
    const char *colon = strrchr(v, ':');
    long long port = 0;
    struct addrinfo hints, *res = NULL;
    int rc;
    (void)row;
    if (colon == NULL || colon == v || (size_t)(colon - v) >= sizeof L->host ||
        c4gh_tf_parse_int(colon + 1, 1, 65535, &port) != C4GH_TF_NUM_OK) {
        (void)snprintf(why, whylen, "want HOST:PORT");
        return -1;
    }
    memcpy(L->host, v, (size_t)(colon - v));
    L->host[colon - v] = '\0';
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    rc = getaddrinfo(L->host, NULL, &hints, &res);
    if (rc != 0 || res == NULL) {
        (void)snprintf(why, whylen, "want HOST:PORT; %s: %s", L->host, gai_strerror(rc));
        return -1;
    }
    freeaddrinfo(res);
    L->port = (unsigned)port;
    return 0;
}

static int opt_policy(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    (void)row;
    if (strcmp(v, "plus-one") != 0 && strcmp(v, "echo") != 0 && strcmp(v, "either") != 0) {
        (void)snprintf(why, whylen, "want plus-one, echo or either");
        return -1;
    }
    ((rp_live_t *)ctx)->policy = v;
    return 0;
}

/* --port LIST and --t-cycle1 US: checked by the shared handlers, passed on as written. */
static int opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    if (rp_check_port(row, v, why, whylen) != 0) {
        return -1;
    }
    ((rp_live_t *)ctx)->ports = v;
    return 0;
}

int rp_check_port(const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rp_common_t c;
    rp_common_default(&c);
    return rp_opt_port(&c, row, v, why, whylen);
}

static int opt_tcycle1(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rp_common_t c;
    rp_common_default(&c);
    if (rp_opt_tcycle1(&c, row, v, why, whylen) != 0) {
        return -1;
    }
    ((rp_live_t *)ctx)->t_cycle1 = v;
    return 0;
}

/* ---- the c4g-sim command line -------------------------------------------- */

int rp_argv_put(char **argv, size_t cap, size_t *n, const char *s)
{
    if (*n + 1U >= cap) {
        return -1;
    }
    argv[(*n)++] = (char *)(uintptr_t)s; /* execv's argv is char *const[]: never written */
    argv[*n] = NULL;
    return 0;
}

int rp_argv_put_opt(char **argv, size_t cap, size_t *n, const char *opt, const char *value)
{
    if (rp_argv_put(argv, cap, n, opt) != 0) {
        return -1;
    }
    return (value != NULL) ? rp_argv_put(argv, cap, n, value) : 0;
}

/* A number written into the next slot of @p num; "%u" takes @p u, the others @p v. */
static const char *num_text(char (*num)[RP_LIVE_NUM], unsigned *k, const char *fmt, double v, unsigned u)
{
    char *t = num[(*k)++];
    if (strcmp(fmt, "%u") == 0) {
        (void)snprintf(t, RP_LIVE_NUM, fmt, u);
    } else {
        (void)snprintf(t, RP_LIVE_NUM, fmt, v);
    }
    return t;
}

int rp_live_argv(const rp_live_t *L, const char *sim, char **argv, size_t cap, char (*num)[RP_LIVE_NUM])
{
    size_t n = 0U;
    unsigned k = 0U; /* at most 7 numbers below: RP_LIVE_NUMS */
    int bad = 0;
    if (cap < 1U) {
        return -1;
    }
    argv[0] = NULL;
    bad |= rp_argv_put(argv, cap, &n, sim);
    bad |= rp_argv_put_opt(argv, cap, &n, "--capture", L->path);
    bad |= rp_argv_put_opt(argv, cap, &n, "--replay-live", NULL);
    bad |= rp_argv_put_opt(argv, cap, &n, "--server", L->host);
    bad |= rp_argv_put_opt(argv, cap, &n, "--port", num_text(num, &k, "%u", 0.0, L->port));
    bad |= rp_argv_put_opt(argv, cap, &n, "--spin-us", num_text(num, &k, "%u", 0.0, L->spin_us));
    /* %.17g: a double read back is the same double */
    if (L->speed > 0.0) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--speed", num_text(num, &k, "%.17g", L->speed, 0U));
    }
    if (L->topspeed) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--topspeed", NULL);
    }
    if (L->loops > 0U) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--loop", num_text(num, &k, "%u", 0.0, L->loops));
    }
    if (L->gap_ms > 0U) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--loop-gap", num_text(num, &k, "%u", 0.0, L->gap_ms));
    }
    if (L->session > 0U) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--session", num_text(num, &k, "%u", 0.0, L->session));
    }
    if (L->tolerance > 0.0) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--tolerance", num_text(num, &k, "%.17g", L->tolerance, 0U));
    }
    if (L->t_cycle1 != NULL) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--t-cycle1", L->t_cycle1);
    }
    if (L->policy != NULL) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--num-policy", L->policy);
    }
    if (L->ports != NULL) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--capture-ports", L->ports);
    }
    if (L->json) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--json", NULL);
    }
    return bad ? -1 : (int)n;
}

void rp_exec_tool(const char *name, char **argv)
{
    char self[PATH_MAX], beside[PATH_MAX + 16];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1U);
    if (n > 0) {
        char *slash;
        self[n] = '\0';
        slash = strrchr(self, '/');
        if (slash != NULL) {
            slash[1] = '\0';
            (void)snprintf(beside, sizeof beside, "%s%s", self, name);
            if (access(beside, X_OK) == 0) {
                argv[0] = beside;
                (void)execv(beside, argv);
            }
        }
    }
    argv[0] = (char *)(uintptr_t)name;
    (void)execvp(name, argv);
}

/* ---- the command -------------------------------------------------------------- */

static const char *const live_examples[] = {
    RP_TOOL " live field.pcap --target 127.0.0.1:1000",
    RP_TOOL " live field.pcap --target 10.2.12.1:1000 --speed 2 --json",
    RP_TOOL " live field.pcap --target 127.0.0.1:31000 --topspeed --loop 100 --tolerance 1e-6",
    NULL};

static const char live_epilogue[] =
    "Every datagram the controller sent in the session (synchronization, initialization,\n"
    "cyclic packets, with their recorded bytes) leaves at its recorded time after the first\n"
    "one, on an absolute clock; each reply is judged as the controller judges it (by its\n"
    "kernel arrival time, deadline the next packet's time) and, when ok, compared field by\n"
    "field with the recorded reply. Each pass is a full start-up: with --loop the server must\n"
    "accept a restarted controller (c4g-server --persist; a capture that does not end with\n"
    "504 also needs --loop-gap longer than the server's loss timeout). c4g-sim --capture plays\n"
    "it: c4g-sim is looked for beside c4g-replay, then on PATH.\n"
    "Exit status: 0 every reply ok and equal to the recorded one, 1 findings or divergences\n"
    "(or a socket error, or c4g-sim not found), 130 interrupted (SIGINT), 2 bad usage, an unreadable\n"
    "file or a session without its start-up, 5 nothing answered (the first 10 packets of a\n"
    "pass got nothing back: live stops there).\n";

int rp_cmd_live(int argc, char **argv)
{
    rp_live_t L;
    c4gh_cli_spec_t spec;
    c4gh_cli_result_t r;
    char *sim_argv[RP_LIVE_ARGS];
    char num[RP_LIVE_NUMS][RP_LIVE_NUM];
    int first = 0;
    memset(&L, 0, sizeof L);
    L.spin_us = 100U;
    {
        int json = 0;
        const c4gh_cli_opt_t rows[] = {
            {"target", 't', C4GH_CLI_CALL, "HOST:PORT", "the PC server (required)", NULL, 0, 0, 0, opt_to, 0},
            {"to", 0, C4GH_CLI_CALL, "HOST:PORT", NULL, NULL, 0, 0, 0, opt_to, 0},
            {"speed", 0, C4GH_CLI_DOUBLE, "X", "time scale: 2 plays twice as fast (default 1)", &L.speed, 0,
             0.01, 1000, NULL, 0},
            {"topspeed", 0, C4GH_CLI_FLAG, NULL, "each packet as soon as the previous one's reply came",
             &L.topspeed, 0, 0, 0, NULL, 0},
            {"loop", 0, C4GH_CLI_UINT, "N", "play the session N times, each a full start-up (default 1)",
             &L.loops, 0, 1, 1000000, NULL, 0},
            {"loop-gap", 0, C4GH_CLI_UINT, "MS", "silence between two passes (default 0)", &L.gap_ms, 0, 0,
             3600000, NULL, 0},
            {"session", 's', C4GH_CLI_UINT, "N", "the session to play (default: the first with its start-up)",
             &L.session, 0, 1, C4GH_AN_MAX_SESSIONS, NULL, 0},
            {"t-cycle1", 0, C4GH_CLI_CALL, "US", "replies later than this count as late (default 500)", NULL,
             0, 0, 0, opt_tcycle1, 0},
            {"num-policy", 0, C4GH_CLI_CALL, "P", "reply NUM accepted: plus-one, echo, either (default)", NULL,
             0, 0, 0, opt_policy, 0},
            {"spin-us", 0, C4GH_CLI_UINT, "US", "busy-wait this long before each packet (default 100)",
             &L.spin_us, 0, 0, 100000, NULL, 0},
            {"tolerance", 0, C4GH_CLI_DOUBLE, "X", "floats equal within X (default 0: the same bits)",
             &L.tolerance, 0, 0, 1e30, NULL, 0},
            {"port", 'p', C4GH_CLI_CALL, "LIST", "PC ports of C4G Open flows in the file (default 1000,1001)",
             NULL, 0, 0, 0, opt_port, 0},
            {"json", 'j', C4GH_CLI_FLAG, NULL, "the report as one JSON object", &json, 0, 0, 0, NULL, 0},
        };
        memset(&spec, 0, sizeof spec);
        spec.tool = RP_TOOL;
        spec.command = "live";
        spec.usage = "Usage: " RP_TOOL " live FILE --target HOST:PORT [OPTIONS]\n"
                     "Play the controller's side of a recorded session to a running PC server over\n"
                     "UDP, check its replies as the controller would, compare them with the\n"
                     "recorded ones, and report the timing achieved.\n";
        spec.opts = rows;
        spec.n_opts = sizeof rows / sizeof rows[0];
        spec.examples = live_examples;
        spec.epilogue = live_epilogue;
        spec.operands_min = 1;
        spec.operands_max = 1;
        spec.permute = 1;
        r = c4gh_cli_parse(&spec, &L, argc, argv, &first);
        L.json = json;
    }
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    if (L.port == 0U) {
        fprintf(stderr, RP_TOOL ": live: --target HOST:PORT is required (the PC server to play to)\n");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (L.topspeed && L.speed > 0.0) {
        fprintf(stderr, RP_TOOL ": live: --speed and --topspeed exclude each other\n");
        return C4GH_CLI_EXIT_USAGE;
    }
    L.path = argv[first];
    if (strcmp(L.path, "-") == 0) {
        fprintf(stderr, RP_TOOL ": live: reads the file once per pass: give a file, not - (standard input)\n");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (rp_live_argv(&L, "c4g-sim", sim_argv, RP_LIVE_ARGS, num) < 0) {
        fprintf(stderr, RP_TOOL ": live: internal: c4g-sim's command line does not fit\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    (void)fflush(NULL);
    rp_exec_tool("c4g-sim", sim_argv);
    fprintf(stderr, RP_TOOL ": live: cannot run c4g-sim (beside " RP_TOOL " or on PATH): %s\n",
            strerror(errno));
    return C4GH_CLI_EXIT_RUNTIME;
}
