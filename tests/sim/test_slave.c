/* SPDX-License-Identifier: MIT */
/* Unit tests of lib/sim/c4gsim_slave.c: the simulated DS402 node frame by frame (NMT,
 * SDO server expedited and segmented, PDOs on SYNC, node guarding, heartbeat, faults). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* the slave's times are in ns; the figures of the heartbeat test are written in us */
#define US(x) ((uint64_t)(x) * 1000U)
#include <cmocka.h>

#include "c4gsim_slave.h"

#define NODE 5U
#define DEVTYPE 0x00020192UL

typedef struct rig {
    c4gsim_slave_t s;
    c4g_co_frame_t out[C4GSIM_SLAVE_OUT];
    int n;
} rig_t;

static void frame(c4g_co_frame_t *f, uint16_t id, uint8_t dlc, const uint8_t *data)
{
    memset(f, 0, sizeof *f);
    f->id = id;
    f->dlc = dlc;
    if (data != NULL) {
        memcpy(f->data, data, dlc);
    }
}

static void rx(rig_t *r, const c4g_co_frame_t *f)
{
    r->n = -1;
    assert_int_equal(c4gsim_slave_rx(&r->s, f, r->out, &r->n), C4G_OK);
}

/* An SDO request: command byte, index, sub-index, 4 data bytes (little-endian @p v). */
static void sdo(rig_t *r, uint8_t cmd, uint16_t index, uint8_t sub, uint32_t v)
{
    const uint8_t d[8] = {cmd, (uint8_t)index, (uint8_t)(index >> 8), sub,
                          (uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    c4g_co_frame_t f;
    frame(&f, (uint16_t)(0x600U + NODE), 8, d);
    rx(r, &f);
}

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

/* The one answer: an SDO response with command @p cmd. */
static void expect_sdo(const rig_t *r, uint8_t cmd)
{
    assert_int_equal(r->n, 1);
    assert_int_equal(r->out[0].id, 0x580U + NODE);
    assert_int_equal(r->out[0].dlc, 8);
    assert_int_equal(r->out[0].data[0], cmd);
}

static void expect_abort(const rig_t *r, uint16_t index, uint8_t sub, uint32_t code)
{
    expect_sdo(r, 0x80);
    assert_int_equal(r->out[0].data[1] | (r->out[0].data[2] << 8), index);
    assert_int_equal(r->out[0].data[3], sub);
    assert_int_equal(le32(&r->out[0].data[4]), code);
}

static void nmt(rig_t *r, uint8_t cmd, uint8_t node)
{
    const uint8_t d[2] = {cmd, node};
    c4g_co_frame_t f;
    frame(&f, 0x000, 2, d);
    rx(r, &f);
    assert_int_equal(r->n, 0);
}

static void sync_frame(rig_t *r)
{
    c4g_co_frame_t f;
    frame(&f, 0x080, 0, NULL);
    rx(r, &f);
}

/* A node past its boot-up message (pre-operational). */
static void booted(rig_t *r)
{
    memset(r, 0, sizeof *r);
    assert_int_equal(c4gsim_slave_init(&r->s, NODE, DEVTYPE), C4G_OK);
    assert_int_equal(c4gsim_slave_poll(&r->s, 1000, r->out, &r->n), C4G_OK);
    assert_int_equal(r->n, 1);
}

static void test_init(void **state)
{
    rig_t r;
    (void)state;
    assert_int_equal(c4gsim_slave_init(NULL, NODE, DEVTYPE), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_init(&r.s, 0, DEVTYPE), C4G_ERR_RANGE);
    assert_int_equal(c4gsim_slave_init(&r.s, 128, DEVTYPE), C4G_ERR_RANGE);
    assert_int_equal(c4gsim_slave_init(&r.s, 127, DEVTYPE), C4G_OK);
    assert_int_equal(c4gsim_slave_init(&r.s, NODE, DEVTYPE), C4G_OK);
    assert_int_equal(r.s.nmt, C4G_CO_STATE_BOOTUP);
    assert_int_equal(r.s.name_len, 19);
    assert_memory_equal(r.s.name, "c4g-sim DS402 drive", 19);
    assert_int_equal(r.s.pdo_cob[0], 0x80000185UL);
    assert_int_equal(r.s.pdo_cob[3], 0x80000485UL);
    assert_int_equal(r.s.pdo_cob[4], 0x80000205UL);
    assert_int_equal(r.s.pdo[0].trans, 1);
    assert_int_equal(r.s.pdo[4].trans, 255);
    assert_int_equal(r.s.ds402, C4G_CO_DS402_SWITCH_ON_DISABLED);
    assert_int_equal(r.s.max_step, 200000);
    assert_int_equal(c4gsim_slave_reset(NULL), C4G_ERR_NULL);
}

static void test_bootup_and_heartbeat(void **state)
{
    rig_t r;
    (void)state;
    memset(&r, 0, sizeof r);
    assert_int_equal(c4gsim_slave_init(&r.s, NODE, DEVTYPE), C4G_OK);
    assert_int_equal(c4gsim_slave_poll(NULL, 0, r.out, &r.n), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_poll(&r.s, 0, NULL, &r.n), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_poll(&r.s, 0, r.out, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_poll(&r.s, US(1000), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 1); /* boot-up: 0x700 + node, state 0 */
    assert_int_equal(r.out[0].id, 0x705);
    assert_int_equal(r.out[0].dlc, 1);
    assert_int_equal(r.out[0].data[0], 0x00);
    assert_int_equal(r.s.nmt, C4G_CO_STATE_PREOP);
    assert_int_equal(c4gsim_slave_poll(&r.s, US(2000), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 0); /* no heartbeat configured */
    sdo(&r, 0x2B, 0x1017, 0, 100); /* 100 ms */
    expect_sdo(&r, 0x60);
    assert_int_equal(c4gsim_slave_poll(&r.s, US(3000), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 0); /* the first one a period from now */
    assert_int_equal(r.s.next_hb_ns, US(103000));
    assert_int_equal(c4gsim_slave_poll(&r.s, US(102999), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 0);
    assert_int_equal(c4gsim_slave_poll(&r.s, US(103000), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 1);
    assert_int_equal(r.out[0].id, 0x705);
    assert_int_equal(r.out[0].data[0], 0x7F); /* pre-operational */
    assert_int_equal(r.s.next_hb_ns, US(203000));
    /* a late poll: one heartbeat, the next a period from now */
    assert_int_equal(c4gsim_slave_poll(&r.s, US(500000), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 1);
    assert_int_equal(r.s.next_hb_ns, US(600000));
    r.s.no_heartbeat = true;
    assert_int_equal(c4gsim_slave_poll(&r.s, US(700000), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 0);
    r.s.no_heartbeat = false;
    r.s.silent = true;
    assert_int_equal(c4gsim_slave_poll(&r.s, US(700000), r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 0);
}

static void test_expedited_upload(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    sdo(&r, 0x40, 0x1000, 0, 0);
    expect_sdo(&r, 0x43); /* 4 bytes */
    assert_int_equal(le32(&r.out[0].data[4]), DEVTYPE);
    assert_int_equal(r.out[0].data[1], 0x00);
    assert_int_equal(r.out[0].data[2], 0x10);
    sdo(&r, 0x40, 0x6041, 0, 0);
    expect_sdo(&r, 0x4B); /* 2 bytes: "switch on disabled" with the remote bit */
    assert_int_equal(le32(&r.out[0].data[4]), 0x0240);
    sdo(&r, 0x40, 0x1001, 0, 0);
    expect_sdo(&r, 0x4F); /* 1 byte: error register, no fault */
    assert_int_equal(le32(&r.out[0].data[4]), 0);
    sdo(&r, 0x40, 0x2000, 0, 0);
    expect_abort(&r, 0x2000, 0, C4G_CO_ABORT_NO_OBJECT);
    sdo(&r, 0x40, 0x1000, 1, 0);
    expect_abort(&r, 0x1000, 1, C4G_CO_ABORT_NO_OBJECT);
    assert_int_equal(r.s.sdo_requests, 5);
}

static void test_expedited_download(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    sdo(&r, 0x23, 0x1006, 0, 2000); /* 4 bytes */
    expect_sdo(&r, 0x60);
    assert_int_equal(r.s.cycle_us, 2000);
    sdo(&r, 0x2B, 0x100C, 0, 300);
    expect_sdo(&r, 0x60);
    sdo(&r, 0x2F, 0x100D, 0, 3);
    expect_sdo(&r, 0x60);
    assert_true(r.s.guard_ms == 300 && r.s.life_factor == 3);
    sdo(&r, 0x2F, 0x6060, 0, 0xF8); /* -8 */
    expect_sdo(&r, 0x60);
    assert_int_equal(r.s.modes, -8);
    sdo(&r, 0x22, 0x607A, 0, 0xFFFFFFFFUL); /* size not indicated: 4 bytes */
    expect_sdo(&r, 0x60);
    assert_int_equal(r.s.target, -1);
    sdo(&r, 0x40, 0x607A, 0, 0);
    expect_sdo(&r, 0x43);
    assert_int_equal(le32(&r.out[0].data[4]), 0xFFFFFFFFUL);
    /* what was written reads back */
    {
        static const struct { uint16_t index; uint8_t cmd; uint32_t v; } back[] = {
            {0x1006, 0x43, 2000}, {0x100C, 0x4B, 300}, {0x100D, 0x4F, 3}, {0x6060, 0x4F, 0xF8},
            {0x1017, 0x4B, 0}, {0x6040, 0x4B, 0}, {0x6064, 0x43, 0}};
        size_t i;
        for (i = 0; i < sizeof back / sizeof back[0]; i++) {
            sdo(&r, 0x40, back[i].index, 0, 0);
            expect_sdo(&r, back[i].cmd);
            assert_int_equal(le32(&r.out[0].data[4]), back[i].v);
        }
    }
    /* wrong length, read-only, no object, no sub-index */
    sdo(&r, 0x23, 0x1017, 0, 100);
    expect_abort(&r, 0x1017, 0, C4G_CO_ABORT_TYPE_LENGTH);
    sdo(&r, 0x23, 0x1000, 0, 1);
    expect_abort(&r, 0x1000, 0, C4G_CO_ABORT_READ_ONLY);
    sdo(&r, 0x2B, 0x6041, 0, 1);
    expect_abort(&r, 0x6041, 0, C4G_CO_ABORT_READ_ONLY);
    sdo(&r, 0x23, 0x6099, 0, 1);
    expect_abort(&r, 0x6099, 0, C4G_CO_ABORT_NO_OBJECT);
    sdo(&r, 0x23, 0x1400, 0, 1);
    expect_abort(&r, 0x1400, 0, C4G_CO_ABORT_NO_OBJECT);
    sdo(&r, 0x23, 0x1401, 5, 1);
    expect_abort(&r, 0x1401, 5, C4G_CO_ABORT_NO_SUB);
    sdo(&r, 0x23, 0x1404, 1, 1); /* only 4 PDOs of each kind */
    expect_abort(&r, 0x1404, 1, C4G_CO_ABORT_NO_SUB);
    /* a segmented download of anything but the name */
    sdo(&r, 0x21, 0x1017, 0, 2);
    expect_abort(&r, 0x1017, 0, C4G_CO_ABORT_TYPE_LENGTH);
    sdo(&r, 0x21, 0x2000, 0, 2);
    expect_abort(&r, 0x2000, 0, C4G_CO_ABORT_NO_OBJECT);
    /* an injected abort */
    r.s.abort_index = 0x1006;
    r.s.abort_sub = 0;
    r.s.abort_code = C4G_CO_ABORT_HARDWARE;
    sdo(&r, 0x40, 0x1006, 0, 0);
    expect_abort(&r, 0x1006, 0, C4G_CO_ABORT_HARDWARE);
    sdo(&r, 0x40, 0x1006, 1, 0);
    expect_abort(&r, 0x1006, 1, C4G_CO_ABORT_NO_OBJECT);
}

static void test_pdo_objects(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    sdo(&r, 0x23, 0x1800, 1, 0x185);
    expect_sdo(&r, 0x60);
    sdo(&r, 0x2F, 0x1800, 2, 10);
    expect_sdo(&r, 0x60);
    assert_true(r.s.pdo_cob[0] == 0x185 && r.s.pdo[0].trans == 10);
    sdo(&r, 0x40, 0x1800, 1, 0);
    expect_sdo(&r, 0x43);
    assert_int_equal(le32(&r.out[0].data[4]), 0x185);
    sdo(&r, 0x40, 0x1800, 2, 0);
    expect_sdo(&r, 0x4F);
    assert_int_equal(r.out[0].data[4], 10);
    sdo(&r, 0x23, 0x1A00, 1, 0x60640020UL);
    expect_sdo(&r, 0x60);
    sdo(&r, 0x2F, 0x1A00, 0, 1);
    expect_sdo(&r, 0x60);
    sdo(&r, 0x40, 0x1A00, 0, 0);
    expect_sdo(&r, 0x4F);
    assert_int_equal(r.out[0].data[4], 1);
    sdo(&r, 0x40, 0x1A00, 1, 0);
    expect_sdo(&r, 0x43);
    assert_int_equal(le32(&r.out[0].data[4]), 0x60640020UL);
    sdo(&r, 0x2F, 0x1A00, 0, 9); /* more entries than the table */
    expect_abort(&r, 0x1A00, 0, C4G_CO_ABORT_VALUE_HIGH);
    sdo(&r, 0x23, 0x1A00, 2, 0x60640021UL); /* 33 bits */
    expect_sdo(&r, 0x60);
    sdo(&r, 0x2F, 0x1A00, 0, 2);
    expect_abort(&r, 0x1A00, 0, C4G_CO_ABORT_MAP_LENGTH);
    assert_int_equal(r.s.pdo[0].n, 1);
    sdo(&r, 0x23, 0x1A00, 9, 0);
    expect_abort(&r, 0x1A00, 9, C4G_CO_ABORT_NO_SUB);
    /* RPDO objects: slots 4..7 */
    sdo(&r, 0x23, 0x1601, 1, 0x607A0020UL);
    expect_sdo(&r, 0x60);
    assert_int_equal(r.s.pdo[5].entry[0], 0x607A0020UL);
    sdo(&r, 0x40, 0x1401, 2, 0);
    expect_sdo(&r, 0x4F);
    assert_int_equal(r.out[0].data[4], 255);
}

static void test_segmented_upload(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    sdo(&r, 0x40, 0x1008, 0, 0);
    expect_sdo(&r, 0x41);
    assert_int_equal(r.out[0].data[4], 19);
    sdo(&r, 0x60, 0, 0, 0);
    expect_sdo(&r, 0x00); /* toggle 0, 7 bytes, more */
    assert_memory_equal(&r.out[0].data[1], "c4g-sim", 7);
    sdo(&r, 0x70, 0, 0, 0);
    expect_sdo(&r, 0x10);
    assert_memory_equal(&r.out[0].data[1], " DS402 ", 7);
    sdo(&r, 0x60, 0, 0, 0);
    expect_sdo(&r, 0x05); /* toggle 0, 2 bytes unused, last */
    assert_memory_equal(&r.out[0].data[1], "drive", 5);
    assert_int_equal(r.s.seg_active, 0);
    /* a segment with no transfer open */
    sdo(&r, 0x60, 0x1008, 0, 0);
    expect_abort(&r, 0x1008, 0, C4G_CO_ABORT_COMMAND);
    /* a wrong toggle */
    sdo(&r, 0x40, 0x1008, 0, 0);
    sdo(&r, 0x70, 0, 0, 0);
    expect_abort(&r, 0x1008, 0, C4G_CO_ABORT_TOGGLE);
    assert_int_equal(r.s.seg_active, 0);
    /* a download segment inside an upload */
    sdo(&r, 0x40, 0x1008, 0, 0);
    sdo(&r, 0x00, 0, 0, 0);
    expect_abort(&r, 0x1008, 0, C4G_CO_ABORT_COMMAND);
    /* the client aborts */
    sdo(&r, 0x40, 0x1008, 0, 0);
    sdo(&r, 0x80, 0x1008, 0, 0);
    assert_int_equal(r.n, 0);
    assert_int_equal(r.s.seg_active, 0);
}

static void segment(rig_t *r, uint8_t cmd, const char *bytes)
{
    uint8_t d[8] = {cmd, 0, 0, 0, 0, 0, 0, 0};
    c4g_co_frame_t f;
    memcpy(&d[1], bytes, strlen(bytes));
    frame(&f, (uint16_t)(0x600U + NODE), 8, d);
    rx(r, &f);
}

static void test_segmented_download(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    sdo(&r, 0x21, 0x1008, 0, 10);
    expect_sdo(&r, 0x60);
    assert_int_equal(r.s.seg_active, 2);
    segment(&r, 0x00, "axis-7 ");
    expect_sdo(&r, 0x20);
    segment(&r, 0x10 | (4 << 1) | 1, "abc"); /* toggle 1, 3 bytes, last */
    expect_sdo(&r, 0x30);
    assert_int_equal(r.s.name_len, 10);
    assert_memory_equal(r.s.name, "axis-7 abc", 10);
    assert_int_equal(r.s.seg_active, 0);
    sdo(&r, 0x40, 0x1008, 0, 0);
    expect_sdo(&r, 0x41);
    assert_int_equal(r.out[0].data[4], 10);
    /* longer than the 24 bytes the node keeps */
    sdo(&r, 0x21, 0x1008, 0, 30);
    segment(&r, 0x00, "1234567");
    segment(&r, 0x10, "1234567");
    segment(&r, 0x00, "1234567");
    expect_sdo(&r, 0x20);
    segment(&r, 0x10, "1234567");
    expect_abort(&r, 0x1008, 0, C4G_CO_ABORT_TYPE_HIGH);
    assert_int_equal(r.s.seg_active, 0);
    assert_int_equal(r.s.name_len, 10);
    /* an upload segment inside a download */
    sdo(&r, 0x21, 0x1008, 0, 10);
    sdo(&r, 0x60, 0, 0, 0);
    expect_abort(&r, 0x1008, 0, C4G_CO_ABORT_COMMAND);
}

static void test_sdo_ignored(void **state)
{
    rig_t r;
    c4g_co_frame_t f;
    const uint8_t d[8] = {0x40, 0x00, 0x10, 0, 0, 0, 0, 0};
    (void)state;
    memset(&r, 0, sizeof r);
    assert_int_equal(c4gsim_slave_init(&r.s, NODE, DEVTYPE), C4G_OK);
    sdo(&r, 0x40, 0x1000, 0, 0); /* still in boot-up */
    assert_int_equal(r.n, 0);
    assert_int_equal(c4gsim_slave_poll(&r.s, US(1000), r.out, &r.n), C4G_OK);
    frame(&f, (uint16_t)(0x600U + NODE), 7, d); /* short */
    rx(&r, &f);
    assert_int_equal(r.n, 0);
    nmt(&r, C4G_CO_NMT_STOP, NODE);
    sdo(&r, 0x40, 0x1000, 0, 0);
    assert_int_equal(r.n, 0);
    assert_int_equal(r.s.sdo_requests, 3);
    nmt(&r, C4G_CO_NMT_PREOP, 0);
    sdo(&r, 0x40, 0x1000, 0, 0);
    expect_sdo(&r, 0x43);
    /* an SDO for another node, a remote frame on the SDO identifier */
    frame(&f, (uint16_t)(0x600U + NODE + 1U), 8, d);
    rx(&r, &f);
    assert_int_equal(r.n, 0);
    frame(&f, (uint16_t)(0x600U + NODE), 8, d);
    f.rtr = 1;
    rx(&r, &f);
    assert_int_equal(r.n, 0);
}

static void test_rx_errors(void **state)
{
    rig_t r;
    c4g_co_frame_t f;
    (void)state;
    booted(&r);
    frame(&f, 0x080, 0, NULL);
    assert_int_equal(c4gsim_slave_rx(NULL, &f, r.out, &r.n), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_rx(&r.s, NULL, r.out, &r.n), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_rx(&r.s, &f, NULL, &r.n), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_rx(&r.s, &f, r.out, NULL), C4G_ERR_NULL);
    f.dlc = 9;
    assert_int_equal(c4gsim_slave_rx(&r.s, &f, r.out, &r.n), C4G_ERR_RANGE);
    assert_int_equal(r.n, 0);
    f.dlc = 0;
    f.id = 0x800;
    assert_int_equal(c4gsim_slave_rx(&r.s, &f, r.out, &r.n), C4G_ERR_RANGE);
    /* unplugged: nothing at all */
    r.s.silent = true;
    sdo(&r, 0x40, 0x1000, 0, 0);
    assert_int_equal(r.n, 0);
    assert_int_equal(r.s.sdo_requests, 0);
}

static void test_nmt(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    nmt(&r, C4G_CO_NMT_START, NODE + 1U); /* another node */
    assert_int_equal(r.s.nmt, C4G_CO_STATE_PREOP);
    nmt(&r, C4G_CO_NMT_START, NODE);
    assert_int_equal(r.s.nmt, C4G_CO_STATE_OPERATIONAL);
    nmt(&r, C4G_CO_NMT_STOP, 0);
    assert_int_equal(r.s.nmt, C4G_CO_STATE_STOPPED);
    nmt(&r, C4G_CO_NMT_PREOP, NODE);
    assert_int_equal(r.s.nmt, C4G_CO_STATE_PREOP);
    /* reset communication: boot-up state, a fresh dictionary, the axis at 0 */
    sdo(&r, 0x2B, 0x1017, 0, 100);
    r.s.actual = 77;
    nmt(&r, C4G_CO_NMT_RESET_COMM, 0);
    assert_int_equal(r.s.nmt, C4G_CO_STATE_BOOTUP);
    assert_int_equal(r.s.heartbeat_ms, 0);
    assert_int_equal(r.s.actual, 0);
    assert_int_equal(r.s.node_id, NODE);
    /* a malformed NMT frame is ignored */
    {
        const uint8_t d[3] = {C4G_CO_NMT_START, 0, 0};
        c4g_co_frame_t f;
        frame(&f, 0x000, 3, d);
        rx(&r, &f);
        assert_int_equal(r.s.nmt, C4G_CO_STATE_BOOTUP);
    }
    assert_int_equal(c4gsim_slave_reset(&r.s), C4G_OK);
}

static void test_guarding(void **state)
{
    rig_t r;
    c4g_co_frame_t f;
    (void)state;
    memset(&r, 0, sizeof r);
    assert_int_equal(c4gsim_slave_init(&r.s, NODE, DEVTYPE), C4G_OK);
    frame(&f, (uint16_t)(0x700U + NODE), 0, NULL);
    f.rtr = 1;
    rx(&r, &f);
    assert_int_equal(r.n, 0); /* no answer before its boot-up */
    assert_int_equal(c4gsim_slave_poll(&r.s, US(1000), r.out, &r.n), C4G_OK);
    rx(&r, &f);
    assert_int_equal(r.n, 1);
    assert_int_equal(r.out[0].id, 0x705);
    assert_int_equal(r.out[0].data[0], 0x7F);
    rx(&r, &f);
    assert_int_equal(r.out[0].data[0], 0xFF); /* the toggle bit */
    r.s.no_heartbeat = true;
    rx(&r, &f);
    assert_int_equal(r.n, 0);
    f.rtr = 0; /* a heartbeat of a node with our id is not a request */
    r.s.no_heartbeat = false;
    rx(&r, &f);
    assert_int_equal(r.n, 0);
}

/* Enabled in cyclic synchronous position mode: the axis moves max_step per SYNC, its
 * position goes out in TPDO1, its target comes in by RPDO1. */
static void test_csp_pdos(void **state)
{
    rig_t r;
    c4g_co_frame_t f;
    static const uint16_t cw[] = {0x06, 0x07, 0x0F};
    size_t i;
    (void)state;
    booted(&r);
    sdo(&r, 0x23, 0x1A00, 1, 0x60640020UL);
    sdo(&r, 0x2F, 0x1A00, 0, 1);
    sdo(&r, 0x23, 0x1800, 1, 0x185);
    sdo(&r, 0x23, 0x1600, 1, 0x607A0020UL);
    sdo(&r, 0x2F, 0x1600, 0, 1);
    sdo(&r, 0x23, 0x1400, 1, 0x205);
    sdo(&r, 0x2F, 0x6060, 0, C4G_CO_MODE_CSP);
    r.s.actual = 1000;
    for (i = 0; i < 3; i++) {
        sdo(&r, 0x2B, 0x6040, 0, cw[i]);
        expect_sdo(&r, 0x60);
    }
    assert_int_equal(r.s.ds402, C4G_CO_DS402_ENABLED);
    assert_int_equal(r.s.target, 1000); /* enabled where it stands */
    sdo(&r, 0x2B, 0x6040, 0, 0x0F); /* enabled again: the target stays */
    sdo(&r, 0x23, 0x607A, 0, 500000);
    sync_frame(&r);
    assert_int_equal(r.n, 0); /* pre-operational: no PDOs, no motion */
    assert_int_equal(r.s.actual, 1000);
    nmt(&r, C4G_CO_NMT_START, 0);
    sync_frame(&r);
    assert_int_equal(r.n, 1);
    assert_int_equal(r.out[0].id, 0x185);
    assert_int_equal(r.out[0].dlc, 4);
    assert_int_equal(le32(r.out[0].data), 201000);
    sync_frame(&r);
    sync_frame(&r);
    assert_int_equal(r.s.actual, 500000);
    /* the target by RPDO, backwards */
    {
        const uint8_t d[4] = {0x10, 0x27, 0, 0}; /* 10000 */
        frame(&f, 0x205, 4, d);
        rx(&r, &f);
        assert_int_equal(r.n, 0);
        assert_int_equal(r.s.target, 10000);
    }
    sync_frame(&r);
    assert_int_equal(r.s.actual, 300000);
    /* an RPDO of the wrong length, one when not operational */
    {
        const uint8_t d[2] = {1, 0};
        frame(&f, 0x205, 2, d);
        rx(&r, &f);
        assert_int_equal(r.s.target, 10000);
    }
    nmt(&r, C4G_CO_NMT_PREOP, 0);
    {
        const uint8_t d[4] = {1, 0, 0, 0};
        frame(&f, 0x205, 4, d);
        rx(&r, &f);
        assert_int_equal(r.s.target, 10000);
    }
    /* not in CSP: no motion */
    nmt(&r, C4G_CO_NMT_START, 0);
    sdo(&r, 0x2F, 0x6060, 0, 1);
    sync_frame(&r);
    assert_int_equal(r.s.actual, 300000);
    /* event-driven TPDOs do not go out on SYNC */
    sdo(&r, 0x2F, 0x1800, 2, 254);
    sync_frame(&r);
    assert_int_equal(r.n, 0);
    sdo(&r, 0x2F, 0x1800, 2, 0);
    sync_frame(&r);
    assert_int_equal(r.n, 0);
}

/* A TPDO mapping that names a sub-index past a mapping table sends 0 (it read past the
 * table's array before). */
static void test_tpdo_maps_past_table(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    r.s.pdo[1].entry[0] = 0x12345678UL; /* what a read past slot 0's table would find */
    sdo(&r, 0x23, 0x1A00, 1, 0x1600C820UL); /* 0x1600 sub 200, 32 bits */
    sdo(&r, 0x23, 0x1A00, 2, 0x16000008UL); /* 0x1600 sub 0: its entry count */
    sdo(&r, 0x23, 0x1A00, 3, 0x20000008UL); /* no such object */
    sdo(&r, 0x2F, 0x1A00, 0, 3);
    expect_sdo(&r, 0x60);
    sdo(&r, 0x23, 0x1800, 1, 0x185);
    nmt(&r, C4G_CO_NMT_START, 0);
    sync_frame(&r);
    assert_int_equal(r.n, 1);
    assert_int_equal(r.out[0].dlc, 6);
    assert_int_equal(le32(r.out[0].data), 0);
    assert_int_equal(r.out[0].data[4], 0);
    assert_int_equal(r.out[0].data[5], 0);
}

static void test_fault(void **state)
{
    rig_t r;
    (void)state;
    booted(&r);
    assert_int_equal(c4gsim_slave_fault(NULL, 0x7300, r.out, &r.n), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_fault(&r.s, 0x7300, NULL, &r.n), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_fault(&r.s, 0x7300, r.out, NULL), C4G_ERR_NULL);
    assert_int_equal(c4gsim_slave_fault(&r.s, 0x7305, r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 1);
    assert_int_equal(r.out[0].id, 0x085);
    assert_int_equal(r.out[0].dlc, 8);
    assert_int_equal(r.out[0].data[0], 0x05);
    assert_int_equal(r.out[0].data[1], 0x73);
    assert_int_equal(r.out[0].data[2], 0x01);
    assert_int_equal(r.out[0].data[3], C4G_CO_DS402_SWITCH_ON_DISABLED);
    assert_int_equal(r.s.ds402, C4G_CO_DS402_FAULT);
    sdo(&r, 0x40, 0x1001, 0, 0);
    assert_int_equal(r.out[0].data[4], 1);
    r.s.silent = true; /* unplugged: the fault, no EMCY */
    assert_int_equal(c4gsim_slave_fault(&r.s, 0x7306, r.out, &r.n), C4G_OK);
    assert_int_equal(r.n, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init),
        cmocka_unit_test(test_bootup_and_heartbeat),
        cmocka_unit_test(test_expedited_upload),
        cmocka_unit_test(test_expedited_download),
        cmocka_unit_test(test_pdo_objects),
        cmocka_unit_test(test_segmented_upload),
        cmocka_unit_test(test_segmented_download),
        cmocka_unit_test(test_sdo_ignored),
        cmocka_unit_test(test_rx_errors),
        cmocka_unit_test(test_nmt),
        cmocka_unit_test(test_guarding),
        cmocka_unit_test(test_csp_pdos),
        cmocka_unit_test(test_tpdo_maps_past_table),
        cmocka_unit_test(test_fault),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
