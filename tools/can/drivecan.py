#!/usr/bin/env python3
"""Watch and command a drive on CAN with the message set of tools/can/drive.dbc.

  drivecan.py monitor --channel vcan0 [--node N] [--duration S]
      a live table of the decoded signals, each message's rate and the
      frames that did not decode (unknown id, wrong length)
  drivecan.py record --channel vcan0 --log run.log [--csv run.csv] [--duration S | --count N]
      a candump -L log (can-utils' format: `candump -L vcan0 > run.log`
      writes the same) and, with --csv, the decoded signals
  drivecan.py decode run.log [--csv out.csv]
      a log of ours or of candump -L, decoded to CSV (t_s,node,message,signal,value)
  drivecan.py plot run.log SIGNAL... [-o run.png]
  drivecan.py plot --channel vcan0 --duration S SIGNAL... [-o run.png]
      signals against time from a log, or from the bus for S seconds
      (recorded to a log next to the PNG, or a temporary one), through
      `cantools plot` (a window, or a PNG with -o); SIGNAL as cantools
      takes it, e.g. 'Velocity.Omega*', '-' starts a new subplot
  drivecan.py send --channel vcan0 [--node N] MESSAGE [SIGNAL=VALUE ...]
      a command by name with physical values, checked against the DBC's
      ranges before anything is sent, e.g. `send CmdSpeed OmegaRef=10 Ramp=50`
  drivecan.py param list|get NAME|set NAME VALUE|save|defaults --channel vcan0 [--node N] [--drive D]
      the drive's and board's parameters by name or id (ParamRequest,
      ParamReply; docs/parameters.md): each request answered done or a
      named refusal (exit 1); set checks the value against the parameter's
      type and range first; VALUE a number, true/false, or an enum's name
  drivecan.py config export FILE.toml | config import FILE.toml [--save] --channel vcan0 [--node N]
      every parameter into a TOML file ([params] name = value), or back:
      import shows each difference and writes only what changed (--save:
      then saves); a refusal stops it, naming the parameter (exit 1)

--interface is python-can's (default socketcan; `virtual` for tests).
Drive node N (0-15) uses the DBC's ids plus N; decoding masks the node
out (cantools' frame-id mask 0x7F0). python-can does the bus and the log
formats, cantools the DBC; this file only glues them.
"""
import argparse
import collections
import csv
import os
import re
import struct
import subprocess
import sys
import time

import can
import cantools

DBC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "drive.dbc")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def project_version(root=ROOT):
    """(major, minor, patch) from project(... VERSION) in the top
    CMakeLists.txt, the one place it is set: what the Version message sends."""
    with open(os.path.join(root, "CMakeLists.txt")) as f:
        m = re.search(r"project\(\s*\w+\s+VERSION\s+(\d+)\.(\d+)\.(\d+)", f.read())
    if not m:
        raise ValueError("CMakeLists.txt: no project(... VERSION x.y.z)")
    return tuple(int(g) for g in m.groups())


def dbc_msg_set_version(path=DBC):
    """The message set's version, N of the DBC's VERSION "drive-can N": what
    the heartbeat's MsgSetVersion sends."""
    with open(path) as f:
        m = re.search(r'^VERSION "drive-can (\d+)"', f.read(), re.M)
    if not m:
        raise ValueError(f'{path}: no VERSION "drive-can N"')
    return int(m.group(1))
NODE_MASK = 0xF


def load_db(path=DBC):
    return cantools.database.load_file(path)


def open_bus(args):
    return can.Bus(interface=args.interface, channel=args.channel, receive_own_messages=False)


def decode(db, msg):
    """(node, message name, {signal: value}) of a frame, or raises KeyError
    (unknown id) / ValueError (a frame the DBC cannot decode)."""
    node = msg.arbitration_id & NODE_MASK
    m = db.get_message_by_frame_id(msg.arbitration_id & ~NODE_MASK)
    if len(msg.data) != m.length:
        raise ValueError(f"{m.name}: {len(msg.data)} bytes, the DBC says {m.length}")
    return node, m.name, m.decode(bytes(msg.data), decode_choices=False)


class Stats:
    """Per message: count, rate over the window, the last values; errors."""

    def __init__(self):
        self.count = collections.Counter()
        self.first = {}
        self.last_t = {}
        self.values = {}
        self.errors = collections.Counter()

    def add(self, db, msg, node_filter=None):
        try:
            node, name, vals = decode(db, msg)
        except KeyError:
            self.errors["unknown id"] += 1
            return
        except ValueError:
            self.errors["wrong length"] += 1
            return
        if node_filter is not None and node != node_filter:
            return
        key = (node, name)
        self.count[key] += 1
        self.first.setdefault(key, msg.timestamp)
        self.last_t[key] = msg.timestamp
        self.values[key] = vals

    def rate(self, key):
        n, dt = self.count[key], self.last_t[key] - self.first[key]
        return (n - 1) / dt if n > 1 and dt > 0 else 0.0

    def table(self):
        lines = [f"{'node':>4} {'message':<12} {'rate/s':>8} {'count':>7}  signals"]
        for key in sorted(self.count):
            sig = "  ".join(f"{k}={v:.6g}" for k, v in self.values[key].items())
            lines.append(f"{key[0]:>4} {key[1]:<12} {self.rate(key):8.1f} {self.count[key]:7d}  {sig}")
        errs = ", ".join(f"{k}: {v}" for k, v in sorted(self.errors.items())) or "none"
        lines.append(f"frames that did not decode: {errs}")
        return "\n".join(lines)


def monitor(args, bus=None, db=None, out=sys.stdout):
    db = db or load_db(args.dbc)
    bus = bus or open_bus(args)
    st = Stats()
    t_end = time.monotonic() + args.duration if args.duration else None
    t_show = time.monotonic() + 1.0
    try:
        while t_end is None or time.monotonic() < t_end:
            msg = bus.recv(timeout=0.1)
            if msg is not None:
                st.add(db, msg, args.node)
            if time.monotonic() >= t_show and not args.duration:
                out.write("\033[H\033[J" + st.table() + "\n")
                out.flush()
                t_show += 1.0
    except KeyboardInterrupt:
        pass
    out.write(st.table() + "\n")
    return st


def write_csv(db, msgs, path, node_filter=None):
    """The decoded signals of msgs, one row per signal: t_s,node,message,signal,value.
    Returns the number of frames that did not decode."""
    bad = 0
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t_s", "node", "message", "signal", "value"])
        for msg in msgs:
            try:
                node, name, vals = decode(db, msg)
            except (KeyError, ValueError):
                bad += 1
                continue
            if node_filter is not None and node != node_filter:
                continue
            for k, v in vals.items():
                w.writerow([f"{msg.timestamp:.6f}", node, name, k, v])
    return bad


def record(args, bus=None, db=None):
    db = db or load_db(args.dbc)
    bus = bus or open_bus(args)
    got = []
    t_end = time.monotonic() + args.duration if args.duration else None
    with can.CanutilsLogWriter(args.log, channel=args.channel or "can0") as log:
        try:
            while (t_end is None or time.monotonic() < t_end) and (not args.count or len(got) < args.count):
                msg = bus.recv(timeout=0.1)
                if msg is None:
                    continue
                log.on_message_received(msg)
                got.append(msg)
        except KeyboardInterrupt:
            pass
    if args.csv:
        write_csv(db, got, args.csv, args.node)
    print(f"drivecan: recorded {len(got)} frames to {args.log}" + (f" and {args.csv}" if args.csv else ""),
          file=sys.stderr)
    return got


def decode_log(args):
    db = load_db(args.dbc)
    msgs = list(can.CanutilsLogReader(args.log))
    out = args.csv or os.path.splitext(args.log)[0] + ".csv"
    bad = write_csv(db, msgs, out, args.node)
    print(f"drivecan: {len(msgs)} frames of {args.log} decoded to {out} ({bad} did not decode)", file=sys.stderr)
    return 0


def plot(args, bus=None):
    items = list(args.items)
    if args.channel:
        if not args.duration or args.duration <= 0:
            print("drivecan: plot --channel needs --duration S > 0", file=sys.stderr)
            return 2
        log_path = (os.path.splitext(args.output)[0] + ".log") if args.output else None
        tmp = None
        if log_path is None:
            import tempfile
            tmp = tempfile.NamedTemporaryFile(suffix=".log", delete=False)
            log_path = tmp.name
            tmp.close()
        rec = argparse.Namespace(dbc=args.dbc, channel=args.channel, interface=args.interface, log=log_path,
                                 csv=None, node=None, duration=args.duration, count=0)
        record(rec, bus=bus)
        signals = items
    else:
        if len(items) < 2:
            print("drivecan: plot needs a log and at least one signal (or --channel and --duration)", file=sys.stderr)
            return 2
        log_path, signals = items[0], items[1:]
    cmd = [sys.executable, "-m", "cantools", "plot", "--frame-id-mask", "0x7F0", "--ignore-unknown-frames",
           args.dbc, *signals]
    if args.output:
        cmd += ["--output-file", args.output]
    with open(log_path) as log:
        return subprocess.run(cmd, stdin=log).returncode


def parse_assignments(m, items):
    vals = {}
    for it in items:
        if "=" not in it:
            raise SystemExit(f"drivecan send: '{it}': expected SIGNAL=VALUE")
        k, v = it.split("=", 1)
        try:
            m.get_signal_by_name(k)
        except KeyError:
            raise SystemExit(f"drivecan send: {m.name} has no signal '{k}' "
                             f"(its signals: {', '.join(s.name for s in m.signals)})")
        try:
            vals[k] = float(v)
        except ValueError:
            raise SystemExit(f"drivecan send: {k}: '{v}' is not a number")
    for s in m.signals:
        vals.setdefault(s.name, 0)
    return vals


def send(args, bus=None, db=None):
    db = db or load_db(args.dbc)
    try:
        m = db.get_message_by_name(args.message)
    except KeyError:
        cmds = ", ".join(x.name for x in db.messages if x.name.startswith("Cmd"))
        raise SystemExit(f"drivecan send: no message '{args.message}' in the DBC (commands: {cmds})")
    if not 0 <= args.node <= NODE_MASK:
        raise SystemExit(f"drivecan send: --node {args.node}: must be 0-15")
    vals = parse_assignments(m, args.values)
    try:
        data = m.encode(vals, strict=True)
    except Exception as e:  # cantools says which signal is out of range
        raise SystemExit(f"drivecan send: {m.name}: {e}")
    bus = bus or open_bus(args)
    bus.send(can.Message(arbitration_id=m.frame_id + args.node, data=data, is_extended_id=False))
    print(f"drivecan: sent {m.name} to node {args.node}: {vals}", file=sys.stderr)
    return 0


# ---- parameters (ParamRequest / ParamReply) --------------------------------
# The parameters' one source (firmware/drives/<drive>/params.toml and
# firmware/config/board_params.toml) read by tools/params/gen_params.py's
# reader: names, ids, types, ranges; the drive of a node from its
# heartbeat's DriveKind (the DBC's choice names start with the drive's).
sys.path.insert(0, os.path.join(ROOT, "tools", "params"))
import gen_params  # noqa: E402

PARAM_OPS = {"read": 0, "write": 1, "save": 2, "defaults": 3, "list": 4}


class ParamError(Exception):
    pass


def param_tables(drive):
    """{id: param} and {name: param} of the board's and the drive's tables."""
    import pathlib
    src = pathlib.Path(ROOT) / "firmware" / "drives" / drive / "params.toml"
    if not src.is_file():
        drives = sorted(d.name for d in (pathlib.Path(ROOT) / "firmware" / "drives").iterdir()
                        if (d / "params.toml").is_file())
        raise ParamError(f"--drive {drive}: no such drive with parameters ({', '.join(drives)})")
    params = gen_params.read_table(pathlib.Path(ROOT) / gen_params.BOARD_SRC, board=True)["params"]
    params += gen_params.read_table(src)["params"]
    return {p["id"]: p for p in params}, {p["name"]: p for p in params}


def value_to_bits(p, text):
    """The 32 bits of VALUE for parameter p, checked against its type and
    range; raises ParamError naming both."""
    t = p["type"]
    try:
        if t == "f32":
            x = float(text)
            if x != x or x in (float("inf"), float("-inf")):
                raise ValueError
            if not gen_params.f32(p["min"]) <= gen_params.f32(x) <= gen_params.f32(p["max"]):
                raise ParamError(f"{p['name']}: {text} outside [{p['min']:g}, {p['max']:g}] {p['unit']}")
            return struct.unpack("<I", struct.pack("<f", x))[0]
        if t == "bool":
            v = {"true": 1, "false": 0, "1": 1, "0": 0}.get(str(text).lower())
            if v is None:
                raise ValueError
            return v
        if t == "enum":
            if text in p["values"]:
                return p["values"].index(text)
            raise ParamError(f"{p['name']}: '{text}' is not one of {', '.join(p['values'])}")
        x = int(str(text), 0)
    except ValueError:
        raise ParamError(f"{p['name']}: '{text}' is not a value of type {t}") from None
    if not p["min"] <= x <= p["max"]:
        raise ParamError(f"{p['name']}: {x} outside [{p['min']}, {p['max']}]")
    return x & 0xFFFFFFFF


def bits_to_value(p, bits):
    """The parameter's value (float, int, bool or the enum's name) of 32 bits."""
    bits &= 0xFFFFFFFF
    t = p["type"] if p else "u32"
    if t == "f32":
        return struct.unpack("<f", struct.pack("<I", bits))[0]
    if t == "i32":
        return bits - (1 << 32) if bits & 0x80000000 else bits
    if t == "bool":
        return bool(bits)
    if t == "enum":
        return p["values"][bits] if bits < len(p["values"]) else bits
    return bits


def fmt_value(p, v):
    if isinstance(v, float):  # a float32's shortest text that reads back as the same float32
        for digits in range(1, 10):
            text = f"{v:.{digits}g}"
            if struct.pack("<f", float(text)) == struct.pack("<f", v):
                return text
        return f"{v:.9g}"
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


class ParamClient:
    """Requests to one node, each answered by the ParamReply of its Seq
    (retried twice on a timeout or a "busy" answer: a board serves one
    request at a time). A save waits at least SAVE_TIMEOUT_S: a board
    erases a flash sector for it (up to 0.5 s on the STM32F405)."""

    SAVE_TIMEOUT_S = 2.0

    def __init__(self, bus, db, node, timeout_s=0.5):
        self.bus, self.db, self.node, self.timeout_s = bus, db, node, timeout_s
        self.req = db.get_message_by_name("ParamRequest")
        self.rep = db.get_message_by_name("ParamReply")
        self.status = {int(k): str(v) for k, v in self.rep.get_signal_by_name("Status").choices.items()}
        self.seq = 0

    def request(self, op, pid=0, bits=0):
        """(status name, id, 32 bits) of the reply."""
        value = bits - (1 << 32) if bits & 0x80000000 else bits
        timeout_s = max(self.timeout_s, self.SAVE_TIMEOUT_S) if op == "save" else self.timeout_s
        answer = None
        for _ in range(3):
            self.seq = (self.seq + 1) & 0xFF
            data = self.req.encode({"Op": PARAM_OPS[op], "Seq": self.seq, "ParamId": pid, "Value": value},
                                   strict=True)
            self.bus.send(can.Message(arbitration_id=self.req.frame_id + self.node, data=data, is_extended_id=False))
            end = time.monotonic() + timeout_s
            answer = None
            while time.monotonic() < end:
                m = self.bus.recv(timeout=max(0.0, end - time.monotonic()))
                if m is None or m.arbitration_id != self.rep.frame_id + self.node or len(m.data) != 8:
                    continue
                r = self.rep.decode(bytes(m.data), decode_choices=False)
                if r["Seq"] == self.seq and r["Op"] == PARAM_OPS[op]:
                    answer = (self.status.get(int(r["Status"]), str(r["Status"])), int(r["ParamId"]),
                              int(r["Value"]) & 0xFFFFFFFF)
                    break
            if answer is not None and answer[0] != "busy":
                return answer
            if answer is not None:
                time.sleep(0.05)  # the node serves another request: ask again
        if answer is not None:
            return answer  # busy three times
        raise ParamError(f"node {self.node}: no ParamReply to {op} within {timeout_s} s (3 tries)")


def node_drive(bus, db, node, timeout_s=1.5):
    """The drive of node (its folder's name) from a heartbeat's DriveKind."""
    hb = db.get_message_by_name("Heartbeat")
    kinds = {int(k): str(v) for k, v in hb.get_signal_by_name("DriveKind").choices.items()}
    drives = sorted((d for d in os.listdir(os.path.join(ROOT, "firmware", "drives"))
                     if os.path.isfile(os.path.join(ROOT, "firmware", "drives", d, "params.toml"))),
                    key=len, reverse=True)
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        m = bus.recv(timeout=max(0.0, end - time.monotonic()))
        if m is None or m.arbitration_id != hb.frame_id + node or len(m.data) != hb.length:
            continue
        kind = kinds.get(int(hb.decode(bytes(m.data), decode_choices=False)["DriveKind"]))
        for d in drives:
            if kind is not None and kind.startswith(d):
                return d
        raise ParamError(f"node {node}: DriveKind {kind} names no drive with parameters (--drive NAME)")
    raise ParamError(f"node {node}: no heartbeat within {timeout_s} s to tell its drive (--drive NAME)")


def param_lookup(by_id, by_name, key):
    if key in by_name:
        return by_name[key]
    try:
        pid = int(key, 0)
    except ValueError:
        raise ParamError(f"no parameter '{key}' (drivecan.py param list names them)") from None
    return by_id.get(pid) or {"id": pid, "name": f"{pid:#06x}", "type": "u32", "unit": "", "access": "?"}


def param_list(client, by_id):
    """[(param, value)] of every parameter the node lists."""
    out, at = [], 0
    while at <= 0xFFFE:
        st, pid, bits = client.request("list", at)
        if st == "unknown_id":
            break
        if st != "done":
            raise ParamError(f"list from {at:#06x}: refused: {st}")
        p = by_id.get(pid)
        if p is None:
            p = {"id": pid, "name": f"{pid:#06x}", "type": "u32", "unit": "", "access": "?"}
        out.append((p, bits_to_value(p, bits)))
        at = pid + 1
    return out


def check_done(what, st):
    if st != "done":
        raise ParamError(f"{what}: refused: {st}")


def param_cmd(args, bus=None, db=None):
    db = db or load_db(args.dbc)
    if not 0 <= args.node <= NODE_MASK:
        raise SystemExit(f"drivecan {args.cmd}: --node {args.node}: must be 0-15")
    bus = bus or open_bus(args)
    try:
        drive = args.drive or node_drive(bus, db, args.node)
        by_id, by_name = param_tables(drive)
        c = ParamClient(bus, db, args.node, args.timeout)
        if args.cmd == "param":
            return param_action(args, c, by_id, by_name)
        return config_action(args, c, drive, by_id, by_name)
    except (ParamError, gen_params.SourceError) as e:
        print(f"drivecan {args.cmd}: {e}", file=sys.stderr)
        return 1


def param_action(args, c, by_id, by_name):
    if args.action == "list":
        for p, v in param_list(c, by_id):
            print(f"{p['id']:#06x}  {p['name']:<28} {fmt_value(p, v):>14} {p['unit']:<8} {p['access']}")
        return 0
    if args.action in ("save", "defaults"):
        check_done(args.action, c.request(args.action)[0])
        print(f"drivecan: {args.action}: done", file=sys.stderr)
        return 0
    if not args.args:
        raise ParamError(f"param {args.action}: which parameter?")
    p = param_lookup(by_id, by_name, args.args[0])
    if args.action == "get":
        st, _, bits = c.request("read", p["id"])
        check_done(f"get {p['name']}", st)
        print(f"{p['name']} = {fmt_value(p, bits_to_value(p, bits))} {p['unit']}".rstrip())
        return 0
    if len(args.args) != 2:
        raise ParamError("param set NAME VALUE")
    st, _, bits = c.request("write", p["id"], value_to_bits(p, args.args[1]))
    check_done(f"set {p['name']}", st)
    print(f"{p['name']} = {fmt_value(p, bits_to_value(p, bits))} {p['unit']}".rstrip())
    return 0


def config_action(args, c, drive, by_id, by_name):
    import tomllib
    if args.action == "export":
        rows = param_list(c, by_id)
        lines = [f"# drivecan.py config export, node {args.node}: the {drive} drive's and its board's parameters",
                 f"drive = \"{drive}\"", "", "[params]"]
        for p, v in rows:
            val = f"\"{v}\"" if isinstance(v, str) else fmt_value(p, v)
            if p["type"] == "f32" and "e" not in val and "." not in val and "n" not in val:
                val += ".0"
            lines.append(f"{p['name']} = {val}  # {p['unit'] or '-'}, {p['access']}")
        tmp = args.file + ".tmp"
        with open(tmp, "w") as f:
            f.write("\n".join(lines) + "\n")
        os.replace(tmp, args.file)
        print(f"drivecan: {len(rows)} parameters into {args.file}", file=sys.stderr)
        return 0
    try:
        with open(args.file, "rb") as f:
            src = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise ParamError(f"{args.file}: {e}") from None
    if src.get("drive", drive) != drive:
        raise ParamError(f"{args.file}: drive = \"{src['drive']}\", node {args.node} runs {drive}")
    want = src.get("params")
    if not isinstance(want, dict):
        raise ParamError(f"{args.file}: no [params] table")
    writes = []
    for name, v in want.items():  # every value checked before anything is written
        if name not in by_name:
            raise ParamError(f"{args.file}: params.{name}: not a parameter of {drive} or its board")
        p = by_name[name]
        text = ("true" if v else "false") if isinstance(v, bool) else str(v)
        writes.append((p, value_to_bits(p, text)))
    changed = 0
    for p, bits in writes:
        st, _, now = c.request("read", p["id"])
        check_done(f"read {p['name']}", st)
        if now == bits:
            continue
        if p["access"] == "ro":
            raise ParamError(f"{p['name']}: read-only, the node has {fmt_value(p, bits_to_value(p, now))}, "
                             f"the file {fmt_value(p, bits_to_value(p, bits))}")
        print(f"  {p['name']}: {fmt_value(p, bits_to_value(p, now))} -> {fmt_value(p, bits_to_value(p, bits))} "
              f"{p['unit']}".rstrip())
        check_done(f"set {p['name']}", c.request("write", p["id"], bits)[0])
        changed += 1
    print(f"drivecan: {changed} of {len(writes)} parameters changed", file=sys.stderr)
    if args.save:
        check_done("save", c.request("save")[0])
        print("drivecan: saved", file=sys.stderr)
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--dbc", default=DBC, help="the DBC (default: tools/can/drive.dbc)")
    sub = ap.add_subparsers(dest="cmd", required=True)

    def bus_args(p):
        p.add_argument("--channel", required=True, help="e.g. vcan0, can0")
        p.add_argument("--interface", default="socketcan", help="python-can interface (default socketcan)")

    p = sub.add_parser("monitor")
    bus_args(p)
    p.add_argument("--node", type=int, default=None)
    p.add_argument("--duration", type=float, default=0.0, help="seconds, then one table (0: until Ctrl-C)")
    p = sub.add_parser("record")
    bus_args(p)
    p.add_argument("--node", type=int, default=None)
    p.add_argument("--log", required=True)
    p.add_argument("--csv")
    p.add_argument("--duration", type=float, default=0.0)
    p.add_argument("--count", type=int, default=0)
    p = sub.add_parser("decode")
    p.add_argument("log")
    p.add_argument("--csv")
    p.add_argument("--node", type=int, default=None)
    p = sub.add_parser("plot")
    p.add_argument("items", nargs="+", metavar="LOG|SIGNAL", help="a log then signals; only signals with --channel")
    p.add_argument("-o", "--output")
    p.add_argument("--channel", help="plot S seconds of this bus instead of a log")
    p.add_argument("--interface", default="socketcan", help="python-can interface (default socketcan)")
    p.add_argument("--duration", type=float, default=0.0)
    p = sub.add_parser("send")
    bus_args(p)
    p.add_argument("--node", type=int, default=0)
    p.add_argument("message")
    p.add_argument("values", nargs="*")
    for name, actions in (("param", ("list", "get", "set", "save", "defaults")), ("config", ("export", "import"))):
        p = sub.add_parser(name)
        bus_args(p)
        p.add_argument("--node", type=int, default=0)
        p.add_argument("--drive", help="the node's drive (default: from its heartbeat)")
        p.add_argument("--timeout", type=float, default=0.5, help="seconds for each reply (default 0.5)")
        p.add_argument("action", choices=actions)
        if name == "param":
            p.add_argument("args", nargs="*", metavar="NAME [VALUE]")
        else:
            p.add_argument("file", metavar="FILE.toml")
            p.add_argument("--save", action="store_true", help="import: save after writing")
    args = ap.parse_args(argv)
    if args.cmd in ("param", "config"):
        return param_cmd(args)
    if args.cmd == "monitor":
        monitor(args)
        return 0
    if args.cmd == "record":
        record(args)
        return 0
    if args.cmd == "decode":
        return decode_log(args)
    if args.cmd == "plot":
        return plot(args)
    return send(args)


if __name__ == "__main__":
    sys.exit(main())
