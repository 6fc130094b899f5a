/* SPDX-License-Identifier: MIT */
/* c4g-sim's socket: sending, receiving with kernel timestamps, waiting for the next tick. */
#include <arpa/inet.h>
#include <errno.h>
#include <string.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "app.h"
#include "c4gh_udp.h"

uint64_t now_ns(void) { return c4gh_now_ns(); }

static void pcap_record(app_t *a, int outgoing, const struct sockaddr_in *peer,
                        const uint8_t *buf, size_t len)
{
    struct timespec ts;
    uint32_t pip;
    uint16_t pport;
    int rc;
    if (a->pcap == NULL) {
        return;
    }
    clock_gettime(CLOCK_REALTIME, &ts);
    pip = ntohl(peer->sin_addr.s_addr);
    pport = ntohs(peer->sin_port);
    if (outgoing) {
        rc = c4gh_pcap_write_udp(a->pcap, &ts, a->local_ip, a->local_port, pip, pport, buf, len);
    } else {
        rc = c4gh_pcap_write_udp(a->pcap, &ts, pip, pport, a->local_ip, a->local_port, buf, len);
    }
    if (rc != 0) {
        a->out_error = 1;
    }
}

long net_sendto(app_t *a, const uint8_t *buf, size_t len, uint32_t *key)
{
    const ssize_t n = sendto(a->fd, buf, len, 0, (const struct sockaddr *)&a->srv, sizeof a->srv);
    const int e = errno;
    /* refused (an ICMP error of an earlier datagram): this one went out all the same */
    if (n >= 0 || e == ECONNREFUSED) {
        pcap_record(a, 1, &a->srv, buf, len);
    }
    if (n >= 0) {
        if (key != NULL) {
            *key = a->tx_seq;
        }
        a->tx_seq++; /* the kernel numbers every datagram sent, from 0 */
    }
    errno = e;
    return (long)n;
}

/* Returns 1 and the SO_TIMESTAMPING id of the datagram in @p key if it went out. */
int raw_send(app_t *a, const uint8_t *buf, size_t len, uint32_t *key)
{
    const long n = net_sendto(a, buf, len, key);
    if (n < 0 && errno != ECONNREFUSED) {
        if (!a->sim.fatal) {
            fprintf(stderr, "c4g-sim: sendto: %s\n", strerror(errno));
            sim_raise(&a->sim, C4G_CERR_TX_UDP, 0, 0);
            sim_all_drive_off(&a->sim);
            a->sim.fatal = 1;
        }
        return 0;
    }
    return n >= 0;
}

/* Bound to any address: the source address the kernel picks towards the server. */
static void local_ip_towards_server(app_t *a)
{
    int t = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in r;
    socklen_t rl = sizeof r;
    if (t >= 0 && connect(t, (struct sockaddr *)&a->srv, sizeof a->srv) == 0 &&
        getsockname(t, (struct sockaddr *)&r, &rl) == 0) {
        a->local_ip = ntohl(r.sin_addr.s_addr);
    }
    if (t >= 0) {
        close(t);
    }
}

int net_open(app_t *a)
{
    struct sockaddr_in *la = &a->local;
    socklen_t ll = sizeof *la;
    a->fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (a->fd < 0 || bind(a->fd, (struct sockaddr *)la, sizeof *la) != 0 ||
        getsockname(a->fd, (struct sockaddr *)la, &ll) != 0) {
        return -1;
    }
    a->local_port = ntohs(la->sin_port);
    a->local_ip = ntohl(la->sin_addr.s_addr);
    /* Replies are judged by their kernel arrival time and our packets by their kernel
     * send time, so the simulator's own scheduling delays are not charged to the PC.
     * If the kernel refuses them: clock reads in user space. */
    a->kstamp = c4gh_udp_enable(a->fd);
    if (!a->kstamp && a->o.verbose) {
        fprintf(stderr, "c4g-sim: no kernel timestamps (%s): reply times from user space\n",
                strerror(errno));
    }
    if (a->local_ip == 0U) {
        local_ip_towards_server(a);
    }
    return 0;
}

/* Read one datagram (errq: a send timestamp from the error queue); 0 when none is left. */
static int read_one(app_t *a, int errq, uint64_t off)
{
    uint8_t buf[MAX_DGRAM];
    c4gh_udp_msg_t m;
    const ssize_t n = c4gh_udp_recv(a->fd, errq, off, buf, sizeof buf, &m);
    uint64_t t, now;
    if (n < 0) {
        return 0;
    }
    t = a->kstamp ? m.stamp_ns : 0U;
    now = now_ns();
    if (errq) {
        /* the send happened after the clock read in emit and before now */
        if (m.has_key && a->has_key && m.key == a->tx_key) {
            (void)c4g_ctrl_sent_stamp(&a->cs, t, now);
        }
        return 1;
    }
    pcap_record(a, 0, &m.from, buf, (size_t)n); /* every datagram, before any check */
    handle_rx(a, buf, (size_t)n, &m.from, (t != 0U && t <= now) ? t : now);
    return 1;
}

/* Read everything that has arrived, each datagram with its kernel arrival time, so a reply
 * that waited in the socket while the simulator was descheduled keeps its real time; then
 * the send timestamps of our own datagrams. */
void drain(app_t *a)
{
    const uint64_t off = a->kstamp ? c4gh_udp_real_minus_mono() : 0U;
    while (read_one(a, 0, off)) {
    }
    while (a->kstamp && read_one(a, 1, off)) {
    }
}

/* Send the delayed packets that are due; returns the earliest due time left (or until). */
static uint64_t release_pending(app_t *a, uint64_t t, uint64_t until)
{
    uint64_t wake = until;
    int i;
    for (i = 0; i < MAX_PENDING; i++) {
        if (a->pend[i].used && a->pend[i].due_ns <= t) {
            (void)raw_send(a, a->pend[i].buf, a->pend[i].len, NULL);
            a->pend[i].used = 0;
        } else if (a->pend[i].used && a->pend[i].due_ns < wake) {
            wake = a->pend[i].due_ns;
        }
    }
    return wake;
}

/* Receive (and release delayed packets) until @p until, or (@p reply) until the outstanding
 * packet's reply came: 1 if it did. */
static int receive(app_t *a, uint64_t until, int reply)
{
    for (;;) {
        const uint64_t t = now_ns();
        const uint64_t wake = release_pending(a, t, until);
        fd_set rf;
        struct timeval tv;
        if (reply && a->cs.out.got) {
            return 1;
        }
        if (t >= until || g_stop) {
            return 0;
        }
        FD_ZERO(&rf);
        FD_SET(a->fd, &rf);
        tv.tv_sec = (time_t)((wake - t) / 1000000000U);
        tv.tv_usec = (suseconds_t)(((wake - t) % 1000000000U) / 1000U);
        if (select(a->fd + 1, &rf, NULL, NULL, &tv) > 0) {
            drain(a);
        }
    }
}

void window(app_t *a, uint64_t until) { (void)receive(a, until, 0); }

int wait_own_reply(app_t *a, uint64_t until) { return receive(a, until, 1); }
