/* SPDX-License-Identifier: MIT */
/* The host's one clock: CLOCK_MONOTONIC in ns, the time base of every timestamp the tools
 * hand the library (which reads no clock itself). */
#ifndef C4GH_CLOCK_H
#define C4GH_CLOCK_H

#include <stdint.h>

/* CLOCK_MONOTONIC in ns. */
uint64_t c4gh_now_ns(void);

#endif
