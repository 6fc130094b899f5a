/* SPDX-License-Identifier: MIT */
/* c4g-sim command line: one table row per option (lib/host/c4gh_cli.h), the INI file
 * under it, then the checks that need both (addresses, scenario, the controller). */
#include <arpa/inet.h>
#include <netdb.h>
#include <sys/socket.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "c4gh_cli.h"
#include "c4gh_textfile.h"

/* ---- value handlers (C4GH_CLI_CALL rows; ctx is the app) ---------------------- */

/* A path: kept as the argv string. row->key picks the field. */
enum { P_CONFIG = 0, P_SCENARIO, P_CSV, P_PCAP, P_CAPTURE };
static int opt_path(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    app_opts_t *o = &((app_t *)ctx)->o;
    const char **dst[] = {&o->config_path, &o->scenario_path, &o->csv_path, &o->pcap_path,
                          &o->cap.path};
    (void)why;
    (void)wl;
    *dst[row->key] = v;
    return 0;
}

/* An int field of the configuration (row->dest) in row->lo..row->hi. */
static int opt_int(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    long long x = 0;
    const c4gh_tf_num_t st = c4gh_tf_parse_int(v, (long long)row->lo, (long long)row->hi, &x);
    (void)ctx;
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, v, row->lo, row->hi, why, wl);
        return -1;
    }
    *(int *)row->dest = (int)x;
    return 0;
}

static int opt_policy(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    (void)row;
    if (c4g_num_policy_parse(v, &((app_t *)ctx)->cfg.policy) == C4G_OK) {
        return 0;
    }
    snprintf(why, wl, "not plus-one, echo or either");
    return -1;
}

/* "6" or "6,4": open axes 1..n of each arm. */
static int opt_axes(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_config_t *cfg = &((app_t *)ctx)->cfg;
    const char *p = v;
    int arms = 0;
    (void)row;
    while (*p != '\0') {
        char *end;
        const long n = strtol(p, &end, 10);
        if (end == p || n < 1 || n > 10 || arms >= (int)C4G_ARMS || (*end != ',' && *end != '\0')) {
            snprintf(why, wl, "must be 1..4 counts of 1..10, e.g. 6,4");
            return -1;
        }
        cfg->open_mask[arms++] = (1U << n) - 1U;
        p = (*end == ',') ? end + 1 : end;
    }
    cfg->n_arms = arms;
    if (sim_config_axes(cfg) < 0) {
        snprintf(why, wl, "ERR_C4GOPEN: %s (more than 20 axes)", c4g_ctrl_error_message(C4G_CERR_CONFIG));
        return -1;
    }
    return 0;
}

static int opt_startup_mode(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_config_t *cfg = &((app_t *)ctx)->cfg;
    long long m = 0;
    unsigned a, l;
    (void)row;
    if (c4gh_tf_parse_int(v, 0, 1000, &m) != C4GH_TF_NUM_OK || !c4g_mode_is_known((int32_t)m)) {
        snprintf(why, wl, "not a mode code");
        return -1;
    }
    for (a = 0; a < C4G_ARMS; a++) {
        for (l = 0; l < C4G_AXES_PER_ARM; l++) {
            cfg->ax[a][l].startup_mode = (int)m;
        }
    }
    return 0;
}

/* --seed 0..2^64-1 and --ticks 1..ULONG_MAX: wider than C4GH_CLI_INT. */
static int opt_u64(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    sim_config_t *cfg = &((app_t *)ctx)->cfg;
    const int seed = strcmp(row->name, "seed") == 0;
    unsigned long long x = 0;
    const c4gh_tf_num_t st = c4gh_tf_parse_uint(v, seed ? ~0ULL : (unsigned long long)~0UL, &x);
    if (st != C4GH_TF_NUM_OK || (!seed && x == 0U)) {
        snprintf(why, wl, seed ? "not a number 0..18446744073709551615" : "not a positive number");
        return -1;
    }
    if (seed) {
        cfg->seed = (uint64_t)x;
    } else {
        cfg->ticks = (unsigned long)x;
    }
    return 0;
}

static int opt_no_follow(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    (void)row;
    (void)v;
    (void)why;
    (void)wl;
    ((app_t *)ctx)->cfg.check_follow = 0;
    return 0;
}

/* --drop F etc. (row->key: the fault); --delay F[:US]. */
static int opt_fault(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    app_opts_t *o = &((app_t *)ctx)->o;
    char frac[64];
    const char *colon = strchr(v, ':');
    const size_t n = (colon != NULL) ? (size_t)(colon - v) : strlen(v);
    unsigned long long us = o->delay_us;
    int bad = n >= sizeof frac || (colon != NULL && row->key != F_DELAY);
    double f = 0.0;
    if (!bad) {
        memcpy(frac, v, n);
        frac[n] = '\0';
        bad = c4gh_tf_parse_double(frac, 0.0, 1.0, &f) != C4GH_TF_NUM_OK ||
              (colon != NULL && c4gh_tf_parse_uint(colon + 1, 10000000ULL, &us) != C4GH_TF_NUM_OK);
    }
    if (bad) {
        snprintf(why, wl, "not a fraction 0..1%s", row->key == F_DELAY ? " (optionally :US)" : "");
        return -1;
    }
    o->fault_frac[row->key] = f;
    o->delay_us = (unsigned)us;
    return 0;
}

static int opt_pause(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    app_opts_t *o = &((app_t *)ctx)->o;
    char tick[32];
    const char *colon = strchr(v, ':');
    unsigned long long at = 0, len = 0;
    (void)row;
    if (colon == NULL || (size_t)(colon - v) >= sizeof tick) {
        snprintf(why, wl, "must be TICK:N");
        return -1;
    }
    memcpy(tick, v, (size_t)(colon - v));
    tick[colon - v] = '\0';
    if (c4gh_tf_parse_uint(tick, (unsigned long long)~0UL, &at) != C4GH_TF_NUM_OK ||
        c4gh_tf_parse_uint(colon + 1, 1000000ULL, &len) != C4GH_TF_NUM_OK || len == 0U) {
        snprintf(why, wl, "must be TICK:N");
        return -1;
    }
    o->pause_at = (unsigned long)at;
    o->pause_len = (unsigned long)len;
    return 0;
}

static int opt_entry(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    app_opts_t *o = &((app_t *)ctx)->o;
    (void)row;
    if (strcmp(v, "drop") == 0 || strcmp(v, "truncate") == 0) {
        o->entry_fault = (v[0] == 'd') ? 1 : 2;
        return 0;
    }
    snprintf(why, wl, "must be drop or truncate");
    return -1;
}

/* "KG" or "KG@X,Y,Z": a payload's mass and its centre in the flange frame [m]. */
int sim_parse_payload(const char *v, double *mass, double com[3], char *why, size_t wl)
{
    char tmp[128];
    char *at;
    char *part[3];
    int k;
    if (strlen(v) >= sizeof tmp) {
        snprintf(why, wl, "want KG or KG@X,Y,Z");
        return -1;
    }
    strcpy(tmp, v);
    at = strchr(tmp, '@');
    if (at != NULL) {
        *at = '\0';
    }
    if (c4gh_tf_parse_double(tmp, 0.0, 1000.0, mass) != C4GH_TF_NUM_OK) {
        snprintf(why, wl, "mass '%s' is not 0..1000 kg (want KG or KG@X,Y,Z)", tmp);
        return -1;
    }
    com[0] = com[1] = com[2] = 0.0;
    if (at == NULL) {
        return 0;
    }
    part[0] = at + 1;
    part[1] = strchr(part[0], ',');
    part[2] = (part[1] != NULL) ? strchr(part[1] + 1, ',') : NULL;
    if (part[1] == NULL || part[2] == NULL || strchr(part[2] + 1, ',') != NULL) {
        snprintf(why, wl, "centre '%s' is not X,Y,Z (m, flange frame)", at + 1);
        return -1;
    }
    *part[1]++ = '\0';
    *part[2]++ = '\0';
    for (k = 0; k < 3; k++) {
        if (c4gh_tf_parse_double(part[k], -2.0, 2.0, &com[k]) != C4GH_TF_NUM_OK) {
            snprintf(why, wl, "centre coordinate '%s' is not -2..2 m", part[k]);
            return -1;
        }
    }
    return 0;
}

/* --payload and --ctrl-payload (row->key 1). */
static int opt_payload(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    plant_cfg_t *pc = &((app_t *)ctx)->cfg.plant;
    if (row->key == 0) {
        return sim_parse_payload(v, &pc->payload, pc->payload_com, why, wl);
    }
    pc->ctrl_payload_set = 1;
    return sim_parse_payload(v, &pc->ctrl_payload, pc->ctrl_payload_com, why, wl);
}

static int opt_plant(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    plant_cfg_t *pc = &((app_t *)ctx)->cfg.plant;
    (void)row;
    if (strlen(v) >= sizeof pc->path) {
        snprintf(why, wl, "path longer than %zu bytes", sizeof pc->path - 1U);
        return -1;
    }
    strcpy(pc->path, v);
    return 0;
}

/* --ctrl-error K: every model error times K (0: the controller's model is exact). */
static int opt_ctrl_error(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    double k = 0.0;
    (void)row;
    if (c4gh_tf_parse_double(v, 0.0, 5.0, &k) != C4GH_TF_NUM_OK) {
        snprintf(why, wl, "not a factor 0..5");
        return -1;
    }
    plant_cfg_scale_errors(&((app_t *)ctx)->cfg.plant, k);
    return 0;
}

/* --capture-ports LIST: the PC ports of C4G Open flows in the capture (default 1000,1001). */
static int opt_cap_ports(void *ctx, const c4gh_cli_opt_t *row, const char *v, char *why, size_t wl)
{
    cap_opts_t *c = &((app_t *)ctx)->o.cap;
    const char *p = v;
    (void)row;
    c->n_ports = 0U;
    while (*p != '\0') {
        char item[16];
        const size_t n = strcspn(p, ",");
        long long port = 0;
        if (n == 0U || n >= sizeof item) {
            snprintf(why, wl, "want ports 1..65535 separated by commas");
            return -1;
        }
        memcpy(item, p, n);
        item[n] = '\0';
        if (c4gh_tf_parse_int(item, 1, 65535, &port) != C4GH_TF_NUM_OK) {
            snprintf(why, wl, "'%s' is not a port 1..65535", item);
            return -1;
        }
        if (c->n_ports >= C4GH_AN_MAX_PORTS) {
            snprintf(why, wl, "at most %u ports", C4GH_AN_MAX_PORTS);
            return -1;
        }
        c->ports[c->n_ports++] = (uint16_t)port;
        p += n;
        if (*p == ',') {
            p++;
            if (*p == '\0') {
                snprintf(why, wl, "want ports 1..65535 separated by commas");
                return -1;
            }
        }
    }
    return 0;
}

/* ---- the table ------------------------------------------------------------ */

#define ROW_CALL(name, s, arg, help, fn, key) {name, s, C4GH_CLI_CALL, arg, help, NULL, 0, 0, 0, fn, key}

static const char usage_text[] =
    "Usage: c4g-sim [OPTIONS]\n"
    "Simulates a Comau C4G controller running C4G Open: the SMP+ UDP client (start-up\n"
    "handshake, cyclic packets, reply checking, table 17.1 errors), the DSA loops and a\n"
    "robot model, and a PDL2-like scenario. The PC server under test must be running.\n"
    "The INI file (-c) is read first; the other options override it. Fault injection\n"
    "applies to the simulator's own packets (F = fraction 0..1). With --capture the\n"
    "controller's packets come from a recorded session instead of the model: each reply is\n"
    "judged as the model's are and compared with the reply the recorded PC gave.\n";
static const char epilogue_text[] =
    "Exit status: 0 ok; 1 a table 17.1 error was raised (e.g. ERR_C4GOPEN_UDP) or a\n"
    "socket failed; 2 usage, configuration or scenario error; 3 a scenario EXPECT failed\n"
    "or WAIT PC timed out; 4 an output file could not be written; 130 SIGINT, 143 SIGTERM.\n"
    "With --capture: 0 every reply ok and equal to the recorded one; 1 findings or\n"
    "divergences (or a socket error); 2 also an unreadable capture or a session without its start-up;\n"
    "5 nothing answered (the first 10 packets of a pass got nothing back).\n";
static const char *const examples[] = {
    "c4g-sim -p 41000 -S fixtures/scenarios/mode0.scn --json",
    "c4g-sim -p 41000 -T 1 --num-policy plus-one -n 5000 --pcap run.pcap --csv run.csv",
    "c4g-sim -p 41000 -c fixtures/sim/two-arms.ini --drop 0.01 --seed 7 -n 2000",
    "c4g-sim -p 41000 --plant fixtures/sim/smart-six.xml --payload 6@0,0,0.05 -S fixtures/scenarios/mode0.scn",
    "c4g-sim -p 41000 --capture fixtures/replay/mode4.pcap --num-policy plus-one --json", NULL};

#define N_ROWS 46

/* The rows point into this app, so they are built at run time. */
static void opt_rows(app_t *a, c4gh_cli_opt_t *rows)
{
    sim_config_t *c = &a->cfg;
    const c4gh_cli_opt_t r[] = {
        {"server", 's', C4GH_CLI_STRING, "ADDR", "PC server: IPv4 address or host name (default 127.0.0.1)", c->server,
         sizeof c->server, 0, 0, NULL, 0},
        {"port", 'p', C4GH_CLI_UINT, "N", "PC server UDP port (default 1000)", &c->port, 0, 1, 65535, NULL, 0},
        {"bind", 0, C4GH_CLI_STRING, "ADDR", "local address to bind (default 0.0.0.0)", c->bind_addr,
         sizeof c->bind_addr, 0, 0, NULL, 0},
        {"local-port", 0, C4GH_CLI_UINT, "N", "local UDP port (default 0: any)", &c->local_port, 0, 0,
         65535, NULL, 0},
        {"period", 'T', C4GH_CLI_CALL, "MS", "SMP+ period, 1 or 2 ms (default 2, as figure 10.1)",
         &c->period_ms, 0, 1, 2, opt_int, 0},
        {"t-cycle1", 0, C4GH_CLI_UINT, "US", "reply budget; later replies count as late (default 500)",
         &c->t_cycle1_us, 0, 1, 1000000, NULL, 0},
        ROW_CALL("num-policy", 0, "P", "accepted reply NUM: plus-one, echo or either (default either)",
                 opt_policy, 0),
        {"max-miss", 0, C4GH_CLI_UINT, "N", "consecutive missing/wrong replies raising ERR_C4GOPEN_UDP (10)",
         &c->max_miss, 0, 1, 1000000, NULL, 0},
        ROW_CALL("config", 'c', "FILE", "INI file (sections [sim] [model] [arm N] [axis A.L])",
                 opt_path, P_CONFIG),
        ROW_CALL("open-axes", 0, "COUNTS", "open axes per arm, e.g. 6 or 6,4 (default 6: figure 10.1)",
                 opt_axes, 0),
        /* --axes is a list of axis numbers in the other tools: the old spelling until 3.0 */
        ROW_CALL("axes", 0, "COUNTS", NULL, opt_axes, 0),
        ROW_CALL("startup-mode", 0, "M", "start-up mode of every open axis (default 0)",
                 opt_startup_mode, 0),
        ROW_CALL("seed", 0, "N", "random seed for noise and faults (default 1)", opt_u64, 0),
        ROW_CALL("no-follow-check", 0, NULL, "disable the controller's following-error check",
                 opt_no_follow, 0),
        ROW_CALL("plant", 0, "FILE", "arm plant: an MJCF model (fixtures/sim/smart-six.xml) moves axes 1..6 of "
                 "arm 1", opt_plant, 0),
        ROW_CALL("payload", 0, "KG[@X,Y,Z]", "arm plant: payload at the flange, centre in m (default 0)",
                 opt_payload, 0),
        ROW_CALL("ctrl-payload", 0, "KG[@X,Y,Z]", "arm plant: the payload the controller's model assumes "
                 "(default: the true one)", opt_payload, 1),
        ROW_CALL("ctrl-error", 0, "K", "arm plant: controller model errors times K (default 1; 0 exact)",
                 opt_ctrl_error, 0),
        ROW_CALL("scenario", 'S', "FILE", "PDL2-like scenario (fixtures/scenarios/*.scn)", opt_path,
                 P_SCENARIO),
        ROW_CALL("ticks", 'n', "N", "stop after N cyclic ticks (default: when the scenario ends)",
                 opt_u64, 0),
        {"hold", 0, C4GH_CLI_FLAG, NULL, "keep running after the scenario ends (until --ticks or signal)",
         &c->hold, 0, 0, 0, NULL, 0},
        ROW_CALL("drop", 0, "F", "fault: lose a fraction F of the packets", opt_fault, F_DROP),
        ROW_CALL("duplicate", 0, "F", "fault: send a fraction F twice", opt_fault, F_DUP),
        ROW_CALL("reorder", 0, "F", "fault: send a fraction F after the next packet", opt_fault,
                 F_REORDER),
        ROW_CALL("corrupt", 0, "F", "fault: flip a byte in a fraction F", opt_fault, F_CORRUPT),
        ROW_CALL("truncate", 0, "F", "fault: cut a fraction F short", opt_fault, F_TRUNCATE),
        ROW_CALL("delay", 0, "F[:US]", "fault: delay a fraction F by US microseconds (default 300)",
                 opt_fault, F_DELAY),
        ROW_CALL("pause", 0, "TICK:N", "stall: send nothing for N ticks from cyclic tick TICK",
                 opt_pause, 0),
        {"lockstep", 0, C4GH_CLI_FLAG, NULL, "wait for each reply and count it on time (not what a "
         "real C4G does: measures a model apart from the host's latency)", &a->o.lockstep, 0, 0, 0, NULL, 0},
        {"lockstep-wait", 0, C4GH_CLI_UINT, "MS", "--lockstep: a reply later than MS past its tick is missing "
         "(default 500)", &a->o.lockstep_wait_ms, 0, 1, 60000, NULL, 0},
        ROW_CALL("entry-fault", 0, "drop|truncate", "lose or cut the packet that opens each new mode",
                 opt_entry, 0),
        ROW_CALL("csv", 0, "FILE", "per-tick records (moni-style)", opt_path, P_CSV),
        ROW_CALL("pcap", 0, "FILE", "every datagram in both directions (Ethernet/IPv4/UDP)",
                 opt_path, P_PCAP),
        {"json", 'j', C4GH_CLI_FLAG, NULL, "end-of-run summary as JSON on stdout", &a->o.json, 0, 0, 0,
         NULL, 0},
        ROW_CALL("capture", 0, "FILE", "play a recorded session (pcap) instead of the model",
                 opt_path, P_CAPTURE),
        {"session", 0, C4GH_CLI_UINT, "N", "--capture: the session to play (default: the first with its "
         "start-up)", &a->o.cap.session, 0, 1, C4GH_AN_MAX_SESSIONS, NULL, 0},
        {"speed", 0, C4GH_CLI_DOUBLE, "X", "--capture: time scale, 2 plays twice as fast (default 1)",
         &a->o.cap.speed, 0, 0.01, 1000, NULL, 0},
        {"topspeed", 0, C4GH_CLI_FLAG, NULL, "--capture: each packet as soon as the previous one's reply "
         "came", &a->o.cap.topspeed, 0, 0, 0, NULL, 0},
        {"loop", 0, C4GH_CLI_UINT, "N", "--capture: play the session N times, each a full start-up",
         &a->o.cap.loops, 0, 1, 1000000, NULL, 0},
        {"loop-gap", 0, C4GH_CLI_UINT, "MS", "--capture: silence between two passes (default 0)",
         &a->o.cap.gap_ms, 0, 0, 3600000, NULL, 0},
        {"spin-us", 0, C4GH_CLI_UINT, "US", "--capture: busy-wait this long before each packet (100)",
         &a->o.cap.spin_us, 0, 0, 100000, NULL, 0},
        {"tolerance", 0, C4GH_CLI_DOUBLE, "X", "--capture: floats equal within X (default 0: the same "
         "bits)", &a->o.cap.tolerance, 0, 0, 1e30, NULL, 0},
        ROW_CALL("capture-ports", 0, "LIST", "--capture: PC ports of C4G Open flows in it (1000,1001)",
                 opt_cap_ports, 0),
        {"replay-live", 0, C4GH_CLI_FLAG, NULL, "--capture: messages and report as c4g-replay live "
         "(its front end)", &a->o.cap.as_replay_live, 0, 0, 0, NULL, 0},
        {"verbose", 'v', C4GH_CLI_FLAG, NULL, "log events on stderr", &a->o.verbose, 0, 0, 0, NULL, 0},
        {"quiet", 'q', C4GH_CLI_FLAG, NULL, "no summary", &a->o.quiet, 0, 0, 0, NULL, 0},
    };
    /* one row per option: a row added above must raise N_ROWS */
    typedef char rows_fill_the_table[(sizeof r / sizeof r[0] == N_ROWS) ? 1 : -1];
    (void)sizeof(rows_fill_the_table);
    memcpy(rows, r, sizeof r);
}

/* Parse the command line over the configuration: C4GH_CLI_RUN, C4GH_CLI_DONE or C4GH_CLI_BAD. */
static c4gh_cli_result_t opt_parse(app_t *a, int argc, char **argv)
{
    c4gh_cli_opt_t rows[N_ROWS];
    c4gh_cli_spec_t spec;
    opt_rows(a, rows);
    memset(&spec, 0, sizeof spec);
    spec.tool = "c4g-sim";
    spec.version_extra = C4GH_PCAP_ANCHOR();
    spec.usage = usage_text;
    spec.opts = rows;
    spec.n_opts = N_ROWS;
    spec.examples = examples;
    spec.epilogue = epilogue_text;
    spec.operands_min = 0;
    spec.operands_max = 0;
    return c4gh_cli_parse(&spec, a, argc, argv, NULL);
}

static void opt_defaults(app_t *a)
{
    memset(&a->o, 0, sizeof a->o);
    a->o.delay_us = 300U;
    a->o.lockstep_wait_ms = 500U;
    a->o.cap.spin_us = CAP_SPIN_UNSET;
    sim_config_default(&a->cfg);
}

int app_options(app_t *a, int argc, char **argv, int *done)
{
    char err[512];
    c4gh_cli_result_t r;
    *done = 1;
    opt_defaults(a);
    /* Pass 1 finds the INI file (and checks every option); pass 2 sets the options
     * again over the file's values, so the command line overrides it. */
    r = opt_parse(a, argc, argv);
    if (r != C4GH_CLI_RUN) {
        return (r == C4GH_CLI_DONE) ? EXIT_OK : EXIT_USAGE;
    }
    if (a->o.config_path != NULL) {
        const char *path = a->o.config_path;
        opt_defaults(a);
        if (sim_config_load(&a->cfg, path, err, sizeof err) != 0) {
            fprintf(stderr, "c4g-sim: %s\n", err);
            return EXIT_USAGE;
        }
        if (opt_parse(a, argc, argv) != C4GH_CLI_RUN) {
            return EXIT_USAGE;
        }
    }
    *done = 0;
    return EXIT_OK;
}

/* An IPv4 address, or (the server) a host name resolved to one. */
static int parse_addr(const char *what, const char *text, unsigned port, int resolve,
                      struct sockaddr_in *sa)
{
    memset(sa, 0, sizeof *sa);
    sa->sin_family = AF_INET;
    sa->sin_port = htons((uint16_t)port);
    if (inet_pton(AF_INET, text, &sa->sin_addr) == 1) {
        return 0;
    }
    if (resolve) {
        struct addrinfo hints, *res = NULL;
        memset(&hints, 0, sizeof hints);
        hints.ai_family = AF_INET;
        hints.ai_socktype = SOCK_DGRAM;
        if (getaddrinfo(text, NULL, &hints, &res) == 0 && res != NULL) {
            sa->sin_addr = ((const struct sockaddr_in *)(const void *)res->ai_addr)->sin_addr;
            freeaddrinfo(res);
            return 0;
        }
        fprintf(stderr, "c4g-sim: %s address '%s' is neither an IPv4 address nor a host name "
                "with one\n", what, text);
        return -1;
    }
    fprintf(stderr, "c4g-sim: %s address '%s' is not an IPv4 address\n", what, text);
    return -1;
}

int app_addresses(app_t *a)
{
    const sim_config_t *c = &a->cfg;
    if (parse_addr("server", c->server, c->port, 1, &a->srv) != 0 ||
        parse_addr("bind", c->bind_addr, c->local_port, 0, &a->local) != 0) {
        return EXIT_USAGE;
    }
    return EXIT_OK;
}

static int load_scenario(app_t *a)
{
    char err[512];
    c4gh_tf_file_t f;
    int bad;
    if (c4gh_tf_load(&f, a->o.scenario_path, C4GH_TF_MAX_SCENARIO, err, sizeof err) != 0) {
        fprintf(stderr, "c4g-sim: %s\n", err);
        return -1;
    }
    bad = scn_parse(a->o.scenario_path, f.data, f.len, &a->scn, err, sizeof err);
    c4gh_tf_free(&f);
    if (bad != 0) {
        fprintf(stderr, "c4g-sim: %s\n", err);
        return -1;
    }
    return 0;
}

int app_prepare(app_t *a)
{
    const sim_config_t *c = &a->cfg;
    const uint64_t p = (uint64_t)c->period_ms * 1000000U;
    const uint64_t b = (uint64_t)c->t_cycle1_us * 1000U;
    c4g_ctrl_config_t cc;
    if (app_addresses(a) != EXIT_OK) {
        return EXIT_USAGE;
    }
    if (c->plant.path[0] == '\0') {
        plant_cfg_t d;
        plant_cfg_default(&d);
        if (memcmp(&d, &c->plant, sizeof d) != 0) {
            /* a payload or model error given for an arm that is not simulated: a mistake */
            fprintf(stderr, "c4g-sim: --payload, --ctrl-payload, --ctrl-error and the INI [plant] keys "
                    "apply to the arm plant: give --plant FILE (or [plant] file)\n");
            return EXIT_USAGE;
        }
    }
    if (a->o.scenario_path != NULL && load_scenario(a) != 0) {
        return EXIT_USAGE;
    }
    if (sim_init(&a->sim, c, a->o.scenario_path ? &a->scn : NULL, a->o.verbose ? stderr : NULL) != 0) {
        if (a->sim.init_err[0] != '\0') {
            fprintf(stderr, "c4g-sim: %s\n", a->sim.init_err);
        }
        fprintf(stderr, "c4g-sim: %s: %s\n", c4g_ctrl_error_name(a->sim.err[0].code), a->sim.err[0].text);
        return EXIT_USAGE;
    }
    (void)c4gsim_rng_seed(&a->frng, c->seed + 0x5EEDU); /* cannot fail: a->frng exists */
    /* a late start up to min(t-cycle1, period - t-cycle1) still leaves a PC that answers
     * within t-cycle1 before the next tick */
    a->tol_ns = (b < p) ? ((b < p - b) ? b : p - b) : p / 2U;
    memset(&cc, 0, sizeof cc);
    cc.policy = c->policy;
    cc.n_axes = (uint32_t)a->sim.n_axes;
    cc.t_cycle1_ns = b;
    cc.tol_ns = a->tol_ns;
    cc.max_miss = c->max_miss;
    cc.sync_before = c->sync_before;
    cc.sync_after = c->sync_after;
    if (c4g_ctrl_init(&a->cs, &cc) != C4G_OK) {
        fprintf(stderr, "c4g-sim: %u axes: the controller end refuses them\n", (unsigned)cc.n_axes);
        return EXIT_USAGE;
    }
    memset(&a->lat, 0, sizeof a->lat);
    return EXIT_OK;
}
