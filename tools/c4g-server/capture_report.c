/* SPDX-License-Identifier: MIT */
/* c4g-server --capture's report (srv_capture.h): the runs, per session what was fed and
 * compared, the first divergence and the count per field, as text or JSON. c4g-replay rerun
 * prints this report (c4g-server runs for it with --replay-rerun). */
#include "srv_capture.h"

#include <jansson.h>
#include <stdio.h>

#define CAP_FIELD_NAME(id, name) name,
static const char *const k_field_names[CAP_F_COUNT] = {CAP_FIELDS(CAP_FIELD_NAME)};
#undef CAP_FIELD_NAME

const char *srv_cap_field_name(srv_cap_field_t f)
{
    return (f < CAP_F_COUNT) ? k_field_names[f] : "?";
}

static const char *kind_name(int kind)
{
    return (kind == C4G_PKT_SYNC) ? "sync" : ((kind == C4G_PKT_INIT) ? "init" : "cyclic");
}

void srv_cap_print_div(FILE *out, const srv_cap_div_t *d)
{
    fprintf(out, "session %u ", d->session);
    if (d->kind == C4G_PKT_CYCLIC) {
        fprintf(out, "tick %llu", (unsigned long long)d->tick);
    } else {
        fprintf(out, "%s packet", kind_name(d->kind));
    }
    fprintf(out, " (controller NUM %d, frame %llu, %.6f s): ", (int)d->num, (unsigned long long)d->frame,
            d->t_s);
    if (d->open > 0) {
        if (d->arm > 0) {
            fprintf(out, "arm %d axis %d (OPEN %d) ", d->arm, d->logical, d->open);
        } else {
            fprintf(out, "OPEN axis %d ", d->open);
        }
    }
    if (d->field == CAP_F_SYNC || d->field == CAP_F_INIT) {
        fprintf(out, "%s word %u", k_field_names[d->field], d->word);
    } else {
        fprintf(out, "%s", k_field_names[d->field]);
    }
    fprintf(out, ": recorded %s, produced %s\n", d->recorded, d->produced);
}

static const char *ep_text(const c4gh_an_endpoint_t *e, char *buf, size_t cap)
{
    char ip[16];
    (void)snprintf(buf, cap, "%s:%u", c4gh_cap_ip_str(e->ip, ip), (unsigned)e->port);
    return buf;
}

static const char *behaviour_name(const srv_cap_t *C)
{
    return C->cfg.cap.echo ? "echo" : "server";
}

void srv_cap_report_text(FILE *out, const srv_cap_t *C, const char *path)
{
    unsigned i;
    int k;
    fprintf(out, "%s: behaviour %s", path, behaviour_name(C));
    if (C->srv_argc > 0) {
        fprintf(out, ", c4g-server options:");
        for (k = 0; k < C->srv_argc; k++) {
            fprintf(out, " %s", C->srv_argv[k]);
        }
    }
    fprintf(out, "\n");
    for (i = 0U; i < C->n_sess; i++) {
        const srv_cap_sess_t *s = &C->sess[i];
        char a[32], b[32];
        fprintf(out, "session %u  controller %s  PC %s\n", s->id, ep_text(&s->ctrl, a, sizeof a),
               ep_text(&s->pc, b, sizeof b));
        fprintf(out, "  fed %llu sync, %llu init, %llu cyclic packets", (unsigned long long)s->fed[C4G_PKT_SYNC],
               (unsigned long long)s->fed[C4G_PKT_INIT], (unsigned long long)s->fed[C4G_PKT_CYCLIC]);
        if (s->held_dropped > 0U) {
            fprintf(out, " (%llu dropped unanswered after an active-freezing pause)",
                   (unsigned long long)s->held_dropped);
        }
        fprintf(out, "\n  replies: %llu compared, %llu equal, %llu divergent",
               (unsigned long long)s->compared, (unsigned long long)(s->compared - s->divergent),
               (unsigned long long)s->divergent);
        if (s->any_div) {
            fprintf(out, " (the first at tick %llu)", (unsigned long long)s->first_div_tick);
        }
        fprintf(out, "\n");
        if (s->recorded_missing > 0U) {
            fprintf(out, "  %llu controller packets have no reply in the capture\n",
                   (unsigned long long)s->recorded_missing);
        }
        if (s->timing_only > 0U) {
            fprintf(out, "  timing: %llu recorded replies came after the controller's next packet, the server's "
                   "in time with the same content (not divergences)\n", (unsigned long long)s->timing_only);
        }
        if (s->primed) {
            fprintf(out, "  no start-up in the capture: the server was first taken through one (9 sync, the "
                   "figure 10.1 init packet for %u axes, %u ms, 2 sync), not compared\n", s->primed_axes,
                   s->primed_period_ms);
        }
    }
    if (C->server_starts > 1U) {
        fprintf(out, "server runs: %llu (a new run where the recorded one would have stopped)\n",
               (unsigned long long)C->server_starts);
    }
    if (C->n_other > 0U) {
        fprintf(out, "not %s: %u session(s) of another controller (", C->cfg.cap.rerun ? "rerun" : "run",
                C->n_other);
        for (i = 0U; i < C->n_other; i++) {
            fprintf(out, "%s%u", (i > 0U) ? ", " : "", C->other_sessions[i]);
        }
        fprintf(out, "): take one with --session N\n");
    }
    if (C->have_first) {
        fprintf(out, "first divergence: ");
        srv_cap_print_div(out, &C->first);
        fprintf(out, "divergences per field:\n");
        for (k = 0; k < (int)CAP_F_COUNT; k++) {
            const srv_cap_field_count_t *f = &C->fields[k];
            if (f->count == 0U) {
                continue;
            }
            fprintf(out, "  %-7s %10llu  first: ", k_field_names[k], (unsigned long long)f->count);
            srv_cap_print_div(out, &f->first);
        }
    }
    if (C->divergent == 0U) {
        fprintf(out, "verdict: 0 divergences in %llu replies: the server gives the recorded replies\n",
               (unsigned long long)C->compared);
    } else {
        fprintf(out, "verdict: %llu of %llu replies diverge\n", (unsigned long long)C->divergent,
               (unsigned long long)C->compared);
    }
}

static json_t *div_json(const srv_cap_div_t *d)
{
    json_t *o = json_pack("{s:i, s:s, s:I, s:i, s:I, s:f, s:s, s:s, s:s}", "session", (json_int_t)d->session,
                          "packet", kind_name(d->kind), "tick", (json_int_t)d->tick, "num", (json_int_t)d->num, "frame", (json_int_t)d->frame,
                          "time", d->t_s, "field", k_field_names[d->field], "recorded", d->recorded,
                          "produced", d->produced);
    if (o == NULL) {
        return NULL;
    }
    if (d->open > 0) {
        (void)json_object_set_new(o, "open", json_integer(d->open));
        if (d->arm > 0) {
            (void)json_object_set_new(o, "arm", json_integer(d->arm));
            (void)json_object_set_new(o, "axis", json_integer(d->logical));
        }
    }
    if (d->field == CAP_F_SYNC || d->field == CAP_F_INIT) {
        (void)json_object_set_new(o, "word", json_integer((json_int_t)d->word));
    }
    return o;
}

int srv_cap_report_json(FILE *out, const srv_cap_t *C, const char *path)
{
    json_t *root = json_object(), *sessions = json_array(), *fields = json_object(), *opts = json_array();
    unsigned i;
    int k, rc;
    char a[32], b[32];
    if (root == NULL || sessions == NULL || fields == NULL || opts == NULL) {
        return -1;
    }
    for (k = 0; k < C->srv_argc; k++) {
        (void)json_array_append_new(opts, json_string(C->srv_argv[k]));
    }
    for (i = 0U; i < C->n_sess; i++) {
        const srv_cap_sess_t *s = &C->sess[i];
        (void)json_array_append_new(
            sessions,
            json_pack("{s:i, s:s, s:s, s:{s:I, s:I, s:I}, s:I, s:I, s:I, s:I, s:I}", "id", (json_int_t)s->id,
                      "controller", ep_text(&s->ctrl, a, sizeof a), "pc", ep_text(&s->pc, b, sizeof b), "fed",
                      "sync", (json_int_t)s->fed[C4G_PKT_SYNC], "init", (json_int_t)s->fed[C4G_PKT_INIT], "cyclic",
                      (json_int_t)s->fed[C4G_PKT_CYCLIC], "compared", (json_int_t)s->compared, "equal",
                      (json_int_t)(s->compared - s->divergent), "divergent", (json_int_t)s->divergent,
                      "recorded_missing", (json_int_t)s->recorded_missing, "dropped_after_pause",
                      (json_int_t)s->held_dropped));
        (void)json_object_set_new(json_array_get(sessions, json_array_size(sessions) - 1U), "timing_only",
                                  json_integer((json_int_t)s->timing_only));
        (void)json_object_set_new(json_array_get(sessions, json_array_size(sessions) - 1U), "synthetic_startup",
                                  json_boolean(s->primed));
    }
    for (k = 0; k < (int)CAP_F_COUNT; k++) {
        if (C->fields[k].count > 0U) {
            (void)json_object_set_new(fields, k_field_names[k],
                                      json_pack("{s:I, s:o}", "count", (json_int_t)C->fields[k].count,
                                                "first", div_json(&C->fields[k].first)));
        }
    }
    (void)json_object_set_new(root, "tool", json_string(C->cfg.cap.rerun ? "c4g-replay rerun" : "c4g-server --capture"));
    (void)json_object_set_new(root, "file", json_string(path));
    (void)json_object_set_new(root, "behaviour", json_string(behaviour_name(C)));
    (void)json_object_set_new(root, "server_options", opts);
    (void)json_object_set_new(root, "tolerance", json_real(C->cfg.cap.tolerance));
    (void)json_object_set_new(root, "sessions", sessions);
    (void)json_object_set_new(root, "server_runs", json_integer((json_int_t)C->server_starts));
    (void)json_object_set_new(root, "sessions_not_rerun", json_integer((json_int_t)C->n_other));
    (void)json_object_set_new(root, "compared", json_integer((json_int_t)C->compared));
    (void)json_object_set_new(root, "divergent", json_integer((json_int_t)C->divergent));
    (void)json_object_set_new(root, "timing_only", json_integer((json_int_t)C->timing_only));
    (void)json_object_set_new(root, "first", C->have_first ? div_json(&C->first) : json_null());
    (void)json_object_set_new(root, "fields", fields);
    rc = json_dumpf(root, out, JSON_INDENT(2) | JSON_PRESERVE_ORDER);
    json_decref(root);
    fputc('\n', out);
    return rc;
}

