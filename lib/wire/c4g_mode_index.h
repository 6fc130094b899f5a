/* SPDX-License-Identifier: MIT */
/* The row index of a mode code in C4G_MODE_TABLE: a switch derived from the table, inlined
 * where a mode is checked per axis and tick (lookups, the codec's known-mode test). */
#ifndef C4G_MODE_INDEX_H
#define C4G_MODE_INDEX_H

#include "../c4g_internal.h"

/* Deviation D-05 (MISRA 20.10): the X-macro names each row by pasting its id. */
/* cppcheck-suppress misra-c2012-20.10 */
#define C4G_MODE_IX_(id, code, flags, fields, rules, op, from, name, text) C4G_MODE_IX_##id,
/* Deviation D-05 (MISRA 2.4): the row indexes are constants, the enum needs no tag. */
/* cppcheck-suppress misra-c2012-2.4 */
enum { C4G_MODE_TABLE(C4G_MODE_IX_) C4G_N_MODES_ };

/* Row index of @p mode, C4G_N_MODES_ for a code the protocol does not define. */
static inline uint32_t c4g_mode_index(int32_t mode)
{
    uint32_t i;
/* Deviation D-05 (MISRA 20.10), as above. */
/* cppcheck-suppress misra-c2012-20.10 */
#define C4G_MODE_CASE_(id, code, flags, fields, rules, op, from, name, text) \
    case (code): i = (uint32_t)C4G_MODE_IX_##id; break;
    switch (mode) {
    C4G_MODE_TABLE(C4G_MODE_CASE_)
    default: i = (uint32_t)C4G_N_MODES_; break;
    }
    return i;
}

#endif /* C4G_MODE_INDEX_H */
