/* SPDX-License-Identifier: MIT */
/* The CSV text of monitoring records and the tools' float format (lib/host/c4gh_csv). */
#include "test_helpers.h"
#include <math.h>

#include "c4gh_csv.h"

static const char *fmt(float v)
{
    static char buf[64];
    size_t len = 99;
    assert_int_equal(c4gh_fmt_float(v, buf, sizeof buf, &len), C4G_OK);
    assert_int_equal(len, strlen(buf));
    return buf;
}

static void test_fmt_float(void **state)
{
    char small[5];
    size_t len = 7;
    (void)state;
    assert_string_equal(fmt(0.0f), "0.000000");
    assert_string_equal(fmt(-0.0f), "0.000000");
    assert_string_equal(fmt(1.5f), "1.500000");
    assert_string_equal(fmt(-12.25f), "-12.250000");
    assert_string_equal(fmt(0.0000004f), "0.000000");
    assert_string_equal(fmt(-0.0000004f), "0.000000");
    assert_string_equal(fmt(0.0000006f), "0.000001");
    assert_string_equal(fmt(24.5f), "24.500000");
    assert_string_equal(fmt(0.142965f), "0.142965");
    assert_string_equal(fmt(-181.587296f), "-181.587296");
    assert_string_equal(fmt(999999936.0f), "999999936.000000");
    assert_string_equal(fmt(1e9f), "1.000000e+09");
    assert_string_equal(fmt(-3.4028235e38f), "-3.402823e+38");
    assert_string_equal(fmt(9.9999999e9f), "1.000000e+10");
    assert_string_equal(fmt(NAN), "nan");
    assert_string_equal(fmt(INFINITY), "inf");
    assert_string_equal(fmt(-INFINITY), "-inf");
    assert_int_equal(c4gh_fmt_float(1.5f, small, sizeof small, &len), C4G_ERR_CAPACITY);
    assert_int_equal(len, 0);
    assert_string_equal(small, "");
    assert_int_equal(c4gh_fmt_float(1.5f, small, 0, &len), C4G_ERR_CAPACITY);
    assert_int_equal(c4gh_fmt_float(1.5f, NULL, 5, &len), C4G_ERR_NULL);
    assert_int_equal(c4gh_fmt_float(1.5f, small, 5, NULL), C4G_ERR_NULL);
}

static void test_csv(void **state)
{
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_moni_rec_t r;
    char buf[C4GH_MONI_ROW_MAX];
    size_t len = 0;
    uint32_t t;
    (void)state;
    moni_packets(&rx, &tx);
    assert_int_equal(c4gh_moni_csv_header(21, buf, sizeof buf, &len), C4G_OK);
    assert_string_equal(buf, "type,num,axis,mode,pc_d1,pc_d2,smp_d1,smp_d3,smp_d5\n");
    assert_int_equal(len, strlen(buf));
    for (t = 19; t <= 24; t++) {
        assert_int_equal(c4gh_moni_csv_header(t, buf, sizeof buf, &len), C4G_OK);
    }
    assert_int_equal(c4gh_moni_csv_header(23, buf, sizeof buf, &len), C4G_OK);
    assert_string_equal(buf, "type,num,axis,mode,smp_d1,smp_d5,smp_e1,smp_e2,pc_d5\n");
    assert_int_equal(c4g_moni_record(23, &rx, &tx, 1, &r), C4G_OK);
    assert_int_equal(c4gh_moni_csv_row(&r, buf, sizeof buf, &len), C4G_OK);
    assert_string_equal(buf, "23,321,1,9,1.000000,5.000000,6.000000,7.000000,15.000000\n");
    /* worst case row fits C4GH_MONI_ROW_MAX */
    r.num = -2147483647 - 1;
    r.mode = -2147483647 - 1;
    r.axis = 4294967295u;
    r.v[0] = r.v[1] = r.v[2] = r.v[3] = r.v[4] = -999999936.0f;
    assert_int_equal(c4gh_moni_csv_row(&r, buf, sizeof buf, &len), C4G_OK);
    assert_true(len < C4GH_MONI_ROW_MAX);
    assert_int_equal(c4gh_moni_csv_row(&r, buf, 20, &len), C4G_ERR_CAPACITY);
    assert_int_equal(c4gh_moni_csv_header(21, buf, 10, &len), C4G_ERR_CAPACITY);
    assert_int_equal(c4gh_moni_csv_header(18, buf, sizeof buf, &len), C4G_ERR_ARG);
    assert_int_equal(c4gh_moni_csv_header(21, NULL, 10, &len), C4G_ERR_NULL);
    assert_int_equal(c4gh_moni_csv_header(21, buf, 10, NULL), C4G_ERR_NULL);
    r.type = 99;
    assert_int_equal(c4gh_moni_csv_row(&r, buf, sizeof buf, &len), C4G_ERR_ARG);
    assert_int_equal(c4gh_moni_csv_row(NULL, buf, sizeof buf, &len), C4G_ERR_NULL);
    assert_int_equal(c4gh_moni_csv_row(&r, NULL, sizeof buf, &len), C4G_ERR_NULL);
    assert_int_equal(c4gh_moni_csv_row(&r, buf, sizeof buf, NULL), C4G_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fmt_float),
        cmocka_unit_test(test_csv),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
