/* SPDX-License-Identifier: MIT */
/* c4g-server configuration: one option table shared by the command line (getopt_long)
 * and the INI file (inih), so every setting has the same name in both. */
#include "srv.h"

#include "c4g_textfile.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Strict numbers (tools/common/c4g_textfile.h); on failure why says what was wrong. */
static int num(const char *s, double lo, double hi, double *out, char *why, size_t whylen)
{
    const tf_num_t st = tf_parse_double(s, lo, hi, out);
    if (st != TF_NUM_OK) {
        tf_num_explain(st, s, lo, hi, why, whylen);
        return -1;
    }
    return 0;
}

/* An integer setting: fractions are refused, never truncated. */
static int inum(const char *s, long long lo, long long hi, double *out, char *why, size_t whylen)
{
    long long v = 0;
    const tf_num_t st = tf_parse_int(s, lo, hi, &v);
    if (st != TF_NUM_OK) {
        tf_num_explain(st, s, (double)lo, (double)hi, why, whylen);
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

/* Apply one setting. @p arm is the arm (0..3) per-arm names apply to. Returns 0, -1 for
 * a bad value or -2 for an unknown setting, with a message in err naming the setting
 * and the value. */
int srv_config_apply(srv_config_t *c, const char *name, const char *val, int arm, char *err,
                     size_t errlen)
{
    double v[4];
    srv_arm_cfg_t *A = &c->arm[(arm >= 0 && arm < (int)C4G_ARMS) ? arm : 0];
    const char *want = NULL;
    char why[200];
#define IS(n) (strcmp(name, (n)) == 0)
#define FLAG(n, field)                                                   \
    if (IS(n)) {                                                         \
        want = "1/0, yes/no or true/false";                              \
        if (flag(val) < 0) goto bad;                                     \
        field = flag(val);                                               \
        return 0;                                                        \
    }
    why[0] = '\0';
    if (val == NULL) {
        val = "1"; /* a command-line flag */
    }
    if (IS("port")) {
        want = "a UDP port 1..65535";
        if (inum(val, 1, 65535, v, why, sizeof why) != 0) goto bad;
        c->port = (unsigned)v[0];
    } else if (IS("bind")) {
        want = "an IPv4 address";
        if (strlen(val) >= sizeof c->bind_addr) goto bad;
        strcpy(c->bind_addr, val);
    } else if (IS("controller")) {
        want = "an IPv4 address or 'any'";
        if (strlen(val) >= sizeof c->ctrl_addr) goto bad;
        strcpy(c->ctrl_addr, val);
    } else if (IS("num-policy")) {
        want = "plus1 (field, default) or echo (manual)";
        if (strcmp(val, "plus1") == 0) c->num_policy = C4G_NUM_PLUS_ONE;
        else if (strcmp(val, "echo") == 0) c->num_policy = C4G_NUM_ECHO;
        else goto bad;
    } else if (IS("lost-timeout-ms")) {
        want = "milliseconds 1..600000";
        if (num(val, 1, 600000, v, why, sizeof why) != 0) goto bad;
        c->lost_timeout_ns = (uint64_t)(v[0] * 1e6);
    } else if (IS("idle-timeout")) {
        want = "seconds >= 0";
        if (num(val, 0, 1e7, v, why, sizeof why) != 0) goto bad;
        c->idle_timeout = v[0];
    } else if (IS("max-seconds")) {
        want = "seconds >= 0";
        if (num(val, 0, 1e7, v, why, sizeof why) != 0) goto bad;
        c->max_seconds = v[0];
    } else FLAG("persist", c->persist)
    else FLAG("mlock", c->mlock)
    else FLAG("rt-strict", c->rt_strict)
    else FLAG("spin", c->spin)
    else if (IS("rt")) {
        want = "1/0, yes/no or true/false";
        if (flag(val) < 0) goto bad;
        if (flag(val) == 1) { /* "rt = 0" in a file must not switch real time on */
            c->mlock = 1;
            if (c->prio == 0) c->prio = 80;
        }
    } else if (IS("prio")) {
        want = "a SCHED_FIFO priority 1..99 (0 = off)";
        if (inum(val, 0, 99, v, why, sizeof why) != 0) goto bad;
        c->prio = (int)v[0];
    } else if (IS("cpu")) {
        want = "a CPU number >= 0 (-1 = off)";
        if (inum(val, -1, 1023, v, why, sizeof why) != 0) goto bad;
        c->cpu = (int)v[0];
    } else if (IS("poll-us")) {
        want = "microseconds 0..100000";
        if (inum(val, 0, 100000, v, why, sizeof why) != 0) goto bad;
        c->poll_us = (unsigned)v[0];
    } else if (IS("late-us")) {
        want = "microseconds 1..1000000";
        if (inum(val, 1, 1000000, v, why, sizeof why) != 0) goto bad;
        c->late_us = (unsigned)v[0];
    } else if (IS("pcap") || IS("moni") || IS("json") || IS("log")) {
        char *dst = IS("pcap") ? c->pcap_path : IS("moni") ? c->moni_path
                  : IS("json") ? c->json_path : c->log_path;
        want = "a file path (under 512 bytes)";
        if (strlen(val) >= 512U || val[0] == '\0') goto bad;
        strcpy(dst, val);
    } else if (IS("moni-type")) {
        want = "0 (full rows) or a manual moni type 19..24";
        if (inum(val, 0, 24, v, why, sizeof why) != 0 || (v[0] != 0.0 && v[0] < 19.0)) goto bad;
        c->moni_type = (int)v[0];
    } else FLAG("verbose", c->verbose)
    else FLAG("quiet", c->quiet)
    else if (IS("skip-replies")) {
        int k = nums(val, v, 2, why, sizeof why);
        want = "AT[,COUNT] (cyclic packet number >= 1, count >= 1)";
        if (k < 1 || v[0] < 1 || v[0] != floor(v[0]) || (k == 2 && (v[1] < 1 || v[1] != floor(v[1])))) goto bad;
        c->skip_at = (uint64_t)v[0];
        c->skip_count = (k == 2) ? (uint64_t)v[1] : 1U;
    } else if (IS("inject")) {
        /* 505@N or 508@N[:AXIS], each part a strict integer */
        char buf[64], *at, *ax;
        long long mode = 0, n = 0, axis = 1;
        want = "505@N or 508@N[:AXIS] (N = cyclic packet number, AXIS = OPEN index 1..20)";
        if (strlen(val) >= sizeof buf) goto bad;
        strcpy(buf, val);
        at = strchr(buf, '@');
        if (at == NULL) goto bad;
        *at++ = '\0';
        ax = strchr(at, ':');
        if (ax != NULL) *ax++ = '\0';
        if (tf_parse_int(buf, 505, 508, &mode) != TF_NUM_OK || (mode != 505 && mode != 508) ||
            tf_parse_int(at, 1, 1000000000000LL, &n) != TF_NUM_OK ||
            (ax != NULL && (mode != 508 || tf_parse_int(ax, 1, 20, &axis) != TF_NUM_OK))) goto bad;
        c->inject_mode = (int)mode;
        c->inject_at = (uint64_t)n;
        c->inject_axis = (int)axis - 1;
    } else if (IS("freeze")) {
        int k = nums(val, v, 2, why, sizeof why);
        want = "AT,MS (cyclic packet number, pause in ms)";
        if (k != 2 || v[0] < 1 || v[0] != floor(v[0]) || v[1] < 0 || v[1] > 60000) goto bad;
        c->freeze_at = (uint64_t)v[0];
        c->freeze_ms = v[1];
    } else if (IS("ff")) {
        want = "a mode-9 parameter file";
        if (strlen(val) >= sizeof A->ff_path) goto bad;
        strcpy(c->arm[0].ff_path, val); /* one file for all arms (it names the arm) */
    /* ---- per-arm settings */
    } else if (IS("axes")) {
        char buf[128], *tok, *save = NULL;
        uint32_t mask = 0U;
        want = "a list of logical axes 1..10 (e.g. 1,2,3) or 'all'";
        if (strcmp(val, "all") == 0) {
            A->axes = (1U << C4G_AXES_PER_ARM) - 1U;
            return 0;
        }
        if (strlen(val) >= sizeof buf) goto bad;
        strcpy(buf, val);
        for (tok = strtok_r(buf, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
            if (inum(tok, 1, 10, v, why, sizeof why) != 0) goto bad;
            mask |= 1U << (uint32_t)(v[0] - 1.0);
        }
        if (mask == 0U) goto bad;
        A->axes = mask;
    } else if (IS("sine")) {
        int k = nums(val, v, 3, why, sizeof why);
        want = "AMP,FREQ[,CYCLES] (turns, Hz > 0, cycles > 0)";
        if (k < 2 || v[1] <= 0 || (k == 3 && v[2] <= 0)) goto bad;
        A->src = SRC_SINE;
        A->sine_amp = v[0];
        A->sine_freq = v[1];
        A->sine_cycles = (k == 3) ? v[2] : 1.0;
    } else if (IS("hold")) {
        want = "1/0, yes/no or true/false";
        if (flag(val) < 0) goto bad;
        if (flag(val) == 1) A->src = SRC_NONE;
    } else if (IS("traj")) {
        want = "a trajectory CSV file";
        if (strlen(val) >= sizeof A->traj_path || val[0] == '\0') goto bad;
        strcpy(A->traj_path, val);
        A->src = SRC_FILE;
    } else if (IS("offset")) {
        int k = nums(val, v, 3, why, sizeof why);
        want = "AMP,RAMP[,HOLD] (turns, s >= 0, s >= 0)";
        if (k < 2 || v[1] < 0 || (k == 3 && v[2] < 0)) goto bad;
        A->offset_amp = v[0];
        A->offset_ramp = v[1];
        A->offset_hold = (k == 3) ? v[2] : 0.5;
    } else if (IS("vel")) {
        int k = nums(val, v, 3, why, sizeof why);
        want = "AMP,FREQ[,CYCLES] (delta turns/tick, Hz > 0, whole cycles >= 1)";
        if (k < 2 || v[1] <= 0 || (k == 3 && (v[2] < 1 || v[2] != floor(v[2])))) goto bad;
        A->vel_amp = v[0];
        A->vel_freq = v[1];
        A->vel_cycles = (k == 3) ? v[2] : 1.0;
    } else if (IS("duration")) {
        want = "seconds >= 0";
        if (num(val, 0, 1e7, v, why, sizeof why) != 0) goto bad;
        A->duration = v[0];
    } else if (IS("gains")) {
        int k = nums(val, v, 3, why, sizeof why);
        want = "KP,KD[,KI] (>= 0)";
        if (k < 2 || v[0] < 0 || v[1] < 0 || (k == 3 && v[2] < 0)) goto bad;
        A->kp = v[0];
        A->kd = v[1];
        A->ki = (k == 3) ? v[2] : 0.0;
    } else if (IS("i-max")) {
        want = "amperes >= 0";
        if (num(val, 0, 1e6, v, why, sizeof why) != 0) goto bad;
        A->i_max = v[0];
    } else if (IS("scs")) {
        want = "seconds >= 0";
        if (num(val, 0, 1e4, v, why, sizeof why) != 0) goto bad;
        A->scs = v[0];
    } else if (IS("no-exit")) {
        want = "1/0, yes/no or true/false";
        if (flag(val) < 0) goto bad;
        A->exit_open = !flag(val);
    } else FLAG("exit-open", A->exit_open)
    else if (IS("max-step")) {
        want = "turns per tick >= 0";
        if (num(val, 0, 1e6, v, why, sizeof why) != 0) goto bad;
        A->max_step = v[0];
    } else if (IS("stroke")) {
        int k = nums(val, v, 2, why, sizeof why), j;
        want = "MIN,MAX in motor turns, MIN < MAX";
        if (k != 2 || v[0] >= v[1]) goto bad;
        for (j = 0; j < (int)C4G_AXES_PER_ARM; j++) {
            A->pos_min[j] = v[0];
            A->pos_max[j] = v[1];
        }
        A->have_stroke = 1;
    } else if (IS("fe-limit")) {
        want = "turns >= 0 (0 = the init packet's FollowError)";
        if (num(val, 0, 1e6, v, why, sizeof why) != 0) goto bad;
        A->fe_limit = v[0];
    } else {
        char n[80];
        tf_escape(name, strlen(name), n, sizeof n);
        snprintf(err, errlen, "unknown setting '%s'", n);
        return -2;
    }
    return 0;
bad:
    {
        char v80[80];
        tf_escape(val, strlen(val), v80, sizeof v80);
        if (why[0] != '\0') {
            snprintf(err, errlen, "%s: %s (want %s)", name, why, want ? want : "?");
        } else {
            snprintf(err, errlen, "%s: bad value '%s' (want %s)", name, v80, want ? want : "?");
        }
    }
    return -1;
#undef IS
#undef FLAG
}

/* ---- the INI file: [server] [rt] [output] [test] take any setting, [arm1]..[arm4] the
 * per-arm ones for that arm only */

static tf_ini_rc_t on_ini(void *user, const char *section, const char *name, const char *value,
                          char *msg, size_t msglen)
{
    srv_config_t *c = user;
    char err[300];
    int arm = -1, a, lo, hi;
    if (strncmp(section, "arm", 3) == 0 && section[3] >= '1' &&
        section[3] <= (char)('0' + C4G_ARMS) && section[4] == '\0') {
        arm = section[3] - '1';
    } else if (section[0] != '\0' && strcmp(section, "server") != 0 &&
               strcmp(section, "rt") != 0 && strcmp(section, "output") != 0 &&
               strcmp(section, "test") != 0 && strcmp(section, "arms") != 0) {
        char s[80];
        tf_escape(section, strlen(section), s, sizeof s);
        snprintf(msg, msglen, "unknown section [%s] (want [server], [rt], [output], [test] or "
                              "[arm1]..[arm4])", s);
        return TF_INI_BAD_SECTION;
    }
    lo = (arm < 0) ? 0 : arm;
    hi = (arm < 0) ? (int)C4G_ARMS - 1 : arm;
    for (a = lo; a <= hi; a++) {
        const int rc = srv_config_apply(c, name, value, a, err, sizeof err);
        if (rc != 0) {
            snprintf(msg, msglen, "[%s] %s", section, err);
            return (rc == -2) ? TF_INI_BAD_KEY : TF_INI_BAD_VALUE;
        }
    }
    return TF_INI_OK;
}

int srv_config_parse_ini(srv_config_t *c, tf_file_t *f, char *err, size_t errlen)
{
    return tf_ini_parse(f, on_ini, c, err, errlen);
}

int srv_config_load_ini(srv_config_t *c, const char *path, char *err, size_t errlen)
{
    tf_file_t f;
    int rc;
    if (tf_load(&f, path, TF_MAX_INI, err, errlen) != 0) {
        return -1;
    }
    rc = srv_config_parse_ini(c, &f, err, errlen);
    tf_free(&f);
    return rc;
}
