/* SPDX-License-Identifier: MIT */
/* c4g-replay follow: how well the arm followed its target in each capture. Over the cyclic
 * ticks where the controller's target moves (|D2| above a threshold) on the chosen axes: the
 * following error D1 - D3 and the current the DSA's own loops had to find (D5 less the PC's
 * mode-9 addition when the reply carried one) as RMS, per axis and over all of them; and in
 * mode 9 the ticks whose reply did not bring the addition by the controller's deadline (none,
 * too late, or another mode), which make a move measure the network rather than the
 * feedforward. Several captures of the same move (mode 0, mode 9
 * with a parameter file...) print side by side with the ratio of each to the first.
 * --skip-late MS adds the same figures over the ticks farther than MS from any late mode-9
 * tick: a first pass over the file finds those, the second leaves their neighbours out, so
 * a move's figure can be read apart from the host's hiccups. */
#include "replay.h"

#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FW_MAX_FILES 16U

typedef struct fw_sums {
    uint64_t ticks;              /* moving ticks seen (axis-ticks for the total) */
    double fe2, dsa2;            /* sums of squares */
    double fe_max;
    uint64_t m9_ticks, m9_missing; /* mode-9 moving ticks; of them without the addition in time */
} fw_sums_t;

typedef struct fw_file {
    const char *path;
    fw_sums_t axis[C4G_MAX_AXES];
    fw_sums_t all;
    fw_sums_t skip_axis[C4G_MAX_AXES]; /* --skip-late: the ticks far from a late one */
    fw_sums_t skip_all;
    uint64_t late_ticks;               /* --skip-late: mode-9 ticks late, any axis */
    unsigned sessions;
    int rc;
} fw_file_t;

typedef struct fw_ctx {
    rp_common_t c;
    uint32_t axes;               /* OPEN index bits, 0: all */
    double moving;               /* |D2| threshold [turns/tick] */
    double from_s, to_s;
    unsigned session;
    int per_axis;
    double skip_ms;              /* --skip-late MS; < 0: not asked */
    int pass;                    /* --skip-late: 1 finds the late ticks, 2 sums */
    int64_t *late;               /* pass 1: capture times of the late ticks, sorted */
    size_t n_late, cap_late;
    int oom;
    fw_file_t *cur;
} fw_ctx_t;

static void add(fw_sums_t *s, double fe, double dsa, int m9, int m9_missing)
{
    s->ticks++;
    s->fe2 += fe * fe;
    s->dsa2 += dsa * dsa;
    if (fabs(fe) > s->fe_max) {
        s->fe_max = fabs(fe);
    }
    if (m9) {
        s->m9_ticks++;
        s->m9_missing += (uint64_t)(m9_missing != 0);
    }
}

static double rms(double sum2, uint64_t n) { return n > 0U ? sqrt(sum2 / (double)n) : 0.0; }

/* Axis @p i of this tick is in mode 9 and its reply did not bring the addition in time. */
static int m9_late(const c4gh_an_exchange_t *x, uint32_t i)
{
    const c4g_pc_axis_t *p = (x->tx != NULL && i < x->tx->n_axes) ? &x->tx->ax[i] : NULL;
    const int in_time = p != NULL && p->mode == C4G_MODE_9 && x->verdict == C4G_CTRL_J_OK;
    return x->rx->ax[i].mode == C4G_MODE_9 && !in_time;
}

/* Pass 1 of --skip-late: the times of the ticks with a late mode-9 reply on any axis (a
 * late reply leaves every axis of the tick without its addition). */
static void note_late(fw_ctx_t *F, const c4gh_an_exchange_t *x)
{
    uint32_t i;
    for (i = 0U; i < x->rx->n_axes && i < C4G_MAX_AXES; i++) {
        if (m9_late(x, i)) {
            break;
        }
    }
    if (i == x->rx->n_axes || i == C4G_MAX_AXES) {
        return;
    }
    if (F->n_late == F->cap_late) {
        const size_t cap = F->cap_late ? 2U * F->cap_late : 256U;
        int64_t *p = realloc(F->late, cap * sizeof *p);
        if (p == NULL) {
            F->oom = 1;
            return;
        }
        F->late = p;
        F->cap_late = cap;
    }
    F->late[F->n_late++] = x->ctrl_ns;
    F->cur->late_ticks++;
}

static int cmp_i64(const void *a, const void *b)
{
    const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* --skip-late: a late tick within skip_ms of @p t (F->late sorted). */
static int near_late(const fw_ctx_t *F, int64_t t)
{
    const double w = F->skip_ms * 1e6;
    size_t lo = 0U, hi = F->n_late;
    while (lo < hi) { /* the first late tick at or after t - w */
        const size_t mid = lo + (hi - lo) / 2U;
        if ((double)F->late[mid] < (double)t - w) {
            lo = mid + 1U;
        } else {
            hi = mid;
        }
    }
    return lo < F->n_late && (double)F->late[lo] <= (double)t + w;
}

static void on_exchange(void *ctx, const c4gh_an_exchange_t *x)
{
    fw_ctx_t *F = ctx;
    const double t = (double)(x->ctrl_ns - x->s->first_ns) * 1e-9;
    uint32_t i;
    int skip;
    if (x->kind != C4G_PKT_CYCLIC || x->rx == NULL) {
        return;
    }
    if (F->session != 0U && x->s->id != F->session) {
        return;
    }
    if (F->pass == 1) {
        note_late(F, x); /* a late tick just outside --from/--to still has neighbours inside */
        return;
    }
    if (t < F->from_s || (F->to_s >= 0.0 && t > F->to_s)) {
        return;
    }
    skip = F->pass == 2 && near_late(F, x->ctrl_ns);
    for (i = 0U; i < x->rx->n_axes && i < C4G_MAX_AXES; i++) {
        const c4g_ctrl_axis_t *a = &x->rx->ax[i];
        const c4g_pc_axis_t *p = (x->tx != NULL && i < x->tx->n_axes) ? &x->tx->ax[i] : NULL;
        const int m9 = a->mode == C4G_MODE_9;
        const int late = m9_late(x, i);
        const double fe = (double)a->target_pos - (double)a->actual_pos;
        double dsa = (double)a->current_ref;
        if ((F->axes != 0U && (F->axes & (1U << i)) == 0U) || !(fabs((double)a->target_vel) > F->moving)) {
            continue;
        }
        if (p != NULL && p->mode == C4G_MODE_9) {
            dsa -= (double)p->current_add;
        }
        add(&F->cur->axis[i], fe, dsa, m9, late);
        add(&F->cur->all, fe, dsa, m9, late);
        if (F->pass == 2 && !skip) {
            add(&F->cur->skip_axis[i], fe, dsa, m9, late);
            add(&F->cur->skip_all, fe, dsa, m9, late);
        }
    }
}

static int opt_axes(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    fw_ctx_t *F = ctx;
    (void)row;
    if (c4gh_cli_parse_axis_list(v, 20U, &F->axes) != 0) {
        (void)snprintf(why, whylen, "want OPEN axes 1..20 like 1,3-5");
        return -1;
    }
    return 0;
}

static int opt_port(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t whylen)
{
    return rp_opt_port(&((fw_ctx_t *)ctx)->c, row, v, why, whylen);
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s != NULL ? s + 1 : path;
}

static void text_row(const char *label, const fw_sums_t *s, const fw_sums_t *first)
{
    const double fe = rms(s->fe2, s->ticks), dsa = rms(s->dsa2, s->ticks);
    const double fe0 = first != NULL ? rms(first->fe2, first->ticks) : 0.0;
    char ratio[24] = "-", late[24] = "-";
    if (first != NULL && fe > 0.0 && fe0 > 0.0) {
        (void)snprintf(ratio, sizeof ratio, "%.1fx", fe0 / fe);
    }
    if (s->m9_ticks > 0U) {
        (void)snprintf(late, sizeof late, "%llu", (unsigned long long)s->m9_missing);
    }
    printf("  %-26s %7llu %14.4g %14.4g %14.4g %8s %9s\n", label, (unsigned long long)s->ticks, fe, s->fe_max,
           dsa, late, ratio);
}

static void report_text(const fw_ctx_t *F, const fw_file_t *files, unsigned n)
{
    unsigned f, i;
    printf("following error over the ticks where the target moves (|D2| > %g turn/tick)\n", F->moving);
    printf("  %-26s %7s %14s %14s %14s %8s %9s\n", "capture", "ticks", "FE RMS [turn]", "FE max [turn]",
           "DSA RMS [A]", "m9 late", "1st/this");
    for (f = 0U; f < n; f++) {
        text_row(base_name(files[f].path), &files[f].all, f > 0U ? &files[0].all : NULL);
        for (i = 0U; F->per_axis && i < C4G_MAX_AXES; i++) {
            char label[40];
            if (files[f].axis[i].ticks == 0U) {
                continue;
            }
            (void)snprintf(label, sizeof label, "  axis %u", i + 1U);
            text_row(label, &files[f].axis[i], f > 0U ? &files[0].axis[i] : NULL);
        }
    }
    if (F->skip_ms >= 0.0) {
        printf("the same without the ticks within %g ms of a late mode-9 tick (--skip-late)\n", F->skip_ms);
        for (f = 0U; f < n; f++) {
            text_row(base_name(files[f].path), &files[f].skip_all, f > 0U ? &files[0].skip_all : NULL);
            for (i = 0U; F->per_axis && i < C4G_MAX_AXES; i++) {
                char label[40];
                if (files[f].axis[i].ticks == 0U) {
                    continue;
                }
                (void)snprintf(label, sizeof label, "  axis %u", i + 1U);
                text_row(label, &files[f].skip_axis[i], f > 0U ? &files[0].skip_axis[i] : NULL);
            }
            printf("  %-26s %llu late mode-9 tick%s, %llu axis-tick%s left out\n", "",
                   (unsigned long long)files[f].late_ticks, files[f].late_ticks == 1U ? "" : "s",
                   (unsigned long long)(files[f].all.ticks - files[f].skip_all.ticks),
                   files[f].all.ticks - files[f].skip_all.ticks == 1U ? "" : "s");
        }
    }
    printf("FE = D1 - D3 (target less actual position); DSA = D5 less the PC's mode-9 addition;\n"
           "m9 late: mode-9 ticks without the PC's addition by the deadline; 1st/this: the\n"
           "first capture's FE RMS over this one's (how many times better this one follows).\n");
}

static json_t *sums_json(const fw_sums_t *s, const fw_sums_t *first)
{
    const double fe = rms(s->fe2, s->ticks);
    json_t *o = json_pack("{s:I,s:f,s:f,s:f,s:I,s:I}", "ticks", (json_int_t)s->ticks, "follow_rms", fe,
                          "follow_max", s->fe_max, "dsa_current_rms", rms(s->dsa2, s->ticks), "mode9_ticks",
                          (json_int_t)s->m9_ticks, "mode9_late", (json_int_t)s->m9_missing);
    if (o != NULL && first != NULL && fe > 0.0 && first->ticks > 0U) {
        (void)json_object_set_new(o, "first_over_this", json_real(rms(first->fe2, first->ticks) / fe));
    }
    return o;
}

/* --skip-late's figures of one capture or axis, beside its own */
static void skip_json(json_t *o, const fw_ctx_t *F, const fw_sums_t *all, const fw_sums_t *s, const fw_sums_t *first)
{
    json_t *k = sums_json(s, first);
    if (k == NULL) {
        return;
    }
    (void)json_object_set_new(k, "ms", json_real(F->skip_ms));
    (void)json_object_set_new(k, "left_out", json_integer((json_int_t)(all->ticks - s->ticks)));
    (void)json_object_set_new(o, "skip_late", k);
}

static int report_json(const fw_ctx_t *F, const fw_file_t *files, unsigned n)
{
    json_t *root = json_object(), *arr = json_array();
    unsigned f, i;
    int rc;
    if (root == NULL || arr == NULL) {
        json_decref(root);
        json_decref(arr);
        return -1;
    }
    (void)json_object_set_new(root, "moving_threshold", json_real(F->moving));
    for (f = 0U; f < n; f++) {
        json_t *o = sums_json(&files[f].all, f > 0U ? &files[0].all : NULL);
        json_t *ax = json_array();
        for (i = 0U; i < C4G_MAX_AXES; i++) {
            json_t *a;
            if (files[f].axis[i].ticks == 0U) {
                continue;
            }
            a = sums_json(&files[f].axis[i], f > 0U ? &files[0].axis[i] : NULL);
            (void)json_object_set_new(a, "axis", json_integer((json_int_t)i + 1));
            if (F->skip_ms >= 0.0) {
                skip_json(a, F, &files[f].axis[i], &files[f].skip_axis[i], f > 0U ? &files[0].skip_axis[i] : NULL);
            }
            (void)json_array_append_new(ax, a);
        }
        (void)json_object_set_new(o, "file", json_string(files[f].path));
        if (F->skip_ms >= 0.0) {
            skip_json(o, F, &files[f].all, &files[f].skip_all, f > 0U ? &files[0].skip_all : NULL);
            (void)json_object_set_new(json_object_get(o, "skip_late"), "late_ticks",
                                      json_integer((json_int_t)files[f].late_ticks));
        }
        (void)json_object_set_new(o, "axes", ax);
        (void)json_array_append_new(arr, o);
    }
    (void)json_object_set_new(root, "captures", arr);
    rc = json_dumpf(root, stdout, JSON_INDENT(2) | JSON_REAL_PRECISION(9));
    json_decref(root);
    printf("\n");
    return rc;
}

static const char *const examples[] = {
    RP_TOOL " follow move0.pcap move9.pcap            # mode 0 against mode 9",
    RP_TOOL " follow --axes 1-3 --per-axis move0.pcap move9.pcap",
    RP_TOOL " follow --json --from 0.5 --to 2.5 run.pcap | jq '.captures[0].follow_rms'",
    RP_TOOL " follow --skip-late 5 move0.pcap move9.pcap  # leave out 5 ms around late mode-9 ticks",
    NULL};

static const char epilogue[] =
    "The ticks counted are those where the controller's target moves on an axis chosen: a\n"
    "move's following error, not the standstill's. With several captures of the same move the\n"
    "last column says how many times smaller each one's following error is than the first's.\n";

int rp_cmd_follow(int argc, char **argv)
{
    static fw_file_t files[FW_MAX_FILES];
    fw_ctx_t F;
    c4gh_cli_spec_t spec;
    int first = 0, f, worst = 0;
    unsigned n;
    c4gh_cli_result_t r;
    const c4gh_cli_opt_t rows[] = {
        {"axes", 0, C4GH_CLI_CALL, "LIST", "OPEN axes, e.g. 1-3 (default all)", NULL, 0, 0, 0, opt_axes, 0},
        {"moving", 0, C4GH_CLI_DOUBLE, "E", "a tick counts when |D2| > E turn/tick (default 1e-6)", &F.moving, 0,
         0, 1e3, NULL, 0},
        {"from", 0, C4GH_CLI_DOUBLE, "S", "ticks at or after S seconds into the session", &F.from_s, 0, 0, 1e9,
         NULL, 0},
        {"to", 0, C4GH_CLI_DOUBLE, "S", "ticks at or before S seconds", &F.to_s, 0, 0, 1e9, NULL, 0},
        {"session", 's', C4GH_CLI_UINT, "N", "only session N of each capture (summary numbers them)", &F.session,
         0, 1, 1e6, NULL, 0},
        {"skip-late", 0, C4GH_CLI_DOUBLE, "MS", "also the figures without the ticks within MS ms of a late "
         "mode-9 tick", &F.skip_ms, 0, 0, 1e6, NULL, 0},
        {"per-axis", 0, C4GH_CLI_FLAG, NULL, "a row per axis under each capture", &F.per_axis, 0, 0, 0, NULL, 0},
        {"json", 'j', C4GH_CLI_FLAG, NULL, "the figures as one JSON object on stdout", &F.c.json, 0, 0, 0, NULL, 0},
        {"port", 'p', C4GH_CLI_CALL, "LIST", "PC ports of C4G Open flows (default 1000,1001)", NULL, 0, 0, 0,
         opt_port, 0},
        {"no-progress", 0, C4GH_CLI_FLAG, NULL, "no progress bar on a terminal", &F.c.no_progress, 0, 0, 0, NULL, 0},
    };
    memset(&F, 0, sizeof F);
    memset(files, 0, sizeof files);
    rp_common_default(&F.c);
    F.moving = 1e-6;
    F.to_s = -1.0;
    F.skip_ms = -1.0;
    memset(&spec, 0, sizeof spec);
    spec.tool = RP_TOOL;
    spec.command = "follow";
    spec.usage = "Usage: " RP_TOOL " follow [OPTIONS] FILE...\n"
                 "Following error and the DSA's own current over the ticks where the target moves,\n"
                 "per capture (and per axis), with each capture's ratio to the first.\n";
    spec.opts = rows;
    spec.n_opts = sizeof rows / sizeof rows[0];
    spec.examples = examples;
    spec.epilogue = epilogue;
    spec.operands_min = 1;
    spec.operands_max = (int)FW_MAX_FILES;
    spec.permute = 1;
    r = c4gh_cli_parse(&spec, &F, argc, argv, &first);
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? C4GH_CLI_EXIT_OK : C4GH_CLI_EXIT_USAGE;
    }
    if (F.to_s >= 0.0 && F.to_s < F.from_s) {
        c4gh_cli_error(&spec, "--to %g is before --from %g: no tick would count", F.to_s, F.from_s);
        return C4GH_CLI_EXIT_USAGE;
    }
    F.c.an.on_exchange = on_exchange;
    F.c.an.ctx = &F;
    for (f = first, n = 0U; f < argc; f++, n++) {
        c4gh_an_t a;
        rp_file_t info;
        files[n].path = argv[f];
        F.cur = &files[n];
        F.n_late = 0U;
        F.pass = 0;
        if (F.skip_ms >= 0.0) {
            /* pass 1: where the late ticks are; the figures come from pass 2 */
            F.pass = 1;
            if (c4gh_an_init(&a, &F.c.an) != 0) {
                fprintf(stderr, RP_TOOL ": out of memory\n");
                free(F.late);
                return C4GH_CLI_EXIT_RUNTIME;
            }
            (void)rp_read(&a, argv[f], &info, 0);
            c4gh_an_free(&a);
            if (F.oom) {
                fprintf(stderr, RP_TOOL ": out of memory\n");
                free(F.late);
                return C4GH_CLI_EXIT_RUNTIME;
            }
            if (F.n_late > 1U) {
                qsort(F.late, F.n_late, sizeof *F.late, cmp_i64);
            }
            F.pass = 2;
        }
        if (c4gh_an_init(&a, &F.c.an) != 0) {
            fprintf(stderr, RP_TOOL ": out of memory\n");
            free(F.late);
            return C4GH_CLI_EXIT_RUNTIME;
        }
        files[n].rc = rp_read(&a, argv[f], &info, !F.c.no_progress);
        files[n].sessions = rp_file_sessions(&a, argv[f]);
        c4gh_an_free(&a);
        if (files[n].rc == 0 && files[n].all.ticks == 0U) {
            fprintf(stderr, RP_TOOL ": %s: no tick where the target moves on the axes chosen (%u session%s)\n",
                    argv[f], files[n].sessions, files[n].sessions == 1U ? "" : "s");
            files[n].rc = 1;
        }
        worst = files[n].rc > worst ? files[n].rc : worst;
    }
    free(F.late);
    F.late = NULL;
    if (F.c.json) {
        if (report_json(&F, files, n) != 0) {
            fprintf(stderr, RP_TOOL ": writing the JSON report failed\n");
            return C4GH_CLI_EXIT_RUNTIME;
        }
    } else {
        report_text(&F, files, n);
    }
    if (fflush(stdout) != 0) {
        fprintf(stderr, RP_TOOL ": writing the report failed\n");
        return C4GH_CLI_EXIT_RUNTIME;
    }
    return (worst == 2) ? RP_EXIT_UNREADABLE : (worst == 1 ? C4GH_CLI_EXIT_RUNTIME : C4GH_CLI_EXIT_OK);
}
