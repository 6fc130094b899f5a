/* SPDX-License-Identifier: MIT */
/* c4g-sim's arm plant (tools/c4g-sim/plant_arm.c) with the shipped model
 * fixtures/sim/smart-six.xml: the physics against hand computations from the model's figures,
 * the controller's model (EXT1, EXT2) against MuJoCo's own matrices, energy, determinism,
 * the wrist's transmission coupling, and the refusals. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include <mujoco/mujoco.h>

#include "c4gsim_fixtures.h"
#include "plant_arm.h"
#include "scenario.h"
#include "sim.h"

#define ARM_XML FIXTURES_DIR "/sim/smart-six.xml"
#define G 9.81

static sim_t g_sim; /* big: not on the stack */
static scn_t g_scn;

/* Figures of fixtures/sim/smart-six.xml, restated by hand: masses [kg] and, in the x-z plane
 * of each link frame, the centres [m] and the next joint's origin. */
static const double m_link[6] = {40.0, 22.0, 18.0, 6.0, 2.5, 0.5};

/* Rotate (x, z) by a about +y (MuJoCo's right-hand rule): x' = x c + z s, z' = -x s + z c. */
static void roty(double a, double x, double z, double *ox, double *oz)
{
    *ox = (x * cos(a)) + (z * sin(a));
    *oz = (-x * sin(a)) + (z * cos(a));
}

/* Gravity holding torques [Nm] of joints 2, 3 and 5 for a pose with q4 = q6 = 0 (the arm in
 * one vertical plane; q1 does not matter), payload @p pm at (@p px, 0, @p pz) in the flange
 * frame: tau_j = -g sum_b m_b (x_b - x_j), x the horizontal distance in the arm's plane. */
static void hand_gravity(const double q[6], double pm, double px, double pz, double tau[6])
{
    double sx = 0.15, sz = 0.45; /* shoulder: joint 2 */
    double ex, ez, wx, wz, dx, dz;
    double cx[7];
    double mass[7];
    const double f2 = q[1], f3 = q[1] + q[2], f5 = q[1] + q[2] + q[4];
    int b;
    memset(tau, 0, 6 * sizeof tau[0]);
    memcpy(mass, m_link, sizeof m_link);
    mass[6] = pm;
    roty(f2, 0.0, 0.30, &dx, &dz);
    cx[1] = sx + dx;
    roty(f2, 0.0, 0.59, &dx, &dz);
    ex = sx + dx;
    ez = sz + dz;
    roty(f3, 0.10, 0.05, &dx, &dz);
    cx[2] = ex + dx;
    roty(f3, 0.25 + 0.20, 0.11, &dx, &dz);
    cx[3] = ex + dx;
    roty(f3, 0.25 + 0.39, 0.11, &dx, &dz);
    wx = ex + dx;
    wz = ez + dz;
    roty(f5, 0.04, 0.0, &dx, &dz);
    cx[4] = wx + dx;
    roty(f5, 0.07, 0.0, &dx, &dz);
    cx[5] = wx + dx;
    roty(f5, 0.085 + px, pz, &dx, &dz);
    cx[6] = wx + dx;
    (void)wz;
    for (b = 1; b < 7; b++) {
        tau[1] -= G * mass[b] * (cx[b] - sx);
        if (b >= 2) {
            tau[2] -= G * mass[b] * (cx[b] - ex);
        }
        if (b >= 4) {
            tau[4] -= G * mass[b] * (cx[b] - wx);
        }
    }
}

/* An arm with an ideal encoder and no noise, its axes at joint angles @p q. */
static void arm_config(sim_config_t *cfg, const double q[6])
{
    c4g_init_t init;
    c4g_kin_t kin;
    double qm[6];
    int l;
    sim_config_default(cfg);
    snprintf(cfg->plant.path, sizeof cfg->plant.path, "%s", ARM_XML);
    assert_int_equal(c4gsim_fig10_1(&init), C4G_OK);
    for (l = 0; l < 6; l++) { /* the init packet c4g-sim sends carries these parameters */
        init.tx_rate[0][l] = (float)cfg->ax[0][l].tx_rate;
        init.cal_data[0][l] = (float)cfg->ax[0][l].cal;
        init.ax_info[0][l] = (float)cfg->ax[0][l].ax_info;
    }
    assert_int_equal(c4g_kin_from_init(&init, 0, &kin), C4G_OK);
    assert_int_equal(c4g_kin_link_to_motor(&kin, q, 6, qm), C4G_OK);
    for (l = 0; l < 6; l++) {
        cfg->ax[0][l].counts = 0.0;
        cfg->ax[0][l].noise = 0.0;
        cfg->ax[0][l].pos0 = qm[l];
    }
}

static void load_scenario(const char *text)
{
    char err[256];
    assert_int_equal(scn_parse("t.scn", text, strlen(text), &g_scn, err, sizeof err), 0);
}

/* Ticks without a PC (mode 0 needs none). */
static void run_ticks(sim_t *s, unsigned long n, c4g_ctrl_packet_t *out)
{
    unsigned long t;
    for (t = 0; t < n; t++) {
        sim_tick(s, NULL, out);
    }
}

/* The kinematics of the init packet the simulator sends. */
static void sim_kin(const sim_t *s, c4g_kin_t *kin)
{
    assert_int_equal(c4g_kin_from_init(&s->init, 0, kin), C4G_OK);
}

/* Kinv[j][i]: joint rad per motor rad, from the library's velocity conversion. */
static void kinv_of(const c4g_kin_t *kin, double kinv[6][6])
{
    int i;
    int j;
    for (i = 0; i < 6; i++) {
        double e[6] = {0, 0, 0, 0, 0, 0};
        double v[6];
        e[i] = 1.0;
        assert_int_equal(c4g_kin_motor_vel_to_link(kin, e, 6, v), C4G_OK);
        for (j = 0; j < 6; j++) {
            kinv[j][i] = v[j] * kin->period_s / (2.0 * M_PI);
        }
    }
}

/* Holding currents in three poses, against the hand computation: the drives settle on
 * gravity alone (no friction at rest), motor 4 holding its share of joint 5 through the
 * wrist coupling. Run twice: with the exact controller model, whose EXT1 must give the hand
 * figure, and with the default model errors, where the loops make up the difference and the
 * current held is still the hand figure. */
static void test_static_holding(void **state)
{
    static const double poses[3][6] = {
        {0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
        {0.3, 0.5, -0.3, 0.0, 0.4, 0.0},
        {1.0, -0.4, 0.8, 0.0, -0.6, 0.0},
    };
    int p;
    int exact;
    (void)state;
    for (p = 0; p < 3; p++) {
        for (exact = 1; exact >= 0; exact--) {
            sim_config_t cfg;
            c4g_ctrl_packet_t out;
            c4g_kin_t kin;
            double tau[6];
            double want[6];
            int i;
            arm_config(&cfg, poses[p]);
            cfg.plant.payload = 6.0;
            cfg.plant.payload_com[0] = 0.05;
            cfg.plant.payload_com[2] = 0.02;
            plant_cfg_scale_errors(&cfg.plant, exact ? 0.0 : 1.0);
            load_scenario("DRIVE ON 1\nDELAY 1600\n");
            assert_int_equal(sim_init(&g_sim, &cfg, &g_scn, NULL), 0);
            sim_kin(&g_sim, &kin);
            hand_gravity(poses[p], 6.0, 0.05, 0.02, tau);
            for (i = 0; i < 6; i++) {
                want[i] = 0.0;
            }
            want[1] = tau[1] / (kin.kr[1] * cfg.ax[0][1].kt);
            want[2] = tau[2] / (kin.kr[2] * cfg.ax[0][2].kt);
            want[4] = tau[4] / (kin.kr[4] * cfg.ax[0][4].kt);
            want[3] = kin.k54 * tau[4] / (kin.kr[3] * cfg.ax[0][3].kt); /* the wrist coupling */
            run_ticks(&g_sim, 1000, &out);
            for (i = 0; i < 6; i++) {
                const double got = out.ax[i].current_ref;
                const double ext1 = g_sim.ax[i].model_cur;
                printf("pose %d, %s model, axis %d: hand %.6f A, held %.6f A, EXT1 %.6f A\n", p,
                       exact ? "exact" : "default", i + 1, want[i], got, ext1);
                assert_true(fabs(got - want[i]) <= 0.002 * fabs(want[i]) + 2e-4);
                if (exact) {
                    assert_true(fabs(ext1 - want[i]) <= 1e-6 * fabs(want[i]) + 1e-9);
                }
            }
            assert_true(fabs(want[2]) > 0.5); /* axis 3 carries the forearm in every pose */
            sim_free(&g_sim);
        }
    }
}

/* EXT2 is the diagonal of Kr^-T M Kr^-1 with M from mj_fullM of the plant (exact model), and
 * the configured errors make the controller's model differ from it. */
static void test_ext2_full_m(void **state)
{
    static const double q[6] = {1.0, -0.4, 0.8, 0.3, -0.6, 0.2};
    sim_config_t cfg;
    c4g_kin_t kin;
    double kinv[6][6];
    double full[36];
    double exact[6];
    const void *vm;
    void *vd;
    int i;
    int j;
    int k;
    int off = 0;
    (void)state;
    arm_config(&cfg, q);
    cfg.plant.payload = 4.0;
    plant_cfg_scale_errors(&cfg.plant, 0.0);
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), 0);
    sim_kin(&g_sim, &kin);
    kinv_of(&kin, kinv);
    plant_arm_mujoco(g_sim.plant, 0, &vm, &vd);
    mj_forward((const mjModel *)vm, (mjData *)vd);
    mj_fullM((const mjModel *)vm, full, ((mjData *)vd)->qM);
    for (i = 0; i < 6; i++) {
        double in = 0.0;
        for (j = 0; j < 6; j++) {
            for (k = 0; k < 6; k++) {
                in += kinv[j][i] * full[j * 6 + k] * kinv[k][i];
            }
        }
        exact[i] = in;
        printf("axis %d: EXT2 %.9g, reflected mj_fullM %.9g kg m^2\n", i + 1, g_sim.ax[i].model_inertia, in);
        assert_true(fabs(g_sim.ax[i].model_inertia - in) <= 1e-9 * in);
        /* the rotor is part of it: at least Jm */
        assert_true(in >= cfg.ax[0][i].j);
    }
    sim_free(&g_sim);
    /* the default errors: off, by less than the largest configured error */
    arm_config(&cfg, q);
    cfg.plant.payload = 4.0;
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), 0);
    for (i = 0; i < 6; i++) {
        const double rel = fabs(g_sim.ax[i].model_inertia - exact[i]) / exact[i];
        printf("axis %d: controller EXT2 off by %.2f %%\n", i + 1, 100.0 * rel);
        assert_true(rel < 0.15);
        off += rel > 0.005;
    }
    assert_true(off >= 3);
    sim_free(&g_sim);
}

/* A wrong payload in the controller shows in EXT1 (the gravity current of axis 2). */
static void test_ctrl_payload(void **state)
{
    static const double q[6] = {0.0, 0.6, 0.0, 0.0, 0.0, 0.0};
    sim_config_t cfg;
    double right;
    double wrong;
    (void)state;
    arm_config(&cfg, q);
    plant_cfg_scale_errors(&cfg.plant, 0.0);
    cfg.plant.payload = 6.0;
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), 0);
    right = g_sim.ax[1].model_cur;
    sim_free(&g_sim);
    cfg.plant.ctrl_payload_set = 1;
    cfg.plant.ctrl_payload = 0.0;
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), 0);
    wrong = g_sim.ax[1].model_cur;
    sim_free(&g_sim);
    printf("axis 2 model current: payload known %.4f A, controller told 0 kg %.4f A\n", right, wrong);
    assert_true(fabs(right - wrong) > 0.1 * fabs(right));
}

/* A frictionless arm swinging under gravity with no current keeps its energy. */
static void test_energy(void **state)
{
    static const double q[6] = {0.0, 0.9, -0.2, 0.5, 0.7, 0.0};
    sim_config_t cfg;
    c4gsim_axis_t *ax[6];
    double e0;
    double emax = 0.0;
    double ke_max = 0.0;
    int i;
    int k;
    (void)state;
    arm_config(&cfg, q);
    for (i = 0; i < 6; i++) {
        cfg.ax[0][i].fv = 0.0;
        cfg.ax[0][i].fc = 0.0;
        cfg.ax[0][i].fs = 0.0;
    }
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), 0);
    for (i = 0; i < 6; i++) {
        ax[i] = &g_sim.ax[i].m;
        ax[i]->drive_on = true;
        ax[i]->cur = 0.0;
    }
    e0 = plant_arm_energy(g_sim.plant);
    for (k = 0; k < 4000; k++) { /* 2 s at the DSA's 0.5 ms */
        double qq[6];
        double qd[6];
        double e;
        double ke = 0.0;
        const void *vm;
        void *vd;
        assert_int_equal(plant_arm_step(g_sim.plant, ax, &g_sim.rng), 0);
        if (k % 50 == 49) {
            e = plant_arm_energy(g_sim.plant);
            plant_arm_mujoco(g_sim.plant, 0, &vm, &vd);
            ke = ((mjData *)vd)->energy[1];
            ke_max = (ke > ke_max) ? ke : ke_max;
            emax = (fabs(e - e0) > emax) ? fabs(e - e0) : emax;
            plant_arm_joints(g_sim.plant, qq, qd);
        }
    }
    printf("free swing 2 s: largest kinetic energy %.3f J, energy drift at most %.5f J (%.3f %%)\n", ke_max,
           emax, 100.0 * emax / ke_max);
    assert_true(ke_max > 10.0);        /* it did swing */
    assert_true(emax < 0.01 * ke_max); /* the bound docs/c4g-sim.md states: 1 % */
    sim_free(&g_sim);
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; i++) {
        h = (h ^ b[i]) * 0x100000001B3ULL;
    }
    return h;
}

/* One mode-0 move of all axes with the default noise: the packets' hash. */
static uint64_t move_hash(uint64_t seed)
{
    static const double q[6] = {0, 0, 0, 0, 0, 0};
    sim_config_t cfg;
    c4g_ctrl_packet_t out;
    uint64_t h = 0xCBF29CE484222325ULL;
    unsigned long t;
    int l;
    arm_config(&cfg, q);
    for (l = 0; l < 6; l++) {
        c4gsim_axis_params_t d;
        assert_int_equal(c4gsim_axis_params_default(&d, (unsigned)l), C4G_OK);
        cfg.ax[0][l].counts = d.counts;
        cfg.ax[0][l].noise = d.noise;
        cfg.ax[0][l].torque_noise = 0.01;
        cfg.ax[0][l].cur_noise = 0.01;
    }
    cfg.seed = seed;
    load_scenario("DRIVE ON 1\nDELAY 50\nMOVE 1 2 -1.5 1 0.5 -0.5 0.25\nDELAY 100\n");
    assert_int_equal(sim_init(&g_sim, &cfg, &g_scn, NULL), 0);
    for (t = 0; t < 800; t++) {
        sim_tick(&g_sim, NULL, &out);
        h = fnv(h, out.ax, sizeof out.ax[0] * out.n_axes);
    }
    assert_int_equal(g_sim.n_err, 0);
    assert_true(fabs(g_sim.ax[0].m.meas_pos - 2.0) < 0.02);
    sim_free(&g_sim);
    return h;
}

static void test_determinism(void **state)
{
    const uint64_t a = move_hash(7);
    const uint64_t b = move_hash(7);
    const uint64_t c = move_hash(8);
    (void)state;
    assert_true(a == b);
    assert_true(a != c); /* the seed reaches the noise */
}

/* The wrist's coupling: motor turns -> joints -> motor turns through the plant, and a motor-5
 * torque loads joint 4 as Kr^T says (Kr[5][4] = -kr5 k54). */
static void test_wrist_coupling(void **state)
{
    static const double q[6] = {0.1, 0.2, -0.3, 0.7, -0.5, 1.1};
    sim_config_t cfg;
    c4g_kin_t kin;
    c4gsim_axis_t *ax[6];
    double want_q[6];
    double qm[6];
    double qj[6];
    double qd[6];
    const void *vm;
    void *vd;
    int i;
    (void)state;
    arm_config(&cfg, q);
    for (i = 0; i < 6; i++) {
        cfg.ax[0][i].fv = 0.0;
        cfg.ax[0][i].fc = 0.0;
        cfg.ax[0][i].fs = 0.0;
        qm[i] = cfg.ax[0][i].pos0;
    }
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), 0);
    sim_kin(&g_sim, &kin);
    assert_int_equal(c4g_kin_motor_to_link(&kin, qm, 6, want_q), C4G_OK);
    plant_arm_joints(g_sim.plant, qj, qd);
    for (i = 0; i < 6; i++) {
        assert_true(fabs(qj[i] - want_q[i]) < 1e-12);
        assert_true(fabs(qj[i] - q[i]) < 1e-6); /* float init packet: 1e-6 */
        ax[i] = &g_sim.ax[i].m;
    }
    /* brakes: one step, the motors read back where they were */
    assert_int_equal(plant_arm_step(g_sim.plant, ax, &g_sim.rng), 0);
    for (i = 0; i < 6; i++) {
        assert_true(fabs(ax[i]->pos - qm[i]) < 1e-9);
        ax[i]->drive_on = true;
        ax[i]->cur = 0.0;
    }
    ax[4]->cur = 2.0; /* motor 5 only */
    assert_int_equal(plant_arm_step(g_sim.plant, ax, &g_sim.rng), 0);
    plant_arm_mujoco(g_sim.plant, 0, &vm, &vd);
    {
        const double *f = ((mjData *)vd)->qfrc_applied;
        const double t5 = cfg.ax[0][4].kt * 2.0;
        printf("motor 5 at 2 A: joint torques %.6f %.6f %.6f Nm\n", f[3], f[4], f[5]);
        assert_true(fabs(f[3] - (-kin.kr[4] * kin.k54 * t5)) < 1e-9);
        assert_true(fabs(f[4] - kin.kr[4] * t5) < 1e-9);
        assert_true(fabs(f[5]) < 1e-12 && fabs(f[0]) < 1e-12 && fabs(f[1]) < 1e-12 && fabs(f[2]) < 1e-12);
    }
    sim_free(&g_sim);
}

/* Files and configurations the plant refuses, each with a message naming why. */
static void test_refusals(void **state)
{
    static const double q[6] = {0, 0, 0, 0, 0, 0};
    sim_config_t cfg;
    (void)state;
    arm_config(&cfg, q);
    snprintf(cfg.plant.path, sizeof cfg.plant.path, "%s", FIXTURES_DIR "/sim/no-such.xml");
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), -1);
    printf("%s\n", g_sim.init_err);
    assert_non_null(strstr(g_sim.init_err, "no-such.xml"));
    assert_null(g_sim.plant);
    /* a transmission other than the model's */
    arm_config(&cfg, q);
    cfg.ax[0][2].tx_rate = 100.0;
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), -1);
    printf("%s\n", g_sim.init_err);
    assert_non_null(strstr(g_sim.init_err, "c4g_tx_rate[2] = 162.473694, but the init packet's TxRate of axis 3 is 100"));
    /* current limits other than the model's */
    arm_config(&cfg, q);
    cfg.ax[0][4].az_lim = 12.0;
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), -1);
    printf("%s\n", g_sim.init_err);
    assert_non_null(strstr(g_sim.init_err, "c4g_az_lim[4] = 9.5, but the init packet's AzLim of axis 5 is 12"));
    /* an axis of the arm not open */
    arm_config(&cfg, q);
    cfg.open_mask[0] = 0x1FU;
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), -1);
    printf("%s\n", g_sim.init_err);
    assert_non_null(strstr(g_sim.init_err, "axis 6 is not open"));
    /* a model that is not a 6-joint arm: the scenario fixture is not even XML */
    arm_config(&cfg, q);
    snprintf(cfg.plant.path, sizeof cfg.plant.path, "%s", FIXTURES_DIR "/scenarios/mode0.scn");
    assert_int_equal(sim_init(&g_sim, &cfg, NULL, NULL), -1);
    printf("%s\n", g_sim.init_err);
    assert_non_null(strstr(g_sim.init_err, "mode0.scn: "));
    sim_free(&g_sim);
}

/* The INI [plant] section and the payload syntax. */
static void test_plant_config(void **state)
{
    sim_config_t cfg;
    char err[512];
    char path[] = "/tmp/c4g-test-plant-XXXXXX";
    const char ini[] = "[plant]\nfile = fixtures/sim/smart-six.xml\npayload = 5.5@0.01,0,0.08\n"
                       "ctrl_payload = 3\nctrl_mass_error = 1,2,3,4,5,6\nctrl_inertia_error = 0 0 0 0 0 -50\n";
    const char bad[] = "[plant]\nctrl_mass_error = 1,2,3\n";
    double m;
    double com[3];
    char why[160];
    int fd;
    FILE *f;
    (void)state;
    fd = mkstemp(path);
    assert_true(fd >= 0);
    f = fdopen(fd, "w");
    assert_non_null(f);
    fputs(ini, f);
    fclose(f);
    sim_config_default(&cfg);
    assert_int_equal(sim_config_load(&cfg, path, err, sizeof err), 0);
    assert_string_equal(cfg.plant.path, "fixtures/sim/smart-six.xml");
    assert_true(cfg.plant.payload == 5.5 && cfg.plant.payload_com[0] == 0.01 && cfg.plant.payload_com[2] == 0.08);
    assert_true(cfg.plant.ctrl_payload_set == 1 && cfg.plant.ctrl_payload == 3.0);
    assert_true(cfg.plant.ctrl_mass_err[2] == 0.03 && cfg.plant.ctrl_inertia_err[5] == -0.5);
    f = fopen(path, "w");
    assert_non_null(f);
    fputs(bad, f);
    fclose(f);
    sim_config_default(&cfg);
    assert_int_equal(sim_config_load(&cfg, path, err, sizeof err), -1);
    assert_non_null(strstr(err, ":2:"));
    assert_non_null(strstr(err, "[plant] ctrl_mass_error: '1,2,3' is not six percentages -90..500"));
    unlink(path);
    assert_int_equal(sim_parse_payload("6", &m, com, why, sizeof why), 0);
    assert_true(m == 6.0 && com[0] == 0.0);
    assert_int_equal(sim_parse_payload("6@1,2", &m, com, why, sizeof why), -1);
    assert_string_equal(why, "centre '1,2' is not X,Y,Z (m, flange frame)");
    assert_int_equal(sim_parse_payload("-1", &m, com, why, sizeof why), -1);
    assert_int_equal(sim_parse_payload("1@0,0,9", &m, com, why, sizeof why), -1);
    assert_string_equal(why, "centre coordinate '9' is not -2..2 m");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_static_holding),
        cmocka_unit_test(test_ext2_full_m),
        cmocka_unit_test(test_ctrl_payload),
        cmocka_unit_test(test_energy),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_wrist_coupling),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_plant_config),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
