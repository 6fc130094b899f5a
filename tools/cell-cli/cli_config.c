/* SPDX-License-Identifier: MIT */
/* cell-cli INI configuration: strict values, every error with file, line, column, key. */
#include "cli_config.h"

#include "c4gh_textfile.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

void cli_config_default(cli_config_t *c)
{
    int d;
    memset(c, 0, sizeof *c);
    for (d = 0; d < C4GH_CELL_DEVICES; d++) {
        strcpy(c->host[d], "127.0.0.1");
        c->port[d] = c4gh_cell_dev_default_port(d);
    }
    c->connect_ms = 2000;
    c->reply_ms = 2000;
    c->hints = 1;
}

/* yes/true/on/1 or no/false/off/0, any case; -1 for anything else. */
static int yes_no(const char *v)
{
    static const char *const yes[] = {"yes", "true", "on", "1"};
    static const char *const no[] = {"no", "false", "off", "0"};
    for (size_t i = 0; i < sizeof yes / sizeof yes[0]; i++) {
        if (strcasecmp(v, yes[i]) == 0) {
            return 1;
        }
        if (strcasecmp(v, no[i]) == 0) {
            return 0;
        }
    }
    return -1;
}

static c4gh_tf_ini_rc_t bad_int(const char *section, const char *name, const char *value, c4gh_tf_num_t st,
                           long long lo, long long hi, char *msg, size_t msglen)
{
    char why[200];
    c4gh_tf_num_explain(st, value, (double)lo, (double)hi, why, sizeof why);
    snprintf(msg, msglen, "[%s] %s: %s", section, name, why);
    return C4GH_TF_INI_BAD_VALUE;
}

static c4gh_tf_ini_rc_t on_ini(void *user, const char *section, const char *name, const char *value,
                          char *msg, size_t msglen)
{
    cli_config_t *c = user;
    long long v = 0;
    c4gh_tf_num_t st;
    int dev = -1;
    int d;
    for (d = 0; d < C4GH_CELL_DEVICES; d++) {
        if (strcasecmp(section, c4gh_cell_dev_name(d)) == 0) {
            dev = d;
        }
    }
    if (dev >= 0) {
        if (strcasecmp(name, "host") == 0) {
            if (value[0] == '\0' || strlen(value) >= sizeof c->host[dev]) {
                snprintf(msg, msglen, "[%s] host: want a host name or IPv4 address (1..%u bytes)",
                         section, (unsigned)sizeof c->host[dev] - 1U);
                return C4GH_TF_INI_BAD_VALUE;
            }
            strcpy(c->host[dev], value);
            return C4GH_TF_INI_OK;
        }
        if (strcasecmp(name, "port") == 0) {
            st = c4gh_tf_parse_int(value, 1, 65535, &v);
            if (st != C4GH_TF_NUM_OK) {
                return bad_int(section, name, value, st, 1, 65535, msg, msglen);
            }
            c->port[dev] = (unsigned)v;
            return C4GH_TF_INI_OK;
        }
    } else if (strcasecmp(section, "cli") == 0) {
        if (strcasecmp(name, "connect_timeout_ms") == 0 || strcasecmp(name, "reply_timeout_ms") == 0) {
            st = c4gh_tf_parse_int(value, 1, 600000, &v);
            if (st != C4GH_TF_NUM_OK) {
                return bad_int(section, name, value, st, 1, 600000, msg, msglen);
            }
            *((name[0] == 'c' || name[0] == 'C') ? &c->connect_ms : &c->reply_ms) = (int)v;
            return C4GH_TF_INI_OK;
        }
        if (strcasecmp(name, "hints") == 0) {
            char v_esc[80];
            c->hints = yes_no(value);
            if (c->hints < 0) {
                c4gh_tf_escape(value, strlen(value), v_esc, sizeof v_esc);
                snprintf(msg, msglen, "[%s] hints: '%s' is not yes or no", section, v_esc);
                return C4GH_TF_INI_BAD_VALUE;
            }
            return C4GH_TF_INI_OK;
        }
    } else {
        char s[80];
        c4gh_tf_escape(section, strlen(section), s, sizeof s);
        snprintf(msg, msglen, "unknown section [%s] (want [robot], [platform], [conditioning] or [cli])", s);
        return C4GH_TF_INI_BAD_SECTION;
    }
    {
        /* an unknown key is an error, so typos do not pass silently */
        char n[80];
        c4gh_tf_escape(name, strlen(name), n, sizeof n);
        snprintf(msg, msglen, "[%s]: unknown key '%s' (want %s)", section, n,
                 dev >= 0 ? "host or port" : "connect_timeout_ms, reply_timeout_ms or hints");
        return C4GH_TF_INI_BAD_KEY;
    }
}

int cli_config_parse(cli_config_t *c, c4gh_tf_file_t *f, char *err, size_t errlen)
{
    return c4gh_tf_ini_parse(f, on_ini, c, err, errlen);
}

int cli_config_load(cli_config_t *c, const char *path, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    if (c4gh_tf_load(&f, path, C4GH_TF_MAX_INI, err, errlen) != 0) {
        return -1;
    }
    rc = cli_config_parse(c, &f, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}
