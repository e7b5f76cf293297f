"""The CAN message set as a contract (issue 11): the firmware's codec
(firmware/comm/can_link.c over the cantools-generated
firmware/comm/generated/drive_can.{h,c}) against cantools reading
tools/can/drive.dbc, both ways, at zero, small, negative, range-edge and
out-of-range values; malformed command frames refused; the generated C
current with the DBC. Needs the can_vectors binary (CAN_VECTORS env)."""
import os
import pathlib
import subprocess
import sys

import cantools
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DBC = ROOT / "tools" / "can" / "drive.dbc"
sys.path.insert(0, str(ROOT / "tools" / "can"))
from drivecan import dbc_msg_set_version, project_version  # noqa: E402
GEN = ROOT / "firmware" / "comm" / "generated"
NODE = 3  # can_vectors packs and parses for node 3


def vectors_bin():
    b = os.environ.get("CAN_VECTORS")
    if not b or not os.path.exists(b):
        pytest.skip("CAN_VECTORS (the can_vectors binary) not given")
    return b


def telemetry_frames():
    out = subprocess.run([vectors_bin(), "tlm"], check=True, capture_output=True, text=True).stdout
    for line in out.splitlines():
        name, value, fid, dlc, data = line.split()
        yield name, float(value), int(fid), int(dlc), bytes.fromhex(data)


# the integer test values can_vectors sets, and the constants the firmware
# sends (its version, its numeric type, the message set's version)
FW = project_version()
INTS = {"DriveKind": 1, "Mode": 2, "State": 4, "Enabled": 1, "MsgSetVersion": dbc_msg_set_version(),
        "FaultCode": 5, "FaultEvents": 7, "RejectedCommands": 9, "Counter": 65535, "Saturated": 1,
        "Overruns": 1234, "Relocks": 3, "FirstFault": 11, "ExcessSteps": 4321, "ConfigSource": 4, "ParamsRefused": 1, "FwMajor": FW[0], "FwMinor": FW[1], "FwPatch": FW[2],
        "FixedPoint": int(os.environ.get("CAN_VECTORS_FIXED", "0"))}


def check_telemetry(db):
    """Every telemetry frame the C packed, decoded by cantools with db: the
    SI value the firmware was given, quantised to the signal's factor and
    saturated to its range. Returns the list of mismatches."""
    bad = []
    for name, v, fid, dlc, data in telemetry_frames():
        msg = db.get_message_by_name(name)
        if fid != msg.frame_id + NODE or dlc != msg.length:
            bad.append(f"{name}: id {fid:#x} dlc {dlc}, DBC {msg.frame_id + NODE:#x} {msg.length}")
            continue
        dec = db.decode_message(msg.frame_id, data, decode_choices=False, scaling=True)
        for sig in msg.signals:
            got = dec[sig.name]
            if sig.name in INTS:
                want = INTS[sig.name]
                ok = got == want
            else:
                lo, hi = sig.minimum, sig.maximum
                want = min(max(v, lo), hi)
                # one step of the signal, plus the Q14.17 LSB of the input
                ok = abs(got - want) <= sig.scale * 0.5 + 1e-5 * max(1.0, abs(v)) * 1e-3 + 8e-6 * sig.scale / sig.scale
            if not ok:
                bad.append(f"{name}.{sig.name} at {v}: decoded {got}, want {want}")
    return bad


def test_telemetry_c_to_cantools():
    db = cantools.database.load_file(str(DBC))
    bad = check_telemetry(db)
    assert not bad, "\n".join(bad[:20])


def test_a_changed_factor_is_caught(tmp_path):
    """Change ThetaRef's factor in a copy of the DBC: the same C no longer
    agrees with it, and the check says so."""
    text = DBC.read_text()
    changed = text.replace("SG_ ThetaRef : 0|32@1- (1e-05,0)", "SG_ ThetaRef : 0|32@1- (2e-05,0)")
    assert changed != text
    p = tmp_path / "changed.dbc"
    p.write_text(changed)
    bad = check_telemetry(cantools.database.load_file(str(p)))
    assert any("Position.ThetaRef" in b for b in bad), bad[:5]
    assert not any("ThetaEst" in b for b in bad)


def parse(lines):
    out = subprocess.run([vectors_bin(), "cmd"], input="".join(lines), check=True, capture_output=True,
                         text=True).stdout
    return out.splitlines()


def frame_line(fid, data):
    return f"{fid} {len(data)} {data.hex()}\n"


KINDS = {"CmdEnable": 1, "CmdMove": 2, "CmdSpeed": 3, "CmdStop": 4, "CmdSetOmegaLim": 5, "CmdClearFaults": 6,
         "CmdSetRate": 7}
# can_vectors' "ok" fields after the kind, in order, and the signal each holds
FIELDS = {"ThetaTo": 0, "Duration": 1, "OmegaRef": 2, "Ramp": 3, "OmegaLim": 4, "Enable": 5, "Message": 6,
          "Period": 7}


def command_cases(db):
    """Valid commands at their range edges, zero, negative, typical."""
    cases = []
    for msg in db.messages:
        if not msg.name.startswith("Cmd"):
            continue
        sigs = [s for s in msg.signals if s.name != "Reserved"]
        if not sigs:
            cases.append((msg, {"Reserved": 0}))
            continue
        picks = []
        for s in sigs:
            lo = s.minimum if s.minimum is not None else 0
            hi = s.maximum
            mids = [lo, hi, (lo + hi) / 2]
            if lo < 0 < hi:
                mids += [0.0, -1.2345 if lo < -1.3 else lo / 2]
            picks.append(mids)
        for k in range(max(len(p) for p in picks)):
            cases.append((msg, {s.name: p[min(k, len(p) - 1)] for s, p in zip(sigs, picks)}))
    return cases


def test_commands_cantools_to_c():
    db = cantools.database.load_file(str(DBC))
    cases = command_cases(db)
    lines = [frame_line(m.frame_id + NODE, m.encode(vals, strict=True)) for m, vals in cases]
    results = parse(lines)
    assert len(results) == len(cases)
    for (m, vals), res in zip(cases, results):
        f = res.split()
        if m.name == "CmdMove" and abs(vals["ThetaTo"]) > 16383.99 and f[0] == "reject":
            # beyond what the fixed-point firmware holds (Q14.17: +-16384):
            # refused as out of range, not saturated
            assert res == "reject 4", res
            continue
        assert f[0] == "ok", f"{m.name} {vals}: {res}"
        assert int(f[1]) == KINDS[m.name], res
        for name, v in vals.items():
            if name == "Reserved":
                continue
            sig = m.get_signal_by_name(name)
            got = float(f[2 + FIELDS[name]])
            # what went on the wire is v quantised to the factor
            wire = round(v / sig.scale) * sig.scale
            assert abs(got - wire) <= max(sig.scale * 1e-3, 8e-6 * max(1.0, abs(wire)) * 2), \
                f"{m.name}.{name} = {v}: C read {got}"


def raw_frame(msg, raws):
    """A frame with signals set to raw integers (cantools scaling=False, no
    range check): how out-of-range values reach the bus."""
    return msg.encode(raws, scaling=False, strict=False)


def test_malformed_commands_are_refused():
    db = cantools.database.load_file(str(DBC))
    move = db.get_message_by_name("CmdMove")
    rate = db.get_message_by_name("CmdSetRate")
    n_tlm = len(rate.get_signal_by_name("Message").choices)  # one past the last telemetry message
    lim = db.get_message_by_name("CmdSetOmegaLim")
    good = move.encode({"ThetaTo": 1.0, "Duration": 2.0})
    cases = [
        (frame_line(move.frame_id + NODE, good[:-1]), "reject 3"),                   # DLC 5
        (frame_line(move.frame_id + NODE, good + b"\x00"), "reject 3"),              # DLC 7
        (f"{move.frame_id + NODE} 9 {good.hex()}\n", "reject 3"),                     # DLC 9
        (frame_line(move.frame_id + NODE, raw_frame(move, {"ThetaTo": 0, "Duration": 0})), "reject 4"),
        (frame_line(rate.frame_id + NODE, raw_frame(rate, {"Message": n_tlm, "Period": 10})), "reject 4"),
        (frame_line(rate.frame_id + NODE, raw_frame(rate, {"Message": 1, "Period": 60001})), "reject 4"),
        (frame_line(lim.frame_id + NODE, raw_frame(lim, {"OmegaLim": 0})), "reject 4"),
        (frame_line(db.get_message_by_name("CmdStop").frame_id + NODE, b"\x01"), "reject 4"),
        (frame_line(db.get_message_by_name("CmdEnable").frame_id + NODE, b"\x03"), "reject 4"),
        (frame_line(0x270 + NODE, b"\x00"), "reject 2"),                             # no such command
        (frame_line(move.frame_id + NODE + 1, good), "reject 1"),                    # another node
        (frame_line(0x110 + NODE, bytes(8)), "reject 1"),                            # a telemetry id
        (frame_line(0x7FF, bytes(8)), "reject 1"),
        (frame_line(move.frame_id + NODE, good), "ok 2 1 2 0 0 0 0 0 0"),            # and the good one
    ]
    got = parse([c for c, _ in cases])
    for (line, want), res in zip(cases, got):
        assert res == want, f"{line.strip()}: {res}, want {want}"


def test_generated_c_is_current():
    """firmware/comm/generated/ is what tools/can/gen_c.py generates from the
    DBC now: edit the DBC, run the script."""
    r = subprocess.run([os.sys.executable, str(ROOT / "tools" / "can" / "gen_c.py"), "--check"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
