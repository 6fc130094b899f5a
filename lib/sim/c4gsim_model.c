/* SPDX-License-Identifier: MIT */
/* c4g-sim robot model: J*acc = Kt*i - Fv*vel - Fc*sign(vel) - gravity, DSA P/PI loops
 * with anti-windup and current saturation, encoder quantization and noise. */
#include "c4gsim_model.h"

#include <math.h>

#define TWO_PI 6.283185307179586
#define STICK_VEL 1e-6   /* turns/s: below this an axis can stick (Coulomb) */
#define ACC_FRACTION 0.25 /* trapezoid: accel and decel each take this share of the move */

void c4gsim_rng_seed(c4gsim_rng_t *r, uint64_t seed)
{
    r->s = seed ^ 0x9E3779B97F4A7C15ULL;
    if (r->s == 0U) {
        r->s = 0x2545F4914F6CDD1DULL;
    }
    r->have_spare = 0;
    r->spare = 0.0;
}

uint64_t c4gsim_rng_next(c4gsim_rng_t *r)
{
    uint64_t x = r->s;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    r->s = x;
    return x * 0x2545F4914F6CDD1DULL;
}

double c4gsim_rng_uniform(c4gsim_rng_t *r)
{
    return (double)(c4gsim_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

double c4gsim_rng_gauss(c4gsim_rng_t *r)
{
    double u1;
    double u2;
    double m;
    if (r->have_spare) {
        r->have_spare = 0;
        return r->spare;
    }
    do {
        u1 = c4gsim_rng_uniform(r);
    } while (u1 <= 1e-300);
    u2 = c4gsim_rng_uniform(r);
    m = sqrt(-2.0 * log(u1));
    r->spare = m * sin(TWO_PI * u2);
    r->have_spare = 1;
    return m * cos(TWO_PI * u2);
}

void c4gsim_axis_params_default(c4gsim_axis_params_t *p, unsigned logical)
{
    /* Figure 10.1 values for axes 1..6 (reused cyclically for further axes). */
    static const double cal[6] = {0.142965, 0.170353, 0.222660, 0.405883, 0.039380, 0.355824};
    static const double azl[6] = {24.5, 24.5, 24.5, 9.5, 9.5, 9.5};
    static const double axi[6] = {0.0, 0.0, 0.0, -0.0200, 0.0204, 0.0200};
    static const double txr[6] = {-181.587296, 159.260864, 162.473694, 72.585968, 78.75, -50.0};
    static const double fol[6] = {7.5, 7.5, 7.5, 7.5, 7.5, 0.0};
    static const double jm[6] = {4e-4, 4e-4, 3e-4, 1e-4, 1e-4, 8e-5};
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
    p->kv = 150.0 * TWO_PI * p->j / p->kt;
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
}

static double quantize(double x, double counts)
{
    return (counts > 0.0) ? floor(x * counts + 0.5) / counts : x;
}

static double measure(const c4gsim_axis_params_t *p, double pos, c4gsim_rng_t *rng)
{
    const double n = (p->noise > 0.0) ? p->noise * c4gsim_rng_gauss(rng) : 0.0;
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

void c4gsim_axis_reset(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, c4gsim_rng_t *rng)
{
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
    a->saturated = 0;
    a->drive_on = 0;
}

double c4gsim_axis_friction_level(const c4gsim_axis_params_t *p, double vel)
{
    if (p->vs > 0.0) {
        const double r = vel / p->vs;
        return p->fc + (p->fs - p->fc) * exp(-r * r);
    }
    return p->fc;
}

double c4gsim_axis_gravity(const c4gsim_axis_params_t *p, double pos)
{
    const double ratio = (fabs(p->tx_rate) > 1e-9) ? p->tx_rate : 1.0;
    return p->gravity * sin(TWO_PI * pos / ratio);
}

static double clampd(double x, double lim)
{
    return (x > lim) ? lim : ((x < -lim) ? -lim : x);
}

void c4gsim_axis_step(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, const c4gsim_dsa_in_t *in,
                   double dt, c4gsim_rng_t *rng)
{
    double share = in->pc_share;
    double rho;
    double vel_cmd;
    double e;
    double i_reg;
    double i_tot;
    double torque;
    double acc;

    /* The velocity feedforward goes through the same filter as the measured velocity (half a
     * step of the encoder's difference, then the low-pass), so an axis that follows its
     * reference exactly leaves the velocity loop nothing to correct. */
    a->ff_vel += p->vel_filter * (0.5 * (in->vel_ff + a->prev_ff) - a->ff_vel);
    a->prev_ff = in->vel_ff;
    if (!a->drive_on) {
        /* Brakes engaged, no current. */
        a->vel = 0.0;
        a->integ = 0.0;
        a->cur = 0.0;
        a->cur_n++;
        a->saturated = 0;
        encoder(a, p, dt, rng);
        return;
    }
    share = (share < 0.0) ? 0.0 : ((share > 1.0) ? 1.0 : share);
    rho = 1.0 - share;

    /* DSA: P position loop, PI velocity loop; the regulator is limited to rho*AzLim
     * (soft control switching, chapter 12) and its integrator cannot wind up. */
    vel_cmd = p->kp * (in->pos_ref - a->meas_pos) + a->ff_vel + in->vel_add;
    e = vel_cmd - a->meas_vel;
    i_reg = p->kv * e + a->integ;
    if (fabs(i_reg) < rho * p->az_lim || (i_reg > 0.0) != (e > 0.0)) {
        a->integ += p->ki * e * dt;
    }
    a->integ = clampd(a->integ, rho * p->az_lim);
    i_reg = clampd(p->kv * e + a->integ, rho * p->az_lim);
    i_tot = i_reg + share * in->cur_pc + in->cur_add;
    a->saturated = fabs(i_tot) > p->az_lim;
    a->cur = clampd(i_tot, p->az_lim);

    a->cur_sum += a->cur;
    a->cur_n++;

    /* Plant, Coulomb/Stribeck friction with sticking. The step uses the midpoint rule
     * (friction at the step's mid velocity, gravity at its mid position) and the trapezoidal rule for the position, so the
     * mean current of a period and the motion over it describe the same instants. */
    torque = p->kt * a->cur - c4gsim_axis_gravity(p, a->pos + 0.5 * dt * a->vel) - p->load;
    if (p->torque_noise > 0.0) {
        torque += p->torque_noise * c4gsim_rng_gauss(rng);
    }
    {
        const double stick = (p->vs > 0.0 && p->fs > p->fc) ? p->fs : p->fc;
        if (fabs(a->vel) < STICK_VEL && fabs(torque) <= stick) {
            a->vel = 0.0;
            encoder(a, p, dt, rng);
            return;
        }
    }
    {
        const double v_old = a->vel;
        const double dir = (fabs(v_old) >= STICK_VEL) ? ((v_old > 0.0) ? 1.0 : -1.0)
                                                      : ((torque > 0.0) ? 1.0 : -1.0);
        const double inertia = p->j * TWO_PI;
        double fr = c4gsim_axis_friction_level(p, v_old);
        double net = torque - p->fv * TWO_PI * v_old - fr * dir;
        const double v_mid = v_old + 0.5 * dt * net / inertia;
        /* Not across a reversal or from rest: there the sticking rules decide. */
        if (fabs(v_old) >= STICK_VEL && (v_mid > 0.0) == (v_old > 0.0)) {
            fr = c4gsim_axis_friction_level(p, v_mid);
            net = torque - p->fv * TWO_PI * v_mid - fr * dir;
        }
        acc = net / inertia;
        a->vel += acc * dt;
        /* Friction cannot reverse the motion within one step. */
        if (v_old != 0.0 && (a->vel > 0.0) != (v_old > 0.0) && fabs(torque) <= fr) {
            a->vel = 0.0;
        }
        a->pos += 0.5 * (v_old + a->vel) * dt;
    }
    encoder(a, p, dt, rng);
}

void c4gsim_dsa_interp(double p0, double v0, double p1, double v1, double w, double period,
                    double *pos, double *vel)
{
    const double w2 = w * w;
    const double w3 = w2 * w;
    const double d0 = v0 * period;
    const double d1 = v1 * period;
    *pos = (2.0 * w3 - 3.0 * w2 + 1.0) * p0 + (w3 - 2.0 * w2 + w) * d0 + (3.0 * w2 - 2.0 * w3) * p1 +
           (w3 - w2) * d1;
    *vel = ((6.0 * w2 - 6.0 * w) * (p0 - p1) + (3.0 * w2 - 4.0 * w + 1.0) * d0 +
            (3.0 * w2 - 2.0 * w) * d1) / period;
}

double c4gsim_axis_report_current(c4gsim_axis_t *a, const c4gsim_axis_params_t *p, c4gsim_rng_t *rng)
{
    const double mean = (a->cur_n > 0U) ? a->cur_sum / (double)a->cur_n : a->cur;
    a->cur_sum = 0.0;
    a->cur_n = 0U;
    /* the sensor noise touches only what is reported, never the loop */
    a->cur_report = mean + ((p->cur_noise > 0.0) ? p->cur_noise * c4gsim_rng_gauss(rng) : 0.0);
    return a->cur_report;
}

double c4gsim_trap_min_time(double d, double vmax, double amax)
{
    const double ad = fabs(d);
    double t1;
    double t2;
    if (ad <= 0.0) {
        return 0.0;
    }
    /* Peak velocity v = d / (T (1 - f)), acceleration a = v / (f T). */
    t1 = (vmax > 0.0) ? ad / (vmax * (1.0 - ACC_FRACTION)) : 0.0;
    t2 = (amax > 0.0) ? sqrt(ad / (amax * ACC_FRACTION * (1.0 - ACC_FRACTION))) : 0.0;
    return (t1 > t2) ? t1 : t2;
}

void c4gsim_trap_plan(c4gsim_trap_t *t, double p0, double p1, double duration)
{
    t->p0 = p0;
    t->d = p1 - p0;
    t->t_total = (duration > 0.0) ? duration : 0.0;
    t->t_acc = ACC_FRACTION * t->t_total;
}

void c4gsim_trap_eval(const c4gsim_trap_t *t, double time, double *pos, double *vel)
{
    double s;
    double v;
    const double T = t->t_total;
    const double ta = t->t_acc;
    if (T <= 0.0 || time >= T) {
        *pos = t->p0 + t->d;
        *vel = 0.0;
        return;
    }
    if (time < 0.0) {
        time = 0.0;
    }
    /* Normalised: peak velocity vp = 1 / (T - ta). */
    {
        const double vp = 1.0 / (T - ta);
        const double a = vp / ta;
        if (time < ta) {
            s = 0.5 * a * time * time;
            v = a * time;
        } else if (time < T - ta) {
            s = 0.5 * a * ta * ta + vp * (time - ta);
            v = vp;
        } else {
            const double r = T - time;
            s = 1.0 - 0.5 * a * r * r;
            v = a * r;
        }
    }
    *pos = t->p0 + t->d * s;
    *vel = t->d * v;
}

void c4gsim_ref_step(c4gsim_ref_t *r, int mode, const c4g_pc_axis_t *pc, double pos_i, double vel_i,
                  double override, double T, c4gsim_dsa_in_t *in)
{
    in->pos_ref = pos_i;
    in->vel_ff = vel_i;
    in->vel_add = 0.0;
    in->cur_add = 0.0;
    in->cur_pc = 0.0;
    switch (mode) {
    case C4G_MODE_1:
    case C4G_MODE_1_STANDBY:
        in->pos_ref = (pc != NULL) ? pc->target_pos : r->pos_ref;
        in->vel_ff = (pc != NULL) ? pc->target_vel / T : 0.0;
        in->vel_add = (pc != NULL) ? pc->vel_add / T : 0.0;
        in->cur_pc = (pc != NULL) ? pc->current_add : 0.0;
        break;
    case C4G_MODE_2:
    case C4G_MODE_2_STANDBY:
        in->vel_add = (pc != NULL) ? pc->vel_add / T : 0.0;
        in->cur_pc = (pc != NULL) ? pc->current_add : 0.0;
        break;
    case C4G_MODE_4:
        in->pos_ref = (pc != NULL) ? pc->target_pos : r->pos_ref;
        in->vel_ff = (pc != NULL) ? pc->target_vel / T : 0.0;
        break;
    case C4G_MODE_5: {
        const double vj = (pc != NULL) ? override * pc->target_vel : 0.0;
        r->pos_k += vel_i * T + vj;
        in->pos_ref = r->pos_k;
        in->vel_ff = vel_i + vj / T;
        break;
    }
    case C4G_MODE_7:
        r->offset += (pc != NULL) ? pc->target_pos : 0.0;
        in->pos_ref = pos_i + r->offset;
        break;
    case C4G_MODE_8: {
        const double v = (pc != NULL) ? pc->vel_add : 0.0;
        r->offset += v;
        in->pos_ref = pos_i + r->offset;
        in->vel_ff = vel_i + v / T;
        break;
    }
    case C4G_MODE_9:
        in->cur_add = (pc != NULL) ? pc->current_add : 0.0;
        break;
    default:
        break;
    }
    r->pos_ref = in->pos_ref;
}
