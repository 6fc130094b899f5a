/* SPDX-License-Identifier: MIT */
/* c4g-server --capture: the server run over a recorded capture instead of its socket. The
 * capture is a datagram source of the host loop (srv.h): the recorded controller packets of
 * one controller endpoint with their recorded reception times, at top speed; the same host
 * loop (address filter, drain after active freezing, deadlines) and core (srv_process) as on
 * the socket answer them, and every reply produced is compared word by word with the reply
 * recorded for the same packet, each word named by its field. capture.c runs it,
 * capture_report.c prints what came of it. c4g-replay rerun is a front end that runs this
 * (c4g-server --replay-rerun). */
#ifndef SRV_CAPTURE_H
#define SRV_CAPTURE_H

#include "srv.h"
#include "c4gh_analyze.h"

#include <stdio.h>

#define CAP_PENDING 8U   /* produced replies awaiting a late recorded one (packets) */
#define CAP_QUEUE 160U   /* the reading's items not yet taken (one frame, or the file's end) */
#define CAP_SYNTH 12U    /* a synthetic start-up: 9 sync, the init packet, 2 sync */
#define CAP_TAKEN 4U     /* datagrams handed to the host loop and not yet done with */
#define CAP_DGRAM 2048U  /* the host loop's receive buffer: larger datagrams are cut */

/* Fields a divergence is counted under: reply (sent on one side only), length, a word of a
 * sync reply or of the init echo, then the cyclic reply's words. */
#define CAP_FIELDS(X)       \
    X(REPLY, "reply")       \
    X(LENGTH, "length")     \
    X(SYNC, "sync")         \
    X(INIT, "init")         \
    X(NUM, "num")           \
    X(INFPAR, "infpar")     \
    X(CMD, "cmd")           \
    X(MODE, "mode")         \
    X(D1, "d1")             \
    X(D2, "d2")             \
    X(D3, "d3")             \
    X(D4, "d4")             \
    X(D5, "d5")             \
    X(EXT1, "ext1")         \
    X(EXT2, "ext2")         \
    X(EXT3, "ext3")

#define CAP_FIELD_ENUM(id, name) CAP_F_##id,
typedef enum srv_cap_field { CAP_FIELDS(CAP_FIELD_ENUM) CAP_F_COUNT } srv_cap_field_t;
#undef CAP_FIELD_ENUM

/* One divergence: where, which field, both values. */
typedef struct srv_cap_div {
    unsigned session;
    uint64_t tick;           /* the cyclic packet's number in its session (1 = the first) */
    int kind;                /* C4G_PKT_SYNC / C4G_PKT_INIT / C4G_PKT_CYCLIC */
    int32_t num;             /* the controller packet's NUM */
    uint64_t frame;          /* its frame in the capture */
    double t_s;              /* since the session's first packet */
    int open;                /* OPEN index 1..20, 0: not an axis field */
    int arm, logical;        /* 1-based, 0 unknown */
    unsigned word;           /* 32-bit word of the reply */
    srv_cap_field_t field;
    char recorded[40], produced[40];
} srv_cap_div_t;

typedef struct srv_cap_field_count {
    uint64_t count;
    srv_cap_div_t first;
} srv_cap_field_count_t;

typedef struct srv_cap_sess {
    unsigned id;
    c4gh_an_endpoint_t ctrl, pc;
    uint64_t fed[3];         /* sync, init, cyclic packets fed */
    uint64_t compared, divergent;
    uint64_t recorded_missing;  /* controller packets the recording has no reply to */
    uint64_t held_dropped;      /* packets the server drops after an active-freezing pause */
    uint64_t first_div_tick;
    int any_div;
    uint64_t timing_only;       /* recorded after the next packet, produced in time, equal */
    int primed;                 /* no start-up in the capture: a synthetic one was fed */
    unsigned primed_axes, primed_period_ms;
} srv_cap_sess_t;

/* A controller packet and the reply recorded to it, as the comparison needs them. */
typedef struct srv_cap_pkt {
    unsigned session;
    const c4gh_an_session_t *s;
    int kind;
    uint64_t tick;
    const uint8_t *ctrl;
    size_t ctrl_len;         /* as recorded (the bytes kept: at most CAP_DGRAM) */
    uint64_t ctrl_frame;
    int64_t ctrl_ns;
    const uint8_t *rec;      /* NULL: nothing recorded */
    size_t rec_len;
    int64_t rec_ns;
} srv_cap_pkt_t;

/* An item of the reading, in the order the analysis gave it: a controller packet with its
 * recorded reply, or a recorded reply that came after its packet's deadline (late). */
typedef struct srv_cap_item {
    int late;
    int synthetic;           /* a start-up packet made up for a session without one */
    int have_init;           /* the session had its init packet when the packet was read */
    int policy;              /* late: the NUM rule the reply is matched by */
    srv_cap_pkt_t p;         /* late: s, rec, rec_len */
    c4gh_an_endpoint_t from;
    int64_t next_ns;         /* the session's next controller packet (0: none) */
    uint8_t ctrl[CAP_DGRAM];
    uint8_t rec[C4G_INIT_SIZE];
} srv_cap_item_t;

/* A reply produced for a packet the recording shows no reply to by its deadline: judged
 * once the recorded reply turns up late (a timing difference, its content compared) or
 * CAP_PENDING packets later (a divergence: recorded none). */
typedef struct srv_cap_pending {
    int used;
    srv_cap_pkt_t p;
    uint8_t ctrl[CAP_DGRAM];
    uint8_t out[C4G_INIT_SIZE];
    size_t out_len;
} srv_cap_pending_t;

typedef struct srv_cap {
    const char *tool, *cmd;  /* in messages: c4g-server capture, or c4g-replay rerun */
    srv_config_t cfg;        /* as the core runs it */
    c4gh_an_options_t an;
    char **srv_argv;         /* the options the report names */
    int srv_argc;
    /* the reading */
    c4gh_an_t *a;
    struct c4gh_cap *file;
    int read_rc;             /* 0 read to the end, 1 stopped early, 2 not opened */
    int eof;
    int progress;
    int overflow;            /* the reading ran ahead of CAP_QUEUE items (never expected) */
    srv_cap_item_t q[CAP_QUEUE];
    unsigned q_head, q_n;
    srv_cap_item_t synth[CAP_SYNTH];
    unsigned synth_head, synth_n;
    srv_cap_item_t taken[CAP_TAKEN];  /* by ref % CAP_TAKEN */
    uint64_t next_ref;
    /* the clock: the recorded time of the datagram being handled, or the end of a pause */
    uint64_t clock;
    uint64_t last_tx;
    /* the run */
    int have_ctrl;
    c4gh_an_endpoint_t ctrl;      /* the controller being run */
    uint64_t server_starts;
    uint64_t other_ctrl_exchanges;  /* packets of sessions not run */
    unsigned other_sessions[C4GH_AN_MAX_SESSIONS];
    unsigned n_other;
    srv_cap_sess_t sess[C4GH_AN_MAX_SESSIONS];
    unsigned n_sess;
    uint64_t compared, divergent, words_divergent;
    int have_first;
    srv_cap_div_t first;
    srv_cap_field_count_t fields[CAP_F_COUNT];
    long long listed;
    srv_cap_pending_t pending[CAP_PENDING];
    unsigned pend_next;
    uint64_t timing_only;
    int init_error;
    char init_why[200];
} srv_cap_t;

/* capture.c */
/* 1 (after the error on stderr) when an option of --capture came without it. */
int srv_capture_misplaced(const srv_capture_opts_t *o);
/* Run the capture @p cfg->cap names through a fresh core per server run, every reply compared
 * (no report printed). @p C is cleared first. Returns the read status (0 read to its end, 1
 * stopped early, 2 not opened: the error is on stderr), or -1 out of memory. */
int srv_capture_run(srv_cap_t *C, const srv_config_t *cfg);
/* c4g-server --capture: the run, its report, the exit code (0 every reply equal, 1 some
 * diverge, 2 bad usage or an unreadable capture). @p argv: the options the report names. */
int srv_capture_main(const srv_config_t *cfg, int argc, char **argv);
/* c4g-server --replay-rerun [CAPTURE OPTIONS] -- [SERVER OPTIONS]: what c4g-replay rerun
 * runs, its messages, report and exit codes. */
int srv_capture_rerun_main(int argc, char **argv);

/* capture_report.c */
const char *srv_cap_field_name(srv_cap_field_t f);
void srv_cap_print_div(FILE *out, const srv_cap_div_t *d);
void srv_cap_report_text(FILE *out, const srv_cap_t *C, const char *path);
/* 0, or -1 when it could not be written */
int srv_cap_report_json(FILE *out, const srv_cap_t *C, const char *path);

#endif
