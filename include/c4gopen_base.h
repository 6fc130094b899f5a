/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_base.h
 * @brief libc4gopen base: version, the one status type of every layer, c4g_strerror.
 *
 * Every function that can fail returns a c4g_status_t: C4G_OK (0) is success, negative
 * values are errors in stable ranges: -1..-99 wire layer and session, -100..-199 control
 * engine, -200..-299 cell protocol. c4g_strerror() gives a short constant text for any of
 * them. Status returns carry C4G_NODISCARD: ignoring one is a compiler warning where the
 * compiler supports the attribute.
 */
#ifndef C4GOPEN_BASE_H
#define C4GOPEN_BASE_H

#if !defined(__cplusplus) && (!defined(__STDC_VERSION__) || (__STDC_VERSION__ < 199901L))
#error "libc4gopen needs a C99 (or later) compiler"
#endif

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/** A poll's next deadline when no time can change anything (c4g_loop_poll,
 *  c4g_co_master_poll): only an input can. */
#define C4G_NO_DEADLINE UINT64_MAX

#ifdef __cplusplus
extern "C" {
#endif

/** @name Version (SemVer; any layout change of a public struct bumps MAJOR) */
/**@{*/
#define C4G_VERSION_MAJOR 2
#define C4G_VERSION_MINOR 0
#define C4G_VERSION_PATCH 0
#define C4G_VERSION_STRING "2.0.0"
/**@}*/

/**
 * Marks a function whose status must be used. Where a cast to void deliberately drops a
 * status the compiler must accept it, so the attribute is used where that holds: C23 and
 * C++17 [[nodiscard]], and clang's warn_unused_result (GCC's ignores the cast).
 */
#if defined(__cplusplus) && (__cplusplus >= 201703L)
#define C4G_NODISCARD [[nodiscard]]
#elif defined(__STDC_VERSION__) && (__STDC_VERSION__ >= 202311L)
#define C4G_NODISCARD [[nodiscard]]
#elif defined(__clang__)
#define C4G_NODISCARD __attribute__((warn_unused_result))
#else
#define C4G_NODISCARD
#endif

/** Status codes of every layer. Stable: values never change meaning. */
typedef enum c4g_status {
    C4G_OK = 0,
    /* wire layer and session: -1..-99 */
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
    /* control engine: -100..-199 (-103 and -106 retired) */
    C4G_ERR_FORBIDDEN = -101,     /**< mode change not allowed from the arm's current mode */
    C4G_ERR_DRIVING_ON = -102,    /**< refused: the arm is driving on (501) */
    C4G_ERR_NOT_MODE0 = -104,     /**< active freezing is only allowed from mode 0 */
    C4G_ERR_DRIVES_OFF = -105,    /**< refused: the arm's drives are off (INFPAR) */
    C4G_ERR_MISSING_DATA = -107,  /**< a field the mode requires was not filled (505 sent) */
    C4G_ERR_NOT_IN_OPEN = -108,   /**< exit from open asked while the arm is in mode 0 */
    C4G_ERR_LEAVING = -109,       /**< the arm is already leaving its mode (stand-by) */
    C4G_ERR_FROZEN = -110,        /**< refused: the arm is frozen (500/502) */
    C4G_ERR_LATCHED = -111,       /**< refused: a drive-off / following error is latched */
    C4G_ERR_PACKET = -112,        /**< packet does not match the control engine's session */
    C4G_ERR_SINGULAR = -113,      /**< kinematics: zero transmission ratio */
    C4G_ERR_LIMITS = -114,        /**< limits invalid, or a current limit of 0 for modes 1/2 */
    C4G_ERR_MODE_RESTORED = -115, /**< the reply carried a mode the rules forbid; restored */
    C4G_ERR_PDL_ONLY = -116,      /**< operating modes are started by the PDL2 program only */
    /* cell protocol: -200..-299 */
    /* cell: the generic codes above serve for NULL, capacity, argument, length, range,
     * non-finite and axis-count errors; these are the string protocol's own */
    C4G_ERR_CELL_TERMINATOR = -205, /**< missing CR LF, or CR/LF inside */
    C4G_ERR_CELL_HEAD = -206,       /**< unknown instruction or reply head */
    C4G_ERR_CELL_SIGN = -207,       /**< sign character is not '+' or '-' */
    C4G_ERR_CELL_DIGIT = -208,      /**< digit expected */
    C4G_ERR_CELL_POINT = -209,      /**< '.' expected */
    C4G_ERR_CELL_FLAG = -210,       /**< 'T' or 'F' expected */
    C4G_ERR_CELL_MODE = -211,       /**< MOV mode is not 'A' or 'R' */
    C4G_ERR_CELL_ACTION = -212,     /**< HND action is not OPEN or CLOSE */
    C4G_ERR_CELL_OVERLONG = -216    /**< line longer than the splitter limit */
} c4g_status_t;

/** Short, constant, never-NULL description of any status code ("unknown status" for a
 *  value no layer defines). */
const char *c4g_strerror(c4g_status_t status);

#ifdef __cplusplus
}
#endif

#endif /* C4GOPEN_BASE_H */
