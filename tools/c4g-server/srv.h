/* SPDX-License-Identifier: MIT */
/* c4g-server's I/O around the server core (tools/c4g-server/srv_core.h): the socket's address
 * filter, the log ring and its writer thread's outputs (text log, pcap, moni), exit codes. */
#ifndef SRV_IO_H
#define SRV_IO_H

#include "srv_core.h"
#include "c4gh_rtlog.h"

#include <netinet/in.h>
#include <stdint.h>
#include <stdio.h>

/* Exit codes (documented in --help and docs/c4g-server.md). */
enum {
    EXIT_END = 0,        /* 504: communication ended by the controller */
    EXIT_SETUP = 1,      /* socket/bind/thread/output file failure, or a --rt-strict RT refusal */
    EXIT_USAGE = 2,      /* bad option, INI, trajectory or parameter file */
    EXIT_LOST = 3,       /* controller silent longer than the loss timeout */
    EXIT_TIMEOUT = 4,    /* --idle-timeout or --max-seconds reached */
    EXIT_SIGNAL = 5      /* SIGINT / SIGTERM */
};

/* Log record kinds carried by the rtlog ring. */
enum { LOG_TEXT = 1, LOG_PCAP_RX = 2, LOG_PCAP_TX = 3, LOG_MONI = 4 };

/* The server: its core and the I/O the core never does. */
typedef struct srv_host {
    srv_t s;                      /* the per-datagram core */
    c4gh_rtlog_t log;              /* RT-safe ring to the writer thread */
    FILE *log_fp, *moni_fp;
    struct c4g_pcap *pcap;        /* lib/host/c4gh_pcap writer (log thread only) */
    uint64_t pcap_errors;
    struct sockaddr_in ctrl;      /* controller filter (sin_addr.s_addr 0 = any) */
    int connected;                /* the socket is connect()ed to conn_peer (kernel filter) */
    c4g_endpoint_t conn_peer;
    uint16_t local_port;
    /* --pcap: the kernel's receive and send times of each datagram (SO_TIMESTAMPING), so
     * the capture shows when a datagram was on the wire, not when the server got to it */
    int kstamp;
    uint64_t kstamp_off;          /* CLOCK_REALTIME - CLOCK_MONOTONIC */
    uint32_t tx_key;              /* the kernel's id of the next send stamp */
} srv_host_t;

/* report.c */
void srv_report(srv_host_t *H, FILE *out, const char *why, int code);
int srv_json(srv_host_t *H, const char *path, const char *why, int code);
void srv_sink(void *ctx, const c4gh_rtlog_rec_t *rec);
int srv_outputs_open(srv_host_t *H);
void srv_outputs_close(srv_host_t *H);

/* rt.c */
int srv_rt_setup(const srv_config_t *cfg, FILE *msg);

#endif
