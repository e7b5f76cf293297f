#!/usr/bin/env python3
"""Issue 31's tables: paper 002's IPMSM held at 0 rpm without a sensor
(sim/scenarios/ipmsm_zero_speed.toml), with the HF injection (the
scenario's estimator = "hfi") and with it off (--estimator flux: paper
001's flux observer alone, the variant that existed before), over seeds;
the injection's cost: its current ripple and added voltage; then the start
from rest and the handover to the flux observer
(sim/scenarios/ipmsm_hfi_handover.toml) over seeds, against the flux
variant told the start angle (--table handover), the same on the
hardware-like plant (sim/scenarios/ipmsm_hfi_handover_hw.toml, --table
handover_hw, also with the drive's iron linear:
tests/sim/failing_runs/ipmsm_hfi_handover_hw_linear_iron.toml); and the reversal through
zero under load on the injection (sim/scenarios/ipmsm_hfi_reversal.toml,
--table reversal) over seeds.

Every number from the runs' CSV logs, one definition for both estimators:
  theta_err_max   max |theta_hat - theta| of the EKF from 50 ms on (rad, mechanical)
  drift_max       max |theta - theta(0)| over the run (rad, mechanical)
  speed_err_max   max |w| (the reference is 0), rad/s
and from the metrics: speed_rmse_rad_s, fault, and for the injection
hfi_current_ripple_rms_A (half the true current's change per sample, the
triangle's amplitude) and hfi_voltage_rms_V. Each run is also judged
against the scenario's [expect] (outcome: pass, or the metrics it missed;
the flux runs are judged on the [expect] keys they share: fault,
theta_est_rmse_rad, speed_err_max_rad_s).

    python3 tools/tables/hfi_table.py [--build build/host] [--seeds 8] [--table zero|handover|handover_hw|reversal]
    python3 tools/tables/hfi_table.py --table cost --pil RESULTS.json...

Standard library only; about 10 s for 8 seeds.
"""
from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "sim" / "scenarios" / "ipmsm_zero_speed.toml"
HANDOVER = ROOT / "sim" / "scenarios" / "ipmsm_hfi_handover.toml"
HANDOVER_HW = ROOT / "sim" / "scenarios" / "ipmsm_hfi_handover_hw.toml"
HANDOVER_HW_LINEAR = ROOT / "tests" / "sim" / "failing_runs" / "ipmsm_hfi_handover_hw_linear_iron.toml"
REVERSAL = ROOT / "sim" / "scenarios" / "ipmsm_hfi_reversal.toml"
SKIP_S = 0.05  # the EKF's start (its first correction) left out, as the metric's
# the [expect] keys both estimators have (the others exist for the injection only)
SHARED = {"fault": (None, 0.0), "theta_est_rmse_rad": (None, None), "speed_err_max_rad_s": (None, None)}


def wrap(a: float) -> float:
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def expect_bounds(path: Path = SCENARIO) -> dict[str, tuple[float | None, float | None]]:
    """The scenario's [expect] as {key: (min, max)} (tomllib: Python 3.11)."""
    import tomllib
    doc = tomllib.loads(path.read_text(encoding="utf-8"))
    return {k: (v.get("min"), v.get("max")) for k, v in doc.get("expect", {}).items()}


def from_csv(rows: list[dict]) -> tuple[float, float, float]:
    th0 = float(rows[0]["theta_rad"])
    err = drift = spd = 0.0
    for r in rows:
        th, the = float(r["theta_rad"]), float(r["theta_est_rad"])
        if float(r["t_s"]) >= SKIP_S - 1e-12:
            err = max(err, abs(wrap(the - th)))
        drift = max(drift, abs(wrap(th - th0)))
        spd = max(spd, abs(float(r["omega_rad_s"])))
    return err, drift, spd


def judged(m: dict, bounds: dict, keys) -> str:
    missed = []
    for k in keys:
        lo, hi = bounds[k]
        v = m.get(k)
        if v is None or (lo is not None and v < lo) or (hi is not None and v > hi):
            missed.append(k)
    return "pass" if not missed else "missed " + ", ".join(missed)


def fault_at(r) -> str:
    """' (fault at T s)' from the run's stderr, or ''."""
    at = re.search(r"drive fault \d+ \([a-z-]+\) at t = ([0-9.]+) s", r.stderr or "")
    return f" (fault at {float(at.group(1)):.4f} s)" if at else ""


def handover(ms, seeds: int, hw: bool = False) -> int:
    """The start from rest and the handover: the injection over seeds, the
    flux variant (told the start angle) once; on the hardware-like plant
    (hw) also the injection with the drive's iron linear once."""
    path = HANDOVER_HW if hw else HANDOVER
    bounds = expect_bounds(path)
    keys = [("speed_err_max_rad_s", "%.3f"), ("speed_rmse_rad_s", "%.3f"), ("final_omega_rad_s", "%.2f"),
            ("theta_est_rmse_rad", "%.2e"), ("hfi_on_fraction", "%.4f"), ("fault", "%d")]
    print("| estimator | seed | outcome | " + " | ".join(f"`{k}`" for k, _ in keys) + " |")
    print("|---|---|---|" + "---|" * len(keys))
    runs = [("hfi", s, path) for s in range(1, seeds + 1)] + [("flux", 1, path)]
    if hw:
        runs.append(("hfi, iron linear", 1, HANDOVER_HW_LINEAR))
    for est, seed, scenario in runs:
        r = motorsim.run(ms, scenario, seed=seed, estimator=est.split(",")[0], expect=False, ok=None)
        m = r.metrics or {}
        out = judged(m, bounds, bounds.keys() if est == "hfi" else [k for k in bounds if k in m])
        out += fault_at(r)
        cells = ["—" if m.get(k) is None else fmt % m[k] for k, fmt in keys]
        print(f"| {est} | {seed} | {out} | " + " | ".join(cells) + " |")
    return 0


def reversal(ms, seeds: int) -> int:
    """The reversal through zero under load, on the injection over seeds,
    and with it off (the flux variant) once."""
    bounds = expect_bounds(REVERSAL)
    keys = [("theta_est_err_max_rad", "%.4f"), ("theta_est_rmse_rad", "%.4f"),
            ("speed_rmse_after_50ms_rad_s", "%.3f"), ("final_omega_rad_s", "%.2f"), ("fault", "%d")]
    print("| estimator | seed | outcome | " + " | ".join(f"`{k}`" for k, _ in keys) + " |")
    print("|---|---|---|" + "---|" * len(keys))
    for est, seed in [("hfi", s) for s in range(1, seeds + 1)] + [("flux", 1)]:
        r = motorsim.run(ms, REVERSAL, seed=seed, estimator=est, expect=False, ok=None)
        m = r.metrics or {}
        out = judged(m, bounds, bounds.keys() if est == "hfi" else [k for k in bounds if k in m])
        out += fault_at(r)
        cells = ["—" if m.get(k) is None else fmt % m[k] for k, fmt in keys]
        print(f"| {est} | {seed} | {out} | " + " | ".join(cells) + " |")
    return 0


# The VESC 6's STM32F405 core clock and the control rate: a step's share
# of the period at one instruction a cycle (the M4F's best case; flash wait
# states and the FPU's divisions and square roots cost more).
CORE_HZ = 168e6
CONTROL_HZ = 1e4


def pil_cost(files: list[str]) -> int:
    """The step's cost on the Cortex-M4F (tools/bench/pil.py --drive
    paper002 --results FILE): one row per results file."""
    import json
    print("| scenario | periods | instructions mean | min | max | p99 | mean share of the 10 kHz period at 168 MHz |")
    print("|---|---|---|---|---|---|---|")
    for f in files:
        d = json.loads(Path(f).read_text(encoding="utf-8"))
        k = "paper002_m4f_float_"
        if d.get("failures") or k + "instr_mean" not in d:
            print(f"hfi_table: {f}: no bit-exact paper002 float results", file=sys.stderr)
            return 1
        mean = d[k + "instr_mean"]
        print(f"| `{Path(d['paper002_scenario']).name}` | {d[k + 'periods']} | {mean:.1f} | {d[k + 'instr_min']} "
              f"| {d[k + 'instr_max']} | {d[k + 'instr_p99']} | {100.0 * mean * CONTROL_HZ / CORE_HZ:.1f} % |")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(motorsim.DEFAULT_BUILD))
    ap.add_argument("--seeds", type=int, default=8, help="seeds 1..N (default 8)")
    ap.add_argument("--table", choices=("zero", "handover", "handover_hw", "reversal", "cost"), default="zero")
    ap.add_argument("--pil", nargs="+", default=[], metavar="RESULTS.json",
                    help="--table cost: tools/bench/pil.py --drive paper002 results files")
    a = ap.parse_args()
    if a.table == "cost":
        if not a.pil:
            print("hfi_table: --table cost needs --pil RESULTS.json ...", file=sys.stderr)
            return 2
        return pil_cost(a.pil)
    if a.seeds < 1:
        print("hfi_table: --seeds: must be >= 1", file=sys.stderr)
        return 2
    ms = motorsim.find(build=a.build)
    if a.table in ("handover", "handover_hw"):
        return handover(ms, a.seeds, hw=a.table == "handover_hw")
    if a.table == "reversal":
        return reversal(ms, a.seeds)
    bounds = expect_bounds()
    print("| estimator | seed | outcome | theta_err_max (rad) | drift_max (rad) | speed_err_max (rad/s) "
          "| speed_rmse_rad_s | fault |")
    print("|---|---|---|---|---|---|---|---|")
    cost = []
    for est in ("hfi", "flux"):
        for seed in range(1, a.seeds + 1):
            r = motorsim.run(ms, SCENARIO, seed=seed, estimator=est, expect=False, csv_log=True, ok=None)
            m = r.metrics or {}
            if not r.rows:
                print(f"| {est} | {seed} | no log (exit {r.status}) | | | | | |")
                continue
            err, drift, spd = from_csv(r.rows)
            keys = bounds.keys() if est == "hfi" else [k for k in bounds if k in SHARED]
            out = judged(m, bounds, keys)
            print(f"| {est} | {seed} | {out} | {err:.4f} | {drift:.4f} | {spd:.3f} | "
                  f"{m.get('speed_rmse_rad_s', float('nan')):.3f} | {m.get('fault', '—')} |")
            if est == "hfi":
                cost.append((m.get("hfi_current_ripple_rms_A"), m.get("hfi_voltage_rms_V"),
                             m.get("max_abs_current_A")))
    if cost:
        rip = [c[0] for c in cost if c[0] is not None]
        volt = [c[1] for c in cost if c[1] is not None]
        imax = [c[2] for c in cost if c[2] is not None]
        print()
        print("| injection's cost (seeds 1-%d) | min | max |" % a.seeds)
        print("|---|---|---|")
        print(f"| current ripple, RMS of the triangle's amplitude (A) | {min(rip):.4f} | {max(rip):.4f} |")
        print(f"| added voltage, RMS (V) | {min(volt):.3f} | {max(volt):.3f} |")
        print(f"| largest phase current of the run (A) | {min(imax):.2f} | {max(imax):.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
