#!/usr/bin/env python3
"""The estimator comparison of docs/observers.md, from fresh motorsim runs.

The paper-001 speed drive takes its estimator by configuration ([speed]
estimator = "flux" | "back_emf"; firmware/drives/paper001/paper001_drive.h): paper
001's gradient flux observer (12)-(14) with the I&I speed and load observer
(15)-(16), or paper 000's back-EMF chain (super-twisting observer (23)-(28),
arctan and jump counter (29)-(32), (71), mechanical observer (33)-(37)).
Both run, with the same IDA-PBC (11), on both motors:

  PMSM     sim/scenarios/paper001_benchmark.toml (paper 001's motor and benchmark)
  stepper  sim/scenarios/stepper_speed.toml      (paper 000's stepper, n_p = 50)

For each of the four runs it prints, from the metrics JSON and the CSV:
time to lock (lock_time_s: the first sample with a valid estimate within
5 deg electrical, held 50 ms), the electrical angle error and the speed
estimate error (w_hat - w) while the estimate is valid after the lock (max
and RMS), the speed tracking error over the run (RMS, max), and the share of
the run in closed loop. With --pil FILE (a JSON of tools/bench/pil.py for
the paper-001 drive) it adds the instructions per step on Cortex-M4F.

    python3 tools/tables/observers.py [--build build/host] [--pil FILE] [--markdown]

Standard library only; a few seconds.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SC = ROOT / "sim" / "scenarios"
MOTORS = [("PMSM (paper 001)", SC / "paper001_benchmark.toml"), ("stepper (paper 000)", SC / "stepper_speed.toml")]
ESTIMATORS = [("flux", "flux + I&I (paper 001)"), ("back_emf", "back-EMF chain (paper 000)")]
RPM = 60.0 / (2.0 * math.pi)
SETTLE_S = 0.05  # after the lock, as theta_est_max_deg_e (sim/motorsim/speed_recorder.h)


def run(ms: Path, scenario: Path, est: str) -> dict:
    r = motorsim.run(ms, scenario, estimator=est, expect=False, csv_log=True)
    m, rows = r.metrics, r.rows
    lock = m["lock_time_s"]
    th, dw = [], []
    if lock is not None:
        for row in rows:
            if float(row["t_s"]) >= lock + SETTLE_S and row["estimate_valid"] == "1":
                th.append(abs(float(row["theta_e_err_rad"])) * 180.0 / math.pi)
                dw.append((float(row["omega_est_rad_s"]) - float(row["omega_rad_s"])) * RPM)
    rms = lambda xs: math.sqrt(sum(x * x for x in xs) / len(xs)) if xs else float("nan")
    return {"lock_time_s": lock, "theta_max_deg": max(th) if th else float("nan"), "theta_rms_deg": rms(th),
            "dw_max_rpm": max(abs(x) for x in dw) if dw else float("nan"), "dw_rms_rpm": rms(dw),
            "track_rms_rpm": m["speed_err_rms_rpm"], "track_max_rpm": m["speed_err_max_rpm"],
            "closed": m["closed_loop_fraction"], "fault": m["fault"]}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host"))
    ap.add_argument("--pil", help="pil.py JSON of the paper-001 drive (instructions per step)")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--pil-only", action="store_true", help="print only the --pil tables (no simulation)")
    a = ap.parse_args()
    if a.pil_only:
        if not a.pil:
            print("observers: --pil-only needs --pil FILE", file=sys.stderr)
            return 2
        print_pil(json.loads(Path(a.pil).read_text()), a.markdown)
        return 0
    try:
        ms = motorsim.find(build=a.build)
    except motorsim.MotorsimError as e:
        print(f"observers: {e}", file=sys.stderr)
        return 2
    pil = json.loads(Path(a.pil).read_text()) if a.pil else None
    head = ["motor", "estimator", "lock (s)", "angle err max / rms (deg e)", "speed est err max / rms (rpm)",
            "tracking rms / max (rpm)", "closed loop"]
    rows = []
    for mname, sc in MOTORS:
        for est, ename in ESTIMATORS:
            try:
                r = run(ms, sc, est)
            except motorsim.MotorsimError as e:
                print(f"observers: {e}", file=sys.stderr)
                return 1
            lock = "never" if r["lock_time_s"] is None else "%.3f" % r["lock_time_s"]
            row = [mname, ename, lock, "%.2f / %.2f" % (r["theta_max_deg"], r["theta_rms_deg"]),
                   "%.2f / %.2f" % (r["dw_max_rpm"], r["dw_rms_rpm"]),
                   "%.2f / %.1f" % (r["track_rms_rpm"], r["track_max_rpm"]), "%.0f %%" % (100 * r["closed"])]
            rows.append(row)
    if a.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        w = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(head)]
        print("  ".join(h.ljust(w[i]) for i, h in enumerate(head)))
        for row in rows:
            print("  ".join(c.ljust(w[i]) for i, c in enumerate(row)))
    if pil:
        print()
        print_pil(pil, a.markdown)
    return 0


def print_pil(pil: dict, markdown: bool) -> None:
    """Instructions per control step of the paper-001 drive on the PMSM
    benchmark, from a tools/bench/pil.py --drive paper001 results JSON."""
    head = ["estimator", "M4F float: step, closed loop mean (max)", "M4F float: whole run mean (max)",
            "M3 fixed: step, closed loop mean (max)", "M3 fixed: whole run mean (max)"]
    rows = []
    for est, ename in ESTIMATORS:
        row = [ename]
        for typ in ("m4f_float", "m3_fixed"):
            k = f"p001_{est}_{typ}"
            if f"{k}_instr_mean" not in pil:
                row += ["not measured", "not measured"]
                continue
            row.append("%.0f (%d)" % (pil[f"{k}_closed_loop_instr_mean"], pil[f"{k}_closed_loop_instr_max"]))
            row.append("%.0f (%d)" % (pil[f"{k}_instr_mean"], pil[f"{k}_instr_max"]))
        rows.append(row)
    parts = [("flux observer (12)-(14)", "flux_observer"), ("I&I observer (15)-(16)", "ii"),
             ("IDA-PBC (11)", "ida_pbc"), ("flux observer + IDA-PBC", "fo_ida")]
    if markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for row in rows:
            print("| " + " | ".join(row) + " |")
        print()
        print("| part of the flux step (closed loop) | M4F float mean | M3 fixed mean |")
        print("|---|---|---|")
        for name, key in parts:
            f = pil.get(f"p001_flux_m4f_float_part_{key}_instr_mean")
            x = pil.get(f"p001_flux_m3_fixed_part_{key}_instr_mean")
            print(f"| {name} | {'-' if f is None else '%.0f' % f} | {'-' if x is None else '%.0f' % x} |")
    else:
        for row in [head] + rows:
            print("  ".join(row))


if __name__ == "__main__":
    sys.exit(main())
