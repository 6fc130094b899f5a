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

/** Instruction heads. */
typedef enum c4g_cell_cmd {
    C4G_CELL_CMD_STA = 0, /**< status */
    C4G_CELL_CMD_SRVON,   /**< servo on */
    C4G_CELL_CMD_SRVOF,   /**< servo off */
    C4G_CELL_CMD_OVR,     /**< set override 0..100 % */
    C4G_CELL_CMD_MOV,     /**< point-to-point motion, absolute or relative */
    C4G_CELL_CMD_STP,     /**< stop the motion */
    C4G_CELL_CMD_RST,     /**< reset (home) */
    C4G_CELL_CMD_CLO,     /**< close the connection */
    C4G_CELL_CMD_ACQ,     /**< acquire an image (camera id) */
    C4G_CELL_CMD_HND,     /**< open/close a gripper valve (gripper id) */
    C4G_CELL_CMD_ITR,     /**< project extension: interrupt the motion */
    C4G_CELL_CMD_PNP,     /**< project extension: pick-and-place motion */
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

/** Three-letter head of @p cmd ("STA", "SRV" for both servo commands...); "???" if invalid. */
const char *c4g_cell_cmd_name(c4g_cell_cmd_t cmd);

/**
 * Convert a real value to counts: rounds to the nearest count, halves away from
 * zero, then checks the field range (after rounding: +-999.9995 mm rounds out).
 * @param[in] unit C4G_CELL_UNIT_MM (value in mm), _RAD (rad) or _INT.
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG (unit),
 *         C4G_ERR_CELL_NONFINITE, C4G_ERR_CELL_RANGE.
 */
C4G_NODISCARD c4g_status_t c4g_cell_from_double(double value, c4g_cell_unit_t unit, int32_t *out);

/**
 * Convert decimal text ("[+-]digits[.digits]", no exponent, no spaces) to counts
 * exactly, with the same rounding rule as c4g_cell_from_double (nearest count,
 * halves away from zero) but applied to the decimal digits, so "1.0005" mm is
 * 1001 counts. Used for human input, where a binary double would round 1.0005
 * down.
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG (unit), C4G_ERR_CELL_LENGTH
 *         (empty), C4G_ERR_CELL_DIGIT (syntax), C4G_ERR_CELL_RANGE.
 */
C4G_NODISCARD c4g_status_t c4g_cell_from_text(const char *s, size_t len, c4g_cell_unit_t unit,
                                     int32_t *out);

/**
 * Convert counts to a real value (mm, rad or units). Exact to the printed digits.
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG (unit), C4G_ERR_CELL_RANGE.
 */
C4G_NODISCARD c4g_status_t c4g_cell_to_double(int32_t counts, c4g_cell_unit_t unit, double *out);

/**
 * Format one field: 8 chars (MM, RAD) or 6 chars (INT), no terminator.
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG, C4G_ERR_CELL_CAPACITY,
 *         C4G_ERR_CELL_RANGE.
 */
C4G_NODISCARD c4g_status_t c4g_cell_field_encode(int32_t counts, c4g_cell_unit_t unit, char *buf,
                                        size_t cap, size_t *out_len);

/**
 * Parse one field of exactly 8 (MM, RAD) or 6 (INT) chars.
 * @param[out] diag optional; its column is relative to @p buf (1 = first char)
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG, C4G_ERR_CELL_LENGTH,
 *         C4G_ERR_CELL_SIGN, C4G_ERR_CELL_DIGIT, C4G_ERR_CELL_POINT.
 */
C4G_NODISCARD c4g_status_t c4g_cell_field_decode(const char *buf, size_t len, c4g_cell_unit_t unit,
                                        int32_t *out, c4g_cell_diag_t *diag);

/**
 * Encode an instruction with its CR LF. Validates first: OVR 0..100, ACQ and HND
 * ids 0..99999, MOV 2 or 4 axes, PNP 4 axes, every count within its field.
 * @param[out] out_len bytes written (no NUL is written)
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG (cmd), C4G_ERR_CELL_AXES,
 *         C4G_ERR_CELL_RANGE, C4G_ERR_CELL_CAPACITY.
 */
C4G_NODISCARD c4g_status_t c4g_cell_instr_encode(const c4g_cell_instr_t *in, char *buf, size_t cap,
                                        size_t *out_len);

/**
 * Decode one instruction line (with CR LF). MOV's layout follows its length:
 * 38 chars robot (4 axes), 22 platform (2 axes). OVR must be 0..100 (RANGE),
 * ACQ/HND ids must be >= 0 (RANGE).
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_LENGTH, C4G_ERR_CELL_TERMINATOR,
 *         C4G_ERR_CELL_HEAD, C4G_ERR_CELL_SIGN, C4G_ERR_CELL_DIGIT, C4G_ERR_CELL_POINT,
 *         C4G_ERR_CELL_MODE, C4G_ERR_CELL_ACTION, C4G_ERR_CELL_RANGE; @p out is zeroed
 *         on error.
 */
C4G_NODISCARD c4g_status_t c4g_cell_instr_decode(const char *line, size_t len, c4g_cell_instr_t *out,
                                        c4g_cell_diag_t *diag);

/**
 * Encode a reply with its CR LF. OK: 4 chars; ER: error number 0..99999 (10
 * chars); STA: 4 axes -> robot (50), 2 axes -> platform (34), override 0..100.
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG (kind), C4G_ERR_CELL_AXES,
 *         C4G_ERR_CELL_RANGE, C4G_ERR_CELL_CAPACITY.
 */
C4G_NODISCARD c4g_status_t c4g_cell_reply_encode(const c4g_cell_reply_t *in, char *buf, size_t cap,
                                        size_t *out_len);

/**
 * Decode one reply line (with CR LF): "OK" (4), "ER"+Sxxxxx (10), robot STA (50) or
 * platform STA (34). The STA override must be 0..100 (RANGE).
 * @return as c4g_cell_instr_decode (with C4G_ERR_CELL_FLAG); @p out zeroed on error.
 */
C4G_NODISCARD c4g_status_t c4g_cell_reply_decode(const char *line, size_t len, c4g_cell_reply_t *out,
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
 * @return C4G_OK, C4G_ERR_CELL_NULL, C4G_ERR_CELL_ARG.
 */
C4G_NODISCARD c4g_status_t c4g_cell_split_init(c4g_cell_splitter_t *sp, char *buf, size_t cap);

/**
 * Append up to @p n bytes of @p data (as many as fit; the rest stays with the
 * caller, who calls c4g_cell_split_next and pushes again).
 * @param[out] used bytes taken from @p data
 * @return C4G_OK, C4G_ERR_CELL_NULL (data may be NULL only when n is 0).
 */
C4G_NODISCARD c4g_status_t c4g_cell_split_push(c4g_cell_splitter_t *sp, const char *data, size_t n,
                                      size_t *used);

/**
 * Take the next event. @p line / @p len are set for C4G_CELL_SPLIT_LINE only.
 * @return C4G_OK, C4G_ERR_CELL_NULL.
 */
C4G_NODISCARD c4g_status_t c4g_cell_split_next(c4g_cell_splitter_t *sp, c4g_cell_split_event_t *ev,
                                      const char **line, size_t *len);

#ifdef __cplusplus
}
#endif
#endif /* C4GOPEN_CELL_H */
