/* SPDX-License-Identifier: MIT */
/* c4g-server outputs: the log writer thread's sink (text log, pcap, moni CSV) and the
 * exit report (chapter 22 timing, counters, safety events) as text and JSON. Nothing
 * here runs on the real-time path. */
#include "srv.h"
#include "c4gh_pcap.h"
#include "c4gh_csv.h"

#include <jansson.h>

#include <arpa/inet.h>
#include <errno.h>
#include <string.h>
#include <time.h>

static uint64_t wall_offset_ns; /* CLOCK_REALTIME - CLOCK_MONOTONIC at start */

int srv_outputs_open(srv_host_t *H)
{
    const srv_t *S = &H->s;
    struct timespec r, m;
    clock_gettime(CLOCK_REALTIME, &r);
    clock_gettime(CLOCK_MONOTONIC, &m);
    wall_offset_ns = ((uint64_t)r.tv_sec * 1000000000ULL + (uint64_t)r.tv_nsec) -
                     ((uint64_t)m.tv_sec * 1000000000ULL + (uint64_t)m.tv_nsec);
    H->log_fp = NULL;
    H->pcap = NULL;
    H->moni_fp = NULL;
    /* the JSON summary is written at exit: its place is checked now, before the session */
    if (S->cfg.json_path[0] != '\0' && c4gh_cli_check_output("c4g-server", "--json-out", S->cfg.json_path) != 0) {
        return -1;
    }
    if (S->cfg.log_path[0] != '\0') {
        H->log_fp = fopen(S->cfg.log_path, "w");
        if (H->log_fp == NULL) {
            c4gh_cli_file_error("c4g-server", "--log", S->cfg.log_path, errno);
            return -1;
        }
    }
    if (S->cfg.pcap_path[0] != '\0') {
        char err[256];
        H->pcap = c4gh_pcap_open(S->cfg.pcap_path, err, sizeof err);
        if (H->pcap == NULL) {
            char pt[600];
            fprintf(stderr, "c4g-server: --pcap %s: %s\n",
                    c4gh_cli_path_text(S->cfg.pcap_path, pt, sizeof pt), err);
            return -1;
        }
    }
    if (S->cfg.moni_path[0] != '\0') {
        H->moni_fp = fopen(S->cfg.moni_path, "w");
        if (H->moni_fp == NULL) {
            c4gh_cli_file_error("c4g-server", "--moni", S->cfg.moni_path, errno);
            return -1;
        }
        if (S->cfg.moni_type == 0) {
            fputs(C4GH_TICK_CSV_COLUMNS "\n", H->moni_fp);
        } else {
            char hdr[256];
            size_t hl = 0U;
            fprintf(H->moni_fp, "# moni type %d (manual chapter 16), rows from c4gh_moni_csv_row\n",
                    S->cfg.moni_type);
            if (c4gh_moni_csv_header((uint32_t)S->cfg.moni_type, hdr, sizeof hdr, &hl) == C4G_OK) {
                fwrite(hdr, 1, hl, H->moni_fp);
            }
        }
    }
    return 0;
}

void srv_outputs_close(srv_host_t *H)
{
    const srv_t *S = &H->s;
    if (H->log_fp != NULL) fclose(H->log_fp);
    if (H->pcap != NULL && c4gh_pcap_close(H->pcap) != 0) {
        fprintf(stderr, "c4g-server: --pcap %s: write error\n", S->cfg.pcap_path);
    }
    H->pcap = NULL;
    if (H->moni_fp != NULL) fclose(H->moni_fp);
    H->log_fp = H->moni_fp = NULL;
}

/* rec->data: peer addr (4, network order), peer port (2), local port (2), payload.
 * Written with the shared lib/host/c4gh_pcap writer (Ethernet/IPv4/UDP frames), the
 * same format as c4g-sim's --pcap. */
static void write_pcap(srv_host_t *H, const c4gh_rtlog_rec_t *rec)
{
    const srv_t *S = &H->s;
    uint32_t peer, local;
    uint16_t pport, lport;
    struct timespec ts;
    const uint64_t t = rec->t_ns + wall_offset_ns;
    const int rx = (rec->kind == LOG_PCAP_RX);
    memcpy(&peer, rec->data, 4U);
    memcpy(&pport, rec->data + 4, 2U);
    memcpy(&lport, rec->data + 6, 2U);
    peer = ntohl(peer);
    pport = ntohs(pport);
    lport = ntohs(lport);
    if (inet_pton(AF_INET, S->cfg.bind_addr, &local) != 1 || local == 0U) {
        local = peer; /* bound to any: the reply leaves from the address it was sent to */
    } else {
        local = ntohl(local);
    }
    ts.tv_sec = (time_t)(t / 1000000000ULL);
    ts.tv_nsec = (long)(t % 1000000000ULL);
    if (c4gh_pcap_write_udp(H->pcap, &ts, rx ? peer : local, rx ? pport : lport,
                           rx ? local : peer, rx ? lport : pport, rec->data + 8,
                           rec->len - 8U) != 0) {
        H->pcap_errors++;
    }
}

static void write_moni(srv_host_t *H, const c4gh_rtlog_rec_t *rec)
{
    const srv_t *S = &H->s;
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    const double t = (double)(rec->t_ns - S->t0_ns) * 1e-9;
    const c4g_axis_map_t *m = srv_map(S);
    uint32_t i;
    memcpy(&rx, rec->data, sizeof rx);
    memcpy(&tx, rec->data + sizeof rx, sizeof tx);
    for (i = 0U; i < rx.n_axes && i < C4G_MAX_AXES; i++) {
        const c4g_ctrl_axis_t *r = &rx.ax[i];
        const c4g_pc_axis_t *o = &tx.ax[i];
        if (S->cfg.moni_type >= 19) {
            c4g_moni_rec_t mr;
            char row[C4GH_MONI_ROW_MAX + 8U];
            size_t rl = 0U;
            if (c4g_moni_record((uint32_t)S->cfg.moni_type, &rx, &tx, i, &mr) == C4G_OK &&
                c4gh_moni_csv_row(&mr, row, sizeof row, &rl) == C4G_OK) {
                fwrite(row, 1, rl, H->moni_fp);
            }
            continue;
        }
        c4gh_tick_csv_row(H->moni_fp, t, rx.num, i + 1U, (uint32_t)m->arm_of[i] + 1U,
                         (uint32_t)m->logical_of[i] + 1U, r, tx.infpar, o);
        fputc('\n', H->moni_fp);
    }
}

void srv_sink(void *ctx, const c4gh_rtlog_rec_t *rec)
{
    srv_host_t *H = (srv_host_t *)ctx;
    const srv_t *S = &H->s;
    switch (rec->kind) {
    case LOG_TEXT: {
        FILE *fp = (H->log_fp != NULL) ? H->log_fp : stderr;
        if (S->cfg.quiet && H->log_fp == NULL) {
            break;
        }
        fprintf(fp, "c4g-server: [%10.6f] %.*s\n", (double)(rec->t_ns - S->t0_ns) * 1e-9,
                (int)rec->len, (const char *)rec->data);
        break;
    }
    case LOG_PCAP_RX:
    case LOG_PCAP_TX:
        if (H->pcap != NULL && rec->len >= 8U) {
            write_pcap(H, rec);
        }
        break;
    case LOG_MONI:
        if (H->moni_fp != NULL) {
            write_moni(H, rec);
        }
        break;
    default:
        break;
    }
}

static double pct_us(const srv_stats_t *st, double p)
{
    return c4gh_hist_us(&st->cycle, p);
}

static const char *const mal_names[C4G_MAL_COUNT_] = {"length", "num", "mode", "nonfinite",
                                                      "init", "phase", "ceiling"};

/* Every session since the start (--persist starts a new one after each 504). */
static void counters_total(const srv_t *S, c4g_counters_t *tot)
{
    *tot = S->done;
    srv_counters_add(tot, srv_counters(S));
}

/* No session started (no initialization or cyclic packet accepted): what was seen instead,
 * in one line, rather than a report of zeros. */
static void report_none(const srv_host_t *H, FILE *out, const c4g_counters_t *c)
{
    const srv_t *S = &H->s;
    const srv_stats_t *st = &S->stats;
    fprintf(out, "c4g-server: no session started: ");
    if (st->foreign > 0U && c->rx == 0U) {
        fprintf(out, "%llu datagrams came from other addresses than the controller's "
                "(--controller %s)%s%s\n", (unsigned long long)st->foreign, S->cfg.ctrl_addr,
                H->ctrl_hinted ? "; the controller's packets came from " : "",
                H->ctrl_hinted ? H->ctrl_seen : "");
    } else if (c->rx == 0U) {
        fprintf(out, "no datagram came to %s:%u (is the controller, or c4g-sim, sending to "
                "this address and port?)\n", S->cfg.bind_addr, S->cfg.port);
    } else {
        fprintf(out, "%llu datagrams, none an initialization packet accepted (sync %llu, "
                "malformed %llu, other endpoints %llu, refused %llu)\n",
                (unsigned long long)c->rx, (unsigned long long)c->sync,
                (unsigned long long)c->malformed_total, (unsigned long long)c->foreign_total,
                (unsigned long long)c->refused);
    }
    fflush(out);
}

void srv_report(srv_host_t *H, FILE *out, const char *why, int code)
{
    const srv_t *S = &H->s;
    c4g_timing_t t;
    c4g_counters_t tot;
    const c4g_counters_t *c = &tot;
    const srv_stats_t *st = &S->stats;
    const srv_safety_t *sf = &S->safety;
    uint32_t k;
    counters_total(S, &tot);
    (void)c4g_loop_timing(&S->loop, &t);
    fprintf(out, "c4g-server: session ended: %s (exit code %d)\n", why, code);
    if (c->init == 0U && c->cyclic == 0U) {
        report_none(H, out, c);
        return;
    }
    fprintf(out, "== Timing (manual chapter 22, PC point of view)\n");
    fprintf(out, "Nominal Inter-Packets Period = %.9f s\n", (double)t.nominal_period_ns * 1e-9);
    fprintf(out, "Worst cycle time = %.9f s\n", (double)t.worst_cycle_ns * 1e-9);
    fprintf(out, "Measured Inter-Packets Period range = [%+.9f; %+.9f] s\n",
            (double)t.min_inter_ns * 1e-9, (double)t.max_inter_ns * 1e-9);
    fprintf(out, "Jitter range = [%+.9f; %+.9f] s\n", (double)t.min_jitter_ns * 1e-9,
            (double)t.max_jitter_ns * 1e-9);
    fprintf(out, "Percentage jitter range = [%+.9f; %+.9f] %%\n", t.min_jitter_pct, t.max_jitter_pct);
    fprintf(out, "Cycle time (rx -> sent): samples %llu, mean %.1f us, p50 %.0f us, p99 %.0f us, "
            "p99.9 %.0f us, max %.1f us; later than %u us: %llu\n",
            (unsigned long long)st->cycle.n, c4gh_hist_mean_us(&st->cycle),
            pct_us(st, 0.5), pct_us(st, 0.99), pct_us(st, 0.999), (double)st->cycle.max_ns / 1000.0,
            S->cfg.late_us, (unsigned long long)st->late);
    fprintf(out, "== Counters\n");
    fprintf(out, "rx %llu, tx %llu, sync %llu, init %llu, cyclic %llu\n",
            (unsigned long long)c->rx, (unsigned long long)c->tx, (unsigned long long)c->sync,
            (unsigned long long)c->init, (unsigned long long)c->cyclic);
    fprintf(out, "gaps %llu (missed %llu), duplicates %llu, out of order %llu, lost %llu, long gaps %llu\n",
            (unsigned long long)c->gaps, (unsigned long long)c->missed,
            (unsigned long long)c->duplicates, (unsigned long long)c->out_of_order,
            (unsigned long long)c->lost_events, (unsigned long long)st->long_gaps);
    fprintf(out, "malformed %llu (", (unsigned long long)c->malformed_total);
    for (k = 0U; k < C4G_MAL_COUNT_; k++) {
        fprintf(out, "%s%s %llu", k ? ", " : "", mal_names[k], (unsigned long long)c->malformed[k]);
    }
    fprintf(out, "), oversize %llu\n", (unsigned long long)st->oversize);
    fprintf(out, "foreign: other address %llu, other port: init %llu, cyclic %llu, other %llu; "
            "silences %llu (longest %.1f ms)\n",
            (unsigned long long)st->foreign, (unsigned long long)c->foreign[C4G_FOREIGN_INIT],
            (unsigned long long)c->foreign[C4G_FOREIGN_CYCLIC],
            (unsigned long long)c->foreign[C4G_FOREIGN_OTHER], (unsigned long long)c->silences,
            (double)c->longest_silence_ns * 1e-6);
    if (c->init_conflicts + c->contended + c->new_peers + c->end_unexpected + c->sync_excess > 0U) {
        fprintf(out, "trust: init conflicts %llu, contended start-ups %llu (refused datagrams %llu), "
                "new peers %llu, 504 out of procedure %llu, syncs beyond the handshake %llu\n",
                (unsigned long long)c->init_conflicts, (unsigned long long)c->contended,
                (unsigned long long)c->refused, (unsigned long long)c->new_peers,
                (unsigned long long)c->end_unexpected, (unsigned long long)c->sync_excess);
    }
    fprintf(out, "replies skipped %llu, send errors %llu, neutral replies %llu, encode errors %llu, "
            "log records dropped %llu\n",
            (unsigned long long)st->skipped, (unsigned long long)st->send_errors,
            (unsigned long long)st->neutral_replies, (unsigned long long)st->encode_errors,
            (unsigned long long)H->log.dropped);
    fprintf(out, "restarts (506) %llu, passive freezings %llu, active freezings %llu, drive-on ends %llu, "
            "mode changes %llu\n", (unsigned long long)st->restarts,
            (unsigned long long)st->frozen_passive, (unsigned long long)st->freezes,
            (unsigned long long)st->drive_on_end, (unsigned long long)st->mode_changes);
    if (st->ff_model_ticks > 0U) {
        fprintf(out, "mode-9 identified model: %llu axis ticks, %llu clamped to the model's range\n",
                (unsigned long long)st->ff_model_ticks, (unsigned long long)st->ff_model_clamped);
    }
    fprintf(out, "EXIT_FROM_OPEN packets per arm: %llu %llu %llu %llu\n",
            (unsigned long long)st->exits_sent[0], (unsigned long long)st->exits_sent[1],
            (unsigned long long)st->exits_sent[2], (unsigned long long)st->exits_sent[3]);
    fprintf(out, "== Safety events\n");
    fprintf(out, "following error (508) replies %llu, drive off (505) replies %llu, current "
            "saturations %llu, delta-current clamps %llu, stroke %llu, continuity %llu, "
            "non-finite %llu, injected %llu\n",
            (unsigned long long)sf->follow_error, (unsigned long long)sf->drive_off,
            (unsigned long long)sf->cur_saturated, (unsigned long long)sf->delta_clamped,
            (unsigned long long)sf->stroke, (unsigned long long)sf->continuity,
            (unsigned long long)sf->nonfinite, (unsigned long long)sf->injected);
    fprintf(out, "first safety event: %s\n", sf->first[0] ? sf->first : "none");
    fflush(out);
}

static void put_u(json_t *o, const char *key, uint64_t v)
{
    json_object_set_new(o, key, json_integer((json_int_t)v));
}

static void put_i(json_t *o, const char *key, long long v)
{
    json_object_set_new(o, key, json_integer((json_int_t)v));
}

static void put_f(json_t *o, const char *key, double v)
{
    json_object_set_new(o, key, json_real(v));
}

static json_t *json_timing(const srv_t *S)
{
    const srv_stats_t *st = &S->stats;
    json_t *o = json_object();
    c4g_timing_t t;
    memset(&t, 0, sizeof t);
    (void)c4g_loop_timing(&S->loop, &t);
    put_i(o, "nominal_period_ns", (long long)t.nominal_period_ns);
    put_i(o, "worst_cycle_ns", (long long)t.worst_cycle_ns);
    put_i(o, "min_inter_ns", (long long)t.min_inter_ns);
    put_i(o, "max_inter_ns", (long long)t.max_inter_ns);
    put_i(o, "min_jitter_ns", (long long)t.min_jitter_ns);
    put_i(o, "max_jitter_ns", (long long)t.max_jitter_ns);
    put_f(o, "min_jitter_pct", t.min_jitter_pct);
    put_f(o, "max_jitter_pct", t.max_jitter_pct);
    put_u(o, "cycle_samples", st->cycle.n);
    put_f(o, "cycle_mean_us", c4gh_hist_mean_us(&st->cycle));
    put_f(o, "cycle_p50_us", pct_us(st, 0.5));
    put_f(o, "cycle_p99_us", pct_us(st, 0.99));
    put_f(o, "cycle_p999_us", pct_us(st, 0.999));
    put_f(o, "cycle_max_us", (double)st->cycle.max_ns / 1000.0);
    put_u(o, "late_us", S->cfg.late_us);
    put_u(o, "late", st->late);
    return o;
}

static json_t *json_counters(const srv_host_t *H)
{
    const srv_t *S = &H->s;
    const srv_stats_t *st = &S->stats;
    c4g_counters_t c;
    json_t *o = json_object();
    json_t *ex = json_array();
    char key[40];
    uint32_t k;
    counters_total(S, &c);
    put_u(o, "rx", c.rx);
    put_u(o, "tx", c.tx);
    put_u(o, "sync", c.sync);
    put_u(o, "init", c.init);
    put_u(o, "cyclic", c.cyclic);
    put_u(o, "gaps", c.gaps);
    put_u(o, "missed", c.missed);
    put_u(o, "duplicates", c.duplicates);
    put_u(o, "out_of_order", c.out_of_order);
    put_u(o, "lost", c.lost_events);
    put_u(o, "long_gaps", st->long_gaps);
    put_u(o, "malformed", c.malformed_total);
    for (k = 0U; k < C4G_MAL_COUNT_; k++) {
        snprintf(key, sizeof key, "malformed_%s", mal_names[k]);
        put_u(o, key, c.malformed[k]);
    }
    put_u(o, "foreign", st->foreign + c.foreign_total);
    put_u(o, "foreign_address", st->foreign);
    put_u(o, "foreign_init", c.foreign[C4G_FOREIGN_INIT]);
    put_u(o, "foreign_cyclic", c.foreign[C4G_FOREIGN_CYCLIC]);
    put_u(o, "foreign_other", c.foreign[C4G_FOREIGN_OTHER]);
    put_u(o, "init_conflicts", c.init_conflicts);
    put_u(o, "contended", c.contended);
    put_u(o, "refused", c.refused);
    put_u(o, "new_peers", c.new_peers);
    put_u(o, "end_unexpected", c.end_unexpected);
    put_u(o, "sync_excess", c.sync_excess);
    put_u(o, "silences", c.silences);
    put_f(o, "longest_silence_ms", (double)c.longest_silence_ns * 1e-6);
    put_u(o, "oversize", st->oversize);
    put_u(o, "skipped", st->skipped);
    put_u(o, "send_errors", st->send_errors);
    put_u(o, "neutral_replies", st->neutral_replies);
    put_u(o, "encode_errors", st->encode_errors);
    put_u(o, "log_dropped", H->log.dropped);
    put_u(o, "restarts", st->restarts);
    put_u(o, "inits", st->inits);
    put_u(o, "passive_freezings", st->frozen_passive);
    put_u(o, "active_freezings", st->freezes);
    put_u(o, "drive_on_end", st->drive_on_end);
    put_u(o, "mode_changes", st->mode_changes);
    put_u(o, "ff_model_ticks", st->ff_model_ticks);
    put_u(o, "ff_model_clamped", st->ff_model_clamped);
    for (k = 0U; k < 4U; k++) {
        json_array_append_new(ex, json_integer((json_int_t)st->exits_sent[k]));
    }
    json_object_set_new(o, "exits_sent", ex);
    return o;
}

static json_t *json_safety(const srv_safety_t *sf)
{
    json_t *o = json_object();
    put_u(o, "follow_error_508", sf->follow_error);
    put_u(o, "drive_off_505", sf->drive_off);
    put_u(o, "current_saturations", sf->cur_saturated);
    put_u(o, "delta_clamps", sf->delta_clamped);
    put_u(o, "stroke", sf->stroke);
    put_u(o, "continuity", sf->continuity);
    put_u(o, "nonfinite", sf->nonfinite);
    put_u(o, "injected", sf->injected);
    json_object_set_new(o, "first", json_string(sf->first)); /* NULL (invalid UTF-8): dropped */
    return o;
}

/* The JSON summary (jansson): one object, one line. */
int srv_json(srv_host_t *H, const char *path, const char *why, int code)
{
    const srv_t *S = &H->s;
    FILE *fp = (strcmp(path, "-") == 0) ? stdout : fopen(path, "w");
    json_t *o;
    int rc;
    if (fp == NULL) {
        c4gh_cli_file_error("c4g-server", "--json-out", path, errno);
        return -1;
    }
    o = json_object();
    json_object_set_new(o, "tool", json_string("c4g-server"));
    json_object_set_new(o, "version", json_string(C4G_VERSION_STRING));
    put_i(o, "exit_code", code);
    json_object_set_new(o, "reason", json_string(why));
    json_object_set_new(o, "num_policy",
                        json_string(S->cfg.num_policy == C4G_NUM_ECHO ? "echo" : "plus-one"));
    put_u(o, "axes", srv_map(S)->n_axes);
    put_i(o, "period_ms", (long long)srv_init_packet(S)->period_ms);
    json_object_set_new(o, "timing", json_timing(S));
    json_object_set_new(o, "counters", json_counters(H));
    json_object_set_new(o, "safety", json_safety(&S->safety));
    rc = json_dumpf(o, fp, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(12));
    json_decref(o);
    fputc('\n', fp);
    if (fp != stdout) {
        if (fclose(fp) != 0) {
            rc = -1;
        }
    } else {
        fflush(fp);
    }
    if (rc != 0) {
        c4gh_cli_file_error("c4g-server", "--json-out", path, errno);
        return -1;
    }
    return 0;
}
