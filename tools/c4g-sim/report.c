/* SPDX-License-Identifier: MIT */
/* c4g-sim outputs: the per-tick CSV, the pcap file's life, the end-of-run summary (text
 * or JSON, docs/c4g-sim.md "Outputs"). */
#include <errno.h>
#include <string.h>
#include <sys/resource.h>

#include "app.h"
#include "c4g_cli.h"

/* ---- files ---------------------------------------------------------------- */

static void csv_header(app_t *a)
{
    int i;
    fprintf(a->csv, "tick,time_s,num,sent,infpar,cmd,reply_ok");
    for (i = 0; i < a->sim.n_axes; i++) {
        fprintf(a->csv, ",a%d_mode,a%d_tpos,a%d_tvel,a%d_apos,a%d_avel,a%d_cur,a%d_rmode,a%d_rd1,"
                        "a%d_rd2,a%d_rd4,a%d_rd5", i, i, i, i, i, i, i, i, i, i, i);
    }
    fputc('\n', a->csv);
}

int outputs_open(app_t *a)
{
    char err[512];
    if (a->o.csv_path != NULL) {
        a->csv = fopen(a->o.csv_path, "w");
        if (a->csv == NULL) {
            cli_file_error("c4g-sim", "--csv", a->o.csv_path, errno);
            return EXIT_OUTPUT;
        }
        csv_header(a);
    }
    if (a->o.pcap_path != NULL) {
        a->pcap = c4g_pcap_open(a->o.pcap_path, err, sizeof err);
        if (a->pcap == NULL) {
            char pt[600];
            fprintf(stderr, "c4g-sim: --pcap %s: %s\n", cli_path_text(a->o.pcap_path, pt, sizeof pt),
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
    if (a->pcap != NULL && c4g_pcap_close(a->pcap) != 0) {
        a->out_error = 1;
    }
    a->csv = NULL;
    a->pcap = NULL;
}

void csv_row(app_t *a, const c4g_ctrl_packet_t *p, int sent, int reply_ok)
{
    int i;
    if (a->csv == NULL) {
        return;
    }
    fprintf(a->csv, "%lu,%.4f,%d,%d,0x%08x,0x%08x,%d", a->sim.tick,
            (double)a->sim.tick * a->sim.period, p->num, sent, (unsigned)p->infpar, (unsigned)p->cmd,
            reply_ok);
    for (i = 0; i < a->sim.n_axes; i++) {
        const c4g_ctrl_axis_t *x = &p->ax[i];
        const c4g_pc_axis_t *r = &a->sim.ax[i].rx;
        fprintf(a->csv, ",%d,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%.9g,%.9g,%.9g,%.9g", (int)x->mode,
                (double)x->target_pos, (double)x->target_vel, (double)x->actual_pos,
                (double)x->actual_vel, (double)x->current_ref, (int)r->mode, (double)r->target_pos,
                (double)r->target_vel, (double)r->vel_add, (double)r->current_add);
    }
    fputc('\n', a->csv);
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
    const cs_counters_t *n = &a->cs.n;
    figures_t f;
    f.per_packet_ns = (a->st.sent > 0U) ? cpu_s * 1e9 / (double)a->st.sent : 0.0;
    f.lat_avg = (n->replies_ok > 0U) ? (double)n->lat_sum / (double)n->replies_ok / 1000.0 : 0.0;
    f.p50 = cs_lat_percentile(n, 0.5);
    f.p99 = cs_lat_percentile(n, 0.99);
    f.p999 = cs_lat_percentile(n, 0.999);
    f.lat_min = (double)n->lat_min / 1000.0;
    f.lat_max = (double)n->lat_max / 1000.0;
    return f;
}

static const char *jbool(int b)
{
    return b ? "true" : "false";
}

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s != '\0'; s++) {
        if (*s == '"' || *s == '\\') {
            fputc('\\', f);
        }
        if ((unsigned char)*s < 0x20U) {
            fprintf(f, "\\u%04x", (unsigned)*s);
        } else {
            fputc(*s, f);
        }
    }
    fputc('"', f);
}

static void json_replies(FILE *f, const app_t *a, const figures_t *g)
{
    const cs_counters_t *n = &a->cs.n;
    fprintf(f, "\"replies\":{\"ok\":%lu,\"missing\":%lu,\"late\":%lu,\"unjudged\":%lu,\"wrong_num\":%lu,"
               "\"malformed\":%lu,\"foreign\":%lu,\"duplicates\":%lu,\"stale\":%lu,\"unexpected\":%lu,"
               "\"max_consecutive_missing\":%lu,\"latency_us\":{\"min\":%.1f,\"avg\":%.1f,\"p50\":%.0f,"
               "\"p99\":%.0f,\"p999\":%.0f,\"max\":%.1f}},",
            n->replies_ok, n->missing, n->late, n->unjudged, n->wrong_num, n->malformed, n->foreign,
            n->duplicates, n->stale, n->unexpected, n->max_consecutive, g->lat_min, g->lat_avg, g->p50,
            g->p99, g->p999, g->lat_max);
}

static void json_faults_errors(FILE *f, const app_t *a)
{
    const sim_t *s = &a->sim;
    int i;
    fprintf(f, "\"num_policy\":\"%s\",\"pc_policy\":\"%s\",\"udp_debug\":%lu,\"overruns\":%lu,"
               "\"overrun_max_us\":%.1f,\"timestamps\":\"%s\",\"paused_ticks\":%lu,"
               "\"mode_rejected\":%lu,\"mode_mismatch\":%lu,\"faults\":{",
            cs_policy_name((int)a->cs.cfg.policy), cs_policy_name(a->cs.detected), s->udp_debug,
            a->st.overruns, (double)a->st.overrun_max / 1000.0, a->kstamp ? "kernel" : "user",
            a->st.paused_ticks, s->mode_rejected, s->mode_mismatch);
    for (i = 0; i < F_COUNT; i++) {
        fprintf(f, "%s\"%s\":%lu", i ? "," : "", fault_names[i], a->st.fault[i]);
    }
    fprintf(f, "},\"errors\":[");
    for (i = 0; i < s->n_err; i++) {
        fprintf(f, "%s{\"name\":\"%s\",\"message\":", i ? "," : "", c4g_ctrl_error_name(s->err[i].code));
        json_str(f, s->err[i].text);
        fprintf(f, ",\"tick\":%lu}", s->err[i].tick);
    }
    fprintf(f, "],");
}

static void json_scenario_robot(FILE *f, const sim_t *s)
{
    int i;
    fprintf(f, "\"scenario\":{\"loaded\":%s,\"done\":%s,\"aborted\":%s,\"commands_run\":%d,"
               "\"expect_passed\":%d,\"expect_failed\":%d,\"wait_pc_timeout\":%s},",
            jbool(s->scn != NULL), jbool(s->scn_done), jbool(s->scn_aborted), s->pc, s->expect_passed,
            s->expect_failed, jbool(s->scn_timeout));
    fprintf(f, "\"robot\":[");
    for (i = 0; i < s->n_axes; i++) {
        const sim_ax_t *x = &s->ax[i];
        fprintf(f, "%s{\"arm\":%d,\"axis\":%d,\"mode\":%d,\"drive_on\":%s,\"pos\":%.6f,\"target\":%.6f,"
                   "\"current\":%.4f}", i ? "," : "", x->arm + 1, x->logical + 1, x->mode,
                jbool(x->m.drive_on), x->m.meas_pos, x->pos_ref, x->m.cur);
    }
    fprintf(f, "],");
}

static void summary_json(const app_t *a, int code, const char *result, double cpu_s)
{
    FILE *f = stdout;
    const sim_t *s = &a->sim;
    const cs_counters_t *n = &a->cs.n;
    const figures_t g = figures(a, cpu_s);
    fprintf(f, "{\"tool\":\"c4g-sim\",\"version\":\"%s\",\"result\":\"%s\",\"exit_code\":%d,",
            C4G_VERSION_STRING, result, code);
    fprintf(f, "\"period_ms\":%d,\"axes\":%d,\"ticks\":%lu,\"packets\":{\"sent\":%lu,\"sync\":%lu,"
               "\"init\":%lu,\"cyclic\":%lu},", s->cfg.period_ms, s->n_axes, s->tick, a->st.sent,
            n->sync_sent, n->init_sent, n->cyclic_sent);
    json_replies(f, a, &g);
    json_faults_errors(f, a);
    json_scenario_robot(f, s);
    fprintf(f, "\"cpu\":{\"seconds\":%.6f,\"ns_per_packet\":%.0f}}\n", cpu_s, g.per_packet_ns);
}

static void text_errors_robot(const sim_t *s)
{
    int i;
    for (i = 0; i < s->n_err; i++) {
        printf("  error at tick %lu: %s: %s\n", s->err[i].tick, c4g_ctrl_error_name(s->err[i].code),
               s->err[i].text);
    }
    if (s->scn != NULL) {
        printf("  scenario: %s, %d commands, expectations %d passed %d failed\n",
               s->scn_aborted ? "aborted" : (s->scn_done ? "done" : "running"), s->pc, s->expect_passed,
               s->expect_failed);
    }
    for (i = 0; i < s->n_axes; i++) {
        const sim_ax_t *x = &s->ax[i];
        printf("  arm %d axis %d: mode %d, pos %.6f turns, target %.6f, current %.3f A\n", x->arm + 1,
               x->logical + 1, x->mode, x->m.meas_pos, x->pos_ref, x->m.cur);
    }
}

static void summary_text(const app_t *a, int code, const char *result, double cpu_s)
{
    const sim_t *s = &a->sim;
    const cs_counters_t *n = &a->cs.n;
    const figures_t g = figures(a, cpu_s);
    int i;
    printf("c4g-sim %s: %s (exit %d)\n", C4G_VERSION_STRING, result, code);
    printf("  ticks %lu, period %d ms, %d open axes\n", s->tick, s->cfg.period_ms, s->n_axes);
    printf("  sent %lu (sync %lu, init %lu, cyclic %lu)\n", a->st.sent, n->sync_sent, n->init_sent,
           n->cyclic_sent);
    printf("  replies ok %lu, missing %lu, late %lu, unjudged %lu, wrong NUM %lu, malformed %lu, "
           "foreign %lu, duplicates %lu, stale %lu\n", n->replies_ok, n->missing, n->late,
           n->unjudged, n->wrong_num, n->malformed, n->foreign, n->duplicates, n->stale);
    printf("  own overruns %lu (worst %.1f us after the tick), %s timestamps\n", a->st.overruns,
           (double)a->st.overrun_max / 1000.0, a->kstamp ? "kernel" : "user-space");
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
