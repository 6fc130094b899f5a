// SPDX-License-Identifier: MIT
// c4g-ident's rigid family (fit --model rigid): the arm's rigid-body model in current space,
//   i_k = sum_j (Kr^-T)_kj (Y_j(q, qd, qdd) theta + ia_j qdd_j) / kt_k
//         + Fv_k vm_k + Fc_k tanh(vm_k / eps_k) + off_k
// solved for the base parameters (rigid_base.hpp) and each motor's friction and offset by a
// robust weighted least squares over normal equations accumulated tick by tick: memory does
// not grow with the log beyond its samples.
#ifndef C4G_IDENT_RIGID_HPP
#define C4G_IDENT_RIGID_HPP

#include "ident.hpp"
#include "input.hpp"
#include "rigid_base.hpp"

extern "C" {
#include "c4gh_kinfile.h"
}

#include <cstdio>
#include <string>
#include <vector>

namespace ident {

struct RigidParam {
    std::string name;          // base combination, or "Fv2", "Fc2", "off2"
    std::string unit;
    double value = 0, sigma = 0, ci95 = 0, pct = 0;
    double sigma_white = 0;    // from the weighted normal matrix alone
    double reach = 0;          // its largest effect per unit on the current of axis `reach_axis` [A/unit]
    unsigned reach_axis = 0;
    bool pinned = false;       // interval within half the value, or its effect within the noise
    double consistent = 0;     // --consistent: the value of the physically consistent fit
};

struct RigidAxis {
    unsigned axis = 0;         // logical, 1-based = joint
    Prep prep;                 // eps, noise floor, its own delay estimate, counts at the common delay
    double sigma = 0;          // robust residual scale [A]
    std::size_t rows = 0;      // ticks whose current took part
    Validation val;            // held-out figures of this motor's current
    Validation val_lin;        // --consistent: the least-squares fit's held-out figures beside them
};

struct RigidResult {
    bool identifiable = false;
    std::string why_not;
    unsigned arm = 1;
    double period = 0.002;
    int n = 0;
    RigidBase base;
    std::vector<RigidParam> params;   // base parameters, then Fv, Fc, off of each motor
    std::vector<RigidAxis> axes;
    std::vector<double> theta;        // full vector (11 n): base members, the others 0
    double q_min[C4G_DYN_MAX_LINKS] = {}, q_max[C4G_DYN_MAX_LINKS] = {};
    double qd_max[C4G_DYN_MAX_LINKS] = {}, qdd_max[C4G_DYN_MAX_LINKS] = {};
    double kr[6][6] = {};             // motor rad per joint rad [motor][joint]
    double delay = 0;                 // ticks, common to every axis
    std::size_t ticks = 0;            // ticks of the first axis' log
    std::size_t states = 0;           // ticks every axis' state was known at
    int blocks = 0;                   // spans of ticks the block-robust covariance summed over
    double cond = 0;                  // condition number of the column-scaled normal matrix
    bool consistent = false;          // --consistent ran (and converged)
    double moved = 0;                 // its change of the predicted currents against the LS fit: RMS in noise sigmas
    std::vector<double> theta_consistent; // its full vector (11 n), every link physical
    std::vector<std::string> warnings;
    double seconds = 0;
};

// Kr (motor rad per joint rad) of the first @p n axes from the init packet's kinematics.
bool rigid_kr(const c4g_kin_t &kin, unsigned n, double kr[6][6], std::string *err);

// The whole job: @p logs holds one log per axis 1..kf.n (any order). @p val: a second run
// to validate on (its logs), or null: the last o.holdout of the run is held out.
RigidResult identify_rigid(std::vector<AxisLog> &logs, const c4g_kin_t &kin, const c4gh_kinfile_t &kf,
                           std::vector<AxisLog> *val, const Options &o, bool consistent);

void rigid_report_text(FILE *out, const RigidResult &r, const std::vector<InputInfo> &inputs, const Options &o,
                       const std::string &kin_path, const std::string &validate_path);
int rigid_report_json(FILE *out, const RigidResult &r, const std::vector<InputInfo> &inputs, const Options &o,
                      const std::string &kin_path, const std::string &validate_path);
// The rigid parameter file (docs/c4g-ident.md "The rigid parameter file"), checksum line included.
std::string rigid_params_text(const RigidResult &r, const c4gh_kinfile_t &kf, const std::vector<InputInfo> &inputs,
                              const std::string &version);

}  // namespace ident

#endif
