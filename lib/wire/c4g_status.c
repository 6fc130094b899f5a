/* SPDX-License-Identifier: MIT */
/* Status catalogue, field names, and the controller errors of the manual's table 17.1. */
#include "c4gopen.h"


/* One switch over every status of every layer: a pointer table would sit in .data.rel.ro
 * under PIE and need an index per range. */
const char *c4g_strerror(c4g_status_t status)
{
    const char *text = "unknown status";
    switch (status) {
    case C4G_OK: text = "ok"; break;
    case C4G_ERR_NULL: text = "null pointer argument"; break;
    case C4G_ERR_LENGTH: text = "wrong datagram length"; break;
    case C4G_ERR_CAPACITY: text = "output buffer too small"; break;
    case C4G_ERR_NUM: text = "bad sequence number (NUM)"; break;
    case C4G_ERR_AXES: text = "bad axis count"; break;
    case C4G_ERR_MODE: text = "unknown mode code"; break;
    case C4G_ERR_NONFINITE: text = "non-finite float (NaN or infinity)"; break;
    case C4G_ERR_RANGE: text = "value out of range"; break;
    case C4G_ERR_INIT_FIELDS: text = "initialization packet: nFieldPck must be 3 and nFieldAx 9"; break;
    case C4G_ERR_INIT_MAP: text = "initialization packet: inconsistent OpenAx axis maps"; break;
    case C4G_ERR_PERIOD: text = "initialization packet: sampling period out of 1..1000 ms"; break;
    case C4G_ERR_STATE: text = "not allowed in the current session phase"; break;
    case C4G_ERR_ARG: text = "argument out of range"; break;
    case C4G_ERR_ENDED: text = "session ended (504 or lost controller)"; break;
    case C4G_ERR_NOT_OPEN: text = "axis is not open"; break;
    case C4G_ERR_FORBIDDEN: text = "mode change not allowed from the arm's current mode"; break;
    case C4G_ERR_DRIVING_ON: text = "refused: the arm is driving on (501)"; break;
    case C4G_ERR_NOT_MODE0: text = "active freezing only from mode 0"; break;
    case C4G_ERR_DRIVES_OFF: text = "refused: the arm's drives are off"; break;
    case C4G_ERR_MISSING_DATA: text = "a field the mode requires was not filled (arm sent 505)"; break;
    case C4G_ERR_NOT_IN_OPEN: text = "exit from open asked while in mode 0"; break;
    case C4G_ERR_LEAVING: text = "the arm is already leaving its mode"; break;
    case C4G_ERR_FROZEN: text = "refused: the arm is frozen"; break;
    case C4G_ERR_LATCHED: text = "refused: a drive off / following error is latched"; break;
    case C4G_ERR_PACKET: text = "packet does not match the control engine"; break;
    case C4G_ERR_SINGULAR: text = "kinematics: zero transmission ratio"; break;
    case C4G_ERR_LIMITS: text = "invalid limits (or a zero current limit for modes 1/2)"; break;
    case C4G_ERR_MODE_RESTORED: text = "the reply carried a forbidden mode: restored"; break;
    case C4G_ERR_PDL_ONLY: text = "only the controller's PDL2 program starts an operating mode"; break;
    case C4G_ERR_CELL_TERMINATOR: text = "cell: missing CR LF terminator, or CR/LF inside the line"; break;
    case C4G_ERR_CELL_HEAD: text = "cell: unknown instruction or reply head"; break;
    case C4G_ERR_CELL_SIGN: text = "cell: sign character must be '+' or '-'"; break;
    case C4G_ERR_CELL_DIGIT: text = "cell: digit expected"; break;
    case C4G_ERR_CELL_POINT: text = "cell: '.' expected"; break;
    case C4G_ERR_CELL_FLAG: text = "cell: 'T' or 'F' expected"; break;
    case C4G_ERR_CELL_MODE: text = "cell: MOV mode must be 'A' or 'R'"; break;
    case C4G_ERR_CELL_ACTION: text = "cell: HND action must be OPEN or CLOSE"; break;
    case C4G_ERR_CELL_OVERLONG: text = "cell: line longer than the splitter limit"; break;
    default: break;
    }
    return text;
}


const char *c4g_field_name(c4g_field_t field)
{
    static const char *const field_names[C4G_FIELD_COUNT_] = {
        "-", "length", "NUM", "INFPAR", "CMD", "SMax", "D1", "D2", "D3", "D4", "D5",
        "EXT1", "EXT2", "EXT3", "nFieldPck", "nFieldAx", "nAxOpen", "OpenMask",
        "field types", "period", "OpenAx", "CalData", "AzLim", "version", "AxInfo",
        "TxRate", "FollowError",
    };
    const char *name = "?";
    /* unsigned compare: enums may be unsigned (e.g. -fshort-enums on ARM EABI) */
    if ((uint32_t)field < (uint32_t)C4G_FIELD_COUNT_) {
        name = field_names[field];
    }
    return name;
}

typedef struct ctrl_error_text {
    const char *name;
    const char *message;
    const char *description;
} ctrl_error_text_t;


static const ctrl_error_text_t *ctrl_error_entry(c4g_ctrl_error_t err)
{
    /* Table 17.1 of the manual, names and messages verbatim. */
    static const ctrl_error_text_t ctrl_errors[C4G_CERR_COUNT_] = {
        {"NONE", "no error", "no error"},
        {"ERR_C4GOPEN_SKT_UDP", "C4GOpen: error opening the socket UDP port 1000",
         "It is not possible to set up a communication with the server, because it is "
         "impossible to open a UDP socket on 1000 port"},
        {"ERR_C4GOPEN_UDP", "C4GOpen: communication error",
         "The C4G did not receive the UDP packet from PC for 10 consecutive times"},
        {"ERR_C4GOPEN", "C4GOpen: configuration error",
         "Too many axes are being configured in an open modality"},
        {"ERR_C4GOPEN_CONFIGURATION_AX", "C4GOpen: Arm %d Axis %d not present",
         "The user is trying to configure the Open modality on an axis not configured for this"},
        {"ERR_C4GOPEN_UDP_DEBUG", "C4GOpen: Rx Debug", "C4G did not receive the packet coming from PC"},
        {"ERR_C4GOPEN_TX_UDP", "C4GOpen: error in socket UDP transmission",
         "It is not possible to send the UDP packet"},
        {"ERR_C4GOPEN_FOLLOW_ERROR", "C4GOpen: arm %s axis %d Following error out of range",
         "PC cannot maintain the following error under a certain limit. This is due to the "
         "value of the currents coming from PC"},
        {"ERR_C4GOPEN_OPT_HW", "C4GOpen: software option not allowed for arm %d",
         "It is not possible to enable the C4GOpen option on this controller"},
        {"ERR_C4GOPEN_DRIVEOFF_SERVER", "C4GOpen: Drive Off from Pc", "DRIVE OFF command from pc"},
        {"ERR_C4GOPEN_SET_0_MODALITY", "C4GOpen: arm %d , forced 0 modality",
         "The 0 modality has been forced after switching the state selector from AUTO to PROG "
         "or from PROG to AUTO when the modality was different from 0."},
    };
    const ctrl_error_text_t *e = NULL;
    if ((uint32_t)err < (uint32_t)C4G_CERR_COUNT_) {
        e = &ctrl_errors[err];
    }
    return e;
}

const char *c4g_ctrl_error_name(c4g_ctrl_error_t err)
{
    const ctrl_error_text_t *e = ctrl_error_entry(err);
    return (e != NULL) ? e->name : "?";
}

const char *c4g_ctrl_error_message(c4g_ctrl_error_t err)
{
    const ctrl_error_text_t *e = ctrl_error_entry(err);
    return (e != NULL) ? e->message : "?";
}

const char *c4g_ctrl_error_description(c4g_ctrl_error_t err)
{
    const ctrl_error_text_t *e = ctrl_error_entry(err);
    return (e != NULL) ? e->description : "?";
}
