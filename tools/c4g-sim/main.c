/* SPDX-License-Identifier: MIT */
/* c4g-sim: a C4G controller (SMP+ UDP client + DSA + robot + PDL2 program) for testing
 * C4G Open PC servers without a robot. See docs/c4g-sim.md; app.h says where each part
 * lives. */
#include <errno.h>
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include "app.h"
#include "c4gh_cli.h"
#include "capture.h"

static void on_signal(int sig)
{
    g_stop = sig;
}

/* The exit code and the summary's result word, from how the run went. */
static int outcome(const app_t *a, const char **result)
{
    const sim_t *s = &a->sim;
    if (g_stop) {
        /* one rule in every tool: a signal decides the exit status; the summary says what
         * the run had found by then */
        *result = "interrupted";
        return (g_stop == SIGTERM) ? C4GH_CLI_EXIT_SIGTERM : C4GH_CLI_EXIT_SIGINT;
    }
    if (s->n_err > 0) {
        *result = "error";
        return EXIT_RUNTIME;
    }
    if (s->expect_failed > 0 || s->scn_timeout || s->scn_aborted) {
        *result = "scenario-failed";
        return EXIT_EXPECT;
    }
    if (a->out_error) {
        *result = "output-error";
        return EXIT_OUTPUT;
    }
    *result = "ok";
    return EXIT_OK;
}

/* ERR_C4GOPEN_SKT_UDP: the socket could not be made or bound. */
static int socket_failed(app_t *a)
{
    fprintf(stderr, "c4g-sim: %s:%u: %s\n", a->cfg.bind_addr, a->cfg.local_port, strerror(errno));
    sim_raise(&a->sim, C4G_CERR_SKT_UDP, 0, 0);
    fprintf(stderr, "c4g-sim: %s: %s\n", c4g_ctrl_error_name(C4G_CERR_SKT_UDP), a->sim.err[0].text);
    if (!a->o.quiet) {
        summary(a, EXIT_RUNTIME, "error", 0.0);
    }
    return EXIT_RUNTIME;
}

/* app_t holds the scenario and the latency histogram: too big for the stack. */
static app_t g_app;

int main(int argc, char **argv)
{
    app_t *a = &g_app;
    const char *result = "ok";
    int done = 0;
    int code;

    memset(a, 0, sizeof *a);
    a->fd = -1;
    code = app_options(a, argc, argv, &done);
    if (done) {
        return code;
    }
    if (a->o.cap.path != NULL && a->o.lockstep) {
        fprintf(stderr, "c4g-sim: --lockstep is for the model; a played capture keeps its own times "
                "(--topspeed sends each packet as soon as the last reply came)\n");
        return EXIT_USAGE;
    }
    if (a->o.cap.path != NULL) {
        return capture_main(a); /* a recorded controller plays instead of the model */
    }
    if (capture_options_misplaced(a)) {
        return EXIT_USAGE;
    }
    code = app_prepare(a);
    if (code != EXIT_OK) {
        return code;
    }
    if (net_open(a) != 0) {
        code = socket_failed(a);
        sim_free(&a->sim);
        return code;
    }
    code = outputs_open(a);
    if (code != EXIT_OK) {
        close(a->fd);
        sim_free(&a->sim);
        return code;
    }
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGPIPE, SIG_IGN);

    app_run(a);

    if (a->sim.fatal) {
        sim_all_drive_off(&a->sim);
    }
    outputs_close(a);
    close(a->fd);
    code = outcome(a, &result);
    {
        /* an error, not a figure of the summary: said on stderr, even with --quiet */
        char why[256];
        if (no_session(&a->cs.n, a->cfg.server, a->cfg.port, why, sizeof why)) {
            fprintf(stderr, "c4g-sim: no session started: %s\n", why);
        }
    }
    if (!a->o.quiet || a->o.json) {
        summary(a, code, result, cpu_seconds());
    }
    sim_free(&a->sim);
    return code;
}
