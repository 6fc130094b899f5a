/* SPDX-License-Identifier: MIT */
/* The arm plant (plant_arm.h): MuJoCo integrates the links; the motors, their friction and
 * the transmission are ours. */
#include "plant_arm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mujoco/mujoco.h>

#define TWO_PI 6.283185307179586
#define PAYLOAD_RADIUS 0.05 /* m: the payload's inertia is a solid sphere of this radius */

struct plant_arm {
    mjModel *m;                        /* the plant */
    mjData *d;
    mjModel *mc;                       /* the controller's model of it */
    mjData *dc;
    c4g_kin_t kin;
    double kr[PLANT_AXES][PLANT_AXES];   /* motor rad per joint rad, [motor][joint] */
    double kinv[PLANT_AXES][PLANT_AXES]; /* joint rad per motor rad, [joint][motor] */
    const c4gsim_axis_params_t *p[PLANT_AXES];
    int qadr[PLANT_AXES];              /* qpos address of joint i */
    int vadr[PLANT_AXES];              /* dof address of joint i */
    int bad_acc;                       /* MuJoCo's bad-acceleration count seen so far */
};

/* Model errors when none are configured: a few to 15 percent, of both signs, so the
 * controller's model is wrong the way an identified one is (docs/c4g-sim.md). */
static const double default_mass_err[PLANT_AXES] = {0.05, -0.08, 0.12, -0.15, 0.03, 0.10};
static const double default_inertia_err[PLANT_AXES] = {-0.10, 0.15, -0.06, 0.09, -0.12, 0.04};

void plant_cfg_default(plant_cfg_t *c)
{
    memset(c, 0, sizeof *c);
    memcpy(c->ctrl_mass_err, default_mass_err, sizeof default_mass_err);
    memcpy(c->ctrl_inertia_err, default_inertia_err, sizeof default_inertia_err);
}

void plant_cfg_scale_errors(plant_cfg_t *c, double k)
{
    int i;
    for (i = 0; i < PLANT_AXES; i++) {
        c->ctrl_mass_err[i] *= k;
        c->ctrl_inertia_err[i] *= k;
    }
}

/* MuJoCo's default warning handler writes MUJOCO_LOG.TXT into the working directory. */
static void mj_warning_to_stderr(const char *msg)
{
    fprintf(stderr, "c4g-sim: MuJoCo: %s\n", msg);
}

static void set_payload(mjModel *m, int body, double mass, const double com[3])
{
    const double i = 0.4 * mass * PAYLOAD_RADIUS * PAYLOAD_RADIUS;
    int k;
    m->body_mass[body] = mass;
    m->body_sameframe[body] = 0; /* MuJoCo skips body_ipos for a body compiled with it at 0 */
    for (k = 0; k < 3; k++) {
        m->body_ipos[(3 * body) + k] = com[k];
        m->body_inertia[(3 * body) + k] = i;
    }
}

/* Kr and its inverse, column by column, through the library's velocity conversions (the
 * transmission is linear: a unit joint velocity gives the column of Kr). */
static int gear_matrices(plant_arm_t *pa)
{
    const double T = pa->kin.period_s;
    int j;
    int i;
    for (j = 0; j < PLANT_AXES; j++) {
        double e[PLANT_AXES] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        double y[PLANT_AXES];
        e[j] = 1.0;
        if (c4g_kin_link_vel_to_motor(&pa->kin, e, PLANT_AXES, y) != C4G_OK) {
            return -1;
        }
        for (i = 0; i < PLANT_AXES; i++) {
            pa->kr[i][j] = (y[i] * TWO_PI) / T; /* turns per tick -> rad/s */
        }
        if (c4g_kin_motor_vel_to_link(&pa->kin, e, PLANT_AXES, y) != C4G_OK) {
            return -1;
        }
        for (i = 0; i < PLANT_AXES; i++) {
            pa->kinv[i][j] = (y[i] * T) / TWO_PI; /* rad/s per turn per tick -> rad per rad */
        }
    }
    return 0;
}

/* A custom numeric of the model (when present) against the init packet's figures. */
static int check_numeric(const mjModel *m, const char *path, const char *name, const char *field,
                         const double want[PLANT_AXES], char *err, size_t errlen)
{
    const int id = mj_name2id(m, mjOBJ_NUMERIC, name);
    int i;
    if (id < 0) {
        return 0;
    }
    if (m->numeric_size[id] != PLANT_AXES) {
        snprintf(err, errlen, "%s: %s has %d values, want 6", path, name, m->numeric_size[id]);
        return -1;
    }
    for (i = 0; i < PLANT_AXES; i++) {
        const double got = m->numeric_data[m->numeric_adr[id] + i];
        if (fabs(got - want[i]) > 1e-5 * fabs(want[i])) {
            snprintf(err, errlen, "%s: %s[%d] = %.9g, but the init packet's %s of axis %d is %.9g", path, name,
                     i, got, field, i + 1, want[i]);
            return -1;
        }
    }
    return 0;
}

/* The structure c4g-sim needs, and the transmission and current limits the init packet
 * sends. */
static int check_model(plant_arm_t *pa, const c4g_init_t *init, unsigned arm, const char *path, char *err,
                       size_t errlen)
{
    const mjModel *m = pa->m;
    double az[PLANT_AXES];
    int i;
    if (m->njnt != PLANT_AXES || m->nv != PLANT_AXES || m->nq != PLANT_AXES) {
        snprintf(err, errlen, "%s: %d joints, %d dofs: the arm plant needs 6 hinge joints (axes 1..6)",
                 path, m->njnt, m->nv);
        return -1;
    }
    for (i = 0; i < PLANT_AXES; i++) {
        if (m->jnt_type[i] != mjJNT_HINGE) {
            snprintf(err, errlen, "%s: joint %d is not a hinge", path, i + 1);
            return -1;
        }
        pa->qadr[i] = m->jnt_qposadr[i];
        pa->vadr[i] = m->jnt_dofadr[i];
        az[i] = (double)init->az_lim[arm][i];
    }
    if (mj_name2id(m, mjOBJ_BODY, "payload") < 0) {
        snprintf(err, errlen, "%s: no body named payload (at the flange)", path);
        return -1;
    }
    if (check_numeric(m, path, "c4g_tx_rate", "TxRate", pa->kin.kr, err, errlen) != 0 ||
        check_numeric(m, path, "c4g_az_lim", "AzLim", az, err, errlen) != 0) {
        return -1;
    }
    return 0;
}

/* The rotors reflected through the transmission: M_rotor = Kr^T Jm Kr. Its diagonal goes into
 * each joint's armature; the off-diagonal terms (the wrist coupling's, a few percent of the
 * diagonal) are left out: MuJoCo's armature is diagonal. */
static void set_armature(plant_arm_t *pa)
{
    int j;
    int k;
    for (j = 0; j < PLANT_AXES; j++) {
        double a = 0.0;
        for (k = 0; k < PLANT_AXES; k++) {
            a += pa->kr[k][j] * pa->kr[k][j] * pa->p[k]->j;
        }
        pa->m->dof_armature[pa->vadr[j]] += a;
    }
}

/* The controller's model: the same arm with every link's mass and inertia off by the
 * configured fraction, no friction, and the payload the controller was told of. */
static int controller_model(plant_arm_t *pa, const plant_cfg_t *cfg)
{
    const int pay = mj_name2id(pa->m, mjOBJ_BODY, "payload");
    int i;
    int k;
    pa->mc = mj_copyModel(NULL, pa->m);
    if (pa->mc == NULL) {
        return -1;
    }
    for (i = 0; i < PLANT_AXES; i++) {
        const int b = pa->mc->jnt_bodyid[i];
        pa->mc->body_mass[b] *= 1.0 + cfg->ctrl_mass_err[i];
        for (k = 0; k < 3; k++) {
            pa->mc->body_inertia[(3 * b) + k] *= 1.0 + cfg->ctrl_inertia_err[i];
        }
        pa->mc->dof_damping[pa->vadr[i]] = 0.0;
        pa->mc->dof_frictionloss[pa->vadr[i]] = 0.0;
    }
    if (cfg->ctrl_payload_set) {
        set_payload(pa->mc, pay, cfg->ctrl_payload, cfg->ctrl_payload_com);
    }
    pa->dc = mj_makeData(pa->mc);
    return (pa->dc != NULL) ? 0 : -1;
}

int plant_arm_open(plant_arm_t **out, const plant_cfg_t *cfg, const c4g_init_t *init, unsigned arm,
                   const c4gsim_axis_params_t *const p[PLANT_AXES], double dt, char *err, size_t errlen)
{
    plant_arm_t *pa;
    char lerr[512];
    int i;
    *out = NULL;
    pa = calloc(1, sizeof *pa);
    if (pa == NULL) {
        snprintf(err, errlen, "%s: out of memory", cfg->path);
        return -1;
    }
    for (i = 0; i < PLANT_AXES; i++) {
        pa->p[i] = p[i];
    }
    mju_user_warning = mj_warning_to_stderr;
    if (c4g_kin_from_init(init, arm, &pa->kin) != C4G_OK || gear_matrices(pa) != 0) {
        snprintf(err, errlen, "%s: the init packet's transmission of arm %u is not invertible", cfg->path,
                 arm + 1U);
        free(pa);
        return -1;
    }
    lerr[0] = '\0';
    pa->m = mj_loadXML(cfg->path, NULL, lerr, (int)sizeof lerr);
    if (pa->m == NULL) {
        char *c;
        for (c = lerr; *c != '\0'; c++) { /* MuJoCo's message spans lines: one line here */
            *c = (*c == '\n') ? ' ' : *c;
        }
        while (c > lerr && c[-1] == ' ') {
            *--c = '\0';
        }
        snprintf(err, errlen, "%s: %s", cfg->path, (lerr[0] != '\0') ? lerr : "MuJoCo could not load it");
        free(pa);
        return -1;
    }
    if (check_model(pa, init, arm, cfg->path, err, errlen) != 0) {
        plant_arm_close(pa);
        return -1;
    }
    pa->m->opt.timestep = dt;
    set_armature(pa);
    set_payload(pa->m, mj_name2id(pa->m, mjOBJ_BODY, "payload"), cfg->payload, cfg->payload_com);
    pa->d = mj_makeData(pa->m);
    if (pa->d == NULL || controller_model(pa, cfg) != 0) {
        snprintf(err, errlen, "%s: MuJoCo could not allocate its data", cfg->path);
        plant_arm_close(pa);
        return -1;
    }
    *out = pa;
    return 0;
}

void plant_arm_close(plant_arm_t *pa)
{
    if (pa == NULL) {
        return;
    }
    if (pa->dc != NULL) {
        mj_deleteData(pa->dc);
    }
    if (pa->mc != NULL) {
        mj_deleteModel(pa->mc);
    }
    if (pa->d != NULL) {
        mj_deleteData(pa->d);
    }
    if (pa->m != NULL) {
        mj_deleteModel(pa->m);
    }
    free(pa);
}

const struct mjModel_ *plant_arm_mjmodel(const plant_arm_t *pa)
{
    return pa->m;
}

int plant_arm_reset(plant_arm_t *pa, const double qm[PLANT_AXES])
{
    double q[PLANT_AXES];
    int i;
    if (c4g_kin_motor_to_link(&pa->kin, qm, PLANT_AXES, q) != C4G_OK) {
        return -1;
    }
    mj_resetData(pa->m, pa->d);
    for (i = 0; i < PLANT_AXES; i++) {
        pa->d->qpos[pa->qadr[i]] = q[i];
    }
    mj_forward(pa->m, pa->d);
    pa->bad_acc = pa->d->warning[mjWARN_BADQACC].number;
    return 0;
}

/* Motor positions [turns] and velocities [turns/s] of the plant's joint state. */
static int motor_state(const plant_arm_t *pa, double qm[PLANT_AXES], double vm[PLANT_AXES])
{
    double q[PLANT_AXES];
    double qd[PLANT_AXES];
    int i;
    plant_arm_joints(pa, q, qd);
    if (c4g_kin_link_to_motor(&pa->kin, q, PLANT_AXES, qm) != C4G_OK ||
        c4g_kin_link_vel_to_motor(&pa->kin, qd, PLANT_AXES, vm) != C4G_OK) {
        return -1;
    }
    for (i = 0; i < PLANT_AXES; i++) {
        vm[i] /= pa->kin.period_s; /* turns per tick -> turns/s */
    }
    return 0;
}

/* Friction of motor @p k at @p v turns/s [Nm], opposing the motion: viscous, and Coulomb with
 * the Stribeck rise (c4gsim_axis_friction_level) through a smooth sign. */
static double motor_friction(const c4gsim_axis_params_t *p, double v)
{
    const double level = c4gsim_axis_friction_level(p, v);
    return (p->fv * TWO_PI * v) + ((level * v) / sqrt((v * v) + (PLANT_FRICTION_EPS * PLANT_FRICTION_EPS)));
}

int plant_arm_step(plant_arm_t *pa, c4gsim_axis_t *const ax[PLANT_AXES], c4gsim_rng_t *rng)
{
    double qm[PLANT_AXES];
    double vm[PLANT_AXES];
    double tm[PLANT_AXES];
    int i;
    int k;
    if (motor_state(pa, qm, vm) != 0) {
        return -1;
    }
    if (!ax[0]->drive_on) {
        /* brakes: the arm holds where it is */
        for (i = 0; i < PLANT_AXES; i++) {
            pa->d->qvel[pa->vadr[i]] = 0.0;
            ax[i]->pos = qm[i];
            ax[i]->vel = 0.0;
        }
        return 0;
    }
    for (k = 0; k < PLANT_AXES; k++) {
        const c4gsim_axis_params_t *p = pa->p[k];
        double noise = 0.0;
        if (p->torque_noise > 0.0 && c4gsim_rng_gauss(rng, &noise) != C4G_OK) {
            return -1;
        }
        tm[k] = (p->kt * ax[k]->cur) + (p->torque_noise * noise) - motor_friction(p, vm[k]);
    }
    /* joint torques: tau = Kr^T tau_m (the same power on both sides of the transmission) */
    for (i = 0; i < PLANT_AXES; i++) {
        double t = 0.0;
        for (k = 0; k < PLANT_AXES; k++) {
            t += pa->kr[k][i] * tm[k];
        }
        pa->d->qfrc_applied[pa->vadr[i]] = t;
    }
    mj_step(pa->m, pa->d);
    if (pa->d->warning[mjWARN_BADQACC].number != pa->bad_acc) {
        pa->bad_acc = pa->d->warning[mjWARN_BADQACC].number;
        return -1;
    }
    if (motor_state(pa, qm, vm) != 0) {
        return -1;
    }
    for (i = 0; i < PLANT_AXES; i++) {
        ax[i]->pos = qm[i];
        ax[i]->vel = vm[i];
    }
    return 0;
}

int plant_arm_model(plant_arm_t *pa, const double qm[PLANT_AXES], const double vm[PLANT_AXES],
                    const double am[PLANT_AXES], double cur[PLANT_AXES], double inertia[PLANT_AXES])
{
    const double T = pa->kin.period_s;
    double q[PLANT_AXES];
    double qd[PLANT_AXES];
    double qdd[PLANT_AXES];
    double v[PLANT_AXES];
    double a[PLANT_AXES];
    double full[PLANT_AXES * PLANT_AXES];
    int i;
    int j;
    int k;
    for (i = 0; i < PLANT_AXES; i++) {
        v[i] = vm[i] * T; /* turns/s -> turns per tick, the library's unit */
        a[i] = am[i] * T;
    }
    if (c4g_kin_motor_to_link(&pa->kin, qm, PLANT_AXES, q) != C4G_OK ||
        c4g_kin_motor_vel_to_link(&pa->kin, v, PLANT_AXES, qd) != C4G_OK ||
        c4g_kin_motor_vel_to_link(&pa->kin, a, PLANT_AXES, qdd) != C4G_OK) {
        return -1;
    }
    for (i = 0; i < PLANT_AXES; i++) {
        pa->dc->qpos[pa->qadr[i]] = q[i];
        pa->dc->qvel[pa->vadr[i]] = qd[i];
        pa->dc->qacc[pa->vadr[i]] = qdd[i]; /* rad/s^2: the conversion is linear */
    }
    mj_inverse(pa->mc, pa->dc);
    mj_fullM(pa->mc, full, pa->dc->qM);
    for (i = 0; i < PLANT_AXES; i++) {
        /* tau_m = Kr^-T tau: the torque motor i supplies */
        double t = 0.0;
        double in = 0.0;
        for (j = 0; j < PLANT_AXES; j++) {
            t += pa->kinv[j][i] * pa->dc->qfrc_inverse[pa->vadr[j]];
            for (k = 0; k < PLANT_AXES; k++) {
                in += pa->kinv[j][i] * full[(pa->vadr[j] * PLANT_AXES) + pa->vadr[k]] * pa->kinv[k][i];
            }
        }
        cur[i] = t / pa->p[i]->kt;
        inertia[i] = in;
    }
    return 0;
}

void plant_arm_joints(const plant_arm_t *pa, double q[PLANT_AXES], double qd[PLANT_AXES])
{
    int i;
    for (i = 0; i < PLANT_AXES; i++) {
        q[i] = pa->d->qpos[pa->qadr[i]];
        qd[i] = pa->d->qvel[pa->vadr[i]];
    }
}

double plant_arm_energy(plant_arm_t *pa)
{
    const int flags = pa->m->opt.enableflags;
    pa->m->opt.enableflags |= mjENBL_ENERGY; /* MuJoCo computes it only when asked to */
    mj_forward(pa->m, pa->d);
    mj_energyPos(pa->m, pa->d);
    mj_energyVel(pa->m, pa->d);
    pa->m->opt.enableflags = flags;
    return pa->d->energy[0] + pa->d->energy[1];
}

void plant_arm_mujoco(const plant_arm_t *pa, int controller, const void **model, void **data)
{
    *model = controller ? (const void *)pa->mc : (const void *)pa->m;
    *data = controller ? (void *)pa->dc : (void *)pa->d;
}

void plant_arm_gear(const plant_arm_t *pa, double kr[PLANT_AXES][PLANT_AXES],
                    double kinv[PLANT_AXES][PLANT_AXES])
{
    memcpy(kr, pa->kr, sizeof pa->kr);
    memcpy(kinv, pa->kinv, sizeof pa->kinv);
}
