#!/usr/bin/env python3
"""Start from any rotor angle (issue 10): runs a paper-000 scenario with the
plant's initial angle at N values spread over one tooth pitch (2 pi / n_p)
and requires, for each:

  * motorsim exit 0: no fault and every [expect] threshold of the scenario
    met (tracking counted over the closed-loop samples, final error against
    the commanded end point relative to the equilibrium the alignment found);
  * no phase current above i_trip_A (no over-current, not even below the
    trip's sampling);
  * the equilibrium found (align_offset_rad) is the nearest one to the start
    angle (at exactly half a pitch both neighbours are nearest).

usage: check_start_angles.py MOTORSIM SCENARIO.toml [--angles N] [--n-p 50]
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("motorsim")
    ap.add_argument("scenario")
    ap.add_argument("--angles", type=int, default=16)
    ap.add_argument("--n-p", type=int, default=50, help="pole pairs of the scenario's motor")
    ap.add_argument("--i-trip", type=float, default=4.5, help="[limits] i_trip_A of the scenario")
    ap.add_argument("extra", nargs="*", help="more motorsim arguments (after --)")
    a = ap.parse_args()
    pitch = 2.0 * math.pi / a.n_p
    bad = []
    print(f"{'theta0 [rad]':>13} {'elec [deg]':>10} {'rc':>3} {'track':>9} {'est':>9} {'final':>9} "
          f"{'offset':>9} {'|i|max':>7} {'align [s]':>9}")
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.angles):
            th0 = k * pitch / a.angles
            out = os.path.join(tmp, f"m{k}.json")
            r = subprocess.run([a.motorsim, "--scenario", a.scenario, "--theta0-rad", repr(th0),
                                "--metrics-out", out, "--quiet", *a.extra],
                               capture_output=True, text=True)
            if not os.path.exists(out):
                bad.append(f"theta0 {th0:.6f}: no metrics (exit {r.returncode}): {r.stderr.strip()}")
                continue
            m = json.load(open(out))
            print(f"{th0:13.6f} {math.degrees(th0 * a.n_p):10.1f} {r.returncode:3d} "
                  f"{m['theta_track_max_rad']:9.5f} {m['theta_est_max_rad']:9.5f} "
                  f"{m['final_theta_err_rad']:9.2e} {m['align_offset_rad']:9.5f} "
                  f"{m['max_abs_current_A']:7.3f} {m['align_time_s']:9.4f}")
            if r.returncode != 0:
                bad.append(f"theta0 {th0:.6f}: exit {r.returncode}: {r.stderr.strip()}")
            if m["max_abs_current_A"] > a.i_trip:
                bad.append(f"theta0 {th0:.6f}: phase current {m['max_abs_current_A']:.4g} A > i_trip {a.i_trip} A")
            nearest = [round(th0 / pitch)]
            if abs(th0 / pitch - math.floor(th0 / pitch) - 0.5) < 1e-9:
                nearest = [math.floor(th0 / pitch), math.ceil(th0 / pitch)]
            teeth = m["align_offset_rad"] / pitch
            if not any(abs(teeth - n) < 1e-6 for n in nearest):
                bad.append(f"theta0 {th0:.6f}: aligned to {teeth:.3f} pitches, the nearest equilibrium is {nearest}")
    for b in bad:
        print("FAILED", b)
    print(f"{a.angles - len(set(b.split(':')[0] for b in bad))}/{a.angles} start angles pass")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
