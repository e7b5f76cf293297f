#!/usr/bin/env python3
"""Issue 31: paper 002's drive started sensorless from 16 unknown rotor
angles ([paper002] hfi_find_angle = true): runs the scenario with the
plant's initial angle (motorsim --theta0-rad) at 2 pi k / (16 n_p),
k = 0..15, one electrical period, and requires, for each:

  * motorsim exit 0: no fault and every [expect] threshold of the scenario;
  * the polarity test decided (metric hfi_start_polarity +1 or -1);
  * right polarity: from --t-check on (after the lock and the test) the
    EKF's angle within --err-e electrical rad of the rotor's, compared
    modulo 2 pi / n_p (the turn among the n_p is unknown and of no matter);
  * no backward motion: the rotor's unwrapped angle never below its start
    by more than --back;
  * the final speed within --final-tol of the reference's end.

With --expect-refusal (a plant without the magnet's bias) every start must
instead end in fault 12 (loss-of-lock, the polarity test undecided), the
metric hfi_start_polarity 0, motorsim's exit status 3, and the rotor not
moved by more than --back before the fault (after it the scenario's load
turns the unpowered rotor).

With --injection-off (motorsim --estimator flux: paper 001's flux observer
alone, the variant before the injection, told each start angle, which the
injection's drive is not) every start must end in a drive fault (exit 3):
the flux observer has no information at standstill.

usage: check_hfi_start16.py MOTORSIM SCENARIO.toml [--expect-refusal | --injection-off] [--seed N]
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile


def wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("motorsim")
    ap.add_argument("scenario")
    ap.add_argument("--angles", type=int, default=16)
    ap.add_argument("--n-p", type=int, default=4, help="pole pairs of the scenario's motor")
    ap.add_argument("--t-check", type=float, default=0.35,
                    help="s: the start over (0.1 s lock, 0.08 s rest, 0.164 s test: 0.344 s)")
    ap.add_argument("--err-e", type=float, default=0.25, help="rad electrical: the estimate's bound after the start")
    ap.add_argument("--back", type=float, default=0.01, help="rad mechanical: the largest backward excursion")
    ap.add_argument("--final", type=float, default=10.0, help="rad/s: the reference's end")
    ap.add_argument("--final-tol", type=float, default=2.0)
    ap.add_argument("--expect-refusal", action="store_true")
    ap.add_argument("--injection-off", action="store_true",
                    help="the flux variant told the angle: every start must end in a drive fault")
    ap.add_argument("--seed", type=int, default=None, help="motorsim --seed (default: the scenario's)")
    a = ap.parse_args()
    if a.expect_refusal and a.injection_off:
        sys.exit("check_hfi_start16.py: --expect-refusal and --injection-off exclude each other")
    if a.angles < 1 or a.n_p < 1:
        sys.exit("check_hfi_start16.py: --angles and --n-p must be >= 1")
    bad = []
    print(f"{'theta0 [rad]':>12} {'elec [deg]':>10} {'rc':>3} {'fault':>5} {'at [s]':>7} {'pol':>4} {'err_e max':>10} "
          f"{'back':>8} {'final':>8}")
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.angles):
            th0 = 2.0 * math.pi * k / (a.angles * a.n_p)
            out = os.path.join(tmp, f"k{k}")
            js = os.path.join(out, "m.json")
            cmd = [a.motorsim, "--scenario", a.scenario, "--theta0-rad", repr(th0), "--out", out,
                   "--metrics-out", js, "--no-plot", "--quiet"]
            if a.seed is not None:
                cmd += ["--seed", str(a.seed)]
            if a.expect_refusal or a.injection_off:
                cmd.append("--no-expect")
            if a.injection_off:
                cmd += ["--estimator", "flux"]
            p = subprocess.run(cmd, capture_output=True, text=True)
            if not os.path.exists(js):
                bad.append(f"k={k}: no metrics (rc {p.returncode}): {p.stderr.strip()[-300:]}")
                continue
            m = json.load(open(js))
            m = m.get("metrics", m)
            stem = os.path.splitext(os.path.basename(a.scenario))[0]
            rows = list(csv.DictReader(open(os.path.join(out, stem + ".csv"))))
            t = [float(r["t_s"]) for r in rows]
            th = [float(r["theta_rad"]) for r in rows]
            te = [float(r["theta_est_rad"]) for r in rows]
            # the rotor unwrapped from its start
            pos, acc, prev = [], 0.0, th[0]
            for x in th:
                acc += wrap(x - prev)
                prev = x
                pos.append(acc)
            back = -min(0.0, min(pos))
            err = [abs(wrap(a.n_p * (y - x))) for x, y, tt in zip(th, te, t) if tt >= a.t_check]
            err_max = max(err) if err else float("nan")
            pol = m.get("hfi_start_polarity")
            fault = m.get("fault")
            final = m.get("final_omega_rad_s", float("nan"))
            at = re.search(r"drive fault \d+ \([a-z-]+\) at t = ([0-9.]+) s", p.stderr)
            t_f = at.group(1) if at else "-"
            print(f"{th0:12.5f} {math.degrees(a.n_p * th0):10.1f} {p.returncode:3d} {fault!s:>5} {t_f:>7} "
                  f"{pol!s:>4} {err_max:10.4f} {back:8.4f} {final:8.2f}")
            why = []
            if a.injection_off:
                if p.returncode != 3:
                    why.append(f"exit {p.returncode}, not 3: the flux variant held the start without the injection")
            elif a.expect_refusal:
                if p.returncode != 3:
                    why.append(f"exit {p.returncode}, not 3 (a drive fault)")
                if fault != 12:
                    why.append(f"fault {fault}, not 12 (loss-of-lock: the polarity test undecided)")
                if pol != 0:
                    why.append(f"hfi_start_polarity {pol}, not 0 (undecided)")
                # up to the fault: after it the load turns the unpowered rotor
                n_f = next((i for i, r in enumerate(rows) if float(r["fault"]) != 0.0), len(rows))
                moved = max([abs(x) for x in pos[:n_f]] or [0.0])
                if moved > a.back:
                    why.append(f"the rotor moved {moved:.4f} rad > {a.back} before the fault")
            else:
                if p.returncode != 0:
                    why.append(f"exit {p.returncode}: {p.stderr.strip()[-200:]}")
                if pol not in (1, -1):
                    why.append(f"hfi_start_polarity {pol}: the test did not decide")
                if not err_max <= a.err_e:
                    why.append(f"the estimate {err_max:.4f} rad (electrical) off after {a.t_check} s > {a.err_e}")
                if back > a.back:
                    why.append(f"ran backwards {back:.4f} rad > {a.back}")
                if not abs(final - a.final) <= a.final_tol:
                    why.append(f"final speed {final} not within {a.final_tol} of {a.final}")
            if why:
                bad.append(f"k={k} (theta0 {th0:.5f} rad): " + "; ".join(why))
    if bad:
        print("FAILED:\n  " + "\n  ".join(bad))
        return 1
    print(f"ok: {a.angles} starts")
    return 0


if __name__ == "__main__":
    sys.exit(main())
