/* SPDX-License-Identifier: MIT */
/* c4g-replay live: what the replay found, as text or one JSON object (jansson). */
#include "live.h"

#include <jansson.h>
#include <string.h>

#define LV_FIELD_NAME(id, name) name,
static const char *const field_names[LV_F_COUNT] = {LV_FIELDS(LV_FIELD_NAME)};
#undef LV_FIELD_NAME

const char *lv_field_name(lv_field_t f) { return (f < LV_F_COUNT) ? field_names[f] : "?"; }


/* Stale replies are not added: each one belongs to a packet already counted missing or
 * unjudged. */
static uint64_t sum_findings(const lv_t *L)
{
    const c4g_ctrl_counters_t *n = &L->n;
    return n->late + n->missing + n->unjudged + n->wrong_num + n->malformed + n->duplicates +
           L->send_errors + L->differing;
}

static void list_findings(FILE *out, const lv_t *L)
{
    const c4g_ctrl_counters_t *n = &L->n;
    const struct { uint64_t v; const char *what; } f[] = {
        {n->late, "late"}, {n->missing, "missing"}, {n->unjudged, "unjudged"},
        {n->wrong_num, "wrong NUM"}, {n->malformed, "malformed"}, {n->duplicates, "duplicates"},
        {L->send_errors, "not sent"}, {L->differing, "divergent replies"}};
    size_t i;
    const char *sep = ": ";
    for (i = 0U; i < sizeof f / sizeof f[0]; i++) {
        if (f[i].v > 0U) {
            fprintf(out, "%s%llu %s", sep, (unsigned long long)f[i].v, f[i].what);
            sep = ", ";
        }
    }
    if (L->interrupted) {
        fprintf(out, "%sinterrupted", sep);
        sep = ", ";
    }
    if (L->read_failed) {
        fprintf(out, "%sthe file could not be read again", sep);
    }
}

int lv_findings(const lv_t *L)
{
    return sum_findings(L) > 0U || L->interrupted || L->read_failed || L->passes_done < L->loops;
}

static const char *kind_name(c4g_pkt_kind_t k)
{
    return (k == C4G_PKT_SYNC) ? "sync" : (k == C4G_PKT_INIT ? "init" : "cyclic");
}

static const lv_scan_t *chosen(const lv_t *L) { return &L->scan[L->chosen - 1U]; }

void lv_report_text(FILE *out, const lv_t *L)
{
    const c4g_ctrl_counters_t *n = &L->n;
    const lv_scan_t *sc = chosen(L);
    unsigned f, shown = 0U;
    fprintf(out, "live: session %u of %s to %s: %u of %u pass%s, ", L->chosen, L->path, L->to_text,
            L->passes_done, L->loops, L->loops == 1U ? "" : "es");
    if (L->topspeed) {
        fprintf(out, "top speed");
    } else {
        fprintf(out, "speed %g", L->speed);
    }
    fprintf(out, ", recorded %.3f s, played in %.3f s%s\n", (double)(sc->last_ns - sc->first_ns) * 1e-9,
            (double)L->elapsed_ns * 1e-9, L->interrupted ? " (interrupted)" : "");
    fprintf(out, "sent: %llu packets (%llu sync, %llu init, %llu cyclic)", (unsigned long long)L->sent,
            (unsigned long long)L->sent_kind[C4G_PKT_SYNC], (unsigned long long)L->sent_kind[C4G_PKT_INIT],
            (unsigned long long)L->sent_kind[C4G_PKT_CYCLIC]);
    if (L->send_errors > 0U) {
        fprintf(out, "; %llu not sent (first: %s)", (unsigned long long)L->send_errors, L->send_error);
    }
    fprintf(out, "\nreplies (NUM policy %s", c4g_num_policy_name(L->policy));
    if (L->policy == C4G_NUM_EITHER) {
        fprintf(out, ", server %s", c4g_num_policy_name(L->cs.detected));
    }
    fprintf(out, "; t-cycle1 %.0f us): %lu ok, %lu late, "
            "%lu missing, %lu unjudged, %lu wrong NUM, %lu malformed, %lu duplicates, %lu stale\n",
            (double)L->c.an.t_cycle1_ns * 1e-3,
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
        fprintf(out, "latency: p50 %.0f us, p99 %.0f us, max %.1f us\n", c4gh_hist_us(&L->lat, 0.5),
                c4gh_hist_us(&L->lat, 0.99), (double)n->lat_max * 1e-3);
    } else {
        fprintf(out, "latency: no reply judged ok\n");
    }
    fprintf(out, "divergences: %llu of %llu replies compared differ from the recorded ones (floats %s)\n",
            (unsigned long long)L->differing, (unsigned long long)L->compared,
            L->tolerance > 0.0 ? "within the tolerance" : "exact, by bits");
    if (L->timing_only > 0U) {
        fprintf(out, "  timing: %llu recorded replies came after the controller's next packet, these in time "
                "with the same content (not divergences)\n", (unsigned long long)L->timing_only);
    }
    if (L->differing > 0U) {
        fprintf(out, "  per field:");
        for (f = 0U; f < LV_F_COUNT; f++) {
            if (L->field[f] > 0U) {
                fprintf(out, "%s %s %llu", shown++ ? "," : "", lv_field_name((lv_field_t)f),
                        (unsigned long long)L->field[f]);
            }
        }
        fputc('\n', out);
    }
    if (L->first.set) {
        const lv_first_t *F = &L->first;
        fprintf(out, "  first: pass %u, %s packet NUM %d (tick %llu)", F->pass, kind_name(F->kind),
                (int)F->num, (unsigned long long)F->tick);
        if (F->axis > 0U) {
            fprintf(out, ", axis %u in mode %d", F->axis, (int)F->mode);
        }
        fprintf(out, ": %s recorded %s, received %s\n", lv_field_name(F->field), F->recorded,
                F->received);
    }
    if (L->topspeed) {
        fprintf(out, "timing: top speed (no schedule)\n");
    } else {
        fprintf(out, "timing: send time - schedule p50 %.0f us, p99 %.0f us, max %.1f us; drift %.1f us "
                "(the last packet); %llu sent over %.0f us late; %s send times\n",
                c4gh_hist_us(&L->err, 0.5), c4gh_hist_us(&L->err, 0.99), (double)L->err.max_ns * 1e-3,
                (double)L->drift_ns * 1e-3, (unsigned long long)L->overruns, (double)L->tol_ns * 1e-3,
                L->kstamp ? "kernel" : "user-space");
    }
    if (!lv_findings(L)) {
        fprintf(out, "result: OK, every reply in time and equal to the recorded one\n");
    } else {
        fprintf(out, "result: FINDINGS");
        list_findings(out, L);
        fputc('\n', out);
    }
}

void lv_report_json(FILE *out, const lv_t *L)
{
    const c4g_ctrl_counters_t *n = &L->n;
    const lv_scan_t *sc = chosen(L);
    json_t *o, *fields, *first = json_null(), *timing = json_null();
    unsigned f;
    fields = json_object();
    for (f = 0U; f < LV_F_COUNT; f++) {
        (void)json_object_set_new(fields, lv_field_name((lv_field_t)f), json_integer((json_int_t)L->field[f]));
    }
    if (L->first.set) {
        const lv_first_t *F = &L->first;
        json_decref(first);
        first = json_pack("{s:i, s:s, s:I, s:i, s:i, s:i, s:s, s:s, s:s}", "pass", (int)F->pass, "kind",
                          kind_name(F->kind), "tick", (json_int_t)F->tick, "num", (int)F->num, "axis",
                          (int)F->axis, "mode", (int)F->mode, "field", lv_field_name(F->field), "recorded",
                          F->recorded, "received", F->received);
    }
    if (!L->topspeed) {
        json_decref(timing);
        timing = json_pack("{s:{s:f, s:f, s:f, s:f}, s:f, s:I, s:f, s:I}", "send_error_us", "p50",
                           c4gh_hist_us(&L->err, 0.5), "p99", c4gh_hist_us(&L->err, 0.99), "max",
                           (double)L->err.max_ns * 1e-3, "min", (double)L->err.min_ns * 1e-3, "drift_us",
                           (double)L->drift_ns * 1e-3, "overruns", (json_int_t)L->overruns,
                           "overrun_margin_us", (double)L->tol_ns * 1e-3, "spin_us", (json_int_t)L->spin_us);
    }
    /* key names as in c4g-sim's summary where they mean the same */
    o = json_pack("{s:s, s:s, s:s, s:i, s:s, s:i, s:i, s:f, s:b, s:b, s:f, s:f}", "tool", RP_TOOL,
                  "command", "live", "file", L->path, "session", (int)L->chosen, "to", L->to_text,
                  "passes", (int)L->loops, "passes_done", (int)L->passes_done, "speed",
                  L->topspeed ? 0.0 : L->speed, "topspeed", L->topspeed, "interrupted", L->interrupted,
                  "recorded_s", (double)(sc->last_ns - sc->first_ns) * 1e-9, "elapsed_s",
                  (double)L->elapsed_ns * 1e-9);
    (void)json_object_set_new(o, "packets", json_pack("{s:I, s:I, s:I, s:I, s:I}", "sent", (json_int_t)L->sent,
                                                      "sync", (json_int_t)L->sent_kind[C4G_PKT_SYNC], "init",
                                                      (json_int_t)L->sent_kind[C4G_PKT_INIT], "cyclic",
                                                      (json_int_t)L->sent_kind[C4G_PKT_CYCLIC], "send_errors",
                                                      (json_int_t)L->send_errors));
    (void)json_object_set_new(
        o, "replies",
        json_pack("{s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:b, s:{s:f, s:f, s:f}}", "ok",
                  (json_int_t)n->replies_ok, "missing", (json_int_t)n->missing, "late", (json_int_t)n->late,
                  "unjudged", (json_int_t)n->unjudged, "wrong_num", (json_int_t)n->wrong_num, "malformed",
                  (json_int_t)n->malformed, "foreign", (json_int_t)n->foreign, "duplicates",
                  (json_int_t)n->duplicates, "stale", (json_int_t)n->stale, "unexpected",
                  (json_int_t)n->unexpected, "max_consecutive_missing", (json_int_t)n->max_consecutive,
                  "err_c4gopen_udp", n->max_consecutive >= 10U, "latency_us", "p50",
                  c4gh_hist_us(&L->lat, 0.5), "p99", c4gh_hist_us(&L->lat, 0.99), "max",
                  (double)n->lat_max * 1e-3));
    (void)json_object_set_new(o, "num_policy", json_string(c4g_num_policy_name(L->policy)));
    (void)json_object_set_new(o, "pc_policy", json_string(c4g_num_policy_name(L->cs.detected)));
    (void)json_object_set_new(o, "t_cycle1_us", json_real((double)L->c.an.t_cycle1_ns * 1e-3));
    (void)json_object_set_new(o, "divergences",
                              json_pack("{s:I, s:I, s:f, s:o, s:o}", "compared", (json_int_t)L->compared,
                                        "differing", (json_int_t)L->differing, "tolerance", L->tolerance,
                                        "fields", fields, "first", first));
    (void)json_object_set_new(json_object_get(o, "divergences"), "timing_only",
                              json_integer((json_int_t)L->timing_only));
    (void)json_object_set_new(o, "timing", timing);
    (void)json_object_set_new(o, "timestamps", json_string(L->kstamp ? "kernel" : "user"));
    (void)json_object_set_new(o, "result", json_string(lv_findings(L) ? "findings" : "ok"));
    (void)json_dumpf(o, out, JSON_COMPACT | JSON_REAL_PRECISION(9));
    fputc('\n', out);
    json_decref(o);
}
