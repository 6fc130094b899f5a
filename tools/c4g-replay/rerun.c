/* SPDX-License-Identifier: MIT */
/* c4g-replay rerun: a front end of c4g-server, the one PC host. c4g-server --capture runs the
 * recorded controller packets of a capture through its own host loop and core at top speed
 * with the recorded reception times, and compares every reply produced with the recorded one
 * (docs/c4g-server.md). This command keeps its own option table (its --help, its man page,
 * its usage errors), then runs c4g-server --replay-rerun with the same request: found beside
 * this executable, then on PATH. */
#include "replay.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- options ------------------------------------------------------------- */

static int opt_behaviour(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    rp_rerun_t *R = ctx;
    (void)row;
    if (strcmp(v, "server") == 0) {
        R->echo = 0;
    } else if (strcmp(v, "echo") == 0) {
        R->echo = 1;
    } else {
        (void)snprintf(why, whylen, "want server or echo");
        return -1;
    }
    return 0;
}

/* --port LIST: checked by the shared handler, passed on as written. */
static int opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    if (rp_check_port(row, v, why, whylen) != 0) {
        return -1;
    }
    ((rp_rerun_t *)ctx)->ports = v;
    return 0;
}

/* ---- the c4g-server command line ------------------------------------------- */

int rp_rerun_argv(const rp_rerun_t *R, const char *srv, char **argv, size_t cap, char (*num)[RP_LIVE_NUM])
{
    size_t n = 0U;
    unsigned k = 0U; /* at most 3 numbers below: RP_RERUN_NUMS */
    int bad = 0, i;
    if (cap < 1U) {
        return -1;
    }
    argv[0] = NULL;
    bad |= rp_argv_put(argv, cap, &n, srv);
    /* first: c4g-server takes its options in two sets, this request and then (after "--")
     * the user's c4g-server options, read as c4g-replay rerun's */
    bad |= rp_argv_put_opt(argv, cap, &n, "--replay-rerun", NULL);
    bad |= rp_argv_put_opt(argv, cap, &n, "--capture", R->path);
    if (R->session > 0U) {
        (void)snprintf(num[k], RP_LIVE_NUM, "%u", R->session);
        bad |= rp_argv_put_opt(argv, cap, &n, "--session", num[k++]);
    }
    if (R->echo) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--behaviour", "echo");
    }
    if (R->tolerance > 0.0) {
        (void)snprintf(num[k], RP_LIVE_NUM, "%.17g", R->tolerance); /* read back: the same double */
        bad |= rp_argv_put_opt(argv, cap, &n, "--tolerance", num[k++]);
    }
    if (R->list > 0) {
        (void)snprintf(num[k], RP_LIVE_NUM, "%lld", R->list);
        bad |= rp_argv_put_opt(argv, cap, &n, "--list", num[k++]);
    }
    if (R->ports != NULL) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--capture-ports", R->ports);
    }
    if (R->json) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--json-out", "-");
    }
    if (R->no_progress) {
        bad |= rp_argv_put_opt(argv, cap, &n, "--no-progress", NULL);
    }
    bad |= rp_argv_put(argv, cap, &n, "--");
    for (i = 0; i < R->srv_argc; i++) {
        bad |= rp_argv_put(argv, cap, &n, R->srv_argv[i]);
    }
    return bad ? -1 : (int)n;
}

/* ---- the command ---------------------------------------------------------- */

static const char *const examples[] = {
    RP_TOOL " rerun fixtures/replay/mode4.pcap",
    RP_TOOL " rerun field.pcap -- --arm 1 --axes 1,2 --sine 0.2,0.5,2",
    RP_TOOL " rerun field.pcap -- --config my-server.ini",
    RP_TOOL " rerun --json field.pcap -- --gains 40,0.5 | jq '.fields'",
    RP_TOOL " rerun --behaviour echo --session 2 field.pcap",
    NULL};

static const char epilogue[] =
    "Everything after \"--\" is c4g-server's own options (--config INI, --arm N, --sine,\n"
    "--traj, --gains, --persist, --num-policy, ...), read by c4g-server's option table;\n"
    "socket, real-time and output options are accepted and have no effect. Behaviours:\n"
    "server (default) runs c4g-server's per-arm behaviours as configured; echo drives no\n"
    "axis (NUM, mode echo and the library's neutral reply only).\n"
    "Fields compared: reply (sent on one side only), length, sync and init words, num,\n"
    "infpar, cmd and per OPEN axis mode, d1..d5, ext1..ext3. A recorded reply that came\n"
    "after the next controller packet is compared with the one produced: equal content is\n"
    "a timing difference (counted apart), not a divergence. A capture that starts after\n"
    "the init packet is rerun after a synthetic start-up (figure 10.1 init, its axis count).\n"
    "Exit status: 0 the replies produced equal the recorded ones, 1 some diverge, 2 bad\n"
    "usage or an unreadable capture.\n";

int rp_cmd_rerun(int argc, char **argv)
{
    rp_rerun_t R;
    c4gh_cli_spec_t spec;
    c4gh_cli_result_t r;
    static char *server_argv[RP_RERUN_ARGS];
    char num[RP_RERUN_NUMS][RP_LIVE_NUM];
    int first = 0, json = 0, no_progress = 0;
    const c4gh_cli_opt_t rows[] = {
        {"behaviour", 'b', C4GH_CLI_CALL, "NAME", "server (c4g-server's behaviours, default) or echo", NULL, 0, 0, 0,
         opt_behaviour, 0},
        {"session", 's', C4GH_CLI_UINT, "N", "only session N (default: every session of the first controller)",
         &R.session, 0, 1, C4GH_AN_MAX_SESSIONS, NULL, 0},
        {"tolerance", 't', C4GH_CLI_DOUBLE, "X", "float fields within X count as equal (default 0: bit-exact)",
         &R.tolerance, 0, 0, 1e9, NULL, 0},
        {"list", 'l', C4GH_CLI_INT, "N", "print the first N divergences, one per line", &R.list, 0, 0, 1e9,
         NULL, 0},
        {"json", 'j', C4GH_CLI_FLAG, NULL, "the report as JSON on stdout", &json, 0, 0, 0, NULL, 0},
        {"port", 'p', C4GH_CLI_CALL, "LIST", "PC ports of C4G Open flows (default 1000,1001)", NULL, 0, 0, 0,
         opt_port, 0},
        {"no-progress", 0, C4GH_CLI_FLAG, NULL, "no progress bar on a terminal", &no_progress, 0, 0, 0, NULL, 0},
    };
    memset(&R, 0, sizeof R);
    memset(&spec, 0, sizeof spec);
    spec.tool = RP_TOOL;
    spec.command = "rerun";
    spec.usage = "Usage: " RP_TOOL " rerun [OPTIONS] FILE [-- C4G-SERVER-OPTIONS]\n"
                 "Feed the recorded controller packets through c4g-server's own core at top speed,\n"
                 "with their recorded times, and compare every reply produced with the recorded one,\n"
                 "field by field: the first divergence (tick, arm, axis, field, recorded vs produced)\n"
                 "and the count per field.\n";
    spec.opts = rows;
    spec.n_opts = sizeof rows / sizeof rows[0];
    spec.examples = examples;
    spec.epilogue = epilogue;
    spec.operands_min = 1;
    spec.operands_max = -1;
    spec.permute = 1;
    r = c4gh_cli_parse(&spec, &R, argc, argv, &first);
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    R.json = json;
    R.no_progress = no_progress;
    R.path = argv[first];
    R.srv_argv = argv + first + 1;
    R.srv_argc = argc - first - 1;
    if (R.srv_argc > RP_RERUN_MAX_SERVER_ARGS) {
        c4gh_cli_error(&spec, "at most %d c4g-server options", RP_RERUN_MAX_SERVER_ARGS);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (rp_rerun_argv(&R, "c4g-server", server_argv, RP_RERUN_ARGS, num) < 0) {
        fprintf(stderr, RP_TOOL ": rerun: internal: c4g-server's command line does not fit\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    (void)fflush(NULL);
    rp_exec_tool("c4g-server", server_argv);
    fprintf(stderr, RP_TOOL ": rerun: cannot run c4g-server (beside " RP_TOOL " or on PATH): %s\n",
            strerror(errno));
    return C4GH_CLI_EXIT_RUNTIME;
}
