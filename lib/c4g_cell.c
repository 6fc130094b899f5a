/* SPDX-License-Identifier: MIT */
/* Cell protocol codec (placeholder until filled in). */
#include "c4gopen.h"

const char *c4g_cell_strerror(int status)
{
    (void)status;
    return "unknown cell-protocol status";
}
