/* SPDX-License-Identifier: MIT */
/* Test and demo fixtures built from the manual's figures. */
#ifndef C4GSIM_FIXTURES_H
#define C4GSIM_FIXTURES_H

#include "c4gopen.h"

/** The manual's figure 10.1 initialization packet (6 axes on ARM 1, 2 ms). */
c4g_status_t c4gsim_fig10_1(c4g_init_t *out);

#endif
