// SPDX-License-Identifier: MIT
#include "input.hpp"

extern "C" {
#include "c4gh_analyze.h"
#include "c4gh_textfile.h"
#include "c4gh_capture.h"
}

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace ident {

namespace {

constexpr int64_t kSessionStride = 1000000000LL;  // ticks of one session never meet the next's

// Bytes of a file shown in an error: at most @p max of them, the unprintable ones as \xNN.
std::string shown(const std::string &s, std::size_t max)
{
    char buf[512];
    c4gh_tf_escape(s.data(), std::min(s.size(), max), buf, sizeof buf);
    return std::string(buf);
}

bool is_capture(const std::string &path)
{
    FILE *f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) return false;
    unsigned char m[4] = {0, 0, 0, 0};
    const size_t n = std::fread(m, 1, 4, f);
    std::fclose(f);
    if (n < 4) return false;
    const uint32_t le = c4g_le_u32(m);
    return le == 0xa1b2c3d4U || le == 0xd4c3b2a1U || le == 0xa1b23c4dU || le == 0x4d3cb2a1U || le == 0x0a0d0d0aU;
}

// Tick numbers from the controller's NUM (15 bits, wrapping): a packet lost before the log
// leaves a gap in the numbers, which splits the signal into segments the filter never crosses.
// Numbering the packets seen instead would close the gap and join two stretches of motion as
// if they were one tick apart (1 % of packets lost made viscous friction 46 % high).
struct NumTicks {
    int32_t last = -1;
    int64_t tick = 0;
    // false for a packet that repeats or goes behind the last one (dropped, counted)
    bool next(int32_t num, InputInfo *info, int64_t *out)
    {
        if (last < 0) {
            last = num;
            tick = 1;
            *out = tick;
            return true;
        }
        const int32_t d = c4g_num_delta(last, num);
        if (d == 0 || d > 0x4000) {
            info->num_dups++;
            return false;
        }
        if (d > 1) {
            info->num_gaps++;
            info->num_missing += static_cast<uint64_t>(d - 1);
        }
        tick += d;
        last = num;
        *out = tick;
        return true;
    }
};

// Per-axis collector shared by the readers.
struct Collector {
    const Selection &sel;
    std::vector<AxisLog> *logs;
    std::map<unsigned, std::size_t> index;  // logical axis (1-based) -> logs slot
    double t_first = NAN;
    std::size_t reserve = 0;  // ticks a lean log is reserved for
    explicit Collector(const Selection &s, std::vector<AxisLog> *l) : sel(s), logs(l) {}
    AxisLog *axis(unsigned logical, unsigned open, double period, double az)
    {
        if (sel.axes != 0 && ((sel.axes >> (logical - 1)) & 1U) == 0U) return nullptr;
        auto it = index.find(logical);
        if (it == index.end()) {
            AxisLog L;
            L.arm = sel.arm;
            L.axis = logical;
            L.open = open;
            L.period = period;
            L.az_lim = az;
            L.lean = sel.lean;
            if (sel.lean && reserve > 0) {
                L.tick.reserve(reserve);
                L.d3.reserve(reserve);
                L.d4.reserve(reserve);
                L.d5.reserve(reserve);
                L.q.reserve(reserve);
            }
            if (az > 0.0) {
                L.az_from = "init packet";
            } else if (logical >= 1U && logical <= kMaxAxes && sel.az_lim[logical - 1U] > 0.0) {
                // a CSV does not carry the limit: without it saturated ticks would stay in
                L.az_lim = sel.az_lim[logical - 1U];
                L.az_from = "--az-lim";
            }
            logs->push_back(std::move(L));  // a copy would drop the reservation
            it = index.emplace(logical, logs->size() - 1).first;
        }
        return &(*logs)[it->second];
    }
    // 1 keep, 0 dropped (counted)
    bool window(AxisLog *L, double t)
    {
        if (std::isnan(t_first)) t_first = t;
        const double rel = t - t_first;
        if (rel < sel.from || (sel.to >= 0.0 && rel > sel.to)) {
            L->dropped_window++;
            return false;
        }
        return true;
    }
    static bool add(AxisLog *L, int64_t tick, double t, int32_t mode, bool drive, const float f[7], double q)
    {
        L->seen++;
        if (!drive) {
            L->dropped_drive++;
            return false;
        }
        if (mode >= 500 || mode < 0) {
            L->dropped_mode++;
            return false;
        }
        for (int k = 0; k < 7; k++) {
            if (!std::isfinite(f[k])) {
                L->dropped_nonfinite++;
                return false;
            }
        }
        L->tick.push_back(tick);
        L->d3.push_back(f[2]);
        L->d4.push_back(f[3]);
        L->d5.push_back(f[4]);
        L->q.push_back(q);
        if (L->lean) return true;
        L->t.push_back(t);
        L->d1.push_back(f[0]);
        L->d2.push_back(f[1]);
        L->e1.push_back(f[5]);
        L->e2.push_back(f[6]);
        return true;
    }
};

struct CapCtx {
    Collector *col;
    InputInfo *info;
    unsigned last_session = 0;
    NumTicks nt;
    c4g_kin_t kin{};
    bool kin_ok = false;
};

void on_exchange(void *vp, const c4gh_an_exchange_t *x)
{
    CapCtx *c = static_cast<CapCtx *>(vp);
    if (x->kind != C4G_PKT_CYCLIC || x->rx == nullptr) return;
    const c4gh_an_session_t *s = x->s;
    if (c->col->sel.session != 0 && s->id != c->col->sel.session) return;
    const uint32_t arm = c->col->sel.arm - 1U;
    if (s->id != c->last_session) {
        c->last_session = s->id;
        c->info->sessions++;
        c->nt = NumTicks();
        c->kin_ok = s->have_init && c4g_kin_from_init(&s->init, arm, &c->kin) == C4G_OK;
        if (c->kin_ok && !c->info->have_init_kin) {
            c->info->have_init_kin = true;
            c->info->kin = c->kin;
        }
    }
    c->info->ticks++;
    int64_t tick = 0;
    if (!c->nt.next(x->rx->num, c->info, &tick)) return;
    const double period = (s->have_init && s->init.period_ms > 0) ? s->init.period_ms * 1e-3 : 0.002;
    const double t = static_cast<double>(x->ctrl_ns) * 1e-9;
    const bool drive = c4g_arm_byte(x->rx->infpar, arm) == C4G_STS_MOVING;
    // link angles of the arm's axes from D3 (the library's kinematics, coupling included)
    double qm[C4G_AXES_PER_ARM] = {0}, ql[C4G_AXES_PER_ARM] = {0};
    uint32_t nl = 0;
    bool have_q = false;
    if (c->kin_ok) {
        for (uint32_t l = 0; l < C4G_AXES_PER_ARM; l++) {
            const uint8_t o = s->map.open_of[arm][l];
            if (o == 0xFF || o >= x->rx->n_axes) break;
            qm[l] = static_cast<double>(x->rx->ax[o].actual_pos);
            nl = l + 1;
        }
        have_q = nl > 0 && c4g_kin_motor_to_link(&c->kin, qm, nl, ql) == C4G_OK;
    }
    // no reply, or one after the controller's next tick: that tick ran without it
    const bool missed = x->reply == nullptr || x->reply_ns - x->ctrl_ns > static_cast<int64_t>(period * 1e9);
    for (uint32_t i = 0; i < x->rx->n_axes; i++) {
        if (s->map.arm_of[i] != arm) continue;
        const unsigned logical = s->map.logical_of[i] + 1U;
        const double az = s->have_init ? static_cast<double>(s->init.az_lim[arm][logical - 1]) : 0.0;
        AxisLog *L = c->col->axis(logical, i + 1U, period, az);
        if (L == nullptr) continue;
        if (missed) L->late_ticks.push_back(static_cast<int64_t>(s->id) * kSessionStride + tick + 1);
        if (!c->col->window(L, t)) continue;
        const c4g_ctrl_axis_t &a = x->rx->ax[i];
        const float f[7] = {a.target_pos, a.target_vel, a.actual_pos, a.actual_vel, a.current_ref, a.ext[0], a.ext[1]};
        const bool lq = have_q && (logical - 1U) < nl;
        L->have_q = lq || (L->have_q && L->tick.empty());
        Collector::add(L, static_cast<int64_t>(s->id) * kSessionStride + tick, t,
                       a.mode, drive, f, lq ? ql[logical - 1U] : NAN);
    }
}

int read_capture(const std::string &path, Collector &col, InputInfo *info, std::string *err)
{
    char e[400];
    c4gh_cap_t *c = c4gh_cap_open(path.c_str(), e, sizeof e);
    if (c == nullptr) {
        *err = e;
        return -1;
    }
    // a tick takes a controller packet and its reply, over 256 bytes with their headers for
    // the axes of an arm: an upper bound of the ticks, so the logs never move while growing
    if (col.sel.lean && c4gh_cap_size(c) > 0) col.reserve = static_cast<std::size_t>(c4gh_cap_size(c) / 256U) + 1024U;
    c4gh_an_options_t o;
    c4gh_an_options_default(&o);
    CapCtx ctx;
    ctx.col = &col;
    ctx.info = info;
    o.on_exchange = on_exchange;
    o.ctx = &ctx;
    c4gh_an_t a;
    if (c4gh_an_init(&a, &o) != 0) {
        c4gh_cap_close(c);
        *err = "out of memory";
        return -1;
    }
    const bool show = col.sel.progress && isatty(2);
    c4gh_cap_pkt_t p;
    uint64_t bad = 0;
    int rc = 0;
    for (;;) {
        const c4gh_cap_res_t r = c4gh_cap_next(c, &p, e, sizeof e);
        if (r == C4GH_CAP_END) break;
        if (r == C4GH_CAP_FATAL) {
            *err = e;
            rc = -1;
            break;
        }
        if (r == C4GH_CAP_BAD) {
            if (++bad <= 10) std::fprintf(stderr, "c4g-ident: %s\n", e);
            continue;
        }
        if (r == C4GH_CAP_DATAGRAM) c4gh_an_datagram(&a, path.c_str(), &p);
        if (show && (c4gh_cap_counts(c)->frames & 0xFFFFU) == 0U && c4gh_cap_size(c) > 0) {
            std::fprintf(stderr, "\rc4g-ident: reading %s %3.0f %%", path.c_str(),
                         100.0 * static_cast<double>(c4gh_cap_pos(c)) / static_cast<double>(c4gh_cap_size(c)));
        }
    }
    if (show) std::fprintf(stderr, "\r\033[K");
    c4gh_an_file_end(&a, path.c_str());
    c4gh_an_free(&a);
    c4gh_cap_close(c);
    info->format = "capture (" + std::string(rc == 0 ? "complete" : "cut short") + ")";
    if (bad > 10) std::fprintf(stderr, "c4g-ident: %s: %llu damaged frames in all\n", path.c_str(), static_cast<unsigned long long>(bad));
    for (const AxisLog &L : *col.logs) info->have_kin = info->have_kin || L.have_q;
    info->reply_times = true;
    return rc;
}

// Splits a CSV line (no quoting in these files).
void split(const std::string &s, std::vector<std::string> *f)
{
    f->clear();
    std::size_t b = 0;
    for (;;) {
        const std::size_t e = s.find(',', b);
        f->push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
        if (e == std::string::npos) break;
        b = e + 1;
    }
}

bool num(const std::string &s, double *v)
{
    if (s.empty()) return false;
    char *end = nullptr;
    errno = 0;
    *v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0' || errno == ERANGE) {
        // "nan" is a value the controller sent: accepted, then dropped as non-finite
        return s == "nan" || s == "-nan" || s == "inf" || s == "-inf";
    }
    return true;
}

// The columns a moni CSV's rows are read from, by position (c4g-server, c4g-sim --csv).
const char *const kMoniCols[13] = {"t_s", "num", "axis", "arm", "logical", "rx_mode", "rx_d1", "rx_d2",
                                   "rx_d3", "rx_d4", "rx_d5", "rx_e1", "rx_e2"};
const char *const kExpAxis[8] = {"mode", "d1", "d2", "d3", "d4", "d5", "ext1", "ext2"};

int read_csv(const std::string &path, Collector &col, InputInfo *info, std::string *err)
{
    struct stat sb;
    if (stat(path.c_str(), &sb) == 0 && S_ISDIR(sb.st_mode)) {
        *err = path + ": " + std::strerror(EISDIR);
        return -1;
    }
    std::ifstream in(path);
    if (!in) {
        *err = path + ": " + std::strerror(errno);
        return -1;
    }
    std::string line;
    std::vector<std::string> f, hdr;
    uint64_t ln = 0;
    bool moni = false, exp = false;
    std::map<std::string, std::size_t> col_of;
    double t_prev = NAN;
    NumTicks nt;
    int64_t tick_moni = 0;
    bool skip_packet = false;   // moni: the rows of a repeated or out-of-order packet
    double prev_num = -1.0, prev_axis = 1e9;
    double period = 0.0;
    std::vector<double> dts;  // tick spacings: the period is their median (receive times jitter)
    // export CSV: (tick, reply latency [us]) of every row, +inf without a reply; judged late
    // against the period once it is known, by the capture's rule
    std::vector<std::pair<int64_t, double>> lat;
    std::size_t pf_col = 0, lu_col = 0, num_col = 0, ip_col = 0;
    bool have_lat = false;
    // export: the column of field k (kExpAxis) of OPEN index i, every one checked present
    std::size_t axcol[21][8] = {};
    bool axon[21] = {};
    unsigned last_session = 0;
    auto fail = [&](const std::string &why) {
        *err = path + ":" + std::to_string(ln) + ": " + why;
        return -1;
    };
    // an export header: every column read is looked up here, a missing one is named
    auto export_header = [&]() -> int {
        col_of.clear();
        for (std::size_t k = 0; k < hdr.size(); k++) col_of[hdr[k]] = k;
        auto need = [&](const std::string &name, std::size_t *at) -> int {
            const auto it = col_of.find(name);
            if (it == col_of.end()) return fail("header: column " + name + " missing");
            *at = it->second;
            return 0;
        };
        if (need("ctrl_num", &num_col) != 0 || need("ctrl_infpar", &ip_col) != 0) return -1;
        const bool pf = col_of.count("pc_frame") != 0, lu = col_of.count("latency_us") != 0;
        if (pf != lu) return fail(std::string("header: column ") + (pf ? "latency_us" : "pc_frame") + " missing");
        have_lat = pf && lu;
        if (have_lat) {
            pf_col = col_of["pc_frame"];
            lu_col = col_of["latency_us"];
        }
        info->reply_times = have_lat;
        unsigned axes = 0;
        for (unsigned i = 1; i <= 20; i++) {
            const std::string pre = "c" + std::to_string(i) + "_";
            unsigned have = 0;
            for (int k = 0; k < 8; k++) have += col_of.count(pre + kExpAxis[k]) != 0 ? 1U : 0U;
            axon[i] = have > 0;
            if (have == 0) continue;
            axes++;
            for (int k = 0; k < 8; k++) {
                if (need(pre + kExpAxis[k], &axcol[i][k]) != 0) return -1;
            }
        }
        if (axes == 0) return fail("header: no controller axis columns (c1_mode, c1_d1, ...)");
        return 0;
    };
    while (std::getline(in, line)) {
        ln++;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        split(line, &f);
        if (!moni && !exp) {
            hdr = f;
            if (hdr.size() >= 3 && hdr[0] == "t_s" && hdr[1] == "num" && hdr[2] == "axis") {
                moni = true;
                info->format = "moni CSV";
                for (std::size_t k = 0; k < 13; k++) {
                    if (k >= hdr.size()) return fail("header: column " + std::string(kMoniCols[k]) + " missing");
                    if (hdr[k] != kMoniCols[k]) {
                        return fail("header field " + std::to_string(k + 1) + ": expected " + kMoniCols[k] + ", found '" +
                                    shown(hdr[k], 40) + "'");
                    }
                }
            } else if (hdr.size() >= 3 && hdr[0] == "session" && hdr[1] == "tick" && hdr[2] == "time") {
                exp = true;
                info->format = "export CSV";
                if (export_header() != 0) return -1;
            } else {
                return fail("not a capture, a c4g-server moni CSV (--moni-type 0) or a c4g-replay export CSV: header '" +
                            shown(line, 60) + "'");
            }
            continue;
        }
        if (exp && f[0] == "session") {  // a new header (the axis count changed)
            hdr = f;
            if (export_header() != 0) return -1;
            continue;
        }
        if (f.size() != hdr.size()) {
            return fail("expected " + std::to_string(hdr.size()) + " fields, found " + std::to_string(f.size()));
        }
        if (moni) {
            // t_s,num,axis,arm,logical,rx_mode,rx_d1..rx_d5,rx_e1,rx_e2,rx_e3,...
            double v[16];
            for (int k = 0; k < 13; k++) {
                if (!num(f[static_cast<std::size_t>(k)], &v[k])) {
                    return fail("field " + std::to_string(k + 1) + " (" + shown(hdr[static_cast<std::size_t>(k)], 40) + "): '" +
                                shown(f[static_cast<std::size_t>(k)], 40) + "' is not a number");
                }
            }
            if (!(v[1] >= 0 && v[1] <= 0x7FFF && v[1] == std::floor(v[1]))) {
                return fail("field 2 (num): '" + shown(f[1], 40) + "' is not a NUM 0..32767");
            }
            // a packet's rows carry one NUM and rising OPEN indexes: a new packet starts where either breaks
            if (v[1] != prev_num || v[2] <= prev_axis) {
                const int64_t before = nt.tick;
                skip_packet = !nt.next(static_cast<int32_t>(v[1]), info, &tick_moni);
                info->ticks++;
                if (!skip_packet) {
                    // the spacing of consecutive NUMs only: a gap would lengthen the period
                    if (!std::isnan(t_prev) && v[0] > t_prev && tick_moni == before + 1 && dts.size() < 4096) {
                        dts.push_back(v[0] - t_prev);
                    }
                    t_prev = v[0];
                }
            }
            prev_num = v[1];
            prev_axis = v[2];
            if (skip_packet) continue;
            if (static_cast<unsigned>(v[3]) != col.sel.arm) continue;
            if (!(v[4] >= 1 && v[4] <= 10)) return fail("field 5 (logical): " + shown(f[4], 40) + " is not 1..10");
            AxisLog *L = col.axis(static_cast<unsigned>(v[4]), static_cast<unsigned>(v[2]), 0.0, 0.0);
            if (L == nullptr || !col.window(L, v[0])) continue;
            const float d[7] = {static_cast<float>(v[6]), static_cast<float>(v[7]), static_cast<float>(v[8]),
                                static_cast<float>(v[9]), static_cast<float>(v[10]), static_cast<float>(v[11]),
                                static_cast<float>(v[12])};
            Collector::add(L, tick_moni, v[0], static_cast<int32_t>(v[5]), true, d, NAN);
        } else {
            double s, tk, t, nm;
            if (!num(f[0], &s) || !num(f[1], &tk) || !num(f[2], &t)) return fail("session, tick or time is not a number");
            if (col.sel.session != 0 && static_cast<unsigned>(s) != col.sel.session) continue;
            if (!num(f[num_col], &nm) || !(nm >= 0 && nm <= 0x7FFF && nm == std::floor(nm))) {
                return fail("field ctrl_num: '" + shown(f[num_col], 40) + "' is not a NUM 0..32767");
            }
            if (static_cast<unsigned>(s) != last_session) {
                last_session = static_cast<unsigned>(s);
                nt = NumTicks();
                t_prev = NAN;
            }
            info->ticks++;
            int64_t tick = 0;
            const int64_t before = nt.tick;
            if (!nt.next(static_cast<int32_t>(nm), info, &tick)) continue;
            if (!std::isnan(t_prev) && t > t_prev && tick == before + 1 && dts.size() < 4096) dts.push_back(t - t_prev);
            t_prev = t;
            const int64_t stamp = static_cast<int64_t>(s) * kSessionStride + tick;
            if (have_lat) {
                double us = std::numeric_limits<double>::infinity();
                if (!f[pf_col].empty() && !num(f[lu_col], &us)) {
                    return fail("field latency_us: '" + shown(f[lu_col], 40) + "' is not a number");
                }
                lat.emplace_back(stamp + 1, us);
            }
            char *end = nullptr;
            const unsigned long infpar = std::strtoul(f[ip_col].c_str(), &end, 16);
            if (f[ip_col].empty() || *end != '\0') {
                return fail("field ctrl_infpar: '" + shown(f[ip_col], 40) + "' is not a hex word");
            }
            const bool drive = ((infpar >> (8U * (col.sel.arm - 1U))) & 0xFFU) == C4G_STS_MOVING;
            for (unsigned i = 1; i <= 20; i++) {
                if (!axon[i]) continue;
                const std::string pre = "c" + std::to_string(i) + "_";
                // export rows carry no axis map: OPEN index i is logical axis i of the selected arm
                AxisLog *L = col.axis(i, i, 0.0, 0.0);
                if (L == nullptr || !col.window(L, t)) continue;
                float d[7];
                double mode;
                const std::size_t mc = axcol[i][0];
                if (!num(f[mc], &mode)) return fail("field " + pre + "mode: '" + shown(f[mc], 40) + "' is not a number");
                for (int k = 0; k < 7; k++) {
                    double x;
                    const std::size_t c = axcol[i][k + 1];
                    if (!num(f[c], &x)) return fail("field " + pre + kExpAxis[k + 1] + ": '" + shown(f[c], 40) + "' is not a number");
                    d[k] = static_cast<float>(x);
                }
                Collector::add(L, stamp, t, static_cast<int32_t>(mode), drive, d, NAN);
            }
        }
    }
    if (!moni && !exp) return fail("empty file");
    if (!dts.empty()) {
        std::nth_element(dts.begin(), dts.begin() + static_cast<long>(dts.size() / 2), dts.end());
        period = dts[dts.size() / 2];
    }
    for (AxisLog &L : *col.logs) {
        if (period > 0.0) L.period = std::round(period * 1e4) / 1e4;
        // no reply, or one after the controller's next tick: that tick ran without it
        for (const auto &x : lat) {
            if (!(x.second <= L.period * 1e6)) L.late_ticks.push_back(x.first);
        }
        std::sort(L.late_ticks.begin(), L.late_ticks.end());
    }
    return 0;
}

}  // namespace

int read_input(const std::string &path, const Selection &sel, std::vector<AxisLog> *logs, InputInfo *info,
               std::string *err)
{
    info->path = path;
    Collector col(sel, logs);
    const int rc = is_capture(path) ? read_capture(path, col, info, err) : read_csv(path, col, info, err);
    if (rc == 0 && sel.keep_late) {
        for (AxisLog &L : *logs) L.late_ticks.clear();
    }
    return rc;
}

namespace {

struct InitGrab {
    bool found = false;
    c4g_init_t init{};
};

void grab_init(void *vp, const c4gh_an_exchange_t *x)
{
    InitGrab *g = static_cast<InitGrab *>(vp);
    if (!g->found && x->s != nullptr && x->s->have_init) {
        g->init = x->s->init;
        g->found = true;
    }
}

}  // namespace

bool read_init(const std::string &path, c4g_init_t *out, std::string *err)
{
    char e[400];
    c4gh_cap_t *c = c4gh_cap_open(path.c_str(), e, sizeof e);
    if (c == nullptr) {
        *err = e;
        return false;
    }
    c4gh_an_options_t o;
    c4gh_an_options_default(&o);
    InitGrab g;
    o.on_exchange = grab_init;
    o.ctx = &g;
    c4gh_an_t a;
    if (c4gh_an_init(&a, &o) != 0) {
        c4gh_cap_close(c);
        *err = "out of memory";
        return false;
    }
    bool ok = true;
    c4gh_cap_pkt_t p;
    while (!g.found) {
        const c4gh_cap_res_t r = c4gh_cap_next(c, &p, e, sizeof e);
        if (r == C4GH_CAP_END) break;
        if (r == C4GH_CAP_FATAL) {
            *err = e;
            ok = false;
            break;
        }
        if (r == C4GH_CAP_DATAGRAM) c4gh_an_datagram(&a, path.c_str(), &p);
    }
    c4gh_an_free(&a);
    c4gh_cap_close(c);
    if (ok && !g.found) {
        *err = path + ": no initialization packet (a capture of a session's start is needed)";
        ok = false;
    }
    if (ok) *out = g.init;
    return ok;
}

}  // namespace ident
