/* SPDX-License-Identifier: MIT */
/* CAN bus logs (candump, pcap DLT_CAN_SOCKETCAN) and the SocketCAN raw socket. */
#include "c4gh_can.h"

#include <errno.h>
#include <fcntl.h>
#include <net/if.h>
#include <pcap/pcap.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>
#include <linux/can.h>
#include <linux/can/raw.h>

#ifndef DLT_CAN_SOCKETCAN
#define DLT_CAN_SOCKETCAN 227
#endif

void c4gh_co_candump_line(char *out, size_t cap, const char *iface, uint64_t wall_us,
                         const c4g_co_frame_t *f)
{
    int o = snprintf(out, cap, "(%llu.%06llu) %s %03X#", (unsigned long long)(wall_us / 1000000u),
                     (unsigned long long)(wall_us % 1000000u), iface, f->id & 0x7FFu);
    if (o < 0 || (size_t)o >= cap) {
        return;
    }
    if (f->rtr) {
        snprintf(out + o, cap - (size_t)o, "R");
        return;
    }
    for (int i = 0; i < f->dlc && i < 8 && (size_t)o + 3 < cap; i++) {
        o += snprintf(out + o, cap - (size_t)o, "%02X", f->data[i]);
    }
}

int c4gh_co_buslog_open(c4gh_co_buslog_t *l, const char *candump_path, const char *pcap_path,
                       const char *iface, uint64_t epoch_us, char *err, size_t errlen)
{
    memset(l, 0, sizeof *l);
    snprintf(l->iface, sizeof l->iface, "%s", iface != NULL ? iface : "vcan0");
    l->epoch_us = epoch_us;
    if (candump_path != NULL) {
        l->candump = fopen(candump_path, "w");
        if (l->candump == NULL) {
            snprintf(err, errlen, "%s: cannot create the candump log: %s", candump_path, strerror(errno));
            return -1;
        }
    }
    if (pcap_path != NULL) {
        pcap_t *p = pcap_open_dead(DLT_CAN_SOCKETCAN, 65535);
        pcap_dumper_t *d = NULL;
        if (p != NULL) {
            d = pcap_dump_open(p, pcap_path);
        }
        if (d == NULL) {
            snprintf(err, errlen, "%s: cannot create the pcap: %s", pcap_path,
                     p != NULL ? pcap_geterr(p) : "pcap_open_dead failed");
            if (p != NULL) {
                pcap_close(p);
            }
            c4gh_co_buslog_close(l);
            return -1;
        }
        l->pcap = p;
        l->dumper = d;
    }
    return 0;
}

void c4gh_co_buslog_write(c4gh_co_buslog_t *l, const c4g_co_frame_t *f)
{
    const uint64_t wall = l->epoch_us + f->t_ns / 1000U; /* the logs show us */
    l->frames++;
    if (l->candump != NULL) {
        char line[96];
        c4gh_co_candump_line(line, sizeof line, l->iface, wall, f);
        fprintf(l->candump, "%s\n", line);
    }
    if (l->dumper != NULL) {
        /* struct can_frame as the SocketCAN link type stores it: id in network byte
           order with the RTR flag, dlc, 3 padding bytes, 8 data bytes */
        uint8_t b[16] = {0};
        uint32_t id = (uint32_t)(f->id & 0x7FFu) | (f->rtr ? CAN_RTR_FLAG : 0u);
        struct pcap_pkthdr h;
        b[0] = (uint8_t)(id >> 24);
        b[1] = (uint8_t)(id >> 16);
        b[2] = (uint8_t)(id >> 8);
        b[3] = (uint8_t)id;
        b[4] = f->dlc;
        memcpy(&b[8], f->data, 8);
        memset(&h, 0, sizeof h);
        h.ts.tv_sec = (time_t)(wall / 1000000u);
        h.ts.tv_usec = (suseconds_t)(wall % 1000000u);
        h.caplen = 16;
        h.len = 16;
        pcap_dump((u_char *)l->dumper, &h, b);
    }
}

void c4gh_co_buslog_cb(void *ctx, const c4g_co_frame_t *f)
{
    c4gh_co_buslog_write((c4gh_co_buslog_t *)ctx, f);
}

void c4gh_co_buslog_close(c4gh_co_buslog_t *l)
{
    if (l->candump != NULL) {
        fclose(l->candump);
        l->candump = NULL;
    }
    if (l->dumper != NULL) {
        pcap_dump_close((pcap_dumper_t *)l->dumper);
        l->dumper = NULL;
    }
    if (l->pcap != NULL) {
        pcap_close((pcap_t *)l->pcap);
        l->pcap = NULL;
    }
}

int c4gh_co_socketcan_open(const char *ifname, char *err, size_t errlen)
{
    struct ifreq ifr;
    struct sockaddr_can addr;
    int fd;
    if (strlen(ifname) >= IFNAMSIZ) {
        snprintf(err, errlen, "%s: interface name too long", ifname);
        return -1;
    }
    fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        snprintf(err, errlen, "%s: no CAN raw socket (kernel without SocketCAN?): %s", ifname,
                 strerror(errno));
        return -1;
    }
    memset(&ifr, 0, sizeof ifr);
    snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "%s", ifname);
    if (ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
        snprintf(err, errlen, "%s: no such CAN interface: %s", ifname, strerror(errno));
        close(fd);
        return -1;
    }
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = ifr.ifr_ifindex;
    if (bind(fd, (struct sockaddr *)&addr, sizeof addr) < 0) {
        snprintf(err, errlen, "%s: bind: %s", ifname, strerror(errno));
        close(fd);
        return -1;
    }
    (void)fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    return fd;
}

int c4gh_co_socketcan_send(int fd, const c4g_co_frame_t *f)
{
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    cf.can_id = (canid_t)(f->id & 0x7FFu) | (f->rtr ? CAN_RTR_FLAG : 0u);
    cf.can_dlc = f->dlc;
    memcpy(cf.data, f->data, 8);
    return write(fd, &cf, sizeof cf) == (ssize_t)sizeof cf ? 0 : -1;
}

int c4gh_co_socketcan_recv(int fd, c4g_co_frame_t *f, uint64_t t_ns)
{
    struct can_frame cf;
    const ssize_t n = read(fd, &cf, sizeof cf);
    if (n < 0) {
        return (errno == EAGAIN || errno == EWOULDBLOCK) ? 0 : -1;
    }
    if (n != (ssize_t)sizeof cf || (cf.can_id & (CAN_EFF_FLAG | CAN_ERR_FLAG)) != 0 || cf.can_dlc > 8) {
        return 0;
    }
    memset(f, 0, sizeof *f);
    f->id = (uint16_t)(cf.can_id & CAN_SFF_MASK);
    f->rtr = (cf.can_id & CAN_RTR_FLAG) ? 1 : 0;
    f->dlc = cf.can_dlc;
    memcpy(f->data, cf.data, 8);
    f->t_ns = t_ns;
    return 1;
}
