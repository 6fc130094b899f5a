/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_loop.h
 * @brief The PC-side loop object: one caller-owned struct holding the session (wire,
 * handshake, trust checks) and the control engine (mode state machines, packet rules,
 * safety filter), driven by three calls per datagram. Included by c4gopen.h.
 *
 * One cycle:
 * @code
 *   c4g_loop_rx(&lp, buf, n, t_rx, &from, &ev);      // decode, init, step
 *   if (ev.cmd != NULL) { fill ev.cmd->ax[i] for the modes it carries; requests on &lp.engine }
 *   if (c4g_loop_reply(&lp, out, sizeof out, &len, NULL) == C4G_OK) { sendto(); c4g_loop_sent(); }
 *   // sleep until the next datagram or next_ns (c4g_loop_deadline), then at next_ns:
 *   //   c4g_loop_poll(&lp, now, &events, &next_ns)
 * @endcode
 * c4g_loop_reply always runs the safety filter on a cyclic reply and answers neutral when
 * the reply cannot be encoded or the control engine has no step for it, so a program
 * built on the loop cannot skip either. The lower
 * layers (c4g_session_*, c4g_engine_*) stay public for programs that need to split the work
 * differently; they then own both duties.
 */
#ifndef C4GOPEN_LOOP_H
#define C4GOPEN_LOOP_H

#include "c4gopen_engine.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Loop configuration; c4g_loop_init with NULL uses the defaults of both layers. */
typedef struct c4g_loop_config {
    c4g_session_config_t session;
    c4g_engine_config_t engine;
} c4g_loop_config_t;

/** Loop counters (the session's and the control engine's own stay in their structs). */
typedef struct c4g_loop_counters {
    uint64_t neutral_replies;   /**< cyclic replies the safety filter could not run on,
                                     answered by the fallback: every axis holds (neutral) */
    uint64_t fallback_drive_off; /**< of those, replies that sent 505 to an arm where the PC
                                      moved some axis */
    uint64_t engine_init_refused;  /**< accepted init packets the control engine refused */
    uint64_t encode_refused;    /**< cyclic replies the encoder refused (NaN, unknown mode) */
    uint64_t limits_refused;    /**< init packets on which the control engine refused the
                                     user limits of an open axis (the engine stays off) */
} c4g_loop_counters_t;

/** The loop's own state: read and written by the library only; its layout may change in
 *  any release. */
typedef struct c4g_loop_priv {
    c4g_engine_config_t engine_cfg;
    c4g_pc_packet_t tx;            /**< the cyclic reply being prepared */
    const c4g_ctrl_packet_t *rx;   /**< the cyclic packet it answers, NULL if none */
    uint32_t prepared;             /**< tx was prepared by c4g_engine_step for rx */
    uint32_t timed;                /**< a cyclic reply was encoded, its send time is due */
    uint32_t due;                  /**< a reply is due (C4G_RX_SYNC, _INIT or _CYCLIC) */
    c4g_axis_limits_t user_lim[C4G_ARMS][C4G_AXES_PER_ARM]; /**< c4g_loop_set_limits */
    uint32_t user_set[C4G_ARMS];   /**< bit j: user_lim[arm][j] is set */
} c4g_loop_priv_t;

/** The PC-side loop. Members are read-only for the caller except through the API; the
 *  control engine `engine` takes requests (c4g_engine_request_*) and limits (c4g_engine_set_limits). */
typedef struct c4g_loop {
    c4g_session_t session;
    c4g_engine_t engine;
    c4g_loop_counters_t counters;
    c4g_engine_report_t report;       /**< of the last step and finish */
    c4g_status_t finish_status;    /**< c4g_safety_filter of the last cyclic reply (505 sent on
                                        C4G_ERR_MISSING_DATA or C4G_ERR_NONFINITE) */
    uint32_t engine_ready;            /**< the control engine holds the accepted init packet */
    c4g_loop_priv_t priv;          /**< internal */
} c4g_loop_t;

/** What one received datagram meant. */
typedef struct c4g_loop_event {
    c4g_rx_kind_t kind;            /**< C4G_RX_DROPPED: nothing to answer */
    uint32_t events;               /**< C4G_EV_* of the session */
    uint32_t engine_events;           /**< C4G_CEV_* of the control step (cyclic packets) */
    const c4g_ctrl_packet_t *pkt;  /**< the controller's cyclic packet, else NULL */
    c4g_pc_packet_t *cmd;          /**< the reply to fill (cyclic packets with the control
                                        engine ready), else NULL; modes are already set and
                                        the fields a mode needs are marked unset */
    c4g_diag_t diag;               /**< with C4G_EV_MALFORMED */
    uint64_t silence_ns;           /**< with C4G_EV_RESUMED */
} c4g_loop_event_t;

/** Start a loop: session in WAIT_INIT, control engine waiting for the init packet.
 *  @return C4G_OK, C4G_ERR_NULL, or the status of the invalid configuration part. */
C4G_NODISCARD c4g_status_t c4g_loop_init(c4g_loop_t *lp, const c4g_loop_config_t *cfg);

/**
 * Feed one received datagram (c4g_session_rx_from trust rules: only the locked controller
 * endpoint steers the loop). An accepted initialization packet (re)starts the control
 * engine; a cyclic packet is stepped through it and its reply prepared in @p ev->cmd.
 * @param[in] from   sender, NULL only for a connect()ed socket
 * @return C4G_OK (including refused datagrams: kind DROPPED); C4G_ERR_NULL, C4G_ERR_ARG,
 *         C4G_ERR_ENDED after 504 (call c4g_loop_init for a new session).
 */
C4G_NODISCARD c4g_status_t c4g_loop_rx(c4g_loop_t *lp, const uint8_t *buf, size_t len, uint64_t now_ns,
                         const c4g_endpoint_t *from, c4g_loop_event_t *ev);

/**
 * Encode the reply due: the sync/init echo, or the cyclic reply after the packet rules and
 * the safety filter (c4g_safety_filter). A cyclic reply the filter cannot run on (the
 * control engine refused the init packet or the packet, the caller changed the reply's axis
 * count, the encoder refused it) is replaced by the fallback: every axis holds
 * (c4g_session_neutral: the applied reference, the controller's current within AzLim,
 * nothing added) and every arm with an axis in a mode where the PC moves it gets 505
 * (counted in counters.neutral_replies and counters.fallback_drive_off).
 * @param[out] rep  the filter's report (flags per axis, events), may be NULL
 * @return C4G_OK (send @p out_len bytes of @p buf); C4G_ERR_STATE nothing is due;
 *         C4G_ERR_NULL; C4G_ERR_CAPACITY when @p cap is too small.
 */
C4G_NODISCARD c4g_status_t c4g_loop_reply(c4g_loop_t *lp, uint8_t *buf, size_t cap, size_t *out_len,
                            c4g_engine_report_t *rep);

/** Record the time the reply left: the cycle time of a cyclic reply (chapter 22
 *  statistics); after a sync or init reply nothing is timed. @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_sent(c4g_loop_t *lp, uint64_t now_ns);

/**
 * The silence and loss check (c4g_session_poll), and the next instant at which it has work:
 * a caller sleeps until the next datagram or @p next_ns, whichever comes first, and polls
 * again then (no fixed timer). The deadline follows from the last accepted datagram, the
 * silence threshold and the loss timeout; C4G_NO_DEADLINE while nothing can time out
 * (waiting for a first start-up, freezing, after the loss or 504).
 * @param[out] events  C4G_EV_SILENCE, C4G_EV_LOST or 0
 * @param[out] next_ns monotonic time of the next check due
 * @return C4G_OK, C4G_ERR_NULL. O(1).
 */
C4G_NODISCARD c4g_status_t c4g_loop_poll(c4g_loop_t *lp, uint64_t now_ns, uint32_t *events,
                                         uint64_t *next_ns);

/** The next deadline c4g_loop_poll would report, without polling (after a datagram: the
 *  sleep until the next one is bounded by it). @return C4G_OK, C4G_ERR_NULL. O(1). */
C4G_NODISCARD c4g_status_t c4g_loop_deadline(const c4g_loop_t *lp, uint64_t *next_ns);

/** The last accepted initialization packet (all zero before the first one).
 *  @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_init_packet(const c4g_loop_t *lp, const c4g_init_t **out);

/** Its axis maps (n_axes 0 before the first accepted init packet).
 *  @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_axis_map(const c4g_loop_t *lp, const c4g_axis_map_t **out);

/** The session's counters and the loop's own (either pointer may be NULL, not both); they
 *  stay valid and current for the loop's lifetime. @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_counters(const c4g_loop_t *lp, const c4g_counters_t **session,
                                             const c4g_loop_counters_t **loop);

/** Chapter 22 timing statistics (c4g_session_timing). @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_timing(const c4g_loop_t *lp, c4g_timing_t *out);

/** The loop's state as a caller reads it (c4g_loop_state). */
typedef struct c4g_loop_state {
    c4g_phase_t phase;        /**< the session's phase */
    bool locked;              /**< peer holds the controller's endpoint */
    c4g_endpoint_t peer;      /**< the controller's endpoint, when locked */
    int32_t last_num;         /**< NUM of the newest accepted packet, -1 none */
    uint32_t drives;          /**< bit a set: arm a reports C4G_STS_MOVING */
    uint64_t silence_ns;      /**< effective silence threshold */
    uint64_t lost_timeout_ns; /**< effective loss timeout */
    bool engine_ready;        /**< the control engine holds the accepted init packet */
    c4g_status_t finish_status; /**< c4g_engine_finish of the last cyclic reply */
} c4g_loop_state_t;

/** A snapshot of the loop's state. @return C4G_OK, C4G_ERR_NULL. O(1). */
C4G_NODISCARD c4g_status_t c4g_loop_state(const c4g_loop_t *lp, c4g_loop_state_t *out);

/** The last cyclic reply prepared (as sent, after the filter or the fallback): valid until
 *  the next c4g_loop_rx. @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_reply_packet(const c4g_loop_t *lp,
                                                 const c4g_pc_packet_t **out);

/** Whether @p from is the controller's endpoint, or none is locked yet (c4g_session_is_peer).
 *  @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_is_peer(const c4g_loop_t *lp, const c4g_endpoint_t *from,
                                            bool *out);

/** The control engine, for requests (c4g_engine_request_*) and queries (c4g_engine_anchor).
 *  @return C4G_OK; C4G_ERR_STATE when it holds no accepted init packet (*out is still set:
 *  requests then return its own errors); C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_loop_engine(c4g_loop_t *lp, c4g_engine_t **out);

/** The control engine, read-only (its kinematics, anchors); as c4g_loop_engine. */
C4G_NODISCARD c4g_status_t c4g_loop_engine_view(const c4g_loop_t *lp, const c4g_engine_t **out);

/**
 * Whether EXIT_FROM_OPEN is under way on @p arm: requested and being sent, or accepted and
 * the arm not back in mode 0 yet (a c4g_engine_request_exit now changes nothing).
 * @param[out] out true while under way
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (arm >= C4G_ARMS), C4G_ERR_STATE (the control
 *         engine holds no init packet). O(1).
 */
C4G_NODISCARD c4g_status_t c4g_loop_exit_pending(const c4g_loop_t *lp, uint32_t arm, bool *out);

/**
 * User limits of logical axis @p axis of @p arm (c4g_axis_limits_t), kept by the loop and
 * applied to the control engine now and after every accepted init packet, so that no
 * restart (506 and a new init packet) lifts them. On an init packet where an open axis's
 * limits are refused (joint limits without the kinematics they need, for example) the
 * control engine stays off: every reply is the fallback (hold, 505 where the PC moves an
 * axis) and counters.limits_refused counts it. Limits of an axis the init packet does not
 * open wait for one that does.
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_ARG (arm, axis); with the engine running, the
 *         status of c4g_engine_set_limits (the limits are then not kept).
 */
C4G_NODISCARD c4g_status_t c4g_loop_set_limits(c4g_loop_t *lp, uint32_t arm, uint32_t axis,
                                               const c4g_axis_limits_t *lim);

/**
 * The limits the safety filter applies to OPEN axis @p axis: the user limits
 * (c4g_engine_set_limits) tightened by the init packet's FollowError and AzLim.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (axis not open), C4G_ERR_STATE (the control
 *         engine holds no init packet). O(1).
 */
C4G_NODISCARD c4g_status_t c4g_loop_limits(const c4g_loop_t *lp, uint32_t axis,
                                           c4g_axis_limits_t *out);

#ifdef __cplusplus
}
#endif

#endif /* C4GOPEN_LOOP_H */
