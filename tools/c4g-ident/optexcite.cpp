// SPDX-License-Identifier: MIT
// The optimised excitation (optexcite.hpp).
#include "optexcite.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ident {

namespace {

constexpr double kTwoPi = 6.283185307179586476925;
constexpr int kGrid = 512;  // points per period where the search measures a joint's peaks

// Deterministic normal numbers from a seed (splitmix64 + Box-Muller): the same on every
// platform, unlike the standard library's distributions.
class Rng {
public:
    explicit Rng(uint64_t seed) : s_(seed * 0x9E3779B97F4A7C15ULL + 0x632BE59BD9B4E019ULL) {}
    double uniform()
    {
        uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        z ^= z >> 31;
        return (static_cast<double>(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    }
    double normal()
    {
        if (have_) {
            have_ = false;
            return spare_;
        }
        const double r = std::sqrt(-2.0 * std::log(uniform())), th = kTwoPi * uniform();
        spare_ = r * std::sin(th);
        have_ = true;
        return r * std::cos(th);
    }

private:
    uint64_t s_;
    double spare_ = 0.0;
    bool have_ = false;
};

// The search's tables: sin and cos of l w t at the grid points of one period.
struct Tables {
    int N = 0;
    std::vector<double> s, c;  // [m * N + (l - 1)]
    explicit Tables(int harmonics) : N(harmonics), s(static_cast<std::size_t>(kGrid * harmonics)), c(s.size())
    {
        for (int m = 0; m < kGrid; m++) {
            for (int l = 1; l <= N; l++) {
                const double x = kTwoPi * l * m / kGrid;
                s[static_cast<std::size_t>(m * N + l - 1)] = std::sin(x);
                c[static_cast<std::size_t>(m * N + l - 1)] = std::cos(x);
            }
        }
    }
};

// The free numbers of one joint (a_1..a_{N-1}, b_1..b_{N-1}) -> its series at rest at t = 0,
// scaled so its tightest limit is reached at p.use, the peaks measured on the grid.
void make_series(const OptProblem &p, unsigned j, const double *x, const Tables &T, Series *S)
{
    const int N = p.harmonics;
    S->w = kTwoPi * p.f0;
    S->a.assign(static_cast<std::size_t>(N), 0.0);
    S->b.assign(static_cast<std::size_t>(N), 0.0);
    double sa = 0.0, slb = 0.0;
    for (int l = 1; l < N; l++) {
        S->a[static_cast<std::size_t>(l - 1)] = x[l - 1];
        S->b[static_cast<std::size_t>(l - 1)] = x[N - 1 + l - 1];
        sa += x[l - 1];
        slb += l * x[N - 1 + l - 1];
    }
    S->a[static_cast<std::size_t>(N - 1)] = -sa;          // qd(0) = sum a_l = 0
    S->b[static_cast<std::size_t>(N - 1)] = -slb / N;     // qdd(0) = w sum l b_l = 0
    double omax = 0.0, omin = 0.0, vmax = 0.0, amax = 0.0;
    for (int m = 0; m < kGrid; m++) {
        double o = 0.0, v = 0.0, a = 0.0;
        for (int l = 1; l <= N; l++) {
            const double sn = T.s[static_cast<std::size_t>(m * N + l - 1)], cs = T.c[static_cast<std::size_t>(m * N + l - 1)];
            const double al = S->a[static_cast<std::size_t>(l - 1)], bl = S->b[static_cast<std::size_t>(l - 1)];
            o += (al * sn - bl * (cs - 1.0)) / (S->w * l);
            v += al * cs + bl * sn;
            a += S->w * l * (bl * cs - al * sn);
        }
        omax = std::max(omax, o);
        omin = std::min(omin, o);
        vmax = std::max(vmax, std::fabs(v));
        amax = std::max(amax, std::fabs(a));
    }
    const OptLimit &L = p.lim[j];
    double s = 1e300;
    if (omax > 0.0) s = std::min(s, (L.q_max - p.start[j]) / omax);
    if (omin < 0.0) s = std::min(s, (p.start[j] - L.q_min) / -omin);
    if (vmax > 0.0) s = std::min(s, L.qd_max / vmax);
    if (amax > 0.0) s = std::min(s, L.qdd_max / amax);
    if (!(s < 1e300)) s = 0.0;
    s *= p.use;
    double q0 = p.start[j];
    for (int l = 1; l <= N; l++) {
        S->a[static_cast<std::size_t>(l - 1)] *= s;
        S->b[static_cast<std::size_t>(l - 1)] *= s;
        q0 += S->b[static_cast<std::size_t>(l - 1)] / (S->w * l);
    }
    S->q0 = q0;
}

// Each joint's block of the search vector at the same length, so the step size means the
// same thing throughout (the scale is the limits' business).
void normalise(std::vector<double> *x, unsigned n, int per)
{
    for (unsigned j = 0; j < n; j++) {
        double s = 0.0;
        for (int k = 0; k < per; k++) s += (*x)[j * per + k] * (*x)[j * per + k];
        if (s <= 0.0) continue;
        const double f = std::sqrt(per / s);
        for (int k = 0; k < per; k++) (*x)[j * per + k] *= f;
    }
}

}  // namespace

// ---------------------------------------------------------------- model

bool OptModel::init(const OptProblem &p, std::string *err)
{
    p_ = &p;
    n_ = static_cast<int>(p.chain.n);
    if (n_ != static_cast<int>(kOptJoints)) {
        *err = "the kinematics has " + std::to_string(n_) + " joints; the excitation drives the arm's " +
               std::to_string(kOptJoints);
        return false;
    }
    // A = diag(1/kt) Kr^-T: joint torques -> motor currents
    Eigen::Matrix<double, kOptJoints, kOptJoints> kr;
    for (unsigned k = 0; k < kOptJoints; k++) {
        for (unsigned j = 0; j < kOptJoints; j++) kr(k, j) = p.kr[k][j];
    }
    Eigen::FullPivLU<Eigen::Matrix<double, kOptJoints, kOptJoints>> lu(kr);
    if (!lu.isInvertible()) {
        *err = "the transmission matrix Kr is singular";
        return false;
    }
    const Eigen::Matrix<double, kOptJoints, kOptJoints> kit = lu.inverse().transpose();
    for (unsigned k = 0; k < kOptJoints; k++) {
        if (!(p.kt[k] > 0.0)) {
            *err = "kt of joint " + std::to_string(k + 1) + " is not positive";
            return false;
        }
        for (unsigned j = 0; j < kOptJoints; j++) a_[k][j] = kit(k, j) / p.kt[k];
    }
    return rigid_base(p.chain, &base_, err);
}

std::string OptModel::column_name(int c) const
{
    const int nb = static_cast<int>(base_.base.size());
    if (c < nb) return base_.name[static_cast<std::size_t>(c)];
    static const char *const fr[3] = {"Fv", "Fc", "off"};
    return std::string(fr[(c - nb) % 3]) + std::to_string((c - nb) / 3 + 1);
}

bool OptModel::rows(const double *q, const double *qd, const double *qdd, std::vector<double> *out) const
{
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> W;
    if (!rigid_regressor(p_->chain, q, qd, qdd, &W)) return false;
    const int nb = static_cast<int>(base_.base.size());
    const int cols = columns();
    for (int k = 0; k < n_; k++) {
        const std::size_t r0 = out->size();
        out->resize(r0 + static_cast<std::size_t>(cols), 0.0);
        double *row = out->data() + r0;
        for (int c = 0; c < nb; c++) {
            const int fc = base_.base[static_cast<std::size_t>(c)];
            double s = 0.0;
            for (int j = 0; j < n_; j++) s += a_[k][j] * W(j, fc);
            row[c] = s;
        }
        double vm = 0.0;  // motor speed [turn/s]
        for (int j = 0; j < n_; j++) vm += p_->kr[k][j] * qd[j];
        vm /= kTwoPi;
        row[nb + 3 * k] = vm;
        row[nb + 3 * k + 1] = std::tanh(vm / p_->eps);
        row[nb + 3 * k + 2] = 1.0;
    }
    return true;
}

// ---------------------------------------------------------------- conditioning

bool conditioning(const OptModel &m, const JointPath &path, const std::vector<double> &times, int weakest,
                  Conditioning *out, std::string *err)
{
    std::vector<double> rows;
    for (double t : times) {
        double q[kOptJoints] = {}, qd[kOptJoints] = {}, qdd[kOptJoints] = {};
        path(t, q, qd, qdd);
        if (!m.rows(q, qd, qdd, &rows)) {
            *err = "the regressor failed at t = " + std::to_string(t) + " s (a non-finite state)";
            return false;
        }
    }
    const int cols = m.columns();
    const Eigen::Index R = static_cast<Eigen::Index>(rows.size() / static_cast<std::size_t>(cols));
    if (R < cols) {
        *err = "fewer regressor rows than base parameters";
        return false;
    }
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> W(rows.data(), R, cols);
    Eigen::BDCSVD<Eigen::MatrixXd> svd(W, Eigen::ComputeThinV);
    const Eigen::VectorXd &s = svd.singularValues();
    out->rows = static_cast<int>(R);
    out->cols = cols;
    out->sigma.assign(s.data(), s.data() + s.size());
    out->cond = (s(cols - 1) > 0.0) ? s(0) / s(cols - 1) : INFINITY;
    out->weakest.clear();
    for (int k = 0; k < weakest && k < cols; k++) {
        const int i = cols - 1 - k;
        Conditioning::Weak w;
        w.rel = s(0) > 0.0 ? s(i) / s(0) : 0.0;
        const Eigen::VectorXd v = svd.matrixV().col(i);
        // sign: the largest member positive, so the direction reads the same every run
        Eigen::Index big = 0;
        v.cwiseAbs().maxCoeff(&big);
        const double sg = v(big) < 0.0 ? -1.0 : 1.0;
        std::vector<std::pair<std::string, double>> mem;
        for (int c = 0; c < cols; c++) {
            if (std::fabs(v(c)) >= 0.2) mem.emplace_back(m.column_name(c), sg * v(c));
        }
        std::stable_sort(mem.begin(), mem.end(),
                         [](const std::pair<std::string, double> &x, const std::pair<std::string, double> &y) {
                             return std::fabs(x.second) > std::fabs(y.second);
                         });
        w.members = mem;
        out->weakest.push_back(w);
    }
    return true;
}

// ---------------------------------------------------------------- series and search

void Series::eval(double t, double *q, double *qd, double *qdd) const
{
    double sq = q0, sv = 0.0, sa = 0.0;
    for (std::size_t i = 0; i < a.size(); i++) {
        const double l = static_cast<double>(i + 1);
        const double x = w * l * t, sn = std::sin(x), cs = std::cos(x);
        sq += (a[i] * sn - b[i] * cs) / (w * l);
        sv += a[i] * cs + b[i] * sn;
        sa += w * l * (b[i] * cs - a[i] * sn);
    }
    *q = sq;
    *qd = sv;
    *qdd = sa;
}

void path_peaks(const JointPath &path, unsigned n, double T, double dt, double peak[kOptJoints][4])
{
    for (unsigned j = 0; j < kOptJoints; j++) {
        peak[j][0] = 1e300;
        peak[j][1] = -1e300;
        peak[j][2] = peak[j][3] = 0.0;
    }
    const long steps = std::lround(T / dt);
    for (long i = 0; i <= steps; i++) {
        double q[kOptJoints] = {}, qd[kOptJoints] = {}, qdd[kOptJoints] = {};
        path(static_cast<double>(i) * dt, q, qd, qdd);
        for (unsigned j = 0; j < n; j++) {
            peak[j][0] = std::min(peak[j][0], q[j]);
            peak[j][1] = std::max(peak[j][1], q[j]);
            peak[j][2] = std::max(peak[j][2], std::fabs(qd[j]));
            peak[j][3] = std::max(peak[j][3], std::fabs(qdd[j]));
        }
    }
}

bool optimize(const OptProblem &p, const OptModel &m, OptResult *out, std::string *err)
{
    const unsigned n = p.chain.n;
    const int N = p.harmonics;
    if (N < 2) {
        *err = "at least 2 harmonics: one cannot start and end at rest";
        return false;
    }
    const int per = 2 * (N - 1);
    const Tables T(N);
    const double Tp = 1.0 / p.f0;
    const int cols = m.columns();
    std::vector<Series> S(n);
    std::vector<double> rows;
    rows.reserve(static_cast<std::size_t>(p.samples) * n * static_cast<std::size_t>(cols));
    bool failed = false;
    // log of the condition number of the regressor over one period (a period repeated adds
    // no information), from the normal matrix's eigenvalues: cheap enough for the search
    auto cost = [&](const std::vector<double> &x) {
        for (unsigned j = 0; j < n; j++) make_series(p, j, x.data() + j * per, T, &S[j]);
        rows.clear();
        for (int s = 0; s < p.samples; s++) {
            const double t = Tp * s / p.samples;
            double q[kOptJoints] = {}, qd[kOptJoints] = {}, qdd[kOptJoints] = {};
            for (unsigned j = 0; j < n; j++) S[j].eval(t, &q[j], &qd[j], &qdd[j]);
            if (!m.rows(q, qd, qdd, &rows)) {
                failed = true;
                return 1e300;
            }
        }
        const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> W(
            rows.data(), static_cast<Eigen::Index>(rows.size() / static_cast<std::size_t>(cols)), cols);
        const Eigen::MatrixXd G = W.transpose() * W;
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(G, Eigen::EigenvaluesOnly);
        const double lmax = es.eigenvalues()(cols - 1);
        const double lmin = std::max(es.eigenvalues()(0), lmax * 1e-30);
        if (!(lmax > 0.0)) return 1e300;
        return 0.5 * std::log(lmax / lmin);
    };
    Rng rng(p.seed);
    const int restarts = std::max(1, p.restarts);
    const int each = std::max(1, p.evals / restarts);
    std::vector<double> best;
    double fbest = 1e300;
    int evals = 0;
    for (int r = 0; r < restarts; r++) {
        std::vector<double> x(static_cast<std::size_t>(n) * per);
        for (double &v : x) v = rng.normal();
        normalise(&x, n, per);
        double f = cost(x), sigma = 0.5;
        evals++;
        for (int e = 1; e < each; e++) {
            std::vector<double> y(x);
            for (double &v : y) v += sigma * rng.normal();
            normalise(&y, n, per);
            const double fy = cost(y);
            evals++;
            // one-fifth success rule: the step grows after a success, shrinks slowly otherwise
            if (fy < f) {
                x.swap(y);
                f = fy;
                sigma = std::min(2.0, sigma * std::exp(1.0 / 3.0));
            } else {
                sigma = std::max(1e-4, sigma * std::exp(-1.0 / 12.0));
            }
        }
        if (f < fbest) {
            fbest = f;
            best = x;
        }
    }
    if (failed) {
        *err = "the regressor failed during the search (a non-finite state)";
        return false;
    }
    for (unsigned j = 0; j < n; j++) make_series(p, j, best.data() + j * per, T, &S[j]);
    // The grid may miss a peak between its points: measure again finely and scale each joint
    // so its tightest limit is met at p.use exactly.
    const JointPath one = [&S, n](double t, double *q, double *qd, double *qdd) {
        for (unsigned j = 0; j < n; j++) S[j].eval(t, &q[j], &qd[j], &qdd[j]);
    };
    double pk[kOptJoints][4];
    path_peaks(one, n, Tp, Tp / 20000.0, pk);
    for (unsigned j = 0; j < n; j++) {
        const OptLimit &L = p.lim[j];
        double use = 0.0;  // largest share of a limit used
        use = std::max(use, (pk[j][1] - p.start[j]) / (L.q_max - p.start[j]));
        use = std::max(use, (p.start[j] - pk[j][0]) / (p.start[j] - L.q_min));
        use = std::max(use, pk[j][2] / L.qd_max);
        use = std::max(use, pk[j][3] / L.qdd_max);
        if (use > p.use) {
            const double k = p.use / use;
            Series &s = S[j];
            s.q0 = p.start[j];
            for (std::size_t i = 0; i < s.a.size(); i++) {
                s.a[i] *= k;
                s.b[i] *= k;
                s.q0 += s.b[i] / (s.w * static_cast<double>(i + 1));
            }
        }
    }
    path_peaks(one, n, Tp, Tp / 20000.0, out->peak);
    out->joint = S;
    out->objective = std::exp(fbest);
    out->evals = evals;
    return true;
}

}  // namespace ident
