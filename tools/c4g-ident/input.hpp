// SPDX-License-Identifier: MIT
// Reading logged runs into per-axis logs: captures (pcap/pcapng through c4g-replay's reader
// and analysis), c4g-server's moni CSV (--moni-type 0) and c4g-replay's export CSV.
#ifndef C4G_IDENT_INPUT_HPP
#define C4G_IDENT_INPUT_HPP

#include "c4gopen_wire.h"
#include "c4gopen_engine.h"
#include "ident.hpp"

#include <string>
#include <vector>

namespace ident {

constexpr unsigned kMaxAxes = C4G_AXES_PER_ARM;  // logical axes of an arm

struct Selection {
    unsigned arm = 1;            // 1-based
    unsigned axes = 0;           // logical axes (bit 0 = axis 1); 0 = every open axis
    double from = 0.0, to = -1.0;// window [s] since the first tick; to < 0: open
    unsigned session = 0;        // captures: 0 = all
    bool progress = false;       // progress on stderr
    bool keep_late = false;      // keep the ticks after a late or missing PC reply
    // keep only what the rigid family reads (tick, D3, D4, D5, q): t, D1, D2, EXT1, EXT2
    // stay empty, and a capture's logs are reserved from its size (untouched pages cost no memory)
    bool lean = false;
    // --az-lim: the DSA current limit [A] of logical axis k+1 for logs that do not carry it
    // (CSV); 0 = not given. Captures read it from their init packet.
    double az_lim[kMaxAxes] = {};
};

struct InputInfo {
    std::string path, format;    // "pcap capture", "moni CSV", "export CSV"
    uint64_t ticks = 0;          // controller ticks read
    uint64_t sessions = 0;
    bool have_kin = false;
    // the arm's transmission from the first session's init packet (have_init_kin): the rigid
    // family needs Kr, which a CSV does not carry
    bool have_init_kin = false;
    c4g_kin_t kin{};
    bool reply_times = false;    // the input says when each PC reply came (capture, export CSV)
    // the controller's NUM sequence: gaps (packets missing from the log), how many packets
    // they miss in all, and packets dropped as repeated or out of order
    uint64_t num_gaps = 0, num_missing = 0, num_dups = 0;
};

// Reads @p path into one log per selected axis. 0 ok; otherwise an error (naming the file,
// line or offset, field and value) is in @p err.
int read_input(const std::string &path, const Selection &sel, std::vector<AxisLog> *logs, InputInfo *info,
               std::string *err);

// The initialization packet of the first session in capture @p path that has one (the
// arm's transmission, for excite --optimize --init). true, or false with why in @p err.
bool read_init(const std::string &path, c4g_init_t *out, std::string *err);

}  // namespace ident

#endif
