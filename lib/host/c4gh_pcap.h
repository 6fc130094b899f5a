/* SPDX-License-Identifier: MIT */
/* c4g_pcap: a small pcap writer for UDP/IPv4/Ethernet frames (tools only, uses libpcap).
 *
 * Every datagram is written as an Ethernet II + IPv4 + UDP frame (DLT_EN10MB) with a
 * correct IPv4 header checksum and UDP checksum, so Wireshark/tshark dissect it and
 * `tshark -r FILE -T fields -e udp.payload` prints exactly the payload bytes.
 *
 * Linking: libc4gopen-host is an archive; a tool that uses this writer links -lpcap
 * (NAME_LDLIBS += -lpcap in its tool.mk).
 */
#ifndef C4GH_PCAP_H
#define C4GH_PCAP_H

#include <stddef.h>
#include <stdint.h>
#include <time.h>
#include <pcap/pcap.h>

/** libpcap's version string (shown by the tools' --version). */
#define C4GH_PCAP_ANCHOR() pcap_lib_version()

typedef struct c4g_pcap c4gh_pcap_t;

/**
 * Create (truncate) @p path as a pcap file (Ethernet link type, snaplen 65535).
 * @return the writer, or NULL with a message in @p err (may be NULL).
 */
c4gh_pcap_t *c4gh_pcap_open(const char *path, char *err, size_t errlen);

/**
 * Append one UDP datagram as an Ethernet/IPv4/UDP frame.
 * @param ts       capture time (CLOCK_REALTIME); NULL = now
 * @param src_ip   IPv4 address in host byte order (e.g. 0x7F000001 for 127.0.0.1)
 * @param len      payload bytes, at most 65507
 * @return 0 on success, -1 on a bad argument or write error.
 */
int c4gh_pcap_write_udp(c4gh_pcap_t *w, const struct timespec *ts, uint32_t src_ip,
                       uint16_t src_port, uint32_t dst_ip, uint16_t dst_port,
                       const uint8_t *payload, size_t len);

/** Frames written so far. */
unsigned long c4gh_pcap_frames(const c4gh_pcap_t *w);

/** Flush and close; @p w may be NULL. @return 0, or -1 if a write failed at any time. */
int c4gh_pcap_close(c4gh_pcap_t *w);

#endif /* C4GH_PCAP_H */
