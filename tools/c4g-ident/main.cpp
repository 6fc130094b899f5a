// SPDX-License-Identifier: MIT
// c4g-ident: friction and inertia of each axis from logged runs (Ceres Solver), written as
// the parameter file c4g-server's mode 9 (current feedforward) applies; and the excitation
// trajectory to record a good identification run.
//   c4g-ident fit [OPTIONS] LOG...      c4g-ident excite [OPTIONS] -o TRAJ.csv
#include "excite.hpp"
#include "ident.hpp"
#include "input.hpp"
#include "output.hpp"
#include "rigid.hpp"

extern "C" {
#include "c4gh_cli.h"
#include "c4gh_kinfile.h"
#include "c4gopen.h"
}

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
};

int ex_axes(void *ctx, const c4gh_cli_opt_t *, const char *v, char *why, size_t whylen)
{
    return parse_axes(v, &static_cast<ExCli *>(ctx)->axes, why, whylen);
}

// "V" or "V1,V2,..." (per excited axis, in order)
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
    c.axes = 0x3F;
    double duration = 38.0, period = 2.0, f0 = 0.1, stair = 0.3;
    unsigned harmonics = 16, seed = 1;
    const c4gh_cli_opt_t opts[] = {
        {"axes", 'x', C4GH_CLI_CALL, "LIST", "logical axes to excite (default 1,2,3,4,5,6)", nullptr, 0, 0, 0, ex_axes, 0},
        {"vmax", 0, C4GH_CLI_STRING, "V[,V...]", "velocity limit [motor turn/s], one or one per axis (default 10)", c.vmax, sizeof c.vmax, 0, 0, nullptr, 0},
        {"amax", 0, C4GH_CLI_STRING, "A[,A...]", "acceleration limit [motor turn/s^2] (default 200)", c.amax, sizeof c.amax, 0, 0, nullptr, 0},
        {"duration", 'd', C4GH_CLI_DOUBLE, "S", "length [s] (default 38: 19000 rows at 2 ms)", &duration, 0, 2, 36000, nullptr, 0},
        {"period", 'T', C4GH_CLI_DOUBLE, "MS", "row spacing [ms] (default 2, the SMP+ period)", &period, 0, 0.1, 100, nullptr, 0},
        {"f0", 0, C4GH_CLI_DOUBLE, "HZ", "multi-sine fundamental (default 0.1)", &f0, 0, 0.001, 100, nullptr, 0},
        {"harmonics", 0, C4GH_CLI_UINT, "N", "multi-sine harmonics (default 16)", &harmonics, 0, 1, 200, nullptr, 0},
        {"stair", 0, C4GH_CLI_DOUBLE, "F", "share of the time in constant-speed runs (default 0.3)", &stair, 0, 0, 0.9, nullptr, 0},
        {"seed", 0, C4GH_CLI_UINT, "N", "phase seed (default 1)", &seed, 0, 0, 1e9, nullptr, 0},
        {"out", 'o', C4GH_CLI_STRING, "FILE", "trajectory CSV for c4g-server --traj (default stdout)", c.out, sizeof c.out, 0, 0, nullptr, 0},
    };
    static const char *const examples[] = {
        "c4g-ident excite --axes 1,2,3 --vmax 20 --amax 300 -o excite.csv",
        "c4g-server --traj excite.csv --pcap ident.pcap      # then c4g-ident fit ident.pcap",
        nullptr};
    c4gh_cli_spec_t spec = {"c4g-ident excite", C4G_VERSION_STRING,
                       "Usage: c4g-ident excite [OPTIONS] [-o FILE]\n"
                       "Writes an excitation trajectory (offsets from the mode-entry position, the format of\n"
                       "c4g-server --traj): constant-speed runs both ways at log-spaced speeds for friction,\n"
                       "then a multi-sine for inertia, within each axis' velocity and acceleration limits,\n"
                       "starting and ending at rest at offset 0.",
                       opts, sizeof opts / sizeof opts[0], examples,
                       "Exit status: 0 written; 1 the file could not be written; 2 bad usage.", 0, 0, 1, nullptr};
    int first = 0;
    const c4gh_cli_result_t r = c4gh_cli_parse(&spec, &c, argc, argv, &first);
    if (r == C4GH_CLI_DONE) return C4GH_CLI_EXIT_OK;
    if (r == C4GH_CLI_BAD) return C4GH_CLI_EXIT_USAGE;
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
