/* SPDX-License-Identifier: MIT */
/* c4g-replay live: the controller's side of a recorded session played to a running PC
 * server over UDP, its replies judged by the controller's checks (the library's controller end, c4gopen_ctrl.h,
 * the code c4g-sim runs) and compared field by field with the recorded ones. live.c plays,
 * live_report.c prints what came of it. */
#ifndef C4G_REPLAY_LIVE_H
#define C4G_REPLAY_LIVE_H

#include "replay.h"

#include <netinet/in.h>


/* Fields a reply is compared on: the names the report prints. */
#define LV_FIELDS(X)                                                                        \
    X(REPLY, "reply") /* the recorded PC did not answer (or not validly) */                 \
    X(BODY, "body")   /* bytes after NUM of a sync reply or an init echo */                 \
    X(NUM, "NUM") X(INFPAR, "INFPAR") X(CMD, "CMD") X(MODE, "mode")                          \
    X(D1, "D1") X(D2, "D2") X(D3, "D3") X(D4, "D4") X(D5, "D5")                               \
    X(EXT1, "EXT1") X(EXT2, "EXT2") X(EXT3, "EXT3")

#define LV_FIELD_ENUM(id, name) LV_F_##id,
typedef enum lv_field { LV_FIELDS(LV_FIELD_ENUM) LV_F_COUNT } lv_field_t;
#undef LV_FIELD_ENUM

const char *lv_field_name(lv_field_t f);



/* The first reply that differed from the recorded one. */
typedef struct lv_first {
    int set;
    unsigned pass;
    c4g_pkt_kind_t kind;
    uint64_t tick;           /* cyclic packets of the session before this one */
    int32_t num;             /* the controller packet's NUM */
    unsigned axis;           /* OPEN index, 1-based; 0 for the header fields */
    int32_t mode;            /* the controller packet's mode on that axis */
    lv_field_t field;
    char recorded[48], received[48];
} lv_first_t;

/* What pass 1 found of each session. */
typedef struct lv_scan {
    uint64_t exchanges, sync, init, cyclic;
    int first_kind;          /* c4g_pkt_kind_t of its first packet */
    uint64_t stop_frame;     /* its last packet and the recorded reply are read by then */
    uint32_t n_axes;
    int32_t period_ms;       /* from the init packet; 0 unknown */
    int64_t first_ns, last_ns;
    const char *end;
} lv_scan_t;

/* The packet sent last, waiting for its judgement. */
typedef struct lv_pending {
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
} lv_pending_t;

typedef struct lv {
    /* options */
    rp_common_t c;
    char to_text[300];
    struct sockaddr_in to;
    int have_to;
    c4g_num_policy_t policy;
    double speed;             /* 0: not given (1) */
    int topspeed;
    unsigned loops;
    unsigned session;         /* 0: the first with an init packet */
    double tolerance;
    unsigned gap_ms;
    unsigned spin_us;
    uint64_t spin_ns;
    const char *path;
    /* pass 1 */
    lv_scan_t scan[C4GH_AN_MAX_SESSIONS];
    unsigned n_scan;
    unsigned chosen;          /* 1-based */
    /* the socket */
    int fd;
    int kstamp;
    uint32_t tx_seq, tx_key;
    int has_key;
    /* one pass */
    c4g_ctrl_t cs;
    unsigned pass;            /* 1-based */
    int started, pass_done;
    int64_t first_rec_ns;
    uint64_t origin_ns, last_rel_ns;
    uint64_t period_ns;       /* recorded period at the replay's speed */
    uint64_t tol_ns;          /* own lateness counted as an overrun (c4g-sim's margin) */
    uint64_t window_ns;       /* the least time a packet's reply is waited for */
    lv_pending_t pend;
    uint8_t live_raw[C4G_INIT_SIZE]; /* the reply c4g_ctrl_reply accepted for the pending packet */
    size_t live_len;
    /* totals */
    c4gh_hist_t pass_lat;     /* this pass's reply latencies judged ok */
    c4g_ctrl_counters_t n;          /* every pass's c4g_ctrl_t counters added up */
    c4gh_hist_t lat;          /* and their latencies */
    unsigned passes_done;
    int interrupted;
    int read_failed;          /* a pass could not read the file again */
    uint64_t sent, sent_kind[3], send_errors;
    char send_error[120];
    c4gh_hist_t err;           /* send time minus schedule */
    int64_t drift_ns;         /* the last packet's send time minus its schedule */
    uint64_t overruns;        /* packets sent more than tol_ns late */
    uint64_t compared, differing, field[LV_F_COUNT];
    uint64_t timing_only;     /* recorded late, answered in time now, same content */
    lv_first_t first;
    uint64_t elapsed_ns;
} lv_t;

/* live_report.c: 0 when every reply was ok and equal to the recorded one. */
int lv_findings(const lv_t *L);
void lv_report_text(FILE *out, const lv_t *L);
void lv_report_json(FILE *out, const lv_t *L);

#endif
