/* SPDX-License-Identifier: MIT */
/* CAN bus I/O of the tools: a bus log in candump's log format ("(sec.usec) iface ID#DATA",
 * readable by can-utils' canplayer/log2asc) and in pcap with the SocketCAN link type
 * (DLT_CAN_SOCKETCAN, for Wireshark's CANopen dissector), and a Linux SocketCAN raw socket
 * (interface by name). Frames carry their time in nanoseconds (t_ns); the logs write it,
 * in microseconds, as the wall-clock time of @p epoch_us + t_ns / 1000. */
#ifndef C4GH_CAN_H
#define C4GH_CAN_H

#include <stdio.h>
#include "c4gopen_canopen.h"

typedef struct c4gh_co_buslog {
    FILE *candump;          /* NULL: none */
    void *pcap;             /* pcap_t (libpcap), NULL: none */
    void *dumper;           /* pcap_dumper_t */
    char iface[16];
    uint64_t epoch_us;      /* wall-clock time [us] of t_ns == 0 */
    uint64_t frames;
} c4gh_co_buslog_t;

/* Opens the logs (either path may be NULL). Returns 0, or -1 with a message in err. */
int c4gh_co_buslog_open(c4gh_co_buslog_t *l, const char *candump_path, const char *pcap_path,
                       const char *iface, uint64_t epoch_us, char *err, size_t errlen);
/* One frame to every open log. */
void c4gh_co_buslog_write(c4gh_co_buslog_t *l, const c4g_co_frame_t *f);
/* A c4gsim_vbus log callback (ctx: the c4gh_co_buslog_t). */
void c4gh_co_buslog_cb(void *ctx, const c4g_co_frame_t *f);
void c4gh_co_buslog_close(c4gh_co_buslog_t *l);
/* One candump log line for a frame, without newline. */
void c4gh_co_candump_line(char *out, size_t cap, const char *iface, uint64_t wall_us,
                         const c4g_co_frame_t *f);

/* SocketCAN raw socket bound to @p ifname; returns the fd, or -1 with a message naming the
 * interface and the reason (no such device, no CAN support in the kernel, ...). */
int c4gh_co_socketcan_open(const char *ifname, char *err, size_t errlen);
/* Sends one frame; 0 or -1 (errno kept). */
int c4gh_co_socketcan_send(int fd, const c4g_co_frame_t *f);
/* Receives one frame if one is waiting (non-blocking): 1 got one, 0 none, -1 error.
 * Extended (29-bit) and error frames are skipped (return 0). */
int c4gh_co_socketcan_recv(int fd, c4g_co_frame_t *f, uint64_t t_ns);

#endif /* C4GH_CAN_H */
