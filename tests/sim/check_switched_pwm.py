#!/usr/bin/env python3
"""The switched legs against the averaged inverter on a shipped hardware-like
scenario (issue 30, [inverter] pwm): runs SCENARIO three times with motorsim,

  averaged   as shipped ([inverter] pwm absent: the averaged legs),
  switched   with [inverter] pwm = "switched",
  no comp.   averaged, the drive's dead-time compensation off
             ([inverter] compensation = false),

prints the main metrics of all three and requires

  * the switched run to pass the scenario's [expect] (motorsim exit 0);
  * on every main metric, |switched - averaged| <= |no comp. - averaged|.

Why that bound. The two models differ only in how the dead time's voltage
error reaches the motor: the averaged legs apply V_dc t_dead f_pwm g(i/i_tr)
against each leg's current held over the period (g smooth through zero over
i_tr, the node capacitance's commutation); the switched legs apply it edge by
edge with the sign of the current at each edge (no node capacitance: the
ripple alone smooths the zero crossing), and the currents carry the ripple,
which is zero at the sampling instant of ideal centre-aligned PWM. Per leg
and carrier period the difference is (sgn(i) - g(i/i_tr)) V_dc t_dead f_pwm
plus the edges' signs within the period, never more than the whole error
V_dc t_dead f_pwm (0.48 V on the VESC 6's 48 V, 500 ns, 20 kHz), and that
only near a leg's zero crossing. The run without compensation leaves the
whole error on every leg at all times: a larger disturbance of the same
kind, so a metric the switched model moves further than that would mean
the averaged model misrepresents the switching by more than its own
nonlinearity is worth.

usage: check_switched_pwm.py MOTORSIM SCENARIO.toml METRIC [METRIC ...]
Standard library only.
"""
import json
import os
import re
import subprocess
import sys
import tempfile


def variant(src: str, dst: str, extra: str) -> None:
    """SCENARIO with `extra` lines at the top of [inverter], its relative
    file paths made absolute (the copy lives elsewhere)."""
    base = os.path.dirname(os.path.abspath(src))
    text = open(src).read()
    text = re.sub(r'^(file\s*=\s*")(\.\.?/[^"]*)"', lambda m: m.group(1) + os.path.normpath(os.path.join(base, m.group(2))) + '"',
                  text, flags=re.M)
    if text.count("\n[inverter]\n") != 1:
        sys.exit(f"check_switched_pwm: {src}: expected one [inverter] table")
    text = text.replace("\n[inverter]\n", "\n[inverter]\n" + extra + "\n")
    with open(dst, "w") as f:
        f.write(text)


def run(motorsim: str, scenario: str, out: str):
    r = subprocess.run([motorsim, "--scenario", scenario, "--metrics-out", out, "--quiet"], capture_output=True, text=True)
    return r, (json.load(open(out)) if os.path.exists(out) else None)


def main() -> int:
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    motorsim, scenario, metrics = sys.argv[1], sys.argv[2], sys.argv[3:]
    bad = []
    with tempfile.TemporaryDirectory() as tmp:
        sw = os.path.join(tmp, "switched.toml")
        nc = os.path.join(tmp, "no_comp.toml")
        variant(scenario, sw, 'pwm = "switched"')
        variant(scenario, nc, "compensation = false")
        runs = {}
        for name, path in (("averaged", scenario), ("switched", sw), ("no comp.", nc)):
            r, m = run(motorsim, path, os.path.join(tmp, name.replace(" ", "_").replace(".", "") + ".json"))
            if m is None:
                print(f"FAIL: {name}: no metrics (exit {r.returncode}): {r.stderr.strip()}")
                return 1
            runs[name] = (r, m)
    if runs["switched"][0].returncode != 0:
        bad.append(f"the switched run misses the scenario's [expect] (exit {runs['switched'][0].returncode}): "
                   f"{runs['switched'][0].stderr.strip()}")
    avg, swm, ncm = runs["averaged"][1], runs["switched"][1], runs["no comp."][1]
    print(f"{os.path.basename(scenario)}")
    print(f"{'metric':28s} {'averaged':>13} {'switched':>13} {'no comp.':>13} {'|sw - avg|':>11} {'bound':>11}")
    for k in metrics:
        if k not in avg:
            bad.append(f"{k}: not a metric of this scenario")
            continue
        d_sw, d_nc = abs(swm[k] - avg[k]), abs(ncm[k] - avg[k])
        print(f"{k:28s} {avg[k]:13.6g} {swm[k]:13.6g} {ncm[k]:13.6g} {d_sw:11.3g} {d_nc:11.3g}")
        if not d_sw <= d_nc:
            bad.append(f"{k}: switched {swm[k]:.6g} differs from averaged {avg[k]:.6g} by {d_sw:.3g}, more than the "
                       f"uncompensated dead time moves it ({d_nc:.3g})")
    print(f"{'realtime_factor':28s} {avg['realtime_factor']:13.4g} {swm['realtime_factor']:13.4g} "
          f"{ncm['realtime_factor']:13.4g}")
    for b in bad:
        print("FAIL:", b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
