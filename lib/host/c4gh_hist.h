/* SPDX-License-Identifier: MIT */
/* One latency histogram for every tool: c4g-server's cycle time (receive to send), the
 * reply latency c4g-sim and c4g-replay judge on the controller's side, and c4g-replay
 * live's send error. 1 us bins up to 20 ms (the last bin collects everything above), the
 * exact minimum, maximum and sum. Fixed memory, no allocation: safe on a real-time path. */
#ifndef C4GH_HIST_H
#define C4GH_HIST_H

#include <stdint.h>

#define C4GH_HIST_BINS 20001U

typedef struct c4gh_hist {
    uint64_t n;
    int64_t min_ns, max_ns;  /* exact, over every sample */
    double sum_ns;
    uint32_t bin[C4GH_HIST_BINS];
} c4gh_hist_t;

/* One sample in ns; a negative one (a kernel stamp a hair before the schedule) counts in
 * the first bin. */
void c4gh_hist_add(c4gh_hist_t *h, int64_t ns);

/* Quantile q (0..1) in us: the upper edge of the bin that reaches it, at most the maximum;
 * 0 when empty. */
double c4gh_hist_us(const c4gh_hist_t *h, double q);

/* Mean in us; 0 when empty. */
double c4gh_hist_mean_us(const c4gh_hist_t *h);

/* Adds every sample of from to to. */
void c4gh_hist_merge(c4gh_hist_t *to, const c4gh_hist_t *from);

#endif
