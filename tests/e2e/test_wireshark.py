# SPDX-License-Identifier: MIT
"""Checks the Wireshark dissector (tools/wireshark/c4gopen.lua) under real tshark against an
independent decode of the same captures.

Two readings of one capture, compared packet by packet:
- independent: `tshark -T fields -e frame.number -e udp.payload ...` (tshark's UDP layer
  only), the payload decoded here with `struct` (decode_payload, decode_init), the sender
  from the PC port, the packet type from the session rules (expected_kinds);
- dissector: `tshark -X lua_script:c4gopen.lua -T pdml`, every c4g.* field with its shown
  value, its position and its raw bytes (dissector_packets). A float is taken from its raw
  bytes (exact float32) after checking that the bytes sit at the right offset and that the
  value the dissector shows is their little-endian reading: `-T fields` prints 6 digits.

A third reading, `c4g-replay export` (CSV), is compared with the dissector's tick by tick
(export_compare; `export-compare`, or `capture --replay`): ticks() pairs each controller
cyclic packet with the PC reply the dissector linked to it (the CSV's ctrl_frame,
pc_frame); a row's ctrl_num/ctrl_infpar/ctrl_cmd and c{i}_mode, c{i}_d1..c{i}_ext3 are the
controller Packet's num, infpar, cmd and axes[i-1].mode, .data[0..7]; p{i}_* the PC
Packet's; latency_us its response_time. Floats printed with %.9g read back as the same
float32: compared bit for bit (so -0 is not 0), NaN by its sign only. Where the two differ
by design: the export's tick is a new controller NUM (a duplicate or late copy is none)
and its reply one the controller accepts (it decodes: NUM in range, known modes, finite
floats, the packet's length), while the dissector links by NUM and flags the rest with
expert info.

The captures: fixtures/wireshark/mode4-short.pcap (c4g-server --sine 0.25,2,0.5 against
c4g-sim -S fixtures/server/sim_mode4.scn, PC on port 31000), also with Decode As only and
from a mid-stream cut; crafted datagrams on the default port 1000 (expert info, every mode
code of C4G_MODE_TABLE, late sync replies); a fresh two-arm capture (c4g-sim -c
fixtures/sim/two-arms.ini, 1 ms period, 9 axes); and c4g-replay fixtures chosen for what they
add to the export comparison.
"""
import argparse
import csv
import io
import math
import os
import re
import signal
import struct
import subprocess
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor

from e2elib import wait_until

HEADER = 12
AXIS = 36
MAX_AXES = 20
INIT_SIZE = 1200
SYNC_REPLY = 732
NUM_MAX = 0x7FFF
ARMS = 4
AXES_PER_ARM = 10
DATA_NAMES = ["d1", "d2", "d3", "d4", "d5", "ext1", "ext2", "ext3"]

# The initialization packet in wire order: (name, count, struct code). 300 fields.
INIT_LAYOUT = [
    ("num", 1, "i"), ("n_field_pck", 1, "i"), ("n_field_ax", 1, "i"), ("n_ax_open", 1, "i"),
    ("open_mask", 40, "i"), ("field_type", 12, "i"), ("period_ms", 1, "i"),
    ("open_ax", 40, "i"), ("cal_data", 40, "f"), ("az_lim", 40, "f"),
    ("version_major", 1, "i"), ("version_minor", 1, "i"), ("version_build", 1, "i"),
    ("ax_info", 40, "f"), ("tx_rate", 40, "f"), ("follow_error", 40, "f"),
]
EXPERTS = {"c4g.bad_length", "c4g.nonfinite", "c4g.unknown_mode", "c4g.num_range",
           "c4g.init_field", "c4g.echo_mismatch", "c4g.reply_num"}


# ------------------------------------------------------------------ packet model
class Axis:
    """One axis block: mode and the 8 floats (d1..d5, ext1..ext3) as exact float32 values."""

    def __init__(self, mode, data, index=None):
        self.mode = mode
        self.data = list(data)          # [d1, d2, d3, d4, d5, ext1, ext2, ext3]
        self.index = index              # OPEN index, 1-based (dissector: c4g.axis)
        self.arm = None                 # dissector: c4g.arm / c4g.arm_axis, when known
        self.arm_axis = None

    def fields(self):
        return [self.mode] + self.data


class Packet:
    """One C4G Open datagram: header, axes, or the init fields (name -> list of values)."""

    def __init__(self, frame, length):
        self.frame = frame
        self.length = length
        self.dir = None                 # "ctrl" / "pc"
        self.type = None                # sync, sync-reply, init, init-echo, cyclic, unknown
        self.dir_by = None
        self.num = None
        self.infpar = None
        self.cmd = None
        self.axes = []
        self.init = None                # {name: [values]} for a 1200-byte packet
        self.time = None                # seconds (epoch), from tshark
        self.src_port = None
        self.dst_port = None
        self.response_to = None         # dissector only: c4g.response_to (frame)
        self.response_time = None       # dissector only: c4g.response_time (s)
        self.experts = []               # dissector only: expert abbreviations
        self.mode_labels = []           # dissector only: the mode items' labels


def cyclic_axes(length):
    if HEADER + AXIS <= length <= HEADER + AXIS * MAX_AXES and (length - HEADER) % AXIS == 0:
        return (length - HEADER) // AXIS
    return None


def f32(raw):
    return struct.unpack("<f", raw)[0]


def decode_init(payload):
    """The 300 fields of an initialization packet, {name: [values]} in wire order."""
    out, off = {}, 0
    for name, count, code in INIT_LAYOUT:
        out[name] = list(struct.unpack_from("<%d%s" % (count, code), payload, off))
        off += 4 * count
    assert off == INIT_SIZE
    return out


def decode_payload(frame, payload):
    """Independent decode of one UDP payload (bytes) into a Packet (no dir/type)."""
    p = Packet(frame, len(payload))
    if len(payload) == INIT_SIZE:
        p.init = decode_init(payload)
        p.num = p.init["num"][0]
        return p
    if len(payload) >= HEADER:
        p.num, p.infpar, p.cmd = struct.unpack_from("<iII", payload, 0)
        n = min((len(payload) - HEADER) // AXIS, MAX_AXES)
        for i in range(n):
            o = HEADER + AXIS * i
            mode = struct.unpack_from("<i", payload, o)[0]
            data = [f32(payload[o + 4 * k:o + 4 * k + 4]) for k in range(1, 9)]
            p.axes.append(Axis(mode, data, i + 1))
    return p


# ------------------------------------------------------------------ tshark runs
def tshark(args):
    """stdout of one tshark run; RuntimeError if it fails or reports a Lua error."""
    r = subprocess.run(["tshark"] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    err = r.stderr.decode(errors="replace")
    if r.returncode != 0 or "Lua" in err:
        raise RuntimeError("tshark %s: %s" % (" ".join(args), err[-2000:]))
    return r.stdout.decode()


def tshark_payloads(pcap):
    """Independent reading: [(frame, src_port, dst_port, time, payload bytes)], no Lua."""
    out = []
    text = tshark(["-r", pcap, "-T", "fields", "-e", "frame.number", "-e", "udp.srcport",
                   "-e", "udp.dstport", "-e", "frame.time_epoch", "-e", "udp.payload"])
    for line in text.splitlines():
        fr, sp, dp, t, hexp = line.split("\t")
        out.append((int(fr), int(sp), int(dp), float(t), bytes.fromhex(hexp)))
    return out


def decode_capture(pcap):
    """Independent Packets of a capture, {frame: Packet} (dir/type not set)."""
    pkts = {}
    for fr, sp, dp, t, payload in tshark_payloads(pcap):
        p = decode_payload(fr, payload)
        p.src_port, p.dst_port, p.time = sp, dp, t
        pkts[fr] = p
    return pkts


def lua_args(lua, opts):
    return ["-X", "lua_script:" + lua] + list(opts)


def pdml_args(pcap, lua, opts):
    # -J: only c4g and udp (with all their children) besides geninfo: a third less to parse
    return ["-r", pcap, "-T", "pdml", "-J", "c4g udp"] + lua_args(lua, opts)


class FieldOcc:
    """One occurrence of a field in the PDML: shown value, raw bytes, frame position."""
    __slots__ = ("name", "show", "showname", "value", "pos", "size")

    def __init__(self, el):
        a = el.attrib
        self.name = a.get("name")
        self.show = a.get("show")
        self.showname = a.get("showname")
        self.value = a.get("value")
        self.pos = int(a.get("pos", "0"))
        self.size = int(a.get("size", "0"))


def pdml_c4g_fields(xml):
    """{frame: (proto_pos, [FieldOcc in document order], proto_size, (udp src port, dst
    port))} for every frame with c4g in the PDML text `xml` (tshark -T pdml)."""
    root = ET.fromstring(xml)
    out = {}
    for pkt in root.iter("packet"):
        frame, ports = None, (None, None)
        for proto in pkt.iter("proto"):
            if proto.get("name") == "geninfo":
                for fld in proto.iter("field"):
                    if fld.get("name") == "num":
                        frame = int(fld.get("show"))
            if proto.get("name") == "udp" and ports == (None, None):
                got = {fld.get("name"): fld.get("show") for fld in proto.iter("field")}
                if "udp.srcport" in got and "udp.dstport" in got:
                    ports = (int(got["udp.srcport"]), int(got["udp.dstport"]))
            if proto.get("name") == "c4g":
                occ = [FieldOcc(el) for el in proto.iter("field")
                       if (el.get("name") or "").startswith("c4g.")]
                out[frame] = (int(proto.get("pos")), occ, int(proto.get("size")), ports)
    return out


def parse_float_show(show):
    s = show.lower()
    if s in ("nan", "-nan"):
        return float("nan")
    if s in ("inf", "infinity"):
        return float("inf")
    if s in ("-inf", "-infinity"):
        return float("-inf")
    return float(s)


def same_float(a, b):
    return (math.isnan(a) and math.isnan(b)) or a == b


def shown_matches(show, value):
    """The dissector's shown text reads as `value` to the printed precision (6 digits)."""
    v = parse_float_show(show)
    if math.isnan(value) or math.isinf(value):
        return same_float(v, value)
    return math.isclose(v, value, rel_tol=5.0000001e-6, abs_tol=0.0)


class DissectorError(Exception):
    pass


def dissector_packets(pcap, lua, opts, xml=None):
    """The dissector's reading, {frame: Packet} (xml: the PDML if already run). Raises
    DissectorError when a field's bytes are not where the protocol puts them or its shown
    value is not their decode."""
    if xml is None:
        xml = tshark(pdml_args(pcap, lua, opts))
    pkts = {}
    for frame, (base, occs, size, ports) in pdml_c4g_fields(xml).items():
        p = Packet(frame, size)
        p.src_port, p.dst_port = ports
        init = {}
        ax = None
        for o in occs:
            name = o.name
            if name in EXPERTS:
                p.experts.append(name)
                continue
            if name == "c4g.dir":
                p.dir = o.show
            elif name == "c4g.type":
                p.type = o.show
            elif name == "c4g.dir_by":
                p.dir_by = o.show
            elif name == "c4g.response_to":
                p.response_to = int(o.show)
            elif name == "c4g.response_time":
                p.response_time = float(o.show)
            elif name in ("c4g.num", "c4g.infpar", "c4g.cmd"):
                off = {"c4g.num": 0, "c4g.infpar": 4, "c4g.cmd": 8}[name]
                want_pos(o, base + off, frame)
                setattr(p, name[4:], int(o.show, 0))
                check_int_raw(o, int(o.show, 0), name == "c4g.num", frame)
            elif name == "c4g.axis":
                ax = Axis(None, [None] * 8, int(o.show))
                p.axes.append(ax)
                want_pos(o, base + HEADER + AXIS * (ax.index - 1), frame, AXIS)
            elif name == "c4g.arm":
                ax.arm = int(o.show)
            elif name == "c4g.arm_axis":
                ax.arm_axis = int(o.show)
            elif name == "c4g.mode":
                want_pos(o, base + HEADER + AXIS * (ax.index - 1), frame)
                ax.mode = int(o.show)
                p.mode_labels.append(o.showname)
                check_int_raw(o, ax.mode, True, frame)
            elif name[4:] in DATA_NAMES:
                k = DATA_NAMES.index(name[4:])
                want_pos(o, base + HEADER + AXIS * (ax.index - 1) + 4 * (k + 1), frame)
                ax.data[k] = float_occ(o, frame)
            elif name.startswith("c4g.init."):
                init.setdefault(name[9:], []).append(o)
        if init:
            p.init = {}
            off = 0
            for key, count, code in INIT_LAYOUT:
                got = init.get(key, [])
                if len(got) != count:
                    raise DissectorError("frame %d: %d c4g.init.%s fields, want %d"
                                         % (frame, len(got), key, count))
                vals = []
                for i, o in enumerate(got):
                    want_pos(o, base + off + 4 * i, frame)
                    if code == "f":
                        vals.append(float_occ(o, frame))
                    else:
                        vals.append(int(o.show))
                        check_int_raw(o, vals[-1], True, frame)
                p.init[key] = vals
                off += 4 * count
            p.num = p.init["num"][0]
        pkts[frame] = p
    return pkts


def want_pos(o, pos, frame, size=4):
    if o.pos != pos or o.size != size:
        raise DissectorError("frame %d: %s at %d+%d, want %d+%d"
                             % (frame, o.name, o.pos, o.size, pos, size))


def check_int_raw(o, v, signed, frame):
    raw = struct.pack("<i" if signed else "<I", v)
    if o.value is not None and bytes.fromhex(o.value) != raw:
        raise DissectorError("frame %d: %s shows %d, bytes %s" % (frame, o.name, v, o.value))


def float_occ(o, frame):
    v = f32(bytes.fromhex(o.value))
    if not shown_matches(o.show, v):
        raise DissectorError("frame %d: %s shows %s, its bytes %s are %r (little-endian)"
                             % (frame, o.name, o.show, o.value, v))
    return v


# ------------------------------------------------------------------ expectations
def expected_kinds(pkts, pc_port, start_phase="wait"):
    """Sender and type of every independent Packet: datagrams from pc_port are the PC's;
    types from the session rules (docs/protocol.md, start-up handshake)."""
    phase, post_left, restart, last_ctrl = start_phase, 0, False, None
    for fr in sorted(pkts):
        p = pkts[fr]
        p.dir = "pc" if p.src_port == pc_port else "ctrl"
        n = cyclic_axes(p.length)
        if p.dir == "ctrl":
            if p.length == INIT_SIZE:
                p.type = "init"
                post_left, restart, phase = (0 if restart else 2), False, "post"
            elif n:
                zero = p.infpar == 0 and p.cmd == 0 and all(
                    a.mode == 0 and all(x == 0 for x in a.data) for a in p.axes)
                if zero and (phase == "wait" or (phase == "post" and post_left > 0)):
                    p.type = "sync"
                    if phase == "post":
                        post_left -= 1
                else:
                    p.type, phase = "cyclic", "cyclic"
                    restart = restart or any(a.mode == 506 for a in p.axes)
            else:
                p.type = "unknown"
            last_ctrl = p
        else:
            if p.length == INIT_SIZE:
                p.type = "init-echo"
            elif p.length == SYNC_REPLY and last_ctrl is not None and last_ctrl.type == "sync":
                p.type = "sync-reply"
            elif n:
                p.type = "cyclic"
            else:
                p.type = "unknown"
    return pkts


def answers(q, r, policy=None):
    plus = 1 if q == NUM_MAX else q + 1
    return {"plus-one": r == plus, "echo": r == q}.get(policy, r == q or r == plus)


def expected_response_to(pkts):
    """{pc frame: ctrl frame}: each PC packet answers the newest controller packet before it,
    when its NUM is that packet's NUM or NUM + 1 and no earlier PC packet answered it; after
    the init echo, only under the policy its NUM showed (11: plus-one, 10: echo)."""
    out, last, answered, policy = {}, None, False, None
    for fr in sorted(pkts):
        p = pkts[fr]
        if p.dir == "ctrl":
            last, answered = p, False
            if p.type == "init":
                policy = None
        elif last is not None and not answered and answers(last.num, p.num, policy):
            out[fr] = last.frame
            answered = True
            if p.type == "init-echo" and last.type == "init":
                policy = "echo" if p.num == last.num else "plus-one"
    return out


def late_replies(pkts):
    """PC frames whose NUM answers not the newest controller packet but one of the 4096
    before it (policy as in expected_response_to): replies late past the next packet, which
    a live capture on a busy host may have (a stall of 100 ms is 100 packets at 1 ms);
    c4g.reply_num flags them."""
    out, recent, policy = set(), [], None
    for fr in sorted(pkts):
        p = pkts[fr]
        if p.dir == "ctrl":
            recent.append(p)
            del recent[:-4097]
            if p.type == "init":
                policy = None
        elif recent and p.type == "init-echo" and recent[-1].type == "init":
            policy = "echo" if p.num == recent[-1].num else "plus-one"
        elif recent and p.num is not None and not answers(recent[-1].num, p.num, policy) and any(
                answers(q.num, p.num, policy) for q in recent[:-1]):
            out.add(fr)
    return out


def ticks(pkts):
    """Controller cyclic packets with the PC packet the dissector linked to them:
    [(ctrl Packet, pc Packet or None)] in capture order (the CSV's ctrl_frame, pc_frame)."""
    reply = {p.response_to: p for p in pkts.values() if p.dir == "pc" and p.response_to}
    return [(p, reply.get(fr)) for fr, p in sorted(pkts.items())
            if p.dir == "ctrl" and p.type == "cyclic"]


# ------------------------------------------------------------------ c4g-replay export
# Experts that mean the controller refuses the datagram (c4g_pc_decode: NUM in range,
# known modes, finite floats, a whole packet).
REFUSING = ("c4g.bad_length", "c4g.num_range", "c4g.unknown_mode", "c4g.nonfinite")
EXPORT_FIELDS = ["mode"] + DATA_NAMES


def replay_export(binary, pcap, ports):
    """`c4g-replay export -p PORTS PCAP` as [{column: text}]. CSV, not --json-lines: JSON
    prints NaN and infinity both as null, CSV keeps them apart (nan, -nan, inf, -inf). The
    header comes again before a row whose axis count differs (another session)."""
    r = subprocess.run([binary, "export", "-p", ports, pcap], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE)
    if r.returncode != 0:
        raise RuntimeError("%s export %s: exit %d: %s" % (binary, pcap, r.returncode,
                                                          r.stderr.decode(errors="replace")))
    rows, cols = [], None
    for rec in csv.reader(io.StringIO(r.stdout.decode())):
        if rec and rec[0] == "session":
            cols = rec
        elif rec:
            if cols is None or len(rec) != len(cols):
                raise RuntimeError("export: a row of %d columns under a header of %s"
                                   % (len(rec), len(cols) if cols else "none"))
            rows.append(dict(zip(cols, rec)))
    return rows


def f32_key(x):
    """Identity of a float32 value as text can carry it: the exact bits, or NaN and its sign
    (%.9g prints no NaN payload)."""
    bits = struct.unpack("<I", struct.pack("<f", x))[0]
    return ("nan", bits >> 31) if math.isnan(x) else bits


def refused(ctrl, pc):
    """Why the controller does not take `pc` as its reply to `ctrl` although its NUM answers
    (c4g_pc_decode with the packet's axis count), or None. The export leaves such a tick
    without a reply; the dissector links the datagram and flags it with expert info."""
    bad = [e for e in pc.experts if e in REFUSING]
    if bad:
        return ",".join(sorted(set(bad)))
    if pc.length != ctrl.length:
        return "%d bytes for a %d-byte packet" % (pc.length, ctrl.length)
    return None


def export_ticks(diss):
    """{controller frame: tick} of the dissector's cyclic controller packets that are ticks
    for c4g-replay: numbered from 1 after the conversation's last init packet (a restart
    starts a new session); a packet that repeats the last tick's NUM or is older (by less
    than 512: a duplicate, a reordered one) is no new tick."""
    out, state = {}, {}
    for fr, p in sorted(diss.items()):
        if p.dir != "ctrl":
            continue
        conv = tuple(sorted((p.src_port, p.dst_port)))
        if p.type == "init":
            state[conv] = (0, None)
        elif p.type == "cyclic":
            n, last = state.get(conv, (0, None))
            if last is not None and 0 <= (last - p.num) % (NUM_MAX + 1) < 512:
                continue
            state[conv] = (n + 1, p.num)
            out[fr] = n + 1
    return out


def export_compare(diss, rows):
    """Every export row against the dissector's tick (same ctrl_frame). Returns (ticks
    compared, fields compared, problems, notes); a problem names the controller frame and
    the column."""
    probs, notes = [], {"unanswered": 0, "refused": [], "repeats": 0}
    nfields = 0
    tick_of = export_ticks(diss)
    notes["repeats"] = sum(1 for c, _ in ticks(diss) if c.frame not in tick_of)
    by_frame = {c.frame: (c, r) for c, r in ticks(diss) if c.frame in tick_of}
    exported = {}
    for row in rows:
        fr = int(row["ctrl_frame"])
        if fr in exported:
            probs.append("frame %d: exported twice" % fr)
        exported[fr] = row
    for fr in sorted(set(exported) - set(by_frame)):
        p = diss.get(fr)
        probs.append("frame %d: an export tick, for the dissector %s" % (
            fr, "%s %s" % (p.dir, p.type) if p else "no C4G Open packet"))
    for fr in sorted(set(by_frame) - set(exported)):
        probs.append("frame %d: a controller cyclic packet the export has no row for" % fr)

    def same(fr, col, got, want):
        nonlocal nfields
        nfields += 1
        if got != want:
            probs.append("frame %d %s: export %r, dissector %r" % (fr, col, got, want))

    n = 0
    for fr in sorted(set(exported) & set(by_frame)):
        row, (c, r) = exported[fr], by_frame[fr]
        n += 1
        why = refused(c, r) if r is not None else None
        if r is None:
            notes["unanswered"] += 1
        elif why:
            notes["refused"].append("frame %d (%s)" % (r.frame, why))
            r = None
        same(fr, "tick", int(row["tick"]), tick_of[fr])
        same(fr, "pc_frame", row["pc_frame"], str(r.frame) if r else "")
        same(fr, "ctrl_num", row["ctrl_num"], str(c.num))
        same(fr, "pc_num", row["pc_num"], str(r.num) if r else "")
        if r and row["latency_us"]:
            # both from the same capture timestamps: the export in us to 3 decimals
            nfields += 1
            if abs(float(row["latency_us"]) - r.response_time * 1e6) > 0.0015:
                probs.append("frame %d latency_us: export %s, dissector %.3f"
                             % (fr, row["latency_us"], r.response_time * 1e6))
        else:
            same(fr, "latency_us", row["latency_us"], "")
        for side, p in (("ctrl", c), ("pc", r)):
            for word in ("infpar", "cmd"):
                col = "%s_%s" % (side, word)
                same(fr, col, int(row[col], 16) if row[col] else None,
                     getattr(p, word) if p else None)
        axes = len(c.axes)
        if "c%d_mode" % axes not in row or "c%d_mode" % (axes + 1) in row:
            probs.append("frame %d: export columns for another axis count than %d"
                         % (fr, axes))
            continue
        for side, p in (("c", c), ("p", r)):
            for i in range(axes):
                ax = p.axes[i] if p else None
                for k, name in enumerate(EXPORT_FIELDS):
                    col = "%s%d_%s" % (side, i + 1, name)
                    text = row[col]
                    if ax is None:
                        same(fr, col, text, "")
                    elif k == 0:
                        same(fr, col, text, str(ax.mode))
                    else:
                        v = ax.data[k - 1]
                        try:
                            ok = f32_key(float(text)) == f32_key(v)
                        except (ValueError, OverflowError):
                            ok = False
                        nfields += 1
                        if not ok:
                            probs.append("frame %d %s: export %r, dissector %s" % (
                                fr, col, text, ("-nan" if math.copysign(1, v) < 0 else "nan")
                                if math.isnan(v) else "%.9g" % v))
    return n, nfields, probs, notes


def check_export(rep, name, diss, rows):
    """One PASS/FAIL line for the export against the dissector, its problems listed first
    (up to 20), each with the controller frame and the column."""
    n, nfields, probs, notes = export_compare(diss, rows)
    for line in probs[:20]:
        print("  %s: %s" % (name, line))
    if len(probs) > 20:
        print("  %s: ... %d more" % (name, len(probs) - 20))
    refused_n = len(notes["refused"])
    rep.check("%s: c4g-replay export = dissector: %d ticks compared, %d fields (%d rows, %d "
              "cyclic controller packets, %d of them repeated or late; %d ticks without a "
              "reply, %d reply(ies) the controller refuses%s)"
              % (name, n, nfields, len(rows), len(ticks(diss)), notes["repeats"],
                 notes["unanswered"], refused_n,
                 (": " + ", ".join(notes["refused"][:4])) if refused_n else ""),
              probs if n else probs + ["no tick"])


def capture_ports(spec, default):
    """FILE or FILE:PORTS (PORTS: 46104 or 46117,46118) -> (file, ports)."""
    head, sep, tail = spec.rpartition(":")
    if sep and re.fullmatch(r"[0-9]+(,[0-9]+)*", tail):
        return head, tail
    if default is None:
        raise SystemExit("%s: no PC port (FILE:PORTS or --pc-port)" % spec)
    return spec, default


def cmd_export_compare(rep, args):
    """tshark with the dissector and c4g-replay export on each capture, tick by tick. The
    tshark runs go ahead two at a time while the previous capture's PDML is parsed."""
    jobs = [capture_ports(spec, args.pc_port) for spec in args.pcap]
    with ThreadPoolExecutor(max_workers=2) as pool:
        runs = [(pcap, pool.submit(replay_export, args.replay, pcap, ports),
                 pool.submit(tshark, pdml_args(pcap, args.lua, ["-o", "c4g.ports:" + ports])))
                for pcap, ports in jobs]
        for pcap, f_rows, f_pdml in runs:
            name = args.name if args.name and len(jobs) == 1 else os.path.basename(pcap)
            try:
                diss = dissector_packets(pcap, args.lua, [], xml=f_pdml.result())
                check_export(rep, name, diss, f_rows.result())
            except (DissectorError, RuntimeError) as err:
                rep.check(name, [str(err)])


# ------------------------------------------------------------------ reporting
class Report:
    def __init__(self):
        self.fails = 0

    def check(self, what, problems):
        """problems: list of strings (empty = PASS)."""
        if problems:
            self.fails += 1
            print("FAIL: %s: %d problem(s); first: %s" % (what, len(problems),
                                                        "; ".join(problems[:3])))
        else:
            print("PASS: %s" % what)


def compare_packets(indep, diss, with_kinds=True):
    """Differences between the independent and the dissector's reading, as strings."""
    probs = []
    if sorted(indep) != sorted(diss):
        return ["frames differ: %d independent, %d dissected" % (len(indep), len(diss))]
    for fr in sorted(indep):
        a, b = indep[fr], diss[fr]
        if with_kinds and (a.dir, a.type) != (b.dir, b.type):
            probs.append("frame %d: %s %s, want %s %s" % (fr, b.dir, b.type, a.dir, a.type))
        if a.num != b.num:
            probs.append("frame %d: NUM %r, want %r" % (fr, b.num, a.num))
        if a.init is not None or b.init is not None:
            if a.init is None or b.init is None:
                probs.append("frame %d: init fields missing" % fr)
                continue
            for key, _, _ in INIT_LAYOUT:
                if not all(same_float(x, y) for x, y in zip(a.init[key], b.init[key])):
                    probs.append("frame %d: init %s %r, want %r"
                                 % (fr, key, b.init[key], a.init[key]))
            continue
        if (a.infpar, a.cmd) != (b.infpar, b.cmd):
            probs.append("frame %d: INFPAR/CMD %r/%r, want %r/%r"
                         % (fr, b.infpar, b.cmd, a.infpar, a.cmd))
        if len(a.axes) != len(b.axes):
            probs.append("frame %d: %d axes, want %d" % (fr, len(b.axes), len(a.axes)))
            continue
        for x, y in zip(a.axes, b.axes):
            if x.index != y.index or x.mode != y.mode or not all(
                    same_float(u, v) for u, v in zip(x.data, y.data)):
                probs.append("frame %d axis %s: %r %r, want %r %r"
                             % (fr, y.index, y.mode, y.data, x.mode, x.data))
    return probs


def arm_map(init):
    """OPEN index (1-based) -> (arm, axis of the arm), both 1-based, from OpenAx."""
    m = {}
    for i, v in enumerate(init["open_ax"]):
        if 0 <= v < MAX_AXES:
            m[v + 1] = (i // AXES_PER_ARM + 1, i % AXES_PER_ARM + 1)
    return m


# ------------------------------------------------------------------ commands
def cmd_capture(rep, args):
    """Full comparison of a capture: -o c4g.ports:PC_PORT, every packet, every field; with
    --filters the display filters, with --direction the sender without the port preference,
    with --replay also c4g-replay export (on the same dissection). The tshark runs go in
    parallel."""
    pcap, port, lua = args.pcap, args.pc_port, args.lua
    opts = ["-o", "c4g.ports:%d" % port]
    decode_as = ["-d", "udp.port==%d,c4g" % port, "-o", "c4g.ports:1000-1001"]
    with ThreadPoolExecutor(max_workers=max(2, os.cpu_count() or 2)) as pool:
        f_indep = pool.submit(decode_capture, pcap)
        f_pdml = pool.submit(tshark, pdml_args(pcap, lua, opts))
        if args.filters:
            f_mode0 = pool.submit(filter_frames, lua, pcap, opts, "c4g.mode == 0")
            f_pc100 = pool.submit(filter_frames, lua, pcap, opts,
                                  'c4g.dir == "pc" && c4g.num == 100')
        if args.direction:
            f_da = pool.submit(kinds_fields, lua, pcap, decode_as)
        indep = expected_kinds(f_indep.result(), port)
        if args.direction:
            # mid-stream: drop the handshake and start on a PC packet (the first-sender rule
            # is then wrong; in one pass until the timing rule decides, in two not at all)
            first_cyclic = min(fr for fr, p in indep.items() if p.type == "cyclic")
            first_pc = min(fr for fr, p in indep.items() if p.dir == "pc"
                           and p.type == "cyclic" and fr > first_cyclic + 20)
            cut = args.tmp + "/mid.pcap"
            subprocess.run(["editcap", "-r", pcap, cut, "%d-%d" % (first_pc, max(indep))],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            f_cut = pool.submit(kinds_fields, lua, cut, ["-2"] + decode_as)
        if args.replay:
            f_rows = pool.submit(replay_export, args.replay, pcap, str(port))
        diss = dissector_packets(pcap, lua, opts, xml=f_pdml.result())
        check_fields(rep, args.name, indep, diss)
        if args.replay:
            check_export(rep, args.name, diss, f_rows.result())
        if args.filters:
            check_filters(rep, args.name, indep, f_mode0.result(), f_pc100.result())
        if args.direction:
            check_direction(rep, args.name, indep, f_da.result(), first_pc, f_cut.result())


def check_fields(rep, name, indep, diss):
    n_init = sum(1 for p in indep.values() if p.init)
    rep.check("%s: %d packets, every field equals the independent decode (sender, type, NUM, "
              "INFPAR, CMD, modes, D1..D5, EXT1..EXT3 as exact float32, %d init packet(s) x "
              "300 fields)" % (name, len(indep), n_init), compare_packets(indep, diss))
    rep.check("%s: init packets have all 300 fields" % name,
              [] if n_init >= 1 and all(sum(len(v) for v in p.init.values()) == 300
                                        for p in diss.values() if p.init) else ["no init"])
    want = expected_response_to(indep)
    got = {fr: p.response_to for fr, p in diss.items() if p.response_to}
    rep.check("%s: c4g.response_to links every reply to its controller packet (%d)"
              % (name, len(want)),
              ["frame %d -> %r, want %r" % (fr, got.get(fr), want.get(fr))
               for fr in sorted(set(want) | set(got)) if got.get(fr) != want.get(fr)])
    late = late_replies(indep)
    rep.check("%s: no expert info on a clean capture (but c4g.reply_num on %d late replies)"
              % (name, len(late)),
              ["frame %d: %s" % (fr, p.experts) for fr, p in sorted(diss.items())
               if p.experts and not (fr in late and set(p.experts) == {"c4g.reply_num"})]
              + ["frame %d: a late reply without c4g.reply_num" % fr for fr in sorted(late)
                 if "c4g.reply_num" not in diss[fr].experts])
    # arm / axis of every axis block from the init packet's OpenAx
    probs, maps = [], None
    for fr in sorted(diss):
        p = diss[fr]
        if indep[fr].type == "init":
            maps = arm_map(indep[fr].init)
        for a in p.axes:
            where = maps.get(a.index) if maps else None
            if where and p.type == "cyclic" and (a.arm, a.arm_axis) != where:
                probs.append("frame %d axis %d: arm %r axis %r, want %r"
                             % (fr, a.index, a.arm, a.arm_axis, where))
    rep.check("%s: c4g.arm / c4g.arm_axis follow the init packet's OpenAx" % name, probs)


def check_filters(rep, name, indep, got0, got_pc):
    """Display filters select what the independent decode says they should."""
    want0 = sorted(fr for fr, p in indep.items() if any(a.mode == 0 for a in p.axes))
    rep.check("%s: -Y 'c4g.mode == 0' selects the %d packets with an axis in mode 0"
              % (name, len(want0)), [] if got0 == want0 else
              ["%d frames, want %d" % (len(got0), len(want0))])
    want_pc = sorted(fr for fr, p in indep.items() if p.dir == "pc" and p.num == 100)
    rep.check("%s: -Y 'c4g.dir == \"pc\" && c4g.num == 100' selects %r"
              % (name, want_pc), [] if got_pc == want_pc and want_pc else
              ["got %r" % got_pc])


def filter_frames(lua, pcap, opts, flt):
    text = tshark(["-r", pcap, "-Y", flt, "-T", "fields", "-e", "frame.number"]
                  + lua_args(lua, opts))
    return sorted(int(x) for x in text.split())


def kinds_fields(lua, pcap, opts):
    text = tshark(["-r", pcap, "-T", "fields", "-e", "frame.number", "-e", "c4g.dir",
                   "-e", "c4g.type", "-e", "c4g.dir_by"] + lua_args(lua, opts))
    out = {}
    for line in text.splitlines():
        fr, d, t, by = line.split("\t")
        out[int(fr)] = (d, t, by)
    return out


def check_direction(rep, name, indep, got, first_pc, two):
    """Sender and type with no port preference (Decode As only): `got` for the whole
    capture, `two` for the cut from frame first_pc on, read in two passes."""
    rep.check("%s, Decode As only: sender and type of every packet from the packets"
              % name, ["frame %d: %s, want %s %s" % (fr, got.get(fr), p.dir, p.type)
                       for fr, p in sorted(indep.items())
                       if got.get(fr, (None, None))[:2] != (p.dir, p.type)])
    bys = sorted(set(v[2] for v in got.values()))
    rep.check("%s, Decode As only: decided by %s" % (name, ",".join(bys)),
              [] if "port" not in bys else ["the port preference decided"])
    want = {fr - first_pc + 1: p for fr, p in indep.items() if fr >= first_pc}
    rep.check("%s cut at frame %d (first packet the PC's), Decode As, two passes: every "
              "sender right, none left to the first-sender guess" % (name, first_pc),
              ["frame %d: %s, want %s %s" % (fr, two.get(fr), p.dir, p.type)
               for fr, p in sorted(want.items())
               if two.get(fr, ())[:2] != (p.dir, p.type) or two[fr][2] in ("first", "port")])


def write_pcap(path, packets):
    """Minimal libpcap file of Ethernet/IPv4/UDP frames: packets = [(sport, dport, payload)]."""
    out = [struct.pack("<IHHiIII", 0xa1b2c3d4, 2, 4, 0, 0, 65535, 1)]
    for i, (sport, dport, payload) in enumerate(packets):
        udp = struct.pack(">HHHH", sport, dport, 8 + len(payload), 0) + payload
        ip = struct.pack(">BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), i, 0, 64, 17, 0,
                         bytes([127, 0, 0, 1]), bytes([127, 0, 0, 1]))
        s = sum(struct.unpack(">10H", ip))
        while s >> 16:
            s = (s & 0xFFFF) + (s >> 16)
        ip = ip[:10] + struct.pack(">H", ~s & 0xFFFF) + ip[12:]
        frame = b"\x02\x00\x00\x00\x00\x02" + b"\x02\x00\x00\x00\x00\x01" + b"\x08\x00" + ip + udp
        out.append(struct.pack("<IIII", 1000 + i, 0, len(frame), len(frame)) + frame)
    with open(path, "wb") as fh:
        fh.write(b"".join(out))


def f32_bytes(x):
    """x: a float, or (bits,) for an exact bit pattern (NaN, infinity)."""
    return struct.pack("<I", x[0]) if isinstance(x, tuple) else struct.pack("<f", x)


def axis_bytes(mode, floats):
    return struct.pack("<i", mode) + b"".join(f32_bytes(x) for x in floats)


def header_modes(header):
    """{code: name} of the C4G_MODE_TABLE rows in include/c4gopen_wire.h."""
    text = open(header).read()
    table = text[text.index("#define C4G_MODE_TABLE(X)"):]
    table = table[:table.index("\n\n")]
    return {int(m.group(1)): m.group(2) for m in re.finditer(
        r'X\(\s*\w+,\s*(\d+),.*?"([A-Z0-9_]+)",\s*\\?\s*"', table, re.S)}


def cmd_crafted(rep, args):
    """Crafted datagrams on the default port 1000 (so the default registration is tested
    too): bad ones draw their expert info; two packets carry every mode code of the
    header's C4G_MODE_TABLE and the dissector must name each one as the table does."""
    nan, inf = (0x7FC00000,), (0x7F800000,)
    init = bytearray(open(args.init_bin, "rb").read())
    struct.pack_into("<i", init, 4, 4)           # nFieldPck 4
    echo = bytearray(init)
    struct.pack_into("<i", echo, 0, 11)          # NUM 11, and a period that is not the init's
    struct.pack_into("<i", echo, 224, 3)
    modes = header_modes(args.header)
    codes = sorted(modes)
    half = (len(codes) + 1) // 2
    cases = [
        ("NaN D1, +inf EXT3, unknown mode 77",
         struct.pack("<iII", 5, 0, 0) + axis_bytes(77, [nan, 0.5, 0, 0, 0, 0, 0, inf]),
         {"c4g.nonfinite": 2, "c4g.unknown_mode": 1}),
        ("13-byte datagram", struct.pack("<iII", 7, 0, 0) + b"\x01", {"c4g.bad_length": 1}),
        ("NUM 0x8000", struct.pack("<iII", 0x8000, 0, 0) + axis_bytes(0, [0.0] * 8),
         {"c4g.num_range": 1}),
        ("NUM -1", struct.pack("<iII", -1, 0, 0) + axis_bytes(4, [0.0] * 8),
         {"c4g.num_range": 1}),
        ("init packet with nFieldPck 4", bytes(init), {"c4g.init_field": 1}),
        ("PC echo of it with another period", bytes(echo),
         {"c4g.init_field": 1, "c4g.echo_mismatch": 1}),
        ("733-byte datagram", bytes(733), {"c4g.bad_length": 1}),
    ]
    cases.append(("PC packet with NUM 99 after the controller's NUM 0",
                  struct.pack("<iII", 99, 0, 0) + axis_bytes(0, [0.0] * 8), {"c4g.reply_num": 1}))
    for part in (codes[:half], codes[half:]):
        cases.append(("modes %d..%d" % (part[0], part[-1]), struct.pack("<iII", 20, 0, 0)
                      + b"".join(axis_bytes(c, [0.0] * 8) for c in part), {}))
    path = args.tmp + "/crafted.pcap"
    from_pc = ("PC echo", "PC packet")
    # then, in a conversation of its own, sync packets whose replies come late: the reply
    # to sync 2 after sync 3, so sync 3's own reply comes to an answered packet
    def sync(num):
        return 40001, 1000, struct.pack("<iII", num, 0, 0) + bytes(2 * AXIS)

    def sync_reply(num):
        return 1000, 40001, struct.pack("<i", num) + bytes(SYNC_REPLY - 4)

    late = [sync(1), sync_reply(2), sync(2), sync(3), sync_reply(3), sync_reply(4), sync(4),
            sync_reply(5)]
    write_pcap(path, [(1000, 40000, c[1]) if c[0].startswith(from_pc) else (40000, 1000, c[1])
                      for c in cases] + late)
    diss = dissector_packets(path, args.lua, [])
    got = [(diss[fr].dir, diss[fr].type) if fr in diss else None
           for fr in range(len(cases) + 1, len(cases) + 1 + len(late))]
    want = [("pc" if sport == 1000 else "ctrl", "sync-reply" if sport == 1000 else "sync")
            for sport, _, _ in late]
    rep.check("crafted sync packets with late replies: every 732-byte reply a sync-reply",
              [] if got == want else ["got %r" % got])
    for i, (what, _, want) in enumerate(cases):
        p = diss.get(i + 1)
        got = {}
        for e in (p.experts if p else []):
            got[e] = got.get(e, 0) + 1
        rep.check("crafted frame %d (%s) on port 1000: expert info %s" % (i + 1, what, want),
                  [] if got == want else ["got %r" % got])
    p = diss.get(1)
    rep.check("crafted frame 1: decoded anyway (mode 77, D1 NaN, D2 0.5, EXT3 inf)",
              [] if p and p.axes and p.axes[0].mode == 77 and math.isnan(p.axes[0].data[0])
              and p.axes[0].data[1] == 0.5 and p.axes[0].data[7] == float("inf")
              else ["got %r" % (p.axes[0].fields() if p and p.axes else None)])
    labels = []
    for fr in (len(cases) - 1, len(cases)):
        labels += diss[fr].mode_labels if fr in diss else []
    probs = ["only %d table rows parsed" % len(codes)] if len(codes) < 30 else []
    for code, label in zip(codes, labels):
        if not label.startswith("Mode (SM): %s (%d)" % (modes[code], code)):
            probs.append("%d: %r, want %s" % (code, label, modes[code]))
    if len(labels) != len(codes):
        probs.append("%d mode items for %d codes" % (len(labels), len(codes)))
    rep.check("c4g.mode names every code of C4G_MODE_TABLE as the table does (%d codes)"
              % len(codes), probs)


# ------------------------------------------------------------------ the tests
LUA = "tools/wireshark/c4gopen.lua"


class Rep(Report):
    """Report whose failed checks fail the test, all of them listed."""

    def __init__(self):
        super().__init__()
        self.failed = []

    def check(self, what, problems):
        super().check(what, problems)
        if problems:
            self.failed.append("%s: %d problem(s); first: %s" % (what, len(problems), "; ".join(problems[:3])))

    def done(self):
        assert not self.failed, "%d check(s) failed:\n  " % len(self.failed) + "\n  ".join(self.failed)


def run_cmd(cmd, **kw):
    rep = Rep()
    args = argparse.Namespace(lua=LUA, **kw)
    try:
        cmd(rep, args)
    except (DissectorError, RuntimeError) as err:
        rep.check(cmd.__name__, [str(err)])
    rep.done()


def test_mode4_capture(bins, tmp_path):
    """sender, type, NUM, INFPAR, CMD, modes, D1..D5 and EXT1..EXT3 as exact float32 of every
    packet, all 300 fields of the init packet and its echo, reply links, display filters; the
    sender again with Decode As only and from a cut that starts in mid-stream on a PC packet;
    c4g-replay export on the same dissection"""
    run_cmd(cmd_capture, tmp=str(tmp_path), pcap="fixtures/wireshark/mode4-short.pcap", pc_port=31000,
            name="mode4-short", filters=True, direction=True, replay=str(bins.replay))


def test_export_compare(bins):
    """c4g-replay export against the dissector, tick by tick: two arms with their own INFPAR
    and EXIT_FROM_OPEN, a plus-one reply late past the next packet, duplicated controller
    packets (no new tick), NaN from the controller (unanswered), infinity from the PC (a reply
    the controller refuses), and two more link layers"""
    f = "fixtures/replay/"
    run_cmd(cmd_export_compare, replay=str(bins.replay), pc_port=None, name=None,
            pcap=[f + "two-arms.pcap:46116", f + "fault-late.pcap:46123", f + "fault-duplicate.pcap:46127",
                  f + "data-nan-ctrl-d3.pcap:46204", f + "data-inf-pc-d1.pcap:46205", f + "fmt-vlan.pcap:46300",
                  f + "fmt-sll2.pcap:46300"])


def test_crafted(tmp_path):
    """NaN and infinity, unknown mode 77, 13 and 733 bytes, NUM out of range, an init packet
    out of range: their expert info; every mode code of the header's C4G_MODE_TABLE named as
    the table names it; sync packets whose replies come late, each still a sync reply"""
    run_cmd(cmd_crafted, tmp=str(tmp_path), init_bin="fixtures/vectors/init-fig10-1.bin",
            header="include/c4gopen_wire.h")


def test_two_arm_capture(bins, procs, ports, tmp_path):
    """a fresh capture: two arms, 1 ms period; the simulator records both directions"""
    port = ports.udp()
    srv = procs.start([bins.server, "-p", port, "--controller", "127.0.0.1", "--max-seconds", "30", "--lost-timeout-ms", "2000"],
                      name="server")
    wait_until(lambda: "listening on" in srv.out() or not srv.running(), 30, "c4g-server listening")
    pcap = tmp_path / "two.pcap"
    r = procs.run([bins.sim, "--bind", "127.0.0.1", "-p", port, "-c", "fixtures/sim/two-arms.ini", "-n", "150",
                   "--max-miss", "500", "-q", "--pcap", pcap], timeout=30)
    srv.signal(signal.SIGTERM)
    srv.wait(10)
    assert pcap.exists() and pcap.stat().st_size > 0, "no two-arm capture: %s %s %s" % (r.stdout, r.stderr, srv.out())
    run_cmd(cmd_capture, tmp=str(tmp_path), pcap=str(pcap), pc_port=port, name="two-arms", filters=False,
            direction=False, replay=str(bins.replay))
