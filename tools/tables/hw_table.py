#!/usr/bin/env python3
"""The hardware-like scenarios with and without the drives' dead-time
compensation (issue 30): the table of docs/plant.md.

Runs every sim/scenarios/*_hw.toml twice, as shipped (the drive's
compensation from [inverter], firmware/control/deadtime_comp.h) and with
[inverter] compensation = false (the same inverter, the drive not told),
each judged against the file's [expect], and prints one markdown row per
run: the outcome (pass, the [expect] metrics missed, the fault, or the run
refused before it started with motorsim's reason) and the drive's key
metrics.

    python3 tools/tables/hw_table.py [--build build/host]

Standard library only; about 1 s.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SC = ROOT / "sim" / "scenarios"
# the key metrics of each drive's runs (the first present set is used)
KEYS = [
    [("speed_err_settled_max_rpm", "%.3f"), ("speed_err_rms_rpm", "%.2f"), ("speed_err_max_rpm", "%.1f"),
     ("theta_est_max_deg_e", "%.2f"), ("load_est_err_settled_nm", "%.4f"), ("max_abs_current_A", "%.2f")],
    [("speed_rmse_rad_s", "%.4f"), ("speed_err_max_rad_s", "%.3f"), ("theta_est_rmse_rad", "%.2e"),
     ("voltage_hf_rms_V", "%.3f"), ("max_abs_current_A", "%.2f")],
    [("theta_track_max_rad", "%.4f"), ("theta_est_max_rad", "%.4f"), ("omega_est_peak_max_rad_s", "%.3f"),
     ("final_theta_err_rad", "%.2e"), ("closed_loop_fraction", "%.3f")],
]


def without_compensation(text: str) -> str:
    if "[inverter]\n" not in text:
        raise SystemExit("hw_table: a *_hw.toml without an [inverter] table")
    return text.replace("[inverter]\n", "[inverter]\ncompensation = false\n", 1)


def outcome(r: motorsim.Run) -> str:
    if r.status == motorsim.OK:
        return "pass"
    if r.status == motorsim.EXPECT_MISSED:
        missed = [ln.split("expect.")[1].split(":")[0] for ln in r.stderr.splitlines() if "expect." in ln]
        return "missed " + ", ".join(missed)
    if r.status == motorsim.FAULT:
        fault = [ln for ln in r.stderr.splitlines() if "drive fault" in ln]
        return fault[0].split("FAILED: ")[-1].split(";")[0].split(":")[0] if fault else "fault"
    last = r.stderr.strip().splitlines()[-1] if r.stderr.strip() else "no message"
    return "refused: " + last.split(": ", 2)[-1]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(motorsim.DEFAULT_BUILD))
    a = ap.parse_args()
    ms = motorsim.find(build=a.build)
    files = sorted(SC.glob("*_hw.toml"))
    if not files:
        raise SystemExit("hw_table: no sim/scenarios/*_hw.toml")
    for f in files:
        text = f.read_text(encoding="utf-8")
        runs = [("on", motorsim.run(ms, f, ok=None)),
                ("off", motorsim.run(ms, text=without_compensation(text), name=f.stem, text_dir=SC, ok=None))]
        m0 = runs[0][1].metrics or {}
        keys = next((ks for ks in KEYS if ks[0][0] in m0), KEYS[0])
        print(f"`{f.name}`\n")
        print("| compensation | outcome | " + " | ".join(f"`{k}`" for k, _ in keys) + " |")
        print("|---|---|" + "---|" * len(keys))
        for label, r in runs:
            m = r.metrics or {}
            cells = ["—" if m.get(k) is None else fmt % m[k] for k, fmt in keys]
            print(f"| {label} | {outcome(r)} | " + " | ".join(cells) + " |")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
