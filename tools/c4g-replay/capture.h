/* SPDX-License-Identifier: MIT */
/* Reading captures: pcap and pcapng files (micro- or nanosecond) through libpcap, one UDP
 * datagram at a time, with bounded memory whatever the file size. Link types: Ethernet
 * (with 802.1Q / 802.1ad tags), raw IPv4, Linux cooked SLL and SLL2, BSD loopback/null.
 * IPv4 only; IP and UDP lengths are checked against the bytes captured, and a fragment is
 * reported, never reassembled or guessed. Every problem names the file, the packet number
 * and the byte offset of its record. */
#ifndef C4G_REPLAY_CAPTURE_H
#define C4G_REPLAY_CAPTURE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct cap cap_t;

/* One UDP datagram of the capture. The payload points into the reader's buffer: valid
 * until the next cap_next. */
typedef struct cap_pkt {
    uint64_t frame;          /* 1-based packet number in the file */
    uint64_t offset;         /* byte offset of its record in the file */
    int64_t ts_ns;           /* capture time, ns since the epoch */
    uint32_t src_ip, dst_ip; /* host byte order */
    uint16_t src_port, dst_port;
    const uint8_t *payload;
    size_t len;              /* UDP length - 8 (every byte was captured) */
} cap_pkt_t;

/* What cap_next found. */
typedef enum cap_res {
    CAP_DATAGRAM = 0, /* *p is a UDP datagram */
    CAP_IGNORED,      /* a frame that is not IPv4/UDP (ARP, IPv6, TCP, ...): counted */
    CAP_BAD,          /* a damaged frame (message in err): counted, the next one follows */
    CAP_END,          /* end of file */
    CAP_FATAL         /* the file cannot be read on (message in err): stop here */
} cap_res_t;

typedef struct cap_counts {
    uint64_t frames;     /* records read */
    uint64_t udp;        /* UDP datagrams delivered */
    uint64_t ignored;    /* not IPv4/UDP */
    uint64_t bad;        /* damaged frames */
    uint64_t fragments;  /* IPv4 fragments (among bad) */
    uint64_t cut;        /* cut by the snapshot length (among bad) */
} cap_counts_t;

/* Open @p path. NULL with "PATH: why" in err when it is not a readable capture. */
cap_t *cap_open(const char *path, char *err, size_t errlen);
/* The same over an open stream (fmemopen, a pipe that can seek); @p name is used in
 * messages. The stream is closed by cap_close, or at once on failure. */
cap_t *cap_open_stream(FILE *fp, const char *name, char *err, size_t errlen);
/* The next frame; CAP_BAD and CAP_FATAL write "PATH: packet N (offset O): why" to err. */
cap_res_t cap_next(cap_t *c, cap_pkt_t *p, char *err, size_t errlen);
const cap_counts_t *cap_counts(const cap_t *c);
/* Bytes read so far and the file's size (0 when unknown, e.g. a pipe): for progress. */
uint64_t cap_pos(const cap_t *c);
uint64_t cap_size(const cap_t *c);
/* "pcap" or "pcapng", and the link type's name ("EN10MB", "LINUX_SLL2", ...). */
const char *cap_format(const cap_t *c);
const char *cap_link_name(const cap_t *c);
/* 1 if the file stores nanosecond timestamps. */
int cap_nanosecond(const cap_t *c);
const char *cap_path(const cap_t *c);
void cap_close(cap_t *c);

/* "a.b.c.d" of a host-order address into buf (16 bytes). */
const char *cap_ip_str(uint32_t ip, char buf[16]);

#endif
