/* SPDX-License-Identifier: MIT */
/* Control layer: modes, safety filter, kinematics (placeholder until filled in). */
#include "c4gopen.h"

const char *c4g_control_strerror(int status)
{
    (void)status;
    return "unknown control-layer status";
}
