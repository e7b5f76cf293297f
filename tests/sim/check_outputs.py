#!/usr/bin/env python3
"""End-to-end output contract of motorsim on a short scenario.

usage: check_outputs.py MOTORSIM SCENARIO WORKDIR

Checks: exit 0; stdout is `key value` lines matching the metrics JSON (a
flat object); the CSV has the documented columns in order and one row per sample;
the PNG exists (needs the venv's matplotlib); no temporary files are left;
with a missing python the run still succeeds, warns, and writes no PNG.
Metrics only (--metrics-out without --out): exactly one file written, no
./out, the same metrics as the full run of the same seed (but the wall time
and realtime factor). --no-csv: the metrics JSON alone in DIR.
Standard library only.
"""
from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

# the position scoring's columns (sim/motorsim/position_recorder.h), then
# paper 000's signals (firmware/drives/paper000/paper000_ops.c), in order
COLUMNS = ["t_s", "mode", "theta_ref_rad", "omega_ref_rad_s", "accel_ref_rad_s2", "theta_rad", "theta_est_rad",
           "omega_rad_s", "omega_est_rad_s", "accel_rad_s2", "accel_est_rad_s2", "load_Nm", "load_est_Nm", "i_a_A",
           "i_b_A", "i_a_meas_A", "i_b_meas_A", "i_f_A", "i_g_A", "e_f_V", "e_g_V", "v_a_V", "v_b_V",
           "delta_theta_rad", "fault",
           "i_f_meas_A", "i_g_meas_A", "i_f_ref_A", "i_g_ref_A", "i_f_est_A", "i_g_est_A", "e_f_est_V", "e_g_est_V",
           "v_f_V", "v_g_V", "delta_theta_est_rad", "jump_count", "model_R_ohm", "model_L_H", "model_K_V_s",
           "rl_id_state", "k_id_state", "relocks"]
METRICS = ["theta_track_max_rad", "theta_est_max_rad", "current_obs_max_a", "omega_est_peak_max_rad_s",
           "final_theta_err_rad", "closed_loop_fraction", "realtime_factor", "n_samples", "seed",
           "wall_time_s", "max_abs_current_A", "max_abs_voltage_V"]


def main() -> int:
    motorsim, scenario, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    shutil.rmtree(work, ignore_errors=True)
    stem = scenario.stem
    errors: list[str] = []

    out = work / "with_plot"
    r = subprocess.run([motorsim, "--scenario", str(scenario), "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        print(r.stderr, file=sys.stderr)
        return 1
    metrics = json.loads((out / f"{stem}_metrics.json").read_text())
    for k in METRICS:
        if k not in metrics:
            errors.append(f"metrics JSON lacks {k}")
    if any(isinstance(v, (dict, list)) for v in metrics.values()):
        errors.append("metrics JSON is not flat")
    printed = dict(line.split(" ", 1) for line in r.stdout.strip().splitlines())
    if set(printed) != set(metrics):
        errors.append(f"stdout keys differ from JSON keys: {set(printed) ^ set(metrics)}")
    with (out / f"{stem}.csv").open() as f:
        rows = list(csv.reader(f))
    header = rows[0]
    if header != COLUMNS:
        errors.append(f"CSV columns {header}, want {COLUMNS}")
    if len(rows) - 1 != metrics.get("n_samples"):
        errors.append(f"CSV has {len(rows) - 1} rows, n_samples = {metrics.get('n_samples')}")
    if any(len(row) != len(header) for row in rows):
        errors.append("CSV rows of unequal length")
    png = out / f"{stem}.png"
    if not png.is_file() or png.read_bytes()[:4] != b"\x89PNG":
        errors.append(f"no PNG at {png} (stderr: {r.stderr.strip()})")
    leftovers = [p.name for p in out.iterdir() if p.name.startswith(".")]
    if leftovers:
        errors.append(f"temporary files left: {leftovers}")

    # No usable python: still a successful run, with a warning and no PNG.
    out2 = work / "no_python"
    env = dict(os.environ, MC_PYTHON=str(work / "no" / "python"))
    r2 = subprocess.run([motorsim, "--scenario", str(scenario), "--out", str(out2), "--quiet"],
                        capture_output=True, text=True, timeout=120, env=env)
    if r2.returncode != 0:
        errors.append(f"run without python failed: {r2.stderr.strip()}")
    if "warning: plot skipped" not in r2.stderr:
        errors.append(f"no plot warning without python (stderr: {r2.stderr.strip()!r})")
    if (out2 / f"{stem}.png").exists():
        errors.append("PNG written without python")
    if r2.stdout:
        errors.append("--quiet printed to stdout")

    # --metrics-out elsewhere, --seed reflected in the metrics.
    mjson = work / "elsewhere" / "m.json"
    r3 = subprocess.run([motorsim, "--scenario", str(scenario), "--out", str(work / "m"), "--no-plot",
                         "--quiet", "--metrics-out", str(mjson), "--seed", "17"],
                        capture_output=True, text=True, timeout=120)
    if r3.returncode != 0 or not mjson.is_file() or json.loads(mjson.read_text()).get("seed") != 17:
        errors.append(f"--metrics-out/--seed not honoured: {r3.stderr.strip()}")
    if (work / "m" / f"{stem}_metrics.json").exists():
        errors.append("metrics JSON also written to the default place")

    # Metrics only: exactly one file, nothing in the current directory, the
    # metrics of the full runs above (same seeds) but for the timing ones.
    timing = {"wall_time_s", "realtime_factor"}
    full_default = metrics
    full_17 = json.loads(mjson.read_text()) if mjson.is_file() else {}
    for seed, full in ((None, full_default), (17, full_17)):
        cwd = work / f"metrics_only_cwd_{seed}"
        cwd.mkdir(parents=True)
        only = work / f"metrics_only_{seed}" / "sub" / "m.json"
        cmd = [motorsim, "--scenario", str(scenario.resolve()), "--metrics-out", str(only)]
        cmd += ["--seed", str(seed)] if seed is not None else []
        r4 = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=cwd)
        if r4.returncode != 0:
            errors.append(f"metrics-only run (seed {seed}) failed: {r4.stderr.strip()}")
            continue
        written = [p for p in (work / f"metrics_only_{seed}").rglob("*") if p.is_file()]
        written += [p for p in cwd.rglob("*")]
        if written != [only]:
            errors.append(f"metrics-only run (seed {seed}) wrote {[str(p) for p in written]}, want [{only}]")
        got = json.loads(only.read_text()) if only.is_file() else {}
        diff = sorted(k for k in set(got) | set(full) if k not in timing and got.get(k) != full.get(k))
        if diff or not full:
            errors.append(f"metrics-only run (seed {seed}) differs from the full run in {diff}")
        printed = dict(line.split(" ", 1) for line in r4.stdout.strip().splitlines())
        if set(printed) != set(got):
            errors.append("metrics-only run: stdout keys differ from its JSON keys")

    # --out DIR --no-csv: the metrics JSON alone, in DIR.
    nocsv = work / "no_csv"
    r5 = subprocess.run([motorsim, "--scenario", str(scenario), "--out", str(nocsv), "--no-csv", "--quiet"],
                        capture_output=True, text=True, timeout=120)
    listed = sorted(p.name for p in nocsv.iterdir()) if nocsv.is_dir() else []
    if r5.returncode != 0 or listed != [f"{stem}_metrics.json"]:
        errors.append(f"--out --no-csv wrote {listed} (exit {r5.returncode}: {r5.stderr.strip()})")

    for e in errors:
        print("FAILED:", e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
