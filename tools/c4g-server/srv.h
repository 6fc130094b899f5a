/* SPDX-License-Identifier: MIT */
/* c4g-server's host around the server core (tools/c4g-server/srv_core.h): the datagram
 * sources (the UDP socket, a capture) and the one loop that runs the core over either
 * (host.c: the controller-address filter, the drain after active freezing), the log ring and
 * its writer thread's outputs (text log, pcap, moni), exit codes. */
#ifndef SRV_IO_H
#define SRV_IO_H

#include "srv_core.h"
#include "c4gh_rtlog.h"

#include <netinet/in.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>

/* Exit codes (documented in --help and docs/c4g-server.md). */
enum {
    EXIT_END = 0,        /* 504: communication ended by the controller */
    EXIT_SETUP = 1,      /* socket/bind/thread/output file failure, or a --rt-strict RT refusal */
    EXIT_USAGE = 2,      /* bad option, INI, trajectory or parameter file */
    EXIT_LOST = 3,       /* controller silent longer than the loss timeout */
    EXIT_TIMEOUT = 4,    /* --idle-timeout or --max-seconds reached */
    EXIT_SIGNAL = 5      /* SIGINT / SIGTERM: main.c exits 130 / 0 (docs/cli.md) */
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
    volatile sig_atomic_t *stop;  /* set by a signal handler (NULL: none) */
    int ctrl_hinted;              /* "is that your controller?" was said */
    char ctrl_seen[24];           /* and the address:port it named */
} srv_host_t;

/* ---- datagram sources: the core does not know where its datagrams come from. The UDP
 * socket (main.c) and a capture (capture.c) give the host loop (srv_serve) the same things:
 * the next datagram with its reception time and source endpoint, a reply to send, and the
 * datagrams queued up to now (the drain after active freezing). */

enum { SRV_SRC_NONE = 0, SRV_SRC_HAVE = 1, SRV_SRC_END = 2 };

/* A datagram as a source gives it. */
typedef struct srv_dgram {
    uint8_t *buf;                 /* the loop's buffer (cap bytes): the source writes into it */
    size_t cap;
    size_t len;                   /* bytes in buf */
    size_t size;                  /* the datagram's size (above cap: cut, counted as oversize) */
    c4g_endpoint_t from;
    uint64_t t_rx;                /* its reception time, on the source's clock (ns) */
    uint64_t t_cap;               /* --pcap: the kernel's receive time, else t_rx */
    uint64_t ref;                 /* the source's own (a capture: which recorded packet) */
} srv_dgram_t;

typedef struct srv_source {
    void *ctx;
    /* the source's clock (ns): the monotonic clock, or a capture's recorded time */
    uint64_t (*now)(void *ctx);
    /* the next datagram, waiting until @p due at most: SRV_SRC_HAVE; SRV_SRC_NONE (the
     * deadline, a signal, a transient error); SRV_SRC_END (no datagram will come) */
    int (*next)(void *ctx, uint64_t due, srv_dgram_t *d);
    /* a datagram already queued by now, without waiting: SRV_SRC_HAVE or SRV_SRC_NONE */
    int (*queued)(void *ctx, srv_dgram_t *d);
    /* the core's answer to @p d: @p out (@p len bytes) to send, NULL when none goes out.
     * Returns the send time. */
    uint64_t (*reply)(void *ctx, const srv_dgram_t *d, const uint8_t *out, size_t len,
                      const srv_verdict_t *v);
    /* active freezing: read nothing for @p ms */
    void (*pause)(void *ctx, double ms);
    /* optional (NULL): @p d goes into the core; @p d is dropped unanswered (another address,
     * or queued during active freezing and not the newest); after each datagram or deadline */
    void (*accepted)(void *ctx, const srv_dgram_t *d);
    void (*dropped)(void *ctx, const srv_dgram_t *d);
    void (*after)(void *ctx);
} srv_source_t;

#define SRV_SOURCE_END (-3) /* srv_serve: the source has no more datagrams */

/* host.c: the endpoint of IPv4 address @p ip (host order) and @p port */
void srv_endpoint(uint32_t ip, uint16_t port, c4g_endpoint_t *e);
/* The controller-address filter (--controller): 1 when @p from is another address than
 * H->ctrl's (then counted and logged; @p buf, @p len: what came, for the wrong-address hint),
 * 0 when it passes (H->ctrl.sin_addr 0: every address passes). */
int srv_foreign(srv_host_t *H, const c4g_endpoint_t *from, const uint8_t *buf, size_t len,
                size_t size, uint64_t t);
/* Run the core over @p src until it stops: the exit code (EXIT_END, EXIT_LOST, EXIT_TIMEOUT,
 * EXIT_SIGNAL), or SRV_SOURCE_END. Per datagram: the address filter, after active freezing
 * the drain (only the newest of the controller's queued datagrams is answered), the core,
 * the reply, the pause; between datagrams the core's deadlines (silence, loss),
 * --idle-timeout and --max-seconds. */
int srv_serve(srv_host_t *H, const srv_source_t *src);

/* report.c */
void srv_report(srv_host_t *H, FILE *out, const char *why, int code);
int srv_json(srv_host_t *H, const char *path, const char *why, int code);
void srv_sink(void *ctx, const c4gh_rtlog_rec_t *rec);
int srv_outputs_open(srv_host_t *H);
void srv_outputs_close(srv_host_t *H);

/* rt.c */
int srv_rt_setup(const srv_config_t *cfg, FILE *msg);

#endif
