/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen.h
 * @brief libc4gopen: the C4G Open real-time protocol, PC side and controller side.
 *
 * INTEGRATION
 *   Include this one header and link libc4gopen.a (or -lc4gopen). The library is
 *   C99, allocation-free and I/O-free: it never calls malloc, stdio, sockets or a
 *   clock. All state lives in structs the caller owns (stack, static or shared
 *   memory); buffers are passed in as (pointer, length/capacity).
 *
 * ARCHITECTURE
 *   Wire layer (this header): byte-exact encode/decode of the cyclic packet in both
 *   directions and of the 1200-byte initialization packet, the axis index maps,
 *   and the PC-side session engine (start-up handshake, NUM policy, counters,
 *   chapter 22 timing statistics). The control layer (c4gopen_control.h: modes,
 *   safety filter, kinematics) and the cell protocol codec (c4gopen_cell.h) are
 *   included at the end of this header.
 *
 *   A PC-side real-time loop is:
 *     n = recvfrom(...);  t_rx = now();
 *     c4g_session_rx(&s, buf, n, t_rx, &rx);             decode + step
 *     ... compute the reply into a c4g_pc_packet_t ...
 *     c4g_session_reply(&s, &tx, out, sizeof out, &len);   encode
 *     sendto(..., out, len, ...);  c4g_session_sent(&s, now());
 *
 * THREADING
 *   Not thread-safe: one context per loop. No call blocks; every call is O(packet
 *   size) with loop bounds fixed by protocol constants, never by input values.
 *
 * ERRORS
 *   Every function that can fail returns a c4g_status_t: 0 is success, negative
 *   values are errors. c4g_strerror() gives a short constant string. Decoders fill an
 *   optional c4g_diag_t naming the byte offset, field, arm/axis and raw value.
 */
#ifndef C4GOPEN_H
#define C4GOPEN_H

#if !defined(__STDC_VERSION__) || (__STDC_VERSION__ < 199901L)
#error "libc4gopen needs a C99 (or later) compiler"
#endif

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** @name Version (SemVer; any layout change of a public struct bumps MAJOR) */
/**@{*/
#define C4G_VERSION_MAJOR 0
#define C4G_VERSION_MINOR 2
#define C4G_VERSION_PATCH 0
#define C4G_VERSION_STRING "0.2.0"
/**@}*/

/** @name Protocol constants (manual chapters 8 and 10, field facts) */
/**@{*/
#define C4G_ARMS 4U                /**< arms a controller can have */
#define C4G_AXES_PER_ARM 10U       /**< logical axes per arm (GBM_NAX_ARM) */
#define C4G_MAX_AXES 20U           /**< open axes in one packet at most */
#define C4G_HEADER_SIZE 12U        /**< NUM, INFPAR, CMD */
#define C4G_AXIS_SIZE 36U          /**< SM + D1..D5 + EXT1..EXT3 */
#define C4G_MAX_CYCLIC_SIZE 732U   /**< 12 + 36 * 20 */
#define C4G_SYNC_REPLY_SIZE 732U   /**< PC reply to a synchronization packet */
#define C4G_INIT_SIZE 1200U        /**< initialization packet, bytes */
#define C4G_INIT_FIELDS 300U       /**< initialization packet, 4-byte fields */
#define C4G_INIT_NUM 10            /**< NUM carried by the initialization packet */
#define C4G_NUM_MAX 0x7FFF         /**< SMP+ counts NUM in 0..0x7FFF */
#define C4G_OPEN_AX_NONE 0xFF      /**< OpenAx value of a logical axis that is not open */
#define C4G_FIELDS_PER_PACKET 3    /**< nFieldPck */
#define C4G_FIELDS_PER_AXIS 9      /**< nFieldAx */
#define C4G_N_FIELD_TYPES 12U        /**< num, infPar, cmd, sMax, d1..d5, ext1..ext3 */
#define C4G_STS_MOVING 5U          /**< INFPAR byte from SMP+: drives ON on that arm */
#define C4G_EXIT_FROM_OPEN 1U      /**< INFPAR byte from PC: leave the open mode */
#define C4G_DEFAULT_PORT 1000U     /**< PC server UDP port (ERR_C4GOPEN_SKT_UDP) */
/**@}*/

/** Cyclic packet size for @p n open axes: 12 + 36 n. */
#define C4G_CYCLIC_SIZE(n) (C4G_HEADER_SIZE + (C4G_AXIS_SIZE * (n)))

/**
 * Status codes. Stable: values never change meaning. Ranges: -1..-99 wire layer
 * and session, -100..-199 control layer, -200..-299 cell protocol.
 */
typedef enum c4g_status {
    C4G_OK = 0,
    C4G_ERR_NULL = -1,          /**< a required pointer argument is NULL */
    C4G_ERR_LENGTH = -2,        /**< datagram length is not what the field set needs */
    C4G_ERR_CAPACITY = -3,      /**< output buffer too small */
    C4G_ERR_NUM = -4,           /**< NUM outside 0..0x7FFF, or wrong for the phase */
    C4G_ERR_AXES = -5,          /**< axis count out of 1..20 or not the session's */
    C4G_ERR_MODE = -6,          /**< unknown mode code */
    C4G_ERR_NONFINITE = -7,     /**< NaN or infinity in a float field */
    C4G_ERR_RANGE = -8,         /**< a value outside its documented range */
    C4G_ERR_INIT_FIELDS = -9,   /**< nFieldPck != 3 or nFieldAx != 9 */
    C4G_ERR_INIT_MAP = -10,     /**< OpenAx maps inconsistent with nAxOpen or each other */
    C4G_ERR_PERIOD = -11,       /**< sampling period not in 1..1000 ms */
    C4G_ERR_STATE = -12,        /**< call not allowed in the current session phase */
    C4G_ERR_ARG = -13,          /**< an argument is out of its documented range */
    C4G_ERR_ENDED = -14,        /**< the session has ended (504 or lost controller) */
    C4G_ERR_NOT_OPEN = -15,     /**< logical axis is not open */
    /* control layer: -100..-199, cell protocol: -200..-299 */
    C4G_ERR_CTL_FIRST_ = -100,
    C4G_ERR_CELL_FIRST_ = -200
} c4g_status_t;

/** Short, constant, never-NULL description of a status code. */
const char *c4g_strerror(int status);

/** Identifies a wire field in a diagnostic. */
typedef enum c4g_field {
    C4G_FIELD_NONE = 0,
    C4G_FIELD_LENGTH, C4G_FIELD_NUM, C4G_FIELD_INFPAR, C4G_FIELD_CMD,
    C4G_FIELD_SM, C4G_FIELD_D1, C4G_FIELD_D2, C4G_FIELD_D3, C4G_FIELD_D4, C4G_FIELD_D5,
    C4G_FIELD_EXT1, C4G_FIELD_EXT2, C4G_FIELD_EXT3,
    C4G_FIELD_NFIELDPCK, C4G_FIELD_NFIELDAX, C4G_FIELD_NAXOPEN, C4G_FIELD_OPENMASK,
    C4G_FIELD_TYPES, C4G_FIELD_PERIOD, C4G_FIELD_OPENAX, C4G_FIELD_CALDATA,
    C4G_FIELD_AZLIM, C4G_FIELD_VERSION, C4G_FIELD_AXINFO, C4G_FIELD_TXRATE,
    C4G_FIELD_FOLLOWERROR,
    C4G_FIELD_COUNT_
} c4g_field_t;

/** Name of a field as the manual spells it ("NUM", "OpenAx", ...). */
const char *c4g_field_name(c4g_field_t field);

/** What a decoder found wrong. Fill is best effort; all members valid on error. */
typedef struct c4g_diag {
    c4g_status_t status; /**< same value the function returned */
    c4g_field_t field;   /**< offending field */
    uint32_t offset;     /**< byte offset of the field in the datagram */
    int16_t arm;         /**< 0-based arm, -1 when not applicable */
    int16_t axis;        /**< 0-based OPEN index (cyclic) or logical axis (init), -1 n/a */
    int64_t value;       /**< raw value (integer fields, lengths, float bits as uint32) */
} c4g_diag_t;

/** One axis of a packet from the SMP+ (controller) to the PC. */
typedef struct c4g_ctrl_axis {
    int32_t mode;        /**< SMax: axis mode */
    float target_pos;    /**< D1: target position [motor turns] */
    float target_vel;    /**< D2: target velocity [delta motor turns / tick] */
    float actual_pos;    /**< D3: actual position [motor turns] */
    float actual_vel;    /**< D4: actual velocity [delta motor turns / tick] */
    float current_ref;   /**< D5: reference current [A] */
    float ext[3];        /**< EXT1..EXT3 */
} c4g_ctrl_axis_t;

/** One axis of a packet from the PC to the SMP+. */
typedef struct c4g_pc_axis {
    int32_t mode;        /**< SMax: axis mode (echo, or a special mode request) */
    float target_pos;    /**< D1: target position [motor turns] (or delta, by mode) */
    float target_vel;    /**< D2: target velocity [delta motor turns] */
    float measure;       /**< D3: measure [various] */
    float vel_add;       /**< D4: velocity contribution [delta motor turns] */
    float current_add;   /**< D5: current contribution [A] */
    float ext[3];        /**< EXT1..EXT3 */
} c4g_pc_axis_t;

/** A cyclic packet SMP+ -> PC. */
typedef struct c4g_ctrl_packet {
    int32_t num;         /**< NUM, 0..0x7FFF */
    uint32_t infpar;     /**< INFPAR: one byte per arm, byte 0 = ARM 1 */
    uint32_t cmd;        /**< CMD: one byte per arm */
    uint32_t n_axes;     /**< open axes carried, 1..20 */
    c4g_ctrl_axis_t ax[C4G_MAX_AXES]; /**< in OPEN index order */
} c4g_ctrl_packet_t;

/** A cyclic packet PC -> SMP+. */
typedef struct c4g_pc_packet {
    int32_t num;
    uint32_t infpar;
    uint32_t cmd;
    uint32_t n_axes;
    c4g_pc_axis_t ax[C4G_MAX_AXES];
} c4g_pc_packet_t;

/** The per-arm byte @p arm (0..3) of an INFPAR or CMD word; 0 for arm > 3. */
uint8_t c4g_arm_byte(uint32_t word, uint32_t arm);
/** @p word with the byte of @p arm (0..3) replaced by @p value; unchanged for arm > 3. */
uint32_t c4g_arm_byte_set(uint32_t word, uint32_t arm, uint8_t value);

/**
 * Decode a cyclic SMP+ -> PC packet.
 * @param[in]  buf      datagram, @p len bytes (only these are read)
 * @param[in]  n_axes   expected open axes (1..20), or 0 to derive it from @p len
 * @param[out] out      decoded packet (untouched fields zero on error)
 * @param[out] diag     optional (may be NULL): what was wrong
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_LENGTH, C4G_ERR_AXES, C4G_ERR_NUM,
 *         C4G_ERR_MODE, C4G_ERR_NONFINITE. O(n_axes).
 */
c4g_status_t c4g_ctrl_decode(const uint8_t *buf, size_t len, uint32_t n_axes,
                             c4g_ctrl_packet_t *out, c4g_diag_t *diag);
/** Encode a cyclic SMP+ -> PC packet (controller side; simulators). Same checks. */
c4g_status_t c4g_ctrl_encode(const c4g_ctrl_packet_t *pkt, uint8_t *buf, size_t cap,
                             size_t *out_len);
/** Decode a cyclic PC -> SMP+ packet (controller side). Same contract as c4g_ctrl_decode. */
c4g_status_t c4g_pc_decode(const uint8_t *buf, size_t len, uint32_t n_axes,
                           c4g_pc_packet_t *out, c4g_diag_t *diag);
/**
 * Encode a cyclic PC -> SMP+ packet. Refuses (never sends) NaN/inf, unknown modes,
 * NUM outside 0..0x7FFF and axis counts outside 1..20.
 */
c4g_status_t c4g_pc_encode(const c4g_pc_packet_t *pkt, uint8_t *buf, size_t cap,
                           size_t *out_len);

/**
 * The neutral reply to @p rx (field facts): same NUM (the session applies the NUM
 * policy), INFPAR = CMD = 0, each axis's mode echoed, data zero; in mode 10 (debug
 * echo) D1..D5 are copied back.
 */
c4g_status_t c4g_pc_reply_neutral(const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx);

/** The initialization packet (field facts order; indices [arm][logical axis]). */
typedef struct c4g_init {
    int32_t num;            /**< nblip, must be 10 */
    int32_t n_field_pck;    /**< must be 3 */
    int32_t n_field_ax;     /**< must be 9 */
    int32_t n_ax_open;      /**< 1..20 */
    int32_t open_mask[C4G_ARMS][C4G_AXES_PER_ARM]; /**< start-up mode per logical axis */
    int32_t field_type[C4G_N_FIELD_TYPES]; /**< num, infPar, cmd, sMax, d1..d5, ext1..3 */
    int32_t period_ms;      /**< SMP+ sampling period, 1..1000 ms */
    int32_t open_ax[C4G_ARMS][C4G_AXES_PER_ARM];   /**< OPEN index or 0xFF */
    float cal_data[C4G_ARMS][C4G_AXES_PER_ARM];    /**< calibration constants [turns] */
    float az_lim[C4G_ARMS][C4G_AXES_PER_ARM];      /**< max current [A], >= 0 */
    int32_t version_major;
    int32_t version_minor;
    int32_t version_build;
    float ax_info[C4G_ARMS][C4G_AXES_PER_ARM];     /**< kinematic influence coefficients */
    float tx_rate[C4G_ARMS][C4G_AXES_PER_ARM];     /**< transmission ratios */
    float follow_error[C4G_ARMS][C4G_AXES_PER_ARM];/**< thresholds [turns]; 0 = none */
} c4g_init_t;

/** @name Byte offsets of the initialization packet's blocks */
/**@{*/
#define C4G_INIT_OFF_OPENMASK 16U
#define C4G_INIT_OFF_TYPES 176U
#define C4G_INIT_OFF_PERIOD 224U
#define C4G_INIT_OFF_OPENAX 228U
#define C4G_INIT_OFF_CALDATA 388U
#define C4G_INIT_OFF_AZLIM 548U
#define C4G_INIT_OFF_VERSION 708U
#define C4G_INIT_OFF_AXINFO 720U
#define C4G_INIT_OFF_TXRATE 880U
#define C4G_INIT_OFF_FOLLOWERROR 1040U
/**@}*/

/**
 * Decode and validate an initialization packet (exactly 1200 bytes).
 * @return C4G_OK or the first problem found (see c4g_init_validate), with @p diag.
 */
c4g_status_t c4g_init_decode(const uint8_t *buf, size_t len, c4g_init_t *out,
                             c4g_diag_t *diag);
/**
 * Validate a decoded initialization packet: NUM 10, nFieldPck 3, nFieldAx 9,
 * 1 <= nAxOpen <= 20, OpenAx values 0..nAxOpen-1 or 0xFF, each OPEN index used
 * exactly once, period 1..1000 ms, start-up modes (OpenMask) known or 0xFF on open axes
 * (any value, e.g. the field tools' -1, on axes that are not open), all floats finite,
 * AzLim > 0 on open axes and >= 0 elsewhere, FollowError >= 0 (0 means "no threshold").
 */
c4g_status_t c4g_init_validate(const c4g_init_t *init, c4g_diag_t *diag);
/** Encode an initialization packet (validated first) into 1200 bytes. */
c4g_status_t c4g_init_encode(const c4g_init_t *init, uint8_t *buf, size_t cap,
                             size_t *out_len);
/** The manual's figure 10.1 initialization packet (6 axes on ARM 1, 2 ms). */
c4g_status_t c4g_init_fig10_1(c4g_init_t *out);

/** Logical <-> OPEN axis index maps derived from OpenAx. */
typedef struct c4g_axis_map {
    uint32_t n_axes;                                /**< open axes, 1..20 */
    uint8_t arm_of[C4G_MAX_AXES];                   /**< OPEN index -> arm (0..3) */
    uint8_t logical_of[C4G_MAX_AXES];               /**< OPEN index -> logical axis (0..9) */
    uint8_t open_of[C4G_ARMS][C4G_AXES_PER_ARM];    /**< logical -> OPEN index, 0xFF if not open */
    uint8_t n_axes_arm[C4G_ARMS];                   /**< open axes per arm */
} c4g_axis_map_t;

/** Build the index maps from a (validated) initialization packet. */
c4g_status_t c4g_axis_map_build(const c4g_init_t *init, c4g_axis_map_t *map,
                                c4g_diag_t *diag);

/** Reply sequence-number policy. */
typedef enum c4g_num_policy {
    C4G_NUM_PLUS_ONE = 0, /**< field behaviour (default): NUM + 1, 0x7FFF wraps to 1 */
    C4G_NUM_ECHO = 1      /**< manual text: reply with the same NUM */
} c4g_num_policy_t;

/** NUM the PC puts in its reply to a packet carrying @p num, under @p policy. */
int32_t c4g_reply_num(int32_t num, c4g_num_policy_t policy);

/** Session phase (PC side). */
typedef enum c4g_phase {
    C4G_PHASE_WAIT_INIT = 0,  /**< answering synchronization packets, waiting for the init packet */
    C4G_PHASE_POST_SYNC = 1,  /**< init received; answering the 2 post-init sync packets */
    C4G_PHASE_CYCLIC = 2,     /**< regular communication */
    C4G_PHASE_ENDED = 3,      /**< 504 received: end of communication */
    C4G_PHASE_LOST = 4        /**< no packet for longer than the loss timeout */
} c4g_phase_t;

/** What a received datagram was. */
typedef enum c4g_rx_kind {
    C4G_RX_DROPPED = 0,  /**< malformed or unexpected: no reply must be sent */
    C4G_RX_SYNC = 1,     /**< synchronization packet: reply with c4g_session_reply */
    C4G_RX_INIT = 2,     /**< initialization packet: reply is the 1200-byte echo */
    C4G_RX_CYCLIC = 3    /**< cyclic packet: fill a c4g_pc_packet_t and reply */
} c4g_rx_kind_t;

/** @name Session events (bit mask) */
/**@{*/
#define C4G_EV_INIT 0x0001U          /**< an initialization packet was accepted */
#define C4G_EV_CYCLIC_START 0x0002U  /**< first cyclic packet of the session */
#define C4G_EV_RESTART 0x0004U       /**< 506 seen: a new init packet will follow */
#define C4G_EV_END 0x0008U           /**< 504 seen: end of communication */
#define C4G_EV_LOST 0x0010U          /**< controller silent longer than the loss timeout; set by
                                          c4g_session_poll, or by c4g_session_rx together with
                                          the packet that ended the silence (kind CYCLIC: the
                                          controller is back; SYNC: it restarted cold) */
#define C4G_EV_GAP 0x0020U           /**< NUM skipped one or more packets */
#define C4G_EV_DUPLICATE 0x0040U     /**< same NUM as the previous packet */
#define C4G_EV_OUT_OF_ORDER 0x0080U  /**< NUM older than the previous packet */
#define C4G_EV_MALFORMED 0x0100U     /**< datagram rejected (see diag) */
#define C4G_EV_FREEZE_IN 0x0200U     /**< 502 seen: passive freezing, loss timer off */
#define C4G_EV_FREEZE_OUT 0x0400U    /**< 503 seen: passive freezing over */
#define C4G_EV_DRIVES 0x0800U        /**< an arm's DRIVE ON byte (INFPAR) changed */
#define C4G_EV_FOREIGN 0x1000U       /**< datagram from another endpoint than the session's
                                          controller: counted, never decoded, never answered */
#define C4G_EV_SILENCE 0x2000U       /**< (poll) the controller is silent for longer than the
                                          silence threshold: reported, the session goes on */
#define C4G_EV_RESUMED 0x4000U       /**< (rx) packets again after a silence or a lost
                                          controller; c4g_rx_result_t.silence_ns is its length */
/**@}*/

/**
 * The sender of a datagram, as the caller's socket reports it: the address bytes in network
 * order (4 for IPv4, 16 for IPv6) and the port. The session is locked to the endpoint of the
 * controller's first accepted packet; datagrams from any other endpoint are foreign.
 */
typedef struct c4g_endpoint {
    uint8_t addr[16];
    uint8_t addr_len;   /**< 4 or 16 */
    uint16_t port;      /**< host order */
} c4g_endpoint_t;

/** Session configuration. */
typedef struct c4g_session_config {
    c4g_num_policy_t num_policy; /**< default C4G_NUM_PLUS_ONE */
    uint64_t lost_timeout_ns;    /**< silence that ends the session (lost controller); 0 = 1 s,
                                      the field library's real-time wait in the cyclic phase */
    uint64_t silence_ns;         /**< silence reported as C4G_EV_SILENCE (the session goes on);
                                      0 = 10 periods, after which the controller itself gives up */
    uint32_t post_init_sync;     /**< sync packets after a cold-start init (field: 2) */
} c4g_session_config_t;

/** Fill @p cfg with the field defaults. */
c4g_status_t c4g_session_config_default(c4g_session_config_t *cfg);

/** Why datagrams were rejected (index of c4g_counters_t.malformed). */
typedef enum c4g_malformed {
    C4G_MAL_LENGTH = 0, C4G_MAL_NUM, C4G_MAL_MODE, C4G_MAL_NONFINITE,
    C4G_MAL_INIT,
    C4G_MAL_PHASE, /**< valid datagram refused in this phase: an initialization packet
                        outside the start-up or after 506 */
    C4G_MAL_COUNT_
} c4g_malformed_t;

/** What a foreign datagram looked like (index of c4g_counters_t.foreign). */
typedef enum c4g_foreign {
    C4G_FOREIGN_INIT = 0, /**< 1200 bytes: an initialization packet */
    C4G_FOREIGN_CYCLIC,   /**< the size of one of this session's cyclic packets */
    C4G_FOREIGN_OTHER,    /**< anything else */
    C4G_FOREIGN_COUNT_
} c4g_foreign_t;

/** Session counters: readable at any time. */
typedef struct c4g_counters {
    uint64_t rx;                 /**< datagrams handed to c4g_session_rx */
    uint64_t tx;                 /**< replies encoded by c4g_session_reply */
    uint64_t sync;               /**< synchronization packets accepted */
    uint64_t init;               /**< initialization packets accepted */
    uint64_t cyclic;             /**< cyclic packets accepted */
    uint64_t gaps;               /**< gap events */
    uint64_t missed;             /**< controller packets never seen (sum of gap sizes) */
    uint64_t duplicates;         /**< same NUM as the newest packet: dropped, not answered */
    uint64_t out_of_order;       /**< NUM older than the newest packet: dropped, not answered */
    uint64_t malformed_total;
    uint64_t malformed[C4G_MAL_COUNT_]; /**< by reason */
    uint64_t lost_events;
    uint64_t foreign_total;      /**< datagrams from another endpoint than the controller's */
    uint64_t foreign[C4G_FOREIGN_COUNT_]; /**< by what they looked like */
    uint64_t silences;           /**< C4G_EV_SILENCE events */
    uint64_t longest_silence_ns; /**< longest silence the session rode out or ended on */
} c4g_counters_t;

/** Chapter 22 timing statistics, all in ns, from caller timestamps. */
typedef struct c4g_timing {
    uint64_t samples_cycle;      /**< cycle times measured (rx -> sent) */
    uint64_t samples_inter;      /**< inter-packet intervals measured */
    int64_t nominal_period_ns;   /**< from the init packet */
    int64_t last_cycle_ns;
    int64_t worst_cycle_ns;
    int64_t min_inter_ns;
    int64_t max_inter_ns;
    int64_t min_jitter_ns;       /**< min_inter - nominal */
    int64_t max_jitter_ns;       /**< max_inter - nominal */
    double min_jitter_pct;       /**< min_jitter / nominal * 100 */
    double max_jitter_pct;
} c4g_timing_t;

/** PC-side session context. Members are read-only for the caller. */
typedef struct c4g_session {
    c4g_session_config_t cfg;
    c4g_phase_t phase;
    c4g_init_t init;             /**< last accepted initialization packet */
    c4g_axis_map_t map;          /**< its axis maps */
    c4g_counters_t counters;
    c4g_timing_t timing;
    c4g_ctrl_packet_t rx[2];     /**< decode double buffer; rx[cur] is the last accepted */
    uint32_t cur;                /**< index of the last accepted cyclic packet in rx[] */
    int32_t last_num;            /**< NUM of the newest accepted packet, -1 none */
    int32_t pending_num;         /**< NUM to answer (after an accepted rx), -1 none */
    c4g_rx_kind_t pending_kind;  /**< what the pending reply answers */
    uint32_t pending_len;        /**< bytes of the pending sync/init packet to echo */
    uint8_t pending_raw[C4G_INIT_SIZE]; /**< received bytes echoed in sync/init replies */
    uint32_t sync_seen;          /**< sync packets since the last init */
    uint32_t post_sync_left;     /**< post-init sync packets still expected */
    uint32_t restart_pending;    /**< 506 seen, init packet expected without sync */
    uint32_t frozen;             /**< passive freezing (502 .. 503) */
    uint32_t frozen_active;      /**< active freezing: PC sent 500, until its EXIT_FROM_OPEN */
    uint32_t drives;             /**< bit a set: arm a reports C4G_STS_MOVING */
    uint64_t last_rx_ns;         /**< time of the newest accepted datagram */
    uint64_t last_cyclic_ns;     /**< time of the previous cyclic packet */
    uint64_t pending_rx_ns;      /**< receive time of the packet being answered */
    uint64_t lost_timeout_ns;    /**< effective loss timeout */
    uint64_t silence_ns;         /**< effective silence threshold */
    uint32_t have_cyclic_time;
    uint32_t silent;             /**< a silence is under way (C4G_EV_SILENCE reported) */
    uint32_t peer_locked;        /**< peer holds the controller's endpoint */
    c4g_endpoint_t peer;         /**< the controller's endpoint (address and port) */
} c4g_session_t;

/** Result of one c4g_session_rx call. */
typedef struct c4g_rx_result {
    c4g_rx_kind_t kind;
    uint32_t events;             /**< C4G_EV_* */
    const c4g_ctrl_packet_t *pkt;/**< decoded cyclic packet (kind CYCLIC), else NULL */
    c4g_diag_t diag;             /**< for C4G_EV_MALFORMED */
    uint64_t silence_ns;         /**< with C4G_EV_RESUMED: how long the controller was silent */
} c4g_rx_result_t;

/** Start a session (phase WAIT_INIT). @p cfg may be NULL for the defaults. */
c4g_status_t c4g_session_init(c4g_session_t *s, const c4g_session_config_t *cfg);

/**
 * Feed one received datagram and the endpoint it came from. Classifies it, validates it,
 * updates counters and NUM statistics, and arms the reply. Trust rules (docs/robustness.md):
 * - the session locks to the endpoint of its first accepted packet; a datagram from any
 *   other endpoint is foreign (C4G_EV_FOREIGN, counted by shape, never decoded into the
 *   session, never answered) until the controller is lost, when a new start-up
 *   (synchronization packets) from any endpoint is served and locks the session anew;
 * - an initialization packet is accepted in the start-up phase, or after 506, only;
 * - a synchronization packet must decode as a cyclic packet of 1..20 axes (finite values,
 *   known modes): its 732-byte reply never echoes a non-finite value or answers a datagram
 *   smaller than a cyclic packet;
 * - a duplicate or an older NUM is dropped (counted, not answered, not delivered).
 * A datagram refused for any of these is not a failure of the call: it returns C4G_OK with
 * kind DROPPED (nothing to answer) and EV_MALFORMED or EV_FOREIGN.
 * @param[in] from   sender; NULL only when the socket itself admits nothing but the
 *                   controller (a connect()ed socket): then no endpoint check is made
 * @param[in] now_ns monotonic receive time
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_ARG (@p from with addr_len > 16);
 *         C4G_ERR_ENDED after 504 (call c4g_session_init).
 */
c4g_status_t c4g_session_rx_from(c4g_session_t *s, const uint8_t *buf, size_t len,
                                 uint64_t now_ns, const c4g_endpoint_t *from,
                                 c4g_rx_result_t *res);

/** c4g_session_rx_from with no endpoint check (a socket connect()ed to the controller). */
c4g_status_t c4g_session_rx(c4g_session_t *s, const uint8_t *buf, size_t len,
                            uint64_t now_ns, c4g_rx_result_t *res);

/** 1 if @p from is the session's controller endpoint (or none is locked yet), else 0. */
int c4g_session_is_peer(const c4g_session_t *s, const c4g_endpoint_t *from);

/**
 * Encode the reply to the last accepted datagram. For SYNC and INIT the reply is
 * built by the library (@p tx may be NULL); for CYCLIC @p tx is required, its NUM
 * is overwritten by the policy and its axis count must equal the session's.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_STATE (nothing to answer), C4G_ERR_AXES,
 *         C4G_ERR_CAPACITY, or an encoder error (NaN, unknown mode).
 */
c4g_status_t c4g_session_reply(c4g_session_t *s, const c4g_pc_packet_t *tx,
                               uint8_t *buf, size_t cap, size_t *out_len);

/** Record the time the reply was sent (cycle time statistics). */
c4g_status_t c4g_session_sent(c4g_session_t *s, uint64_t now_ns);

/**
 * Check the controller's silence when no datagram arrived. Past the silence threshold it
 * sets C4G_EV_SILENCE (once per silence: the session goes on and resumes with the next
 * packet, C4G_EV_RESUMED); past the loss timeout C4G_EV_LOST (once) and the phase LOST: the
 * session is over, and a new start-up of the controller is served from its first
 * synchronization packet. Passive freezing (502 .. 503 from the controller) and active
 * freezing (a reply of ours carrying 500, until a reply of ours carries EXIT_FROM_OPEN)
 * suspend both: manual 15.1 and 15.3.
 */
c4g_status_t c4g_session_poll(c4g_session_t *s, uint64_t now_ns, uint32_t *events);

/** Copy the chapter 22 statistics, with jitter computed against the init period. */
c4g_status_t c4g_session_timing(const c4g_session_t *s, c4g_timing_t *out);

/** Controller-side errors of the manual's table 17.1 (raised by simulators). */
typedef enum c4g_ctrl_error {
    C4G_CERR_NONE = 0,
    C4G_CERR_SKT_UDP,            /**< ERR_C4GOPEN_SKT_UDP */
    C4G_CERR_UDP,                /**< ERR_C4GOPEN_UDP */
    C4G_CERR_CONFIG,             /**< ERR_C4GOPEN */
    C4G_CERR_CONFIGURATION_AX,   /**< ERR_C4GOPEN_CONFIGURATION_AX */
    C4G_CERR_UDP_DEBUG,          /**< ERR_C4GOPEN_UDP_DEBUG */
    C4G_CERR_TX_UDP,             /**< ERR_C4GOPEN_TX_UDP */
    C4G_CERR_FOLLOW_ERROR,       /**< ERR_C4GOPEN_FOLLOW_ERROR */
    C4G_CERR_OPT_HW,             /**< ERR_C4GOPEN_OPT_HW */
    C4G_CERR_DRIVEOFF_SERVER,    /**< ERR_C4GOPEN_DRIVEOFF_SERVER */
    C4G_CERR_SET_0_MODALITY,     /**< ERR_C4GOPEN_SET_0_MODALITY */
    C4G_CERR_COUNT_
} c4g_ctrl_error_t;

/** Manual name ("ERR_C4GOPEN_UDP"); "?" for an unknown code. */
const char *c4g_ctrl_error_name(c4g_ctrl_error_t err);
/** Manual message (printf format with %d/%s where the manual has them). */
const char *c4g_ctrl_error_message(c4g_ctrl_error_t err);
/** Manual description (table 17.1, third column). */
const char *c4g_ctrl_error_description(c4g_ctrl_error_t err);

/** @name Mode codes (field facts; manual chapters 14 and 15) */
/**@{*/
#define C4G_MODE_0 0              /**< SMP+ trajectory and loops; PC data ignored */
#define C4G_MODE_0_DEBUG 10       /**< mode 0': debug echo, PC copies D1, D2 back */
#define C4G_MODE_1 1              /**< PC position + velocity loops (currents) */
#define C4G_MODE_1_STANDBY 11
#define C4G_MODE_2 2              /**< PC trajectory + loops */
#define C4G_MODE_2_STANDBY 12
#define C4G_MODE_3 3              /**< not yet available on the controller */
#define C4G_MODE_4 4              /**< PC absolute targets */
#define C4G_MODE_4_STANDBY 14
#define C4G_MODE_5 5              /**< PC relative targets */
#define C4G_MODE_5_STANDBY 15
#define C4G_MODE_6 6              /**< not yet available */
#define C4G_MODE_7 7              /**< PC position addition */
#define C4G_MODE_7_STANDBY 17
#define C4G_MODE_7_STANDBY_EXIT 170
#define C4G_MODE_8 8              /**< PC velocity addition */
#define C4G_MODE_9 9              /**< PC current addition */
#define C4G_MODE_101 101          /**< accelerometer (not yet available) */
#define C4G_MODE_102 102          /**< vision (not yet available) */
#define C4G_MODE_103 103          /**< force (not yet available) */
#define C4G_MODE_201 201          /**< not yet available */
#define C4G_MODE_202 202          /**< not yet available */
#define C4G_MODE_FREEZING_A 500   /**< active freezing */
#define C4G_MODE_DRIVING_ON 501   /**< drive-on in progress */
#define C4G_MODE_FREEZING_P_IN 502
#define C4G_MODE_FREEZING_P_OUT 503
#define C4G_MODE_EXIT_OPEN 504    /**< end of communication */
#define C4G_MODE_DRIVE_OFF 505    /**< PC request: drive off */
#define C4G_MODE_SVR_RESTART 506  /**< client restart */
#define C4G_MODE_FOLLOW_ERROR 508 /**< PC request: following error */
/**@}*/

/** 1 if @p mode is a mode code the protocol defines (field facts list), else 0. */
int c4g_mode_is_known(int32_t mode);

#ifdef __cplusplus
}
#endif

/* Deviation D-03 (MISRA 20.1): the layer headers need the types above. */
/* cppcheck-suppress misra-c2012-20.1 */
#include "c4gopen_control.h"
/* cppcheck-suppress misra-c2012-20.1 */
#include "c4gopen_cell.h"
/* cppcheck-suppress misra-c2012-20.1 */
#include "c4gopen_loop.h"

#endif /* C4GOPEN_H */
