#!/usr/bin/env python3
"""Float vs fixed point: the paper-000 metrics of both builds side by side, and
the largest difference of theta_est between them on the same currents.

Each build's motorsim runs the scenario in closed loop (its own metrics).
Then the currents the float run measured are replayed, open loop, through
drive_replay of both builds, so the estimates can be compared sample by
sample without the two closed loops drifting apart.

    python3 tools/checks/compare_builds.py [--scenario FILE] [--check RAD]
needs build/host and build/host-fixed (cmake --preset host / host-fixed).
Exit 77 (skipped) when a build is missing; with --check, exit 1 when the
theta_est difference in closed loop reaches RAD.
"""
from __future__ import annotations

import argparse
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))  # the toolbox, tools/lib
from lib import motorsim  # noqa: E402
KEYS = ["theta_track_max_rad", "theta_est_max_rad", "current_obs_max_a", "omega_est_peak_max_rad_s",
        "final_theta_err_rad", "closed_loop_fraction"]


def run(cmd):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, cmd))} failed: {p.stderr.strip()}")


def columns(path: Path, names):
    with open(path, newline="") as f:
        r = csv.reader(f)
        head = next(r)
        idx = [head.index(n) for n in names]
        return [[float(row[i]) for i in idx] for row in r]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", action="append",
                    help="scenario file (repeatable; default: paper000_ideal and paper000_experiment)")
    ap.add_argument("--float-build", default=str(ROOT / "build/host"))
    ap.add_argument("--fixed-build", default=str(ROOT / "build/host-fixed"))
    ap.add_argument("--check", type=float, default=None, metavar="RAD")
    args = ap.parse_args()
    scenarios = [Path(s) for s in (args.scenario or [ROOT / "sim/scenarios/paper000_ideal.toml",
                                                      ROOT / "sim/scenarios/paper000_experiment.toml"])]
    builds = {"float": Path(args.float_build), "fixed": Path(args.fixed_build)}
    for name, b in builds.items():
        for exe in ("sim/motorsim", "sim/drive_replay"):
            if not (b / exe).is_file():
                print(f"compare_builds.py: skipped: {b / exe} missing (build the {name} host preset first)")
                return 77
    results = {}
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for sc in scenarios:
            res = {}
            for name, b in builds.items():
                try:
                    r = motorsim.run(b / "sim/motorsim", sc, out=tmp / f"{sc.stem}_{name}")
                except motorsim.MotorsimError as e:
                    raise RuntimeError(f"{name} build: {e}") from None
                res[name] = r.metrics
            currents = tmp / f"{sc.stem}_float" / f"{sc.stem}.csv"
            rep = {}
            for name, b in builds.items():
                run([b / "sim/drive_replay", sc, currents, tmp / f"replay_{name}.csv"])
                rep[name] = columns(tmp / f"replay_{name}.csv", ["mode", "theta_est"])
            both_cl = [(a[1], f[1]) for a, f in zip(rep["float"], rep["fixed"]) if a[0] == 1 and f[0] == 1]
            d_cl = max((abs(a - f) for a, f in both_cl), default=0.0)
            d_all = max(abs(a[1] - f[1]) for a, f in zip(rep["float"], rep["fixed"]))
            res["theta_est_diff_closed_loop_rad"] = d_cl
            res["theta_est_diff_all_rad"] = d_all
            worst = max(worst, d_cl)
            results[sc.stem] = res
    print(f"{'metric':<28} " + " ".join(f"{s + ' ' + n:>28}" for s in results for n in ("float", "fixed")))
    for k in KEYS:
        print(f"{k:<28} " + " ".join(f"{results[s][n][k]:>28.5g}" for s in results for n in ("float", "fixed")))
    for s, r in results.items():
        print(f"{s}: max |theta_est float - theta_est fixed| on the same currents: "
              f"{r['theta_est_diff_closed_loop_rad']:.3g} rad in closed loop, {r['theta_est_diff_all_rad']:.3g} rad overall")
    print(json.dumps({"bench": "compare_builds", "results": results}))
    if args.check is not None and not worst < args.check:
        print(f"compare_builds.py: theta_est differs by {worst:.3g} rad >= {args.check} rad", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
