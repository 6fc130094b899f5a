/* SPDX-License-Identifier: MIT */
/* What summary and check print: text for people, JSON (jansson) for machines, and one line
 * per finding for CI logs. */
#include "replay.h"

#include <jansson.h>
#include <string.h>

static double sec(int64_t ns) { return (double)ns * 1e-9; }

static const char *ep(const c4gh_an_endpoint_t *e, char buf[32])
{
    char ip[16];
    (void)snprintf(buf, 32, "%s:%u", c4gh_cap_ip_str(e->ip, ip), (unsigned)e->port);
    return buf;
}

static const char *policy_name(const c4gh_an_session_t *s)
{
    if (s->policy == C4G_NUM_PLUS_ONE || s->policy == C4G_NUM_ECHO) {
        return c4g_num_policy_name(s->policy);
    }
    if (s->policy_plus > 0U && s->policy_echo > 0U) {
        return "mixed";
    }
    if (s->policy_plus > 0U) {
        return "plus-one";
    }
    if (s->policy_echo > 0U) {
        return "echo";
    }
    return "unknown";
}

static const char *mode_str(int32_t m, char buf[24])
{
    if (m < 0) {
        return "-";
    }
    (void)snprintf(buf, 24, "%d", (int)m);
    return buf;
}

unsigned rp_count_findings(const c4gh_an_t *a, const rp_file_t *files, unsigned n_files, uint32_t allow)
{
    unsigned i, n = 0U;
    for (i = 0U; i < a->n_sess; i++) {
        n += c4gh_an_findings(&a->sess[i], allow);
    }
    if ((allow & (1U << AN_K_CAPTURE)) == 0U) {
        for (i = 0U; i < n_files; i++) {
            if (files[i].opened && (files[i].n.bad > 0U || !files[i].complete)) {
                n++;
            }
            if (files[i].opened && files[i].doubled > 0U) {
                n++;
            }
        }
    }
    return n;
}

unsigned rp_file_sessions(const c4gh_an_t *a, const char *path)
{
    unsigned i, n = 0U;
    for (i = 0U; i < a->n_sess; i++) {
        n += (a->sess[i].file == path) ? 1U : 0U;
    }
    return n;
}

const char *rp_no_session_text(const c4gh_an_t *a, const rp_file_t *f, char *buf, size_t cap)
{
    size_t used;
    unsigned i;
    used = (size_t)snprintf(buf, cap, "no C4G Open session found in %llu frames (%llu UDP, %llu not "
                            "IPv4/UDP; looked for: PC ports", (unsigned long long)f->n.frames,
                            (unsigned long long)f->n.udp, (unsigned long long)f->n.ignored);
    for (i = 0U; i < a->opt.n_ports && used < cap; i++) {
        used += (size_t)snprintf(buf + used, cap - used, " %u", (unsigned)a->opt.ports[i]);
    }
    if (used < cap) {
        (void)snprintf(buf + used, cap - used, ", a 1200-byte initialization packet, or %u datagrams "
                       "of the C4G Open shape in a row; IPv4 only)", 8U);
    }
    return buf;
}

/* ---- text ------------------------------------------------------------------ */

static const char *doubled_text(const rp_file_t *f, char *buf, size_t cap)
{
    (void)snprintf(buf, cap, "%llu frames captured twice (an identical datagram at the same time "
                   "right after itself, e.g. a file merged with itself): each analysed once",
                   (unsigned long long)f->doubled);
    return buf;
}

static void text_init(FILE *out, const c4gh_an_session_t *s)
{
    const c4g_init_t *in = &s->init;
    uint32_t arm, i;
    if (!s->have_init) {
        fprintf(out, "  init: none in the capture: %u axes from the packet length, all taken as arm "
                "%s; thresholds unknown, data checks off\n", (unsigned)s->n_axes,
                s->n_axes > 10U ? "1, 2, ..." : "1");
        return;
    }
    fprintf(out, "  init: %u open axes (", (unsigned)s->n_axes);
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        if (s->map.n_axes_arm[arm] > 0U) {
            fprintf(out, "%sarm %u: %u", arm > 0U ? ", " : "", (unsigned)arm + 1U,
                    (unsigned)s->map.n_axes_arm[arm]);
        }
    }
    fprintf(out, "), period %d ms, version %d.%d.%d\n", (int)in->period_ms, (int)in->version_major,
            (int)in->version_minor, (int)in->version_build);
    for (i = 0U; i < s->n_axes; i++) {
        const uint32_t a = s->map.arm_of[i], l = s->map.logical_of[i];
        fprintf(out, "    axis %2u = arm %u axis %2u: start mode %d, AzLim %g A, FollowError %g turns, "
                "TxRate %g, CalData %g\n", (unsigned)i + 1U, (unsigned)a + 1U, (unsigned)l + 1U,
                (int)in->open_mask[a][l], (double)in->az_lim[a][l], (double)in->follow_error[a][l],
                (double)in->tx_rate[a][l], (double)in->cal_data[a][l]);
    }
}

static void text_modes(FILE *out, const c4gh_an_session_t *s)
{
    uint32_t arm, k;
    char b1[24], b2[24];
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        if (s->n_tl[arm] == 0U) {
            continue;
        }
        fprintf(out, "  arm %u modes:", (unsigned)arm + 1U);
        for (k = 0U; k < s->n_tl[arm]; k++) {
            const c4gh_an_transition_t *t = &s->tl[arm][k];
            fprintf(out, "%s%s -> %s at %.3f s (NUM %d)%s", k == 0U ? " " : "; ", mode_str(t->from, b1),
                    mode_str(t->to, b2), sec(t->t_ns), (int)t->num, t->mixed ? " mixed" : "");
        }
        if (s->tl_more[arm] > 0U) {
            fprintf(out, "; ... %llu more", (unsigned long long)s->tl_more[arm]);
        }
        fputc('\n', out);
    }
    for (k = 0U; k < s->n_ev; k++) {
        const c4gh_an_event_t *e = &s->ev[k];
        fprintf(out, "  event: %.3f s NUM %d arm %u: %s\n", sec(e->t_ns), (int)e->num,
                (unsigned)e->arm + 1U, e->what);
    }
    if (s->ev_more > 0U) {
        fprintf(out, "  events: %llu more\n", (unsigned long long)s->ev_more);
    }
    for (k = 0U; k < 9U; k++) {
        if (s->special_seen[k] > 0U) {
            fprintf(out, "  special mode %u (%s): %llu packets\n", 500U + k,
                    c4g_mode_name((int32_t)(500U + k)), (unsigned long long)s->special_seen[k]);
        }
    }
}

static void text_session(FILE *out, const c4gh_an_session_t *s, uint32_t allow)
{
    char b1[32], b2[32];
    const c4g_ctrl_counters_t *n = &s->cs.n;
    unsigned k, nf;
    fprintf(out, "session %u: %s, controller %s -> PC %s, %.3f s, frames %llu..%llu, ended by %s\n", s->id,
            s->file, ep(&s->ctrl, b1), ep(&s->pc, b2), sec(s->last_ns - s->first_ns),
            (unsigned long long)s->first_frame, (unsigned long long)s->last_frame, s->end);
    text_init(out, s);
    fprintf(out, "  packets: controller %llu sync, %llu init, %llu cyclic, %llu other; PC %llu sync "
            "replies, %llu init echoes, %llu cyclic replies, %llu other\n",
            (unsigned long long)s->ctrl_sync, (unsigned long long)s->ctrl_init,
            (unsigned long long)s->ctrl_cyclic, (unsigned long long)s->ctrl_other,
            (unsigned long long)s->pc_sync, (unsigned long long)s->pc_init,
            (unsigned long long)s->pc_cyclic, (unsigned long long)s->pc_other);
    fprintf(out, "  NUM policy: %s%s\n", policy_name(s),
            s->policy_from_cyclic ? " (from the cyclic replies: no init echo in time)" : "");
    fprintf(out, "  replies: %lu in time, latency p50 %.0f us, p99 %.0f us, p99.9 %.0f us, max %.0f us; "
            "%lu late (> %.0f us)\n", n->replies_ok, c4gh_an_latency_us(s, 0.5), c4gh_an_latency_us(s, 0.99),
            c4gh_an_latency_us(s, 0.999), (double)n->lat_max * 1e-3, n->late,
            (double)s->cs.cfg.t_cycle1_ns * 1e-3);
    fprintf(out, "  missing: %lu (longest run %llu", n->missing, (unsigned long long)s->run_longest);
    if (s->run_longest > 0U) {
        fprintf(out, " from NUM %d at %.3f s", (int)s->longest_start_num, sec(s->longest_start_ns));
    }
    fprintf(out, "); NUM mismatches %lu; duplicate replies %lu; stale replies %lu\n", n->wrong_num,
            n->duplicates, n->stale);
    fprintf(out, "  controller NUM: %llu gaps (%llu packets skipped), %llu repeated, %llu out of order",
            (unsigned long long)s->ctrl_gaps, (unsigned long long)s->ctrl_skipped,
            (unsigned long long)s->ctrl_dups, (unsigned long long)s->ctrl_older);
    if (s->pc_unseen > 0U) {
        fprintf(out, "; %llu replies to packets the capture lost (the PC answered them)",
                (unsigned long long)s->pc_unseen);
    }
    fputc('\n', out);
    text_modes(out, s);
    nf = c4gh_an_findings(s, allow);
    fprintf(out, "  findings: %s\n", nf == 0U ? "none" : "");
    for (k = 0U; k < (unsigned)AN_K_COUNT; k++) {
        const c4gh_an_finding_t *f = &s->f[k];
        if (f->count == 0U) {
            continue;
        }
        fprintf(out, "    %-13s %6llu%s  first at %.3f s (frame %llu): %s\n", c4gh_an_kind_name((c4gh_an_kind_t)k),
                (unsigned long long)f->count, (allow & (1U << k)) != 0U ? " (allowed)" : "",
                sec(f->t_ns), (unsigned long long)f->frame, f->first);
    }
}

void rp_report_text(FILE *out, const c4gh_an_t *a, const rp_file_t *files, unsigned n_files, uint32_t allow)
{
    unsigned i, nf;
    char buf[160];
    for (i = 0U; i < n_files; i++) {
        const rp_file_t *f = &files[i];
        if (!f->opened) {
            fprintf(out, "unreadable: %s\n", f->fatal);
            continue;
        }
        fprintf(out, "%s: %s (%s, %s), %llu frames, %llu UDP, %llu other, %llu damaged%s%s\n", f->path,
                f->format, f->link, f->nano ? "ns" : "us", (unsigned long long)f->n.frames,
                (unsigned long long)f->n.udp, (unsigned long long)f->n.ignored,
                (unsigned long long)f->n.bad, f->complete ? "" : "; stopped early: ",
                f->complete ? "" : f->fatal);
        if (f->doubled > 0U) {
            fprintf(out, "%s: capture: %s\n", f->path, doubled_text(f, buf, sizeof buf));
        }
    }
    for (i = 0U; i < a->n_sess; i++) {
        text_session(out, &a->sess[i], allow);
    }
    if (a->sess_dropped > 0U || a->flows_dropped > 0U) {
        fprintf(out, "not analysed: %llu sessions and %llu datagrams of flows beyond the limits (%u sessions, "
                "%u flows per file)\n", (unsigned long long)a->sess_dropped,
                (unsigned long long)a->flows_dropped, C4GH_AN_MAX_SESSIONS, C4GH_AN_MAX_FLOWS);
    }
    nf = rp_count_findings(a, files, n_files, allow);
    if (a->n_sess == 0U) {
        fprintf(out, "verdict: no C4G Open session found (ports");
        for (i = 0U; i < a->opt.n_ports; i++) {
            fprintf(out, " %u", (unsigned)a->opt.ports[i]);
        }
        fprintf(out, ", or a 1200-byte initialization packet)%s\n", nf > 0U ? "; damaged capture" : "");
    } else {
        unsigned empty = 0U;
        for (i = 0U; i < n_files; i++) {
            empty += (files[i].opened && rp_file_sessions(a, files[i].path) == 0U) ? 1U : 0U;
        }
        if (nf == 0U) {
            fprintf(out, "verdict: clean: %u session%s, no findings", a->n_sess, a->n_sess == 1U ? "" : "s");
        } else {
            fprintf(out, "verdict: %u finding%s in %u session%s", nf, nf == 1U ? "" : "s", a->n_sess,
                    a->n_sess == 1U ? "" : "s");
        }
        if (empty > 0U) {
            fprintf(out, "; no C4G Open session in %u of the files (not checked)", empty);
        }
        fputc('\n', out);
    }
}

/* ---- findings, one line each --------------------------------------------------- */

unsigned rp_report_findings(FILE *out, const c4gh_an_t *a, const rp_file_t *files, unsigned n_files,
                            uint32_t allow)
{
    unsigned i, k, n = 0U;
    for (i = 0U; i < n_files; i++) {
        const rp_file_t *f = &files[i];
        if ((allow & (1U << AN_K_CAPTURE)) != 0U || !f->opened) {
            continue;
        }
        if (f->n.bad > 0U) {
            fprintf(out, "%s: capture: %llu damaged frames; first: %s\n", f->path,
                    (unsigned long long)f->n.bad, f->first_bad);
            n++;
        } else if (!f->complete) {
            fprintf(out, "%s: capture: %s\n", f->path, f->fatal);
            n++;
        }
        if (f->doubled > 0U) {
            char buf[160];
            fprintf(out, "%s: capture: %s\n", f->path, doubled_text(f, buf, sizeof buf));
            n++;
        }
    }
    for (i = 0U; i < a->n_sess; i++) {
        const c4gh_an_session_t *s = &a->sess[i];
        for (k = 0U; k < (unsigned)AN_K_COUNT; k++) {
            const c4gh_an_finding_t *f = &s->f[k];
            if (f->count == 0U || (allow & (1U << k)) != 0U) {
                continue;
            }
            fprintf(out, "%s: session %u: %s: %llu, first at %.3f s (frame %llu, NUM %d): %s\n", s->file,
                    s->id, c4gh_an_kind_name((c4gh_an_kind_t)k), (unsigned long long)f->count, sec(f->t_ns),
                    (unsigned long long)f->frame, (int)f->num, f->first);
            n++;
        }
    }
    return n;
}

/* ---- JSON ---------------------------------------------------------------------- */

static json_t *j_endpoint(const c4gh_an_endpoint_t *e)
{
    char ip[16];
    return json_pack("{s:s, s:i}", "ip", c4gh_cap_ip_str(e->ip, ip), "port", (json_int_t)e->port);
}

static json_t *j_init(const c4gh_an_session_t *s)
{
    const c4g_init_t *in = &s->init;
    json_t *o, *axes, *arms;
    uint32_t i, arm;
    if (!s->have_init) {
        return json_null();
    }
    axes = json_array();
    arms = json_array();
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        (void)json_array_append_new(arms, json_integer((json_int_t)s->map.n_axes_arm[arm]));
    }
    for (i = 0U; i < s->n_axes; i++) {
        const uint32_t a = s->map.arm_of[i], l = s->map.logical_of[i];
        (void)json_array_append_new(
            axes, json_pack("{s:i, s:i, s:i, s:i, s:f, s:f, s:f, s:f, s:f}", "open", (json_int_t)i + 1,
                            "arm", (json_int_t)a + 1, "axis", (json_int_t)l + 1, "start_mode",
                            (json_int_t)in->open_mask[a][l], "az_lim", (double)in->az_lim[a][l],
                            "follow_error", (double)in->follow_error[a][l], "tx_rate",
                            (double)in->tx_rate[a][l], "cal_data", (double)in->cal_data[a][l],
                            "ax_info", (double)in->ax_info[a][l]));
    }
    o = json_pack("{s:i, s:i, s:o, s:[i,i,i], s:o}", "open_axes", (json_int_t)s->n_axes, "period_ms",
                  (json_int_t)in->period_ms, "axes_per_arm", arms, "version",
                  (json_int_t)in->version_major, (json_int_t)in->version_minor,
                  (json_int_t)in->version_build, "axes", axes);
    return o;
}

static json_t *j_modes(const c4gh_an_session_t *s)
{
    json_t *arr = json_array();
    uint32_t arm, k;
    for (arm = 0U; arm < C4G_ARMS; arm++) {
        json_t *tl;
        if (s->n_tl[arm] == 0U) {
            continue;
        }
        tl = json_array();
        for (k = 0U; k < s->n_tl[arm]; k++) {
            const c4gh_an_transition_t *t = &s->tl[arm][k];
            (void)json_array_append_new(
                tl, json_pack("{s:f, s:i, s:I, s:i, s:i, s:s, s:b}", "t", sec(t->t_ns), "num",
                              (json_int_t)t->num, "frame", (json_int_t)t->frame, "from", (json_int_t)t->from,
                              "to", (json_int_t)t->to, "name", c4g_mode_name(t->to), "mixed",
                              (int)t->mixed));
        }
        (void)json_array_append_new(arr, json_pack("{s:i, s:o, s:I}", "arm", (json_int_t)arm + 1,
                                                   "transitions", tl, "more",
                                                   (json_int_t)s->tl_more[arm]));
    }
    return arr;
}

static json_t *j_events(const c4gh_an_session_t *s)
{
    json_t *arr = json_array();
    uint32_t k;
    for (k = 0U; k < s->n_ev; k++) {
        const c4gh_an_event_t *e = &s->ev[k];
        (void)json_array_append_new(arr, json_pack("{s:f, s:i, s:I, s:i, s:s}", "t", sec(e->t_ns),
                                                   "num", (json_int_t)e->num, "frame",
                                                   (json_int_t)e->frame, "arm", (json_int_t)e->arm + 1,
                                                   "what", e->what));
    }
    return arr;
}

static json_t *j_findings(const c4gh_an_session_t *s, uint32_t allow)
{
    json_t *arr = json_array();
    unsigned k;
    for (k = 0U; k < (unsigned)AN_K_COUNT; k++) {
        const c4gh_an_finding_t *f = &s->f[k];
        if (f->count == 0U) {
            continue;
        }
        (void)json_array_append_new(
            arr, json_pack("{s:s, s:I, s:b, s:f, s:I, s:i, s:f, s:s}", "kind", c4gh_an_kind_name((c4gh_an_kind_t)k),
                           "count", (json_int_t)f->count, "allowed", (allow & (1U << k)) != 0U, "t",
                           sec(f->t_ns), "frame", (json_int_t)f->frame, "num", (json_int_t)f->num,
                           "worst", f->worst, "first", f->first));
    }
    return arr;
}

static json_t *j_session(const c4gh_an_session_t *s, uint32_t allow)
{
    const c4g_ctrl_counters_t *n = &s->cs.n;
    json_t *special = json_object();
    json_t *o;
    unsigned k;
    for (k = 0U; k < 9U; k++) {
        if (s->special_seen[k] > 0U) {
            char key[8];
            (void)snprintf(key, sizeof key, "%u", 500U + k);
            (void)json_object_set_new(special, key, json_integer((json_int_t)s->special_seen[k]));
        }
    }
    o = json_pack("{s:i, s:s, s:o, s:o, s:f, s:I, s:I, s:s, s:o, s:b}", "id", (json_int_t)s->id, "file",
                  s->file, "controller", j_endpoint(&s->ctrl), "pc", j_endpoint(&s->pc), "duration_s",
                  sec(s->last_ns - s->first_ns), "first_frame", (json_int_t)s->first_frame,
                  "last_frame", (json_int_t)s->last_frame, "end", s->end, "init", j_init(s),
                  "axes_assumed", s->synthetic_map != 0);
    (void)json_object_set_new(o, "packets", json_pack("{s:{s:I,s:I,s:I,s:I}, s:{s:I,s:I,s:I,s:I}}",
        "controller", "sync", (json_int_t)s->ctrl_sync, "init", (json_int_t)s->ctrl_init, "cyclic",
        (json_int_t)s->ctrl_cyclic, "other", (json_int_t)s->ctrl_other, "pc", "sync",
        (json_int_t)s->pc_sync, "init", (json_int_t)s->pc_init, "cyclic", (json_int_t)s->pc_cyclic,
        "other", (json_int_t)s->pc_other));
    (void)json_object_set_new(o, "num_policy", json_string(policy_name(s)));
    (void)json_object_set_new(o, "replies", json_pack(
        "{s:I, s:I, s:I, s:I, s:i, s:I, s:I, s:I, s:{s:f, s:f, s:f, s:f}}", "in_time",
        (json_int_t)n->replies_ok, "late", (json_int_t)n->late, "missing", (json_int_t)n->missing,
        "longest_missing_run", (json_int_t)s->run_longest, "longest_run_from_num",
        (json_int_t)(s->run_longest > 0U ? s->longest_start_num : -1), "num_mismatch",
        (json_int_t)n->wrong_num, "duplicates", (json_int_t)n->duplicates, "stale",
        (json_int_t)n->stale, "latency_us", "p50", c4gh_an_latency_us(s, 0.5), "p99",
        c4gh_an_latency_us(s, 0.99), "p99_9", c4gh_an_latency_us(s, 0.999), "max", (double)n->lat_max * 1e-3));
    (void)json_object_set_new(o, "controller_num", json_pack("{s:I, s:I, s:I, s:I}", "gaps",
        (json_int_t)s->ctrl_gaps, "skipped", (json_int_t)s->ctrl_skipped, "repeated",
        (json_int_t)s->ctrl_dups, "out_of_order", (json_int_t)s->ctrl_older));
    if (s->pc_unseen > 0U) {
        (void)json_object_set_new(json_object_get(o, "controller_num"), "replies_to_lost",
                                  json_integer((json_int_t)s->pc_unseen));
    }
    (void)json_object_set_new(o, "modes", j_modes(s));
    (void)json_object_set_new(o, "events", j_events(s));
    (void)json_object_set_new(o, "special_modes", special);
    (void)json_object_set_new(o, "findings", j_findings(s, allow));
    (void)json_object_set_new(o, "verdict", json_string(c4gh_an_findings(s, allow) == 0U ? "clean" : "findings"));
    return o;
}

int rp_report_json(FILE *out, const c4gh_an_t *a, const rp_file_t *files, unsigned n_files, uint32_t allow)
{
    json_t *root = json_object(), *jf = json_array(), *js = json_array();
    unsigned i, nf;
    int rc;
    for (i = 0U; i < n_files; i++) {
        const rp_file_t *f = &files[i];
        json_t *o = json_pack("{s:s, s:b}", "file", f->path, "readable", f->opened);
        if (f->opened) {
            (void)json_object_set_new(o, "format", json_string(f->format));
            (void)json_object_set_new(o, "link", json_string(f->link));
            (void)json_object_set_new(o, "nanosecond", json_boolean(f->nano));
            (void)json_object_set_new(o, "frames", json_integer((json_int_t)f->n.frames));
            (void)json_object_set_new(o, "udp", json_integer((json_int_t)f->n.udp));
            (void)json_object_set_new(o, "other", json_integer((json_int_t)f->n.ignored));
            (void)json_object_set_new(o, "damaged", json_integer((json_int_t)f->n.bad));
            (void)json_object_set_new(o, "complete", json_boolean(f->complete));
            if (f->doubled > 0U) {
                (void)json_object_set_new(o, "doubled", json_integer((json_int_t)f->doubled));
            }
        }
        if (f->first_bad[0] != '\0') {
            (void)json_object_set_new(o, "first_damage", json_string(f->first_bad));
        }
        if (f->fatal[0] != '\0') {
            (void)json_object_set_new(o, "error", json_string(f->fatal));
        }
        (void)json_array_append_new(jf, o);
    }
    for (i = 0U; i < a->n_sess; i++) {
        (void)json_array_append_new(js, j_session(&a->sess[i], allow));
    }
    nf = rp_count_findings(a, files, n_files, allow);
    (void)json_object_set_new(root, "tool", json_string(RP_TOOL " " C4G_VERSION_STRING));
    (void)json_object_set_new(root, "files", jf);
    (void)json_object_set_new(root, "sessions", js);
    (void)json_object_set_new(root, "sessions_not_analysed", json_integer((json_int_t)a->sess_dropped));
    (void)json_object_set_new(root, "findings", json_integer((json_int_t)nf));
    (void)json_object_set_new(root, "verdict", json_string(a->n_sess == 0U ? "no-session"
                                                           : (nf == 0U ? "clean" : "findings")));
    rc = json_dumpf(root, out, JSON_INDENT(2) | JSON_REAL_PRECISION(9));
    fputc('\n', out);
    json_decref(root);
    return rc;
}
