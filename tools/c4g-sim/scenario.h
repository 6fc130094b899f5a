/* SPDX-License-Identifier: MIT */
/* c4g-sim scenario language: a PDL2-like script (manual figure 24.4). */
#ifndef SIM_SCENARIO_H
#define SIM_SCENARIO_H

#include <stddef.h>

#define SCN_MAX_CMDS 1024
#define SCN_MAX_VALUES 10

typedef enum scn_op {
    SCN_DRIVE_ON = 1, SCN_DRIVE_OFF, SCN_MOVE, SCN_MOVE_REL, SCN_WAIT_MOVE, SCN_DELAY,
    SCN_MODE, SCN_CMD, SCN_WAIT_PC, SCN_FREEZE, SCN_RESTART, SCN_EXIT_OPEN,
    SCN_OVERRIDE, SCN_SELECTOR, SCN_EXPECT_POS, SCN_EXPECT_MODE, SCN_EXPECT_ERROR, SCN_END
} scn_op_t;

typedef struct scn_cmd {
    scn_op_t op;
    int line;                    /* 1-based source line */
    int arm;                     /* 1..4, 0 = every arm */
    int n;                       /* values in v[] */
    double v[SCN_MAX_VALUES];    /* MOVE targets (turns), EXPECT value/tolerance */
    unsigned axes_mask;          /* MODE: logical axes (bit 0 = axis 1), 0 = every open axis */
    int iv;                      /* mode, CMD byte, logical axis (EXPECT), AUTO=0/PROG=1 */
    double ms;                   /* DELAY, FREEZE, WAIT PC timeout (0 = none), OVERRIDE pct */
    int nowait;                  /* MOVE ... NOWAIT */
    char name[48];               /* EXPECT ERROR name */
} scn_cmd_t;

typedef struct scn {
    int n;
    scn_cmd_t cmd[SCN_MAX_CMDS];
} scn_t;

/**
 * Parse a scenario text (@p path names it in messages). Returns 0, or -1 with
 * "PATH:LINE:COL: ..." in @p err. Never reads outside @p len bytes; lines over 511
 * bytes, NUL and other binary bytes, and numbers out of range are errors.
 */
int scn_parse(const char *path, const char *text, size_t len, scn_t *out, char *err,
              size_t errlen);

const char *scn_op_name(scn_op_t op);

#endif
