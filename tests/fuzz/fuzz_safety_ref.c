/* SPDX-License-Identifier: MIT */
/* libFuzzer target: the differential drive of tests/lib/ref_drive.h on arbitrary bytes. The
   bytes choose the world (axes, limits, kinematics) and every tick's packet, requests and
   caller reply; the library's c4g_engine_step / c4g_safety_filter and the reference
   (tests/lib/ref_safety.h, the code before it was restructured for speed) must agree to the
   bit after every call: statuses, replies, reports and engine state (abort otherwise). */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "../lib/ref_drive.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static ref_world_t w;
    ref_src_t s;
    memset(&s, 0, sizeof s);
    s.buf = data;
    s.len = size;
    if (ref_world_init(&w, &s) != 0) {
        uint32_t t;
        for (t = 0U; (t < 256U) && (ref_exhausted(&s) == 0); t++) {
            if (ref_tick(&w, &s) == 0) {
                fprintf(stderr, "fuzz_safety_ref: %s\n", w.why);
                abort();
            }
        }
    }
    return 0;
}
