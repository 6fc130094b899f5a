/* SPDX-License-Identifier: MIT */
/* c4gh_fmt_f32 over every float32 (lib/host/c4gh_fmt.h), against strtof:
 *   - every finite float's text reads back (strtof) to the same bits;
 *   - it is the shortest: with n > 1 digits, neither (n-1)-digit decimal next to it (the
 *     text cut by one digit, and that plus one unit) reads back to the float;
 *   - a negative float's text is "-" and its magnitude's (-0 included);
 *   - NaN is "nan" and infinities "inf" / "-inf" for every such bit pattern.
 * The positive patterns are split over THREADS threads (default 2). Then the speed of
 * c4gh_fmt_f32 against snprintf %.9g on the same floats, ns a float (information).
 *   fmt_exhaustive [--threads N] [--first HEX --last HEX]   (default: every pattern) */
#include "c4gh_fmt.h"

#include <inttypes.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_THREADS 64

typedef struct job {
    uint32_t first, last; /* positive finite patterns, inclusive */
    uint64_t checked, failures;
    uint32_t first_bad;
    char why[160];
} job_t;

static float from_bits(uint32_t b)
{
    float f;
    memcpy(&f, &b, sizeof f);
    return f;
}

static uint32_t bits_of(float f)
{
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b;
}

/* "<m>e<e>", written by hand: snprintf would double the run time */
static void decimal_text(uint64_t m, int e, char *out)
{
    char t[24];
    int n = 0, i = 0;
    unsigned ae = (unsigned)(e < 0 ? -e : e);
    do {
        t[n++] = (char)('0' + m % 10U);
        m /= 10U;
    } while (m != 0U);
    while (n > 0) {
        out[i++] = t[--n];
    }
    out[i++] = 'e';
    if (e < 0) {
        out[i++] = '-';
    }
    do {
        t[n++] = (char)('0' + ae % 10U);
        ae /= 10U;
    } while (ae != 0U);
    while (n > 0) {
        out[i++] = t[--n];
    }
    out[i] = '\0';
}

static void fail(job_t *j, uint32_t b, const char *what, const char *text)
{
    if (j->failures++ == 0U) {
        j->first_bad = b;
        (void)snprintf(j->why, sizeof j->why, "0x%08" PRIx32 " (%.9g): %s: \"%s\"", b,
                       (double)from_bits(b), what, text);
    }
}

/* The digits of @p s as an integer, the exponent of its last digit, the digit count. */
static int split(const char *s, uint64_t *m, int *e, int *n)
{
    int frac = 0, in_frac = 0, digits = 0, lead = 1;
    uint64_t x = 0U;
    const char *p = s;
    for (; *p != '\0' && *p != 'e'; p++) {
        if (*p == '.') {
            in_frac = 1;
            continue;
        }
        if (*p < '0' || *p > '9') {
            return -1;
        }
        if (in_frac) {
            frac++;
        }
        if (lead && *p == '0') {
            continue; /* 0.000123: the zeros before the first digit are not significant */
        }
        lead = 0;
        x = x * 10U + (uint64_t)(*p - '0');
        digits++;
    }
    *e = -frac + ((*p == 'e') ? atoi(p + 1) : 0);
    while (x != 0U && x % 10U == 0U) { /* an integer's zeros before the point */
        x /= 10U;
        (*e)++;
        digits--;
    }
    *m = x;
    *n = digits;
    return 0;
}

static void check_one(job_t *j, uint32_t b, char *pos)
{
    const float v = from_bits(b);
    char neg[C4GH_F32_TEXT_MAX], cand[32];
    uint64_t m;
    int e, n, k;
    const size_t len = c4gh_fmt_f32(v, pos);
    if (len == 0U || len >= C4GH_F32_TEXT_MAX || strlen(pos) != len) {
        fail(j, b, "length", pos);
        return;
    }
    if (bits_of(strtof(pos, NULL)) != b) {
        fail(j, b, "does not read back", pos);
        return;
    }
    if (split(pos, &m, &e, &n) != 0 || n > 9 || (b != 0U && m % 10U == 0U)) {
        fail(j, b, "malformed", pos);
        return;
    }
    for (k = 0; n > 1 && k < 2; k++) {
        decimal_text(m / 10U + (uint64_t)k, e + 1, cand);
        if (bits_of(strtof(cand, NULL)) == b) {
            fail(j, b, "a shorter text reads back too", cand);
            return;
        }
    }
    if (c4gh_fmt_f32(-v, neg) != len + 1U || neg[0] != '-' || strcmp(neg + 1, pos) != 0) {
        fail(j, b | 0x80000000U, "negative is not '-' and the magnitude", neg);
    }
}

static void *run(void *arg)
{
    job_t *j = arg;
    char pos[C4GH_F32_TEXT_MAX];
    uint32_t b = j->first;
    for (;;) {
        check_one(j, b, pos);
        j->checked++;
        if (b == j->last) {
            break;
        }
        b++;
    }
    return NULL;
}

static uint64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ULL + (uint64_t)ts.tv_nsec;
}

/* NaN and infinity spellings over all 2^24 such patterns. */
static uint64_t specials(void)
{
    uint64_t bad = 0U;
    uint32_t f;
    char t[C4GH_F32_TEXT_MAX];
    for (f = 0U; f < 0x800000U; f++) {
        unsigned s;
        for (s = 0U; s < 2U; s++) {
            const uint32_t b = (s << 31) | 0x7F800000U | f;
            const char *want = (f != 0U) ? "nan" : (s ? "-inf" : "inf");
            if (c4gh_fmt_f32(from_bits(b), t) != strlen(want) || strcmp(t, want) != 0) {
                if (bad++ == 0U) {
                    fprintf(stderr, "fmt_exhaustive: 0x%08" PRIx32 " gave \"%s\", want \"%s\"\n", b, t, want);
                }
            }
        }
    }
    return bad;
}

/* ns a float of c4gh_fmt_f32 and of snprintf %.9g over the same spread of patterns. */
static void speed(void)
{
    enum { N = 2000000 };
    char t[32];
    volatile size_t sink = 0U;
    uint64_t t0, t1, t2;
    uint32_t i, b;
    t0 = mono_ns();
    for (i = 0U, b = 0x3A000000U; i < N; i++, b += 0x1F3U) {
        sink += c4gh_fmt_f32(from_bits(b), t);
    }
    t1 = mono_ns();
    for (i = 0U, b = 0x3A000000U; i < N; i++, b += 0x1F3U) {
        sink += (size_t)snprintf(t, sizeof t, "%.9g", (double)from_bits(b));
    }
    t2 = mono_ns();
    printf("speed: c4gh_fmt_f32 %.1f ns a float, snprintf %%.9g %.1f ns (%.1fx)\n",
           (double)(t1 - t0) / N, (double)(t2 - t1) / N, (double)(t2 - t1) / (double)(t1 - t0));
    (void)sink;
}

int main(int argc, char **argv)
{
    static job_t jobs[MAX_THREADS];
    pthread_t th[MAX_THREADS];
    uint32_t first = 0U, last = 0x7F7FFFFFU; /* +0 .. FLT_MAX */
    unsigned threads = 2U, i;
    uint64_t checked = 0U, failures = 0U;
    int a, full;
    uint64_t t0;
    for (a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--threads") == 0 && a + 1 < argc) {
            threads = (unsigned)strtoul(argv[++a], NULL, 0);
        } else if (strcmp(argv[a], "--first") == 0 && a + 1 < argc) {
            first = (uint32_t)strtoul(argv[++a], NULL, 16);
        } else if (strcmp(argv[a], "--last") == 0 && a + 1 < argc) {
            last = (uint32_t)strtoul(argv[++a], NULL, 16);
        } else {
            fprintf(stderr, "usage: fmt_exhaustive [--threads N] [--first HEX --last HEX]\n");
            return 2;
        }
    }
    if (threads == 0U || threads > MAX_THREADS || first > last || last > 0x7F7FFFFFU) {
        fprintf(stderr, "fmt_exhaustive: bad range or thread count\n");
        return 2;
    }
    full = (first == 0U && last == 0x7F7FFFFFU);
    t0 = mono_ns();
    for (i = 0U; i < threads; i++) {
        const uint64_t span = (uint64_t)last - first + 1U;
        jobs[i].first = first + (uint32_t)(span * i / threads);
        jobs[i].last = first + (uint32_t)(span * (i + 1U) / threads - 1U);
        if (pthread_create(&th[i], NULL, run, &jobs[i]) != 0) {
            fprintf(stderr, "fmt_exhaustive: no thread\n");
            return 1;
        }
    }
    for (i = 0U; i < threads; i++) {
        pthread_join(th[i], NULL);
        checked += jobs[i].checked;
        failures += jobs[i].failures;
        if (jobs[i].failures != 0U) {
            fprintf(stderr, "fmt_exhaustive: %" PRIu64 " failures from 0x%08" PRIx32 ", first %s\n",
                    jobs[i].failures, jobs[i].first, jobs[i].why);
        }
    }
    failures += specials();
    printf("c4gh_fmt_f32: %" PRIu64 " finite magnitudes 0x%08" PRIx32 "..0x%08" PRIx32
           " (and their negatives), %s NaN/inf patterns: %" PRIu64 " failures, %.0f s on %u threads\n",
           checked, first, last, "all 2^24", failures, (double)(mono_ns() - t0) * 1e-9, threads);
    speed();
    printf("shortest round-trip text over %s: %s\n", full ? "all 2^32 patterns" : "the range given",
           failures == 0U ? "met" : "NOT");
    return failures == 0U ? 0 : 1;
}
