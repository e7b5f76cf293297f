#!/usr/bin/env python3
"""SocketCAN end-to-end test of the drives on CAN (ctest label vcan; run in
the VM fixture by tests/vcan/run_vcan_e2e.sh, or on any Linux with vcan):

  for the paper-000 position drive and the speed drives of papers 001
  and 002:
  motorsim --can vcan0 --realtime runs a short scenario (tests/vcan/*.toml)
  while candump -L records the bus and this script commands the drive
  over python-can once the telemetry says it is ready. Then:
  - every recorded telemetry frame, decoded with tools/can/drive.dbc by
    cantools, equals the simulator's own CSV at the sample it was sent
    at (the n-th frame of a message is sent at sample m + n * period, the
    schedule of firmware/comm/can_tx.c), to one step of the signal;
  - the valid commands changed the drive as the CSV shows (a new move, a
    new speed, a stop), and the bad frames (wrong length, out of range,
    unknown id, the other drive's command, a move during a move) were
    refused: the heartbeat's RejectedCommands and motorsim's metrics count
    them, and the CSV's reference did not move until the valid command;
  - `cantools decode` reads the recording with the DBC as it is;
  - the parameters (issue 44): paper 001 on the bus with --flash-image;
    each refusal of ParamReply met once (not while enabled, unknown id,
    read-only, out of range, bad value, bad request, design refused with
    CmdEnable refused meanwhile, store failed), a resistance written while
    disabled and saved; a second motorsim on the same image reads it back,
    and its run is bit for bit the native run of the scenario whose
    [drive_model] has that resistance (and differs from the scenario's).

    vcan_e2e.py --motorsim build/host/sim/motorsim --out DIR [--iface vcan0] [--plot PNG]
                [--phase all|record|check] [--vm]

Two phases: `record` runs the drives on the bus and writes each case's
recording, CSV, metrics and what the commander sent (DIR/CASE/case.json);
`check` reads them back and checks. `all` (the default) does both where
vcan is; `--vm` runs the record phase in the VM fixture (tools/vm/vm_run.py)
and the check phase here, natively: under the VM's TCG the checks (reading
four CSVs, decoding with cantools) took about 55 s of the test's 110.

Exit 0 pass, 1 fail (each failed check printed), 77 no SocketCAN here.
"""
import argparse
import csv
import json
import os
import re
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools", "can"))
import can  # noqa: E402
import cantools  # noqa: E402
from drivecan import dbc_msg_set_version, project_version  # noqa: E402

DBC = os.path.join(ROOT, "tools", "can", "drive.dbc")
SKIP = 77
FS_HZ = 10000
# firmware/comm/can_tx.c: message m first due at sample m; defaults 100 ms
# (heartbeat) and 10 ms
ORDER = ["Heartbeat", "Position", "Velocity", "Currents", "Observer", "Voltages", "Timing", "Version"]
PERIOD = {"Heartbeat": 1000, "Version": 10000}
DEFAULT_PERIOD = 100
HEARTBEAT_PERIOD_S = PERIOD["Heartbeat"] / FS_HZ

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)
    return ok


def ensure_iface(iface):
    if os.path.exists(f"/sys/class/net/{iface}"):
        return True
    r = subprocess.run(["ip", "link", "add", "dev", iface, "type", "vcan"], capture_output=True, text=True)
    if r.returncode != 0:
        print(f"vcan_e2e: cannot create {iface}: {r.stderr.strip()} (no vcan module, or not root)", file=sys.stderr)
        return False
    subprocess.run(["ip", "link", "set", "up", iface], check=True)
    return True


class Drive:
    """The bus side of one run: telemetry seen so far, commands out."""

    def __init__(self, db, iface):
        self.db = db
        self.bus = can.Bus(interface="socketcan", channel=iface, receive_own_messages=False)
        self.last = {}

    def poll(self, timeout):
        msg = self.bus.recv(timeout)
        if msg is None or msg.is_extended_id:
            return
        try:
            m = self.db.get_message_by_frame_id(msg.arbitration_id & ~0xF)
        except KeyError:
            return
        if m.senders and m.senders[0] == "DRIVE":
            self.last[m.name] = m.decode(bytes(msg.data), decode_choices=False)

    def wait_for(self, cond, timeout_s, what):
        t_end = time.monotonic() + timeout_s
        while time.monotonic() < t_end:
            self.poll(0.05)
            try:
                if cond(self.last):
                    return True
            except KeyError:
                pass
        return check(False, f"telemetry never showed {what} within {timeout_s:g} s")

    def wait_sim(self, seconds, timeout_s=30):
        """Waits for `seconds` of the drive's own time, counted in heartbeats
        (HEARTBEAT_PERIOD_S apart, Counter): under TCG the simulator can run
        slower than the wall clock, and a wall-clock sleep then gives the
        drive less time than the checks assume."""
        c0 = self.last["Heartbeat"]["Counter"]
        n = round(seconds / HEARTBEAT_PERIOD_S)
        return self.wait_for(lambda s: (s["Heartbeat"]["Counter"] - c0) % 65536 >= n, timeout_s,
                             f"{n} heartbeats ({seconds:g} s of drive time)")

    def send(self, name, **values):
        m = self.db.get_message_by_name(name)
        self.bus.send(can.Message(arbitration_id=m.frame_id, data=m.encode(values), is_extended_id=False))

    def send_raw(self, frame_id, data):
        self.bus.send(can.Message(arbitration_id=frame_id, data=bytes(data), is_extended_id=False))

    def param(self, op, pid=0, bits=0, timeout_s=2.0, tries=3):
        """One ParamRequest; (status name, id, 32 bits) of its ParamReply
        (matched by Seq), or None. Retried on a timeout as drivecan.py does
        (a reply can be pushed out of the node's full transmit queue by
        newer telemetry when the bus is slow: seen under a loaded VM; every
        request here gives the same answer when repeated)."""
        for _ in range(tries):
            got = self._param_once(op, pid, bits, timeout_s)
            if got is not None:
                return got
        return None

    def _param_once(self, op, pid, bits, timeout_s):
        self.seq = (getattr(self, "seq", 0) + 1) & 0xFF
        req, rep = self.db.get_message_by_name("ParamRequest"), self.db.get_message_by_name("ParamReply")
        value = bits - (1 << 32) if bits & 0x80000000 else bits
        self.bus.send(can.Message(arbitration_id=req.frame_id, is_extended_id=False,
                                  data=req.encode({"Op": op, "Seq": self.seq, "ParamId": pid, "Value": value})))
        names = {int(k): str(v) for k, v in rep.get_signal_by_name("Status").choices.items()}
        t_end = time.monotonic() + timeout_s
        while time.monotonic() < t_end:
            msg = self.bus.recv(0.05)
            if msg is None or msg.arbitration_id != rep.frame_id or len(msg.data) != 8:
                if msg is not None and not msg.is_extended_id:
                    try:
                        m = self.db.get_message_by_frame_id(msg.arbitration_id & ~0xF)
                        if m.senders and m.senders[0] == "DRIVE" and m.name != "ParamReply":
                            self.last[m.name] = m.decode(bytes(msg.data), decode_choices=False)
                    except KeyError:
                        pass
                continue
            r = rep.decode(bytes(msg.data), decode_choices=False)
            if r["Seq"] == self.seq:
                return names.get(int(r["Status"]), str(r["Status"])), int(r["ParamId"]), int(r["Value"]) & 0xFFFFFFFF
        return None

    def close(self):
        self.bus.shutdown()


def read_log(path, db):
    """{message: [decoded signals, ...]} of the drive's frames, in order."""
    out = {n: [] for n in ORDER}
    for msg in can.CanutilsLogReader(path):
        try:
            m = db.get_message_by_frame_id(msg.arbitration_id & ~0xF)
        except KeyError:
            continue
        if m.name in out:
            out[m.name].append(m.decode(bytes(msg.data), decode_choices=False))
    return out


def read_csv(path):
    with open(path) as f:
        r = csv.reader(f)
        head = next(r)
        cols = {h: i for i, h in enumerate(head)}
        rows = [[float(x) for x in row] for row in r]
    return cols, rows


def compare(frames, cols, rows, mapping, what):
    """Each frame of each message against the CSV row of its sample."""
    worst = {}
    n_cmp = 0
    for msg, pairs in mapping.items():
        m0 = ORDER.index(msg)
        period = PERIOD.get(msg, DEFAULT_PERIOD)
        for n, sig in enumerate(frames[msg]):
            tick = m0 + n * period
            if tick >= len(rows):
                check(False, f"{what}: {msg} frame {n} is past the CSV's {len(rows)} samples")
                return
            for signal_name, col, lsb in pairs:
                ref = rows[tick][cols[col]]
                err = abs(sig[signal_name] - ref)
                key = f"{msg}.{signal_name}"
                worst[key] = max(worst.get(key, 0.0), err / lsb)
                n_cmp += 1
    bad = {k: v for k, v in worst.items() if v > 1.0}
    check(n_cmp > 1000 and not bad,
          f"{what}: {n_cmp} decoded values equal the CSV at their samples to one step (worst in steps: "
          + ", ".join(f"{k} {v:.2f}" for k, v in sorted(worst.items())) + ")")


def record_case(args, db, name, scenario, commander, extra=()):
    """The bus side of one case: motorsim on the bus, candump recording,
    the commander talking to the drive. Writes DIR/NAME/case.json with what
    the check phase needs that the files do not hold."""
    out = os.path.join(args.out, name)
    os.makedirs(out, exist_ok=True)
    log_path = os.path.join(out, f"{name}.log")
    with open(log_path, "w") as log:
        dump = subprocess.Popen(["candump", "-L", args.iface], stdout=log)
    drive = Drive(db, args.iface)
    time.sleep(0.3)  # candump bound before the first frame
    err_path = os.path.join(out, "motorsim.stderr")
    n_fail = len(failures)
    sent_bad = []
    with open(err_path, "w") as err:
        sim = subprocess.Popen([args.motorsim, "--scenario", scenario, "--can", args.iface, "--realtime",
                                "--out", out, "--no-plot", "--no-expect", *extra], stdout=subprocess.DEVNULL,
                               stderr=err)
    rc = None
    try:
        commander(drive, sent_bad)
        rc = sim.wait(timeout=120)
    finally:
        if sim.poll() is None:
            sim.kill()
        drive.close()
        time.sleep(0.3)
        dump.send_signal(signal.SIGINT)
        dump.wait(timeout=10)
    with open(os.path.join(out, "case.json"), "w") as f:
        json.dump({"scenario": scenario, "motorsim_rc": rc, "sent_bad": sent_bad, "out": out,
                   "commander_failures": failures[n_fail:]}, f, indent=1)


def load_case(args, db, name):
    """What the record phase left in DIR/NAME, read back; the commander's
    failures (a telemetry wait that timed out) counted again here."""
    out = os.path.join(args.out, name)
    try:
        case = json.load(open(os.path.join(out, "case.json")))
    except (OSError, ValueError) as e:
        check(False, f"{name}: no recording to check ({e}): did the record phase run?")
        return None
    for what in case["commander_failures"]:
        check(False, what)
    rc = case["motorsim_rc"]
    err_path = os.path.join(out, "motorsim.stderr")
    stderr = open(err_path).read()
    check(rc == 0, f"{name}: motorsim exit status {rc} (0 expected)" + ("" if rc == 0 else ": " + stderr[-400:]))
    stem = os.path.splitext(os.path.basename(case["scenario"]))[0]
    log_path = os.path.join(out, f"{name}.log")
    metrics = json.load(open(os.path.join(out, f"{stem}_metrics.json")))
    cols, rows = read_csv(os.path.join(out, f"{stem}.csv"))
    frames = read_log(log_path, db)
    print(f"{name}: {sum(len(v) for v in frames.values())} telemetry frames recorded, {len(rows)} CSV rows; "
          f"motorsim said:\n  " + "\n  ".join(l for l in stderr.splitlines() if "CAN" in l))
    return metrics, cols, rows, frames, case["sent_bad"], log_path


def position_commander(d, sent_bad):
    # the configured move is over: 18 rad, at rest, back in open loop
    if not d.wait_for(lambda s: abs(s["Position"]["ThetaRef"] - 18.0) < 1e-4 and s["Velocity"]["OmegaRef"] == 0,
                      60, "the end of the 18 rad move"):
        return
    # the polynomial's last 50 ms move it by less than ThetaRef's step:
    # wait them out (a move is refused while one is in progress)
    time.sleep(0.15)
    bad = [
        ("CmdMove with 5 bytes (DLC)", 0x210, [0, 0, 0, 0, 0]),
        ("CmdMove with Duration 0 (range)", 0x210, [0x40, 0x42, 0x0F, 0, 0, 0]),
        ("unknown identifier 0x2F0", 0x2F0, [1, 2, 3]),
        ("CmdStop with a non-zero reserved byte (range)", 0x230, [1]),
        ("CmdEnable with bit 1 set (range)", 0x200, [2]),
    ]
    for what, fid, data in bad:
        d.send_raw(fid, data)
        sent_bad.append(what)
    d.send("CmdSpeed", OmegaRef=5.0, Ramp=10.0)  # the speed drive's: mode
    sent_bad.append("CmdSpeed to the position drive (mode)")
    t_end = time.monotonic() + 0.2  # they are carried out (or not) before the move below
    while time.monotonic() < t_end:
        d.poll(0.05)
    d.send("CmdMove", ThetaTo=6.0, Duration=2.0)
    time.sleep(0.2)
    d.send("CmdMove", ThetaTo=0.0, Duration=1.0)  # during the move: mode
    sent_bad.append("CmdMove during a move (mode)")


def position_checks(metrics, cols, rows, frames, sent_bad):
    mapping = {
        "Position": [("ThetaRef", "theta_ref_rad", 1e-5), ("ThetaEst", "theta_est_rad", 1e-5)],
        "Velocity": [("OmegaRef", "omega_ref_rad_s", 0.01), ("OmegaEst", "omega_est_rad_s", 0.01),
                     ("AccelEst", "accel_est_rad_s2", 1.0), ("LoadEst", "load_est_Nm", 1e-4)],
        "Currents": [("I1", "i_f_meas_A", 1e-3), ("I2", "i_g_meas_A", 1e-3), ("I1Ref", "i_f_ref_A", 1e-3),
                     ("I2Ref", "i_g_ref_A", 1e-3)],
        "Observer": [("I1Est", "i_f_est_A", 1e-3), ("I2Est", "i_g_est_A", 1e-3)],
        "Voltages": [("V1", "v_f_V", 2e-3), ("V2", "v_g_V", 2e-3)],
        "Heartbeat": [("Mode", "mode", 1.0)],
    }
    compare(frames, cols, rows, mapping, "position")
    hb = frames["Heartbeat"]
    msv = dbc_msg_set_version()
    check(bool(hb) and all(h["MsgSetVersion"] == msv and h["DriveKind"] == 0 for h in hb),
          f"position: heartbeats carry DriveKind 0 and MsgSetVersion {msv}")
    fw = project_version()
    ver = frames["Version"]
    check(len(ver) >= 2 and all((v["FwMajor"], v["FwMinor"], v["FwPatch"], v["FixedPoint"]) == fw + (0,) for v in ver),
          f"position: {len(ver)} Version frames carry firmware {'.'.join(map(str, fw))} (CMakeLists.txt), float build")
    check(bool(hb) and hb[-1]["RejectedCommands"] == len(sent_bad),
          f"position: heartbeat RejectedCommands {hb[-1]['RejectedCommands'] if hb else None} = the "
          f"{len(sent_bad)} bad frames sent ({'; '.join(sent_bad)})")
    check(metrics.get("can_commands_accepted") == 1 and metrics.get("can_commands_refused") == len(sent_bad),
          f"position: motorsim counted {metrics.get('can_commands_accepted')} accepted, "
          f"{metrics.get('can_commands_refused')} refused (1 and {len(sent_bad)} expected)")
    # the reference: 18 until the accepted CmdMove, then a move to 6
    th = [r[cols["theta_ref_rad"]] for r in rows]
    k18 = next((k for k, x in enumerate(th) if abs(x - 18.0) < 1e-6), None)
    k_move = next((k for k in range(k18 or 0, len(th)) if abs(th[k] - 18.0) > 1e-6), None) if k18 else None
    check(k18 is not None and k_move is not None and all(abs(x - 18.0) < 1e-6 for x in th[k18:k_move]),
          "position: the CSV's reference held at 18 rad through the bad frames until the CmdMove")
    check(abs(th[-1] - 6.0) < 1e-5, f"position: the CSV's final reference {th[-1]:.6f} rad is the commanded 6 rad")
    theta_end = rows[-1][cols["theta_rad"]]
    check(abs(theta_end - 6.0) < 0.02, f"position: the rotor ended at {theta_end:.4f} rad (6 +- 0.02)")
    check(metrics.get("theta_track_max_rad", 1.0) < 0.02 and metrics.get("fault") == 0,
          f"position: tracking of the commanded move max {metrics.get('theta_track_max_rad'):.4f} rad < 0.02, no fault")


SPEED_MAPPING = {
    "Velocity": [("OmegaRef", "omega_ref_rad_s", 0.01), ("OmegaEst", "omega_est_rad_s", 0.01),
                 ("LoadEst", "load_est_Nm", 1e-4)],
    "Currents": [("I1", "i_d_meas_A", 1e-3), ("I2", "i_q_meas_A", 1e-3), ("I2Ref", "i_q_ref_A", 1e-3)],
    "Heartbeat": [("Mode", "mode", 1.0)],
}


def speed_command_checks(name, kind, metrics, cols, rows, frames, sent_bad, mapping=SPEED_MAPPING,
                         ref_col="omega_ref_rad_s", target=10.0, tol=0.1):
    """A speed drive commanded to TARGET rad/s, then stopped, over CAN: the
    telemetry equals the CSV, the heartbeat's DriveKind and refusals, the
    commands carried out, the rotor at TARGET (within TOL) and then at rest."""
    compare(frames, cols, rows, mapping, name)
    hb = frames["Heartbeat"]
    check(bool(hb) and all(h["DriveKind"] == kind for h in hb), f"{name}: heartbeats carry DriveKind {kind}")
    check(bool(hb) and hb[-1]["RejectedCommands"] == len(sent_bad),
          f"{name}: heartbeat RejectedCommands {hb[-1]['RejectedCommands'] if hb else None} = {len(sent_bad)}")
    check(metrics.get("can_commands_accepted") == 2, f"{name}: {metrics.get('can_commands_accepted')} commands "
          "carried out (CmdSpeed, CmdStop)")
    w_ref = [r[cols[ref_col]] for r in rows]
    w = [r[cols["omega_rad_s"]] for r in rows]
    held = [k for k, x in enumerate(w_ref) if abs(x - target) < 1e-6]
    check(len(held) > 3000,
          f"{name}: the CSV's reference held {target:g} rad/s for {len(held) / FS_HZ:.3f} s after CmdSpeed")
    if held:
        k_end = held[-1]
        err = max(abs(w[k] - target) for k in range(k_end - 2000, k_end + 1))
        check(err < tol, f"{name}: the rotor ran at {target:g} rad/s (max error {err:.4f} rad/s over the last 0.2 s "
              "of it)")
    check(abs(w_ref[-1]) < 1e-6 and abs(w[-1]) < tol,
          f"{name}: after CmdStop the reference is {w_ref[-1]:.4f} and the rotor {w[-1]:.4f} rad/s (0 expected)")
    check(metrics.get("fault") == 0, f"{name}: no fault")


def speed_commander(d, sent_bad):
    if not d.wait_for(lambda s: s["Heartbeat"]["Mode"] == 1 and s["Velocity"]["OmegaRef"] > 5.2, 60,
                      "closed loop at 50 rpm"):
        return
    time.sleep(0.3)
    d.send("CmdMove", ThetaTo=1.0, Duration=1.0)  # the position drive's: mode
    sent_bad.append("CmdMove to the speed drive (mode)")
    d.send("CmdSpeed", OmegaRef=10.0, Ramp=20.0)
    if not d.wait_for(lambda s: abs(s["Velocity"]["OmegaRef"] - 10.0) < 0.01, 10, "the new reference 10 rad/s"):
        return
    if not d.wait_sim(0.6):
        return
    d.send("CmdStop", Reserved=0)


def speed_checks(metrics, cols, rows, frames, sent_bad):
    speed_command_checks("speed", 1, metrics, cols, rows, frames, sent_bad)


def paper002_commander(d, sent_bad):
    if not d.wait_for(lambda s: s["Heartbeat"]["DriveKind"] == 2 and s["Velocity"]["OmegaRef"] > 99.99, 60,
                      "the reference at 100 rad/s"):
        return
    time.sleep(0.2)
    d.send("CmdSetOmegaLim", OmegaLim=3.0)  # no open loop: mode
    sent_bad.append("CmdSetOmegaLim to paper 002's drive (mode)")
    d.send("CmdSpeed", OmegaRef=50.0, Ramp=500.0)
    if not d.wait_for(lambda s: abs(s["Velocity"]["OmegaRef"] - 50.0) < 0.01, 10, "the new reference 50 rad/s"):
        return
    if not d.wait_sim(0.5):
        return
    d.send("CmdStop", Reserved=0)


def paper002_checks(metrics, cols, rows, frames, sent_bad):
    mapping = {
        "Position": [("ThetaEst", "theta_est_rad", 1e-5)],
        "Velocity": [("OmegaRef", "omega_d_rad_s", 0.01), ("OmegaEst", "omega_est_rad_s", 0.01),
                     ("LoadEst", "M0_est_Nm", 1e-4)],
        "Currents": [("I1", "i_d_meas_A", 1e-3), ("I2", "i_q_meas_A", 1e-3), ("I1Ref", "i_d_ref_A", 1e-3),
                     ("I2Ref", "i_q_ref_A", 1e-3)],
        "Observer": [("I1Est", "i_d_est_A", 1e-3), ("I2Est", "i_q_est_A", 1e-3)],
        "Voltages": [("V1", "u_d_V", 2e-3), ("V2", "u_q_V", 2e-3)],
        "Heartbeat": [("Mode", "mode", 1.0)],
    }
    speed_command_checks("paper002", 2, metrics, cols, rows, frames, sent_bad, mapping=mapping,
                         ref_col="omega_d_rad_s", target=50.0, tol=0.5)


def sensored_commander(d, sent_bad):
    """The fourth drive (issue 27) on the shipped scenario itself:
    motorsim --scenario sim/scenarios/sensored_benchmark.toml --can IFACE."""
    if not d.wait_for(lambda s: s["Heartbeat"]["Mode"] == 1 and s["Velocity"]["OmegaRef"] > 5.2, 60,
                      "the profile at 50 rpm"):
        return
    d.send("CmdSetOmegaLim", OmegaLim=3.0)  # a sensorless drive's: refused (mode)
    sent_bad.append("CmdSetOmegaLim to the sensored drive (mode)")
    d.send("CmdSpeed", OmegaRef=10.0, Ramp=20.0)
    if not d.wait_for(lambda s: abs(s["Velocity"]["OmegaRef"] - 10.0) < 0.01, 10, "the new reference 10 rad/s"):
        return
    # 1.6 s: the check's last 0.2 s of the hold then start at least 0.14 s
    # after the scenario's load step at 2.5 s (CmdSpeed lands at 1.0-1.5 s);
    # with 0.6 s they could start 40 ms after it (0.25 rad/s of transient)
    if not d.wait_sim(1.6):
        return
    d.send("CmdStop", Reserved=0)


def sensored_checks(metrics, cols, rows, frames, sent_bad):
    speed_command_checks("sensored", 3, metrics, cols, rows, frames, sent_bad)


# name, scenario, what the commander does on the bus, what is checked after
# ---- the parameters over CAN and --flash-image (issue 44) ----------------
# ids of firmware/drives/paper001/params.toml (docs/parameters.md)
R_OHM, TS_S, I_TRIP_A = 0x0101, 0x0210, 0x0202
R_NEW = 0.27  # ohm: the scenario's motor has 0.225


def f32_bits(x):
    import struct
    return struct.unpack("<I", struct.pack("<f", x))[0]


def f32_of(bits):
    import struct
    return struct.unpack("<f", struct.pack("<I", bits))[0]


def image_path(args):
    return os.path.join(os.path.abspath(args.out), "params.img")


def quiet_telemetry(d):
    """Every telemetry message but the heartbeat off (CmdSetRate, period 0),
    as a host configuring a drive would: at 800 frames a second a loaded
    VM's bus and this script's socket lost ParamReply frames (clean-clone
    CI runs of dec378b and db116c9)."""
    for m in range(1, 8):
        d.send("CmdSetRate", Message=m, Period=0)


def params_set_commander(d, answers, image):
    """Every refusal once, then R written while disabled and saved."""
    if not d.wait_for(lambda s: s["Heartbeat"]["Enabled"] == 1, 60, "the drive running"):
        return
    quiet_telemetry(d)

    def ask(what, op, pid=0, bits=0):
        a = d.param(op, pid, bits)
        answers.append({"what": what, "status": a[0] if a else None, "bits": a[2] if a else None})

    def heartbeat(what, signal):
        d.wait_sim(0.2)  # two heartbeats after the last request
        answers.append({"what": what, "status": int(d.last["Heartbeat"][signal]), "bits": None})

    heartbeat("heartbeat ConfigSource of a new image", "ConfigSource")
    ask("write R while enabled", 1, R_OHM, f32_bits(R_NEW))
    ask("save while enabled", 2)
    d.send("CmdEnable", Enable=0)
    if not d.wait_for(lambda s: s["Heartbeat"]["Enabled"] == 0, 10, "the drive disabled"):
        return
    ask("read an unknown id", 0, 0x0FFF)
    ask("write the read-only Ts", 1, TS_S, f32_bits(2e-4))
    ask("write R = 1000 ohm", 1, R_OHM, f32_bits(1000.0))
    ask("write R = NaN", 1, R_OHM, 0x7FC00000)
    ask("op 9", 9)
    ask("write i_trip below i_max", 1, I_TRIP_A, f32_bits(4.0))
    heartbeat("heartbeat ParamsRefused after the refused design", "ParamsRefused")
    d.send("CmdEnable", Enable=1)  # refused: the parameters do not design
    d.wait_sim(0.3)  # three heartbeats after it
    answers.append({"what": "enabled after CmdEnable while not designed",
                    "status": int(d.last["Heartbeat"]["Enabled"]), "bits": None})
    ask("write i_trip back to 12 A", 1, I_TRIP_A, f32_bits(12.0))
    heartbeat("heartbeat ParamsRefused once it designs", "ParamsRefused")
    os.mkdir(image + ".tmp")  # the image cannot be replaced: the store fails
    ask("save with the image's folder refusing", 2)
    os.rmdir(image + ".tmp")
    ask("write R", 1, R_OHM, f32_bits(R_NEW))
    ask("save", 2)


def params_read_commander(d, answers, image):
    if not d.wait_for(lambda s: "Heartbeat" in s, 60, "a heartbeat"):
        return
    quiet_telemetry(d)
    a = d.param(0, R_OHM)
    answers.append({"what": "read R after the restart", "status": a[0] if a else None, "bits": a[2] if a else None})
    answers.append({"what": "heartbeat ConfigSource after the restart",
                    "status": int(d.last["Heartbeat"]["ConfigSource"]), "bits": None})


PARAMS_SET_EXPECT = [
    ("heartbeat ConfigSource of a new image", 3),  # defaults_empty (tools/can/drive.dbc)
    ("write R while enabled", "not_while_enabled"), ("save while enabled", "not_while_enabled"),
    ("read an unknown id", "unknown_id"), ("write the read-only Ts", "read_only"),
    ("write R = 1000 ohm", "out_of_range"), ("write R = NaN", "bad_value"), ("op 9", "bad_request"),
    ("write i_trip below i_max", "design_refused"), ("heartbeat ParamsRefused after the refused design", 1),
    ("enabled after CmdEnable while not designed", 0),
    ("write i_trip back to 12 A", "done"), ("heartbeat ParamsRefused once it designs", 0), ("save with the image's folder refusing", "store_failed"),
    ("write R", "done"), ("save", "done"),
]


def record_params_set(args, db, image):
    """The requests' case: motorsim on tests/vcan/params_can.toml (60 s,
    no CSV) with --flash-image, stopped once the commander is done (the
    image is written by then); DIR/params_set/case.json holds the answers."""
    out = os.path.join(args.out, "params_set")
    os.makedirs(out, exist_ok=True)
    drive = Drive(db, args.iface)
    n_fail = len(failures)
    answers = []
    with open(os.path.join(out, "motorsim.stderr"), "w") as err:
        sim = subprocess.Popen([args.motorsim, "--scenario", os.path.join(HERE, "params_can.toml"), "--can", args.iface,
                                "--realtime", "--no-csv", "--metrics-out", os.path.join(out, "metrics.json"),
                                "--no-expect", "--flash-image", image], stdout=subprocess.DEVNULL, stderr=err)
    try:
        params_set_commander(drive, answers, image)
        alive = sim.poll() is None  # still running: every answer came from the run
    finally:
        sim.terminate()
        sim.wait(timeout=30)
        drive.close()
    with open(os.path.join(out, "case.json"), "w") as f:
        json.dump({"answers": answers, "alive_at_end": alive, "commander_failures": failures[n_fail:]}, f, indent=1)


def params_set_checks(args):
    try:
        case = json.load(open(os.path.join(args.out, "params_set", "case.json")))
    except (OSError, ValueError) as e:
        check(False, f"params_set: no recording to check ({e}): did the record phase run?")
        return
    for what in case["commander_failures"]:
        check(False, what)
    answers = case["answers"]
    for (what, want), got in zip(PARAMS_SET_EXPECT, answers):
        check(got["what"] == what and got["status"] == want, f"params: {what}: {got['status']} ({want} expected)")
    check(len(answers) == len(PARAMS_SET_EXPECT), f"params: {len(answers)} answers ({len(PARAMS_SET_EXPECT)} expected)")
    check(case["alive_at_end"], "params: motorsim still running when the last answer came (no fault, no early end)")


def params_read_checks(metrics, cols, rows, frames, answers, case_out=None):
    got = answers[0] if answers else {"status": None, "bits": None}
    check(got["status"] == "done" and got["bits"] == f32_bits(R_NEW),
          f"params: after the restart R reads {f32_of(got['bits']) if got['bits'] is not None else None} ohm "
          f"({got['status']}; {R_NEW} written and saved)")
    src = answers[1]["status"] if len(answers) > 1 else None
    check(src == 1, f"params: after the restart the heartbeat's ConfigSource is {src} (1, record, expected)")


def params_native_checks(args):
    """The second run against motorsim run natively on the scenario with
    [drive_model] R_ohm = the float32 written, and on the scenario alone."""
    out = os.path.join(args.out, "params_read")
    try:
        stderr = open(os.path.join(out, "motorsim.stderr")).read()
        cols, rows = read_csv(os.path.join(out, "speed_can.csv"))
    except OSError as e:
        check(False, f"params: no second run to compare ({e})")
        return
    # record 1, or a later one if a save's reply was lost and the save retried
    check("parameters: --flash-image" in stderr and re.search(r"record \d+, ", stderr) is not None,
          "params: the second motorsim started from the image's record: "
          + next((l for l in stderr.splitlines() if "parameters:" in l), "(no line)"))
    base = open(os.path.join(HERE, "speed_can.toml")).read().replace('"../../sim/', f'"{ROOT}/sim/')
    for name, extra, same in (("with_r", f"\n[drive_model]\nR_ohm = {f32_of(f32_bits(R_NEW))!r}\n", True),
                              ("scenario", "", False)):
        d = os.path.join(args.out, "params_native_" + name)
        os.makedirs(d, exist_ok=True)
        scen = os.path.join(d, "speed_can.toml")
        with open(scen, "w") as f:
            f.write(base + extra)
        r = subprocess.run([args.motorsim, "--scenario", scen, "--out", d, "--no-plot", "--no-expect", "--quiet"],
                           capture_output=True, text=True)
        if not check(r.returncode == 0, f"params: native run {name} (exit {r.returncode}) {r.stderr[-300:]}"):
            continue
        c2, r2 = read_csv(os.path.join(d, "speed_can.csv"))
        # every column but the reference's: on a bus it is the drive's own
        # (score_against_drive_reference), without one the scenario's
        keep = [i for h, i in sorted(cols.items(), key=lambda x: x[1]) if h != "omega_ref_rad_s"]
        equal = c2 == cols and len(r2) == len(rows) and all(
            [a[i] for i in keep] == [b[i] for i in keep] for a, b in zip(r2, rows))
        check(equal == same, f"params: the second run's CSV ({len(keep)} columns, all but the reference's) "
              f"{'equals' if equal else 'differs from'} the native run "
              + ("of the scenario with [drive_model] R_ohm = the value saved" if same else "of the scenario alone"))


CASES = [
    ("position", os.path.join(HERE, "position_can.toml"), position_commander, position_checks),
    ("speed", os.path.join(HERE, "speed_can.toml"), speed_commander, speed_checks),
    ("paper002", os.path.join(HERE, "paper002_can.toml"), paper002_commander, paper002_checks),
    ("sensored", os.path.join(ROOT, "sim", "scenarios", "sensored_benchmark.toml"), sensored_commander,
     sensored_checks),
    ("params_read", os.path.join(HERE, "speed_can.toml"), params_read_commander, params_read_checks, True),
]


def record(args, db):
    if not ensure_iface(args.iface):
        return False
    image = image_path(args)
    if os.path.exists(image):
        os.remove(image)  # a new board
    record_params_set(args, db, image)
    for name, scenario, commander, _, *flash in CASES:
        if flash:
            record_case(args, db, name, scenario, lambda d, a: commander(d, a, image), ("--flash-image", image))
        else:
            record_case(args, db, name, scenario, commander)
    return True


def check_all(args, db):
    for name, _, _, checks, *_ in CASES:
        case = load_case(args, db, name)
        if case is not None:
            checks(*case[:5])
    params_set_checks(args)
    params_native_checks(args)
    pos_log = os.path.join(args.out, "position", "position.log")
    # the DBC as it is with cantools' own command line
    r = subprocess.run([sys.executable, "-m", "cantools", "decode", DBC], stdin=open(pos_log), capture_output=True,
                       text=True)
    check(r.returncode == 0 and "Position(" in r.stdout and "ThetaRef:" in r.stdout,
          f"cantools decode reads the candump recording with tools/can/drive.dbc (exit {r.returncode}"
          + (")" if r.returncode == 0 else f": {r.stderr[-300:]})"))
    if args.plot:
        r = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "can", "drivecan.py"), "plot", pos_log,
                            "Position.Theta*", "-", "Velocity.Omega*", "-", "Currents.I1*", "Currents.I2*", "-o", args.plot], capture_output=True, text=True)
        check(r.returncode == 0 and os.path.exists(args.plot),
              f"drivecan.py plot wrote {args.plot} (exit {r.returncode}{': ' + r.stderr[-300:] if r.returncode else ''})")


def record_in_vm(args):
    """The record phase in the VM fixture; its exit status (77: no VM here)."""
    cmd = [sys.executable, os.path.join(ROOT, "tools", "vm", "vm_run.py"), "--share", ROOT, "--timeout", "480", "--",
           sys.executable, os.path.abspath(__file__), "--phase", "record", "--motorsim", os.path.abspath(args.motorsim),
           "--out", os.path.abspath(args.out), "--iface", args.iface]
    return subprocess.run(cmd, cwd=ROOT).returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--motorsim", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--iface", default="vcan0")
    ap.add_argument("--plot", help="also plot the position run's recording into this PNG (docs/can.md)")
    ap.add_argument("--phase", choices=["all", "record", "check"], default="all",
                    help="record: run the drives on the bus; check: check what was recorded; all: both")
    ap.add_argument("--vm", action="store_true",
                    help="record in the VM fixture (tools/vm/vm_run.py), then check here")
    args = ap.parse_args()
    if args.vm and args.phase != "all":
        ap.error("--vm runs both phases: leave out --phase")
    os.makedirs(args.out, exist_ok=True)
    for name, *_ in CASES + [("params_set",)]:  # nothing of an earlier run is checked again
        stale = os.path.join(args.out, name, "case.json")
        if args.phase != "check" and os.path.exists(stale):
            os.remove(stale)
    db = cantools.database.load_file(DBC)
    if args.vm:
        rc = record_in_vm(args)
        if rc == SKIP:
            return SKIP
        if rc not in (0, 1):
            print(f"vcan_e2e: the VM's record phase failed (exit {rc})", file=sys.stderr)
            return 1
    elif args.phase in ("all", "record"):
        if not record(args, db):
            return SKIP
    if args.phase in ("all", "check"):
        check_all(args, db)
    print(f"vcan_e2e ({'record' if args.phase == 'record' else 'checks'}): "
          f"{'FAILED: ' + str(len(failures)) + ' checks' if failures else 'all checks passed'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
