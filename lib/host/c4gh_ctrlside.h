/* SPDX-License-Identifier: MIT */
/* The controller side of C4G Open, without I/O: which packet the controller sends next
 * (start-up handshake, restart), the NUM policy it holds the PC to, the checks of each
 * reply and the judgement of each packet's reply against its deadline, with counters.
 * The caller owns the struct, the socket and the clock: it passes the bytes it received
 * and their arrival time in ns (any monotonic origin), and reads back verdicts. c4g-sim
 * drives it live; a replay of a capture can feed it the capture's packets and timestamps.
 * No globals, no stdio, no clocks. See docs/ctrlside.md. */
#ifndef C4GH_CTRLSIDE_H
#define C4GH_CTRLSIDE_H

#include "c4gh_hist.h"
#include <stddef.h>
#include <stdint.h>

#include "c4gopen.h"

/* Reply NUM the controller accepts. The values match c4g-sim's sim_policy_t. */
typedef enum c4gh_cs_policy { C4GH_CS_NUM_PLUS_ONE = 0, C4GH_CS_NUM_ECHO = 1, C4GH_CS_NUM_EITHER = 2 } c4gh_cs_policy_t;

/* Kind of packet the controller sends. */
typedef enum c4gh_cs_kind { C4GH_CS_SYNC = 0, C4GH_CS_INIT, C4GH_CS_CYCLIC } c4gh_cs_kind_t;

/* Handshake phase: 9 sync, init, 2 sync, cyclic (defaults); a restart goes to init. */
typedef enum c4gh_cs_phase { C4GH_CS_PH_SYNC_PRE = 0, C4GH_CS_PH_INIT, C4GH_CS_PH_SYNC_POST, C4GH_CS_PH_CYCLIC } c4gh_cs_phase_t;

/* What one received datagram was, as c4gh_cs_reply judged it. */
typedef enum c4gh_cs_rx {
    C4GH_CS_RX_ACCEPTED = 0, /* a valid reply to the outstanding packet; judged at its deadline */
    C4GH_CS_RX_UNEXPECTED,   /* no packet awaits a checked reply */
    C4GH_CS_RX_SHORT,        /* under 4 bytes: no NUM (malformed) */
    C4GH_CS_RX_WRONG_NUM,    /* NUM breaks the policy */
    C4GH_CS_RX_STALE,        /* NUM of one of the C4GH_CS_STALE_WINDOW packets before: came too late */
    C4GH_CS_RX_BAD_LENGTH,   /* a sync reply that is not 732 bytes (malformed) */
    C4GH_CS_RX_BAD_INIT,     /* an init reply that is not the 1200 bytes echoed (malformed) */
    C4GH_CS_RX_BAD_DECODE,   /* a cyclic reply c4g_pc_decode refuses (malformed; diag says why) */
    C4GH_CS_RX_DUPLICATE     /* a second valid reply to the same packet */
} c4gh_cs_rx_t;

/* The judgement of the outstanding packet at the tick after it (c4gh_cs_judge). */
typedef enum c4gh_cs_verdict {
    C4GH_CS_J_NONE = 0,  /* nothing outstanding, or its reply is not checked */
    C4GH_CS_J_OK,        /* a valid reply by the deadline (c4gh_cs_t.last_late: later than t-cycle1) */
    C4GH_CS_J_MISSING,   /* none by the deadline: the PC's fault (ERR_C4GOPEN_UDP_DEBUG) */
    C4GH_CS_J_UNJUDGED   /* none by a deadline the caller itself woke past: not counted missing */
} c4gh_cs_verdict_t;

/* A reply to one of this many packets before the outstanding one is stale, not wrong:
 * a PC that a busy host stopped for a second answers the backlog (NUM counts to 0x7FFF,
 * so a wrong NUM is still told apart). */
#define C4GH_CS_STALE_WINDOW 512
#define C4GH_CS_LAT_BINS 20001 /* 1 us bins; the last one collects everything above */

typedef struct c4gh_cs_config {
    c4gh_cs_policy_t policy;
    uint32_t n_axes;        /* open axes: the cyclic reply size */
    uint64_t t_cycle1_ns;   /* a reply later than this after its packet counts as late */
    uint64_t tol_ns;        /* caller's own lateness beyond which a deadline is unjudged */
    unsigned max_miss;      /* consecutive packets without a reply: c4gh_cs_judge says fatal */
    unsigned sync_before;   /* sync packets before the init packet (9) */
    unsigned sync_after;    /* after it, at the first start only (2) */
} c4gh_cs_config_t;

typedef struct c4gh_cs_counters {
    unsigned long sync_sent, init_sent, cyclic_sent;
    unsigned long rx_total, replies_ok, missing, late, unjudged;
    unsigned long wrong_num, malformed, foreign, duplicates, stale, unexpected;
    unsigned long consecutive, max_consecutive;
    uint64_t lat_min, lat_max, lat_sum; /* ns, over the replies judged ok */
    c4gh_hist_t lat;             /* the same latencies, for percentiles */
} c4gh_cs_counters_t;

/* The packet whose reply is awaited. */
typedef struct c4gh_cs_outstanding {
    int active;
    int check;              /* 0: its reply is not checked (504) */
    c4gh_cs_kind_t kind;
    int32_t num;
    uint64_t sent_ns;
    uint64_t deadline_ns;   /* UINT64_MAX until c4gh_cs_set_deadline */
    int got;                /* a valid reply arrived (the first one is kept) */
    uint64_t got_ns;
    int answered;           /* judged ok: its reply is handed to the next tick */
    size_t len;
    uint8_t raw[C4G_INIT_SIZE];
    c4g_pc_packet_t reply;  /* cyclic: the decoded reply */
} c4gh_cs_outstanding_t;

typedef struct c4gh_cs {
    c4gh_cs_config_t cfg;
    c4gh_cs_phase_t phase;
    unsigned left;          /* sync packets left in this phase */
    int cold;               /* the first start: syncs follow the init packet */
    int32_t num;            /* NUM of the next packet */
    int detected;           /* policy "either": C4GH_CS_NUM_PLUS_ONE or C4GH_CS_NUM_ECHO once the init
                             * echo showed it, -1 before */
    c4gh_cs_outstanding_t out;
    c4gh_cs_counters_t n;
    /* details of the last c4gh_cs_reply / c4gh_cs_judge, for the caller's messages */
    int32_t last_num;       /* NUM of the last datagram (c4gh_cs_reply) */
    c4g_diag_t last_diag;   /* why c4g_pc_decode refused it (C4GH_CS_RX_BAD_DECODE) */
    int last_late;          /* c4gh_cs_judge C4GH_CS_J_OK: later than t-cycle1 */
    int last_stale;         /* c4gh_cs_judge: the reply came, after the deadline */
    int fatal;              /* c4gh_cs_judge: max_miss packets in a row without a reply */
} c4gh_cs_t;

/* Start from the first sync packet (NUM 1). */
void c4gh_cs_init(c4gh_cs_t *c, const c4gh_cs_config_t *cfg);

/* ---- handshake driver: what to send this tick ---- */
/* Kind of the packet due now (from the phase). */
c4gh_cs_kind_t c4gh_cs_next_kind(const c4gh_cs_t *c);
/* NUM the packet due now carries. */
int32_t c4gh_cs_next_num(const c4gh_cs_t *c);
/* The packet due now went out (a cyclic one that is not sent must not call this): the
 * NUM and the phase move on. */
void c4gh_cs_advance(c4gh_cs_t *c);
/* A 506 went out: the init packet follows, without sync packets. */
void c4gh_cs_restart(c4gh_cs_t *c);
/* NUM after n: 0..0x7FFF, then 0. */
int32_t c4gh_cs_num_after(int32_t n);

/* ---- replies ---- */
/* Packet NUM num left at sent_ns: its reply is awaited (check 0: not checked). Counts it.
 * buf is the packet as encoded (at most C4G_INIT_SIZE bytes; the init echo is compared
 * with it). */
void c4gh_cs_emit(c4gh_cs_t *c, c4gh_cs_kind_t kind, int32_t num, const uint8_t *buf, size_t len, int check,
             uint64_t sent_ns);
/* The packet's deadline (the next tick), once known. */
void c4gh_cs_set_deadline(c4gh_cs_t *c, uint64_t deadline_ns);
/* A better send time of the outstanding packet (kernel stamp), taken if it is plausible:
 * at most 200 us before the recorded one and not after now_ns. Returns 1 if taken. */
int c4gh_cs_sent_stamp(c4gh_cs_t *c, uint64_t stamp_ns, uint64_t now_ns);
/* One datagram from the PC, arrived at at_ns: checks it and counts it. */
c4gh_cs_rx_t c4gh_cs_reply(c4gh_cs_t *c, const uint8_t *buf, size_t len, uint64_t at_ns);
/* A datagram from another address (the caller tells): counted as foreign. */
void c4gh_cs_foreign(c4gh_cs_t *c);
/* 1 if NUM got is a reply to NUM sent under the policy (and, for "either", the policy the
 * PC showed in its init echo). */
int c4gh_cs_num_ok(const c4gh_cs_t *c, int32_t sent, int32_t got);
/* 1 if got answers one of the C4GH_CS_STALE_WINDOW packets before cur. */
int c4gh_cs_is_stale(const c4gh_cs_t *c, int32_t cur, int32_t got);

/* ---- deadlines ---- */
/* At a tick (the caller woke at woke_ns and passed everything that arrived): judge the
 * outstanding packet. suspended: replies are not checked now (active freezing). */
c4gh_cs_verdict_t c4gh_cs_judge(c4gh_cs_t *c, uint64_t woke_ns, int suspended);
/* The reply judged ok at the last c4gh_cs_judge, if the packet was cyclic; NULL otherwise.
 * Hands it over once. */
const c4g_pc_packet_t *c4gh_cs_take_reply(c4gh_cs_t *c);

/* ---- reporting ---- */
/* Reply latency percentile q (0..1) in us from the histogram (upper bin edge, at most
 * the maximum); 0 without replies. */
double c4gh_cs_lat_percentile(const c4gh_cs_counters_t *n, double q);
/* "plus-one", "echo", "either"; for c4gh_cs_t.detected: "unknown" below 0. */
const char *c4gh_cs_policy_name(int policy);

#endif
