#!/usr/bin/env python3
"""Cross-check of our inverter's dead-time error against gym-electric-motor.

gym-electric-motor (GEM 3.0.3) models a converter's interlocking (dead)
time in its continuous converters: each leg's duty loses
sign(i_leg) * t_interlock / tau (physical_systems/converters.py,
ContDynamicallyAveragedConverter._interlock; the B6 bridge's legs are
ContTwoQuadrantConverters), with tau its step, i.e. one switching period per
step, and the leg current taken where the step starts. Ours
(sim/model/inverter.h) loses sgn(i) t_dead f_pwm of duty, the current taken
at the sampling instant (model/hal_sw_plant.cpp). With f_pwm = 1/Ts and the
hard sign (i_transition_A = 0) the two are the same law, so one seeded
sequence of commanded leg voltages (a rotating vector, so the currents
cross zero, plus uniform noise) goes through both:

  ours   tests/sim/inverter_replay: our inverter, then our plant (RK4, one
         step per sample), at a held speed;
  GEM    tools/crosscheck/gem_replay.py, model mode with the interlocking
         time: GEM's ContB6BridgeConverter, PMSM equations and DOP853 solver
         (rtol = atol = 1e-12).

It reports (and checks) the agreement of the applied leg voltages and of
the phase currents, and the size of the effect being checked: the same
sequence through each without its dead time (ours --ideal, GEM with
interlocking time 0). The check passes when the currents agree within
--tol (default 1e-6 A, as tools/crosscheck/crosscheck_pmsm.py) and the
dead time moves the currents by more than 1000 times that.

usage: crosscheck_inverter.py --inverter-replay BIN --motor FILE.toml
         [--omega W] [--n N] [--ts TS] [--dead-time-s T] [--seed S] [--tol A]
Exit 0 if they agree, 1 if not, 2 on bad input, 3 if GEM is missing.
"""
from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import tomllib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gem_replay  # noqa: E402

PHASES = ("i_a_A", "i_b_A", "i_c_A")


def commands(n: int, ts: float, omega_e: float, seed: int) -> np.ndarray:
    """A rotating 8 V vector at the rotor's electrical speed, 0.6 rad ahead,
    plus uniform +-2 V per leg and sample: currents of a few amperes that
    cross zero every half electrical period."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * ts
    th = omega_e * t + 0.6
    v = np.stack([8.0 * np.cos(th - 2.0 * math.pi * j / 3.0) for j in range(3)], axis=1)
    return v + rng.uniform(-2.0, 2.0, size=(n, 3))


def run_ours(binary, motor, v, omega, ts, vdc, dead, ideal):
    with tempfile.TemporaryDirectory() as d:
        vin = os.path.join(d, "v.csv")
        iout = os.path.join(d, "i.csv")
        np.savetxt(vin, v, delimiter=",", header="v_a_V,v_b_V,v_c_V", comments="", fmt="%.17g")
        cmd = [binary, "--motor", motor, "--in", vin, "--out", iout, "--omega", repr(omega), "--ts", repr(ts),
               "--vdc", repr(vdc), "--dead-time-s", repr(dead)]
        if ideal:
            cmd.append("--ideal")
        subprocess.run(cmd, check=True)
        return np.genfromtxt(iout, delimiter=",", names=True)


def max_diff(a, b, keys_a, keys_b=None, rows=None):
    keys_b = keys_b or keys_a
    sl = slice(None) if rows is None else slice(0, rows)
    return max(float(np.max(np.abs(np.asarray(a[ka])[sl] - np.asarray(b[kb])[sl]))) for ka, kb in zip(keys_a, keys_b))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--inverter-replay", required=True)
    ap.add_argument("--motor", required=True)
    ap.add_argument("--omega", type=float, default=10.0, help="mechanical speed [rad/s]")
    ap.add_argument("--n", type=int, default=12000, help="samples (0.6 s: three electrical periods at 10 rad/s)")
    ap.add_argument("--ts", type=float, default=5e-5, help="sample = PWM period [s] (20 kHz)")
    ap.add_argument("--dead-time-s", type=float, default=500e-9,
                    help="dead time [s] (default: this project's VESC 6 image, 500 ns)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--tol", type=float, default=1e-6)
    a = ap.parse_args()
    with open(a.motor, "rb") as f:
        m = tomllib.load(f)
    if m.get("type") != "pmsm3":
        print(f"error: {a.motor}: type: the cross-check needs a pmsm3 motor", file=sys.stderr)
        return 2
    if not (a.n >= 2 and a.ts > 0 and 0 <= a.dead_time_s < 0.5 * a.ts):
        print("error: --n >= 2, --ts > 0, 0 <= --dead-time-s < ts/2", file=sys.stderr)
        return 2
    params = {"R_ohm": m["R_ohm"], "L_d_H": m["L_d_H"], "L_q_H": m["L_q_H"], "Phi_Wb": m["Phi_Wb"],
              "n_p": m["n_p"], "J_kgm2": m["J_kgm2"]}
    v = commands(a.n, a.ts, m["n_p"] * a.omega, a.seed)
    vdc = 32.0  # the legs swing +-16 V; the commands stay within +-10.1 V (duties 0.18..0.82)
    try:
        gem_dead = gem_replay.replay(params, v, a.omega, a.ts, 0.0, interlocking_time_s=a.dead_time_s, u_dc_V=vdc)
        gem_ideal = gem_replay.replay(params, v, a.omega, a.ts, 0.0, u_dc_V=vdc)
    except ImportError as e:
        print(f"error: gym-electric-motor not available: {e}", file=sys.stderr)
        return 3
    ours_dead = run_ours(a.inverter_replay, a.motor, v, a.omega, a.ts, vdc, a.dead_time_s, False)
    ours_ideal = run_ours(a.inverter_replay, a.motor, v, a.omega, a.ts, vdc, a.dead_time_s, True)

    # GEM does not compute the last row's voltage (it only moves the state past the log)
    rows = a.n - 1
    gem_v = {f"v_{x}_V": gem_dead["v_applied_V"][:, j] for j, x in enumerate("abc")}
    dv = max_diff(ours_dead, gem_v, ("v_a_V", "v_b_V", "v_c_V"), rows=rows)
    di = max_diff(ours_dead, gem_dead, PHASES)
    di_ideal = max_diff(ours_ideal, gem_ideal, PHASES)
    effect_ours = max_diff(ours_dead, ours_ideal, PHASES)
    effect_gem = max_diff(gem_dead, gem_ideal, PHASES)
    err_v = vdc * a.dead_time_s / a.ts
    # the error flips with each leg current's sign: count the flips exercised
    flips = sum(int(np.sum(np.diff(np.sign(np.asarray(gem_dead[ph]))) != 0)) for ph in PHASES)
    peak = max(float(np.max(np.abs(gem_dead[ph]))) for ph in PHASES)
    print(f"crosscheck_inverter: {a.n} samples of {a.ts:g} s at {a.omega:g} rad/s, V_dc {vdc:g} V, "
          f"dead time {a.dead_time_s:g} s (error {err_v:.4g} V per leg, its sign flipped {flips} times over the legs): "
          f"applied voltages max |v_ours - v_gem| = {dv:.3g} V; currents max |i_ours - i_gem| = {di:.3g} A "
          f"(without dead time {di_ideal:.3g} A); the dead time moves the currents by {effect_ours:.3g} A (ours), "
          f"{effect_gem:.3g} A (GEM); peak current {peak:.3g} A, tolerance {a.tol:g} A")
    ok = di <= a.tol and effect_ours > 1000.0 * a.tol and effect_gem > 1000.0 * a.tol
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
