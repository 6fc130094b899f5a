/* SPDX-License-Identifier: MIT */
/* c4g-sim robot model: J*acc = Kt*i - Fv*vel - Fc*sign(vel) - gravity, DSA P/PI loops
 * with anti-windup and current saturation, encoder quantization and noise. */
#include "c4gsim_model.h"

#include <math.h>
#include <stddef.h>

#define TWO_PI 6.283185307179586
#define STICK_VEL 1e-6   /* turns/s: below this an axis can stick (Coulomb) */
#define ACC_FRACTION 0.25 /* trapezoid: accel and decel each take this share of the move */

/* ---- checks --------------------------------------------------------------- */

static bool fin(double x)
{
    return isfinite(x) != 0;
}

static bool fin4(double a, double b, double c, double d)
{
    return fin(a) && fin(b) && fin(c) && fin(d);
}

c4g_status_t c4gsim_axis_params_check(const c4gsim_axis_params_t *p)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (p != NULL) {
        const bool finite = fin4(p->j, p->kt, p->fv, p->fc) && fin4(p->fs, p->vs, p->load, p->cur_noise) &&
                            fin4(p->torque_noise, p->gravity, p->kp, p->kv) &&
                            fin4(p->ki, p->az_lim, p->tx_rate, p->cal) &&
                            fin4(p->ax_info, p->follow_error, p->counts, p->noise) &&
                            fin4(p->vel_filter, p->vmax, p->amax, p->pos0);
        if (!finite) {
            st = C4G_ERR_NONFINITE;
        } else if ((p->j <= 0.0) || (p->kt <= 0.0) || (p->vs < 0.0) || (p->cur_noise < 0.0) ||
                   (p->torque_noise < 0.0) || (p->az_lim < 0.0) || (p->counts < 0.0) ||
                   (p->noise < 0.0) || (p->vel_filter < 0.0) || (p->vel_filter > 1.0)) {
            st = C4G_ERR_RANGE;
        } else {
            st = C4G_OK;
        }
    }
    return st;
}

/* ---- random numbers ------------------------------------------------------- */

c4g_status_t c4gsim_rng_seed(c4gsim_rng_t *r, uint64_t seed)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (r != NULL) {
        r->s = seed ^ 0x9E3779B97F4A7C15ULL;
        if (r->s == 0U) {
            r->s = 0x2545F4914F6CDD1DULL;
        }
        r->have_spare = false;
        r->spare = 0.0;
        st = C4G_OK;
    }
    return st;
}

static uint64_t rng_next(c4gsim_rng_t *r)
{
    uint64_t x = r->s;
    x ^= x >> 12U;
    x ^= x << 25U;
    x ^= x >> 27U;
    r->s = x;
    return x * 0x2545F4914F6CDD1DULL;
}

static double rng_uniform(c4gsim_rng_t *r)
{
    const uint64_t bits = rng_next(r) >> 11U; /* 53 bits: exact in a double */
    return (double)bits * (1.0 / 9007199254740992.0);
}

static double rng_gauss(c4gsim_rng_t *r)
{
    double g;
    if (r->have_spare) {
        r->have_spare = false;
        g = r->spare;
    } else {
        double u1 = 0.0;
        double u2;
        double m;
        bool redraw = true;
        while (redraw) { /* log(0) is not a number: draw again */
            u1 = rng_uniform(r);
            redraw = u1 <= 1e-300;
        }
        u2 = rng_uniform(r);
        m = sqrt(-2.0 * log(u1));
        r->spare = m * sin(TWO_PI * u2);
        r->have_spare = true;
        g = m * cos(TWO_PI * u2);
    }
    return g;
}

c4g_status_t c4gsim_rng_next(c4gsim_rng_t *r, uint64_t *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((r != NULL) && (out != NULL)) {
        *out = rng_next(r);
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4gsim_rng_uniform(c4gsim_rng_t *r, double *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((r != NULL) && (out != NULL)) {
        *out = rng_uniform(r);
        st = C4G_OK;
    }
    return st;
}

c4g_status_t c4gsim_rng_gauss(c4gsim_rng_t *r, double *out)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((r != NULL) && (out != NULL)) {
        *out = rng_gauss(r);
        st = C4G_OK;
    }
    return st;
}

/* ---- axis ----------------------------------------------------------------- */

c4g_status_t c4gsim_axis_params_default(c4gsim_axis_params_t *p, unsigned logical)
{
    /* Figure 10.1 values for axes 1..6 (reused cyclically for further axes). */
    static const double cal[6] = {0.142965, 0.170353, 0.222660, 0.405883, 0.039380, 0.355824};
    static const double azl[6] = {24.5, 24.5, 24.5, 9.5, 9.5, 9.5};
    static const double axi[6] = {0.0, 0.0, 0.0, -0.0200, 0.0204, 0.0200};
    static const double txr[6] = {-181.587296, 159.260864, 162.473694, 72.585968, 78.75, -50.0};
    static const double fol[6] = {7.5, 7.5, 7.5, 7.5, 7.5, 0.0};
    static const double jm[6] = {4e-4, 4e-4, 3e-4, 1e-4, 1e-4, 8e-5};
    c4g_status_t st = C4G_ERR_NULL;
    if (p != NULL) {
        const unsigned k = logical % 6U;
        p->j = jm[k];
        p->kt = (k < 3U) ? 0.8 : 0.5;
        p->fv = 1e-3;
        p->fc = (k < 3U) ? 0.15 : 0.05;
        p->fs = p->fc;
        p->vs = 0.0;
        p->load = 0.0;
        p->cur_noise = 0.0;
        p->torque_noise = 0.0;
        p->gravity = (logical == 1U) ? 6.0 : ((logical == 2U) ? 3.0 : 0.0);
        p->kp = 40.0;
        /* Velocity loop bandwidth about 150 rad/s: kv = w * 2 pi J / Kt. */
        p->kv = (150.0 * TWO_PI * p->j) / p->kt;
        p->ki = p->kv * 40.0;
        p->az_lim = azl[k];
        p->tx_rate = txr[k];
        p->cal = cal[k];
        p->ax_info = axi[k];
        p->follow_error = fol[k];
        p->counts = 16384.0;
        p->noise = 2e-5;
        p->vel_filter = 0.25;
        p->vmax = 20.0;
        p->amax = 200.0;
        p->pos0 = 0.0;
        p->startup_mode = 0;
        st = C4G_OK;
    }
    return st;
}

static double quantize(double x, double counts)
{
    return (counts > 0.0) ? (floor((x * counts) + 0.5) / counts) : x;
}

static double measure(const c4gsim_axis_params_t *p, double pos, c4gsim_rng_t *rng)
{
    const double n = (p->noise > 0.0) ? (p->noise * rng_gauss(rng)) : 0.0;
    return quantize(pos + n, p->counts);
}

/* The encoder is read at the end of each DSA step: the next step regulates on it, and the
 * value at the end of the SMP+ period is what D3 reports for that period's instant (the
 * instant D1 names). */
static void encoder(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, double dt, c4gsim_rng_t *rng)
{
    double raw_vel;
    a->meas_pos = measure(p, a->pos, rng);
    raw_vel = (a->meas_pos - a->prev_meas) / dt;
    a->prev_meas = a->meas_pos;
    a->meas_vel += p->vel_filter * (raw_vel - a->meas_vel);
}

c4g_status_t c4gsim_axis_reset(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, c4gsim_rng_t *rng)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((a != NULL) && (rng != NULL)) {
        st = c4gsim_axis_params_check(p);
    }
    if (st == C4G_OK) {
        a->pos = p->pos0;
        a->vel = 0.0;
        a->integ = 0.0;
        a->cur = 0.0;
        a->cur_report = 0.0;
        a->cur_sum = 0.0;
        a->cur_n = 0U;
        a->meas_pos = measure(p, a->pos, rng);
        a->prev_meas = a->meas_pos;
        a->meas_vel = 0.0;
        a->ff_vel = 0.0;
        a->prev_ff = 0.0;
        a->saturated = false;
        a->drive_on = false;
    }
    return st;
}

double c4gsim_axis_friction_level(const c4gsim_axis_params_t *p, double vel)
{
    double level = p->fc;
    if (p->vs > 0.0) {
        const double r = vel / p->vs;
        level = p->fc + ((p->fs - p->fc) * exp(-r * r));
    }
    return level;
}

double c4gsim_axis_gravity(const c4gsim_axis_params_t *p, double pos)
{
    const double ratio = (fabs(p->tx_rate) > 1e-9) ? p->tx_rate : 1.0;
    return p->gravity * sin((TWO_PI * pos) / ratio);
}

static double clampd(double x, double lim)
{
    return (x > lim) ? lim : ((x < -lim) ? -lim : x);
}

/* Drive off: brakes engaged, no current. */
static void brake(c4gsim_axis_t *a)
{
    a->vel = 0.0;
    a->integ = 0.0;
    a->cur = 0.0;
    a->cur_n++;
    a->saturated = false;
}

/* DSA: P position loop, PI velocity loop; the regulator is limited to rho*AzLim (soft
 * control switching, chapter 12) and its integrator cannot wind up. Sets the current. */
static void regulate(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, const c4gsim_dsa_in_t *in,
                     double dt)
{
    const double share = (in->pc_share < 0.0) ? 0.0 : ((in->pc_share > 1.0) ? 1.0 : in->pc_share);
    const double rho = 1.0 - share;
    const double vel_cmd = (p->kp * (in->pos_ref - a->meas_pos)) + a->ff_vel + in->vel_add;
    const double e = vel_cmd - a->meas_vel;
    const double i_reg0 = (p->kv * e) + a->integ;
    double i_reg;
    double i_tot;
    if ((fabs(i_reg0) < (rho * p->az_lim)) || ((i_reg0 > 0.0) != (e > 0.0))) {
        a->integ += p->ki * e * dt;
    }
    a->integ = clampd(a->integ, rho * p->az_lim);
    i_reg = clampd((p->kv * e) + a->integ, rho * p->az_lim);
    i_tot = i_reg + (share * in->cur_pc) + in->cur_add;
    a->saturated = fabs(i_tot) > p->az_lim;
    a->cur = clampd(i_tot, p->az_lim);
    a->cur_sum += a->cur;
    a->cur_n++;
}

/* Motor torque [Nm] over the step: current, gravity at the step's mid position, load and
 * the disturbance. */
static double motor_torque(const c4gsim_axis_t *a, const c4gsim_axis_params_t *p, double dt,
                           c4gsim_rng_t *rng)
{
    double torque = (p->kt * a->cur) - c4gsim_axis_gravity(p, a->pos + (0.5 * dt * a->vel)) - p->load;
    if (p->torque_noise > 0.0) {
        torque += p->torque_noise * rng_gauss(rng);
    }
    return torque;
}

/* An axis at rest stays there while the torque does not overcome static friction. */
static bool sticks(const c4gsim_axis_t *a, const c4gsim_axis_params_t *p, double torque)
{
    const double stick = ((p->vs > 0.0) && (p->fs > p->fc)) ? p->fs : p->fc;
    return (fabs(a->vel) < STICK_VEL) && (fabs(torque) <= stick);
}

/* Plant, Coulomb/Stribeck friction. The step uses the midpoint rule (friction at the
 * step's mid velocity) and the trapezoidal rule for the position, so the mean current of a
 * period and the motion over it describe the same instants. */
static void move(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, double torque, double dt)
{
    const double v_old = a->vel;
    const double dir = (fabs(v_old) >= STICK_VEL) ? ((v_old > 0.0) ? 1.0 : -1.0)
                                                  : ((torque > 0.0) ? 1.0 : -1.0);
    const double inertia = p->j * TWO_PI;
    double fr = c4gsim_axis_friction_level(p, v_old);
    double net = torque - (p->fv * TWO_PI * v_old) - (fr * dir);
    const double v_mid = v_old + ((0.5 * dt * net) / inertia);
    /* Not across a reversal or from rest: there the sticking rules decide. */
    if ((fabs(v_old) >= STICK_VEL) && ((v_mid > 0.0) == (v_old > 0.0))) {
        fr = c4gsim_axis_friction_level(p, v_mid);
        net = torque - (p->fv * TWO_PI * v_mid) - (fr * dir);
    }
    a->vel += (net / inertia) * dt;
    /* Friction cannot reverse the motion within one step. */
    if (((v_old > 0.0) || (v_old < 0.0)) && ((a->vel > 0.0) != (v_old > 0.0)) && (fabs(torque) <= fr)) {
        a->vel = 0.0;
    }
    a->pos += 0.5 * (v_old + a->vel) * dt;
}

static bool dsa_in_finite(const c4gsim_dsa_in_t *in)
{
    return fin4(in->pos_ref, in->vel_ff, in->vel_add, in->cur_add) && fin(in->cur_pc) && fin(in->pc_share);
}

/* The checks both c4gsim_dsa_current and c4gsim_axis_step make. */
static c4g_status_t dsa_check(const c4gsim_axis_t *a, const c4gsim_axis_params_t *p, const c4gsim_dsa_in_t *in,
                              double dt)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((a != NULL) && (in != NULL)) {
        st = c4gsim_axis_params_check(p);
    }
    if ((st == C4G_OK) && (!dsa_in_finite(in) || !fin(dt))) {
        st = C4G_ERR_NONFINITE;
    }
    if ((st == C4G_OK) && (dt <= 0.0)) {
        st = C4G_ERR_RANGE;
    }
    return st;
}

/* The DSA's loops for one step: the feedforward's filter, then brakes or the regulator. */
static void dsa_current(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, const c4gsim_dsa_in_t *in, double dt)
{
    /* The velocity feedforward goes through the same filter as the measured velocity
     * (half a step of the encoder's difference, then the low-pass), so an axis that
     * follows its reference exactly leaves the velocity loop nothing to correct. */
    a->ff_vel += p->vel_filter * ((0.5 * (in->vel_ff + a->prev_ff)) - a->ff_vel);
    a->prev_ff = in->vel_ff;
    if (!a->drive_on) {
        brake(a);
    } else {
        regulate(a, p, in, dt);
    }
}

c4g_status_t c4gsim_dsa_current(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, const c4gsim_dsa_in_t *in,
                                double dt)
{
    const c4g_status_t st = dsa_check(a, p, in, dt);
    if (st == C4G_OK) {
        dsa_current(a, p, in, dt);
    }
    return st;
}

c4g_status_t c4gsim_axis_measure(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, double dt, c4gsim_rng_t *rng)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((a != NULL) && (rng != NULL)) {
        st = c4gsim_axis_params_check(p);
    }
    if ((st == C4G_OK) && (!fin(dt) || !fin(a->pos))) {
        st = C4G_ERR_NONFINITE;
    }
    if ((st == C4G_OK) && (dt <= 0.0)) {
        st = C4G_ERR_RANGE;
    }
    if (st == C4G_OK) {
        encoder(a, p, dt, rng);
    }
    return st;
}

c4g_status_t c4gsim_axis_step(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, const c4gsim_dsa_in_t *in,
                              double dt, c4gsim_rng_t *rng)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (rng != NULL) {
        st = dsa_check(a, p, in, dt);
    }
    if (st == C4G_OK) {
        dsa_current(a, p, in, dt);
        if (a->drive_on) {
            /* the decoupled plant: one motor, its friction and its own gravity */
            const double torque = motor_torque(a, p, dt, rng);
            if (sticks(a, p, torque)) {
                a->vel = 0.0;
            } else {
                move(a, p, torque, dt);
            }
        }
        encoder(a, p, dt, rng);
    }
    return st;
}

c4g_status_t c4gsim_dsa_interp(double p0, double v0, double p1, double v1, double w, double period,
                               double *pos, double *vel)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((pos != NULL) && (vel != NULL)) {
        st = (fin4(p0, v0, p1, v1) && fin(w) && fin(period)) ? C4G_OK : C4G_ERR_NONFINITE;
    }
    if ((st == C4G_OK) && (period <= 0.0)) {
        st = C4G_ERR_RANGE;
    }
    if (st == C4G_OK) {
        const double w2 = w * w;
        const double w3 = w2 * w;
        const double d0 = v0 * period;
        const double d1 = v1 * period;
        *pos = ((((2.0 * w3) - (3.0 * w2)) + 1.0) * p0) + (((w3 - (2.0 * w2)) + w) * d0) +
               (((3.0 * w2) - (2.0 * w3)) * p1) + ((w3 - w2) * d1);
        *vel = (((((6.0 * w2) - (6.0 * w)) * (p0 - p1)) + ((((3.0 * w2) - (4.0 * w)) + 1.0) * d0)) +
                (((3.0 * w2) - (2.0 * w)) * d1)) / period;
    }
    return st;
}

c4g_status_t c4gsim_axis_report_current(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, c4gsim_rng_t *rng,
                                        double *current)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((a != NULL) && (rng != NULL) && (current != NULL)) {
        st = c4gsim_axis_params_check(p);
    }
    if (st == C4G_OK) {
        const double mean = (a->cur_n > 0U) ? (a->cur_sum / (double)a->cur_n) : a->cur;
        a->cur_sum = 0.0;
        a->cur_n = 0U;
        /* the sensor noise touches only what is reported, never the loop */
        a->cur_report = mean + ((p->cur_noise > 0.0) ? (p->cur_noise * rng_gauss(rng)) : 0.0);
        *current = a->cur_report;
    }
    return st;
}

/* ---- trajectory ----------------------------------------------------------- */

double c4gsim_trap_min_time(double d, double vmax, double amax)
{
    const double ad = fabs(d);
    double t = 0.0;
    if (ad > 0.0) {
        /* Peak velocity v = d / (T (1 - f)), acceleration a = v / (f T). */
        const double t1 = (vmax > 0.0) ? (ad / (vmax * (1.0 - ACC_FRACTION))) : 0.0;
        const double t2 = (amax > 0.0) ? sqrt(ad / (amax * ACC_FRACTION * (1.0 - ACC_FRACTION))) : 0.0;
        t = (t1 > t2) ? t1 : t2;
    }
    return t;
}

c4g_status_t c4gsim_trap_plan(c4gsim_trap_t *t, double p0, double p1, double duration)
{
    c4g_status_t st = C4G_ERR_NULL;
    if (t != NULL) {
        st = (fin(p0) && fin(p1) && fin(duration)) ? C4G_OK : C4G_ERR_NONFINITE;
    }
    if (st == C4G_OK) {
        t->p0 = p0;
        t->d = p1 - p0;
        t->t_total = (duration > 0.0) ? duration : 0.0;
        t->t_acc = ACC_FRACTION * t->t_total;
    }
    return st;
}

/* Normalised profile (distance 1) at @p time inside (0, T): peak velocity 1 / (T - ta). */
static void trap_unit(double T, double ta, double time, double *s, double *v)
{
    const double vp = 1.0 / (T - ta);
    const double acc = vp / ta;
    if (time < ta) {
        *s = 0.5 * acc * time * time;
        *v = acc * time;
    } else if (time < (T - ta)) {
        *s = (0.5 * acc * ta * ta) + (vp * (time - ta));
        *v = vp;
    } else {
        const double r = T - time;
        *s = 1.0 - (0.5 * acc * r * r);
        *v = acc * r;
    }
}

c4g_status_t c4gsim_trap_eval(const c4gsim_trap_t *t, double time, double *pos, double *vel)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((t != NULL) && (pos != NULL) && (vel != NULL)) {
        st = (fin4(t->p0, t->d, t->t_total, t->t_acc) && fin(time)) ? C4G_OK : C4G_ERR_NONFINITE;
    }
    if (st == C4G_OK) {
        if ((t->t_total <= 0.0) || (time >= t->t_total)) {
            *pos = t->p0 + t->d;
            *vel = 0.0;
        } else {
            double s;
            double v;
            trap_unit(t->t_total, t->t_acc, (time < 0.0) ? 0.0 : time, &s, &v);
            *pos = t->p0 + (t->d * s);
            *vel = t->d * v;
        }
    }
    return st;
}

/* ---- the controller's reference ------------------------------------------- */

/* Modes 1 and 2 (and their stand-bys): the PC's current, mode 1 also its position. */
static void ref_current_modes(const c4gsim_ref_t *r, int mode, const c4g_pc_axis_t *pc, double T,
                              c4gsim_dsa_in_t *in)
{
    if ((mode == C4G_MODE_1) || (mode == C4G_MODE_1_STANDBY)) {
        in->pos_ref = (pc != NULL) ? (double)pc->target_pos : r->pos_ref;
        in->vel_ff = (pc != NULL) ? ((double)pc->target_vel / T) : 0.0;
    }
    in->vel_add = (pc != NULL) ? ((double)pc->vel_add / T) : 0.0;
    in->cur_pc = (pc != NULL) ? (double)pc->current_add : 0.0;
}

/* Mode 5: pos_k += vel_i T + override D2 (fig. 14.1). */
static void ref_mode5(c4gsim_ref_t *r, const c4g_pc_axis_t *pc, double vel_i, double override, double T,
                      c4gsim_dsa_in_t *in)
{
    const double vj = (pc != NULL) ? (override * (double)pc->target_vel) : 0.0;
    r->pos_k += (vel_i * T) + vj;
    in->pos_ref = r->pos_k;
    in->vel_ff = vel_i + (vj / T);
}

/* Modes 7 and 8: the PC's offset (mode 8: integrated from its velocity addition). */
static void ref_offset_modes(c4gsim_ref_t *r, int mode, const c4g_pc_axis_t *pc, double pos_i, double vel_i,
                             double T, c4gsim_dsa_in_t *in)
{
    if (mode == C4G_MODE_7) {
        r->offset += (pc != NULL) ? (double)pc->target_pos : 0.0;
        in->pos_ref = pos_i + r->offset;
    } else {
        const double v = (pc != NULL) ? (double)pc->vel_add : 0.0;
        r->offset += v;
        in->pos_ref = pos_i + r->offset;
        in->vel_ff = vel_i + (v / T);
    }
}

static void ref_mode(c4gsim_ref_t *r, int mode, const c4g_pc_axis_t *pc, double pos_i, double vel_i,
                     double override, double T, c4gsim_dsa_in_t *in)
{
    switch (mode) {
    case C4G_MODE_1:
    case C4G_MODE_1_STANDBY:
    case C4G_MODE_2:
    case C4G_MODE_2_STANDBY:
        ref_current_modes(r, mode, pc, T, in);
        break;
    case C4G_MODE_4:
        in->pos_ref = (pc != NULL) ? (double)pc->target_pos : r->pos_ref;
        in->vel_ff = (pc != NULL) ? ((double)pc->target_vel / T) : 0.0;
        break;
    case C4G_MODE_5:
        ref_mode5(r, pc, vel_i, override, T, in);
        break;
    case C4G_MODE_7:
    case C4G_MODE_8:
        ref_offset_modes(r, mode, pc, pos_i, vel_i, T, in);
        break;
    case C4G_MODE_9:
        in->cur_add = (pc != NULL) ? (double)pc->current_add : 0.0;
        break;
    default:
        /* every other mode: the SMP+ trajectory alone */
        break;
    }
}

c4g_status_t c4gsim_ref_step(c4gsim_ref_t *r, int mode, const c4g_pc_axis_t *pc, double pos_i, double vel_i,
                             double override, double T, c4gsim_dsa_in_t *in)
{
    c4g_status_t st = C4G_ERR_NULL;
    if ((r != NULL) && (in != NULL)) {
        const bool state_ok = fin(r->pos_k) && fin(r->offset) && fin(r->pos_ref);
        st = (fin4(pos_i, vel_i, override, T) && state_ok) ? C4G_OK : C4G_ERR_NONFINITE;
    }
    if ((st == C4G_OK) && (pc != NULL) &&
        !fin4((double)pc->target_pos, (double)pc->target_vel, (double)pc->vel_add, (double)pc->current_add)) {
        st = C4G_ERR_NONFINITE;
    }
    if ((st == C4G_OK) && (T <= 0.0)) {
        st = C4G_ERR_RANGE;
    }
    if (st == C4G_OK) {
        in->pos_ref = pos_i;
        in->vel_ff = vel_i;
        in->vel_add = 0.0;
        in->cur_add = 0.0;
        in->cur_pc = 0.0;
        ref_mode(r, mode, pc, pos_i, vel_i, override, T, in);
        r->pos_ref = in->pos_ref;
    }
    return st;
}
