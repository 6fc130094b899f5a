/* SPDX-License-Identifier: MIT */
/* UDP datagrams with kernel timestamps: see c4g_udpts.h. */
#include "c4gh_udp.h"

#include <errno.h>
#include <linux/errqueue.h>
#include <linux/net_tstamp.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>

static uint64_t ts_ns(const struct timespec *ts)
{
    return (uint64_t)ts->tv_sec * 1000000000ULL + (uint64_t)ts->tv_nsec;
}

void c4gh_udp_sleep_until(uint64_t t_ns, const volatile sig_atomic_t *stop)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(t_ns / 1000000000U);
    ts.tv_nsec = (long)(t_ns % 1000000000U);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR &&
           (stop == NULL || !*stop)) {
    }
}

int c4gh_udp_enable(int fd)
{
    const unsigned ts = SOF_TIMESTAMPING_RX_SOFTWARE | SOF_TIMESTAMPING_TX_SOFTWARE |
                        SOF_TIMESTAMPING_SOFTWARE | SOF_TIMESTAMPING_OPT_ID |
                        SOF_TIMESTAMPING_OPT_TSONLY;
    return setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPING, &ts, sizeof ts) == 0;
}

/* The real-time read sits between two monotonic reads; the narrowest of three brackets
 * wins, so a preemption between the reads does not shift the offset. */
uint64_t c4gh_udp_real_minus_mono(void)
{
    uint64_t best = 0, width = UINT64_MAX;
    int i;
    for (i = 0; i < 3 && width > 2000U; i++) {
        struct timespec r;
        const uint64_t m1 = c4gh_now_ns();
        uint64_t m2;
        clock_gettime(CLOCK_REALTIME, &r);
        m2 = c4gh_now_ns();
        if (m2 - m1 < width) {
            width = m2 - m1;
            best = ts_ns(&r) - (m1 + (m2 - m1) / 2U);
        }
    }
    return best;
}

/* The software stamp of a message on the monotonic clock (0 if none), and for the error
 * queue the id of the send it belongs to. */
static uint64_t msg_stamp(struct msghdr *m, uint64_t off, int errq, c4gh_udp_msg_t *out)
{
    struct cmsghdr *c;
    uint64_t t = 0;
    for (c = CMSG_FIRSTHDR(m); c != NULL; c = CMSG_NXTHDR(m, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPING) {
            struct scm_timestamping st;
            memcpy(&st, CMSG_DATA(c), sizeof st);
            t = ts_ns(&st.ts[0]);
        } else if (errq && c->cmsg_level == IPPROTO_IP && c->cmsg_type == IP_RECVERR) {
            struct sock_extended_err e;
            memcpy(&e, CMSG_DATA(c), sizeof e);
            if (e.ee_origin == SO_EE_ORIGIN_TIMESTAMPING) {
                out->has_key = 1;
                out->key = e.ee_data;
            }
        }
    }
    return (t > off) ? t - off : 0U;
}

ssize_t c4gh_udp_recv(int fd, int errq, uint64_t off, uint8_t *buf, size_t cap, c4gh_udp_msg_t *out)
{
    return c4gh_udp_recv_flags(fd, MSG_DONTWAIT | (errq ? MSG_ERRQUEUE : 0), off, buf, cap, out);
}

ssize_t c4gh_udp_recv_flags(int fd, int flags, uint64_t off, uint8_t *buf, size_t cap, c4gh_udp_msg_t *out)
{
    union { char c[256]; struct cmsghdr align; } ctl;
    struct iovec iov;
    struct msghdr m;
    ssize_t n;
    memset(out, 0, sizeof *out);
    memset(&m, 0, sizeof m);
    iov.iov_base = buf;
    iov.iov_len = cap;
    m.msg_name = &out->from;
    m.msg_namelen = sizeof out->from;
    m.msg_iov = &iov;
    m.msg_iovlen = 1;
    m.msg_control = ctl.c;
    m.msg_controllen = sizeof ctl.c;
    n = recvmsg(fd, &m, flags);
    if (n < 0) {
        return -1;
    }
    out->stamp_ns = msg_stamp(&m, off, (flags & MSG_ERRQUEUE) != 0, out);
    return n;
}
