// SPDX-License-Identifier: MIT
// The base parameters of the rigid-body model (rigid_base.hpp).
#include "rigid_base.hpp"

#include <cmath>
#include <cstdio>
#include <random>

namespace ident {

namespace {

const char *const kLinkParam[kRigidPerLink] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};

// A coefficient of K as the name shows it: "+ ", "- ", "+ 0.15*".
std::string coef_text(double c)
{
    char b[48];
    const double a = std::fabs(c);
    if (std::fabs(a - 1.0) < 1e-9) std::snprintf(b, sizeof b, " %c ", c < 0.0 ? '-' : '+');
    else std::snprintf(b, sizeof b, " %c %.6g*", c < 0.0 ? '-' : '+', a);
    return b;
}

}  // namespace

std::string rigid_param_name(int n, int idx)
{
    if (idx >= kRigidPerLink * n) return "ia" + std::to_string(idx - kRigidPerLink * n + 1);
    return std::string(kLinkParam[idx % kRigidPerLink]) + std::to_string(idx / kRigidPerLink + 1);
}

bool rigid_regressor(const c4g_dyn_chain_t &ch, const double *q, const double *qd, const double *qdd,
                     Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> *W)
{
    const int n = static_cast<int>(ch.n);
    const int nl = kRigidPerLink * n;
    W->setZero(n, nl + n);
    double y[C4G_DYN_MAX_LINKS * C4G_DYN_MAX_LINKS * C4G_DYN_PARAMS];
    if (c4g_dyn_regressor(&ch, q, qd, qdd, y, static_cast<uint32_t>(sizeof y / sizeof y[0])) != C4G_OK) return false;
    for (int r = 0; r < n; r++) {
        for (int c = 0; c < nl; c++) (*W)(r, c) = y[r * nl + c];
        (*W)(r, nl + r) = qdd[r];
    }
    return true;
}

bool rigid_base(const c4g_dyn_chain_t &ch, RigidBase *out, std::string *err, int samples, double tol, unsigned seed)
{
    const int n = static_cast<int>(ch.n);
    if (n < 1 || n > static_cast<int>(C4G_DYN_MAX_LINKS) || samples < 11 * n) {
        *err = "base parameters: a chain of 1.." + std::to_string(C4G_DYN_MAX_LINKS) + " joints and at least 11 samples per joint";
        return false;
    }
    const int nf = (kRigidPerLink + 1) * n;
    // Random states over the whole circle, speeds and accelerations of a few rad/s(^2): every
    // term of the dynamics (gravity, inertia, Coriolis) is present, none dominates by orders.
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uq(-M_PI, M_PI), uv(-2.0, 2.0), ua(-5.0, 5.0);
    Eigen::MatrixXd W(static_cast<Eigen::Index>(samples) * n, nf);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Wk;
    double q[C4G_DYN_MAX_LINKS], qd[C4G_DYN_MAX_LINKS], qdd[C4G_DYN_MAX_LINKS];
    for (int s = 0; s < samples; s++) {
        for (int j = 0; j < n; j++) {
            q[j] = uq(rng);
            qd[j] = uv(rng);
            qdd[j] = ua(rng);
        }
        if (!rigid_regressor(ch, q, qd, qdd, &Wk)) {
            *err = "base parameters: the dynamics library refused the chain";
            return false;
        }
        W.block(static_cast<Eigen::Index>(s) * n, 0, n, nf) = Wk;
    }
    // Greedy pass in theta's order: a column is a base member when its distance from the
    // span of those kept so far is above tol of its norm (Gram-Schmidt, twice for accuracy).
    double maxnorm = 0.0;
    for (int c = 0; c < nf; c++) maxnorm = std::max(maxnorm, W.col(c).norm());
    RigidBase B;
    B.n = n;
    B.nfull = nf;
    B.samples = samples;
    B.tol = tol;
    Eigen::MatrixXd Q(W.rows(), 0);
    for (int c = 0; c < nf; c++) {
        const double norm = W.col(c).norm();
        if (!(norm > 1e-10 * maxnorm)) {
            B.dep.push_back(c);  // never acts
            continue;
        }
        Eigen::VectorXd v = W.col(c);
        for (int pass = 0; pass < 2; pass++) {
            if (Q.cols() > 0) v -= Q * (Q.transpose() * v);
        }
        if (v.norm() > tol * norm) {
            Q.conservativeResize(Eigen::NoChange, Q.cols() + 1);
            Q.col(Q.cols() - 1) = v / v.norm();
            B.base.push_back(c);
        } else {
            B.dep.push_back(c);
        }
    }
    // The rank the column-pivoting QR of the column-scaled stack sees: the greedy pass must
    // agree with it (a disagreement means the tolerance sits inside the spectrum's gap).
    Eigen::MatrixXd Ws = W;
    for (int c = 0; c < nf; c++) {
        const double norm = W.col(c).norm();
        Ws.col(c) = (norm > 1e-10 * maxnorm) ? Eigen::VectorXd(W.col(c) / norm) : Eigen::VectorXd::Zero(W.rows());
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Ws);
    qr.setThreshold(tol);
    B.rank_qr = static_cast<int>(qr.rank());
    if (B.rank_qr != static_cast<int>(B.base.size())) {
        *err = "base parameters: the rank is not clear (" + std::to_string(B.base.size()) + " columns by the greedy pass, " +
               std::to_string(B.rank_qr) + " by the pivoting QR)";
        return false;
    }
    // K: W_d = W_b K (exact up to rounding), so W theta = W_b (theta_b + K theta_d).
    const int nb = static_cast<int>(B.base.size()), nd = static_cast<int>(B.dep.size());
    Eigen::MatrixXd Wb(W.rows(), nb), Wd(W.rows(), nd);
    for (int k = 0; k < nb; k++) Wb.col(k) = W.col(B.base[static_cast<std::size_t>(k)]);
    for (int k = 0; k < nd; k++) Wd.col(k) = W.col(B.dep[static_cast<std::size_t>(k)]);
    B.K = Wb.colPivHouseholderQr().solve(Wd);
    // the coefficients are products of the DH lengths: rounding noise below 1e-9 is none
    for (Eigen::Index i = 0; i < B.K.size(); i++) {
        if (std::fabs(B.K.data()[i]) < 1e-9) B.K.data()[i] = 0.0;
    }
    B.P = Eigen::MatrixXd::Zero(nb, nf);
    for (int k = 0; k < nb; k++) B.P(k, B.base[static_cast<std::size_t>(k)]) = 1.0;
    for (int d = 0; d < nd; d++) B.P.col(B.dep[static_cast<std::size_t>(d)]) = B.K.col(d);
    for (int k = 0; k < nb; k++) {
        std::string s = rigid_param_name(n, B.base[static_cast<std::size_t>(k)]);
        for (int d = 0; d < nd; d++) {
            if (B.K(k, d) != 0.0) s += coef_text(B.K(k, d)) + rigid_param_name(n, B.dep[static_cast<std::size_t>(d)]);
        }
        B.name.push_back(s);
    }
    *out = B;
    return true;
}

}  // namespace ident
