/* SPDX-License-Identifier: MIT */
/* The per-tick CSV rows: see c4g_tickcsv.h. Floats with 9 significant digits: every float32
 * reads back exactly. */
#include "c4g_tickcsv.h"

void c4g_tick_csv_row(FILE *f, double t_s, int32_t num, uint32_t axis, uint32_t arm,
                      uint32_t logical, const c4g_ctrl_axis_t *rx, uint32_t tx_infpar,
                      const c4g_pc_axis_t *tx)
{
    fprintf(f, "%.6f,%d,%u,%u,%u,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%u,%d,%.9g,%.9g,%.9g,"
            "%.9g,%.9g", t_s, (int)num, (unsigned)axis, (unsigned)arm, (unsigned)logical,
            (int)rx->mode, (double)rx->target_pos, (double)rx->target_vel, (double)rx->actual_pos,
            (double)rx->actual_vel, (double)rx->current_ref, (double)rx->ext[0],
            (double)rx->ext[1], (double)rx->ext[2], (unsigned)tx_infpar, (int)tx->mode,
            (double)tx->target_pos, (double)tx->target_vel, (double)tx->measure,
            (double)tx->vel_add, (double)tx->current_add);
}
