/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_cell.h
 * @brief libc4gopen cell protocol codec (included by c4gopen.h; usable alone: it needs
 *        only c4gopen_base.h).
 *
 * The micro-manipulation cell's line protocol (ITIA-CNR MM&A-PRIN2009-SCOM,
 * docs/cell-protocol.md): a central controller (TCP client) sends instructions
 * "HHH<data>\r\n" to the robot (port 2001), orientation platform (2002) and
 * conditioning system (2003); each device answers "OK<data>\r\n" or
 * "ER<Sxxxxx>\r\n".
 *
 * VALUES
 *   The codec works on exact integer "counts", one count per last printed digit:
 *   lengths (Sxxx.yyy) in 0.001 mm, angles (Sxx.yyyy) in 0.0001 rad, integers
 *   (Sxxxxx) in units. Every field therefore holds -999999..+999999 counts
 *   (integers -99999..+99999). c4g_cell_from_double() is the one place where a
 *   real number becomes counts; its rounding rule is "nearest count, halves away
 *   from zero". Out-of-range values are errors, never clamped.
 *
 * PARSING
 *   Decoders take one whole line including its CR LF (as returned by the line
 *   splitter) and are strict: exact length, '+' or '-' signs, digits, '.' where the
 *   format puts it, 'T'/'F' flags, a final CR LF and no other CR or LF. On error
 *   the optional c4g_cell_diag_t gives the 1-based column of the first offending
 *   character. A decoder reads only the @p len bytes it is given.
 *
 * PROJECT EXTENSIONS (marked as such in docs/cell-protocol.md)
 *   ITR (interrupt the motion, 5 chars) and PNP (pick-and-place, 45 chars:
 *   clearance Z then the target X Y Z C) are not defined by the spec's command
 *   list; error numbers +00101..+00107 are project codes.
 *
 * THREADING AND MEMORY
 *   No state outside the caller's structs, no allocation, no I/O; every call is
 *   O(line length) with C4G_CELL_LINE_MAX bounding the lines.
 */
#ifndef C4GOPEN_CELL_H
#define C4GOPEN_CELL_H
#include "c4gopen_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @name Limits */
/**@{*/
#define C4G_CELL_LINE_MAX 64U     /**< recommended splitter capacity (longest line: 50) */
#define C4G_CELL_FIELD_LEN 8U     /**< chars of a length or angle field */
#define C4G_CELL_INT_LEN 6U       /**< chars of an integer field */
#define C4G_CELL_COUNTS_MAX 999999 /**< largest |counts| of a length or angle field */
#define C4G_CELL_INT_MAX 99999    /**< largest |value| of an integer field */
#define C4G_CELL_OVR_MAX 100      /**< override is 0..100 % */
#define C4G_CELL_AXES_ROBOT 4U    /**< X, Y, Z [length], C [angle] */
#define C4G_CELL_AXES_PLATFORM 2U /**< A, B [angle] */
#define C4G_CELL_AXES_MAX 4U
/**@}*/

/** @name Line lengths including CR LF (spec section 4; HND CLOSE is 16, field facts) */
/**@{*/
#define C4G_CELL_LEN_STA 5U
#define C4G_CELL_LEN_SRV 7U
#define C4G_CELL_LEN_OVR 11U
#define C4G_CELL_LEN_MOV_ROBOT 38U
#define C4G_CELL_LEN_MOV_PLATFORM 22U
#define C4G_CELL_LEN_SHORT 5U     /**< STP, RST, CLO, ITR */
#define C4G_CELL_LEN_ACQ 11U
#define C4G_CELL_LEN_HND_OPEN 15U
#define C4G_CELL_LEN_HND_CLOSE 16U
#define C4G_CELL_LEN_PNP 45U      /**< project extension */
#define C4G_CELL_LEN_OK 4U
#define C4G_CELL_LEN_ER 10U
#define C4G_CELL_LEN_STA_ROBOT 50U
#define C4G_CELL_LEN_STA_PLATFORM 34U
/**@}*/

/** @name Wire error numbers (ER replies and the STA error field) */
/**@{*/
#define C4G_CELL_E_NONE 0           /**< spec: no error */
#define C4G_CELL_E_GENERIC 1        /**< spec: generic error */
#define C4G_CELL_E_SERVO1 2         /**< spec: servo motor 1 error */
#define C4G_CELL_E_SERVO2 3         /**< spec: servo motor 2 error */
#define C4G_CELL_E_UNKNOWN_CMD 101  /**< project: unknown instruction head */
#define C4G_CELL_E_MALFORMED 102    /**< project: instruction does not parse */
#define C4G_CELL_E_RANGE 103        /**< project: value out of range */
#define C4G_CELL_E_SERVO_OFF 104    /**< project: motion refused, servo off */
#define C4G_CELL_E_WORKSPACE 105    /**< project: target outside the workspace */
#define C4G_CELL_E_UNSUPPORTED 106  /**< project: instruction not handled by this device */
#define C4G_CELL_E_BUSY 107         /**< project: motion already in progress */
/**@}*/

/** @name Devices an instruction is meant for (bit mask of the command table) */
/**@{*/
#define C4G_CELL_ON_ROBOT 0x1U        /**< the robot controller (port 2001) */
#define C4G_CELL_ON_PLATFORM 0x2U     /**< the orientation platform (2002) */
#define C4G_CELL_ON_CONDITIONING 0x4U /**< the conditioning system (2003) */
#define C4G_CELL_ON_MOTION 0x3U       /**< robot and platform */
#define C4G_CELL_ON_ALL 0x7U          /**< every device */
/**@}*/

/** What follows an instruction's head on the wire (its argument layout). */
typedef enum c4g_cell_args {
    C4G_CELL_ARGS_NONE = 0,  /**< nothing */
    C4G_CELL_ARGS_INT,       /**< integer Sxxxxx in [lo, hi] -> value */
    C4G_CELL_ARGS_INT_ACTION,/**< integer Sxxxxx in [lo, hi] -> value, then OPEN|CLOSE -> open */
    C4G_CELL_ARGS_MODE_POSE, /**< 'A'|'R' -> relative, then robot X Y Z C (38-char line) or
                                  platform A B (22-char line) -> pose */
    C4G_CELL_ARGS_CLEAR_POSE /**< length Sxxx.yyy -> clearance, then robot X Y Z C -> pose */
} c4g_cell_args_t;

/**
 * THE CELL COMMAND TABLE: the one definition of the instruction vocabulary
 * (docs/cell-commands.md: how to add a command). Each row is
 *
 *   X(cmd, head, args, lo, hi, reply, devices, words, arg, what, help)
 *
 *   cmd      enum constant (c4g_cell_cmd_t, in row order; STA is 0)
 *   head     head text on the wire, >= 3 chars; no head may be a prefix of another
 *            (SRVON and SRVOF share the spec's "SRV" and differ in the rest)
 *   args     c4g_cell_args_t: what follows the head
 *   lo, hi   range of the integer argument (ARGS_INT, ARGS_INT_ACTION), else 0, 0
 *   reply    c4g_cell_reply_kind_t of a successful reply (ER is always possible)
 *   devices  C4G_CELL_ON_* mask of the devices that handle it
 *   words    command words of the tools, '|' between alternatives, the first is the
 *            primary one; "servo on" is a two-word alternative
 *   arg      tools: placeholder of the integer argument in usage texts ("" if none)
 *   what     tools: the integer argument's name in error messages ("" if none)
 *   help     tools: help text (cell-cli "help")
 *
 * The library expands it into c4g_cell_cmd_t, the head table, the encoder and the
 * decoder; cell-cli into its command parser, help and completion.
 */
/* Deviation D-05 (MISRA 20.7): X names the row macro to apply; it cannot be parenthesized. */
/* cppcheck-suppress misra-c2012-20.7 */
#define C4G_CELL_COMMANDS(X) \
    X(C4G_CELL_CMD_STA, "STA", C4G_CELL_ARGS_NONE, 0, 0, C4G_CELL_REPLY_STA, \
      C4G_CELL_ON_MOTION, "sta|status", "", "", \
      "DEV sta            status: moving flag, position, servo, override, error (STA)") \
    X(C4G_CELL_CMD_SRVON, "SRVON", C4G_CELL_ARGS_NONE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_MOTION, "srvon|servo on", "", "", \
      "DEV srvon | DEV servo on     switch the servo motors on (SRVON)") \
    X(C4G_CELL_CMD_SRVOF, "SRVOF", C4G_CELL_ARGS_NONE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_MOTION, "srvof|srvoff|servo off", "", "", \
      "DEV srvof | DEV servo off    switch the servo motors off (SRVOF)") \
    X(C4G_CELL_CMD_OVR, "OVR", C4G_CELL_ARGS_INT, 0, C4G_CELL_OVR_MAX, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_MOTION, "ovr|override", "PERCENT", "override (percent)", \
      "DEV ovr PERCENT    set the override 0..100 % (OVR), e.g. robot ovr 50") \
    X(C4G_CELL_CMD_MOV, "MOV", C4G_CELL_ARGS_MODE_POSE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_MOTION, "mov|move", "", "", \
      "robot mov abs|rel x=MM y=MM z=MM c=RAD    point-to-point motion (MOVA/MOVR)\n" \
      "platform mov abs|rel a=RAD b=RAD          absolute needs every axis;\n" \
      "                                          relative axes default to 0") \
    X(C4G_CELL_CMD_STP, "STP", C4G_CELL_ARGS_NONE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_MOTION, "stp|stop", "", "", \
      "DEV stp            stop the motion (STP)") \
    X(C4G_CELL_CMD_RST, "RST", C4G_CELL_ARGS_NONE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_ALL, "rst|reset", "", "", \
      "DEV rst            reset: stop, clear the error, home if the servo is on (RST)") \
    X(C4G_CELL_CMD_CLO, "CLO", C4G_CELL_ARGS_NONE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_ALL, "clo|close", "", "", \
      "DEV clo            ask the device to close the connection (CLO)") \
    X(C4G_CELL_CMD_ACQ, "ACQ", C4G_CELL_ARGS_INT, 0, C4G_CELL_INT_MAX, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_CONDITIONING, "acq", "CAMERA", "camera id", \
      "conditioning acq CAMERA         acquire an image (ACQ), cameras 1..2 on cell-sim") \
    X(C4G_CELL_CMD_HND, "HND", C4G_CELL_ARGS_INT_ACTION, 0, C4G_CELL_INT_MAX, \
      C4G_CELL_REPLY_OK, C4G_CELL_ON_CONDITIONING, "hnd|gripper", "GRIPPER", "gripper id", \
      "conditioning hnd ID open|close  gripper valve (HND): 0 vacuum, 1 blow") \
    X(C4G_CELL_CMD_ITR, "ITR", C4G_CELL_ARGS_NONE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_MOTION, "itr", "", "", \
      "DEV itr            interrupt the motion (project extension ITR, as STP)") \
    X(C4G_CELL_CMD_PNP, "PNP", C4G_CELL_ARGS_CLEAR_POSE, 0, 0, C4G_CELL_REPLY_OK, \
      C4G_CELL_ON_ROBOT, "pnp", "", "", \
      "robot pnp clear=MM x=MM y=MM z=MM c=RAD  pick-and-place (project extension PNP):\n" \
      "                                          lift to Z=clear, travel, descend")

/** Expands one row of C4G_CELL_COMMANDS into its enum constant. */
#define C4G_CELL_X_CMD(cmd, head, args, lo, hi, reply, devices, words, arg, what, help) cmd,

/** Instruction heads: one constant per row of C4G_CELL_COMMANDS, in its order. */
typedef enum c4g_cell_cmd {
    C4G_CELL_COMMANDS(C4G_CELL_X_CMD)
    C4G_CELL_CMD_COUNT_
} c4g_cell_cmd_t;

/** Field formats. */
typedef enum c4g_cell_unit {
    C4G_CELL_UNIT_MM = 0, /**< length Sxxx.yyy, counts of 0.001 mm */
    C4G_CELL_UNIT_RAD,    /**< angle Sxx.yyyy, counts of 0.0001 rad */
    C4G_CELL_UNIT_INT     /**< integer Sxxxxx */
} c4g_cell_unit_t;

/** A pose: robot X, Y, Z [0.001 mm], C [0.0001 rad]; platform A, B [0.0001 rad]. */
typedef struct c4g_cell_pose {
    uint32_t n_axes;                  /**< 4 (robot) or 2 (platform) */
    int32_t v[C4G_CELL_AXES_MAX];     /**< counts; unused entries 0 */
} c4g_cell_pose_t;

/** A decoded (or to-be-encoded) instruction. */
typedef struct c4g_cell_instr {
    c4g_cell_cmd_t cmd;
    uint8_t relative;       /**< MOV: 1 = 'R' (relative), 0 = 'A' (absolute) */
    uint8_t open;           /**< HND: 1 = OPEN, 0 = CLOSE */
    int32_t value;          /**< OVR: percent 0..100; ACQ: camera id; HND: gripper id */
    int32_t clearance;      /**< PNP: travel height Z [0.001 mm] */
    c4g_cell_pose_t pose;   /**< MOV, PNP (PNP: always 4 axes) */
} c4g_cell_instr_t;

/** Reply kinds. */
typedef enum c4g_cell_reply_kind {
    C4G_CELL_REPLY_OK = 0,  /**< "OK" */
    C4G_CELL_REPLY_ER,      /**< "ER" + error number */
    C4G_CELL_REPLY_STA      /**< "OK" + status data (robot 50 chars, platform 34) */
} c4g_cell_reply_kind_t;

/** A decoded (or to-be-encoded) reply. */
typedef struct c4g_cell_reply {
    c4g_cell_reply_kind_t kind;
    int32_t error;          /**< ER: error number; STA: error field */
    uint8_t moving;         /**< STA: 1 = 'T' (moving) */
    uint8_t servo_on;       /**< STA: 1 = 'T' (servo on) */
    int32_t override_pct;   /**< STA: 0..100 */
    c4g_cell_pose_t pose;   /**< STA: position */
} c4g_cell_reply_t;

/** One row of the command table as the library sees it (c4g_cell_cmd_info()). */
typedef struct c4g_cell_cmd_info {
    c4g_cell_cmd_t cmd;
    const char *head;            /**< head text on the wire ("STA", "SRVON" ...), NUL-ended */
    size_t head_len;             /**< its length */
    c4g_cell_args_t args;        /**< argument layout */
    int32_t lo;                  /**< integer argument range (ARGS_INT, ARGS_INT_ACTION) */
    int32_t hi;
    c4g_cell_reply_kind_t reply; /**< kind of a successful reply */
    uint32_t devices;            /**< C4G_CELL_ON_* mask */
} c4g_cell_cmd_info_t;

/** Which part of a line a diagnostic points at. */
typedef enum c4g_cell_part {
    C4G_CELL_PART_NONE = 0, C4G_CELL_PART_HEAD, C4G_CELL_PART_FLAG, C4G_CELL_PART_VALUE,
    C4G_CELL_PART_AXIS, C4G_CELL_PART_MODE, C4G_CELL_PART_ACTION, C4G_CELL_PART_TERMINATOR,
    C4G_CELL_PART_LENGTH
} c4g_cell_part_t;

/** Decoder diagnostic: all members set on error. */
typedef struct c4g_cell_diag {
    c4g_status_t status; /**< same value the decoder returned */
    uint32_t column;          /**< 1-based column of the first offending character */
    c4g_cell_part_t part;     /**< what was being parsed there */
    int32_t axis;             /**< 0-based axis index for PART_AXIS, else -1 */
} c4g_cell_diag_t;


/**
 * Meaning of a wire error number (ER replies, STA error field): the spec's list
 * (+00000..+00003) and the project codes (+00101..+00107).
 * @param[out] project set to 1 for a project code, 0 for a spec code (may be NULL)
 * @return constant text; "unknown error number" (with *project 0) otherwise.
 */
const char *c4g_cell_error_text(int32_t code, int *project);

/** Head text of @p cmd as on the wire ("STA", "SRVON", "SRVOF"...); "???" if invalid. */
const char *c4g_cell_cmd_name(c4g_cell_cmd_t cmd);

/**
 * The command table's row of @p cmd (head, argument layout, reply, devices).
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (cmd outside the table).
 */
c4g_status_t c4g_cell_cmd_info(c4g_cell_cmd_t cmd, c4g_cell_cmd_info_t *out);

/**
 * Convert a real value to counts: rounds to the nearest count, halves away from
 * zero, then checks the field range (after rounding: +-999.9995 mm rounds out).
 * @param[in] unit C4G_CELL_UNIT_MM (value in mm), _RAD (rad) or _INT.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (unit),
 *         C4G_ERR_NONFINITE, C4G_ERR_RANGE.
 */
c4g_status_t c4g_cell_from_double(double value, c4g_cell_unit_t unit, int32_t *out);

/**
 * Convert decimal text ("[+-]digits[.digits]", no exponent, no spaces) to counts
 * exactly, with the same rounding rule as c4g_cell_from_double (nearest count,
 * halves away from zero) but applied to the decimal digits, so "1.0005" mm is
 * 1001 counts. Used for human input, where a binary double would round 1.0005
 * down.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (unit), C4G_ERR_LENGTH
 *         (empty), C4G_ERR_CELL_DIGIT (syntax), C4G_ERR_RANGE.
 */
c4g_status_t c4g_cell_from_text(const char *s, size_t len, c4g_cell_unit_t unit,
                                     int32_t *out);

/**
 * Convert counts to a real value (mm, rad or units). Exact to the printed digits.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (unit), C4G_ERR_RANGE.
 */
c4g_status_t c4g_cell_to_double(int32_t counts, c4g_cell_unit_t unit, double *out);

/**
 * Format one field: 8 chars (MM, RAD) or 6 chars (INT), no terminator.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG, C4G_ERR_CAPACITY,
 *         C4G_ERR_RANGE.
 */
c4g_status_t c4g_cell_field_encode(int32_t counts, c4g_cell_unit_t unit, char *buf,
                                        size_t cap, size_t *out_len);

/**
 * Parse one field of exactly 8 (MM, RAD) or 6 (INT) chars.
 * @param[out] diag optional; its column is relative to @p buf (1 = first char)
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG, C4G_ERR_LENGTH,
 *         C4G_ERR_CELL_SIGN, C4G_ERR_CELL_DIGIT, C4G_ERR_CELL_POINT.
 */
c4g_status_t c4g_cell_field_decode(const char *buf, size_t len, c4g_cell_unit_t unit,
                                        int32_t *out, c4g_cell_diag_t *diag);

/**
 * Encode an instruction with its CR LF. Validates first: OVR 0..100, ACQ and HND
 * ids 0..99999, MOV 2 or 4 axes, PNP 4 axes, every count within its field.
 * @param[out] out_len bytes written (no NUL is written)
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (cmd), C4G_ERR_AXES,
 *         C4G_ERR_RANGE, C4G_ERR_CAPACITY.
 */
c4g_status_t c4g_cell_instr_encode(const c4g_cell_instr_t *in, char *buf, size_t cap,
                                        size_t *out_len);

/**
 * Decode one instruction line (with CR LF). MOV's layout follows its length:
 * 38 chars robot (4 axes), 22 platform (2 axes). OVR must be 0..100 (RANGE),
 * ACQ/HND ids must be >= 0 (RANGE).
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_LENGTH, C4G_ERR_CELL_TERMINATOR,
 *         C4G_ERR_CELL_HEAD, C4G_ERR_CELL_SIGN, C4G_ERR_CELL_DIGIT, C4G_ERR_CELL_POINT,
 *         C4G_ERR_CELL_MODE, C4G_ERR_CELL_ACTION, C4G_ERR_RANGE; @p out is zeroed
 *         on error.
 */
c4g_status_t c4g_cell_instr_decode(const char *line, size_t len, c4g_cell_instr_t *out,
                                        c4g_cell_diag_t *diag);

/**
 * Encode a reply with its CR LF. OK: 4 chars; ER: error number 0..99999 (10
 * chars); STA: 4 axes -> robot (50), 2 axes -> platform (34), override 0..100.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG (kind), C4G_ERR_AXES,
 *         C4G_ERR_RANGE, C4G_ERR_CAPACITY.
 */
c4g_status_t c4g_cell_reply_encode(const c4g_cell_reply_t *in, char *buf, size_t cap,
                                        size_t *out_len);

/**
 * Decode one reply line (with CR LF): "OK" (4), "ER"+Sxxxxx (10), robot STA (50) or
 * platform STA (34). The STA override must be 0..100 (RANGE).
 * @return as c4g_cell_instr_decode (with C4G_ERR_CELL_FLAG); @p out zeroed on error.
 */
c4g_status_t c4g_cell_reply_decode(const char *line, size_t len, c4g_cell_reply_t *out,
                                        c4g_cell_diag_t *diag);

/**
 * Streaming line splitter for a TCP byte stream, over a caller-owned buffer whose
 * capacity is the line limit (C4G_CELL_LINE_MAX recommended). Lines end at LF and
 * are returned with their terminator; a line that does not fit is dropped up to
 * its LF and reported once as C4G_CELL_SPLIT_OVERLONG. Members are private.
 */
typedef struct c4g_cell_splitter {
    char *buf;          /**< caller storage */
    size_t cap;         /**< its size = longest accepted line, CR LF included */
    size_t head;        /**< first unconsumed byte */
    size_t tail;        /**< one past the last stored byte */
    uint32_t dropping;  /**< inside an overlong line: discard up to LF */
} c4g_cell_splitter_t;

/** What c4g_cell_split_next found. */
typedef enum c4g_cell_split_event {
    C4G_CELL_SPLIT_NONE = 0,   /**< no complete line: push more bytes */
    C4G_CELL_SPLIT_LINE,       /**< a line (valid until the next push/next call) */
    C4G_CELL_SPLIT_OVERLONG    /**< an overlong line was discarded (reported once) */
} c4g_cell_split_event_t;

/**
 * Attach @p buf (@p cap bytes, 4..65535) to @p sp and empty it.
 * @return C4G_OK, C4G_ERR_NULL, C4G_ERR_ARG.
 */
c4g_status_t c4g_cell_split_init(c4g_cell_splitter_t *sp, char *buf, size_t cap);

/**
 * Append up to @p n bytes of @p data (as many as fit; the rest stays with the
 * caller, who calls c4g_cell_split_next and pushes again).
 * @param[out] used bytes taken from @p data
 * @return C4G_OK, C4G_ERR_NULL (data may be NULL only when n is 0).
 */
c4g_status_t c4g_cell_split_push(c4g_cell_splitter_t *sp, const char *data, size_t n,
                                      size_t *used);

/**
 * Take the next event. @p line / @p len are set for C4G_CELL_SPLIT_LINE only.
 * @return C4G_OK, C4G_ERR_NULL.
 */
c4g_status_t c4g_cell_split_next(c4g_cell_splitter_t *sp, c4g_cell_split_event_t *ev,
                                      const char **line, size_t *len);

/* Deprecated (removed in 3.0): the cell layer's copies of the generic statuses. The cell
 * functions return the generic codes; these names stay for one release. */
#define C4G_ERR_CELL_NULL C4G_ERR_NULL
#define C4G_ERR_CELL_CAPACITY C4G_ERR_CAPACITY
#define C4G_ERR_CELL_ARG C4G_ERR_ARG
#define C4G_ERR_CELL_LENGTH C4G_ERR_LENGTH
#define C4G_ERR_CELL_RANGE C4G_ERR_RANGE
#define C4G_ERR_CELL_NONFINITE C4G_ERR_NONFINITE
#define C4G_ERR_CELL_AXES C4G_ERR_AXES

#ifdef __cplusplus
}
#endif
#endif /* C4GOPEN_CELL_H */
