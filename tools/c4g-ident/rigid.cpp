// SPDX-License-Identifier: MIT
// The rigid family's fit (rigid.hpp).
#include "rigid.hpp"

#include <Eigen/Dense>
#include <ceres/ceres.h>

#include <algorithm>
#include <atomic>
#include <thread>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ident {

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr int kBlocks = 40;          // spans of ticks for the block-robust covariance
constexpr std::size_t kStartTicks = 6000;  // ticks the robust start is fitted on
constexpr int kBuf = 256;            // rows per rank update

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Weight of a residual r at scale s under the loss (IRLS: psi(r)/r).
double robust_w(Loss loss, double k, double r, double s)
{
    const double u = std::fabs(r) / std::max(s, 1e-300);
    if (loss == LOSS_HUBER) return (u <= k) ? 1.0 : k / u;
    if (loss == LOSS_CAUCHY) return 1.0 / (1.0 + (u / k) * (u / k));
    return 1.0;
}

// Solve the normal equations A x = b, columns scaled to unit diagonal; false when singular.
bool solve_normal(const Eigen::MatrixXd &A, const Eigen::VectorXd &b, Eigen::VectorXd *x, double *cond = nullptr)
{
    const Eigen::VectorXd d = A.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd S = d.asDiagonal() * A * d.asDiagonal();
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-13 * ldlt.vectorD().maxCoeff())) return false;
    *x = d.asDiagonal() * ldlt.solve(d.asDiagonal() * b);
    if (cond != nullptr) {
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
        *cond = std::sqrt(es.eigenvalues().maxCoeff() / std::max(es.eigenvalues().minCoeff(), 1e-300));
    }
    return x->allFinite();
}

// Walks the axes' logs tick by tick: the ticks every axis logged, each axis' index there.
struct Joiner {
    std::vector<const AxisLog *> L;
    std::vector<std::size_t> at;
    std::size_t k0 = 0;  // index into L[0]
    // from index @p start of L[0] on
    explicit Joiner(const std::vector<const AxisLog *> &logs, std::size_t start = 0) : L(logs), at(logs.size(), 0), k0(start)
    {
        if (start == 0 || start >= L[0]->tick.size()) return;
        for (std::size_t a = 1; a < L.size(); a++) {
            at[a] = static_cast<std::size_t>(std::lower_bound(L[a]->tick.begin(), L[a]->tick.end(), L[0]->tick[start]) -
                                             L[a]->tick.begin());
        }
    }
    // the next tick of L[0] every other axis has too; false at the end
    bool next(std::vector<std::size_t> *idx)
    {
        for (; k0 < L[0]->tick.size(); k0++) {
            const int64_t t = L[0]->tick[k0];
            bool all = true;
            for (std::size_t a = 1; a < L.size(); a++) {
                while (at[a] < L[a]->tick.size() && L[a]->tick[at[a]] < t) at[a]++;
                all = all && at[a] < L[a]->tick.size() && L[a]->tick[at[a]] == t;
            }
            if (all) {
                (*idx)[0] = k0;
                for (std::size_t a = 1; a < L.size(); a++) (*idx)[a] = at[a];
                k0++;
                return true;
            }
        }
        return false;
    }
};

// What one pass over a run needs: its logs in joint order and their tracks.
struct Run {
    std::vector<const AxisLog *> L;
    std::vector<Track> tr;
};

// The model's fixed parts: chain, current map, base columns, friction eps.
struct Model {
    int n = 0, nb = 0, P = 0;
    c4g_dyn_chain_t ch{};
    double kinv[6][6] = {};   // joint rad per motor rad
    double m[6][6] = {};      // (Kr^-T)_kj / kt_k: joint torque -> motor current
    std::vector<int> base;
    std::vector<double> eps;
};

// The state of joint set at one tick from the tracks; false when a filter window is cut.
bool state(const Model &M, const Run &R, const std::vector<std::size_t> &idx, double *q, double *qd, double *qdd,
           double *vm)
{
    double am[6];
    for (int a = 0; a < M.n; a++) {
        const Track &T = R.tr[static_cast<std::size_t>(a)];
        const std::size_t k = idx[static_cast<std::size_t>(a)];
        if (!T.ok[k]) return false;
        q[a] = T.q[k];
        vm[a] = static_cast<double>(T.v[k]);
        am[a] = static_cast<double>(T.a[k]);
    }
    for (int j = 0; j < M.n; j++) {
        double v = 0.0, ac = 0.0;
        for (int k = 0; k < M.n; k++) {
            v += M.kinv[j][k] * kTwoPi * vm[k];
            ac += M.kinv[j][k] * kTwoPi * am[k];
        }
        qd[j] = v;
        qdd[j] = ac;
    }
    return true;
}

// The regressor rows of every motor at one state: phi (n x P).
bool rows(const Model &M, const double *q, const double *qd, const double *qdd, const double *vm, RowMat *W, RowMat *phi)
{
    if (!rigid_regressor(M.ch, q, qd, qdd, W)) return false;
    phi->setZero(M.n, M.P);
    for (int k = 0; k < M.n; k++) {
        for (int c = 0; c < M.nb; c++) {
            double s = 0.0;
            for (int j = 0; j < M.n; j++) s += M.m[k][j] * (*W)(j, M.base[static_cast<std::size_t>(c)]);
            (*phi)(k, c) = s;
        }
        const int f = M.nb + 3 * k;
        (*phi)(k, f) = vm[k];
        (*phi)(k, f + 1) = std::tanh(vm[k] / M.eps[static_cast<std::size_t>(k)]);
        (*phi)(k, f + 2) = 1.0;
    }
    return true;
}

// Normal equations of one span of ticks, filled through a buffer of rows.
struct Block {
    Eigen::MatrixXd A;   // lower triangle
    Eigen::VectorXd b;
    double yy = 0.0;     // sum of the weighted squared currents
    std::size_t rows = 0;
};

// Sums per group (a span of ticks, or a motor), each filled through its own buffer of rows
// (kBuf rows per rank update: the products run as matrix products).
struct Accum {
    int P = 0;
    std::vector<Block> blk;
    std::vector<Eigen::MatrixXd> U;   // per group: P x kBuf weighted rows, column-wise
    std::vector<Eigen::VectorXd> y;   // per group: weighted currents
    std::vector<int> fill;
    Accum(int p, int g) : P(p), blk(static_cast<std::size_t>(g)), fill(static_cast<std::size_t>(g), 0)
    {
        for (Block &B : blk) {
            B.A = Eigen::MatrixXd::Zero(p, p);
            B.b = Eigen::VectorXd::Zero(p);
        }
        U.resize(static_cast<std::size_t>(g));
        y.resize(static_cast<std::size_t>(g));
    }
    void flush(std::size_t g)
    {
        const int f = fill[g];
        if (f == 0) return;
        Block &B = blk[g];
        B.A.selfadjointView<Eigen::Lower>().rankUpdate(U[g].leftCols(f));
        B.b += U[g].leftCols(f) * y[g].head(f);
        B.yy += y[g].head(f).squaredNorm();
        B.rows += static_cast<std::size_t>(f);
        fill[g] = 0;
    }
    void flush_all()
    {
        for (std::size_t g = 0; g < blk.size(); g++) flush(g);
    }
    void flush() { flush_all(); }
    void add(int gi, const double *phi, double i, double w)
    {
        const std::size_t g = static_cast<std::size_t>(gi);
        if (U[g].size() == 0) {
            U[g].resize(P, kBuf);
            y[g].resize(kBuf);
        }
        if (fill[g] == kBuf) flush(g);
        const double s = std::sqrt(w);
        const int f = fill[g];
        for (int c = 0; c < P; c++) U[g](c, f) = s * phi[c];
        y[g](f) = s * i;
        fill[g] = f + 1;
    }
    void merge(const Accum &o)
    {
        for (std::size_t g = 0; g < blk.size(); g++) {
            blk[g].A += o.blk[g].A;
            blk[g].b += o.blk[g].b;
            blk[g].yy += o.blk[g].yy;
            blk[g].rows += o.blk[g].rows;
        }
    }
    // sum of groups [g0, g1), the lower triangle mirrored
    void sum(int g0, int g1, Eigen::MatrixXd *A, Eigen::VectorXd *b) const
    {
        *A = Eigen::MatrixXd::Zero(P, P);
        *b = Eigen::VectorXd::Zero(P);
        for (int g = g0; g < g1; g++) {
            *A += blk[static_cast<std::size_t>(g)].A;
            *b += blk[static_cast<std::size_t>(g)].b;
        }
        *A = A->selfadjointView<Eigen::Lower>();
    }
    // sum over group g of (y - phi x)^2 (unit weights): yy - 2 x.b + x'Ax
    double sse(std::size_t g, const Eigen::VectorXd &x) const
    {
        const Block &B = blk[g];
        return std::max(0.0, B.yy - 2.0 * x.dot(B.b) + x.dot(B.A.selfadjointView<Eigen::Lower>() * x));
    }
};

const char *const kFricName[3] = {"Fv", "Fc", "off"};
const char *const kFricUnit[3] = {"A/(turn/s)", "A", "A"};

// Unit of base parameter c: that of its base member.
std::string base_unit(int n, int member)
{
    if (member >= kRigidPerLink * n) return "kg m^2";
    const int p = member % kRigidPerLink;
    return p == 0 ? "kg" : (p < 4 ? "kg m" : "kg m^2");
}

// ---- the physically consistent fit: each link's 10 parameters from a log-Cholesky factor of
// its pseudo-inertia J = [[Sigma, h], [h^T, m]] (Sigma = tr(I)/2 E - I about the origin):
// J = U U^T, U = e^alpha [[e^d1, s12, s13, t1], [0, e^d2, s23, t2], [0, 0, e^d3, t3], [0, 0, 0, 1]],
// positive definite for every value of the 10 numbers (mass positive, the inertia obeying
// the triangle inequalities); each rotor inertia ia = e^g. The cost is the weighted least
// squares of the fit written through its normal equations (|L^T x - L^-1 b|^2, A = L L^T):
// it does not grow with the samples.
constexpr int kPsiLink = 10;

template <typename T>
void link_from_psi(const T *z, T *pi)
{
    using std::exp;
    const T ea = exp(z[0]);
    T U[4][4] = {{exp(z[1]), z[4], z[6], z[7]}, {T(0), exp(z[2]), z[5], z[8]}, {T(0), T(0), exp(z[3]), z[9]},
                 {T(0), T(0), T(0), T(1)}};
    T J[4][4];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            T v(0);
            for (int k = 0; k < 4; k++) v += U[r][k] * U[c][k];
            J[r][c] = ea * ea * v;
        }
    const T tr = J[0][0] + J[1][1] + J[2][2];
    pi[0] = J[3][3];
    pi[1] = J[0][3];
    pi[2] = J[1][3];
    pi[3] = J[2][3];
    pi[4] = tr - J[0][0];   // Ixx = Syy + Szz
    pi[5] = -J[0][1];
    pi[6] = -J[0][2];
    pi[7] = tr - J[1][1];
    pi[8] = -J[1][2];
    pi[9] = tr - J[2][2];
}

struct ConsistentCost {
    int n, P, nb;
    const Eigen::MatrixXd *Lt;     // L^T
    const Eigen::VectorXd *c;      // L^-1 b
    const Eigen::MatrixXd *Pm;     // beta = P theta
    const Eigen::VectorXd *psi0;   // the start, weakly held (directions no data sees)
    double reg;
    template <typename T>
    bool operator()(T const *const *par, T *res) const
    {
        const T *psi = par[0], *fr = par[1];
        const int nf = (kPsiLink + 1) * n;
        std::vector<T> th(static_cast<std::size_t>(nf));
        for (int j = 0; j < n; j++) link_from_psi(psi + kPsiLink * j, &th[static_cast<std::size_t>(kPsiLink * j)]);
        for (int j = 0; j < n; j++) th[static_cast<std::size_t>(kPsiLink * n + j)] = exp(psi[kPsiLink * n + j]);
        std::vector<T> x(static_cast<std::size_t>(P));
        for (int r = 0; r < nb; r++) {
            T v(0);
            for (int k = 0; k < nf; k++) {
                const double pk = (*Pm)(r, k);
                if (pk != 0.0) v += pk * th[static_cast<std::size_t>(k)];
            }
            x[static_cast<std::size_t>(r)] = v;
        }
        for (int k = nb; k < P; k++) x[static_cast<std::size_t>(k)] = fr[k - nb];
        for (int r = 0; r < P; r++) {
            T v(-(*c)(r));
            for (int k = r; k < P; k++) v += (*Lt)(r, k) * x[static_cast<std::size_t>(k)];
            res[r] = v;
        }
        for (int k = 0; k < nf; k++) res[P + k] = reg * (psi[k] - (*psi0)(k));
        return true;
    }
};

// The consistent solution (x: base parameters and friction as the LS fit has them, theta:
// its full vector) of the normal equations A x = b, from @p xls's friction. false: no
// convergence (or a Cholesky failure).
bool consistent_fit(const RigidBase &B, int n, int nb, const Eigen::MatrixXd &A, const Eigen::VectorXd &b,
                    const Eigen::VectorXd &xls, Eigen::VectorXd *x, Eigen::VectorXd *theta, Eigen::VectorXd *psi_io,
                    std::string *note)
{
    const int P = static_cast<int>(A.rows());
    const Eigen::LLT<Eigen::MatrixXd> llt(A);
    if (llt.info() != Eigen::Success) return false;
    const Eigen::MatrixXd Lt = llt.matrixU();
    const Eigen::VectorXd c = llt.matrixL().solve(b);
    const int nf = (kPsiLink + 1) * n;
    // start: each link 10 kg at its origin with 0.5 kg m^2 about each axis, rotors 0.1 kg m^2
    // (an industrial arm's order of magnitude: the log-Cholesky steps are relative)
    Eigen::VectorXd psi0 = Eigen::VectorXd::Zero(nf);
    for (int j = 0; j < n; j++) {
        // J = 10 diag(0.025, 0.025, 0.025, 1): e^alpha = sqrt(10), e^d = sqrt(0.025)
        psi0(kPsiLink * j) = 0.5 * std::log(10.0);
        for (int k = 1; k <= 3; k++) psi0(kPsiLink * j + k) = 0.5 * std::log(0.025);
        psi0(kPsiLink * n + j) = std::log(0.1);
    }
    Eigen::VectorXd psi = (psi_io->size() == nf) ? *psi_io : psi0;
    Eigen::VectorXd fr = xls.tail(P - nb);
    auto *cost = new ceres::DynamicAutoDiffCostFunction<ConsistentCost, 16>(
        new ConsistentCost{n, P, nb, &Lt, &c, &B.P, &psi0, 1e-4});
    cost->AddParameterBlock(nf);
    cost->AddParameterBlock(P - nb);
    cost->SetNumResiduals(P + nf);
    ceres::Problem pb;
    pb.AddResidualBlock(cost, nullptr, psi.data(), fr.data());
    ceres::Solver::Options so;
    so.max_num_iterations = 3000;
    so.linear_solver_type = ceres::DENSE_QR;
    so.use_nonmonotonic_steps = true;
    so.max_consecutive_nonmonotonic_steps = 10;
    so.function_tolerance = 1e-12;
    so.gradient_tolerance = 1e-12;
    so.parameter_tolerance = 1e-12;
    ceres::Solver::Summary sum;
    ceres::Solve(so, &pb, &sum);
    if (sum.termination_type == ceres::FAILURE) return false;
    if (sum.termination_type == ceres::NO_CONVERGENCE) {
        // the directions no data sees keep it walking: the fit is what it reached
        char m[160];
        std::snprintf(m, sizeof m, "the consistent fit stopped after %d iterations short of the solver's tolerances",
                      static_cast<int>(sum.iterations.size()) - 1);
        *note = m;
    }
    *psi_io = psi;
    theta->resize(nf);
    double pi[kPsiLink];
    for (int j = 0; j < n; j++) {
        link_from_psi(psi.data() + kPsiLink * j, pi);
        for (int k = 0; k < kPsiLink; k++) (*theta)(kPsiLink * j + k) = pi[k];
        (*theta)(kPsiLink * n + j) = std::exp(psi(kPsiLink * n + j));
    }
    x->resize(P);
    x->head(nb) = B.P * *theta;
    x->tail(P - nb) = fr;
    return x->allFinite();
}

}  // namespace

bool rigid_kr(const c4g_kin_t &kin, unsigned n, double kr[6][6], std::string *err)
{
    // column by column through the library's velocity conversion (it is linear): a unit
    // joint velocity gives Kr's column, as the arm plant builds it
    const double T = kin.period_s;
    for (unsigned j = 0; j < n; j++) {
        double e[6] = {0, 0, 0, 0, 0, 0}, y[6] = {0, 0, 0, 0, 0, 0};
        e[j] = 1.0;
        if (c4g_kin_link_vel_to_motor(&kin, e, n, y) != C4G_OK || !(T > 0.0)) {
            *err = "the init packet's transmission of axis " + std::to_string(j + 1) + " is unusable";
            return false;
        }
        for (unsigned i = 0; i < n; i++) kr[i][j] = y[i] * kTwoPi / T;
    }
    return true;
}

RigidResult identify_rigid(std::vector<AxisLog> &logs, const c4g_kin_t &kin, const c4gh_kinfile_t &kf,
                           std::vector<AxisLog> *val, const Options &o, bool consistent)
{
    const auto t0 = std::chrono::steady_clock::now();
    RigidResult R;
    const int n = static_cast<int>(kf.n);
    R.n = n;
    Model M;
    M.n = n;
    M.ch = kf.chain;
    // the logs in joint order
    Run run;
    for (int j = 0; j < n; j++) {
        const AxisLog *p = nullptr;
        for (const AxisLog &L : logs) {
            if (L.axis == static_cast<unsigned>(j + 1)) p = &L;
        }
        if (p == nullptr) {
            R.why_not = "axis " + std::to_string(j + 1) + " of the kinematics file is not in the log";
            return R;
        }
        if (!p->have_q) {
            R.why_not = "axis " + std::to_string(j + 1) + " has no link angle (the capture's init packet gives it)";
            return R;
        }
        run.L.push_back(p);
    }
    R.arm = run.L[0]->arm;
    R.period = run.L[0]->period;
    R.ticks = run.L[0]->tick.size();
    if (!rigid_kr(kin, static_cast<unsigned>(n), R.kr, &R.why_not)) return R;
    {
        Eigen::MatrixXd K(n, n);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) K(i, j) = R.kr[i][j];
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
        if (!lu.isInvertible()) {
            R.why_not = "the init packet's transmission matrix Kr is singular";
            return R;
        }
        const Eigen::MatrixXd Ki = lu.inverse();
        for (int j = 0; j < n; j++)
            for (int k = 0; k < n; k++) {
                M.kinv[j][k] = Ki(j, k);
                M.m[k][j] = Ki(j, k) / kf.j[k].kt;  // (Kr^-T)_kj / kt_k
            }
    }
    if (!rigid_base(M.ch, &R.base, &R.why_not)) return R;
    M.base = R.base.base;
    M.nb = static_cast<int>(M.base.size());
    M.P = M.nb + 3 * n;
    if (R.ticks < static_cast<std::size_t>(4 * o.sg_half + 10)) {
        R.why_not = "too few ticks (" + std::to_string(R.ticks) + ")";
        return R;
    }
    // Each axis: eps, noise floor, its own delay; then one delay for all (the median of the
    // axes that pin theirs): the state of every joint is needed at each motor's D5 time.
    R.axes.resize(static_cast<std::size_t>(n));
    {
        std::vector<double> d;
        // the axes' delay searches are independent: o.threads of them at once
        std::atomic<int> next(0);
        auto work = [&]() {
            for (int a = next++; a < n; a = next++) {
                RigidAxis &A = R.axes[static_cast<std::size_t>(a)];
                A.axis = static_cast<unsigned>(a + 1);
                A.prep = prepare_axis(*run.L[static_cast<std::size_t>(a)], o);
            }
        };
        std::vector<std::thread> pool;
        for (int w = 1; w < std::min(o.threads, n); w++) pool.emplace_back(work);
        work();
        for (std::thread &t : pool) t.join();
        for (const RigidAxis &A : R.axes) {
            if (!A.prep.delay_at_bound) d.push_back(A.prep.delay);
        }
        if (!o.delay_auto) {
            R.delay = o.delay;
        } else if (d.empty()) {
            R.why_not = "no axis pins the delay of D5 after D4 (each ran to the end of its search): excite faster or give --delay";
            return R;
        } else {
            std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
            R.delay = d[d.size() / 2];
        }
    }
    run.tr.resize(static_cast<std::size_t>(n));
    for (int a = 0; a < n; a++) {
        RigidAxis &A = R.axes[static_cast<std::size_t>(a)];
        M.eps.push_back(A.prep.eps);
        track(*run.L[static_cast<std::size_t>(a)], o, R.delay, &A.prep, &run.tr[static_cast<std::size_t>(a)]);
        if (A.prep.kept < 200) {
            char b[200];
            std::snprintf(b, sizeof b, "axis %d hardly moved: %llu usable ticks above the standstill speed %.3g turn/s", a + 1,
                          static_cast<unsigned long long>(A.prep.kept), 5.0 * A.prep.eps);
            R.why_not = b;
            return R;
        }
    }
    const std::size_t N = R.ticks;
    const std::size_t n_train = (val != nullptr) ? N : static_cast<std::size_t>(std::floor(static_cast<double>(N) * (1.0 - o.holdout)));
    const int g_train = (val != nullptr) ? kBlocks : static_cast<int>(std::lround(kBlocks * (1.0 - o.holdout)));
    auto block_of = [&](std::size_t k) {
        if (k < n_train) return static_cast<int>(k * static_cast<std::size_t>(g_train) / std::max<std::size_t>(1, n_train));
        return g_train + static_cast<int>((k - n_train) * static_cast<std::size_t>(kBlocks - g_train) / std::max<std::size_t>(1, N - n_train));
    };
    double q[7], qd[7], qdd[7], vm[7];
    RowMat W, phi;
    std::vector<std::size_t> idx(static_cast<std::size_t>(n));
    // 1. A robust start on at most kStartTicks ticks spread over the training part: IRLS
    //    with each motor's own scale (their noise differs), rows kept in memory.
    Eigen::VectorXd theta;
    std::vector<double> sig(static_cast<std::size_t>(n), 0.0);
    {
        const std::size_t stride = std::max<std::size_t>(1, n_train / kStartTicks);
        std::vector<double> X, Y;
        std::vector<int> ax;
        X.reserve(static_cast<std::size_t>(M.P) * static_cast<std::size_t>(n) * (kStartTicks + 16));
        Y.reserve(static_cast<std::size_t>(n) * (kStartTicks + 16));
        Joiner J(run.L);
        while (J.next(&idx)) {
            if (idx[0] >= n_train) break;
            if (idx[0] % stride != 0) continue;
            if (!state(M, run, idx, q, qd, qdd, vm) || !rows(M, q, qd, qdd, vm, &W, &phi)) continue;
            for (int k = 0; k < n; k++) {
                const std::size_t at = idx[static_cast<std::size_t>(k)];
                if (!run.tr[static_cast<std::size_t>(k)].use[at]) continue;
                X.insert(X.end(), phi.row(k).data(), phi.row(k).data() + M.P);
                Y.push_back(static_cast<double>(run.L[static_cast<std::size_t>(k)]->d5[at]));
                ax.push_back(k);
            }
        }
        const Eigen::Map<const RowMat> Xm(X.data(), static_cast<Eigen::Index>(Y.size()), M.P);
        const Eigen::Map<const Eigen::VectorXd> Ym(Y.data(), static_cast<Eigen::Index>(Y.size()));
        if (Y.size() < static_cast<std::size_t>(4 * M.P)) {
            R.why_not = "too few usable ticks for " + std::to_string(M.P) + " parameters (" + std::to_string(Y.size()) + " currents)";
            return R;
        }
        for (int k = 0; k < n; k++) {
            const double f = R.axes[static_cast<std::size_t>(k)].prep.noise_floor;
            sig[static_cast<std::size_t>(k)] = (f > 0.0) ? f : 1.0;
        }
        Eigen::VectorXd w = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(Y.size()));
        for (int it = 0; it < 4; it++) {
            for (std::size_t r = 0; r < Y.size(); r++) {
                const double s = sig[static_cast<std::size_t>(ax[r])];
                w(static_cast<Eigen::Index>(r)) = (it == 0) ? 1.0 / (s * s) : w(static_cast<Eigen::Index>(r));
            }
            const Eigen::VectorXd sw = w.cwiseSqrt();
            const Eigen::MatrixXd Xs = sw.asDiagonal() * Xm;
            Eigen::MatrixXd A = Eigen::MatrixXd::Zero(M.P, M.P);
            A.selfadjointView<Eigen::Lower>().rankUpdate(Xs.transpose());
            A = A.selfadjointView<Eigen::Lower>();
            const Eigen::VectorXd b = Xs.transpose() * (sw.asDiagonal() * Ym);
            if (!solve_normal(A, b, &theta)) {
                R.why_not = "the regressor is singular on this run: some base parameter has no effect on the currents logged "
                            "(excite every axis)";
                return R;
            }
            const Eigen::VectorXd res = Ym - Xm * theta;
            for (int k = 0; k < n; k++) {
                std::vector<double> rk;
                for (std::size_t r = 0; r < Y.size(); r++) {
                    if (ax[r] == k) rk.push_back(res(static_cast<Eigen::Index>(r)));
                }
                sig[static_cast<std::size_t>(k)] = std::max(1.4826 * median_abs(rk), 1e-9);
            }
            for (std::size_t r = 0; r < Y.size(); r++) {
                const double s = sig[static_cast<std::size_t>(ax[r])];
                w(static_cast<Eigen::Index>(r)) = robust_w(o.loss, o.loss_k, res(static_cast<Eigen::Index>(r)), s) / (s * s);
            }
        }
    }
    // 2. Every tick once: the robust weights at the start's solution (a one-step M-estimate
    //    from a consistent start), accumulated per span of ticks. Nothing per tick is kept.
    //    The held-out ticks also go, unweighted, into one sum per motor (all of them, and
    //    those within 4 sigma of the start, which saw none of them): their residual at any
    //    solution then follows from the quadratic form, with no second pass.
    //    o.threads workers take equal runs of spans, each with its own sums.
    struct Part {
        Accum acc, hold_all, hold_in;  // spans; held-out sums per motor (a group each)
        Eigen::MatrixXd reach;
        std::vector<std::size_t> rows, n_all, n_in;
        std::vector<double> peak;
        double q_min[C4G_DYN_MAX_LINKS], q_max[C4G_DYN_MAX_LINKS], qd_max[C4G_DYN_MAX_LINKS] = {},
            qdd_max[C4G_DYN_MAX_LINKS] = {};
        std::size_t states = 0;
        Part(int P, int n)
            : acc(P, kBlocks), hold_all(P, n), hold_in(P, n), reach(Eigen::MatrixXd::Zero(P, n)),
              rows(static_cast<std::size_t>(n), 0), n_all(static_cast<std::size_t>(n), 0), n_in(static_cast<std::size_t>(n), 0),
              peak(static_cast<std::size_t>(n), 0.0)
        {
            for (int j = 0; j < static_cast<int>(C4G_DYN_MAX_LINKS); j++) {
                q_min[j] = 1e300;
                q_max[j] = -1e300;
            }
        }
    };
    const int workers = std::max(1, std::min(o.threads, 8));
    std::vector<Part> parts;
    for (int w = 0; w < workers; w++) parts.emplace_back(M.P, n);
    auto pass = [&](int w) {
        Part &pt = parts[static_cast<std::size_t>(w)];
        // this worker's ticks: spans [w G / workers, (w + 1) G / workers)
        const int g0 = w * kBlocks / workers, g1 = (w + 1) * kBlocks / workers;
        std::size_t k0 = 0;
        while (k0 < N && block_of(k0) < g0) k0 += 64;
        while (k0 > 0 && block_of(k0 - 1) >= g0) k0--;
        Joiner J(run.L, k0);
        std::vector<std::size_t> ix(static_cast<std::size_t>(n));
        double sq[7], sqd[7], sqdd[7], svm[7];
        RowMat sW, sphi;
        while (J.next(&ix)) {
            const int g = block_of(ix[0]);
            if (g >= g1) break;
            if (!state(M, run, ix, sq, sqd, sqdd, svm) || !rows(M, sq, sqd, sqdd, svm, &sW, &sphi)) continue;
            pt.states++;
            const bool held = val == nullptr && ix[0] >= n_train;
            bool any = false;
            for (int k = 0; k < n; k++) {
                const std::size_t at = ix[static_cast<std::size_t>(k)], kk = static_cast<std::size_t>(k);
                if (!run.tr[kk].use[at]) continue;
                any = true;
                const double i = static_cast<double>(run.L[kk]->d5[at]);
                const double r = i - sphi.row(k).dot(theta);
                const double s = sig[kk];
                pt.acc.add(g, sphi.row(k).data(), i, robust_w(o.loss, o.loss_k, r, s) / (s * s));
                pt.reach.col(k) = pt.reach.col(k).cwiseMax(sphi.row(k).transpose().cwiseAbs());
                pt.rows[kk]++;
                if (held) {
                    pt.hold_all.add(k, sphi.row(k).data(), i, 1.0);
                    pt.n_all[kk]++;
                    pt.peak[kk] = std::max(pt.peak[kk], std::fabs(i));
                    if (std::fabs(r) <= 4.0 * s) {
                        pt.hold_in.add(k, sphi.row(k).data(), i, 1.0);
                        pt.n_in[kk]++;
                    }
                }
            }
            if (!any) continue;
            for (int j = 0; j < n; j++) {
                pt.q_min[j] = std::min(pt.q_min[j], sq[j]);
                pt.q_max[j] = std::max(pt.q_max[j], sq[j]);
                pt.qd_max[j] = std::max(pt.qd_max[j], std::fabs(sqd[j]));
                pt.qdd_max[j] = std::max(pt.qdd_max[j], std::fabs(sqdd[j]));
            }
        }
        pt.acc.flush();
        pt.hold_all.flush_all();
        pt.hold_in.flush_all();
    };
    {
        std::vector<std::thread> pool;
        for (int w = 1; w < workers; w++) pool.emplace_back(pass, w);
        pass(0);
        for (std::thread &t : pool) t.join();
    }
    // the workers' sums into the first one's
    Accum &acc = parts[0].acc;
    Eigen::MatrixXd reach = parts[0].reach;
    std::vector<std::size_t> n_all(static_cast<std::size_t>(n), 0), n_in(static_cast<std::size_t>(n), 0);
    std::vector<double> peak(static_cast<std::size_t>(n), 0.0);
    for (int j = 0; j < n; j++) {
        R.q_min[j] = 1e300;
        R.q_max[j] = -1e300;
    }
    for (std::size_t w = 0; w < parts.size(); w++) {
        Part &pt = parts[w];
        if (w > 0) {
            acc.merge(pt.acc);
            parts[0].hold_all.merge(pt.hold_all);
            parts[0].hold_in.merge(pt.hold_in);
            reach = reach.cwiseMax(pt.reach);
        }
        R.states += pt.states;
        for (int j = 0; j < n; j++) {
            const std::size_t jj = static_cast<std::size_t>(j);
            R.q_min[j] = std::min(R.q_min[j], pt.q_min[j]);
            R.q_max[j] = std::max(R.q_max[j], pt.q_max[j]);
            R.qd_max[j] = std::max(R.qd_max[j], pt.qd_max[j]);
            R.qdd_max[j] = std::max(R.qdd_max[j], pt.qdd_max[j]);
            R.axes[jj].rows += pt.rows[jj];
            n_all[jj] += pt.n_all[jj];
            n_in[jj] += pt.n_in[jj];
            peak[jj] = std::max(peak[jj], pt.peak[jj]);
        }
    }
    Eigen::MatrixXd A;
    Eigen::VectorXd b, th_all, th_train;
    acc.sum(0, kBlocks, &A, &b);
    if (!solve_normal(A, b, &th_all, &R.cond)) {
        R.why_not = "the regressor is singular on this run: some base parameter has no effect on the currents logged (excite every axis)";
        return R;
    }
    th_train = th_all;
    if (val == nullptr) {
        Eigen::MatrixXd At;
        Eigen::VectorXd bt;
        acc.sum(0, g_train, &At, &bt);
        if (!solve_normal(At, bt, &th_train)) th_train = th_all;
    }
    // 3. The block-robust covariance (as the other families): A^-1 (sum_b g_b g_b^T) A^-1
    //    G/(G-1) with g_b the score of span b at the solution; the white figure A^-1 beside it.
    const Eigen::MatrixXd Ai = A.selfadjointView<Eigen::Lower>().ldlt().solve(Eigen::MatrixXd::Identity(M.P, M.P));
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(M.P, M.P);
    int g_used = 0;
    for (const Block &B : acc.blk) {
        if (B.rows == 0) continue;
        const Eigen::VectorXd gb = B.A.selfadjointView<Eigen::Lower>() * th_all - B.b;
        S += gb * gb.transpose();
        g_used++;
    }
    R.blocks = g_used;
    Eigen::MatrixXd C = Ai * S * Ai * (g_used > 1 ? static_cast<double>(g_used) / (g_used - 1) : 1.0);
    const double tq = g_used > 1 ? t975(g_used - 1) : 1.959964;
    for (int c = 0; c < M.P; c++) {
        RigidParam p;
        if (c < M.nb) {
            p.name = R.base.name[static_cast<std::size_t>(c)];
            p.unit = base_unit(n, M.base[static_cast<std::size_t>(c)]);
        } else {
            const int k = (c - M.nb) / 3, f = (c - M.nb) % 3;
            p.name = std::string(kFricName[f]) + std::to_string(k + 1);
            p.unit = kFricUnit[f];
        }
        p.value = th_all(c);
        p.sigma_white = std::sqrt(std::max(0.0, Ai(c, c)));
        p.sigma = std::max(p.sigma_white, std::sqrt(std::max(0.0, C(c, c))));
        p.ci95 = tq * p.sigma;
        p.pct = (p.value != 0.0) ? 100.0 * p.sigma / std::fabs(p.value) : 1e300;
        // pinned: the interval within half the value, or its whole effect on every motor's
        // current over the range this run saw within that motor's noise
        bool small = true;
        for (int k = 0; k < n; k++) {
            const double noise = std::max(sig[static_cast<std::size_t>(k)], R.axes[static_cast<std::size_t>(k)].prep.noise_floor);
            if (p.ci95 * reach(c, k) > noise) small = false;
            if (reach(c, k) > p.reach) {
                p.reach = reach(c, k);
                p.reach_axis = static_cast<unsigned>(k + 1);
            }
        }
        p.pinned = p.ci95 <= 0.5 * std::fabs(p.value) || small;
        R.params.push_back(p);
    }
    for (int k = 0; k < n; k++) R.axes[static_cast<std::size_t>(k)].sigma = sig[static_cast<std::size_t>(k)];
    // 4. Held-out residuals per motor: the fit of the training part on the held-out ticks (or
    //    the whole fit on the --validate run at the same delay and eps).
    auto validate_run = [&](const Run &V, std::size_t from, const Eigen::VectorXd &th, bool lin) {
        std::vector<double> ss(static_cast<std::size_t>(n), 0.0), si(static_cast<std::size_t>(n), 0.0),
            pk(static_cast<std::size_t>(n), 0.0);
        std::vector<std::size_t> cnt(static_cast<std::size_t>(n), 0), ni(static_cast<std::size_t>(n), 0);
        Joiner J(V.L);
        while (J.next(&idx)) {
            if (idx[0] < from) continue;
            if (!state(M, V, idx, q, qd, qdd, vm) || !rows(M, q, qd, qdd, vm, &W, &phi)) continue;
            for (int k = 0; k < n; k++) {
                const std::size_t at = idx[static_cast<std::size_t>(k)], kk = static_cast<std::size_t>(k);
                if (!V.tr[kk].use[at]) continue;
                const double i = static_cast<double>(V.L[kk]->d5[at]);
                const double r = i - phi.row(k).dot(th);
                ss[kk] += r * r;
                cnt[kk]++;
                pk[kk] = std::max(pk[kk], std::fabs(i));
                if (std::fabs(r) <= 4.0 * sig[kk]) {
                    si[kk] += r * r;
                    ni[kk]++;
                }
            }
        }
        for (int k = 0; k < n; k++) {
            const std::size_t kk = static_cast<std::size_t>(k);
            Validation &Vd = lin ? R.axes[kk].val_lin : R.axes[kk].val;
            Vd.n = cnt[kk];
            Vd.rms = std::sqrt(ss[kk] / static_cast<double>(std::max<std::size_t>(1, cnt[kk])));
            Vd.rms_inlier = std::sqrt(si[kk] / static_cast<double>(std::max<std::size_t>(1, ni[kk])));
            Vd.pct_peak = pk[kk] > 0.0 ? 100.0 * Vd.rms_inlier / pk[kk] : 0.0;
            const double noise = R.axes[kk].prep.noise_floor > 0.0 ? R.axes[kk].prep.noise_floor : sig[kk];
            Vd.x_noise = noise > 0.0 ? Vd.rms_inlier / noise : 0.0;
        }
    };
    Run vrun;
    if (val != nullptr) {
        for (int j = 0; j < n; j++) {
            const AxisLog *p = nullptr;
            for (const AxisLog &L : *val) {
                if (L.axis == static_cast<unsigned>(j + 1)) p = &L;
            }
            if (p == nullptr || !p->have_q) {
                R.why_not = "--validate: axis " + std::to_string(j + 1) + (p == nullptr ? " is not in the log" : " has no link angle");
                return R;
            }
            vrun.L.push_back(p);
        }
        vrun.tr.resize(static_cast<std::size_t>(n));
        for (int a = 0; a < n; a++) {
            Prep pv = R.axes[static_cast<std::size_t>(a)].prep;
            pv.kept = pv.dropped_edge = pv.dropped_still = pv.dropped_sat = pv.dropped_late = pv.dropped_gap = 0;
            track(*vrun.L[static_cast<std::size_t>(a)], o, R.delay, &pv, &vrun.tr[static_cast<std::size_t>(a)]);
        }
        validate_run(vrun, 0, th_all, false);
    } else {
        for (int k = 0; k < n; k++) {
            const std::size_t kk = static_cast<std::size_t>(k);
            Validation &Vd = R.axes[kk].val;
            Vd.n = n_all[kk];
            Vd.rms = std::sqrt(parts[0].hold_all.sse(kk, th_train) / static_cast<double>(std::max<std::size_t>(1, n_all[kk])));
            Vd.rms_inlier = std::sqrt(parts[0].hold_in.sse(kk, th_train) / static_cast<double>(std::max<std::size_t>(1, n_in[kk])));
            Vd.pct_peak = peak[kk] > 0.0 ? 100.0 * Vd.rms_inlier / peak[kk] : 0.0;
            const double noise = R.axes[kk].prep.noise_floor > 0.0 ? R.axes[kk].prep.noise_floor : sig[kk];
            Vd.x_noise = noise > 0.0 ? Vd.rms_inlier / noise : 0.0;
        }
    }
    if (consistent) {
        // the consistent fits of the training part (held-out figures) and of everything (the
        // values, the file); the least-squares figures stay beside them
        Eigen::VectorXd xc, thc, xct, thct;
        Eigen::MatrixXd At;
        Eigen::VectorXd bt;
        if (val == nullptr) acc.sum(0, g_train, &At, &bt);
        Eigen::VectorXd psi;
        std::string note, note_t;
        // the training part's fit starts where the whole one ended (they differ by a fifth of the data)
        if (!consistent_fit(R.base, n, M.nb, A, b, th_all, &xc, &thc, &psi, &note) ||
            (val == nullptr && !consistent_fit(R.base, n, M.nb, At, bt, th_train, &xct, &thct, &psi, &note_t))) {
            R.warnings.push_back("the physically consistent fit did not converge: the least-squares values are reported and written");
        } else {
            R.consistent = true;
            if (!note.empty()) R.warnings.push_back(note);
            for (int k = 0; k < n; k++) {
                const std::size_t kk = static_cast<std::size_t>(k);
                R.axes[kk].val_lin = R.axes[kk].val;
            }
            if (val != nullptr) {
                validate_run(vrun, 0, xc, false);
            } else {
                for (int k = 0; k < n; k++) {
                    const std::size_t kk = static_cast<std::size_t>(k);
                    Validation &Vd = R.axes[kk].val;
                    Vd.rms = std::sqrt(parts[0].hold_all.sse(kk, xct) / static_cast<double>(std::max<std::size_t>(1, n_all[kk])));
                    Vd.rms_inlier = std::sqrt(parts[0].hold_in.sse(kk, xct) / static_cast<double>(std::max<std::size_t>(1, n_in[kk])));
                    Vd.pct_peak = peak[kk] > 0.0 ? 100.0 * Vd.rms_inlier / peak[kk] : 0.0;
                    const double noise = R.axes[kk].prep.noise_floor > 0.0 ? R.axes[kk].prep.noise_floor : sig[kk];
                    Vd.x_noise = noise > 0.0 ? Vd.rms_inlier / noise : 0.0;
                }
            }
            // how far it moved: the RMS change of the predicted currents over the fit's rows,
            // in noise sigmas (the weights are 1/sigma^2)
            std::size_t rows_all = 0;
            for (const RigidAxis &ax : R.axes) rows_all += ax.rows;
            const Eigen::VectorXd d = xc - th_all;
            R.moved = std::sqrt(std::max(0.0, d.dot(A * d)) / static_cast<double>(std::max<std::size_t>(1, rows_all)));
            for (int c = 0; c < M.P; c++) R.params[static_cast<std::size_t>(c)].consistent = xc(c);
            R.theta_consistent.assign(thc.data(), thc.data() + thc.size());
        }
    }
    // the full vector: each base member carries its combination, the others 0
    R.theta.assign(static_cast<std::size_t>(R.base.nfull), 0.0);
    for (int c = 0; c < M.nb; c++) R.theta[static_cast<std::size_t>(M.base[static_cast<std::size_t>(c)])] = th_all(c);
    // identifiable: every parameter pinned (the same rule as the per-axis families)
    R.identifiable = true;
    for (const RigidParam &p : R.params) {
        if (p.pinned) continue;
        char b[400];
        std::snprintf(b, sizeof b, "%s is not pinned by this run: %.4g +- %.3g (95 %%), up to %.3g A per unit on axis %u's "
                      "current: excite the arm more", p.name.c_str(), p.value, p.ci95, p.reach, p.reach_axis);
        R.why_not = b;
        R.identifiable = false;
        break;
    }
    if (R.cond > 1e6) {
        char b[160];
        std::snprintf(b, sizeof b, "normal matrix condition number %.3g (columns scaled): parameters are nearly collinear", R.cond);
        R.warnings.push_back(b);
    }
    R.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return R;
}

}  // namespace ident
