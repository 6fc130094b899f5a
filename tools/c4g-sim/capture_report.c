/* SPDX-License-Identifier: MIT */
/* c4g-sim --capture: what the played capture found, as text or one JSON object (jansson).
 * c4g-replay live prints this report (c4g-sim runs for it with --replay-live). */
#include "capture.h"

#include <jansson.h>
#include <string.h>

#define CAP_FIELD_NAME(id, name) name,
static const char *const field_names[CAP_F_COUNT] = {CAP_FIELDS(CAP_FIELD_NAME)};
#undef CAP_FIELD_NAME

const char *cap_field_name(cap_field_t f) { return (f < CAP_F_COUNT) ? field_names[f] : "?"; }


/* Stale replies are not added: each one belongs to a packet already counted missing or
 * unjudged. */
static uint64_t sum_findings(const cap_t *C)
{
    const c4g_ctrl_counters_t *n = &C->n;
    return n->late + n->missing + n->unjudged + n->wrong_num + n->malformed + n->duplicates +
           C->send_errors + C->differing;
}

static void list_findings(FILE *out, const cap_t *C)
{
    const c4g_ctrl_counters_t *n = &C->n;
    const struct { uint64_t v; const char *what; } f[] = {
        {n->late, "late"}, {n->missing, "missing"}, {n->unjudged, "unjudged"},
        {n->wrong_num, "wrong NUM"}, {n->malformed, "malformed"}, {n->duplicates, "duplicates"},
        {C->send_errors, "not sent"}, {C->differing, "divergent replies"}};
    size_t i;
    const char *sep = ": ";
    for (i = 0U; i < sizeof f / sizeof f[0]; i++) {
        if (f[i].v > 0U) {
            fprintf(out, "%s%llu %s", sep, (unsigned long long)f[i].v, f[i].what);
            sep = ", ";
        }
    }
    if (C->interrupted) {
        fprintf(out, "%sinterrupted", sep);
        sep = ", ";
    }
    if (C->read_failed) {
        fprintf(out, "%sthe file could not be read again", sep);
    }
}

int cap_findings(const cap_t *C)
{
    return sum_findings(C) > 0U || C->interrupted || C->read_failed || C->passes_done < C->o.loops;
}

static const char *kind_name(c4g_pkt_kind_t k)
{
    return (k == C4G_PKT_SYNC) ? "sync" : (k == C4G_PKT_INIT ? "init" : "cyclic");
}

static const cap_scan_t *chosen(const cap_t *C) { return &C->scan[C->chosen - 1U]; }

/* Nothing ever answered: every figure would be zero, one line says so instead. */
static void report_none(FILE *out, const cap_t *C)
{
    fprintf(out, "%s: session %u of %s to %s: no session started: nothing answered there "
            "(stopped after %llu packets of pass %u, %.3f s)\n", C->cmd, C->chosen, C->o.path,
            C->to_text, (unsigned long long)C->sent, C->dead_pass, (double)C->elapsed_ns * 1e-9);
    fprintf(out, "result: NO ANSWER\n");
}

void cap_report_text(FILE *out, const cap_t *C)
{
    const c4g_ctrl_counters_t *n = &C->n;
    const cap_scan_t *sc = chosen(C);
    unsigned f, shown = 0U;
    if (C->dead && n->rx_total == n->foreign) {
        report_none(out, C);
        return;
    }
    fprintf(out, "%s: session %u of %s to %s: %u of %u pass%s, ", C->cmd, C->chosen, C->o.path, C->to_text,
            C->passes_done, C->o.loops, C->o.loops == 1U ? "" : "es");
    if (C->o.topspeed) {
        fprintf(out, "top speed");
    } else {
        fprintf(out, "speed %g", C->o.speed);
    }
    fprintf(out, ", recorded %.3f s, played in %.3f s%s\n", (double)(sc->last_ns - sc->first_ns) * 1e-9,
            (double)C->elapsed_ns * 1e-9, C->interrupted ? " (interrupted)" : "");
    fprintf(out, "sent: %llu packets (%llu sync, %llu init, %llu cyclic)", (unsigned long long)C->sent,
            (unsigned long long)C->sent_kind[C4G_PKT_SYNC], (unsigned long long)C->sent_kind[C4G_PKT_INIT],
            (unsigned long long)C->sent_kind[C4G_PKT_CYCLIC]);
    if (C->send_errors > 0U) {
        fprintf(out, "; %llu not sent (first: %s)", (unsigned long long)C->send_errors, C->send_error);
    }
    fprintf(out, "\nreplies (NUM policy %s", c4g_num_policy_name(C->policy));
    if (C->policy == C4G_NUM_EITHER) {
        fprintf(out, ", server %s", c4g_num_policy_name(C->app->cs.detected));
    }
    fprintf(out, "; t-cycle1 %.0f us): %lu ok, %lu late, "
            "%lu missing, %lu unjudged, %lu wrong NUM, %lu malformed, %lu duplicates, %lu stale\n",
            (double)C->an.t_cycle1_ns * 1e-3,
            n->replies_ok, n->late, n->missing, n->unjudged, n->wrong_num, n->malformed,
            n->duplicates, n->stale);
    fprintf(out, "longest run without a reply: %lu%s\n", n->max_consecutive,
            n->max_consecutive >= 10U ? ": the controller would raise ERR_C4GOPEN_UDP (10 in a row) "
                                        "and stop communicating"
                                      : " (the controller raises ERR_C4GOPEN_UDP at 10 in a row)");
    if (n->unexpected + n->foreign > 0U) {
        fprintf(out, "other datagrams: %lu with no packet awaiting a checked reply (e.g. to 504), "
                "%lu from other addresses\n", n->unexpected, n->foreign);
    }
    if (n->replies_ok > 0U) {
        fprintf(out, "latency: p50 %.0f us, p99 %.0f us, max %.1f us\n", c4gh_hist_us(&C->app->lat, 0.5),
                c4gh_hist_us(&C->app->lat, 0.99), (double)n->lat_max * 1e-3);
    } else {
        fprintf(out, "latency: no reply judged ok\n");
    }
    fprintf(out, "divergences: %llu of %llu replies compared differ from the recorded ones (floats %s)\n",
            (unsigned long long)C->differing, (unsigned long long)C->compared,
            C->o.tolerance > 0.0 ? "within the tolerance" : "exact, by bits");
    if (C->timing_only > 0U) {
        fprintf(out, "  timing: %llu recorded replies came after the controller's next packet, these in time "
                "with the same content (not divergences)\n", (unsigned long long)C->timing_only);
    }
    if (C->differing > 0U) {
        fprintf(out, "  per field:");
        for (f = 0U; f < CAP_F_COUNT; f++) {
            if (C->field[f] > 0U) {
                fprintf(out, "%s %s %llu", shown++ ? "," : "", cap_field_name((cap_field_t)f),
                        (unsigned long long)C->field[f]);
            }
        }
        fputc('\n', out);
    }
    if (C->first.set) {
        const cap_first_t *F = &C->first;
        fprintf(out, "  first: pass %u, %s packet NUM %d (tick %llu)", F->pass, kind_name(F->kind),
                (int)F->num, (unsigned long long)F->tick);
        if (F->axis > 0U) {
            fprintf(out, ", axis %u in mode %d", F->axis, (int)F->mode);
        }
        fprintf(out, ": %s recorded %s, received %s\n", cap_field_name(F->field), F->recorded,
                F->received);
    }
    if (C->o.topspeed) {
        fprintf(out, "timing: top speed (no schedule)\n");
    } else {
        fprintf(out, "timing: send time - schedule p50 %.0f us, p99 %.0f us, max %.1f us; drift %.1f us "
                "(the last packet); %llu sent over %.0f us late; %s send times\n",
                c4gh_hist_us(&C->err, 0.5), c4gh_hist_us(&C->err, 0.99), (double)C->err.max_ns * 1e-3,
                (double)C->drift_ns * 1e-3, (unsigned long long)C->overruns, (double)C->tol_ns * 1e-3,
                C->app->kstamp ? "kernel" : "user-space");
    }
    if (C->dead) {
        fprintf(out, "result: NO ANSWER in pass %u (stopped after %u packets without a datagram "
                "back)\n", C->dead_pass, CAP_DEAD_PACKETS);
    } else if (!cap_findings(C)) {
        fprintf(out, "result: OK, every reply in time and equal to the recorded one\n");
    } else {
        fprintf(out, "result: FINDINGS");
        list_findings(out, C);
        fputc('\n', out);
    }
}

void cap_report_json(FILE *out, const cap_t *C)
{
    const c4g_ctrl_counters_t *n = &C->n;
    const cap_scan_t *sc = chosen(C);
    json_t *o, *fields, *first = json_null(), *timing = json_null();
    unsigned f;
    fields = json_object();
    for (f = 0U; f < CAP_F_COUNT; f++) {
        (void)json_object_set_new(fields, cap_field_name((cap_field_t)f), json_integer((json_int_t)C->field[f]));
    }
    if (C->first.set) {
        const cap_first_t *F = &C->first;
        json_decref(first);
        first = json_pack("{s:i, s:s, s:I, s:i, s:i, s:i, s:s, s:s, s:s}", "pass", (int)F->pass, "kind",
                          kind_name(F->kind), "tick", (json_int_t)F->tick, "num", (int)F->num, "axis",
                          (int)F->axis, "mode", (int)F->mode, "field", cap_field_name(F->field), "recorded",
                          F->recorded, "received", F->received);
    }
    if (!C->o.topspeed) {
        json_decref(timing);
        timing = json_pack("{s:{s:f, s:f, s:f, s:f}, s:f, s:I, s:f, s:I}", "send_error_us", "p50",
                           c4gh_hist_us(&C->err, 0.5), "p99", c4gh_hist_us(&C->err, 0.99), "max",
                           (double)C->err.max_ns * 1e-3, "min", (double)C->err.min_ns * 1e-3, "drift_us",
                           (double)C->drift_ns * 1e-3, "overruns", (json_int_t)C->overruns,
                           "overrun_margin_us", (double)C->tol_ns * 1e-3, "spin_us", (json_int_t)C->o.spin_us);
    }
    /* key names as in c4g-sim's summary where they mean the same */
    o = json_pack("{s:s, s:s, s:s, s:i, s:s, s:i, s:i, s:f, s:b, s:b, s:f, s:f}", "tool", C->tool,
                  "command", C->cmd, "file", C->o.path, "session", (int)C->chosen, "to", C->to_text,
                  "passes", (int)C->o.loops, "passes_done", (int)C->passes_done, "speed",
                  C->o.topspeed ? 0.0 : C->o.speed, "topspeed", C->o.topspeed, "interrupted", C->interrupted,
                  "recorded_s", (double)(sc->last_ns - sc->first_ns) * 1e-9, "elapsed_s",
                  (double)C->elapsed_ns * 1e-9);
    (void)json_object_set_new(o, "packets", json_pack("{s:I, s:I, s:I, s:I, s:I}", "sent", (json_int_t)C->sent,
                                                      "sync", (json_int_t)C->sent_kind[C4G_PKT_SYNC], "init",
                                                      (json_int_t)C->sent_kind[C4G_PKT_INIT], "cyclic",
                                                      (json_int_t)C->sent_kind[C4G_PKT_CYCLIC], "send_errors",
                                                      (json_int_t)C->send_errors));
    (void)json_object_set_new(
        o, "replies",
        json_pack("{s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:b, s:{s:f, s:f, s:f}}", "ok",
                  (json_int_t)n->replies_ok, "missing", (json_int_t)n->missing, "late", (json_int_t)n->late,
                  "unjudged", (json_int_t)n->unjudged, "wrong_num", (json_int_t)n->wrong_num, "malformed",
                  (json_int_t)n->malformed, "foreign", (json_int_t)n->foreign, "duplicates",
                  (json_int_t)n->duplicates, "stale", (json_int_t)n->stale, "unexpected",
                  (json_int_t)n->unexpected, "max_consecutive_missing", (json_int_t)n->max_consecutive,
                  "err_c4gopen_udp", n->max_consecutive >= 10U, "latency_us", "p50",
                  c4gh_hist_us(&C->app->lat, 0.5), "p99", c4gh_hist_us(&C->app->lat, 0.99), "max",
                  (double)n->lat_max * 1e-3));
    (void)json_object_set_new(o, "num_policy", json_string(c4g_num_policy_name(C->policy)));
    (void)json_object_set_new(o, "pc_policy", json_string(c4g_num_policy_name(C->app->cs.detected)));
    (void)json_object_set_new(o, "t_cycle1_us", json_real((double)C->an.t_cycle1_ns * 1e-3));
    (void)json_object_set_new(o, "divergences",
                              json_pack("{s:I, s:I, s:f, s:o, s:o}", "compared", (json_int_t)C->compared,
                                        "differing", (json_int_t)C->differing, "tolerance", C->o.tolerance,
                                        "fields", fields, "first", first));
    (void)json_object_set_new(json_object_get(o, "divergences"), "timing_only",
                              json_integer((json_int_t)C->timing_only));
    (void)json_object_set_new(o, "timing", timing);
    (void)json_object_set_new(o, "timestamps", json_string(C->app->kstamp ? "kernel" : "user"));
    (void)json_object_set_new(o, "result", json_string(C->dead ? "no-answer" : (cap_findings(C) ? "findings" : "ok")));
    (void)json_dumpf(o, out, JSON_COMPACT | JSON_REAL_PRECISION(9));
    fputc('\n', out);
    json_decref(o);
}
