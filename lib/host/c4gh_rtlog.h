/* SPDX-License-Identifier: MIT */
/* c4gh_rtlog: a lock-free single-producer single-consumer record ring with a writer
 * thread, so a real-time loop can log (text lines, pcap records, moni rows) without
 * allocation, locks or I/O. The producer is the RT thread; the consumer is a plain
 * pthread that hands each record to a sink callback (which does the file I/O).
 *
 * Memory ordering: C11 <stdatomic.h> is not available in C99 mode, so head and tail
 * use the GCC/Clang __atomic builtins. The producer fills a slot, then publishes it
 * with __atomic_store_n(&head, h + 1, __ATOMIC_RELEASE); the consumer reads head with
 * __ATOMIC_ACQUIRE, so it sees the slot's bytes. The consumer frees the slot with a
 * RELEASE store of tail; the producer reads tail with ACQUIRE before reusing a slot.
 * Indices are free-running uint32 counters (wrap is harmless: size is a power of 2).
 * When the ring is full the record is dropped and counted, never waited for.
 *
 * The writer does not poll: it blocks on a semaphore and drains in batches, woken by the
 * producer once a quarter of the ring is queued (one sem_post, no lock), by
 * c4gh_rtlog_stop, or after idle_ms (so a lone text line waits at most that long). At 1 kHz
 * that is a few wake-ups a second instead of one per tick. */
#ifndef C4GH_RTLOG_H
#define C4GH_RTLOG_H

#include <pthread.h>
#include <semaphore.h>
#include <stddef.h>
#include <stdint.h>

#define C4GH_RTLOG_SLOTS 1024U      /* power of two */
#define C4GH_RTLOG_SLOT_BYTES 2040U /* payload bytes per record */

typedef struct c4gh_rtlog_rec {
    uint32_t kind;   /* caller-defined record type */
    uint32_t len;    /* payload bytes used */
    uint64_t t_ns;   /* caller timestamp */
    unsigned char data[C4GH_RTLOG_SLOT_BYTES];
} c4gh_rtlog_rec_t;

/* Called on the writer thread for every record, in order. */
typedef void (*c4gh_rtlog_sink_fn)(void *ctx, const c4gh_rtlog_rec_t *rec);

typedef struct c4gh_rtlog {
    c4gh_rtlog_rec_t slot[C4GH_RTLOG_SLOTS];
    uint32_t head;          /* written by the producer only (atomic) */
    uint32_t tail;          /* written by the consumer only (atomic) */
    uint32_t stop;          /* set once to stop the writer (atomic) */
    uint64_t dropped;       /* producer-side: records lost to a full ring */
    uint64_t written;       /* consumer-side: records handed to the sink */
    uint32_t high_water;    /* producer-side: most records queued at once */
    c4gh_rtlog_sink_fn sink;
    void *ctx;
    pthread_t thread;
    int running;
    sem_t wake;             /* posted by the producer (quarter full) and by stop */
    unsigned idle_ms;       /* longest the writer sleeps with records queued */
} c4gh_rtlog_t;

/* Set up the ring (no allocation: the struct is caller storage, usually static). */
void c4gh_rtlog_init(c4gh_rtlog_t *r, c4gh_rtlog_sink_fn sink, void *ctx);
/* Start the writer thread; returns 0 or an errno value. */
int c4gh_rtlog_start(c4gh_rtlog_t *r);
/* Drain everything queued, then stop and join the writer thread. */
void c4gh_rtlog_stop(c4gh_rtlog_t *r);

/* Producer side (RT thread): reserve a slot, fill it, commit it. Returns NULL when
 * the ring is full (the loss is counted). No system call, no lock, O(1). */
c4gh_rtlog_rec_t *c4gh_rtlog_reserve(c4gh_rtlog_t *r);
void c4gh_rtlog_commit(c4gh_rtlog_t *r);
/* Copy @p len bytes (truncated to the slot size) as one record. 0 ok, -1 dropped. */
int c4gh_rtlog_put(c4gh_rtlog_t *r, uint32_t kind, uint64_t t_ns, const void *data, size_t len);
/* printf-style text record (vsnprintf into the slot; no allocation for the
 * integer/string/float conversions used by the tools). 0 ok, -1 dropped. */
int c4gh_rtlog_printf(c4gh_rtlog_t *r, uint32_t kind, uint64_t t_ns, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

#endif /* C4GH_RTLOG_H */
