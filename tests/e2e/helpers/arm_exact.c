/* SPDX-License-Identifier: MIT */
/* arm_exact: the EXACT rigid parameter file (model = rigid-body-1, docs/c4g-server.md
 * "Mode-9 parameter files") of c4g-sim's arm plant, for tests and measurements only (never
 * used by c4g-ident, which finds the parameters from data). It opens the plant as c4g-sim
 * does (plant_arm_open: the MJCF model, each joint's armature from the motors' rotor
 * inertias through the transmission, the payload) and writes:
 *   - each link's ten parameters about its frame origin in the kinematics file's chain:
 *     every MuJoCo body's mass, centre and inertia (MuJoCo's xipos, ximat at q = 0) moved
 *     into the frame of the link whose joint carries it (the chain's forward kinematics at
 *     q = 0), summed per link (the payload body goes to link 6);
 *   - ia_j: the plant's armature of joint j;
 *   - each motor's friction in current (c4g-sim's axis defaults: Fv = fv 2 pi / kt,
 *     Fc = fc / kt, eps = the plant's smoothing speed);
 * after checking that the kinematics file puts every joint where the model has it (axis
 * direction and a point on the axis). Usage in main()'s help. Built by make e2e-helpers;
 * tests/tools/test_arm_exact.c includes this file (ARM_EXACT_NO_MAIN) to reach its
 * functions and proves the result against MuJoCo's inverse dynamics. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mujoco/mujoco.h>

#include "c4gh_ffmodel.h"
#include "c4gh_kinfile.h"
#include "c4gopen_dyn.h"
#include "c4gsim_fixtures.h"
#include "c4gsim_model.h"
#include "plant_arm.h"
#include "sim.h"

#define AX PLANT_AXES
#define TWO_PI 6.283185307179586

/* What the file holds besides the kinematics. */
typedef struct exact {
    double pi[AX * C4G_DYN_PARAMS];
    double ia[AX];
    c4gsim_axis_params_t p[AX];   /* c4g-sim's motors */
} exact_t;

/* The init packet c4g-sim sends for arm 1 with its default axes (sim.c: figure 10.1 with
 * the axis parameters' TxRate, AxInfo and CalData, as floats). */
static void exact_init(c4g_init_t *init, c4gsim_axis_params_t p[AX])
{
    unsigned l;
    (void)c4gsim_fig10_1(init);
    for (l = 0U; l < AX; l++) {
        (void)c4gsim_axis_params_default(&p[l], l);
        init->tx_rate[0][l] = (float)p[l].tx_rate;
        init->ax_info[0][l] = (float)p[l].ax_info;
        init->cal_data[0][l] = (float)p[l].cal;
    }
}

/* Link frames of the chain at q = 0 in the base frame: R (columns: the frame's axes), o. */
static void chain_frames(const c4g_dyn_chain_t *ch, double R[][3][3], double o[][3])
{
    double Rp[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double op[3] = {0, 0, 0};
    uint32_t i;
    int r, c, k;
    for (i = 0U; i < ch->n; i++) {
        const c4g_dyn_joint_t *J = &ch->j[i];
        const double ct = cos(J->theta0), st = sin(J->theta0);
        const double rz[3][3] = {{ct, -st, 0}, {st, ct, 0}, {0, 0, 1}};
        double t[3][3];
        for (r = 0; r < 3; r++) {
            o[i][r] = op[r];
            for (k = 0; k < 3; k++) {
                o[i][r] += Rp[r][k] * J->pos[k];
            }
            for (c = 0; c < 3; c++) {
                t[r][c] = 0.0;
                for (k = 0; k < 3; k++) {
                    t[r][c] += Rp[r][k] * J->rot[k][c];
                }
            }
        }
        for (r = 0; r < 3; r++) {
            for (c = 0; c < 3; c++) {
                R[i][r][c] = 0.0;
                for (k = 0; k < 3; k++) {
                    R[i][r][c] += t[r][k] * rz[k][c];
                }
            }
        }
        memcpy(Rp, R[i], sizeof Rp);
        memcpy(op, o[i], sizeof op);
    }
}

/* The joint whose motion carries body b (its nearest ancestor with a joint), or -1. */
static int carrier(const mjModel *m, int b)
{
    while (b > 0) {
        if (m->body_jntnum[b] > 0) {
            return m->body_jntadr[b];
        }
        b = m->body_parentid[b];
    }
    return -1;
}

/* Every body's inertial into its link's frame, summed per link; the joints checked against
 * the chain (direction within 1e-9, the model's anchor on the chain's axis within 1e-9 m). */
static int exact_links(const mjModel *m, const c4gh_kinfile_t *kin, exact_t *x, char *err, size_t errlen)
{
    double R[C4G_DYN_MAX_LINKS][3][3], o[C4G_DYN_MAX_LINKS][3];
    mjData *d = mj_makeData(m);
    int b, j, r, c, k;
    if (d == NULL) {
        snprintf(err, errlen, "MuJoCo could not allocate its data");
        return -1;
    }
    if ((int)kin->n != AX || m->njnt != AX) {
        snprintf(err, errlen, "the kinematics has %u joints, the model %d: want %d", (unsigned)kin->n, m->njnt, AX);
        mj_deleteData(d);
        return -1;
    }
    mj_resetData(m, d); /* q = 0 */
    mj_forward(m, d);
    chain_frames(&kin->chain, R, o);
    for (j = 0; j < AX; j++) {
        const double *ax = &d->xaxis[3 * j];
        const double *an = &d->xanchor[3 * j];
        double dz = 0.0, w[3], cr[3];
        for (r = 0; r < 3; r++) {
            dz += fabs(ax[r] - R[j][r][2]);
            w[r] = an[r] - o[j][r];
        }
        cr[0] = w[1] * R[j][2][2] - w[2] * R[j][1][2];
        cr[1] = w[2] * R[j][0][2] - w[0] * R[j][2][2];
        cr[2] = w[0] * R[j][1][2] - w[1] * R[j][0][2];
        if (dz > 1e-9 || sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) > 1e-9) {
            snprintf(err, errlen, "joint %d: the model's axis (%g %g %g) through (%g %g %g) is not the "
                     "kinematics' z (%g %g %g) through (%g %g %g)", j + 1, ax[0], ax[1], ax[2], an[0], an[1],
                     an[2], R[j][0][2], R[j][1][2], R[j][2][2], o[j][0], o[j][1], o[j][2]);
            mj_deleteData(d);
            return -1;
        }
        x->ia[j] = m->dof_armature[m->jnt_dofadr[j]];
    }
    memset(x->pi, 0, sizeof x->pi);
    for (b = 1; b < m->nbody; b++) {
        const int l = carrier(m, b);
        const double *xm = &d->ximat[9 * b]; /* row-major: world = xm local */
        const double *I = &m->body_inertia[3 * b];
        double c3[3], iw[3][3], il[3][3], icom[6], pb[10];
        if (l < 0 || m->body_mass[b] == 0.0) {
            continue; /* the base, or an empty body (no payload) */
        }
        for (r = 0; r < 3; r++) {
            c3[r] = 0.0;
            for (k = 0; k < 3; k++) {
                c3[r] += R[l][k][r] * (d->xipos[3 * b + k] - o[l][k]);
            }
            for (c = 0; c < 3; c++) {
                iw[r][c] = 0.0;
                for (k = 0; k < 3; k++) {
                    iw[r][c] += xm[3 * r + k] * I[k] * xm[3 * c + k];
                }
            }
        }
        for (r = 0; r < 3; r++) { /* R^T Iw R */
            for (c = 0; c < 3; c++) {
                double s = 0.0;
                int a2;
                for (k = 0; k < 3; k++) {
                    for (a2 = 0; a2 < 3; a2++) {
                        s += R[l][k][r] * iw[k][a2] * R[l][a2][c];
                    }
                }
                il[r][c] = s;
            }
        }
        icom[0] = il[0][0];
        icom[1] = il[0][1];
        icom[2] = il[0][2];
        icom[3] = il[1][1];
        icom[4] = il[1][2];
        icom[5] = il[2][2];
        if (c4g_dyn_params_from_com(m->body_mass[b], c3, icom, pb) != C4G_OK) {
            snprintf(err, errlen, "body %d: its inertial is refused", b);
            mj_deleteData(d);
            return -1;
        }
        for (k = 0; k < 10; k++) {
            x->pi[(l * 10) + k] += pb[k];
        }
    }
    mj_deleteData(d);
    return 0;
}

/* The plant as c4g-sim opens it (payload @p pm at @p pc, flange frame), then every figure. */
static int exact_compute(const char *xml, const c4gh_kinfile_t *kin, double pm, const double pc[3], exact_t *x,
                         plant_arm_t **keep, char *err, size_t errlen)
{
    c4g_init_t init;
    plant_cfg_t cfg;
    plant_arm_t *pa = NULL;
    const c4gsim_axis_params_t *pp[AX];
    int l, rc;
    exact_init(&init, x->p);
    for (l = 0; l < AX; l++) {
        pp[l] = &x->p[l];
    }
    plant_cfg_default(&cfg);
    snprintf(cfg.path, sizeof cfg.path, "%s", xml);
    cfg.payload = pm;
    memcpy(cfg.payload_com, pc, sizeof cfg.payload_com);
    if (plant_arm_open(&pa, &cfg, &init, 0U, pp, 5e-4, err, errlen) != 0) {
        return -1;
    }
    rc = exact_links((const mjModel *)plant_arm_mjmodel(pa), kin, x, err, errlen);
    if (keep != NULL && rc == 0) {
        *keep = pa;
    } else {
        plant_arm_close(pa);
    }
    return rc;
}

#define W(...) (n += (size_t)snprintf(out + n, (n < cap) ? cap - n : 0U, __VA_ARGS__))

/* The file's text into @p out (sealed with its checksum); ranges as given. 0, or -1: too small. */
static int exact_write(char *out, size_t cap, const c4gh_kinfile_t *kin, const exact_t *x, const char *source,
                       const double qr[2], double qd_max, double qdd_max)
{
    static const char *const nm[10] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
    size_t n = 0U;
    uint64_t sum = 0U;
    char hex[25];
    char *line;
    int j, k;
    W("# The EXACT rigid-body parameters of c4g-sim's arm plant (tests/e2e/helpers/arm_exact.c)\n");
    W("[model]\nformat = c4g-ident 1\nmodel = rigid-body-1\narm = 1\nperiod_ms = 2\n");
    W("source = %s\ncreated_by = arm_exact\nrange = clamp\nconsistent = 1\n", source);
    W("checksum = fnv1a64:0000000000000000\n\n[kinematics]\nconvention = %s\nangles = %s\n",
      (kin->conv == C4G_DYN_DH_MODIFIED) ? "modified" : "standard", kin->deg ? "deg" : "rad");
    W("gravity = %.17g %.17g %.17g\n", kin->gravity[0], kin->gravity[1], kin->gravity[2]);
    for (j = 0; j < AX; j++) {
        const c4gh_kin_joint_t *J = &kin->j[j];
        const c4gsim_axis_params_t *p = &x->p[j];
        W("\n[joint %d]\na = %.17g\nalpha = %.17g\nd = %.17g\ntheta0 = %.17g\nkt = %.17g\n", j + 1, J->a, J->alpha,
          J->d, J->theta0, J->kt);
        for (k = 0; k < 10; k++) {
            W("%s = %.17g\n", nm[k], x->pi[(j * 10) + k]);
        }
        W("ia = %.17g\nq_min = %.17g\nq_max = %.17g\nqd_max = %.17g\nqdd_max = %.17g\n", x->ia[j], qr[0], qr[1],
          qd_max, qdd_max);
        W("\n[axis %d]\nvariant = %s\nFv = %.17g\nFc = %.17g\n", j + 1, (p->vs > 0.0) ? "stribeck" : "coulomb",
          p->fv * TWO_PI / p->kt, p->fc / p->kt);
        if (p->vs > 0.0) {
            W("Fs = %.17g\nvs = %.17g\n", p->fs / p->kt, p->vs);
        }
        W("off = 0\neps = %.17g\n", (double)PLANT_FRICTION_EPS);
    }
    if (n >= cap || c4gh_ffm_checksum_text(out, n, &sum) != 0) {
        return -1;
    }
    c4gh_ffm_checksum_format(sum, hex);
    line = strstr(out, "checksum = fnv1a64:");
    memcpy(line + 11, hex, 24U);
    return 0;
}
#undef W

#ifndef ARM_EXACT_NO_MAIN
static const char usage[] =
    "usage: arm_exact [--model XML] [--kin FILE] [--payload KG[@X,Y,Z]] [--q-range LO,HI]\n"
    "                 [--qd-max RAD/S] [--qdd-max RAD/S2] [--out FILE]\n"
    "The EXACT model = rigid-body-1 parameter file of c4g-sim's arm plant (c4g-sim's default axes),\n"
    "for tests and measurements. Defaults: fixtures/sim/smart-six.xml, fixtures/ident/smart-six.kin,\n"
    "no payload, range -6.3,6.3 rad, 20 rad/s, 1000 rad/s^2, standard output.\n"
    "example: arm_exact --payload 6@0,0,0.05 --out exact.ini\n"
    "         arm_exact --q-range -0.1,0.1 --out narrow.ini   (a file whose range a move leaves)\n";

int main(int argc, char **argv)
{
    static const struct option lo[] = {
        {"model", required_argument, NULL, 'm'}, {"kin", required_argument, NULL, 'k'},
        {"payload", required_argument, NULL, 'p'}, {"q-range", required_argument, NULL, 'q'},
        {"qd-max", required_argument, NULL, 'v'}, {"qdd-max", required_argument, NULL, 'a'},
        {"out", required_argument, NULL, 'o'}, {"help", no_argument, NULL, 'h'}, {NULL, 0, NULL, 0}};
    const char *xml = "fixtures/sim/smart-six.xml", *kinp = "fixtures/ident/smart-six.kin", *outp = NULL;
    double pm = 0.0, pc[3] = {0.0, 0.0, 0.0}, qr[2] = {-6.3, 6.3}, qd_max = 20.0, qdd_max = 1000.0;
    static c4gh_kinfile_t kin;
    static exact_t x;
    static char text[1 << 16];
    char err[1024];
    char src[600];
    int c;
    while ((c = getopt_long(argc, argv, "h", lo, NULL)) != -1) {
        char *e = NULL;
        switch (c) {
        case 'm': xml = optarg; break;
        case 'k': kinp = optarg; break;
        case 'o': outp = optarg; break;
        case 'p':
            if (sim_parse_payload(optarg, &pm, pc, err, sizeof err) != 0) {
                fprintf(stderr, "arm_exact: --payload: %s\n", err);
                return 2;
            }
            break;
        case 'q':
            qr[0] = strtod(optarg, &e);
            if (e == optarg || *e != ',' || (qr[1] = strtod(e + 1, &e), *e != '\0') || !(qr[0] < qr[1])) {
                fprintf(stderr, "arm_exact: --q-range '%s': want LO,HI with LO < HI [rad]\n", optarg);
                return 2;
            }
            break;
        case 'v':
        case 'a': {
            const double v = strtod(optarg, &e);
            if (e == optarg || *e != '\0' || !(v > 0.0)) {
                fprintf(stderr, "arm_exact: --%s '%s': want a number > 0\n", (c == 'v') ? "qd-max" : "qdd-max", optarg);
                return 2;
            }
            *((c == 'v') ? &qd_max : &qdd_max) = v;
            break;
        }
        case 'h': fputs(usage, stdout); return 0;
        default: fputs(usage, stderr); return 2;
        }
    }
    if (optind != argc) {
        fputs(usage, stderr);
        return 2;
    }
    if (c4gh_kin_load(kinp, &kin, err, sizeof err) != 0 || exact_compute(xml, &kin, pm, pc, &x, NULL, err, sizeof err) != 0) {
        fprintf(stderr, "arm_exact: %s\n", err);
        return 1;
    }
    snprintf(src, sizeof src, "%s + %s, payload %g kg at %g,%g,%g", xml, kinp, pm, pc[0], pc[1], pc[2]);
    if (exact_write(text, sizeof text, &kin, &x, src, qr, qd_max, qdd_max) != 0) {
        fprintf(stderr, "arm_exact: the file does not fit %zu bytes\n", sizeof text);
        return 1;
    }
    if (outp == NULL) {
        fputs(text, stdout);
        return 0;
    }
    {
        FILE *f = fopen(outp, "w");
        if (f == NULL || fputs(text, f) == EOF || fclose(f) != 0) {
            fprintf(stderr, "arm_exact: %s: cannot write\n", outp);
            return 1;
        }
    }
    return 0;
}
#endif
