/* SPDX-License-Identifier: MIT */
/* Compatibility for one release: the control layer is now called the engine
 * (c4gopen_engine.h, lib/engine). Include c4gopen_engine.h; this header goes in 3.0. */
#ifndef C4GOPEN_CONTROL_H
#define C4GOPEN_CONTROL_H
#include "c4gopen_engine.h"
#endif
