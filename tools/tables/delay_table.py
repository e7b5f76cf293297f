#!/usr/bin/env python3
"""The drives against a computation delay (issue 10): each shipped scenario
run with `--compute-delay-samples` 0, 0.5 and 1 (the voltage computed from
the currents of t_k acts from t_k + d Ts; hal_sw_plant.h), and whether it
still meets its own [expect] thresholds.

    python3 tools/tables/delay_table.py [--build build/host]

Standard library only; about a second.
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SC = ROOT / "sim" / "scenarios"
CASES = [("paper000_ideal", ["theta_track_max_rad", "theta_est_max_rad", "current_obs_max_a"]),
         ("paper000_experiment", ["theta_track_max_rad", "theta_est_max_rad", "current_obs_max_a"]),
         ("paper001_benchmark", ["speed_err_settled_max_rpm", "speed_err_rms_rpm", "theta_est_max_deg_e"])]
DELAYS = (0.0, 0.5, 1.0)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host"))
    a = ap.parse_args()
    try:
        ms = motorsim.find(build=a.build)
    except motorsim.MotorsimError as e:
        print(f"delay_table: {e}", file=sys.stderr)
        return 2
    print("| scenario | delay (samples) | metrics | its [expect] |")
    print("| --- | --- | --- | --- |")
    for name, keys in CASES:
        for d in DELAYS:
            try:
                r = motorsim.run(ms, SC / f"{name}.toml", compute_delay_samples=d, ok=motorsim.RESULTS)
            except motorsim.MotorsimError as e:
                print(f"delay_table: {e}", file=sys.stderr)
                return 1
            m = r.metrics
            missed = sorted(set(re.findall(r"expect\.([a-z_0-9]+):", r.stderr)))
            verdict = "met" if r.status == 0 else (
                "missed: " + ", ".join(f"`{k}`" for k in missed) if missed else f"exit {r.status}")
            vals = ", ".join(f"{k} {m[k]:.3g}" for k in keys)
            print(f"| {name} | {d:g} | {vals} | {verdict} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
