/* SPDX-License-Identifier: MIT */
/* CSV text of monitoring records (moni types 19..24) and the tools' float format. */
#ifndef C4GH_CSV_H
#define C4GH_CSV_H

#include "c4gopen.h"
#include <stdint.h>
#include <stdio.h>

/** Fixed decimals the CSV formatter writes (|v| < 1e9; larger values in d.dddddde+XX). */
#define C4GH_MONI_DECIMALS 6U
/** Longest CSV row, bytes including the newline. */
#define C4GH_MONI_ROW_MAX 160U

/** CSV header of @p type ("type,num,axis,mode,pc_d1,...\n"), NUL-terminated.
 *  @return OK, NULL, ARG, CAPACITY. */
c4g_status_t c4gh_moni_csv_header(uint32_t type, char *buf, size_t cap, size_t *len);
/** One CSV row, NUL-terminated; *len excludes the NUL. @return OK, NULL, ARG, CAPACITY. */
c4g_status_t c4gh_moni_csv_row(const c4g_moni_rec_t *rec, char *buf, size_t cap, size_t *len);
/** Format @p v with C4GH_MONI_DECIMALS decimals: "-12.500000", "nan", "inf".
 *  @return OK, NULL, CAPACITY. */
c4g_status_t c4gh_fmt_float(float v, char *buf, size_t cap, size_t *len);

/* The per-tick CSV every tool writes the same way (docs/csv.md): one row per open axis per
 * cyclic packet, the controller's packet (rx_*) and the PC's reply (tx_*), named from the
 * PC's side. */
/* The header's columns (no newline): a tool may append its own. */
#define C4GH_TICK_CSV_COLUMNS                                                                  \
    "t_s,num,axis,arm,logical,rx_mode,rx_d1,rx_d2,rx_d3,rx_d4,rx_d5,rx_e1,rx_e2,rx_e3,"      \
    "tx_infpar,tx_mode,tx_d1,tx_d2,tx_d3,tx_d4,tx_d5"

/* One row's columns (no newline): time [s], NUM, axis (1-based OPEN index), arm and
 * logical axis (1-based), the controller's axis, the reply's INFPAR and axis. */
void c4gh_tick_csv_row(FILE *f, double t_s, int32_t num, uint32_t axis, uint32_t arm,
                      uint32_t logical, const c4g_ctrl_axis_t *rx, uint32_t tx_infpar,
                      const c4g_pc_axis_t *tx);

#endif
