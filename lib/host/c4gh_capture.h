/* SPDX-License-Identifier: MIT */
/* Reading captures: pcap and pcapng files (micro- or nanosecond) through libpcap, one UDP
 * datagram at a time, with bounded memory whatever the file size. Link types: Ethernet
 * (with 802.1Q / 802.1ad tags), raw IPv4, Linux cooked SLL and SLL2, BSD loopback/null.
 * IPv4 only; IP and UDP lengths are checked against the bytes captured, and a fragment is
 * reported, never reassembled or guessed. Every problem names the file, the packet number
 * and the byte offset of its record. */
#ifndef C4GH_CAPTURE_H
#define C4GH_CAPTURE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct c4gh_cap c4gh_cap_t;

/* One UDP datagram of the capture. The payload points into the reader's buffer: valid
 * until the next c4gh_cap_next. */
typedef struct c4gh_cap_pkt {
    uint64_t frame;          /* 1-based packet number in the file */
    uint64_t offset;         /* byte offset of its record in the file */
    int64_t ts_ns;           /* capture time, ns since the epoch */
    uint32_t src_ip, dst_ip; /* host byte order */
    uint16_t src_port, dst_port;
    const uint8_t *payload;
    size_t len;              /* UDP length - 8 (every byte was captured) */
} c4gh_cap_pkt_t;

/* What c4gh_cap_next found. */
typedef enum c4gh_cap_res {
    C4GH_CAP_DATAGRAM = 0, /* *p is a UDP datagram */
    C4GH_CAP_IGNORED,      /* a frame that is not IPv4/UDP (ARP, IPv6, TCP, ...): counted */
    C4GH_CAP_BAD,          /* a damaged frame (message in err): counted, the next one follows */
    C4GH_CAP_END,          /* end of file */
    C4GH_CAP_FATAL         /* the file cannot be read on (message in err): stop here */
} c4gh_cap_res_t;

typedef struct c4gh_cap_counts {
    uint64_t frames;     /* records read */
    uint64_t udp;        /* UDP datagrams delivered */
    uint64_t ignored;    /* not IPv4/UDP */
    uint64_t bad;        /* damaged frames */
    uint64_t fragments;  /* IPv4 fragments (among bad) */
    uint64_t cut;        /* cut by the snapshot length (among bad) */
} c4gh_cap_counts_t;

/* Open @p path. NULL with "PATH: why" in err when it is not a readable capture. */
c4gh_cap_t *c4gh_cap_open(const char *path, char *err, size_t errlen);
/* The same over an open stream (fmemopen, a pipe that can seek); @p name is used in
 * messages. The stream is closed by c4gh_cap_close, or at once on failure. */
c4gh_cap_t *c4gh_cap_open_stream(FILE *fp, const char *name, char *err, size_t errlen);
/* The next frame; C4GH_CAP_BAD and C4GH_CAP_FATAL write "PATH: packet N (offset O): why" to err. */
c4gh_cap_res_t c4gh_cap_next(c4gh_cap_t *c, c4gh_cap_pkt_t *p, char *err, size_t errlen);
const c4gh_cap_counts_t *c4gh_cap_counts(const c4gh_cap_t *c);
/* Bytes read so far and the file's size (0 when unknown, e.g. a pipe): for progress. */
uint64_t c4gh_cap_pos(const c4gh_cap_t *c);
uint64_t c4gh_cap_size(const c4gh_cap_t *c);
/* "pcap" or "pcapng", and the link type's name ("EN10MB", "LINUX_SLL2", ...). */
const char *c4gh_cap_format(const c4gh_cap_t *c);
const char *c4gh_cap_link_name(const c4gh_cap_t *c);
/* 1 if the file stores nanosecond timestamps. */
int c4gh_cap_nanosecond(const c4gh_cap_t *c);
const char *c4gh_cap_path(const c4gh_cap_t *c);
void c4gh_cap_close(c4gh_cap_t *c);

/* "a.b.c.d" of a host-order address into buf (16 bytes). */
const char *c4gh_cap_ip_str(uint32_t ip, char buf[16]);

#endif
