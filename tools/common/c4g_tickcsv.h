/* SPDX-License-Identifier: MIT */
/* The per-tick CSV every tool writes the same way (docs/csv.md): one row per open axis per
 * cyclic packet, the controller's packet (rx_*) and the PC's reply (tx_*), named from the
 * PC's side. c4g-server --moni (type 0) writes exactly these columns; c4g-sim --csv adds its
 * own after them; c4g-ident fit reads any file that starts with them. */
#ifndef C4G_TICKCSV_H
#define C4G_TICKCSV_H

#include <stdint.h>
#include <stdio.h>

#include "c4gopen.h"

/* The header's columns (no newline): a tool may append its own. */
#define C4G_TICK_CSV_COLUMNS                                                                  \
    "t_s,num,axis,arm,logical,rx_mode,rx_d1,rx_d2,rx_d3,rx_d4,rx_d5,rx_e1,rx_e2,rx_e3,"      \
    "tx_infpar,tx_mode,tx_d1,tx_d2,tx_d3,tx_d4,tx_d5"

/* One row's columns (no newline): time [s], NUM, axis (1-based OPEN index), arm and
 * logical axis (1-based), the controller's axis, the reply's INFPAR and axis. */
void c4g_tick_csv_row(FILE *f, double t_s, int32_t num, uint32_t axis, uint32_t arm,
                      uint32_t logical, const c4g_ctrl_axis_t *rx, uint32_t tx_infpar,
                      const c4g_pc_axis_t *tx);

#endif
