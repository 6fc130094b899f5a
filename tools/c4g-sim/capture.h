/* SPDX-License-Identifier: MIT */
/* c4g-sim --capture: the controller played from a recorded session instead of the model.
 * The controller packets of one session leave at their recorded times through c4g-sim's
 * socket (net.c: the same foreign filter and kernel timestamps), each reply is judged by
s * the library's controller end (c4g_ctrl_*) as the model's are, and each reply judged ok is compared
 * field by field with the reply the recorded PC gave. capture.c plays, capture_report.c
 * prints what came of it. c4g-replay live is a front end that runs this. */
#ifndef SIM_CAPTURE_H
#define SIM_CAPTURE_H

#include "app.h"
#include "c4gh_analyze.h"

/* A pass stops when its first packets, this many and each judged (its window closed), got
 * nothing at all back from the target: nothing listens there, and the rest of the capture
 * would only count missing replies. The controller itself gives up at 10 in a row. */
#define CAP_DEAD_PACKETS 10U

/* Fields a reply is compared on: the names the report prints. */
#define CAP_FIELDS(X)                                                                       \
    X(REPLY, "reply") /* the recorded PC did not answer (or not validly) */                 \
    X(BODY, "body")   /* bytes after NUM of a sync reply or an init echo */                 \
    X(NUM, "NUM") X(INFPAR, "INFPAR") X(CMD, "CMD") X(MODE, "mode")                          \
    X(D1, "D1") X(D2, "D2") X(D3, "D3") X(D4, "D4") X(D5, "D5")                               \
    X(EXT1, "EXT1") X(EXT2, "EXT2") X(EXT3, "EXT3")

#define CAP_FIELD_ENUM(id, name) CAP_F_##id,
typedef enum cap_field { CAP_FIELDS(CAP_FIELD_ENUM) CAP_F_COUNT } cap_field_t;
#undef CAP_FIELD_ENUM

const char *cap_field_name(cap_field_t f);

/* The first reply that differed from the recorded one. */
typedef struct cap_first {
    int set;
    unsigned pass;
    c4g_pkt_kind_t kind;
    uint64_t tick;           /* cyclic packets of the session before this one */
    int32_t num;             /* the controller packet's NUM */
    unsigned axis;           /* OPEN index, 1-based; 0 for the header fields */
    int32_t mode;            /* the controller packet's mode on that axis */
    cap_field_t field;
    char recorded[48], received[48];
} cap_first_t;

/* What the first reading found of each session. */
typedef struct cap_scan {
    uint64_t exchanges, sync, init, cyclic;
    int first_kind;          /* c4g_pkt_kind_t of its first packet */
    uint64_t stop_frame;     /* its last packet and the recorded reply are read by then */
    uint32_t n_axes;
    int32_t period_ms;       /* from the init packet; 0 unknown */
    int64_t first_ns, last_ns;
} cap_scan_t;

/* The packet sent last, waiting for its judgement. */
typedef struct cap_pending {
    int active;
    c4g_pkt_kind_t kind;
    uint64_t tick;
    int32_t num;
    int check, suspended;
    int64_t rec_ns;           /* capture time */
    uint64_t sched_ns;        /* when it was due: the pass's origin + its recorded time */
    uint64_t sent_ns;         /* clock read before sendto */
    int has_rec;              /* the recorded PC answered it validly */
    size_t rec_len;
    uint8_t rec_raw[C4G_INIT_SIZE];
    c4g_pc_packet_t rec;      /* cyclic: the recorded reply decoded */
    int rec_decoded;
    int rec_late;             /* the recorded reply came after the next packet (stale) */
    uint32_t n_modes;
    int32_t modes[C4G_MAX_AXES]; /* the controller packet's modes */
} cap_pending_t;


typedef struct cap {
    app_t *app;               /* the socket, its timestamps and the controller side */
    cap_opts_t o;
    const char *tool, *cmd;   /* in messages and the report */
    c4g_num_policy_t policy;  /* --num-policy */
    char to_text[96];
    c4gh_an_options_t an;
    uint64_t spin_ns;
    /* the first reading */
    cap_scan_t scan[C4GH_AN_MAX_SESSIONS];
    unsigned n_scan;
    unsigned chosen;          /* 1-based */
    /* one pass */
    unsigned pass;            /* 1-based */
    int started, pass_done;
    int64_t first_rec_ns;
    uint64_t origin_ns, last_rel_ns;
    uint64_t period_ns;       /* recorded period at the replay's speed */
    uint64_t tol_ns;          /* own lateness counted as an overrun (c4g-sim's margin) */
    uint64_t window_ns;       /* the least time a packet's reply is waited for */
    cap_pending_t pend;
    /* totals */
    c4g_ctrl_counters_t n;     /* every pass's c4g_ctrl_t counters added up */
    unsigned passes_done;
    int interrupted;
    int read_failed;          /* a pass could not read the file again */
    int dead;                 /* nothing answered: the run stopped (CAP_DEAD_PACKETS) */
    unsigned dead_pass;       /* in this pass */
    uint64_t dead_ns;         /* this long after the pass started */
    uint64_t sent, sent_kind[3], send_errors;
    char send_error[120];
    c4gh_hist_t err;          /* send time minus schedule */
    int64_t drift_ns;         /* the last packet's send time minus its schedule */
    uint64_t overruns;        /* packets sent more than tol_ns late */
    uint64_t compared, differing, field[CAP_F_COUNT];
    uint64_t timing_only;     /* recorded late, answered in time now, same content */
    cap_first_t first;
    uint64_t elapsed_ns;
} cap_t;

/* capture.c: c4g-sim --capture from after the command line to the exit code. */
int capture_main(app_t *a);
/* capture.c: 1 (after the error on stderr) when an option of --capture came without it. */
int capture_options_misplaced(const app_t *a);

/* capture_report.c: 1 when a reply was not ok or not equal to the recorded one. */
int cap_findings(const cap_t *C);
void cap_report_text(FILE *out, const cap_t *C);
void cap_report_json(FILE *out, const cap_t *C);

#endif
