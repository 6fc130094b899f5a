/* SPDX-License-Identifier: MIT */
/* Monitoring records (moni types 19..24); their CSV text is the host archive's (tests/host/test_csv.c). */
#include "test_helpers.h"
#include <math.h>

static void test_records(void **state)
{
    static const float want[6][5] = {
        {11, 12, 13, 14, 15}, {1, 2, 3, 4, 5}, {11, 12, 1, 3, 5},
        {14, 15, 1, 3, 5},    {1, 5, 6, 7, 15}, {1, 5, 6, 7, 14},
    };
    c4g_ctrl_packet_t rx;
    c4g_pc_packet_t tx;
    c4g_moni_rec_t r;
    uint32_t t, k;
    (void)state;
    moni_packets(&rx, &tx);
    for (t = 19; t <= 24; t++) {
        assert_int_equal(c4g_moni_record(t, &rx, &tx, 1, &r), C4G_OK);
        assert_int_equal(r.type, t);
        assert_int_equal(r.num, 321);
        assert_int_equal(r.axis, 1);
        assert_int_equal(r.mode, 9);
        for (k = 0; k < 5; k++) {
            assert_true(r.v[k] == want[t - 19][k]);
        }
    }
    assert_int_equal(c4g_moni_record(18, &rx, &tx, 1, &r), C4G_ERR_ARG);
    assert_int_equal(c4g_moni_record(25, &rx, &tx, 1, &r), C4G_ERR_ARG);
    assert_int_equal(c4g_moni_record(19, &rx, &tx, 2, &r), C4G_ERR_AXES);
    tx.n_axes = 1;
    assert_int_equal(c4g_moni_record(19, &rx, &tx, 1, &r), C4G_ERR_AXES);
    rx.n_axes = tx.n_axes = 25;
    assert_int_equal(c4g_moni_record(19, &rx, &tx, 20, &r), C4G_ERR_AXES);
    assert_int_equal(c4g_moni_record(19, NULL, &tx, 1, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_moni_record(19, &rx, NULL, 1, &r), C4G_ERR_NULL);
    assert_int_equal(c4g_moni_record(19, &rx, &tx, 1, NULL), C4G_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_records),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
