#!/usr/bin/env python3
"""Cross-check of our PMSM plant against gym-electric-motor (GEM).

One seeded sequence of random held leg voltages goes through our plant
(sim/replay/plant_replay, RK4 on the alpha-beta state, one step per sample)
and through GEM's PMSM equations (tools/crosscheck/gem_replay.py, model mode:
GEM's motor, transforms and converter, integrated by GEM's DOP853 solver at
rtol = atol = 1e-12), both at a constant speed with the voltage held in the
stator frame as an inverter holds it. The phase currents must agree within
--tol (default 1e-6 A: six orders below the 5 mA current noise of the
benchmark, and far above the solvers' own errors, ~1e-12 A).

usage: crosscheck_pmsm.py --plant-replay BIN --motor FILE.toml [--omega W]
                          [--n N] [--ts TS] [--seed S] [--tol A]
Exit 0 if they agree, 1 if not, 2 on bad input, 3 if GEM is missing.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import tomllib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gem_replay  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plant-replay", required=True)
    ap.add_argument("--motor", required=True)
    ap.add_argument("--omega", type=float, default=10.0, help="mechanical speed [rad/s]")
    ap.add_argument("--n", type=int, default=2000, help="samples")
    ap.add_argument("--ts", type=float, default=1e-4)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--tol", type=float, default=1e-6)
    a = ap.parse_args()
    with open(a.motor, "rb") as f:
        m = tomllib.load(f)
    if m.get("type") != "pmsm3":
        print(f"error: {a.motor}: type: the cross-check needs a pmsm3 motor", file=sys.stderr)
        return 2
    params = {"R_ohm": m["R_ohm"], "L_d_H": m["L_d_H"], "L_q_H": m["L_q_H"], "Phi_Wb": m["Phi_Wb"],
              "n_p": m["n_p"], "J_kgm2": m["J_kgm2"]}
    rng = np.random.default_rng(a.seed)
    v = rng.uniform(-20.0, 20.0, size=(a.n, 3))
    try:
        gem = gem_replay.replay(params, v, a.omega, a.ts, 0.0)
    except ImportError as e:
        print(f"error: gym-electric-motor not available: {e}", file=sys.stderr)
        return 3
    with tempfile.TemporaryDirectory() as d:
        vin = os.path.join(d, "v.csv")
        iout = os.path.join(d, "i.csv")
        np.savetxt(vin, v, delimiter=",", header="v_a_V,v_b_V,v_c_V", comments="", fmt="%.17g")
        subprocess.run([a.plant_replay, "--motor", a.motor, "--in", vin, "--out", iout, "--omega", repr(a.omega),
                        "--ts", repr(a.ts)], check=True)
        ours = np.genfromtxt(iout, delimiter=",", names=True)
    diff = 0.0
    peak = 0.0
    for ph in ("i_a_A", "i_b_A", "i_c_A"):
        diff = max(diff, float(np.max(np.abs(ours[ph] - gem[ph]))))
        peak = max(peak, float(np.max(np.abs(gem[ph]))))
    print(f"crosscheck_pmsm: {a.n} samples at {a.omega} rad/s: max |i_ours - i_gem| = {diff:.3g} A "
          f"(peak current {peak:.3g} A, tolerance {a.tol:g} A)")
    return 0 if diff <= a.tol else 1


if __name__ == "__main__":
    sys.exit(main())
