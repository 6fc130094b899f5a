/* SPDX-License-Identifier: MIT */
/* libFuzzer: c4g-sim's scenario parser (tools/c4g-sim/scenario.c). Invariants: an
 * error is one well-formed "PATH:LINE..." message; an accepted script has only known
 * commands with arms, axes, values and times inside their documented ranges. */
#include "fuzz_text.h"
#include "scenario.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static scn_t s; /* big: keep off the fuzzer's stack */
    char err[512];
    char *buf = fuzz_copy(data, size);
    int i, k, prev = 0;
    if (buf == NULL) {
        return 0;
    }
    memset(err, 0x55, sizeof err);
    if (scn_parse("f.scn", buf, size, &s, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "f.scn");
        free(buf);
        return 0;
    }
    if (s.n < 0 || s.n > SCN_MAX_CMDS) {
        abort();
    }
    for (i = 0; i < s.n; i++) {
        const scn_cmd_t *c = &s.cmd[i];
        if ((int)c->op < 1 || (int)c->op > (int)SCN_END || c->arm < 0 || c->arm > 4 ||
            c->n < 0 || c->n > SCN_MAX_VALUES || c->line <= prev || c->axes_mask > 0x3FFU ||
            memchr(c->name, '\0', sizeof c->name) == NULL) {
            abort();
        }
        prev = c->line;
        for (k = 0; k < c->n; k++) {
            FUZZ_FINITE_IN(c->v[k], -1e6, 1e6);
        }
        FUZZ_FINITE_IN(c->ms, 0.0, 3.6e6);
        if (c->op == SCN_OVERRIDE) {
            FUZZ_FINITE_IN(c->ms, 0.0, 100.0);
        }
        if ((c->op == SCN_MODE && (c->iv < 0 || c->iv > 1000)) ||
            (c->op == SCN_CMD && (c->iv < 0 || c->iv > 255)) ||
            (c->op == SCN_EXPECT_MODE && (c->v[0] < 0.0 || c->v[0] > 1000.0 ||
                                          c->v[0] != (double)(int)c->v[0]))) {
            abort();
        }
    }
    free(buf);
    return 0;
}
