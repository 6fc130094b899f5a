/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_ctrl.h
 * @brief libc4gopen controller end: the conversation as the SMP+ holds it, without I/O.
 *
 * Which packet the controller sends next (start-up handshake, 506 restart), the NUM policy
 * it holds the PC to (c4g_num_accepts), the checks of each reply and the judgement of each
 * packet's reply against its deadline, with counters. The caller owns the struct, the
 * socket and the clock: it passes the bytes it received and their arrival time in ns (any
 * monotonic origin), and reads back verdicts. A simulator drives it live; a capture
 * checker feeds it a capture's packets and timestamps; a test feeds it the PC end's
 * replies in memory. Each judged latency is reported (c4g_ctrl_t.last_lat_ns); a
 * histogram, if any, is the caller's.
 */
#ifndef C4GOPEN_CTRL_H
#define C4GOPEN_CTRL_H

#include "c4gopen_wire.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Handshake phase: 9 sync, init, 2 sync, cyclic (defaults); a restart goes to init. */
typedef enum c4g_ctrl_phase {
    C4G_CTRL_PH_SYNC_PRE = 0,
    C4G_CTRL_PH_INIT,
    C4G_CTRL_PH_SYNC_POST,
    C4G_CTRL_PH_CYCLIC
} c4g_ctrl_phase_t;

/** What one received datagram was, as c4g_ctrl_reply judged it. */
typedef enum c4g_ctrl_rx {
    C4G_CTRL_RX_ACCEPTED = 0, /**< a valid reply to the outstanding packet; judged at its deadline */
    C4G_CTRL_RX_UNEXPECTED,   /**< no packet awaits a checked reply */
    C4G_CTRL_RX_SHORT,        /**< under 4 bytes: no NUM (malformed) */
    C4G_CTRL_RX_WRONG_NUM,    /**< NUM breaks the policy */
    C4G_CTRL_RX_STALE,        /**< NUM of one of the C4G_CTRL_STALE_WINDOW packets before */
    C4G_CTRL_RX_BAD_LENGTH,   /**< a sync reply that is not 732 bytes (malformed) */
    C4G_CTRL_RX_BAD_INIT,     /**< an init reply that is not the 1200 bytes echoed (malformed) */
    C4G_CTRL_RX_BAD_DECODE,   /**< a cyclic reply c4g_pc_decode refuses (last_diag says why) */
    C4G_CTRL_RX_DUPLICATE     /**< a second valid reply to the same packet */
} c4g_ctrl_rx_t;

/** The judgement of the outstanding packet at the tick after it (c4g_ctrl_judge). */
typedef enum c4g_ctrl_verdict {
    C4G_CTRL_J_NONE = 0, /**< nothing outstanding, or its reply is not checked */
    C4G_CTRL_J_OK,       /**< a valid reply by the deadline (last_late: later than t-cycle1) */
    C4G_CTRL_J_MISSING,  /**< none by the deadline: the PC's fault (ERR_C4GOPEN_UDP_DEBUG) */
    C4G_CTRL_J_UNJUDGED  /**< none by a deadline the caller itself woke past: not missing */
} c4g_ctrl_verdict_t;

/**
 * A reply to one of this many packets before the outstanding one is stale, not wrong: a
 * PC that a busy host stopped for a second answers the backlog (NUM counts to 0x7FFF, so
 * a wrong NUM is still told apart).
 */
#define C4G_CTRL_STALE_WINDOW 512
/** A kernel send stamp may precede the caller's own send time by this much [ns]. */
#define C4G_CTRL_STAMP_SLACK_NS 200000U

/** Controller end configuration. */
typedef struct c4g_ctrl_config {
    c4g_num_policy_t policy; /**< reply NUM accepted (C4G_NUM_EITHER: the init echo decides) */
    uint32_t n_axes;         /**< open axes: the cyclic reply size (1..20; 0: any size) */
    uint64_t t_cycle1_ns;    /**< a reply later than this after its packet counts as late */
    uint64_t tol_ns;         /**< caller's own lateness beyond which a deadline is unjudged */
    uint32_t max_miss;       /**< packets in a row without a reply: c4g_ctrl_t.fatal */
    uint32_t sync_before;    /**< sync packets before the init packet (field: 9) */
    uint32_t sync_after;     /**< after it, at the first start only (field: 2) */
} c4g_ctrl_config_t;

/** Controller end counters: readable at any time. */
typedef struct c4g_ctrl_counters {
    uint64_t sync_sent;      /**< packets emitted, by kind */
    uint64_t init_sent;
    uint64_t cyclic_sent;
    uint64_t rx_total;       /**< datagrams handed to c4g_ctrl_reply / c4g_ctrl_foreign */
    uint64_t replies_ok;     /**< packets whose reply came by the deadline */
    uint64_t missing;        /**< ... whose reply did not: the PC's fault */
    uint64_t late;           /**< replies ok but later than t_cycle1 */
    uint64_t unjudged;       /**< no reply by a deadline the caller itself woke past */
    uint64_t wrong_num;      /**< datagrams by what c4g_ctrl_reply found (c4g_ctrl_rx_t) */
    uint64_t malformed;
    uint64_t foreign;
    uint64_t duplicates;
    uint64_t stale;          /**< stale NUMs, and replies that came after their deadline */
    uint64_t unexpected;
    uint64_t consecutive;    /**< packets without a reply in a row, now */
    uint64_t max_consecutive;/**< and at most */
    uint64_t lat_min;        /**< ns, over the replies judged ok */
    uint64_t lat_max;
    uint64_t lat_sum;
} c4g_ctrl_counters_t;

/** The packet whose reply is awaited. */
typedef struct c4g_ctrl_outstanding {
    uint32_t active;
    uint32_t check;          /**< 0: its reply is not checked (504) */
    c4g_pkt_kind_t kind;
    int32_t num;
    uint64_t sent_ns;
    uint64_t deadline_ns;    /**< UINT64_MAX until c4g_ctrl_set_deadline */
    uint32_t got;            /**< a valid reply arrived (the first one is kept) */
    uint64_t got_ns;
    uint32_t answered;       /**< judged ok: its reply is handed to the next tick */
    size_t len;
    uint8_t raw[C4G_INIT_SIZE];
    c4g_pc_packet_t reply;   /**< cyclic: the decoded reply */
} c4g_ctrl_outstanding_t;

/** Controller end context. Members are read-only for the caller. */
typedef struct c4g_ctrl {
    c4g_ctrl_config_t cfg;
    c4g_ctrl_phase_t phase;
    uint32_t left;           /**< sync packets left in this phase */
    uint32_t cold;           /**< the first start: syncs follow the init packet */
    int32_t num;             /**< NUM of the next packet */
    int32_t detected;        /**< policy "either": C4G_NUM_PLUS_ONE or C4G_NUM_ECHO once the
                                  init echo showed it, -1 before */
    c4g_ctrl_outstanding_t out;
    c4g_ctrl_counters_t n;
    /* details of the last c4g_ctrl_reply / c4g_ctrl_judge, for the caller's messages */
    int32_t last_num;        /**< NUM of the last datagram (c4g_ctrl_reply) */
    c4g_diag_t last_diag;    /**< why c4g_pc_decode refused it (C4G_CTRL_RX_BAD_DECODE) */
    uint32_t last_late;      /**< c4g_ctrl_judge C4G_CTRL_J_OK: later than t-cycle1 */
    uint32_t last_stale;     /**< c4g_ctrl_judge: the reply came, after the deadline */
    uint64_t last_lat_ns;    /**< c4g_ctrl_judge C4G_CTRL_J_OK: the reply's latency */
    uint32_t fatal;          /**< c4g_ctrl_judge: max_miss packets in a row without a reply */
} c4g_ctrl_t;

/**
 * Start from the first sync packet (NUM 1), or from the init packet if sync_before is 0.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (policy unknown, n_axes over 20).
 */
C4G_NODISCARD c4g_status_t c4g_ctrl_init(c4g_ctrl_t *c, const c4g_ctrl_config_t *cfg);

/** Kind of the packet due now (from the phase). */
c4g_pkt_kind_t c4g_ctrl_next_kind(const c4g_ctrl_t *c);
/** NUM the packet due now carries. */
int32_t c4g_ctrl_next_num(const c4g_ctrl_t *c);
/**
 * The packet due now went out (a cyclic one that is not sent must not call this): the NUM
 * and the phase move on. @return C4G_OK, C4G_ERR_NULL.
 */
C4G_NODISCARD c4g_status_t c4g_ctrl_advance(c4g_ctrl_t *c);
/** A 506 went out: the init packet follows, without sync packets. */
C4G_NODISCARD c4g_status_t c4g_ctrl_restart(c4g_ctrl_t *c);

/**
 * Packet NUM @p num left at @p sent_ns: its reply is awaited (@p check 0: not checked, as
 * after 504). Counts it. @p buf is the packet as encoded (the init echo is compared with
 * it; bytes beyond C4G_INIT_SIZE are not kept).
 * @return C4G_OK, C4G_ERR_NULL (no c or buf), C4G_ERR_ARG (kind is not sync, init or
 *         cyclic: nothing changes).
 */
C4G_NODISCARD c4g_status_t c4g_ctrl_emit(c4g_ctrl_t *c, c4g_pkt_kind_t kind, int32_t num,
                                         const uint8_t *buf, size_t len, bool check,
                                         uint64_t sent_ns);
/** The outstanding packet's deadline (the next tick), once known. */
C4G_NODISCARD c4g_status_t c4g_ctrl_set_deadline(c4g_ctrl_t *c, uint64_t deadline_ns);
/**
 * A better send time of the outstanding packet (a kernel stamp), taken if plausible: at
 * most C4G_CTRL_STAMP_SLACK_NS before the recorded one and not after @p now_ns.
 * @return C4G_OK (taken), C4G_ERR_NULL, C4G_ERR_STATE (nothing outstanding),
 *         C4G_ERR_ARG (implausible: not taken).
 */
C4G_NODISCARD c4g_status_t c4g_ctrl_sent_stamp(c4g_ctrl_t *c, uint64_t stamp_ns, uint64_t now_ns);
/**
 * One datagram from the PC, arrived at @p at_ns: checks it, counts it and says what it
 * was in @p out. @return C4G_OK, C4G_ERR_NULL.
 */
C4G_NODISCARD c4g_status_t c4g_ctrl_reply(c4g_ctrl_t *c, const uint8_t *buf, size_t len,
                                          uint64_t at_ns, c4g_ctrl_rx_t *out);
/** A datagram from another address (the caller tells): counted as foreign. */
C4G_NODISCARD c4g_status_t c4g_ctrl_foreign(c4g_ctrl_t *c);
/** The policy in force: cfg.policy, or for "either" the one the init echo showed (still
 *  C4G_NUM_EITHER before it). */
c4g_num_policy_t c4g_ctrl_policy(const c4g_ctrl_t *c);

/**
 * At a tick (the caller woke at @p woke_ns and passed everything that arrived): judge the
 * outstanding packet. @p suspended: replies are not checked now (active freezing): the
 * verdict is C4G_CTRL_J_NONE and nothing is counted, but a valid reply is still handed over
 * (c4g_ctrl_take_reply), since the one that ends the freezing (EXIT_FROM_OPEN) comes while
 * the checks are suspended. On C4G_CTRL_J_OK last_lat_ns is the reply's latency.
 * @return C4G_OK, C4G_ERR_NULL.
 */
C4G_NODISCARD c4g_status_t c4g_ctrl_judge(c4g_ctrl_t *c, uint64_t woke_ns, bool suspended,
                                          c4g_ctrl_verdict_t *out);
/**
 * The reply judged ok (or, suspended, received) at the last c4g_ctrl_judge, if the packet
 * was cyclic; handed over once. @return C4G_OK (*reply set), C4G_ERR_NULL, C4G_ERR_STATE (none: *reply NULL).
 */
C4G_NODISCARD c4g_status_t c4g_ctrl_take_reply(c4g_ctrl_t *c, const c4g_pc_packet_t **reply);

#ifdef __cplusplus
}
#endif

#endif /* C4GOPEN_CTRL_H */
