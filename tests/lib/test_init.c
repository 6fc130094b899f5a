/* SPDX-License-Identifier: MIT */
/* Initialization packet: the manual's figure 10.1 vector, validation, axis maps. */
#define TH_FIG10_1
#include "test_helpers.h"
#include <math.h>


static void test_fig10_1_decode(void **state)
{
    c4g_init_t in;
    c4g_diag_t d;
    unsigned ax;
    (void)state;
    assert_int_equal(c4g_init_decode(th_fig, sizeof th_fig, &in, &d), C4G_OK);
    assert_int_equal(d.status, C4G_OK);
    assert_int_equal(in.num, 10);
    assert_int_equal(in.n_field_pck, 3);
    assert_int_equal(in.n_field_ax, 9);
    assert_int_equal(in.n_ax_open, 6);
    assert_int_equal(in.period_ms, 2);
    assert_int_equal(in.version_major, 3);
    assert_int_equal(in.version_minor, 11);
    assert_int_equal(in.version_build, 115);
    assert_int_equal(in.field_type[0], 1);
    assert_int_equal(in.field_type[2], 3);
    assert_int_equal(in.field_type[4], 2);
    assert_int_equal(in.field_type[11], 3);
    for (ax = 0; ax < 10; ax++) {
        assert_int_equal(in.open_mask[0][ax], 0);
        assert_int_equal(in.open_ax[0][ax], ax < 6 ? (int)ax : 0xFF);
        assert_int_equal(in.open_ax[3][ax], 0xFF);
    }
    assert_float_equal(in.cal_data[0][0], 0.142965f, 1e-6);
    assert_float_equal(in.cal_data[0][5], 0.355824f, 1e-6);
    assert_float_equal(in.az_lim[0][0], 24.5f, 0);
    assert_float_equal(in.az_lim[0][3], 9.5f, 0);
    assert_float_equal(in.ax_info[0][3], -0.02f, 1e-7);
    assert_float_equal(in.ax_info[0][4], 0.0204f, 1e-7);
    assert_float_equal(in.ax_info[0][5], 0.02f, 1e-7);
    assert_float_equal(in.tx_rate[0][0], -181.587296f, 1e-4);
    assert_float_equal(in.tx_rate[0][5], -50.0f, 0);
    assert_float_equal(in.follow_error[0][4], 7.5f, 0);
    assert_float_equal(in.follow_error[0][5], 0.0f, 0);   /* 0: no threshold */
}

static void test_fig10_1_builtin_matches_vector(void **state)
{
    c4g_init_t in;
    uint8_t out[1300];
    size_t len = 0;
    (void)state;
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_init_encode(&in, out, sizeof out, &len), C4G_OK);
    assert_int_equal(len, 1200);
    assert_memory_equal(out, th_fig, 1200);   /* byte-exact against the shared vector */
    assert_int_equal(c4g_init_encode(&in, out, 1199, &len), C4G_ERR_CAPACITY);
    assert_int_equal(len, 0);
    assert_int_equal(c4gsim_fig10_1(NULL), C4G_ERR_NULL);
}

static void test_axis_map(void **state)
{
    c4g_init_t in;
    c4g_axis_map_t m;
    c4g_diag_t d;
    unsigned i;
    (void)state;
    assert_int_equal(c4g_init_decode(th_fig, sizeof th_fig, &in, NULL), C4G_OK);
    assert_int_equal(c4g_axis_map_build(&in, &m, &d), C4G_OK);
    assert_int_equal(m.n_axes, 6);
    assert_int_equal(m.n_axes_arm[0], 6);
    assert_int_equal(m.n_axes_arm[1], 0);
    for (i = 0; i < 6; i++) {
        assert_int_equal(m.arm_of[i], 0);
        assert_int_equal(m.logical_of[i], i);
        assert_int_equal(m.open_of[0][i], i);
    }
    assert_int_equal(m.open_of[0][6], 0xFF);
    assert_int_equal(m.open_of[2][0], 0xFF);

    /* two arms, interleaved OPEN order: ARM2 axis 1 first, then ARM1 axes 1,3 */
    memset(in.open_ax, 0, sizeof in.open_ax);
    for (i = 0; i < 40; i++) {
        in.open_ax[i / 10][i % 10] = 0xFF;
    }
    in.n_ax_open = 3;
    in.open_ax[1][0] = 0;
    in.open_ax[0][0] = 1;
    in.open_ax[0][2] = 2;
    in.az_lim[1][0] = 3.0f; /* an open axis needs a current limit */
    assert_int_equal(c4g_init_validate(&in, NULL), C4G_OK);
    assert_int_equal(c4g_axis_map_build(&in, &m, NULL), C4G_OK);
    assert_int_equal(m.n_axes, 3);
    assert_int_equal(m.arm_of[0], 1);
    assert_int_equal(m.logical_of[0], 0);
    assert_int_equal(m.arm_of[2], 0);
    assert_int_equal(m.logical_of[2], 2);
    assert_int_equal(m.open_of[0][2], 2);
    assert_int_equal(m.n_axes_arm[0], 2);
    assert_int_equal(m.n_axes_arm[1], 1);

    /* 20 axes over 4 arms (at most 10 per arm by construction) */
    for (i = 0; i < 40; i++) {
        in.open_ax[i / 10][i % 10] = (i % 2 == 0) ? (int32_t)(i / 2) : 0xFF;
    }
    in.n_ax_open = 20;
    assert_int_equal(c4g_axis_map_build(&in, &m, NULL), C4G_OK);
    assert_int_equal(m.n_axes, 20);
    assert_int_equal(m.n_axes_arm[3], 5);
    assert_int_equal(c4g_axis_map_build(NULL, &m, NULL), C4G_ERR_NULL);
    assert_int_equal(c4g_axis_map_build(&in, NULL, NULL), C4G_ERR_NULL);
    in.n_ax_open = 19;
    assert_int_equal(c4g_axis_map_build(&in, &m, &d), C4G_ERR_INIT_MAP);
    assert_int_equal(m.n_axes, 0);
    in.n_ax_open = 21;
    assert_int_equal(c4g_axis_map_build(&in, &m, &d), C4G_ERR_AXES);
}

/* Patch one 4-byte field of the vector and expect @p st naming @p field at @p off. */
static void expect_bad_at(uint32_t off, uint32_t value, c4g_status_t st, c4g_field_t field,
                          uint32_t diag_off)
{
    uint8_t b[1200];
    c4g_init_t in;
    c4g_diag_t d;
    memcpy(b, th_fig, sizeof b);
    th_put_u32(&b[off], value);
    assert_int_equal(c4g_init_decode(b, sizeof b, &in, &d), st);
    assert_int_equal(d.status, st);
    assert_int_equal(d.field, field);
    assert_int_equal(d.offset, diag_off);
}

static void expect_bad(uint32_t off, uint32_t value, c4g_status_t st, c4g_field_t field)
{
    expect_bad_at(off, value, st, field, off);
}

static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

static void test_hostile_fields(void **state)
{
    uint32_t arm, ax;
    (void)state;
    expect_bad(0, 9, C4G_ERR_NUM, C4G_FIELD_NUM);
    expect_bad(0, 11, C4G_ERR_NUM, C4G_FIELD_NUM);
    expect_bad(4, 4, C4G_ERR_INIT_FIELDS, C4G_FIELD_NFIELDPCK);
    expect_bad(8, 8, C4G_ERR_INIT_FIELDS, C4G_FIELD_NFIELDAX);
    expect_bad(12, 0, C4G_ERR_AXES, C4G_FIELD_NAXOPEN);
    expect_bad(12, 21, C4G_ERR_AXES, C4G_FIELD_NAXOPEN);
    expect_bad(12, 0x80000000u, C4G_ERR_AXES, C4G_FIELD_NAXOPEN);
    expect_bad_at(12, 5, C4G_ERR_INIT_MAP, C4G_FIELD_OPENAX, 228 + 20); /* index 5 >= nAxOpen */
    expect_bad(12, 7, C4G_ERR_INIT_MAP, C4G_FIELD_NAXOPEN);  /* only 6 mapped */
    expect_bad(224, 0, C4G_ERR_PERIOD, C4G_FIELD_PERIOD);
    expect_bad(224, 1001, C4G_ERR_PERIOD, C4G_FIELD_PERIOD);
    expect_bad(224, 0xFFFFFFFFu, C4G_ERR_PERIOD, C4G_FIELD_PERIOD);
    expect_bad(16 + 4 * 3, 507, C4G_ERR_MODE, C4G_FIELD_OPENMASK);
    expect_bad(16 + 4 * 2, 0xFFFFFFFFu, C4G_ERR_MODE, C4G_FIELD_OPENMASK); /* -1, open axis */
    /* duplicate OPEN index, negative index, out-of-range index */
    expect_bad(228 + 4 * 1, 0, C4G_ERR_INIT_MAP, C4G_FIELD_OPENAX);
    expect_bad(228 + 4 * 2, 0xFFFFFFFFu, C4G_ERR_INIT_MAP, C4G_FIELD_OPENAX);
    expect_bad(228 + 40 * 2, 6, C4G_ERR_INIT_MAP, C4G_FIELD_OPENAX);
    expect_bad(228 + 40 * 1 + 4 * 9, 0xFE, C4G_ERR_INIT_MAP, C4G_FIELD_OPENAX);
    /* 0xFF on an open axis: count mismatch reported on nAxOpen */
    expect_bad_at(228 + 4 * 5, 0xFF, C4G_ERR_INIT_MAP, C4G_FIELD_NAXOPEN, 12);
    /* non-finite in every float block, and negative limits */
    expect_bad(388 + 4, fbits(NAN), C4G_ERR_NONFINITE, C4G_FIELD_CALDATA);
    expect_bad(548 + 40 * 3 + 4 * 9, fbits(INFINITY), C4G_ERR_NONFINITE, C4G_FIELD_AZLIM);
    expect_bad(720 + 8, fbits(-INFINITY), C4G_ERR_NONFINITE, C4G_FIELD_AXINFO);
    expect_bad(880, fbits(NAN), C4G_ERR_NONFINITE, C4G_FIELD_TXRATE);
    expect_bad(1040 + 4 * 5, fbits(NAN), C4G_ERR_NONFINITE, C4G_FIELD_FOLLOWERROR);
    expect_bad(548, fbits(-1.0f), C4G_ERR_RANGE, C4G_FIELD_AZLIM);
    /* an open axis with no current allowed is refused; a closed one may carry 0 */
    expect_bad(548 + 4 * 5, fbits(0.0f), C4G_ERR_RANGE, C4G_FIELD_AZLIM);
    expect_bad(548 + 4 * 1, fbits(-0.0f), C4G_ERR_RANGE, C4G_FIELD_AZLIM);
    expect_bad(1040 + 1196 - 1040, fbits(-0.5f), C4G_ERR_RANGE, C4G_FIELD_FOLLOWERROR);
    /* every OpenMask slot accepts 0xFF ("open, mode not specified") */
    for (arm = 0; arm < 4; arm++) {
        for (ax = 0; ax < 10; ax++) {
            uint8_t b[1200];
            c4g_init_t in;
            memcpy(b, th_fig, sizeof b);
            th_put_u32(&b[16 + 40 * arm + 4 * ax], 0xFF);
            assert_int_equal(c4g_init_decode(b, sizeof b, &in, NULL), C4G_OK);
        }
    }
}

/* Field tools fill OpenMask with -1 on the axes that are not open: accepted, kept as sent. */
static void test_openmask_minus1_vector(void **state)
{
    uint8_t b[1200];
    uint8_t out[1200];
    size_t len = 0;
    c4g_init_t in;
    c4g_diag_t d;
    uint32_t arm, ax;
    (void)state;
    assert_int_equal(th_read_file(FIXTURES_DIR "/vectors/init-openmask-minus1.bin", b, sizeof b),
                     1200);
    assert_int_equal(c4g_init_decode(b, sizeof b, &in, &d), C4G_OK);
    for (arm = 0; arm < 4; arm++) {
        for (ax = 0; ax < 10; ax++) {
            const int open = (arm == 0 && ax < 6);
            assert_int_equal(in.open_mask[arm][ax], open ? 0 : -1);
        }
    }
    assert_int_equal(c4g_init_encode(&in, out, sizeof out, &len), C4G_OK);
    assert_memory_equal(out, b, sizeof b);
    /* any value is accepted where the axis is not open, 0 and -1 alike */
    memcpy(b, th_fig, sizeof b);
    th_put_u32(&b[16 + 40 * 2 + 4 * 7], 12345u);
    assert_int_equal(c4g_init_decode(b, sizeof b, &in, NULL), C4G_OK);
    assert_int_equal(in.open_mask[2][7], 12345);
}

static void test_diag_names_arm_axis(void **state)
{
    uint8_t b[1200];
    c4g_init_t in;
    c4g_diag_t d;
    (void)state;
    memcpy(b, th_fig, sizeof b);
    th_put_f32(&b[388 + 40 * 2 + 4 * 7], NAN);
    assert_int_equal(c4g_init_decode(b, sizeof b, &in, &d), C4G_ERR_NONFINITE);
    assert_int_equal(d.arm, 2);
    assert_int_equal(d.axis, 7);
    assert_int_equal(d.value, (int64_t)fbits(NAN));
}

static void test_every_length(void **state)
{
    static uint8_t big[1500];
    uint32_t len;
    (void)state;
    memcpy(big, th_fig, sizeof th_fig);
    for (len = 0; len <= sizeof big; len++) {
        c4g_init_t in;
        c4g_diag_t d;
        uint8_t *exact = malloc(len ? len : 1);
        memcpy(exact, big, len);
        assert_int_equal(c4g_init_decode(exact, len, &in, &d), len == 1200 ? C4G_OK : C4G_ERR_LENGTH);
        if (len != 1200) {
            assert_int_equal(d.value, (int64_t)len);
        }
        free(exact);
    }
}

/* The decoder copies the packet's 300 words into c4g_init_t in one piece: the struct must
 * hold them in the packet's order, 4 bytes each, no padding. */
static void test_struct_is_wire_layout(void **state)
{
    (void)state;
    assert_int_equal(sizeof(c4g_init_t), C4G_INIT_SIZE);
    assert_int_equal(offsetof(c4g_init_t, n_ax_open), 12);
    assert_int_equal(offsetof(c4g_init_t, open_mask), C4G_INIT_OFF_OPENMASK);
    assert_int_equal(offsetof(c4g_init_t, field_type), C4G_INIT_OFF_TYPES);
    assert_int_equal(offsetof(c4g_init_t, period_ms), C4G_INIT_OFF_PERIOD);
    assert_int_equal(offsetof(c4g_init_t, open_ax), C4G_INIT_OFF_OPENAX);
    assert_int_equal(offsetof(c4g_init_t, cal_data), C4G_INIT_OFF_CALDATA);
    assert_int_equal(offsetof(c4g_init_t, az_lim), C4G_INIT_OFF_AZLIM);
    assert_int_equal(offsetof(c4g_init_t, version_major), C4G_INIT_OFF_VERSION);
    assert_int_equal(offsetof(c4g_init_t, version_build), C4G_INIT_OFF_VERSION + 8U);
    assert_int_equal(offsetof(c4g_init_t, ax_info), C4G_INIT_OFF_AXINFO);
    assert_int_equal(offsetof(c4g_init_t, tx_rate), C4G_INIT_OFF_TXRATE);
    assert_int_equal(offsetof(c4g_init_t, follow_error), C4G_INIT_OFF_FOLLOWERROR);
}

/* c4g_init_validate on a decoded struct refuses what the decoder refuses, with the same
 * diagnostic (its one-pass check and the ordered one agree), and accepts the vector. */
static void test_validate_agrees_with_decode(void **state)
{
    static const uint32_t vals[] = {0U, 1U, 6U, 20U, 21U, 0xFFU, 0xFFFFFFFFU, 507U, 1000U,
                                    0x7FC00000U, 0x7F800000U, 0xBF800000U, 0x80000000U,
                                    0x80000001U, 0x00000001U};
    uint32_t off, k;
    (void)state;
    for (off = 0U; off < C4G_INIT_SIZE; off += 4U) {
        for (k = 0U; k < sizeof vals / sizeof vals[0]; k++) {
            uint8_t b[1200];
            c4g_init_t in;
            c4g_diag_t d1, d2;
            c4g_status_t s1, s2;
            memcpy(b, th_fig, sizeof b);
            th_put_u32(&b[off], vals[k]);
            s1 = c4g_init_decode(b, sizeof b, &in, &d1); /* in: the values, refused or not */
            s2 = c4g_init_validate(&in, &d2);
            assert_int_equal(s1, s2);
            assert_int_equal(d1.status, d2.status);
            assert_int_equal(d1.field, d2.field);
            assert_int_equal(d1.offset, d2.offset);
            assert_int_equal(d1.arm, d2.arm);
            assert_int_equal(d1.axis, d2.axis);
            assert_true(d1.value == d2.value);
        }
    }
}

static void test_nulls_and_encode_validation(void **state)
{
    c4g_init_t in;
    uint8_t out[1200];
    size_t len = 5;
    c4g_diag_t d;
    (void)state;
    assert_int_equal(c4g_init_decode(NULL, 1200, &in, &d), C4G_ERR_NULL);
    assert_int_equal(c4g_init_decode(th_fig, 1200, NULL, &d), C4G_ERR_NULL);
    assert_int_equal(c4g_init_validate(NULL, &d), C4G_ERR_NULL);
    assert_int_equal(d.status, C4G_ERR_NULL);
    assert_int_equal(c4g_init_encode(NULL, out, 1200, &len), C4G_ERR_NULL);
    assert_int_equal(c4gsim_fig10_1(&in), C4G_OK);
    assert_int_equal(c4g_init_encode(&in, NULL, 1200, &len), C4G_ERR_NULL);
    assert_int_equal(c4g_init_encode(&in, out, 1200, NULL), C4G_ERR_NULL);
    in.az_lim[0][0] = NAN;
    assert_int_equal(c4g_init_encode(&in, out, sizeof out, &len), C4G_ERR_NONFINITE);
    assert_int_equal(len, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fig10_1_decode),
        cmocka_unit_test(test_fig10_1_builtin_matches_vector),
        cmocka_unit_test(test_openmask_minus1_vector),
        cmocka_unit_test(test_axis_map),
        cmocka_unit_test(test_hostile_fields),
        cmocka_unit_test(test_diag_names_arm_axis),
        cmocka_unit_test(test_every_length),
        cmocka_unit_test(test_nulls_and_encode_validation),
        cmocka_unit_test(test_struct_is_wire_layout),
        cmocka_unit_test(test_validate_agrees_with_decode),
    };
    return cmocka_run_group_tests_name("init", tests, th_load_fig, NULL);
}
