/* SPDX-License-Identifier: MIT */
/* cell-sim: the orientation platform on a CANopen bus (see sim_canopen.h). */
#include "sim_canopen.h"
#include "c4gh_cell.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

/* The bus's clock: ns since the simulator started (the library's unit) */
static uint64_t bus_ns(const sim_co_t *s, uint64_t now_ns)
{
    return now_ns - s->t0_ns;
}

static uint64_t wall_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* ---- the bus: virtual, or two SocketCAN sockets (master side, node side) */

static void socketcan_step(sim_co_t *s, uint64_t t)
{
    c4g_co_frame_t f, out[C4GSIM_SLAVE_OUT];
    bool have = true;
    int n = 0;
    for (int i = 0; i < s->cfg.net.n_nodes; i++) {
        if (c4gsim_slave_poll(&s->slave[i], t, out, &n) != C4G_OK) {
            n = 0;
        }
        for (int k = 0; k < n; k++) {
            (void)c4gh_co_socketcan_send(s->fd_nodes, &out[k]);
        }
    }
    {
        uint64_t next;
        (void)c4g_co_master_poll(&s->m, t, &next);
    }
    for (int round = 0; round < 64; round++) {
        int moved = 0;
        while (c4g_co_master_tx(&s->m, &f, &have) == C4G_OK && have) {
            f.t_ns = t;
            c4gh_co_buslog_write(&s->log, &f);
            (void)c4gh_co_socketcan_send(s->fd_master, &f);
            moved = 1;
        }
        while (c4gh_co_socketcan_recv(s->fd_nodes, &f, t) == 1) {
            for (int i = 0; i < s->cfg.net.n_nodes; i++) {
                if (c4gsim_slave_rx(&s->slave[i], &f, out, &n) != C4G_OK) {
                    n = 0; /* a frame no node can take (the recv side checks dlc and id) */
                }
                for (int k = 0; k < n; k++) {
                    (void)c4gh_co_socketcan_send(s->fd_nodes, &out[k]);
                }
            }
            moved = 1;
        }
        while (c4gh_co_socketcan_recv(s->fd_master, &f, t) == 1) {
            c4gh_co_buslog_write(&s->log, &f);
            (void)c4g_co_master_rx(&s->m, &f);
            moved = 1;
        }
        if (!moved) {
            break;
        }
    }
}

static void bus_step(sim_co_t *s, uint64_t now_ns)
{
    const uint64_t t = bus_ns(s, now_ns);
    if (s->fd_master >= 0) {
        socketcan_step(s, t);
    } else {
        (void)c4gsim_vbus_step(&s->bus, t); /* cannot fail: the bus exists */
    }
}

static int axis_running(const sim_co_t *s, int a)
{
    return s->axis_slot[a] >= 0 && s->m.node[s->axis_slot[a]].boot == C4G_CO_BOOT_RUNNING;
}

static uint8_t axis_node(const sim_co_t *s, int a)
{
    return s->cfg.net.node[s->axis_slot[a]].node_id;
}

static void sdo_finished(sim_co_t *s, const c4g_co_event_t *e);

/* Master events: lost, stopped and recovered drives; a user SDO's end goes to the shell
 * connection that asked for it. */
static void handle_events(sim_co_t *s, sim_device_t *platform)
{
    c4g_co_event_t e;
    bool have = true;
    while (c4g_co_master_event(&s->m, &e, &have) == C4G_OK && have) {
        int a = -1;
        if (e.kind == C4G_CO_EV_SDO_DONE) {
            sdo_finished(s, &e);
            continue;
        }
        for (int k = 0; k < 2; k++) {
            if (s->axis_slot[k] >= 0 && e.node == axis_node(s, k)) {
                a = k;
            }
        }
        if (s->verbose) {
            fprintf(stderr, "cell-sim: canopen: event %d node %u cause %u value 0x%08X\n", e.kind,
                    e.node, e.cause, e.value);
        }
        if (a >= 0 && platform != NULL &&
            (e.kind == C4G_CO_EV_NODE_LOST || e.kind == C4G_CO_EV_NODE_FAILED ||
             e.kind == C4G_CO_EV_NODE_STATE)) {
            /* a lost drive, or one no longer operational (its targets would be ignored):
             * the motion stops and the platform reports servo motor N error */
            s->lost[a] = 1;
            platform->moving = 0;
            platform->servo = 0;
            platform->error = a == 0 ? C4G_CELL_E_SERVO1 : C4G_CELL_E_SERVO2;
        } else if (a >= 0 && platform != NULL && e.kind == C4G_CO_EV_EMCY && e.value != 0) {
            /* a drive fault: the drive stays in fault until SRVON asks for a reset */
            s->fault_hold[a] = 1;
            platform->moving = 0;
            platform->servo = 0;
            platform->error = a == 0 ? C4G_CELL_E_SERVO1 : C4G_CELL_E_SERVO2;
        } else if (a >= 0 && e.kind == C4G_CO_EV_NODE_RECOVERED) {
            s->lost[a] = 0;
        }
    }
}

/* Targets (ideal positions) and controlwords of both axes into the RxPDOs. */
static void set_outputs(sim_co_t *s, const sim_device_t *platform)
{
    for (int a = 0; a < 2; a++) {
        uint32_t sw = 0;
        if (!axis_running(s, a)) {
            continue;
        }
        const uint8_t id = axis_node(s, a);
        const double counts = platform->pos[a] * SIM_CO_COUNTS_PER_RAD;
        (void)c4g_co_master_set(&s->m, id, C4G_CO_OBJ_TARGET_POS, 0, (uint32_t)(int32_t)lround(counts));
        (void)c4g_co_master_set(&s->m, id, C4G_CO_OBJ_MODES, 0, C4G_CO_MODE_CSP);
        if (!s->fault_hold[a] &&
            c4g_co_master_get(&s->m, id, true, C4G_CO_OBJ_STATUSWORD, 0, &sw) == C4G_OK) {
            uint16_t cw = s->cw[a];
            if (c4g_co_ds402_command((uint16_t)sw, s->goal, s->cw[a], &cw) == C4G_OK) {
                s->cw[a] = cw;
                (void)c4g_co_master_set(&s->m, id, C4G_CO_OBJ_CONTROLWORD, 0, cw);
            }
        }
    }
}

static void shell_serve(sim_co_t *s, uint64_t now_ns);

void sim_co_step(sim_co_t *s, uint64_t now_ns, sim_device_t *platform)
{
    s->platform = platform;
    sim_device_update(platform, now_ns);
    set_outputs(s, platform);
    bus_step(s, now_ns);
    handle_events(s, platform);
    shell_serve(s, now_ns);
}

static int axis_state(const sim_co_t *s, int a, c4g_co_ds402_t *st)
{
    uint32_t sw = 0;
    if (!axis_running(s, a) ||
        c4g_co_master_get(&s->m, axis_node(s, a), true, C4G_CO_OBJ_STATUSWORD, 0, &sw) != C4G_OK) {
        return -1;
    }
    *st = c4g_co_ds402_state((uint16_t)sw);
    return 0;
}

/* Both drives show @p want: 1; 0 not yet; -1 a drive is not running. */
static int drives_in(const sim_co_t *s, c4g_co_ds402_t want)
{
    c4g_co_ds402_t a = C4G_CO_DS402_UNKNOWN, b = C4G_CO_DS402_UNKNOWN;
    if (axis_state(s, 0, &a) != 0 || axis_state(s, 1, &b) != 0) {
        return -1;
    }
    return (a == want && b == want) ? 1 : 0;
}

static const char *lost_reply(sim_co_t *s, sim_device_t *platform, c4g_cell_reply_t *rep)
{
    const int a = axis_running(s, 0) ? 1 : 0;
    rep->kind = C4G_CELL_REPLY_ER;
    rep->error = a == 0 ? C4G_CELL_E_SERVO1 : C4G_CELL_E_SERVO2;
    platform->error = rep->error;
    return a == 0 ? "axis A drive lost on the CANopen bus" : "axis B drive lost on the CANopen bus";
}

/* SRVON / SRVOF once the drives are where they were sent (or are not): the reply. */
static const char *servo_finish(sim_co_t *s, sim_device_t *platform, const c4g_cell_instr_t *in,
                                int there, uint64_t now_ns, c4g_cell_reply_t *rep,
                                int *close_after)
{
    const char *note;
    if (in->cmd == C4G_CELL_CMD_SRVON && there != 1) {
        memset(rep, 0, sizeof *rep);
        *close_after = 0;
        s->goal = C4G_CO_GOAL_READY;
        return lost_reply(s, platform, rep);
    }
    note = sim_device_exec(platform, in, now_ns, rep, close_after);
    if (in->cmd == C4G_CELL_CMD_SRVON && rep->kind == C4G_CELL_REPLY_OK) {
        note = "servo on: drives in operation enabled (DS402)";
    }
    return note;
}

const char *sim_co_exec(sim_co_t *s, sim_device_t *platform, const c4g_cell_instr_t *in,
                        uint64_t now_ns, c4g_cell_reply_t *rep, int *close_after, int *deferred)
{
    const int ok = axis_running(s, 0) && axis_running(s, 1);
    const char *note;
    *deferred = 0;
    sim_co_step(s, now_ns, platform);
    if (in->cmd == C4G_CELL_CMD_SRVON || in->cmd == C4G_CELL_CMD_SRVOF) {
        const c4g_co_ds402_t want = in->cmd == C4G_CELL_CMD_SRVON ? C4G_CO_DS402_ENABLED
                                                                  : C4G_CO_DS402_READY;
        if (in->cmd == C4G_CELL_CMD_SRVON && !ok) {
            memset(rep, 0, sizeof *rep);
            *close_after = 0;
            return lost_reply(s, platform, rep);
        }
        s->goal = in->cmd == C4G_CELL_CMD_SRVON ? C4G_CO_GOAL_ENABLED : C4G_CO_GOAL_READY;
        if (in->cmd == C4G_CELL_CMD_SRVON) {
            s->fault_hold[0] = s->fault_hold[1] = 0;
        }
        if (drives_in(s, want) != 0) {
            return servo_finish(s, platform, in, drives_in(s, want), now_ns, rep, close_after);
        }
        /* the drives take a few SYNC periods: the reply waits, the event loop goes on */
        s->servo.active = 1;
        s->servo.in = *in;
        s->servo.want = want;
        s->servo.deadline_ns = now_ns + SIM_CO_SERVO_NS;
        *deferred = 1;
        return NULL;
    }
    if ((in->cmd == C4G_CELL_CMD_MOV || in->cmd == C4G_CELL_CMD_RST) && !ok) {
        memset(rep, 0, sizeof *rep);
        *close_after = 0;
        if (in->cmd == C4G_CELL_CMD_RST) {
            platform->error = 0; /* RST clears the latched error; the drive is still away */
        }
        return lost_reply(s, platform, rep);
    }
    note = sim_device_exec(platform, in, now_ns, rep, close_after);
    if (in->cmd == C4G_CELL_CMD_STA && rep->kind == C4G_CELL_REPLY_STA) {
        for (int a = 0; a < 2; a++) {
            uint32_t v = 0;
            if (axis_running(s, a) &&
                c4g_co_master_get(&s->m, axis_node(s, a), true, C4G_CO_OBJ_ACTUAL_POS, 0, &v) == C4G_OK) {
                const double act = (double)(int32_t)v / SIM_CO_COUNTS_PER_RAD;
                (void)c4g_cell_from_double(act, C4G_CELL_UNIT_RAD, &rep->pose.v[a]);
                /* moving until the drive has reached the last target (0.1 mrad) */
                if (platform->servo && fabs(act - platform->pos[a]) > 1e-4) {
                    rep->moving = 1;
                }
            }
        }
        note = "status (positions from the drives' TxPDOs)";
    }
    return note;
}

int sim_co_servo_busy(const sim_co_t *s)
{
    return s->servo.active;
}

int sim_co_servo_poll(sim_co_t *s, sim_device_t *platform, uint64_t now_ns,
                      c4g_cell_reply_t *rep, const char **note, int *close_after)
{
    int there;
    if (!s->servo.active) {
        return 0;
    }
    there = drives_in(s, s->servo.want);
    if (there == 0 && now_ns < s->servo.deadline_ns) {
        return 0;
    }
    s->servo.active = 0;
    *note = servo_finish(s, platform, &s->servo.in, there, now_ns, rep, close_after);
    return 1;
}

int sim_co_open(sim_co_t *s, const char *ini, const char *ifname, const char *candump,
                const char *pcap, const char *shell_bind, unsigned shell_port, char *err,
                size_t errlen)
{
    memset(s, 0, sizeof *s);
    s->fd_master = s->fd_nodes = -1;
    s->listen_fd = -1;
    s->sdo_owner = -1;
    for (int k = 0; k < SIM_CO_SHELLS; k++) {
        s->sh[k].fd = -1;
    }
    s->axis_slot[0] = s->axis_slot[1] = -1;
    s->goal = C4G_CO_GOAL_READY;
    if (c4gh_co_config_load(&s->cfg, ini, err, errlen) != 0) {
        return -1;
    }
    if (s->cfg.net.n_nodes < 2) {
        snprintf(err, errlen, "%s: the platform needs two nodes (axes A and B), the file has %u",
                 ini, s->cfg.net.n_nodes);
        return -1;
    }
    s->axis_slot[0] = 0;
    s->axis_slot[1] = 1;
    if (c4g_co_master_init(&s->m, &s->cfg.net) != C4G_OK) {
        snprintf(err, errlen, "%s: configuration refused by the master", ini);
        return -1;
    }
    for (int i = 0; i < s->cfg.net.n_nodes; i++) {
        if (c4gsim_slave_init(&s->slave[i], s->cfg.net.node[i].node_id,
                              s->cfg.net.node[i].device_type & ~C4G_CO_DEVTYPE_LG_REVERSE) != C4G_OK) {
            snprintf(err, errlen, "%s: node id %u refused by the simulated node", ini,
                     (unsigned)s->cfg.net.node[i].node_id);
            return -1;
        }
    }
    if (ifname != NULL) {
        s->fd_master = c4gh_co_socketcan_open(ifname, err, errlen);
        if (s->fd_master < 0) {
            return -1;
        }
        s->fd_nodes = c4gh_co_socketcan_open(ifname, err, errlen);
        if (s->fd_nodes < 0) {
            close(s->fd_master);
            return -1;
        }
    }
    if (c4gh_co_buslog_open(&s->log, candump, pcap, ifname != NULL ? ifname : "vcan0", 0, err,
                           errlen) != 0) {
        return -1;
    }
    s->t0_ns = c4gh_now_ns();
    s->log.epoch_us = wall_us();
    (void)c4gsim_vbus_init(&s->bus, &s->m); /* cannot fail: the bus exists */
    for (int i = 0; i < s->cfg.net.n_nodes; i++) {
        (void)c4gsim_vbus_add(&s->bus, &s->slave[i]); /* n_nodes <= C4G_CO_MAX_NODES (master init) */
    }
    s->bus.log = c4gh_co_buslog_cb;
    s->bus.log_ctx = &s->log;
    if (shell_port != 0) {
        s->listen_fd = c4gh_cell_tcp_listen(shell_bind, shell_port, 4);
        if (s->listen_fd < 0) {
            snprintf(err, errlen, "cannot listen on %s:%u for the CANopen shell: %s", shell_bind,
                     shell_port, strerror(errno));
            return -1;
        }
    }
    /* the nodes power up (boot-up messages), then the master boots the network */
    bus_step(s, s->t0_ns);
    (void)c4g_co_master_start(&s->m, 0);
    return 0;
}

void sim_co_close(sim_co_t *s)
{
    c4gh_co_buslog_close(&s->log);
    if (s->fd_master >= 0) {
        close(s->fd_master);
    }
    if (s->fd_nodes >= 0) {
        close(s->fd_nodes);
    }
    for (int k = 0; k < SIM_CO_SHELLS; k++) {
        if (s->sh[k].fd >= 0) {
            close(s->sh[k].fd);
        }
    }
    if (s->listen_fd >= 0) {
        close(s->listen_fd);
    }
}

/* ---- diagnostic shell */

static const char *boot_name(uint8_t b)
{
    static const char *const n[] = {"waiting", "configuring", "configured", "running", "failed", "lost"};
    return b < 6 ? n[b] : "?";
}

static const char *nmt_name(uint8_t st)
{
    switch (st) {
    case C4G_CO_STATE_BOOTUP: return "boot-up";
    case C4G_CO_STATE_STOPPED: return "stopped";
    case C4G_CO_STATE_OPERATIONAL: return "operational";
    case C4G_CO_STATE_PREOP: return "pre-operational";
    default: return "unknown";
    }
}

static const char *cause_name(uint8_t c)
{
    static const char *const n[] = {"none", "SDO timeout", "SDO abort", "SDO protocol error",
                                    "wrong device type", "heartbeat timeout", "guarding failed",
                                    "node reset (boot-up)", "left operational (NMT state)"};
    return c < 9 ? n[c] : "?";
}

static int parse_node(sim_co_t *s, const char *tok, uint8_t *id, uint8_t *slot, char *out, size_t cap)
{
    char *end = NULL;
    long v = tok ? strtol(tok, &end, 0) : -1;
    if (tok == NULL || *end != '\0' || v < 1 || v > 127 ||
        c4g_co_master_slot(&s->m, (uint8_t)v, slot) != C4G_OK) {
        snprintf(out, cap, "ERR node: want the id of a configured node");
        return -1;
    }
    *id = (uint8_t)v;
    return 0;
}

/* CO_ROBJ / CO_WOBJ / CO_SDO: queued on connection k (1), or a usage error now (0). */
static int sh_sdo(sim_co_t *s, int k, uint8_t id, bool upload, char **tok, int nt,
                  uint64_t now_ns, char *out, size_t cap)
{
    sim_co_shell_t *c = &s->sh[k];
    const long idx = nt > 0 ? strtol(tok[0], NULL, 0) : -1;
    const long sub = nt > 1 ? strtol(tok[1], NULL, 0) : -1;
    const long size = (!upload && nt > 2) ? strtol(tok[2], NULL, 0) : 0;
    const unsigned long val = (!upload && nt > 3) ? strtoul(tok[3], NULL, 0) : 0;
    if (idx < 0 || idx > 0xFFFF || sub < 0 || sub > 255 || (!upload && (nt < 4 || size < 1 || size > 4))) {
        snprintf(out, cap, "ERR usage: %s", upload ? "INDEX SUB" : "INDEX SUB SIZE VALUE");
        return 0;
    }
    c->sdo = 1;
    c->sdo_since_ns = now_ns;
    c->node = id;
    c->upload = upload ? 1 : 0;
    c->index = (uint16_t)idx;
    c->sub = (uint8_t)sub;
    c->size = (uint8_t)size;
    c->value = (uint32_t)val;
    return 1;
}

static void shell_queue(sim_co_shell_t *c, const char *text)
{
    const size_t n = strlen(text);
    if (c->fd < 0) {
        return;
    }
    if (c->out_len + n + 1 > sizeof c->out) {
        close(c->fd); /* it does not read its replies: it loses its connection, not others */
        c->fd = -1;
        return;
    }
    memcpy(c->out + c->out_len, text, n);
    c->out[c->out_len + n] = '\n';
    c->out_len += n + 1;
}

/* The user SDO of a shell connection ended: its reply. */
static void sdo_finished(sim_co_t *s, const c4g_co_event_t *e)
{
    char out[256];
    sim_co_shell_t *c;
    if (s->sdo_owner < 0) {
        return;
    }
    c = &s->sh[s->sdo_owner];
    s->sdo_owner = -1;
    if (c->sdo != 2) {
        return; /* the connection closed meanwhile */
    }
    c->sdo = 0;
    if (e->cause != C4G_CO_CAUSE_NONE) {
        snprintf(out, sizeof out, "ERR node %u 0x%04X:%02X: %s 0x%08X (%s)", c->node, c->index,
                 c->sub, cause_name(e->cause), e->value,
                 e->cause == C4G_CO_CAUSE_SDO_TIMEOUT ? "no answer" : c4g_co_abort_name(e->value));
    } else if (c->upload) {
        snprintf(out, sizeof out, "node %u 0x%04X:%02X = 0x%08X (%u)", c->node, c->index, c->sub,
                 e->value, e->value);
    } else {
        snprintf(out, sizeof out, "node %u 0x%04X:%02X written", c->node, c->index, c->sub);
    }
    shell_queue(c, out);
}

/* Queued SDOs start when the master's SDO client is free (one transfer at a time: a
 * recovery poll or another connection's transfer may hold it), in connection order from
 * the one after the last served; one that waited too long is refused. */
static void sdo_start_queued(sim_co_t *s, uint64_t now_ns)
{
    static int next;
    for (int j = 0; j < SIM_CO_SHELLS && s->sdo_owner < 0; j++) {
        const int k = (next + j) % SIM_CO_SHELLS;
        sim_co_shell_t *c = &s->sh[k];
        c4g_status_t st;
        char out[160];
        if (c->fd < 0 || c->sdo != 1) {
            continue;
        }
        st = c4g_co_master_sdo(&s->m, c->node, c->upload != 0, c->index, c->sub, c->value,
                               c->size, bus_ns(s, now_ns));
        if (st == C4G_OK) {
            c->sdo = 2;
            s->sdo_owner = k;
            next = k + 1;
        } else if (st != C4G_ERR_STATE || now_ns - c->sdo_since_ns > SIM_CO_SDO_QUEUE_NS) {
            c->sdo = 0;
            snprintf(out, sizeof out, "ERR %s", st == C4G_ERR_STATE
                     ? "busy: the SDO client stayed busy (recovery polls, other transfers); retry"
                     : c4g_strerror(st));
            shell_queue(c, out);
        }
    }
}

static void sh_pdo(sim_co_t *s, uint8_t slot, int rx, char **tok, int nt, char *out, size_t cap)
{
    const long p = nt > 0 ? strtol(tok[0], NULL, 0) : 0;
    const long e = nt > 1 ? strtol(tok[1], NULL, 0) : 0;
    const c4g_co_node_cfg_t *nc = &s->cfg.net.node[slot];
    const c4g_co_pdo_map_t *m;
    if (p < 1 || p > 4 || e < 1 || e > 8) {
        snprintf(out, cap, "ERR usage: PDO(1..4) ELEMENT(1..8)");
        return;
    }
    m = rx ? &nc->rx[p - 1] : &nc->tx[p - 1];
    if (e > m->n) {
        snprintf(out, cap, "ERR %s PDO %ld of node %u has %u elements", rx ? "Rx" : "Tx", p,
                 nc->node_id, m->n);
        return;
    }
    const uint32_t v = rx ? s->m.node[slot].rx_val[p - 1][e - 1] : s->m.node[slot].tx_val[p - 1][e - 1];
    const uint32_t bits = m->entry[e - 1] & 0xFFu;
    const int32_t sv = bits == 32 ? (int32_t)v : bits == 16 ? (int32_t)(int16_t)v : (int32_t)(int8_t)v;
    snprintf(out, cap, "node %u %sPDO%ld[%ld] %s (0x%04X:%02X) = %d (0x%0*X)", nc->node_id,
             rx ? "Rx" : "Tx", p, e, rx ? s->cfg.rx_name[slot][p - 1][e - 1] : s->cfg.tx_name[slot][p - 1][e - 1],
             m->entry[e - 1] >> 16, (m->entry[e - 1] >> 8) & 0xFF, sv, (int)(bits / 4), v);
}

static void sh_node_diag(sim_co_t *s, uint8_t slot, char *out, size_t cap)
{
    const c4g_co_node_t *n = &s->m.node[slot];
    snprintf(out, cap, "node %u: %s, NMT %s, step %u failed: %s 0x%08X at 0x%04X:%02X, bypassed 0x%02X, "
             "losses %u, RxPDOs %u, EMCY %u",
             s->cfg.net.node[slot].node_id, boot_name(n->boot), nmt_name(n->nmt), n->fail_step,
             cause_name(n->fail_cause), n->fail_value, n->fail_index, n->fail_sub, n->bypassed,
             n->losses, n->rx_pdos, n->emcy_n);
}

static void sh_emcy(sim_co_t *s, uint8_t slot, char *out, size_t cap)
{
    const c4g_co_node_t *n = &s->m.node[slot];
    int o = snprintf(out, cap, "node %u: %u EMCY", s->cfg.net.node[slot].node_id, n->emcy_n);
    for (int i = 0; i < n->emcy_n && o > 0 && (size_t)o < cap; i++) {
        const c4g_co_emcy_t *e = &n->emcy[(n->emcy_head + C4G_CO_EMCY_DEPTH - n->emcy_n + i) % C4G_CO_EMCY_DEPTH];
        o += snprintf(out + o, cap - (size_t)o, "; code 0x%04X register 0x%02X mfr %02X%02X%02X%02X%02X",
                      e->code, e->reg, e->mfr[0], e->mfr[1], e->mfr[2], e->mfr[3], e->mfr[4]);
    }
}

static void sh_nmt(sim_co_t *s, char **tok, int nt, char *out, size_t cap)
{
    static const struct { const char *n; uint8_t c; } cmds[] = {
        {"start", C4G_CO_NMT_START}, {"stop", C4G_CO_NMT_STOP}, {"preop", C4G_CO_NMT_PREOP},
        {"reset", C4G_CO_NMT_RESET_NODE}, {"resetcomm", C4G_CO_NMT_RESET_COMM}};
    const long node = nt > 0 ? strtol(tok[0], NULL, 0) : -1;
    for (size_t i = 0; nt > 1 && i < sizeof cmds / sizeof cmds[0]; i++) {
        if (strcasecmp(tok[1], cmds[i].n) == 0) {
            if (node < 0 || node > 127 || c4g_co_master_nmt(&s->m, (uint8_t)node, cmds[i].c) != C4G_OK) {
                snprintf(out, cap, "ERR node: want 0 (all) or a configured node");
                return;
            }
            snprintf(out, cap, "NMT %s sent to %s %ld", cmds[i].n, node ? "node" : "all nodes", node);
            return;
        }
    }
    snprintf(out, cap, "ERR usage: S_NMT NODE start|stop|preop|reset|resetcomm");
}

static void sh_sim(sim_co_t *s, const char *cmd, uint8_t slot, char **tok, int nt, char *out, size_t cap)
{
    c4gsim_slave_t *sl = &s->slave[slot];
    if (strcasecmp(cmd, "SIM_UNPLUG") == 0) {
        sl->silent = 1;
        snprintf(out, cap, "node %u unplugged (silent)", sl->node_id);
    } else if (strcasecmp(cmd, "SIM_PLUG") == 0) {
        (void)c4gsim_slave_reset(sl); /* cannot fail: sl exists */
        sl->silent = 0;
        sl->no_heartbeat = 0;
        snprintf(out, cap, "node %u plugged in (power-up, boot-up message)", sl->node_id);
    } else if (strcasecmp(cmd, "SIM_MUTE") == 0) {
        sl->no_heartbeat = 1;
        snprintf(out, cap, "node %u: heartbeat and guarding replies stopped", sl->node_id);
    } else if (strcasecmp(cmd, "SIM_DEVTYPE") == 0) {
        sl->device_type = nt > 0 ? (uint32_t)strtoul(tok[0], NULL, 0) : 0;
        snprintf(out, cap, "node %u: device type 0x%08X", sl->node_id, sl->device_type);
    } else if (strcasecmp(cmd, "SIM_FAULT") == 0) {
        c4g_co_frame_t f[C4GSIM_SLAVE_OUT];
        int n = 0;
        const long code = nt > 0 ? strtol(tok[0], NULL, 0) : 0x7300;
        if (c4gsim_slave_fault(sl, (uint16_t)code, f, &n) != C4G_OK) {
            n = 0;
        }
        for (int k = 0; k < n; k++) {
            if (s->fd_nodes >= 0) {
                (void)c4gh_co_socketcan_send(s->fd_nodes, &f[k]);
            } else {
                (void)c4gsim_vbus_inject(&s->bus, &f[k], bus_ns(s, c4gh_now_ns())); /* cannot fail */
            }
        }
        handle_events(s, s->platform);
        snprintf(out, cap, "node %u: fault, EMCY 0x%04lX sent", sl->node_id, (unsigned long)code);
    } else {
        const long idx = nt > 0 ? strtol(tok[0], NULL, 0) : 0;
        const long sub = nt > 1 ? strtol(tok[1], NULL, 0) : 0;
        sl->abort_index = (uint16_t)idx;
        sl->abort_sub = (uint8_t)sub;
        sl->abort_code = nt > 2 ? (uint32_t)strtoul(tok[2], NULL, 0) : C4G_CO_ABORT_NO_OBJECT;
        snprintf(out, cap, "node %u: SDO abort 0x%08X on 0x%04lX:%02lX", sl->node_id, sl->abort_code,
                 (unsigned long)idx, (unsigned long)sub);
    }
}

/* The documentation's device commands and synonyms. */
static const char *resolve_alias(const char *cmd)
{
    static const char *const alias[][2] = {
        {"CO_WNMT", "CO_RNMT"}, {"D_NMT", "CO_RNMT"}, {"D_EMCY", "CO_REMCY"},
        {"D_RPDO", "CO_RRPDO"}, {"D_TPDO", "CO_RTPDO"}, {"D_CO_WSDIAGNO", "CO_WSDIAGNO"},
        {"D_CO_CHINFO", "CO_CHDIAGNO"}};
    for (size_t i = 0; i < sizeof alias / sizeof alias[0]; i++) {
        if (strcasecmp(cmd, alias[i][0]) == 0) {
            return alias[i][1];
        }
    }
    return cmd;
}

static void sh_emcyinfo(sim_co_t *s, char *out, size_t cap)
{
    int o = snprintf(out, cap, "EMCY:");
    for (int i = 0; i < s->cfg.net.n_nodes && o > 0 && (size_t)o < cap; i++) {
        const c4g_co_node_t *n = &s->m.node[i];
        const c4g_co_emcy_t *last = &n->emcy[(n->emcy_head + C4G_CO_EMCY_DEPTH - 1) % C4G_CO_EMCY_DEPTH];
        o += snprintf(out + o, cap - (size_t)o, " node %u: %u, last 0x%04X;", s->cfg.net.node[i].node_id,
                      n->emcy_n, n->emcy_n ? last->code : 0);
    }
}

int sim_co_shell(sim_co_t *s, int k, const char *line, uint64_t now_ns, char *out, size_t cap)
{
    char buf[256];
    char *tok[8];
    int nt = 0;
    char *save = NULL;
    uint8_t id = 0, slot = 0;
    snprintf(buf, sizeof buf, "%s", line);
    for (char *t = strtok_r(buf, " \t,", &save); t != NULL && nt < 8; t = strtok_r(NULL, " \t,", &save)) {
        tok[nt++] = t;
    }
    if (nt == 0) {
        snprintf(out, cap, "ERR empty command");
        return 0;
    }
    const char *cmd = resolve_alias(tok[0]);
    if (strcasecmp(cmd, "CO_EMCYINFO") == 0) {
        sh_emcyinfo(s, out, cap);
        return 0;
    }
    if (strcasecmp(cmd, "CO_CHDIAGNO") == 0) {
        const c4g_co_counters_t *c = &s->m.count;
        snprintf(out, cap, "channel %u: %u nodes, %s, rx %u tx %u sync %u, bad frame %u, bad dlc %u, "
                 "bad value %u, unknown %u, foreign %u, rtr %u, sdo ignored %u, bad toggle %u, "
                 "txq full %u, evq full %u",
                 s->cfg.net.channel, s->cfg.net.n_nodes,
                 s->m.phase == 2 ? "running" : s->m.phase == 1 ? "booting" : "idle", c->rx, c->tx,
                 c->syncs, c->bad_frame, c->bad_dlc, c->bad_value, c->unknown, c->foreign, c->rtr,
                 c->sdo_ignored, c->bad_toggle, c->txq_full, c->evq_full);
        return 0;
    }
    if (strcasecmp(cmd, "S_NMT") == 0) {
        sh_nmt(s, tok + 1, nt - 1, out, cap);
        return 0;
    }
    if (strcasecmp(cmd, "HELP") == 0) {
        snprintf(out, cap, "CO_RNMT N | CO_ROBJ N IDX SUB | CO_WOBJ N IDX SUB SIZE VALUE | CO_SDO N R|W ... | "
                 "CO_RRPDO N PDO EL | CO_RTPDO N PDO EL | CO_STATE_MAC N | CO_CHDIAGNO | CO_WSDIAGNO N | "
                 "CO_REMCY N | S_NMT N CMD | SIM_UNPLUG N | SIM_PLUG N | SIM_MUTE N | SIM_FAULT N CODE | "
                 "SIM_ABORT N IDX SUB CODE | SIM_DEVTYPE N VALUE");
        return 0;
    }
    if (parse_node(s, nt > 1 ? tok[1] : NULL, &id, &slot, out, cap) != 0) {
        return 0;
    }
    if (strcasecmp(cmd, "CO_RNMT") == 0) {
        snprintf(out, cap, "node %u: NMT %s (0x%02X), %s", id, nmt_name(s->m.node[slot].nmt),
                 s->m.node[slot].nmt, boot_name(s->m.node[slot].boot));
    } else if (strcasecmp(cmd, "CO_ROBJ") == 0) {
        return sh_sdo(s, k, id, true, tok + 2, nt - 2, now_ns, out, cap);
    } else if (strcasecmp(cmd, "CO_WOBJ") == 0) {
        return sh_sdo(s, k, id, false, tok + 2, nt - 2, now_ns, out, cap);
    } else if (strcasecmp(cmd, "CO_SDO") == 0 && nt > 2) {
        return sh_sdo(s, k, id, tok[2][0] == 'r' || tok[2][0] == 'R', tok + 3, nt - 3, now_ns,
                      out, cap);
    } else if (strcasecmp(cmd, "CO_RRPDO") == 0 || strcasecmp(cmd, "CO_RTPDO") == 0) {
        sh_pdo(s, slot, cmd[4] == 'R' || cmd[4] == 'r', tok + 2, nt - 2, out, cap);
    } else if (strcasecmp(cmd, "CO_STATE_MAC") == 0) {
        uint32_t sw = 0;
        if (c4g_co_master_get(&s->m, id, true, C4G_CO_OBJ_STATUSWORD, 0, &sw) != C4G_OK) {
            snprintf(out, cap, "ERR node %u maps no statusword in its RxPDOs", id);
        } else {
            snprintf(out, cap, "node %u: DS402 %s (statusword 0x%04X)", id,
                     c4g_co_ds402_name(c4g_co_ds402_state((uint16_t)sw)), sw);
        }
    } else if (strcasecmp(cmd, "CO_WSDIAGNO") == 0) {
        sh_node_diag(s, slot, out, cap);
    } else if (strcasecmp(cmd, "CO_REMCY") == 0) {
        sh_emcy(s, slot, out, cap);
    } else if (strncasecmp(cmd, "SIM_", 4) == 0 &&
               (strcasecmp(cmd, "SIM_UNPLUG") == 0 || strcasecmp(cmd, "SIM_PLUG") == 0 ||
                strcasecmp(cmd, "SIM_MUTE") == 0 || strcasecmp(cmd, "SIM_FAULT") == 0 ||
                strcasecmp(cmd, "SIM_ABORT") == 0 || strcasecmp(cmd, "SIM_DEVTYPE") == 0)) {
        sh_sim(s, cmd, slot, tok + 2, nt - 2, out, cap);
    } else {
        snprintf(out, cap, "ERR unknown command '%.40s' (HELP lists them)", cmd);
    }
    return 0;
}

/* New shell connections: up to SIM_CO_SHELLS at once (an idle one keeps its place and
 * locks nobody out); one more is told so and closed. */
static void shell_accept(sim_co_t *s)
{
    for (;;) {
        int k = 0;
        const int fd = accept(s->listen_fd, NULL, NULL);
        if (fd < 0) {
            return;
        }
        while (k < SIM_CO_SHELLS && s->sh[k].fd >= 0) {
            k++;
        }
        if (k == SIM_CO_SHELLS) {
            static const char full[] = "ERR too many shell connections (8): retry later\n";
            (void)!write(fd, full, sizeof full - 1);
            close(fd);
            continue;
        }
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
        memset(&s->sh[k], 0, sizeof s->sh[k]);
        s->sh[k].fd = fd;
    }
}

static void shell_close(sim_co_t *s, int k)
{
    close(s->sh[k].fd);
    s->sh[k].fd = -1;
    s->sh[k].sdo = 0; /* a transfer still running ends unanswered (sdo_finished) */
}

/* Connection k: its complete lines, one at a time; none while its SDO is queued or runs
 * (the replies keep the order of the commands). */
static void shell_lines(sim_co_t *s, int k, uint64_t now_ns)
{
    sim_co_shell_t *c = &s->sh[k];
    while (c->fd >= 0 && c->sdo == 0) {
        char *lf = memchr(c->in, '\n', c->in_len);
        char reply[1024];
        size_t used;
        if (lf == NULL) {
            if (c->in_len >= sizeof c->in - 1) {
                c->in_len = 0; /* overlong line: dropped */
                shell_queue(c, "ERR line too long");
            }
            return;
        }
        *lf = '\0';
        if (lf > c->in && lf[-1] == '\r') {
            lf[-1] = '\0';
        }
        if (sim_co_shell(s, k, c->in, now_ns, reply, sizeof reply) == 0) {
            shell_queue(c, reply);
        }
        used = (size_t)(lf + 1 - c->in);
        memmove(c->in, lf + 1, c->in_len - used);
        c->in_len -= used;
    }
}

/* Every shell connection, without blocking: reads, the commands they complete, SDOs that
 * can start, the replies (an SDO's reply comes with the event of its end). */
static void shell_serve(sim_co_t *s, uint64_t now_ns)
{
    if (s->listen_fd < 0) {
        return;
    }
    shell_accept(s);
    for (int k = 0; k < SIM_CO_SHELLS; k++) {
        sim_co_shell_t *c = &s->sh[k];
        ssize_t n;
        if (c->fd < 0) {
            continue;
        }
        n = read(c->fd, c->in + c->in_len, sizeof c->in - 1 - c->in_len);
        if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
            shell_close(s, k);
            continue;
        }
        if (n > 0) {
            c->in_len += (size_t)n;
        }
        shell_lines(s, k, now_ns);
    }
    sdo_start_queued(s, now_ns);
    for (int k = 0; k < SIM_CO_SHELLS; k++) {
        sim_co_shell_t *c = &s->sh[k];
        if (c->fd >= 0 && c->sdo == 0) {
            shell_lines(s, k, now_ns); /* lines that waited for an SDO's end */
        }
        if (c->fd >= 0 && c->out_len > 0) {
            const ssize_t w = send(c->fd, c->out, c->out_len, MSG_NOSIGNAL | MSG_DONTWAIT);
            if (w > 0) {
                memmove(c->out, c->out + w, c->out_len - (size_t)w);
                c->out_len -= (size_t)w;
            } else if (w < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
                shell_close(s, k);
            }
        }
    }
}
