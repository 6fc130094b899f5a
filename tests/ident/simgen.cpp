// SPDX-License-Identifier: MIT
#include "simgen.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace simgen {

constexpr double kTwoPi = 6.283185307179586;

// The model's statuses: a case it refuses is a broken harness, not a result.
static void must(c4g_status_t st)
{
    if (st != C4G_OK) {
        throw std::runtime_error("c4g-sim model: status " + std::to_string(static_cast<int>(st)));
    }
}

static double uniform(c4gsim_rng_t *r)
{
    double u = 0.0;
    must(c4gsim_rng_uniform(r, &u));
    return u;
}

ident::Vec truth(const c4gsim_axis_params_t &p)
{
    ident::Vec t{};
    t[ident::JA] = kTwoPi * p.j / p.kt;
    t[ident::FV] = kTwoPi * p.fv / p.kt;
    t[ident::FC] = p.fc / p.kt;
    t[ident::FS] = (p.vs > 0.0) ? p.fs / p.kt : p.fc / p.kt;
    t[ident::VS] = p.vs;
    t[ident::OFF] = p.load / p.kt;
    // gravity/kt * sin(2 pi pos / tx) = G sin(q + phi), q = 2 pi (pos - cal) / tx
    const double G = p.gravity / p.kt, phi = kTwoPi * p.cal / p.tx_rate;
    t[ident::GA] = G * std::sin(phi);
    t[ident::GB] = G * std::cos(phi);
    return t;
}

double link_angle(const c4gsim_axis_params_t &p, double motor) { return kTwoPi * (motor - p.cal) / p.tx_rate; }

ident::AxisLog run(const Case &c, uint64_t seed)
{
    c4gsim_rng_t rng, orng;
    must(c4gsim_rng_seed(&rng, seed));
    must(c4gsim_rng_seed(&orng, seed * 7919U + 17U));
    ident::ExciteOptions eo = c.ex;
    eo.duration = c.seconds;
    eo.seed = static_cast<unsigned>(seed % 97U);
    ident::ExciteAxis ea;
    ea.vmax = c.vmax;
    ea.amax = c.amax;
    ea.on = !c.still;
    const ident::Excitation ex(eo, {ea});
    c4gsim_axis_t a;
    must(c4gsim_axis_reset(&a, &c.p, &rng));
    a.drive_on = true;
    ident::AxisLog L;
    L.arm = 1;
    L.axis = c.logical + 1;
    L.open = c.logical + 1;
    L.period = c.period;
    L.az_lim = c.p.az_lim;
    L.have_q = true;
    const int sub = static_cast<int>(std::lround(c.period / 0.0005));
    const double dt = c.period / sub;
    const std::size_t n = static_cast<std::size_t>(c.seconds / c.period);
    double prev = a.meas_pos;
    double prev_ref = c.p.pos0;
    double prev_vel = 0.0;
    for (std::size_t k = 1; k <= n; k++) {
        const double t = static_cast<double>(k) * c.period;
        double q, v, acc;
        ex.eval(0, t, &q, &v, &acc);
        c4gsim_dsa_in_t in{};
        in.pos_ref = c.p.pos0 + q;
        in.vel_ff = v;
        // as c4g-sim: the DSA interpolates the reference over its steps
        for (int j = 0; j < sub; j++) {
            c4gsim_dsa_in_t st = in;
            must(c4gsim_dsa_interp(prev_ref, prev_vel, in.pos_ref, in.vel_ff, static_cast<double>(j) / sub,
                                   c.period, &st.pos_ref, &st.vel_ff));
            must(c4gsim_axis_step(&a, &c.p, &st, dt, &rng));
        }
        prev_ref = in.pos_ref;
        prev_vel = in.vel_ff;
        double d5 = 0.0;
        must(c4gsim_axis_report_current(&a, &c.p, &rng, &d5));
        if (c.outliers > 0.0 && uniform(&orng) < c.outliers) {
            const double m = c.outlier_size * (0.5 + 0.5 * uniform(&orng));
            d5 += (uniform(&orng) < 0.5) ? -m : m;
        }
        L.tick.push_back(static_cast<int64_t>(k));
        L.t.push_back(t);
        L.d1.push_back(static_cast<float>(in.pos_ref));
        L.d2.push_back(static_cast<float>(v * c.period));
        L.d3.push_back(static_cast<float>(a.meas_pos));
        L.d4.push_back(static_cast<float>(a.meas_pos - prev));
        L.d5.push_back(static_cast<float>(d5));
        L.e1.push_back(static_cast<float>(c4gsim_axis_gravity(&c.p, a.pos) / c.p.kt));
        L.e2.push_back(static_cast<float>(c.p.j));
        L.q.push_back(link_angle(c.p, static_cast<double>(static_cast<float>(a.meas_pos))));
        prev = a.meas_pos;
        L.seen++;
    }
    return L;
}

}  // namespace simgen
