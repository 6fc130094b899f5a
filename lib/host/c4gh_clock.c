/* SPDX-License-Identifier: MIT */
#define _POSIX_C_SOURCE 200809L
#include "c4gh_clock.h"

#include <time.h>

uint64_t c4gh_now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}
