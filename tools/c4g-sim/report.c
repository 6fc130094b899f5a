/* SPDX-License-Identifier: MIT */
/* c4g-sim outputs: the per-tick CSV, the pcap file's life, the end-of-run summary (text
 * or JSON, docs/c4g-sim.md "Outputs"). */
#include <errno.h>
#include <string.h>
#include <sys/resource.h>

#include "app.h"
#include "c4gh_cli.h"
#include "c4gh_csv.h"

#include <jansson.h>

/* ---- files ---------------------------------------------------------------- */

static void csv_header(app_t *a)
{
    fputs(C4GH_TICK_CSV_COLUMNS ",tick,sent,reply_ok,rx_infpar,rx_cmd\n", a->csv);
}

int outputs_open(app_t *a)
{
    char err[512];
    if (a->o.csv_path != NULL) {
        a->csv = fopen(a->o.csv_path, "w");
        if (a->csv == NULL) {
            c4gh_cli_file_error("c4g-sim", "--csv", a->o.csv_path, errno);
            return EXIT_OUTPUT;
        }
        csv_header(a);
    }
    if (a->o.pcap_path != NULL) {
        a->pcap = c4gh_pcap_open(a->o.pcap_path, err, sizeof err);
        if (a->pcap == NULL) {
            char pt[600];
            fprintf(stderr, "c4g-sim: --pcap %s: %s\n", c4gh_cli_path_text(a->o.pcap_path, pt, sizeof pt),
                    err);
            return EXIT_OUTPUT;
        }
    }
    return EXIT_OK;
}

void outputs_close(app_t *a)
{
    if (a->csv != NULL && fclose(a->csv) != 0) {
        a->out_error = 1;
    }
    if (a->pcap != NULL && c4gh_pcap_close(a->pcap) != 0) {
        a->out_error = 1;
    }
    a->csv = NULL;
    a->pcap = NULL;
}

/* The per-tick CSV (docs/csv.md): rx_* the packet sent, tx_* the PC reply applied in this
 * tick (the last one received; tx_infpar 0 when none came this tick), then the simulator's
 * tick, whether the packet went out, whether a reply came, and the packet's INFPAR and CMD. */
void csv_row(app_t *a, const c4g_ctrl_packet_t *p, const c4g_pc_packet_t *rep, int sent)
{
    int i;
    if (a->csv == NULL) {
        return;
    }
    for (i = 0; i < a->sim.n_axes; i++) {
        const sim_ax_t *x = &a->sim.ax[i];
        c4gh_tick_csv_row(a->csv, (double)a->sim.tick * a->sim.period, p->num, (uint32_t)i + 1U,
                         (uint32_t)x->arm + 1U, (uint32_t)x->logical + 1U, &p->ax[i],
                         rep != NULL ? rep->infpar : 0U, &x->rx);
        fprintf(a->csv, ",%lu,%d,%d,0x%08x,0x%08x\n", a->sim.tick, sent, rep != NULL,
                (unsigned)p->infpar, (unsigned)p->cmd);
    }
}

double cpu_seconds(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_utime.tv_sec + (double)ru.ru_utime.tv_usec / 1e6 +
           (double)ru.ru_stime.tv_sec + (double)ru.ru_stime.tv_usec / 1e6;
}

/* ---- summary --------------------------------------------------------------- */

/* Numbers both summaries print. */
typedef struct figures {
    double per_packet_ns, lat_avg, p50, p99, p999, lat_min, lat_max;
} figures_t;

static figures_t figures(const app_t *a, double cpu_s)
{
    const c4g_ctrl_counters_t *n = &a->cs.n;
    figures_t f;
    f.per_packet_ns = (a->st.sent > 0U) ? cpu_s * 1e9 / (double)a->st.sent : 0.0;
    f.lat_avg = (n->replies_ok > 0U) ? (double)n->lat_sum / (double)n->replies_ok / 1000.0 : 0.0;
    f.p50 = c4gh_hist_us(&a->lat, 0.5);
    f.p99 = c4gh_hist_us(&a->lat, 0.99);
    f.p999 = c4gh_hist_us(&a->lat, 0.999);
    f.lat_min = (double)n->lat_min / 1000.0;
    f.lat_max = (double)n->lat_max / 1000.0;
    return f;
}

static void put_u(json_t *o, const char *key, unsigned long v)
{
    json_object_set_new(o, key, json_integer((json_int_t)v));
}

static void put_f(json_t *o, const char *key, double v)
{
    json_object_set_new(o, key, json_real(v));
}

static json_t *json_replies(const app_t *a, const figures_t *g)
{
    const c4g_ctrl_counters_t *n = &a->cs.n;
    json_t *o = json_object();
    json_t *l = json_object();
    put_u(o, "ok", n->replies_ok);
    put_u(o, "missing", n->missing);
    put_u(o, "late", n->late);
    put_u(o, "unjudged", n->unjudged);
    put_u(o, "wrong_num", n->wrong_num);
    put_u(o, "malformed", n->malformed);
    put_u(o, "foreign", n->foreign);
    put_u(o, "duplicates", n->duplicates);
    put_u(o, "stale", n->stale);
    put_u(o, "unexpected", n->unexpected);
    put_u(o, "max_consecutive_missing", n->max_consecutive);
    put_f(l, "min", g->lat_min);
    put_f(l, "avg", g->lat_avg);
    put_f(l, "p50", g->p50);
    put_f(l, "p99", g->p99);
    put_f(l, "p999", g->p999);
    put_f(l, "max", g->lat_max);
    json_object_set_new(o, "latency_us", l);
    return o;
}

static void json_faults_errors(json_t *o, const app_t *a)
{
    const sim_t *s = &a->sim;
    json_t *faults = json_object();
    json_t *errors = json_array();
    int i;
    json_object_set_new(o, "num_policy", json_string(c4g_num_policy_name((int)a->cs.cfg.policy)));
    json_object_set_new(o, "pc_policy", json_string(c4g_num_policy_name(a->cs.detected)));
    put_u(o, "udp_debug", s->udp_debug);
    put_u(o, "overruns", a->st.overruns);
    put_f(o, "overrun_max_us", (double)a->st.overrun_max / 1000.0);
    json_object_set_new(o, "timestamps", json_string(a->kstamp ? "kernel" : "user"));
    put_u(o, "paused_ticks", a->st.paused_ticks);
    json_object_set_new(o, "lockstep", json_boolean(a->o.lockstep));
    put_u(o, "lockstep_waits", a->st.lockstep_waits);
    put_f(o, "lockstep_wait_max_us", (double)a->st.lockstep_wait_max / 1000.0);
    put_u(o, "mode_rejected", s->mode_rejected);
    put_u(o, "mode_mismatch", s->mode_mismatch);
    for (i = 0; i < F_COUNT; i++) {
        put_u(faults, fault_names[i], a->st.fault[i]);
    }
    json_object_set_new(o, "faults", faults);
    for (i = 0; i < s->n_err; i++) {
        json_array_append_new(errors, json_pack("{s:s, s:s?, s:I}", "name",
                                                c4g_ctrl_error_name(s->err[i].code), "message",
                                                s->err[i].text, "tick", (json_int_t)s->err[i].tick));
    }
    json_object_set_new(o, "errors", errors);
}

static void json_scenario_robot(json_t *o, const sim_t *s)
{
    json_t *robot = json_array();
    int i;
    json_object_set_new(o, "scenario",
                        json_pack("{s:b, s:b, s:b, s:i, s:i, s:i, s:b}", "loaded", s->scn != NULL,
                                  "done", s->scn_done, "aborted", s->scn_aborted, "commands_run",
                                  s->pc, "expect_passed", s->expect_passed, "expect_failed",
                                  s->expect_failed, "wait_pc_timeout", s->scn_timeout));
    if (s->expect_first[0] != '\0') {
        json_object_set_new(json_object_get(o, "scenario"), "first_failure",
                            json_string(s->expect_first));
    }
    for (i = 0; i < s->n_axes; i++) {
        const sim_ax_t *x = &s->ax[i];
        json_array_append_new(robot, json_pack("{s:i, s:i, s:i, s:b, s:f, s:f, s:f}", "arm",
                                               x->arm + 1, "axis", x->logical + 1, "mode", x->mode,
                                               "drive_on", x->m.drive_on, "pos", x->m.meas_pos,
                                               "target", x->pos_ref, "current", x->m.cur));
    }
    json_object_set_new(o, "robot", robot);
}

/* The JSON summary (jansson): one object on one line of stdout. */
static void summary_json(const app_t *a, int code, const char *result, double cpu_s)
{
    const sim_t *s = &a->sim;
    const c4g_ctrl_counters_t *n = &a->cs.n;
    const figures_t g = figures(a, cpu_s);
    json_t *o = json_object();
    json_object_set_new(o, "tool", json_string("c4g-sim"));
    json_object_set_new(o, "version", json_string(C4G_VERSION_STRING));
    json_object_set_new(o, "result", json_string(result));
    json_object_set_new(o, "exit_code", json_integer(code));
    json_object_set_new(o, "period_ms", json_integer(s->cfg.period_ms));
    json_object_set_new(o, "axes", json_integer(s->n_axes));
    put_u(o, "ticks", s->tick);
    json_object_set_new(o, "packets", json_pack("{s:I, s:I, s:I, s:I}", "sent",
                                                (json_int_t)a->st.sent, "sync",
                                                (json_int_t)n->sync_sent, "init",
                                                (json_int_t)n->init_sent, "cyclic",
                                                (json_int_t)n->cyclic_sent));
    json_object_set_new(o, "replies", json_replies(a, &g));
    json_faults_errors(o, a);
    json_scenario_robot(o, s);
    json_object_set_new(o, "cpu", json_pack("{s:f, s:f}", "seconds", cpu_s, "ns_per_packet",
                                            g.per_packet_ns));
    json_dumpf(o, stdout, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(12));
    fputc('\n', stdout);
    json_decref(o);
}

static void text_errors_robot(const sim_t *s)
{
    int i;
    for (i = 0; i < s->n_err; i++) {
        printf("  error at tick %lu: %s: %s\n", s->err[i].tick, c4g_ctrl_error_name(s->err[i].code),
               s->err[i].text);
    }
    if (s->scn != NULL) {
        /* the run is over: a scenario that did not reach its end stopped where the run did */
        char state[64] = "done";
        if (s->scn_aborted) {
            snprintf(state, sizeof state, "aborted");
        } else if (!s->scn_done && s->pc < s->scn->n) {
            snprintf(state, sizeof state, "ended at line %d (%s)", s->scn->cmd[s->pc].line,
                     scn_op_name(s->scn->cmd[s->pc].op));
        }
        printf("  scenario: %s, %d commands, expectations %d passed %d failed\n", state, s->pc,
               s->expect_passed, s->expect_failed);
        if (s->expect_first[0] != '\0') {
            printf("  first failed expectation: scenario %s\n", s->expect_first);
        }
    }
    for (i = 0; i < s->n_axes; i++) {
        const sim_ax_t *x = &s->ax[i];
        printf("  arm %d axis %d: mode %d, pos %.6f turns, target %.6f, current %.3f A\n", x->arm + 1,
               x->logical + 1, x->mode, x->m.meas_pos, x->pos_ref, x->m.cur);
    }
}

int no_session(const c4g_ctrl_counters_t *n, const char *server, unsigned port, char *why,
               size_t cap)
{
    if (n->replies_ok > 0U) {
        return 0;
    }
    if (n->sync_sent + n->init_sent + n->cyclic_sent == 0U) {
        (void)snprintf(why, cap, "no packet was sent to %s:%u", server, port);
    } else if (n->rx_total == 0U) {
        (void)snprintf(why, cap, "nothing answered on %s:%u (is c4g-server running there?)",
                       server, port);
    } else if (n->foreign == n->rx_total) {
        (void)snprintf(why, cap, "%lu datagrams came, all from other addresses than %s:%u "
                       "(the PC given by --server and --port)", (unsigned long)n->rx_total,
                       server, port);
    } else {
        (void)snprintf(why, cap, "%s:%u answered %lu times, never validly (wrong NUM %lu, "
                       "malformed %lu, stale %lu, duplicates %lu)", server, port,
                       (unsigned long)(n->rx_total - n->foreign), (unsigned long)n->wrong_num,
                       (unsigned long)n->malformed, (unsigned long)n->stale,
                       (unsigned long)n->duplicates);
    }
    return 1;
}

/* No reply was ever accepted: the counters are all zero, so one line says why instead. */
static void summary_none(const app_t *a, int code, const char *result, const char *why)
{
    const c4g_ctrl_counters_t *n = &a->cs.n;
    int i;
    printf("c4g-sim %s: %s (exit %d)\n", C4G_VERSION_STRING, result, code);
    printf("  no session started: %s; sent %lu (sync %lu, init %lu, cyclic %lu)\n", why,
           a->st.sent, n->sync_sent, n->init_sent, n->cyclic_sent);
    for (i = 0; i < a->sim.n_err; i++) {
        printf("  error at tick %lu: %s: %s\n", a->sim.err[i].tick,
               c4g_ctrl_error_name(a->sim.err[i].code), a->sim.err[i].text);
    }
}

static void summary_text(const app_t *a, int code, const char *result, double cpu_s)
{
    const sim_t *s = &a->sim;
    const c4g_ctrl_counters_t *n = &a->cs.n;
    const figures_t g = figures(a, cpu_s);
    int i;
    char why[256];
    if (no_session(n, a->cfg.server, a->cfg.port, why, sizeof why)) {
        summary_none(a, code, result, why);
        return;
    }
    printf("c4g-sim %s: %s (exit %d)\n", C4G_VERSION_STRING, result, code);
    printf("  ticks %lu, period %d ms, %d open axes\n", s->tick, s->cfg.period_ms, s->n_axes);
    printf("  sent %lu (sync %lu, init %lu, cyclic %lu)\n", a->st.sent, n->sync_sent, n->init_sent,
           n->cyclic_sent);
    printf("  replies ok %lu, missing %lu, late %lu, unjudged %lu, wrong NUM %lu, malformed %lu, "
           "foreign %lu, duplicates %lu, stale %lu\n", n->replies_ok, n->missing, n->late,
           n->unjudged, n->wrong_num, n->malformed, n->foreign, n->duplicates, n->stale);
    if (n->missing > 0 || n->stale > 0) {
        printf("  (missing: no reply to a packet by the next tick; stale: a reply that came "
               "after that, to an older packet; the PC server counts the same losses as gaps)\n");
    }
    printf("  own overruns %lu (worst %.1f us after the tick), %s timestamps\n", a->st.overruns,
           (double)a->st.overrun_max / 1000.0, a->kstamp ? "kernel" : "user-space");
    if (a->o.lockstep) {
        printf("  lockstep: %lu replies waited for past their tick (longest %.1f us past it)\n",
               a->st.lockstep_waits, (double)a->st.lockstep_wait_max / 1000.0);
    }
    printf("  reply latency us: min %.1f avg %.1f p50 %.0f p99 %.0f p99.9 %.0f max %.1f; max consecutive missing %lu\n",
           g.lat_min, g.lat_avg, g.p50, g.p99, g.p999, g.lat_max, n->max_consecutive);
    printf("  faults:");
    for (i = 0; i < F_COUNT; i++) {
        printf(" %s %lu", fault_names[i], a->st.fault[i]);
    }
    printf("; paused ticks %lu\n", a->st.paused_ticks);
    text_errors_robot(s);
    printf("  cpu %.3f s, %.0f ns per packet\n", cpu_s, g.per_packet_ns);
}

void summary(const app_t *a, int code, const char *result, double cpu_s)
{
    if (a->o.json) {
        summary_json(a, code, result, cpu_s);
    } else {
        summary_text(a, code, result, cpu_s);
    }
}
