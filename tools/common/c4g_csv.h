/* SPDX-License-Identifier: MIT */
/* CSV text of monitoring records (moni types 19..24) and the tools' float format. */
#ifndef C4G_CSV_H
#define C4G_CSV_H

#include "c4gopen.h"
#include "c4g_csv.h"

/** Fixed decimals the CSV formatter writes (|v| < 1e9; larger values in d.dddddde+XX). */
#define C4G_MONI_DECIMALS 6U
/** Longest CSV row, bytes including the newline. */
#define C4G_MONI_ROW_MAX 160U

/** CSV header of @p type ("type,num,axis,mode,pc_d1,...\n"), NUL-terminated.
 *  @return OK, NULL, ARG, CAPACITY. */
c4g_status_t c4g_moni_csv_header(uint32_t type, char *buf, size_t cap, size_t *len);
/** One CSV row, NUL-terminated; *len excludes the NUL. @return OK, NULL, ARG, CAPACITY. */
c4g_status_t c4g_moni_csv_row(const c4g_moni_rec_t *rec, char *buf, size_t cap, size_t *len);
/** Format @p v with C4G_MONI_DECIMALS decimals: "-12.500000", "nan", "inf".
 *  @return OK, NULL, CAPACITY. */
c4g_status_t c4g_fmt_float(float v, char *buf, size_t cap, size_t *len);

#endif
