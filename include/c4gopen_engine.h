/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_engine.h
 * @brief libc4gopen engine: modes, per-arm mode state machine, PC-side requests,
 *        per-mode packet rules, PC-side safety filter, kinematic transforms, soft control
 *        switching and monitoring records (included by c4gopen.h).
 *
 * PER-TICK FLOW (PC side)
 *   c4g_session_rx(&s, buf, n, t_rx, &res);              wire layer: decode, session rules
 *   if (res.kind == C4G_RX_CYCLIC) {
 *     c4g_engine_step(&eng, res.pkt, t_rx, &tx, &rep);     state machines + prepared reply
 *     ... fill the fields the mode needs (c4g_mode_pc_fields), e.g. tx.ax[i].target_pos ...
 *     c4g_safety_filter(&eng, res.pkt, &tx, &rep);          packet rules + safety filter
 *     c4g_session_reply(&s, &tx, out, sizeof out, &len); encode
 *   }
 *   Requests (c4g_engine_request_*) may be made at any time between ticks; the wire effect of
 *   a mode request appears in the next c4g_engine_step, the others in the next c4g_safety_filter.
 *
 * REQUIRED FIELDS AND THE "UNSET" MARKER
 *   c4g_engine_step writes a quiet NaN with a reserved payload (C4G_UNSET_BITS) into every
 *   field the outgoing mode requires (field facts "What the PC must fill per mode"). A field
 *   still unset at c4g_safety_filter means the data of the mode is missing: the arm is sent a
 *   drive-off request (505) instead, and C4G_ERR_MISSING_DATA is returned. So the data of
 *   a new mode is always present in the first packet that carries the mode.
 *
 * UNITS
 *   Packets carry motor-side values: positions in motor turns, velocities in motor turns per
 *   controller tick, currents in A. The kinematic functions convert to link side (rad or mm,
 *   and rad/s or mm/s).
 *
 * No allocation, no I/O, no clock: time is passed in (ns, monotonic). Not thread-safe.
 */
#ifndef C4GOPEN_CONTROL_H
#define C4GOPEN_CONTROL_H
#include "c4gopen_wire.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ====================================================================== state machine */

/** Phase of an arm's operating mode (chapter 24.2). */
typedef enum c4g_mode_phase {
    C4G_MPH_NONE = 0,   /**< mode 0 / 0': no transitory */
    C4G_MPH_START = 1,  /**< entering: first tick, or the SMP+ switching time (modes 1, 2) */
    C4G_MPH_CRUISE = 2, /**< running in the mode */
    C4G_MPH_END = 3,    /**< leaving: exit sent, or a stand-by mode */
    C4G_MPH_SPECIAL = 4 /**< a special mode (500..508) */
} c4g_mode_phase_t;

/** Conceptual FSM state of figure 24.1, when it can be inferred. */
typedef enum c4g_fsm_state {
    C4G_FSM_UNKNOWN = 0, /**< drives off, driving on, special mode, or no packet yet */
    C4G_FSM_S00 = 1,     /**< DRIVE ON, not moving, SMP+ control (STOP) */
    C4G_FSM_S10 = 2,     /**< moving under SMP+ control (CLOSED) */
    C4G_FSM_S01 = 3,     /**< under PC control (OPEN TYPE A) */
    C4G_FSM_S11 = 4      /**< moving under SMP+ and PC control (OPEN TYPE B) */
} c4g_fsm_state_t;

/** @name State machine events (bit mask, per arm) */
/**@{*/
#define C4G_CEV_MODE_CHANGE 0x00000001U  /**< SMax changed */
#define C4G_CEV_START 0x00000002U        /**< an operating mode was entered (START) */
#define C4G_CEV_CRUISE 0x00000004U       /**< START over: CRUISE */
#define C4G_CEV_END 0x00000008U          /**< END phase began (exit sent or stand-by) */
#define C4G_CEV_MODE0 0x00000010U        /**< back in mode 0 */
#define C4G_CEV_DRIVING_ON 0x00000020U   /**< SMax became 501 */
#define C4G_CEV_DRIVING_ON_END 0x00000040U /**< first tick SMax left 501 */
#define C4G_CEV_DRIVE_ON 0x00000080U     /**< INFPAR byte became C4G_STS_MOVING */
#define C4G_CEV_DRIVE_OFF 0x00000100U    /**< INFPAR byte left C4G_STS_MOVING */
#define C4G_CEV_UNEXPECTED 0x00000200U   /**< transition not allowed by c4g_mode_transition_ok */
#define C4G_CEV_MIXED 0x00000400U        /**< the arm's axes carry different modes */
#define C4G_CEV_REQ_TIMEOUT 0x00001000U  /**< an exit request got no answer in time: dropped */
#define C4G_CEV_EXIT_DONE 0x00004000U    /**< mode 0 reached after an exit from open */
#define C4G_CEV_FREEZE_A 0x00008000U     /**< the controller reports active freezing (500) */
#define C4G_CEV_FREEZE_A_END 0x00010000U /**< active freezing over */
#define C4G_CEV_FREEZE_P_IN 0x00020000U  /**< 502 seen */
#define C4G_CEV_FREEZE_P_OUT 0x00040000U /**< 503 seen */
#define C4G_CEV_END_COMM 0x00080000U     /**< 504 seen: the session ends */
#define C4G_CEV_RESTART 0x00100000U      /**< 506 seen: a new init packet follows */
#define C4G_CEV_LATCH_CLEARED 0x00200000U/**< drives off after a 505/508: latch cleared */
#define C4G_CEV_SAFETY 0x00400000U       /**< the safety filter changed the reply */
#define C4G_CEV_EXIT_SENT 0x00800000U    /**< EXIT_FROM_OPEN went out in this reply */
/**@}*/

/** @name Latches (c4g_arm_sm_t.latch): kept until the drives are off and a packet went out */
/**@{*/
#define C4G_LATCH_DRIVE_OFF 0x1U    /**< every axis of the arm carries 505 */
#define C4G_LATCH_FOLLOW_ERROR 0x2U /**< every axis of the arm carries 508 */
#define C4G_LATCH_AXIS_FE 0x4U      /**< the safety filter sent 508 on some axes of the arm */
#define C4G_LATCH_STROKE 0x8U       /**< a stroke end stopped the arm: every axis carries 505 */
/**@}*/

/** Configuration of the state machines. */
typedef struct c4g_engine_config {
    uint32_t request_timeout_ticks; /**< ticks an exit request waits (default 100) */
    uint64_t start_ns;  /**< START length of modes 1 and 2 (SMP+ switching, T1+T2+T3); default 0 */
    float moving_eps;   /**< |SMP+ target velocity| above which the arm moves (default 0) */
} c4g_engine_config_t;

/** Per-arm mode state machine (SW_PC of chapter 24). Read-only for the caller. */
typedef struct c4g_arm_sm {
    uint32_t n_axes;         /**< open axes of the arm; 0: arm not open */
    uint32_t started;        /**< a packet was seen */
    int32_t mode;            /**< SMax of the arm (special > non-zero > 0 among its axes) */
    int32_t prev_mode;       /**< SMax before the last change */
    int32_t op_mode;         /**< operating mode (1 during 1 and 11), 0 in mode 0 */
    c4g_mode_phase_t phase;
    c4g_fsm_state_t fsm;
    uint32_t mixed;          /**< the arm's axes carry different modes */
    uint32_t moving;         /**< SMP+ target velocity above moving_eps on some axis */
    uint32_t drive_on;       /**< INFPAR byte is C4G_STS_MOVING */
    uint32_t driving_on;     /**< SMax is 501 */
    int32_t frozen;          /**< 0, C4G_MODE_FREEZING_A (PC froze) or C4G_MODE_FREEZING_P_IN */
    uint32_t ended;          /**< 504 seen */
    uint32_t restart;        /**< 506 seen */
    uint64_t mode_since_ns;  /**< time the current SMax was first seen */
    uint64_t phase_since_ns; /**< time the current phase began (SCS t1) */
    uint32_t ticks_in_mode;  /**< packets since the current SMax was first seen */
    uint32_t exit_req;       /**< EXIT_FROM_OPEN is being sent */
    uint32_t exit_ticks;     /**< replies that carried it */
    int32_t exit_from;       /**< SMax when the exit was asked */
    uint32_t leaving;        /**< exit accepted, waiting for mode 0 */
    uint32_t latch;          /**< C4G_LATCH_* */
    uint32_t latch_sent;     /**< a reply carried the latch */
} c4g_arm_sm_t;

/** Fill @p cfg with the defaults. @return C4G_OK, C4G_ERR_NULL. */
C4G_NODISCARD c4g_status_t c4g_engine_config_default(c4g_engine_config_t *cfg);
/** Whether c4g_engine_init would take @p cfg. @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG. */
C4G_NODISCARD c4g_status_t c4g_engine_config_check(const c4g_engine_config_t *cfg);

/** Start an arm state machine with @p n_axes open axes (0..10). @return OK, NULL, ARG. */
C4G_NODISCARD c4g_status_t c4g_arm_sm_init(c4g_arm_sm_t *sm, uint32_t n_axes);

/**
 * Feed the state machine one received packet's view of the arm (pure transition function).
 * @param[in] mode       aggregated SMax of the arm's axes (must be a known mode)
 * @param[in] mixed      1 if the axes disagree
 * @param[in] drive_byte the arm's INFPAR byte from the SMP+
 * @param[in] moving     1 if the SMP+ target velocity is non-zero on some axis
 * @param[out] events    C4G_CEV_* raised by this packet
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_MODE. O(1).
 */
C4G_NODISCARD c4g_status_t c4g_arm_sm_update(c4g_arm_sm_t *sm, const c4g_engine_config_t *cfg, int32_t mode,
                               uint32_t mixed, uint8_t drive_byte, uint32_t moving,
                               uint64_t now_ns, uint32_t *events);

/** What a PC request asks for. */
typedef enum c4g_req_kind {
    C4G_REQ_MODE = 0,         /**< a new operating mode: always refused (PDL2 starts modes) */
    C4G_REQ_EXIT = 1,         /**< EXIT_FROM_OPEN (INFPAR byte 1) */
    C4G_REQ_DRIVE_OFF = 2,    /**< 505 on every axis of the arm */
    C4G_REQ_FOLLOW_ERROR = 3, /**< 508 on every axis of the arm */
    C4G_REQ_FREEZE = 4        /**< active freezing, 500 on every axis of the arm */
} c4g_req_kind_t;

/**
 * The request rules (pure): may @p kind (with @p mode for C4G_REQ_MODE) be asked now?
 * A mode is never the PC's to start (manual 24.2: SW_PDL sets every operating mode; the PC
 * echoes it): C4G_REQ_MODE gives C4G_ERR_PDL_ONLY (C4G_ERR_MODE for an unknown code).
 * Freezing only from mode 0; exit only in an operating mode (not mode 2, which PDL2
 * ends by setting 12) or an active freezing; drive off and following error always.
 * @return C4G_OK or the reason: C4G_ERR_NULL, C4G_ERR_ARG, C4G_ERR_NOT_OPEN,
 *         C4G_ERR_ENDED, C4G_ERR_MODE, C4G_ERR_*. O(1).
 */
C4G_NODISCARD c4g_status_t c4g_arm_sm_check(const c4g_arm_sm_t *sm, c4g_req_kind_t kind, int32_t mode);

/* ====================================================================== kinematics */

/** @name Link-side unit of a logical axis (c4g_kin_t.linear) */
/**@{*/
#define C4G_KIN_ROTARY 0U /**< rad: motor turns = Kr q / 2 pi */
#define C4G_KIN_LINEAR 1U /**< mm: motor turns = Kr q (TxRate in turns per mm) */
/**@}*/

/** Kinematic data of one arm (chapter 19), built from the initialization packet. */
typedef struct c4g_kin {
    double kr[C4G_AXES_PER_ARM];   /**< pure transmission ratios (Kr2 diagonal), TxRate */
    double cal[C4G_AXES_PER_ARM];  /**< calibration constants q0 [motor turns], CalData */
    double k54;                    /**< AxInfo[3]: axis 4 influence on axis 5 */
    double k64;                    /**< AxInfo[4]: axis 4 influence on axis 6 */
    double k65;                    /**< AxInfo[5]: axis 5 influence on axis 6 */
    uint32_t linear[C4G_AXES_PER_ARM]; /**< C4G_KIN_ROTARY (default) or C4G_KIN_LINEAR */
    double period_s;               /**< controller tick [s], for velocities */
} c4g_kin_t;

/** Kr2, K1 and Kr = Kr2 K1^-T of the 6 main axes (auxiliary axes: Kr = Kr2). */
typedef struct c4g_kin_matrices {
    double kr2[6][6];
    double k1[6][6];
    double kr[6][6];
} c4g_kin_matrices_t;

/**
 * Build the kinematic data of @p arm (0..3) from a validated initialization packet.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (arm), C4G_ERR_PERIOD, C4G_ERR_NONFINITE.
 */
C4G_NODISCARD c4g_status_t c4g_kin_from_init(const c4g_init_t *init, uint32_t arm, c4g_kin_t *kin);
/** The three matrices of chapter 19. @return OK, NULL, NONFINITE. O(1). */
C4G_NODISCARD c4g_status_t c4g_kin_matrices(const c4g_kin_t *kin, c4g_kin_matrices_t *m);
/**
 * Link-side positions @p q (rad or mm) of logical axes 0..n-1 -> motor turns, including
 * the calibration constants: qm = Kr q / 2 pi + q0. @p n is 1..10.
 * @return OK, NULL, ARG, NONFINITE (input or result), C4G_ERR_SINGULAR. O(n).
 */
C4G_NODISCARD c4g_status_t c4g_kin_link_to_motor(const c4g_kin_t *kin, const double *q, uint32_t n,
                                   double *qm);
/** Inverse of c4g_kin_link_to_motor: q = 2 pi K1^T Kr2^-1 (qm - q0). Same statuses. */
C4G_NODISCARD c4g_status_t c4g_kin_motor_to_link(const c4g_kin_t *kin, const double *qm, uint32_t n,
                                   double *q);
/** Link velocities (rad/s or mm/s) -> motor turns per tick (no calibration offset). */
C4G_NODISCARD c4g_status_t c4g_kin_link_vel_to_motor(const c4g_kin_t *kin, const double *v, uint32_t n,
                                       double *vm);
/** Motor turns per tick -> link velocities (rad/s or mm/s). */
C4G_NODISCARD c4g_status_t c4g_kin_motor_vel_to_link(const c4g_kin_t *kin, const double *vm, uint32_t n,
                                       double *v);

/* ====================================================================== safety */

/** @name Safety filter actions (per axis, c4g_engine_report_t.axis_flags; pure check results) */
/**@{*/
#define C4G_SF_MISSING 0x0001U      /**< a required field was not filled */
#define C4G_SF_NONFINITE 0x0002U    /**< a NaN / infinity was produced */
#define C4G_SF_FOLLOW_ERROR 0x0004U /**< |pos_ref - pos_mis| > threshold: axis carries 508 */
#define C4G_SF_CURRENT 0x0008U      /**< current saturated to +/- limit (modes 1, 2) */
#define C4G_SF_DCURRENT 0x0010U     /**< delta current clamped (mode 9) */
#define C4G_SF_STEP 0x0020U         /**< position step per tick limited */
#define C4G_SF_VELOCITY 0x0040U     /**< velocity per tick limited */
#define C4G_SF_STROKE 0x0080U       /**< stroke end (motor turns) */
#define C4G_SF_STROKE_JOINT 0x0100U /**< stroke end (joint units, through kinematics) */
#define C4G_SF_HELD 0x0200U         /**< data replaced by the hold (what the controller applied) */
#define C4G_SF_DRIVE_OFF 0x0400U    /**< axis carries 505 */
#define C4G_SF_FE_SENT 0x0800U      /**< axis carries 508 */
#define C4G_SF_MODE_RESTORED 0x1000U/**< the caller wrote a forbidden mode: restored */
#define C4G_SF_COPY_BACK 0x2000U    /**< mode 10: D1..D5 copied back by the library */
#define C4G_SF_BAD_LIMIT 0x4000U    /**< a check got a non-finite / negative limit: off */
#define C4G_SF_NO_RULE 0x8000U      /**< a mode the C4G does not have: no data, the arm gets 505 */
/**@}*/

/** User limits of one logical axis. 0 leaves a check off (a stroke: both ends 0); a stroke
 *  that is not an interval (min >= max) is refused, never taken as "off". */
typedef struct c4g_axis_limits {
    float follow_error; /**< [motor turns] > 0: tighter than (or instead of) FollowError */
    float current_max;  /**< [A] > 0: tighter than AzLim */
    float max_step;     /**< [motor turns / tick] position step (modes 1, 4, 5, 7) */
    float max_vel;      /**< [motor turns / tick] |D2| (modes 1, 4, 5) */
    float motor_min;    /**< stroke ends [motor turns]; both 0: off */
    float motor_max;
    float joint_min;    /**< stroke ends [rad or mm], through the kinematics; both 0: off */
    float joint_max;
} c4g_axis_limits_t;

/**
 * Following error check (15.7): @p err = |pos_ref - pos_mis|; C4G_SF_FOLLOW_ERROR when
 * @p threshold > 0 and err > threshold (threshold 0: no threshold). Non-finite input:
 * C4G_SF_NONFINITE. @return the C4G_SF_* bits raised (0: fine). O(1).
 */
uint32_t c4g_sf_follow_error(float pos_ref, float pos_mis, float threshold, float *err);
/** Saturate @p cur to [-lim, lim] into @p out. @return 0, C4G_SF_CURRENT, NONFINITE, BAD_LIMIT. */
uint32_t c4g_sf_current(float cur, float lim, float *out);
/** Clamp a delta current so that smp_cur + delta stays in [-lim, lim]. @return 0, DCURRENT, ... */
uint32_t c4g_sf_delta_current(float smp_cur, float delta, float lim, float *out);
/** Limit a position step: |target - prev| <= max_step (0: off). @return 0, C4G_SF_STEP, ... */
uint32_t c4g_sf_step(float prev, float target, float max_step, float *out);
/** Limit a velocity to [-max_vel, max_vel] (0: off). @return 0, C4G_SF_VELOCITY, ... */
uint32_t c4g_sf_velocity(float vel, float max_vel, float *out);
/** Clamp @p pos into [min, max] (off when both are 0; BAD_LIMIT when min >= max otherwise).
 *  @return 0, C4G_SF_STROKE, C4G_SF_NONFINITE, C4G_SF_BAD_LIMIT */
uint32_t c4g_sf_stroke(float pos, float min, float max, float *out);

/* ====================================================================== the engine */

/** What c4g_engine_step / c4g_safety_filter did on one tick. */
typedef struct c4g_engine_report {
    uint32_t events;                    /**< union of arm_events */
    uint32_t arm_events[C4G_ARMS];      /**< C4G_CEV_* per arm */
    uint32_t axis_flags[C4G_MAX_AXES];  /**< C4G_SF_* per OPEN index */
    float follow_err[C4G_MAX_AXES];     /**< |pos_ref - pos_mis| where checked, else 0 */
    uint32_t n_filtered;                /**< axes the filter changed */
} c4g_engine_report_t;

/** The engine's own state: read and written by the library only; its layout may change in
 *  any release. */
typedef struct c4g_engine_priv {
    uint32_t joint_on[C4G_ARMS];        /**< some joint stroke end set on the arm */
    uint32_t n_joint[C4G_ARMS];         /**< logical axes in the arm's joint check */
    int32_t prep_mode[C4G_MAX_AXES];    /**< mode c4g_engine_step prepared per axis */
    uint32_t prep_rules[C4G_MAX_AXES];  /**< what the filter does with that mode */
    c4g_pc_axis_t prep_tx[C4G_MAX_AXES];/**< reply data prepared for that mode */
    uint32_t fe_latch[C4G_MAX_AXES];    /**< axis latched to 508 by the filter */
    float anchor[C4G_MAX_AXES];         /**< SMP+ target while in mode 0 / 0' (c4g_engine_anchor) */
    uint32_t anchor_set[C4G_MAX_AXES];  /**< anchor[] holds a value */
    uint32_t stepped;                   /**< step done, finish expected */
    int32_t step_num;                   /**< NUM of the stepped packet */
    uint32_t uni_rules;                 /**< prep_rules of every axis when equal, else a marker */
    uint32_t fe_any;                    /**< some fe_latch[] is set */
} c4g_engine_priv_t;

/** PC-side control context: one per session. The public members are read-only for the
 *  caller. */
typedef struct c4g_engine {
    c4g_engine_config_t cfg;
    c4g_axis_map_t map;
    c4g_kin_t kin[C4G_ARMS];
    uint32_t kin_ok[C4G_ARMS];          /**< kinematics usable (all ratios non-zero) */
    c4g_axis_limits_t lim[C4G_MAX_AXES];/**< effective limits by OPEN index */
    float ctrl_fe[C4G_MAX_AXES];         /**< FollowError of the init packet, by OPEN index */
    float ctrl_az[C4G_MAX_AXES];         /**< AzLim of the init packet, by OPEN index */
    c4g_arm_sm_t arm[C4G_ARMS];
    c4g_engine_priv_t priv;             /**< internal */
} c4g_engine_t;

/**
 * Start a control context from a validated initialization packet: axis maps, kinematics
 * per arm, limits from AzLim and FollowError, one state machine per arm.
 * @param[in] cfg may be NULL for the defaults
 * @return C4G_OK, C4G_ERR_NULL, an init validation status, C4G_ERR_ARG (cfg). O(axes).
 */
C4G_NODISCARD c4g_status_t c4g_engine_init(c4g_engine_t *eng, const c4g_init_t *init, const c4g_engine_config_t *cfg);

/**
 * Set user limits for logical axis @p axis of @p arm (see c4g_axis_limits_t). Limits can only
 * tighten the controller's: follow_error and current_max take the smaller positive value.
 * Set them again after every accepted init packet (c4g_engine_init starts from the
 * controller's own). A stroke converted from joint ends through a negative transmission
 * ratio has its ends swapped: order them (the call refuses a reversed stroke).
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG, C4G_ERR_NOT_OPEN, C4G_ERR_NONFINITE,
 *         C4G_ERR_LIMITS (negative values; a stroke with min >= max that is not 0, 0),
 *         C4G_ERR_SINGULAR (joint limits without
 *         usable kinematics), C4G_ERR_NOT_OPEN also when joint limits need an axis 0..axis of
 *         the arm that is not open.
 */
C4G_NODISCARD c4g_status_t c4g_engine_set_limits(c4g_engine_t *eng, uint32_t arm, uint32_t axis,
                                const c4g_axis_limits_t *lim);

/**
 * One received cyclic packet: update every arm's state machine and prepare the reply @p tx:
 * each axis echoes its mode (or carries a pending requested mode), data zero, mode 10
 * copied back, and the fields the outgoing mode requires set to the unset marker.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_PACKET (axis count), C4G_ERR_MODE,
 *         C4G_ERR_NONFINITE (@p rx invalid: @p tx untouched). O(axes).
 */
C4G_NODISCARD c4g_status_t c4g_engine_step(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, uint64_t now_ns,
                          c4g_pc_packet_t *tx, c4g_engine_report_t *rep);

/**
 * Check and complete the reply before encoding: request overlays (EXIT_FROM_OPEN, 500,
 * 505, 508), mode rules (a mode c4g_engine_step did not prepare is restored), mode-10 copy
 * back, required fields, and the safety filter (sections 14.17.2, 15.7). After any return
 * except C4G_ERR_NULL and C4G_ERR_STATE, @p tx is safe to encode and must be sent.
 * @return C4G_OK; C4G_ERR_MISSING_DATA or C4G_ERR_NONFINITE (an arm was sent 505);
 *         C4G_ERR_MODE_RESTORED; C4G_ERR_NULL; C4G_ERR_STATE (no matching step). O(axes).
 */
C4G_NODISCARD c4g_status_t c4g_safety_filter(c4g_engine_t *eng, const c4g_ctrl_packet_t *rx, c4g_pc_packet_t *tx,
                            c4g_engine_report_t *rep);

/**
 * Operating modes are started by the controller's PDL2 program, never by the PC (manual
 * 24.2). Kept so that a program ported from code that tried gets a clear answer.
 * @return C4G_ERR_PDL_ONLY (C4G_ERR_MODE: unknown code; NULL, ARG, NOT_OPEN, ENDED).
 */
C4G_NODISCARD c4g_status_t c4g_engine_request_mode(c4g_engine_t *eng, uint32_t arm, int32_t mode);
/**
 * Where OPEN axis @p axis stood when its current mode began: the controller's reference D1
 * on the first packet seen in that mode (in mode 0 or 0': on the latest packet). A mode
 * that begins again after a passive freezing (502, 503) or a stand-by begins where the axis
 * stands then, not where it stood in mode 0: start a position trajectory here. The filter
 * itself measures every step of an absolute target (modes 1, 11, 4) from the reference the
 * controller reports on the packet being answered.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (axis), C4G_ERR_STATE (no packet yet). O(1).
 */
C4G_NODISCARD c4g_status_t c4g_engine_anchor(const c4g_engine_t *eng, uint32_t axis, float *pos);
/** Request EXIT_FROM_OPEN on @p arm (also ends an active freezing). Idempotent. */
C4G_NODISCARD c4g_status_t c4g_engine_request_exit(c4g_engine_t *eng, uint32_t arm);
/** Request a drive off (505 on every axis of @p arm until its drives are off). Never refused. */
C4G_NODISCARD c4g_status_t c4g_engine_request_drive_off(c4g_engine_t *eng, uint32_t arm);
/** Signal a following error (508 on every axis of @p arm until drives off). Never refused. */
C4G_NODISCARD c4g_status_t c4g_engine_request_follow_error(c4g_engine_t *eng, uint32_t arm);
/** Active freezing of @p arm (500), from mode 0 only; left with c4g_engine_request_exit. */
C4G_NODISCARD c4g_status_t c4g_engine_request_freeze(c4g_engine_t *eng, uint32_t arm);

/** The unset marker (a quiet NaN with payload C4G_UNSET_BITS). */
#define C4G_UNSET_BITS 0x7FC4C0DEU
/** The unset marker as a float. */
float c4g_unset(void);
/** true if @p f is the unset marker (bit compare). */
bool c4g_is_unset(float f);

/* ====================================================================== soft control switching */

/** The linear switching model of chapter 12 at one instant. */
typedef struct c4g_scs {
    float chi; /**< (t - t1) / (t2 - t1), clamped to [0, 1] */
    float eta; /**< chi */
    float rho; /**< 1 - chi */
} c4g_scs_t;

/** Direction of a switch. */
typedef enum c4g_scs_dir {
    C4G_SCS_TO_PC = 0, /**< from DSA control to PC control (entering modes 1, 2) */
    C4G_SCS_TO_DSA = 1 /**< from PC control back to DSA (leaving) */
} c4g_scs_dir_t;

/** chi, eta, rho at @p t_ns for a switch over [t1, t2]. @return OK, NULL, ARG (t2 <= t1). */
C4G_NODISCARD c4g_status_t c4g_scs_linear(uint64_t t_ns, uint64_t t1_ns, uint64_t t2_ns, c4g_scs_t *out);
/** Variable-gain reducer: out = gain * i, gain in [0, 1]. @return OK, NULL, ARG, NONFINITE. */
C4G_NODISCARD c4g_status_t c4g_scs_reduce(float gain, float i, float *out);
/**
 * Variable-threshold limiter: threshold = gain (i_max - i_min); |i| above it -> threshold
 * sgn(i). @return OK, NULL, ARG (gain outside [0,1], i_max < i_min), NONFINITE.
 */
C4G_NODISCARD c4g_status_t c4g_scs_limit(float gain, float i_max, float i_min, float i, float *out);
/**
 * Both currents of a switch at one instant (chapter 12): TO_PC: I_dyn * eta and I_reg limited
 * by rho (I_max - I_min); TO_DSA: I_dyn * rho and I_reg limited by eta (I_max - I_min).
 * @return OK, NULL, ARG, NONFINITE.
 */
C4G_NODISCARD c4g_status_t c4g_scs_currents(const c4g_scs_t *s, c4g_scs_dir_t dir, float i_dyn, float i_reg,
                              float i_max, float i_min, float *dyn_out, float *reg_out);
/** Controller tick in ns from an initialization packet. @return OK, NULL, PERIOD. */
C4G_NODISCARD c4g_status_t c4g_period_ns(const c4g_init_t *init, uint64_t *ns);

/* ====================================================================== monitoring (chapter 16) */

/** One moni record: one axis, one tick. */
typedef struct c4g_moni_rec {
    uint32_t type;  /**< 19..24 */
    int32_t num;    /**< NUM of the controller packet */
    uint32_t axis;  /**< OPEN index */
    int32_t mode;   /**< SMax sent by the controller */
    float v[5];     /**< the five values of the type, in the manual's order */
} c4g_moni_rec_t;

#define C4G_MONI_FIRST 19U
#define C4G_MONI_LAST 24U
/**
 * Record of moni @p type for OPEN axis @p axis from one received (@p rx, "TX packet" of the
 * manual, which speaks from the SMP+) and one sent (@p tx, the manual's "RX packet") packet.
 * @return OK, NULL, ARG (type), C4G_ERR_AXES (axis not in both packets).
 */
C4G_NODISCARD c4g_status_t c4g_moni_record(uint32_t type, const c4g_ctrl_packet_t *rx,
                             const c4g_pc_packet_t *tx, uint32_t axis, c4g_moni_rec_t *out);
/** Column name of value @p k (0..4) of moni @p type ("pc_d1", "smp_e2"); "?" when out of range. */
const char *c4g_moni_value_name(uint32_t type, uint32_t k);

/** Deprecated (removed in 3.0): the filter's entry point was called c4g_engine_finish. */
/* cppcheck-suppress misra-c2012-2.5 */
#define c4g_engine_finish c4g_safety_filter

#ifdef __cplusplus
}
#endif
#endif /* C4GOPEN_CONTROL_H */
