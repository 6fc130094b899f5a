/* SPDX-License-Identifier: MIT */
/* libFuzzer: c4g-server's trajectory CSV (tools/c4g-server/srv_files.c). Invariants: an
 * error is one well-formed "PATH:..." message; an accepted file has 1..20000 rows of
 * 1..10 columns, strictly increasing finite times and offsets within +-1e6 turns. */
#include "fuzz_text.h"
#include "srv_core.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static srv_traj_t tr;
    char err[512];
    c4gh_tf_file_t f;
    char *buf = fuzz_copy(data, size);
    uint32_t r, k;
    if (buf == NULL) {
        return 0;
    }
    c4gh_tf_open_mem(&f, "f.csv", buf, size);
    memset(err, 0x55, sizeof err);
    if (srv_parse_traj(&f, &tr, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "f.csv");
        free(buf);
        return 0;
    }
    if (tr.rows < 1U || tr.rows > SRV_MAX_TRAJ_ROWS || tr.cols < 1U || tr.cols > C4G_AXES_PER_ARM) {
        abort();
    }
    for (r = 0U; r < tr.rows; r++) {
        FUZZ_FINITE_IN(tr.t[r], 0.0, 1e7);
        if (r > 0U && !(tr.t[r] > tr.t[r - 1U])) {
            abort();
        }
        for (k = 0U; k < C4G_AXES_PER_ARM; k++) {
            FUZZ_FINITE_IN(tr.q[r][k], -1e6f, 1e6f);
            if (k >= tr.cols && tr.q[r][k] != 0.0f) {
                abort();
            }
        }
    }
    free(buf);
    return 0;
}
