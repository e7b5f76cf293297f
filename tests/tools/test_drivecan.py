"""tools/can/drivecan.py on python-can's virtual bus (no kernel CAN here):
send, record (candump -L log and CSV), decode, monitor, plot, and the
refusals of bad input."""
import argparse
import csv
import importlib.util
import pathlib
import subprocess
import sys
import threading
import time

import can
import cantools
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("drivecan", ROOT / "tools" / "can" / "drivecan.py")
dc = importlib.util.module_from_spec(spec)
spec.loader.exec_module(dc)
DB = cantools.database.load_file(str(ROOT / "tools" / "can" / "drive.dbc"))


def ns(**kw):
    base = dict(dbc=dc.DBC, channel="t", interface="virtual", node=None, duration=0.0, count=0, csv=None)
    base.update(kw)
    return argparse.Namespace(**base)


def telemetry(node, k):
    vel = DB.get_message_by_name("Velocity")
    pos = DB.get_message_by_name("Position")
    return [
        can.Message(arbitration_id=vel.frame_id + node, is_extended_id=False, timestamp=0.01 * k,
                    data=vel.encode({"OmegaRef": 1.5 * k, "OmegaEst": -2.25, "AccelEst": 100, "LoadEst": 0.0752})),
        can.Message(arbitration_id=pos.frame_id + node, is_extended_id=False, timestamp=0.01 * k,
                    data=pos.encode({"ThetaRef": 0.001 * k, "ThetaEst": -18.0})),
    ]


def test_send_encodes_by_name_and_refuses_bad_input():
    rx = can.Bus(interface="virtual", channel="send")
    tx = can.Bus(interface="virtual", channel="send")
    dc.send(ns(channel="send", node=3, message="CmdSpeed", values=["OmegaRef=10", "Ramp=50"]), bus=tx, db=DB)
    msg = rx.recv(timeout=1.0)
    assert msg.arbitration_id == 0x223
    assert DB.decode_message(0x220, msg.data) == {"OmegaRef": 10.0, "Ramp": 50.0}
    for bad, why in [(["OmegaRef=1000", "Ramp=50"], "OmegaRef"),       # beyond the DBC's range
                     (["Omega=10"], "no signal 'Omega'"),
                     (["OmegaRef=ten"], "not a number"),
                     (["OmegaRef"], "SIGNAL=VALUE")]:
        with pytest.raises(SystemExit) as e:
            dc.send(ns(channel="send", node=3, message="CmdSpeed", values=bad), bus=tx, db=DB)
        assert why in str(e.value), str(e.value)
    with pytest.raises(SystemExit, match="no message 'CmdFly'"):
        dc.send(ns(channel="send", node=0, message="CmdFly", values=[]), bus=tx, db=DB)
    with pytest.raises(SystemExit, match="--node 16"):
        dc.send(ns(channel="send", node=16, message="CmdStop", values=[]), bus=tx, db=DB)
    assert rx.recv(timeout=0.1) is None  # nothing was sent for the refused ones
    rx.shutdown()
    tx.shutdown()


def test_record_decode_and_monitor(tmp_path):
    rx = can.Bus(interface="virtual", channel="rec")
    tx = can.Bus(interface="virtual", channel="rec")
    frames = [m for k in range(20) for m in telemetry(2, k)]
    frames.append(can.Message(arbitration_id=0x7A0, data=b"\x00", is_extended_id=False))      # unknown id
    frames.append(can.Message(arbitration_id=0x122, data=b"\x00\x01", is_extended_id=False))  # short Velocity

    def sender():
        time.sleep(0.05)
        for m in frames:
            tx.send(m)

    th = threading.Thread(target=sender)
    th.start()
    log, out = tmp_path / "run.log", tmp_path / "run.csv"
    got = dc.record(ns(channel="rec", log=str(log), csv=str(out), count=len(frames)), bus=rx, db=DB)
    th.join()
    assert len(got) == len(frames)
    # the log is candump -L format, which python-can and cantools both read
    lines = log.read_text().splitlines()
    assert len(lines) == len(frames) and lines[0].startswith("(") and " rec 122#" in lines[0]
    rows = list(csv.DictReader(open(out)))
    omega = [float(r["value"]) for r in rows if r["message"] == "Velocity" and r["signal"] == "OmegaRef"]
    assert omega == pytest.approx([1.5 * k for k in range(20)])
    assert all(r["node"] == "2" for r in rows)
    # decode the log again (as for a log written by candump -L)
    out2 = tmp_path / "again.csv"
    assert dc.decode_log(ns(log=str(log), csv=str(out2))) == 0
    assert list(csv.DictReader(open(out2))) == rows
    # monitor: rates and the two frames that did not decode
    st = dc.Stats()
    for m in got:
        st.add(DB, m)
    assert st.count[(2, "Velocity")] == 20 and st.count[(2, "Position")] == 20
    assert st.errors["unknown id"] == 1 and st.errors["wrong length"] == 1
    table = st.table()
    assert "Velocity" in table and "unknown id: 1" in table and "wrong length: 1" in table
    rx.shutdown()
    tx.shutdown()


def test_plot_from_a_log(tmp_path):
    """A log in candump -L format plotted through cantools plot."""
    log = tmp_path / "run.log"
    with can.CanutilsLogWriter(str(log), channel="vcan0") as w:
        for k in range(50):
            for m in telemetry(1, k):
                w.on_message_received(m)
    png = tmp_path / "run.png"
    r = subprocess.run([sys.executable, str(ROOT / "tools" / "can" / "drivecan.py"), "plot", str(log),
                        "Velocity.Omega*", "-o", str(png)], capture_output=True, text=True,
                       env={"MPLBACKEND": "Agg", "PATH": "/usr/bin:/bin"})
    assert r.returncode == 0, r.stderr
    assert png.exists() and png.stat().st_size > 5000


def test_plot_live_from_the_bus(tmp_path):
    """plot --channel: S seconds of the bus recorded next to the PNG, then plotted."""
    rx = can.Bus(interface="virtual", channel="live")
    tx = can.Bus(interface="virtual", channel="live")
    stop = threading.Event()

    def sender():
        k = 0
        while not stop.is_set():
            for m in telemetry(2, k % 200):
                tx.send(m)
            k += 1
            time.sleep(0.002)

    th = threading.Thread(target=sender)
    th.start()
    png = tmp_path / "live.png"
    try:
        args = argparse.Namespace(
            dbc=dc.DBC, items=["Velocity.Omega*"], output=str(png), channel="live", interface="virtual",
            duration=0.5)
        rc = dc.plot(args, bus=rx)
    finally:
        stop.set()
        th.join()
        rx.shutdown()
        tx.shutdown()
    assert rc == 0
    assert png.exists() and png.stat().st_size > 5000
    log = tmp_path / "live.log"
    assert log.exists() and sum(1 for _ in can.CanutilsLogReader(str(log))) > 50


# ---- param and config: against a node on the virtual bus that keeps
# paper 001's parameters by id as the firmware's service does (values, the
# read-only rule, a list walk, save and defaults counted); the C service
# itself is tested by firmware.ParamService.* and over SocketCAN by
# tools.vcan_e2e.
class MockParamNode(threading.Thread):
    def __init__(self, channel, node=2, drive_kind=1):
        super().__init__(daemon=True)
        self.bus = can.Bus(interface="virtual", channel=channel)
        self.node, self.kind = node, drive_kind
        by_id, _ = dc.param_tables("paper001")
        self.params = by_id
        self.values = {pid: self.default_bits(p) for pid, p in by_id.items()}
        self.writes, self.saves, self.stop = [], 0, False

    @staticmethod
    def default_bits(p):
        return dc.value_to_bits(p, str(p["default"]).lower() if isinstance(p["default"], bool) else str(p["default"]))

    def run(self):
        req, rep, hb = (DB.get_message_by_name(n) for n in ("ParamRequest", "ParamReply", "Heartbeat"))
        next_hb = 0.0
        while not self.stop:
            if time.monotonic() >= next_hb:
                data = hb.encode({s.name: 0 for s in hb.signals} | {"DriveKind": self.kind, "MsgSetVersion": 5})
                self.bus.send(can.Message(arbitration_id=hb.frame_id + self.node, data=data, is_extended_id=False))
                next_hb = time.monotonic() + 0.05
            m = self.bus.recv(timeout=0.01)
            if m is None or m.arbitration_id != req.frame_id + self.node:
                continue
            r = req.decode(bytes(m.data), decode_choices=False)
            op, pid, bits = int(r["Op"]), int(r["ParamId"]), int(r["Value"]) & 0xFFFFFFFF
            status, out_id, out = 0, pid, 0
            if op in (0, 1) and pid not in self.values:
                status = 1
            elif op == 0:
                out = self.values[pid]
            elif op == 1:
                if self.params[pid]["access"] == "ro":
                    status = 2
                else:
                    self.values[pid] = bits
                    self.writes.append(pid)
                    out = bits
            elif op == 2:
                self.saves += 1
            elif op == 3:
                self.values = {i: self.default_bits(p) for i, p in self.params.items()}
            elif op == 4:
                later = sorted(i for i in self.values if i >= pid)
                status, out_id = (0, later[0]) if later else (1, 0xFFFF)
                out = self.values[later[0]] if later else 0
            else:
                status = 8
            v = out - (1 << 32) if out & 0x80000000 else out
            data = rep.encode({"Op": op, "Status": status, "Seq": int(r["Seq"]), "ParamId": out_id, "Value": v})
            self.bus.send(can.Message(arbitration_id=rep.frame_id + self.node, data=data, is_extended_id=False))


def pns(channel, **kw):
    base = dict(dbc=dc.DBC, channel=channel, interface="virtual", node=2, drive=None, timeout=0.5, cmd="param",
                args=[], save=False)
    base.update(kw)
    return argparse.Namespace(**base)


def test_param_and_config_against_a_node(tmp_path, capsys):
    node = MockParamNode("params")
    node.start()
    bus = can.Bus(interface="virtual", channel="params")
    try:
        # the drive found from the heartbeat; every parameter listed with its value
        assert dc.param_cmd(pns("params", action="list"), bus=bus, db=DB) == 0
        out = capsys.readouterr().out
        assert "R_ohm" in out and "0.225" in out and "estimator" in out and "flux" in out
        assert len(out.strip().splitlines()) == len(node.params)
        # set by name: checked first, then written; get reads it back
        assert dc.param_cmd(pns("params", action="set", args=["R_ohm", "0.3"]), bus=bus, db=DB) == 0
        rid = next(i for i, p in node.params.items() if p["name"] == "R_ohm")
        assert node.writes == [rid]
        assert dc.param_cmd(pns("params", action="get", args=["R_ohm"]), bus=bus, db=DB) == 0
        assert "R_ohm = 0.3 ohm" in capsys.readouterr().out
        # refusals named, nothing sent for a value the tool refuses
        for args, why in ((["R_ohm", "1e9"], "outside"), (["estimator", "magic"], "not one of"),
                          (["nothing", "1"], "no parameter 'nothing'"), (["ts_s", "1e-4"], "refused: read_only")):
            assert dc.param_cmd(pns("params", action="set", args=args), bus=bus, db=DB) == 1
            assert why in capsys.readouterr().err
        assert node.writes == [rid]
        # export, edit two values, import: only those written, then saved
        f = tmp_path / "m.toml"
        assert dc.param_cmd(pns("params", cmd="config", action="export", file=str(f)), bus=bus, db=DB) == 0
        text = f.read_text()
        assert 'drive = "paper001"' in text and "R_ohm = 0.3" in text
        text = text.replace("R_ohm = 0.3 ", "R_ohm = 0.25 ").replace('estimator = "flux"',
                                                                             'estimator = "back_emf"')
        f.write_text(text)
        node.writes.clear()
        assert dc.param_cmd(pns("params", cmd="config", action="import", file=str(f), save=True),
                            bus=bus, db=DB) == 0
        cap = capsys.readouterr()
        assert "R_ohm: 0.3 -> 0.25 ohm" in cap.out and "estimator: flux -> back_emf" in cap.out
        assert "2 of" in cap.err and "saved" in cap.err
        assert len(node.writes) == 2 and node.saves == 1
        # a file of another drive or with an unknown name is refused before any write
        node.writes.clear()
        f.write_text('drive = "paper001"\n[params]\nR_ohm = 0.2\nwarp_factor = 9\n')
        assert dc.param_cmd(pns("params", cmd="config", action="import", file=str(f)), bus=bus, db=DB) == 1
        assert "params.warp_factor: not a parameter" in capsys.readouterr().err
        assert node.writes == []
        # no node: a timeout, said
        assert dc.param_cmd(pns("params", node=9, drive="paper001", action="get", args=["R_ohm"], timeout=0.05),
                            bus=bus, db=DB) == 1
        assert "no ParamReply" in capsys.readouterr().err
    finally:
        node.stop = True
        node.join(2)
        bus.shutdown()
        node.bus.shutdown()
