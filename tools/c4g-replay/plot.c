/* SPDX-License-Identifier: MIT */
/* c4g-replay plot: one field of one axis over time with the arm's mode changes marked, or
 * the reply latency histogram, drawn by gnuplot (PNG, SVG, or text on the terminal). The
 * data goes through a temporary file; gnuplot reads the script on its standard input. */
#include "replay.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct pl_ctx {
    rp_common_t c;
    unsigned axis;          /* OPEN index, 1-based */
    char field[40];
    char side[8];           /* "ctrl" or "pc" */
    char output[512];
    unsigned session;       /* 0: the first with cyclic packets */
    int latency;
    unsigned field_k[4];    /* 0 mode, 1..5 D1..D5, 6..8 EXT1..3 */
    unsigned n_fields;
    FILE *data;
    unsigned chosen;        /* session plotted */
    uint64_t points;
} pl_ctx_t;

static const char *const field_names[9] = {"mode", "d1", "d2", "d3", "d4", "d5", "ext1", "ext2", "ext3"};

static void on_exchange(void *ctx, const c4gh_an_exchange_t *x)
{
    pl_ctx_t *p = ctx;
    const uint8_t *d;
    size_t len, off;
    double v;
    unsigned k;
    if (x->kind != C4G_PKT_CYCLIC) {
        return;
    }
    if (p->chosen == 0U && (p->session == 0U || p->session == x->s->id)) {
        p->chosen = x->s->id;
    }
    if (x->s->id != p->chosen) {
        return;
    }
    if (p->latency) {
        /* the replies the controller used (judged in time): a stale one is no latency */
        if (x->reply != NULL && x->verdict == C4G_CTRL_J_OK) {
            fprintf(p->data, "%.3f\n", (double)(x->reply_ns - x->ctrl_ns) * 1e-3);
            p->points++;
        }
        return;
    }
    d = (strcmp(p->side, "pc") == 0) ? x->reply : x->ctrl;
    len = (strcmp(p->side, "pc") == 0) ? x->reply_len : x->ctrl_len;
    if (d == NULL) {
        return;
    }
    fprintf(p->data, "%.9f", (double)(x->ctrl_ns - x->s->first_ns) * 1e-9);
    for (k = 0U; k < p->n_fields; k++) {
        off = C4G_HEADER_SIZE + (size_t)(p->axis - 1U) * C4G_AXIS_SIZE + 4U * p->field_k[k];
        if (len < off + 4U) {
            fprintf(p->data, " NaN");
            continue;
        }
        v = (p->field_k[k] == 0U) ? (double)c4g_le_i32(d + off) : (double)c4g_le_f32(d + off);
        if (isfinite(v)) {
            fprintf(p->data, " %.9g", v);
        } else {
            fprintf(p->data, " NaN");
        }
    }
    fputc('\n', p->data);
    p->points++;
}

/* What a field means, with its unit: the controller's packet (docs/protocol.md); the PC's
 * reply fields mean what its mode says (docs/modes.md). */
static const char *field_label(const pl_ctx_t *p, unsigned k)
{
    static const char *const ctrl[9] = {"mode", "D1 target position (turns)", "D2 target velocity",
                                        "D3 actual position (turns)", "D4 actual velocity",
                                        "D5 reference current (A)", "EXT1", "EXT2", "EXT3"};
    static const char *const pc[9] = {"mode", "D1 (by mode: docs/modes.md)", "D2 (by mode)", "D3 (by mode)",
                                      "D4 velocity contribution", "D5 current contribution (A)", "EXT1",
                                      "EXT2", "EXT3"};
    return (strcmp(p->side, "pc") == 0) ? pc[k] : ctrl[k];
}

static const char *terminal_for(const char *out)
{
    const size_t n = strlen(out);
    if (n >= 4U && strcmp(out + n - 4U, ".svg") == 0) {
        return "svg size 1000,500 dynamic";
    }
    if (n >= 4U && strcmp(out + n - 4U, ".png") == 0) {
        return "pngcairo size 1000,500";
    }
    return NULL;
}

/* The gnuplot script: output, mode changes as labelled vertical lines, the data. */
static int draw(const pl_ctx_t *p, const c4gh_an_t *a, const char *data_path)
{
    const c4gh_an_session_t *s = NULL;
    FILE *gp;
    unsigned i;
    int rc;
    for (i = 0U; i < a->n_sess; i++) {
        if (a->sess[i].id == p->chosen) {
            s = &a->sess[i];
        }
    }
    /* into a file: gnuplot's standard output is not the terminal (a failed 'set output'
     * would write the image there) */
    gp = popen(p->output[0] != '\0' ? "gnuplot >/dev/null" : "gnuplot", "w");
    if (gp == NULL) {
        fprintf(stderr, RP_TOOL ": plot: cannot run gnuplot (install gnuplot-nox)\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (p->output[0] != '\0') {
        fprintf(gp, "set terminal %s\nset output '%s'\n", terminal_for(p->output), p->output);
    } else {
        fprintf(gp, "set terminal dumb size 100,30\n");
    }
    if (p->latency) {
        /* log-spaced bins (20 a decade) on a log axis, drawn as impulses (no box widens a
         * sparse bin), and the T_CYCLE1 deadline */
        const double tc = (double)a->opt.t_cycle1_ns * 1e-3;
        fprintf(gp, "set title 'session %u: reply latency of the replies the controller used (stale ones left out)'\nset xlabel 'us (log)'\n"
                "set ylabel 'replies'\nset logscale x 10\nset grid\n"
                "bin(x) = 10 ** (floor(log10(x > 1 ? x : 1) * 20) / 20.0)\n"
                "set arrow from %.3f, graph 0 to %.3f, graph 1 nohead lc rgb 'red' lw 2\n"
                "set label 'T_CYCLE1 %.0f us' at %.3f, graph 0.95 right offset -1,0 tc rgb 'red' noenhanced\n"
                "plot '%s' using (bin($1)):(1.0) smooth freq with impulses lw 4 title 'replies per bin'\n",
                p->chosen, tc, tc, tc, tc, data_path);
    } else {
        unsigned k;
        const double span = (s != NULL) ? (double)(s->last_ns - s->first_ns) * 1e-9 : 0.0;
        fprintf(gp, "set title 'session %u: OPEN axis %u, %s'\nset xlabel 'time since the session start (s)'\n"
                "set ylabel '%s'\nset grid\nset key outside bottom center horizontal\n", p->chosen,
                p->axis, strcmp(p->side, "pc") == 0 ? "replies of the PC" : "packets of the controller",
                p->n_fields == 1U ? field_label(p, p->field_k[0]) : "");
        if (s != NULL && p->axis <= s->n_axes) {
            const uint32_t arm = s->map.arm_of[p->axis - 1U];
            double last = -1e9;
            for (i = 0U; arm < C4G_ARMS && i < s->n_tl[arm]; i++) {
                const double t = (double)s->tl[arm][i].t_ns * 1e-9;
                fprintf(gp, "set arrow from %.6f, graph 0 to %.6f, graph 1 nohead dt 2 lc rgb 'gray40'\n", t, t);
                if (t - last >= span / 50.0) { /* a label closer than that would overlap */
                    fprintf(gp, "set label 'mode %d' at %.6f, graph 0.95 left rotate by 90 font ',8'\n",
                            (int)s->tl[arm][i].to, t);
                    last = t;
                }
            }
        }
        fprintf(gp, "plot");
        for (k = 0U; k < p->n_fields; k++) {
            fprintf(gp, "%s '%s' using 1:%u with lines title '%s'", k > 0U ? "," : "", data_path, k + 2U,
                    field_label(p, p->field_k[k]));
        }
        fputc('\n', gp);
    }
    rc = pclose(gp);
    if (rc != 0) {
        fprintf(stderr, RP_TOOL ": plot: gnuplot failed (status %d)\n", rc);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (p->output[0] != '\0') {
        FILE *f = fopen(p->output, "rb");
        const int written = (f != NULL) && fgetc(f) != EOF;
        if (f != NULL) {
            fclose(f);
        }
        if (!written) {
            fprintf(stderr, RP_TOOL ": plot: gnuplot could not write %s\n", p->output);
            return C4GH_CLI_EXIT_RUNTIME;
        }
        fprintf(stderr, RP_TOOL ": plot: %llu points of session %u written to %s\n",
                (unsigned long long)p->points, p->chosen, p->output);
    }
    return C4GH_CLI_EXIT_OK;
}

static int run(pl_ctx_t *p, const char *path)
{
    char tmp[] = "/tmp/c4g-replay-plot-XXXXXX";
    const int fd = mkstemp(tmp);
    c4gh_an_t a;
    rp_file_t file;
    int rc;
    if (fd < 0 || (p->data = fdopen(fd, "w")) == NULL) {
        fprintf(stderr, RP_TOOL ": plot: cannot create a temporary file\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    p->c.an.on_exchange = on_exchange;
    p->c.an.ctx = p;
    if (c4gh_an_init(&a, &p->c.an) != 0) {
        fclose(p->data);
        unlink(tmp);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    rc = rp_read(&a, path, &file, 1);
    fclose(p->data);
    if (rc == 2) {
        rc = RP_EXIT_UNREADABLE;
    } else if (p->points == 0U) {
        fprintf(stderr, RP_TOOL ": plot: %s: nothing to plot (session %u, axis %u, %s %s)\n", path, p->session,
                p->axis, p->side, p->latency ? "latency" : p->field);
        rc = C4GH_CLI_EXIT_RUNTIME;
    } else {
        rc = draw(p, &a, tmp);
    }
    c4gh_an_free(&a);
    unlink(tmp);
    return rc;
}

static const char *const examples[] = {
    RP_TOOL " plot fixtures/replay/mode4.pcap --axis 1 --field d1",
    RP_TOOL " plot field.pcap --axis 2 --field d1 --side pc --out d1.png",
    RP_TOOL " plot field.pcap --latency --out latency.svg",
    RP_TOOL " plot field.pcap --axis 1 --field d1,d3 --out target-actual.png",
    NULL};

int rp_cmd_plot(int argc, char **argv)
{
    pl_ctx_t p;
    c4gh_cli_spec_t spec;
    int first = 0;
    unsigned k;
    c4gh_cli_result_t r;
    const c4gh_cli_opt_t rows[] = {
        {"axis", 'a', C4GH_CLI_UINT, "N", "OPEN axis 1..20 (default 1)", &p.axis, 0, 1, 20, NULL, 0},
        {"field", 'f', C4GH_CLI_STRING, "F[,F]", "mode, d1..d5 or ext1..ext3, up to 4 in one plot (default d1; "
         "d1,d3: target and actual)", p.field, sizeof p.field, 0, 0, NULL, 0},
        {"side", 0, C4GH_CLI_STRING, "ctrl|pc", "the controller's packets or the PC's replies (default ctrl)", p.side,
         sizeof p.side, 0, 0, NULL, 0},
        {"session", 's', C4GH_CLI_UINT, "N", "session N (default the first)", &p.session, 0, 1, 1e6, NULL, 0},
        {"latency", 0, C4GH_CLI_FLAG, NULL, "the reply latency histogram instead", &p.latency, 0, 0, 0, NULL, 0},
        {"out", 'o', C4GH_CLI_STRING, "FILE", "FILE.png or FILE.svg (default: a text plot on stdout)", p.output,
         sizeof p.output, 0, 0, NULL, 0},
        {"output", 0, C4GH_CLI_STRING, "FILE", NULL, p.output, sizeof p.output, 0, 0, NULL, 0},
    };
    memset(&p, 0, sizeof p);
    rp_common_default(&p.c);
    p.axis = 1U;
    strcpy(p.field, "d1");
    strcpy(p.side, "ctrl");
    memset(&spec, 0, sizeof spec);
    spec.tool = RP_TOOL;
    spec.command = "plot";
    spec.usage = "Usage: " RP_TOOL " plot [OPTIONS] FILE\n"
                 "One field of one axis over time, with the arm's mode changes marked, or the\n"
                 "reply latency histogram (gnuplot).\n";
    spec.opts = rows;
    spec.n_opts = sizeof rows / sizeof rows[0];
    spec.examples = examples;
    spec.operands_min = 1;
    spec.operands_max = 1;
    spec.permute = 1;
    r = c4gh_cli_parse(&spec, &p, argc, argv, &first);
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    {
        const char *f = p.field;
        while (*f != '\0') {
            const size_t n = strcspn(f, ",");
            for (k = 0U; k < 9U && !(strlen(field_names[k]) == n && strncmp(field_names[k], f, n) == 0); k++) {
            }
            if (k == 9U || p.n_fields >= 4U) {
                c4gh_cli_error(&spec, "--field: bad value '%s' (want up to 4 of mode, d1..d5, ext1..ext3 "
                          "separated by commas, e.g. d1,d3)", p.field);
                return C4GH_CLI_EXIT_USAGE;
            }
            p.field_k[p.n_fields++] = k;
            f += n;
            if (*f == ',') {
                f++;
            }
        }
        if (p.n_fields == 0U) {
            c4gh_cli_error(&spec, "--field: no field given");
            return C4GH_CLI_EXIT_USAGE;
        }
    }
    if (strcmp(p.side, "ctrl") != 0 && strcmp(p.side, "pc") != 0) {
        c4gh_cli_error(&spec, "--side: bad value '%s' (want ctrl or pc)", p.side);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (p.output[0] != '\0' && terminal_for(p.output) == NULL) {
        c4gh_cli_error(&spec, "--out: bad value '%s' (want a name ending in .png or .svg)", p.output);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (strchr(p.output, '\'') != NULL) {
        c4gh_cli_error(&spec, "--out: bad value '%s' (no quotes in the name)", p.output);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (p.output[0] != '\0' && c4gh_cli_check_output(spec.tool, "--out", p.output) != 0) {
        return C4GH_CLI_EXIT_RUNTIME; /* before gnuplot runs: the plot could not be written */
    }
    return run(&p, argv[first]);
}
