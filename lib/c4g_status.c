/* SPDX-License-Identifier: MIT */
/* Status catalogue, field names, and the controller errors of the manual's table 17.1. */
#include "c4gopen.h"


const char *c4g_strerror(int status)
{
    static const char *const wire_status_text[] = {
        "ok",
        "null pointer argument",
        "wrong datagram length",
        "output buffer too small",
        "bad sequence number (NUM)",
        "bad axis count",
        "unknown mode code",
        "non-finite float (NaN or infinity)",
        "value out of range",
        "initialization packet: nFieldPck must be 3 and nFieldAx 9",
        "initialization packet: inconsistent OpenAx axis maps",
        "initialization packet: sampling period out of 1..1000 ms",
        "not allowed in the current session phase",
        "argument out of range",
        "session ended (504 or lost controller)",
        "axis is not open",
    };
    const size_t count = (sizeof wire_status_text) / (sizeof wire_status_text[0]);
    const int n_wire = (int)count;
    const char *text = "unknown status";
    if ((status <= 0) && (status > -n_wire)) {
        text = wire_status_text[-status];
    } else if ((status <= -100) && (status > -200)) {
        text = c4g_control_strerror(status);
    } else if ((status <= -200) && (status > -300)) {
        text = c4g_cell_strerror(status);
    } else {
        /* unknown: keep the default text */
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
