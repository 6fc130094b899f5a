/* SPDX-License-Identifier: MIT */
/* UDP datagrams with kernel timestamps, on the monotonic clock: what the tools that play the
 * controller's side (c4g-sim, c4g-replay live) share. A reply is judged by the time the
 * kernel received it and a packet by the time the kernel sent it, so the tool's own
 * scheduling delays are not charged to the PC. Linux (SO_TIMESTAMPING, software stamps);
 * without it the caller falls back to clock reads in user space. */
#ifndef C4GH_UDP_H
#define C4GH_UDP_H

#include "c4gh_clock.h"

#include <netinet/in.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>


/* Sleep until @p t_ns on CLOCK_MONOTONIC (TIMER_ABSTIME: no drift from the wake-ups);
 * a signal ends the sleep only once *stop is set (stop may be NULL). */
void c4gh_udp_sleep_until(uint64_t t_ns, const volatile sig_atomic_t *stop);

/* Software receive and send timestamps on @p fd, send stamps numbered from 0 per datagram
 * (SOF_TIMESTAMPING_OPT_ID). 1 if the kernel took them; 0 with errno set if not. */
int c4gh_udp_enable(int fd);

/* CLOCK_REALTIME minus CLOCK_MONOTONIC in ns (kernel stamps are real time). */
uint64_t c4gh_udp_real_minus_mono(void);

/* One received message: its source, its kernel stamp moved to the monotonic clock with
 * @p off (0 when it has none) and, from the error queue, the id of the send it stamps. */
typedef struct c4gh_udp_msg {
    struct sockaddr_in from;
    uint64_t stamp_ns;
    int has_key;
    uint32_t key;
} c4gh_udp_msg_t;

/* Read one datagram without blocking (errq: a send stamp from the error queue) into buf.
 * Its length, or -1 when none is waiting. */
ssize_t c4gh_udp_recv(int fd, int errq, uint64_t off, uint8_t *buf, size_t cap, c4gh_udp_msg_t *m);

/* The same with recvmsg's @p flags (0: block as the socket does; MSG_TRUNC: the datagram's
 * full length), for a caller that waits in the receive call itself (c4g-server). */
ssize_t c4gh_udp_recv_flags(int fd, int flags, uint64_t off, uint8_t *buf, size_t cap, c4gh_udp_msg_t *m);

#endif
