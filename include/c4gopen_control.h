/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_control.h
 * @brief libc4gopen control layer: modes, safety filter, kinematics (included by c4gopen.h).
 */
#ifndef C4GOPEN_CONTROL_H
#define C4GOPEN_CONTROL_H
#ifndef C4GOPEN_H
#error "include c4gopen.h, not c4gopen_control.h"
#endif
#ifdef __cplusplus
extern "C" {
#endif

/** Short description of a control-layer status (-100..-199); used by c4g_strerror. */
const char *c4g_control_strerror(int status);

#ifdef __cplusplus
}
#endif
#endif /* C4GOPEN_CONTROL_H */
