/* SPDX-License-Identifier: MIT */
/* The arm plant's exact rigid parameters (tests/e2e/helpers/arm_exact.c) against MuJoCo:
 * for random states, MuJoCo's inverse dynamics of the plant as c4g-sim builds it
 * (qfrc_inverse: armature and payload included) equals c4g_dyn_rnea + ia qdd with the
 * parameters the converter found in the kinematics file's frames, to 1e-9 relative; so the
 * fixture (fixtures/ident/smart-six.kin), the converter and lib/dyn agree. Then the file it
 * writes read back (c4gh_ffm_parse_text) and evaluated (c4gh_ffr_current) gives the motor
 * currents Kr^-T qfrc_inverse / kt + friction, and a kinematics that misplaces a joint is
 * refused. arm_exact.c is included to reach its static functions. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#define ARM_EXACT_NO_MAIN
#include "../e2e/helpers/arm_exact.c" /* static functions: exact_compute, exact_write */

#define KIN FIXTURES_DIR "/ident/smart-six.kin"
#define XML FIXTURES_DIR "/sim/smart-six.xml"

static c4gh_kinfile_t g_kin;
static exact_t g_x;
static c4gh_ffm_file_t g_file;
static char g_text[1 << 16];

/* Uniform in [lo, hi) from a fixed sequence (the test repeats). */
static double urand(uint64_t *s, double lo, double hi)
{
    *s = (*s * 6364136223846793005ULL) + 1442695040888963407ULL;
    return lo + (hi - lo) * ((double)(*s >> 11) / 9007199254740992.0);
}

static plant_arm_t *open_exact(double pm, const double pc[3])
{
    char err[1024];
    plant_arm_t *pa = NULL;
    if (c4gh_kin_load(KIN, &g_kin, err, sizeof err) != 0 ||
        exact_compute(XML, &g_kin, pm, pc, &g_x, &pa, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    return pa;
}

/* mj_inverse of the plant = rnea + ia qdd, 1e-9 relative, with and without a payload. */
static void test_inverse_matches(void **state)
{
    static const double pcs[2][3] = {{0, 0, 0}, {0.02, -0.01, 0.05}};
    const double pms[2] = {0.0, 6.0};
    uint64_t seed = 12345U;
    int c;
    (void)state;
    for (c = 0; c < 2; c++) {
        plant_arm_t *pa = open_exact(pms[c], pcs[c]);
        const mjModel *m = (const mjModel *)plant_arm_mjmodel(pa);
        mjData *d = mj_makeData(m);
        double worst = 0.0;
        int s, j;
        assert_non_null(d);
        /* the armature really is in the model (the plant's rule), and in the file */
        for (j = 0; j < AX; j++) {
            assert_true(g_x.ia[j] > 1e-3 && g_x.ia[j] == m->dof_armature[j]);
        }
        for (s = 0; s < 500; s++) {
            double q[AX], qd[AX], qdd[AX], tau[AX], big = 0.0, diff = 0.0;
            for (j = 0; j < AX; j++) {
                q[j] = urand(&seed, -3.2, 3.2);
                qd[j] = urand(&seed, -4.0, 4.0);
                qdd[j] = urand(&seed, -40.0, 40.0);
                d->qpos[m->jnt_qposadr[j]] = q[j];
                d->qvel[m->jnt_dofadr[j]] = qd[j];
                d->qacc[m->jnt_dofadr[j]] = qdd[j];
            }
            mj_inverse(m, d);
            assert_int_equal(c4g_dyn_rnea(&g_kin.chain, q, qd, qdd, g_x.pi, g_x.ia, tau), C4G_OK);
            for (j = 0; j < AX; j++) {
                big = fmax(big, fabs(d->qfrc_inverse[m->jnt_dofadr[j]]));
                diff = fmax(diff, fabs(d->qfrc_inverse[m->jnt_dofadr[j]] - tau[j]));
            }
            assert_true(big > 1.0);
            worst = fmax(worst, diff / big);
        }
        print_message("payload %g kg: worst relative difference %.3g over 500 states\n", pms[c], worst);
        assert_true(worst < 1e-9);
        /* the payload is in link 6: its mass, the 0.5 kg flange's and 6 kg */
        assert_true(fabs(g_x.pi[50] - (0.5 + pms[c])) < 1e-12);
        mj_deleteData(d);
        plant_arm_close(pa);
    }
}

/* The written file read back: the same parameters (bit for bit), and its current equals
 * the plant's inverse dynamics through the transmission plus the friction. */
static void test_file_current(void **state)
{
    static const double pc[3] = {0.0, 0.0, 0.05};
    const double qr[2] = {-6.3, 6.3};
    char err[1024];
    plant_arm_t *pa = open_exact(6.0, pc);
    const mjModel *m = (const mjModel *)plant_arm_mjmodel(pa);
    mjData *d = mj_makeData(m);
    c4g_init_t init;
    c4gsim_axis_params_t p[AX];
    c4g_kin_t kin;
    c4gh_ffr_t r;
    c4gh_ffr_out_t o;
    uint64_t seed = 99U;
    int s, j, k;
    (void)state;
    assert_int_equal(exact_write(g_text, sizeof g_text, &g_kin, &g_x, "test", qr, 20.0, 1000.0), 0);
    if (c4gh_ffm_parse_text("exact.ini", g_text, strlen(g_text), &g_file, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    assert_true(g_file.rigid && g_file.kin.n == 6U && g_file.consistent == 1);
    assert_true(memcmp(g_file.pi, g_x.pi, sizeof g_x.pi) == 0 && memcmp(g_file.ia, g_x.ia, sizeof g_x.ia) == 0);
    exact_init(&init, p);
    init.period_ms = 2;
    assert_int_equal(c4g_kin_from_init(&init, 0U, &kin), C4G_OK);
    assert_int_equal(c4gh_ffr_setup(&r, &g_file, &kin), 0);
    for (s = 0; s < 200; s++) {
        double q[AX], qd[AX], qdd[AX], qm[AX], vm[AX], am[AX];
        for (j = 0; j < AX; j++) {
            q[j] = urand(&seed, -3.0, 3.0);
            qd[j] = urand(&seed, -3.0, 3.0);
            qdd[j] = urand(&seed, -30.0, 30.0);
            d->qpos[j] = q[j];
            d->qvel[j] = qd[j];
            d->qacc[j] = qdd[j];
        }
        mj_inverse(m, d);
        assert_int_equal(c4g_kin_link_to_motor(&kin, q, AX, qm), C4G_OK);
        assert_int_equal(c4g_kin_link_vel_to_motor(&kin, qd, AX, vm), C4G_OK);
        assert_int_equal(c4g_kin_link_vel_to_motor(&kin, qdd, AX, am), C4G_OK);
        for (k = 0; k < AX; k++) {
            vm[k] /= kin.period_s; /* turns per tick -> turns/s */
            am[k] /= kin.period_s;
        }
        assert_int_equal(c4gh_ffr_current(&r, qm, vm, am, &o), 0);
        for (k = 0; k < AX; k++) {
            /* tau_m = Kr^-T tau, friction of the plant's motor k in current (tanh smoothing) */
            double tm = 0.0, want;
            for (j = 0; j < AX; j++) {
                tm += r.kinv[j][k] * d->qfrc_inverse[j];
            }
            want = tm / p[k].kt + (p[k].fv * TWO_PI * vm[k] + p[k].fc * tanh(vm[k] / PLANT_FRICTION_EPS)) / p[k].kt;
            assert_int_equal(o.clamped[k], 0);
            if (fabs(o.cur[k] - want) > 1e-9 * fmax(1.0, fabs(want))) {
                fail_msg("state %d motor %d: %.17g A, want %.17g A", s, k + 1, o.cur[k], want);
            }
        }
    }
    mj_deleteData(d);
    plant_arm_close(pa);
}

/* A kinematics that puts a joint elsewhere than the model: refused, naming the joint. */
static void test_misplaced_joint(void **state)
{
    static const double pc[3] = {0, 0, 0};
    char err[1024];
    FILE *f;
    char *text;
    long n;
    (void)state;
    f = fopen(KIN, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    n = ftell(f);
    rewind(f);
    text = calloc(1, (size_t)n + 1U);
    assert_non_null(text);
    assert_int_equal(fread(text, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    memcpy(strstr(text, "a = 0.11"), "a = 0.12", 8U); /* the forearm's offset */
    assert_int_equal(c4gh_kin_parse_text("bad.kin", text, strlen(text), &g_kin, err, sizeof err), 0);
    assert_int_equal(exact_compute(XML, &g_kin, 0.0, pc, &g_x, NULL, err, sizeof err), -1);
    assert_non_null(strstr(err, "joint 4: the model's axis"));
    free(text);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inverse_matches),
        cmocka_unit_test(test_file_current),
        cmocka_unit_test(test_misplaced_joint),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
