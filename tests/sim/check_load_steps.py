#!/usr/bin/env python3
"""Load steps at any time of the move (issue 10): runs a paper-000 load-step
scenario with its [load] step moved to each of the given times (and seeds)
and requires, for each run, the issue's load-step thresholds:

  * no fault (motorsim exit 0 with --no-expect);
  * tracking error below --max-err (0.05 rad) over the whole run, open loop
    included (a pole slip is 0.063 rad);
  * back within --settled (0.02 rad) from 100 ms after the step, every
    sample (theta_track_load_settled_max_rad);
  * no phase current above --i-max (i_max_A of the scenario, 3 A);
  * the voltage limit active on no more than --sat-max of the samples
    (0.02: the drive does not live at the supply's limit; 0.008-0.011
    measured with a step, 0.06 without the law's voltage cut).

The scenario's other [expect] thresholds (the experiment's, for its run
without a step) are not applied here. The estimate error is printed, not
bounded: the issue states no bound for it during a step, and where a step
sets the rotor ringing through a loop closing it reaches 0.032 rad in the
sample before the back-EMF becomes unobservable and the loop opens.

usage: check_load_steps.py MOTORSIM SCENARIO.toml [--times T ...] [--seeds S ...]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

# the move of paper 000's experiment: out to 18 rad in 2 s and back; the
# times cover the open-loop start, the acceleration, the peak speed, the
# deceleration, the dwell (open loop), the return and its end
TIMES = (0.2, 0.5, 1.0, 1.5, 1.9, 2.1, 2.3, 2.5, 3.0, 3.3, 3.6, 3.9)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("motorsim")
    ap.add_argument("scenario")
    ap.add_argument("--times", type=float, nargs="+", default=TIMES)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--i-max", type=float, default=3.0, help="[limits] i_max_A of the scenario")
    ap.add_argument("--max-err", type=float, default=0.05, help="max tracking error over the run [rad]")
    ap.add_argument("--settled", type=float, default=0.02, help="max tracking error from 100 ms after the step [rad]")
    ap.add_argument("--sat-max", type=float, default=0.02, help="max fraction of samples at the voltage limit")
    a = ap.parse_args()
    text = open(a.scenario).read()
    steps = re.compile(r"^steps\s*=\s*\[\{\s*t_s\s*=\s*[0-9.eE+-]+\s*,", re.M)
    if len(steps.findall(text)) != 1:
        sys.exit(f"check_load_steps: {a.scenario}: expected one '[load] steps = [{{t_s = ..., ...}}]' line")
    motors = os.path.join(os.path.dirname(os.path.abspath(a.scenario)), "..", "motors") + "/"
    bad = []
    with tempfile.TemporaryDirectory() as tmp:
        def run(case):
            t, seed = case
            path = os.path.join(tmp, f"s_{t}_{seed}.toml")
            body = steps.sub(f"steps = [{{t_s = {t!r},", text).replace('file = "../motors/', f'file = "{motors}')
            with open(path, "w") as f:
                f.write(body)
            out = os.path.join(tmp, f"m_{t}_{seed}.json")
            r = subprocess.run([a.motorsim, "--scenario", path, "--seed", str(seed), "--metrics-out", out, "--quiet",
                                "--no-expect"],
                               capture_output=True, text=True)
            return t, seed, r, (json.load(open(out)) if os.path.exists(out) else None)

        cases = [(t, s) for s in a.seeds for t in a.times]
        with ThreadPoolExecutor(max(1, min(2, os.cpu_count() or 1))) as pool:
            results = list(pool.map(run, cases))
    print(f"{'step at [s]':>11} {'seed':>4} {'rc':>3} {'max err':>9} {'settled':>9} {'est':>9} {'|i|max':>7} {'v sat':>7}")
    for t, seed, r, m in results:
        if m is None:
            bad.append(f"step at {t} s, seed {seed}: no metrics (exit {r.returncode}): {r.stderr.strip()}")
            continue
        st = m.get("theta_track_load_settled_max_rad")
        print(f"{t:11.2f} {seed:4d} {r.returncode:3d} {m['theta_track_max_all_rad']:9.5f} "
              f"{(f'{st:9.5f}' if st is not None else '        -')} {m['theta_est_max_rad']:9.5f} "
              f"{m['max_abs_current_A']:7.3f} {m['voltage_saturated_fraction']:7.4f}")
        if r.returncode != 0:
            bad.append(f"step at {t} s, seed {seed}: exit {r.returncode}: {r.stderr.strip()}")
        if not m["theta_track_max_all_rad"] < a.max_err:
            bad.append(f"step at {t} s, seed {seed}: tracking error {m['theta_track_max_all_rad']:.4g} rad "
                       f">= {a.max_err} rad")
        if not m["voltage_saturated_fraction"] <= a.sat_max:
            bad.append(f"step at {t} s, seed {seed}: at the voltage limit on {m['voltage_saturated_fraction']:.3g} "
                       f"of the samples > {a.sat_max}")
        if st is None or not st < a.settled:
            bad.append(f"step at {t} s, seed {seed}: error from 100 ms after the step {st} rad, not < {a.settled} rad")
        if m["max_abs_current_A"] > a.i_max:
            bad.append(f"step at {t} s, seed {seed}: phase current {m['max_abs_current_A']:.4g} A > i_max {a.i_max} A")
    for b in bad:
        print("FAIL:", b)
    print(f"{len(results) - len(bad)} of {len(results)} runs pass" if not bad else f"{len(bad)} failure(s)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
