// SPDX-License-Identifier: MIT
// The base parameters of a serial arm's rigid-body model: the combinations of the link
// parameters (c4gopen_dyn.h: m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz per link, about the
// link frame's origin) and the rotor inertias ia_j that the joint torques depend on. Some
// parameters never act (link 1's mass on a vertical axis 1), others act only together (a
// link's mass and the inertias of the link before it): no data can separate them, so the fit
// solves for one member of each combination and the others are folded into it.
//
// Full vector theta (n*11): link j's 10 parameters at 10*j .. 10*j+9, then ia_1..ia_n at
// 10*n .. 11*n-1. Torques: tau = W theta = W_b beta with W_b the base columns of W and
// beta = theta_b + K theta_d (theta_b the base members, theta_d the others).
#ifndef C4G_IDENT_RIGID_BASE_HPP
#define C4G_IDENT_RIGID_BASE_HPP

#include "c4gopen_dyn.h"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace ident {

constexpr int kRigidPerLink = 10;  // C4G_DYN_PARAMS

struct RigidBase {
    int n = 0;                    // joints
    int nfull = 0;                // 11 n: link parameters and rotor inertias
    std::vector<int> base;        // the base members (indices into theta), ascending
    std::vector<int> dep;         // the others (folded into a base member, or never acting)
    Eigen::MatrixXd K;            // base.size() x dep.size(): beta = theta_b + K theta_d
    Eigen::MatrixXd P;            // base.size() x nfull: beta = P theta (the same map, full width)
    std::vector<std::string> name;// per base parameter, e.g. "Ixx2 - Iyy2" or "Izz1 + Iyy2 + ia1"
    int samples = 0;              // regressor rows stacked
    double tol = 0.0;             // relative rank tolerance used
    int rank_qr = 0;              // rank by column-pivoting QR of the whole stack (equals base.size())
};

// Name of full parameter @p idx of an n-joint arm: "m3", "mx3", "Ixx3", "ia3" (1-based joints).
std::string rigid_param_name(int n, int idx);

// One sample's full regressor (n rows x 11 n, row-major): c4g_dyn_regressor's columns and
// ia_j qdd_j in column 10 n + j of row j. false on a library error.
bool rigid_regressor(const c4g_dyn_chain_t &ch, const double *q, const double *qd, const double *qdd,
                     Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> *W);

// The base set of @p ch from @p samples random states (fixed @p seed: the result is
// reproducible), rank by the relative tolerance @p tol. Columns are taken in theta's order
// and kept when independent of those kept before (a column's distance from their span over
// its own norm above tol): the base member of a combination is its first parameter in that
// order (a link's mass goes into the link before it, Iyy into Ixx and into the previous
// link's Izz), as in the textbook's closed forms. false (and why) on a library error or
// when the greedy count disagrees with the column-pivoting QR rank.
bool rigid_base(const c4g_dyn_chain_t &ch, RigidBase *out, std::string *err, int samples = 300,
                double tol = 1e-7, unsigned seed = 1);

}  // namespace ident

#endif
