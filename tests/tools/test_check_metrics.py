"""tests/sim/check_metrics.py: thresholds, report-only keys, the baseline ratchet."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tests" / "sim" / "check_metrics.py"


def run(tmp: Path, metrics: dict, *checks: str, base: dict | None = None) -> int:
    mp = tmp / "m.json"
    mp.write_text(json.dumps(metrics).replace("Infinity", "NaN"))
    args = [sys.executable, str(SCRIPT), str(mp)]
    if base is not None:
        bp = tmp / "b.json"
        bp.write_text(json.dumps(base))
        args += ["--baseline", str(bp), "--entry", "e"]
    return subprocess.run([*args, *checks], capture_output=True, text=True).returncode


def test_thresholds(tmp_path: Path) -> None:
    assert run(tmp_path, {"a": 0.5}, "a<1") == 0
    assert run(tmp_path, {"a": 1.5}, "a<1") == 1
    assert run(tmp_path, {"a": 0.5}, "a>0.6") == 1


def test_report_only_key_must_exist_and_be_finite(tmp_path: Path) -> None:
    assert run(tmp_path, {"a": 0.5}, "a") == 0
    assert run(tmp_path, {"a": 0.5}, "b") == 1
    assert run(tmp_path, {"a": float("inf")}, "a") == 1  # written as NaN
    assert run(tmp_path, {"a": None}, "a") == 1
    assert run(tmp_path, {"a": True}, "a") == 1


BASE = {"margins": {"err": {"worse": "max", "rel": 0.1, "abs": 0.0},
                    "frac": {"worse": "min", "rel": 0.0, "abs": 0.01}},
        "entries": {"e": {"err": 1.0, "frac": 0.64}}}


def test_ratchet(tmp_path: Path) -> None:
    assert run(tmp_path, {"err": 1.09, "frac": 0.635}, base=BASE) == 0
    assert run(tmp_path, {"err": 0.5, "frac": 0.9}, base=BASE) == 0  # better is fine
    assert run(tmp_path, {"err": 1.11, "frac": 0.64}, base=BASE) == 1
    assert run(tmp_path, {"err": 1.0, "frac": 0.62}, base=BASE) == 1
    assert run(tmp_path, {"frac": 0.64}, base=BASE) == 1  # key gone
    no_entry = dict(BASE, entries={})
    assert run(tmp_path, {"err": 1.0, "frac": 0.64}, base=no_entry) == 1
