// SPDX-License-Identifier: MIT
// The optimised excitation (c4g-ident excite --optimize): per joint a finite Fourier series
// (Swevers et al.)
//     q_j(t) = q0_j + sum_l a_jl/(w l) sin(w l t) - b_jl/(w l) cos(w l t),  l = 1..N,
// whose coefficients minimise the condition number of the base regressor of the rigid-body
// model as the fit sees it (motor currents: link parameters and rotor inertias through
// diag(1/kt) Kr^-T, plus each motor's viscous, Coulomb and offset columns), sampled over
// one period, within each joint's position, velocity and acceleration limits.
// sum_l a_jl = 0 and sum_l l b_jl = 0: speed and acceleration are 0 at t = 0, so every
// period starts and ends at rest at the start pose (no ramp needed). Each candidate is
// scaled per joint to use a fixed share of its tightest limit, so the search runs over the
// series' shapes only; a (1+1) evolution strategy from a few seeded starts, a fixed
// number of evaluations: the same options give the same bytes.
#ifndef C4G_IDENT_OPTEXCITE_HPP
#define C4G_IDENT_OPTEXCITE_HPP

#include "c4gopen_dyn.h"
#include "rigid_base.hpp"

#include <functional>
#include <string>
#include <vector>

namespace ident {

constexpr unsigned kOptJoints = 6;  // the arm's main axes: Kr of the init packet is 6 x 6

struct OptLimit {
    double q_min = 0, q_max = 0;  // absolute joint angle [rad]
    double qd_max = 0;            // |speed| [rad/s]
    double qdd_max = 0;           // |acceleration| [rad/s^2]
};

struct OptProblem {
    c4g_dyn_chain_t chain{};
    double kr[kOptJoints][kOptJoints] = {};  // motor rad per joint rad, [motor][joint]
    double kt[kOptJoints] = {};              // N m/A
    double start[kOptJoints] = {};           // pose at t = 0 [rad]
    OptLimit lim[kOptJoints];
    double f0 = 0.1;       // base frequency [Hz]
    int harmonics = 5;
    double eps = 0.05;     // smooth sign of the Coulomb column: tanh(vm / eps), vm [motor turn/s]
    double use = 0.95;     // share of the tightest limit each joint's motion reaches
    int samples = 100;     // regressor samples per period
    int evals = 2000;      // objective evaluations in all
    int restarts = 4;      // seeded starting points sharing them
    unsigned seed = 1;
};

// Joint state at time t: q, qd, qdd (kOptJoints each; joints beyond the chain stay 0).
using JointPath = std::function<void(double t, double *q, double *qd, double *qdd)>;

// The regressor of the fit's model and its base columns.
class OptModel {
public:
    bool init(const OptProblem &p, std::string *err);
    int columns() const { return static_cast<int>(base_.base.size()) + 3 * n_; }
    std::string column_name(int c) const;
    // Rows (n per state) of the base regressor for the states, appended to @p rows
    // (columns() wide, row-major); false on a library error.
    bool rows(const double *q, const double *qd, const double *qdd, std::vector<double> *rows) const;
    const RigidBase &base() const { return base_; }

private:
    const OptProblem *p_ = nullptr;
    int n_ = 0;
    RigidBase base_;
    double a_[kOptJoints][kOptJoints] = {};  // diag(1/kt) Kr^-T: joint torque -> motor current
};

// What the regressor along a path says.
struct Conditioning {
    double cond = 0.0;                 // sigma_max / sigma_min of the base regressor
    int rows = 0, cols = 0;
    std::vector<double> sigma;         // singular values, largest first
    struct Weak {
        double rel;                    // sigma / sigma_max
        std::vector<std::pair<std::string, double>> members;  // base parameters, weights
    };
    std::vector<Weak> weakest;         // the least determined directions, weakest first
};

// The regressor stacked over @p times of @p path, and its singular values (@p weakest: how
// many of the smallest directions to name).
bool conditioning(const OptModel &m, const JointPath &path, const std::vector<double> &times, int weakest,
                  Conditioning *out, std::string *err);

// A joint's series (coefficients already scaled to its limits).
struct Series {
    std::vector<double> a, b;  // N each
    double w = 0.0;            // base angular frequency [rad/s]
    double q0 = 0.0;           // so that q(0) is the start pose
    void eval(double t, double *q, double *qd, double *qdd) const;
};

struct OptResult {
    std::vector<Series> joint;  // n
    double objective = 0.0;     // cond at the end of the search (the search's samples)
    int evals = 0;
    double peak[kOptJoints][4] = {};  // min and max of q, max |qd|, max |qdd| over a fine grid
};

bool optimize(const OptProblem &p, const OptModel &m, OptResult *out, std::string *err);

// Peaks of @p path over [0, T] sampled every @p dt: q min and max, |qd| and |qdd| max per joint.
void path_peaks(const JointPath &path, unsigned n, double T, double dt, double peak[kOptJoints][4]);

}  // namespace ident

#endif
