// SPDX-License-Identifier: MIT
#include "excite.hpp"

#include <algorithm>
#include <cmath>

namespace ident {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Smooth 0 -> 1 over [0, 1] with zero first and second derivatives at both ends.
void smooth_step(double x, double *s, double *ds, double *dds)
{
    if (x <= 0.0) { *s = 0; *ds = 0; *dds = 0; return; }
    if (x >= 1.0) { *s = 1; *ds = 0; *dds = 0; return; }
    *s = x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
    *ds = 30.0 * x * x * (1.0 - x) * (1.0 - x);
    *dds = 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x);
}
}  // namespace

Excitation::Excitation(const ExciteOptions &o, const std::vector<ExciteAxis> &axes) : o_(o)
{
    const int K = std::max(1, o.harmonics);
    amp_.resize(axes.size());
    ph_.resize(axes.size());
    for (std::size_t ax = 0; ax < axes.size(); ax++) {
        std::vector<double> &A = amp_[ax], &P = ph_[ax];
        A.assign(static_cast<std::size_t>(K), 0.0);
        P.assign(static_cast<std::size_t>(K), 0.0);
        if (!axes[ax].on) continue;
        for (int k = 1; k <= K; k++) {
            A[static_cast<std::size_t>(k - 1)] = std::pow(static_cast<double>(k), -o.slope);
            // Schroeder phases (low crest factor), shifted per axis and seed
            P[static_cast<std::size_t>(k - 1)] = -kPi * k * (k - 1) / K + 0.7 * static_cast<double>(ax + 1) * k + 0.37 * o.seed * k;
        }
        // scale: the peak velocity and acceleration over one period within the limits
        double vp = 0.0, ap = 0.0;
        const double Tp = 1.0 / o.f0;
        for (int j = 0; j < 4000; j++) {
            double q, v, a;
            raw(ax, Tp * j / 4000.0, &q, &v, &a);
            vp = std::max(vp, std::fabs(v));
            ap = std::max(ap, std::fabs(a));
        }
        const double slow = (o.stops > 0.0) ? 1.0 / 3.5 : 1.0; // the stages' time warp peaks at 1.875x
        const double s = 0.9 * slow * std::min(axes[ax].vmax / std::max(vp, 1e-300), axes[ax].amax / std::max(ap, 1e-300));
        for (double &x : A) x *= s;
    }
    // constant-speed runs: out at +v and back at -v for each level, smooth speed changes
    const double Tst = o.stair * o.duration;
    seg_.resize(axes.size());
    stair_q_.assign(axes.size(), 0.0);
    double tmax = 0.0;
    for (std::size_t ax = 0; ax < axes.size(); ax++) {
        if (!axes[ax].on || o.stair <= 0.0 || o.levels < 1) continue;
        const double vm = axes[ax].vmax, am = axes[ax].amax;
        std::vector<double> lv;
        for (int j = 0; j < o.levels; j++) {
            const double r = (o.levels > 1) ? static_cast<double>(j) / (o.levels - 1) : 1.0;
            lv.push_back(vm / 300.0 * std::pow(150.0, r));
        }
        // time per level: transitions at 0.5 amax (smooth step peaks at 1.875x the mean)
        auto tr = [&](double dv) { return std::max(0.05, 1.875 * std::fabs(dv) / (0.5 * am)); };
        double fixed = 0.0;
        for (std::size_t j = 0; j < lv.size(); j++) fixed += tr(lv[j]) + tr(2.0 * lv[j]) + tr(lv[j]);
        const double hold = std::max(0.05, (Tst - fixed) / (2.0 * static_cast<double>(lv.size())));
        std::vector<Seg> &S = seg_[ax];
        double t = 0.0, q = 0.0, v = 0.0;
        auto add = [&](double v1, double dur) {
            S.push_back({t, dur, v, v1, q});
            q += (v + v1) * 0.5 * dur;  // the smooth step is antisymmetric: mean speed is the midpoint
            t += dur;
            v = v1;
        };
        for (double L : lv) {
            add(L, tr(L));
            add(L, hold);
            add(-L, tr(2.0 * L));
            add(-L, hold);
            add(0.0, tr(L));
        }
        stair_q_[ax] = q;
        tmax = std::max(tmax, t);
    }
    stair_t_ = tmax;
}

void Excitation::stair(std::size_t ax, double t, double *q, double *v, double *a) const
{
    const std::vector<Seg> &S = seg_[ax];
    *q = stair_q_[ax];
    *v = 0.0;
    *a = 0.0;
    for (const Seg &g : S) {
        if (t >= g.t0 + g.dur) continue;
        const double u = std::max(0.0, (t - g.t0) / g.dur);
        double s, ds, dds;
        smooth_step(u, &s, &ds, &dds);
        const double dv = g.v1 - g.v0;
        const double integ = u * u * u * u * (2.5 - 3.0 * u + u * u);  // integral of the step
        *q = g.q0 + g.v0 * (t - g.t0) + dv * g.dur * integ;
        *v = g.v0 + dv * s;
        *a = dv * ds / g.dur;
        return;
    }
}

void Excitation::raw(std::size_t ax, double t, double *q, double *v, double *a) const
{
    double sq = 0, sv = 0, sa = 0;
    for (std::size_t k = 0; k < amp_[ax].size(); k++) {
        const double w = 2.0 * kPi * o_.f0 * static_cast<double>(k + 1);
        const double x = w * t + ph_[ax][k];
        sq += amp_[ax][k] * std::sin(x);
        sv += amp_[ax][k] * w * std::cos(x);
        sa -= amp_[ax][k] * w * w * std::sin(x);
    }
    *q = sq;
    *v = sv;
    *a = sa;
}

void Excitation::eval(std::size_t ax, double t0, double *q, double *v, double *a) const
{
    if (t0 < stair_t_) {
        stair(ax, t0, q, v, a);
        return;
    }
    const double base = seg_[ax].empty() ? 0.0 : stair_q_[ax];
    const double t = t0 - stair_t_;
    const double span = o_.duration - stair_t_;
    // stop-and-go: time runs through the multi-sine in stages, resting in between
    double tau = t, dtau = 1.0, ddtau = 0.0;
    if (o_.stops > 0.0) {
        const double Tp = 0.5 / o_.f0;           // a stage per half fundamental period
        const double rest = o_.stops * Tp;
        const double cyc = Tp + rest;
        const double n = std::floor(t / cyc);
        const double u = t - n * cyc;
        // within a stage, tau advances with a smooth start and stop
        double s, ds, dds;
        smooth_step(u / Tp, &s, &ds, &dds);
        tau = n * Tp + Tp * s;
        dtau = (u < Tp) ? ds : 0.0;
        ddtau = (u < Tp) ? dds / Tp : 0.0;
    }
    double rq, rv, ra;
    raw(ax, tau, &rq, &rv, &ra);
    double r0;
    {
        double v0, a0;
        raw(ax, 0.0, &r0, &v0, &a0);
    }
    // the path relative to its start, so the offset is 0 at t = 0
    const double qq = rq - r0, vv = rv * dtau, aa = ra * dtau * dtau + rv * ddtau;
    // fade in and out: offset * window
    double w = 1.0, dw = 0.0, ddw = 0.0;
    const double F = std::max(o_.fade, 1e-9);
    if (t < F) {
        smooth_step(t / F, &w, &dw, &ddw);
        dw /= F;
        ddw /= F * F;
    } else if (t > span - F) {
        smooth_step((span - t) / F, &w, &dw, &ddw);
        dw = -dw / F;
        ddw /= F * F;
    }
    if (t >= span) {
        w = dw = ddw = 0.0;
    }
    *q = base + qq * w;
    *v = vv * w + qq * dw;
    *a = aa * w + 2.0 * vv * dw + qq * ddw;
}

}  // namespace ident
