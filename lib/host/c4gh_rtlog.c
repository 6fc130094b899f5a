/* SPDX-License-Identifier: MIT */
/* Lock-free SPSC record ring + writer thread (see c4gh_rtlog.h for the memory model). */
#include "c4gh_rtlog.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#define RING_MASK (C4GH_RTLOG_SLOTS - 1U)
#define WAKE_AT (C4GH_RTLOG_SLOTS / 4U) /* queued records that wake the writer */

void c4gh_rtlog_init(c4gh_rtlog_t *r, c4gh_rtlog_sink_fn sink, void *ctx)
{
    r->head = 0U;
    r->tail = 0U;
    r->stop = 0U;
    r->dropped = 0U;
    r->written = 0U;
    r->high_water = 0U;
    r->sink = sink;
    r->ctx = ctx;
    r->running = 0;
    r->idle_ms = 100U;
}

c4gh_rtlog_rec_t *c4gh_rtlog_reserve(c4gh_rtlog_t *r)
{
    const uint32_t h = r->head; /* only this thread writes head */
    const uint32_t t = __atomic_load_n(&r->tail, __ATOMIC_ACQUIRE);
    const uint32_t used = h - t;
    if (used >= C4GH_RTLOG_SLOTS) {
        r->dropped++;
        return NULL;
    }
    if (used + 1U > r->high_water) {
        r->high_water = used + 1U;
    }
    return &r->slot[h & RING_MASK];
}

void c4gh_rtlog_commit(c4gh_rtlog_t *r)
{
    const uint32_t h = r->head + 1U;
    __atomic_store_n(&r->head, h, __ATOMIC_RELEASE);
    /* the queue grows by one per commit, so it meets WAKE_AT on its way up: one post */
    if (r->running && h - __atomic_load_n(&r->tail, __ATOMIC_ACQUIRE) == WAKE_AT) {
        (void)sem_post(&r->wake);
    }
}

int c4gh_rtlog_put(c4gh_rtlog_t *r, uint32_t kind, uint64_t t_ns, const void *data, size_t len)
{
    c4gh_rtlog_rec_t *rec = c4gh_rtlog_reserve(r);
    if (rec == NULL) {
        return -1;
    }
    if (len > C4GH_RTLOG_SLOT_BYTES) {
        len = C4GH_RTLOG_SLOT_BYTES;
    }
    rec->kind = kind;
    rec->t_ns = t_ns;
    rec->len = (uint32_t)len;
    if (len > 0U) {
        memcpy(rec->data, data, len);
    }
    c4gh_rtlog_commit(r);
    return 0;
}

int c4gh_rtlog_printf(c4gh_rtlog_t *r, uint32_t kind, uint64_t t_ns, const char *fmt, ...)
{
    va_list ap;
    int n;
    c4gh_rtlog_rec_t *rec = c4gh_rtlog_reserve(r);
    if (rec == NULL) {
        return -1;
    }
    va_start(ap, fmt);
    n = vsnprintf((char *)rec->data, C4GH_RTLOG_SLOT_BYTES, fmt, ap);
    va_end(ap);
    if (n < 0) {
        n = 0;
    }
    if ((size_t)n >= C4GH_RTLOG_SLOT_BYTES) {
        n = (int)C4GH_RTLOG_SLOT_BYTES - 1;
    }
    rec->kind = kind;
    rec->t_ns = t_ns;
    rec->len = (uint32_t)n;
    c4gh_rtlog_commit(r);
    return 0;
}

/* Consume everything published so far; returns the number of records handled. */
static unsigned drain(c4gh_rtlog_t *r)
{
    unsigned n = 0U;
    uint32_t t = r->tail; /* only this thread writes tail */
    const uint32_t h = __atomic_load_n(&r->head, __ATOMIC_ACQUIRE);
    while (t != h) {
        if (r->sink != NULL) {
            r->sink(r->ctx, &r->slot[t & RING_MASK]);
        }
        t++;
        r->written++;
        n++;
        __atomic_store_n(&r->tail, t, __ATOMIC_RELEASE);
    }
    return n;
}

/* Sleep until the producer or stop posts, or idle_ms passed (sem_timedwait counts on the
 * realtime clock: a clock step only moves one wake-up). */
static void writer_wait(c4gh_rtlog_t *r)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    ts.tv_sec += (time_t)(r->idle_ms / 1000U);
    ts.tv_nsec += (long)(r->idle_ms % 1000U) * 1000000L;
    if (ts.tv_nsec >= 1000000000L) {
        ts.tv_nsec -= 1000000000L;
        ts.tv_sec++;
    }
    while (sem_timedwait(&r->wake, &ts) != 0 && errno == EINTR) {
    }
}

static void *writer(void *arg)
{
    c4gh_rtlog_t *r = (c4gh_rtlog_t *)arg;
    for (;;) {
        const uint32_t stop = __atomic_load_n(&r->stop, __ATOMIC_ACQUIRE);
        if (drain(r) == 0U && stop != 0U) {
            break;
        }
        if (stop == 0U) {
            writer_wait(r);
        }
    }
    return NULL;
}

int c4gh_rtlog_start(c4gh_rtlog_t *r)
{
    int e;
    if (sem_init(&r->wake, 0, 0U) != 0) {
        return errno;
    }
    r->running = 1; /* before the thread: commit may post from now on */
    e = pthread_create(&r->thread, NULL, writer, r);
    if (e != 0) {
        r->running = 0;
        (void)sem_destroy(&r->wake);
    }
    return e;
}

void c4gh_rtlog_stop(c4gh_rtlog_t *r)
{
    if (r->running) {
        __atomic_store_n(&r->stop, 1U, __ATOMIC_RELEASE);
        (void)sem_post(&r->wake);
        pthread_join(r->thread, NULL);
        r->running = 0;
        (void)sem_destroy(&r->wake);
    } else {
        (void)drain(r); /* no thread: drain synchronously */
    }
}
