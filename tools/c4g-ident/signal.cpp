// SPDX-License-Identifier: MIT
// From logged ticks to fit samples: Savitzky-Golay velocity and acceleration from D4 (never
// differences of the float32 position D3), the delay of D5 against D4, the noise floor, and
// the samples a friction model cannot explain (standstill, reversals, saturation) left out.
#include "ident.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

namespace ident {

double median_abs(std::vector<double> x)
{
    if (x.empty()) return 0.0;
    for (double &y : x) y = std::fabs(y);
    const std::size_t m = x.size() / 2;
    std::nth_element(x.begin(), x.begin() + static_cast<long>(m), x.end());
    return x[m];
}

double t975(int df)
{
    const double z = 1.959964, n = std::max(1, df);
    return z + (z * z * z + z) / (4.0 * n) + (5.0 * std::pow(z, 5) + 16.0 * z * z * z + 3.0 * z) / (96.0 * n * n);
}

std::vector<double> sg_weights(int half, int order, int deriv, double x)
{
    const int n = 2 * half + 1;
    Eigen::MatrixXd A(n, order + 1);
    for (int j = 0; j < n; j++) {
        const double s = j - half;
        double p = 1.0;
        for (int k = 0; k <= order; k++) {
            A(j, k) = p;
            p *= s;
        }
    }
    Eigen::VectorXd h = Eigen::VectorXd::Zero(order + 1);
    for (int k = deriv; k <= order; k++) {
        // d^deriv/dx^deriv of x^k at x
        double c = 1.0;
        for (int d = 0; d < deriv; d++) c *= (k - d);
        h(k) = c * std::pow(x, k - deriv);
    }
    // w^T = h^T (A^T A)^-1 A^T
    const Eigen::MatrixXd AtA = A.transpose() * A;
    const Eigen::VectorXd z = AtA.ldlt().solve(h);
    const Eigen::VectorXd w = A * z;
    return std::vector<double>(w.data(), w.data() + n);
}

namespace {

// Start of the contiguous segment each sample belongs to, and its end (exclusive).
void segments(const AxisLog &L, std::vector<std::size_t> *lo, std::vector<std::size_t> *hi)
{
    const std::size_t n = L.tick.size();
    lo->assign(n, 0);
    hi->assign(n, n);
    std::size_t s = 0;
    for (std::size_t k = 0; k < n; k++) {
        if (k > 0 && L.tick[k] != L.tick[k - 1] + 1) s = k;
        (*lo)[k] = s;
    }
    std::size_t e = n;
    for (std::size_t k = n; k-- > 0;) {
        (*hi)[k] = e;
        if (k > 0 && L.tick[k] != L.tick[k - 1] + 1) e = k;
    }
}

// Link angle at tick k + d (|d| <= 1): linear between neighbouring ticks of the same segment.
// D5 is the mean current over a tick, so gravity must be read where v and a are, not at the
// tick's end: the difference grows with the speed and would pass for viscous friction.
double q_at(const AxisLog &L, std::size_t k, double d)
{
    const double q = L.q[k];
    if (d < 0.0 && k > 0 && L.tick[k - 1] + 1 == L.tick[k]) return q + d * (q - L.q[k - 1]);
    if (d > 0.0 && k + 1 < L.q.size() && L.tick[k + 1] == L.tick[k] + 1) return q + d * (L.q[k + 1] - q);
    return q;
}

struct Filtered {
    std::vector<double> v, a;
    std::vector<unsigned char> ok;  // full window inside the segment
};

// v and a at D4 sample k + x (ticks), for every k with a full window.
void filter(const AxisLog &L, const Options &o, double x, std::size_t stride, Filtered *f)
{
    const int m = o.sg_half;
    const std::vector<double> w0 = sg_weights(m, o.sg_order, 0, x);
    const std::vector<double> w1 = sg_weights(m, o.sg_order, 1, x);
    std::vector<std::size_t> lo, hi;
    segments(L, &lo, &hi);
    const std::size_t n = L.tick.size();
    const double T = L.period;
    f->v.assign(n, 0.0);
    f->a.assign(n, 0.0);
    f->ok.assign(n, 0);
    for (std::size_t k = 0; k < n; k += stride) {
        if (k < lo[k] + static_cast<std::size_t>(m) || k + static_cast<std::size_t>(m) >= hi[k]) continue;
        double sv = 0.0, sa = 0.0;
        const float *d = &L.d4[k - static_cast<std::size_t>(m)];
        for (int j = 0; j <= 2 * m; j++) {
            sv += w0[static_cast<std::size_t>(j)] * static_cast<double>(d[j]);
            sa += w1[static_cast<std::size_t>(j)] * static_cast<double>(d[j]);
        }
        f->v[k] = sv / T;
        f->a[k] = sa / (T * T);
        f->ok[k] = 1;
    }
}

// Samples near standstill (|v| < 5 eps), a reversal or a tick without the PC's reply (each
// widened, see below: around them the acceleration jumps and no smooth filter follows it),
// and samples at a saturated current (that tick only).
std::vector<unsigned char> usable(const AxisLog &L, const Filtered &f, double eps, int half,
                                  Prep *pr, bool count)
{
    const std::size_t n = L.tick.size();
    std::vector<unsigned char> bad(n, 0), use(n, 0);
    const double sat = (L.az_lim > 0.0) ? 0.98 * L.az_lim : 1e300;
    std::size_t li = 0;  // walks L.late_ticks (ascending) beside L.tick
    for (std::size_t k = 0; k < n; k++) {
        while (li < L.late_ticks.size() && L.late_ticks[li] < L.tick[k]) li++;
        if (li < L.late_ticks.size() && L.late_ticks[li] == L.tick[k]) {
            bad[k] = 3;
            continue;
        }
        if (!f.ok[k]) continue;
        // a reversal can pass between two ticks without any tick near zero speed
        const bool flip = k > 0 && f.ok[k - 1] && L.tick[k - 1] + 1 == L.tick[k] && (f.v[k] > 0.0) != (f.v[k - 1] > 0.0);
        if (std::fabs(f.v[k]) < 5.0 * eps || flip) bad[k] = 1;
        else if (std::fabs(static_cast<double>(L.d5[k])) >= sat) bad[k] = 2;
    }
    // Dilate the still/reversal marks (1) and the ticks without the PC's reply (3) by the
    // filter's half window + 2 ticks and 20 ms each way, by tick number. The drive's loops
    // take a few of their time constants to settle after the friction flips at a reversal,
    // and as long after a missing reply (the reference held, then a step to catch up): with
    // the filter's reach alone there, the inertia of loaded captures came out up to 1.7 % low.
    const int64_t w = half + 2 + static_cast<int64_t>(std::lround(0.02 / L.period));
    auto dilate = [&](unsigned char mark) {
        std::vector<unsigned char> out(n, 0);
        int64_t last = INT64_MIN / 2;
        for (std::size_t k = 0; k < n; k++) {
            if (bad[k] == mark) last = L.tick[k];
            if (L.tick[k] - last <= w) out[k] = 1;
        }
        last = INT64_MAX / 2;
        for (std::size_t k = n; k-- > 0;) {
            if (bad[k] == mark) last = L.tick[k];
            if (last - L.tick[k] <= w) out[k] = 1;
        }
        return out;
    };
    const std::vector<unsigned char> near = dilate(1), jolt = dilate(3);
    // A gap in the NUM sequence: packets the PC never saw, so ticks the controller ran without
    // its reply, as after a late one; the missing ticks are not in the log, so the distance is
    // measured from the gap's ends by tick number.
    std::vector<unsigned char> gap(n, 0);
    {
        int64_t last = INT64_MIN / 2;
        for (std::size_t k = 0; k < n; k++) {
            if (k > 0 && L.tick[k] > L.tick[k - 1] + 1 && L.tick[k] - L.tick[k - 1] < 1000) last = L.tick[k] - 1;
            if (L.tick[k] - last <= w) gap[k] = 1;
        }
        last = INT64_MAX / 2;
        for (std::size_t k = n; k-- > 0;) {
            if (k + 1 < n && L.tick[k + 1] > L.tick[k] + 1 && L.tick[k + 1] - L.tick[k] < 1000) last = L.tick[k] + 1;
            if (last - L.tick[k] <= w) gap[k] = 1;
        }
    }
    for (std::size_t k = 0; k < n; k++) {
        if (!f.ok[k]) {
            if (count) pr->dropped_edge++;
        } else if (bad[k] == 2) {
            if (count) pr->dropped_sat++;
        } else if (near[k]) {
            if (count) pr->dropped_still++;
        } else if (jolt[k]) {
            if (count) pr->dropped_late++;
        } else if (gap[k]) {
            if (count) pr->dropped_gap++;
        } else {
            use[k] = 1;
        }
    }
    return use;
}

// Cost of the linear Coulomb(+gravity) fit with the filter evaluated at x.
// Ticks in @p skip (outliers in D5, from outlier_mask) take no part.
double delay_cost(const AxisLog &L, const Options &o, double x, double eps, std::size_t stride, double vs,
                  const std::vector<unsigned char> &skip, double *best_vs = nullptr, std::size_t *used = nullptr)
{
    Filtered f;
    filter(L, o, x, stride, &f);
    Prep dummy;
    const std::vector<unsigned char> use = usable(L, f, eps, o.sg_half, &dummy, false);
    Samples s;
    for (std::size_t k = 0; k < L.tick.size(); k++) {
        if (!use[k] || (!skip.empty() && skip[k])) continue;
        s.v.push_back(f.v[k]);
        s.a.push_back(f.a[k]);
        s.i.push_back(static_cast<double>(L.d5[k]));
        const double q = L.have_q ? q_at(L, k, x - 0.5) : 0.0;
        s.cq.push_back(L.have_q ? std::cos(q) : 0.0);
        s.sq.push_back(L.have_q ? std::sin(q) : 0.0);
    }
    Vec p{};
    double cost = 0.0;
    if (used != nullptr) *used = s.n();
    if (s.n() < 50) return 1e300;
    if (best_vs != nullptr) {
        // the Stribeck velocity that explains this filter output best (a linear fit per vs)
        double vmax = 0.0, bc = 1e300;
        for (double v : s.v) vmax = std::max(vmax, std::fabs(v));
        const double lo = 10.0 * eps, hi = std::max(2.0 * lo, 0.5 * vmax);
        *best_vs = 0.0;
        for (int k = 0; k < 16; k++) {
            const double vk = lo * std::pow(hi / lo, k / 15.0);
            Vec pk{};
            double ck = 0.0;
            if (fit_linear(s, L.have_q ? STRIBECK_G : STRIBECK, eps, vk, &pk, &ck) && ck < bc) {
                bc = ck;
                *best_vs = vk;
            }
        }
        return bc;
    }
    const Variant var = (vs > 0.0) ? (L.have_q ? STRIBECK_G : STRIBECK) : (L.have_q ? COULOMB_G : COULOMB);
    if (!fit_linear(s, var, eps, vs, &p, &cost)) {
        return 1e300;
    }
    // mean squared residual, each clipped at 3 robust sigmas (outliers in D5 must not steer
    // the delay, and the cost must stay smooth in x for the golden section)
    std::vector<double> r(s.n());
    for (std::size_t k = 0; k < s.n(); k++) {
        r[k] = s.i[k] - model_eval(p, eps, s.v[k], s.a[k], s.cq[k], s.sq[k], nullptr);
    }
    const double c = 3.0 * 1.4826 * median_abs(r);
    double sum = 0.0;
    for (double e : r) sum += std::min(e * e, c * c);
    return sum / static_cast<double>(r.size());
}

// Ticks whose D5 is off the linear Coulomb(+gravity) fit at delay x - 0.5 by more than 3
// robust sigmas. Outliers would otherwise steer the least-squares fits of the delay search:
// with 10 % of D5 spoilt its estimate scattered by a whole tick.
std::vector<unsigned char> outlier_mask(const AxisLog &L, const Options &o, double x, double eps)
{
    Filtered f;
    filter(L, o, x, 1, &f);
    Prep dummy;
    const std::vector<unsigned char> use = usable(L, f, eps, o.sg_half, &dummy, false);
    Samples s;
    std::vector<std::size_t> at;
    for (std::size_t k = 0; k < L.tick.size(); k++) {
        if (!use[k]) continue;
        s.v.push_back(f.v[k]);
        s.a.push_back(f.a[k]);
        s.i.push_back(static_cast<double>(L.d5[k]));
        const double q = L.have_q ? q_at(L, k, x - 0.5) : 0.0;
        s.cq.push_back(L.have_q ? std::cos(q) : 0.0);
        s.sq.push_back(L.have_q ? std::sin(q) : 0.0);
        at.push_back(k);
    }
    std::vector<unsigned char> mask;
    Vec p{};
    double cost = 0.0;
    if (s.n() < 50 || !fit_linear(s, L.have_q ? COULOMB_G : COULOMB, eps, 0.0, &p, &cost)) return mask;
    std::vector<double> r(s.n());
    for (std::size_t k = 0; k < s.n(); k++) {
        r[k] = s.i[k] - model_eval(p, eps, s.v[k], s.a[k], s.cq[k], s.sq[k], nullptr);
    }
    const double c = 3.0 * 1.4826 * median_abs(r);
    mask.assign(L.tick.size(), 0);
    for (std::size_t k = 0; k < s.n(); k++) {
        if (std::fabs(r[k]) > c) mask[at[k]] = 1;
    }
    return mask;
}

double auto_eps(const AxisLog &L, const Options &o, double *vnoise, double *vmax)
{
    Filtered f;
    filter(L, o, 0.0, 1, &f);
    std::vector<double> r;
    double vm = 0.0;
    for (std::size_t k = 0; k < L.tick.size(); k++) {
        if (!f.ok[k]) continue;
        r.push_back(static_cast<double>(L.d4[k]) / L.period - f.v[k]);
        vm = std::max(vm, std::fabs(f.v[k]));
    }
    const double sd_raw = 1.4826 * median_abs(std::move(r));
    const std::vector<double> w0 = sg_weights(o.sg_half, o.sg_order, 0, 0.0);
    double g = 0.0;
    for (double w : w0) g += w * w;
    *vnoise = sd_raw * std::sqrt(g);
    *vmax = vm;
    return std::max({3.0 * *vnoise, 1e-3 * vm, 1e-9});
}

}  // namespace

double noise_floor(const AxisLog &L)
{
    std::vector<double> d;
    const std::size_t n = L.tick.size();
    for (std::size_t k = 2; k < n; k++) {
        if (L.tick[k] != L.tick[k - 1] + 1 || L.tick[k - 1] != L.tick[k - 2] + 1) continue;
        d.push_back(static_cast<double>(L.d5[k]) - 2.0 * static_cast<double>(L.d5[k - 1]) +
                    static_cast<double>(L.d5[k - 2]));
    }
    return 1.4826 * median_abs(std::move(d)) / std::sqrt(6.0);
}

namespace {

// Golden-section search of the delay over [a, b] (the cost is smooth and unimodal there).
double golden(const AxisLog &L, const Options &o, double eps, std::size_t stride, double vs,
              const std::vector<unsigned char> &skip, double a, double b)
{
    const double g = 0.6180339887498949;
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    double f1 = delay_cost(L, o, x1 + 0.5, eps, stride, vs, skip), f2 = delay_cost(L, o, x2 + 0.5, eps, stride, vs, skip);
    while (b - a > 0.005) {
        if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = delay_cost(L, o, x1 + 0.5, eps, stride, vs, skip);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = delay_cost(L, o, x2 + 0.5, eps, stride, vs, skip);
        }
    }
    return 0.5 * (a + b);
}

}  // namespace

namespace {

// Blocks of 2000 consecutive ticks, every k-th, so that at most about @p max ticks remain:
// the delay search filters and fits the log some fifty times, and a long log says no more
// about one delay than a spread-out sample of it.
AxisLog thin_blocks(const AxisLog &L, std::size_t max)
{
    const std::size_t n = L.tick.size(), blk = 2000;
    if (n <= max) return L;
    const std::size_t k = (n + max - 1) / max;
    AxisLog d = L;
    d.tick.clear(); d.t.clear(); d.d1.clear(); d.d2.clear(); d.d3.clear(); d.d4.clear();
    d.d5.clear(); d.e1.clear(); d.e2.clear(); d.q.clear();
    for (std::size_t b = 0; b * blk < n; b += k) {
        for (std::size_t j = b * blk; j < std::min(n, (b + 1) * blk); j++) {
            d.tick.push_back(L.tick[j]);
            d.d3.push_back(L.d3[j]); d.d4.push_back(L.d4[j]); d.d5.push_back(L.d5[j]);
            if (!L.lean) {
                d.t.push_back(L.t[j]); d.d1.push_back(L.d1[j]); d.d2.push_back(L.d2[j]);
                d.e1.push_back(L.e1[j]); d.e2.push_back(L.e2[j]);
            }
            if (j < L.q.size()) d.q.push_back(L.q[j]);
        }
    }
    d.late_ticks = L.late_ticks;
    return d;
}

}  // namespace

namespace {

// Ticks [b, e) of a log (the fields the delay search reads).
AxisLog slice(const AxisLog &L, std::size_t b, std::size_t e)
{
    AxisLog d = L;
    auto cut = [&](auto &v) {
        using V = std::decay_t<decltype(v)>;
        v = V(v.begin() + static_cast<long>(std::min(b, v.size())), v.begin() + static_cast<long>(std::min(e, v.size())));
    };
    cut(d.tick); cut(d.t); cut(d.d1); cut(d.d2); cut(d.d3); cut(d.d4); cut(d.d5); cut(d.e1); cut(d.e2); cut(d.q);
    return d;
}

}  // namespace

double estimate_delay(const AxisLog &Lfull, const Options &o, double eps, double *sd, bool *at_bound)
{
    const AxisLog L = thin_blocks(Lfull, 30000);
    const std::size_t stride = 1;
    // x = delay + 0.5: D4(k) is the mean velocity of (k-1, k], its time k - 0.5.
    // First with the Coulomb model: a coarse grid over +-kDelayMax, then golden section.
    // The range is wider than any delay a drive has (about half a tick): a minimum at its end
    // says the cost is flat (gentle excitation), not where the delay is.
    double best = 0.0, bc = 1e300;
    const std::vector<unsigned char> none;
    for (double d = -kDelayMax; d <= kDelayMax + 1e-4; d += 0.25) {
        const double c = delay_cost(L, o, d + 0.5, eps, stride, 0.0, none);
        if (c < bc) {
            bc = c;
            best = d;
        }
    }
    const std::vector<unsigned char> skip = outlier_mask(L, o, best + 0.5, eps);
    const double d0 = golden(L, o, eps, stride, 0.0, skip, std::max(-kDelayMax, best - 0.25), std::min(kDelayMax, best + 0.25));
    // A Stribeck dip the Coulomb model cannot follow pulls the delay: refine with the
    // Stribeck velocity that fits best at d0, when it fits clearly better.
    double vs = 0.0;
    const double cs = delay_cost(L, o, d0 + 0.5, eps, stride, 0.0, skip, &vs);
    const double cc = delay_cost(L, o, d0 + 0.5, eps, stride, 0.0, skip);
    double d = d0;
    if (vs > 0.0 && cs < 0.99 * cc) {
        d = golden(L, o, eps, stride, vs, skip, std::max(-kDelayMax, d0 - 0.5), std::min(kDelayMax, d0 + 0.5));
    } else {
        vs = 0.0;
    }
    if (at_bound != nullptr) *at_bound = std::fabs(d) >= kDelayMax - 0.05;
    if (sd != nullptr) {
        // least squares in one more parameter: var(d) = sigma^2 / sum (dr/dd)^2, and the mean
        // squared residual c(d) has c'' = 2 sum (dr/dd)^2 / n, c(d0) = sigma^2
        auto curv_sd = [&](const AxisLog &P, double at, double scale) {
            const double h = 0.25;
            std::size_t n = 0;
            const double c0 = delay_cost(P, o, at + 0.5, eps, stride, vs, skip.size() == P.tick.size() ? skip : none, nullptr, &n);
            const double cp = delay_cost(P, o, at + h + 0.5, eps, stride, vs, skip.size() == P.tick.size() ? skip : none);
            const double cm = delay_cost(P, o, at - h + 0.5, eps, stride, vs, skip.size() == P.tick.size() ? skip : none);
            const double curv = (cp + cm - 2.0 * c0) / (h * h);
            const double nn = static_cast<double>(n) * scale;
            return (curv > 0.0 && nn > 0.0 && c0 < 1e299) ? std::sqrt(2.0 * c0 / (nn * curv)) : kDelayMax;
        };
        // the thinned log stands for the whole one
        const double scale = static_cast<double>(Lfull.tick.size()) / static_cast<double>(std::max<std::size_t>(1, L.tick.size()));
        *sd = curv_sd(L, d, scale);
        // The spread of the delays found on each fifth of the log: a coloured
        // residual or a second valley moves them apart, where the curvature at the minimum
        // sees nothing. Only the fifths that pin a delay of their own (curvature figure under a
        // tick) take part: a stretch of constant-speed runs says nothing either way.
        constexpr int kParts = 5;
        if (L.tick.size() >= static_cast<std::size_t>(kParts) * 2000U) {
            std::vector<double> dj;
            for (int part = 0; part < kParts; part++) {
                const AxisLog P = slice(L, L.tick.size() * static_cast<std::size_t>(part) / kParts,
                                        L.tick.size() * static_cast<std::size_t>(part + 1) / kParts);
                double pb = 0.0, pc = 1e300;
                for (double x = -kDelayMax; x <= kDelayMax + 1e-4; x += 0.25) {
                    const double c = delay_cost(P, o, x + 0.5, eps, stride, vs, none);
                    if (c < pc) {
                        pc = c;
                        pb = x;
                    }
                }
                if (!(pc < 1e299)) continue;
                const double x = golden(P, o, eps, stride, vs, none, std::max(-kDelayMax, pb - 0.25), std::min(kDelayMax, pb + 0.25));
                if (curv_sd(P, x, scale) < 1.0) dj.push_back(x);
            }
            if (dj.size() >= 3) {
                double m = 0.0;
                for (double x : dj) m += x;
                m /= static_cast<double>(dj.size());
                double ss = 0.0;
                for (double x : dj) ss += (x - m) * (x - m);
                const double J = static_cast<double>(dj.size());
                // the parts' own spread, not divided by sqrt(J) as independent estimates of
                // one delay would be: parts that disagree say the model's delay depends on
                // what the axis did, and a fit of the whole is as uncertain as that
                *sd = std::max(*sd, std::sqrt(ss / (J - 1.0)));
            }
        }
    }
    return d;
}

namespace {

constexpr double kTwoPi = 6.283185307179586;

// The least-squares slope of EXT1 (cq) on the inertial torque (sq, unscaled) with the
// nuisance columns 1, v, v^2 (Coriolis) and a cubic in D3 (gravity). 0 when none.
double ctrl_scale(const Samples &s)
{
    const int P = 7;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(P, P);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(P);
    Eigen::VectorXd z(P);
    double lo = 1e300, hi = -1e300;
    for (std::size_t j = 0; j < s.n(); j++) {
        lo = std::min(lo, s.pos[j]);
        hi = std::max(hi, s.pos[j]);
    }
    const double span = (hi > lo) ? hi - lo : 1.0;
    for (std::size_t j = 0; j < s.n(); j++) {
        const double x = 2.0 * (s.pos[j] - lo) / span - 1.0;
        z(0) = s.sq[j];
        z(1) = 1.0;
        z(2) = s.v[j];
        z(3) = s.v[j] * s.v[j];
        z(4) = x;
        z(5) = x * x;
        z(6) = x * x * x;
        M += z * z.transpose();
        b += z * s.cq[j];
    }
    if (s.n() < static_cast<std::size_t>(4 * P)) return 0.0;
    const Eigen::VectorXd d = M.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::VectorXd x = d.asDiagonal() * (d.asDiagonal() * M * d.asDiagonal()).ldlt().solve(d.asDiagonal() * b);
    return (x.allFinite() && x(0) > 0.0) ? x(0) : 0.0;
}

}  // namespace

Prep prepare(const AxisLog &L, const Options &o, Samples *out)
{
    Prep pr = prepare_axis(L, o);
    Filtered f;
    filter(L, o, pr.delay + 0.5, 1, &f);
    const std::vector<unsigned char> use = usable(L, f, pr.eps, o.sg_half, &pr, true);
    *out = Samples();
    for (std::size_t k = 0; k < L.tick.size(); k++) {
        if (!use[k]) continue;
        out->v.push_back(f.v[k]);
        out->a.push_back(f.a[k]);
        out->i.push_back(static_cast<double>(L.d5[k]));
        const double q = L.have_q ? q_at(L, k, pr.delay) : 0.0;
        if (o.ctrl) {
            // the ctrl family's columns: EXT1 and EXT2's inertial torque (scaled below)
            out->cq.push_back(static_cast<double>(L.e1[k]));
            out->sq.push_back(static_cast<double>(L.e2[k]) * kTwoPi * f.a[k]);
        } else {
            out->cq.push_back(L.have_q ? std::cos(q) : 0.0);
            out->sq.push_back(L.have_q ? std::sin(q) : 0.0);
        }
        out->pos.push_back(static_cast<double>(L.d3[k]));
        out->tick.push_back(L.tick[k]);
        out->t.push_back(L.t[k]);
        pr.vmax = std::max(pr.vmax, std::fabs(f.v[k]));
        pr.amax = std::max(pr.amax, std::fabs(f.a[k]));
        pr.ipeak = std::max(pr.ipeak, std::fabs(static_cast<double>(L.d5[k])));
    }
    pr.kept = out->n();
    if (o.ctrl) {
        // ks: EXT1's own slope on the inertial torque EXT2*2*pi*a (the controller's 1/Kt),
        // beside what else EXT1 holds (gravity, Coriolis: a constant, v, v^2, a cubic in D3).
        // With it k2 ~ 1 when the controller's inertia is right.
        pr.ks = ctrl_scale(*out);
        for (std::size_t j = 0; j < out->n(); j++) {
            out->sq[j] *= pr.ks;
            out->cq[j] -= out->sq[j];  // EXT1 but its inertial part
            pr.e1max = std::max(pr.e1max, std::fabs(out->cq[j]));
            pr.inmax = std::max(pr.inmax, std::fabs(out->sq[j]));
        }
    }
    return pr;
}

Prep prepare_axis(const AxisLog &L, const Options &o)
{
    Prep pr;
    double vmax = 0.0;
    const double eps_auto = auto_eps(L, o, &pr.vnoise, &vmax);
    pr.eps = (o.eps > 0.0) ? o.eps : eps_auto;
    pr.noise_floor = noise_floor(L);
    if (o.delay_auto) pr.delay = estimate_delay(L, o, pr.eps, &pr.delay_sd, &pr.delay_at_bound);
    else pr.delay = o.delay;
    return pr;
}

void track(const AxisLog &L, const Options &o, double delay, Prep *pr, Track *out)
{
    Filtered f;
    filter(L, o, delay + 0.5, 1, &f);
    const std::vector<unsigned char> use = usable(L, f, pr->eps, o.sg_half, pr, true);
    const std::size_t n = L.tick.size();
    out->v.resize(n);
    out->a.resize(n);
    out->q.resize(n);
    out->ok = f.ok;
    out->use = use;
    for (std::size_t k = 0; k < n; k++) {
        out->v[k] = static_cast<float>(f.v[k]);
        out->a[k] = static_cast<float>(f.a[k]);
        out->q[k] = L.have_q ? static_cast<float>(q_at(L, k, delay)) : 0.0F;
        if (use[k]) {
            pr->kept++;
            pr->vmax = std::max(pr->vmax, std::fabs(f.v[k]));
            pr->amax = std::max(pr->amax, std::fabs(f.a[k]));
            pr->ipeak = std::max(pr->ipeak, std::fabs(static_cast<double>(L.d5[k])));
        }
    }
}

}  // namespace ident
