/* SPDX-License-Identifier: MIT */
/* libFuzzer: c4g-server's mode-9 feedforward parameter file (tools/c4g-server/srv_files.c).
 * Invariants: an error is one well-formed "PATH:..." message; an accepted file sets at
 * least one axis, each once, with finite coefficients within +-1e6. */
#include "fuzz_text.h"
#include "srv_core.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static srv_ff_t ff[C4G_ARMS][C4G_AXES_PER_ARM];
    char err[512];
    c4gh_tf_file_t f;
    char *buf = fuzz_copy(data, size);
    unsigned a, l, n = 0U;
    if (buf == NULL) {
        return 0;
    }
    memset(ff, 0, sizeof ff);
    c4gh_tf_open_mem(&f, "f.txt", buf, size);
    memset(err, 0x55, sizeof err);
    if (srv_parse_ff(&f, ff, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "f.txt");
        free(buf);
        return 0;
    }
    for (a = 0U; a < C4G_ARMS; a++) {
        for (l = 0U; l < C4G_AXES_PER_ARM; l++) {
            const srv_ff_t *p = &ff[a][l];
            if (p->set == 0) {
                continue;
            }
            n++;
            FUZZ_FINITE_IN(p->c0, -1e6, 1e6);
            FUZZ_FINITE_IN(p->cv, -1e6, 1e6);
            FUZZ_FINITE_IN(p->cc, -1e6, 1e6);
            FUZZ_FINITE_IN(p->ca, -1e6, 1e6);
            FUZZ_FINITE_IN(p->gs, -1e6, 1e6);
            FUZZ_FINITE_IN(p->gscale, -1e6, 1e6);
            FUZZ_FINITE_IN(p->gphase, -1e6, 1e6);
        }
    }
    if (n == 0U) {
        abort();
    }
    free(buf);
    return 0;
}
