// SPDX-License-Identifier: MIT
#include "output.hpp"
#include "rigid.hpp"

extern "C" {
#include "c4gh_ffmodel.h"
}

#include <jansson.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace ident {

namespace {

const char *loss_name(Loss l) { return l == LOSS_HUBER ? "huber" : (l == LOSS_CAUCHY ? "cauchy" : "none"); }

std::string axis_name(const AxisResult &r)
{
    return "arm " + std::to_string(r.arm) + " axis " + std::to_string(r.axis);
}

}  // namespace

void report_text(FILE *out, const Job &j)
{
    for (const InputInfo &in : j.inputs) {
        // a CSV has no sessions to count (an export's are numbered in its rows)
        const std::string sessions = in.sessions > 0 ? ", " + std::to_string(in.sessions) + " session(s)" : "";
        std::fprintf(out, "input %s: %s, %llu controller ticks%s%s%s\n", in.path.c_str(), in.format.c_str(),
                     static_cast<unsigned long long>(in.ticks), sessions.c_str(),
                     in.have_kin ? ", kinematics from the init packet" : "",
                     in.reply_times ? "" : ", no reply times (ticks after a late reply are kept)");
        if (in.num_gaps > 0 || in.num_dups > 0) {
            std::fprintf(out, "  NUM sequence: %llu gap(s), %llu controller packet(s) missing (ticks numbered from NUM: the "
                              "filter never reaches across a gap); %llu repeated or out-of-order packet(s) dropped\n",
                         static_cast<unsigned long long>(in.num_gaps), static_cast<unsigned long long>(in.num_missing),
                         static_cast<unsigned long long>(in.num_dups));
        }
    }
    if (j.opt.ctrl) {
        std::fprintf(out, "model: ctrl: i = k1*(EXT1 - in) + k2*in + Fv*v + (Fc + (Fs-Fc)*exp(-(v/vs)^2))*tanh(v/eps) + off, "
                          "in = ks*EXT2*2pi*a\n");
    } else {
        std::fprintf(out, "model: axis: i = Ja*a + Fv*v + (Fc + (Fs-Fc)*exp(-(v/vs)^2))*tanh(v/eps) + off + ga*cos(q) + gb*sin(q)\n");
    }
    std::fprintf(out, "fit: %s loss (scale %.3g sigma), Savitzky-Golay %d/%d, validation: %s\n", loss_name(j.opt.loss),
                 j.opt.loss_k, 2 * j.opt.sg_half + 1, j.opt.sg_order,
                 j.validate_path.empty() ? (std::to_string(static_cast<int>(j.opt.holdout * 100)) + " % held out at the end").c_str()
                                         : j.validate_path.c_str());
    for (std::size_t k = 0; k < j.results.size(); k++) {
        const AxisResult &r = j.results[k];
        const AxisLog &L = j.logs[k];
        std::fprintf(out, "\n%s (OPEN %u), period %.4g ms", axis_name(r).c_str(), r.open, r.period * 1e3);
        if (L.az_lim > 0.0) std::fprintf(out, ", current limit %.4g A (%s)\n", L.az_lim, L.az_from);
        else std::fprintf(out, ", current limit unknown: saturation not checked (--az-lim)\n");
        std::fprintf(out, "  ticks: %llu seen, %llu kept", static_cast<unsigned long long>(L.seen),
                     static_cast<unsigned long long>(r.prep.kept));
        std::fprintf(out, "; dropped: %llu drive off, %llu special mode, %llu non-finite, %llu outside the window, "
                          "%llu standstill/reversal, %llu near a late PC reply, %llu near a NUM gap, %llu saturated, %llu filter edges\n",
                     static_cast<unsigned long long>(L.dropped_drive), static_cast<unsigned long long>(L.dropped_mode),
                     static_cast<unsigned long long>(L.dropped_nonfinite), static_cast<unsigned long long>(L.dropped_window),
                     static_cast<unsigned long long>(r.prep.dropped_still), static_cast<unsigned long long>(r.prep.dropped_late),
                     static_cast<unsigned long long>(r.prep.dropped_gap), static_cast<unsigned long long>(r.prep.dropped_sat), static_cast<unsigned long long>(r.prep.dropped_edge));
        if (!r.identifiable) {
            std::fprintf(out, "  UNIDENTIFIABLE: %s\n", r.why_not.c_str());
            continue;
        }
        std::fprintf(out, "  delay of D5 after D4: %+.3f ticks (sd %.3f); eps %.4g turn/s; range |v| <= %.4g turn/s, |a| <= %.4g turn/s^2\n",
                     r.prep.delay, r.prep.delay_sd, r.prep.eps, r.prep.vmax, r.prep.amax);
        if (variant_ctrl(r.fit.variant)) {
            std::fprintf(out, "  family: ctrl (k1 scales EXT1 but its inertial part, k2 that part: both 1 when the controller's model is right), ks %.6g A/(N m) (EXT1's slope on "
                              "EXT2's inertial torque)\n", r.prep.ks);
        } else {
            std::fprintf(out, "  family: axis (i = Ja*a + friction + off + gravity)\n");
        }
        std::fprintf(out, "  variant: %s (held-out cost:", variant_name[r.fit.variant]);
        for (int v = 0; v < NVARIANT; v++) {
            if (r.tried[static_cast<std::size_t>(v)]) std::fprintf(out, " %s %.4g", variant_name[v], r.val_cost[static_cast<std::size_t>(v)]);
        }
        std::fprintf(out, ")\n");
        std::fprintf(out, "  %-4s %14s %12s %9s  %s\n", "par", "value", "+-95 %", "sigma %", "unit");
        for (int p = 0; p < NPARAM; p++) {
            const ParamStat &s = r.fit.st[static_cast<std::size_t>(p)];
            if (!s.free) continue;
            const char *pn = param_name_of(r.fit.variant, p), *pu = param_unit_of(r.fit.variant, p);
            if (s.at_bound) std::fprintf(out, "  %-4s %14.7g %12s %9s  %s (held at its bound)\n", pn, s.value, "-", "-", pu);
            else if (!(s.pct < 1e299)) std::fprintf(out, "  %-4s %14.7g %12.4g %9s  %s\n", pn, s.value, s.ci95, "-", pu);
            else std::fprintf(out, "  %-4s %14.7g %12.4g %9.3f  %s\n", pn, s.value, s.ci95, s.pct, pu);
        }
        std::fprintf(out, "  residual: RMS %.4g A (inliers %.4g A, %.2f %% outliers), robust sigma %.4g A, noise floor %.4g A "
                          "(x%.3f)\n",
                     r.fit.rms, r.fit.rms_inlier, 100.0 * r.fit.outlier_frac, r.fit.sigma, r.prep.noise_floor,
                     r.prep.noise_floor > 0 ? r.fit.rms_inlier / r.prep.noise_floor : 0.0);
        if (r.val.n > 0) {
            std::fprintf(out, "  validation: %zu samples, inlier RMS %.4g A = %.3f %% of peak current = %.3f x noise\n", r.val.n,
                         r.val.rms_inlier, r.val.pct_peak, r.val.x_noise);
        }
        std::fprintf(out, "  intervals: t(%d) x sigma, sigma the larger of white-noise and block-robust (%d spans; colour x%.3g "
                          "in variance) with the delay's share\n", r.fit.blocks > 1 ? r.fit.blocks - 1 : 0, r.fit.blocks, r.fit.colour);
        std::fprintf(out, "  regressor condition number %.4g; %d solver iterations, %.3f s\n", r.fit.cond, r.fit.iterations,
                     r.fit.seconds);
        std::fprintf(out, "  controller's own model beside it: RMS(D5 - EXT1) %.4g A, mean EXT2 (inertia) %.4g\n", r.ext1_rms,
                     r.ext2_mean);
        for (const std::string &w : r.warnings) std::fprintf(out, "  warning: %s\n", w.c_str());
    }
}

int report_json(FILE *out, const Job &j)
{
    json_t *root = json_object();
    json_t *ins = json_array();
    for (const InputInfo &in : j.inputs) {
        json_t *o = json_pack("{s:s,s:s,s:I,s:I,s:b,s:b}", "path", in.path.c_str(), "format", in.format.c_str(),
                              "ticks", static_cast<json_int_t>(in.ticks), "sessions", static_cast<json_int_t>(in.sessions),
                              "kinematics", in.have_kin, "reply_times", in.reply_times);
        json_object_set_new(o, "num_gaps", json_integer(static_cast<json_int_t>(in.num_gaps)));
        json_object_set_new(o, "num_missing", json_integer(static_cast<json_int_t>(in.num_missing)));
        json_object_set_new(o, "num_dropped", json_integer(static_cast<json_int_t>(in.num_dups)));
        json_array_append_new(ins, o);
    }
    json_object_set_new(root, "inputs", ins);
    json_object_set_new(root, "loss", json_string(loss_name(j.opt.loss)));
    json_object_set_new(root, "seconds", json_real(j.seconds));
    json_t *axes = json_array();
    for (std::size_t k = 0; k < j.results.size(); k++) {
        const AxisResult &r = j.results[k];
        const AxisLog &L = j.logs[k];
        json_t *a = json_pack("{s:I,s:I,s:I,s:f,s:b}", "arm", static_cast<json_int_t>(r.arm), "axis",
                              static_cast<json_int_t>(r.axis), "open", static_cast<json_int_t>(r.open), "period_s", r.period,
                              "identifiable", r.identifiable);
        json_object_set_new(a, "az_lim", L.az_lim > 0.0 ? json_real(L.az_lim) : json_null());
        json_object_set_new(a, "az_lim_from", json_string(L.az_from));
        json_object_set_new(a, "ticks", json_pack("{s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I}", "seen", static_cast<json_int_t>(L.seen),
                                                  "kept", static_cast<json_int_t>(r.prep.kept), "drive_off",
                                                  static_cast<json_int_t>(L.dropped_drive), "special_mode",
                                                  static_cast<json_int_t>(L.dropped_mode), "nonfinite",
                                                  static_cast<json_int_t>(L.dropped_nonfinite), "window",
                                                  static_cast<json_int_t>(L.dropped_window), "standstill",
                                                  static_cast<json_int_t>(r.prep.dropped_still), "late_reply",
                                                  static_cast<json_int_t>(r.prep.dropped_late), "saturated",
                                                  static_cast<json_int_t>(r.prep.dropped_sat), "edges",
                                                  static_cast<json_int_t>(r.prep.dropped_edge)));
        json_object_set_new(json_object_get(a, "ticks"), "num_gap", json_integer(static_cast<json_int_t>(r.prep.dropped_gap)));
        if (!r.identifiable) {
            json_object_set_new(a, "why", json_string(r.why_not.c_str()));
            json_array_append_new(axes, a);
            continue;
        }
        json_object_set_new(a, "model", json_string(variant_ctrl(r.fit.variant) ? "ctrl" : "axis"));
        if (variant_ctrl(r.fit.variant)) json_object_set_new(a, "ks", json_real(r.prep.ks));
        json_object_set_new(a, "variant", json_string(variant_name[r.fit.variant]));
        json_object_set_new(a, "delay_ticks", json_real(r.prep.delay));
        json_object_set_new(a, "delay_sd_ticks", json_real(r.prep.delay_sd));
        json_object_set_new(a, "covariance_blocks", json_integer(r.fit.blocks));
        json_object_set_new(a, "residual_colour", json_real(r.fit.colour));
        json_object_set_new(a, "eps", json_real(r.prep.eps));
        json_object_set_new(a, "v_max", json_real(r.prep.vmax));
        json_object_set_new(a, "a_max", json_real(r.prep.amax));
        json_t *ps = json_object();
        for (int p = 0; p < NPARAM; p++) {
            const ParamStat &s = r.fit.st[static_cast<std::size_t>(p)];
            if (!s.free) continue;
            json_t *po = json_pack("{s:f,s:f,s:f,s:f,s:s}", "value", s.value, "sigma", s.sigma, "ci95", s.ci95, "sigma_pct",
                                   (s.pct < 1e299) ? s.pct : -1.0, "unit", param_unit_of(r.fit.variant, p));
            json_object_set_new(po, "sigma_white", json_real(s.sigma_white));
            json_object_set_new(po, "sigma_delay", json_real(s.sigma_delay));
            json_object_set_new(po, "at_bound", json_boolean(s.at_bound));
            json_object_set_new(ps, param_name_of(r.fit.variant, p), po);
        }
        json_object_set_new(a, "parameters", ps);
        json_t *vc = json_object();
        for (int v = 0; v < NVARIANT; v++) {
            if (r.tried[static_cast<std::size_t>(v)]) json_object_set_new(vc, variant_name[v], json_real(r.val_cost[static_cast<std::size_t>(v)]));
        }
        json_object_set_new(a, "heldout_cost", vc);
        json_object_set_new(a, "residual", json_pack("{s:f,s:f,s:f,s:f,s:f}", "rms", r.fit.rms, "rms_inlier", r.fit.rms_inlier,
                                                     "outlier_fraction", r.fit.outlier_frac, "sigma", r.fit.sigma, "noise_floor",
                                                     r.prep.noise_floor));
        if (r.val.n > 0) {
            json_object_set_new(a, "validation", json_pack("{s:I,s:f,s:f,s:f,s:f}", "samples", static_cast<json_int_t>(r.val.n),
                                                           "rms", r.val.rms, "rms_inlier", r.val.rms_inlier, "pct_peak",
                                                           r.val.pct_peak, "x_noise", r.val.x_noise));
        }
        json_object_set_new(a, "condition", json_real(r.fit.cond));
        json_object_set_new(a, "solver", json_pack("{s:i,s:f}", "iterations", r.fit.iterations, "seconds", r.fit.seconds));
        json_object_set_new(a, "covariance_ok", json_boolean(r.fit.cov_ok));
        json_object_set_new(a, "controller_model", json_pack("{s:f,s:f}", "rms_d5_minus_ext1", r.ext1_rms, "ext2_mean", r.ext2_mean));
        json_t *w = json_array();
        for (const std::string &s : r.warnings) json_array_append_new(w, json_string(s.c_str()));
        json_object_set_new(a, "warnings", w);
        json_array_append_new(axes, a);
    }
    json_object_set_new(root, "axes", axes);
    const int rc = json_dumpf(root, out, JSON_INDENT(2) | JSON_REAL_PRECISION(10));
    std::fputc('\n', out);
    json_decref(root);
    return rc;
}

std::string params_text(const Job &j, const std::string &version)
{
    std::ostringstream o;
    o.precision(10);
    unsigned arm = j.results.empty() ? 1 : j.results.front().arm;
    double period_ms = j.results.empty() ? 2.0 : j.results.front().period * 1e3;
    o << "# c4g-ident parameter file: the identified motor-side model of each axis of one arm.\n"
         "# i = Ja*a + Fv*v + (Fc + (Fs-Fc)*exp(-(v/vs)^2))*tanh(v/eps) + off + ga*cos(q) + gb*sin(q)\n"
         "# i [A], v [motor turn/s], a [motor turn/s^2], q link angle [rad] (library kinematics).\n"
         "# Units: Ja A/(turn/s^2), Fv A/(turn/s), Fc Fs off ga gb A, vs eps v_max turn/s,\n"
         "# a_max turn/s^2, delay ticks. An axis of model = ctrl corrects the controller's own model:\n"
         "# i = k1*(EXT1 - in) + k2*in + (friction as above) + off, in = ks*EXT2*2*pi*a, EXT1 [A] and\n"
         "# EXT2 [kg m^2] from the controller's packet, ks A/(N m). Edit nothing: the checksum covers every other line.\n"
         "[model]\nformat = c4g-ident 1\nmodel = motor-current-1\n";
    o << "arm = " << arm << "\nperiod_ms = " << period_ms << "\n";
    o << "source = ";
    for (std::size_t k = 0; k < j.inputs.size(); k++) o << (k ? " " : "") << j.inputs[k].path;
    o << "\ncreated_by = c4g-ident " << version << "\n";
    std::ostringstream body;
    body.precision(10);
    for (const AxisResult &r : j.results) {
        if (!r.identifiable) continue;
        const Vec &p = r.fit.p;
        const bool ctrl = variant_ctrl(r.fit.variant);
        body << "\n[axis " << r.axis << "]\nmodel = " << (ctrl ? "ctrl" : "axis") << "\nvariant = " << variant_name[r.fit.variant]
             << "\n";
        if (ctrl) body << "k1 = " << p[GA] << "\nk2 = " << p[GB] << "\nks = " << r.prep.ks << "\n";
        else body << "Ja = " << p[JA] << "\n";
        body << "Fv = " << p[FV] << "\nFc = " << p[FC] << "\n";
        if (variant_has(r.fit.variant, FS)) body << "Fs = " << p[FS] << "\nvs = " << p[VS] << "\n";
        body << "off = " << p[OFF] << "\n";
        if (variant_gravity(r.fit.variant)) body << "ga = " << p[GA] << "\ngb = " << p[GB] << "\n";
        body << "eps = " << r.prep.eps << "\ndelay = " << r.prep.delay << "\nv_max = " << r.prep.vmax << "\na_max = "
             << r.prep.amax << "\n";
    }
    // the checksum covers every byte but its own line
    const std::string without = o.str() + body.str();
    uint64_t sum = c4gh_ffm_fnv1a64(without.data(), without.size(), C4GH_FFM_FNV_BASIS);
    char line[64];
    std::snprintf(line, sizeof line, "checksum = fnv1a64:%016llx\n", static_cast<unsigned long long>(sum));
    return o.str() + line + body.str();
}

int write_params(const std::string &path, const Job &j, const std::string &version, std::string *err)
{
    const std::string text = params_text(j, version);
    FILE *f = std::fopen(path.c_str(), "w");
    if (f == nullptr) {
        *err = path + ": " + std::strerror(errno);
        return -1;
    }
    const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (std::fclose(f) != 0 || !ok) {
        *err = path + ": write error";
        return -1;
    }
    return 0;
}

// The samples axis k was fitted to: its log prepared again with the delay and eps found.
static Samples fitted_samples(const Job &j, std::size_t k)
{
    const AxisResult &r = j.results[k];
    Samples s;
    Options o = j.opt;
    o.delay_auto = false;
    o.delay = r.prep.delay;
    o.eps = r.prep.eps;
    (void)prepare(j.logs[k], o, &s);
    return s;
}

int write_samples(const std::string &dir, const Job &j, std::string *err)
{
    if (mkdir(dir.c_str(), 0777) != 0 && errno != EEXIST) {
        *err = dir + ": " + std::strerror(errno);
        return -1;
    }
    for (std::size_t k = 0; k < j.results.size(); k++) {
        const AxisResult &r = j.results[k];
        if (!r.identifiable) continue;
        const Samples s = fitted_samples(j, k);
        const std::string path = dir + "/arm" + std::to_string(r.arm) + "_axis" + std::to_string(r.axis) + ".csv";
        FILE *f = std::fopen(path.c_str(), "w");
        if (f == nullptr) {
            *err = path + ": " + std::strerror(errno);
            return -1;
        }
        std::fprintf(f, "# c4g-ident samples: arm %u axis %u variant %s eps %.17g delay %.6g fit_seconds %.6g\n", r.arm,
                     r.axis, variant_name[r.fit.variant], r.prep.eps, r.prep.delay, r.fit.seconds);
        // the ctrl family's last two columns are its regressors: EXT1 but its inertial part, that part
        std::fprintf(f, variant_ctrl(r.fit.variant) ? "v,a,i,ext1_less_in,in\n" : "v,a,i,cos_q,sin_q\n");
        for (std::size_t i = 0; i < s.n(); i++) {
            std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g\n", s.v[i], s.a[i], s.i[i], s.cq[i], s.sq[i]);
        }
        if (std::fclose(f) != 0) {
            *err = path + ": " + std::strerror(errno);
            return -1;
        }
    }
    return 0;
}

int write_plots(const std::string &dir, const Job &j, std::string *err)
{
    if (mkdir(dir.c_str(), 0777) != 0 && errno != EEXIST) {
        *err = dir + ": " + std::strerror(errno);
        return -1;
    }
    for (std::size_t k = 0; k < j.results.size(); k++) {
        const AxisResult &r = j.results[k];
        if (!r.identifiable) continue;
        const Samples s = fitted_samples(j, k);
        const std::string base = dir + "/arm" + std::to_string(r.arm) + "_axis" + std::to_string(r.axis);
        // data: t, i, predicted, residual, v, friction part of i (i - inertia - gravity - off)
        {
            std::ofstream d(base + ".dat");
            if (!d) {
                *err = base + ".dat: " + std::strerror(errno);
                return -1;
            }
            const std::size_t step = std::max<std::size_t>(1, s.n() / 20000);
            for (std::size_t i = 0; i < s.n(); i += step) {
                const double pr = model_eval(r.fit.p, r.prep.eps, s.v[i], s.a[i], s.cq[i], s.sq[i], nullptr);
                const double fr = s.i[i] - r.fit.p[JA] * s.a[i] - r.fit.p[GA] * s.cq[i] - r.fit.p[GB] * s.sq[i] - r.fit.p[OFF];
                d << s.t[i] - s.t[0] << ' ' << s.i[i] << ' ' << pr << ' ' << s.i[i] - pr << ' ' << s.v[i] << ' ' << fr << '\n';
            }
        }
        {
            // the fitted friction curve
            std::ofstream c(base + "_curve.dat");
            const double vm = std::max(r.prep.vmax, 1e-9);
            for (int i = -400; i <= 400; i++) {
                const double v = vm * i / 400.0;
                Vec p = r.fit.p;
                p[JA] = p[GA] = p[GB] = p[OFF] = 0.0;
                c << v << ' ' << model_eval(p, r.prep.eps, v, 0, 0, 0, nullptr) << '\n';
            }
        }
        const std::string name = axis_name(r);
        for (const char *term : {"pngcairo size 1000,700", "svg size 1000,700"}) {
            const std::string ext = (term[0] == 'p') ? "png" : "svg";
            std::ostringstream g;
            g << "set terminal " << term << "\nset grid\n";
            g << "set output '" << base << "_current." << ext << "'\nset title '" << name
              << ": measured vs predicted current'\nset xlabel 't [s]'\nset ylabel 'current [A]'\n"
              << "plot '" << base << ".dat' u 1:2 w l lw 1 t 'D5 measured', '' u 1:3 w l lw 1 t 'model'\n";
            g << "set output '" << base << "_residual." << ext << "'\nset title '" << name
              << ": residual histogram'\nset xlabel 'residual [A]'\nset ylabel 'samples'\nset style fill solid 0.5\n"
              << "bw = " << std::max(r.fit.sigma / 5.0, 1e-12) << "\nbin(x) = bw*floor(x/bw + 0.5)\n"
              << "plot '" << base << ".dat' u (bin($4)):(1.0) smooth freq w boxes t 'residual'\n";
            g << "set output '" << base << "_friction." << ext << "'\nset title '" << name
              << ": friction vs velocity'\nset xlabel 'v [turn/s]'\nset ylabel 'friction current [A]'\nset style fill empty\n"
              << "plot '" << base << ".dat' u 5:6 w dots t 'data (D5 - inertia - gravity - offset)', '" << base
              << "_curve.dat' u 1:2 w l lw 2 t 'fitted'\n";
            FILE *p = popen("gnuplot", "w");
            if (p == nullptr) {
                *err = "gnuplot: " + std::string(std::strerror(errno));
                return -1;
            }
            const std::string script = g.str();
            std::fwrite(script.data(), 1, script.size(), p);
            const int st = pclose(p);
            if (st != 0) {
                *err = "gnuplot failed for " + base + " (exit status " + std::to_string(WIFEXITED(st) ? WEXITSTATUS(st) : -1) + ")";
                return -1;
            }
        }
    }
    return 0;
}

// ---------------------------------------------------------------- the rigid family

namespace {

void rigid_inputs_text(FILE *out, const std::vector<InputInfo> &inputs)
{
    for (const InputInfo &in : inputs) {
        std::fprintf(out, "input %s: %s, %llu controller ticks, %llu session(s)%s\n", in.path.c_str(), in.format.c_str(),
                     static_cast<unsigned long long>(in.ticks), static_cast<unsigned long long>(in.sessions),
                     in.have_init_kin ? ", transmission from the init packet" : "");
        if (in.num_gaps > 0 || in.num_dups > 0) {
            std::fprintf(out, "  NUM sequence: %llu gap(s), %llu controller packet(s) missing; %llu repeated or out-of-order "
                              "packet(s) dropped\n",
                         static_cast<unsigned long long>(in.num_gaps), static_cast<unsigned long long>(in.num_missing),
                         static_cast<unsigned long long>(in.num_dups));
        }
    }
}

}  // namespace

void rigid_report_text(FILE *out, const RigidResult &r, const std::vector<InputInfo> &inputs, const Options &o,
                       const std::string &kin_path, const std::string &validate_path)
{
    rigid_inputs_text(out, inputs);
    std::fprintf(out, "model: rigid: i_k = sum_j (Kr^-T)_kj (Y_j(q,qd,qdd) theta + ia_j qdd_j) / kt_k + Fv_k*v_k + Fc_k*tanh(v_k/eps_k) + off_k\n");
    std::fprintf(out, "kinematics: %s, %d joints; transmission Kr from the init packet\n", kin_path.c_str(), r.n);
    std::fprintf(out, "fit: %s loss (scale %.3g sigma) in one weighted pass over the normal equations, Savitzky-Golay %d/%d, "
                      "validation: %s\n",
                 o.loss == LOSS_HUBER ? "huber" : (o.loss == LOSS_CAUCHY ? "cauchy" : "none"), o.loss_k, 2 * o.sg_half + 1,
                 o.sg_order,
                 validate_path.empty() ? (std::to_string(static_cast<int>(o.holdout * 100)) + " % held out at the end").c_str()
                                       : validate_path.c_str());
    std::fprintf(out, "ticks: %zu logged, %zu with every joint's state known\n", r.ticks, r.states);
    for (const RigidAxis &a : r.axes) {
        std::fprintf(out, "  axis %u: %zu currents used; dropped %llu standstill/reversal, %llu near a late PC reply, %llu near a "
                          "NUM gap, %llu saturated, %llu filter edges; eps %.4g turn/s, own delay %+.2f ticks%s\n",
                     a.axis, a.rows, static_cast<unsigned long long>(a.prep.dropped_still),
                     static_cast<unsigned long long>(a.prep.dropped_late), static_cast<unsigned long long>(a.prep.dropped_gap),
                     static_cast<unsigned long long>(a.prep.dropped_sat), static_cast<unsigned long long>(a.prep.dropped_edge),
                     a.prep.eps, a.prep.delay, a.prep.delay_at_bound ? " (at the end of its search: not used)" : "");
    }
    if (r.base.n == 0) {
        std::fprintf(out, "UNIDENTIFIABLE: %s\n", r.why_not.c_str());
        return;
    }
    std::fprintf(out, "delay of D5 after D4: %+.3f ticks (every axis)\n", r.delay);
    std::fprintf(out, "base parameters: %zu of %d (the others cannot be told apart by any motion: folded into the first "
                      "member of each combination)\n", r.base.base.size(), r.base.nfull);
    if (r.params.empty()) {
        std::fprintf(out, "UNIDENTIFIABLE: %s\n", r.why_not.c_str());
        return;
    }
    std::fprintf(out, "  %-3s %-44s %14s %12s %9s %s%s\n", "#", "parameter", "value", "+-95 %", "sigma %", "unit",
                 r.consistent ? "  consistent" : "");
    for (std::size_t k = 0; k < r.params.size(); k++) {
        const RigidParam &p = r.params[k];
        char pct[32];
        if (p.pct < 1e299) std::snprintf(pct, sizeof pct, "%9.3f", p.pct);
        else std::snprintf(pct, sizeof pct, "%9s", "-");
        std::fprintf(out, "  %-3zu %-44s %14.7g %12.4g %s %s%s", k + 1, p.name.c_str(), p.value, p.ci95, pct, p.unit.c_str(),
                     p.pinned ? "" : "  NOT PINNED");
        if (r.consistent) std::fprintf(out, "  %.7g", p.consistent);
        std::fputc('\n', out);
    }
    std::fprintf(out, "intervals: t(%d) x sigma, sigma the larger of white-noise and block-robust (%d spans)\n",
                 r.blocks > 1 ? r.blocks - 1 : 0, r.blocks);
    std::fprintf(out, "normal matrix condition number %.4g (columns scaled); %.3f s\n", r.cond, r.seconds);
    if (r.consistent) {
        std::fprintf(out, "consistent fit (every link's pseudo-inertia positive definite, log-Cholesky): the predicted currents "
                          "moved by %.3g noise sigmas RMS from the least-squares fit; the file holds the consistent values\n", r.moved);
    }
    std::fprintf(out, "per axis: %-8s %10s %12s %12s %10s\n", "axis", "sigma [A]", "noise [A]", "held-out [A]", "x noise");
    for (const RigidAxis &a : r.axes) {
        std::fprintf(out, "          %-8u %10.4g %12.4g %12.4g %10.3f", a.axis, a.sigma, a.prep.noise_floor, a.val.rms_inlier,
                     a.val.x_noise);
        if (r.consistent) std::fprintf(out, "  (least squares %.3f)", a.val_lin.x_noise);
        std::fputc('\n', out);
    }
    std::fprintf(out, "fitted range:\n");
    for (int j = 0; j < r.n; j++) {
        std::fprintf(out, "  joint %d: q %.4g .. %.4g rad, |qd| <= %.4g rad/s, |qdd| <= %.4g rad/s^2\n", j + 1, r.q_min[j],
                     r.q_max[j], r.qd_max[j], r.qdd_max[j]);
    }
    if (!r.identifiable) std::fprintf(out, "UNIDENTIFIABLE: %s\n", r.why_not.c_str());
    for (const std::string &w : r.warnings) std::fprintf(out, "warning: %s\n", w.c_str());
}

int rigid_report_json(FILE *out, const RigidResult &r, const std::vector<InputInfo> &inputs, const Options &o,
                      const std::string &kin_path, const std::string &validate_path)
{
    json_t *root = json_object();
    json_t *ins = json_array();
    for (const InputInfo &in : inputs) {
        json_array_append_new(ins, json_pack("{s:s,s:s,s:I,s:I,s:I}", "path", in.path.c_str(), "format", in.format.c_str(),
                                             "ticks", static_cast<json_int_t>(in.ticks), "num_gaps",
                                             static_cast<json_int_t>(in.num_gaps), "num_missing",
                                             static_cast<json_int_t>(in.num_missing)));
    }
    json_object_set_new(root, "inputs", ins);
    json_object_set_new(root, "model", json_string("rigid"));
    json_object_set_new(root, "kinematics", json_string(kin_path.c_str()));
    json_object_set_new(root, "validation", json_string(validate_path.empty() ? "holdout" : validate_path.c_str()));
    json_object_set_new(root, "holdout", json_real(o.holdout));
    json_object_set_new(root, "identifiable", json_boolean(r.identifiable));
    if (!r.why_not.empty()) json_object_set_new(root, "why", json_string(r.why_not.c_str()));
    json_object_set_new(root, "arm", json_integer(r.arm));
    json_object_set_new(root, "joints", json_integer(r.n));
    json_object_set_new(root, "delay_ticks", json_real(r.delay));
    json_object_set_new(root, "ticks", json_integer(static_cast<json_int_t>(r.ticks)));
    json_object_set_new(root, "states", json_integer(static_cast<json_int_t>(r.states)));
    json_object_set_new(root, "full_params", json_integer(r.base.nfull));
    json_object_set_new(root, "base_params", json_integer(static_cast<json_int_t>(r.base.base.size())));
    json_object_set_new(root, "covariance_blocks", json_integer(r.blocks));
    json_object_set_new(root, "condition", json_real(r.cond));
    json_object_set_new(root, "seconds", json_real(r.seconds));
    json_object_set_new(root, "consistent", json_boolean(r.consistent));
    if (r.consistent) json_object_set_new(root, "consistent_moved", json_real(r.moved));
    json_t *ps = json_array();
    for (const RigidParam &p : r.params) {
        json_t *po = json_pack("{s:s,s:f,s:f,s:f,s:f,s:s,s:b}", "name", p.name.c_str(), "value", p.value, "sigma", p.sigma,
                               "sigma_white", p.sigma_white, "ci95", p.ci95, "unit", p.unit.c_str(), "pinned", p.pinned);
        json_object_set_new(po, "reach", json_real(p.reach));
        json_object_set_new(po, "reach_axis", json_integer(p.reach_axis));
        if (r.consistent) json_object_set_new(po, "consistent", json_real(p.consistent));
        json_array_append_new(ps, po);
    }
    json_object_set_new(root, "parameters", ps);
    json_t *axes = json_array();
    for (const RigidAxis &a : r.axes) {
        json_t *ao = json_pack("{s:I,s:I,s:f,s:f,s:f,s:f}", "axis", static_cast<json_int_t>(a.axis), "rows",
                               static_cast<json_int_t>(a.rows), "sigma", a.sigma, "noise_floor", a.prep.noise_floor, "eps",
                               a.prep.eps, "own_delay_ticks", a.prep.delay);
        json_object_set_new(ao, "dropped", json_pack("{s:I,s:I,s:I,s:I,s:I}", "standstill",
                                                     static_cast<json_int_t>(a.prep.dropped_still), "late_reply",
                                                     static_cast<json_int_t>(a.prep.dropped_late), "num_gap",
                                                     static_cast<json_int_t>(a.prep.dropped_gap), "saturated",
                                                     static_cast<json_int_t>(a.prep.dropped_sat), "edges",
                                                     static_cast<json_int_t>(a.prep.dropped_edge)));
        json_object_set_new(ao, "validation", json_pack("{s:I,s:f,s:f,s:f,s:f}", "samples", static_cast<json_int_t>(a.val.n),
                                                        "rms", a.val.rms, "rms_inlier", a.val.rms_inlier, "pct_peak",
                                                        a.val.pct_peak, "x_noise", a.val.x_noise));
        if (r.consistent) {
            json_object_set_new(ao, "validation_least_squares", json_pack("{s:f,s:f}", "rms_inlier", a.val_lin.rms_inlier,
                                                                          "x_noise", a.val_lin.x_noise));
        }
        json_array_append_new(axes, ao);
    }
    json_object_set_new(root, "axes", axes);
    json_t *w = json_array();
    for (const std::string &s : r.warnings) json_array_append_new(w, json_string(s.c_str()));
    json_object_set_new(root, "warnings", w);
    const int rc = json_dumpf(root, out, JSON_INDENT(2) | JSON_REAL_PRECISION(10));
    std::fputc('\n', out);
    json_decref(root);
    return rc;
}

std::string rigid_params_text(const RigidResult &r, const c4gh_kinfile_t &kf, const std::vector<InputInfo> &inputs,
                              const std::string &version)
{
    std::ostringstream o;
    o.precision(17);
    o << "# c4g-ident parameter file: the rigid-body model of one arm (c4g-ident fit --model rigid).\n"
         "# i_k = sum_j (Kr^-T)_kj (tau_j) / kt_k + Fv*v + (Fc + (Fs-Fc)*exp(-(v/vs)^2))*tanh(v/eps) + off,\n"
         "# tau = RNEA(q, qd, qdd; [joint N] m..Izz) + ia*qdd, Kr from the init packet. Link parameters\n"
         "# about each link frame's origin [kg, kg m, kg m^2]: the base-parameter solution with the members\n"
         "# no motion separates set to 0 (the torques are exact, the single values need not be physical).\n"
         "# Friction in A per motor as model = axis. Edit nothing: the checksum covers every other line.\n"
         "[model]\nformat = c4g-ident 1\nmodel = rigid-body-1\n";
    o << "arm = " << r.arm << "\nperiod_ms = " << r.period * 1e3 << "\n";
    o << "source = ";
    for (std::size_t k = 0; k < inputs.size(); k++) o << (k ? " " : "") << inputs[k].path;
    o << "\ncreated_by = c4g-ident " << version << "\n";
    std::ostringstream body;
    body.precision(17);
    body << "range = clamp\nconsistent = " << (r.consistent ? 1 : 0) << "\nbase_params = " << r.base.base.size() << "\n";
    body << "\n[kinematics]\nconvention = " << (kf.conv == C4G_DYN_DH_MODIFIED ? "modified" : "standard")
         << "\nangles = " << (kf.deg ? "deg" : "rad") << "\ngravity = " << kf.gravity[0] << " " << kf.gravity[1] << " "
         << kf.gravity[2] << "\n";
    static const char *const pn[kRigidPerLink] = {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
    for (int j = 0; j < r.n; j++) {
        const c4gh_kin_joint_t &J = kf.j[j];
        body << "\n[joint " << j + 1 << "]\na = " << J.a << "\nalpha = " << J.alpha << "\nd = " << J.d << "\ntheta0 = " << J.theta0
             << "\nkt = " << J.kt << "\n";
        const std::vector<double> &th = r.consistent ? r.theta_consistent : r.theta;
        for (int p = 0; p < kRigidPerLink; p++) body << pn[p] << " = " << th[static_cast<std::size_t>(kRigidPerLink * j + p)] << "\n";
        body << "ia = " << th[static_cast<std::size_t>(kRigidPerLink * r.n + j)] << "\n";
        body << "q_min = " << r.q_min[j] << "\nq_max = " << r.q_max[j] << "\nqd_max = " << r.qd_max[j] << "\nqdd_max = "
             << r.qdd_max[j] << "\n";
    }
    const std::size_t nb = r.base.base.size();
    for (int k = 0; k < r.n; k++) {
        const RigidAxis &a = r.axes[static_cast<std::size_t>(k)];
        const std::size_t f = nb + 3 * static_cast<std::size_t>(k);
        auto v = [&](std::size_t i) { return r.consistent ? r.params[i].consistent : r.params[i].value; };
        body << "\n[axis " << k + 1 << "]\nFv = " << v(f) << "\nFc = " << v(f + 1) << "\noff = " << v(f + 2) << "\neps = " << a.prep.eps
             << "\n";
    }
    const std::string without = o.str() + body.str();
    const uint64_t sum = c4gh_ffm_fnv1a64(without.data(), without.size(), C4GH_FFM_FNV_BASIS);
    char line[64];
    std::snprintf(line, sizeof line, "checksum = fnv1a64:%016llx\n", static_cast<unsigned long long>(sum));
    return o.str() + line + body.str();
}

}  // namespace ident
