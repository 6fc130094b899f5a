/* SPDX-License-Identifier: MIT */
/* Unit tests of lib/sim/c4gsim_vbus.c: the in-process CAN bus between the CANopen master
 * and simulated nodes (order of frames, their times, the log, capacity). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "c4gsim_vbus.h"

#define DEVTYPE 0x00020192UL

typedef struct trace {
    c4g_co_frame_t f[64];
    int n;
} trace_t;

static void log_fn(void *ctx, const c4g_co_frame_t *f)
{
    trace_t *t = ctx;
    if (t->n < 64) {
        t->f[t->n] = *f;
        t->n++;
    }
}

static void test_init_add(void **state)
{
    static c4gsim_slave_t s[C4G_CO_MAX_NODES + 1U];
    c4gsim_vbus_t b;
    uint32_t i;
    (void)state;
    assert_int_equal(c4gsim_vbus_init(NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_vbus_init(&b, NULL), C4G_OK);
    assert_null(b.master);
    assert_int_equal(b.n_slaves, 0);
    assert_int_equal(c4gsim_vbus_add(NULL, &s[0]), C4G_ERR_NULL);
    assert_int_equal(c4gsim_vbus_add(&b, NULL), C4G_ERR_NULL);
    for (i = 0; i < C4G_CO_MAX_NODES; i++) {
        assert_int_equal(c4gsim_slave_init(&s[i], (uint8_t)(i + 1U), DEVTYPE), C4G_OK);
        assert_int_equal(c4gsim_vbus_add(&b, &s[i]), C4G_OK);
    }
    assert_int_equal(c4gsim_vbus_add(&b, &s[C4G_CO_MAX_NODES]), C4G_ERR_CAPACITY);
    assert_int_equal(b.n_slaves, C4G_CO_MAX_NODES);
    assert_ptr_equal(b.slave[C4G_CO_MAX_NODES - 1U], &s[C4G_CO_MAX_NODES - 1U]);
    assert_int_equal(c4gsim_vbus_step(NULL, 0), C4G_ERR_NULL);
    {
        c4g_co_frame_t f;
        memset(&f, 0, sizeof f);
        assert_int_equal(c4gsim_vbus_inject(NULL, &f, 0), C4G_ERR_NULL);
    }
}

/* Nodes alone: their boot-up messages on the bus, stamped and logged once each. */
static void test_nodes_alone(void **state)
{
    c4gsim_slave_t s[2];
    c4gsim_vbus_t b;
    trace_t t;
    c4g_co_frame_t f;
    (void)state;
    memset(&t, 0, sizeof t);
    assert_int_equal(c4gsim_vbus_init(&b, NULL), C4G_OK);
    b.log = log_fn;
    b.log_ctx = &t;
    assert_int_equal(c4gsim_slave_init(&s[0], 3, DEVTYPE), C4G_OK);
    assert_int_equal(c4gsim_slave_init(&s[1], 9, DEVTYPE), C4G_OK);
    assert_int_equal(c4gsim_vbus_add(&b, &s[0]), C4G_OK);
    assert_int_equal(c4gsim_vbus_add(&b, &s[1]), C4G_OK);
    assert_int_equal(c4gsim_vbus_step(&b, 1234), C4G_OK);
    assert_int_equal(t.n, 2);
    assert_int_equal(t.f[0].id, 0x703);
    assert_int_equal(t.f[1].id, 0x709);
    assert_true(t.f[0].t_ns == 1234U && t.f[1].t_ns == 1234U);
    assert_true(b.frames == 2U);
    assert_int_equal(c4gsim_vbus_step(&b, 2000), C4G_OK); /* quiet */
    assert_int_equal(t.n, 2);
    /* an injected frame: logged with its time; no master to take it */
    memset(&f, 0, sizeof f);
    f.id = 0x083;
    f.dlc = 8;
    assert_int_equal(c4gsim_vbus_inject(&b, NULL, 5000), C4G_ERR_NULL);
    assert_int_equal(c4gsim_vbus_inject(&b, &f, 5000), C4G_OK);
    assert_int_equal(t.n, 3);
    assert_true(t.f[2].id == 0x083 && t.f[2].t_ns == 5000U && b.frames == 3U);
    assert_true(f.t_ns == 0U); /* the caller's frame is not touched */
    b.log = NULL; /* no log: still counted */
    assert_int_equal(c4gsim_vbus_inject(&b, &f, 6000), C4G_OK);
    assert_true(b.frames == 4U && t.n == 3);
}

/* With the master: its frames reach every node, their answers reach the master, in order. */
static void test_with_master(void **state)
{
    static c4g_co_master_t m;
    c4g_co_net_cfg_t cfg;
    c4gsim_slave_t s;
    c4gsim_vbus_t b;
    trace_t t;
    int k;
    (void)state;
    memset(&cfg, 0, sizeof cfg);
    memset(&t, 0, sizeof t);
    cfg.bitrate = 500000;
    cfg.sync_period_ns = 10000000U;
    cfg.sdo_timeout_ns = 20000000U;
    cfg.sdo_retries = 1;
    cfg.n_nodes = 1;
    cfg.node[0].node_id = 4;
    cfg.node[0].device_type = DEVTYPE;
    cfg.node[0].heartbeat_ms = 100;
    cfg.node[0].station = 4;
    cfg.node[0].axis = 4;
    cfg.node[0].cycle_period_us = 2000;
    cfg.node[0].consumer_ms = 250;
    cfg.node[0].watchdog = C4G_CO_WD_HEARTBEAT;
    assert_int_equal(c4g_co_master_init(&m, &cfg), C4G_OK);
    assert_int_equal(c4gsim_vbus_init(&b, &m), C4G_OK);
    assert_int_equal(c4gsim_slave_init(&s, 4, DEVTYPE), C4G_OK);
    assert_int_equal(c4gsim_vbus_add(&b, &s), C4G_OK);
    b.log = log_fn;
    b.log_ctx = &t;
    assert_int_equal(c4g_co_master_start(&m, 1000000U), C4G_OK);
    for (k = 0; k < 20; k++) {
        assert_int_equal(c4gsim_vbus_step(&b, 1000000U + 1000000U * (uint64_t)k), C4G_OK);
    }
    /* the boot-up message first; the master's first SDO request, then the node's answer */
    assert_true(t.n >= 3);
    assert_int_equal(t.f[0].id, 0x704);
    for (k = 1; k < t.n && t.f[k].id != 0x604; k++) {
    }
    assert_true(k + 1 < t.n);
    assert_int_equal(t.f[k].data[0], 0x40); /* an upload: the device type first */
    assert_int_equal(t.f[k].data[1] | (t.f[k].data[2] << 8), 0x1000);
    assert_int_equal(t.f[k + 1].id, 0x584);
    assert_int_equal(t.f[k + 1].data[0], 0x43);
    assert_true(t.f[k + 1].t_ns == t.f[k].t_ns); /* answered within the same step */
    assert_true(s.sdo_requests >= 1U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init_add),
        cmocka_unit_test(test_nodes_alone),
        cmocka_unit_test(test_with_master),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
