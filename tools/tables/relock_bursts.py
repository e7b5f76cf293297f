#!/usr/bin/env python3
"""The re-lock after a noise burst over the paper-000 move (docs/faults.md).

Runs sim/scenarios/paper000_experiment.toml with the re-lock reaction on
([protection] loss_of_sync = "relock") and a 20 ms burst of sensor noise
([faults] noise_burst) of 1.2 or 1.5 A (sigma) injected at 0.8, 1.2, 1.4,
1.5, 1.6, 2.5 and 3.0 s, seeds 1-3 (42 runs), for each over-current trip
count [limits] i_trip_samples = 1, 2, 3, and prints one markdown row per
count: the runs that recovered (no fault standing at the end and the rotor
within 0.05 rad of the commanded end, final_theta_err_rad), those that
ended in an over-current fault (code 1) and those whose loss of
synchronism stood after the re-locks (code 5); and how many ended without
a fault but off the end point (a silent wrong tooth).

--law load_angle runs the paper-000 drive's load-angle law ([design]
control_law, control/load_angle.h) instead of paper 000's twisting law;
"other" counts the runs that ended in another fault (4: the voltage
limit active for too long).

    python3 tools/tables/relock_bursts.py [--build build/host] [--jobs 2] [--law twisting|load_angle]

126 motorsim runs, metrics only: a few seconds. Standard library only.
"""
from __future__ import annotations

import argparse
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SC = ROOT / "sim" / "scenarios" / "paper000_experiment.toml"
NOISE_A = (1.2, 1.5)
TIMES_S = (0.8, 1.2, 1.4, 1.5, 1.6, 2.5, 3.0)
SEEDS = (1, 2, 3)
COUNTS = (1, 2, 3)
BURST_S = 0.02
END_TOL_RAD = 0.05  # the "finishes the move within 0.05 rad"


def scenario(count: int, noise_A: float, t_s: float, law: str = "twisting") -> str:
    text = motorsim.with_absolute_motor(SC.read_text())
    if "[limits]\n" not in text:
        sys.exit("relock_bursts: no [limits] table in " + str(SC))
    text = text.replace("[limits]\n", f"[limits]\ni_trip_samples = {count}\n", 1)
    text += '\n[protection]\nloss_of_sync = "relock"\n'
    if law != "twisting":
        text += f'\n[design]\ncontrol_law = "{law}"\n'
    text += f"\n[faults]\nnoise_burst = {{t_s = {t_s}, duration_s = {BURST_S}, noise_A = {noise_A}}}\n"
    return text


def run(ms: Path, case: tuple[int, float, float, int], law: str = "twisting") -> tuple[int, int, float]:
    count, noise_A, t_s, seed = case
    m = motorsim.metrics(ms, text=scenario(count, noise_A, t_s, law), name=f"burst_n{count}_{noise_A:g}A_{t_s:g}s",
                         seed=seed, expect=False, ok=(motorsim.OK, motorsim.FAULT))
    return count, int(m["fault"]), float(m["final_theta_err_rad"])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "host"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--law", choices=("twisting", "load_angle"), default="twisting",
                    help="the paper-000 drive's position law ([design] control_law)")
    a = ap.parse_args()
    try:
        ms = motorsim.find(build=a.build)
    except motorsim.MotorsimError as e:
        print(f"relock_bursts: {e}", file=sys.stderr)
        return 2
    if a.jobs < 1:
        print(f"relock_bursts: --jobs must be >= 1 (got {a.jobs})", file=sys.stderr)
        return 2
    cases = [(c, n, t, s) for c in COUNTS for n in NOISE_A for t in TIMES_S for s in SEEDS]
    try:
        with ThreadPoolExecutor(a.jobs) as pool:
            res = list(pool.map(lambda c: run(ms, c, a.law), cases))
    except motorsim.MotorsimError as e:
        print(f"relock_bursts: {e}", file=sys.stderr)
        return 1
    n = len(cases) // len(COUNTS)
    print("| `[limits] i_trip_samples` | recovered | over-current (code 1) | loss of synchronism standing (code 5) "
          "| no fault, off the end |")
    print("| --- | --- | --- | --- | --- |")
    for count in COUNTS:
        mine = [(f, e) for c, f, e in res if c == count]
        ok = sum(1 for f, e in mine if f == 0 and e < END_TOL_RAD)
        off = sum(1 for f, e in mine if f == 0 and not e < END_TOL_RAD)
        oc = sum(1 for f, _ in mine if f == 1)
        los = sum(1 for f, _ in mine if f == 5)
        other = len(mine) - ok - off - oc - los
        name = f"{count} (default)" if count == 1 else str(count)
        print(f"| {name} | {ok} of {n} | {oc} | {los}" + (f" (+{other} other)" if other else "") + f" | {off} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
