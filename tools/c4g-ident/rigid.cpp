// SPDX-License-Identifier: MIT
// The rigid family's fit (rigid.hpp).
#include "rigid.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <thread>
#include <chrono>
#include <cmath>
#include <cstring>

namespace ident {

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr int kBlocks = 40;          // spans of ticks for the block-robust covariance
constexpr std::size_t kStartTicks = 6000;  // ticks the robust start is fitted on
constexpr int kBuf = 256;            // rows per rank update

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

double t975(int df)
{
    const double z = 1.959964, n = std::max(1, df);
    return z + (z * z * z + z) / (4.0 * n) + (5.0 * std::pow(z, 5) + 16.0 * z * z * z + 3.0 * z) / (96.0 * n * n);
}

double median_abs(std::vector<double> x)
{
    if (x.empty()) return 0.0;
    for (double &y : x) y = std::fabs(y);
    const std::size_t m = x.size() / 2;
    std::nth_element(x.begin(), x.begin() + static_cast<long>(m), x.end());
    return x[m];
}

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
    explicit Joiner(const std::vector<const AxisLog *> &logs) : L(logs), at(logs.size(), 0) {}
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
    Eigen::MatrixXd A;
    Eigen::VectorXd b;
    std::size_t rows = 0;
};

struct Accum {
    int P = 0;
    std::vector<Block> blk;
    Eigen::MatrixXd U;   // P x kBuf: weighted rows, column-wise
    Eigen::VectorXd y;   // weighted currents
    int fill = 0, cur = -1;
    explicit Accum(int p, int g) : P(p), blk(static_cast<std::size_t>(g)), U(p, kBuf), y(kBuf)
    {
        for (Block &B : blk) {
            B.A = Eigen::MatrixXd::Zero(p, p);
            B.b = Eigen::VectorXd::Zero(p);
        }
    }
    void flush()
    {
        if (fill == 0 || cur < 0) return;
        Block &B = blk[static_cast<std::size_t>(cur)];
        B.A.selfadjointView<Eigen::Lower>().rankUpdate(U.leftCols(fill));
        B.b += U.leftCols(fill) * y.head(fill);
        B.rows += static_cast<std::size_t>(fill);
        fill = 0;
    }
    void add(int g, const double *phi, double i, double w)
    {
        if (g != cur || fill == kBuf) {
            flush();
            cur = g;
        }
        const double s = std::sqrt(w);
        for (int c = 0; c < P; c++) U(c, fill) = s * phi[c];
        y(fill) = s * i;
        fill++;
    }
    // sum of blocks [g0, g1), the lower triangle mirrored
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
                A.prep = prepare_rigid_axis(*run.L[static_cast<std::size_t>(a)], o);
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
    Accum acc(M.P, kBlocks);
    Eigen::MatrixXd reach = Eigen::MatrixXd::Zero(M.P, n);
    for (int j = 0; j < n; j++) {
        R.q_min[j] = 1e300;
        R.q_max[j] = -1e300;
    }
    {
        Joiner J(run.L);
        while (J.next(&idx)) {
            if (!state(M, run, idx, q, qd, qdd, vm) || !rows(M, q, qd, qdd, vm, &W, &phi)) continue;
            R.states++;
            const int g = block_of(idx[0]);
            bool any = false;
            for (int k = 0; k < n; k++) {
                const std::size_t at = idx[static_cast<std::size_t>(k)];
                if (!run.tr[static_cast<std::size_t>(k)].use[at]) continue;
                any = true;
                const double i = static_cast<double>(run.L[static_cast<std::size_t>(k)]->d5[at]);
                const double r = i - phi.row(k).dot(theta);
                const double s = sig[static_cast<std::size_t>(k)];
                acc.add(g, phi.row(k).data(), i, robust_w(o.loss, o.loss_k, r, s) / (s * s));
                reach.col(k) = reach.col(k).cwiseMax(phi.row(k).transpose().cwiseAbs());
                R.axes[static_cast<std::size_t>(k)].rows++;
            }
            if (!any) continue;
            for (int j = 0; j < n; j++) {
                R.q_min[j] = std::min(R.q_min[j], q[j]);
                R.q_max[j] = std::max(R.q_max[j], q[j]);
                R.qd_max[j] = std::max(R.qd_max[j], std::fabs(qd[j]));
                R.qdd_max[j] = std::max(R.qdd_max[j], std::fabs(qdd[j]));
            }
        }
        acc.flush();
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
        validate_run(run, n_train, th_train, false);
    }
    (void)consistent;
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
