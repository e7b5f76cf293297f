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
    args = ap.parse_args(argv)
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
