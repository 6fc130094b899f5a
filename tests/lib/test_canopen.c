/* SPDX-License-Identifier: MIT */
/* CANopen codecs (CiA 301 frame layouts checked byte by byte), the SDO client
   (expedited, segmented, aborts, timeouts and retries, hostile answers) and the DS402
   state machine. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "c4gopen.h"

/* the tests count time in us; the library takes ns */
#define US(x) ((uint64_t)(x) * 1000U)

static c4g_co_frame_t fr(uint16_t id, uint8_t dlc, const uint8_t *d)
{
    c4g_co_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = dlc;
    if (d != NULL) {
        memcpy(f.data, d, dlc > 8 ? 8 : dlc);
    }
    return f;
}

static void test_classify(void **state)
{
    (void)state;
    static const struct {
        uint16_t id;
        c4g_co_kind_t kind;
        uint8_t node, pdo;
    } rows[] = {
        {0x000, C4G_CO_K_NMT, 0, 0},     {0x080, C4G_CO_K_SYNC, 0, 0},
        {0x081, C4G_CO_K_EMCY, 1, 0},    {0x0FF, C4G_CO_K_EMCY, 127, 0},
        {0x100, C4G_CO_K_TIME, 0, 0},    {0x181, C4G_CO_K_TPDO, 1, 0},
        {0x201, C4G_CO_K_RPDO, 1, 0},    {0x285, C4G_CO_K_TPDO, 5, 1},
        {0x305, C4G_CO_K_RPDO, 5, 1},    {0x38A, C4G_CO_K_TPDO, 10, 2},
        {0x40A, C4G_CO_K_RPDO, 10, 2},   {0x48B, C4G_CO_K_TPDO, 11, 3},
        {0x50B, C4G_CO_K_RPDO, 11, 3},   {0x581, C4G_CO_K_SDO_TX, 1, 0},
        {0x601, C4G_CO_K_SDO_RX, 1, 0},  {0x701, C4G_CO_K_NMT_EC, 1, 0},
        {0x680, C4G_CO_K_UNKNOWN, 0, 0}, {0x7E5, C4G_CO_K_UNKNOWN, 0, 0},
        {0x180, C4G_CO_K_UNKNOWN, 0, 0}, {0x001, C4G_CO_K_UNKNOWN, 0, 0},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        c4g_co_frame_t f = fr(rows[i].id, 0, NULL);
        c4g_co_kind_t k;
        uint8_t node = 99, pdo = 99;
        assert_int_equal(c4g_co_classify(&f, &k, &node, &pdo), C4G_OK);
        assert_int_equal(k, rows[i].kind);
        assert_int_equal(node, rows[i].node);
        assert_int_equal(pdo, rows[i].pdo);
    }
    c4g_co_frame_t f = fr(0x800, 0, NULL);
    c4g_co_kind_t k;
    uint8_t node, pdo;
    assert_int_equal(c4g_co_classify(&f, &k, &node, &pdo), C4G_ERR_RANGE);
    f = fr(0x181, 9, NULL);
    assert_int_equal(c4g_co_classify(&f, &k, &node, &pdo), C4G_ERR_LENGTH);
    assert_int_equal(c4g_co_classify(NULL, &k, &node, &pdo), C4G_ERR_NULL);
    assert_int_equal(c4g_co_classify(&f, NULL, &node, &pdo), C4G_ERR_NULL);
    assert_int_equal(c4g_co_classify(&f, &k, NULL, &pdo), C4G_ERR_NULL);
    assert_int_equal(c4g_co_classify(&f, &k, &node, NULL), C4G_ERR_NULL);
}

static void test_nmt_sync(void **state)
{
    (void)state;
    c4g_co_frame_t f;
    uint8_t cmd = 0, node = 0;
    const uint8_t cmds[] = {0x01, 0x02, 0x80, 0x81, 0x82};
    for (size_t i = 0; i < sizeof cmds; i++) {
        assert_int_equal(c4g_co_nmt_encode(&f, cmds[i], 5), C4G_OK);
        assert_int_equal(f.id, 0x000);
        assert_int_equal(f.dlc, 2);
        assert_int_equal(f.data[0], cmds[i]);
        assert_int_equal(f.data[1], 5);
        assert_int_equal(c4g_co_nmt_decode(&f, &cmd, &node), C4G_OK);
        assert_int_equal(cmd, cmds[i]);
        assert_int_equal(node, 5);
    }
    assert_int_equal(c4g_co_nmt_encode(&f, 0x03, 1), C4G_ERR_ARG);
    assert_int_equal(c4g_co_nmt_encode(&f, 0x01, 128), C4G_ERR_ARG);
    assert_int_equal(c4g_co_nmt_encode(NULL, 0x01, 1), C4G_ERR_NULL);
    f.data[0] = 0x7F;
    assert_int_equal(c4g_co_nmt_decode(&f, &cmd, &node), C4G_ERR_RANGE);
    f.dlc = 3;
    assert_int_equal(c4g_co_nmt_decode(&f, &cmd, &node), C4G_ERR_LENGTH);
    f.id = 1;
    assert_int_equal(c4g_co_nmt_decode(&f, &cmd, &node), C4G_ERR_ARG);
    f.id = 0;
    f.rtr = 1;
    assert_int_equal(c4g_co_nmt_decode(&f, &cmd, &node), C4G_ERR_ARG);
    assert_int_equal(c4g_co_nmt_decode(NULL, &cmd, &node), C4G_ERR_NULL);
    assert_int_equal(c4g_co_nmt_decode(&f, NULL, &node), C4G_ERR_NULL);
    assert_int_equal(c4g_co_nmt_decode(&f, &cmd, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sync_encode(&f), C4G_OK);
    assert_int_equal(f.id, 0x080);
    assert_int_equal(f.dlc, 0);
    assert_int_equal(c4g_co_sync_encode(NULL), C4G_ERR_NULL);
}

static void test_error_control(void **state)
{
    (void)state;
    c4g_co_frame_t f;
    uint8_t node, st, tg;
    assert_int_equal(c4g_co_ec_encode(&f, 3, C4G_CO_STATE_OPERATIONAL, 1), C4G_OK);
    assert_int_equal(f.id, 0x703);
    assert_int_equal(f.dlc, 1);
    assert_int_equal(f.data[0], 0x85);
    assert_int_equal(c4g_co_ec_decode(&f, &node, &st, &tg), C4G_OK);
    assert_int_equal(node, 3);
    assert_int_equal(st, 5);
    assert_int_equal(tg, 1);
    assert_int_equal(c4g_co_ec_encode(&f, 127, C4G_CO_STATE_PREOP, 0), C4G_OK);
    assert_int_equal(f.data[0], 0x7F);
    assert_int_equal(c4g_co_ec_encode(&f, 1, C4G_CO_STATE_STOPPED, 0), C4G_OK);
    assert_int_equal(c4g_co_ec_encode(&f, 1, C4G_CO_STATE_BOOTUP, 0), C4G_OK);
    assert_int_equal(f.data[0], 0x00);
    assert_int_equal(c4g_co_ec_encode(&f, 0, 5, 0), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ec_encode(&f, 1, 6, 0), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ec_encode(&f, 1, 5, 2), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ec_encode(NULL, 1, 5, 0), C4G_ERR_NULL);
    f = fr(0x701, 1, (const uint8_t[]){0x06});
    assert_int_equal(c4g_co_ec_decode(&f, &node, &st, &tg), C4G_ERR_RANGE);
    f.dlc = 2;
    assert_int_equal(c4g_co_ec_decode(&f, &node, &st, &tg), C4G_ERR_LENGTH);
    f.id = 0x700;
    assert_int_equal(c4g_co_ec_decode(&f, &node, &st, &tg), C4G_ERR_ARG);
    f.id = 0x780;
    assert_int_equal(c4g_co_ec_decode(&f, &node, &st, &tg), C4G_ERR_ARG);
    f.id = 0x701;
    f.rtr = 1;
    assert_int_equal(c4g_co_ec_decode(&f, &node, &st, &tg), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ec_decode(NULL, &node, &st, &tg), C4G_ERR_NULL);
    assert_int_equal(c4g_co_ec_decode(&f, NULL, &st, &tg), C4G_ERR_NULL);
    assert_int_equal(c4g_co_ec_decode(&f, &node, NULL, &tg), C4G_ERR_NULL);
    assert_int_equal(c4g_co_ec_decode(&f, &node, &st, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_guard_request(&f, 9), C4G_OK);
    assert_int_equal(f.id, 0x709);
    assert_int_equal(f.rtr, 1);
    assert_int_equal(f.dlc, 1);
    assert_int_equal(c4g_co_guard_request(&f, 0), C4G_ERR_ARG);
    assert_int_equal(c4g_co_guard_request(NULL, 1), C4G_ERR_NULL);
}

static void test_emcy(void **state)
{
    (void)state;
    c4g_co_emcy_t e = {0}, d;
    c4g_co_frame_t f;
    uint8_t node;
    e.code = 0x7305;
    e.reg = 0x81;
    memcpy(e.mfr, "\x01\x02\x03\x04\x05", 5);
    assert_int_equal(c4g_co_emcy_encode(&f, 4, &e), C4G_OK);
    const uint8_t want[8] = {0x05, 0x73, 0x81, 1, 2, 3, 4, 5};
    assert_int_equal(f.id, 0x084);
    assert_int_equal(f.dlc, 8);
    assert_memory_equal(f.data, want, 8);
    f.t_ns = 77;
    assert_int_equal(c4g_co_emcy_decode(&f, &node, &d), C4G_OK);
    assert_int_equal(node, 4);
    assert_int_equal(d.code, 0x7305);
    assert_int_equal(d.reg, 0x81);
    assert_int_equal(d.t_ns, 77);
    assert_memory_equal(d.mfr, e.mfr, 5);
    assert_int_equal(c4g_co_emcy_encode(&f, 0, &e), C4G_ERR_ARG);
    assert_int_equal(c4g_co_emcy_encode(NULL, 1, &e), C4G_ERR_NULL);
    assert_int_equal(c4g_co_emcy_encode(&f, 1, NULL), C4G_ERR_NULL);
    f = fr(0x084, 7, want);
    assert_int_equal(c4g_co_emcy_decode(&f, &node, &d), C4G_ERR_LENGTH);
    f = fr(0x080, 8, want);
    assert_int_equal(c4g_co_emcy_decode(&f, &node, &d), C4G_ERR_ARG);
    f = fr(0x100, 8, want);
    assert_int_equal(c4g_co_emcy_decode(&f, &node, &d), C4G_ERR_ARG);
    f = fr(0x084, 8, want);
    f.rtr = 1;
    assert_int_equal(c4g_co_emcy_decode(&f, &node, &d), C4G_ERR_ARG);
    assert_int_equal(c4g_co_emcy_decode(NULL, &node, &d), C4G_ERR_NULL);
    assert_int_equal(c4g_co_emcy_decode(&f, NULL, &d), C4G_ERR_NULL);
    assert_int_equal(c4g_co_emcy_decode(&f, &node, NULL), C4G_ERR_NULL);
}

static void test_pdo(void **state)
{
    (void)state;
    c4g_co_pdo_map_t m = {{0}, 0, 1};
    m.entry[0] = C4G_CO_MAP(0x6040, 0, 16);
    m.entry[1] = C4G_CO_MAP(0x6060, 0, 8);
    m.entry[2] = C4G_CO_MAP(0x607A, 0, 32);
    m.n = 3;
    assert_int_equal(m.entry[2], 0x607A0020u);
    uint8_t len = 0;
    assert_int_equal(c4g_co_pdo_length(&m, &len), C4G_OK);
    assert_int_equal(len, 7);
    const uint32_t vals[3] = {0x000F, 8, 0xFFFFFF9Cu};
    c4g_co_frame_t f;
    assert_int_equal(c4g_co_pdo_pack(&m, 0x201, vals, &f), C4G_OK);
    const uint8_t want[7] = {0x0F, 0x00, 0x08, 0x9C, 0xFF, 0xFF, 0xFF};
    assert_int_equal(f.id, 0x201);
    assert_int_equal(f.dlc, 7);
    assert_memory_equal(f.data, want, 7);
    uint32_t back[8] = {0};
    assert_int_equal(c4g_co_pdo_unpack(&m, &f, back), C4G_OK);
    assert_memory_equal(back, vals, sizeof vals);
    f.dlc = 6;
    assert_int_equal(c4g_co_pdo_unpack(&m, &f, back), C4G_ERR_LENGTH);
    f.dlc = 7;
    f.rtr = 1;
    assert_int_equal(c4g_co_pdo_unpack(&m, &f, back), C4G_ERR_LENGTH);
    f.rtr = 0;
    assert_int_equal(c4g_co_pdo_unpack(&m, NULL, back), C4G_ERR_NULL);
    assert_int_equal(c4g_co_pdo_unpack(&m, &f, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_pdo_pack(&m, 0x800, vals, &f), C4G_ERR_ARG);
    assert_int_equal(c4g_co_pdo_pack(&m, 0x201, NULL, &f), C4G_ERR_NULL);
    assert_int_equal(c4g_co_pdo_pack(&m, 0x201, vals, NULL), C4G_ERR_NULL);
    /* bad mappings */
    c4g_co_pdo_map_t bad = m;
    bad.entry[1] = C4G_CO_MAP(0x6060, 0, 12);
    assert_int_equal(c4g_co_pdo_length(&bad, &len), C4G_ERR_RANGE);
    assert_int_equal(c4g_co_pdo_pack(&bad, 0x201, vals, &f), C4G_ERR_RANGE);
    assert_int_equal(c4g_co_pdo_unpack(&bad, &f, back), C4G_ERR_RANGE);
    bad = m;
    bad.n = 9;
    assert_int_equal(c4g_co_pdo_length(&bad, &len), C4G_ERR_RANGE);
    bad.n = 3;
    bad.entry[0] = C4G_CO_MAP(0x6064, 0, 32);
    bad.entry[1] = C4G_CO_MAP(0x6064, 0, 32);
    assert_int_equal(c4g_co_pdo_length(&bad, &len), C4G_ERR_LENGTH);
    assert_int_equal(c4g_co_pdo_length(NULL, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_co_pdo_length(&m, NULL), C4G_ERR_NULL);
    /* eight 8-bit entries: the whole frame */
    c4g_co_pdo_map_t all = {{0}, 8, 1};
    uint32_t v8[8];
    for (int i = 0; i < 8; i++) {
        all.entry[i] = C4G_CO_MAP(0x2000, i + 1, 8);
        v8[i] = (uint32_t)(0xA0 + i);
    }
    assert_int_equal(c4g_co_pdo_pack(&all, 0x181, v8, &f), C4G_OK);
    assert_int_equal(f.dlc, 8);
    assert_int_equal(f.data[7], 0xA7);
}

static void test_abort_names(void **state)
{
    (void)state;
    static const uint32_t codes[] = {
        0x05030000, 0x05040000, 0x05040001, 0x05040002, 0x05040003, 0x05040004, 0x05040005,
        0x06010000, 0x06010001, 0x06010002, 0x06020000, 0x06040041, 0x06040042, 0x06040043,
        0x06040047, 0x06060000, 0x06070010, 0x06070012, 0x06070013, 0x06090011, 0x06090030,
        0x06090031, 0x06090032, 0x06090036, 0x060A0023, 0x08000000, 0x08000020, 0x08000021,
        0x08000022, 0x08000023, 0x08000024};
    for (size_t i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        const char *t = c4g_co_abort_name(codes[i]);
        assert_non_null(t);
        assert_string_not_equal(t, "unknown abort code");
        for (size_t j = 0; j < i; j++) {
            assert_string_not_equal(t, c4g_co_abort_name(codes[j]));
        }
    }
    assert_string_equal(c4g_co_abort_name(0x06020000), "object does not exist in the object dictionary");
    assert_string_equal(c4g_co_abort_name(0x05030000), "toggle bit not alternated");
    assert_string_equal(c4g_co_abort_name(0x12345678), "unknown abort code");
    c4g_co_frame_t f;
    assert_int_equal(c4g_co_sdo_abort_encode(&f, 0x581, 0x1017, 0, 0x06090031), C4G_OK);
    const uint8_t want[8] = {0x80, 0x17, 0x10, 0x00, 0x31, 0x00, 0x09, 0x06};
    assert_memory_equal(f.data, want, 8);
    assert_int_equal(f.dlc, 8);
    assert_int_equal(c4g_co_sdo_abort_encode(&f, 0x800, 0, 0, 0), C4G_ERR_ARG);
    assert_int_equal(c4g_co_sdo_abort_encode(NULL, 0x581, 0, 0, 0), C4G_ERR_NULL);
}

/* ---- SDO client */

static c4g_co_frame_t take(c4g_co_sdo_client_t *c)
{
    c4g_co_frame_t f;
    bool have = false;
    memset(&f, 0, sizeof f);
    assert_int_equal(c4g_co_sdo_take(c, &f, &have), C4G_OK);
    assert_true(have);
    return f;
}

static void no_frame(c4g_co_sdo_client_t *c)
{
    c4g_co_frame_t f;
    bool have = true;
    assert_int_equal(c4g_co_sdo_take(c, &f, &have), C4G_OK);
    assert_false(have);
}

static void answer(c4g_co_sdo_client_t *c, uint16_t id, const uint8_t d[8], uint64_t t)
{
    c4g_co_frame_t f = fr(id, 8, d);
    f.t_ns = US(t);
    assert_int_equal(c4g_co_sdo_rx(c, &f), C4G_OK);
}

static void test_sdo_expedited(void **state)
{
    (void)state;
    c4g_co_sdo_client_t c;
    assert_int_equal(c4g_co_sdo_init(&c, US(50000), 1), C4G_OK);
    assert_false(c4g_co_sdo_busy(&c));
    assert_int_equal(c4g_co_sdo_upload(&c, 2, 0x1000, 0, US(100)), C4G_OK);
    assert_true(c4g_co_sdo_busy(&c));
    c4g_co_frame_t f = take(&c);
    const uint8_t req[8] = {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0};
    assert_int_equal(f.id, 0x602);
    assert_memory_equal(f.data, req, 8);
    no_frame(&c);
    assert_int_equal(c4g_co_sdo_upload(&c, 2, 0x1000, 0, US(100)), C4G_ERR_STATE);
    answer(&c, 0x582, (const uint8_t[]){0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00}, 200);
    assert_false(c4g_co_sdo_busy(&c));
    assert_int_equal(c.result, C4G_CO_SDO_OK);
    uint32_t v = 0;
    assert_int_equal(c4g_co_sdo_value(&c, &v), C4G_OK);
    assert_int_equal(v, 0x00020192);
    /* size not indicated: 4 bytes; size 1 */
    assert_int_equal(c4g_co_sdo_upload(&c, 2, 0x1001, 0, US(300)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x582, (const uint8_t[]){0x42, 0x01, 0x10, 0x00, 0x11, 0x22, 0x33, 0x44}, 301);
    assert_int_equal(c4g_co_sdo_value(&c, &v), C4G_OK);
    assert_int_equal(v, 0x44332211);
    assert_int_equal(c4g_co_sdo_upload(&c, 2, 0x1001, 0, US(300)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x582, (const uint8_t[]){0x4F, 0x01, 0x10, 0x00, 0x7E, 0x22, 0x33, 0x44}, 301);
    assert_int_equal(c4g_co_sdo_value(&c, &v), C4G_OK);
    assert_int_equal(v, 0x7E);
    /* download 2 bytes */
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x1017, 0, (const uint8_t[]){0x64, 0x00}, 2, US(400)), C4G_OK);
    f = take(&c);
    const uint8_t dl[8] = {0x2B, 0x17, 0x10, 0x00, 0x64, 0x00, 0, 0};
    assert_memory_equal(f.data, dl, 8);
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x1017, 0, dl, 2, US(400)), C4G_ERR_STATE);
    answer(&c, 0x582, (const uint8_t[]){0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0}, 401);
    assert_int_equal(c.result, C4G_CO_SDO_OK);
    /* download 1 and 4 bytes */
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x100D, 0, (const uint8_t[]){3}, 1, US(500)), C4G_OK);
    f = take(&c);
    assert_int_equal(f.data[0], 0x2F);
    answer(&c, 0x582, (const uint8_t[]){0x60, 0x0D, 0x10, 0x00, 0, 0, 0, 0}, 501);
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x1006, 0, (const uint8_t[]){1, 2, 3, 4}, 4, US(600)), C4G_OK);
    f = take(&c);
    assert_int_equal(f.data[0], 0x23);
    assert_int_equal(f.data[7], 4);
    answer(&c, 0x582, (const uint8_t[]){0x60, 0x06, 0x10, 0x00, 0, 0, 0, 0}, 601);
    assert_int_equal(c.result, C4G_CO_SDO_OK);
    /* argument errors */
    assert_int_equal(c4g_co_sdo_init(NULL, US(50000), 1), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_init(&c, US(999), 1), C4G_ERR_ARG);
    assert_int_equal(c4g_co_sdo_init(&c, US(10000001), 1), C4G_ERR_ARG);
    assert_int_equal(c4g_co_sdo_init(&c, US(50000), 6), C4G_ERR_ARG);
    assert_int_equal(c4g_co_sdo_upload(NULL, 2, 0x1000, 0, US(0)), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_upload(&c, 0, 0x1000, 0, US(0)), C4G_ERR_ARG);
    assert_int_equal(c4g_co_sdo_upload(&c, 128, 0x1000, 0, US(0)), C4G_ERR_ARG);
    assert_int_equal(c4g_co_sdo_download(NULL, 2, 0x1000, 0, dl, 1, US(0)), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x1000, 0, NULL, 1, US(0)), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x1000, 0, dl, 0, US(0)), C4G_ERR_LENGTH);
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x1000, 0, dl, C4G_CO_SDO_MAX + 1, US(0)), C4G_ERR_LENGTH);
    assert_int_equal(c4g_co_sdo_rx(NULL, &f), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_rx(&c, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_poll(NULL, US(0)), C4G_ERR_NULL);
    bool have;
    assert_int_equal(c4g_co_sdo_take(NULL, &f, &have), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_take(&c, NULL, &have), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_take(&c, &f, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_value(NULL, &v), C4G_ERR_NULL);
    assert_int_equal(c4g_co_sdo_value(&c, NULL), C4G_ERR_NULL);
    assert_false(c4g_co_sdo_busy(NULL));
}

static void test_sdo_segmented(void **state)
{
    (void)state;
    c4g_co_sdo_client_t c;
    assert_int_equal(c4g_co_sdo_init(&c, US(50000), 0), C4G_OK);
    /* upload of "c4g-sim drive" (13 bytes) in two segments */
    assert_int_equal(c4g_co_sdo_upload(&c, 3, 0x1008, 0, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x41, 0x08, 0x10, 0x00, 13, 0, 0, 0}, 10);
    c4g_co_frame_t f = take(&c);
    assert_int_equal(f.data[0], 0x60);
    answer(&c, 0x583, (const uint8_t[]){0x00, 'c', '4', 'g', '-', 's', 'i', 'm'}, 20);
    f = take(&c);
    assert_int_equal(f.data[0], 0x70);
    answer(&c, 0x583, (const uint8_t[]){0x13, ' ', 'd', 'r', 'i', 'v', 'e', 0}, 30);
    assert_int_equal(c.result, C4G_CO_SDO_OK);
    assert_int_equal(c.len, 13);
    assert_memory_equal(c.data, "c4g-sim drive", 13);
    uint32_t v;
    assert_int_equal(c4g_co_sdo_value(&c, &v), C4G_OK);
    assert_int_equal(v, 0x2D673463);
    /* size not indicated, wrong toggle: the client aborts */
    assert_int_equal(c4g_co_sdo_upload(&c, 3, 0x1008, 0, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0}, 10);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x10, 'x', 0, 0, 0, 0, 0, 0}, 20);
    assert_int_equal(c.result, C4G_CO_SDO_PROTOCOL);
    assert_int_equal(c.abort_code, C4G_CO_ABORT_TOGGLE);
    f = take(&c);
    assert_int_equal(f.id, 0x603);
    assert_int_equal(f.data[0], 0x80);
    assert_int_equal(f.data[4], 0x00);
    assert_int_equal(f.data[7], 0x05);
    assert_int_equal(c4g_co_sdo_value(&c, &v), C4G_ERR_STATE);
    /* an answer after the transfer ended: counted, not trusted */
    const uint32_t ign = c.ignored;
    answer(&c, 0x583, (const uint8_t[]){0x00, 'y', 0, 0, 0, 0, 0, 0}, 21);
    assert_int_equal(c.ignored, ign + 1);
    /* an empty object: no data, no value */
    assert_int_equal(c4g_co_sdo_upload(&c, 3, 0x1008, 0, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x41, 0x08, 0x10, 0x00, 0, 0, 0, 0}, 10);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x0F, 0, 0, 0, 0, 0, 0, 0}, 20);
    assert_int_equal(c.result, C4G_CO_SDO_OK);
    assert_int_equal(c.len, 0);
    assert_int_equal(c4g_co_sdo_value(&c, &v), C4G_ERR_STATE);
    /* announced size too large for the client */
    assert_int_equal(c4g_co_sdo_upload(&c, 3, 0x1008, 0, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x41, 0x08, 0x10, 0x00, 0xFF, 0, 0, 0}, 10);
    assert_int_equal(c.abort_code, C4G_CO_ABORT_MEMORY);
    /* more data than announced */
    assert_int_equal(c4g_co_sdo_upload(&c, 3, 0x1008, 0, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x41, 0x08, 0x10, 0x00, 3, 0, 0, 0}, 10);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x00, 1, 2, 3, 4, 5, 6, 7}, 20);
    assert_int_equal(c.abort_code, C4G_CO_ABORT_TYPE_HIGH);
    /* segmented download of 16 bytes: 7 + 7 + 2 */
    uint8_t name[16];
    memcpy(name, "0123456789ABCDEF", 16);
    assert_int_equal(c4g_co_sdo_download(&c, 3, 0x1008, 0, name, 16, US(0)), C4G_OK);
    f = take(&c);
    const uint8_t init[8] = {0x21, 0x08, 0x10, 0x00, 16, 0, 0, 0};
    assert_memory_equal(f.data, init, 8);
    answer(&c, 0x583, (const uint8_t[]){0x60, 0x08, 0x10, 0x00, 0, 0, 0, 0}, 10);
    f = take(&c);
    assert_int_equal(f.data[0], 0x00);
    assert_memory_equal(&f.data[1], "0123456", 7);
    answer(&c, 0x583, (const uint8_t[]){0x20, 0, 0, 0, 0, 0, 0, 0}, 20);
    f = take(&c);
    assert_int_equal(f.data[0], 0x10);
    assert_memory_equal(&f.data[1], "789ABCD", 7);
    answer(&c, 0x583, (const uint8_t[]){0x30, 0, 0, 0, 0, 0, 0, 0}, 30);
    f = take(&c);
    assert_int_equal(f.data[0], 0x0B); /* toggle 0, n = 5, last */
    assert_memory_equal(&f.data[1], "EF", 2);
    answer(&c, 0x583, (const uint8_t[]){0x20, 0, 0, 0, 0, 0, 0, 0}, 40);
    assert_int_equal(c.result, C4G_CO_SDO_OK);
    /* download segment acknowledged with the wrong toggle */
    assert_int_equal(c4g_co_sdo_download(&c, 3, 0x1008, 0, name, 8, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x60, 0x08, 0x10, 0x00, 0, 0, 0, 0}, 10);
    (void)take(&c);
    answer(&c, 0x583, (const uint8_t[]){0x30, 0, 0, 0, 0, 0, 0, 0}, 20);
    assert_int_equal(c.result, C4G_CO_SDO_PROTOCOL);
    assert_int_equal(c.abort_code, C4G_CO_ABORT_TOGGLE);
}

static void test_sdo_hostile_and_timeouts(void **state)
{
    (void)state;
    c4g_co_sdo_client_t c;
    assert_int_equal(c4g_co_sdo_init(&c, US(50000), 2), C4G_OK);
    /* answer while idle, before any transfer: not for this client */
    answer(&c, 0x582, (const uint8_t[]){0x43, 0, 0x10, 0, 0, 0, 0, 0}, 0);
    assert_int_equal(c.ignored, 0);
    assert_int_equal(c4g_co_sdo_upload(&c, 2, 0x1000, 0, US(1000)), C4G_OK);
    (void)take(&c);
    /* another node's answer: ignored, not counted */
    answer(&c, 0x583, (const uint8_t[]){0x43, 0, 0x10, 0, 0, 0, 0, 0}, 1);
    assert_int_equal(c.ignored, 0);
    /* wrong length, remote frame, other object: counted */
    c4g_co_frame_t f = fr(0x582, 4, (const uint8_t[]){0x43, 0, 0x10, 0});
    assert_int_equal(c4g_co_sdo_rx(&c, &f), C4G_OK);
    f = fr(0x582, 8, (const uint8_t[]){0x43, 0, 0x10, 0, 0, 0, 0, 0});
    f.rtr = 1;
    assert_int_equal(c4g_co_sdo_rx(&c, &f), C4G_OK);
    answer(&c, 0x582, (const uint8_t[]){0x43, 0x17, 0x10, 0, 0, 0, 0, 0}, 2);
    answer(&c, 0x582, (const uint8_t[]){0x80, 0x17, 0x10, 0, 0, 0, 0x02, 0x06}, 2);
    answer(&c, 0x582, (const uint8_t[]){0x43, 0x00, 0x10, 1, 0, 0, 0, 0}, 2); /* other sub */
    assert_int_equal(c.ignored, 5);
    assert_true(c4g_co_sdo_busy(&c));
    /* timeout: two retries, each resends the request */
    assert_int_equal(c4g_co_sdo_poll(&c, US(50999)), C4G_OK);
    no_frame(&c);
    assert_int_equal(c4g_co_sdo_poll(&c, US(51000)), C4G_OK);
    f = take(&c);
    assert_int_equal(f.data[0], 0x40);
    assert_int_equal(c4g_co_sdo_poll(&c, US(101000)), C4G_OK);
    f = take(&c);
    assert_int_equal(f.data[0], 0x40);
    assert_int_equal(c4g_co_sdo_poll(&c, US(151000)), C4G_OK);
    f = take(&c);
    assert_int_equal(f.data[0], 0x80);
    assert_int_equal(f.data[7], 0x05);
    assert_int_equal(f.data[6], 0x04);
    assert_int_equal(c.result, C4G_CO_SDO_TIMEOUT);
    assert_int_equal(c.abort_code, C4G_CO_ABORT_TIMEOUT);
    assert_int_equal(c4g_co_sdo_poll(&c, US(999999)), C4G_OK); /* idle: nothing */
    no_frame(&c);
    /* timeout inside a segmented upload restarts from the initiate request */
    assert_int_equal(c4g_co_sdo_init(&c, US(50000), 1), C4G_OK);
    assert_int_equal(c4g_co_sdo_upload(&c, 2, 0x1008, 0, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x582, (const uint8_t[]){0x41, 0x08, 0x10, 0x00, 9, 0, 0, 0}, 10);
    (void)take(&c);
    assert_int_equal(c4g_co_sdo_poll(&c, US(50010)), C4G_OK);
    f = take(&c);
    assert_int_equal(f.data[0], 0x40);
    /* the server aborts */
    answer(&c, 0x582, (const uint8_t[]){0x80, 0x08, 0x10, 0x00, 0x00, 0x00, 0x02, 0x06}, 50020);
    assert_int_equal(c.result, C4G_CO_SDO_ABORTED);
    assert_int_equal(c.abort_code, 0x06020000);
    no_frame(&c);
    /* a download timing out in its segments restarts as a download */
    assert_int_equal(c4g_co_sdo_download(&c, 2, 0x1008, 0, (const uint8_t *)"abcdefghij", 10, US(0)), C4G_OK);
    (void)take(&c);
    answer(&c, 0x582, (const uint8_t[]){0x60, 0x08, 0x10, 0x00, 0, 0, 0, 0}, 10);
    (void)take(&c);
    assert_int_equal(c4g_co_sdo_poll(&c, US(60000)), C4G_OK);
    f = take(&c);
    assert_int_equal(f.data[0], 0x21);
    /* wrong command specifier: the client aborts with 0x05040001 */
    answer(&c, 0x582, (const uint8_t[]){0x43, 0x08, 0x10, 0x00, 0, 0, 0, 0}, 60010);
    assert_int_equal(c.result, C4G_CO_SDO_PROTOCOL);
    assert_int_equal(c.abort_code, C4G_CO_ABORT_COMMAND);
    f = take(&c);
    assert_int_equal(f.data[0], 0x80);
}

/* ---- DS402 */

static void test_ds402_states(void **state)
{
    (void)state;
    static const struct {
        uint16_t sw;
        c4g_co_ds402_t s;
    } rows[] = {
        {0x0000, C4G_CO_DS402_NOT_READY},    {0x0250, C4G_CO_DS402_SWITCH_ON_DISABLED},
        {0x0231, C4G_CO_DS402_READY},        {0x0233, C4G_CO_DS402_SWITCHED_ON},
        {0x1237, C4G_CO_DS402_ENABLED},      {0x0217, C4G_CO_DS402_QUICK_STOP},
        {0x021F, C4G_CO_DS402_FAULT_REACTION}, {0x0218, C4G_CO_DS402_FAULT},
        {0x0001, C4G_CO_DS402_UNKNOWN},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        assert_int_equal(c4g_co_ds402_state(rows[i].sw), rows[i].s);
    }
    for (int s = C4G_CO_DS402_NOT_READY; s < C4G_CO_DS402_UNKNOWN; s++) {
        uint16_t sw = 0;
        assert_int_equal(c4g_co_ds402_statusword((c4g_co_ds402_t)s, &sw), C4G_OK);
        assert_int_equal(c4g_co_ds402_state(sw), s);
        assert_string_not_equal(c4g_co_ds402_name((c4g_co_ds402_t)s), "unknown");
    }
    uint16_t sw;
    assert_int_equal(c4g_co_ds402_statusword(C4G_CO_DS402_UNKNOWN, &sw), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ds402_statusword((c4g_co_ds402_t)42, &sw), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ds402_statusword(C4G_CO_DS402_READY, NULL), C4G_ERR_NULL);
    assert_string_equal(c4g_co_ds402_name(C4G_CO_DS402_ENABLED), "operation enabled");
    assert_string_equal(c4g_co_ds402_name(C4G_CO_DS402_UNKNOWN), "unknown");
    assert_string_equal(c4g_co_ds402_name((c4g_co_ds402_t)42), "unknown");
}

/* The master's commands drive a drive model to each goal in a few steps. */
static c4g_co_ds402_t drive_to(c4g_co_ds402_t s, c4g_co_goal_t goal, int *steps)
{
    uint16_t cw = 0, prev = 0;
    for (*steps = 0; *steps < 10; (*steps)++) {
        uint16_t sw;
        c4g_co_ds402_t next;
        assert_int_equal(c4g_co_ds402_statusword(s, &sw), C4G_OK);
        assert_int_equal(c4g_co_ds402_command(sw, goal, prev, &cw), C4G_OK);
        assert_int_equal(c4g_co_ds402_apply(s, prev, cw, &next), C4G_OK);
        prev = cw;
        if (next == s && ((goal == C4G_CO_GOAL_ENABLED && s == C4G_CO_DS402_ENABLED) ||
                          (goal == C4G_CO_GOAL_READY && s == C4G_CO_DS402_READY) ||
                          (goal == C4G_CO_GOAL_DISABLED && s == C4G_CO_DS402_SWITCH_ON_DISABLED) ||
                          (goal == C4G_CO_GOAL_QUICK_STOP &&
                           (s == C4G_CO_DS402_QUICK_STOP || s == C4G_CO_DS402_SWITCH_ON_DISABLED)))) {
            break;
        }
        s = next;
    }
    return s;
}

static void test_ds402_transitions(void **state)
{
    (void)state;
    int steps = 0;
    /* switch on disabled -> ready -> switched on -> enabled: three commands */
    assert_int_equal(drive_to(C4G_CO_DS402_SWITCH_ON_DISABLED, C4G_CO_GOAL_ENABLED, &steps),
                     C4G_CO_DS402_ENABLED);
    assert_int_equal(steps, 3);
    assert_int_equal(drive_to(C4G_CO_DS402_NOT_READY, C4G_CO_GOAL_ENABLED, &steps), C4G_CO_DS402_ENABLED);
    assert_int_equal(drive_to(C4G_CO_DS402_FAULT, C4G_CO_GOAL_ENABLED, &steps), C4G_CO_DS402_ENABLED);
    assert_int_equal(drive_to(C4G_CO_DS402_FAULT_REACTION, C4G_CO_GOAL_ENABLED, &steps), C4G_CO_DS402_ENABLED);
    assert_int_equal(drive_to(C4G_CO_DS402_QUICK_STOP, C4G_CO_GOAL_ENABLED, &steps), C4G_CO_DS402_ENABLED);
    assert_int_equal(drive_to(C4G_CO_DS402_ENABLED, C4G_CO_GOAL_READY, &steps), C4G_CO_DS402_READY);
    assert_int_equal(drive_to(C4G_CO_DS402_QUICK_STOP, C4G_CO_GOAL_READY, &steps), C4G_CO_DS402_READY);
    assert_int_equal(drive_to(C4G_CO_DS402_ENABLED, C4G_CO_GOAL_DISABLED, &steps), C4G_CO_DS402_SWITCH_ON_DISABLED);
    assert_int_equal(drive_to(C4G_CO_DS402_ENABLED, C4G_CO_GOAL_QUICK_STOP, &steps), C4G_CO_DS402_QUICK_STOP);
    assert_int_equal(drive_to(C4G_CO_DS402_READY, C4G_CO_GOAL_QUICK_STOP, &steps), C4G_CO_DS402_SWITCH_ON_DISABLED);
    /* single transitions of the drive side */
    c4g_co_ds402_t n;
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_SWITCH_ON_DISABLED, 0, 0x0F, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_SWITCH_ON_DISABLED); /* only shutdown leaves it */
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_READY, 0x06, 0x0F, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_READY); /* enable needs switched on first */
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_ENABLED, 0x0F, 0x07, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_SWITCHED_ON); /* disable operation */
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_QUICK_STOP, 0x02, 0x06, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_QUICK_STOP);
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_QUICK_STOP, 0x02, 0x02, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_QUICK_STOP);
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_SWITCHED_ON, 0x07, 0x03, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_SWITCH_ON_DISABLED); /* quick stop outside enabled */
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_READY, 0x06, 0x06, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_READY);
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_QUICK_STOP, 0x02, 0x0F, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_ENABLED); /* back from quick stop */
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_FAULT, 0x80, 0x80, &n), C4G_OK);
    assert_int_equal(n, C4G_CO_DS402_FAULT); /* no rising edge */
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_UNKNOWN, 0, 0, &n), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ds402_apply(C4G_CO_DS402_READY, 0, 0, NULL), C4G_ERR_NULL);
    uint16_t cw;
    assert_int_equal(c4g_co_ds402_command(0x0250, C4G_CO_GOAL_ENABLED, 0, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_co_ds402_command(0x0250, (c4g_co_goal_t)9, 0, &cw), C4G_ERR_ARG);
    assert_int_equal(c4g_co_ds402_command(0x0218, C4G_CO_GOAL_DISABLED, 0, &cw), C4G_OK);
    assert_int_equal(cw, C4G_CO_CW_FAULT_RESET);
    assert_int_equal(c4g_co_ds402_command(0x0218, C4G_CO_GOAL_DISABLED, 0x80, &cw), C4G_OK);
    assert_int_equal(cw, 0);
    assert_int_equal(c4g_co_ds402_command(0x0000, C4G_CO_GOAL_ENABLED, 0, &cw), C4G_OK);
    assert_int_equal(cw, 0); /* not ready: wait */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_classify),
        cmocka_unit_test(test_nmt_sync),
        cmocka_unit_test(test_error_control),
        cmocka_unit_test(test_emcy),
        cmocka_unit_test(test_pdo),
        cmocka_unit_test(test_abort_names),
        cmocka_unit_test(test_sdo_expedited),
        cmocka_unit_test(test_sdo_segmented),
        cmocka_unit_test(test_sdo_hostile_and_timeouts),
        cmocka_unit_test(test_ds402_states),
        cmocka_unit_test(test_ds402_transitions),
    };
    return cmocka_run_group_tests_name("canopen codecs, SDO client, DS402", tests, NULL, NULL);
}
