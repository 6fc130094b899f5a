/* SPDX-License-Identifier: MIT */
/* Differential test of the per-tick engine step and safety filter against the reference
 * (tests/lib/ref_safety.h, the code before it was restructured for speed): seeded random
 * worlds (1..20 axes, every mode, limits hit and not hit, non-finite values, requests),
 * every call compared to the bit (statuses, replies, reports, engine state). The drive is
 * tests/lib/ref_drive.h; tests/fuzz/fuzz_safety_ref.c runs it on the fuzzer's bytes.
 * REF_SAFETY_SEEDS=N runs N seeds instead of the default (a long run: millions of ticks). */
#include "test_helpers.h"

#include "lib/ref_drive.h"

#include <stdlib.h>

#define TICKS_PER_SEED 200U
#define DEFAULT_SEEDS 400U

static uint32_t seeds(void)
{
    const char *e = getenv("REF_SAFETY_SEEDS");
    uint32_t n = DEFAULT_SEEDS;
    if ((e != NULL) && (atol(e) > 0)) {
        n = (uint32_t)atol(e);
    }
    return n;
}

/* Every filter action and status the drive reaches, so that a palette change that stops
 * exercising a rule fails here rather than proving nothing. */
static void test_ref_equal(void **state)
{
    static ref_world_t w;
    const uint32_t n_seeds = seeds();
    uint32_t flags = 0U;
    uint64_t ticks = 0U;
    uint32_t seed;
    (void)state;
    for (seed = 1U; seed <= n_seeds; seed++) {
        ref_src_t s;
        uint32_t t;
        memset(&s, 0, sizeof s);
        s.rng = 0x9E3779B97F4A7C15ULL ^ ((uint64_t)seed * 0x100000001B3ULL);
        if (ref_world_init(&w, &s) == 0) {
            continue;
        }
        for (t = 0U; t < TICKS_PER_SEED; t++) {
            uint32_t i;
            if (ref_tick(&w, &s) == 0) {
                fail_msg("seed %u: %s", seed, w.why);
            }
            for (i = 0U; i < w.n; i++) {
                flags |= w.rep_a.axis_flags[i];
            }
        }
        ticks += w.ticks;
    }
    print_message("ref_safety: %u seeds, %llu ticks equal\n", n_seeds, (unsigned long long)ticks);
    assert_int_equal(flags & 0xBFFFU, 0xBFFFU); /* every C4G_SF_* the filter raises */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ref_equal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
