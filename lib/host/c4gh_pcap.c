/* SPDX-License-Identifier: MIT */
/* c4g_pcap: UDP/IPv4/Ethernet frames into a pcap file through libpcap (see c4g_pcap.h). */
#include "c4gh_pcap.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#define ETH_LEN 14U
#define IP_LEN 20U
#define UDP_LEN 8U
#define HDR_LEN (ETH_LEN + IP_LEN + UDP_LEN)
#define MAX_PAYLOAD 65507U

struct c4g_pcap {
    pcap_t *p;
    pcap_dumper_t *d;
    uint16_t ip_id;
    unsigned long frames;
    int failed;
    uint8_t frame[HDR_LEN + MAX_PAYLOAD];
};

static void put16(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)(v >> 8);
    b[1] = (uint8_t)v;
}

static void put32(uint8_t *b, uint32_t v)
{
    put16(b, v >> 16);
    put16(&b[2], v & 0xFFFFU);
}

/* One's complement sum of 16-bit big-endian words. */
static uint32_t csum_add(uint32_t sum, const uint8_t *b, size_t len)
{
    size_t i;
    for (i = 0; i + 1U < len; i += 2U) {
        sum += ((uint32_t)b[i] << 8) | b[i + 1U];
    }
    if ((len & 1U) != 0U) {
        sum += (uint32_t)b[len - 1U] << 8;
    }
    return sum;
}

static uint16_t csum_fold(uint32_t sum)
{
    while ((sum >> 16) != 0U) {
        sum = (sum & 0xFFFFU) + (sum >> 16);
    }
    return (uint16_t)(~sum & 0xFFFFU);
}

c4gh_pcap_t *c4gh_pcap_open(const char *path, char *err, size_t errlen)
{
    c4gh_pcap_t *w;
    if (err != NULL && errlen > 0U) {
        err[0] = '\0';
    }
    if (path == NULL) {
        if (err != NULL) snprintf(err, errlen, "no pcap path");
        return NULL;
    }
    w = calloc(1, sizeof *w);
    if (w == NULL) {
        if (err != NULL) snprintf(err, errlen, "out of memory");
        return NULL;
    }
    w->p = pcap_open_dead(DLT_EN10MB, 65535);
    if (w->p == NULL) {
        if (err != NULL) snprintf(err, errlen, "pcap_open_dead failed");
        free(w);
        return NULL;
    }
    {
        /* opened here so the error is the system's reason alone: callers name the path */
        FILE *fp = fopen(path, "wb");
        const int e = errno;
        if (fp == NULL) {
            if (err != NULL) snprintf(err, errlen, "%s", strerror(e));
            pcap_close(w->p);
            free(w);
            errno = e;
            return NULL;
        }
        w->d = pcap_dump_fopen(w->p, fp);
        if (w->d == NULL) {
            if (err != NULL) snprintf(err, errlen, "%s", pcap_geterr(w->p));
            (void)fclose(fp);
            pcap_close(w->p);
            free(w);
            return NULL;
        }
    }
    w->ip_id = 1U;
    return w;
}

int c4gh_pcap_write_udp(c4gh_pcap_t *w, const struct timespec *ts, uint32_t src_ip,
                       uint16_t src_port, uint32_t dst_ip, uint16_t dst_port,
                       const uint8_t *payload, size_t len)
{
    static const uint8_t mac_src[6] = {0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
    static const uint8_t mac_dst[6] = {0x02, 0x00, 0x00, 0x00, 0x00, 0x02};
    struct pcap_pkthdr h;
    struct timespec now;
    uint8_t *f;
    uint8_t *ip;
    uint8_t *udp;
    uint32_t sum;
    uint8_t pseudo[12];
    uint16_t uc;

    if (w == NULL || (payload == NULL && len > 0U) || len > MAX_PAYLOAD) {
        return -1;
    }
    if (ts == NULL) {
        clock_gettime(CLOCK_REALTIME, &now);
        ts = &now;
    }
    f = w->frame;
    /* Ethernet II: locally administered MACs, type IPv4. */
    memcpy(f, mac_dst, 6);
    memcpy(&f[6], mac_src, 6);
    put16(&f[12], 0x0800U);
    /* IPv4, no options, don't fragment, TTL 64, protocol UDP. */
    ip = &f[ETH_LEN];
    ip[0] = 0x45U;
    ip[1] = 0U;
    put16(&ip[2], (uint32_t)(IP_LEN + UDP_LEN + len));
    put16(&ip[4], w->ip_id);
    w->ip_id = (uint16_t)(w->ip_id + 1U);
    put16(&ip[6], 0x4000U);
    ip[8] = 64U;
    ip[9] = 17U;
    put16(&ip[10], 0U);
    put32(&ip[12], src_ip);
    put32(&ip[16], dst_ip);
    put16(&ip[10], csum_fold(csum_add(0U, ip, IP_LEN)));
    /* UDP with checksum over the pseudo header. */
    udp = &ip[IP_LEN];
    put16(&udp[0], src_port);
    put16(&udp[2], dst_port);
    put16(&udp[4], (uint32_t)(UDP_LEN + len));
    put16(&udp[6], 0U);
    if (len > 0U) {
        memcpy(&udp[UDP_LEN], payload, len);
    }
    put32(pseudo, src_ip);
    put32(&pseudo[4], dst_ip);
    pseudo[8] = 0U;
    pseudo[9] = 17U;
    put16(&pseudo[10], (uint32_t)(UDP_LEN + len));
    sum = csum_add(0U, pseudo, sizeof pseudo);
    sum = csum_add(sum, udp, UDP_LEN + len);
    uc = csum_fold(sum);
    put16(&udp[6], (uc == 0U) ? 0xFFFFU : uc);

    memset(&h, 0, sizeof h);
    h.ts.tv_sec = ts->tv_sec;
    h.ts.tv_usec = (suseconds_t)(ts->tv_nsec / 1000L);
    h.caplen = (bpf_u_int32)(HDR_LEN + len);
    h.len = h.caplen;
    pcap_dump((u_char *)w->d, &h, f);
    w->frames++;
    return 0;
}

unsigned long c4gh_pcap_frames(const c4gh_pcap_t *w)
{
    return (w != NULL) ? w->frames : 0UL;
}

int c4gh_pcap_close(c4gh_pcap_t *w)
{
    int rc = 0;
    if (w == NULL) {
        return 0;
    }
    if (pcap_dump_flush(w->d) != 0) {
        rc = -1;
    }
    pcap_dump_close(w->d);
    pcap_close(w->p);
    if (w->failed) {
        rc = -1;
    }
    free(w);
    return rc;
}
