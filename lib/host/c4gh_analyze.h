/* SPDX-License-Identifier: MIT */
/* The analysis of a capture, one datagram at a time: C4G Open flows found by themselves
 * (the 1200-byte initialization packet, or the PC ports), which side is the controller
 * decided from the protocol, sessions kept apart (a 506 restart, a cold restart, two
 * controllers), every reply judged as the controller judges it (the library's controller end, c4gopen_ctrl.h,
 * the code c4g-sim runs), the mode timeline per arm (the library's arm state machine) and
 * the safety findings in the data. Memory is fixed: counters, a latency histogram and
 * bounded timelines per session, whatever the file's length. */
#ifndef C4GH_ANALYZE_H
#define C4GH_ANALYZE_H

#include "c4gh_hist.h"
#include "c4gopen.h"
#include "c4gh_capture.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define C4GH_AN_MAX_FLOWS 32U
#define C4GH_AN_MAX_SESSIONS 64U
#define C4GH_AN_TIMELINE 64U      /* transitions kept per arm (the rest are counted) */
#define C4GH_AN_EVENTS 64U        /* PC requests and session events kept */
#define C4GH_AN_PENDING 16U       /* datagrams held while a flow's direction is undecided */
#define C4GH_AN_MAX_PORTS 16U
#define C4GH_AN_RECENT 64U        /* other UDP datagrams remembered: a flow found by its init
                              * packet takes the synchronization packets before it */

/* A float from its bits (words read with c4g_le_u32). */
static inline float c4gh_an_f32_bits(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Kinds of finding: the names are what --allow takes. */
#define C4GH_AN_KINDS(X)                                                                          \
    X(CAPTURE, "capture", "damaged frames in the capture file")                              \
    X(MISSING, "missing", "controller packets without a reply by the next tick")             \
    X(MISSING_RUN, "missing-run", "10 or more replies missing in a row (ERR_C4GOPEN_UDP)")   \
    X(LATE, "late", "replies later than T_CYCLE1")                                           \
    X(NUM, "num", "replies whose NUM breaks the NUM policy")                                 \
    X(DUPLICATE, "duplicate", "a second reply to one controller packet")                     \
    X(CTRL_GAP, "ctrl-gap", "controller NUMs skipped (packets lost before the capture)")     \
    X(REORDER, "reorder", "controller packets repeated or out of order")                     \
    X(MALFORMED, "malformed", "datagrams of the wrong length or layout")                     \
    X(NONFINITE, "nonfinite", "NaN or infinity in a float field")                            \
    X(UNKNOWN_MODE, "unknown-mode", "a mode code the protocol does not define")              \
    X(TRANSITION, "transition", "a mode change the protocol does not allow")                 \
    X(FOLLOW_ERROR, "follow-error", "|target - actual| over the init packet's FollowError")  \
    X(CURRENT, "current-limit", "a current the controller would apply over AzLim")           \
    X(POS_STEP, "position-step", "a position reference the controller would reject")        \
    X(CLOCK_STEP, "clock-step", "the capture's clock went back (frames kept in capture order)") \
    X(SILENCE, "silence", "no controller packet for over 1 s outside a freezing")

#define C4GH_AN_KIND_ENUM(id, name, text) AN_K_##id,
typedef enum c4gh_an_kind { C4GH_AN_KINDS(C4GH_AN_KIND_ENUM) AN_K_COUNT } c4gh_an_kind_t;
#undef C4GH_AN_KIND_ENUM

const char *c4gh_an_kind_name(c4gh_an_kind_t k);
const char *c4gh_an_kind_text(c4gh_an_kind_t k);
/* The kind named @p name, or -1. */
int c4gh_an_kind_find(const char *name);

typedef struct c4gh_an_finding {
    uint64_t count;
    uint64_t frame;          /* first occurrence */
    int64_t t_ns;            /* since the session's first packet */
    int32_t num;
    double worst;            /* largest value seen (kinds with a value) */
    char first[200];         /* the first occurrence, in words */
} c4gh_an_finding_t;

typedef struct c4gh_an_transition {
    int64_t t_ns;            /* since the session's first packet */
    int32_t num;
    uint64_t frame;
    int32_t from, to;        /* arm modes; from -1 at the first packet */
    uint32_t mixed;          /* the arm's axes disagreed */
} c4gh_an_transition_t;

/* A session event: a PC request (505, 508, 500, EXIT_FROM_OPEN), drive on/off. */
typedef struct c4gh_an_event {
    int64_t t_ns;
    int32_t num;
    uint64_t frame;
    uint32_t arm;            /* 0-based */
    char what[48];
} c4gh_an_event_t;

typedef struct c4gh_an_endpoint {
    uint32_t ip;
    uint16_t port;
} c4gh_an_endpoint_t;

/* One session: from a start-up (or the first packet seen) to its end. */
typedef struct c4gh_an_session {
    unsigned id;                /* 1-based, in order of first packet */
    const char *file;
    c4gh_an_endpoint_t ctrl, pc;
    int64_t first_ns, last_ns;  /* capture times */
    uint64_t first_frame, last_frame;
    int have_init;
    c4g_init_t init;
    c4g_axis_map_t map;
    uint32_t n_axes;            /* open axes (from the init packet, else the packet length) */
    int synthetic_map;          /* no init packet: all axes taken as arm 1 (2, ...) by tens */
    const char *end;            /* "504", "506 restart", "cold restart", "capture end", ... */
    /* packets */
    uint64_t ctrl_sync, ctrl_init, ctrl_cyclic, ctrl_other;
    uint64_t pc_sync, pc_init, pc_cyclic, pc_other;
    /* replies, judged as the controller judges them */
    c4g_ctrl_t cs;
    c4gh_hist_t lat;            /* the latencies of the replies judged ok */
    int policy;                 /* C4G_NUM_PLUS_ONE / C4G_NUM_ECHO seen, -1 unknown */
    uint64_t run, run_longest;  /* missing replies in a row */
    int64_t run_start_ns, longest_start_ns;
    int32_t run_start_num, longest_start_num;
    /* controller NUM sequence */
    int32_t ctrl_num;           /* last, -1 none */
    uint64_t ctrl_gaps, ctrl_skipped, ctrl_dups, ctrl_older;
    /* modes */
    c4g_arm_sm_t sm[C4G_ARMS];
    c4gh_an_transition_t tl[C4G_ARMS][C4GH_AN_TIMELINE];
    uint32_t n_tl[C4G_ARMS];
    uint64_t tl_more[C4G_ARMS];
    c4gh_an_event_t ev[C4GH_AN_EVENTS];
    uint32_t n_ev;
    uint64_t ev_more;
    uint64_t special_seen[9];   /* packets carrying 500..508 on some axis */
    int frozen;                 /* 502 .. 503, or 500: replies are not checked */
    uint8_t req[C4G_ARMS];      /* PC requests in force per arm (bit per kind), for events */
    uint64_t policy_plus, policy_echo; /* cyclic replies under each NUM policy */
    int policy_from_cyclic;     /* no init echo in time: the policy learnt from cyclic replies */
    int prev_in_time;           /* the last packet judged was cyclic and answered in time */
    uint64_t pc_unseen;         /* replies to controller packets missing from the capture */
    /* data */
    c4gh_an_finding_t f[AN_K_COUNT];
    /* internal */
    c4g_ctrl_packet_t rx;       /* the outstanding controller packet, decoded */
    int rx_ok;
    c4g_pc_packet_t last_tx;    /* the last reply judged ok (kept with opt.max_step > 0) */
    int have_last_tx;
    int cold;                   /* syncs seen before the init packet */
    unsigned post_sync;         /* syncs still expected after the init packet */
    int cyclic_started;
    uint8_t reply_raw[C4G_INIT_SIZE];
    size_t reply_len;
    int64_t reply_ns;
    uint64_t reply_frame;
    uint8_t other_raw[C4G_INIT_SIZE]; /* the first PC datagram of the tick that was not a valid
                                       * reply (wrong NUM, the unchecked reply to 504, ...) */
    size_t other_len;
    int64_t other_ns;
    uint64_t other_frame;
    uint64_t ctrl_frame;
    int64_t ctrl_ns;
    uint8_t ctrl_raw[C4G_INIT_SIZE];
    size_t ctrl_len;
} c4gh_an_session_t;

/* One controller packet and what came back, handed over when it is judged (at the next
 * controller packet of the session, or at its end). */
typedef struct c4gh_an_exchange {
    const c4gh_an_session_t *s;
    c4g_pkt_kind_t kind;
    uint64_t tick;              /* cyclic: its number in the session (1 = the first); else the
                                 * cyclic packets before it */
    const uint8_t *ctrl;        /* the controller's datagram */
    size_t ctrl_len;
    uint64_t ctrl_frame;
    int64_t ctrl_ns;            /* capture time */
    const c4g_ctrl_packet_t *rx;/* decoded (cyclic), else NULL */
    const uint8_t *reply;       /* the first valid reply (to a 504, which the controller
                                 * does not check: one that answers its NUM and decodes),
                                 * NULL if none came */
    size_t reply_len;
    uint64_t reply_frame;
    int64_t reply_ns;
    const c4g_pc_packet_t *tx;  /* decoded (cyclic), else NULL */
    const uint8_t *other;       /* the first PC datagram after the packet that was not a valid
                                 * reply (a wrong NUM, a bad length), NULL if none came */
    size_t other_len;
    uint64_t other_frame;
    int64_t other_ns;
    c4g_ctrl_verdict_t verdict;
    int late;                   /* verdict OK but later than T_CYCLE1 */
    int64_t next_ns;            /* the session's next controller packet, 0 at the end */
} c4gh_an_exchange_t;

typedef void (*c4gh_an_exchange_fn)(void *ctx, const c4gh_an_exchange_t *x);
/* A reply that came after its packet's deadline (stale): its bytes, time and frame. */
typedef void (*c4gh_an_late_fn)(void *ctx, const c4gh_an_session_t *s, const uint8_t *d, size_t len,
                           int64_t ns, uint64_t frame);

typedef struct c4gh_an_options {
    uint16_t ports[C4GH_AN_MAX_PORTS]; /* PC ports of C4G Open flows (1000, 1001) */
    unsigned n_ports;
    uint64_t t_cycle1_ns;         /* 500 us */
    double max_step;              /* position step per tick over which a reply is flagged; 0 off */
    c4g_num_policy_t num_policy;  /* the controller's: C4G_NUM_EITHER (learnt from the
                                   * init echo, default), C4G_NUM_PLUS_ONE or C4G_NUM_ECHO */
    c4gh_an_exchange_fn on_exchange;   /* may be NULL */
    c4gh_an_late_fn on_late;           /* may be NULL */
    void *ctx;
} c4gh_an_options_t;

typedef struct an_flow c4gh_an_flow_t;

/* The whole analysis of one or more files (sessions keep their file's name). */
typedef struct c4gh_an {
    c4gh_an_options_t opt;
    c4gh_an_session_t *sess;          /* C4GH_AN_MAX_SESSIONS, allocated once */
    unsigned n_sess;
    uint64_t sess_dropped;       /* sessions beyond C4GH_AN_MAX_SESSIONS: not analysed */
    c4gh_an_flow_t *flows;            /* C4GH_AN_MAX_FLOWS */
    struct an_held *recent;      /* C4GH_AN_RECENT, a ring */
    unsigned n_recent, recent_head;
    unsigned n_flows;
    uint64_t flows_dropped;
    uint64_t datagrams, c4g_datagrams, other_udp;
    const char *file;
    /* the file's clock: times are made monotonic in capture order (a step back shifts
     * every later time by its size), the step reported in the next session datagram */
    int have_ts;
    int64_t last_ts, clock_shift;
    int step_pending;
    int64_t step_ns;
    uint64_t step_frame;
    /* frames captured twice (an identical datagram at the same time right after itself):
     * analysed once, counted per file */
    uint64_t doubled;
    c4gh_cap_pkt_t prev;
    uint8_t prev_data[C4G_INIT_SIZE + 4U];
    int have_prev;
} c4gh_an_t;

void c4gh_an_options_default(c4gh_an_options_t *o);
/* 0, or -1 out of memory. */
int c4gh_an_init(c4gh_an_t *a, const c4gh_an_options_t *o);
void c4gh_an_free(c4gh_an_t *a);
/* One UDP datagram of @p file (its name is kept by reference). */
void c4gh_an_datagram(c4gh_an_t *a, const char *file, const c4gh_cap_pkt_t *p);
/* The file ended: pending flows are decided, open sessions closed. */
void c4gh_an_file_end(c4gh_an_t *a, const char *file);

/* Reply latency percentile in us. */
double c4gh_an_latency_us(const c4gh_an_session_t *s, double q);
/* Findings of the session not waived by @p allow (bit per kind). */
unsigned c4gh_an_findings(const c4gh_an_session_t *s, uint32_t allow);

#endif
