#!/usr/bin/env python3
"""The measured tables of docs/paper000.md, from fresh motorsim runs.

  --results   the results table: ideal and experiment (seed 1) against the
              paper's figures, and the range over seeds 1-10 of the experiment
  --load-steps  load steps on the experiment: a step of 0.1, 0.2, 0.3 N m at
              1 s, 0.2 N m with [bounds] bound_load_Nm = 0.3, and 0.2 N m
              ramped over 20 ms

    python3 tools/bench/paper000_tables.py --results [--build build/host]

Standard library only; about a second.
"""
from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SC = ROOT / "sim" / "scenarios"
# The paper's figures (Figs. 4-8 of paper 000), for the comparison column.
PAPER = {"theta_track_max_rad": "< 0.02", "theta_est_max_rad": "< 0.01", "current_obs_max_a": "< 0.01",
         "omega_est_peak_max_rad_s": "~1 at 20 rad/s", "final_theta_err_rad": "-", "closed_loop_fraction": "-"}


def run(ms: Path, scenario_text: str | None, scenario: Path, *extra: str) -> dict:
    with tempfile.TemporaryDirectory() as d:
        path = scenario
        if scenario_text is not None:
            path = Path(d) / scenario.name
            path.write_text(scenario_text.replace('file = "../motors/', f'file = "{SC.parent}/motors/'))
        out = Path(d) / "m.json"
        r = subprocess.run([str(ms), "--scenario", str(path), "--metrics-out", str(out), "--quiet", "--no-expect",
                            *extra], capture_output=True, text=True)
        if r.returncode not in (0, 3, 5):
            sys.exit(f"paper000_tables: {scenario.name} {' '.join(extra)}: exit {r.returncode}: {r.stderr.strip()}")
        return json.loads(out.read_text())


def g(x: float) -> str:
    return f"{x:.3g}" if abs(x) < 1e-3 else (f"{x:.4f}" if abs(x) < 0.1 else f"{x:.3f}")


def results(ms: Path) -> None:
    ideal = run(ms, None, SC / "paper000_ideal.toml")
    exp = run(ms, None, SC / "paper000_experiment.toml")
    print("| metric | paper (Figs. 4-8) | ideal | experiment (±0.03 A) |")
    print("| --- | --- | --- | --- |")
    for k, paper in PAPER.items():
        print(f"| `{k}` | {paper} | {g(ideal[k])} | {g(exp[k])} |")
    with ThreadPoolExecutor(2) as pool:
        seeds = list(pool.map(lambda s: run(ms, None, SC / "paper000_experiment.toml", "--seed", str(s)),
                              range(1, 11)))
    def rng(k: str) -> str:
        xs = [m[k] for m in seeds]
        return f"{g(min(xs))}-{g(max(xs))}"
    print()
    print(f"Seeds 1-10 of the experiment: `theta_track_max_rad` {rng('theta_track_max_rad')}, "
          f"`theta_est_max_rad` {rng('theta_est_max_rad')}, "
          f"`omega_est_peak_max_rad_s` {rng('omega_est_peak_max_rad_s')}.")


def load_steps(ms: Path) -> None:
    base = (SC / "paper000_experiment.toml").read_text()
    def variant(torque: float, ramp: float = 0.0, bound: float = 0.0) -> str:
        t = base + f"\n[load]\nsteps = [{{ t_s = 1.0, torque_Nm = {torque}, ramp_s = {ramp} }}]\n"
        if bound > 0.0:
            t += f"\n[bounds]\nbound_load_Nm = {bound}\n"
        return t
    cases = [("0.1 N m step at 1 s", variant(0.1)), ("0.2 N m step", variant(0.2)),
             ("0.2 N m step, `bound_load_Nm = 0.3`", variant(0.2, bound=0.3)),
             ("0.2 N m over a 20 ms ramp", variant(0.2, ramp=0.02)), ("0.3 N m step", variant(0.3))]
    with ThreadPoolExecutor(2) as pool:
        ms_ = list(pool.map(lambda c: run(ms, c[1], SC / "paper000_experiment.toml"), cases))
    print("| load (experiment, seed 1) | `theta_track_max_rad` | fault |")
    print("| --- | --- | --- |")
    for (name, _), m in zip(cases, ms_):
        tr = m["theta_track_max_rad"]
        verdict = " (lost: beyond half a pole pitch)" if tr >= 0.063 else ""
        print(f"| {name} | {g(tr)}{verdict} | {m['fault']} |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host"))
    ap.add_argument("--results", action="store_true")
    ap.add_argument("--load-steps", action="store_true")
    a = ap.parse_args()
    ms = Path(a.build).resolve() / "sim" / "motorsim"
    if not ms.exists():
        print(f"paper000_tables: {ms}: not built", file=sys.stderr)
        return 2
    if not (a.results or a.load_steps):
        print("paper000_tables: give --results and/or --load-steps", file=sys.stderr)
        return 2
    if a.results:
        results(ms)
    if a.load_steps:
        if a.results:
            print()
        load_steps(ms)
    return 0


if __name__ == "__main__":
    sys.exit(main())
