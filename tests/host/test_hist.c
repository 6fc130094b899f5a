/* SPDX-License-Identifier: MIT */
/* The shared latency histogram (lib/host/c4gh_hist.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include "c4gh_hist.h"

static c4gh_hist_t a, b;

static void test_quantiles(void **st)
{
    (void)st;
    memset(&a, 0, sizeof a);
    assert_true(c4gh_hist_us(&a, 0.5) == 0.0 && c4gh_hist_mean_us(&a) == 0.0);
    c4gh_hist_add(&a, 500000);  /* 500 us */
    c4gh_hist_add(&a, 500400);
    c4gh_hist_add(&a, 2000000);
    c4gh_hist_add(&a, 2100000); /* 2100 us */
    assert_int_equal(a.n, 4);
    assert_int_equal(a.min_ns, 500000);
    assert_int_equal(a.max_ns, 2100000);
    assert_true(c4gh_hist_us(&a, 0.5) > 500.9 && c4gh_hist_us(&a, 0.5) < 501.1); /* upper edge */
    assert_true(c4gh_hist_us(&a, 1.0) > 2099.9 && c4gh_hist_us(&a, 1.0) < 2100.1); /* at most the max */
    assert_true(c4gh_hist_mean_us(&a) > 1275.0 && c4gh_hist_mean_us(&a) < 1275.2);
}

static void test_edges_and_merge(void **st)
{
    (void)st;
    memset(&b, 0, sizeof b);
    c4gh_hist_add(&b, -300);          /* before the schedule: first bin, exact minimum */
    c4gh_hist_add(&b, 90000000000LL); /* 90 s: the overflow bin, exact maximum */
    assert_int_equal(b.bin[0], 1);
    assert_int_equal(b.bin[C4GH_HIST_BINS - 1U], 1);
    assert_int_equal(b.min_ns, -300);
    assert_true(c4gh_hist_us(&b, 1.0) > 20000.0);
    c4gh_hist_merge(&a, &b);
    assert_int_equal(a.n, 6);
    assert_int_equal(a.min_ns, -300);
    assert_int_equal(a.max_ns, 90000000000LL);
    memset(&b, 0, sizeof b);
    c4gh_hist_merge(&a, &b); /* an empty one changes nothing */
    assert_int_equal(a.n, 6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quantiles),
        cmocka_unit_test(test_edges_and_merge),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
