// SPDX-License-Identifier: MIT
// c4g-ident: friction and inertia of each axis from logged runs (Ceres Solver), written as
// the parameter file c4g-server's mode 9 (current feedforward) applies; and the excitation
// trajectory to record a good identification run.
//   c4g-ident fit [OPTIONS] LOG...      c4g-ident excite [OPTIONS] -o TRAJ.csv
#include "excite.hpp"
#include "ident.hpp"
#include "optexcite.hpp"
#include "input.hpp"
#include "output.hpp"
#include "rigid.hpp"

extern "C" {
#include "c4gh_cli.h"
#include "c4gh_kinfile.h"
#include "c4gopen.h"
#include "c4gsim_fixtures.h"
}

#include <Eigen/Dense>
#include <jansson.h>

#include <ceres/version.h>
#include <glog/logging.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <algorithm>
#include <thread>
#include <mutex>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace ident;

namespace {

const char *const kTool = "c4g-ident";

// The items of a comma-separated option value, empty ones included (so they can be named).
std::vector<std::string> split_commas(const char *v)
{
    std::vector<std::string> out;
    const std::string s(v);
    std::size_t b = 0;
    for (;;) {
        const std::size_t e = s.find(',', b);
        out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
        if (e == std::string::npos) return out;
        b = e + 1;
    }
}

// A logical axis 1..kMaxAxes; false (and why) otherwise.
bool parse_axis(const std::string &t, long *axis, char *why, size_t whylen)
{
    char *end = nullptr;
    *axis = std::strtol(t.c_str(), &end, 10);
    if (t.empty() || *end != '\0' || *axis < 1 || *axis > static_cast<long>(kMaxAxes)) {
        std::snprintf(why, whylen, "'%s' is not a logical axis 1..%u", t.c_str(), kMaxAxes);
        return false;
    }
    return true;
}

int parse_axes(const char *v, unsigned *mask, char *why, size_t whylen)
{
    *mask = 0;
    for (const std::string &t : split_commas(v)) {
        long n = 0;
        if (!parse_axis(t, &n, why, whylen)) return -1;
        *mask |= 1U << (n - 1);
    }
    return 0;
}

// ---------------------------------------------------------------- fit
struct FitCli {
    Selection sel;
    Options opt;
    char out[1024] = "";
    char plot[1024] = "";
    char samples[1024] = "";
    char validate[1024] = "";
    char kin[1024] = "";
    int json = 0, quiet = 0, no_gravity = 0, keep_late = 0, consistent = 0;
    bool rigid = false;        // --model rigid
};

int fit_axes(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    return parse_axes(v, &static_cast<FitCli *>(ctx)->sel.axes, why, whylen);
}

// --az-lim A or AXIS:A[,AXIS:A...]: one limit for every axis, or one per logical axis
int fit_az_lim(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    double *lim = static_cast<FitCli *>(ctx)->sel.az_lim;
    const std::vector<std::string> items = split_commas(v);
    std::fill(lim, lim + kMaxAxes, 0.0);
    for (const std::string &t : items) {
        const std::size_t colon = t.find(':');
        long axis = 0;
        if (colon == std::string::npos && items.size() > 1) {
            std::snprintf(why, whylen, "'%s': want A for every axis, or AXIS:A pairs", t.c_str());
            return -1;
        }
        if (colon != std::string::npos && !parse_axis(t.substr(0, colon), &axis, why, whylen)) return -1;
        const std::string num = (colon == std::string::npos) ? t : t.substr(colon + 1);
        char *end = nullptr;
        const double a = std::strtod(num.c_str(), &end);
        if (num.empty() || *end != '\0' || !std::isfinite(a) || a <= 0.0 || a > 1000.0) {
            std::snprintf(why, whylen, "'%s' is not a current limit in A (0..1000)", num.c_str());
            return -1;
        }
        if (axis == 0) std::fill(lim, lim + kMaxAxes, a);
        else lim[axis - 1] = a;
    }
    return 0;
}

int fit_loss(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    Options &o = static_cast<FitCli *>(ctx)->opt;
    if (std::strcmp(v, "huber") == 0) o.loss = LOSS_HUBER;
    else if (std::strcmp(v, "cauchy") == 0) o.loss = LOSS_CAUCHY;
    else if (std::strcmp(v, "none") == 0) o.loss = LOSS_NONE;
    else {
        std::snprintf(why, whylen, "huber, cauchy or none");
        return -1;
    }
    return 0;
}

int fit_model(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    FitCli &c = *static_cast<FitCli *>(ctx);
    c.rigid = false;
    c.opt.ctrl = false;
    if (std::strcmp(v, "ctrl") == 0) c.opt.ctrl = true;
    else if (std::strcmp(v, "rigid") == 0) c.rigid = true;
    else if (std::strcmp(v, "axis") != 0) {
        std::snprintf(why, whylen, "axis, ctrl or rigid");
        return -1;
    }
    return 0;
}

int fit_variant(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    Options &o = static_cast<FitCli *>(ctx)->opt;
    if (std::strcmp(v, "auto") == 0) {
        o.force_variant = -1;
        return 0;
    }
    for (int k = 0; k < NVARIANT; k++) {
        if (std::strcmp(v, variant_name[k]) == 0) {
            o.force_variant = k;
            return 0;
        }
    }
    std::snprintf(why, whylen, "auto, coulomb, coulomb+gravity, stribeck, stribeck+gravity, ctrl+coulomb or ctrl+stribeck");
    return -1;
}

int fit_delay(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    Options &o = static_cast<FitCli *>(ctx)->opt;
    if (std::strcmp(v, "auto") == 0) {
        o.delay_auto = true;
        return 0;
    }
    char *end = nullptr;
    const double d = std::strtod(v, &end);
    if (*end != '\0' || !std::isfinite(d) || d < -3.0 || d > 3.0) {
        std::snprintf(why, whylen, "auto or a number of ticks in -3..3");
        return -1;
    }
    o.delay_auto = false;
    o.delay = d;
    return 0;
}

// --plot DIR: an existing writable directory, or one that can be made
bool plot_dir_writable(const char *tool, const char *dir)
{
    struct stat st;
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode)) {
            c4gh_cli_file_error(tool, "--plot", dir, ENOTDIR);
            return false;
        }
        if (access(dir, W_OK | X_OK) != 0) {
            c4gh_cli_file_error(tool, "--plot", dir, errno);
            return false;
        }
        return true;
    }
    return c4gh_cli_check_output(tool, "--plot", dir) == 0;
}

// --model rigid once the logs are read: one fit of the whole arm, its report and file.
int run_rigid(const FitCli &c, const c4gh_kinfile_t &kf, const Job &job, std::vector<AxisLog> &logs,
              std::vector<AxisLog> *vlogs, std::chrono::steady_clock::time_point t0)
{
    const bool tty = isatty(2);
    if (tty) std::fprintf(stderr, "\r%s: fitting the rigid-body model of arm %u\033[K", kTool, c.sel.arm);
    RigidResult r = identify_rigid(logs, job.inputs.front().kin, kf, vlogs, c.opt, c.consistent != 0);
    if (tty) std::fprintf(stderr, "\r\033[K");
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!c.quiet) {
        if (c.json) rigid_report_json(stdout, r, job.inputs, c.opt, c.kin, job.validate_path);
        else rigid_report_text(stdout, r, job.inputs, c.opt, c.kin, job.validate_path);
    }
    if (!r.identifiable) {
        if (c.out[0] != '\0') std::fprintf(stderr, "%s: the arm is not identified (%s): --out %s not written\n", kTool,
                                           r.why_not.c_str(), c.out);
        return 3;
    }
    if (c.out[0] != '\0') {
        const std::string text = rigid_params_text(r, kf, job.inputs, C4G_VERSION_STRING);
        FILE *f = std::fopen(c.out, "w");
        const bool ok = f != nullptr && std::fwrite(text.data(), 1, text.size(), f) == text.size();
        if (f == nullptr || std::fclose(f) != 0 || !ok) {
            std::fprintf(stderr, "%s: %s: %s\n", kTool, c.out, f == nullptr ? std::strerror(errno) : "write error");
            return C4GH_CLI_EXIT_RUNTIME;
        }
    }
    return C4GH_CLI_EXIT_OK;
}

int run_fit(int argc, char **argv)
{
    FitCli c;
    double holdout = 0.2, loss_k = 1.345, eps = 0.0, from = 0.0, to = -1.0;
    unsigned arm = 1, half = 12, order = 3, threads = 2, session = 0;
    const c4gh_cli_opt_t opts[] = {
        {"arm", 'a', C4GH_CLI_UINT, "N", "arm 1..4 (default 1)", &arm, 0, 1, 4, nullptr, 0},
        {"axes", 'x', C4GH_CLI_CALL, "LIST", "logical axes, e.g. 1,2,3 (default: every open axis)", nullptr, 0, 0, 0, fit_axes, 0},
        {"from", 0, C4GH_CLI_DOUBLE, "S", "use ticks from S seconds after the first one", &from, 0, 0, 1e7, nullptr, 0},
        {"to", 0, C4GH_CLI_DOUBLE, "S", "... up to S seconds after the first one", &to, 0, 0, 1e7, nullptr, 0},
        {"session", 0, C4GH_CLI_UINT, "N", "captures: only session N (default all)", &session, 0, 1, 1e6, nullptr, 0},
        {"validate", 0, C4GH_CLI_STRING, "LOG", "validate on a second log instead of the last 20 %", c.validate, sizeof c.validate, 0, 0, nullptr, 0},
        {"holdout", 0, C4GH_CLI_DOUBLE, "F", "share held out at the end for validation (default 0.2)", &holdout, 0, 0.05, 0.5, nullptr, 0},
        {"model", 0, C4GH_CLI_CALL, "FAMILY", "axis (default: Ja*a + friction + gravity), ctrl (k1*EXT1 + k2*EXT2 inertia + friction: corrects the controller's own model) or rigid (the arm's rigid-body model: needs --kin and a capture)", nullptr, 0, 0, 0, fit_model, 0},
        {"kin", 0, C4GH_CLI_STRING, "FILE", "--model rigid: the arm's kinematics file (DH parameters, gravity, kt)", c.kin, sizeof c.kin, 0, 0, nullptr, 0},
        {"consistent", 0, C4GH_CLI_FLAG, nullptr, "--model rigid: also the physically consistent fit (every link's pseudo-inertia positive definite)", &c.consistent, 0, 0, 0, nullptr, 0},
        {"variant", 0, C4GH_CLI_CALL, "NAME", "auto (default: chosen on held-out data), coulomb, stribeck, ...+gravity; ctrl+coulomb, ctrl+stribeck", nullptr, 0, 0, 0, fit_variant, 0},
        {"keep-late", 0, C4GH_CLI_FLAG, nullptr, "keep the ticks after a late or missing PC reply (a moni CSV cannot tell them)", &c.keep_late, 0, 0, 0, nullptr, 0},
        {"az-lim", 0, C4GH_CLI_CALL, "A|AXIS:A,...", "CSV logs: the DSA current limit (AzLim) of every axis or of each; ticks at 98 % of it are dropped", nullptr, 0, 0, 0, fit_az_lim, 0},
        {"no-gravity", 0, C4GH_CLI_FLAG, nullptr, "never offer the gravity variants", &c.no_gravity, 0, 0, 0, nullptr, 0},
        {"loss", 0, C4GH_CLI_CALL, "NAME", "robust loss: huber (default), cauchy or none", nullptr, 0, 0, 0, fit_loss, 0},
        {"loss-scale", 0, C4GH_CLI_DOUBLE, "K", "robust scale in noise sigmas (default 1.345)", &loss_k, 0, 0.1, 100, nullptr, 0},
        {"sg-half", 0, C4GH_CLI_UINT, "N", "Savitzky-Golay half window in ticks (default 12)", &half, 0, 2, 200, nullptr, 0},
        {"sg-order", 0, C4GH_CLI_UINT, "N", "Savitzky-Golay polynomial order 2..6 (default 3)", &order, 0, 2, 6, nullptr, 0},
        {"delay", 0, C4GH_CLI_CALL, "TICKS", "delay of D5 after D4: auto (default) or ticks", nullptr, 0, 0, 0, fit_delay, 0},
        {"eps", 0, C4GH_CLI_DOUBLE, "V", "smooth-sign velocity [turn/s] (default automatic)", &eps, 0, 0, 1e4, nullptr, 0},
        {"threads", 'j', C4GH_CLI_UINT, "N", "axes fitted at once, or solver threads for one axis (default 2)", &threads, 0, 1, 64, nullptr, 0},
        {"out", 'o', C4GH_CLI_STRING, "FILE", "write the parameter file for c4g-server --ff", c.out, sizeof c.out, 0, 0, nullptr, 0},
        {"plot", 0, C4GH_CLI_STRING, "DIR", "write PNG and SVG plots (gnuplot) into DIR", c.plot, sizeof c.plot, 0, 0, nullptr, 0},
        {"samples", 0, C4GH_CLI_STRING, "DIR", "write the samples each axis was fitted to (CSV) into DIR", c.samples, sizeof c.samples, 0, 0, nullptr, 0},
        {"json", 0, C4GH_CLI_FLAG, nullptr, "the report as JSON on stdout", &c.json, 0, 0, 0, nullptr, 0},
        {"quiet", 'q', C4GH_CLI_FLAG, nullptr, "no report", &c.quiet, 0, 0, 0, nullptr, 0},
    };
    static const char *const examples[] = {
        "c4g-ident fit run.pcap -o arm1.ini",
        "c4g-ident fit --axes 1,2 --json run.pcap > fit.json",
        "c4g-ident fit --validate run2.pcap --plot plots run1.pcap",
        "c4g-ident fit --arm 1 moni.csv          # c4g-server --moni-type 0 CSV",
        "c4g-ident fit --az-lim 1:24.5,4:9.5 moni.csv   # AzLim as c4g-replay summary shows it",
        "c4g-ident fit --model ctrl --axes 1-3 arm.pcap -o arm1-ctrl.ini   # correct EXT1/EXT2",
        "c4g-ident fit --model rigid --kin fixtures/ident/smart-six.kin arm.pcap -o arm1-rigid.ini",
        nullptr};
    c4gh_cli_spec_t spec = {"c4g-ident fit", C4G_VERSION_STRING,
                       "Usage: c4g-ident fit [OPTIONS] LOG...\n"
                       "Fits each axis' inertia, friction (viscous, Coulomb, Stribeck), offset and gravity from\n"
                       "logged runs: captures (pcap, pcapng), c4g-server --moni CSV (--moni-type 0) or\n"
                       "c4g-replay export CSV. Several LOGs are fitted together. Only drive-on ticks outside\n"
                       "special modes are used; the report says how many were kept and why the rest were not.\n"
                       "--model rigid --kin FILE fits the whole arm's rigid-body model (base parameters, each\n"
                       "motor's friction and offset) from captures: their init packet gives the transmission.",
                       opts, sizeof opts / sizeof opts[0], examples,
                       "Exit status: 0 every selected axis identified; 1 a file could not be written; 2 bad\n"
                       "usage or an unreadable log; 3 an axis could not be identified (reported, not fitted;\n"
                       "when none was, no --out file is written).",
                       1, -1, 1, nullptr};
    int first = 0;
    const c4gh_cli_result_t r = c4gh_cli_parse(&spec, &c, argc, argv, &first);
    if (r == C4GH_CLI_DONE) return C4GH_CLI_EXIT_OK;
    if (r == C4GH_CLI_BAD) return C4GH_CLI_EXIT_USAGE;
    c.sel.arm = arm;
    c.sel.from = from;
    c.sel.to = to;
    c.sel.session = session;
    c.sel.progress = true;
    c.sel.keep_late = c.keep_late != 0;
    c.opt.holdout = holdout;
    c.opt.loss_k = loss_k;
    c.opt.eps = eps;
    c.opt.sg_half = static_cast<int>(half);
    c.opt.sg_order = static_cast<int>(order);
    c.opt.threads = static_cast<int>(threads);
    c.opt.want_gravity = !c.no_gravity;
    if (c.no_gravity && c.opt.force_variant >= 0 && variant_gravity(static_cast<Variant>(c.opt.force_variant))) {
        c4gh_cli_error(&spec, "--no-gravity and --variant %s contradict each other", variant_name[c.opt.force_variant]);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (c.opt.force_variant >= 0 && c.opt.ctrl != variant_ctrl(static_cast<Variant>(c.opt.force_variant)) &&
        (variant_gravity(static_cast<Variant>(c.opt.force_variant)) || !c.opt.ctrl)) {
        c4gh_cli_error(&spec, "--variant %s is not a variant of --model %s", variant_name[c.opt.force_variant],
                       c.opt.ctrl ? "ctrl" : "axis");
        return C4GH_CLI_EXIT_USAGE;
    }
    if ((c.kin[0] != '\0' || c.consistent) && !c.rigid) {
        c4gh_cli_error(&spec, "%s applies to --model rigid", c.kin[0] != '\0' ? "--kin" : "--consistent");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (c.rigid && c.kin[0] == '\0') {
        c4gh_cli_error(&spec, "--model rigid needs the arm's kinematics: --kin FILE (docs/c4g-ident.md)");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (c.rigid && (c.plot[0] != '\0' || c.samples[0] != '\0')) {
        c4gh_cli_error(&spec, "--%s does not apply to --model rigid (its report and --json say what the fit found)",
                       c.plot[0] != '\0' ? "plot" : "samples");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (c.rigid && (c.sel.axes != 0 || c.opt.force_variant >= 0 || c.no_gravity)) {
        c4gh_cli_error(&spec, "--model rigid fits every joint of the kinematics file with its own friction: --%s does not apply",
                       c.sel.axes != 0 ? "axes" : (c.no_gravity ? "no-gravity" : "variant"));
        return C4GH_CLI_EXIT_USAGE;
    }
    if (to >= 0.0 && to <= from) {
        c4gh_cli_error(&spec, "--to %g must be after --from %g", to, from);
        return C4GH_CLI_EXIT_USAGE;
    }
    // output paths are checked before any work: a file that could not be written is exit 1
    if (c.out[0] != '\0' && c4gh_cli_check_output(spec.tool, "--out", c.out) != 0) {
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (c.plot[0] != '\0' && !plot_dir_writable(spec.tool, c.plot)) {
        return C4GH_CLI_EXIT_RUNTIME;
    }
    c4gh_kinfile_t kf{};
    if (c.rigid) {
        char kerr[512];
        if (c4gh_kin_load(c.kin, &kf, kerr, sizeof kerr) != 0) {
            std::fprintf(stderr, "%s: --kin %s\n", kTool, kerr);
            return C4GH_CLI_EXIT_USAGE;
        }
        c.sel.axes = 0;
        c.sel.lean = true;
    }
    const auto t0 = std::chrono::steady_clock::now();
    Job job;
    job.opt = c.opt;
    std::vector<AxisLog> merged;
    for (int i = first; i < argc; i++) {
        std::vector<AxisLog> logs;
        InputInfo info;
        std::string err;
        if (read_input(argv[i], c.sel, &logs, &info, &err) != 0) {
            std::fprintf(stderr, "%s: %s\n", kTool, err.c_str());
            return C4GH_CLI_EXIT_USAGE;
        }
        if (c.rigid && !info.have_init_kin) {
            // the rigid model maps joint torques to motor currents through Kr (wrist coupling
            // included), which only a capture's initialization packet carries
            std::fprintf(stderr, "%s: --model rigid: %s: %s without the init packet's transmission (Kr): the rigid model "
                                 "needs a capture (pcap, pcapng) that holds the initialization packet\n",
                         kTool, argv[i], info.format.c_str());
            return C4GH_CLI_EXIT_USAGE;
        }
        job.inputs.push_back(info);
        // several logs: one run after another, never filtered across the seam
        for (AxisLog &L : logs) {
            AxisLog *dst = nullptr;
            for (AxisLog &M : merged) {
                if (M.axis == L.axis) dst = &M;
            }
            if (dst == nullptr) {
                merged.push_back(std::move(L));  // a copy would double the samples' memory
                continue;
            }
            const int64_t shift = (dst->tick.empty() ? 0 : dst->tick.back() + 1000) - (L.tick.empty() ? 0 : L.tick.front());
            const double tshift = (dst->t.empty() ? 0 : dst->t.back() + 1.0) - (L.t.empty() ? 0 : L.t.front());
            for (std::size_t k = 0; k < L.tick.size(); k++) {
                dst->tick.push_back(L.tick[k] + shift);
                dst->d3.push_back(L.d3[k]); dst->d4.push_back(L.d4[k]); dst->d5.push_back(L.d5[k]);
                dst->q.push_back(L.q[k]);
                if (L.lean) continue;
                dst->t.push_back(L.t[k] + tshift);
                dst->d1.push_back(L.d1[k]); dst->d2.push_back(L.d2[k]);
                dst->e1.push_back(L.e1[k]); dst->e2.push_back(L.e2[k]);
            }
            for (int64_t lt : L.late_ticks) dst->late_ticks.push_back(lt + shift);
            dst->have_q = dst->have_q && L.have_q;
            dst->seen += L.seen; dst->dropped_drive += L.dropped_drive; dst->dropped_mode += L.dropped_mode;
            dst->dropped_nonfinite += L.dropped_nonfinite; dst->dropped_window += L.dropped_window;
        }
    }
    if (merged.empty()) {
        std::fprintf(stderr, "%s: no axis of arm %u%s in the log(s)\n", kTool, arm, c.sel.axes ? " among --axes" : "");
        return C4GH_CLI_EXIT_USAGE;
    }
    // every axis asked for must be in the logs: one left out silently would pass for fitted
    for (unsigned k = 0; k < kMaxAxes; k++) {
        if (((c.sel.axes >> k) & 1U) == 0U) continue;
        bool found = false;
        std::string have;
        for (const AxisLog &M : merged) {
            found = found || M.axis == k + 1U;
            have += (have.empty() ? "" : ",") + std::to_string(M.axis);
        }
        if (!found) {
            std::fprintf(stderr, "%s: --axes: axis %u of arm %u is not in the log(s) (they carry axes %s)\n", kTool, k + 1U,
                         arm, have.c_str());
            return C4GH_CLI_EXIT_USAGE;
        }
    }
    std::vector<AxisLog> vlogs;
    if (c.validate[0] != '\0') {
        InputInfo info;
        std::string err;
        if (read_input(c.validate, c.sel, &vlogs, &info, &err) != 0) {
            std::fprintf(stderr, "%s: --validate %s\n", kTool, err.c_str());
            return C4GH_CLI_EXIT_USAGE;
        }
        job.validate_path = c.validate;
    }
    if (c.rigid) return run_rigid(c, kf, job, merged, c.validate[0] != '\0' ? &vlogs : nullptr, t0);
    const bool tty = isatty(2);
    bool all_ok = true;
    // Axes are independent: --threads workers take them in turn, each fit single-threaded
    // (one axis per core beats one fit spread over the cores: less synchronisation).
    job.results.assign(merged.size(), AxisResult());
    {
        const unsigned workers = std::max(1U, std::min(threads, static_cast<unsigned>(merged.size())));
        Options one = c.opt;
        one.threads = (workers > 1U) ? 1 : c.opt.threads;
        std::atomic<std::size_t> next(0), done(0);
        std::mutex progress;
        auto work = [&]() {
            for (std::size_t k = next++; k < merged.size(); k = next++) {
                const AxisLog *val = nullptr;
                for (const AxisLog &V : vlogs) {
                    if (V.axis == merged[k].axis) val = &V;
                }
                job.results[k] = identify(merged[k], val, one);
                const std::size_t d = ++done;
                if (tty) {
                    std::lock_guard<std::mutex> lk(progress);
                    std::fprintf(stderr, "\r%s: fitted %zu of %zu axes of arm %u\033[K", kTool, d, merged.size(), arm);
                }
            }
        };
        if (tty) std::fprintf(stderr, "\r%s: fitting %zu axes of arm %u\033[K", kTool, merged.size(), arm);
        std::vector<std::thread> pool;
        for (unsigned w = 1; w < workers; w++) pool.emplace_back(work);
        work();
        for (std::thread &t : pool) t.join();
    }
    for (const AxisResult &R : job.results) all_ok = all_ok && R.identifiable;
    if (tty) std::fprintf(stderr, "\r\033[K");
    job.logs = merged;
    job.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!c.quiet) {
        if (c.json) report_json(stdout, job);
        else report_text(stdout, job);
    }
    std::string err;
    bool any = false;
    for (const AxisResult &R : job.results) any = any || R.identifiable;
    if (c.out[0] != '\0' && !any) {
        // a file without axes would only be refused by c4g-server later
        std::fprintf(stderr, "%s: no axis identified: --out %s not written\n", kTool, c.out);
        return 3;
    }
    if (c.out[0] != '\0' && write_params(c.out, job, C4G_VERSION_STRING, &err) != 0) {
        std::fprintf(stderr, "%s: %s\n", kTool, err.c_str());
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (c.plot[0] != '\0' && write_plots(c.plot, job, &err) != 0) {
        std::fprintf(stderr, "%s: --plot: %s\n", kTool, err.c_str());
        return C4GH_CLI_EXIT_RUNTIME;
    }
    if (c.samples[0] != '\0' && write_samples(c.samples, job, &err) != 0) {
        std::fprintf(stderr, "%s: --samples: %s\n", kTool, err.c_str());
        return C4GH_CLI_EXIT_RUNTIME;
    }
    return all_ok ? C4GH_CLI_EXIT_OK : 3;
}

// ---------------------------------------------------------------- excite
struct ExCli {
    unsigned axes = 0;
    char out[1024] = "";
    char vmax[256] = "10";
    char amax[256] = "200";
    // --optimize
    int optimize = 0, json = 0;
    char kin[1024] = "";
    char init[1024] = "";
    char start[512] = "";
    char q_min[512] = "", q_max[512] = "", qd_max[512] = "", qdd_max[512] = "";
};

int ex_axes(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    return parse_axes(v, &static_cast<ExCli *>(ctx)->axes, why, whylen);
}

// "V" or "V1,V2,..." (per excited axis, in order)
bool list(const char *s, std::vector<double> *out);

// --optimize: the Fourier excitation of the rigid-body model (optexcite.hpp)
struct OptCli {
    double f0, period;
    unsigned harmonics, seed, periods, evals;
};
int run_optimize(const c4gh_cli_spec_t &spec, const ExCli &c, const OptCli &o);

bool list(const char *s, std::vector<double> *out)
{
    out->clear();
    std::string t(s);
    std::size_t b = 0;
    for (;;) {
        const std::size_t e = t.find(',', b);
        const std::string x = t.substr(b, e == std::string::npos ? std::string::npos : e - b);
        char *end = nullptr;
        const double d = std::strtod(x.c_str(), &end);
        if (x.empty() || *end != '\0' || !std::isfinite(d) || d <= 0.0 || d > 1e5) return false;
        out->push_back(d);
        if (e == std::string::npos) return true;
        b = e + 1;
    }
}

int run_excite(int argc, char **argv)
{
    ExCli c;
    // -1 / 0: not given (the defaults differ with --optimize, and some options do not apply)
    double duration = -1.0, period = -1.0, f0 = 0.1, stair = -1.0;
    unsigned harmonics = 0, seed = 1, periods = 0, evals = 0;
    const c4gh_cli_opt_t opts[] = {
        {"axes", 'x', C4GH_CLI_CALL, "LIST", "logical axes to excite (default 1,2,3,4,5,6)", nullptr, 0, 0, 0, ex_axes, 0},
        {"vmax", 0, C4GH_CLI_STRING, "V[,V...]", "velocity limit [motor turn/s], one or one per axis (default 10)", c.vmax, sizeof c.vmax, 0, 0, nullptr, 0},
        {"amax", 0, C4GH_CLI_STRING, "A[,A...]", "acceleration limit [motor turn/s^2] (default 200)", c.amax, sizeof c.amax, 0, 0, nullptr, 0},
        {"duration", 'd', C4GH_CLI_DOUBLE, "S", "length [s] (default 38: 19000 rows at 2 ms)", &duration, 0, 2, 36000, nullptr, 0},
        {"period", 'T', C4GH_CLI_DOUBLE, "MS", "row spacing [ms]: the controller's period (-T 1 at 1 kHz); default 2, or "
         "--init's period", &period, 0, 0.1, 100, nullptr, 0},
        {"f0", 0, C4GH_CLI_DOUBLE, "HZ", "multi-sine fundamental, or the Fourier series' base frequency (default 0.1)", &f0, 0, 0.001, 100, nullptr, 0},
        {"harmonics", 0, C4GH_CLI_UINT, "N", "multi-sine harmonics (default 16), or the series' (with --optimize: default 8, 2..20)", &harmonics, 0, 1, 200, nullptr, 0},
        {"stair", 0, C4GH_CLI_DOUBLE, "F", "share of the time in constant-speed runs (default 0.3)", &stair, 0, 0, 0.9, nullptr, 0},
        {"seed", 0, C4GH_CLI_UINT, "N", "phase seed, or the search's seed (default 1)", &seed, 0, 0, 1e9, nullptr, 0},
        {"out", 'o', C4GH_CLI_STRING, "FILE", "trajectory CSV for c4g-server --traj (default stdout; required with --optimize)", c.out, sizeof c.out, 0, 0, nullptr, 0},
        {"optimize", 0, C4GH_CLI_FLAG, nullptr, "a Fourier series per joint that identifies the rigid-body model (needs --kin)", &c.optimize, 0, 0, 0, nullptr, 0},
        {"kin", 0, C4GH_CLI_STRING, "FILE", "--optimize: the arm's kinematics file (fixtures/ident/smart-six.kin)", c.kin, sizeof c.kin, 0, 0, nullptr, 0},
        {"init", 0, C4GH_CLI_STRING, "CAPTURE", "--optimize: arm 1's transmission from this capture's init packet (default figure 10.1's, the arm plant's)", c.init, sizeof c.init, 0, 0, nullptr, 0},
        {"periods", 0, C4GH_CLI_UINT, "N", "--optimize: periods of the series played (default 3)", &periods, 0, 1, 1000, nullptr, 0},
        {"start", 0, C4GH_CLI_STRING, "Q1,...,Q6", "--optimize: joint angles at mode entry [rad] (default the arm plant's: motor position 0)", c.start, sizeof c.start, 0, 0, nullptr, 0},
        {"q-min", 0, C4GH_CLI_STRING, "Q[,Q...]", "--optimize: lowest joint angle [rad] (default start - 1.57,0.70,0.70,1.57,1.05,1.57)", c.q_min, sizeof c.q_min, 0, 0, nullptr, 0},
        {"q-max", 0, C4GH_CLI_STRING, "Q[,Q...]", "--optimize: highest joint angle [rad] (default start + the same)", c.q_max, sizeof c.q_max, 0, 0, nullptr, 0},
        {"qd-max", 0, C4GH_CLI_STRING, "V[,V...]", "--optimize: joint speed limit [rad/s] (default 95 % of --vmax through the transmission)", c.qd_max, sizeof c.qd_max, 0, 0, nullptr, 0},
        {"qdd-max", 0, C4GH_CLI_STRING, "A[,A...]", "--optimize: joint acceleration limit [rad/s^2] (default 95 % of --amax through it)", c.qdd_max, sizeof c.qdd_max, 0, 0, nullptr, 0},
        {"evals", 0, C4GH_CLI_UINT, "N", "--optimize: condition numbers the search computes (default 2000)", &evals, 0, 10, 1e6, nullptr, 0},
        {"json", 0, C4GH_CLI_FLAG, nullptr, "--optimize: the report as JSON on stdout", &c.json, 0, 0, 0, nullptr, 0},
    };
    static const char *const examples[] = {
        "c4g-ident excite --axes 1,2,3 --vmax 20 --amax 300 -o excite.csv",
        "c4g-server --traj excite.csv --pcap ident.pcap      # then c4g-ident fit ident.pcap",
        "c4g-ident excite --optimize --kin fixtures/ident/smart-six.kin -o rigid.csv",
        nullptr};
    c4gh_cli_spec_t spec = {"c4g-ident excite", C4G_VERSION_STRING,
                       "Usage: c4g-ident excite [OPTIONS] [-o FILE]\n"
                       "Writes an excitation trajectory (offsets from the mode-entry position, the format of\n"
                       "c4g-server --traj): constant-speed runs both ways at log-spaced speeds for friction,\n"
                       "then a multi-sine for inertia, within each axis' velocity and acceleration limits,\n"
                       "starting and ending at rest at offset 0. With --optimize: a Fourier series per joint\n"
                       "whose coefficients minimise the condition number of the rigid-body model's base\n"
                       "regressor within the joints' limits; the report (stdout) compares it with the plain one.",
                       opts, sizeof opts / sizeof opts[0], examples,
                       "Rows: give -T the period of the controller that plays the file (-T 1 at 1 kHz):\n"
                       "c4g-server interpolates rows of another spacing linearly, and the kink at each row\n"
                       "is a current ripple at the row rate that no model predicts. With --optimize --init\n"
                       "CAPTURE the default is the capture's period (its init packet's).\n"
                       "Exit status: 0 written; 1 the file could not be written; 2 bad usage or kinematics file.", 0, 0, 1, nullptr};
    int first = 0;
    const c4gh_cli_result_t r = c4gh_cli_parse(&spec, &c, argc, argv, &first);
    if (r == C4GH_CLI_DONE) return C4GH_CLI_EXIT_OK;
    if (r == C4GH_CLI_BAD) return C4GH_CLI_EXIT_USAGE;
    if (c.optimize) {
        const char *na = c.axes != 0U ? "--axes" : duration >= 0.0 ? "--duration" : stair >= 0.0 ? "--stair" : nullptr;
        if (na != nullptr) {
            c4gh_cli_error(&spec, "%s does not apply to --optimize (it moves every joint, for --periods periods)", na);
            return C4GH_CLI_EXIT_USAGE;
        }
        if (period < 0.0) {
            // rows at the controller's period: c4g-server interpolates coarser rows linearly,
            // and the kinks each row leaves are a current ripple no model predicts
            c4g_init_t init;
            std::string why;
            period = (c.init[0] != '\0' && read_init(c.init, &init, &why)) ? static_cast<double>(init.period_ms) : 2.0;
        }
        OptCli o{f0, period, harmonics == 0U ? 8U : harmonics, seed, periods == 0U ? 3U : periods, evals == 0U ? 2000U : evals};
        return run_optimize(spec, c, o);
    }
    {
        const char *oo = c.kin[0] ? "--kin" : c.init[0] ? "--init" : c.start[0] ? "--start" : c.q_min[0] ? "--q-min" : c.q_max[0] ? "--q-max"
                       : c.qd_max[0] ? "--qd-max" : c.qdd_max[0] ? "--qdd-max" : c.json ? "--json"
                       : periods ? "--periods" : evals ? "--evals" : nullptr;
        if (oo != nullptr) {
            c4gh_cli_error(&spec, "%s applies only to --optimize", oo);
            return C4GH_CLI_EXIT_USAGE;
        }
    }
    if (c.axes == 0U) c.axes = 0x3F;
    if (period < 0.0) period = 2.0;
    if (duration < 0.0) duration = 38.0;
    if (stair < 0.0) stair = 0.3;
    if (harmonics == 0U) harmonics = 16;
    std::vector<double> vm, am;
    if (!list(c.vmax, &vm)) {
        c4gh_cli_error(&spec, "--vmax: bad value '%s' (positive numbers)", c.vmax);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (!list(c.amax, &am)) {
        c4gh_cli_error(&spec, "--amax: bad value '%s' (positive numbers)", c.amax);
        return C4GH_CLI_EXIT_USAGE;
    }
    unsigned last = 0, n_on = 0;
    for (unsigned k = 0; k < 10; k++) {
        if ((c.axes >> k) & 1U) {
            last = k + 1;
            n_on++;
        }
    }
    if ((vm.size() != 1 && vm.size() != n_on) || (am.size() != 1 && am.size() != n_on)) {
        c4gh_cli_error(&spec, "--vmax and --amax take one value or one per excited axis (%u)", n_on);
        return C4GH_CLI_EXIT_USAGE;
    }
    const double rows = duration / (period * 1e-3);
    if (rows > 20000.0) {
        c4gh_cli_error(&spec, "%.0f rows: c4g-server --traj reads at most 20000 (shorten --duration or widen --period)", rows);
        return C4GH_CLI_EXIT_USAGE;
    }
    ExciteOptions eo;
    eo.duration = duration;
    eo.f0 = f0;
    eo.harmonics = static_cast<int>(harmonics);
    eo.stair = stair;
    eo.seed = seed;
    eo.dt = period * 1e-3;
    std::vector<ExciteAxis> ax(last);
    unsigned j = 0;
    for (unsigned k = 0; k < last; k++) {
        ax[k].on = ((c.axes >> k) & 1U) != 0U;
        if (ax[k].on) {
            ax[k].vmax = vm[vm.size() == 1 ? 0 : j];
            ax[k].amax = am[am.size() == 1 ? 0 : j];
            j++;
        }
    }
    const Excitation ex(eo, ax);
    FILE *out = stdout;
    if (c.out[0] != '\0') {
        out = std::fopen(c.out, "w");
        if (out == nullptr) {
            c4gh_cli_file_error(spec.tool, "--out", c.out, errno);
            return C4GH_CLI_EXIT_RUNTIME;
        }
    }
    std::fprintf(out, "# c4g-ident excite: %s, %.6g s, rows every %.6g ms; offsets [motor turns] from the\n"
                      "# mode-entry position (c4g-server --traj). Speeds within vmax, accelerations within amax.\n",
                 n_on == 1 ? "one axis" : (std::to_string(n_on) + " axes").c_str(), duration, period);
    std::fprintf(out, "t");
    for (unsigned k = 0; k < last; k++) std::fprintf(out, ",ax%u", k + 1);
    std::fputc('\n', out);
    const long n = std::lround(rows);
    for (long i = 0; i <= n; i++) {
        const double t = static_cast<double>(i) * period * 1e-3;
        std::fprintf(out, "%.6f", t);
        for (unsigned k = 0; k < last; k++) {
            double q = 0, v = 0, a = 0;
            if (ax[k].on) ex.eval(k, t, &q, &v, &a);
            std::fprintf(out, ",%.9g", q);
        }
        std::fputc('\n', out);
    }
    if (out != stdout && std::fclose(out) != 0) {
        c4gh_cli_error(&spec, "--out %s: write error", c.out);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    return C4GH_CLI_EXIT_OK;
}

// A list of signed numbers (1 or @p n of them) -> @p n values; false on a bad item.
bool list_n(const char *s, unsigned n, double lo, double hi, std::vector<double> *out)
{
    out->clear();
    for (const std::string &x : split_commas(s)) {
        char *end = nullptr;
        const double d = std::strtod(x.c_str(), &end);
        if (x.empty() || *end != '\0' || !std::isfinite(d) || d < lo || d > hi) return false;
        out->push_back(d);
    }
    if (out->size() == 1) out->assign(n, out->front());
    return out->size() == n;
}

// How far the default position range reaches on each side of the start pose [rad]: 90, 40, 40,
// 90, 60, 90 degrees. The arm plant has no data-sheet ranges (fixtures/sim/smart-six.xml: no
// joint limits, no collisions); these keep the upper arm within 40 degrees of vertical and the
// forearm within 40 degrees of horizontal, so the wrist stays well above the floor, and the
// wrist joints within a quarter turn.
const double kReach[kOptJoints] = {1.5708, 0.6981, 0.6981, 1.5708, 1.0472, 1.5708};
constexpr double kMargin = 0.95;  // share of the motor limits the default joint limits use
constexpr double kSampleMs = 20.0; // the condition numbers' sample spacing
constexpr double kUnidentifiable = 1e-6; // singular value below this share of the largest

// What --optimize works from: the problem, the transmission and the motor limits.
struct OptSetup {
    OptProblem p;
    c4g_kin_t kin{};
    c4g_kin_matrices_t mx{};
    std::vector<double> vm, am;  // --vmax, --amax per motor
    double T = 0.0, dt = 0.0;    // length [s], row spacing [s]
    long rows = 0;               // rows - 1
};

int opt_limits(const c4gh_cli_spec_t &spec, const ExCli &c, OptSetup *s);

// The options' values checked and turned into the problem; an exit code, or -1 to go on.
int opt_setup(const c4gh_cli_spec_t &spec, const ExCli &c, const OptCli &o, OptSetup *s)
{
    if (c.kin[0] == '\0') {
        c4gh_cli_error(&spec, "--optimize needs --kin FILE (the arm's kinematics)");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (c.out[0] == '\0' || std::strcmp(c.out, "-") == 0) {
        c4gh_cli_error(&spec, "--optimize writes the trajectory to --out FILE (the report goes to stdout)");
        return C4GH_CLI_EXIT_USAGE;
    }
    if (o.harmonics < 2U || o.harmonics > 20U) {
        c4gh_cli_error(&spec, "--harmonics %u: --optimize takes 2..20 (it needs 2 to start and end at rest)", o.harmonics);
        return C4GH_CLI_EXIT_USAGE;
    }
    // the highest harmonic: within what the report's 20 ms samples and the file's rows follow
    const double top = o.harmonics * o.f0;
    if (top > 5.0 || 1.0 / top < 20.0 * o.period * 1e-3) {
        c4gh_cli_error(&spec, "--harmonics %u of --f0 %g Hz: the highest, %g Hz, must stay at or below 5 Hz and 20 rows "
                              "of --period %g ms a cycle", o.harmonics, o.f0, top, o.period);
        return C4GH_CLI_EXIT_USAGE;
    }
    s->T = o.periods / o.f0;
    s->dt = o.period * 1e-3;
    const double rows = s->T / s->dt;
    if (rows > 20000.0) {
        c4gh_cli_error(&spec, "%.0f rows: c4g-server --traj reads at most 20000 (fewer --periods, a higher --f0 or a wider --period)", rows);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (std::fabs(rows - std::round(rows)) > 1e-6 * rows) {
        c4gh_cli_error(&spec, "--period %g ms does not divide the %g s length into whole rows", o.period, s->T);
        return C4GH_CLI_EXIT_USAGE;
    }
    s->rows = std::lround(rows);
    if (!list_n(c.vmax, kOptJoints, 1e-6, 1e5, &s->vm)) {
        c4gh_cli_error(&spec, "--vmax: bad value '%s' (one positive number or %u)", c.vmax, kOptJoints);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (!list_n(c.amax, kOptJoints, 1e-6, 1e7, &s->am)) {
        c4gh_cli_error(&spec, "--amax: bad value '%s' (one positive number or %u)", c.amax, kOptJoints);
        return C4GH_CLI_EXIT_USAGE;
    }
    char err[1024];
    c4gh_kinfile_t kf;
    if (c4gh_kin_load(c.kin, &kf, err, sizeof err) != 0) {
        std::fprintf(stderr, "%s: --kin %s\n", spec.tool, err);
        return C4GH_CLI_EXIT_USAGE;
    }
    if (kf.n != kOptJoints) {
        std::fprintf(stderr, "%s: --kin %s: %u joints; --optimize drives the arm's %u main axes\n", spec.tool, c.kin,
                     kf.n, kOptJoints);
        return C4GH_CLI_EXIT_USAGE;
    }
    // The transmission: arm 1's of a capture's init packet, or the one c4g-sim's arm plant
    // sends (the manual's figure 10.1).
    c4g_init_t init;
    std::string why;
    if (c.init[0] != '\0' && !read_init(c.init, &init, &why)) {
        std::fprintf(stderr, "%s: --init %s\n", spec.tool, why.c_str());
        return C4GH_CLI_EXIT_USAGE;
    }
    if ((c.init[0] == '\0' && c4gsim_fig10_1(&init) != C4G_OK) || c4g_kin_from_init(&init, 0, &s->kin) != C4G_OK ||
        c4g_kin_matrices(&s->kin, &s->mx) != C4G_OK) {
        std::fprintf(stderr, "%s: %s%s: no transmission of arm 1 there\n", spec.tool, c.init[0] ? "--init " : "",
                     c.init[0] ? c.init : "figure 10.1");
        return C4GH_CLI_EXIT_USAGE;
    }
    for (unsigned k = 0; k < kOptJoints; k++) {
        if (!(std::fabs(s->mx.kr[k][k]) > 0.0)) {
            std::fprintf(stderr, "%s: --init %s: arm 1 axis %u has no transmission ratio\n", spec.tool, c.init, k + 1);
            return C4GH_CLI_EXIT_USAGE;
        }
    }
    OptProblem &p = s->p;
    p.chain = kf.chain;
    p.f0 = o.f0;
    p.harmonics = static_cast<int>(o.harmonics);
    p.seed = o.seed;
    p.evals = static_cast<int>(o.evals);
    p.samples = std::max(100, 12 * p.harmonics);  // 12 a cycle of the highest harmonic at least
    p.use = kMargin;
    for (unsigned k = 0; k < kOptJoints; k++) {
        for (unsigned j = 0; j < kOptJoints; j++) p.kr[k][j] = s->mx.kr[k][j];
        p.kt[k] = kf.j[k].kt;
    }
    return opt_limits(spec, c, s);
}

// The start pose and the joints' limits (defaults, then the options); as opt_setup.
int opt_limits(const c4gh_cli_spec_t &spec, const ExCli &c, OptSetup *s)
{
    OptProblem &p = s->p;
    std::vector<double> v;
    const double zero[kOptJoints] = {};
    if (c.start[0] != '\0') {
        if (!list_n(c.start, kOptJoints, -100.0, 100.0, &v) || split_commas(c.start).size() != kOptJoints) {
            c4gh_cli_error(&spec, "--start: bad value '%s' (%u joint angles [rad])", c.start, kOptJoints);
            return C4GH_CLI_EXIT_USAGE;
        }
        std::copy(v.begin(), v.end(), p.start);
    } else if (c4g_kin_motor_to_link(&s->kin, zero, kOptJoints, p.start) != C4G_OK) {
        std::fprintf(stderr, "%s: the start pose could not be computed\n", spec.tool);
        return C4GH_CLI_EXIT_RUNTIME;
    }
    for (unsigned j = 0; j < kOptJoints; j++) {
        OptLimit &L = p.lim[j];
        L.q_min = p.start[j] - kReach[j];
        L.q_max = p.start[j] + kReach[j];
        L.qd_max = kMargin * 2.0 * M_PI * s->vm[j] / std::fabs(s->mx.kr[j][j]);
        L.qdd_max = kMargin * 2.0 * M_PI * s->am[j] / std::fabs(s->mx.kr[j][j]);
    }
    struct LimOpt {
        const char *name, *text;
        int which;
    };
    const LimOpt lo[] = {{"--q-min", c.q_min, 0}, {"--q-max", c.q_max, 1}, {"--qd-max", c.qd_max, 2}, {"--qdd-max", c.qdd_max, 3}};
    for (const LimOpt &x : lo) {
        if (x.text[0] == '\0') continue;
        const bool pos = x.which >= 2;
        if (!list_n(x.text, kOptJoints, pos ? 1e-9 : -100.0, pos ? 1e6 : 100.0, &v)) {
            c4gh_cli_error(&spec, "%s: bad value '%s' (one %s or %u)", x.name, x.text,
                           pos ? "positive number" : "angle [rad]", kOptJoints);
            return C4GH_CLI_EXIT_USAGE;
        }
        for (unsigned j = 0; j < kOptJoints; j++) {
            double *f[4] = {&p.lim[j].q_min, &p.lim[j].q_max, &p.lim[j].qd_max, &p.lim[j].qdd_max};
            *f[x.which] = v[j];
        }
    }
    for (unsigned j = 0; j < kOptJoints; j++) {
        if (!(p.lim[j].q_min < p.start[j] && p.start[j] < p.lim[j].q_max)) {
            c4gh_cli_error(&spec, "joint %u: the start pose %.6g rad is not inside --q-min %.6g .. --q-max %.6g", j + 1,
                           p.start[j], p.lim[j].q_min, p.lim[j].q_max);
            return C4GH_CLI_EXIT_USAGE;
        }
    }
    return -1;
}

// What the report says.
struct OptReport {
    Conditioning co, cp;            // optimised, plain
    OptResult res;
    double pp[kOptJoints][4] = {};  // the plain excitation's joint peaks
    double mpk[kOptJoints][4] = {}; // motors along the file: offset min, max [turn], |speed|, |accel|
    double plain_s = 0.0, secs = 0.0;
    std::size_t base = 0;
};

// The trajectory file, and what the motors do along it (every row); false after an error
// (said on stderr).
bool opt_write(const c4gh_cli_spec_t &spec, const ExCli &c, const OptCli &o, const OptSetup &s, const JointPath &opt,
               OptReport *R)
{
    FILE *out = std::fopen(c.out, "w");
    if (out == nullptr) {
        c4gh_cli_file_error(spec.tool, "--out", c.out, errno);
        return false;
    }
    double m_start[kOptJoints];
    bool bad = c4g_kin_link_to_motor(&s.kin, s.p.start, kOptJoints, m_start) != C4G_OK;
    std::fprintf(out, "# c4g-ident excite --optimize: a Fourier series per joint (%u harmonics of %.6g Hz, seed %u),\n"
                      "# %u period(s), %.6g s, rows every %.6g ms; offsets [motor turns] from the mode-entry\n"
                      "# position (c4g-server --traj). Base regressor condition number %.6g (plain excite %.6g).\n",
                 o.harmonics, o.f0, o.seed, o.periods, s.T, o.period, R->co.cond, R->cp.cond);
    std::fprintf(out, "t");
    for (unsigned k = 0; k < kOptJoints; k++) std::fprintf(out, ",ax%u", k + 1);
    std::fputc('\n', out);
    for (long i = 0; i <= s.rows && !bad; i++) {
        const double t = static_cast<double>(i) * s.dt;
        double q[kOptJoints], qd[kOptJoints], qdd[kOptJoints], m[kOptJoints];
        opt(t, q, qd, qdd);
        bad = c4g_kin_link_to_motor(&s.kin, q, kOptJoints, m) != C4G_OK;
        std::fprintf(out, "%.6f", t);
        for (unsigned k = 0; k < kOptJoints; k++) {
            // the first and last rows are the start pose: 0 exactly, as --traj wants
            const double off = (i == 0 || i == s.rows) ? 0.0 : m[k] - m_start[k];
            double sv = 0.0, sa = 0.0;
            for (unsigned j = 0; j < kOptJoints; j++) {
                sv += s.mx.kr[k][j] * qd[j];
                sa += s.mx.kr[k][j] * qdd[j];
            }
            double *pk = R->mpk[k];
            pk[0] = std::min(pk[0], off);
            pk[1] = std::max(pk[1], off);
            pk[2] = std::max(pk[2], std::fabs(sv) / (2.0 * M_PI));
            pk[3] = std::max(pk[3], std::fabs(sa) / (2.0 * M_PI));
            std::fprintf(out, ",%.9g", off);
        }
        std::fputc('\n', out);
    }
    if (std::fclose(out) != 0 || bad) {
        c4gh_cli_error(&spec, "--out %s: %s", c.out, bad ? "a pose outside the transmission's range" : "write error");
        return false;
    }
    return true;
}

// Share of each limit joint @p j uses with peaks @p pk: position (the nearer side), speed, acceleration.
void limit_share(const OptProblem &p, unsigned j, const double pk[4], double *sq, double *sv, double *sa)
{
    const OptLimit &L = p.lim[j];
    *sq = std::max((pk[1] - p.start[j]) / (L.q_max - p.start[j]), (p.start[j] - pk[0]) / (p.start[j] - L.q_min));
    *sv = pk[2] / L.qd_max;
    *sa = pk[3] / L.qdd_max;
}

void opt_report_json(const ExCli &c, const OptCli &o, const OptSetup &s, const OptReport &R)
{
    const OptProblem &p = s.p;
    json_t *root = json_object();
    json_object_set_new(root, "trajectory", json_string(c.out));
    json_object_set_new(root, "kinematics", json_string(c.kin));
    json_object_set_new(root, "transmission", json_string(c.init[0] ? c.init : "figure 10.1"));
    json_object_set_new(root, "joints", json_integer(kOptJoints));
    json_object_set_new(root, "harmonics", json_integer(o.harmonics));
    json_object_set_new(root, "f0_hz", json_real(o.f0));
    json_object_set_new(root, "periods", json_integer(o.periods));
    json_object_set_new(root, "duration_s", json_real(s.T));
    json_object_set_new(root, "rows", json_integer(s.rows + 1));
    json_object_set_new(root, "row_ms", json_real(o.period));
    json_object_set_new(root, "seed", json_integer(o.seed));
    json_object_set_new(root, "evals", json_integer(R.res.evals));
    json_object_set_new(root, "seconds", json_real(R.secs));
    json_object_set_new(root, "base_parameters", json_integer(static_cast<json_int_t>(R.base)));
    json_object_set_new(root, "columns", json_integer(R.co.cols));
    json_t *cond = json_object();
    json_object_set_new(cond, "optimized", json_real(R.co.cond));
    json_object_set_new(cond, "plain", json_real(R.cp.cond));
    json_object_set_new(cond, "ratio", json_real(R.cp.cond / R.co.cond));
    json_object_set_new(cond, "sample_ms", json_real(kSampleMs));
    json_object_set_new(cond, "plain_duration_s", json_real(R.plain_s));
    json_object_set_new(root, "condition", cond);
    json_t *lims = json_array();
    for (unsigned j = 0; j < kOptJoints; j++) {
        const OptLimit &L = p.lim[j];
        const double *pk = R.res.peak[j];
        double sq, sv, sa;
        limit_share(p, j, pk, &sq, &sv, &sa);
        json_array_append_new(
            lims, json_pack("{s:i,s:f,s:f,s:f,s:f,s:f,s:f,s:f,s:f,s:f,s:{s:f,s:f,s:f},s:{s:f,s:f,s:f,s:f}}", "joint",
                            static_cast<int>(j + 1), "start", p.start[j], "q_min", L.q_min, "q_max", L.q_max, "qd_max",
                            L.qd_max, "qdd_max", L.qdd_max, "q_lo", pk[0], "q_hi", pk[1], "qd_peak", pk[2], "qdd_peak",
                            pk[3], "margin", "q", 1.0 - sq, "qd", 1.0 - sv, "qdd", 1.0 - sa, "plain", "q_lo", R.pp[j][0],
                            "q_hi", R.pp[j][1], "qd_peak", R.pp[j][2], "qdd_peak", R.pp[j][3]));
    }
    json_object_set_new(root, "limits", lims);
    json_t *mot = json_array();
    for (unsigned k = 0; k < kOptJoints; k++) {
        json_array_append_new(mot, json_pack("{s:i,s:f,s:f,s:f,s:f}", "axis", static_cast<int>(k + 1), "stroke_min",
                                             R.mpk[k][0], "stroke_max", R.mpk[k][1], "speed_peak", R.mpk[k][2],
                                             "acc_peak", R.mpk[k][3]));
    }
    json_object_set_new(root, "motors", mot);
    json_t *weak = json_array();
    for (const Conditioning::Weak &w : R.co.weakest) {
        json_t *mem = json_array();
        for (const auto &m : w.members) json_array_append_new(mem, json_pack("{s:s,s:f}", "name", m.first.c_str(), "weight", m.second));
        json_array_append_new(weak, json_pack("{s:f,s:b,s:o}", "relative_sigma", w.rel, "unidentifiable",
                                              w.rel < kUnidentifiable, "members", mem));
    }
    json_object_set_new(root, "weakest", weak);
    json_dumpf(root, stdout, JSON_INDENT(2) | JSON_REAL_PRECISION(9));
    std::fputc('\n', stdout);
    json_decref(root);
}

void opt_report_text(const ExCli &c, const OptCli &o, const OptSetup &s, const OptReport &R)
{
    const OptProblem &p = s.p;
    std::printf("c4g-ident excite --optimize: %s written: %u joints, %u harmonics of %.6g Hz, %u period(s) = %.6g s, "
                "%ld rows every %.6g ms\n", c.out, kOptJoints, o.harmonics, o.f0, o.periods, s.T, s.rows + 1, o.period);
    std::printf("transmission: %s (arm 1)\n", c.init[0] ? c.init : "figure 10.1, the arm plant's");
    std::printf("search: %d condition numbers from %d seeded starts (seed %u) in %.1f s\n", R.res.evals, p.restarts, o.seed,
                R.secs);
    std::printf("base regressor: %zu rigid-body base parameters + %u friction columns (Fv, Fc, off per motor), "
                "sampled every %.0f ms\n", R.base, 3 * kOptJoints, kSampleMs);
    std::printf("  condition number, optimised:   %.6g\n", R.co.cond);
    std::printf("  condition number, plain excite: %.6g (its defaults, %.6g s; %.3gx the optimised)\n", R.cp.cond,
                R.plain_s, R.cp.cond / R.co.cond);
    std::printf("limits (share used; margin = 1 - share):\n"
                "  joint  start    q range [rad]            limits [rad]             |qd| [rad/s]      |qdd| [rad/s^2]\n");
    for (unsigned j = 0; j < kOptJoints; j++) {
        const OptLimit &L = p.lim[j];
        const double *pk = R.res.peak[j];
        double sq, sv, sa;
        limit_share(p, j, pk, &sq, &sv, &sa);
        std::printf("  %u  %8.4f  %8.4f .. %8.4f  %8.4f .. %8.4f  %.4f/%.4f %3.0f%%  %.4f/%.4f %3.0f%%  (q %3.0f%%)\n", j + 1,
                    p.start[j], pk[0], pk[1], L.q_min, L.q_max, pk[2], L.qd_max, 100.0 * sv, pk[3], L.qdd_max, 100.0 * sa,
                    100.0 * sq);
    }
    std::printf("motors (for c4g-server --stroke, --max-step):\n"
                "  axis  offset range [turn]      |speed| [turn/s]  |accel| [turn/s^2]\n");
    for (unsigned k = 0; k < kOptJoints; k++) {
        std::printf("  %u  %9.4f .. %9.4f  %8.4f  %9.3f\n", k + 1, R.mpk[k][0], R.mpk[k][1], R.mpk[k][2], R.mpk[k][3]);
    }
    std::printf("least determined directions of the base parameters (singular value / largest; members' weights):\n");
    for (const Conditioning::Weak &w : R.co.weakest) {
        std::printf("  %.3g%s:", w.rel, w.rel < kUnidentifiable ? " UNIDENTIFIABLE" : "");
        const char *sep = " ";
        for (const auto &m : w.members) {
            std::printf("%s%+.2f [%s]", sep, m.second, m.first.c_str());
            sep = ", ";
        }
        std::putchar('\n');
    }
}

int run_optimize(const c4gh_cli_spec_t &spec, const ExCli &c, const OptCli &o)
{
    OptSetup s;
    const int rc = opt_setup(spec, c, o, &s);
    if (rc >= 0) return rc;
    if (c4gh_cli_check_output(spec.tool, "--out", c.out) != 0) return C4GH_CLI_EXIT_RUNTIME;
    const OptProblem &p = s.p;
    const auto t0 = std::chrono::steady_clock::now();
    OptModel model;
    std::string why;
    if (!model.init(p, &why)) {
        std::fprintf(stderr, "%s: --kin %s: %s\n", spec.tool, c.kin, why.c_str());
        return C4GH_CLI_EXIT_USAGE;
    }
    OptReport R;
    if (!optimize(p, model, &R.res, &why)) {
        std::fprintf(stderr, "%s: %s\n", spec.tool, why.c_str());
        return C4GH_CLI_EXIT_RUNTIME;
    }
    R.secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    R.base = model.base().base.size();
    const std::vector<Series> &S = R.res.joint;
    const JointPath opt = [&S](double t, double *q, double *qd, double *qdd) {
        for (unsigned j = 0; j < kOptJoints; j++) S[j].eval(t, &q[j], &qd[j], &qdd[j]);
    };
    // The plain excitation with its defaults (and these --vmax, --amax) on every axis, in
    // joint terms: q = start + Kr^-1 2 pi offset.
    ExciteOptions eo;
    eo.duration = 38.0;
    R.plain_s = eo.duration;
    std::vector<ExciteAxis> ax(kOptJoints);
    for (unsigned k = 0; k < kOptJoints; k++) {
        ax[k].vmax = s.vm[k];
        ax[k].amax = s.am[k];
    }
    const Excitation plain_ex(eo, ax);
    Eigen::Matrix<double, kOptJoints, kOptJoints> kr;
    for (unsigned k = 0; k < kOptJoints; k++) {
        for (unsigned j = 0; j < kOptJoints; j++) kr(k, j) = s.mx.kr[k][j];
    }
    const Eigen::Matrix<double, kOptJoints, kOptJoints> kinv = kr.inverse();
    const double *st = p.start;
    const JointPath plain = [&plain_ex, &kinv, st](double t, double *q, double *qd, double *qdd) {
        Eigen::Matrix<double, kOptJoints, 1> m0, m1, m2;
        for (unsigned k = 0; k < kOptJoints; k++) plain_ex.eval(k, t, &m0(k), &m1(k), &m2(k));
        const Eigen::Matrix<double, kOptJoints, 1> a = kinv * (2.0 * M_PI * m0), b = kinv * (2.0 * M_PI * m1),
                                                   c2 = kinv * (2.0 * M_PI * m2);
        for (unsigned j = 0; j < kOptJoints; j++) {
            q[j] = st[j] + a(j);
            qd[j] = b(j);
            qdd[j] = c2(j);
        }
    };
    auto times = [](double len) {
        std::vector<double> t;
        const long n = std::lround(len / (kSampleMs * 1e-3));
        for (long i = 0; i < n; i++) t.push_back(static_cast<double>(i) * kSampleMs * 1e-3);
        return t;
    };
    if (!conditioning(model, opt, times(s.T), 3, &R.co, &why) ||
        !conditioning(model, plain, times(eo.duration), 0, &R.cp, &why)) {
        std::fprintf(stderr, "%s: %s\n", spec.tool, why.c_str());
        return C4GH_CLI_EXIT_RUNTIME;
    }
    path_peaks(plain, kOptJoints, eo.duration, s.dt, R.pp);
    if (!opt_write(spec, c, o, s, opt, &R)) return C4GH_CLI_EXIT_RUNTIME;
    if (c.json) opt_report_json(c, o, s, R);
    else opt_report_text(c, o, s, R);
    return C4GH_CLI_EXIT_OK;
}

void usage(FILE *out)
{
    std::fprintf(out,
                 "Usage: c4g-ident COMMAND [OPTIONS] ...\n"
                 "Identifies each axis' inertia and friction from logged runs (Ceres Solver) and writes the\n"
                 "parameter file c4g-server's mode 9 (current feedforward) applies.\n\nCommands:\n"
                 "  fit      fit the model to captures or CSV logs; report, parameter file, plots\n"
                 "  excite   write an excitation trajectory for c4g-server --traj\n\n"
                 "  c4g-ident COMMAND --help   options and examples of one command\n"
                 "  -h, --help                 this text\n"
                 "  -V, --version              version of the tool, libc4gopen and Ceres\n\n"
                 "Examples:\n"
                 "  c4g-ident excite --axes 1,2,3 --vmax 20 --amax 300 -o excite.csv\n"
                 "  c4g-ident fit ident.pcap -o arm1.ini --plot plots\n"
                 "  c4g-server --ff arm1.ini      # mode 9 applies the identified model\n\n"
                 "Exit status: 0 success; 1 a file could not be written; 2 bad usage or an unreadable\n"
                 "input; 3 an axis could not be identified. See docs/c4g-ident.md and c4g-ident(1).\n");
}

}  // namespace

int main(int argc, char **argv)
{
    // Ceres logs through glog: its messages (a rank-deficient covariance of a variant that is
    // then not chosen) are the report's business, not stderr's
    FLAGS_minloglevel = 3;
    google::InitGoogleLogging(kTool);
    if (argc < 2) {
        usage(stderr);
        return C4GH_CLI_EXIT_USAGE;
    }
    const std::string cmd = argv[1];
    if (cmd == "-h" || cmd == "--help" || cmd == "help") {
        usage(stdout);
        return C4GH_CLI_EXIT_OK;
    }
    if (cmd == "-V" || cmd == "--version") {
        std::printf("c4g-ident %s (libc4gopen %s, Ceres Solver %s)\n", C4G_VERSION_STRING, C4G_VERSION_STRING, CERES_VERSION_STRING);
        return C4GH_CLI_EXIT_OK;
    }
    if (cmd == "fit") return run_fit(argc - 1, argv + 1);
    if (cmd == "excite") return run_excite(argc - 1, argv + 1);
    char shown[80];
    c4gh_cli_path_text(cmd.c_str(), shown, sizeof shown);
    if (cmd[0] == '-') {
        std::fprintf(stderr, "%s: unrecognized option '%s' (see %s --help)\n", kTool, shown, kTool);
        return C4GH_CLI_EXIT_USAGE;
    }
    std::fprintf(stderr, "%s: unknown command '%s' (see %s --help)\n", kTool, shown, kTool);
    return C4GH_CLI_EXIT_USAGE;
}
