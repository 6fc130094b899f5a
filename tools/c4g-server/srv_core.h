/* SPDX-License-Identifier: MIT */
/* The PC-side server core: configuration, per-arm behaviours, statistics and the
 * per-datagram step (srv_process) that c4g-server runs on every received datagram, from
 * its socket or a capture (--capture). No sockets, no clock, no stdio on that path: the
 * caller gives each datagram its reception time, sends what the verdict says, and
 * receives log lines through its own logger (NULL: none). Same packets with the same
 * timestamps from a fresh srv_t give the same replies. */
#ifndef C4G_SRV_H
#define C4G_SRV_H

#include "c4gopen.h"
#include "c4gh_cli.h"
#include "c4gh_hist.h"
#include "controllers.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define SRV_MAX_TRAJ_ROWS CTLR_MAX_TRAJ_ROWS /* trajectory file rows (static storage) */
#define SRV_MAX_TRAJ_BYTES (8U << 20) /* file size caps: a bigger file (or /dev/zero) is refused */
#define SRV_MAX_FF_BYTES (1U << 20)
#define SRV_MAX_FF_FILES 4U       /* --ff files: one identified model per arm */

/* The controllers' types (tools/c4g-server/controllers.h) under the server's names. */
#define SRC_NONE CTLR_SRC_NONE
#define SRC_SINE CTLR_SRC_SINE
#define SRC_FILE CTLR_SRC_FILE
typedef ctlr_ff_t srv_ff_t;
typedef ctlr_arm_cfg_t srv_arm_cfg_t;
typedef ctlr_traj_t srv_traj_t;

/* Safety events and counters (reported at exit). */
typedef struct srv_safety {
    uint64_t follow_error;      /* 508 replies */
    uint64_t drive_off;         /* 505 replies */
    uint64_t cur_saturated;     /* |D5| clamped to AzLim (modes 1, 2) */
    uint64_t delta_clamped;     /* mode 9 delta clamped to AzLim */
    uint64_t stroke;            /* stroke-end violations */
    uint64_t continuity;        /* reference step violations */
    uint64_t nonfinite;         /* NaN/inf produced by a behaviour */
    uint64_t injected;          /* --inject requests */
    char first[256];            /* first safety event, human-readable */
} srv_safety_t;

typedef struct srv_stats {
    uint64_t foreign;           /* datagrams from another source address: dropped */
    uint64_t oversize;          /* datagrams larger than the receive buffer */
    uint64_t send_errors;
    uint64_t skipped;           /* replies deliberately not sent (--skip-replies) */
    uint64_t late;              /* replies later than --late-us after reception */
    uint64_t neutral_replies;   /* cyclic replies answered by the loop's fallback (every axis
                                   holds, 505 where the PC moves an axis): the filter could
                                   not run on the reply, whatever the reason */
    uint64_t encode_errors;     /* of those, replies the encoder refused (NaN, unknown mode) */
    uint64_t drive_on_end;      /* 501 -> other transitions (drive-on finished) */
    uint64_t restarts;          /* 506 seen */
    uint64_t inits;
    uint64_t exits_sent[C4G_ARMS]; /* packets carrying EXIT_FROM_OPEN per arm */
    uint64_t freezes;           /* active freezings done */
    uint64_t frozen_passive;    /* 502 seen */
    uint64_t long_gaps;         /* a packet came after more than the loss timeout */
    uint64_t mode_changes;
    uint64_t ff_model_ticks;    /* mode-9 axis ticks whose current came from an identified model */
    uint64_t ff_model_clamped;  /* of those, ticks with v or a clamped to the model's range */
    c4gh_hist_t cycle;           /* cycle time: controller packet received -> reply sent */
} srv_stats_t;

/* c4g-server --capture (capture.c): the core run over a recorded capture instead of the
 * socket, every reply compared with the recorded one. */
#define SRV_CAPTURE_MAX_PORTS 16U    /* C4GH_AN_MAX_PORTS (capture.c checks) */
#define SRV_CAPTURE_MAX_SESSIONS 64U /* C4GH_AN_MAX_SESSIONS (capture.c checks) */
typedef struct srv_capture_opts {
    char path[4096];            /* "": the socket (PATH_MAX: any path rerun was given) */
    unsigned session;           /* 0: every session of the first controller */
    char ports[128];            /* PC ports of C4G Open flows in it, as given; "": 1000,1001 */
    double tolerance;           /* float fields within it are equal; 0: bit-exact */
    unsigned list;              /* divergences printed one per line */
    int echo;                   /* --behaviour echo: no axis driven */
    int no_progress;
    int rerun;                  /* --replay-rerun: messages as c4g-replay rerun (its front end) */
} srv_capture_opts_t;

typedef struct srv_config {
    char bind_addr[64];
    unsigned port;
    char ctrl_addr[64];         /* "any" or an IPv4 address */
    c4g_num_policy_t num_policy;
    double az_lim_max;          /* the largest AzLim accepted from an init packet [A] */
    double fe_max;              /* the largest FollowError accepted [motor turns] */
    uint64_t lost_timeout_ns;   /* 0: 10 periods */
    double idle_timeout;        /* s without any packet before the first one; 0 = forever */
    double max_seconds;         /* total run bound; 0 = none */
    int persist;                /* keep serving after 504 / loss */
    /* real time */
    int mlock;
    int prio;                   /* SCHED_FIFO priority, 0 = off */
    int cpu;                    /* CPU affinity, -1 = off */
    int rt_strict;              /* a refused RT setting is fatal */
    int spin;                   /* busy-poll the socket */
    unsigned poll_us;           /* >0: non-blocking recv + clock_nanosleep every poll_us */
    unsigned late_us;           /* reply deadline for the "late" counter (500) */
    /* outputs */
    char pcap_path[512];
    char moni_path[512];
    int moni_type;              /* 19..24, 0 = full rx/tx rows */
    char json_path[512];
    char log_path[512];
    int verbose, quiet;
    /* test hooks */
    uint64_t skip_at, skip_count;   /* don't answer cyclic packets skip_at .. +count-1 */
    uint64_t inject_at;             /* cyclic packet number to inject inject_mode at */
    int inject_mode;                /* 505 or 508 */
    int inject_axis;                /* OPEN index for 508 (0-based) */
    uint64_t freeze_at;             /* active freezing: cyclic packet number */
    double freeze_ms;               /* pause length */
    srv_arm_cfg_t arm[C4G_ARMS];
    char ff_path[SRV_MAX_FF_FILES][512]; /* mode-9 parameter files (--ff), in order */
    unsigned n_ff;
    srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM]; /* what they set (srv_load_files) */
    c4gh_ffm_file_t rigid[C4G_ARMS];  /* an arm's model = rigid-body-1 file (rigid[a].rigid) */
    unsigned rigid_file[C4G_ARMS];    /* its index in ff_path */
    srv_capture_opts_t cap;
} srv_config_t;

/* A log line: printf format and arguments, timed with the datagram's reception time. */
typedef void (*srv_log_fn)(void *ctx, uint64_t t_ns, const char *fmt, va_list ap);

/* The server's state (static storage in the tools: large; nothing allocated). */
typedef struct srv {
    srv_config_t cfg;
    c4g_loop_config_t loop_cfg;   /* the loop's configuration (a new session after 504) */
    c4g_loop_t loop;              /* library loop: session + control engine + reply path */
    c4g_counters_t done;          /* counters of the sessions --persist ended by 504 */
    ctlr_axis_t ax[C4G_MAX_AXES]; /* controller state per OPEN index */
    srv_safety_t safety;
    srv_stats_t stats;
    uint64_t cyc_k;               /* cyclic packet number (session counter) being answered */
    int thaw;                     /* this reply ends active freezing: request EXIT_FROM_OPEN */
    int thaw_due;                 /* active freezing paused: the next cyclic reply ends it */
    int restart_due;              /* 504 with --persist: a new session once the reply is out */
    c4g_rx_kind_t last_kind;      /* the last datagram srv_process handled, for srv_sent */
    uint64_t last_rx_ns;
    uint64_t t0_ns;               /* the run's start: safety events are timed from it */
    srv_log_fn log_fn;
    void *log_ctx;
    /* mode 9 with a rigid-body file: per arm, built at the init packet */
    c4gh_ffr_t ffr[C4G_ARMS];
    int ffr_ok[C4G_ARMS];         /* 1 ready, -1 the transmission refused it, 0 no file */
    unsigned ffr_logged[C4G_MAX_AXES]; /* C4GH_FFR_* clamps logged this session, 8: failure */
} srv_t;

/* Why the run stops after a datagram (the caller's exit code). */
typedef enum srv_stop {
    SRV_STOP_NONE = 0,
    SRV_STOP_END,                 /* 504 without --persist (after the reply is sent) */
    SRV_STOP_LOST                 /* the controller was lost, without --persist */
} srv_stop_t;

/* What srv_process decided about one datagram. */
typedef struct srv_verdict {
    c4g_rx_kind_t kind;           /* the session's class; C4G_RX_DROPPED: refused */
    uint32_t events;              /* C4G_EV_* of the session */
    bool send;                    /* out[0 .. *out_len) is the reply: send it now */
    bool skipped;                 /* a cyclic reply --skip-replies held back */
    bool ended;                   /* 504: the session ended (--persist: a new one starts
                                     at srv_sent or the next call) */
    srv_stop_t stop;              /* the run ends here, after the send */
    bool freeze;                  /* active freezing: pause pause_ms after the send, then
                                     answer only the newest datagram queued meanwhile */
    double pause_ms;
    const c4g_ctrl_packet_t *pkt; /* the cyclic packet answered (moni rows; with srv_reply_packet(),
                                     valid until srv_sent or the next call), else NULL */
} srv_verdict_t;

/* the arms' trajectories (c4g_srv_files.c fills them, the behaviours read them) */
extern srv_traj_t srv_traj[C4G_ARMS];

/* c4g_srv.c: the per-datagram core */
/* A fresh server on @p cfg (not S->cfg itself): the loop, the controllers, zero counters.
 * C4G_OK, or the loop's refusal of the configuration. */
C4G_NODISCARD c4g_status_t srv_init(srv_t *S, const srv_config_t *cfg, srv_log_fn log_fn,
                                    void *log_ctx);
/* One datagram of the controller's address received at @p t_rx_ns: trust checks, session
 * events, behaviours, the reply (into @p out, at most @p cap bytes) and the counters.
 * C4G_OK with the verdict filled, or the loop's error (nothing to do). */
C4G_NODISCARD c4g_status_t srv_process(srv_t *S, const uint8_t *in, size_t len,
                                       const c4g_endpoint_t *from, uint64_t t_rx_ns,
                                       uint8_t *out, size_t cap, size_t *out_len,
                                       srv_verdict_t *v);
/* The reply of the last srv_process was sent at @p t_ns: the loop's send time, the cycle
 * time statistics (cyclic replies). */
void srv_sent(srv_t *S, uint64_t t_ns);
/* No datagram for a while at @p t_ns: silence and loss of the controller. */
srv_stop_t srv_idle(srv_t *S, uint64_t t_ns);
/* A datagram dropped unanswered (another endpoint's, queued during active freezing):
 * the session counts it as foreign. */
void srv_drop(srv_t *S, const uint8_t *in, size_t len, const c4g_endpoint_t *from,
              uint64_t t_ns);
/* The loop's read accessors under short names (the library's c4g_loop_* queries cannot
 * fail on a loop the core owns). */
static inline const c4g_axis_map_t *srv_map(const srv_t *S)
{
    const c4g_axis_map_t *m = NULL;
    (void)c4g_loop_axis_map(&S->loop, &m);
    return m;
}
static inline const c4g_init_t *srv_init_packet(const srv_t *S)
{
    const c4g_init_t *p = NULL;
    (void)c4g_loop_init_packet(&S->loop, &p);
    return p;
}
static inline const c4g_counters_t *srv_counters(const srv_t *S)
{
    const c4g_counters_t *c = NULL;
    (void)c4g_loop_counters(&S->loop, &c, NULL);
    return c;
}
static inline const c4g_loop_counters_t *srv_loop_counters(const srv_t *S)
{
    const c4g_loop_counters_t *c = NULL;
    (void)c4g_loop_counters(&S->loop, NULL, &c);
    return c;
}
static inline c4g_loop_state_t srv_state(const srv_t *S)
{
    c4g_loop_state_t st;
    (void)c4g_loop_state(&S->loop, &st);
    return st;
}
static inline const c4g_pc_packet_t *srv_reply_packet(const srv_t *S)
{
    const c4g_pc_packet_t *tx = NULL;
    (void)c4g_loop_reply_packet(&S->loop, &tx);
    return tx;
}
static inline c4g_engine_t *srv_engine(srv_t *S)
{
    c4g_engine_t *e = NULL;
    (void)c4g_loop_engine(&S->loop, &e);
    return e;
}
static inline const c4g_engine_t *srv_engine_view(const srv_t *S)
{
    const c4g_engine_t *e = NULL;
    (void)c4g_loop_engine_view(&S->loop, &e);
    return e;
}
/* The next instant srv_idle has work (C4G_NO_DEADLINE: only a datagram). */
uint64_t srv_deadline(const srv_t *S);
/* Counters of one more session added to @p sum (the longest silence is the longest). */
void srv_counters_add(c4g_counters_t *sum, const c4g_counters_t *c);
/* A log line through the caller's logger. */
void srv_log(srv_t *S, uint64_t t_ns, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* c4g_srv_behave.c: the controllers (tools/c4g-server/controllers.h) on the loop's
 * control engine */
void srv_behave_reset(srv_t *S);
/* after an accepted init packet: the control engine's user limits */
void srv_behave_init(srv_t *S, uint64_t t_ns);
/* a cyclic packet with a prepared reply (ev->cmd): fill it, post the requests */
void srv_behave(srv_t *S, const c4g_loop_event_t *ev, uint64_t t_ns);
/* after c4g_loop_reply: the finish status, exits sent, the filter's safety events */
void srv_behave_done(srv_t *S, const c4g_engine_report_t *rep, uint64_t t_ns);

struct c4gh_tf_file;

/* c4g_srv_opts.c: one option table for the command line and the INI file */
void srv_config_default(srv_config_t *c);
int srv_config_apply(srv_config_t *c, const char *name, const char *val, int arm, char *err,
                     size_t errlen);
/* Which rows a command line takes: all of them (c4g-server), the server's without the
 * capture's (what c4g-replay rerun takes after "--"), or the capture's and --json only (what
 * c4g-replay rerun asks of c4g-server --replay-rerun). */
typedef enum srv_cli_rows { SRV_CLI_ALL = 0, SRV_CLI_SERVER, SRV_CLI_CAPTURE } srv_cli_rows_t;
/* the command line (lib/host/c4gh_cli.h): C4GH_CLI_RUN, C4GH_CLI_DONE (--help, --version) or
 * C4GH_CLI_BAD (the error is on stderr); @p tool names the program in messages (c4g-replay
 * rerun takes c4g-server's options too) */
c4gh_cli_result_t srv_config_cli(srv_config_t *c, const char *tool, const char *version_extra,
                                 srv_cli_rows_t which, int argc, char **argv);
/* INI file (at most 1 MiB): 0, or -1 with "PATH:LINE:COL: ..." in err */
int srv_config_load_ini(srv_config_t *c, const char *path, char *err, size_t errlen);
int srv_config_parse_ini(srv_config_t *c, struct c4gh_tf_file *f, char *err, size_t errlen);

/* c4g_srv_files.c: "PATH:LINE:COL: ..." in err on an error */
int srv_load_traj(const char *path, srv_traj_t *tr, char *err, size_t errlen);
int srv_load_ff(const char *path, srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err,
                size_t errlen);
/* the same over a file already in memory (lib/host/c4gh_textfile.h) */
int srv_parse_traj(struct c4gh_tf_file *f, srv_traj_t *tr, char *err, size_t errlen);
int srv_parse_ff(struct c4gh_tf_file *f, srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err,
                 size_t errlen);
/* A mode-9 parameter file of either format, told apart by its first line that is not
 * blank or a comment: '[' starts c4g-ident's INI (c4g_ffmodel.h), anything else is the
 * line format. Sets the axes it names in ff (file index @p file); an axis another file
 * already set is an error naming both; a rigid-body file (model = rigid-body-1) also fills
 * rigid[arm] (NULL: such a file is refused). 0, or -1 with the error in err. */
int srv_load_ff_any(const char *path, unsigned file, const char *const *paths,
                    srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], c4gh_ffm_file_t rigid[C4G_ARMS],
                    char *err, size_t errlen);
/* 1 when the text is c4g-ident's INI format (see srv_load_ff_any) */
int srv_ff_is_ini(const char *text, size_t len);
/* every file the configuration names: trajectories into srv_traj, feedforward into
 * cfg->ff; 0, or -1 with "trajectory: ..." / "feedforward: ..." in err */
int srv_load_files(srv_config_t *cfg, char *err, size_t errlen);

#endif
