/* SPDX-License-Identifier: MIT */
/* libFuzzer: c4g-ident's mode-9 parameter file (lib/host/c4gh_ffmodel_load.c through
 * the shared INI layer and inih). Invariants: an error is one well-formed "PATH:..."
 * message; an accepted file names an arm 1..4, a period in (0, 1000] ms, at least one
 * axis, every number finite in its range, the checksum the text really has, and the
 * model gives a finite current anywhere in the fit's range (a model = ctrl axis: no Ja,
 * ga, gb; ks > 0; finite for any float EXT1, EXT2). A rigid-body file: a chain of 1..7
 * joints, [axis N] for exactly its motors, q_min < q_max, qd_max, qdd_max > 0, and its
 * evaluation (c4gh_ffr_current, on a plain transmission) finite at the range's corners. */
#include "fuzz_text.h"
#include "c4gh_ffmodel.h"

#include <math.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_axis(const c4gh_ffm_axis_t *p, int rigid)
{
    const double v = (p->v_max > 0.0) ? p->v_max : 1e3;
    const double a = (p->a_max > 0.0) ? p->a_max : 1e3;
    if (rigid ? (p->ctrl || p->ja != 0.0 || p->ga != 0.0 || p->gb != 0.0 || p->ks != 0.0)
              : (p->ctrl ? !(p->ja == 0.0 && p->ga == 0.0 && p->gb == 0.0 && p->ks > 0.0) : !(p->ja > 0.0))) {
        abort();
    }
    if (!(p->eps > 0.0) || p->line < 1 || memchr(p->variant, '\0', sizeof p->variant) == NULL) {
        abort();
    }
    FUZZ_FINITE_IN(p->ja, 0.0, 1e6);
    FUZZ_FINITE_IN(p->fv, 0.0, 1e6);
    FUZZ_FINITE_IN(p->fc, 0.0, 1e6);
    FUZZ_FINITE_IN(p->fs, 0.0, 1e6);
    FUZZ_FINITE_IN(p->vs, 0.0, 1e6);
    FUZZ_FINITE_IN(p->eps, 0.0, 1e6);
    FUZZ_FINITE_IN(p->v_max, 0.0, 1e6);
    FUZZ_FINITE_IN(p->a_max, 0.0, 1e6);
    FUZZ_FINITE_IN(p->off, -1e6, 1e6);
    FUZZ_FINITE_IN(p->ga, -1e6, 1e6);
    FUZZ_FINITE_IN(p->gb, -1e6, 1e6);
    FUZZ_FINITE_IN(p->delay, -1e6, 1e6);
    FUZZ_FINITE_IN(p->k1, -1e6, 1e6);
    FUZZ_FINITE_IN(p->k2, -1e6, 1e6);
    FUZZ_FINITE_IN(p->ks, 0.0, 1e6);
    if (p->ctrl && (!isfinite(c4gh_ffm_current_ctrl(p, v, a, 3.4e38, 3.4e38)) ||
                    !isfinite(c4gh_ffm_current_ctrl(p, -v, -a, -3.4e38, 3.4e38)))) {
        abort();
    }
    if (!isfinite(c4gh_ffm_current(p, v, a, 1.0, 1)) || !isfinite(c4gh_ffm_current(p, -v, -a, -1.0, 1)) ||
        !isfinite(c4gh_ffm_current(p, 0.0, 0.0, 0.0, 0))) {
        abort();
    }
}

/* The rigid model on a transmission of ratio 100 per axis, no coupling: finite currents at
 * the corners of the fitted range and at its centre. */
static void check_rigid(const c4gh_ffm_file_t *m)
{
    static c4gh_ffr_t r;
    c4g_kin_t kin;
    c4gh_ffr_out_t o;
    double qm[C4G_DYN_MAX_LINKS], vm[C4G_DYN_MAX_LINKS], am[C4G_DYN_MAX_LINKS];
    unsigned j, c;
    if (m->kin.n < 1U || m->kin.n > C4G_DYN_MAX_LINKS || m->kin.chain.n != m->kin.n) {
        abort();
    }
    for (j = 0U; j < C4GH_FFM_AXES; j++) {
        if ((m->ax[j].set != 0) != (j < m->kin.n)) {
            abort();
        }
    }
    for (j = 0U; j < m->kin.n; j++) {
        if (!(m->q_min[j] < m->q_max[j]) || !(m->qd_max[j] > 0.0) || !(m->qdd_max[j] > 0.0) ||
            !(m->kin.j[j].kt > 0.0)) {
            abort();
        }
    }
    memset(&kin, 0, sizeof kin);
    kin.period_s = 0.002;
    for (j = 0U; j < C4G_AXES_PER_ARM; j++) {
        kin.kr[j] = 100.0;
    }
    if (c4gh_ffr_setup(&r, m, &kin) != 0) {
        abort();
    }
    for (c = 0U; c < 3U; c++) {
        for (j = 0U; j < m->kin.n; j++) {
            const double s = (c == 0U) ? -1.0 : ((c == 1U) ? 1.0 : 0.0);
            const double q = (c == 0U) ? m->q_min[j] : ((c == 1U) ? m->q_max[j] : 0.5 * (m->q_min[j] + m->q_max[j]));
            qm[j] = 100.0 * q / 6.283185307179586;
            vm[j] = s * 100.0 * m->qd_max[j] / 6.283185307179586;
            am[j] = s * 100.0 * m->qdd_max[j] / 6.283185307179586;
        }
        if (c4gh_ffr_current(&r, qm, vm, am, &o) != 0) {
            abort();
        }
        for (j = 0U; j < m->kin.n; j++) {
            if (!isfinite(o.cur[j])) {
                abort();
            }
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static c4gh_ffm_file_t m;
    char err[512];
    char *buf = fuzz_copy(data, size);
    unsigned l, n = 0U;
    uint64_t sum = 0U;
    if (buf == NULL) {
        return 0;
    }
    memset(err, 0x55, sizeof err);
    if (c4gh_ffm_parse_text("f.ini", buf, size, &m, err, sizeof err) != 0) {
        fuzz_check_err(err, sizeof err, "f.ini");
        free(buf);
        return 0;
    }
    if (m.arm < 1U || m.arm > 4U || !(m.period_ms > 0.0 && m.period_ms <= 1000.0) ||
        c4gh_ffm_checksum_text(buf, size, &sum) != 0 || sum != m.checksum) {
        abort();
    }
    for (l = 0U; l < C4GH_FFM_AXES; l++) {
        if (m.ax[l].set) {
            check_axis(&m.ax[l], m.rigid);
            n++;
        }
    }
    if (n == 0U) {
        abort();
    }
    if (m.rigid) {
        check_rigid(&m);
    }
    free(buf);
    return 0;
}
