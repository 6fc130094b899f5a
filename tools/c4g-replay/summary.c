/* SPDX-License-Identifier: MIT */
/* c4g-replay summary and check: the analysis of every file given, then the report. */
#include "replay.h"

#include <stdlib.h>
#include <string.h>

typedef struct sum_ctx {
    rp_common_t c;
    uint32_t allow;
    int lines;          /* check: findings only */
} sum_ctx_t;

static int opt_allow(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    sum_ctx_t *s = ctx;
    const char *p = v;
    (void)row;
    while (*p != '\0') {
        char name[32];
        const size_t n = strcspn(p, ",");
        int k;
        if (n == 0U || n >= sizeof name) {
            (void)snprintf(why, whylen, "want kinds separated by commas");
            return -1;
        }
        memcpy(name, p, n);
        name[n] = '\0';
        if (strcmp(name, "all") == 0) {
            s->allow = 0xFFFFFFFFU;
        } else if ((k = c4gh_an_kind_find(name)) >= 0) {
            s->allow |= 1U << (unsigned)k;
        } else {
            unsigned i;
            size_t used = (size_t)snprintf(why, whylen, "unknown kind '%s'; kinds:", name);
            for (i = 0U; i < (unsigned)AN_K_COUNT && used < whylen; i++) {
                used += (size_t)snprintf(why + used, whylen - used, " %s", c4gh_an_kind_name((c4gh_an_kind_t)i));
            }
            return -1;
        }
        p += n;
        if (*p == ',') {
            p++;
        }
    }
    return 0;
}

static int opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_port(&((sum_ctx_t *)ctx)->c, row, v, why, whylen);
}

static int opt_tcycle1(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_tcycle1(&((sum_ctx_t *)ctx)->c, row, v, why, whylen);
}

static int opt_num_policy(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_num_policy(&((sum_ctx_t *)ctx)->c, row, v, why, whylen);
}

static const char *const summary_examples[] = {
    RP_TOOL " summary fixtures/replay/mode4.pcap",
    RP_TOOL " summary --json field.pcapng | jq '.sessions[].replies'",
    RP_TOOL " summary --port 1001 --t-cycle1 400 two-controllers.pcap",
    NULL};

static const char *const check_examples[] = {
    RP_TOOL " check fixtures/replay/*.pcap",
    RP_TOOL " check --allow late,ctrl-gap field.pcap",
    "find captures/ -name '*.pcap*' -print0 | xargs -0 -n 1 -P 4 " RP_TOOL " check",
    "parallel --halt never " RP_TOOL " check ::: captures/*.pcapng",
    NULL};

static const char check_epilogue[] =
    "Kinds (--allow): capture missing missing-run late num duplicate ctrl-gap reorder malformed\n"
    "nonfinite unknown-mode transition follow-error current-limit position-step clock-step\n"
    "silence (or all).\n"
    "Exit status: 0 no findings, 1 findings, 2 bad usage or an unreadable file, 3 no finding\n"
    "but a file without any C4G Open session (nothing was checked in it).\n";

static const char summary_epilogue[] =
    "Exit status: 0 the files were read (whatever they show), 1 a file stopped early,\n"
    "2 bad usage or an unreadable file. Use check for a verdict in the exit status.\n";

/* check: one line per finding, a no-session line per file without a session, the verdict. */
static int check_lines(const sum_ctx_t *s, c4gh_an_t *a, rp_file_t *files, unsigned n, int worst)
{
    unsigned empty = 0U;
    unsigned i;
    const unsigned nf = rp_report_findings(stdout, a, files, n, s->allow);
    /* a file without a session was not checked at all: never clean */
    for (i = 0U; i < n; i++) {
        if (files[i].opened && rp_file_sessions(a, files[i].path) == 0U) {
            char why[300];
            printf("%s: no-session: %s\n", files[i].path,
                   rp_no_session_text(a, &files[i], why, sizeof why));
            empty++;
        }
    }
    if (!s->c.quiet) {
        const char *verdict = (worst == 2) ? "UNREADABLE"
                              : (nf > 0U ? "FINDINGS" : (empty > 0U ? "NO SESSION" : "CLEAN"));
        printf("%s: %u file%s, %u session%s, %u finding%s", verdict, n, n == 1U ? "" : "s",
               a->n_sess, a->n_sess == 1U ? "" : "s", nf, nf == 1U ? "" : "s");
        if (empty > 0U) {
            printf(", %u file%s without a session", empty, empty == 1U ? "" : "s");
        }
        printf("\n");
    }
    if (worst == 2) {
        return RP_EXIT_UNREADABLE;
    }
    return nf > 0U ? RP_EXIT_FINDINGS : (empty > 0U ? RP_EXIT_NO_SESSION : C4GH_CLI_EXIT_OK);
}

static int run(sum_ctx_t *s, int argc, char **argv, int first)
{
    c4gh_an_t a;
    rp_file_t *files;
    const unsigned n = (unsigned)(argc - first);
    unsigned i;
    int worst = 0, rc;
    files = calloc(n, sizeof *files);
    if (files == NULL || c4gh_an_init(&a, &s->c.an) != 0) {
        fprintf(stderr, RP_TOOL ": out of memory\n");
        free(files);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    for (i = 0U; i < n; i++) {
        rc = rp_read(&a, argv[first + (int)i], &files[i], !s->c.no_progress);
        if (rc > worst) {
            worst = rc;
        }
    }
    if (s->lines) {
        rc = check_lines(s, &a, files, n, worst);
    } else {
        if (s->c.json) {
            (void)rp_report_json(stdout, &a, files, n, s->allow);
        } else {
            rp_report_text(stdout, &a, files, n, s->allow);
        }
        rc = (worst == 2) ? RP_EXIT_UNREADABLE : (worst == 1 ? C4GH_CLI_EXIT_RUNTIME : C4GH_CLI_EXIT_OK);
    }
    c4gh_an_free(&a);
    free(files);
    return rc;
}

static int command(int argc, char **argv, int check)
{
    sum_ctx_t s;
    c4gh_cli_spec_t spec;
    int first = 0;
    c4gh_cli_result_t r;
    const c4gh_cli_opt_t rows[] = {
        {"port", 'p', C4GH_CLI_CALL, "LIST", "PC ports of C4G Open flows (default 1000,1001)", NULL, 0, 0, 0,
         opt_port, 0},
        {"t-cycle1", 0, C4GH_CLI_CALL, "US", "replies later than this count as late (default 500)", NULL, 0,
         0, 0, opt_tcycle1, 0},
        {"num-policy", 0, C4GH_CLI_CALL, "P", "the controller's NUM rule: auto (from the init echo), plus-one, echo",
         NULL, 0, 0, 0, opt_num_policy, 0},
        {"max-step", 0, C4GH_CLI_DOUBLE, "TURNS", "flag absolute targets that move more per tick (default off)",
         &s.c.an.max_step, 0, 0, 1e6, NULL, 0},
        {"allow", 'a', C4GH_CLI_CALL, "KIND[,KIND]", "waive findings of these kinds (repeatable)", NULL, 0, 0,
         0, opt_allow, 0},
        {"json", 'j', C4GH_CLI_FLAG, NULL, "the whole analysis as one JSON object (summary)", &s.c.json, 0, 0,
         0, NULL, 0},
        {"quiet", 'q', C4GH_CLI_FLAG, NULL, "check: no closing count line", &s.c.quiet, 0, 0, 0, NULL, 0},
        {"no-progress", 0, C4GH_CLI_FLAG, NULL, "no progress bar on a terminal", &s.c.no_progress, 0, 0, 0,
         NULL, 0},
    };
    memset(&s, 0, sizeof s);
    rp_common_default(&s.c);
    s.lines = check;
    memset(&spec, 0, sizeof spec);
    spec.tool = RP_TOOL;
    spec.command = check ? "check" : "summary";
    spec.usage = check ? "Usage: " RP_TOOL " check [OPTIONS] FILE...\n"
                         "Analyse each capture as summary does and print one line per finding:\n"
                         "made for CI pipelines over a fleet's captures.\n"
                       : "Usage: " RP_TOOL " summary [OPTIONS] FILE...\n"
                         "Per session: the controller's configuration from the init packet,\n"
                         "duration, packets each way, NUM policy, reply latency, late and missing\n"
                         "replies, NUM mismatches, duplicates and reordering, the mode timeline\n"
                         "per arm, special modes and drive on/off, and safety findings in the\n"
                         "data; then a one-line verdict.\n";
    spec.opts = rows;
    spec.n_opts = sizeof rows / sizeof rows[0];
    spec.examples = check ? check_examples : summary_examples;
    spec.epilogue = check ? check_epilogue : summary_epilogue;
    spec.operands_min = 1;
    spec.operands_max = -1;
    spec.permute = 1;
    r = c4gh_cli_parse(&spec, &s, argc, argv, &first);
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    if (check && s.c.json) {
        c4gh_cli_error(&spec, "--json: check prints lines; use summary --json");
        return C4GH_CLI_EXIT_USAGE;
    }
    return run(&s, argc, argv, first);
}

int rp_cmd_summary(int argc, char **argv) { return command(argc, argv, 0); }
int rp_cmd_check(int argc, char **argv) { return command(argc, argv, 1); }
