/* SPDX-License-Identifier: MIT */
/* c4g-sim configuration: defaults and the INI file (read with inih). */
#include "sim.h"

#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void sim_config_default(sim_config_t *c)
{
    unsigned a;
    unsigned l;
    memset(c, 0, sizeof *c);
    strcpy(c->server, "127.0.0.1");
    c->port = C4G_DEFAULT_PORT;
    strcpy(c->bind_addr, "0.0.0.0");
    c->period_ms = 2;
    c->t_cycle1_us = 500U;
    c->policy = SIM_NUM_EITHER;
    c->max_miss = 10U;
    c->seed = 1U;
    c->sync_before = 9U;
    c->sync_after = 2U;
    c->drive_on_ms = 400.0;
    c->switch_ms = 200.0;
    c->check_follow = 1;
    c->n_arms = 1;
    c->open_mask[0] = 0x3FU;
    c->version[0] = 3;
    c->version[1] = 11;
    c->version[2] = 115;
    for (a = 0; a < C4G_ARMS; a++) {
        c->option_ok[a] = 1;
        for (l = 0; l < C4G_AXES_PER_ARM; l++) {
            sim_axis_params_default(&c->ax[a][l], l);
        }
    }
}

int sim_config_axes(const sim_config_t *c)
{
    int a;
    int n = 0;
    if (c->n_arms < 1 || c->n_arms > (int)C4G_ARMS) {
        return -1;
    }
    for (a = 0; a < c->n_arms; a++) {
        unsigned m = c->open_mask[a] & 0x3FFU;
        if (m == 0U) {
            return -1;
        }
        while (m != 0U) {
            n += (int)(m & 1U);
            m >>= 1;
        }
    }
    return (n > (int)C4G_MAX_AXES) ? -1 : n;
}

typedef struct load_ctx {
    sim_config_t *c;
    char msg[200];
} load_ctx_t;

static int num(const char *v, double lo, double hi, double *out)
{
    char *end;
    double d;
    errno = 0;
    d = strtod(v, &end);
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    if (end == v || *end != '\0' || errno != 0 || !isfinite(d) || d < lo || d > hi) {
        return -1;
    }
    *out = d;
    return 0;
}

/* Axis parameter by name; returns 0 ok, -1 bad value, -2 unknown key. */
static int axis_key(sim_axis_params_t *p, const char *k, const char *v)
{
    static const struct {
        const char *name;
        size_t off;
        double lo, hi;
    } keys[] = {
#define K(n, lo, hi) {#n, offsetof(sim_axis_params_t, n), lo, hi}
        K(j, 1e-9, 1e3), K(kt, 1e-6, 1e3), K(fv, 0.0, 1e3), K(fc, 0.0, 1e3), K(gravity, -1e4, 1e4),
        K(kp, 0.0, 1e5), K(kv, 0.0, 1e5), K(ki, 0.0, 1e7), K(az_lim, 0.0, 1e4),
        K(tx_rate, -1e5, 1e5), K(cal, -1e6, 1e6), K(ax_info, -1e3, 1e3), K(follow_error, 0.0, 1e6),
        K(counts, 0.0, 1e9), K(noise, 0.0, 1.0), K(vel_filter, 1e-6, 1.0), K(vmax, 1e-6, 1e5),
        K(amax, 1e-6, 1e7), K(pos0, -1e6, 1e6)
#undef K
    };
    size_t i;
    double d;
    if (strcmp(k, "startup_mode") == 0) {
        if (num(v, 0, 1000, &d) != 0 || !c4g_mode_is_known((int32_t)d) || d != floor(d)) {
            return -1;
        }
        p->startup_mode = (int)d;
        return 0;
    }
    for (i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        if (strcmp(k, keys[i].name) == 0) {
            if (num(v, keys[i].lo, keys[i].hi, &d) != 0) {
                return -1;
            }
            *(double *)((char *)p + keys[i].off) = d;
            return 0;
        }
    }
    return -2;
}

static int handler(void *user, const char *section, const char *name, const char *value)
{
    load_ctx_t *x = user;
    sim_config_t *c = x->c;
    double d;
    int rc = 0;
    unsigned a;
    unsigned l;
    if (strcmp(section, "sim") == 0) {
        if (strcmp(name, "server") == 0 || strcmp(name, "bind") == 0) {
            char *dst = (name[0] == 's') ? c->server : c->bind_addr;
            if (strlen(value) >= sizeof c->server) {
                rc = -1;
            } else {
                strcpy(dst, value);
            }
        } else if (strcmp(name, "port") == 0 || strcmp(name, "local_port") == 0) {
            rc = num(value, (name[0] == 'p') ? 1 : 0, 65535, &d);
            if (rc == 0) {
                *((name[0] == 'p') ? &c->port : &c->local_port) = (unsigned)d;
            }
        } else if (strcmp(name, "period_ms") == 0) {
            rc = (num(value, 1, 2, &d) == 0 && d == floor(d)) ? 0 : -1;
            c->period_ms = (int)d;
        } else if (strcmp(name, "t_cycle1_us") == 0) {
            rc = num(value, 1, 1e6, &d);
            c->t_cycle1_us = (unsigned)d;
        } else if (strcmp(name, "num_policy") == 0) {
            if (strcmp(value, "plus-one") == 0) {
                c->policy = SIM_NUM_PLUS_ONE;
            } else if (strcmp(value, "echo") == 0) {
                c->policy = SIM_NUM_ECHO;
            } else if (strcmp(value, "either") == 0) {
                c->policy = SIM_NUM_EITHER;
            } else {
                rc = -1;
            }
        } else if (strcmp(name, "max_miss") == 0) {
            rc = num(value, 1, 1e6, &d);
            c->max_miss = (unsigned)d;
        } else if (strcmp(name, "seed") == 0) {
            rc = num(value, 0, 1.8e19, &d);
            c->seed = (uint64_t)d;
        } else if (strcmp(name, "drive_on_ms") == 0) {
            rc = num(value, 0, 1e5, &c->drive_on_ms);
        } else if (strcmp(name, "switch_ms") == 0) {
            rc = num(value, 0, 1e5, &c->switch_ms);
        } else if (strcmp(name, "follow_check") == 0) {
            rc = num(value, 0, 1, &d);
            c->check_follow = (int)d;
        } else if (strcmp(name, "sync_before") == 0) {
            rc = num(value, 0, 1000, &d);
            c->sync_before = (unsigned)d;
        } else if (strcmp(name, "sync_after") == 0) {
            rc = num(value, 0, 100, &d);
            c->sync_after = (unsigned)d;
        } else if (strcmp(name, "version") == 0) {
            rc = (sscanf(value, "%d.%d.%d", &c->version[0], &c->version[1], &c->version[2]) == 3) ? 0 : -1;
        } else {
            rc = -2;
        }
    } else if (strcmp(section, "model") == 0) {
        for (a = 0; a < C4G_ARMS && rc == 0; a++) {
            for (l = 0; l < C4G_AXES_PER_ARM && rc == 0; l++) {
                rc = axis_key(&c->ax[a][l], name, value);
            }
        }
    } else if (sscanf(section, "arm %u", &a) == 1 && a >= 1U && a <= C4G_ARMS) {
        if ((int)a > c->n_arms) {
            unsigned k;
            for (k = (unsigned)c->n_arms; k < a; k++) {
                c->open_mask[k] = 0x3FU;
            }
            c->n_arms = (int)a;
        }
        if (strcmp(name, "open") == 0) {
            const char *p = value;
            unsigned m = 0U;
            while (*p != '\0' && rc == 0) {
                char *end;
                long v = strtol(p, &end, 10);
                if (end == p || v < 1 || v > 10) {
                    rc = -1;
                } else {
                    m |= 1U << (v - 1);
                    p = end;
                    while (*p == ' ' || *p == ',' || *p == '\t') {
                        p++;
                    }
                }
            }
            if (m == 0U) {
                rc = -1;
            }
            c->open_mask[a - 1U] = m;
        } else if (strcmp(name, "option") == 0) {
            rc = num(value, 0, 1, &d);
            c->option_ok[a - 1U] = (int)d;
        } else {
            for (l = 0; l < C4G_AXES_PER_ARM && rc == 0; l++) {
                rc = axis_key(&c->ax[a - 1U][l], name, value);
            }
        }
    } else if (sscanf(section, "axis %u.%u", &a, &l) == 2 && a >= 1U && a <= C4G_ARMS &&
               l >= 1U && l <= C4G_AXES_PER_ARM) {
        rc = axis_key(&c->ax[a - 1U][l - 1U], name, value);
    } else {
        snprintf(x->msg, sizeof x->msg, "unknown section [%s]", section);
        return 0;
    }
    if (rc == -2) {
        snprintf(x->msg, sizeof x->msg, "[%s]: unknown key '%s'", section, name);
        return 0;
    }
    if (rc != 0) {
        snprintf(x->msg, sizeof x->msg, "[%s] %s: bad value '%s'", section, name, value);
        return 0;
    }
    return 1;
}

int sim_config_load(sim_config_t *c, const char *path, char *err, size_t errlen)
{
    load_ctx_t x;
    int rc;
    x.c = c;
    x.msg[0] = '\0';
    rc = ini_parse(path, handler, &x);
    if (rc == -1) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    if (rc != 0) {
        snprintf(err, errlen, "%s:%d: %s", path, rc, x.msg[0] != '\0' ? x.msg : "syntax error");
        return -1;
    }
    if (sim_config_axes(c) < 0) {
        snprintf(err, errlen, "%s: more than 20 open axes, or an arm with none", path);
        return -1;
    }
    return 0;
}
