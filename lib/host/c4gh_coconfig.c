/* SPDX-License-Identifier: MIT */
/* CANopen network configuration INI (see c4gh_co_config.h). */
#include "c4gh_coconfig.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <ctype.h>

/* The variable kinds the Robox documentation lists for RX and TX PDOs, as DS402 objects. */
static const struct kind {
    const char *name;
    int rx;          /* 1: master receives (RxPDO), 0: master transmits (TxPDO) */
    uint32_t entry;
} kinds[] = {
    {"real_position", 1, C4G_CO_MAP(0x6064, 0, 32)},        /* CP(ax) */
    {"drive_ideal_position", 1, C4G_CO_MAP(0x6062, 0, 32)}, /* ideal position, drive format */
    {"input_word", 1, C4G_CO_MAP(0x60FD, 0, 32)},           /* IW(n) */
    {"statusword", 1, C4G_CO_MAP(0x6041, 0, 16)},           /* CANopen status word */
    {"ideal_position", 0, C4G_CO_MAP(0x607A, 0, 32)},       /* IP(ax) */
    {"ideal_speed", 0, C4G_CO_MAP(0x60FF, 0, 32)},          /* IV(ax) */
    {"output_word", 0, C4G_CO_MAP(0x60FE, 1, 32)},          /* OW(n) */
    {"speed_reference", 0, C4G_CO_MAP(0x60FF, 0, 32)},      /* SREF(ax) */
    {"torque_reference", 0, C4G_CO_MAP(0x6071, 0, 16)},     /* TREF(ax) */
    {"controlword", 0, C4G_CO_MAP(0x6040, 0, 16)},          /* CANopen control word */
    {"modes_of_operation", 0, C4G_CO_MAP(0x6060, 0, 8)},    /* 0x6060 (CSP = 8) */
};

int c4gh_co_config_kind(const char *name, int rx, uint32_t *entry)
{
    unsigned idx = 0, sub = 0, bits = 0;
    char tail = 0;
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
        if (strcasecmp(name, kinds[i].name) == 0 && kinds[i].rx == rx) {
            *entry = kinds[i].entry;
            return 0;
        }
    }
    /* registers (R(n), RR(n)) and anything else: an explicit object */
    if (sscanf(name, "0x%4x:%2x/%u%c", &idx, &sub, &bits, &tail) == 3 &&
        (bits == 8 || bits == 16 || bits == 32)) {
        *entry = C4G_CO_MAP(idx, sub, bits);
        return 0;
    }
    return -1;
}

static c4gh_tf_ini_rc_t bad(char *msg, size_t msglen, const char *section, const char *name,
                       const char *why)
{
    snprintf(msg, msglen, "[%s] %s: %s", section, name, why);
    return C4GH_TF_INI_BAD_VALUE;
}

static c4gh_tf_ini_rc_t num(const char *section, const char *name, const char *value, long long lo,
                       long long hi, long long *v, char *msg, size_t msglen)
{
    c4gh_tf_num_t st;
    if (value[0] == '0' && (value[1] == 'x' || value[1] == 'X')) {
        char *end = NULL;
        unsigned long long u = strtoull(value + 2, &end, 16);
        if (value[2] != '\0' && *end == '\0' && (long long)u >= lo && (long long)u <= hi) {
            *v = (long long)u;
            return C4GH_TF_INI_OK;
        }
        st = C4GH_TF_NUM_RANGE;
    } else {
        st = c4gh_tf_parse_int(value, lo, hi, v);
        if (st == C4GH_TF_NUM_OK) {
            return C4GH_TF_INI_OK;
        }
    }
    {
        char why[200];
        c4gh_tf_num_explain(st, value, (double)lo, (double)hi, why, sizeof why);
        return bad(msg, msglen, section, name, why);
    }
}

static int flag(const char *value)
{
    if (strcasecmp(value, "true") == 0 || strcmp(value, "1") == 0 || strcasecmp(value, "yes") == 0) {
        return 1;
    }
    if (strcasecmp(value, "false") == 0 || strcmp(value, "0") == 0 || strcasecmp(value, "no") == 0) {
        return 0;
    }
    return -1;
}

static c4gh_tf_ini_rc_t on_channel(c4gh_co_config_t *c, const char *s, const char *name,
                              const char *value, char *msg, size_t msglen)
{
    long long v = 0;
    c4gh_tf_ini_rc_t rc;
    if (strcasecmp(name, "channel") == 0) {
        rc = num(s, name, value, 0, 3, &v, msg, msglen);
        c->net.channel = (uint8_t)v;
    } else if (strcasecmp(name, "bitrate") == 0) {
        rc = num(s, name, value, 10000, 1000000, &v, msg, msglen);
        c->net.bitrate = (uint32_t)v;
    } else if (strcasecmp(name, "sync_period_us") == 0) {
        rc = num(s, name, value, 500, 1000000, &v, msg, msglen);
        c->net.sync_period_ns = (uint32_t)v * 1000U; /* the key is in us, the library in ns */
    } else if (strcasecmp(name, "sdo_timeout_ms") == 0) {
        rc = num(s, name, value, 1, 10000, &v, msg, msglen);
        c->net.sdo_timeout_ns = (uint64_t)v * 1000000U;
    } else if (strcasecmp(name, "sdo_retries") == 0) {
        rc = num(s, name, value, 0, 5, &v, msg, msglen);
        c->net.sdo_retries = (uint8_t)v;
    } else {
        snprintf(msg, msglen, "[%s]: unknown key '%s' (want channel, bitrate, sync_period_us, "
                 "sdo_timeout_ms or sdo_retries)", s, name);
        return C4GH_TF_INI_BAD_KEY;
    }
    return rc;
}

static c4gh_tf_ini_rc_t on_pdo(c4gh_co_config_t *c, c4g_co_node_cfg_t *n, const char *s,
                          const char *name, const char *value, char *msg, size_t msglen)
{
    const int rx = (tolower((unsigned char)name[0]) == 'r');
    const int k = name[5] - '1';
    c4g_co_pdo_map_t *m = rx ? &n->rx[k] : &n->tx[k];
    char buf[256];
    char *save = NULL;
    uint8_t bytes = 0;
    if (strlen(name) > 6) { /* rxpdoN_type */
        long long v = 0;
        c4gh_tf_ini_rc_t rc = num(s, name, value, 1, 255, &v, msg, msglen);
        if (rc == C4GH_TF_INI_OK && v > 240 && v < 254) {
            return bad(msg, msglen, s, name, "transmission type must be 1..240 (synchronous) or 254/255");
        }
        m->trans = (uint8_t)v;
        return rc;
    }
    snprintf(buf, sizeof buf, "%s", value);
    m->n = 0;
    for (char *tok = strtok_r(buf, ", ", &save); tok != NULL; tok = strtok_r(NULL, ", ", &save)) {
        uint32_t e = 0;
        if (m->n >= C4G_CO_MAX_ENTRIES) {
            return bad(msg, msglen, s, name, "more than 8 variables in one PDO");
        }
        if (c4gh_co_config_kind(tok, rx, &e) != 0) {
            char why[200];
            snprintf(why, sizeof why, "'%.40s' is not a %s variable (%s) nor 0xIIII:SS/BITS", tok,
                     rx ? "RxPDO" : "TxPDO",
                     rx ? "real_position, drive_ideal_position, input_word, statusword"
                        : "ideal_position, ideal_speed, output_word, speed_reference, "
                          "torque_reference, controlword, modes_of_operation");
            return bad(msg, msglen, s, name, why);
        }
        snprintf(rx ? c->rx_name[c->cur][k][m->n] : c->tx_name[c->cur][k][m->n], 24, "%s", tok);
        m->entry[m->n++] = e;
    }
    if (m->n == 0) {
        return bad(msg, msglen, s, name, "no variables");
    }
    if (c4g_co_pdo_length(m, &bytes) != C4G_OK) {
        return bad(msg, msglen, s, name, "the variables exceed the 8 bytes of a PDO");
    }
    if (m->trans == 0) {
        m->trans = 1;
    }
    return C4GH_TF_INI_OK;
}

static c4gh_tf_ini_rc_t on_bypass(c4g_co_node_cfg_t *n, const char *s, const char *name,
                             const char *value, char *msg, size_t msglen)
{
    char buf[128];
    char *save = NULL;
    snprintf(buf, sizeof buf, "%s", value);
    n->flags &= ~(uint32_t)(C4G_CO_F_BYPASS_CYCLE | C4G_CO_F_BYPASS_WD | C4G_CO_F_BYPASS_PDO);
    for (char *tok = strtok_r(buf, ", ", &save); tok != NULL; tok = strtok_r(NULL, ", ", &save)) {
        if (strcasecmp(tok, "cycle") == 0) {
            n->flags |= C4G_CO_F_BYPASS_CYCLE;
        } else if (strcasecmp(tok, "watchdog") == 0) {
            n->flags |= C4G_CO_F_BYPASS_WD;
        } else if (strcasecmp(tok, "pdo") == 0) {
            n->flags |= C4G_CO_F_BYPASS_PDO;
        } else if (strcasecmp(tok, "none") != 0) {
            return bad(msg, msglen, s, name, "want a list of cycle, watchdog, pdo (or none)");
        }
    }
    return C4GH_TF_INI_OK;
}

static int is_pdo_key(const char *name)
{
    return (strncasecmp(name, "rxpdo", 5) == 0 || strncasecmp(name, "txpdo", 5) == 0) &&
           name[5] >= '1' && name[5] <= '4' &&
           (name[6] == '\0' || strcasecmp(name + 6, "_type") == 0);
}

static c4gh_tf_ini_rc_t on_node_flag(c4g_co_node_cfg_t *n, uint32_t bit, const char *s,
                                const char *name, const char *value, char *msg, size_t msglen)
{
    const int b = flag(value);
    if (b < 0) {
        return bad(msg, msglen, s, name, "want true or false");
    }
    n->flags = b ? (n->flags | bit) : (n->flags & ~bit);
    return C4GH_TF_INI_OK;
}

static c4gh_tf_ini_rc_t on_node(c4gh_co_config_t *c, const char *s, const char *name, const char *value,
                           char *msg, size_t msglen)
{
    c4g_co_node_cfg_t *n = &c->net.node[c->cur];
    long long v = 0;
    c4gh_tf_ini_rc_t rc = C4GH_TF_INI_OK;
    if (strcasecmp(name, "station") == 0) {
        rc = num(s, name, value, 1, 64, &v, msg, msglen);
        n->station = (uint8_t)v;
    } else if (strcasecmp(name, "axis") == 0) {
        rc = num(s, name, value, 1, 32, &v, msg, msglen);
        n->axis = (uint8_t)v;
    } else if (strcasecmp(name, "device_type") == 0) {
        rc = num(s, name, value, 0, 0xFFFFFFFFLL, &v, msg, msglen);
        n->device_type = (uint32_t)v;
    } else if (strcasecmp(name, "ignore_device_type") == 0) {
        rc = on_node_flag(n, C4G_CO_F_IGNORE_DEVTYPE, s, name, value, msg, msglen);
    } else if (strcasecmp(name, "recovery") == 0) {
        rc = on_node_flag(n, C4G_CO_F_RECOVERY, s, name, value, msg, msglen);
    } else if (strcasecmp(name, "bypass") == 0) {
        rc = on_bypass(n, s, name, value, msg, msglen);
    } else if (strcasecmp(name, "cycle_period_us") == 0) {
        rc = num(s, name, value, 0, 0xFFFFFFFFLL, &v, msg, msglen);
        n->cycle_period_us = (uint32_t)v;
    } else if (strcasecmp(name, "watchdog") == 0) {
        if (strcasecmp(value, "heartbeat") == 0) {
            n->watchdog = C4G_CO_WD_HEARTBEAT;
        } else if (strcasecmp(value, "lifeguard") == 0) {
            n->watchdog = C4G_CO_WD_LIFEGUARD;
        } else if (strcasecmp(value, "none") == 0) {
            n->watchdog = C4G_CO_WD_NONE;
        } else {
            rc = bad(msg, msglen, s, name, "want heartbeat, lifeguard or none");
        }
    } else if (strcasecmp(name, "heartbeat_ms") == 0 || strcasecmp(name, "consumer_ms") == 0 ||
               strcasecmp(name, "guard_ms") == 0) {
        rc = num(s, name, value, 1, 65535, &v, msg, msglen);
        *(name[0] == 'h' || name[0] == 'H' ? &n->heartbeat_ms
          : name[0] == 'c' || name[0] == 'C' ? &n->consumer_ms : &n->guard_ms) = (uint16_t)v;
    } else if (strcasecmp(name, "life_factor") == 0) {
        rc = num(s, name, value, 1, 255, &v, msg, msglen);
        n->life_factor = (uint8_t)v;
    } else if (is_pdo_key(name)) {
        rc = on_pdo(c, n, s, name, value, msg, msglen);
    } else {
        snprintf(msg, msglen, "[%s]: unknown key '%s' (want station, axis, device_type, "
                 "ignore_device_type, cycle_period_us, watchdog, heartbeat_ms, consumer_ms, "
                 "guard_ms, life_factor, recovery, bypass, rxpdo1..4, txpdo1..4, rxpdoN_type, txpdoN_type)",
                 s, name);
        rc = C4GH_TF_INI_BAD_KEY;
    }
    return rc;
}

typedef struct parse_ctx {
    c4gh_co_config_t *c;
    c4gh_tf_file_t *f;
    char last[64];
} parse_ctx_t;

static c4gh_tf_ini_rc_t new_section(parse_ctx_t *p, const char *section, char *msg, size_t msglen)
{
    c4gh_co_config_t *c = p->c;
    long long id = 0;
    snprintf(p->last, sizeof p->last, "%s", section);
    c->cur = -1;
    if (strcasecmp(section, "channel") == 0) {
        return C4GH_TF_INI_OK;
    }
    if (strncasecmp(section, "node ", 5) != 0 || c4gh_tf_parse_int(section + 5, 1, 127, &id) != C4GH_TF_NUM_OK) {
        snprintf(msg, msglen, "unknown section [%.40s] (want [channel] or [node N], N = node id 1..127)",
                 section);
        return C4GH_TF_INI_BAD_SECTION;
    }
    for (int i = 0; i < c->net.n_nodes; i++) {
        if (c->net.node[i].node_id == id) {
            snprintf(msg, msglen, "[%s]: node %lld is configured twice", section, id);
            return C4GH_TF_INI_BAD_SECTION;
        }
    }
    if (c->net.n_nodes >= C4G_CO_MAX_NODES) {
        snprintf(msg, msglen, "[%s]: more than %u nodes on one channel", section, C4G_CO_MAX_NODES);
        return C4GH_TF_INI_BAD_SECTION;
    }
    c->cur = c->net.n_nodes++;
    c4g_co_node_cfg_t *n = &c->net.node[c->cur];
    memset(n, 0, sizeof *n);
    n->node_id = (uint8_t)id;
    n->station = (uint8_t)(id <= 64 ? id : 64);
    n->axis = 1;
    n->watchdog = C4G_CO_WD_HEARTBEAT;
    n->heartbeat_ms = 100;
    n->consumer_ms = 250;
    n->guard_ms = 100;
    n->life_factor = 3;
    n->cycle_period_us = c->net.sync_period_ns / 1000U; /* 0x1006 is in us */
    c->node_line[c->cur] = p->f->line;
    return C4GH_TF_INI_OK;
}

static c4gh_tf_ini_rc_t on_ini(void *user, const char *section, const char *name, const char *value,
                          char *msg, size_t msglen)
{
    parse_ctx_t *p = user;
    if (strcmp(section, p->last) != 0 || p->last[0] == '\0') {
        c4gh_tf_ini_rc_t rc = new_section(p, section, msg, msglen);
        if (rc != C4GH_TF_INI_OK) {
            return rc;
        }
    }
    if (p->c->cur < 0) {
        return on_channel(p->c, section, name, value, msg, msglen);
    }
    return on_node(p->c, section, name, value, msg, msglen);
}

int c4gh_co_config_parse(c4gh_co_config_t *c, c4gh_tf_file_t *f, char *err, size_t errlen)
{
    parse_ctx_t p;
    uint8_t bad_node = 0;
    c4g_status_t st;
    memset(c, 0, sizeof *c);
    c->cur = -1;
    c->net.bitrate = 500000;
    c->net.sync_period_ns = 2000000U;
    c->net.sdo_timeout_ns = 50000000U;
    c->net.sdo_retries = 2;
    memset(&p, 0, sizeof p);
    p.c = c;
    p.f = f;
    if (c4gh_tf_ini_parse(f, on_ini, &p, err, errlen) != 0) {
        return -1;
    }
    if (c->net.n_nodes == 0) {
        snprintf(err, errlen, "%s: no [node N] section: a channel needs 1..%u nodes", f->path,
                 C4G_CO_MAX_NODES);
        return -1;
    }
    st = c4g_co_net_check(&c->net, &bad_node);
    if (st != C4G_OK) {
        const c4g_co_node_cfg_t *n = &c->net.node[bad_node < C4G_CO_MAX_NODES ? bad_node : 0];
        if (bad_node >= C4G_CO_MAX_NODES) {
            snprintf(err, errlen, "%s: [channel]: %s", f->path, c4g_strerror(st));
        } else {
            const char *why = "invalid node";
            for (int i = 0; i < bad_node; i++) {
                if (c->net.node[i].station == n->station) {
                    why = "station id already used by another node";
                }
            }
            if (n->watchdog == C4G_CO_WD_HEARTBEAT && n->consumer_ms <= n->heartbeat_ms) {
                why = "consumer_ms must be greater than heartbeat_ms";
            }
            snprintf(err, errlen, "%s:%u: [node %u]: %s", f->path, c->node_line[bad_node],
                     n->node_id, why);
        }
        return -1;
    }
    return 0;
}

int c4gh_co_config_load(c4gh_co_config_t *c, const char *path, char *err, size_t errlen)
{
    c4gh_tf_file_t f;
    int rc;
    if (c4gh_tf_load(&f, path, C4GH_TF_MAX_INI, err, errlen) != 0) {
        return -1;
    }
    rc = c4gh_co_config_parse(c, &f, err, errlen);
    c4gh_tf_free(&f);
    return rc;
}
