// SPDX-License-Identifier: MIT
// Test data for c4g-ident, made in-process by c4g-sim's own axis model (the DSA loops and the
// plant c4g-sim runs), so thirty seeds take seconds; the truth is the model's parameters.
#ifndef C4G_IDENT_SIMGEN_HPP
#define C4G_IDENT_SIMGEN_HPP

#include "excite.hpp"
#include "ident.hpp"

extern "C" {
#include "c4gsim_model.h"
}

namespace simgen {

struct Case {
    c4gsim_axis_params_t p{};
    unsigned logical = 0;         // 0-based, for the defaults
    double period = 0.002;
    double seconds = 40.0;
    ident::ExciteOptions ex;
    double vmax = 8.0, amax = 150.0;
    double outliers = 0.0;        // fraction of D5 samples replaced by a gross error
    double outlier_size = 2.0;    // A, uniform in +-[size/2, size]
    bool still = false;           // the axis is commanded to stand still
};

// The truth in c4g-ident's units.
ident::Vec truth(const c4gsim_axis_params_t &p);
// Link angle of a motor position (what the library's kinematics gives on an uncoupled axis).
double link_angle(const c4gsim_axis_params_t &p, double motor);
ident::AxisLog run(const Case &c, uint64_t seed);

}  // namespace simgen

#endif
