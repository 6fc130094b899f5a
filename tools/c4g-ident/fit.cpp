// SPDX-License-Identifier: MIT
// The fit: a linear least-squares start (for a grid of Stribeck velocities), then Ceres with
// analytic derivatives over blocks of samples, a per-sample robust loss, bounds, and the
// covariance scaled by a robust noise estimate; the variant is chosen on held-out data.
#include "ident.hpp"

#include <ceres/ceres.h>
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace ident {

const char *const param_name[NPARAM] = {"Ja", "Fv", "Fc", "off", "Fs", "vs", "ga", "gb"};
const char *const param_unit[NPARAM] = {"A/(turn/s^2)", "A/(turn/s)", "A", "A", "A", "turn/s", "A", "A"};
const char *const variant_name[NVARIANT] = {"coulomb", "coulomb+gravity", "stribeck",
                                            "stribeck+gravity"};

bool variant_gravity(Variant v) { return v == COULOMB_G || v == STRIBECK_G; }

bool variant_has(Variant v, Param p)
{
    switch (p) {
    case JA: case FV: case FC: case OFF: return true;
    case FS: case VS: return v == STRIBECK || v == STRIBECK_G;
    case GA: case GB: return variant_gravity(v);
    default: return false;
    }
}

double model_eval(const Vec &p, double eps, double v, double a, double cq, double sq, Vec *g)
{
    const double S = std::tanh(v / eps);
    double E = 0.0;
    if (p[VS] > 0.0) {
        const double r = v / p[VS];
        E = std::exp(-r * r);
    }
    const double f = p[JA] * a + p[FV] * v + (p[FC] + (p[FS] - p[FC]) * E) * S + p[OFF] +
                     p[GA] * cq + p[GB] * sq;
    if (g != nullptr) {
        (*g)[JA] = a;
        (*g)[FV] = v;
        (*g)[FC] = (1.0 - E) * S;
        (*g)[OFF] = 1.0;
        (*g)[FS] = E * S;
        (*g)[VS] = (p[VS] > 0.0) ? (p[FS] - p[FC]) * S * E * 2.0 * v * v / (p[VS] * p[VS] * p[VS]) : 0.0;
        (*g)[GA] = cq;
        (*g)[GB] = sq;
    }
    return f;
}

namespace {

std::vector<int> active(Variant v)
{
    std::vector<int> idx;
    for (int p = 0; p < NPARAM; p++) {
        if (variant_has(v, static_cast<Param>(p))) idx.push_back(p);
    }
    return idx;
}

double median_abs(std::vector<double> x)
{
    if (x.empty()) return 0.0;
    for (double &y : x) y = std::fabs(y);
    const std::size_t m = x.size() / 2;
    std::nth_element(x.begin(), x.begin() + static_cast<long>(m), x.end());
    return x[m];
}

// rho(s) for s = r^2 and the robust residual sqrt(rho) with its slope d(rt)/dr.
inline void robust(Loss loss, double c, double r, double *rt, double *slope)
{
    const double ar = std::fabs(r);
    if (loss == LOSS_HUBER) {
        if (ar <= c) {
            *rt = r;
            *slope = 1.0;
        } else {
            const double q = std::sqrt(2.0 * c * ar - c * c);
            *rt = (r > 0.0) ? q : -q;
            *slope = c / q;
        }
    } else if (loss == LOSS_CAUCHY) {
        const double s = r * r / (c * c);
        if (s < 1e-12) {
            *rt = r;
            *slope = 1.0;
            return;
        }
        const double rho = c * c * std::log1p(s);
        const double q = std::sqrt(rho);
        *rt = (r > 0.0) ? q : -q;
        *slope = (1.0 / (1.0 + s)) * ar / q;  // rho'(s) r / rt, with rho' = 1/(1+s)
    } else {
        *rt = r;
        *slope = 1.0;
    }
}

// A block of samples as one Ceres residual block: the robust loss is applied per sample
// inside it (a Ceres LossFunction would act on the block's whole squared norm).
class BlockCost : public ceres::CostFunction {
public:
    BlockCost(const Samples &s, std::size_t b, std::size_t e, const std::vector<int> &idx,
              const Vec &fixed, double eps, Loss loss, double c)
        : s_(s), b_(b), e_(e), idx_(idx), fixed_(fixed), eps_(eps), loss_(loss), c_(c)
    {
        set_num_residuals(static_cast<int>(e - b));
        mutable_parameter_block_sizes()->push_back(static_cast<int>(idx.size()));
    }
    bool Evaluate(double const *const *x, double *res, double **jac) const override
    {
        Vec p = fixed_;
        const std::size_t P = idx_.size();
        for (std::size_t k = 0; k < P; k++) p[static_cast<std::size_t>(idx_[k])] = x[0][k];
        Vec g;
        for (std::size_t j = b_; j < e_; j++) {
            const double f = model_eval(p, eps_, s_.v[j], s_.a[j], s_.cq[j], s_.sq[j],
                                        jac != nullptr && jac[0] != nullptr ? &g : nullptr);
            const double r = f - s_.i[j];
            double rt, sl;
            robust(loss_, c_, r, &rt, &sl);
            if (!std::isfinite(rt)) return false;
            res[j - b_] = rt;
            if (jac != nullptr && jac[0] != nullptr) {
                double *row = jac[0] + (j - b_) * P;
                for (std::size_t k = 0; k < P; k++) row[k] = sl * g[static_cast<std::size_t>(idx_[k])];
            }
        }
        return true;
    }

private:
    const Samples &s_;
    std::size_t b_, e_;
    std::vector<int> idx_;
    Vec fixed_;
    double eps_;
    Loss loss_;
    double c_;
};

constexpr std::size_t kBlock = 512;

void residuals(const Samples &s, const Vec &p, double eps, std::vector<double> *r)
{
    r->resize(s.n());
    for (std::size_t j = 0; j < s.n(); j++) {
        (*r)[j] = s.i[j] - model_eval(p, eps, s.v[j], s.a[j], s.cq[j], s.sq[j], nullptr);
    }
}

// Information matrix J^T J over the samples (no loss), for the active parameters.
Eigen::MatrixXd info(const Samples &s, const std::vector<int> &idx, const Vec &p, double eps)
{
    const Eigen::Index P = static_cast<Eigen::Index>(idx.size());
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(P, P);
    Vec g;
    Eigen::VectorXd row(P);
    for (std::size_t j = 0; j < s.n(); j++) {
        (void)model_eval(p, eps, s.v[j], s.a[j], s.cq[j], s.sq[j], &g);
        for (Eigen::Index k = 0; k < P; k++) row(k) = g[static_cast<std::size_t>(idx[static_cast<std::size_t>(k)])];
        M.selfadjointView<Eigen::Lower>().rankUpdate(row);
    }
    return M.selfadjointView<Eigen::Lower>();
}

double scaled_cond(const Eigen::MatrixXd &M)
{
    const Eigen::VectorXd d = M.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd N = d.asDiagonal() * M * d.asDiagonal();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(N);
    const double lmin = std::max(es.eigenvalues().minCoeff(), 1e-300);
    return std::sqrt(es.eigenvalues().maxCoeff() / lmin);
}

}  // namespace

bool fit_linear(const Samples &s, Variant v, double eps, double vs, Vec *p, double *cost)
{
    // columns: a, v, (1-E)S, 1, [E S], [cos q, sin q]
    const bool str = (v == STRIBECK || v == STRIBECK_G) && vs > 0.0;
    const bool grav = variant_gravity(v);
    std::vector<int> col = {JA, FV, FC, OFF};
    if (str) col.push_back(FS);
    if (grav) {
        col.push_back(GA);
        col.push_back(GB);
    }
    const Eigen::Index P = static_cast<Eigen::Index>(col.size());
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(P, P);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(P);
    Eigen::VectorXd row(P);
    double yy = 0.0;
    for (std::size_t j = 0; j < s.n(); j++) {
        const double S = std::tanh(s.v[j] / eps);
        double E = 0.0;
        if (str) {
            const double r = s.v[j] / vs;
            E = std::exp(-r * r);
        }
        Eigen::Index k = 0;
        row(k++) = s.a[j];
        row(k++) = s.v[j];
        row(k++) = (1.0 - E) * S;
        row(k++) = 1.0;
        if (str) row(k++) = E * S;
        if (grav) {
            row(k++) = s.cq[j];
            row(k++) = s.sq[j];
        }
        M.selfadjointView<Eigen::Lower>().rankUpdate(row);
        b += row * s.i[j];
        yy += s.i[j] * s.i[j];
    }
    M = M.selfadjointView<Eigen::Lower>();
    const Eigen::VectorXd d = M.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd N = d.asDiagonal() * M * d.asDiagonal();
    Eigen::LDLT<Eigen::MatrixXd> ldlt(N);
    if (ldlt.info() != Eigen::Success) return false;
    const Eigen::VectorXd z = ldlt.solve(d.asDiagonal() * b);
    const Eigen::VectorXd x = d.asDiagonal() * z;
    if (!x.allFinite()) return false;
    *p = Vec{};
    for (Eigen::Index k = 0; k < P; k++) (*p)[static_cast<std::size_t>(col[static_cast<std::size_t>(k)])] = x(k);
    if (!str) (*p)[FS] = (*p)[FC];
    (*p)[VS] = str ? vs : 0.0;
    if (cost != nullptr) *cost = std::max(0.0, (yy - x.dot(b)) / static_cast<double>(std::max<std::size_t>(1, s.n())));
    return true;
}

namespace {

Vec linear_start(const Samples &s, Variant v, double eps, double vmax)
{
    Vec best{};
    double bc = 1e300;
    if (v == STRIBECK || v == STRIBECK_G) {
        const double lo = std::max(10.0 * eps, 1e-6), hi = std::max(lo * 2.0, 0.5 * vmax);
        for (int k = 0; k < 16; k++) {
            const double vs = lo * std::pow(hi / lo, k / 15.0);
            Vec p;
            double c;
            if (fit_linear(s, v, eps, vs, &p, &c) && c < bc) {
                bc = c;
                best = p;
            }
        }
        if (bc < 1e300) return best;
    }
    if (!fit_linear(s, v, eps, 0.0, &best, &bc)) best = Vec{};
    if (v == STRIBECK || v == STRIBECK_G) {
        best[FS] = best[FC];
        best[VS] = std::max(10.0 * eps, 0.1 * vmax);
    }
    return best;
}

}  // namespace

Fit fit(const Samples &s, Variant v, double eps, const Options &o)
{
    const auto t0 = std::chrono::steady_clock::now();
    Fit F;
    F.variant = v;
    double vmax = 0.0;
    for (double x : s.v) vmax = std::max(vmax, std::fabs(x));
    Vec p = linear_start(s, v, eps, vmax);
    // keep the start inside the bounds
    p[JA] = std::max(p[JA], 1e-12);
    for (int k : {FV, FC, FS}) p[static_cast<std::size_t>(k)] = std::max(p[static_cast<std::size_t>(k)], 0.0);
    std::vector<double> r;
    residuals(s, p, eps, &r);
    double sigma = 1.4826 * median_abs(r);
    if (!(sigma > 0.0)) sigma = 1e-9;
    const std::vector<int> idx = active(v);
    const std::size_t P = idx.size();
    std::vector<double> x(P);
    ceres::Solver::Summary sum;
    for (int pass = 0; pass < 3; pass++) {
        for (std::size_t k = 0; k < P; k++) x[k] = p[static_cast<std::size_t>(idx[k])];
        ceres::Problem::Options po;
        po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
        ceres::Problem prob(po);
        const double c = o.loss_k * sigma;
        for (std::size_t b = 0; b < s.n(); b += kBlock) {
            const std::size_t e = std::min(s.n(), b + kBlock);
            prob.AddResidualBlock(new BlockCost(s, b, e, idx, p, eps, o.loss, c), nullptr, x.data());
        }
        for (std::size_t k = 0; k < P; k++) {
            const int q = idx[k];
            if (q == JA) prob.SetParameterLowerBound(x.data(), static_cast<int>(k), 1e-12);
            if (q == FV || q == FC || q == FS) prob.SetParameterLowerBound(x.data(), static_cast<int>(k), 0.0);
            if (q == VS) prob.SetParameterLowerBound(x.data(), static_cast<int>(k), 2.0 * eps);
        }
        ceres::Solver::Options so;
        so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
        so.num_threads = std::max(1, o.threads);
        so.max_num_iterations = 100;
        so.function_tolerance = 1e-9;
        so.gradient_tolerance = 1e-12;
        so.parameter_tolerance = 1e-9;
        so.logging_type = ceres::SILENT;
        ceres::Solve(so, &prob, &sum);
        F.iterations += static_cast<int>(sum.iterations.size());
        for (std::size_t k = 0; k < P; k++) p[static_cast<std::size_t>(idx[k])] = x[k];
        if (v == COULOMB || v == COULOMB_G) p[FS] = p[FC];
        residuals(s, p, eps, &r);
        const double s2 = 1.4826 * median_abs(r);
        const bool settled = std::fabs(s2 - sigma) <= 0.02 * sigma;
        sigma = (s2 > 0.0) ? s2 : sigma;
        if (settled || o.loss == LOSS_NONE) {
            // covariance of this very problem, read only when Compute succeeded
            ceres::Covariance::Options co;
            co.algorithm_type = ceres::DENSE_SVD;
            co.num_threads = std::max(1, o.threads);
            co.null_space_rank = 0;
            co.min_reciprocal_condition_number = 1e-14;
            ceres::Covariance cov(co);
            std::vector<std::pair<const double *, const double *>> blocks = {{x.data(), x.data()}};
            if (cov.Compute(blocks, &prob)) {
                std::vector<double> C(P * P);
                if (cov.GetCovarianceBlock(x.data(), x.data(), C.data())) {
                    F.cov_ok = true;
                    for (std::size_t k = 0; k < P; k++) {
                        const double var = C[k * P + k];
                        ParamStat &st = F.st[static_cast<std::size_t>(idx[k])];
                        st.sigma = (var > 0.0) ? sigma * std::sqrt(var) : 0.0;
                    }
                }
            }
            if (!F.cov_ok) F.warnings.push_back("covariance could not be computed (rank-deficient regressor)");
            break;
        }
    }
    F.p = p;
    F.sigma = sigma;
    double ss = 0.0, si = 0.0;
    std::size_t ni = 0;
    for (double e : r) {
        ss += e * e;
        if (std::fabs(e) <= 4.0 * sigma) {
            si += e * e;
            ni++;
        }
    }
    F.rms = std::sqrt(ss / static_cast<double>(std::max<std::size_t>(1, r.size())));
    F.rms_inlier = std::sqrt(si / static_cast<double>(std::max<std::size_t>(1, ni)));
    F.outlier_frac = 1.0 - static_cast<double>(ni) / static_cast<double>(std::max<std::size_t>(1, r.size()));
    F.cond = scaled_cond(info(s, idx, p, eps));
    for (std::size_t k = 0; k < P; k++) {
        ParamStat &st = F.st[static_cast<std::size_t>(idx[k])];
        st.free = true;
        st.value = p[static_cast<std::size_t>(idx[k])];
        st.ci95 = 1.959964 * st.sigma;
        st.pct = (st.value != 0.0) ? 100.0 * st.sigma / std::fabs(st.value) : 1e300;
    }
    if (sum.termination_type == ceres::FAILURE) F.warnings.push_back("the solver failed: " + sum.message);
    F.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return F;
}

Validation validate(const Samples &s, const Fit &f, double eps, double noise)
{
    Validation V;
    std::vector<double> r;
    residuals(s, f.p, eps, &r);
    double ss = 0, si = 0, peak = 0;
    std::size_t ni = 0;
    for (std::size_t j = 0; j < r.size(); j++) {
        ss += r[j] * r[j];
        peak = std::max(peak, std::fabs(s.i[j]));
        if (std::fabs(r[j]) <= 4.0 * f.sigma) {
            si += r[j] * r[j];
            ni++;
        }
    }
    V.n = r.size();
    V.rms = std::sqrt(ss / static_cast<double>(std::max<std::size_t>(1, r.size())));
    V.rms_inlier = std::sqrt(si / static_cast<double>(std::max<std::size_t>(1, ni)));
    V.pct_peak = (peak > 0.0) ? 100.0 * V.rms_inlier / peak : 0.0;
    V.x_noise = (noise > 0.0) ? V.rms_inlier / noise : 0.0;
    return V;
}

bool crlb(const Samples &s, Variant v, const Vec &p, double eps, double sigma, Vec *sd)
{
    const std::vector<int> idx = active(v);
    const Eigen::MatrixXd M = info(s, idx, p, eps);
    Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
    if (ldlt.info() != Eigen::Success) return false;
    const Eigen::MatrixXd C = ldlt.solve(Eigen::MatrixXd::Identity(M.rows(), M.cols()));
    *sd = Vec{};
    for (std::size_t k = 0; k < idx.size(); k++) {
        const double var = C(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
        if (!(var > 0.0)) return false;
        (*sd)[static_cast<std::size_t>(idx[k])] = sigma * std::sqrt(var);
    }
    return true;
}

namespace {

double heldout_cost(const Samples &s, const Fit &f, double eps, const Options &o)
{
    std::vector<double> r;
    residuals(s, f.p, eps, &r);
    const double c = o.loss_k * f.sigma;
    double sum = 0.0;
    for (double e : r) {
        double rt, sl;
        robust(o.loss, c, e, &rt, &sl);
        sum += rt * rt;
    }
    return sum / static_cast<double>(std::max<std::size_t>(1, r.size()));
}

void split(const Samples &s, double frac, Samples *a, Samples *b)
{
    const std::size_t n = s.n();
    const std::size_t cut = static_cast<std::size_t>(static_cast<double>(n) * (1.0 - frac));
    auto part = [&](std::size_t lo, std::size_t hi, Samples *d) {
        auto cp = [&](const std::vector<double> &x, std::vector<double> *y) { y->assign(x.begin() + static_cast<long>(lo), x.begin() + static_cast<long>(hi)); };
        cp(s.v, &d->v); cp(s.a, &d->a); cp(s.i, &d->i); cp(s.cq, &d->cq); cp(s.sq, &d->sq); cp(s.t, &d->t);
        d->tick.assign(s.tick.begin() + static_cast<long>(lo), s.tick.begin() + static_cast<long>(hi));
    };
    part(0, cut, a);
    part(cut, n, b);
}

}  // namespace

AxisResult identify(const AxisLog &log, const AxisLog *val_log, const Options &o)
{
    AxisResult R;
    R.arm = log.arm;
    R.axis = log.axis;
    R.open = log.open;
    R.period = log.period;
    {
        double s2 = 0, se = 0;
        std::size_t n = 0;
        for (std::size_t k = 0; k < log.d5.size(); k++) {
            const double d = static_cast<double>(log.d5[k]) - static_cast<double>(log.e1[k]);
            s2 += d * d;
            se += static_cast<double>(log.e2[k]);
            n++;
        }
        R.ext1_rms = n ? std::sqrt(s2 / static_cast<double>(n)) : 0.0;
        R.ext2_mean = n ? se / static_cast<double>(n) : 0.0;
    }
    if (log.tick.size() < static_cast<std::size_t>(4 * o.sg_half + 10)) {
        R.why_not = "too few ticks (" + std::to_string(log.tick.size()) + ")";
        return R;
    }
    Samples all;
    R.prep = prepare(log, o, &all);
    const std::size_t min_n = 200;
    if (all.n() < min_n) {
        char b[200];
        std::snprintf(b, sizeof b, "the axis hardly moved: %llu of %zu ticks above the standstill speed %.3g turn/s",
                      static_cast<unsigned long long>(all.n()), log.tick.size(), 5.0 * R.prep.eps);
        R.why_not = b;
        return R;
    }
    // both directions are needed to tell Coulomb friction from the offset
    std::size_t pos = 0, neg = 0;
    for (double v : all.v) (v > 0.0 ? pos : neg)++;
    if (pos < min_n / 4 || neg < min_n / 4) {
        R.why_not = "the axis moved in one direction only (" + std::to_string(pos) + " samples forward, " +
                    std::to_string(neg) + " backward): Coulomb friction and offset cannot be told apart";
        return R;
    }
    Samples train, val;
    Options ov = o;
    if (val_log != nullptr) {
        train = all;
        ov.delay_auto = false;
        ov.delay = R.prep.delay;
        ov.eps = R.prep.eps;
        (void)prepare(*val_log, ov, &val);
    } else {
        split(all, o.holdout, &train, &val);
    }
    std::vector<Variant> cand;
    if (o.force_variant >= 0) {
        cand.push_back(static_cast<Variant>(o.force_variant));
    } else {
        cand = {COULOMB, STRIBECK};
        if (log.have_q && o.want_gravity) {
            cand.push_back(COULOMB_G);
            cand.push_back(STRIBECK_G);
        }
    }
    if ((o.force_variant >= 0 && variant_gravity(static_cast<Variant>(o.force_variant))) && !log.have_q) {
        R.why_not = "the gravity variant needs the link angle (a capture with its init packet)";
        return R;
    }
    double best = 1e300;
    std::array<Fit, NVARIANT> fits;
    for (Variant v : cand) {
        fits[v] = fit(val.n() > 0 ? train : all, v, R.prep.eps, o);
        R.tried[v] = true;
        R.val_cost[v] = (val.n() > 0) ? heldout_cost(val, fits[v], R.prep.eps, o) : fits[v].rms;
        best = std::min(best, R.val_cost[v]);
    }
    // the simplest variant within 0.2 % of the best held-out cost
    static const Variant order[NVARIANT] = {COULOMB, COULOMB_G, STRIBECK, STRIBECK_G};
    Variant chosen = cand.front();
    for (Variant v : order) {
        if (R.tried[v] && R.val_cost[v] <= best * 1.002) {
            chosen = v;
            break;
        }
    }
    const double noise = (R.prep.noise_floor > 0.0) ? R.prep.noise_floor : fits[chosen].sigma;
    if (val.n() > 0) R.val = validate(val, fits[chosen], R.prep.eps, noise);
    R.fit = (val_log != nullptr) ? fits[chosen] : fit(all, chosen, R.prep.eps, o);
    R.identifiable = true;
    for (int k = 0; k < NPARAM; k++) {
        const ParamStat &st = R.fit.st[static_cast<std::size_t>(k)];
        if (st.free && (!R.fit.cov_ok || st.pct > 50.0)) {
            char b[160];
            std::snprintf(b, sizeof b, "%s is poorly identified (sigma %.3g %%): excite the axis more", param_name[k], st.pct);
            R.warnings.push_back(b);
        }
    }
    if (R.fit.cond > 1e6) {
        char b[120];
        std::snprintf(b, sizeof b, "regressor condition number %.3g: parameters are nearly collinear", R.fit.cond);
        R.warnings.push_back(b);
    }
    for (const std::string &w : R.fit.warnings) R.warnings.push_back(w);
    return R;
}

}  // namespace ident
