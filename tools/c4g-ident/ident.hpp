// SPDX-License-Identifier: MIT
// c4g-ident: the motor-side dynamic model of each axis, fitted from logged runs.
//
//   i = Ja*a + Fv*v + (Fc + (Fs - Fc)*exp(-(v/vs)^2))*tanh(v/eps) + off + ga*cos(q) + gb*sin(q)
//
// i the reference current D5 [A], v [motor turns/s] and a [motor turns/s^2] from D4 through
// a zero-phase Savitzky-Golay filter, q the link angle [rad] from D3 through the library's
// kinematics. Everything here is plain computation on arrays the caller fills.
#ifndef C4G_IDENT_HPP
#define C4G_IDENT_HPP

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ident {

// One logged axis: every tick the reader kept, in order. tick numbers may jump (a gap
// splits the signal into segments the filter never crosses).
struct AxisLog {
    unsigned arm = 0;       // 1-based
    unsigned axis = 0;      // logical, 1-based
    unsigned open = 0;      // OPEN index, 1-based (0 unknown)
    double period = 0.002;  // s
    double az_lim = 0.0;    // A, 0 unknown
    const char *az_from = "none";  // where az_lim came from: "init packet", "--az-lim", "none"
    bool have_q = false;    // q is the link angle
    bool lean = false;      // t, d1, d2, e1, e2 not kept (Selection::lean)
    std::vector<int64_t> tick;
    std::vector<double> t;  // s
    std::vector<float> d1, d2, d3, d4, d5, e1, e2;
    std::vector<double> q;  // rad (when have_q)
    // ticks the controller ran without the PC's reply to the tick before (none, or too late):
    // what it did there is not what the trajectory asked (captures only; ascending)
    std::vector<int64_t> late_ticks;
    // why ticks were dropped by the reader (not drive-on, special mode, non-finite, window)
    uint64_t seen = 0, dropped_drive = 0, dropped_mode = 0, dropped_nonfinite = 0,
             dropped_window = 0;
};

// Parameter indices (a model variant uses a subset).
enum Param { JA = 0, FV, FC, OFF, FS, VS, GA, GB, NPARAM };
extern const char *const param_name[NPARAM];
extern const char *const param_unit[NPARAM];

// CTRL_C, CTRL_S: the `ctrl` family (--model ctrl), a correction of the controller's own
// model: i = k1*(EXT1 - in) + k2*in + friction + off, in = ks*EXT2*2*pi*a the inertial part
// of EXT1 (ks the controller's 1/Kt as EXT1 shows it): k1 scales the rest of the controller's
// model (gravity, Coriolis), k2 its inertia, both 1 when the model is right. The gravity
// slots GA, GB hold k1, k2 (their columns cq, sq hold EXT1 - in and in); Ja is not a parameter.
enum Variant { COULOMB = 0, COULOMB_G, STRIBECK, STRIBECK_G, CTRL_C, CTRL_S, NVARIANT };
extern const char *const variant_name[NVARIANT];
bool variant_has(Variant v, Param p);
bool variant_gravity(Variant v);
bool variant_ctrl(Variant v);
// The parameter's name in this variant (GA, GB are k1, k2 in the ctrl family).
const char *param_name_of(Variant v, int p);
const char *param_unit_of(Variant v, int p);

using Vec = std::array<double, NPARAM>;

// The prediction and its derivatives for one sample (all NPARAM; unused ones ignored).
double model_eval(const Vec &p, double eps, double v, double a, double cq, double sq,
                  Vec *grad);

enum Loss { LOSS_HUBER = 0, LOSS_CAUCHY, LOSS_NONE };

struct Options {
    int sg_half = 12;          // Savitzky-Golay half window [ticks]
    int sg_order = 3;          // polynomial order
    bool delay_auto = true;
    double delay = 0.0;        // ticks (D5 time - end of D4's interval), when !delay_auto
    double eps = 0.0;          // smooth-sign velocity [turns/s]; 0 = automatic
    Loss loss = LOSS_HUBER;
    double loss_k = 1.345;     // robust scale in noise sigmas
    double holdout = 0.2;      // fraction held out at the end (when no validation log)
    int threads = 2;
    int force_variant = -1;    // -1: chosen on held-out data
    bool want_gravity = true;  // offer the gravity variants (when q is known)
    std::size_t select_max = 30000; // samples the variants are compared on (evenly thinned)
    bool ctrl = false;         // the ctrl family (--model ctrl) instead of the axis family
};

// Samples ready for the fit.
struct Samples {
    std::vector<double> v, a, i, cq, sq;
    // the ctrl family: cq holds EXT1 - in [A], sq the inertial term in = ks*EXT2*2*pi*a [A]
    std::vector<double> pos;   // D3 [motor turns]: what a log without the link angle has of q
    std::vector<int64_t> tick;
    std::vector<double> t;
    std::size_t n() const { return i.size(); }
};

// What the preparation found.
struct Prep {
    double delay = 0.0;        // ticks
    double delay_sd = 0.0;     // its standard deviation from the search's cost curvature [ticks], 0 unknown
    bool delay_at_bound = false; // the search ended at an end of its range: the data do not pin it
    double eps = 0.0;          // turns/s
    double vnoise = 0.0;       // sigma of the velocity estimate [turns/s]
    double noise_floor = 0.0;  // sigma of D5's tick-to-tick roughness [A]
    uint64_t kept = 0, dropped_edge = 0, dropped_still = 0, dropped_sat = 0;
    uint64_t dropped_late = 0;     // near a tick without the PC's reply in time
    uint64_t dropped_gap = 0;      // near a gap in the controller's NUM sequence
    double vmax = 0.0, amax = 0.0; // largest |v|, |a| kept
    double ipeak = 0.0;        // largest |i| kept
    // ctrl family: ks [A/(N m)], EXT2's torque to current (EXT1's own slope on the inertial
    // torque EXT2*2*pi*a), and the largest |EXT1 - in|, |in| kept (in = ks*EXT2*2*pi*a)
    double ks = 0.0, e1max = 0.0, inmax = 0.0;
};

// Savitzky-Golay weights for the derivative @p deriv (0, 1) of the order-@p order fit over
// 2*half+1 points, evaluated at offset @p x (ticks) from the centre.
std::vector<double> sg_weights(int half, int order, int deriv, double x);

// From a log to samples: velocity/acceleration at D5's time, standstill and reversal
// neighbourhoods, saturation and filter edges dropped.
Prep prepare(const AxisLog &log, const Options &o, Samples *out);
// The delay search's range [ticks]: a minimum at either end is not a delay the data pin.
constexpr double kDelayMax = 3.0;
// The delay that best explains D5 (linear fit of the Coulomb model), to 0.01 tick; its
// standard deviation (white-noise figure from the cost's curvature) in @p sd, and whether it
// ended at the range's end in @p at_bound.
double estimate_delay(const AxisLog &log, const Options &o, double eps, double *sd = nullptr, bool *at_bound = nullptr);
// The median of |x| (robust scales: 1.4826 times it is a normal sigma).
double median_abs(std::vector<double> x);
// 97.5 % quantile of Student's t with @p df degrees of freedom (Cornish-Fisher, 1e-3 at df 5).
double t975(int df);
// Robust sigma of D5's noise from its second differences (model-free).
double noise_floor(const AxisLog &log);

// The rigid family (rigid.hpp) filters every axis of the arm at one delay and keeps each
// tick's state: v, a [turn/s, turn/s^2] and q [rad] at D5's time, ok (the filter's window
// inside the segment: the state is known) and use (prepare's rules for this axis' current).
struct Track {
    std::vector<float> v, a, q;
    std::vector<unsigned char> ok, use;
};
// eps, the noise floor and this axis' own delay estimate: the start of prepare(), and all
// the rigid family takes per axis.
Prep prepare_axis(const AxisLog &log, const Options &o);
// The track of @p log at @p delay; counts kept and dropped ticks into @p pr (eps from it).
void track(const AxisLog &log, const Options &o, double delay, Prep *pr, Track *out);

struct ParamStat {
    // sigma: the larger of the white-noise and the block-robust figures (and the delay's
    // share); ci95 = t(blocks - 1) * sigma; pct: 100*sigma/|value|
    double value = 0, sigma = 0, ci95 = 0, pct = 0;
    double sigma_white = 0;    // sigma from the white-noise covariance alone
    double sigma_delay = 0;    // the part of sigma the delay's uncertainty gives
    bool free = false;
    bool at_bound = false;  // held at its lower bound: the data push it below
};

struct Fit {
    Variant variant = COULOMB;
    Vec p{};
    std::array<ParamStat, NPARAM> st{};
    double sigma = 0.0;        // robust residual scale [A]
    double rms = 0.0;          // residual RMS (all samples) [A]
    double rms_inlier = 0.0;   // residual RMS of |r| <= 4 sigma [A]
    double outlier_frac = 0.0;
    double cond = 0.0;         // condition number of the column-scaled regressor
    bool cov_ok = false;
    int blocks = 0;            // spans of ticks the block-robust covariance summed the scores over
    double colour = 1.0;       // largest ratio block-robust / white-noise variance (1: white residual)
    int iterations = 0;
    double seconds = 0.0;
    std::vector<int> held;     // parameters the data held at their lower bound
    std::vector<std::string> warnings;
};

struct Validation {
    double rms = 0, rms_inlier = 0, pct_peak = 0, x_noise = 0;
    std::size_t n = 0;
};

// Linear least squares for a fixed vs (or none): the start of every non-linear fit.
bool fit_linear(const Samples &s, Variant v, double eps, double vs, Vec *p, double *cost);
// The robust non-linear fit (Ceres), covariance, statistics.
// @p start: where to begin (a fit of a subset); by default a linear least-squares start.
Fit fit(const Samples &s, Variant v, double eps, const Options &o, const Vec *start = nullptr);
Validation validate(const Samples &s, const Fit &f, double eps, double noise);
// sigma^2 (J^T J)^-1 at @p p: the Cramer-Rao bound of the parameters with Gaussian noise.
bool crlb(const Samples &s, Variant v, const Vec &p, double eps, double sigma, Vec *sd);

struct AxisResult {
    unsigned arm = 0, axis = 0, open = 0;
    double period = 0;
    Prep prep;
    bool identifiable = false;
    std::string why_not;
    Fit fit;
    Validation val;
    std::array<double, NVARIANT> val_cost{};  // held-out robust cost per variant tried
    std::array<bool, NVARIANT> tried{};
    double ext1_rms = 0, ext2_mean = 0;        // the controller's own model, beside the fit
    std::vector<std::string> warnings;
};

// The whole job for one axis: prepare, choose the variant on held-out data (or @p val_log),
// refit on everything.
AxisResult identify(const AxisLog &log, const AxisLog *val_log, const Options &o);

}  // namespace ident

#endif
