/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_wire.h
 * @brief libc4gopen wire layer: byte-exact encode/decode of the cyclic packet in both
 *        directions and of the 1200-byte initialization packet, the axis index maps, the
 *        mode vocabulary, and the PC-side session (start-up handshake, trust rules, NUM
 *        policy, counters, chapter 22 timing statistics).
 *
 * Most programs use the loop object of c4gopen_loop.h, which drives this layer and the
 * control engine together and cannot skip the safety filter; this layer stays public for
 * programs that split the work differently (a controller simulator, a capture checker).
 */
#ifndef C4GOPEN_WIRE_H
#define C4GOPEN_WIRE_H

#include "c4gopen_base.h"

#ifdef __cplusplus
extern "C" {
#endif

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

/** @name The wire's little-endian 32-bit words (every field of a datagram is one) */
/**@{*/
/** The unsigned word at @p p (4 bytes are read). */
uint32_t c4g_le_u32(const uint8_t *p);
/** The signed word at @p p (NUM, SMax, the init packet's integers). */
int32_t c4g_le_i32(const uint8_t *p);
/** The IEEE 754 single at @p p (D1..D5, EXT, the init packet's floats), bit for bit. */
float c4g_le_f32(const uint8_t *p);
/**@}*/

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
C4G_NODISCARD c4g_status_t c4g_ctrl_decode(const uint8_t *buf, size_t len, uint32_t n_axes,
                             c4g_ctrl_packet_t *out, c4g_diag_t *diag);
/** Encode a cyclic SMP+ -> PC packet (controller side; simulators). Same checks. */
C4G_NODISCARD c4g_status_t c4g_ctrl_encode(const c4g_ctrl_packet_t *pkt, uint8_t *buf, size_t cap,
                             size_t *out_len);
/** Decode a cyclic PC -> SMP+ packet (controller side). Same contract as c4g_ctrl_decode. */
C4G_NODISCARD c4g_status_t c4g_pc_decode(const uint8_t *buf, size_t len, uint32_t n_axes,
                           c4g_pc_packet_t *out, c4g_diag_t *diag);
/**
 * Encode a cyclic PC -> SMP+ packet. Refuses (never sends) NaN/inf, unknown modes,
 * NUM outside 0..0x7FFF and axis counts outside 1..20.
 */
C4G_NODISCARD c4g_status_t c4g_pc_encode(const c4g_pc_packet_t *pkt, uint8_t *buf, size_t cap,
                           size_t *out_len);

/**
 * The neutral reply to @p rx: it holds, every field means "nothing new". Same NUM (the
 * session applies the NUM policy), INFPAR = CMD = 0, each axis's mode echoed; in an
 * absolute mode (1, 11, 4) D1 is the controller's reported reference and in a mode where
 * the PC closes the loops (1, 11, 2, 12) D5 is the controller's own current (zero there
 * would mean "go to 0" and "no current"); every other field is zero (no addition, no
 * delta, no velocity); in mode 10 (debug echo) D1..D5 are copied back. The current is not
 * bounded here: c4g_session_neutral bounds it by AzLim.
 */
C4G_NODISCARD c4g_status_t c4g_pc_reply_neutral(const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx);

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
C4G_NODISCARD c4g_status_t c4g_init_decode(const uint8_t *buf, size_t len, c4g_init_t *out,
                             c4g_diag_t *diag);
/**
 * Validate a decoded initialization packet: NUM 10, nFieldPck 3, nFieldAx 9,
 * 1 <= nAxOpen <= 20, OpenAx values 0..nAxOpen-1 or 0xFF, each OPEN index used
 * exactly once, period 1..1000 ms, start-up modes (OpenMask) known or 0xFF on open axes
 * (any value, e.g. the field tools' -1, on axes that are not open), all floats finite,
 * AzLim > 0 on open axes and >= 0 elsewhere, FollowError >= 0 (0 means "no threshold").
 */
C4G_NODISCARD c4g_status_t c4g_init_validate(const c4g_init_t *init, c4g_diag_t *diag);
/** Encode an initialization packet (validated first) into 1200 bytes. */
C4G_NODISCARD c4g_status_t c4g_init_encode(const c4g_init_t *init, uint8_t *buf, size_t cap,
                             size_t *out_len);

/** Logical <-> OPEN axis index maps derived from OpenAx. */
typedef struct c4g_axis_map {
    uint32_t n_axes;                                /**< open axes, 1..20 */
    uint8_t arm_of[C4G_MAX_AXES];                   /**< OPEN index -> arm (0..3) */
    uint8_t logical_of[C4G_MAX_AXES];               /**< OPEN index -> logical axis (0..9) */
    uint8_t open_of[C4G_ARMS][C4G_AXES_PER_ARM];    /**< logical -> OPEN index, 0xFF if not open */
    uint8_t n_axes_arm[C4G_ARMS];                   /**< open axes per arm */
} c4g_axis_map_t;

/** Build the index maps from a (validated) initialization packet. */
C4G_NODISCARD c4g_status_t c4g_axis_map_build(const c4g_init_t *init, c4g_axis_map_t *map,
                                c4g_diag_t *diag);

/* ====================================================================== peek */

/** What a datagram is, by its length and content (c4g_peek). */
typedef enum c4g_pkt_kind {
    C4G_PKT_SYNC = 0,   /**< a synchronization packet, or the PC's reply to one */
    C4G_PKT_INIT = 1,   /**< the 1200-byte initialization packet, or its echo */
    C4G_PKT_CYCLIC = 2, /**< a cyclic packet of 1..20 axes (12 + 36 n bytes) */
    C4G_PKT_FOREIGN = 3 /**< none of these: not C4G Open */
} c4g_pkt_kind_t;

/** c4g_peek's findings. */
typedef struct c4g_peek {
    c4g_pkt_kind_t kind;
    int32_t num;        /**< the NUM word, -1 under 4 bytes */
    uint32_t n_axes;    /**< SYNC, CYCLIC: axes implied by the length; else 0 */
} c4g_peek_t;

/**
 * Classify a datagram without decoding it: 1200 bytes with nFieldPck 3 and nFieldAx 9 is
 * INIT; 12 + 36 n bytes (n 1..20) is SYNC while @p startup (before the initialization
 * packet, as the field library treats every other datagram then), else CYCLIC; anything
 * else is FOREIGN. The reader still decodes (and may refuse) what it keeps.
 * @return C4G_OK, C4G_ERR_NULL.
 */
C4G_NODISCARD c4g_status_t c4g_peek(const uint8_t *buf, size_t len, bool startup, c4g_peek_t *out);

/* ====================================================================== NUM */

/**
 * Reply sequence-number policy: the one vocabulary of the PC end (which NUM it answers
 * with), the controller end (which NUM it accepts) and the capture analysis.
 */
typedef enum c4g_num_policy {
    C4G_NUM_PLUS_ONE = 0, /**< field behaviour (default): NUM + 1, 0x7FFF wraps to 1 */
    C4G_NUM_ECHO = 1,     /**< manual text: reply with the same NUM */
    C4G_NUM_EITHER = 2    /**< controller end only: either one, the PC's echo of the init
                               packet decides which (a PC end cannot answer "either") */
} c4g_num_policy_t;

/** The NUM counter's modulus: SMP+ counts 0..0x7FFF, then 0. */
#define C4G_NUM_MODULO 0x8000

/**
 * NUM the PC puts in its reply to a packet carrying @p num, under @p policy (PLUS_ONE:
 * num + 1, 0x7FFF and out-of-range values answered with 1; ECHO and EITHER: @p num).
 */
int32_t c4g_reply_num(int32_t num, c4g_num_policy_t policy);
/** NUM of the controller's packet after one carrying @p num: num + 1, 0 after 0x7FFF. */
int32_t c4g_num_next(int32_t num);
/**
 * How far @p to is ahead of @p from on the 15-bit counter: 0..0x7FFF (0: the same NUM,
 * 0x7FFF: one behind). Any int32 values (raw, unvalidated fields) are taken.
 */
int32_t c4g_num_delta(int32_t from, int32_t to);
/** true if a reply carrying @p got answers the packet carrying @p sent under @p policy. */
bool c4g_num_accepts(c4g_num_policy_t policy, int32_t sent, int32_t got);
/**
 * true if a reply carrying @p got answers one of the @p window packets before the one
 * carrying @p cur under @p policy: a late reply, not a wrong one.
 */
bool c4g_num_answers_recent(c4g_num_policy_t policy, int32_t cur, int32_t got, int32_t window);
/** "plus-one", "echo", "either"; "unknown" for any other value. */
const char *c4g_num_policy_name(int policy);
/**
 * The policy named @p name: "plus-one", "echo" or "either" (the tools' spellings).
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (unknown name).
 */
C4G_NODISCARD c4g_status_t c4g_num_policy_parse(const char *name, c4g_num_policy_t *out);

/** Session phase (PC side). */
typedef enum c4g_phase {
    C4G_PHASE_WAIT_INIT = 0,  /**< answering synchronization packets, waiting for the init packet */
    C4G_PHASE_POST_SYNC = 1,  /**< init received; answering the 2 post-init sync packets */
    C4G_PHASE_CYCLIC = 2,     /**< regular communication */
    C4G_PHASE_ENDED = 3,      /**< 504 received: end of communication */
    C4G_PHASE_LOST = 4,       /**< no packet for longer than the loss timeout */
    C4G_PHASE_REFUSED = 5     /**< refused (C4G_EV_INIT_CONFLICT, C4G_EV_CONTENDED): nothing is
                                   accepted or answered; once the controller has been silent
                                   for the loss timeout the phase is LOST, and a new start-up
                                   is served */
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
#define C4G_EV_INIT_CONFLICT 0x8000U /**< a second initialization packet that differs from the
                                          one accepted in the same start-up (or, after 506, from
                                          the session's): both refused, phase REFUSED; diag
                                          names the first field that differs */
#define C4G_EV_CONTENDED 0x10000U    /**< a start-up packet (sync or init) from another endpoint
                                          while the session's start-up runs: two endpoints claim
                                          the session, both refused, phase REFUSED */
#define C4G_EV_NEW_PEER 0x20000U     /**< a new start-up after a loss came from another endpoint
                                          than the lost controller's: served, the session locks
                                          to it (a cold restart may change the port) */
#define C4G_EV_END_UNEXPECTED 0x40000U /**< with C4G_EV_END: the 504 came while an axis of the
                                          previous packet was in an operating mode (manual
                                          15.4 presets mode 0): forged or out of procedure */
#define C4G_EV_REFUSED 0x80000U      /**< datagram dropped because the session is REFUSED */
#define C4G_EV_SYNC_EXCESS 0x100000U /**< a sync beyond C4G_SYNC_REPLY_BUDGET (start-up): not
                                          answered; a start-up silent for the loss timeout
                                          starts afresh */
/**@}*/

/** @name Default ceilings of c4g_session_config_t */
/**@{*/
#define C4G_AZLIM_MAX_DEFAULT 200.0F       /**< largest AzLim accepted [A] */
#define C4G_FOLLOW_ERROR_MAX_DEFAULT 50.0F /**< largest FollowError accepted [motor turns] */
#define C4G_HANDSHAKE_SYNCS 9U             /**< syncs before the init packet (field) */
#define C4G_SYNC_REPLY_BUDGET 18U          /**< syncs answered before an init packet: the
                                                handshake's 9, each duplicated on the path */
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
    float az_lim_max;            /**< the largest AzLim of an open axis this cell accepts [A]:
                                      an initialization packet above it is refused (finite,
                                      > 0; default C4G_AZLIM_MAX_DEFAULT) */
    float follow_error_max;      /**< the largest FollowError window accepted [motor turns]
                                      (finite, > 0; default C4G_FOLLOW_ERROR_MAX_DEFAULT). 0 in
                                      the packet stays "no threshold" (field fact) */
} c4g_session_config_t;

/** Fill @p cfg with the field defaults. */
C4G_NODISCARD c4g_status_t c4g_session_config_default(c4g_session_config_t *cfg);

/** Why datagrams were rejected (index of c4g_counters_t.malformed). */
typedef enum c4g_malformed {
    C4G_MAL_LENGTH = 0, C4G_MAL_NUM, C4G_MAL_MODE, C4G_MAL_NONFINITE,
    C4G_MAL_INIT,
    C4G_MAL_PHASE, /**< valid datagram refused in this phase: an initialization packet
                        outside the start-up or after 506 */
    C4G_MAL_CEILING, /**< an initialization packet above the PC's ceilings (az_lim_max,
                          follow_error_max): diag names the field, arm, axis, value */
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
    uint64_t init_conflicts;     /**< C4G_EV_INIT_CONFLICT events */
    uint64_t contended;          /**< C4G_EV_CONTENDED events */
    uint64_t new_peers;          /**< C4G_EV_NEW_PEER events */
    uint64_t end_unexpected;     /**< C4G_EV_END_UNEXPECTED events */
    uint64_t refused;            /**< datagrams dropped in the REFUSED phase */
    uint64_t sync_excess;        /**< syncs beyond C4G_SYNC_REPLY_BUDGET: not answered */
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

/** The library's own state of a session: read and written by the library only. Its layout
 *  may change in any release; read what a caller needs through the public members above
 *  it and the c4g_session_* functions. */
typedef struct c4g_session_priv {
    c4g_ctrl_packet_t rx[2];     /**< decode double buffer; rx[cur] is the last accepted */
    uint32_t cur;                /**< index of the last accepted cyclic packet in rx[] */
    uint32_t rx_mixed_modes;     /**< rx[cur]'s axes do not all carry one mode */
    int32_t last_num;            /**< NUM of the newest accepted packet, -1 none */
    int32_t pending_num;         /**< NUM to answer (after an accepted rx), -1 none */
    c4g_rx_kind_t pending_kind;  /**< what the pending reply answers */
    uint32_t pending_len;        /**< bytes of the pending sync/init packet to echo */
    uint8_t pending_raw[C4G_INIT_SIZE]; /**< received bytes echoed in sync/init replies */
    uint32_t pending_reply_len;  /**< size of the pending sync/init reply */
    uint8_t init_raw[C4G_INIT_SIZE]; /**< the accepted initialization packet's bytes */
    uint32_t startup_init;       /**< an init was accepted and no cyclic packet came since */
    uint32_t startup_only;       /**< lost after a refusal: only a new start-up may follow */
    uint32_t sync_seen;          /**< sync packets since the last init */
    uint32_t post_sync_left;     /**< post-init sync packets still expected */
    uint32_t restart_pending;    /**< 506 seen, init packet expected without sync */
    uint32_t frozen;             /**< passive freezing (502 .. 503) */
    uint32_t frozen_active;      /**< active freezing: PC sent 500, until its EXIT_FROM_OPEN */
    uint64_t last_rx_ns;         /**< time of the newest accepted datagram */
    uint64_t last_cyclic_ns;     /**< time of the previous cyclic packet */
    uint64_t pending_rx_ns;      /**< receive time of the packet being answered */
    uint32_t have_cyclic_time;
    uint32_t silent;             /**< a silence is under way (C4G_EV_SILENCE reported) */
    uint32_t neutral_n;          /**< axes in neutral_axes, 0 none */
    int32_t neutral_mode;        /**< the mode of every axis in neutral_axes */
    uint32_t neutral_data;       /**< that mode's hold carries data (not the template's) */
    uint8_t neutral_axes[C4G_MAX_AXES * C4G_AXIS_SIZE]; /**< the axes of a neutral reply */
} c4g_session_priv_t;

/** A PC-side session. Caller-owned storage; the public members are read-only for the
 *  caller (c4g_session_* functions write them). */
typedef struct c4g_session {
    c4g_session_config_t cfg;
    c4g_phase_t phase;
    c4g_init_t init;             /**< last accepted initialization packet */
    c4g_axis_map_t map;          /**< its axis maps */
    c4g_counters_t counters;
    c4g_timing_t timing;
    uint32_t drives;             /**< bit a set: arm a reports C4G_STS_MOVING */
    uint64_t lost_timeout_ns;    /**< effective loss timeout */
    uint64_t silence_ns;         /**< effective silence threshold */
    uint32_t peer_locked;        /**< peer holds the controller's endpoint */
    c4g_endpoint_t peer;         /**< the controller's endpoint (address and port) */
    c4g_session_priv_t priv;     /**< internal */
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
C4G_NODISCARD c4g_status_t c4g_session_init(c4g_session_t *s, const c4g_session_config_t *cfg);

/**
 * Feed one received datagram and the endpoint it came from. Classifies it, validates it,
 * updates counters and NUM statistics, and arms the reply. Trust rules (docs/robustness.md):
 * - the session locks to the endpoint of its first accepted packet; a datagram from any
 *   other endpoint is foreign (C4G_EV_FOREIGN, counted by shape, never decoded into the
 *   session, never answered) until the controller is lost, when a new start-up
 *   (synchronization packets) from any endpoint is served and locks the session anew;
 * - an initialization packet is accepted once per start-up, within the configured ceilings
 *   (above: C4G_MAL_CEILING); a different one in the same start-up, or after 506 one that
 *   differs from the session's, refuses the session (C4G_EV_INIT_CONFLICT, phase REFUSED:
 *   nothing accepted or answered until the controller is silent for the loss timeout);
 * - during the start-up, a start-up packet from another endpoint refuses the session too
 *   (C4G_EV_CONTENDED); after a loss, a start-up from another endpoint is served and
 *   reported (C4G_EV_NEW_PEER);
 * - a synchronization packet must decode as a cyclic packet of 1..20 axes (finite values,
 *   known modes): its reply never echoes a non-finite value or answers a datagram smaller
 *   than a cyclic packet; the handshake's syncs (up to C4G_SYNC_REPLY_BUDGET, and the
 *   post-init ones) get the 732-byte reply, more are not answered (C4G_EV_SYNC_EXCESS);
 * - a duplicate or an older NUM is dropped (counted, not answered, not delivered).
 * A datagram refused for any of these is not a failure of the call: it returns C4G_OK with
 * kind DROPPED (nothing to answer) and EV_MALFORMED or EV_FOREIGN.
 * @param[in] from   sender; NULL only when the socket itself admits nothing but the
 *                   controller (a connect()ed socket): then no endpoint check is made
 * @param[in] now_ns monotonic receive time
 * @return C4G_OK; C4G_ERR_NULL; C4G_ERR_ARG (@p from with addr_len > 16);
 *         C4G_ERR_ENDED after 504 (call c4g_session_init).
 */
C4G_NODISCARD c4g_status_t c4g_session_rx_from(c4g_session_t *s, const uint8_t *buf, size_t len,
                                 uint64_t now_ns, const c4g_endpoint_t *from,
                                 c4g_rx_result_t *res);

/** c4g_session_rx_from with no endpoint check (a socket connect()ed to the controller). */
C4G_NODISCARD c4g_status_t c4g_session_rx(c4g_session_t *s, const uint8_t *buf, size_t len,
                            uint64_t now_ns, c4g_rx_result_t *res);

/** true if @p from is the session's controller endpoint (or none is locked yet). */
bool c4g_session_is_peer(const c4g_session_t *s, const c4g_endpoint_t *from);

/**
 * Encode the reply to the last accepted datagram. For SYNC and INIT the reply is
 * built by the library (@p tx may be NULL); for CYCLIC @p tx is required, its NUM
 * is overwritten by the policy and its axis count must equal the session's.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_STATE (nothing to answer), C4G_ERR_AXES,
 *         C4G_ERR_CAPACITY, or an encoder error (NaN, unknown mode).
 */
C4G_NODISCARD c4g_status_t c4g_session_reply(c4g_session_t *s, const c4g_pc_packet_t *tx,
                               uint8_t *buf, size_t cap, size_t *out_len);

/**
 * The neutral reply to @p rx (c4g_pc_reply_neutral) with the session's bounds: the current
 * it holds in modes 1, 11, 2, 12 within +-AzLim of the accepted init packet.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_STATE (no init packet yet), C4G_ERR_AXES.
 */
C4G_NODISCARD c4g_status_t c4g_session_neutral(const c4g_session_t *s, const c4g_ctrl_packet_t *rx,
                                               c4g_pc_packet_t *tx);

/**
 * c4g_session_reply with the neutral reply (c4g_session_neutral) to a pending cyclic
 * packet, encoded straight from the decoded packet: the same bytes for less work, the
 * values it echoes having been checked when they were received. SYNC and INIT are answered
 * as by c4g_session_reply.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_STATE (nothing to answer) or C4G_ERR_CAPACITY.
 */
C4G_NODISCARD c4g_status_t c4g_session_reply_neutral(c4g_session_t *s, uint8_t *buf, size_t cap,
                                                     size_t *out_len);

/** Record the time the reply was sent (cycle time statistics). */
C4G_NODISCARD c4g_status_t c4g_session_sent(c4g_session_t *s, uint64_t now_ns);

/**
 * Check the controller's silence when no datagram arrived. Past the silence threshold it
 * sets C4G_EV_SILENCE (once per silence: the session goes on and resumes with the next
 * packet, C4G_EV_RESUMED); past the loss timeout C4G_EV_LOST (once) and the phase LOST: the
 * session is over, and a new start-up of the controller is served from its first
 * synchronization packet. Passive freezing (502 .. 503 from the controller) and active
 * freezing (a reply of ours carrying 500, until a reply of ours carries EXIT_FROM_OPEN)
 * suspend both: manual 15.1 and 15.3.
 */
C4G_NODISCARD c4g_status_t c4g_session_poll(c4g_session_t *s, uint64_t now_ns, uint32_t *events);

/** Copy the chapter 22 statistics, with jitter computed against the init period. */
C4G_NODISCARD c4g_status_t c4g_session_timing(const c4g_session_t *s, c4g_timing_t *out);

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

/* ====================================================================== modes */

/** @name Mode flags (c4g_mode_info_t.flags) */
/**@{*/
#define C4G_MF_AVAILABLE 0x01U  /**< available on the controller (may be generated) */
#define C4G_MF_PC_TRAJ 0x02U    /**< the PC generates (all or part of) the trajectory */
#define C4G_MF_PC_LOOPS 0x04U   /**< the PC closes the position/velocity loops */
#define C4G_MF_SPECIAL 0x08U    /**< special mode 500..508 */
#define C4G_MF_STANDBY 0x10U    /**< auxiliary stand-by / exit mode (11, 12, 14, 15, 17, 170) */
#define C4G_MF_PC_REQUEST 0x20U /**< a mode only the PC sends (505, 508) */
/**@}*/

/** @name PC -> SMP+ fields (bit mask) */
/**@{*/
#define C4G_PCF_D1 0x01U /**< target_pos */
#define C4G_PCF_D2 0x02U /**< target_vel */
#define C4G_PCF_D3 0x04U /**< measure */
#define C4G_PCF_D4 0x08U /**< vel_add */
#define C4G_PCF_D5 0x10U /**< current_add */
/**@}*/

/**
 * @name Mode rules (c4g_mode_info_t.rules): what the controller does with the PC's fields
 * in a mode, and so what the safety filter bounds. The controller's reference of an
 * integrating mode is the SMP+ target D1 it reports.
 */
/**@{*/
#define C4G_MR_ABS 0x0100U    /**< D1 is the absolute position reference (1, 11, 4) */
#define C4G_MR_INT_D1 0x0200U /**< the controller adds D1 to its reference each tick (7) */
#define C4G_MR_INT_D2 0x0400U /**< ... integrates D2 into its target, fig. 14.1 (5) */
#define C4G_MR_INT_D4 0x0800U /**< ... integrates the velocity addition D4 (8) */
#define C4G_MR_VEL 0x1000U    /**< D2 is a velocity reference: |D2| <= max_vel */
#define C4G_MR_VADD 0x2000U   /**< D4 is a velocity contribution: |D4| <= max_vel */
#define C4G_MR_CUR 0x4000U    /**< D5 is the current */
#define C4G_MR_DCUR 0x8000U   /**< D5 is added to the controller's current (9) */
#define C4G_MR_FE 0x10000U    /**< following error checked: the PC moves the robot */
#define C4G_MR_COPY 0x20000U  /**< mode 0': the PC copies the controller's data back */
/**@}*/

/** @name Where an arm may come from into a mode (c4g_mode_info_t.from) */
/**@{*/
#define C4G_FROM_ANY (-1)  /**< from any mode */
#define C4G_FROM_IDLE (-2) /**< from mode 0 or 0' (and, for operating modes, 501 / 503) */
/**@}*/

/**
 * THE MODE TABLE: the one definition of the mode vocabulary (field facts; manual chapters
 * 13, 14, 15, 24). Every code constant, lookup, name, predicate, required-field set,
 * filter rule and transition rule of the library derives from it. Columns:
 * X(ID, code, flags, PC fields, rules, operating mode, from, name, description), where
 * `from` is C4G_FROM_ANY, C4G_FROM_IDLE or the one mode the arm must come from (a stand-by
 * mode may also follow its operating mode). Adding a mode is one row here plus its tests
 * (docs/architecture.md, "How to add a mode").
 */
/* Deviation D-05 (MISRA 20.7): X is a macro name, applied to each row. */
/* cppcheck-suppress misra-c2012-20.7 */
#define C4G_MODE_TABLE(X)                                                                     \
    X(0, 0, C4G_MF_AVAILABLE, 0U, 0U, 0, C4G_FROM_ANY, "MODE_0",                                 \
      "SMP+ generates the trajectory and closes the loops; PC data ignored")                    \
    X(0_DEBUG, 10, C4G_MF_AVAILABLE, C4G_PCF_D1 | C4G_PCF_D2, C4G_MR_COPY, 10, C4G_FROM_IDLE,    \
      "MODE_0_DEBUG", "mode 0': debug echo, the PC copies D1..D5 back")                          \
    X(1, 1, C4G_MF_AVAILABLE | C4G_MF_PC_TRAJ | C4G_MF_PC_LOOPS,                                 \
      C4G_PCF_D1 | C4G_PCF_D2 | C4G_PCF_D4 | C4G_PCF_D5,                                         \
      C4G_MR_ABS | C4G_MR_VEL | C4G_MR_VADD | C4G_MR_CUR | C4G_MR_FE, 1, C4G_FROM_IDLE,          \
      "MODE_1", "PC generates the trajectory and closes the loops (currents)")                  \
    X(1_STANDBY, 11, C4G_MF_AVAILABLE | C4G_MF_PC_TRAJ | C4G_MF_PC_LOOPS | C4G_MF_STANDBY,       \
      C4G_PCF_D1 | C4G_PCF_D2 | C4G_PCF_D4 | C4G_PCF_D5,                                         \
      C4G_MR_ABS | C4G_MR_VEL | C4G_MR_VADD | C4G_MR_CUR | C4G_MR_FE, 1, 1, "MODE_1_STANDBY",    \
      "mode 1 exit: PC holds the robot while SMP+ switches back")                               \
    X(2, 2, C4G_MF_AVAILABLE | C4G_MF_PC_LOOPS, C4G_PCF_D4 | C4G_PCF_D5,                         \
      C4G_MR_VADD | C4G_MR_CUR | C4G_MR_FE, 2, C4G_FROM_IDLE, "MODE_2",                          \
      "SMP+ generates the trajectory, the PC closes the loops (currents)")                      \
    X(2_STANDBY, 12, C4G_MF_AVAILABLE | C4G_MF_PC_LOOPS | C4G_MF_STANDBY,                        \
      C4G_PCF_D4 | C4G_PCF_D5, C4G_MR_VADD | C4G_MR_CUR | C4G_MR_FE, 2, 2, "MODE_2_STANDBY",     \
      "mode 2 exit (set by PDL2): PC loops while SMP+ switches back")                           \
    X(3, 3, C4G_MF_PC_LOOPS, C4G_PCF_D5, 0U, 3, C4G_FROM_IDLE, "MODE_3",                         \
      "SMP+ velocity target, PC velocity loop (not available)")                                 \
    X(4, 4, C4G_MF_AVAILABLE | C4G_MF_PC_TRAJ, C4G_PCF_D1 | C4G_PCF_D2,                          \
      C4G_MR_ABS | C4G_MR_VEL | C4G_MR_FE, 4, C4G_FROM_IDLE, "MODE_4",                           \
      "PC generates absolute position targets, SMP+ closes the loops")                          \
    X(4_STANDBY, 14, C4G_MF_AVAILABLE | C4G_MF_STANDBY, 0U, 0U, 4, 4, "MODE_4_STANDBY",          \
      "mode 4 stand-by")                                                                        \
    X(5, 5, C4G_MF_AVAILABLE | C4G_MF_PC_TRAJ, C4G_PCF_D1 | C4G_PCF_D2,                          \
      C4G_MR_INT_D2 | C4G_MR_VEL | C4G_MR_FE, 5, C4G_FROM_IDLE, "MODE_5",                        \
      "PC generates relative position targets, SMP+ closes the loops")                          \
    X(5_STANDBY, 15, C4G_MF_AVAILABLE | C4G_MF_STANDBY, 0U, 0U, 5, 5, "MODE_5_STANDBY",          \
      "mode 5 stand-by")                                                                        \
    X(6, 6, C4G_MF_PC_TRAJ, C4G_PCF_D2, 0U, 6, C4G_FROM_IDLE, "MODE_6",                          \
      "PC generates velocity targets (not available)")                                          \
    X(7, 7, C4G_MF_AVAILABLE | C4G_MF_PC_TRAJ, C4G_PCF_D1, C4G_MR_INT_D1 | C4G_MR_FE, 7,         \
      C4G_FROM_IDLE, "MODE_7", "PC adds a position delta to the SMP+ trajectory")               \
    X(7_STANDBY, 17, C4G_MF_AVAILABLE | C4G_MF_STANDBY, 0U, 0U, 7, 7, "MODE_7_STANDBY",          \
      "mode 7 exit: SMP+ ends its motion, PC sends a null delta")                               \
    X(7_STANDBY_EXIT, 170, C4G_MF_AVAILABLE | C4G_MF_STANDBY, 0U, 0U, 7, 17,                     \
      "MODE_7_STANDBY_EXIT", "mode 7 exit: null references, then mode 0")                       \
    X(8, 8, C4G_MF_AVAILABLE, C4G_PCF_D4, C4G_MR_INT_D4 | C4G_MR_VADD | C4G_MR_FE, 8,            \
      C4G_FROM_IDLE, "MODE_8", "PC adds a velocity contribution to the SMP+ trajectory")        \
    X(9, 9, C4G_MF_AVAILABLE, C4G_PCF_D5, C4G_MR_DCUR | C4G_MR_FE, 9, C4G_FROM_IDLE, "MODE_9",   \
      "PC adds a current contribution to the SMP+ control")                                     \
    X(101, 101, 0U, C4G_PCF_D3, 0U, 101, C4G_FROM_IDLE, "MODE_101",                              \
      "accelerometer measure from the PC (not available)")                                      \
    X(102, 102, 0U, C4G_PCF_D3, 0U, 102, C4G_FROM_IDLE, "MODE_102",                              \
      "vision measure from the PC (not available)")                                             \
    X(103, 103, 0U, C4G_PCF_D3, 0U, 103, C4G_FROM_IDLE, "MODE_103",                              \
      "force measure from the PC (not available)")                                              \
    X(201, 201, C4G_MF_PC_TRAJ, 0U, 0U, 201, C4G_FROM_IDLE, "MODE_201",                          \
      "PC cartesian position target (not available)")                                           \
    X(202, 202, C4G_MF_PC_TRAJ, 0U, 0U, 202, C4G_FROM_IDLE, "MODE_202",                          \
      "PC cartesian position delta (not available)")                                            \
    X(FREEZING_A, 500, C4G_MF_AVAILABLE | C4G_MF_SPECIAL, 0U, 0U, 500, C4G_FROM_IDLE,            \
      "FREEZING_A", "active freezing: SMP+ stops checking the PC (from mode 0)")                 \
    X(DRIVING_ON, 501, C4G_MF_AVAILABLE | C4G_MF_SPECIAL, 0U, 0U, 501, C4G_FROM_IDLE,            \
      "DRIVING_ON", "drive on in progress: mode requests are ignored")                          \
    X(FREEZING_P_IN, 502, C4G_MF_AVAILABLE | C4G_MF_SPECIAL, 0U, 0U, 502, C4G_FROM_ANY,          \
      "FREEZING_P_IN", "passive freezing: SMP+ stops sending")                                  \
    X(FREEZING_P_OUT, 503, C4G_MF_AVAILABLE | C4G_MF_SPECIAL, 0U, 0U, 503, 502,                  \
      "FREEZING_P_OUT", "passive freezing over")                                                \
    X(EXIT_OPEN, 504, C4G_MF_AVAILABLE | C4G_MF_SPECIAL, 0U, 0U, 504, C4G_FROM_ANY, "EXIT_OPEN", \
      "end of communication")                                                                   \
    X(DRIVE_OFF, 505, C4G_MF_AVAILABLE | C4G_MF_SPECIAL | C4G_MF_PC_REQUEST, 0U, 0U, 505,        \
      C4G_FROM_ANY, "DRIVE_OFF", "PC request: drive off")                                       \
    X(SVR_RESTART, 506, C4G_MF_AVAILABLE | C4G_MF_SPECIAL, 0U, 0U, 506, C4G_FROM_ANY,            \
      "SVR_RESTART", "client restart: a new initialization packet follows")                     \
    X(FOLLOW_ERROR, 508, C4G_MF_AVAILABLE | C4G_MF_SPECIAL | C4G_MF_PC_REQUEST, 0U, 0U, 508,     \
      C4G_FROM_ANY, "FOLLOW_ERROR", "PC request: following error")

/** Mode codes (SMax values): C4G_MODE_0, C4G_MODE_1_STANDBY, C4G_MODE_DRIVE_OFF ... */
/* Deviation D-05 (MISRA 20.10): each code constant is C4G_MODE_ pasted to the row id. */
/* cppcheck-suppress misra-c2012-20.10 */
#define C4G_MODE_CODE_(id, code, flags, fields, rules, op, from, name, text) C4G_MODE_##id = (code),
enum { C4G_MODE_TABLE(C4G_MODE_CODE_) C4G_MODE_CODE_END_ = -1 };

/** One row of the mode table. */
typedef struct c4g_mode_info {
    int32_t code;            /**< SMax value */
    uint32_t flags;          /**< C4G_MF_* */
    uint32_t pc_fields;      /**< C4G_PCF_* the PC must fill when it sends this mode */
    uint32_t rules;          /**< C4G_MR_*: what the controller does with the fields */
    int32_t operating;       /**< operating mode it belongs to (1 for 11, 7 for 170), or itself */
    int32_t from;            /**< C4G_FROM_ANY, C4G_FROM_IDLE or the mode it must follow */
    const char *name;        /**< constant name, e.g. "MODE_1_STANDBY" */
    const char *description; /**< one line: who generates what */
} c4g_mode_info_t;

/** The table row of @p mode, NULL for a code the protocol does not define. O(1). */
const c4g_mode_info_t *c4g_mode_find(int32_t mode);
/** Copy the table row of @p mode into @p out. @return OK, NULL, C4G_ERR_MODE (unknown). */
C4G_NODISCARD c4g_status_t c4g_mode_info(int32_t mode, c4g_mode_info_t *out);
/** true if @p mode is a mode code the protocol defines. */
bool c4g_mode_is_known(int32_t mode);
/** C4G_MF_* flags of @p mode, 0 for an unknown code. O(1). */
uint32_t c4g_mode_flags(int32_t mode);
/** Constant name of @p mode ("MODE_4"), "UNKNOWN" for an unknown code. */
const char *c4g_mode_name(int32_t mode);
/** One-line description of @p mode, "unknown mode" for an unknown code. */
const char *c4g_mode_description(int32_t mode);
/** true if @p mode is available on the controller (never generate the others). */
bool c4g_mode_is_available(int32_t mode);
/** true if the PC generates all or part of the trajectory in @p mode (1, 11, 4, 5, 7 ...). */
bool c4g_mode_pc_trajectory(int32_t mode);
/** true if the PC closes the loops in @p mode (1, 11, 2, 12, 3). */
bool c4g_mode_pc_loops(int32_t mode);
/** true if @p mode is a special mode (500..508). */
bool c4g_mode_is_special(int32_t mode);
/** true if @p mode is an auxiliary stand-by / exit mode (11, 12, 14, 15, 17, 170). */
bool c4g_mode_is_standby(int32_t mode);
/** C4G_PCF_* fields the PC must fill when its reply carries @p mode (0 for unknown). */
uint32_t c4g_mode_pc_fields(int32_t mode);
/** C4G_MR_* rules of @p mode (0 for unknown). */
uint32_t c4g_mode_rules(int32_t mode);
/** Operating mode @p mode belongs to (11 -> 1, 170 -> 7, 4 -> 4); -1 for unknown. */
int32_t c4g_mode_operating(int32_t mode);
/**
 * true if the controller may legitimately move an arm from mode @p from to mode @p to
 * (chapters 13, 15, 24: through mode 0, stand-by sequences 1->11->0, 2->12->0,
 * 7->17->170->0, forced returns to 0, special modes). Same mode: true.
 */
bool c4g_mode_transition_ok(int32_t from, int32_t to);

#ifdef __cplusplus
}
#endif

#endif /* C4GOPEN_WIRE_H */
