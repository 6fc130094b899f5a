/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_canopen.h
 * @brief libc4gopen CANopen master (CiA 301 / CiA 402) for the cell's platform controller:
 *        frame codecs, SDO client, the boot-up sequence of the Robox CAN master, node
 *        supervision and recovery, PDO process image, DS402 drive state machine.
 *        Usable alone: needs only c4gopen_base.h.
 *
 * TIME
 *   The library reads no clock: every call that needs the time takes it (nanoseconds
 *   of a monotonic clock of the caller's choice, as the rest of the library); received frames carry their own
 *   reception time in c4g_co_frame_t.t_ns.
 *
 * I/O
 *   None. c4g_co_master_rx() takes a received frame; c4g_co_master_poll() runs the
 *   timers; frames to transmit are taken with c4g_co_master_tx() and events with
 *   c4g_co_master_event(), both from bounded queues inside the caller's master.
 *
 * BOOT (docs/canopen.md maps each step to the code)
 *   1 broadcast NMT Enter Pre-Operational; per node, one at a time: 2 SDO upload of
 *   DeviceType 0x1000:00 checked against the configured value; 3 SDO download of
 *   0x1006:00; 4 the watchdog (heartbeat: 0x1017:00; lifeguard: 0x100C:00, 0x100D:00,
 *   0x1017:00 = 0, or 0x1017:00 = 0 first when bit 30 of the configured device type is
 *   set); 5 the PDOs; 6 broadcast NMT Start; 7 SYNC and PDO exchange. A failed step
 *   aborts that node's configuration unless the step's bypass flag is set.
 *
 * HOSTILE FRAMES
 *   A frame that does not fit (wrong length, unknown identifier, unexpected SDO answer,
 *   wrong toggle, remote request) is counted in c4g_co_counters_t and changes nothing
 *   else; c4g_co_master_rx() still returns C4G_OK (the bus is not the caller's fault).
 */
#ifndef C4GOPEN_CANOPEN_H
#define C4GOPEN_CANOPEN_H
#include "c4gopen_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @name Limits (the Robox master: 16 nodes per channel, 4 channels, 4+4 PDOs) */
/**@{*/
#define C4G_CO_MAX_NODES 16U
#define C4G_CO_MAX_CHANNELS 4U
#define C4G_CO_MAX_PDO 4U
#define C4G_CO_MAX_ENTRIES 8U
#define C4G_CO_EMCY_DEPTH 8U
#define C4G_CO_TXQ_LEN 128U
#define C4G_CO_EVQ_LEN 64U
#define C4G_CO_SDO_MAX 64U               /**< largest SDO transfer of the client, bytes */
#define C4G_CO_RECOVERY_POLL_NS 2500000000ULL /**< DeviceType poll of a lost node: every 2.5 s */
#define C4G_CO_DEVTYPE_LG_REVERSE 0x40000000UL /**< bit 30 of the configured device type */
/**@}*/

/** @name Identifiers (11-bit COB-IDs of the predefined connection set) */
/**@{*/
#define C4G_CO_COB_NMT 0x000U
#define C4G_CO_COB_SYNC 0x080U
#define C4G_CO_COB_EMCY 0x080U   /**< + node */
#define C4G_CO_COB_TPDO1 0x180U  /**< + 0x100 * k + node: node transmits */
#define C4G_CO_COB_RPDO1 0x200U  /**< + 0x100 * k + node: node receives */
#define C4G_CO_COB_SDO_TX 0x580U /**< + node: server (node) to client */
#define C4G_CO_COB_SDO_RX 0x600U /**< + node: client to server (node) */
#define C4G_CO_COB_NMT_EC 0x700U /**< + node: heartbeat, boot-up, node guarding */
/**@}*/

/** @name NMT commands and states */
/**@{*/
#define C4G_CO_NMT_START 0x01U
#define C4G_CO_NMT_STOP 0x02U
#define C4G_CO_NMT_PREOP 0x80U
#define C4G_CO_NMT_RESET_NODE 0x81U
#define C4G_CO_NMT_RESET_COMM 0x82U
#define C4G_CO_STATE_BOOTUP 0x00U
#define C4G_CO_STATE_STOPPED 0x04U
#define C4G_CO_STATE_OPERATIONAL 0x05U
#define C4G_CO_STATE_PREOP 0x7FU
#define C4G_CO_STATE_UNKNOWN 0xFFU
/**@}*/

/** @name SDO abort codes (CiA 301, section 7.2.4.3.17) */
/**@{*/
#define C4G_CO_ABORT_TOGGLE 0x05030000UL
#define C4G_CO_ABORT_TIMEOUT 0x05040000UL
#define C4G_CO_ABORT_COMMAND 0x05040001UL
#define C4G_CO_ABORT_BLOCK_SIZE 0x05040002UL
#define C4G_CO_ABORT_SEQUENCE 0x05040003UL
#define C4G_CO_ABORT_CRC 0x05040004UL
#define C4G_CO_ABORT_MEMORY 0x05040005UL
#define C4G_CO_ABORT_ACCESS 0x06010000UL
#define C4G_CO_ABORT_WRITE_ONLY 0x06010001UL
#define C4G_CO_ABORT_READ_ONLY 0x06010002UL
#define C4G_CO_ABORT_NO_OBJECT 0x06020000UL
#define C4G_CO_ABORT_NO_MAP 0x06040041UL
#define C4G_CO_ABORT_MAP_LENGTH 0x06040042UL
#define C4G_CO_ABORT_PARAM_INCOMPAT 0x06040043UL
#define C4G_CO_ABORT_DEVICE_INCOMPAT 0x06040047UL
#define C4G_CO_ABORT_HARDWARE 0x06060000UL
#define C4G_CO_ABORT_TYPE_LENGTH 0x06070010UL
#define C4G_CO_ABORT_TYPE_HIGH 0x06070012UL
#define C4G_CO_ABORT_TYPE_LOW 0x06070013UL
#define C4G_CO_ABORT_NO_SUB 0x06090011UL
#define C4G_CO_ABORT_VALUE 0x06090030UL
#define C4G_CO_ABORT_VALUE_HIGH 0x06090031UL
#define C4G_CO_ABORT_VALUE_LOW 0x06090032UL
#define C4G_CO_ABORT_MAX_MIN 0x06090036UL
#define C4G_CO_ABORT_RESOURCE 0x060A0023UL
#define C4G_CO_ABORT_GENERAL 0x08000000UL
#define C4G_CO_ABORT_STORE 0x08000020UL
#define C4G_CO_ABORT_STORE_LOCAL 0x08000021UL
#define C4G_CO_ABORT_STORE_STATE 0x08000022UL
#define C4G_CO_ABORT_NO_DICTIONARY 0x08000023UL
#define C4G_CO_ABORT_NO_DATA 0x08000024UL
/**@}*/

/** @name DS402 objects and control words */
/**@{*/
#define C4G_CO_OBJ_DEVICE_TYPE 0x1000U
#define C4G_CO_OBJ_CYCLE_PERIOD 0x1006U
#define C4G_CO_OBJ_GUARD_TIME 0x100CU
#define C4G_CO_OBJ_LIFE_FACTOR 0x100DU
#define C4G_CO_OBJ_HEARTBEAT 0x1017U
#define C4G_CO_OBJ_CONTROLWORD 0x6040U
#define C4G_CO_OBJ_STATUSWORD 0x6041U
#define C4G_CO_OBJ_MODES 0x6060U
#define C4G_CO_OBJ_TARGET_POS 0x607AU
#define C4G_CO_OBJ_ACTUAL_POS 0x6064U
#define C4G_CO_MODE_CSP 8U /**< 0x6060: cyclic synchronous position */
#define C4G_CO_CW_DISABLE_VOLTAGE 0x0000U
#define C4G_CO_CW_QUICK_STOP 0x0002U
#define C4G_CO_CW_SHUTDOWN 0x0006U
#define C4G_CO_CW_SWITCH_ON 0x0007U
#define C4G_CO_CW_ENABLE_OP 0x000FU
#define C4G_CO_CW_FAULT_RESET 0x0080U
/**@}*/

/** A CAN 2.0A frame. */
typedef struct c4g_co_frame {
    uint64_t t_ns;   /**< reception (or transmission) time, caller's clock */
    uint16_t id;     /**< 11-bit identifier, 0..0x7FF */
    uint8_t rtr;     /**< 1: remote transmission request */
    uint8_t dlc;     /**< 0..8 */
    uint8_t data[8];
} c4g_co_frame_t;

/** What an identifier is, by its function code (predefined connection set). */
typedef enum c4g_co_kind {
    C4G_CO_K_NMT = 0,
    C4G_CO_K_SYNC,
    C4G_CO_K_EMCY,
    C4G_CO_K_TIME,
    C4G_CO_K_TPDO,   /**< node transmits (master receives), pdo = 0..3 */
    C4G_CO_K_RPDO,   /**< node receives (master transmits), pdo = 0..3 */
    C4G_CO_K_SDO_TX, /**< 0x580 + node: server answers */
    C4G_CO_K_SDO_RX, /**< 0x600 + node: client requests */
    C4G_CO_K_NMT_EC, /**< 0x700 + node */
    C4G_CO_K_UNKNOWN
} c4g_co_kind_t;

/** Frame validity and kind: id <= 0x7FF, dlc <= 8 (else C4G_ERR_RANGE / C4G_ERR_LENGTH);
 *  @p node is 0 for NMT/SYNC/TIME/unknown, @p pdo 0 unless a PDO. */
C4G_NODISCARD c4g_status_t c4g_co_classify(const c4g_co_frame_t *f, c4g_co_kind_t *kind,
                                           uint8_t *node, uint8_t *pdo);

/** @name NMT, SYNC, heartbeat / node guarding, EMCY codecs (node 1..127; NMT node 0 = all) */
/**@{*/
C4G_NODISCARD c4g_status_t c4g_co_nmt_encode(c4g_co_frame_t *f, uint8_t cmd, uint8_t node);
C4G_NODISCARD c4g_status_t c4g_co_nmt_decode(const c4g_co_frame_t *f, uint8_t *cmd,
                                             uint8_t *node);
C4G_NODISCARD c4g_status_t c4g_co_sync_encode(c4g_co_frame_t *f);
/** Heartbeat / boot-up (toggle 0) or guard reply (toggle 0/1) of @p node in @p state. */
C4G_NODISCARD c4g_status_t c4g_co_ec_encode(c4g_co_frame_t *f, uint8_t node, uint8_t state,
                                            uint8_t toggle);
C4G_NODISCARD c4g_status_t c4g_co_ec_decode(const c4g_co_frame_t *f, uint8_t *node,
                                            uint8_t *state, uint8_t *toggle);
/** Node guarding request: remote frame on 0x700 + node. */
C4G_NODISCARD c4g_status_t c4g_co_guard_request(c4g_co_frame_t *f, uint8_t node);

/** One emergency message. */
typedef struct c4g_co_emcy {
    uint64_t t_ns;
    uint16_t code;   /**< emergency error code (0x0000: error reset) */
    uint8_t reg;     /**< error register 0x1001 */
    uint8_t mfr[5];  /**< manufacturer-specific bytes */
} c4g_co_emcy_t;
C4G_NODISCARD c4g_status_t c4g_co_emcy_encode(c4g_co_frame_t *f, uint8_t node,
                                              const c4g_co_emcy_t *e);
C4G_NODISCARD c4g_status_t c4g_co_emcy_decode(const c4g_co_frame_t *f, uint8_t *node,
                                              c4g_co_emcy_t *e);
/**@}*/

/** @name PDO mapping and packing */
/**@{*/
/** Mapping entry as in 0x1600/0x1A00: index << 16 | sub << 8 | length in bits. */
#define C4G_CO_MAP(index, sub, bits) \
    ((((uint32_t)(index)) << 16U) | (((uint32_t)(sub)) << 8U) | ((uint32_t)(bits)))

/** One PDO: up to 8 entries of 8, 16 or 32 bits, 64 bits in all. */
typedef struct c4g_co_pdo_map {
    uint32_t entry[C4G_CO_MAX_ENTRIES];
    uint8_t n;      /**< entries used; 0 = PDO not used */
    uint8_t trans;  /**< transmission type (1..240 synchronous, 254/255 event) */
} c4g_co_pdo_map_t;

/** Checks a mapping (entry lengths 8/16/32, at most 64 bits) and gives its byte length. */
C4G_NODISCARD c4g_status_t c4g_co_pdo_length(const c4g_co_pdo_map_t *map, uint8_t *bytes);
/** Packs @p vals (one per entry, low bits used) little-endian into a frame on @p cob. */
C4G_NODISCARD c4g_status_t c4g_co_pdo_pack(const c4g_co_pdo_map_t *map, uint16_t cob,
                                           const uint32_t *vals, c4g_co_frame_t *f);
/** Unpacks a PDO; its dlc must be the mapping's length (C4G_ERR_LENGTH otherwise). */
C4G_NODISCARD c4g_status_t c4g_co_pdo_unpack(const c4g_co_pdo_map_t *map,
                                             const c4g_co_frame_t *f, uint32_t *vals);
/**@}*/

/** @name SDO (expedited and segmented; client side, and the frames a server sends) */
/**@{*/
/** CiA 301 name of an abort code ("unknown abort code" otherwise). */
const char *c4g_co_abort_name(uint32_t code);
/** Abort transfer frame on @p cob (0x580+node from a server, 0x600+node from a client). */
C4G_NODISCARD c4g_status_t c4g_co_sdo_abort_encode(c4g_co_frame_t *f, uint16_t cob,
                                                   uint16_t index, uint8_t sub, uint32_t code);

typedef enum c4g_co_sdo_result {
    C4G_CO_SDO_NONE = 0, /**< no transfer finished yet */
    C4G_CO_SDO_OK,
    C4G_CO_SDO_ABORTED,  /**< the server aborted: abort_code */
    C4G_CO_SDO_TIMEOUT,  /**< no answer after every retry (client sent abort 0x05040000) */
    C4G_CO_SDO_PROTOCOL  /**< wrong answer (client sent abort: toggle, command, size) */
} c4g_co_sdo_result_t;

/** SDO client: one transfer at a time; frames to send are taken with c4g_co_sdo_take. */
typedef struct c4g_co_sdo_client {
    uint64_t deadline_ns;
    uint64_t timeout_ns;
    uint32_t abort_code;    /**< of the last transfer that ended in ABORTED/PROTOCOL/TIMEOUT */
    uint32_t ignored;       /**< answers that fitted no transfer (counted, not trusted) */
    uint16_t index;
    uint16_t len;           /**< bytes to send / received */
    uint16_t pos;
    uint8_t sub;
    uint8_t node;
    uint8_t state;          /**< internal phase; 0 = idle */
    uint8_t toggle;
    uint8_t retries;        /**< retries after a timeout */
    uint8_t tries_left;
    uint8_t result;         /**< c4g_co_sdo_result_t of the last finished transfer */
    uint8_t out_ready;
    c4g_co_frame_t out;
    uint8_t data[C4G_CO_SDO_MAX];
} c4g_co_sdo_client_t;

/** @p timeout_ns per request (1 ms .. 10 s), @p retries 0..5. */
C4G_NODISCARD c4g_status_t c4g_co_sdo_init(c4g_co_sdo_client_t *c, uint64_t timeout_ns,
                                           uint8_t retries);
/** Starts an upload of index:sub from @p node; C4G_ERR_STATE while a transfer runs. */
C4G_NODISCARD c4g_status_t c4g_co_sdo_upload(c4g_co_sdo_client_t *c, uint8_t node,
                                             uint16_t index, uint8_t sub, uint64_t now_ns);
/** Starts a download of @p len bytes (1..C4G_CO_SDO_MAX; expedited up to 4). */
C4G_NODISCARD c4g_status_t c4g_co_sdo_download(c4g_co_sdo_client_t *c, uint8_t node,
                                               uint16_t index, uint8_t sub,
                                               const uint8_t *data, uint16_t len,
                                               uint64_t now_ns);
/** Feeds a received frame; frames not on 0x580 + node are ignored (not counted). */
C4G_NODISCARD c4g_status_t c4g_co_sdo_rx(c4g_co_sdo_client_t *c, const c4g_co_frame_t *f);
/** Runs the timeout: a retry or the end of the transfer. */
C4G_NODISCARD c4g_status_t c4g_co_sdo_poll(c4g_co_sdo_client_t *c, uint64_t now_ns);
/** The next frame to send, if any (*have = false otherwise). */
C4G_NODISCARD c4g_status_t c4g_co_sdo_take(c4g_co_sdo_client_t *c, c4g_co_frame_t *f,
                                           bool *have);
/** True while a transfer runs. */
bool c4g_co_sdo_busy(const c4g_co_sdo_client_t *c);
/** The first 1..4 bytes of the last upload as a little-endian number. */
C4G_NODISCARD c4g_status_t c4g_co_sdo_value(const c4g_co_sdo_client_t *c, uint32_t *value);
/**@}*/

/** @name DS402 drive state machine (0x6040 controlword, 0x6041 statusword) */
/**@{*/
typedef enum c4g_co_ds402 {
    C4G_CO_DS402_NOT_READY = 0,
    C4G_CO_DS402_SWITCH_ON_DISABLED,
    C4G_CO_DS402_READY,
    C4G_CO_DS402_SWITCHED_ON,
    C4G_CO_DS402_ENABLED,
    C4G_CO_DS402_QUICK_STOP,
    C4G_CO_DS402_FAULT_REACTION,
    C4G_CO_DS402_FAULT,
    C4G_CO_DS402_UNKNOWN
} c4g_co_ds402_t;

typedef enum c4g_co_goal {
    C4G_CO_GOAL_DISABLED = 0, /**< switch on disabled (voltage off) */
    C4G_CO_GOAL_READY,        /**< ready to switch on (SRVOF) */
    C4G_CO_GOAL_ENABLED,      /**< operation enabled (SRVON) */
    C4G_CO_GOAL_QUICK_STOP
} c4g_co_goal_t;

/** The state a statusword shows. */
c4g_co_ds402_t c4g_co_ds402_state(uint16_t statusword);
/** Short name of a state ("unknown" otherwise). */
const char *c4g_co_ds402_name(c4g_co_ds402_t state);
/** Controlword that moves a drive showing @p statusword one step toward @p goal; a fault is
 *  reset on a rising edge of bit 7, so @p prev_cw (the last word sent) is needed. */
C4G_NODISCARD c4g_status_t c4g_co_ds402_command(uint16_t statusword, c4g_co_goal_t goal,
                                                uint16_t prev_cw, uint16_t *cw);
/** Drive side: the state after @p cw in @p state (the transitions of CiA 402 figure 6). */
C4G_NODISCARD c4g_status_t c4g_co_ds402_apply(c4g_co_ds402_t state, uint16_t prev_cw,
                                              uint16_t cw, c4g_co_ds402_t *next);
/** Drive side: the statusword bits of a state (bit 4 voltage enabled and 9 remote set). */
C4G_NODISCARD c4g_status_t c4g_co_ds402_statusword(c4g_co_ds402_t state, uint16_t *sw);
/**@}*/

/** @name Network configuration (one channel) */
/**@{*/
typedef enum c4g_co_watchdog {
    C4G_CO_WD_NONE = 0,
    C4G_CO_WD_HEARTBEAT,
    C4G_CO_WD_LIFEGUARD
} c4g_co_watchdog_t;

#define C4G_CO_F_IGNORE_DEVTYPE 0x01U /**< accept a wrong DeviceType (step 2b) */
#define C4G_CO_F_BYPASS_CYCLE 0x02U   /**< go on when 0x1006 fails (step 3) */
#define C4G_CO_F_BYPASS_WD 0x04U      /**< go on when the watchdog fails (step 4) */
#define C4G_CO_F_BYPASS_PDO 0x08U     /**< go on when the PDO configuration fails (step 5) */
#define C4G_CO_F_RECOVERY 0x10U       /**< poll a lost node and boot it again */

typedef struct c4g_co_node_cfg {
    uint32_t device_type;       /**< expected 0x1000; bit 30: lifeguard order reversed */
    uint32_t cycle_period_us;   /**< written to 0x1006 */
    uint32_t flags;             /**< C4G_CO_F_* */
    uint16_t heartbeat_ms;      /**< producer time written to 0x1017 (HEARTBEAT) */
    uint16_t consumer_ms;       /**< master's heartbeat timeout (> heartbeat_ms) */
    uint16_t guard_ms;          /**< 0x100C (LIFEGUARD): the master's guard period */
    uint8_t life_factor;        /**< 0x100D (LIFEGUARD) */
    uint8_t watchdog;           /**< c4g_co_watchdog_t */
    uint8_t node_id;            /**< 1..127 */
    uint8_t station;            /**< Robox station id 1..64 */
    uint8_t axis;               /**< Robox axis id 1..32 */
    uint8_t pad;
    c4g_co_pdo_map_t rx[C4G_CO_MAX_PDO]; /**< master receives: the node's TPDO k */
    c4g_co_pdo_map_t tx[C4G_CO_MAX_PDO]; /**< master transmits: the node's RPDO k */
} c4g_co_node_cfg_t;

typedef struct c4g_co_net_cfg {
    uint32_t bitrate;           /**< bit/s (10k..1M), informative for the library */
    uint32_t sync_period_ns;    /**< SYNC and TxPDO period, 500 us .. 1 s (in ns) */
    uint64_t sdo_timeout_ns;    /**< per SDO request, 1 ms .. 10 s */
    uint8_t sdo_retries;
    uint8_t n_nodes;            /**< 1..16 */
    uint8_t channel;            /**< 0..3 */
    uint8_t pad;
    c4g_co_node_cfg_t node[C4G_CO_MAX_NODES];
} c4g_co_net_cfg_t;

/** Validates a configuration (ranges, unique node and station ids, mappings). */
C4G_NODISCARD c4g_status_t c4g_co_net_check(const c4g_co_net_cfg_t *cfg, uint8_t *bad_node);
/**@}*/

/** @name Master */
/**@{*/
typedef enum c4g_co_boot {
    C4G_CO_BOOT_WAIT = 0,    /**< not configured yet */
    C4G_CO_BOOT_CONFIG,      /**< steps 2-5 running */
    C4G_CO_BOOT_READY,       /**< configured, waiting for NMT Start */
    C4G_CO_BOOT_RUNNING,     /**< operational, supervised, PDOs exchanged */
    C4G_CO_BOOT_FAILED,      /**< configuration aborted (no recovery flag) */
    C4G_CO_BOOT_LOST         /**< lost or aborted with the recovery flag: polled */
} c4g_co_boot_t;

typedef enum c4g_co_step {
    C4G_CO_STEP_NONE = 0,
    C4G_CO_STEP_DEVTYPE = 2,
    C4G_CO_STEP_CYCLE = 3,
    C4G_CO_STEP_WATCHDOG = 4,
    C4G_CO_STEP_PDO = 5
} c4g_co_step_t;

typedef enum c4g_co_cause {
    C4G_CO_CAUSE_NONE = 0,
    C4G_CO_CAUSE_SDO_TIMEOUT,   /**< no answer */
    C4G_CO_CAUSE_SDO_ABORT,     /**< the node aborted (abort code in value) */
    C4G_CO_CAUSE_SDO_PROTOCOL,  /**< wrong answer */
    C4G_CO_CAUSE_DEVTYPE,       /**< wrong DeviceType (read value in value) */
    C4G_CO_CAUSE_HEARTBEAT,     /**< heartbeat consumer timeout */
    C4G_CO_CAUSE_GUARD,         /**< no valid guard reply within the life time */
    C4G_CO_CAUSE_BOOTUP,        /**< the node sent boot-up while running (it was reset) */
    C4G_CO_CAUSE_NMT_STATE      /**< the node reported it left operational (state in value) */
} c4g_co_cause_t;

typedef enum c4g_co_event_kind {
    C4G_CO_EV_NODE_READY = 1,  /**< node configured (boot or recovery) */
    C4G_CO_EV_NODE_FAILED,     /**< configuration aborted: step, cause, value */
    C4G_CO_EV_NET_STARTED,     /**< NMT Start sent, SYNC running (step 6-7) */
    C4G_CO_EV_NODE_LOST,       /**< cause: heartbeat, guard, boot-up */
    C4G_CO_EV_NODE_RECOVERED,  /**< a lost node is operational again */
    C4G_CO_EV_EMCY,            /**< value: error code */
    C4G_CO_EV_SDO_DONE,        /**< a user transfer ended: cause 0 ok, value */
    C4G_CO_EV_NODE_STATE       /**< a running node reported STOPPED or PRE-OPERATIONAL in its
                                    heartbeat or guard reply (value: that state); it no longer
                                    runs: its PDOs are neither sent nor taken, and it is lost
                                    (polled for recovery with C4G_CO_F_RECOVERY) */
} c4g_co_event_kind_t;

typedef struct c4g_co_event {
    uint64_t t_ns;
    uint32_t value;
    uint16_t index;
    uint8_t sub;
    uint8_t kind;  /**< c4g_co_event_kind_t */
    uint8_t node;  /**< node id */
    uint8_t step;  /**< c4g_co_step_t */
    uint8_t cause; /**< c4g_co_cause_t */
    uint8_t pad;
} c4g_co_event_t;

/** Hostile or odd frames, counted and never trusted. */
typedef struct c4g_co_counters {
    uint32_t rx;           /**< frames received */
    uint32_t tx;           /**< frames taken for transmission */
    uint32_t bad_frame;    /**< id > 0x7FF or dlc > 8 */
    uint32_t bad_dlc;      /**< wrong length for its kind */
    uint32_t bad_value;    /**< right length, impossible content (e.g. an NMT state) */
    uint32_t unknown;      /**< identifier of no configured node / no kind */
    uint32_t foreign;      /**< a frame only a master sends (another master?) */
    uint32_t rtr;          /**< remote requests */
    uint32_t sdo_ignored;  /**< SDO answers that fit no transfer */
    uint32_t bad_toggle;   /**< guard replies with the wrong toggle bit */
    uint32_t txq_full;     /**< frames dropped: transmit queue full */
    uint32_t evq_full;     /**< events dropped: event queue full */
    uint32_t syncs;        /**< SYNC frames sent */
} c4g_co_counters_t;

/** Per node state, readable by the caller (read-only). */
typedef struct c4g_co_node {
    uint64_t last_seen_ns;      /**< last heartbeat / guard reply */
    uint64_t next_ns;           /**< next guard request or recovery poll */
    uint64_t started_ns;        /**< when it was last started (NMT Start) */
    uint32_t devtype_read;      /**< last DeviceType read */
    uint32_t fail_value;        /**< abort code or wrong DeviceType */
    uint32_t rx_val[C4G_CO_MAX_PDO][C4G_CO_MAX_ENTRIES]; /**< from the node's TPDOs */
    uint32_t tx_val[C4G_CO_MAX_PDO][C4G_CO_MAX_ENTRIES]; /**< to the node's RPDOs */
    uint32_t rx_pdos;           /**< PDOs received */
    uint32_t losses;            /**< times lost */
    uint16_t fail_index;        /**< object of the failed or bypassed SDO */
    uint16_t op;                /**< next configuration operation */
    uint8_t fail_sub;
    uint8_t boot;               /**< c4g_co_boot_t */
    uint8_t fail_step;          /**< c4g_co_step_t */
    uint8_t fail_cause;         /**< c4g_co_cause_t */
    uint8_t bypassed;           /**< steps that failed but were bypassed (bit per step) */
    uint8_t nmt;                /**< last NMT state reported, C4G_CO_STATE_UNKNOWN */
    uint8_t toggle;             /**< next expected guard toggle (2: the next reply sets it) */
    uint8_t recovering;         /**< 1 while a recovery runs */
    uint8_t emcy_n;             /**< entries in the history (<= depth) */
    uint8_t emcy_head;          /**< next slot */
    uint8_t op_seen;            /**< 1: reported OPERATIONAL since it was last started */
    uint8_t pad;
    c4g_co_emcy_t emcy[C4G_CO_EMCY_DEPTH];
} c4g_co_node_t;

typedef struct c4g_co_master {
    c4g_co_net_cfg_t cfg;
    c4g_co_node_t node[C4G_CO_MAX_NODES];
    c4g_co_sdo_client_t sdo;
    c4g_co_counters_t count;
    uint64_t next_sync_ns;
    uint8_t phase;          /**< 0 idle, 1 boot, 2 running */
    uint8_t cur;            /**< node (slot) whose SDO runs, 0xFF none */
    uint8_t user_sdo;       /**< 1: the running SDO is a user transfer */
    uint8_t pad;
    uint16_t txq_head;
    uint16_t txq_n;
    uint16_t evq_head;
    uint16_t evq_n;
    c4g_co_frame_t txq[C4G_CO_TXQ_LEN];
    c4g_co_event_t evq[C4G_CO_EVQ_LEN];
} c4g_co_master_t;

/** Checks @p cfg (c4g_co_net_check) and resets the master with a copy of it. */
C4G_NODISCARD c4g_status_t c4g_co_master_init(c4g_co_master_t *m, const c4g_co_net_cfg_t *cfg);
/** Boot-up: step 1 now, then steps 2-7 as c4g_co_master_poll / _rx run. */
C4G_NODISCARD c4g_status_t c4g_co_master_start(c4g_co_master_t *m, uint64_t now_ns);
/** A received frame (its t_ns is the reception time). */
C4G_NODISCARD c4g_status_t c4g_co_master_rx(c4g_co_master_t *m, const c4g_co_frame_t *f);
/**
 * Timers: SDO timeouts, SYNC and TxPDOs, heartbeat/guard supervision, recovery polls; and the
 * next instant at which they have work (@p next_ns; C4G_NO_DEADLINE: none). A caller sleeps
 * until the next frame or @p next_ns; a received frame can make work due sooner (an SDO
 * answered, a recovery poll free to start): poll again after c4g_co_master_rx.
 * @return C4G_OK, C4G_ERR_NULL.
 */
C4G_NODISCARD c4g_status_t c4g_co_master_poll(c4g_co_master_t *m, uint64_t now_ns,
                                              uint64_t *next_ns);
C4G_NODISCARD c4g_status_t c4g_co_master_tx(c4g_co_master_t *m, c4g_co_frame_t *f, bool *have);
C4G_NODISCARD c4g_status_t c4g_co_master_event(c4g_co_master_t *m, c4g_co_event_t *ev,
                                               bool *have);
/** Slot of @p node_id (C4G_ERR_ARG if not configured). */
C4G_NODISCARD c4g_status_t c4g_co_master_slot(const c4g_co_master_t *m, uint8_t node_id,
                                              uint8_t *slot);
/** Value of a mapped object in the PDO image: the node's TPDOs (@p from_node) or RPDOs. */
C4G_NODISCARD c4g_status_t c4g_co_master_get(const c4g_co_master_t *m, uint8_t node_id,
                                             bool from_node, uint16_t index, uint8_t sub,
                                             uint32_t *value);
/** Sets a mapped object of the node's RPDOs (sent on the next SYNC). */
C4G_NODISCARD c4g_status_t c4g_co_master_set(c4g_co_master_t *m, uint8_t node_id,
                                             uint16_t index, uint8_t sub, uint32_t value);
/** A user SDO (CO_ROBJ / CO_WOBJ): upload, or download of @p size (1..4) bytes of @p value;
 *  ends with a C4G_CO_EV_SDO_DONE event. C4G_ERR_STATE while another SDO runs. */
C4G_NODISCARD c4g_status_t c4g_co_master_sdo(c4g_co_master_t *m, uint8_t node_id, bool upload,
                                             uint16_t index, uint8_t sub, uint32_t value,
                                             uint8_t size, uint64_t now_ns);
/** Force an NMT command to one node (S_NMT), or to all with node 0. */
C4G_NODISCARD c4g_status_t c4g_co_master_nmt(c4g_co_master_t *m, uint8_t node_id, uint8_t cmd);
/**@}*/

#ifdef __cplusplus
}
#endif

#endif /* C4GOPEN_CANOPEN_H */
