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
