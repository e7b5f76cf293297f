#!/usr/bin/env python3
"""The measured tables of docs/paper001.md, from fresh motorsim runs.

Runs the paper-001 benchmark from the ten initial rotor angles of the ctest
loop (k/10 of an electrical turn, 2 pi/3 rad mechanical at n_p = 3), the
identification scenario, and the three robustness scenarios, in the float
build and (--fixed) the fixed-point build, and prints markdown tables:

    python3 tools/tables/paper001_tables.py [--build build/host] [--fixed build/host-fixed]

Standard library only; about 2 s per build.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SC = ROOT / "sim" / "scenarios"
ANGLES = [k * (2.0 * math.pi / 3.0) / 10.0 for k in range(10)]
KEYS = [("speed_err_settled_max_rpm", "< 0.1", "%.3f"), ("speed_err_rms_rpm", "< 3.5", "%.2f"),
        ("speed_err_max_rpm", "< 25", "%.1f"), ("theta_est_max_deg_e", "< 0.5", "%.3f"),
        ("load_est_err_settled_nm", "< 0.01", "%.4f"), ("lock_time_s", "reported", "%.3f"),
        ("speed_err_ramp_max_rpm", "reported", "%.2f"), ("max_abs_current_A", "< 8", "%.1f")]


def run(ms: Path, scenario: Path, theta0_rad: str | None = None) -> dict:
    """The metrics of a shipped scenario, which must meet its [expect]."""
    return motorsim.metrics(ms, scenario, theta0_rad=theta0_rad)


def run_text(ms: Path, text: str) -> dict:
    """A scenario given as text, written next to the shipped ones (its
    motor path is relative to them); judged without its [expect]."""
    return motorsim.metrics(ms, text=text, name="p001", text_dir=SC, expect=False,
                            ok=(motorsim.OK, motorsim.FAULT, motorsim.DIVERGED))


def fault(m: dict) -> str:
    """The fault code, with its time when there is one."""
    return f"{m['fault']} at {m['fault_first_t_s']:.2f} s" if m["fault"] else "0"


def fmt(fmt_: str, x) -> str:
    return "null" if x is None else fmt_ % x


def rng(fmt_: str, xs: list) -> str:
    if any(x is None for x in xs):
        return "null in %d" % sum(x is None for x in xs)
    lo, hi = fmt_ % min(xs), fmt_ % max(xs)
    return lo if lo == hi else f"{lo}-{hi}"


def tables(build: Path, label: str) -> None:
    ms = build / "sim" / "motorsim"
    bench = SC / "paper001_benchmark.toml"
    angles = [run(ms, bench, theta0_rad="%.5f" % th) for th in ANGLES]
    ident = run(ms, SC / "paper001_identify.toml")
    print("| metric | θ(0) = 0 | 10 angles | identify (R +50 %, Φ +15 %) | threshold |")
    print("|---|---|---|---|---|")
    for key, thr, f in KEYS:
        print(f"| {key} | {fmt(f, angles[0][key])} | {rng(f, [a[key] for a in angles])} | {fmt(f, ident[key])} | {thr} |")
    print()
    print("| identified (`paper001_identify.toml`) | value | plant | error |")
    print("|---|---|---|---|")
    for key, plant, unit in (("R_ohm", 0.3375, "Ω"), ("L_H", 3.8e-3, "H"), ("Phi_Wb", 0.1955, "Wb")):
        print(f"| {key} | {ident['id_' + key]:.6g} {unit} | {plant:g} {unit} | {ident['id_' + key.split('_')[0] + '_err_pct']:+.4f} % |")
    print(f"| commissioning time | {ident['id_time_s']:.2f} s | | |")
    print()
    print("| robustness scenario | settled, moving (rpm) | settled incl. standstill (rpm) | load err settled (N m) | lock_time_s | fault |")
    print("|---|---|---|---|---|---|")
    for case, what in (("R150", "R +50 %"), ("L150", "L +50 %"), ("Phi115", "Φ +15 %")):
        # R +50 % ends in its expected loss of lock at standstill (the file's [expect])
        m = motorsim.metrics(ms, SC / f"paper001_{case}.toml", ok=(motorsim.OK, motorsim.FAULT))
        print(f"| `paper001_{case}.toml` ({what}) | {m['speed_err_settled_moving_max_rpm']:.3f} | "
              f"{m['speed_err_settled_max_rpm']:.3f} | {m['load_est_err_settled_nm']:.4f} | "
              f"{fmt('%.3f', m['lock_time_s'])} | {fault(m)} |")
    # issue 30's case (a): R +30 %, L -15 %, its loss of lock expected
    m = motorsim.metrics(ms, ROOT / "tests" / "sim" / "failing_runs" / "paper001_R130_L85.toml",
                         ok=(motorsim.OK, motorsim.FAULT))
    print(f"| `paper001_R130_L85.toml` (R +30 %, L −15 %; tests/sim/failing_runs) | "
          f"{m['speed_err_settled_moving_max_rpm']:.3f} | {m['speed_err_settled_max_rpm']:.3f} | "
          f"{m['load_est_err_settled_nm']:.4f} | {fmt('%.3f', m['lock_time_s'])} | {fault(m)} |")
    # the other way round: the motor nominal, the drive's (the observer's)
    # R or Phi over-estimated; the benchmark with a [drive_model] added
    base = (SC / "paper001_benchmark.toml").read_text()
    for what, R, Phi in (("drive R ×1.5: the observer over-estimates R", 0.3375, 0.17),
                         ("drive Φ ×1.15: the observer over-estimates Φ", 0.225, 0.1955)):
        text = base + (f"\n[drive_model]\nR_ohm = {R}\nL_d_H = 3.8e-3\nL_q_H = 3.8e-3\nPhi_Wb = {Phi}\n")
        m = run_text(ms, text)
        print(f"| benchmark, {what} | {m['speed_err_settled_moving_max_rpm']:.3f} | "
              f"{m['speed_err_settled_max_rpm']:.3f} | {m['load_est_err_settled_nm']:.4f} | "
              f"{fmt('%.3f', m['lock_time_s'])} | {fault(m)} |")
    print()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host"),
                    help="host build to run (build/host: float; build/host-fixed: fixed point)")
    a = ap.parse_args()
    try:
        motorsim.find(build=a.build)
    except motorsim.MotorsimError as e:
        print(f"paper001_tables: {e}", file=sys.stderr)
        return 2
    try:
        tables(Path(a.build).resolve(), "")
    except motorsim.MotorsimError as e:
        print(f"paper001_tables: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
