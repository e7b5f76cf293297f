#!/usr/bin/env python3
"""The measured tables of docs/paper000.md, from fresh motorsim runs.

  --results   the results table: ideal and experiment (seed 1) against the
              paper's figures, and the range over seeds 1-10 of the experiment
  --load-steps  load steps on the experiment: a step of 0.1, 0.2, 0.3 N m at
              1 s, 0.2 N m with [bounds] bound_load_Nm = 0.3, and 0.2 N m
              ramped over 20 ms
  --designs   the two gain designs ([design] gain_design) side by side:
              ideal, experiment over seeds 1-10, and the experiment with its
              bounds raised (bound_load_rate_Nm_s = 10, and bound_load_Nm =
              0.475 with it)
  --load-capacity  load steps of 0.1-0.4 N m at 0.5, 1.0, 1.5, 2.5, 3.0 s on
              the experiment (seed 1), both designs, with the default bounds
              and with bound_load_Nm = the step + the Coulomb friction, and
              with the load-angle law 0.4-0.6 N m; a cell
              is max / settled tracking error (theta_track_max_rad /
              theta_track_load_settled_max_rad) and passes (ok) when there is
              no trip, no pole slip, max < 0.05 and settled < 0.02 rad

    python3 tools/tables/paper000_tables.py --results [--build build/host]

Standard library only; about a second.
"""
from __future__ import annotations

import argparse
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SC = ROOT / "sim" / "scenarios"
# The paper's figures (Figs. 4-8 of paper 000), for the comparison column.
PAPER = {"theta_track_max_rad": "< 0.02", "theta_est_max_rad": "< 0.01", "current_obs_max_a": "< 0.01",
         "omega_est_peak_max_rad_s": "~1 at 20 rad/s", "final_theta_err_rad": "-", "closed_loop_fraction": "-"}


def run(ms: Path, scenario_text: str | None, scenario: Path, seed: int | None = None) -> dict:
    """The metrics of one run judged without its [expect] (a fault or a
    divergence is a result here); scenario_text: a variant of `scenario`."""
    ok = (motorsim.OK, motorsim.FAULT, motorsim.DIVERGED)
    if scenario_text is None:
        return motorsim.metrics(ms, scenario, seed=seed, expect=False, ok=ok)
    return motorsim.metrics(ms, text=motorsim.with_absolute_motor(scenario_text), name=scenario.stem, seed=seed,
                            expect=False, ok=ok)


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
        seeds = list(pool.map(lambda s: run(ms, None, SC / "paper000_experiment.toml", seed=s),
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


COULOMB_NM = 0.0752   # sim/motors/paper000_stepper.toml: the default load bound
HALF_PITCH_RAD = 0.0628  # pi/n_p: beyond it the rotor has slipped a pole
STEP_TIMES = (0.5, 1.0, 1.5, 2.5, 3.0)
STEP_LOADS = (0.1, 0.15, 0.2, 0.3, 0.4)
# the load-angle law (control_law = "load_angle"): the step, and
# beyond it up to where it slips
LOAD_ANGLE_LOADS = (0.4, 0.5, 0.6)


def experiment_variant(design: str, bounds: dict[str, float], load: tuple[float, float] | None = None,
                       law: str = "twisting") -> str:
    t = (SC / "paper000_experiment.toml").read_text()
    t += f'\n[design]\ngain_design = "{design}"\n'
    if law != "twisting":
        t += f'control_law = "{law}"\n'
    if bounds:
        t += "\n[bounds]\n" + "".join(f"{k} = {v}\n" for k, v in bounds.items())
    if load is not None:
        t += f"\n[load]\nsteps = [{{ t_s = {load[1]}, torque_Nm = {load[0]} }}]\n"
    return t


def designs(ms: Path) -> None:
    ideal_text = (SC / "paper000_ideal.toml").read_text()
    raised = [("`bound_load_rate_Nm_s = 10`", {"bound_load_rate_Nm_s": 10.0}),
              ("and `bound_load_Nm = 0.475`", {"bound_load_rate_Nm_s": 10.0, "bound_load_Nm": 0.475})]
    print("| | continuous | discrete |")
    print("| --- | --- | --- |")
    rows: dict[str, list[str]] = {}
    for design in ("continuous", "discrete"):
        ideal = run(ms, ideal_text + f'\n[design]\ngain_design = "{design}"\n', SC / "paper000_ideal.toml")
        rows.setdefault("ideal: `theta_track_max_rad` / `theta_est_max_rad` / `current_obs_max_a`", []).append(
            f"{g(ideal['theta_track_max_rad'])} / {g(ideal['theta_est_max_rad'])} / {g(ideal['current_obs_max_a'])}")
        for name, bounds in [("experiment, seeds 1-10", {})] + [("experiment " + n, b) for n, b in raised]:
            text = experiment_variant(design, bounds)
            with ThreadPoolExecutor(2) as pool:
                seeds = list(pool.map(lambda s: run(ms, text, SC / "paper000_experiment.toml", seed=s),
                                      range(1, 11)))
            def mx(k: str) -> str:
                return g(max(m[k] for m in seeds))
            trips = sum(1 for m in seeds if m["fault"] != 0)
            rows.setdefault(name + ": max over seeds of `theta_track_max_rad` / `theta_est_max_rad` / "
                            "`omega_est_peak_max_rad_s`", []).append(
                f"{mx('theta_track_max_rad')} / {mx('theta_est_max_rad')} / {mx('omega_est_peak_max_rad_s')}"
                + (f", {trips} trip(s)" if trips else ""))
    for k, v in rows.items():
        print(f"| {k} | {v[0]} | {v[1]} |")


def load_capacity(ms: Path) -> None:
    cases = []
    for design in ("continuous", "discrete"):
        for raised in (False, True):
            for load in STEP_LOADS:
                bounds = {"bound_load_Nm": round(load + COULOMB_NM, 4)} if raised else {}
                cases.append(("twisting", design, raised, load,
                              [experiment_variant(design, bounds, (load, t)) for t in STEP_TIMES]))
    for design in ("continuous", "discrete"):
        for load in LOAD_ANGLE_LOADS:
            cases.append(("load_angle", design, False, load,
                          [experiment_variant(design, {}, (load, t), "load_angle") for t in STEP_TIMES]))
    flat = [(i, j, text) for i, c in enumerate(cases) for j, text in enumerate(c[4])]
    with ThreadPoolExecutor(2) as pool:
        res = list(pool.map(lambda x: run(ms, x[2], SC / "paper000_experiment.toml"), flat))
    cell: dict[tuple[int, int], str] = {}
    for (i, j, _), m in zip(flat, res):
        if m["theta_track_max_all_rad"] >= HALF_PITCH_RAD:
            cell[(i, j)] = "slip" + (", trip" if m["fault"] else "")
        elif m["fault"]:
            cell[(i, j)] = "trip"
        else:
            tr, st = m["theta_track_max_rad"], m["theta_track_load_settled_max_rad"]
            ok = tr < 0.05 and st is not None and st < 0.02
            cell[(i, j)] = f"{g(tr)} / {g(st) if st is not None else '-'}" + (" ok" if ok else "")
    print("| law | design | bounds | step | " + " | ".join(f"at {t:g} s" for t in STEP_TIMES) + " |")
    print("| --- | --- | --- | --- | " + " | ".join("---" for _ in STEP_TIMES) + " |")
    for i, (law, design, raised, load, _) in enumerate(cases):
        b = f"`bound_load_Nm = {load + COULOMB_NM:.3g}`" if raised else "default"
        print(f"| {law} | {design} | {b} | {load:g} N m | "
              + " | ".join(cell[(i, j)] for j in range(len(STEP_TIMES))) + " |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host"))
    ap.add_argument("--results", action="store_true")
    ap.add_argument("--load-steps", action="store_true")
    ap.add_argument("--designs", action="store_true")
    ap.add_argument("--load-capacity", action="store_true")
    a = ap.parse_args()
    try:
        ms = motorsim.find(build=a.build)
    except motorsim.MotorsimError as e:
        print(f"paper000_tables: {e}", file=sys.stderr)
        return 2
    if not (a.results or a.load_steps or a.designs or a.load_capacity):
        print("paper000_tables: give --results, --load-steps, --designs and/or --load-capacity", file=sys.stderr)
        return 2
    try:
        if a.results:
            results(ms)
        if a.load_steps:
            if a.results:
                print()
            load_steps(ms)
        if a.designs:
            designs(ms)
        if a.load_capacity:
            load_capacity(ms)
    except motorsim.MotorsimError as e:
        print(f"paper000_tables: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
