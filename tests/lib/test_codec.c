/* SPDX-License-Identifier: MIT */
/* Cyclic packet codec: byte layout, round trips, hostile lengths and values. */
#include "test_helpers.h"
#include "../lib/c4g_internal.h" /* the bulk word helpers of the codec */
#include <math.h>

static void test_layout_little_endian(void **state)
{
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    c4g_ctrl_packet_t p;
    size_t len = 0;
    (void)state;
    memset(&p, 0, sizeof p);
    p.num = 0x1234;
    p.infpar = 0x05000005u;
    p.cmd = 0x00030201u;
    p.n_axes = 2;
    p.ax[0].mode = C4G_MODE_4;
    p.ax[0].target_pos = 1.0f;   /* 0x3f800000 */
    p.ax[1].mode = C4G_MODE_DRIVING_ON;
    p.ax[1].ext[2] = -2.0f;      /* 0xc0000000 */
    assert_int_equal(c4g_ctrl_encode(&p, buf, sizeof buf, &len), C4G_OK);
    assert_int_equal(len, 12 + 36 * 2);
    assert_int_equal(C4G_CYCLIC_SIZE(20), 732);
    assert_memory_equal(buf, "\x34\x12\x00\x00\x05\x00\x00\x05\x01\x02\x03\x00", 12);
    assert_memory_equal(&buf[12], "\x04\x00\x00\x00\x00\x00\x80\x3f", 8);
    assert_memory_equal(&buf[48], "\xf5\x01\x00\x00", 4);          /* 501 */
    assert_memory_equal(&buf[48 + 32], "\x00\x00\x00\xc0", 4);     /* EXT3 */
}

static void test_roundtrip_random(void **state)
{
    uint32_t seed = 0xC4C4u;
    uint32_t round;
    (void)state;
    for (round = 0; round < 2000; round++) {
        uint8_t buf[C4G_MAX_CYCLIC_SIZE];
        c4g_ctrl_packet_t a, b;
        c4g_pc_packet_t pa, pb;
        size_t len = 0;
        uint32_t n = 1 + th_rand(&seed) % 20, i;
        memset(&a, 0, sizeof a);
        a.num = (int32_t)(th_rand(&seed) % 0x8000);
        a.infpar = th_rand(&seed);
        a.cmd = th_rand(&seed);
        a.n_axes = n;
        for (i = 0; i < n; i++) {
            static const int32_t modes[] = {0, 10, 1, 4, 5, 7, 8, 9, 501, 504};
            a.ax[i].mode = modes[th_rand(&seed) % 10];
            a.ax[i].target_pos = th_randf(&seed);
            a.ax[i].target_vel = th_randf(&seed);
            a.ax[i].actual_pos = th_randf(&seed);
            a.ax[i].actual_vel = th_randf(&seed);
            a.ax[i].current_ref = th_randf(&seed);
            a.ax[i].ext[0] = th_randf(&seed);
            a.ax[i].ext[1] = th_randf(&seed);
            a.ax[i].ext[2] = th_randf(&seed);
        }
        assert_int_equal(c4g_ctrl_encode(&a, buf, sizeof buf, &len), C4G_OK);
        assert_int_equal(len, C4G_CYCLIC_SIZE(n));
        assert_int_equal(c4g_ctrl_decode(buf, len, n, &b, NULL), C4G_OK);
        if (memcmp(&a, &b, sizeof a) != 0) {
            fail_msg("ctrl round trip differs, seed state %u round %u", seed, round);
        }
        /* same bytes seen as a PC packet: identical layout */
        assert_int_equal(c4g_pc_decode(buf, len, 0, &pa, NULL), C4G_OK);
        assert_int_equal(pa.n_axes, n);
        assert_int_equal(c4g_pc_encode(&pa, buf, sizeof buf, &len), C4G_OK);
        assert_int_equal(c4g_pc_decode(buf, len, n, &pb, NULL), C4G_OK);
        assert_memory_equal(&pa, &pb, sizeof pa);
        assert_true(pa.ax[n - 1].current_add == a.ax[n - 1].current_ref);
    }
}

static void test_every_length(void **state)
{
    uint8_t buf[1500];
    uint32_t len;
    (void)state;
    memset(buf, 0, sizeof buf);
    for (len = 0; len <= 1500; len++) {
        c4g_ctrl_packet_t p;
        c4g_pc_packet_t q;
        c4g_diag_t d;
        const int valid = (len >= 48) && (len <= 732) && ((len - 12) % 36 == 0);
        c4g_status_t st;
        uint8_t *exact = malloc(len ? len : 1);   /* exact size: ASan catches over-reads */
        memcpy(exact, buf, len);
        st = c4g_ctrl_decode(exact, len, 0, &p, &d);
        assert_int_equal(st, valid ? C4G_OK : C4G_ERR_LENGTH);
        if (!valid) {
            assert_int_equal(d.field, C4G_FIELD_LENGTH);
            assert_int_equal(d.value, (int64_t)len);
            assert_int_equal(p.n_axes, 0);
        } else {
            assert_int_equal(p.n_axes, (len - 12) / 36);
        }
        st = c4g_pc_decode(exact, len, 6, &q, NULL);
        assert_int_equal(st, len == 228 ? C4G_OK : C4G_ERR_LENGTH);
        free(exact);
    }
}

static void test_axis_count_mismatch(void **state)
{
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    c4g_ctrl_packet_t p;
    c4g_diag_t d;
    size_t len = th_ctrl_bytes(buf, sizeof buf, 5, 6, 0);
    (void)state;
    assert_int_equal(c4g_ctrl_decode(buf, len, 5, &p, &d), C4G_ERR_LENGTH);
    assert_int_equal(c4g_ctrl_decode(buf, len, 7, &p, &d), C4G_ERR_LENGTH);
    assert_int_equal(c4g_ctrl_decode(buf, len, 21, &p, &d), C4G_ERR_AXES);
    assert_int_equal(d.value, 21);
    assert_int_equal(c4g_ctrl_decode(buf, len, 6, &p, &d), C4G_OK);
    assert_int_equal(d.status, C4G_OK);
}

static void test_bad_num(void **state)
{
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    c4g_ctrl_packet_t p;
    c4g_diag_t d;
    size_t len = th_ctrl_bytes(buf, sizeof buf, 5, 1, 0);
    (void)state;
    th_put_u32(buf, 0x8000);
    assert_int_equal(c4g_ctrl_decode(buf, len, 1, &p, &d), C4G_ERR_NUM);
    assert_int_equal(d.field, C4G_FIELD_NUM);
    assert_int_equal(d.offset, 0);
    assert_int_equal(d.value, 0x8000);
    th_put_u32(buf, 0xFFFFFFFFu);
    assert_int_equal(c4g_ctrl_decode(buf, len, 1, &p, &d), C4G_ERR_NUM);
    assert_int_equal(d.value, -1);
    th_put_u32(buf, 0x7FFF);
    assert_int_equal(c4g_ctrl_decode(buf, len, 1, &p, &d), C4G_OK);
    assert_int_equal(p.num, 0x7FFF);
}

static void test_bad_mode_and_nonfinite(void **state)
{
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t q;
    c4g_diag_t d;
    size_t len = th_ctrl_bytes(buf, sizeof buf, 5, 3, 0);
    const float bad[] = {NAN, INFINITY, -INFINITY};
    uint32_t k, f;
    (void)state;
    th_put_u32(&buf[12 + 36 * 2], 507);
    assert_int_equal(c4g_ctrl_decode(buf, len, 3, &p, &d), C4G_ERR_MODE);
    assert_int_equal(d.field, C4G_FIELD_SM);
    assert_int_equal(d.axis, 2);
    assert_int_equal(d.offset, 12 + 72);
    assert_int_equal(d.value, 507);
    th_put_u32(&buf[12 + 36 * 2], 0);
    for (k = 0; k < 3; k++) {
        for (f = 0; f < 8; f++) {
            uint8_t copy[C4G_MAX_CYCLIC_SIZE];
            memcpy(copy, buf, len);
            th_put_f32(&copy[12 + 36 + 4 + 4 * f], bad[k]);
            assert_int_equal(c4g_ctrl_decode(copy, len, 3, &p, &d), C4G_ERR_NONFINITE);
            assert_int_equal(d.field, C4G_FIELD_D1 + f);
            assert_int_equal(d.axis, 1);
            assert_int_equal(d.offset, 12 + 36 + 4 + 4 * f);
            assert_int_equal(c4g_pc_decode(copy, len, 3, &q, NULL), C4G_ERR_NONFINITE);
        }
    }
}

static void test_encode_refuses(void **state)
{
    uint8_t buf[C4G_MAX_CYCLIC_SIZE + 16];
    c4g_pc_packet_t q;
    c4g_ctrl_packet_t p;
    size_t len = 99;
    uint32_t i;
    (void)state;
    memset(&q, 0, sizeof q);
    q.n_axes = 6;
    q.ax[3].vel_add = NAN;
    memset(buf, 0xA5, sizeof buf);
    assert_int_equal(c4g_pc_encode(&q, buf, sizeof buf, &len), C4G_ERR_NONFINITE);
    assert_int_equal(len, 0);
    q.ax[3].vel_add = 0.0f;
    q.ax[5].mode = 999;
    assert_int_equal(c4g_pc_encode(&q, buf, sizeof buf, &len), C4G_ERR_MODE);
    q.ax[5].mode = 0;
    q.num = -1;
    assert_int_equal(c4g_pc_encode(&q, buf, sizeof buf, &len), C4G_ERR_NUM);
    q.num = 0x8000;
    assert_int_equal(c4g_pc_encode(&q, buf, sizeof buf, &len), C4G_ERR_NUM);
    q.num = 1;
    q.n_axes = 0;
    assert_int_equal(c4g_pc_encode(&q, buf, sizeof buf, &len), C4G_ERR_AXES);
    q.n_axes = 21;
    assert_int_equal(c4g_pc_encode(&q, buf, sizeof buf, &len), C4G_ERR_AXES);
    q.n_axes = 6;
    assert_int_equal(c4g_pc_encode(&q, buf, 227, &len), C4G_ERR_CAPACITY);
    /* guard band: encode into the middle, bytes outside untouched */
    memset(buf, 0xA5, sizeof buf);
    assert_int_equal(c4g_pc_encode(&q, &buf[8], 228, &len), C4G_OK);
    assert_int_equal(len, 228);
    for (i = 0; i < 8; i++) {
        assert_int_equal(buf[i], 0xA5);
    }
    for (i = 8 + 228; i < sizeof buf; i++) {
        assert_int_equal(buf[i], 0xA5);
    }
    th_ctrl_packet(&p, 1, 2, 0);
    p.ax[1].ext[1] = INFINITY;
    assert_int_equal(c4g_ctrl_encode(&p, buf, sizeof buf, &len), C4G_ERR_NONFINITE);
}

static void test_more_rejections(void **state)
{
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t q;
    c4g_diag_t d;
    size_t len = th_ctrl_bytes(buf, sizeof buf, 5, 2, 0);
    (void)state;
    th_put_u32(&buf[12], 0xFFFFFFFFu);          /* mode -1 */
    assert_int_equal(c4g_ctrl_decode(buf, len, 2, &p, &d), C4G_ERR_MODE);
    assert_int_equal(d.value, -1);
    assert_int_equal(p.n_axes, 0);
    assert_int_equal(c4g_pc_decode(buf, len, 2, &q, &d), C4G_ERR_MODE);
    assert_int_equal(q.n_axes, 0);
    th_put_u32(&buf[12], 13);                   /* 13 is not a mode (0..17 has gaps) */
    assert_int_equal(c4g_ctrl_decode(buf, len, 2, &p, &d), C4G_ERR_MODE);
    th_put_u32(&buf[12], 17);
    assert_int_equal(c4g_ctrl_decode(buf, len, 2, &p, &d), C4G_OK);
    th_put_u32(&buf[12 + 36 + 4 + 28], 0x7F800000u);   /* +inf in EXT3, the last slot */
    assert_int_equal(c4g_ctrl_decode(buf, len, 2, &p, &d), C4G_ERR_NONFINITE);
    assert_int_equal(d.field, C4G_FIELD_EXT3);
    assert_int_equal(d.offset, 12 + 36 + 32);
    th_ctrl_packet(&p, 1, 3, 0);
    p.ax[0].mode = 16;
    memset(buf, 0x77, sizeof buf);
    assert_int_equal(c4g_ctrl_encode(&p, buf, sizeof buf, &len), C4G_ERR_MODE);
    assert_int_equal(len, 0);
    assert_int_equal(th_get_u32(buf), 0);       /* header voided: not a valid packet */
}

static void test_nulls(void **state)
{
    uint8_t buf[64] = {0};
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t q;
    size_t len;
    c4g_diag_t d;
    (void)state;
    assert_int_equal(c4g_ctrl_decode(NULL, 48, 0, &p, &d), C4G_ERR_NULL);
    assert_int_equal(d.status, C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_decode(buf, 48, 0, NULL, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_decode(NULL, 48, 0, &q, &d), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_decode(buf, 48, 0, NULL, &d), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_encode(&q, NULL, 64, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_encode(&q, buf, 64, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_encode(NULL, buf, 64, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_encode(&p, NULL, 64, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_ctrl_encode(&p, buf, 64, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_encode(NULL, buf, 64, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_reply_neutral(NULL, &q), C4G_ERR_NULL);
    assert_int_equal(c4g_pc_reply_neutral(&p, NULL), C4G_ERR_NULL);
}

static void test_arm_bytes(void **state)
{
    (void)state;
    assert_int_equal(c4g_arm_byte(0x04030201u, 0), 1);
    assert_int_equal(c4g_arm_byte(0x04030201u, 3), 4);
    assert_int_equal(c4g_arm_byte(0x04030201u, 4), 0);
    assert_int_equal(c4g_arm_byte_set(0, 0, C4G_EXIT_FROM_OPEN), 0x00000001u);
    assert_int_equal(c4g_arm_byte_set(0xFFFFFFFFu, 2, 0x05), 0xFF05FFFFu);
    assert_int_equal(c4g_arm_byte_set(0x11223344u, 7, 0x05), 0x11223344u);
}

static void test_reply_num(void **state)
{
    (void)state;
    assert_int_equal(c4g_reply_num(1, C4G_NUM_PLUS_ONE), 2);
    assert_int_equal(c4g_reply_num(0, C4G_NUM_PLUS_ONE), 1);
    assert_int_equal(c4g_reply_num(0x7FFE, C4G_NUM_PLUS_ONE), 0x7FFF);
    assert_int_equal(c4g_reply_num(0x7FFF, C4G_NUM_PLUS_ONE), 1);
    assert_int_equal(c4g_reply_num(-5, C4G_NUM_PLUS_ONE), 1);
    assert_int_equal(c4g_reply_num(0x7FFF, C4G_NUM_ECHO), 0x7FFF);
    assert_int_equal(c4g_reply_num(0, C4G_NUM_ECHO), 0);
}

static void test_neutral_reply(void **state)
{
    c4g_ctrl_packet_t p;
    c4g_pc_packet_t q;
    (void)state;
    th_ctrl_packet(&p, 77, 3, C4G_MODE_0);
    p.infpar = 0x05;
    p.cmd = 0x0101;
    p.ax[1].mode = C4G_MODE_0_DEBUG;
    assert_int_equal(c4g_pc_reply_neutral(&p, &q), C4G_OK);
    assert_int_equal(q.num, 77);
    assert_int_equal(q.infpar, 0);
    assert_int_equal(q.cmd, 0);
    assert_int_equal(q.n_axes, 3);
    assert_int_equal(q.ax[0].mode, 0);
    assert_true(q.ax[0].target_pos == 0.0f && q.ax[0].current_add == 0.0f);
    assert_int_equal(q.ax[1].mode, 10);
    assert_true(q.ax[1].target_pos == p.ax[1].target_pos);
    assert_true(q.ax[1].target_vel == p.ax[1].target_vel);
    assert_true(q.ax[1].measure == p.ax[1].actual_pos);
    assert_true(q.ax[1].vel_add == p.ax[1].actual_vel);
    assert_true(q.ax[1].current_add == p.ax[1].current_ref);
    assert_true(q.ax[1].ext[0] == 0.0f);
    p.n_axes = 0;
    assert_int_equal(c4g_pc_reply_neutral(&p, &q), C4G_ERR_AXES);
    p.n_axes = 21;
    assert_int_equal(c4g_pc_reply_neutral(&p, &q), C4G_ERR_AXES);
}

static void test_modes_known(void **state)
{
    static const int32_t known[] = {0, 10, 1, 11, 2, 12, 3, 4, 14, 5, 15, 6, 7, 17, 170, 8, 9,
                                    101, 102, 103, 201, 202, 500, 501, 502, 503, 504, 505, 506, 508};
    int32_t m;
    unsigned count = 0, i;
    (void)state;
    for (i = 0; i < sizeof known / sizeof known[0]; i++) {
        assert_int_equal(c4g_mode_is_known(known[i]), 1);
    }
    for (m = -1000; m < 2000; m++) {
        count += (unsigned)c4g_mode_is_known(m);
    }
    assert_int_equal(count, sizeof known / sizeof known[0]);
    assert_int_equal(c4g_mode_is_known(507), 0);
    assert_int_equal(c4g_mode_is_known(0xFF), 0);
}

static void test_status_strings(void **state)
{
    int st;
    (void)state;
    assert_string_equal(c4g_strerror(C4G_OK), "ok");
    assert_string_equal(c4g_strerror(C4G_ERR_LENGTH), "wrong datagram length");
    assert_string_equal(c4g_strerror(1), "unknown status");
    assert_string_equal(c4g_strerror(-99), "unknown status");
    assert_string_equal(c4g_strerror(-1000), "unknown status");
    for (st = -300; st <= 5; st++) {
        assert_non_null(c4g_strerror(st));
        assert_true(strlen(c4g_strerror(st)) > 0);
    }
    assert_string_equal(c4g_field_name(C4G_FIELD_NUM), "NUM");
    assert_string_equal(c4g_field_name(C4G_FIELD_FOLLOWERROR), "FollowError");
    assert_string_equal(c4g_field_name(C4G_FIELD_COUNT_), "?");
    assert_string_equal(c4g_field_name((c4g_field_t)-1), "?");
}

static void test_ctrl_errors(void **state)
{
    (void)state;
    assert_string_equal(c4g_ctrl_error_name(C4G_CERR_UDP), "ERR_C4GOPEN_UDP");
    assert_string_equal(c4g_ctrl_error_message(C4G_CERR_UDP), "C4GOpen: communication error");
    assert_string_equal(c4g_ctrl_error_description(C4G_CERR_UDP),
                        "The C4G did not receive the UDP packet from PC for 10 consecutive times");
    assert_string_equal(c4g_ctrl_error_name(C4G_CERR_DRIVEOFF_SERVER), "ERR_C4GOPEN_DRIVEOFF_SERVER");
    assert_string_equal(c4g_ctrl_error_name(C4G_CERR_FOLLOW_ERROR), "ERR_C4GOPEN_FOLLOW_ERROR");
    assert_string_equal(c4g_ctrl_error_message(C4G_CERR_SKT_UDP),
                        "C4GOpen: error opening the socket UDP port 1000");
    assert_string_equal(c4g_ctrl_error_name(C4G_CERR_COUNT_), "?");
    assert_string_equal(c4g_ctrl_error_message((c4g_ctrl_error_t)-1), "?");
    assert_string_equal(c4g_ctrl_error_description(C4G_CERR_COUNT_), "?");
}

/* The codec's bulk helpers: the byte reversal a big-endian host runs (forced here, where the
 * host is little-endian), and the NaN/inf pass in its 8-word groups and its tail. */
static void test_bulk_words(void **state)
{
    static const uint8_t src[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    static const uint8_t swapped[8] = {4, 3, 2, 1, 8, 7, 6, 5};
    const uint32_t probe = 1U;
    uint8_t first;
    uint8_t dst[8];
    uint32_t w[11];
    uint32_t k;
    (void)state;
    assert_int_equal(sizeof(c4g_ctrl_axis_t), C4G_AXIS_WORDS * 4U);
    assert_int_equal(sizeof(c4g_pc_axis_t), C4G_AXIS_WORDS * 4U);
    memcpy(&first, &probe, 1);
    assert_int_equal(c4g_host_big_endian(), first == 0U ? 1U : 0U);
    c4g_words_le(dst, src, 2U, 1U);
    assert_memory_equal(dst, swapped, sizeof dst);
    c4g_words_le(dst, src, 2U, 0U);
    assert_memory_equal(dst, src, sizeof dst);
    for (k = 0U; k < 11U; k++) {
        w[k] = 0x3F800000U + k; /* finite */
    }
    assert_int_equal(c4g_words_carry((const uint8_t *)w, 11U), 0U);
    w[3] = 0x7FC00000U; /* NaN in the group of eight */
    assert_int_not_equal(c4g_words_carry((const uint8_t *)w, 11U), 0U);
    assert_int_equal(c4g_words_carry((const uint8_t *)w, 3U), 0U); /* tail only, before it */
    w[3] = 0x3F800000U;
    w[10] = 0xFF800000U; /* -inf in the tail */
    assert_int_not_equal(c4g_words_carry((const uint8_t *)w, 11U), 0U);
    assert_int_equal(c4g_words_carry((const uint8_t *)w, 10U), 0U);
    assert_int_equal(c4g_host_i32_at((const uint8_t *)&w[0]), 0x3F800000);
}

/* The axis-array check: a NaN/inf at word k is seen by every count that covers k, rounded up
 * to whole quads, and by no count before; the largest finite values and every mode pass. */
static void test_axes_carry(void **state)
{
    static const uint32_t bad[] = {0x7FC00000U, 0x7F800000U, 0xFF800000U, 0xFFFFFFFFU, 0x7F800001U};
    uint32_t w[C4G_MAX_AXES * C4G_AXIS_WORDS];
    size_t k, m, b;
    (void)state;
    for (k = 0U; k < C4G_MAX_AXES * C4G_AXIS_WORDS; k++) {
        w[k] = (k % 3U == 0U) ? 0x7F7FFFFFU : ((k % 3U == 1U) ? 0xFF7FFFFFU : 506U);
    }
    for (m = 0U; m <= C4G_MAX_AXES * C4G_AXIS_WORDS; m++) {
        assert_int_equal(c4g_axes_carry((const uint8_t *)w, m, 1U), 0U);
        assert_int_equal(c4g_axes_carry((const uint8_t *)w, m, 0U), 0U);
    }
    for (b = 0U; b < sizeof bad / sizeof bad[0]; b++) {
        for (k = 0U; k < C4G_MAX_AXES * C4G_AXIS_WORDS; k++) {
            const uint32_t keep = w[k];
            w[k] = bad[b];
            for (m = 0U; m <= C4G_MAX_AXES * C4G_AXIS_WORDS; m++) {
                const int seen = c4g_axes_carry((const uint8_t *)w, m, 1U) != 0U;
                const int exact = c4g_axes_carry((const uint8_t *)w, m, 0U) != 0U;
                assert_int_equal(seen, (((m + 3U) / 4U) * 4U) > k);
                assert_int_equal(exact, m > k);
            }
            w[k] = keep;
        }
    }
}

/* The encoder reads nothing past the axes (the caller's, maybe uninitialised): a NaN or an
 * unknown mode there must not refuse a good packet, one inside must. */
static void test_encode_ignores_words_past_axes(void **state)
{
    c4g_pc_packet_t tx;
    uint8_t buf[C4G_MAX_CYCLIC_SIZE];
    size_t len = 0, n;
    (void)state;
    for (n = 1U; n < C4G_MAX_AXES; n++) {
        memset(&tx, 0xFF, sizeof tx); /* garbage: NaN words and unknown modes */
        tx.num = 5;
        tx.infpar = 0U;
        tx.cmd = 0U;
        tx.n_axes = (uint32_t)n;
        memset(tx.ax, 0, n * sizeof tx.ax[0]);
        assert_int_equal(c4g_pc_encode(&tx, buf, sizeof buf, &len), C4G_OK);
        assert_int_equal(len, C4G_CYCLIC_SIZE(n));
        tx.ax[n - 1U].ext[2] = NAN;
        assert_int_equal(c4g_pc_encode(&tx, buf, sizeof buf, &len), C4G_ERR_NONFINITE);
        assert_int_equal(len, 0U);
        tx.ax[n - 1U].ext[2] = 0.0f;
        tx.ax[n - 1U].mode = 99;
        assert_int_equal(c4g_pc_encode(&tx, buf, sizeof buf, &len), C4G_ERR_MODE);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layout_little_endian),
        cmocka_unit_test(test_bulk_words),
        cmocka_unit_test(test_axes_carry),
        cmocka_unit_test(test_encode_ignores_words_past_axes),
        cmocka_unit_test(test_roundtrip_random),
        cmocka_unit_test(test_every_length),
        cmocka_unit_test(test_axis_count_mismatch),
        cmocka_unit_test(test_bad_num),
        cmocka_unit_test(test_bad_mode_and_nonfinite),
        cmocka_unit_test(test_encode_refuses),
        cmocka_unit_test(test_more_rejections),
        cmocka_unit_test(test_nulls),
        cmocka_unit_test(test_arm_bytes),
        cmocka_unit_test(test_reply_num),
        cmocka_unit_test(test_neutral_reply),
        cmocka_unit_test(test_modes_known),
        cmocka_unit_test(test_status_strings),
        cmocka_unit_test(test_ctrl_errors),
    };
    return cmocka_run_group_tests_name("codec", tests, NULL, NULL);
}
