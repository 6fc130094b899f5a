/* SPDX-License-Identifier: MIT */
/* c4g-sim the process: the controller model (sim.h) and the controller side of the
 * protocol (the library's controller end, c4gopen_ctrl.h) wired to a socket, a clock, fault injection and output files.
 * options.c: command line; net.c: socket and timestamps; faults.c: fault injection;
 * run.c: the tick loop; report.c: summary and CSV; main.c: the steps in order. */
#ifndef SIM_APP_H
#define SIM_APP_H

#include <netinet/in.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>

#include "c4gh_analyze.h"
#include "c4gh_hist.h"
#include "c4gopen.h"
#include "c4gh_pcap.h"
#include "sim.h"

/* Exit codes (docs/c4g-sim.md): 0, 1 and 2 are the shared ones of c4g_cli.h. */
#define EXIT_OK 0
#define EXIT_RUNTIME 1
#define EXIT_USAGE 2
#define EXIT_EXPECT 3
#define EXIT_OUTPUT 4
#define EXIT_NO_ANSWER 5 /* --capture: nothing answered at the server's address */

#define MAX_PENDING 8
#define MAX_DGRAM 2048

enum fault { F_DROP = 0, F_DELAY, F_DUP, F_REORDER, F_CORRUPT, F_TRUNCATE, F_COUNT };
extern const char *const fault_names[F_COUNT];

typedef struct pending {
    int used;
    uint64_t due_ns;
    size_t len;
    uint8_t buf[C4G_INIT_SIZE];
} pending_t;

/* The options of --capture (app_opts_t holds them while the command line is read). */
typedef struct cap_opts {
    const char *path;         /* --capture FILE */
    double speed;             /* 0: not given (1) */
    int topspeed;
    unsigned loops;           /* 0: not given (1) */
    unsigned gap_ms;
    unsigned session;         /* 0: the first with an init packet */
    double tolerance;
    unsigned spin_us;         /* CAP_SPIN_UNSET: not given (100) */
    uint16_t ports[C4GH_AN_MAX_PORTS]; /* --capture-ports; n_ports 0: 1000,1001 */
    unsigned n_ports;
    int as_replay_live;       /* --replay-live: messages and report as c4g-replay live */
} cap_opts_t;

#define CAP_SPIN_UNSET 0xFFFFFFFFU

/* What the command line asks for besides sim_config_t. */
typedef struct app_opts {
    const char *config_path;
    const char *scenario_path;
    const char *csv_path;
    const char *pcap_path;
    int quiet;
    int json;
    int verbose;
    double fault_frac[F_COUNT];
    unsigned delay_us;
    unsigned long pause_at, pause_len;
    int entry_fault; /* --entry-fault: 0 none, 1 drop, 2 truncate */
    int lockstep;    /* --lockstep: wait for each reply (not what a C4G does) */
    unsigned lockstep_wait_ms; /* --lockstep-wait: how long at most (default 500) */
    cap_opts_t cap;  /* --capture and its options */
} app_opts_t;

/* The simulator's own counters (the protocol's are in c4g_ctrl_t). */
typedef struct app_stats {
    unsigned long sent;
    unsigned long fault[F_COUNT];
    unsigned long paused_ticks;
    unsigned long overruns;
    uint64_t overrun_max;
    unsigned long lockstep_waits;  /* --lockstep: replies the next packet waited for */
    uint64_t lockstep_wait_max;    /* the longest such wait past the nominal tick [ns] */
} app_stats_t;

typedef struct app {
    app_opts_t o;
    sim_config_t cfg;
    sim_t sim;
    scn_t scn;
    c4g_ctrl_t cs;
    c4gh_hist_t lat;         /* reply latencies the controller end judged ok */
    int fd;
    struct sockaddr_in srv;
    struct sockaddr_in local;
    uint32_t local_ip;
    uint16_t local_port;
    FILE *csv;
    c4gh_pcap_t *pcap;
    int out_error;
    app_stats_t st;
    pending_t pend[MAX_PENDING];
    pending_t held;          /* reorder: sent after the next packet */
    int32_t sent_modes[C4G_MAX_AXES]; /* modes of the last cyclic packet sent */
    c4gsim_rng_t frng;
    int kstamp;              /* kernel send/receive timestamps (SO_TIMESTAMPING) are on */
    uint32_t tx_seq;         /* SO_TIMESTAMPING id of the next sendto */
    int has_key;             /* tx_key: SO_TIMESTAMPING id of the outstanding packet */
    uint32_t tx_key;
    uint64_t tol_ns;         /* own lateness beyond which a tick is an overrun */
    struct cap *cap;         /* --capture: the player (capture.h); NULL: the model plays */
    uint8_t rx_raw[C4G_INIT_SIZE]; /* the reply c4g_ctrl_reply accepted last, its bytes */
    size_t rx_len;
} app_t;

extern volatile sig_atomic_t g_stop;

uint64_t now_ns(void);

/* options.c: 0 to run; otherwise the exit code (help printed, or the error on stderr). */
int app_options(app_t *a, int argc, char **argv, int *done);
/* options.c: addresses, scenario and sim_init; 0 or EXIT_USAGE. */
int app_prepare(app_t *a);
/* options.c: the server's and the bind address into a->srv and a->local; 0 or EXIT_USAGE. */
int app_addresses(app_t *a);

/* net.c */
int net_open(app_t *a);
int raw_send(app_t *a, const uint8_t *buf, size_t len, uint32_t *key);
/* sendto the server, recorded in --pcap: the bytes sent, or -1 (errno kept). */
long net_sendto(app_t *a, const uint8_t *buf, size_t len, uint32_t *key);
void drain(app_t *a);
void window(app_t *a, uint64_t until);
/* Receive until the outstanding packet's reply came or @p until; 1 if it came. */
int wait_own_reply(app_t *a, uint64_t until);

/* faults.c */
int send_packet(app_t *a, const uint8_t *pkt, size_t len, uint32_t *key);

/* run.c */
void app_run(app_t *a);
void judge(app_t *a, uint64_t woke);
void handle_rx(app_t *a, const uint8_t *buf, size_t len, const struct sockaddr_in *from,
               uint64_t t);

/* report.c */
int outputs_open(app_t *a);
void outputs_close(app_t *a);
void csv_row(app_t *a, const c4g_ctrl_packet_t *p, const c4g_pc_packet_t *rep, int sent);
void summary(const app_t *a, int code, const char *result, double cpu_s);
/* 1 when no reply was ever accepted (no session started), @p why then says what was seen
 * of the PC at @p server:@p port; 0 otherwise. capture.c says the same of a played capture. */
int no_session(const c4g_ctrl_counters_t *n, const char *server, unsigned port, char *why,
               size_t cap);
double cpu_seconds(void);

#endif
