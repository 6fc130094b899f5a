-- SPDX-License-Identifier: MIT
--[[
c4gopen.lua: Wireshark / tshark dissector for the Comau C4G Open real-time UDP protocol
(libc4gopen, docs/protocol.md and docs/wireshark.md). Plain Lua for Wireshark 3.x / 4.x
(tested with tshark 4.0, tests/e2e/wireshark.sh).

WHAT IT DISSECTS (all fields little-endian; int32 / uint32 / IEEE-754 binary32)
  * Cyclic packets, both directions: 12-byte header NUM (int32), INFPAR (uint32, one byte
    per arm, byte 0 = ARM 1), CMD (uint32, one byte per arm), then per open axis, in OPEN
    index order, 36 bytes: SM mode (int32), D1..D5, EXT1..EXT3 (float32). 12 + 36 n bytes,
    n = 1..20. D1..D5 are labelled by direction: controller -> PC target position, target
    velocity, actual position, actual velocity, reference current; PC -> controller target
    position, target velocity, measure, velocity contribution, current contribution.
  * Synchronization packets (controller, cyclic shape, zero-filled: NUM 1..9 before the
    initialization packet and the 2 after it) and the PC's 732-byte replies.
  * The 1200-byte initialization packet (controller, NUM 10) and the PC's echo (same bytes,
    NUM 11 under the plus-one policy or 10 under echo): all 300 fields, per arm and axis.
  * Expert info: non-finite floats, unknown mode codes, lengths that are no C4G Open packet,
    NUM outside 0..0x7FFF, initialization fields out of range, an echo that differs from
    the initialization packet in more than NUM, a reply NUM that answers nothing.
  Filter fields: c4g.dir ("ctrl" / "pc": who sent it), c4g.type ("sync", "sync-reply",
  "init", "init-echo", "cyclic"; "unknown" for a datagram of no C4G Open length), c4g.num,
  c4g.infpar, c4g.cmd, c4g.axis (OPEN index, 1-based), c4g.mode, c4g.d1..c4g.d5,
  c4g.ext1..c4g.ext3, c4g.init.<name> (num, n_field_pck, n_field_ax, n_ax_open,
  open_mask, field_type, period_ms, open_ax, cal_data, az_lim, version_major,
  version_minor, version_build, ax_info, tx_rate, follow_error), plus c4g.dir_by,
  c4g.n_axes, c4g.arm, c4g.arm_axis, c4g.response_to, c4g.response_in, c4g.response_time.

HOW THE DIRECTION IS DECIDED (per conversation = address/port pair; no fixed port assumed)
  The strongest rule seen so far decides (1-2 over 3 over 4-5); c4g.dir_by names it.
  1. "init": a 1200-byte datagram that is not the echo of the one just before it comes
     from the controller. "init-echo": a 1200-byte datagram equal, from byte 4 on, to the
     1200-byte datagram the other endpoint sent just before comes from the PC (one with
     NUM 11 and no initialization packet before it is taken as an echo too).
  2. "sync-reply": a 732-byte datagram that answers the shorter cyclic-shaped datagram the
     other endpoint sent just before (same bytes after NUM, zeros after them, NUM equal or
     + 1) comes from the PC.
  3. "timing": in the cyclic phase the PC's packet follows the controller's within a
     fraction of the period, with the controller's NUM + 1 (0x7FFF -> 1) or the same NUM.
     For each pair of consecutive same-length cyclic datagrams from the two endpoints whose
     NUMs relate that way, the gap is recorded per orientation; once both orientations have
     5 samples, the one whose median gap is at most half the other's is controller -> PC.
  4. "port": datagrams TO a port of the "PC ports" preference (default 1000-1001) come
     from the controller (and FROM such a port, from the PC).
  5. "first": the first datagram seen in the conversation comes from the controller (it is
     the UDP client and speaks first).
  Rules 1-2 decide a conversation for good, rule 3 until rule 1-2 evidence arrives, rules
  4-5 only until any of 1-3 does. A one-pass read (plain tshark) labels the datagrams seen
  before the evidence with the provisional answer; Wireshark's GUI and `tshark -2` label
  them again with the conversation's final answer (cyclic datagrams only). Preference
  c4g.trust_ports puts rule 4 before rule 3 (a capture without the handshake of a PC that
  answers later than 2/3 of the period). A datagram quoted in an ICMP error or cut by the
  snapshot length is shown, never learnt from (c4g.dir_by "quoted").
  The packet type then follows the PC session's state machine: a controller datagram of
  cyclic shape whose body (after NUM) is all zero is a synchronization packet before the
  initialization packet (at the start of a capture: if its NUM is at most 12) and for the
  2 packets after it (none after a client restart, 506); a 732-byte PC datagram answering
  a synchronization packet is a sync-reply; every other cyclic-shaped datagram is cyclic.

REPLY LINKS
  A PC datagram answers the newest controller packet of its conversation if no earlier one
  did and its NUM is that packet's NUM + 1 (0x7FFF -> 1) or the same NUM; once the init
  echo has shown the PC's policy (NUM 11: plus-one, 10: echo), only that one, as the
  controller does (c4g.response_to / response_in / response_time, else c4g.reply_num).

INSTALL AND USE
  One-off:      wireshark -X lua_script:tools/wireshark/c4gopen.lua capture.pcap
                tshark -X lua_script:tools/wireshark/c4gopen.lua -r capture.pcap
  Per user:     make wireshark-install-user   (copies it to ~/.local/lib/wireshark/plugins)
  System-wide:  make install (into $(PREFIX)/lib/wireshark/plugins; Wireshark searches it
                only when installed under the same prefix: its global Lua folder is the
                "Global Lua Plugins" line of `tshark -G folders`, on Debian
                /usr/lib/x86_64-linux-gnu/wireshark/plugins, set by WIRESHARK_PLUGIN_DIR=).
  Registered on UDP ports 1000 and 1001 (preference c4g.ports, e.g. -o c4g.ports:31000);
  any other port: Decode As "C4G" (tshark -d udp.port==31000,c4g).
  Filters: c4g.mode == 505, c4g.dir == "pc" && c4g.num == 100, c4g.type == "init".
--]]

local c4g = Proto("c4g", "Comau C4G Open")

local HEADER = 12
local AXIS = 36
local MAX_AXES = 20
local INIT_SIZE = 1200
local SYNC_REPLY = 732
local NUM_MAX = 0x7FFF
local ARMS = 4
local AXES_PER_ARM = 10
local OPEN_AX_NONE = 0xFF
local TIMING_SAMPLES = 5
local TIMING_KEEP = 15

-- The mode vocabulary (include/c4gopen_wire.h, C4G_MODE_TABLE): code, name, description.
local MODES = {
    { 0, "MODE_0", "SMP+ generates the trajectory and closes the loops; PC data ignored" },
    { 10, "MODE_0_DEBUG", "mode 0': debug echo, the PC copies D1..D5 back" },
    { 1, "MODE_1", "PC generates the trajectory and closes the loops (currents)" },
    { 11, "MODE_1_STANDBY", "mode 1 exit: PC holds the robot while SMP+ switches back" },
    { 2, "MODE_2", "SMP+ generates the trajectory, the PC closes the loops (currents)" },
    { 12, "MODE_2_STANDBY", "mode 2 exit (set by PDL2): PC loops while SMP+ switches back" },
    { 3, "MODE_3", "SMP+ velocity target, PC velocity loop (not available)" },
    { 4, "MODE_4", "PC generates absolute position targets, SMP+ closes the loops" },
    { 14, "MODE_4_STANDBY", "mode 4 stand-by" },
    { 5, "MODE_5", "PC generates relative position targets, SMP+ closes the loops" },
    { 15, "MODE_5_STANDBY", "mode 5 stand-by" },
    { 6, "MODE_6", "PC generates velocity targets (not available)" },
    { 7, "MODE_7", "PC adds a position delta to the SMP+ trajectory" },
    { 17, "MODE_7_STANDBY", "mode 7 exit: SMP+ ends its motion, PC sends a null delta" },
    { 170, "MODE_7_STANDBY_EXIT", "mode 7 exit: null references, then mode 0" },
    { 8, "MODE_8", "PC adds a velocity contribution to the SMP+ trajectory" },
    { 9, "MODE_9", "PC adds a current contribution to the SMP+ control" },
    { 101, "MODE_101", "accelerometer measure from the PC (not available)" },
    { 102, "MODE_102", "vision measure from the PC (not available)" },
    { 103, "MODE_103", "force measure from the PC (not available)" },
    { 201, "MODE_201", "PC cartesian position target (not available)" },
    { 202, "MODE_202", "PC cartesian position delta (not available)" },
    { 500, "FREEZING_A", "active freezing: SMP+ stops checking the PC (from mode 0)" },
    { 501, "DRIVING_ON", "drive on in progress: mode requests are ignored" },
    { 502, "FREEZING_P_IN", "passive freezing: SMP+ stops sending" },
    { 503, "FREEZING_P_OUT", "passive freezing over" },
    { 504, "EXIT_OPEN", "end of communication" },
    { 505, "DRIVE_OFF", "PC request: drive off" },
    { 506, "SVR_RESTART", "client restart: a new initialization packet follows" },
    { 508, "FOLLOW_ERROR", "PC request: following error" },
}
local MODE_RESTART = 506
local mode_names, mode_desc = {}, {}
for _, m in ipairs(MODES) do
    mode_names[m[1]] = m[2]
    mode_desc[m[1]] = m[3]
end

-- D1..D5 meaning by sender.
local D_LABELS = {
    ctrl = { "target position [turns]", "target velocity [turns/tick]", "actual position [turns]",
             "actual velocity [turns/tick]", "reference current [A]" },
    pc = { "target position [turns]", "target velocity [turns/tick]", "measure",
           "velocity contribution [turns/tick]", "current contribution [A]" },
}
local FIELD_TYPE_NAMES = { "num", "infPar", "cmd", "sMax", "d1", "d2", "d3", "d4", "d5",
                           "ext1", "ext2", "ext3" }

-- ---------------------------------------------------------------- fields
local f = {
    dir = ProtoField.string("c4g.dir", "Sender", base.ASCII, "ctrl (controller, SMP+) or pc"),
    dir_by = ProtoField.string("c4g.dir_by", "Sender decided by", base.ASCII,
        "rule that decided the direction: init, init-echo, sync-reply, timing, port, first"),
    type = ProtoField.string("c4g.type", "Packet type", base.ASCII,
        "sync, sync-reply, init, init-echo, cyclic (unknown: no C4G Open length)"),
    n_axes = ProtoField.uint8("c4g.n_axes", "Axes in the packet", base.DEC),
    num = ProtoField.int32("c4g.num", "NUM", base.DEC),
    infpar = ProtoField.uint32("c4g.infpar", "INFPAR", base.HEX),
    cmd = ProtoField.uint32("c4g.cmd", "CMD", base.HEX),
    axis = ProtoField.uint8("c4g.axis", "Axis (OPEN index)", base.DEC),
    arm = ProtoField.uint8("c4g.arm", "Arm", base.DEC),
    arm_axis = ProtoField.uint8("c4g.arm_axis", "Logical axis of the arm", base.DEC),
    mode = ProtoField.int32("c4g.mode", "Mode (SM)", base.DEC, mode_names),
    trailing = ProtoField.bytes("c4g.trailing", "Bytes after the last whole axis"),
    response_to = ProtoField.framenum("c4g.response_to", "Reply to the controller packet in frame",
        base.NONE, frametype and frametype.RESPONSE),
    response_in = ProtoField.framenum("c4g.response_in", "Reply from the PC in frame",
        base.NONE, frametype and frametype.REQUEST),
    response_time = ProtoField.relative_time("c4g.response_time", "Reply time",
        "time from the controller packet to the PC's reply"),
    infpar_arm = {}, cmd_arm = {},
}
-- D1..D5 and EXT1..EXT3 once per sender: same abbreviation (c4g.d1 ... matches both), the
-- name tells the meaning. f.data[dir][k], k = 1..8.
f.data = { ctrl = {}, pc = {} }
for dir, labels in pairs(D_LABELS) do
    for k = 1, 5 do
        f.data[dir][k] = ProtoField.float("c4g.d" .. k, "D" .. k .. " " .. labels[k])
    end
    for k = 1, 3 do
        f.data[dir][5 + k] = ProtoField.float("c4g.ext" .. k, "EXT" .. k)
    end
end
for a = 1, ARMS do
    local mask = 0xFF * (256 ^ (a - 1))
    f.infpar_arm[a] = ProtoField.uint32("c4g.infpar.arm" .. a, "Arm " .. a, base.DEC, nil, mask)
    f.cmd_arm[a] = ProtoField.uint32("c4g.cmd.arm" .. a, "Arm " .. a, base.DEC, nil, mask)
end

local fi = {
    num = ProtoField.int32("c4g.init.num", "NUM (nblip)", base.DEC),
    n_field_pck = ProtoField.int32("c4g.init.n_field_pck", "nFieldPck", base.DEC),
    n_field_ax = ProtoField.int32("c4g.init.n_field_ax", "nFieldAx", base.DEC),
    n_ax_open = ProtoField.int32("c4g.init.n_ax_open", "nAxOpen", base.DEC),
    open_mask = ProtoField.int32("c4g.init.open_mask", "OpenMask (start-up mode)", base.DEC),
    field_type = ProtoField.int32("c4g.init.field_type", "Field type", base.DEC),
    period_ms = ProtoField.int32("c4g.init.period_ms", "Period [ms]", base.DEC),
    open_ax = ProtoField.int32("c4g.init.open_ax", "OpenAx (OPEN index, 0-based)", base.DEC),
    cal_data = ProtoField.float("c4g.init.cal_data", "CalData [turns]"),
    az_lim = ProtoField.float("c4g.init.az_lim", "AzLim [A]"),
    version_major = ProtoField.int32("c4g.init.version_major", "Version major", base.DEC),
    version_minor = ProtoField.int32("c4g.init.version_minor", "Version minor", base.DEC),
    version_build = ProtoField.int32("c4g.init.version_build", "Version build", base.DEC),
    ax_info = ProtoField.float("c4g.init.ax_info", "AxInfo"),
    tx_rate = ProtoField.float("c4g.init.tx_rate", "TxRate"),
    follow_error = ProtoField.float("c4g.init.follow_error", "FollowError [turns]"),
}

local list = {}
for _, k in ipairs({ "dir", "dir_by", "type", "n_axes", "num", "infpar", "cmd", "axis", "arm",
                     "arm_axis", "mode", "trailing", "response_to", "response_in",
                     "response_time" }) do
    list[#list + 1] = f[k]
end
for _, t in ipairs({ f.data.ctrl, f.data.pc, f.infpar_arm, f.cmd_arm }) do
    for _, x in ipairs(t) do list[#list + 1] = x end
end
for _, x in pairs(fi) do list[#list + 1] = x end
c4g.fields = list

local ex = {
    bad_length = ProtoExpert.new("c4g.bad_length", "Length is not a C4G Open packet",
        expert.group.MALFORMED, expert.severity.ERROR),
    nonfinite = ProtoExpert.new("c4g.nonfinite", "Non-finite float (NaN or infinity)",
        expert.group.MALFORMED, expert.severity.WARN),
    unknown_mode = ProtoExpert.new("c4g.unknown_mode", "Unknown mode code",
        expert.group.PROTOCOL, expert.severity.WARN),
    num_range = ProtoExpert.new("c4g.num_range", "NUM outside 0..0x7FFF",
        expert.group.PROTOCOL, expert.severity.WARN),
    init_field = ProtoExpert.new("c4g.init_field", "Initialization field out of range",
        expert.group.PROTOCOL, expert.severity.WARN),
    echo_mismatch = ProtoExpert.new("c4g.echo_mismatch",
        "Echo differs from the packet it answers in more than NUM",
        expert.group.PROTOCOL, expert.severity.WARN),
    reply_num = ProtoExpert.new("c4g.reply_num", "Reply NUM answers no controller packet",
        expert.group.SEQUENCE, expert.severity.NOTE),
}
c4g.experts = { ex.bad_length, ex.nonfinite, ex.unknown_mode, ex.num_range, ex.init_field,
                ex.echo_mismatch, ex.reply_num }

-- ---------------------------------------------------------------- preferences
c4g.prefs.ports = Pref.range("PC ports", "1000-1001",
    "UDP ports of the C4G Open PC (server): the dissector is registered on them, and a "
    .. "datagram to one of them comes from the controller when nothing better tells", 65535)
c4g.prefs.trust_ports = Pref.bool("Trust the PC ports over the timing rule", false,
    "Let the PC ports decide the direction before the timing rule (for a capture without "
    .. "the start-up handshake of a PC that answers late in the period)")

local pc_ports = {}
local registered = ""
local udp_table = DissectorTable.get("udp.port")

local function parse_ranges(s)
    local r = {}
    for part in string.gmatch(s or "", "[^,%s]+") do
        local a, b = part:match("^(%d+)%-(%d+)$")
        if a then
            r[#r + 1] = { tonumber(a), tonumber(b) }
        elseif tonumber(part) then
            r[#r + 1] = { tonumber(part), tonumber(part) }
        end
    end
    return r
end

local function is_pc_port(p)
    for _, x in ipairs(pc_ports) do
        if p >= x[1] and p <= x[2] then return true end
    end
    return false
end

local function register_ports()
    if registered ~= "" then udp_table:remove(registered, c4g) end
    registered = c4g.prefs.ports or ""
    if registered ~= "" then udp_table:add(registered, c4g) end
    pc_ports = parse_ranges(registered)
end

function c4g.prefs_changed()
    register_ports()
end

-- ---------------------------------------------------------------- helpers
-- Inside an ICMP error the UDP payload is a quoted copy: dissect it, never learn from it.
local icmp_type = Field.new("icmp.type")
local icmpv6_type = Field.new("icmpv6.type")

local function cyclic_axes(len)
    if len >= HEADER + AXIS and len <= HEADER + AXIS * MAX_AXES and (len - HEADER) % AXIS == 0 then
        return math.floor((len - HEADER) / AXIS)
    end
    return nil
end

local function reply_num(n)
    if n == NUM_MAX then return 1 end
    return n + 1
end

-- Reply NUM r answers controller NUM q under the NUM policy: "plus-one" (q + 1, 0x7FFF -> 1),
-- "echo" (q) or nil (not known yet: either).
local function answers(q, r, policy)
    if q == nil or r == nil then return false end
    if policy == "plus-one" then return r == reply_num(q) end
    if policy == "echo" then return r == q end
    return r == q or r == reply_num(q)
end

local zeros_cache = {}
local function zeros(n)
    local z = zeros_cache[n]
    if not z then
        z = string.rep("\0", n)
        zeros_cache[n] = z
    end
    return z
end

local function finite(v)
    return v == v and v ~= math.huge and v ~= -math.huge
end

-- Shortest decimal text that reads back as the same float32.
local function fmt_float(v, raw)
    if v ~= v then return "NaN" end
    if v == math.huge then return "inf" end
    if v == -math.huge then return "-inf" end
    for p = 6, 8 do
        local s = string.format("%." .. p .. "g", v)
        if Struct.pack("<f", tonumber(s)) == raw then return s end
    end
    return string.format("%.9g", v)
end

local function median(t)
    local c = {}
    for i, x in ipairs(t) do c[i] = x end
    table.sort(c)
    return c[math.floor((#c + 1) / 2)]
end

local function ns_time(ns)
    return NSTime.new(math.floor(ns / 1e9), ns % 1e9)
end

-- ---------------------------------------------------------------- state
-- convs[key]: per address/port pair; frames[n]: what the first pass decided for frame n.
local convs, frames

local function reset_state()
    convs = {}
    frames = {}
end
reset_state()

function c4g.init()
    reset_state()
end

local LEVEL = { first = 1, port = 1, timing = 2, init = 3, ["init-echo"] = 3, ["sync-reply"] = 3 }

local function set_ctrl(conv, ep, by)
    local lvl = LEVEL[by]
    if by == "port" and c4g.prefs.trust_ports then lvl = 2.5 end
    if lvl > conv.level or (lvl == 2 and conv.level == 2) then
        conv.ctrl, conv.by, conv.level = ep, by, lvl
    end
end

-- The axis map of an initialization packet: OPEN index (1-based) -> { arm, axis } (1-based).
local function init_map(tvb)
    local map = {}
    for a = 0, ARMS - 1 do
        for x = 0, AXES_PER_ARM - 1 do
            local v = tvb(228 + 40 * a + 4 * x, 4):le_int()
            if v >= 0 and v < MAX_AXES then map[v + 1] = { a + 1, x + 1 } end
        end
    end
    return map
end

-- Direction rules 1-5 (header comment) for one datagram of the first pass.
local function decide_direction(conv, src, dst, sport, dport, len, num, tvb, t)
    local last = conv.last
    local from_peer = last ~= nil and last.ep == dst
    if len == INIT_SIZE then
        local tail = tvb:raw(4, INIT_SIZE - 4)
        if from_peer and last.len == INIT_SIZE and last.tail == tail then
            set_ctrl(conv, dst, "init-echo")
        elseif num == 11 and not (from_peer and last.len == INIT_SIZE) and conv.level < 3 then
            set_ctrl(conv, dst, "init-echo")
        else
            set_ctrl(conv, src, "init")
        end
    elseif len == SYNC_REPLY and from_peer and last.len < SYNC_REPLY and cyclic_axes(last.len)
        and answers(last.num, num) and tvb:raw(4, last.len - 4) == last.tail
        and tvb:raw(last.len, SYNC_REPLY - last.len) == zeros(SYNC_REPLY - last.len) then
        set_ctrl(conv, dst, "sync-reply")
    elseif conv.level <= 2 and from_peer and last.len == len and cyclic_axes(len)
        and answers(last.num, num) then
        -- rule 3: gap from the peer's packet to this one, per orientation (peer -> me)
        local g = conv.gaps[dst]
        if not g then
            g = {}
            conv.gaps[dst] = g
        end
        g[#g + 1] = t - last.t
        if #g > TIMING_KEEP then table.remove(g, 1) end
        local h = conv.gaps[src]
        if h and #g >= TIMING_SAMPLES and #h >= TIMING_SAMPLES then
            local mg, mh = median(g), median(h)
            if mg * 2 <= mh then
                set_ctrl(conv, dst, "timing")
            elseif mh * 2 <= mg then
                set_ctrl(conv, src, "timing")
            end
        end
    end
    if conv.level == 0 then
        if is_pc_port(dport) and not is_pc_port(sport) then
            set_ctrl(conv, src, "port")
        elseif is_pc_port(sport) and not is_pc_port(dport) then
            set_ctrl(conv, dst, "port")
        else
            set_ctrl(conv, src, "first")
        end
    end
    return (src == conv.ctrl) and "ctrl" or "pc"
end

-- Packet type from the session state machine (header comment); updates the phase.
local function classify(conv, dir, len, num, tvb, body_zero)
    local n = cyclic_axes(len)
    if dir == "ctrl" then
        if len == INIT_SIZE then
            conv.phase = "post"
            conv.post_left = conv.restart and 0 or 2
            conv.restart = false
            return "init"
        elseif n then
            local ph = conv.phase
            if body_zero and ((ph == "unknown" and num >= 0 and num <= 12) or ph == "wait"
                or (ph == "post" and conv.post_left > 0)
                or (ph == "cyclic" and num == 1 and conv.last_ctrl and conv.last_ctrl.num ~= 0)) then
                if ph == "post" then
                    conv.post_left = conv.post_left - 1
                else
                    conv.phase = "wait"
                end
                return "sync"
            end
            conv.phase = "cyclic"
            for i = 0, n - 1 do
                if tvb(HEADER + AXIS * i, 4):le_int() == MODE_RESTART then conv.restart = true end
            end
            return "cyclic"
        end
        return "unknown"
    end
    if len == INIT_SIZE then return "init-echo" end
    -- answered or not: after a reply to the previous sync packet came late, this one's follows
    if len == SYNC_REPLY and conv.last_ctrl and conv.last_ctrl.type == "sync" then
        return "sync-reply"
    end
    if n then return "cyclic" end
    return "unknown"
end

local function conv_key(a, b)
    if a < b then return a .. "|" .. b end
    return b .. "|" .. a
end

-- First pass: decide direction and type, link replies, learn; returns the frame record.
local function learn(tvb, pinfo)
    local len = tvb:len()
    local src = tostring(pinfo.src) .. "/" .. pinfo.src_port
    local dst = tostring(pinfo.dst) .. "/" .. pinfo.dst_port
    local key = conv_key(src, dst)
    local conv = convs[key]
    if not conv then
        conv = { key = key, level = 0, gaps = {}, phase = "unknown", post_left = 0 }
        convs[key] = conv
    end
    local num = (len >= 4) and tvb(0, 4):le_int() or nil
    local t = pinfo.rel_ts
    local dir = decide_direction(conv, src, dst, pinfo.src_port, pinfo.dst_port, len, num, tvb, t)
    local body_zero = len > 4 and len <= SYNC_REPLY and tvb:raw(4, len - 4) == zeros(len - 4)
    local typ = classify(conv, dir, len, num, tvb, body_zero)
    local rec = { dir = dir, type = typ, by = conv.by, level = conv.level, conv = conv,
                  map = conv.map }
    if dir == "ctrl" then
        if typ == "init" then
            conv.map = init_map(tvb)
            conv.init_tail = tvb:raw(4, INIT_SIZE - 4)
            conv.policy = nil -- learnt again from this packet's echo
            rec.map = conv.map
        end
        conv.last_ctrl = { frame = pinfo.number, num = num, t = t, type = typ }
    else
        local lc = conv.last_ctrl
        if typ == "init-echo" and conv.init_tail then
            rec.echo_ok = (tvb:raw(4, INIT_SIZE - 4) == conv.init_tail)
        end
        if lc and not lc.answered and num ~= nil then
            if answers(lc.num, num, conv.policy) then
                lc.answered = true
                -- The init echo's NUM shows the PC's policy, as the controller locks on it:
                -- under plus-one a reply late past the next packet carries that packet's
                -- NUM and would otherwise pass for its echo.
                if typ == "init-echo" and lc.type == "init" then
                    conv.policy = (num == lc.num) and "echo" or "plus-one"
                end
                rec.response_to = lc.frame
                rec.response_ns = math.floor((t - lc.t) * 1e9 + 0.5)
                local lrec = frames[lc.frame]
                if lrec then lrec.response_in = pinfo.number end
            else
                rec.bad_reply = lc.num
                rec.policy = conv.policy
            end
        end
    end
    local tail = nil
    if len <= SYNC_REPLY and len > 4 then tail = tvb:raw(4, len - 4) end
    if len == INIT_SIZE then tail = tvb:raw(4, INIT_SIZE - 4) end
    conv.last = { ep = src, len = len, num = num, t = t, tail = tail }
    return rec
end

-- A copy inside an ICMP error, or a datagram cut by the capture's snapshot length: its
-- sender from what the conversation already knows, else from the PC ports; nothing learnt.
local function quoted_record(tvb, pinfo)
    local src = tostring(pinfo.src) .. "/" .. pinfo.src_port
    local dst = tostring(pinfo.dst) .. "/" .. pinfo.dst_port
    local conv = convs[conv_key(src, dst)]
    local dir, by = "?", "quoted"
    if conv and conv.ctrl then
        dir = (src == conv.ctrl) and "ctrl" or "pc"
    elseif is_pc_port(pinfo.dst_port) and not is_pc_port(pinfo.src_port) then
        dir = "ctrl"
    elseif is_pc_port(pinfo.src_port) and not is_pc_port(pinfo.dst_port) then
        dir = "pc"
    end
    local n = cyclic_axes(tvb:reported_len())
    local typ = (tvb:reported_len() == INIT_SIZE) and (dir == "pc" and "init-echo" or "init")
        or (n and "cyclic") or "unknown"
    return { dir = dir, type = typ, by = by, quoted = true }
end

-- ---------------------------------------------------------------- tree
-- true if the float32 with these bits is NaN or an infinity
local function nonfinite_bits(u)
    return (u >= 0x7F800000 and u < 0x80000000) or u >= 0xFF800000
end

local function mode_text(m)
    return (mode_names[m] or "unknown") .. " (" .. m .. ")"
end

local function add_mode(tree, range)
    local m = range:le_int()
    local item = tree:add_le(f.mode, range)
    if mode_desc[m] then
        item:append_text(": " .. mode_desc[m])
    else
        item:add_proto_expert_info(ex.unknown_mode, "Unknown mode code " .. m)
    end
    return m
end

local function add_header(tree, tvb, dir)
    local num = tvb(0, 4):le_int()
    local item = tree:add_le(f.num, tvb(0, 4))
    if num < 0 or num > NUM_MAX then
        item:add_proto_expert_info(ex.num_range, "NUM " .. num .. " is outside 0..0x7FFF")
    end
    local words = { { f.infpar, f.infpar_arm, 4 }, { f.cmd, f.cmd_arm, 8 } }
    for w, spec in ipairs(words) do
        local r = tvb(spec[3], 4)
        local wi = tree:add_le(spec[1], r)
        for a = 1, ARMS do
            local ai = wi:add_le(spec[2][a], r)
            local b = r:range(a - 1, 1):uint()
            if w == 1 and dir == "ctrl" and b == 5 then ai:append_text(" (STS_MOVING: drives ON)") end
            if w == 1 and dir == "pc" and b == 1 then ai:append_text(" (EXIT_FROM_OPEN)") end
        end
    end
    return num
end

local function add_axes(tree, tvb, dir, n, map)
    local fields = f.data[dir]
    local modes = {}
    for i = 1, n do
        local o = HEADER + AXIS * (i - 1)
        local ar = tvb(o, AXIS)
        local mr = tvb(o, 4)
        local m = mr:le_int()
        modes[i] = m
        local pos = map and map[i]
        local at
        if pos then
            at = tree:add(ar, string.format("Axis %d (arm %d, axis %d): %s", i, pos[1], pos[2],
                mode_text(m)))
            at:add(f.axis, ar, i):set_generated()
            at:add(f.arm, ar, pos[1]):set_generated()
            at:add(f.arm_axis, ar, pos[2]):set_generated()
        else
            at = tree:add(ar, string.format("Axis %d: %s", i, mode_text(m)))
            at:add(f.axis, ar, i):set_generated()
        end
        add_mode(at, mr)
        for k = 1, 8 do
            local r = tvb(o + 4 * k, 4)
            local item = at:add_le(fields[k], r)
            if nonfinite_bits(r:le_uint()) then
                item:add_proto_expert_info(ex.nonfinite, string.format("%s of axis %d is %s",
                    k <= 5 and ("D" .. k) or ("EXT" .. (k - 5)), i, fmt_float(r:le_float(), r:raw())))
            end
        end
    end
    return modes
end

local function modes_summary(modes)
    if #modes == 0 then return "" end
    local same = true
    for i = 2, #modes do
        if modes[i] ~= modes[1] then same = false end
    end
    if same then
        return string.format(" %s x%d", mode_names[modes[1]] or ("mode " .. modes[1]), #modes)
    end
    local s = {}
    for i, m in ipairs(modes) do s[i] = tostring(m) end
    return " modes " .. table.concat(s, ",")
end

-- One 4-byte field per logical axis of each arm, as a subtree Arm n -> Axis k.
local function add_arm_block(tree, tvb, base_off, field, title, is_float, describe, check)
    local bt = tree:add(tvb(base_off, 4 * ARMS * AXES_PER_ARM), title)
    for a = 1, ARMS do
        local ao = base_off + 40 * (a - 1)
        local at = bt:add(tvb(ao, 40), "Arm " .. a)
        for x = 1, AXES_PER_ARM do
            local r = tvb(ao + 4 * (x - 1), 4)
            local item = at:add_le(field, r)
            local v, text
            if is_float then
                v = r:le_float()
                text = fmt_float(v, r:raw())
                if not finite(v) then
                    item:add_proto_expert_info(ex.nonfinite, title .. " arm " .. a .. " axis " .. x
                        .. " is " .. text)
                end
            else
                v = r:le_int()
                text = tostring(v)
            end
            if describe then text = text .. describe(v) end
            item:set_text(string.format("Arm %d axis %d: %s", a, x, text))
            if check then
                local msg = check(v, a, x)
                if msg then item:add_proto_expert_info(ex.init_field, msg) end
            end
        end
    end
end

local function check_int(tree, tvb, off, field, label, ok, want)
    local v = tvb(off, 4):le_int()
    local item = tree:add_le(field, tvb(off, 4))
    if not ok(v) then
        item:add_proto_expert_info(ex.init_field, label .. " is " .. v .. ", expected " .. want)
    end
    return v
end

local function dissect_init(tree, tvb, typ)
    local it = tree:add(tvb(0, INIT_SIZE), "Initialization packet (300 fields)")
    check_int(it, tvb, 0, fi.num, "NUM", function(v)
        if typ == "init-echo" then return v == 10 or v == 11 end
        return v == 10
    end, typ == "init-echo" and "10 or 11" or "10")
    check_int(it, tvb, 4, fi.n_field_pck, "nFieldPck", function(v) return v == 3 end, "3")
    check_int(it, tvb, 8, fi.n_field_ax, "nFieldAx", function(v) return v == 9 end, "9")
    local n_open = check_int(it, tvb, 12, fi.n_ax_open, "nAxOpen",
        function(v) return v >= 1 and v <= MAX_AXES end, "1..20")
    -- which logical axes are open (OpenAx), to judge the per-axis blocks
    local open, used = {}, {}
    for a = 1, ARMS do
        open[a] = {}
        for x = 1, AXES_PER_ARM do
            local v = tvb(228 + 40 * (a - 1) + 4 * (x - 1), 4):le_int()
            open[a][x] = (v ~= OPEN_AX_NONE)
        end
    end
    add_arm_block(it, tvb, 16, fi.open_mask, "OpenMask (start-up mode per logical axis)", false,
        function(v)
            if v == OPEN_AX_NONE then return " (open, mode not specified)" end
            if mode_names[v] then return " (" .. mode_names[v] .. ")" end
            return ""
        end,
        function(v, a, x)
            if open[a][x] and v ~= OPEN_AX_NONE and not mode_names[v] then
                return "start-up mode " .. v .. " of an open axis is not a mode"
            end
        end)
    local tt = it:add(tvb(176, 48), "Field types (" .. #FIELD_TYPE_NAMES .. ")")
    for i, name in ipairs(FIELD_TYPE_NAMES) do
        local r = tvb(176 + 4 * (i - 1), 4)
        tt:add_le(fi.field_type, r):set_text(string.format("Field type %s: %d", name, r:le_int()))
    end
    check_int(it, tvb, 224, fi.period_ms, "Period", function(v) return v >= 1 and v <= 1000 end,
        "1..1000 ms")
    add_arm_block(it, tvb, 228, fi.open_ax, "OpenAx (OPEN index per logical axis)", false,
        function(v)
            if v == OPEN_AX_NONE then return " (not open)" end
            return string.format(" (c4g.axis %d)", v + 1)
        end,
        function(v)
            if v == OPEN_AX_NONE then return nil end
            if v < 0 or v >= n_open then
                return "OPEN index " .. v .. " is outside 0.." .. (n_open - 1)
            end
            if used[v] then return "OPEN index " .. v .. " used twice" end
            used[v] = true
        end)
    add_arm_block(it, tvb, 388, fi.cal_data, "CalData (calibration constants) [turns]", true)
    add_arm_block(it, tvb, 548, fi.az_lim, "AzLim (maximum current) [A]", true, nil,
        function(v, a, x)
            if v < 0 or (open[a][x] and v == 0) then
                return "AzLim " .. v .. (open[a][x] and " of an open axis must be > 0" or " must be >= 0")
            end
        end)
    local vt = it:add(tvb(708, 12), string.format("Version %d.%d.%d", tvb(708, 4):le_int(),
        tvb(712, 4):le_int(), tvb(716, 4):le_int()))
    vt:add_le(fi.version_major, tvb(708, 4))
    vt:add_le(fi.version_minor, tvb(712, 4))
    vt:add_le(fi.version_build, tvb(716, 4))
    add_arm_block(it, tvb, 720, fi.ax_info, "AxInfo (kinematic influence coefficients)", true)
    add_arm_block(it, tvb, 880, fi.tx_rate, "TxRate (transmission ratios)", true)
    add_arm_block(it, tvb, 1040, fi.follow_error, "FollowError (thresholds, 0 = none) [turns]",
        true, nil, function(v)
            if v < 0 then return "FollowError " .. v .. " must be >= 0" end
        end)
    local used_n = 0
    for _ in pairs(used) do used_n = used_n + 1 end
    if n_open >= 1 and n_open <= MAX_AXES and used_n ~= n_open then
        it:add_proto_expert_info(ex.init_field,
            "OpenAx opens " .. used_n .. " axes, nAxOpen is " .. n_open)
    end
    return n_open, tvb(224, 4):le_int()
end

-- ---------------------------------------------------------------- dissector
function c4g.dissector(tvb, pinfo, tree)
    local len = tvb:len()
    local quoted = (icmp_type() ~= nil) or (icmpv6_type() ~= nil) or len < tvb:reported_len()
    local rec
    if quoted then
        rec = quoted_record(tvb, pinfo)
    elseif not pinfo.visited then
        rec = learn(tvb, pinfo)
        frames[pinfo.number] = rec
    else
        rec = frames[pinfo.number] or { dir = "?", type = "unknown", by = "none" }
    end
    local dir, by = rec.dir, rec.by
    -- a later and better decision relabels the provisional ones (second pass only)
    if pinfo.visited and rec.conv and rec.level < rec.conv.level and rec.type == "cyclic" then
        local src = tostring(pinfo.src) .. "/" .. pinfo.src_port
        dir = (src == rec.conv.ctrl) and "ctrl" or "pc"
        by = rec.conv.by
    end
    local typ = rec.type

    pinfo.cols.protocol = "C4G"
    local root = tree:add(c4g, tvb(), string.format("Comau C4G Open, %s, %s", dir, typ))
    root:add(f.dir, dir):set_generated()
    root:add(f.dir_by, by):set_generated()
    root:add(f.type, typ):set_generated()

    local info = string.format("%s %s", dir, typ)
    local n = cyclic_axes(len)
    if len == INIT_SIZE then
        local n_open, period = dissect_init(root, tvb, typ)
        info = info .. string.format(" NUM=%d nAxOpen=%d period=%d ms", tvb(0, 4):le_int(),
            n_open, period)
        if typ == "init-echo" and rec.echo_ok == false then
            root:add_proto_expert_info(ex.echo_mismatch)
        end
    elseif rec.quoted and tvb:reported_len() == INIT_SIZE then
        root:add(tvb(), string.format("Initialization packet, %d of its 1200 bytes", len))
    elseif len >= HEADER then
        local hdr_dir = (dir == "pc") and "pc" or "ctrl"
        local num = add_header(root, tvb, hdr_dir)
        local whole = math.min(math.floor((len - HEADER) / AXIS), MAX_AXES)
        root:add(f.n_axes, whole):set_generated()
        local modes = add_axes(root, tvb, hdr_dir, whole, rec.map)
        info = info .. " NUM=" .. num .. modes_summary(modes)
        if not n then
            local rest = len - HEADER - AXIS * whole
            if rest > 0 then root:add(f.trailing, tvb(HEADER + AXIS * whole, rest)) end
        end
    end
    if len ~= INIT_SIZE and not n and not rec.quoted then
        root:add_proto_expert_info(ex.bad_length, "Length " .. len
            .. " is not 12 + 36 n (n = 1..20) nor 1200")
        info = info .. " [bad length " .. len .. "]"
    end
    if rec.response_to then
        root:add(f.response_to, rec.response_to):set_generated()
        root:add(f.response_time, ns_time(rec.response_ns)):set_generated()
    elseif rec.bad_reply then
        local q = rec.bad_reply
        local want = q .. " or " .. reply_num(q)
        if rec.policy == "plus-one" then want = reply_num(q) .. " (plus-one policy)" end
        if rec.policy == "echo" then want = q .. " (echo policy)" end
        root:add_proto_expert_info(ex.reply_num, string.format(
            "Reply NUM %d does not answer the last controller packet, NUM %d: want %s",
            tvb(0, 4):le_int(), q, want))
    end
    if rec.response_in then
        root:add(f.response_in, rec.response_in):set_generated()
    end
    pinfo.cols.info = info
    return len
end

-- Registration needs the dissector function above.
register_ports()
udp_table:add_for_decode_as(c4g)
