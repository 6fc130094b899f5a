/* SPDX-License-Identifier: MIT */
/* CANopen master against simulated DS402 nodes on the in-process virtual bus: the boot-up
   sequence frame by frame in the order of the Robox CANopen master documentation ("Operazioni
   effettuate dal Master all'avvio della rete"), each bypass and abort path, heartbeat and
   lifeguard (both orders of bit 30), node loss and recovery every 2.5 s, DS402 over PDOs,
   EMCY history, user SDOs, hostile frames. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "c4gopen.h"
#include "c4gsim_slave.h"
#include "c4gsim_vbus.h"

/* the rig counts time in us (its traces and expectations); the library takes ns */
#define US(x) ((uint64_t)(x) * 1000U)
#define T_US(ev) ((ev)->t_ns / 1000U)
#define DEVTYPE 0x00020192u /* DS402 servo drive */
#define TR_MAX 4096

typedef struct trace {
    char line[TR_MAX][32];
    uint64_t t[TR_MAX];
    int n;
} trace_t;

typedef struct rig {
    c4g_co_net_cfg_t cfg;
    c4g_co_master_t m;
    c4gsim_slave_t s[4];
    c4gsim_vbus_t bus;
    trace_t tr;
    uint64_t now;
    c4g_co_event_t ev[256];
    int nev;
} rig_t;

static void fmt(char *out, const c4g_co_frame_t *f)
{
    int o = sprintf(out, "%03X#", f->id);
    if (f->rtr) {
        sprintf(out + o, "R");
        return;
    }
    for (int i = 0; i < f->dlc; i++) {
        o += sprintf(out + o, "%02X", f->data[i]);
    }
}

static void log_fn(void *ctx, const c4g_co_frame_t *f)
{
    trace_t *tr = ctx;
    if (tr->n < TR_MAX) {
        fmt(tr->line[tr->n], f);
        tr->t[tr->n] = f->t_ns / 1000U;
        tr->n++;
    }
}

static void node_cfg(c4g_co_node_cfg_t *nc, uint8_t id, uint8_t wd, int pdos)
{
    memset(nc, 0, sizeof *nc);
    nc->node_id = id;
    nc->station = id;
    nc->axis = id;
    nc->device_type = DEVTYPE;
    nc->cycle_period_us = 2000;
    nc->watchdog = wd;
    nc->heartbeat_ms = 100;
    nc->consumer_ms = 250;
    nc->guard_ms = 100;
    nc->life_factor = 3;
    if (pdos) {
        nc->rx[0].n = 2;
        nc->rx[0].trans = 1;
        nc->rx[0].entry[0] = C4G_CO_MAP(0x6041, 0, 16);
        nc->rx[0].entry[1] = C4G_CO_MAP(0x6064, 0, 32);
        nc->tx[0].n = 3;
        nc->tx[0].trans = 1;
        nc->tx[0].entry[0] = C4G_CO_MAP(0x6040, 0, 16);
        nc->tx[0].entry[1] = C4G_CO_MAP(0x6060, 0, 8);
        nc->tx[0].entry[2] = C4G_CO_MAP(0x607A, 0, 32);
    }
}

static void net_cfg(c4g_co_net_cfg_t *c, int n)
{
    memset(c, 0, sizeof *c);
    c->bitrate = 500000;
    c->sync_period_ns = US(10000);
    c->sdo_timeout_ns = US(20000);
    c->sdo_retries = 1;
    c->n_nodes = (uint8_t)n;
    for (int i = 0; i < n; i++) {
        node_cfg(&c->node[i], (uint8_t)(i + 1), C4G_CO_WD_HEARTBEAT, 1);
    }
}

/* The rig with its configuration already in r->cfg; slaves booted, master not started. */
static void rig_init(rig_t *r)
{
    assert_int_equal(c4g_co_master_init(&r->m, &r->cfg), C4G_OK);
    assert_int_equal(c4gsim_vbus_init(&r->bus, &r->m), C4G_OK);
    for (int i = 0; i < r->cfg.n_nodes; i++) {
        assert_int_equal(c4gsim_slave_init(&r->s[i], r->cfg.node[i].node_id, DEVTYPE), C4G_OK);
        assert_int_equal(c4gsim_vbus_add(&r->bus, &r->s[i]), C4G_OK);
    }
    r->bus.log = log_fn;
    r->bus.log_ctx = &r->tr;
    r->now = 1000;
    assert_int_equal(c4gsim_vbus_step(&r->bus, US(r->now)), C4G_OK); /* boot-up messages */
    r->tr.n = 0;
    r->nev = 0;
}

static void drain_events(rig_t *r)
{
    c4g_co_event_t e;
    bool have = true;
    while (have) {
        assert_int_equal(c4g_co_master_event(&r->m, &e, &have), C4G_OK);
        if (have && r->nev < 256) {
            r->ev[r->nev++] = e;
        }
    }
}

static void run_until(rig_t *r, uint64_t until)
{
    while (r->now < until) {
        r->now += 1000;
        assert_int_equal(c4gsim_vbus_step(&r->bus, US(r->now)), C4G_OK);
        drain_events(r);
    }
}

static const c4g_co_event_t *find_ev(const rig_t *r, int kind, int node)
{
    for (int i = 0; i < r->nev; i++) {
        if (r->ev[i].kind == kind && (node == 0 || r->ev[i].node == node)) {
            return &r->ev[i];
        }
    }
    return NULL;
}

static int count_ev(const rig_t *r, int kind)
{
    int n = 0;
    for (int i = 0; i < r->nev; i++) {
        n += r->ev[i].kind == kind;
    }
    return n;
}

static void start(rig_t *r)
{
    assert_int_equal(c4g_co_master_start(&r->m, US(r->now)), C4G_OK);
    assert_int_equal(c4gsim_vbus_step(&r->bus, US(r->now)), C4G_OK);
    drain_events(r);
}

/* ---- expected traces */

typedef struct expect {
    char line[1024][32];
    int n;
} expect_t;

static void ex(expect_t *e, const char *s)
{
    snprintf(e->line[e->n++], 32, "%s", s);
}

static void ex_up(expect_t *e, int node, int index, int sub, uint32_t v)
{
    snprintf(e->line[e->n++], 32, "%03X#40%02X%02X%02X00000000", 0x600 + node, index & 0xFF,
             index >> 8, sub);
    snprintf(e->line[e->n++], 32, "%03X#43%02X%02X%02X%02X%02X%02X%02X", 0x580 + node,
             index & 0xFF, index >> 8, sub, v & 0xFF, (v >> 8) & 0xFF, (v >> 16) & 0xFF, v >> 24);
}

static void ex_dl(expect_t *e, int node, int index, int sub, int size, uint32_t v)
{
    uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    for (int i = size; i < 4; i++) {
        b[i] = 0;
    }
    snprintf(e->line[e->n++], 32, "%03X#%02X%02X%02X%02X%02X%02X%02X%02X", 0x600 + node,
             0x23 | ((4 - size) << 2), index & 0xFF, index >> 8, sub, b[0], b[1], b[2], b[3]);
    snprintf(e->line[e->n++], 32, "%03X#60%02X%02X%02X00000000", 0x580 + node, index & 0xFF,
             index >> 8, sub);
}

/* Step 5 for one PDO of node: disable, count 0, entries, count, type, enable. */
static void ex_pdo(expect_t *e, int node, int comm, const c4g_co_pdo_map_t *m, uint32_t cob)
{
    ex_dl(e, node, comm, 1, 4, cob | 0x80000000u);
    ex_dl(e, node, comm + 0x200, 0, 1, 0);
    for (int i = 0; i < m->n; i++) {
        ex_dl(e, node, comm + 0x200, i + 1, 4, m->entry[i]);
    }
    ex_dl(e, node, comm + 0x200, 0, 1, m->n);
    ex_dl(e, node, comm, 2, 1, m->trans);
    ex_dl(e, node, comm, 1, 4, cob);
}

static void assert_trace(const trace_t *tr, int from, const expect_t *e)
{
    assert_true(tr->n >= from + e->n);
    for (int i = 0; i < e->n; i++) {
        if (strcmp(tr->line[from + i], e->line[i]) != 0) {
            fail_msg("frame %d: got %s, expected %s", from + i, tr->line[from + i], e->line[i]);
        }
    }
}

static int find_line(const trace_t *tr, int from, const char *s)
{
    for (int i = from; i < tr->n; i++) {
        if (strcmp(tr->line[i], s) == 0) {
            return i;
        }
    }
    return -1;
}

/* ---- boot */

static void test_boot_heartbeat_order(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    rig_init(&r);
    start(&r);
    run_until(&r, r.now + 1000);
    /* byte-exact anchors written out by hand */
    assert_string_equal(r.tr.line[0], "000#8000");             /* 1: broadcast pre-operational */
    assert_string_equal(r.tr.line[1], "601#4000100000000000"); /* 2: upload 0x1000:00 */
    assert_string_equal(r.tr.line[2], "581#4300100092010200");
    assert_string_equal(r.tr.line[3], "601#23061000D0070000"); /* 3: 0x1006:00 = 2000 us */
    assert_string_equal(r.tr.line[5], "601#2B17100064000000"); /* 4: 0x1017:00 = 100 ms */
    assert_string_equal(r.tr.line[7], "601#2300180181010080"); /* 5: TPDO1 COB-ID disabled */
    expect_t e = {.n = 0};
    ex(&e, "000#8000");
    ex_up(&e, 1, 0x1000, 0, DEVTYPE);
    ex_dl(&e, 1, 0x1006, 0, 4, 2000);
    ex_dl(&e, 1, 0x1017, 0, 2, 100);
    ex_pdo(&e, 1, 0x1800, &r.cfg.node[0].rx[0], 0x181);
    ex_pdo(&e, 1, 0x1400, &r.cfg.node[0].tx[0], 0x201);
    ex(&e, "000#0100"); /* 6: broadcast start */
    ex(&e, "201#00000000000000"); /* 7: TxPDO then SYNC, then the node's TPDO */
    ex(&e, "080#");
    ex(&e, "181#400200000000");
    assert_trace(&r.tr, 0, &e);
    assert_non_null(find_ev(&r, C4G_CO_EV_NODE_READY, 1));
    assert_non_null(find_ev(&r, C4G_CO_EV_NET_STARTED, 0));
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.m.node[0].devtype_read, DEVTYPE);
    assert_int_equal(r.s[0].nmt, C4G_CO_STATE_OPERATIONAL);
    /* SYNC at the configured period, heartbeats keep the node */
    run_until(&r, r.now + 1000000);
    assert_int_equal(r.m.count.syncs, 101);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.m.node[0].nmt, C4G_CO_STATE_OPERATIONAL);
    assert_true(r.m.node[0].rx_pdos >= 100);
    int hb = find_line(&r.tr, 0, "701#05");
    assert_true(hb > 0);
    assert_int_equal(r.m.count.bad_dlc + r.m.count.unknown + r.m.count.foreign, 0);
}

/* Lifeguard: 0x100C, 0x100D, 0x1017 = 0; bit 30 of the device type: 0x1017 = 0 first. */
static void test_boot_lifeguard_orders(void **state)
{
    (void)state;
    static rig_t r;
    for (int rev = 0; rev < 2; rev++) {
        memset(&r, 0, sizeof r);
        net_cfg(&r.cfg, 1);
        node_cfg(&r.cfg.node[0], 1, C4G_CO_WD_LIFEGUARD, 0);
        if (rev) {
            r.cfg.node[0].device_type |= C4G_CO_DEVTYPE_LG_REVERSE;
        }
        rig_init(&r);
        /* second pass: a node whose toggle is not at 0 (not reset): its first reply sets it */
        r.s[0].guard_toggle = (uint8_t)rev;
        start(&r);
        expect_t e = {.n = 0};
        ex(&e, "000#8000");
        ex_up(&e, 1, 0x1000, 0, DEVTYPE); /* bit 30 is not compared */
        ex_dl(&e, 1, 0x1006, 0, 4, 2000);
        if (rev) {
            ex_dl(&e, 1, 0x1017, 0, 2, 0);
        }
        ex_dl(&e, 1, 0x100C, 0, 2, 100);
        ex_dl(&e, 1, 0x100D, 0, 1, 3);
        if (!rev) {
            ex_dl(&e, 1, 0x1017, 0, 2, 0);
        }
        ex(&e, "000#0100");
        assert_trace(&r.tr, 0, &e);
        assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
        /* guarding: remote request every guard time, replies toggle */
        int from = r.tr.n;
        run_until(&r, r.now + 450000);
        int g1 = find_line(&r.tr, from, "701#R");
        assert_true(g1 >= 0);
        assert_string_equal(r.tr.line[g1 + 1], rev ? "701#85" : "701#05");
        int g2 = find_line(&r.tr, g1 + 1, "701#R");
        assert_true(g2 > g1);
        assert_string_equal(r.tr.line[g2 + 1], rev ? "701#05" : "701#85");
        assert_int_equal(r.tr.t[g2] - r.tr.t[g1], 100000);
        assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
        assert_int_equal(r.m.count.bad_toggle, 0);
        /* no guard replies: lost after guard time x life time factor */
        r.s[0].no_heartbeat = 1;
        uint64_t t0 = r.now;
        run_until(&r, r.now + 400000);
        const c4g_co_event_t *lost = find_ev(&r, C4G_CO_EV_NODE_LOST, 1);
        assert_non_null(lost);
        assert_int_equal(lost->cause, C4G_CO_CAUSE_GUARD);
        assert_true(T_US(lost) > t0 && T_US(lost) <= t0 + 310000);
        assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_FAILED); /* no recovery flag */
        /* a node without the recovery flag is never polled */
        from = r.tr.n;
        run_until(&r, r.now + 6000000);
        assert_int_equal(find_line(&r.tr, from, "601#4000100000000000"), -1);
    }
}

typedef struct path_case {
    const char *what;
    uint16_t abort_index;
    uint8_t abort_sub;
    uint32_t flags;
    uint32_t devtype;   /* what the node reports */
    int silent;
    int boot;           /* expected final state */
    int step, cause;
    uint32_t value;
} path_case_t;

static void test_boot_bypass_and_abort(void **state)
{
    (void)state;
    static const path_case_t cases[] = {
        {"silent node", 0, 0, 0, DEVTYPE, 1, C4G_CO_BOOT_FAILED, 2, C4G_CO_CAUSE_SDO_TIMEOUT, C4G_CO_ABORT_TIMEOUT},
        {"silent node, recovery", 0, 0, C4G_CO_F_RECOVERY, DEVTYPE, 1, C4G_CO_BOOT_LOST, 2, C4G_CO_CAUSE_SDO_TIMEOUT, C4G_CO_ABORT_TIMEOUT},
        {"wrong device type", 0, 0, 0, 0x00020191, 0, C4G_CO_BOOT_FAILED, 2, C4G_CO_CAUSE_DEVTYPE, 0x00020191},
        {"wrong device type ignored", 0, 0, C4G_CO_F_IGNORE_DEVTYPE, 0x00020191, 0, C4G_CO_BOOT_RUNNING, 0, 0, 0},
        {"0x1000 aborted", 0x1000, 0, C4G_CO_F_BYPASS_CYCLE | C4G_CO_F_BYPASS_WD | C4G_CO_F_BYPASS_PDO, DEVTYPE, 0, C4G_CO_BOOT_FAILED, 2, C4G_CO_CAUSE_SDO_ABORT, C4G_CO_ABORT_NO_OBJECT},
        {"0x1006 aborted", 0x1006, 0, 0, DEVTYPE, 0, C4G_CO_BOOT_FAILED, 3, C4G_CO_CAUSE_SDO_ABORT, C4G_CO_ABORT_NO_OBJECT},
        {"0x1006 bypassed", 0x1006, 0, C4G_CO_F_BYPASS_CYCLE, DEVTYPE, 0, C4G_CO_BOOT_RUNNING, 3, C4G_CO_CAUSE_SDO_ABORT, C4G_CO_ABORT_NO_OBJECT},
        {"0x1017 aborted", 0x1017, 0, C4G_CO_F_BYPASS_CYCLE, DEVTYPE, 0, C4G_CO_BOOT_FAILED, 4, C4G_CO_CAUSE_SDO_ABORT, C4G_CO_ABORT_NO_OBJECT},
        {"0x1017 bypassed", 0x1017, 0, C4G_CO_F_BYPASS_WD, DEVTYPE, 0, C4G_CO_BOOT_RUNNING, 4, C4G_CO_CAUSE_SDO_ABORT, C4G_CO_ABORT_NO_OBJECT},
        {"0x1800:02 aborted", 0x1800, 2, C4G_CO_F_BYPASS_WD, DEVTYPE, 0, C4G_CO_BOOT_FAILED, 5, C4G_CO_CAUSE_SDO_ABORT, C4G_CO_ABORT_NO_OBJECT},
        {"0x1800:02 bypassed", 0x1800, 2, C4G_CO_F_BYPASS_PDO, DEVTYPE, 0, C4G_CO_BOOT_RUNNING, 5, C4G_CO_CAUSE_SDO_ABORT, C4G_CO_ABORT_NO_OBJECT},
    };
    static rig_t r;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const path_case_t *c = &cases[i];
        memset(&r, 0, sizeof r);
        net_cfg(&r.cfg, 2);
        r.cfg.node[0].flags = c->flags;
        rig_init(&r);
        r.s[0].device_type = c->devtype;
        r.s[0].silent = c->silent;
        r.s[0].abort_index = c->abort_index;
        r.s[0].abort_sub = c->abort_sub;
        r.s[0].abort_code = C4G_CO_ABORT_NO_OBJECT;
        start(&r);
        run_until(&r, r.now + 100000);
        const c4g_co_node_t *n = &r.m.node[0];
        if (n->boot != c->boot || n->fail_step != c->step || n->fail_cause != c->cause ||
            n->fail_value != c->value) {
            fail_msg("%s: boot %d step %d cause %d value %08X", c->what, n->boot, n->fail_step,
                     n->fail_cause, n->fail_value);
        }
        if (c->abort_index != 0) {
            assert_int_equal(n->fail_index, c->abort_index);
            assert_int_equal(n->fail_sub, c->abort_sub);
        }
        if (c->boot == C4G_CO_BOOT_RUNNING && c->step != 0) {
            assert_int_equal(n->bypassed, 1u << c->step);
        }
        if (c->boot != C4G_CO_BOOT_RUNNING) {
            const c4g_co_event_t *f = find_ev(&r, C4G_CO_EV_NODE_FAILED, 1);
            assert_non_null(f);
            assert_int_equal(f->step, c->step);
            assert_int_equal(f->cause, c->cause);
        }
        /* the other node boots and the network starts whatever happened to node 1 */
        assert_int_equal(r.m.node[1].boot, C4G_CO_BOOT_RUNNING);
        assert_non_null(find_ev(&r, C4G_CO_EV_NET_STARTED, 0));
        assert_int_equal(r.s[1].nmt, C4G_CO_STATE_OPERATIONAL);
    }
}

/* A silent node: the request, one retry after the SDO timeout, then the abort. */
static void test_boot_silent_retries(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    rig_init(&r);
    r.s[0].silent = 1;
    start(&r);
    run_until(&r, r.now + 100000);
    expect_t e = {.n = 0};
    ex(&e, "000#8000");
    ex(&e, "601#4000100000000000");
    ex(&e, "601#4000100000000000");
    ex(&e, "601#8000100000000405"); /* abort: SDO protocol timed out */
    ex(&e, "000#0100");
    assert_trace(&r.tr, 0, &e);
    assert_int_equal(r.tr.t[2] - r.tr.t[1], 20000);
    assert_int_equal(r.tr.t[3] - r.tr.t[2], 20000);
}

/* Without a watchdog: no 0x1017 and no supervision (the master cannot see the node go). */
static void test_boot_no_watchdog(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    node_cfg(&r.cfg.node[0], 1, C4G_CO_WD_NONE, 0);
    rig_init(&r);
    start(&r);
    expect_t e = {.n = 0};
    ex(&e, "000#8000");
    ex_up(&e, 1, 0x1000, 0, DEVTYPE);
    ex_dl(&e, 1, 0x1006, 0, 4, 2000);
    ex(&e, "000#0100");
    assert_trace(&r.tr, 0, &e);
    r.s[0].silent = 1;
    run_until(&r, r.now + 1000000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    /* a late poll: one SYNC, the next a full period later (no burst) */
    const uint32_t syncs = r.m.count.syncs;
    r.now += 55000;
    assert_int_equal(c4gsim_vbus_step(&r.bus, US(r.now)), C4G_OK);
    assert_int_equal(r.m.count.syncs, syncs + 1);
    assert_int_equal(r.m.next_sync_ns, US(r.now + 10000));
}

/* A wrong answer to a configuration SDO (bad command specifier): protocol failure. */
static void test_boot_protocol_failure(void **state)
{
    (void)state;
    static c4g_co_net_cfg_t c;
    static c4g_co_master_t m;
    net_cfg(&c, 1);
    assert_int_equal(c4g_co_master_init(&m, &c), C4G_OK);
    assert_int_equal(c4g_co_master_start(&m, 0), C4G_OK);
    c4g_co_frame_t f;
    bool have = true;
    while (have) {
        assert_int_equal(c4g_co_master_tx(&m, &f, &have), C4G_OK);
    }
    const uint8_t d[8] = {0x20, 0x00, 0x10, 0x00, 0, 0, 0, 0};
    memset(&f, 0, sizeof f);
    f.id = 0x581;
    f.dlc = 8;
    memcpy(f.data, d, 8);
    assert_int_equal(c4g_co_master_rx(&m, &f), C4G_OK);
    assert_int_equal(m.node[0].boot, C4G_CO_BOOT_FAILED);
    assert_int_equal(m.node[0].fail_cause, C4G_CO_CAUSE_SDO_PROTOCOL);
    assert_int_equal(m.node[0].fail_value, C4G_CO_ABORT_COMMAND);
}

/* ---- node loss and recovery */

static void test_loss_and_recovery(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 2);
    r.cfg.node[0].flags = C4G_CO_F_RECOVERY;
    rig_init(&r);
    start(&r);
    run_until(&r, r.now + 500000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    /* node 1 is unplugged */
    r.s[0].silent = 1;
    const uint64_t t_off = r.now;
    run_until(&r, r.now + 400000);
    const c4g_co_event_t *lost = find_ev(&r, C4G_CO_EV_NODE_LOST, 1);
    assert_non_null(lost);
    assert_int_equal(lost->cause, C4G_CO_CAUSE_HEARTBEAT);
    assert_true(T_US(lost) > t_off + 150000 && T_US(lost) <= t_off + 251000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_LOST);
    assert_int_equal(r.m.node[0].losses, 1);
    /* polls of DeviceType every 2.5 s while it stays away; node 2 keeps running */
    const uint32_t syncs = r.m.count.syncs;
    const uint32_t pdos2 = r.m.node[1].rx_pdos;
    int from = r.tr.n;
    run_until(&r, T_US(lost) + 7600000);
    uint64_t polls[8];
    int np = 0;
    for (int i = from; i < r.tr.n && np < 8; i++) {
        if (strcmp(r.tr.line[i], "601#4000100000000000") == 0 &&
            (np == 0 || r.tr.t[i] - polls[np - 1] > 100000)) {
            polls[np++] = r.tr.t[i];
        }
    }
    assert_int_equal(np, 3);
    assert_int_equal(polls[0] - T_US(lost), 2500000);
    assert_int_equal(polls[1] - polls[0], 2500000);
    assert_int_equal(polls[2] - polls[1], 2500000);
    assert_true(r.m.count.syncs - syncs >= 700);
    assert_true(r.m.node[1].rx_pdos - pdos2 >= 700);
    assert_int_equal(r.m.node[1].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(count_ev(&r, C4G_CO_EV_NODE_LOST), 1);
    /* it comes back (power cycle): at the next poll, steps 1-6 for it alone */
    assert_int_equal(c4gsim_slave_reset(&r.s[0]), C4G_OK);
    r.s[0].silent = 0;
    from = r.tr.n;
    run_until(&r, polls[2] + 2600000);
    int p = find_line(&r.tr, from, "601#4000100000000000");
    assert_true(p >= 0);
    assert_int_equal(r.tr.t[p], polls[2] + 2500000);
    assert_string_equal(r.tr.line[p + 1], "581#4300100092010200");
    assert_string_equal(r.tr.line[p + 2], "000#8001"); /* node-addressed pre-operational */
    assert_string_equal(r.tr.line[p + 3], "601#4000100000000000");
    int s1 = find_line(&r.tr, p, "000#0101"); /* node-addressed start */
    assert_true(s1 > p);
    assert_int_equal(find_line(&r.tr, from, "000#8000"), -1); /* never broadcast */
    assert_int_equal(find_line(&r.tr, from, "000#0100"), -1);
    const c4g_co_event_t *rec = find_ev(&r, C4G_CO_EV_NODE_RECOVERED, 1);
    assert_non_null(rec);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.s[0].nmt, C4G_CO_STATE_OPERATIONAL);
    run_until(&r, r.now + 500000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
}

/* A node reset while running (boot-up message) is lost; a wrong answer to the poll keeps it
   lost; a recovery whose configuration fails goes back to polling. */
static void test_bootup_and_failed_recovery(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    r.cfg.node[0].flags = C4G_CO_F_RECOVERY;
    rig_init(&r);
    start(&r);
    run_until(&r, r.now + 200000);
    assert_int_equal(c4gsim_slave_reset(&r.s[0]), C4G_OK);
    r.s[0].device_type = 0x1234; /* comes back as another device */
    run_until(&r, r.now + 5000);
    const c4g_co_event_t *lost = find_ev(&r, C4G_CO_EV_NODE_LOST, 1);
    assert_non_null(lost);
    assert_int_equal(lost->cause, C4G_CO_CAUSE_BOOTUP);
    run_until(&r, T_US(lost) + 2600000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_LOST); /* wrong DeviceType: still lost */
    /* right device, but 0x1017 is refused: the recovery aborts, polling goes on */
    r.s[0].device_type = DEVTYPE;
    r.s[0].abort_index = 0x1017;
    r.s[0].abort_code = C4G_CO_ABORT_HARDWARE;
    run_until(&r, T_US(lost) + 5100000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_LOST);
    const c4g_co_event_t *f = find_ev(&r, C4G_CO_EV_NODE_FAILED, 1);
    assert_non_null(f);
    assert_int_equal(f->step, C4G_CO_STEP_WATCHDOG);
    assert_int_equal(f->value, C4G_CO_ABORT_HARDWARE);
    r.s[0].abort_index = 0;
    run_until(&r, T_US(lost) + 7600000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_non_null(find_ev(&r, C4G_CO_EV_NODE_RECOVERED, 1));
    /* with the ignore flag, a node that comes back as another device type recovers too */
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    r.cfg.node[0].flags = C4G_CO_F_RECOVERY | C4G_CO_F_IGNORE_DEVTYPE;
    rig_init(&r);
    start(&r);
    run_until(&r, r.now + 100000);
    assert_int_equal(c4gsim_slave_reset(&r.s[0]), C4G_OK);
    r.s[0].device_type = 0x1234;
    run_until(&r, r.now + 2600000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.m.node[0].devtype_read, 0x1234);
    assert_non_null(find_ev(&r, C4G_CO_EV_NODE_RECOVERED, 1));
}

/* ---- process image, DS402 over PDOs, EMCY, user SDO, NMT */

static void test_ds402_over_pdos(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    rig_init(&r);
    start(&r);
    assert_int_equal(c4g_co_master_set(&r.m, 1, 0x6060, 0, C4G_CO_MODE_CSP), C4G_OK);
    uint16_t cw = 0;
    for (int i = 0; i < 20; i++) {
        uint32_t sw = 0;
        run_until(&r, r.now + 10000);
        assert_int_equal(c4g_co_master_get(&r.m, 1, true, 0x6041, 0, &sw), C4G_OK);
        if (c4g_co_ds402_state((uint16_t)sw) == C4G_CO_DS402_ENABLED) {
            break;
        }
        assert_int_equal(c4g_co_ds402_command((uint16_t)sw, C4G_CO_GOAL_ENABLED, cw, &cw), C4G_OK);
        assert_int_equal(c4g_co_master_set(&r.m, 1, 0x6040, 0, cw), C4G_OK);
    }
    assert_int_equal(r.s[0].ds402, C4G_CO_DS402_ENABLED);
    assert_int_equal(r.s[0].modes, 8);
    /* CSP: target in the RxPDO, actual position back in the TxPDO */
    assert_int_equal(c4g_co_master_set(&r.m, 1, 0x607A, 0, (uint32_t)-10000), C4G_OK);
    run_until(&r, r.now + 100000);
    uint32_t act = 0;
    assert_int_equal(c4g_co_master_get(&r.m, 1, true, 0x6064, 0, &act), C4G_OK);
    assert_int_equal((int32_t)act, -10000);
    uint32_t v = 0;
    assert_int_equal(c4g_co_master_get(&r.m, 1, false, 0x607A, 0, &v), C4G_OK);
    assert_int_equal((int32_t)v, -10000);
    assert_int_equal(c4g_co_master_get(&r.m, 1, true, 0x607A, 0, &v), C4G_ERR_ARG);
    assert_int_equal(c4g_co_master_get(&r.m, 9, true, 0x6064, 0, &v), C4G_ERR_ARG);
    assert_int_equal(c4g_co_master_get(&r.m, 1, true, 0x6064, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_get(NULL, 1, true, 0x6064, 0, &v), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_set(&r.m, 1, 0x6064, 0, 0), C4G_ERR_ARG);
    assert_int_equal(c4g_co_master_set(&r.m, 9, 0x6040, 0, 0), C4G_ERR_ARG);
    /* a drive fault: EMCY into the history, an event, statusword fault */
    c4g_co_frame_t out[8];
    int n = 0;
    for (int k = 0; k < 10; k++) {
        assert_int_equal(c4gsim_slave_fault(&r.s[0], (uint16_t)(0x7300 + k), out, &n), C4G_OK);
        assert_int_equal(n, 1);
        assert_int_equal(c4gsim_vbus_inject(&r.bus, &out[0], US(r.now)), C4G_OK);
    }
    drain_events(&r);
    const c4g_co_node_t *nd = &r.m.node[0];
    assert_int_equal(nd->emcy_n, C4G_CO_EMCY_DEPTH);
    assert_int_equal(nd->emcy[(nd->emcy_head + C4G_CO_EMCY_DEPTH - 1) % C4G_CO_EMCY_DEPTH].code, 0x7309);
    assert_int_equal(nd->emcy[nd->emcy_head].code, 0x7302); /* oldest kept */
    assert_int_equal(nd->emcy[nd->emcy_head].reg, 0x01);
    const c4g_co_event_t *em = find_ev(&r, C4G_CO_EV_EMCY, 1);
    assert_non_null(em);
    assert_int_equal(em->value, 0x7300);
    assert_int_equal(count_ev(&r, C4G_CO_EV_EMCY), 10);
    run_until(&r, r.now + 20000);
    uint32_t sw = 0;
    assert_int_equal(c4g_co_master_get(&r.m, 1, true, 0x6041, 0, &sw), C4G_OK);
    assert_int_equal(c4g_co_ds402_state((uint16_t)sw), C4G_CO_DS402_FAULT);
}

static void test_user_sdo_and_nmt(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    rig_init(&r);
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, true, 0x1000, 0, 0, 0, US(r.now)), C4G_ERR_STATE);
    start(&r);
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, true, 0x1017, 0, 0, 0, US(r.now)), C4G_OK);
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, true, 0x1017, 0, 0, 0, US(r.now)), C4G_ERR_STATE);
    run_until(&r, r.now + 2000);
    const c4g_co_event_t *d = find_ev(&r, C4G_CO_EV_SDO_DONE, 1);
    assert_non_null(d);
    assert_int_equal(d->index, 0x1017);
    assert_int_equal(d->cause, 0);
    assert_int_equal(d->value, 100);
    /* write 0x6060 by SDO, then read it back */
    r.nev = 0;
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, false, 0x6060, 0, 8, 1, US(r.now)), C4G_OK);
    run_until(&r, r.now + 2000);
    assert_int_equal(r.s[0].modes, 8);
    assert_non_null(find_ev(&r, C4G_CO_EV_SDO_DONE, 1));
    /* an object the node does not have: the abort code comes back */
    r.nev = 0;
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, true, 0x2000, 0, 0, 0, US(r.now)), C4G_OK);
    run_until(&r, r.now + 2000);
    d = find_ev(&r, C4G_CO_EV_SDO_DONE, 1);
    assert_non_null(d);
    assert_int_equal(d->cause, C4G_CO_CAUSE_SDO_ABORT);
    assert_int_equal(d->value, C4G_CO_ABORT_NO_OBJECT);
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, false, 0x6060, 0, 8, 0, US(r.now)), C4G_ERR_LENGTH);
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, false, 0x6060, 0, 8, 5, US(r.now)), C4G_ERR_LENGTH);
    assert_int_equal(c4g_co_master_sdo(&r.m, 9, true, 0x6060, 0, 0, 0, US(r.now)), C4G_ERR_ARG);
    assert_int_equal(c4g_co_master_sdo(NULL, 1, true, 0x6060, 0, 0, 0, US(r.now)), C4G_ERR_NULL);
    /* S_NMT: stop one node, then start all; the stopped node no longer runs (without the
       recovery flag it stays failed) */
    assert_int_equal(c4g_co_master_nmt(&r.m, 1, C4G_CO_NMT_STOP), C4G_OK);
    run_until(&r, r.now + 300000);
    assert_int_equal(r.s[0].nmt, C4G_CO_STATE_STOPPED);
    assert_int_equal(r.m.node[0].nmt, C4G_CO_STATE_STOPPED);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_FAILED);
    /* a user SDO to a stopped node times out */
    r.nev = 0;
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, true, 0x1000, 0, 0, 0, US(r.now)), C4G_OK);
    run_until(&r, r.now + 50000);
    d = find_ev(&r, C4G_CO_EV_SDO_DONE, 1);
    assert_non_null(d);
    assert_int_equal(d->cause, C4G_CO_CAUSE_SDO_TIMEOUT);
    assert_int_equal(c4g_co_master_nmt(&r.m, 0, C4G_CO_NMT_START), C4G_OK);
    run_until(&r, r.now + 300000);
    assert_int_equal(r.m.node[0].nmt, C4G_CO_STATE_OPERATIONAL);
    assert_int_equal(c4g_co_master_nmt(&r.m, 9, C4G_CO_NMT_START), C4G_ERR_ARG);
    assert_int_equal(c4g_co_master_nmt(&r.m, 1, 0x33), C4G_ERR_ARG);
    assert_int_equal(c4g_co_master_nmt(NULL, 1, 1), C4G_ERR_NULL);
}

/* A running node that reports STOPPED or PRE-OPERATIONAL (heartbeat or guard reply) no longer
   runs: an event of its own (not NODE_LOST), no RPDO sent to it, its TPDOs not taken; with
   the recovery flag the DeviceType poll boots it again once it answers. A report within the
   start grace, before the node was seen operational, may predate NMT Start: ignored. */
static void inject(rig_t *r, uint16_t id, uint8_t dlc, int rtr, const uint8_t *d);

static void test_nmt_state_not_running(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 2);
    r.cfg.node[0].flags = C4G_CO_F_RECOVERY;
    node_cfg(&r.cfg.node[1], 2, C4G_CO_WD_LIFEGUARD, 1);
    rig_init(&r);
    start(&r);
    run_until(&r, r.now + 300000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.m.node[1].boot, C4G_CO_BOOT_RUNNING);
    /* heartbeat node 1 stopped by another master's NMT */
    r.nev = 0;
    assert_int_equal(c4g_co_master_nmt(&r.m, 1, C4G_CO_NMT_STOP), C4G_OK);
    run_until(&r, r.now + 200000);
    const c4g_co_event_t *e = find_ev(&r, C4G_CO_EV_NODE_STATE, 1);
    assert_non_null(e);
    assert_int_equal(e->cause, C4G_CO_CAUSE_NMT_STATE);
    assert_int_equal(e->value, C4G_CO_STATE_STOPPED);
    assert_int_equal(count_ev(&r, C4G_CO_EV_NODE_LOST), 0);
    assert_int_equal(count_ev(&r, C4G_CO_EV_NODE_STATE), 1);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_LOST);
    assert_int_equal(r.m.node[0].fail_cause, C4G_CO_CAUSE_NMT_STATE);
    assert_int_equal(r.m.node[0].losses, 1);
    /* no RPDO goes to it any more; node 2 keeps its PDOs */
    int from = r.tr.n;
    run_until(&r, r.now + 100000);
    int to1 = 0, to2 = 0;
    for (int i = from; i < r.tr.n; i++) {
        to1 += strncmp(r.tr.line[i], "201#", 4) == 0;
        to2 += strncmp(r.tr.line[i], "202#", 4) == 0;
    }
    assert_int_equal(to1, 0);
    assert_true(to2 >= 9);
    /* a TPDO it would still send is not taken */
    const uint32_t pdos = r.m.node[0].rx_pdos;
    const uint8_t tpdo[8] = {0x37, 0x02, 0x10, 0x27, 0, 0, 0, 0};
    inject(&r, 0x181, 6, 0, tpdo);
    assert_int_equal(r.m.node[0].rx_pdos, pdos);
    /* started again by NMT: the next DeviceType poll finds it, steps 1-6 run again */
    assert_int_equal(c4g_co_master_nmt(&r.m, 1, C4G_CO_NMT_START), C4G_OK);
    run_until(&r, T_US(e) + 2600000);
    assert_non_null(find_ev(&r, C4G_CO_EV_NODE_RECOVERED, 1));
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    /* lifeguarded node 2 sent to pre-operational: the guard reply says so */
    r.nev = 0;
    assert_int_equal(c4g_co_master_nmt(&r.m, 2, C4G_CO_NMT_PREOP), C4G_OK);
    run_until(&r, r.now + 300000);
    e = find_ev(&r, C4G_CO_EV_NODE_STATE, 2);
    assert_non_null(e);
    assert_int_equal(e->value, C4G_CO_STATE_PREOP);
    assert_int_equal(r.m.node[1].boot, C4G_CO_BOOT_FAILED); /* no recovery flag */
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    /* the grace: a PRE-OPERATIONAL heartbeat right after NMT Start, before the node was
       seen operational, may have been queued before the Start: not an event */
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    rig_init(&r);
    r.s[0].no_heartbeat = 1;
    start(&r);
    while (find_ev(&r, C4G_CO_EV_NET_STARTED, 0) == NULL) {
        run_until(&r, r.now + 1000);
    }
    const uint8_t preop[8] = {C4G_CO_STATE_PREOP, 0, 0, 0, 0, 0, 0, 0};
    inject(&r, 0x701, 1, 0, preop);
    drain_events(&r);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_null(find_ev(&r, C4G_CO_EV_NODE_STATE, 1));
    r.s[0].no_heartbeat = 0;
    run_until(&r, r.now + 200000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.m.node[0].op_seen, 1);
    /* once the node was seen operational, the same report is an event at once */
    r.s[0].no_heartbeat = 1;
    r.now += 10000;
    inject(&r, 0x701, 1, 0, preop);
    drain_events(&r);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_FAILED);
    assert_non_null(find_ev(&r, C4G_CO_EV_NODE_STATE, 1));
}

/* ---- the poll's next deadline */

/* Frames the master queued (taken), 0 when none. */
static int take_all(rig_t *r, int *syncs)
{
    c4g_co_frame_t f;
    bool have = true;
    int n = 0;
    *syncs = 0;
    while (c4g_co_master_tx(&r->m, &f, &have) == C4G_OK && have) {
        n++;
        *syncs += (f.id == 0x080);
    }
    return n;
}

/* A caller that sleeps until the deadline the poll gives misses nothing: one ns before it
 * the poll has no work, at it the work is done (SYNC, guard request, loss, recovery poll). */
static void test_poll_deadline(void **state)
{
    (void)state;
    static rig_t r;
    uint64_t next = 0U, next2 = 0U;
    int syncs = 0;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 2);
    node_cfg(&r.cfg.node[1], 2, C4G_CO_WD_LIFEGUARD, 1);
    r.cfg.node[0].flags = C4G_CO_F_RECOVERY;
    rig_init(&r);
    start(&r);
    run_until(&r, r.now + 500000);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.m.node[1].boot, C4G_CO_BOOT_RUNNING);
    /* running: the next SYNC or the next guard request, whichever is first */
    assert_int_equal(c4g_co_master_poll(&r.m, US(r.now), &next), C4G_OK);
    (void)take_all(&r, &syncs);
    assert_true(next > US(r.now));
    assert_true(next == (r.m.next_sync_ns < r.m.node[1].next_ns ? r.m.next_sync_ns
                                                                  : r.m.node[1].next_ns));
    assert_int_equal(c4g_co_master_poll(&r.m, next - 1U, &next2), C4G_OK);
    assert_int_equal(take_all(&r, &syncs), 0);
    assert_true(next2 == next);
    assert_int_equal(c4g_co_master_poll(&r.m, next, &next2), C4G_OK);
    assert_true(take_all(&r, &syncs) > 0);
    assert_true(next2 > next);
    /* node 1 goes silent; poll only at the deadlines given: the loss comes at its heartbeat
     * deadline (250 ms after the last heartbeat), then its recovery poll 2.5 s later */
    r.s[0].silent = 1;
    {
        const uint64_t seen = r.m.node[0].last_seen_ns;
        uint64_t t = next2;
        int k;
        for (k = 0; k < 2000 && r.m.node[0].boot == C4G_CO_BOOT_RUNNING; k++) {
            assert_true(t <= seen + US(250000) + 1U);
            assert_int_equal(c4g_co_master_poll(&r.m, t, &t), C4G_OK);
            (void)take_all(&r, &syncs);
        }
        assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_LOST);
        assert_true(r.m.node[0].next_ns == seen + US(250000) + 1U + C4G_CO_RECOVERY_POLL_NS);
        assert_true(t <= r.m.node[0].next_ns);
    }
}

/* ---- hostile frames: counted, never trusted */

static void inject(rig_t *r, uint16_t id, uint8_t dlc, int rtr, const uint8_t *d)
{
    c4g_co_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = dlc;
    f.rtr = (uint8_t)rtr;
    if (d != NULL) {
        memcpy(f.data, d, 8);
    }
    f.t_ns = US(r->now);
    assert_int_equal(c4g_co_master_rx(&r->m, &f), C4G_OK);
}

static void test_hostile_frames(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 2);
    node_cfg(&r.cfg.node[1], 2, C4G_CO_WD_LIFEGUARD, 1);
    rig_init(&r);
    start(&r);
    run_until(&r, r.now + 50000);
    c4g_co_counters_t before = r.m.count;
    uint32_t pos_before = r.m.node[0].rx_val[0][1];
    const uint8_t z[8] = {0};
    const uint8_t st5[8] = {0x05};
    const uint8_t st85[8] = {0x85};
    const uint8_t st6[8] = {0x06};
    const uint8_t big[8] = {0x41, 0x02, 0, 0, 0x78, 0x56, 0x34, 0x12};
    inject(&r, 0x800, 0, 0, NULL);         /* bad frame: id */
    inject(&r, 0x181, 9, 0, z);            /* bad frame: dlc */
    inject(&r, 0x701, 2, 0, st5);          /* heartbeat of wrong length */
    inject(&r, 0x701, 1, 0, st6);          /* impossible NMT state */
    inject(&r, 0x701, 1, 0, st85);         /* toggle set in a heartbeat */
    inject(&r, 0x702, 1, 0, r.m.node[1].toggle ? st5 : st85); /* guard reply, wrong toggle */
    inject(&r, 0x000, 2, 0, z);            /* NMT from another master */
    inject(&r, 0x080, 0, 0, NULL);         /* SYNC from another master */
    inject(&r, 0x201, 7, 0, z);            /* RPDO from another master */
    inject(&r, 0x601, 8, 0, z);            /* SDO request from another client */
    inject(&r, 0x100, 6, 0, z);            /* TIME */
    inject(&r, 0x705, 1, 0, st5);          /* heartbeat of no configured node */
    inject(&r, 0x7E5, 1, 0, st5);          /* unknown identifier */
    inject(&r, 0x181, 6, 1, z);            /* remote request */
    inject(&r, 0x081, 4, 0, z);            /* EMCY too short */
    inject(&r, 0x181, 8, 0, big);          /* TPDO of the wrong length */
    inject(&r, 0x281, 2, 0, z);            /* TPDO2: not mapped */
    inject(&r, 0x581, 8, 0, big);          /* SDO answer with no transfer */
    inject(&r, 0x585, 8, 0, big);          /* SDO answer of no configured node */
    assert_int_equal(r.m.count.bad_frame - before.bad_frame, 2);
    assert_int_equal(r.m.count.bad_dlc - before.bad_dlc, 3);
    assert_int_equal(r.m.count.bad_value - before.bad_value, 1);
    assert_int_equal(r.m.count.bad_toggle - before.bad_toggle, 2);
    assert_int_equal(r.m.count.foreign - before.foreign, 4);
    assert_int_equal(r.m.count.unknown - before.unknown, 5);
    assert_int_equal(r.m.count.rtr - before.rtr, 1);
    assert_int_equal(r.m.count.sdo_ignored - before.sdo_ignored, 1);
    assert_int_equal(r.m.count.rx - before.rx, 19);
    assert_int_equal(r.m.node[0].rx_val[0][1], pos_before);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    assert_int_equal(r.m.node[1].boot, C4G_CO_BOOT_RUNNING);
    /* during a user SDO: an answer for another object is not trusted */
    assert_int_equal(c4g_co_master_sdo(&r.m, 1, true, 0x1017, 0, 0, 0, US(r.now)), C4G_OK);
    bool have = true;
    c4g_co_frame_t f;
    while (have) {
        assert_int_equal(c4g_co_master_tx(&r.m, &f, &have), C4G_OK);
    }
    const uint8_t other[8] = {0x43, 0x06, 0x10, 0x00, 1, 2, 3, 4};
    inject(&r, 0x581, 8, 0, other);
    assert_int_equal(r.m.count.sdo_ignored - before.sdo_ignored, 2);
    inject(&r, 0x582, 8, 0, other); /* node 2 answers while node 1's transfer runs */
    assert_int_equal(r.m.count.sdo_ignored - before.sdo_ignored, 3);
    assert_true(c4g_co_sdo_busy(&r.m.sdo));
    /* a heartbeat stamped after the poll's time: no underflow, the node stays */
    c4g_co_frame_t hb;
    uint64_t next = 0U;
    assert_int_equal(c4g_co_ec_encode(&hb, 1, C4G_CO_STATE_OPERATIONAL, 0), C4G_OK);
    hb.t_ns = US(r.now + 500000);
    assert_int_equal(c4g_co_master_rx(&r.m, &hb), C4G_OK);
    assert_int_equal(c4g_co_master_poll(&r.m, US(r.now + 1000), &next), C4G_OK);
    assert_int_equal(r.m.node[0].boot, C4G_CO_BOOT_RUNNING);
    /* node 2's boot-up in pre-operational after a reset: lost */
    inject(&r, 0x702, 1, 0, z);
    assert_int_equal(r.m.node[1].boot, C4G_CO_BOOT_FAILED);
    assert_int_equal(r.m.node[1].fail_cause, C4G_CO_CAUSE_BOOTUP);
    /* a TPDO of a node that is not running */
    before = r.m.count;
    inject(&r, 0x182, 6, 0, z);
    assert_int_equal(r.m.count.unknown - before.unknown, 1);
}

/* ---- configuration, queues, misuse */

static void test_config_check(void **state)
{
    (void)state;
    static c4g_co_net_cfg_t good, c;
    static c4g_co_master_t m;
    uint8_t bad = 0;
    net_cfg(&good, 3);
    node_cfg(&good.node[1], 2, C4G_CO_WD_LIFEGUARD, 1);
    node_cfg(&good.node[2], 3, C4G_CO_WD_NONE, 0);
    assert_int_equal(c4g_co_net_check(&good, &bad), C4G_OK);
    assert_int_equal(bad, 0xFF);
#define NET_BAD(stmt)                                                     \
    do {                                                                  \
        c = good;                                                         \
        stmt;                                                             \
        assert_int_equal(c4g_co_net_check(&c, &bad), C4G_ERR_RANGE);      \
        assert_int_equal(c4g_co_master_init(&m, &c), C4G_ERR_RANGE);      \
    } while (0)
    NET_BAD(c.n_nodes = 0);
    NET_BAD(c.n_nodes = 17);
    NET_BAD(c.channel = 4);
    NET_BAD(c.bitrate = 9999);
    NET_BAD(c.bitrate = 1000001);
    NET_BAD(c.sync_period_ns = US(499));
    NET_BAD(c.sync_period_ns = US(1000001));
    NET_BAD(c.sdo_timeout_ns = US(999));
    NET_BAD(c.sdo_timeout_ns = US(10000001));
    NET_BAD(c.sdo_retries = 6);
#define NODE_BAD(slot, stmt)                                              \
    do {                                                                  \
        c = good;                                                         \
        stmt;                                                             \
        assert_int_equal(c4g_co_net_check(&c, &bad), C4G_ERR_ARG);        \
        assert_int_equal(bad, slot);                                      \
    } while (0)
    NODE_BAD(0, c.node[0].node_id = 0);
    NODE_BAD(0, c.node[0].node_id = 128);
    NODE_BAD(0, c.node[0].station = 0);
    NODE_BAD(0, c.node[0].station = 65);
    NODE_BAD(0, c.node[0].axis = 0);
    NODE_BAD(0, c.node[0].axis = 33);
    NODE_BAD(0, c.node[0].flags = 0x20);
    NODE_BAD(0, c.node[0].heartbeat_ms = 0);
    NODE_BAD(0, c.node[0].consumer_ms = 100);
    NODE_BAD(1, c.node[1].guard_ms = 0);
    NODE_BAD(1, c.node[1].life_factor = 0);
    NODE_BAD(2, c.node[2].watchdog = 3);
    NODE_BAD(0, c.node[0].rx[0].entry[0] = C4G_CO_MAP(0x6041, 0, 12));
    NODE_BAD(0, c.node[0].tx[0].trans = 0);
    NODE_BAD(0, c.node[0].tx[0].trans = 241);
    NODE_BAD(1, c.node[1].node_id = 1);
    NODE_BAD(2, c.node[2].station = 2);
    NODE_BAD(2, c.node[2].node_id = 1);
    c = good;
    c.node[0].tx[0].trans = 254;
    assert_int_equal(c4g_co_net_check(&c, &bad), C4G_OK);
    assert_int_equal(c4g_co_net_check(NULL, &bad), C4G_ERR_NULL);
    assert_int_equal(c4g_co_net_check(&good, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_init(NULL, &good), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_init(&m, NULL), C4G_ERR_NULL);
}

static void test_master_misuse_and_queues(void **state)
{
    (void)state;
    static rig_t r;
    memset(&r, 0, sizeof r);
    net_cfg(&r.cfg, 1);
    rig_init(&r);
    c4g_co_frame_t f;
    c4g_co_event_t e;
    bool have;
    uint8_t slot;
    uint64_t next = 0U;
    assert_int_equal(c4g_co_master_start(NULL, 0), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_rx(NULL, &f), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_rx(&r.m, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_poll(NULL, 0, &next), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_poll(&r.m, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_tx(NULL, &f, &have), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_tx(&r.m, NULL, &have), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_tx(&r.m, &f, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_event(NULL, &e, &have), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_event(&r.m, NULL, &have), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_event(&r.m, &e, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_slot(NULL, 1, &slot), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_slot(&r.m, 1, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_master_slot(&r.m, 1, &slot), C4G_OK);
    assert_int_equal(slot, 0);
    assert_int_equal(c4g_co_master_slot(&r.m, 2, &slot), C4G_ERR_ARG);
    /* poll before start: nothing happens */
    assert_int_equal(c4g_co_master_poll(&r.m, US(5000), &next), C4G_OK);
    assert_true(next == C4G_NO_DEADLINE); /* not started: nothing timed */
    assert_int_equal(c4g_co_master_tx(&r.m, &f, &have), C4G_OK);
    assert_false(have);
    assert_int_equal(c4g_co_master_start(&r.m, US(5000)), C4G_OK);
    assert_int_equal(c4g_co_master_start(&r.m, US(5000)), C4G_ERR_STATE);
    /* transmit queue full: frames counted as dropped */
    for (int i = 0; i < (int)C4G_CO_TXQ_LEN + 5; i++) {
        assert_int_equal(c4g_co_master_nmt(&r.m, 1, C4G_CO_NMT_PREOP), C4G_OK);
    }
    assert_true(r.m.count.txq_full >= 5);
    /* event queue full */
    for (int i = 0; i < (int)C4G_CO_EVQ_LEN + 3; i++) {
        c4g_co_emcy_t em = {0};
        em.code = 0x1000;
        assert_int_equal(c4g_co_emcy_encode(&f, 1, &em), C4G_OK);
        assert_int_equal(c4g_co_master_rx(&r.m, &f), C4G_OK);
    }
    assert_int_equal(r.m.count.evq_full, 3);
    int n = 0;
    have = true;
    while (have) {
        assert_int_equal(c4g_co_master_event(&r.m, &e, &have), C4G_OK);
        n += have;
    }
    assert_int_equal(n, C4G_CO_EVQ_LEN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_boot_heartbeat_order),
        cmocka_unit_test(test_boot_lifeguard_orders),
        cmocka_unit_test(test_boot_bypass_and_abort),
        cmocka_unit_test(test_boot_silent_retries),
        cmocka_unit_test(test_boot_no_watchdog),
        cmocka_unit_test(test_boot_protocol_failure),
        cmocka_unit_test(test_loss_and_recovery),
        cmocka_unit_test(test_bootup_and_failed_recovery),
        cmocka_unit_test(test_ds402_over_pdos),
        cmocka_unit_test(test_user_sdo_and_nmt),
        cmocka_unit_test(test_poll_deadline),
        cmocka_unit_test(test_nmt_state_not_running),
        cmocka_unit_test(test_hostile_frames),
        cmocka_unit_test(test_config_check),
        cmocka_unit_test(test_master_misuse_and_queues),
    };
    return cmocka_run_group_tests_name("canopen master on simulated DS402 nodes", tests, NULL, NULL);
}
