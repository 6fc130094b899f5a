/* SPDX-License-Identifier: MIT */
/* libFuzzer: the kinematics file (lib/host/c4gh_kinfile.c through the shared INI layer and
 * inih). Invariants: an error is one well-formed "PATH:..." message; an accepted file has
 * 1..C4G_DYN_MAX_LINKS joints, each with kt > 0 and finite lengths, a chain the library
 * took, and the chain's gravity torques are finite at any joint angle. */
#include "fuzz_text.h"
#include "c4gh_kinfile.h"

#include <math.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static c4gh_kinfile_t k;
    char err[512];
    char *buf = fuzz_copy(data, size);
    double pi[C4G_DYN_MAX_LINKS * C4G_DYN_PARAMS];
    double q[C4G_DYN_MAX_LINKS];
    double z[C4G_DYN_MAX_LINKS];
    double tau[C4G_DYN_MAX_LINKS];
    uint32_t i;
    if (buf == NULL) {
        return 0;
    }
    memset(err, 0x55, sizeof err);
    if (c4gh_kin_parse_text("k.kin", buf, size, &k, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "k.kin");
        free(buf);
        return 0;
    }
    if (k.n < 1U || k.n > C4G_DYN_MAX_LINKS || k.chain.n != k.n) {
        abort();
    }
    for (i = 0U; i < k.n; i++) {
        if (!(k.j[i].kt > 0.0) || k.j[i].line < 1U) {
            abort();
        }
        FUZZ_FINITE_IN(k.j[i].a, -C4G_DYN_LENGTH_MAX, C4G_DYN_LENGTH_MAX);
        FUZZ_FINITE_IN(k.j[i].d, -C4G_DYN_LENGTH_MAX, C4G_DYN_LENGTH_MAX);
    }
    for (i = 0U; i < C4G_DYN_MAX_LINKS * C4G_DYN_PARAMS; i++) {
        pi[i] = (i % C4G_DYN_PARAMS == 0U) ? 10.0 : 0.5;
    }
    for (i = 0U; i < C4G_DYN_MAX_LINKS; i++) {
        q[i] = 0.7 * (double)i;
        z[i] = 0.0;
    }
    if (c4g_dyn_rnea(&k.chain, q, z, z, pi, NULL, tau) != C4G_OK) {
        abort();
    }
    free(buf);
    return 0;
}
