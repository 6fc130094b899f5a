/* SPDX-License-Identifier: MIT */
/* c4g-server internals: configuration, per-arm behaviours, safety filter, statistics. */
#ifndef C4G_SRV_H
#define C4G_SRV_H

#include "c4gopen.h"
#include "c4g_rtlog.h"

#include <netinet/in.h>
#include <stdint.h>
#include <stdio.h>

#define SRV_MAX_TRAJ_ROWS 20000U  /* trajectory file rows (static storage) */
#define SRV_MAX_TRAJ_BYTES (8U << 20) /* file size caps: a bigger file (or /dev/zero) is refused */
#define SRV_MAX_FF_BYTES (1U << 20)
#define SRV_HIST_US 20000U        /* cycle-time histogram: 1 us bins up to 20 ms */

/* Exit codes (documented in --help and docs/c4g-server.md). */
enum {
    EXIT_END = 0,        /* 504: communication ended by the controller */
    EXIT_USAGE = 1,      /* bad option, INI, trajectory or parameter file */
    EXIT_SETUP = 2,      /* socket/bind/thread failure, or a --rt-strict RT refusal */
    EXIT_LOST = 3,       /* controller silent longer than the loss timeout */
    EXIT_TIMEOUT = 4,    /* --idle-timeout or --max-seconds reached */
    EXIT_SIGNAL = 5      /* SIGINT / SIGTERM */
};

/* Log record kinds carried by the rtlog ring. */
enum { LOG_TEXT = 1, LOG_PCAP_RX = 2, LOG_PCAP_TX = 3, LOG_MONI = 4 };

/* Trajectory source for modes 1, 4, 5. */
enum { SRC_NONE = 0, SRC_SINE = 1, SRC_FILE = 2 };

/* Per-axis mode-9 feedforward parameters (see fixtures/server/ff_example.txt). */
typedef struct srv_ff {
    int set;                /* 0, or the line of the parameter file that set it */
    double c0, cv, cc, ca, gs, gscale, gphase;
} srv_ff_t;

/* Per-arm behaviour configuration. Times in seconds, positions in motor turns,
 * velocities in delta motor turns per tick, currents in A. */
typedef struct srv_arm_cfg {
    uint32_t axes;          /* logical axes driven (bit 0 = axis 1); default all */
    int src;                /* SRC_SINE or SRC_FILE (modes 1, 4, 5) */
    double sine_amp;        /* raised-cosine amplitude [turns] */
    double sine_freq;       /* [Hz] */
    double sine_cycles;     /* cycles before exit from open */
    char traj_path[512];
    double offset_amp;      /* mode 7 offset step [turns] */
    double offset_ramp;     /* mode 7 ramp time [s] */
    double offset_hold;     /* mode 7 hold time before exit [s] */
    double vel_amp;         /* mode 8 velocity delta amplitude [delta turns/tick] */
    double vel_freq;        /* mode 8 [Hz] */
    double vel_cycles;      /* mode 8 full cycles (zero mean) */
    char ff_path[512];      /* mode 9 parameter file */
    double duration;        /* modes 1 (with no trajectory), 2, 9: time before exit [s] */
    double kp, kd, ki;      /* modes 1, 2: PD(+I) gains [A/turn], [A/(turn/tick)], [A/(turn s)] */
    double i_max;           /* integrator limit [A] (anti-windup); 0 = AzLim */
    double scs;             /* soft control switching ramp time [s] (mode 1/2 entry) */
    int exit_open;          /* send EXIT_FROM_OPEN when the behaviour is done */
    double max_step;        /* continuity limit on PC position refs [turns/tick]; 0 = off */
    double pos_min[C4G_AXES_PER_ARM], pos_max[C4G_AXES_PER_ARM]; /* stroke ends */
    int have_stroke;
    double fe_limit;        /* following-error limit override [turns]; 0 = init packet */
} srv_arm_cfg_t;

/* A loaded trajectory file: t[s] plus up to 10 offset columns (logical axes). */
typedef struct srv_traj {
    uint32_t rows, cols;
    double t[SRV_MAX_TRAJ_ROWS];
    float q[SRV_MAX_TRAJ_ROWS][C4G_AXES_PER_ARM];
} srv_traj_t;

/* Per OPEN-index axis runtime state (behaviours + safety). */
typedef struct srv_axis {
    int32_t mode;           /* mode seen on the previous packet, -1 none */
    uint32_t ticks;         /* packets in the current mode */
    double start;           /* reference at mode entry */
    double q_prev;          /* previous generator offset */
    double ref_prev;        /* previous absolute PC position reference */
    int have_ref_prev;
    double integ;           /* integrator state [A] */
    double v_prev;          /* previous target velocity (mode 9 acceleration) */
    int done;               /* behaviour finished (exit from open requested) */
} srv_axis_t;

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
    uint64_t encode_errors;
    uint64_t drive_on_end;      /* 501 -> other transitions (drive-on finished) */
    uint64_t restarts;          /* 506 seen */
    uint64_t inits;
    uint64_t exits_sent[C4G_ARMS]; /* packets carrying EXIT_FROM_OPEN per arm */
    uint64_t freezes;           /* active freezings done */
    uint64_t frozen_passive;    /* 502 seen */
    uint64_t long_gaps;         /* a packet came after more than the loss timeout */
    uint64_t mode_changes;
    uint32_t hist[SRV_HIST_US + 1U]; /* cycle time histogram (1 us bins, last = overflow) */
    uint64_t hist_n;
    int64_t cycle_max_ns;
    double cycle_sum_us;
} srv_stats_t;

typedef struct srv_config {
    char bind_addr[64];
    unsigned port;
    char ctrl_addr[64];         /* "any" or an IPv4 address */
    c4g_num_policy_t num_policy;
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
    srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM];
} srv_config_t;

/* The whole server state (static storage; nothing allocated after start-up). */
typedef struct srv {
    srv_config_t cfg;
    c4g_session_t session;
    c4g_counters_t done;          /* counters of the sessions --persist ended by 504 */
    srv_axis_t ax[C4G_MAX_AXES];
    srv_safety_t safety;
    srv_stats_t stats;
    uint32_t arm_busy[C4G_ARMS];  /* arm has an axis in an open mode with a behaviour */
    c4g_engine_t ctl;                /* library control layer: state machines, rules, safety */
    c4g_engine_config_t engine_cfg;
    int ctl_ok;                   /* ctl initialised from the current init packet */
    uint64_t cyc_k;               /* cyclic packet number (session counter) being answered */
    int thaw;                     /* active freezing over: request EXIT_FROM_OPEN */
    c4g_rtlog_t log;
    FILE *log_fp, *moni_fp;
    struct c4g_pcap *pcap;        /* tools/common/c4g_pcap writer (log thread only) */
    uint64_t pcap_errors;
    struct sockaddr_in ctrl;      /* controller filter (sin_addr.s_addr 0 = any) */
    uint16_t local_port;
    uint64_t t0_ns;
} srv_t;

extern srv_traj_t srv_traj[C4G_ARMS];

/* behave.c */
void srv_behave_reset(srv_t *S);
void srv_behave_init(srv_t *S, uint64_t t_ns);
int srv_reply(srv_t *S, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx, uint64_t t_ns);

struct tf_file;

/* opts.c: one option table for the command line and the INI file */
void srv_config_default(srv_config_t *c);
int srv_config_apply(srv_config_t *c, const char *name, const char *val, int arm, char *err,
                     size_t errlen);
/* INI file (at most 1 MiB): 0, or -1 with "PATH:LINE:COL: ..." in err */
int srv_config_load_ini(srv_config_t *c, const char *path, char *err, size_t errlen);
int srv_config_parse_ini(srv_config_t *c, struct tf_file *f, char *err, size_t errlen);

/* files.c: "PATH:LINE:COL: ..." in err on an error */
int srv_load_traj(const char *path, srv_traj_t *tr, char *err, size_t errlen);
int srv_load_ff(const char *path, srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err,
                size_t errlen);
/* the same over a file already in memory (tools/common/c4g_textfile.h) */
int srv_parse_traj(struct tf_file *f, srv_traj_t *tr, char *err, size_t errlen);
int srv_parse_ff(struct tf_file *f, srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM], char *err,
                 size_t errlen);

/* report.c */
void srv_counters_add(c4g_counters_t *sum, const c4g_counters_t *c);

/* rt.c */
int srv_rt_setup(const srv_config_t *cfg, FILE *msg);

/* logging helper (ring, RT-safe) */
void srv_log(srv_t *S, uint64_t t_ns, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#endif
