/* SPDX-License-Identifier: MIT */
/* CiA 402 drive state machine: the statusword's states, the controlword toward a goal
   (master side) and the transitions a drive makes (drive side, for simulated nodes). */
#include "c4gopen_canopen.h"
#include "c4g_co_internal.h"

c4g_co_ds402_t c4g_co_ds402_state(uint16_t statusword)
{
    const uint16_t m4f = (uint16_t)(statusword & 0x4FU);
    const uint16_t m6f = (uint16_t)(statusword & 0x6FU);
    c4g_co_ds402_t s = C4G_CO_DS402_UNKNOWN;
    if (m4f == 0x00U) {
        s = C4G_CO_DS402_NOT_READY;
    } else if (m4f == 0x40U) {
        s = C4G_CO_DS402_SWITCH_ON_DISABLED;
    } else if (m6f == 0x21U) {
        s = C4G_CO_DS402_READY;
    } else if (m6f == 0x23U) {
        s = C4G_CO_DS402_SWITCHED_ON;
    } else if (m6f == 0x27U) {
        s = C4G_CO_DS402_ENABLED;
    } else if (m6f == 0x07U) {
        s = C4G_CO_DS402_QUICK_STOP;
    } else if (m4f == 0x0FU) {
        s = C4G_CO_DS402_FAULT_REACTION;
    } else if (m4f == 0x08U) {
        s = C4G_CO_DS402_FAULT;
    } else {
        s = C4G_CO_DS402_UNKNOWN;
    }
    return s;
}

const char *c4g_co_ds402_name(c4g_co_ds402_t state)
{
    const char *t = "unknown";
    switch (state) {
    case C4G_CO_DS402_NOT_READY: t = "not ready to switch on"; break;
    case C4G_CO_DS402_SWITCH_ON_DISABLED: t = "switch on disabled"; break;
    case C4G_CO_DS402_READY: t = "ready to switch on"; break;
    case C4G_CO_DS402_SWITCHED_ON: t = "switched on"; break;
    case C4G_CO_DS402_ENABLED: t = "operation enabled"; break;
    case C4G_CO_DS402_QUICK_STOP: t = "quick stop active"; break;
    case C4G_CO_DS402_FAULT_REACTION: t = "fault reaction active"; break;
    case C4G_CO_DS402_FAULT: t = "fault"; break;
    case C4G_CO_DS402_UNKNOWN:
    default: t = "unknown"; break;
    }
    return t;
}

/* Toward operation enabled. */
static uint16_t cw_enable(c4g_co_ds402_t s)
{
    uint16_t cw = C4G_CO_CW_DISABLE_VOLTAGE;
    if (s == C4G_CO_DS402_SWITCH_ON_DISABLED) {
        cw = C4G_CO_CW_SHUTDOWN;
    } else if (s == C4G_CO_DS402_READY) {
        cw = C4G_CO_CW_SWITCH_ON;
    } else if ((s == C4G_CO_DS402_SWITCHED_ON) || (s == C4G_CO_DS402_ENABLED)) {
        cw = C4G_CO_CW_ENABLE_OP;
    } else {
        cw = C4G_CO_CW_DISABLE_VOLTAGE; /* quick stop: leave it through switch on disabled */
    }
    return cw;
}

/* Toward ready to switch on. */
static uint16_t cw_ready(c4g_co_ds402_t s)
{
    uint16_t cw = C4G_CO_CW_SHUTDOWN;
    if (s == C4G_CO_DS402_QUICK_STOP) {
        cw = C4G_CO_CW_DISABLE_VOLTAGE;
    }
    return cw;
}

c4g_status_t c4g_co_ds402_command(uint16_t statusword, c4g_co_goal_t goal, uint16_t prev_cw,
                                  uint16_t *cw)
{
    c4g_status_t st = C4G_OK;
    const c4g_co_ds402_t s = c4g_co_ds402_state(statusword);
    if (cw == NULL) {
        st = C4G_ERR_NULL;
    } else if ((uint32_t)goal > (uint32_t)C4G_CO_GOAL_QUICK_STOP) {
        st = C4G_ERR_ARG;
    } else if (s == C4G_CO_DS402_FAULT) {
        /* fault reset acts on the rising edge of bit 7 */
        if ((prev_cw & C4G_CO_CW_FAULT_RESET) != 0U) {
            *cw = C4G_CO_CW_DISABLE_VOLTAGE;
        } else {
            *cw = C4G_CO_CW_FAULT_RESET;
        }
    } else if (goal == C4G_CO_GOAL_ENABLED) {
        *cw = cw_enable(s);
    } else if (goal == C4G_CO_GOAL_READY) {
        *cw = cw_ready(s);
    } else if (goal == C4G_CO_GOAL_QUICK_STOP) {
        if ((s == C4G_CO_DS402_ENABLED) || (s == C4G_CO_DS402_QUICK_STOP)) {
            *cw = C4G_CO_CW_QUICK_STOP;
        } else {
            *cw = C4G_CO_CW_DISABLE_VOLTAGE;
        }
    } else {
        *cw = C4G_CO_CW_DISABLE_VOLTAGE;
    }
    return st;
}

/* Drive side transitions on a controlword (CiA 402 device control commands). */
static c4g_co_ds402_t apply_cmd(c4g_co_ds402_t s, uint16_t cw)
{
    c4g_co_ds402_t n;
    const bool disable_voltage = (cw & 0x02U) == 0U;
    const bool quick_stop = ((cw & 0x06U) == 0x02U);
    const bool shutdown = ((cw & 0x07U) == 0x06U);
    const bool switch_on = ((cw & 0x0FU) == 0x07U);
    if (disable_voltage) {
        n = C4G_CO_DS402_SWITCH_ON_DISABLED;
    } else if (quick_stop) {
        n = ((s == C4G_CO_DS402_ENABLED) || (s == C4G_CO_DS402_QUICK_STOP))
                ? C4G_CO_DS402_QUICK_STOP
                : C4G_CO_DS402_SWITCH_ON_DISABLED;
    } else if (shutdown) {
        n = (s == C4G_CO_DS402_QUICK_STOP) ? s : C4G_CO_DS402_READY;
    } else if (switch_on) {
        n = ((s == C4G_CO_DS402_READY) || (s == C4G_CO_DS402_ENABLED)) ? C4G_CO_DS402_SWITCHED_ON
                                                                        : s;
    } else {
        /* bits 0-3 all set: enable operation */
        n = ((s == C4G_CO_DS402_SWITCHED_ON) || (s == C4G_CO_DS402_QUICK_STOP))
                ? C4G_CO_DS402_ENABLED
                : s;
    }
    if ((s == C4G_CO_DS402_SWITCH_ON_DISABLED) && (n != C4G_CO_DS402_READY)) {
        n = s; /* only shutdown leaves switch on disabled */
    }
    return n;
}

c4g_status_t c4g_co_ds402_apply(c4g_co_ds402_t state, uint16_t prev_cw, uint16_t cw,
                                c4g_co_ds402_t *next)
{
    c4g_status_t st = C4G_OK;
    if (next == NULL) {
        st = C4G_ERR_NULL;
    } else if ((uint32_t)state >= (uint32_t)C4G_CO_DS402_UNKNOWN) {
        st = C4G_ERR_ARG;
    } else if (state == C4G_CO_DS402_FAULT) {
        const bool edge = ((cw & C4G_CO_CW_FAULT_RESET) != 0U) &&
                          ((prev_cw & C4G_CO_CW_FAULT_RESET) == 0U);
        *next = edge ? C4G_CO_DS402_SWITCH_ON_DISABLED : state;
    } else if ((state == C4G_CO_DS402_NOT_READY) || (state == C4G_CO_DS402_FAULT_REACTION)) {
        /* automatic transitions of the drive, not commanded */
        *next = (state == C4G_CO_DS402_NOT_READY) ? C4G_CO_DS402_SWITCH_ON_DISABLED
                                                  : C4G_CO_DS402_FAULT;
    } else {
        *next = apply_cmd(state, cw);
    }
    return st;
}

c4g_status_t c4g_co_ds402_statusword(c4g_co_ds402_t state, uint16_t *sw)
{
    c4g_status_t st = C4G_OK;
    uint16_t v = 0U;
    switch (state) {
    case C4G_CO_DS402_NOT_READY: v = 0x0000U; break;
    case C4G_CO_DS402_SWITCH_ON_DISABLED: v = 0x0040U; break;
    case C4G_CO_DS402_READY: v = 0x0031U; break;
    case C4G_CO_DS402_SWITCHED_ON: v = 0x0033U; break;
    case C4G_CO_DS402_ENABLED: v = 0x0037U; break;
    case C4G_CO_DS402_QUICK_STOP: v = 0x0017U; break;
    case C4G_CO_DS402_FAULT_REACTION: v = 0x001FU; break;
    case C4G_CO_DS402_FAULT: v = 0x0018U; break;
    case C4G_CO_DS402_UNKNOWN:
    default: st = C4G_ERR_ARG; break;
    }
    if (sw == NULL) {
        st = C4G_ERR_NULL;
    } else if (st == C4G_OK) {
        *sw = (uint16_t)(v | 0x0200U);
    } else {
        /* st set above */
    }
    return st;
}
