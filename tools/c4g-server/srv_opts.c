/* SPDX-License-Identifier: MIT */
/* The server's configuration (c4g-server's options): one option table shared by the command line (getopt_long)
 * and the INI file (inih), so every setting has the same name in both. */
#include "srv_core.h"

#include "c4gh_cli.h"
#include "c4gh_textfile.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Strict numbers (lib/host/c4gh_textfile.h); on failure why says what was wrong. */
static int num(const char *s, double lo, double hi, double *out, char *why, size_t whylen)
{
    const c4gh_tf_num_t st = c4gh_tf_parse_double(s, lo, hi, out);
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, s, lo, hi, why, whylen);
        return -1;
    }
    return 0;
}

/* An integer setting: fractions are refused, never truncated. */
static int inum(const char *s, long long lo, long long hi, double *out, char *why, size_t whylen)
{
    long long v = 0;
    const c4gh_tf_num_t st = c4gh_tf_parse_int(s, lo, hi, &v);
    if (st != C4GH_TF_NUM_OK) {
        c4gh_tf_num_explain(st, s, (double)lo, (double)hi, why, whylen);
        return -1;
    }
    *out = (double)v;
    return 0;
}

/* Up to n comma-separated numbers; returns how many, -1 on a bad one. */
static int nums(const char *s, double *v, int n, char *why, size_t whylen)
{
    char buf[256], *tok, *save = NULL;
    int k = 0;
    if (strlen(s) >= sizeof buf) {
        snprintf(why, whylen, "longer than %u bytes", (unsigned)sizeof buf - 1U);
        return -1;
    }
    strcpy(buf, s);
    for (tok = strtok_r(buf, ",:", &save); tok != NULL; tok = strtok_r(NULL, ",:", &save)) {
        if (k >= n) {
            snprintf(why, whylen, "more than %d values", n);
            return -1;
        }
        if (num(tok, -1e12, 1e12, &v[k], why, whylen) != 0) {
            return -1;
        }
        k++;
    }
    return k;
}

/* 1/yes/true or 0/no/false; -1 for anything else. */
static int flag(const char *val)
{
    if (strcmp(val, "1") == 0 || strcmp(val, "yes") == 0 || strcmp(val, "true") == 0) {
        return 1;
    }
    if (strcmp(val, "0") == 0 || strcmp(val, "no") == 0 || strcmp(val, "false") == 0) {
        return 0;
    }
    return -1;
}

void srv_config_default(srv_config_t *c)
{
    uint32_t a;
    memset(c, 0, sizeof *c);
    strcpy(c->bind_addr, "0.0.0.0");
    c->port = C4G_DEFAULT_PORT;
    strcpy(c->ctrl_addr, "10.2.12.150"); /* manual 7.1: SMP+ = IPADDRESS_DSA - 4 */
    c->num_policy = C4G_NUM_PLUS_ONE;
    c->az_lim_max = (double)C4G_AZLIM_MAX_DEFAULT;
    c->fe_max = (double)C4G_FOLLOW_ERROR_MAX_DEFAULT;
    c->cpu = -1;
    c->late_us = 500U;
    c->inject_axis = 0;
    for (a = 0U; a < C4G_ARMS; a++) {
        srv_arm_cfg_t *A = &c->arm[a];
        A->axes = (1U << C4G_AXES_PER_ARM) - 1U;
        A->src = SRC_SINE;
        A->sine_amp = 0.1;
        A->sine_freq = 0.5;
        A->sine_cycles = 1.0;
        A->offset_amp = 0.05;
        A->offset_ramp = 0.5;
        A->offset_hold = 0.5;
        A->vel_amp = 0.0005;
        A->vel_freq = 1.0;
        A->vel_cycles = 1.0;
        A->duration = 2.0;
        A->kp = 30.0;
        A->kd = 200.0;
        A->ki = 300.0;
        A->exit_open = 1;
    }
}

/* ---- the settings table: one row per setting, from which the command line (getopt's
 * table and --help, through lib/host/c4gh_cli.h) and the INI keys derive */

#define SW_CLI 1U /* a command-line option */
#define SW_INI 2U /* an INI key */
#define SW_ARM 4U /* per arm: the destination is in srv_arm_cfg_t */
#define SW_CAP 8U /* --capture's (command line only): not among the options c4g-replay rerun
                     passes after "--" */
#define SW_REP 16U /* also a row of --replay-rerun's own options (SRV_CLI_CAPTURE) */
#define SW_BOTH (SW_CLI | SW_INI)

typedef enum srv_kind {
    SK_FLAG,   /* int: 1/0, yes/no, true/false (command line: no value, 1) */
    SK_INT,    /* integer in [lo, hi] into an int */
    SK_UINT,   /* integer in [lo, hi] into an unsigned */
    SK_NUM,    /* finite number in [lo, hi] into a double */
    SK_STR,    /* text shorter than cap bytes */
    SK_PATH,   /* a file name: not empty, shorter than cap bytes */
    SK_CALL,   /* the row's handler */
    SK_ARM,    /* --arm: the arm following per-arm options apply to (command line) */
    SK_CONFIG  /* --config: an INI file (command line) */
} srv_kind_t;

/* A handler: 0, or -1 with why filled when it knows more than "bad value". */
typedef int (*srv_set_fn)(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                          size_t whylen);

typedef struct srv_setting {
    const char *name;   /* long option and INI key */
    int short_name;     /* 0: none */
    const char *arg;    /* --help placeholder; NULL: a flag on the command line */
    unsigned where;     /* SW_* */
    srv_kind_t kind;
    double lo, hi;      /* SK_INT, SK_UINT, SK_NUM */
    size_t off, cap;    /* destination in srv_config_t (srv_arm_cfg_t with SW_ARM), size */
    srv_set_fn fn;      /* SK_CALL */
    const char *want;   /* what a good value looks like (error messages) */
    const char *help;   /* --help text (continuation lines indented to the text column) */
} srv_setting_t;

#define FLAG_WANT "1/0, yes/no or true/false"

static int set_num_policy(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                          size_t whylen)
{
    (void)A, (void)why, (void)whylen;
    if (strcmp(val, "plus-one") == 0) {
        c->num_policy = C4G_NUM_PLUS_ONE;
    } else if (strcmp(val, "plus1") == 0) {
        /* the spelling before the tools shared one vocabulary (docs/cli.md) */
        fprintf(stderr, "c4g-server: --num-policy plus1 is spelt plus-one now, as in the other tools "
                        "(plus1 is accepted until 3.0)\n");
        c->num_policy = C4G_NUM_PLUS_ONE;
    } else if (strcmp(val, "echo") == 0) {
        c->num_policy = C4G_NUM_ECHO;
    } else {
        return -1;
    }
    return 0;
}

static int set_lost_timeout(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                            size_t whylen)
{
    double v;
    (void)A;
    if (num(val, 1, 600000, &v, why, whylen) != 0) {
        return -1;
    }
    c->lost_timeout_ns = (uint64_t)(v * 1e6);
    return 0;
}

static int set_rt(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    (void)A, (void)why, (void)whylen;
    if (flag(val) < 0) {
        return -1;
    }
    if (flag(val) == 1) { /* "rt = 0" in a file must not switch real time on */
        c->mlock = 1;
        if (c->prio == 0) {
            c->prio = 80;
        }
    }
    return 0;
}

/* --json / -j: the JSON summary on stdout (--json-out -). In an INI file "json = FILE" is the
 * old spelling of json-out (until 3.0): a value that is no flag word is taken as the file. */
static int set_json(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    (void)A;
    if (strcmp(val, "1") == 0 || strcmp(val, "true") == 0 || strcmp(val, "yes") == 0 ||
        strcmp(val, "on") == 0) {
        strcpy(c->json_path, "-");
        return 0;
    }
    if (strcmp(val, "0") == 0 || strcmp(val, "false") == 0 || strcmp(val, "no") == 0 ||
        strcmp(val, "off") == 0) {
        return 0;
    }
    if (val[0] == '\0' || strlen(val) >= sizeof c->json_path) {
        snprintf(why, whylen, "want a flag word, or (old spelling of json-out) a file path");
        return -1;
    }
    fprintf(stderr, "c4g-server: note: json = %s: the summary's file is json-out now (json is "
            "the flag for stdout, as in every tool); taken as json-out until 3.0\n", val);
    strcpy(c->json_path, val);
    return 0;
}

static int set_moni_type(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                         size_t whylen)
{
    double v;
    (void)A;
    if (inum(val, 0, 24, &v, why, whylen) != 0 || (v != 0.0 && v < 19.0)) {
        return -1;
    }
    c->moni_type = (int)v;
    return 0;
}

/* A whole number >= 1 (counts and packet numbers given as lists of numbers). */
static int whole(double v)
{
    return v >= 1 && v == floor(v);
}

static int set_skip(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    double v[2];
    const int k = nums(val, v, 2, why, whylen);
    (void)A;
    if (k < 1 || !whole(v[0]) || (k == 2 && !whole(v[1]))) {
        return -1;
    }
    c->skip_at = (uint64_t)v[0];
    c->skip_count = (k == 2) ? (uint64_t)v[1] : 1U;
    return 0;
}

/* 505@N or 508@N[:AXIS], each part a strict integer */
static int set_inject(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                      size_t whylen)
{
    char buf[64], *at, *ax;
    long long mode = 0, n = 0, axis = 1;
    (void)A, (void)why, (void)whylen;
    if (strlen(val) >= sizeof buf) {
        return -1;
    }
    strcpy(buf, val);
    at = strchr(buf, '@');
    if (at == NULL) {
        return -1;
    }
    *at++ = '\0';
    ax = strchr(at, ':');
    if (ax != NULL) {
        *ax++ = '\0';
    }
    if (c4gh_tf_parse_int(buf, 505, 508, &mode) != C4GH_TF_NUM_OK || (mode != 505 && mode != 508) ||
        c4gh_tf_parse_int(at, 1, 1000000000000LL, &n) != C4GH_TF_NUM_OK ||
        (ax != NULL && (mode != 508 || c4gh_tf_parse_int(ax, 1, 20, &axis) != C4GH_TF_NUM_OK))) {
        return -1;
    }
    c->inject_mode = (int)mode;
    c->inject_at = (uint64_t)n;
    c->inject_axis = (int)axis - 1;
    return 0;
}

static int set_freeze(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                      size_t whylen)
{
    double v[2];
    const int k = nums(val, v, 2, why, whylen);
    (void)A;
    if (k != 2 || !whole(v[0]) || v[1] < 0 || v[1] > 60000) {
        return -1;
    }
    c->freeze_at = (uint64_t)v[0];
    c->freeze_ms = v[1];
    return 0;
}

/* Each file names its arm(s): the files add up, up to one per arm. */
static int set_ff(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    (void)A;
    if (val[0] == '\0' || strlen(val) >= sizeof c->ff_path[0]) {
        return -1;
    }
    if (c->n_ff >= SRV_MAX_FF_FILES) {
        snprintf(why, whylen, "more than %u parameter files", SRV_MAX_FF_FILES);
        return -1;
    }
    strcpy(c->ff_path[c->n_ff++], val);
    return 0;
}

static int set_axes(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    char buf[128], *tok, *save = NULL;
    uint32_t mask = 0U;
    double v;
    (void)c;
    if (strcmp(val, "all") == 0) {
        A->axes = (1U << C4G_AXES_PER_ARM) - 1U;
        return 0;
    }
    if (strlen(val) >= sizeof buf) {
        return -1;
    }
    strcpy(buf, val);
    for (tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
        if (inum(tok, 1, 10, &v, why, whylen) != 0) {
            return -1;
        }
        mask |= 1U << (uint32_t)(v - 1.0);
    }
    if (mask == 0U) {
        return -1;
    }
    A->axes = mask;
    return 0;
}

static int set_sine(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    double v[3];
    const int k = nums(val, v, 3, why, whylen);
    (void)c;
    if (k < 2 || v[1] <= 0 || (k == 3 && v[2] <= 0)) {
        return -1;
    }
    A->src = SRC_SINE;
    A->sine_amp = v[0];
    A->sine_freq = v[1];
    A->sine_cycles = (k == 3) ? v[2] : 1.0;
    return 0;
}

static int set_hold(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    (void)c, (void)why, (void)whylen;
    if (flag(val) < 0) {
        return -1;
    }
    if (flag(val) == 1) {
        A->src = SRC_NONE;
    }
    return 0;
}

static int set_traj(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    (void)c, (void)why, (void)whylen;
    if (strlen(val) >= sizeof A->traj_path || val[0] == '\0') {
        return -1;
    }
    strcpy(A->traj_path, val);
    A->src = SRC_FILE;
    return 0;
}

static int set_offset(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                      size_t whylen)
{
    double v[3];
    const int k = nums(val, v, 3, why, whylen);
    (void)c;
    if (k < 2 || v[1] < 0 || (k == 3 && v[2] < 0)) {
        return -1;
    }
    A->offset_amp = v[0];
    A->offset_ramp = v[1];
    A->offset_hold = (k == 3) ? v[2] : 0.5;
    return 0;
}

static int set_vel(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why, size_t whylen)
{
    double v[3];
    const int k = nums(val, v, 3, why, whylen);
    (void)c;
    if (k < 2 || v[1] <= 0 || (k == 3 && !whole(v[2]))) {
        return -1;
    }
    A->vel_amp = v[0];
    A->vel_freq = v[1];
    A->vel_cycles = (k == 3) ? v[2] : 1.0;
    return 0;
}

static int set_gains(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                     size_t whylen)
{
    double v[3];
    const int k = nums(val, v, 3, why, whylen);
    (void)c;
    if (k < 2 || v[0] < 0 || v[1] < 0 || (k == 3 && v[2] < 0)) {
        return -1;
    }
    A->kp = v[0];
    A->kd = v[1];
    A->ki = (k == 3) ? v[2] : 0.0;
    return 0;
}

static int set_no_exit(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                       size_t whylen)
{
    (void)c, (void)why, (void)whylen;
    if (flag(val) < 0) {
        return -1;
    }
    A->exit_open = !flag(val);
    return 0;
}

static int set_stroke(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                      size_t whylen)
{
    double v[2];
    const int k = nums(val, v, 2, why, whylen);
    int j;
    (void)c;
    if (k != 2 || v[0] >= v[1]) {
        return -1;
    }
    for (j = 0; j < (int)C4G_AXES_PER_ARM; j++) {
        A->pos_min[j] = v[0];
        A->pos_max[j] = v[1];
    }
    A->have_stroke = 1;
    return 0;
}

/* --capture-ports LIST: comma-separated PC ports 1..65535, at most 8 (as c4g-replay's --port). */
static int set_capture_ports(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                             size_t whylen)
{
    const char *p = val;
    unsigned n = 0U;
    (void)A;
    if (strlen(val) >= sizeof c->cap.ports) {
        snprintf(why, whylen, "longer than %u bytes", (unsigned)sizeof c->cap.ports - 1U);
        return -1;
    }
    while (*p != '\0') {
        char item[16];
        const size_t k = strcspn(p, ",");
        long long port = 0;
        if (k == 0U || k >= sizeof item) {
            snprintf(why, whylen, "want ports 1..65535 separated by commas");
            return -1;
        }
        memcpy(item, p, k);
        item[k] = '\0';
        if (c4gh_tf_parse_int(item, 1, 65535, &port) != C4GH_TF_NUM_OK) {
            snprintf(why, whylen, "'%s' is not a port 1..65535", item);
            return -1;
        }
        if (++n > SRV_CAPTURE_MAX_PORTS) {
            snprintf(why, whylen, "at most %u ports", SRV_CAPTURE_MAX_PORTS);
            return -1;
        }
        p += k;
        if (*p == ',') {
            p++;
        }
    }
    if (n == 0U) {
        snprintf(why, whylen, "no port given");
        return -1;
    }
    strcpy(c->cap.ports, val);
    return 0;
}

static int set_behaviour(srv_config_t *c, srv_arm_cfg_t *A, const char *val, char *why,
                         size_t whylen)
{
    (void)A, (void)why, (void)whylen;
    if (strcmp(val, "server") == 0) {
        c->cap.echo = 0;
    } else if (strcmp(val, "echo") == 0) {
        c->cap.echo = 1;
    } else {
        return -1;
    }
    return 0;
}

#define NL "\n                               " /* a --help continuation line */
#define SRV_MAX_ARGS 4096 /* command-line words c4g-server reads */
#define G(m) offsetof(srv_config_t, m), sizeof(((srv_config_t *)0)->m)
#define P(m) offsetof(srv_arm_cfg_t, m), sizeof(((srv_arm_cfg_t *)0)->m)
#define NONE 0, 0

static const srv_setting_t settings[] = {
    /* network and session */
    {"port", 'p', "N", SW_BOTH, SK_UINT, 1, 65535, G(port), NULL, "a UDP port 1..65535",
     "UDP port to bind (default 1000)"},
    {"bind", 'b', "ADDR", SW_BOTH, SK_STR, 0, 0, G(bind_addr), NULL, "an IPv4 address",
     "local address (default 0.0.0.0)"},
    {"controller", 0, "ADDR", SW_BOTH, SK_STR, 0, 0, G(ctrl_addr), NULL,
     "an IPv4 address or 'any'",
     "accept packets only from ADDR (default 10.2.12.150, the" NL
     "manual's SMP+ address); 'any' accepts every source." NL
     "Other sources are dropped and counted (\"foreign\")."},
    {"num-policy", 0, "P", SW_BOTH, SK_CALL, 0, 0, NONE, set_num_policy,
     "plus-one (field, default) or echo (manual)",
     "plus-one (field library, default: reply NUM+1, 0x7FFF->1)" NL
     "or echo (manual text: reply with the same NUM)"},
    {"lost-timeout-ms", 0, "N", SW_BOTH, SK_CALL, 0, 0, NONE, set_lost_timeout,
     "milliseconds 1..600000",
     "silence that ends the session (default 1000 ms; shorter" NL
     "silences are reported and ridden out)"},
    {"az-lim-max", 0, "A", SW_BOTH, SK_NUM, 0.001, 1e5, G(az_lim_max), NULL,
     "amperes 0.001..100000",
     "the largest AzLim (axis current limit) an init packet may" NL
     "carry on an open axis; above it the packet is refused" NL
     "(default 200 A: set this cell's largest)"},
    {"fe-max", 0, "T", SW_BOTH, SK_NUM, 0.001, 1e6, G(fe_max), NULL,
     "motor turns 0.001..1000000",
     "the largest FollowError window an init packet may carry" NL
     "(default 50 turns; 0 in the packet stays \"no threshold\")"},
    {"idle-timeout", 0, "S", SW_BOTH, SK_NUM, 0, 1e7, G(idle_timeout), NULL, "seconds >= 0",
     "give up if no packet at all arrives within S s (default: wait)"},
    {"max-seconds", 0, "S", SW_BOTH, SK_NUM, 0, 1e7, G(max_seconds), NULL, "seconds >= 0",
     "stop after S s in total (default: no limit)"},
    {"persist", 0, NULL, SW_BOTH, SK_FLAG, 0, 0, G(persist), NULL, FLAG_WANT,
     "keep serving after 504 or a lost controller"},
    {"config", 'c', "FILE", SW_CLI, SK_CONFIG, 0, 0, NONE, NULL, "an INI file",
     "INI file: [server] [rt] [output] [test] sections take the" NL
     "long option names as keys, [arm1]..[arm4] the per-arm ones"},
    /* real time */
    {"rt", 0, NULL, SW_BOTH, SK_CALL, 0, 0, NONE, set_rt, FLAG_WANT,
     "--mlock and SCHED_FIFO priority 80"},
    {"mlock", 0, NULL, SW_BOTH, SK_FLAG, 0, 0, G(mlock), NULL, FLAG_WANT,
     "mlockall(MCL_CURRENT|MCL_FUTURE) and prefault the stack"},
    {"prio", 0, "N", SW_BOTH, SK_INT, 0, 99, G(prio), NULL,
     "a SCHED_FIFO priority 1..99 (0 = off)", "SCHED_FIFO priority 1..99 for the packet loop"},
    {"cpu", 0, "N", SW_BOTH, SK_INT, -1, 1023, G(cpu), NULL, "a CPU number >= 0 (-1 = off)",
     "pin the packet loop to CPU N"},
    {"rt-strict", 0, NULL, SW_BOTH, SK_FLAG, 0, 0, G(rt_strict), NULL, FLAG_WANT,
     "a refused real-time setting is fatal (exit 1); by default" NL
     "the server says what was refused and why, and continues"},
    {"spin", 0, NULL, SW_BOTH, SK_FLAG, 0, 0, G(spin), NULL, FLAG_WANT,
     "busy-poll the socket (lowest latency, burns a CPU)"},
    {"poll-us", 0, "N", SW_BOTH, SK_UINT, 0, 100000, G(poll_us), NULL,
     "microseconds 0..100000",
     "non-blocking recvfrom + clock_nanosleep(TIMER_ABSTIME) every" NL
     "N us instead of a blocking wait"},
    {"late-us", 0, "N", SW_BOTH, SK_UINT, 1, 1000000, G(late_us), NULL,
     "microseconds 1..1000000", "reply deadline counted as \"late\" (default 500, T_CYCLE1)"},
    /* per-arm behaviours */
    {"arm", 0, "N", SW_CLI, SK_ARM, 1, C4G_ARMS, NONE, NULL, "1..4",
     "following per-arm options (--axes .. --fe-limit) apply to" NL
     "arm N (1..4); before any --arm they apply to every arm"},
    {"axes", 0, "LIST", SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_axes,
     "a list of logical axes 1..10 (e.g. 1,2,3) or 'all'",
     "logical axes driven, e.g. 1,2,3 (default all)"},
    {"sine", 0, "A,F[,C]", SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_sine,
     "AMP,FREQ[,CYCLES] (turns, Hz > 0, cycles > 0)",
     "modes 1/4/5: raised cosine A turns, F Hz, C cycles (default" NL
     "0.1,0.5,1), then EXIT_FROM_OPEN"},
    {"traj", 0, "FILE", SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_traj,
     "a trajectory CSV file", "modes 1/4/5: follow a trajectory CSV (t,ax1..axN offsets)"},
    {"hold", 0, NULL, SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_hold, FLAG_WANT,
     "modes 1/4/5: hold the entry position for --duration"},
    {"offset", 0, "A,R[,H]", SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_offset,
     "AMP,RAMP[,HOLD] (turns, s >= 0, s >= 0)",
     "mode 7: offset step to A turns over R s, hold H s (0.05,0.5,0.5)"},
    {"vel", 0, "A,F[,C]", SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_vel,
     "AMP,FREQ[,CYCLES] (delta turns/tick, Hz > 0, whole cycles >= 1)",
     "mode 8: zero-mean velocity addition (0.0005,1,1)"},
    {"ff", 0, "FILE", SW_BOTH, SK_CALL, 0, 0, NONE, set_ff,
     "a mode-9 parameter file (at most 4, under 512 bytes each)",
     "mode 9: current feedforward parameters: a c4g-ident model" NL
     "(INI, one arm per file: per-axis, or the arm's rigid-body" NL
     "model) or the line format; repeat for more arms (up to 4 files)"},
    {"ff-ext1", 0, NULL, SW_BOTH | SW_ARM, SK_FLAG, 0, 0, P(ff_ext1), NULL, FLAG_WANT,
     "mode 9: add the controller's dynamic-model current (EXT1) to D5" NL
     "(with or without --ff; not on the axes of a ctrl or rigid-body file)"},
    {"duration", 0, "S", SW_BOTH | SW_ARM, SK_NUM, 0, 1e7, P(duration), NULL, "seconds >= 0",
     "modes 1 (hold), 2, 9: time before EXIT_FROM_OPEN (default 2)"},
    {"gains", 0, "KP,KD[,KI]", SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_gains,
     "KP,KD[,KI] (>= 0)", "modes 1/2 joint PD(+I) [A/turn, A/(turn/tick), A/(turn s)]"},
    {"i-max", 0, "A", SW_BOTH | SW_ARM, SK_NUM, 0, 1e6, P(i_max), NULL, "amperes >= 0",
     "integrator limit (anti-windup), default AzLim"},
    {"scs", 0, "S", SW_BOTH | SW_ARM, SK_NUM, 0, 1e4, P(scs), NULL, "seconds >= 0",
     "soft-control-switching ramp of the PC current limit (0 = off)"},
    {"no-exit", 0, NULL, SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_no_exit, FLAG_WANT,
     "never send EXIT_FROM_OPEN (the controller ends the mode)"},
    {"exit-open", 0, NULL, SW_INI | SW_ARM, SK_FLAG, 0, 0, P(exit_open), NULL, FLAG_WANT,
     "send EXIT_FROM_OPEN when the behaviour is done (INI only)"},
    {"max-step", 0, "T", SW_BOTH | SW_ARM, SK_NUM, 0, 1e6, P(max_step), NULL,
     "turns per tick >= 0", "reference continuity limit [turns/tick] -> 505 (0 = off)"},
    {"stroke", 0, "MIN,MAX", SW_BOTH | SW_ARM, SK_CALL, 0, 0, NONE, set_stroke,
     "MIN,MAX in motor turns, MIN < MAX", "stroke ends for PC absolute references [turns] -> 505"},
    {"fe-limit", 0, "T", SW_BOTH | SW_ARM, SK_NUM, 0, 1e6, P(fe_limit), NULL,
     "turns >= 0 (0 = the init packet's FollowError)",
     "following-error threshold override (default: init packet)"},
    /* outputs */
    {"pcap", 0, "FILE", SW_BOTH, SK_PATH, 0, 0, G(pcap_path), NULL,
     "a file path (under 512 bytes)", "every datagram in and out (written by the log thread)"},
    {"moni", 0, "FILE", SW_BOTH, SK_PATH, 0, 0, G(moni_path), NULL,
     "a file path (under 512 bytes)", "moni CSV, one row per axis per cyclic packet"},
    {"moni-type", 0, "N", SW_BOTH, SK_CALL, 0, 0, NONE, set_moni_type,
     "0 (full rows) or a manual moni type 19..24",
     "0 = full rx/tx rows (default), 19..24 = the manual's types"},
    {"json-out", 0, "FILE", SW_BOTH | SW_REP, SK_PATH, 0, 0, G(json_path), NULL,
     "a file path (under 512 bytes)", "JSON summary at exit into FILE ('-' = stdout)"},
    {"json", 'j', NULL, SW_BOTH | SW_REP, SK_CALL, 0, 0, NONE, set_json, FLAG_WANT,
     "JSON summary at exit on stdout (--json-out -)"},
    {"log", 0, "FILE", SW_BOTH, SK_PATH, 0, 0, G(log_path), NULL,
     "a file path (under 512 bytes)", "log lines (default stderr)"},
    {"verbose", 'v', NULL, SW_BOTH, SK_FLAG, 0, 0, G(verbose), NULL, FLAG_WANT,
     "log every mode change and session event"},
    {"quiet", 'q', NULL, SW_BOTH, SK_FLAG, 0, 0, G(quiet), NULL, FLAG_WANT,
     "no log lines, no text report (JSON still written)"},
    /* test hooks */
    {"skip-replies", 0, "AT[,N]", SW_BOTH, SK_CALL, 0, 0, NONE, set_skip,
     "AT[,COUNT] (cyclic packet number >= 1, count >= 1)",
     "do not answer cyclic packets AT..AT+N-1"},
    {"inject", 0, "505@N|508@N[:AXIS]", SW_BOTH, SK_CALL, 0, 0, NONE, set_inject,
     "505@N or 508@N[:AXIS] (N = cyclic packet number, AXIS = OPEN index 1..20)",
     "request drive off / following error at packet N"},
    {"freeze", 0, "AT,MS", SW_BOTH, SK_CALL, 0, 0, NONE, set_freeze,
     "AT,MS (cyclic packet number, pause in ms)",
     "active freezing: at packet AT reply 500, pause MS ms, then" NL
     "re-activate with EXIT_FROM_OPEN"},
    /* a capture instead of the socket (capture.c) */
    {"capture", 0, "FILE", SW_CLI | SW_CAP, SK_PATH, 0, 0, G(cap.path), NULL,
     "a pcap or pcapng file (under 4096 bytes)",
     "no socket: the controller packets of a capture at top" NL
     "speed with their recorded times; every reply compared" NL
     "with the recorded one (--json: the report as JSON)"},
    {"session", 0, "N", SW_CLI | SW_CAP, SK_UINT, 1, SRV_CAPTURE_MAX_SESSIONS, G(cap.session), NULL,
     "a session number 1..64", "--capture: only session N (default: every session of" NL
     "the first controller in the file)"},
    {"capture-ports", 0, "LIST", SW_CLI | SW_CAP, SK_CALL, 0, 0, NONE, set_capture_ports,
     "PC ports 1..65535 separated by commas",
     "--capture: PC ports of C4G Open flows in it (1000,1001)"},
    {"behaviour", 0, "NAME", SW_CLI | SW_CAP, SK_CALL, 0, 0, NONE, set_behaviour,
     "server or echo", "--capture: server (the behaviours configured, default) or" NL
     "echo (no axis driven: NUM, mode echo, neutral replies)"},
    {"tolerance", 0, "X", SW_CLI | SW_CAP, SK_NUM, 0, 1e9, G(cap.tolerance), NULL,
     "a number 0..1e9", "--capture: float fields within X count as equal" NL
     "(default 0: bit-exact)"},
    {"list", 0, "N", SW_CLI | SW_CAP, SK_UINT, 0, 1e9, G(cap.list), NULL, "a count 0..1e9",
     "--capture: print the first N divergences, one per line"},
    {"no-progress", 0, NULL, SW_CLI | SW_CAP, SK_FLAG, 0, 0, G(cap.no_progress), NULL, FLAG_WANT,
     "--capture: no progress bar on a terminal"},
    {"replay-rerun", 0, NULL, SW_CLI | SW_CAP, SK_FLAG, 0, 0, G(cap.rerun), NULL, FLAG_WANT,
     "--capture: messages and report as c4g-replay rerun (its" NL
     "front end runs c4g-server so)"},
};

#define N_SETTINGS (sizeof settings / sizeof settings[0])

/* A number-like row into its destination. 0, or -1 (why filled). */
static int store_number(const srv_setting_t *row, void *dst, const char *val, char *why,
                        size_t whylen)
{
    double v;
    if (row->kind == SK_NUM) {
        return num(val, row->lo, row->hi, (double *)dst, why, whylen);
    }
    if (inum(val, (long long)row->lo, (long long)row->hi, &v, why, whylen) != 0) {
        return -1;
    }
    if (row->kind == SK_INT) {
        *(int *)dst = (int)v;
    } else {
        *(unsigned *)dst = (unsigned)v;
    }
    return 0;
}

/* One row's value for arm @p arm (0..3). 0, or -1 with why (maybe empty: "bad value"). */
static int apply_row(srv_config_t *c, const srv_setting_t *row, int arm, const char *val,
                     char *why, size_t whylen)
{
    srv_arm_cfg_t *A = &c->arm[(arm >= 0 && arm < (int)C4G_ARMS) ? arm : 0];
    void *dst = ((row->where & SW_ARM) != 0U) ? (void *)((char *)A + row->off)
                                              : (void *)((char *)c + row->off);
    why[0] = '\0';
    switch (row->kind) {
    case SK_FLAG:
        if (flag(val) < 0) {
            return -1;
        }
        *(int *)dst = flag(val);
        return 0;
    case SK_INT:
    case SK_UINT:
    case SK_NUM:
        return store_number(row, dst, val, why, whylen);
    case SK_STR:
    case SK_PATH:
        if (strlen(val) >= row->cap || (row->kind == SK_PATH && val[0] == '\0')) {
            return -1;
        }
        memcpy(dst, val, strlen(val) + 1U);
        return 0;
    case SK_CALL:
        return row->fn(c, A, val, why, whylen);
    default:
        return -1; /* SK_ARM, SK_CONFIG: command line only */
    }
}

/* Apply a row to arm @p arm, or to every arm when arm < 0 (settings of no arm: once).
 * 0, or -1 with why (maybe empty: "bad value"). */
static int apply_arms(srv_config_t *c, const srv_setting_t *row, int arm, const char *val,
                      char *why, size_t whylen)
{
    const int lo = (arm < 0) ? 0 : arm;
    const int hi = (arm < 0 && (row->where & SW_ARM) != 0U) ? (int)C4G_ARMS - 1 : lo;
    int a;
    for (a = lo; a <= hi; a++) {
        if (apply_row(c, row, a, val, why, whylen) != 0) {
            return -1;
        }
    }
    return 0;
}

/* "NAME: WHY (want W)", or "NAME: bad value 'VALUE' (want W)" when why is empty. */
static void bad_value(const srv_setting_t *row, const char *val, const char *why, char *err,
                      size_t errlen)
{
    char v80[80];
    c4gh_tf_escape(val, strlen(val), v80, sizeof v80);
    if (why[0] != '\0') {
        snprintf(err, errlen, "%s: %s (want %s)", row->name, why, row->want);
    } else {
        snprintf(err, errlen, "%s: bad value '%s' (want %s)", row->name, v80, row->want);
    }
}

static const srv_setting_t *find_setting(const char *name, unsigned where)
{
    size_t i;
    for (i = 0U; i < N_SETTINGS; i++) {
        if ((settings[i].where & where) != 0U && strcmp(settings[i].name, name) == 0) {
            return &settings[i];
        }
    }
    return NULL;
}

/* Apply one setting (an INI key). @p arm is the arm (0..3) per-arm names apply to. Returns
 * 0, -1 for a bad value or -2 for an unknown setting, with a message in err naming the
 * setting and the value. */
int srv_config_apply(srv_config_t *c, const char *name, const char *val, int arm, char *err,
                     size_t errlen)
{
    const srv_setting_t *row = find_setting(name, SW_INI);
    char why[200];
    if (row == NULL) {
        char n[80];
        c4gh_tf_escape(name, strlen(name), n, sizeof n);
        snprintf(err, errlen, "unknown setting '%s'", n);
        return -2;
    }
    if (val == NULL) {
        val = "1"; /* a flag */
    }
    if (apply_arms(c, row, (arm >= 0 && arm < (int)C4G_ARMS) ? arm : 0, val, why,
                   sizeof why) != 0) {
        bad_value(row, val, why, err, errlen);
        return -1;
    }
    return 0;
}

/* ---- the command line (lib/host/c4gh_cli.h), rows derived from the settings */

typedef struct srv_cli {
    srv_config_t *c;
    int arm;  /* -1: per-arm options apply to every arm */
    int pass; /* 1: only --config (the files first), 2: every other option */
} srv_cli_t;

/* -c was --controller ADDR before 2.0 and is --config FILE now, as in every tool. A value of
 * digits and dots (or "any") that names no file is the old spelling: taken as the address
 * until 3.0, with a note (a wrong address is refused as --controller refuses it). 1 when it
 * was (*bad: 0, or -1 with why), 0 for a file. */
static int old_controller(srv_config_t *c, const char *value, char *why, size_t whylen, int *bad)
{
    const srv_setting_t *row = find_setting("controller", SW_CLI);
    char err[300];
    *bad = 0;
    if ((strcmp(value, "any") != 0 && (value[0] == '\0' || strspn(value, "0123456789.") != strlen(value))) ||
        access(value, F_OK) == 0 || row == NULL) {
        return 0;
    }
    fprintf(stderr, "c4g-server: note: -c/--config %s: the controller's address is --controller "
            "%s now (-c is --config FILE in every tool); taken as --controller until 3.0\n",
            value, value);
    if (apply_arms(c, row, -1, value, err, sizeof err) != 0) {
        snprintf(why, whylen, "want %s", row->want);
        *bad = -1;
    }
    return 1;
}

static int on_cli(void *ctx, const c4gh_cli_opt_t *o, const char *value, char *why, size_t whylen)
{
    srv_cli_t *x = ctx;
    const srv_setting_t *row = &settings[o->key];
    char err[600];
    int bad = 0;
    if ((row->kind == SK_CONFIG) != (x->pass == 1)) {
        return 0; /* the other pass's option */
    }
    if (row->kind == SK_ARM) {
        long long v = 0;
        const c4gh_tf_num_t st = c4gh_tf_parse_int(value, (long long)row->lo, (long long)row->hi, &v);
        if (st != C4GH_TF_NUM_OK) {
            c4gh_tf_num_explain(st, value, row->lo, row->hi, why, whylen);
            return -1;
        }
        x->arm = (int)v - 1;
        return 0;
    }
    if (row->kind == SK_CONFIG) {
        if (old_controller(x->c, value, why, whylen, &bad)) {
            return bad;
        }
        if (srv_config_load_ini(x->c, value, err, sizeof err) != 0) {
            snprintf(why, whylen, "%s", err);
            return -1;
        }
        return 0;
    }
    if (apply_arms(x->c, row, x->arm, (value != NULL) ? value : "1", err, sizeof err) != 0) {
        /* the caller names the option and the value: why, and what is wanted */
        if (err[0] != '\0') {
            snprintf(why, whylen, "%s; want %s", err, row->want);
        } else {
            snprintf(why, whylen, "want %s", row->want);
        }
        return -1;
    }
    return 0;
}

/* the --help text both option sets share (without and with the capture options) */
#define USAGE_HEAD \
    "Usage: c4g-server [OPTIONS]\n" \
    "The PC side (UDP server) of the Comau C4G Open protocol. Answers every packet of the\n" \
    "controller (SMP+) with the field library's behaviour: start-up handshake (732-byte\n" \
    "sync replies, 1200-byte init echo), NUM + 1, mode echo, mode-10 copy; and, per arm,\n" \
    "a built-in behaviour for the open mode the controller selects, through the PC-side\n" \
    "safety filter (following error -> 508, current saturation to AzLim, delta-current\n" \
    "clamp, stroke ends and reference continuity -> 505).\n" \
    "\n" \
    "Per-arm behaviours (--axes .. --fe-limit) apply to every arm, or to the arm named by\n"

static const char usage[] =
    USAGE_HEAD
    "the last --arm N. Every long option but --arm and --config is also an INI key.\n";

static const char usage_all[] =
    USAGE_HEAD
    "the last --arm N. Every long option but --arm, --config and --capture .. --replay-rerun\n"
    "is also an INI key.\n";

static const char epilogue[] =
    "Exit codes: 0 ended by 504, 1 setup failure before the session (socket, bind, an\n"
    "output file that cannot be written, thread, refused RT setting with --rt-strict),\n"
    "2 bad option or input file, 3 controller lost, 4\n"
    "--idle-timeout / --max-seconds reached, 130 stopped by SIGINT, 0 by SIGTERM (also\n"
    "with --persist). The chapter 22 timing report, the counters and the safety events are\n"
    "printed at every exit that follows a session (with --persist the counters add up\n"
    "every session since the start, the timing lines are the last session's).\n";

static const char *const examples[] = {
    "c4g-server --rt --cpu 1                          # lab: port 1000, SMP+ 10.2.12.150",
    "c4g-server -p 31000 --controller 127.0.0.1 --json     # loopback against c4g-sim",
    "c4g-server --arm 1 --axes 1,2 --sine 0.2,0.5,2   # mode 4/5 sine on axes 1-2 of arm 1",
    "c4g-server --traj fixtures/server/traj_example.csv --pcap run.pcap --moni run.csv",
    "c4g-server --ff fixtures/server/ff_example.txt --duration 5   # mode 9 feedforward",
    "c4g-server --ff fixtures/server/ff_ident_example.ini --duration 5   # identified model",
    "c4g-server --config fixtures/server/server_example.ini",
    NULL};

/* What c4g-server's own --help adds to the server's (the rows after "--" of c4g-replay
 * rerun keep the texts above). */
static const char epilogue_all[] =
    "Exit codes: 0 ended by 504, 1 setup failure before the session (socket, bind, an\n"
    "output file that cannot be written, thread, refused RT setting with --rt-strict),\n"
    "2 bad option or input file, 3 controller lost, 4\n"
    "--idle-timeout / --max-seconds reached, 130 stopped by SIGINT, 0 by SIGTERM (also\n"
    "with --persist). The chapter 22 timing report, the counters and the safety events are\n"
    "printed at every exit that follows a session (with --persist the counters add up\n"
    "every session since the start, the timing lines are the last session's).\n"
    "With --capture FILE: no socket; one server per run of the recorded controller (a new\n"
    "one where the recorded server would have stopped); socket, real-time and output\n"
    "options other than --json(-out) have no effect. Exit codes then: 0 every reply produced\n"
    "equals the recorded one, 1 some diverge, 2 bad usage or an unreadable capture.\n";

static const char *const examples_all[] = {
    "c4g-server --rt --cpu 1                          # lab: port 1000, SMP+ 10.2.12.150",
    "c4g-server -p 31000 --controller 127.0.0.1 --json     # loopback against c4g-sim",
    "c4g-server --arm 1 --axes 1,2 --sine 0.2,0.5,2   # mode 4/5 sine on axes 1-2 of arm 1",
    "c4g-server --traj fixtures/server/traj_example.csv --pcap run.pcap --moni run.csv",
    "c4g-server --ff fixtures/server/ff_example.txt --duration 5   # mode 9 feedforward",
    "c4g-server --ff fixtures/server/ff_ident_example.ini --duration 5   # identified model",
    "c4g-server --config fixtures/server/server_example.ini",
    "c4g-server --capture fixtures/replay/mode4.pcap --sine 0.25,1,0.5   # a capture, diffed",
    NULL};

/* --json FILE and --json=FILE were the summary's file before 2.0; --json is the flag of every
 * tool now and the file is --json-out. c4g-server takes no operands, so a word after --json
 * that is not an option (or is "-") can only be the old FILE: rewritten to --json-out, with a
 * note, until 3.0. @p out holds argc + 1 pointers; @p eq is the "--json-out=FILE" text. */
static void old_json(int argc, char **argv, char **out, char *eq, size_t eqcap)
{
    int i, noted = 0;
    static char json_out[] = "--json-out";
    for (i = 0; i < argc; i++) {
        const char *a = argv[i];
        out[i] = argv[i];
        if (strcmp(a, "--") == 0) {
            for (i++; i < argc; i++) {
                out[i] = argv[i];
            }
            break;
        }
        if (strncmp(a, "--json=", 7U) == 0 && strlen(a) + 4U < eqcap) {
            (void)snprintf(eq, eqcap, "--json-out=%s", a + 7);
            out[i] = eq;
        } else if (strcmp(a, "--json") == 0 && i + 1 < argc &&
                   (argv[i + 1][0] != '-' || strcmp(argv[i + 1], "-") == 0)) {
            out[i] = json_out;
        } else {
            continue;
        }
        if (!noted++) {
            fprintf(stderr, "c4g-server: note: --json FILE is --json-out FILE now (--json alone is "
                    "the JSON summary on stdout, as in every tool); taken as --json-out until 3.0\n");
        }
    }
    out[argc] = NULL;
}

c4gh_cli_result_t srv_config_cli(srv_config_t *c, const char *tool, const char *version_extra,
                                 srv_cli_rows_t which, int argc, char **argv)
{
    static c4gh_cli_opt_t rows[N_SETTINGS];
    static char *args[SRV_MAX_ARGS + 1];
    static char eq[600];
    c4gh_cli_spec_t spec;
    srv_cli_t x;
    size_t i, n = 0U;
    for (i = 0U; i < N_SETTINGS; i++) {
        const srv_setting_t *s = &settings[i];
        if ((s->where & SW_CLI) == 0U || (which == SRV_CLI_SERVER && (s->where & SW_CAP) != 0U) ||
            (which == SRV_CLI_CAPTURE && (s->where & (SW_CAP | SW_REP)) == 0U)) {
            continue;
        }
        memset(&rows[n], 0, sizeof rows[n]);
        rows[n].name = s->name;
        rows[n].short_name = s->short_name;
        rows[n].kind = C4GH_CLI_CALL;
        rows[n].arg = s->arg;
        rows[n].help = s->help;
        rows[n].fn = on_cli;
        rows[n].key = (int)i;
        n++;
    }
    memset(&spec, 0, sizeof spec);
    spec.tool = tool;
    spec.version_extra = version_extra;
    spec.usage = (which == SRV_CLI_SERVER) ? usage : usage_all;
    spec.opts = rows;
    spec.n_opts = n;
    spec.examples = (which == SRV_CLI_SERVER) ? examples : examples_all;
    spec.epilogue = (which == SRV_CLI_SERVER) ? epilogue : epilogue_all;
    spec.operands_min = 0;
    spec.operands_max = 0;
    x.c = c;
    x.arm = -1;
    if (argc < 0 || argc >= SRV_MAX_ARGS) {
        fprintf(stderr, "%s: more than %d arguments\n", tool, SRV_MAX_ARGS - 1);
        return C4GH_CLI_BAD;
    }
    old_json(argc, argv, args, eq, sizeof eq);
    argv = args;
    /* the files first, then the command line over them, wherever --config stands in it (as
     * the other tools do: docs/cli.md) */
    x.pass = 1;
    {
        const c4gh_cli_result_t r = c4gh_cli_parse(&spec, &x, argc, argv, NULL);
        if (r != C4GH_CLI_RUN) {
            return r;
        }
    }
    x.pass = 2;
    x.arm = -1;
    return c4gh_cli_parse(&spec, &x, argc, argv, NULL);
}

/* ---- the INI file: [server] [rt] [output] [test] take any setting, [arm1]..[arm4] the
 * per-arm ones for that arm only */

static c4gh_tf_ini_rc_t on_ini(void *user, const char *section, const char *name, const char *value,
                          char *msg, size_t msglen)
{
    srv_config_t *c = user;
    char err[300], why[200];
    int arm = -1;
    if (strncmp(section, "arm", 3) == 0 && section[3] >= '1' &&
        section[3] <= (char)('0' + C4G_ARMS) && section[4] == '\0') {
        arm = section[3] - '1';
    } else if (section[0] != '\0' && strcmp(section, "server") != 0 &&
               strcmp(section, "rt") != 0 && strcmp(section, "output") != 0 &&
               strcmp(section, "test") != 0 && strcmp(section, "arms") != 0) {
        char s[80];
        c4gh_tf_escape(section, strlen(section), s, sizeof s);
        snprintf(msg, msglen, "unknown section [%s] (want [server], [rt], [output], [test] or "
                              "[arm1]..[arm4])", s);
        return C4GH_TF_INI_BAD_SECTION;
    }
    {
        const srv_setting_t *row = find_setting(name, SW_INI);
        if (row == NULL) {
            char n[80];
            c4gh_tf_escape(name, strlen(name), n, sizeof n);
            snprintf(msg, msglen, "[%s] unknown setting '%s'", section, n);
            return C4GH_TF_INI_BAD_KEY;
        }
        if (apply_arms(c, row, arm, value, why, sizeof why) != 0) {
            bad_value(row, value, why, err, sizeof err);
            snprintf(msg, msglen, "[%s] %s", section, err);
            return C4GH_TF_INI_BAD_VALUE;
        }
    }
    return C4GH_TF_INI_OK;
}

int srv_config_parse_ini(srv_config_t *c, c4gh_tf_file_t *f, char *err, size_t errlen)
{
    return c4gh_tf_ini_parse(f, on_ini, c, err, errlen);
}

int srv_config_load_ini(srv_config_t *c, const char *path, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    if (c4gh_tf_load(&f, path, C4GH_TF_MAX_INI, err, errlen) != 0) {
        return -1;
    }
    rc = srv_config_parse_ini(c, &f, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}
