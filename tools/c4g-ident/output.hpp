// SPDX-License-Identifier: MIT
// What c4g-ident writes: the report (text or JSON), the parameter file c4g-server's mode 9
// reads, and the plots (gnuplot).
#ifndef C4G_IDENT_OUTPUT_HPP
#define C4G_IDENT_OUTPUT_HPP

#include "ident.hpp"
#include "input.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace ident {

struct Job {
    std::vector<InputInfo> inputs;
    std::string validate_path;
    std::vector<AxisLog> logs;       // what the fit used, per axis
    std::vector<AxisResult> results;
    Options opt;
    double seconds = 0.0;
};

void report_text(FILE *out, const Job &j);
int report_json(FILE *out, const Job &j);
// The parameter file of the arm (identified axes only). 0 ok, else errno-style message in err.
int write_params(const std::string &path, const Job &j, const std::string &version, std::string *err);
// The text of the parameter file (checksum line included).
std::string params_text(const Job &j, const std::string &version);
// PNG and SVG plots into dir (created if missing): 0 ok.
int write_plots(const std::string &dir, const Job &j, std::string *err);
// The samples each identified axis was fitted to (v, a, i, cos q, sin q), one CSV per axis.
int write_samples(const std::string &dir, const Job &j, std::string *err);

}  // namespace ident

#endif
