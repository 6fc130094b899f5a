/* SPDX-License-Identifier: MIT */
/* The shared latency histogram: see c4gh_hist.h. */
#include "c4gh_hist.h"

void c4gh_hist_add(c4gh_hist_t *h, int64_t ns)
{
    const int64_t us = (ns > 0) ? ns / 1000 : 0;
    if (h->n == 0U || ns < h->min_ns) {
        h->min_ns = ns;
    }
    if (h->n == 0U || ns > h->max_ns) {
        h->max_ns = ns;
    }
    h->bin[(us < (int64_t)C4GH_HIST_BINS - 1) ? (uint32_t)us : C4GH_HIST_BINS - 1U]++;
    h->sum_ns += (double)ns;
    h->n++;
}

double c4gh_hist_us(const c4gh_hist_t *h, double q)
{
    const uint64_t need = (uint64_t)(q * (double)h->n + 0.999999);
    const double max_us = (double)h->max_ns / 1000.0;
    uint64_t acc = 0U;
    uint32_t i;
    if (h->n == 0U) {
        return 0.0;
    }
    for (i = 0U; i < C4GH_HIST_BINS; i++) {
        acc += h->bin[i];
        if (acc >= need && acc > 0U) {
            const double edge = (double)(i + 1U);
            return (edge < max_us) ? edge : max_us;
        }
    }
    return max_us;
}

double c4gh_hist_mean_us(const c4gh_hist_t *h)
{
    return (h->n > 0U) ? h->sum_ns / (double)h->n / 1000.0 : 0.0;
}

void c4gh_hist_merge(c4gh_hist_t *to, const c4gh_hist_t *from)
{
    uint32_t i;
    if (from->n == 0U) {
        return;
    }
    if (to->n == 0U || from->min_ns < to->min_ns) {
        to->min_ns = from->min_ns;
    }
    if (to->n == 0U || from->max_ns > to->max_ns) {
        to->max_ns = from->max_ns;
    }
    for (i = 0U; i < C4GH_HIST_BINS; i++) {
        to->bin[i] += from->bin[i];
    }
    to->sum_ns += from->sum_ns;
    to->n += from->n;
}
