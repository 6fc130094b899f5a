// SPDX-License-Identifier: MIT
// Excitation trajectories: constant-speed runs both ways at log-spaced speeds (friction and
// its Stribeck dip need time at slow, steady speed), then a multi-sine per axis (Schroeder phases, amplitudes falling with
// the harmonic so slow and fast motion both get time), scaled to the axis' velocity and
// acceleration limits, faded in and out so it starts and ends at rest at offset 0.
#ifndef C4G_IDENT_EXCITE_HPP
#define C4G_IDENT_EXCITE_HPP

#include <vector>

namespace ident {

struct ExciteAxis {
    double vmax = 10.0;   // turns/s
    double amax = 200.0;  // turns/s^2
    bool on = true;
};

struct ExciteOptions {
    double duration = 60.0;   // s
    double f0 = 0.1;          // fundamental [Hz]
    int harmonics = 16;
    double slope = 1.0;       // amplitude of harmonic k ~ k^-slope
    double fade = 1.0;        // s
    double dt = 0.002;        // row spacing [s]
    unsigned seed = 1;        // phases differ per axis and seed
    double stops = 0.0;       // fraction of each fundamental period spent at rest (stop-and-go)
    double stair = 0.3;       // share of the duration spent on constant-speed runs (friction)
    int levels = 12;          // constant speeds, log-spaced from vmax/300 to vmax/2
};

// Offset [turns], velocity [turns/s] and acceleration [turns/s^2] of axis @p ax at time @p t.
class Excitation {
public:
    Excitation(const ExciteOptions &o, const std::vector<ExciteAxis> &axes);
    void eval(std::size_t ax, double t, double *q, double *v, double *a) const;
    double duration() const { return o_.duration; }
    std::size_t axes() const { return amp_.size(); }

    double stair_end() const { return stair_t_; }

private:
    struct Seg {
        double t0, dur, v0, v1, q0;
    };
    void stair(std::size_t ax, double t, double *q, double *v, double *a) const;
    void raw(std::size_t ax, double t, double *q, double *v, double *a) const;
    ExciteOptions o_;
    std::vector<std::vector<double>> amp_, ph_;
    std::vector<std::vector<Seg>> seg_;
    std::vector<double> stair_q_;  // position at the end of the runs
    double stair_t_ = 0.0;
};

}  // namespace ident

#endif
