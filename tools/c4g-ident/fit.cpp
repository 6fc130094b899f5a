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
                                            "stribeck+gravity", "ctrl+coulomb", "ctrl+stribeck"};

bool variant_gravity(Variant v) { return v == COULOMB_G || v == STRIBECK_G; }
bool variant_ctrl(Variant v) { return v == CTRL_C || v == CTRL_S; }

bool variant_has(Variant v, Param p)
{
    switch (p) {
    case JA: return !variant_ctrl(v);
    case FV: case FC: case OFF: return true;
    case FS: case VS: return v == STRIBECK || v == STRIBECK_G || v == CTRL_S;
    case GA: case GB: return variant_gravity(v) || variant_ctrl(v);
    default: return false;
    }
}

const char *param_name_of(Variant v, int p)
{
    if (variant_ctrl(v) && p == GA) return "k1";
    if (variant_ctrl(v) && p == GB) return "k2";
    return param_name[p];
}

const char *param_unit_of(Variant v, int p)
{
    if (variant_ctrl(v) && (p == GA || p == GB)) return "1";
    return param_unit[p];
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

// The robust cost's gradient over the active parameters, at p.
std::vector<double> cost_gradient(const Samples &s, const Vec &p, double eps, Loss loss, double c,
                                  const std::vector<int> &idx)
{
    std::vector<double> g(idx.size(), 0.0);
    Vec d;
    for (std::size_t j = 0; j < s.n(); j++) {
        const double f = model_eval(p, eps, s.v[j], s.a[j], s.cq[j], s.sq[j], &d);
        double rt, sl;
        robust(loss, c, f - s.i[j], &rt, &sl);
        for (std::size_t k = 0; k < idx.size(); k++) g[k] += rt * sl * d[static_cast<std::size_t>(idx[k])];
    }
    return g;
}

// Sum of row row^T (lower triangle) for rows of at most NPARAM: plain loops the compiler
// keeps in registers; a dynamic-size Eigen rank update per row cost more than the model.
struct Gram {
    double m[NPARAM][NPARAM] = {};
    std::size_t n;
    explicit Gram(std::size_t size) : n(size) {}
    void add(const double *row)
    {
        for (std::size_t a = 0; a < n; a++) {
            for (std::size_t b = 0; b <= a; b++) m[a][b] += row[a] * row[b];
        }
    }
    Eigen::MatrixXd matrix() const
    {
        Eigen::MatrixXd M(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
        for (std::size_t a = 0; a < n; a++) {
            for (std::size_t b = 0; b <= a; b++) {
                M(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = m[a][b];
                M(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(a)) = m[a][b];
            }
        }
        return M;
    }
};

// J^T J of the robust problem at p, as Ceres sees it (each row scaled by the loss' slope).
Eigen::MatrixXd robust_normal(const Samples &s, const Vec &p, double eps, Loss loss, double c,
                              const std::vector<int> &idx)
{
    const std::size_t P = idx.size();
    Gram G(P);
    double row[NPARAM];
    Vec d;
    for (std::size_t j = 0; j < s.n(); j++) {
        const double f = model_eval(p, eps, s.v[j], s.a[j], s.cq[j], s.sq[j], &d);
        double rt, sl;
        robust(loss, c, f - s.i[j], &rt, &sl);
        for (std::size_t k = 0; k < P; k++) row[k] = sl * d[static_cast<std::size_t>(idx[k])];
        G.add(row);
    }
    return G.matrix();
}

// The whole problem compressed into P residuals with the same normal matrix: r = U (x - x0),
// U^T U = J^T J. Ceres' covariance of it equals that of the full problem and costs nothing
// next to a dense factorization of 10^5..10^6 rows.
class NormalFactor : public ceres::CostFunction {
public:
    NormalFactor(const Eigen::MatrixXd &U, const std::vector<double> &x0) : U_(U), x0_(x0)
    {
        set_num_residuals(static_cast<int>(U.rows()));
        mutable_parameter_block_sizes()->push_back(static_cast<int>(U.cols()));
    }
    bool Evaluate(double const *const *x, double *res, double **jac) const override
    {
        const Eigen::Index P = U_.cols();
        for (Eigen::Index i = 0; i < P; i++) {
            double acc = 0.0;
            for (Eigen::Index k = 0; k < P; k++) acc += U_(i, k) * (x[0][k] - x0_[static_cast<std::size_t>(k)]);
            res[i] = acc;
            if (jac != nullptr && jac[0] != nullptr) {
                for (Eigen::Index k = 0; k < P; k++) jac[0][i * P + k] = U_(i, k);
            }
        }
        return true;
    }

private:
    Eigen::MatrixXd U_;
    std::vector<double> x0_;
};

// Lower bounds: Ja > 0, friction >= 0, vs >= 2 eps.
bool has_lower(int q) { return q == JA || q == FV || q == FC || q == FS || q == VS; }
double lower_of(int q, double eps) { return (q == JA) ? 1e-12 : ((q == VS) ? 2.0 * eps : 0.0); }

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
    Gram G(idx.size());
    Vec g;
    double row[NPARAM];
    for (std::size_t j = 0; j < s.n(); j++) {
        (void)model_eval(p, eps, s.v[j], s.a[j], s.cq[j], s.sq[j], &g);
        for (std::size_t k = 0; k < idx.size(); k++) row[k] = g[static_cast<std::size_t>(idx[k])];
        G.add(row);
    }
    return G.matrix();
}

double scaled_cond(const Eigen::MatrixXd &M)
{
    const Eigen::VectorXd d = M.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd N = d.asDiagonal() * M * d.asDiagonal();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(N);
    const double lmin = std::max(es.eigenvalues().minCoeff(), 1e-300);
    return std::sqrt(es.eigenvalues().maxCoeff() / lmin);
}

// Blocks the scores are summed over for the block-robust covariance.
constexpr int kHacBlocks = 30;

// Block-robust ("sandwich") covariance of the free parameters: H^-1 M H^-1 with H the robust
// normal matrix and M the sum over kHacBlocks equal spans of ticks of the outer products of
// the scores summed in each span. The residual of a real drive is coloured (the DSA loops,
// the filter's 25-tick window, unmodelled effects): the white-noise covariance sigma^2 H^-1
// then claims intervals several times too narrow. Spans of a few seconds hold the
// correlation; G/(G-1) corrects the estimator's bias. false when H is singular.
bool block_cov(const Samples &s, const Vec &p, double eps, Loss loss, double c, const std::vector<int> &free,
               Eigen::MatrixXd *cov, int *blocks)
{
    const std::size_t P = free.size();
    if (P == 0 || s.n() < 2) return false;
    const Eigen::MatrixXd H = robust_normal(s, p, eps, loss, c, free);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
    if (ldlt.info() != Eigen::Success) return false;
    const int64_t t0 = s.tick.empty() ? 0 : s.tick.front();
    const int64_t span = s.tick.empty() ? static_cast<int64_t>(s.n()) : s.tick.back() - t0 + 1;
    std::vector<double> S(static_cast<std::size_t>(kHacBlocks) * P, 0.0);
    std::vector<unsigned char> used(kHacBlocks, 0);
    Vec d;
    for (std::size_t j = 0; j < s.n(); j++) {
        const int64_t at = s.tick.empty() ? static_cast<int64_t>(j) : s.tick[j] - t0;
        const std::size_t b = static_cast<std::size_t>(std::min<int64_t>(kHacBlocks - 1, at * kHacBlocks / std::max<int64_t>(1, span)));
        const double f = model_eval(p, eps, s.v[j], s.a[j], s.cq[j], s.sq[j], &d);
        double rt, sl;
        robust(loss, c, f - s.i[j], &rt, &sl);
        const double psi = rt * sl;
        for (std::size_t k = 0; k < P; k++) S[b * P + k] += psi * d[static_cast<std::size_t>(free[k])];
        used[b] = 1;
    }
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(P), static_cast<Eigen::Index>(P));
    int g = 0;
    for (std::size_t b = 0; b < static_cast<std::size_t>(kHacBlocks); b++) {
        if (!used[b]) continue;
        g++;
        const Eigen::Map<const Eigen::VectorXd> sb(&S[b * P], static_cast<Eigen::Index>(P));
        M += sb * sb.transpose();
    }
    if (g < 2) return false;
    const Eigen::MatrixXd Hi = ldlt.solve(Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(P), static_cast<Eigen::Index>(P)));
    *cov = Hi * M * Hi * (static_cast<double>(g) / static_cast<double>(g - 1));
    *blocks = g;
    return cov->allFinite();
}

}  // namespace

bool fit_linear(const Samples &s, Variant v, double eps, double vs, Vec *p, double *cost)
{
    // columns: a, v, (1-E)S, 1, [E S], [cos q, sin q]
    const bool str = variant_has(v, FS) && vs > 0.0;
    const bool grav = variant_has(v, GA);
    const bool ja = variant_has(v, JA);
    std::vector<int> col = {FV, FC, OFF};
    if (ja) col.insert(col.begin(), JA);
    if (str) col.push_back(FS);
    if (grav) {
        col.push_back(GA);
        col.push_back(GB);
    }
    const Eigen::Index P = static_cast<Eigen::Index>(col.size());
    Gram G(col.size());
    double bb[NPARAM] = {};
    double row[NPARAM];
    double yy = 0.0;
    for (std::size_t j = 0; j < s.n(); j++) {
        const double S = std::tanh(s.v[j] / eps);
        double E = 0.0;
        if (str) {
            const double r = s.v[j] / vs;
            E = std::exp(-r * r);
        }
        std::size_t k = 0;
        if (ja) row[k++] = s.a[j];
        row[k++] = s.v[j];
        row[k++] = (1.0 - E) * S;
        row[k++] = 1.0;
        if (str) row[k++] = E * S;
        if (grav) {
            row[k++] = s.cq[j];
            row[k++] = s.sq[j];
        }
        G.add(row);
        for (std::size_t c = 0; c < k; c++) bb[c] += row[c] * s.i[j];
        yy += s.i[j] * s.i[j];
    }
    const Eigen::MatrixXd M = G.matrix();
    Eigen::VectorXd b(P);
    for (Eigen::Index c = 0; c < P; c++) b(c) = bb[c];
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
    if (variant_has(v, FS)) {
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
    if (variant_has(v, FS)) {
        best[FS] = best[FC];
        best[VS] = std::max(10.0 * eps, 0.1 * vmax);
    }
    return best;
}

}  // namespace

Fit fit(const Samples &s, Variant v, double eps, const Options &o, const Vec *start)
{
    const auto t0 = std::chrono::steady_clock::now();
    Fit F;
    F.variant = v;
    double vmax = 0.0;
    for (double x : s.v) vmax = std::max(vmax, std::fabs(x));
    Vec p = (start != nullptr) ? *start : linear_start(s, v, eps, vmax);
    // keep the start inside the bounds
    if (variant_has(v, JA)) p[JA] = std::max(p[JA], 1e-12);
    else p[JA] = 0.0;
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
        const double c = o.loss_k * sigma;
        // Active set: a parameter the data push against its bound is held there. Ceres only
        // projects its steps onto the bounds, which takes it a hundred or more shrinking
        // steps to settle a misfitting variant (viscous friction pinned at 0, say).
        std::vector<int> held;
        for (std::size_t k = 0; k < P; k++) {
            const int q = idx[k];
            if (has_lower(q) && x[k] <= lower_of(q, eps)) held.push_back(static_cast<int>(k));
        }
        std::unique_ptr<ceres::Problem> probp;
        for (int round = 0; round < 4; round++) {
            ceres::Problem::Options po;
            po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
            probp.reset(new ceres::Problem(po));
            ceres::Problem &pr = *probp;
            for (std::size_t b = 0; b < s.n(); b += kBlock) {
                const std::size_t e = std::min(s.n(), b + kBlock);
                pr.AddResidualBlock(new BlockCost(s, b, e, idx, p, eps, o.loss, c), nullptr, x.data());
            }
            for (std::size_t k = 0; k < P; k++) {
                const int q = idx[k];
                if (has_lower(q)) pr.SetParameterLowerBound(x.data(), static_cast<int>(k), lower_of(q, eps));
            }
            if (!held.empty() && held.size() < P) pr.SetManifold(x.data(), new ceres::SubsetManifold(static_cast<int>(P), held));
            ceres::Solver::Options so;
            so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
            so.num_threads = std::max(1, o.threads);
            so.max_num_iterations = 100;
            so.function_tolerance = 1e-9;
            so.gradient_tolerance = 1e-12;
            so.parameter_tolerance = 1e-9;
            so.logging_type = ceres::SILENT;
            ceres::Solve(so, &pr, &sum);
            F.iterations += static_cast<int>(sum.iterations.size());
            Vec pt = p;
            for (std::size_t k = 0; k < P; k++) pt[static_cast<std::size_t>(idx[k])] = x[k];
            const std::vector<double> g = cost_gradient(s, pt, eps, o.loss, c, idx);
            std::vector<int> next;
            for (std::size_t k = 0; k < P; k++) {
                const int q = idx[k];
                const bool at = has_lower(q) && x[k] <= lower_of(q, eps) * (1.0 + 1e-9) + 1e-15;
                // the cost falls below the bound (gradient > 0 there): hold it
                if (at && g[k] > 0.0) next.push_back(static_cast<int>(k));
            }
            if (next == held) break;
            held = next;
        }
        F.held.clear();
        for (int k : held) F.held.push_back(idx[static_cast<std::size_t>(k)]);
        for (std::size_t k = 0; k < P; k++) p[static_cast<std::size_t>(idx[k])] = x[k];
        if (!variant_has(v, FS)) p[FS] = p[FC];
        residuals(s, p, eps, &r);
        const double s2 = 1.4826 * median_abs(r);
        const bool settled = std::fabs(s2 - sigma) <= 0.02 * sigma;
        sigma = (s2 > 0.0) ? s2 : sigma;
        if (settled || o.loss == LOSS_NONE || pass == 2) {
            // covariance of this very problem (compressed to its normal matrix), read only
            // when Compute succeeded
            const Eigen::LLT<Eigen::MatrixXd> llt(robust_normal(s, p, eps, o.loss, c, idx));
            if (llt.info() == Eigen::Success) {
                std::vector<double> xc = x;
                ceres::Problem cp;
                cp.AddResidualBlock(new NormalFactor(llt.matrixU(), x), nullptr, xc.data());
                if (!held.empty() && held.size() < P) cp.SetManifold(xc.data(), new ceres::SubsetManifold(static_cast<int>(P), held));
                ceres::Covariance::Options co;
                co.algorithm_type = ceres::DENSE_SVD;
                co.num_threads = 1;
                co.null_space_rank = 0;
                co.min_reciprocal_condition_number = 1e-14;
                ceres::Covariance cov(co);
                std::vector<std::pair<const double *, const double *>> blocks = {{xc.data(), xc.data()}};
                if (cov.Compute(blocks, &cp)) {
                    std::vector<double> C(P * P);
                    if (cov.GetCovarianceBlock(xc.data(), xc.data(), C.data())) {
                        F.cov_ok = true;
                        for (std::size_t k = 0; k < P; k++) {
                            const double var = C[k * P + k];
                            ParamStat &st = F.st[static_cast<std::size_t>(idx[k])];
                            st.sigma = (var > 0.0) ? sigma * std::sqrt(var) : 0.0;
                        }
                    }
                }
            }
            if (!F.cov_ok) F.warnings.push_back("covariance could not be computed (rank-deficient regressor)");
            // the block-robust figure over the parameters not held at a bound
            std::vector<int> free;
            for (std::size_t k = 0; k < P; k++) {
                if (std::find(held.begin(), held.end(), static_cast<int>(k)) == held.end()) free.push_back(idx[k]);
            }
            Eigen::MatrixXd bc;
            int g = 0;
            if (F.cov_ok && block_cov(s, p, eps, o.loss, c, free, &bc, &g)) {
                F.blocks = g;
                for (std::size_t k = 0; k < free.size(); k++) {
                    ParamStat &st = F.st[static_cast<std::size_t>(free[k])];
                    st.sigma_white = st.sigma;
                    const double sb = std::sqrt(std::max(0.0, bc(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k))));
                    if (st.sigma_white > 0.0) F.colour = std::max(F.colour, (sb * sb) / (st.sigma_white * st.sigma_white));
                    st.sigma = std::max(st.sigma_white, sb);
                }
            } else if (F.cov_ok) {
                for (std::size_t k = 0; k < P; k++) F.st[static_cast<std::size_t>(idx[k])].sigma_white = F.st[static_cast<std::size_t>(idx[k])].sigma;
            }
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
        st.ci95 = (F.blocks > 1 ? t975(F.blocks - 1) : 1.959964) * st.sigma;
        st.at_bound = std::find(F.held.begin(), F.held.end(), idx[k]) != F.held.end();
        st.pct = st.at_bound ? 0.0 : ((st.value != 0.0) ? 100.0 * st.sigma / std::fabs(st.value) : 1e300);
        if (st.at_bound) {
            char b[160];
            std::snprintf(b, sizeof b, "%s held at its bound %.3g: the data push it below (the variant misfits)",
                          param_name[idx[k]], st.value);
            F.warnings.push_back(b);
        }
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

// Every k-th sample, so that at most @p max remain.
Samples thin(const Samples &s, std::size_t max)
{
    if (max == 0 || s.n() <= max) return s;
    const std::size_t k = (s.n() + max - 1) / max;
    Samples d;
    for (std::size_t j = 0; j < s.n(); j += k) {
        d.v.push_back(s.v[j]);
        d.a.push_back(s.a[j]);
        d.i.push_back(s.i[j]);
        d.cq.push_back(s.cq[j]);
        d.sq.push_back(s.sq[j]);
        if (j < s.pos.size()) d.pos.push_back(s.pos[j]);
        if (j < s.tick.size()) d.tick.push_back(s.tick[j]);
        if (j < s.t.size()) d.t.push_back(s.t[j]);
    }
    return d;
}

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
        if (s.pos.size() == n) cp(s.pos, &d->pos);
        d->tick.assign(s.tick.begin() + static_cast<long>(lo), s.tick.begin() + static_cast<long>(hi));
    };
    part(0, cut, a);
    part(cut, n, b);
}

}  // namespace

namespace {

// RMS [A] of the part of the residual a cubic in the position D3 explains: gravity, which a
// log without the link angle cannot model, shows here (a constant is the offset's already).
double position_effect(const Samples &s, const Fit &f, double eps)
{
    std::vector<double> r;
    residuals(s, f.p, eps, &r);
    double lo = 1e300, hi = -1e300;
    for (double x : s.pos) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
    }
    if (!(hi > lo)) return 0.0;
    Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    for (std::size_t j = 0; j < s.n(); j++) {
        const double x = 2.0 * (s.pos[j] - lo) / (hi - lo) - 1.0;
        const Eigen::Vector4d z(1.0, x, 1.5 * x * x - 0.5, 2.5 * x * x * x - 1.5 * x);
        M += z * z.transpose();
        b += z * r[j];
    }
    const Eigen::Vector4d c = M.ldlt().solve(b);
    double ss = 0.0;
    for (std::size_t j = 0; j < s.n(); j++) {
        const double x = 2.0 * (s.pos[j] - lo) / (hi - lo) - 1.0;
        const double y = c(1) * x + c(2) * (1.5 * x * x - 0.5) + c(3) * (2.5 * x * x * x - 1.5 * x);
        ss += y * y;
    }
    return std::sqrt(ss / static_cast<double>(std::max<std::size_t>(1, s.n())));
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
    if (R.prep.delay_at_bound) {
        char b[240];
        std::snprintf(b, sizeof b, "the delay of D5 after D4 ran to %+.2f ticks, the end of its search (+-%.0f): the "
                      "excitation does not pin it (a drive's is about -0.5); excite faster or give --delay",
                      R.prep.delay, kDelayMax);
        R.why_not = b;
        return R;
    }
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
    if (o.ctrl) {
        // the ctrl family: its two friction forms (a forced variant names the friction)
        if (o.force_variant >= 0) cand.push_back(variant_has(static_cast<Variant>(o.force_variant), FS) ? CTRL_S : CTRL_C);
        else cand = {CTRL_C, CTRL_S};
        if (!(R.prep.ks > 0.0)) {
            R.why_not = "EXT1 does not follow EXT2's inertial torque (no positive slope ks): the log carries no "
                        "controller model the ctrl family could correct";
            return R;
        }
    } else if (o.force_variant >= 0) {
        cand.push_back(static_cast<Variant>(o.force_variant));
    } else {
        cand = {COULOMB, STRIBECK};
        if (log.have_q && o.want_gravity) {
            cand.push_back(COULOMB_G);
            cand.push_back(STRIBECK_G);
        }
    }
    if (!o.ctrl && (o.force_variant >= 0 && variant_gravity(static_cast<Variant>(o.force_variant))) && !log.have_q) {
        R.why_not = "the gravity variant needs the link angle (a capture with its init packet)";
        return R;
    }
    // The variants are compared on evenly spread subsets of at most o.select_max samples of
    // the training part (the choice and the held-out figures need no more); the chosen one is
    // then fitted to every sample, starting from there.
    const Samples &fit_set = (val.n() > 0) ? train : all;
    const Samples sel_train = thin(fit_set, o.select_max);
    const Samples sel_val = thin(val, o.select_max);
    double best = 1e300;
    std::array<Fit, NVARIANT> fits;
    for (Variant v : cand) {
        fits[v] = fit(sel_train, v, R.prep.eps, o);
        R.tried[v] = true;
        R.val_cost[v] = (val.n() > 0) ? heldout_cost(sel_val, fits[v], R.prep.eps, o) : fits[v].rms;
        best = std::min(best, R.val_cost[v]);
    }
    // the simplest variant within 0.2 % of the best held-out cost
    static const Variant order[NVARIANT] = {COULOMB, COULOMB_G, STRIBECK, STRIBECK_G, CTRL_C, CTRL_S};
    Variant chosen = cand.front();
    for (Variant v : order) {
        if (R.tried[v] && R.val_cost[v] <= best * 1.002) {
            chosen = v;
            break;
        }
    }
    const double noise = (R.prep.noise_floor > 0.0) ? R.prep.noise_floor : fits[chosen].sigma;
    if (val.n() > 0) R.val = validate(val, fits[chosen], R.prep.eps, noise);
    R.fit = (val_log != nullptr) ? fits[chosen] : fit(all, chosen, R.prep.eps, o, &fits[chosen].p);
    // The delay's own uncertainty moves every parameter with it: its share is added to each
    // interval (the slope of a linear refit at the delay +- 0.25 tick). The white-noise
    // figure from the search's curvature is widened by the residual's colour.
    if (o.delay_auto && R.prep.delay_sd > 0.0 && val_log == nullptr) {
        const double sd = R.prep.delay_sd * std::sqrt(R.fit.colour);
        const double h = 0.25;
        Options od = o;
        od.delay_auto = false;
        od.eps = R.prep.eps;
        Vec pp{}, pm{};
        Samples sp, sm;
        od.delay = R.prep.delay + h;
        (void)prepare(log, od, &sp);
        od.delay = R.prep.delay - h;
        (void)prepare(log, od, &sm);
        const double vs = variant_has(R.fit.variant, VS) ? R.fit.p[VS] : 0.0;
        if (fit_linear(sp, R.fit.variant, R.prep.eps, vs, &pp, nullptr) &&
            fit_linear(sm, R.fit.variant, R.prep.eps, vs, &pm, nullptr)) {
            const double tq = R.fit.blocks > 1 ? t975(R.fit.blocks - 1) : 1.959964;
            for (int k = 0; k < NPARAM; k++) {
                ParamStat &st = R.fit.st[static_cast<std::size_t>(k)];
                if (!st.free || st.at_bound || k == VS) continue;
                st.sigma_delay = std::fabs(pp[static_cast<std::size_t>(k)] - pm[static_cast<std::size_t>(k)]) / (2.0 * h) * sd;
                st.sigma = std::sqrt(st.sigma * st.sigma + st.sigma_delay * st.sigma_delay);
                st.ci95 = tq * st.sigma;
                st.pct = (st.value != 0.0) ? 100.0 * st.sigma / std::fabs(st.value) : 1e300;
            }
        }
        if (1.96 * sd > 1.0) {
            char b[240];
            std::snprintf(b, sizeof b, "the delay of D5 after D4 is poorly pinned (%+.2f +- %.2f ticks at 95 %%): its share is "
                          "in the intervals; excite faster or give --delay", R.prep.delay, 1.96 * sd);
            R.warnings.push_back(b);
        }
    }
    // A log without the link angle (CSV) on an axis whose current depends on the position
    // (gravity): the model without gravity would take the load for inertia or friction.
    // (the ctrl family's EXT1 carries the controller's gravity: no such check)
    if (!o.ctrl && !log.have_q && all.pos.size() == all.n()) {
        const double g = position_effect(all, R.fit, R.prep.eps);
        if (g > 0.5 * std::max(R.fit.sigma, R.prep.noise_floor)) {
            char b[320];
            std::snprintf(b, sizeof b, "the current depends on the position (%.3g A RMS beyond the model, gravity?) and the "
                          "log carries no link angle (a CSV): fit a capture of the run (its init packet gives the kinematics)", g);
            R.why_not = b;
            return R;
        }
    }
    // Identifiable means every parameter of the model is pinned by this run: its interval
    // within half its value, or its whole effect on the current over the range the run saw
    // (|a|, |v| at most what was kept) within the noise. An axis that barely moved passes the
    // count of samples and fails here.
    {
        const double noise = std::max(R.fit.sigma, R.prep.noise_floor);
        for (int k : {JA, FV, FC, GA, GB}) {
            const ParamStat &st = R.fit.st[static_cast<std::size_t>(k)];
            if (!st.free) continue;
            if (k == JA && st.at_bound) {
                R.why_not = "Ja ran to its bound (no positive inertia explains the current): the model does not fit this axis";
                return R;
            }
            if (st.at_bound) continue;
            double reach = (k == JA) ? R.prep.amax : ((k == FV) ? R.prep.vmax : 1.0);
            if (o.ctrl && k == GA) reach = R.prep.e1max;   // k1 times EXT1
            if (o.ctrl && k == GB) reach = R.prep.inmax;   // k2 times the inertial term
            if (!R.fit.cov_ok || (st.ci95 > 0.5 * std::fabs(st.value) && st.ci95 * reach > noise)) {
                char b[320];
                std::snprintf(b, sizeof b, "%s is not pinned by this run: %.4g +- %.3g (95 %%) with |v| <= %.3g turn/s, |a| <= %.3g "
                              "turn/s^2: excite the axis more", param_name_of(R.fit.variant, k), st.value, st.ci95, R.prep.vmax, R.prep.amax);
                R.why_not = b;
                return R;
            }
        }
    }
    R.identifiable = true;
    for (int k = 0; k < NPARAM; k++) {
        const ParamStat &st = R.fit.st[static_cast<std::size_t>(k)];
        if (st.free && !st.at_bound && (!R.fit.cov_ok || st.pct > 50.0)) {
            char b[160];
            std::snprintf(b, sizeof b, "%s is poorly identified (sigma %.3g %%): excite the axis more", param_name_of(R.fit.variant, k), st.pct);
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
