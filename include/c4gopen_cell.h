/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen_cell.h
 * @brief libc4gopen cell protocol codec (STA/MOV/...; included by c4gopen.h).
 */
#ifndef C4GOPEN_CELL_H
#define C4GOPEN_CELL_H
#ifndef C4GOPEN_H
#error "include c4gopen.h, not c4gopen_cell.h"
#endif
#ifdef __cplusplus
extern "C" {
#endif

/** Short description of a cell-protocol status (-200..-299); used by c4g_strerror. */
const char *c4g_cell_strerror(int status);

#ifdef __cplusplus
}
#endif
#endif /* C4GOPEN_CELL_H */
