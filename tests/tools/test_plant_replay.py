"""sim/replay/plant_replay: the constant speed and the speed trajectory.

The speed column (v_a_V,v_b_V,v_c_V,omega_rad_s) sets the speed of each row;
a constant column gives bit for bit what --omega gives; a closed-loop run's
voltages and speed replayed give that run's currents (tools/bench/sim_speed.py
times our plant on exactly that, "the same run" as gym-electric-motor's
lines); bad combinations are refused with the option named, nothing written.

Uses PLANT_REPLAY and MOTORSIM (else build/host/sim/...).
"""
from __future__ import annotations

import csv
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PLANT_REPLAY = Path(os.environ.get("PLANT_REPLAY", ROOT / "build" / "host" / "sim" / "plant_replay"))
MOTORSIM = Path(os.environ.get("MOTORSIM", ROOT / "build" / "host" / "sim" / "motorsim"))
MOTOR = ROOT / "sim" / "motors" / "paper001_pmsm.toml"
TS = 1e-4

pytestmark = pytest.mark.skipif(not (PLANT_REPLAY.is_file() and MOTORSIM.is_file()),
                                reason="plant_replay and motorsim not built (build the host preset)")


def replay(tmp: Path, rows: list[list[float]], header: str, *extra: str) -> subprocess.CompletedProcess:
    vin = tmp / "v.csv"
    vin.write_text(header + "\n" + "".join(",".join(repr(x) for x in r) + "\n" for r in rows))
    return subprocess.run([str(PLANT_REPLAY), "--motor", str(MOTOR), "--in", str(vin), "--out", str(tmp / "i.csv"),
                           "--ts", repr(TS), *extra], capture_output=True, text=True)


def volts(n: int) -> list[list[float]]:
    # a rotating 20 V vector at 60 rad/s electrical, as leg voltages
    import math
    return [[20 * math.cos(60 * k * TS + 2 * math.pi * j / 3) for j in (0, -1, 1)] for k in range(n)]


def test_constant_speed_column_is_bit_exact_with_omega(tmp_path):
    v = volts(2000)
    r = replay(tmp_path, v, "v_a_V,v_b_V,v_c_V", "--omega", "12.5")
    assert r.returncode == 0, r.stderr
    a = (tmp_path / "i.csv").read_text()
    r = replay(tmp_path, [x + [12.5] for x in v], "v_a_V,v_b_V,v_c_V,omega_rad_s")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "i.csv").read_text() == a


@pytest.mark.parametrize("header,extra,msg", [
    ("v_a_V,v_b_V,v_c_V,omega_rad_s", ("--omega", "1"), "--omega: "),
    ("v_a_V,v_b_V,v_c_V", (), "--omega: required"),
    ("v_a_V,v_b_V,v_c_V,w", ("--omega", "1"), "header must be"),
])
def test_bad_speed_input_is_refused(tmp_path, header, extra, msg):
    rows = [x + [1.0] for x in volts(10)] if header.count(",") == 3 else volts(10)
    r = replay(tmp_path, rows, header, *extra)
    assert r.returncode == 2
    assert msg in r.stderr and r.stderr.count("\n") == 1, r.stderr
    assert not (tmp_path / "i.csv").exists()


def test_closed_loop_run_replayed_gives_its_currents(tmp_path):
    # paper 001's benchmark for 1.5 s (start, ramp, the 1 N m step at 1 s)
    sc = (ROOT / "sim" / "scenarios" / "paper001_benchmark.toml").read_text()
    sc = sc.replace('file = "../motors/', f'file = "{ROOT}/sim/motors/').replace("duration_s = 10.0", "duration_s = 1.5")
    assert "duration_s = 1.5" in sc
    (tmp_path / "b.toml").write_text(sc)
    r = subprocess.run([str(MOTORSIM), "--scenario", str(tmp_path / "b.toml"), "--out", str(tmp_path / "o"),
                        "--no-plot", "--quiet", "--no-expect"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "o" / "b.csv", newline="") as f:
        run = list(csv.DictReader(f))
    # the speed over row k: the mean of the run's speeds at its two ends
    w = [float(x["omega_rad_s"]) for x in run]
    w_mid = [0.5 * (w[k] + w[min(k + 1, len(w) - 1)]) for k in range(len(w))]
    rows = [[float(x["v_a_V"]), float(x["v_b_V"]), float(x["v_c_V"]), w_mid[k]] for k, x in enumerate(run)]
    assert "theta0_rad = 0.0" in sc  # the plant starts at electrical angle 0, as the replay does
    r = replay(tmp_path, rows, "v_a_V,v_b_V,v_c_V,omega_rad_s")
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "i.csv", newline="") as f:
        got = list(csv.DictReader(f))
    assert len(got) == len(run)
    worst = max(abs(float(g[c + "_A"]) - float(x[c + "_A"])) for g, x in zip(got, run) for c in ("i_a", "i_b", "i_c"))
    # the speed held over each sample at its mean instead of integrated, and
    # the CSV's 10 digits (measured 1e-5 A)
    assert worst < 1e-4, worst
    # and not trivially: the currents are amperes
    assert max(abs(float(x["i_a_A"])) for x in run) > 1.0
