#!/usr/bin/env python3
"""Our simulator against gym-electric-motor (GEM 3.0.3) on paper 001's 10 s
speed benchmark, in one run, side by side.

What each line of the table computes (N = 100,000 samples of Ts = 1e-4 s,
10 s of simulated time; the motor is the scenario's motor file, for the
benchmark sim/motors/paper001_pmsm.toml: R 0.225 ohm, L_d = L_q 3.8 mH,
Phi 0.17 Wb, n_p 3; 48 V bus):

ours, closed loop (headline)
    ``motorsim --scenario S --metrics-out X.json --quiet``: each period the
    current sensor model (5 mA Gaussian noise, 14-bit ADC: Box-Muller on
    mt19937_64), the paper-001 drive (flux observer, I&I speed/load
    observer, IDA-PBC, speed profile, supervisor; float build), the
    amplifier clamp, the plant (alpha-beta currents, speed and angle, one
    RK4 step per sample, load-torque profile) and the benchmark metrics.
    Wall time = motorsim's own ``wall_time_s``: the N-period loop, without
    process start, scenario parsing and drive design (those are in the
    "end to end" column: the process's wall time). Median of --repeats runs.
ours, plant only (unless --no-plant-replay)
    ``plant_replay --timing``: the same N held phase voltages through the
    same plant (sim/model/pm_plant, RK4, one step per sample) with our run's
    speed trajectory (each sample's mean speed, held over the sample), timed
    by its own loop timer (the integration loop alone, no CSV I/O): the like
    of GEM's lines, the same run through our simulator. Its currents must
    match the closed-loop run's (they do to 1e-5 A, the CSV's digits).
GEM env, default solver
    ``gem.make("Cont-CC-PMSM-v0", ...)`` with GEM's
    PermanentMagnetSynchronousMotor given the same parameters, its
    ContB6BridgeConverter and IdealVoltageSupply(u_nominal = bus voltage),
    tau = Ts, GEM's ExternalSpeedLoad whose speed profile is our run's
    rotor speed (the CSV's omega_rad_s, linear between samples), and
    everything else GEM's defaults (ode_solver: ScipyOdeSolver, i.e.
    scipy.integrate.ode "dopri5" with scipy's rtol 1e-6 / atol 1e-12; the
    class docstring says EulerSolver but the code uses this; the default
    Wiener-process current reference, reward and current constraint), except
    visualization=None (no dashboard; a user timing a run turns it off).
    Actions: our run's applied leg voltages (CSV v_a_V, v_b_V, v_c_V,
    row k held over [k Ts, (k+1) Ts)) divided by half the bus voltage.
    Wall time: env.reset() + N-1 env.step() calls (the state after the last
    row is not needed, as in our log); "end to end" adds building the env
    (GEM's import time is printed apart; reading our CSV is in neither).
GEM physical system, default solver (unless --no-gem-system)
    The same components as a bare SynchronousMotorSystem driven by
    system.simulate(action): GEM's plant without the env layer (reference,
    reward, constraint monitor, gymnasium wrappers), default solver.
GEM env, DOP853 1e-12 (only with --accurate; ~150 s)
    The env line with ode_solver=ScipySolveIvpSolver(method="DOP853",
    rtol=atol=1e-12), the solver of our cross-check (tools/crosscheck).

Both sides see the same voltages and the same speed trajectory, so their
phase currents must agree: each GEM line reports max |i_GEM - i_ours| over
the run and the three phases against the plant currents in our CSV
(i_a_A..i_c_A; GEM's i_abc rebuilt from its i_sd, i_sq and end-of-step
angle). GEM's env turns the abc voltage into dq once per step at the step's
start angle and holds u_dq, so the applied voltage rotates with the rotor
within a step (an O(omega_el Ts) error): expect ~0.05 A at 120 rpm, not
the 1e-10 A of the cross-check, which holds the voltage in the stator frame
(the difference is GEM's: with GEM stepping at Ts/10 it drops tenfold).
--tol (0.25 A) only catches a run that is not the same run.

Ratio column: the line's wall time over ours (closed loop): how many times
faster ours is. Per sample ours computes more than GEM's plant (the sensor
model, the drive and the metrics on top of the plant); GEM's env adds its
reference generator, reward and constraint check, its physical-system line
only the plant. The ratio is a benchmark figure taken on whatever machine
runs it: the machine and its 1-minute load average are printed with it.

usage: sim_speed.py [--motorsim BIN] [--plant-replay BIN] [--scenario TOML]
                    [--repeats N] [--accurate] [--no-gem-system]
                    [--no-plant-replay] [--gem-samples N] [--markdown]
                    [--json FILE]
Exit 0 ok, 1 a run failed or the currents disagree (> --tol A),
2 bad input, 3 GEM not importable.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # tools/: the toolbox
from lib import motorsim as motorsim_lib  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEF_MOTORSIM = os.path.join(REPO, "build", "host", "sim", "motorsim")
DEF_PLANT_REPLAY = os.path.join(REPO, "build", "host", "sim", "plant_replay")
# plant_replay on our run's voltages and speeds gives its currents to the
# CSV's 10 digits (1e-5 A measured): anything near a mA is not the same run
REPLAY_TOL_A = 1e-3
DEF_SCENARIO = os.path.join(REPO, "sim", "scenarios", "paper001_benchmark.toml")
CSV_COLS = ("t_s", "omega_rad_s", "v_a_V", "v_b_V", "v_c_V", "i_a_A", "i_b_A", "i_c_A")


class BenchError(RuntimeError):
    """A run failed (exit 1)."""


# ----------------------------------------------------------------------------- inputs


def load_setup(scenario_path):
    """Scenario + its motor file -> dict of what both sides need."""
    with open(scenario_path, "rb") as f:
        sc = tomllib.load(f)
    motor_path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(scenario_path)),
                                               sc["motor"]["file"]))
    with open(motor_path, "rb") as f:
        m = tomllib.load(f)
    if m.get("type") != "pmsm3":
        raise ValueError(f"{motor_path}: type: GEM's PMSM needs a pmsm3 motor")
    if "speed" not in sc:
        raise ValueError(f"{scenario_path}: no [speed] section: not a speed-drive scenario")
    run = sc["run"]
    return dict(
        scenario=os.path.abspath(scenario_path), motor_file=motor_path,
        duration_s=float(run["duration_s"]), ts_s=float(run["Ts_s"]),
        theta0_e=float(run.get("theta0_rad", 0.0)) * int(m["n_p"]),
        v_bus_V=float(sc["supply"]["v_bus_V"]),
        i_trip_A=float(sc.get("limits", {}).get("i_trip_A", 20.0)),
        R=float(m["R_ohm"]), Ld=float(m["L_d_H"]), Lq=float(m["L_q_H"]), Phi=float(m["Phi_Wb"]),
        n_p=int(m["n_p"]), J=float(m["J_kgm2"]),
    )


def read_run_csv(path):
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    missing = [c for c in CSV_COLS if c not in header]
    if missing:
        raise BenchError(f"{path}: missing column(s) {', '.join(missing)}")
    idx = [header.index(c) for c in CSV_COLS]
    a = np.loadtxt(path, delimiter=",", skiprows=1, usecols=idx, ndmin=2)
    return {c: a[:, k].copy() for k, c in enumerate(CSV_COLS)}


# ----------------------------------------------------------------------------- ours


def _motorsim(motorsim, scenario, what, **kw):
    """One motorsim run through the toolbox (tools/lib/motorsim.py)."""
    try:
        return motorsim_lib.run(motorsim, scenario, **kw)
    except motorsim_lib.MotorsimError as e:
        raise BenchError(f"{what}: {e}") from None


def run_ours_csv(motorsim, setup, out_dir):
    """One motorsim run writing the CSV: the voltages, speed and currents for GEM."""
    r = _motorsim(motorsim, setup["scenario"], "motorsim (CSV run)", out=out_dir)
    return read_run_csv(str(r.csv))


def time_ours_closed_loop(motorsim, setup, tmp, repeats):
    loops, procs = [], []
    for _ in range(repeats):
        r = _motorsim(motorsim, setup["scenario"], "motorsim")
        procs.append(r.wall_s)
        m = r.metrics
        loops.append(float(m["wall_time_s"]))
        n = int(m["n_samples"])
    return dict(wall_s=statistics.median(loops), e2e_s=statistics.median(procs), n=n,
                runs=loops, sim_s=float(m["sim_time_s"]))


def time_ours_plant_replay(plant_replay, setup, data, tmp, repeats):
    """Our plant alone on the same run: the same held voltages and our run's
    speed trajectory (each sample's mean speed, as GEM's ExternalSpeedLoad
    follows it), through plant_replay; its own loop timer (--timing: the
    integration loop, no CSV I/O, no formatting). Its currents are checked
    against the closed-loop run's (di_A)."""
    vin = os.path.join(tmp, "v.csv")
    iout = os.path.join(tmp, "i.csv")
    w = np.asarray(data["omega_rad_s"], dtype=float)
    w_mid = 0.5 * (w + np.append(w[1:], w[-1]))
    v = np.column_stack([data["v_a_V"], data["v_b_V"], data["v_c_V"], w_mid])
    np.savetxt(vin, v, delimiter=",", header="v_a_V,v_b_V,v_c_V,omega_rad_s", comments="", fmt="%.17g")
    loops, procs = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = subprocess.run([plant_replay, "--motor", setup["motor_file"], "--in", vin, "--out", iout,
                            "--ts", repr(setup["ts_s"]), "--theta0-e", repr(setup["theta0_e"]), "--timing"],
                           capture_output=True, text=True)
        procs.append(time.perf_counter() - t0)
        if r.returncode != 0:
            raise BenchError(f"plant_replay exit {r.returncode}: {r.stderr.strip()}")
        loops.append(float(json.loads(r.stdout)["loop_s"]))
    cur = np.loadtxt(iout, delimiter=",", skiprows=1)
    ours = np.column_stack([data["i_a_A"], data["i_b_A"], data["i_c_A"]])
    if cur.shape[0] != ours.shape[0]:
        raise BenchError(f"plant_replay wrote {cur.shape[0]} rows for {ours.shape[0]} samples")
    di = float(np.max(np.abs(cur[:, 1:4] - ours)))
    return dict(wall_s=statistics.median(loops), e2e_s=statistics.median(procs), n=v.shape[0], di_A=di)


# ----------------------------------------------------------------------------- GEM


def _import_gem():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import gym_electric_motor as gem
        from gym_electric_motor import physical_systems as ps
        from gym_electric_motor.physical_systems.physical_systems import SynchronousMotorSystem
    return gem, ps, SynchronousMotorSystem


def _speed_profile(omega, ts):
    """Our recorded speed as GEM's speed_profile(t): linear between samples, held after the last."""
    w = [float(x) for x in omega]
    n = len(w)
    inv_ts = 1.0 / ts

    def profile(t):
        x = t * inv_ts
        if x <= 0.0:
            return w[0]
        k = int(x)
        if k >= n - 1:
            return w[-1]
        f = x - k
        return w[k] + f * (w[k + 1] - w[k])

    return profile


def _gem_components(ps, setup, data):
    u_dc = setup["v_bus_V"]
    w_lim = max(2.0 * float(np.max(np.abs(data["omega_rad_s"]))), 4e3 * math.pi / 30)
    i_lim = max(setup["i_trip_A"], 2.0 * float(np.max(np.abs(np.column_stack(
        [data["i_a_A"], data["i_b_A"], data["i_c_A"]])))))
    motor = ps.PermanentMagnetSynchronousMotor(
        motor_parameter=dict(r_s=setup["R"], l_d=setup["Ld"], l_q=setup["Lq"], psi_p=setup["Phi"],
                             p=setup["n_p"], j_rotor=setup["J"]),
        # limits/nominal values only normalise GEM's observations and bound its
        # current constraint; wide enough that nothing clips or terminates
        limit_values=dict(omega=w_lim, i=i_lim, u=u_dc),
        nominal_values=dict(omega=w_lim, i=i_lim, u=u_dc),
        motor_initializer=dict(states=dict(i_sd=0.0, i_sq=0.0,
                                           epsilon=math.remainder(setup["theta0_e"], 2 * math.pi))),
    )
    load = ps.ExternalSpeedLoad(speed_profile=_speed_profile(data["omega_rad_s"], setup["ts_s"]),
                                tau=setup["ts_s"])
    return motor, load


def _actions(data, u_dc):
    # Cont-B6C: leg voltage about the midpoint = action * u_dc / 2
    return np.column_stack([data["v_a_V"], data["v_b_V"], data["v_c_V"]]) * (2.0 / u_dc)


def _agreement(states, pos, data, n):
    """max |i_abc(GEM) - i_abc(ours)| and max |omega(GEM) - omega(ours)| over the first n samples."""
    i_d = states[:n, pos["i_sd"]]
    i_q = states[:n, pos["i_sq"]]
    eps = states[:n, pos["epsilon"]]
    i_al = i_d * np.cos(eps) - i_q * np.sin(eps)
    i_be = i_d * np.sin(eps) + i_q * np.cos(eps)
    s3 = math.sqrt(3.0) / 2.0
    gem_abc = (i_al, -0.5 * i_al + s3 * i_be, -0.5 * i_al - s3 * i_be)
    di = max(float(np.max(np.abs(g - data[c][:n]))) for g, c in zip(gem_abc, ("i_a_A", "i_b_A", "i_c_A")))
    dw = float(np.max(np.abs(states[:n, pos["omega"]] - data["omega_rad_s"][:n])))
    return di, dw


def time_gem_env(setup, data, n, solver=None):
    """GEM's Cont-CC-PMSM-v0 env over the first n rows; returns timings and agreement."""
    t_e2e = time.perf_counter()
    gem, ps, _ = _import_gem()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        motor, load = _gem_components(ps, setup, data)
        kw = {} if solver is None else dict(ode_solver=solver(ps))
        env = gem.make("Cont-CC-PMSM-v0", motor=motor, load=load,
                       supply=dict(u_nominal=setup["v_bus_V"]), tau=setup["ts_s"],
                       visualization=None, **kw)
        system = env.unwrapped.physical_system
        lim = np.asarray(system.limits, dtype=float)
        pos = system.state_positions
        act = _actions(data, setup["v_bus_V"])
        states = np.empty((n, len(lim)))
        solver_name = type(system._ode_solver).__name__
        t0 = time.perf_counter()
        c0 = time.process_time()
        (state, _ref), _info = env.reset(seed=1)
        states[0] = state
        for k in range(n - 1):
            (state, _ref), _r, term, trunc, _info = env.step(act[k])
            states[k + 1] = state
            if term or trunc:
                raise BenchError(f"GEM env terminated at step {k} (a constraint was violated)")
        wall = time.perf_counter() - t0
        cpu = time.process_time() - c0
        env.close()
    e2e = time.perf_counter() - t_e2e
    di, dw = _agreement(states * lim, pos, data, n)
    return dict(wall_s=wall, cpu_s=cpu, e2e_s=e2e, n=n, di_A=di, dw=dw, solver=solver_name)


def time_gem_system(setup, data, n):
    """GEM's SynchronousMotorSystem alone (no env layer), default solver."""
    t_e2e = time.perf_counter()
    gem, ps, SynchronousMotorSystem = _import_gem()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        motor, load = _gem_components(ps, setup, data)
        system = SynchronousMotorSystem(
            converter=ps.ContB6BridgeConverter(), motor=motor, load=load,
            supply=ps.IdealVoltageSupply(u_nominal=setup["v_bus_V"]),
            ode_solver=ps.ScipyOdeSolver(),  # the envs' default
            tau=setup["ts_s"])
        lim = np.asarray(system.limits, dtype=float)
        pos = system.state_positions
        act = _actions(data, setup["v_bus_V"])
        states = np.empty((n, len(lim)))
        t0 = time.perf_counter()
        c0 = time.process_time()
        states[0] = system.reset()
        for k in range(n - 1):
            states[k + 1] = system.simulate(act[k])
        wall = time.perf_counter() - t0
        cpu = time.process_time() - c0
    e2e = time.perf_counter() - t_e2e
    di, dw = _agreement(states * lim, pos, data, n)
    return dict(wall_s=wall, cpu_s=cpu, e2e_s=e2e, n=n, di_A=di, dw=dw, solver="ScipyOdeSolver")


def _dop853(ps):
    return ps.ScipySolveIvpSolver(method="DOP853", rtol=1e-12, atol=1e-12)


# ----------------------------------------------------------------------------- report


def machine():
    name = platform.system()
    try:
        with open("/etc/os-release", encoding="utf-8") as f:
            for ln in f:
                if ln.startswith("PRETTY_NAME="):
                    name = ln.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    cpu = platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for ln in f:
                if ln.startswith("model name"):
                    cpu = ln.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{name}, {os.cpu_count()} CPUs ({cpu}), Python {platform.python_version()}, load {load:.2f}"


def rows_of(res, ts):
    ref = res["ours"]["wall_s"]
    rows = []
    for key, name, what in (
        ("ours", "ours: motorsim, closed loop",
         "sensor + drive + plant (RK4, 1 step/sample) + metrics; loop timer"),
        ("replay", "ours: plant only (plant_replay)",
         "the same held voltages and speed trajectory through our plant (RK4, 1 step/sample); loop timer"),
        ("gem_env", "GEM 3.0.3 env, default solver",
         "Cont-CC-PMSM-v0, ExternalSpeedLoad, scipy ode dopri5 (rtol 1e-6)"),
        ("gem_system", "GEM 3.0.3 physical system, default solver",
         "SynchronousMotorSystem.simulate, scipy ode dopri5 (rtol 1e-6)"),
        ("gem_dop853", "GEM 3.0.3 env, accurate solver",
         "as the env line, solve_ivp DOP853 rtol = atol = 1e-12"),
    ):
        r = res.get(key)
        if r is None:
            continue
        sim_s = r["n"] * ts
        if r["n"] != res["ours"]["n"]:
            what += f"; first {r['n']} samples only"
        rows.append(dict(name=name, what=what, n=r["n"], sim_s=sim_s, wall_s=r["wall_s"], e2e_s=r["e2e_s"],
                         rtf=sim_s / r["wall_s"], ratio=(r["wall_s"] / ref) * (res["ours"]["n"] / r["n"]),
                         di_A=r.get("di_A")))
    return rows


def _fmt_t(x):
    return f"{x:.4f}" if x < 1 else f"{x:.2f}"


def print_text(rows, info, f=sys.stdout):
    hdr = ("simulator", "samples", "sim s", "wall s", "end to end s", "real-time factor", "time / ours",
           "max |di| vs ours A")
    body = [(r["name"], str(r["n"]), f"{r['sim_s']:g}", _fmt_t(r["wall_s"]), _fmt_t(r["e2e_s"]), f"{r['rtf']:.4g}",
             f"{r['ratio']:.0f}x" if r["ratio"] >= 10 else f"{r['ratio']:.2f}x",
             "-" if r["di_A"] is None else f"{r['di_A']:.2g}") for r in rows]
    w = [max(len(h), *(len(b[k]) for b in body)) for k, h in enumerate(hdr)]
    f.write("  ".join(h.ljust(w[k]) for k, h in enumerate(hdr)) + "\n")
    for b in body:
        f.write("  ".join(c.ljust(w[k]) if k == 0 else c.rjust(w[k]) for k, c in enumerate(b)) + "\n")
    for r in rows:
        f.write(f"  {r['name']}: {r['what']}\n")
    f.write(info + "\n")


def print_markdown(rows, info, f=sys.stdout):
    f.write("| simulator | what is simulated | wall time (s) | real-time factor | time / ours |"
            " max \\|i − i_ours\\| (A) |\n")
    f.write("|---|---|---|---|---|---|\n")
    for r in rows:
        ratio = f"{r['ratio']:.0f}×" if r["ratio"] >= 10 else f"{r['ratio']:.2f}×"
        di = "–" if r["di_A"] is None else f"{r['di_A']:.2g}"
        f.write(f"| {r['name']} | {r['what']} | {_fmt_t(r['wall_s'])} | {r['rtf']:.4g} | {ratio} | {di} |\n")
    f.write(f"\n{info}\n")


# ----------------------------------------------------------------------------- main


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--motorsim", default=DEF_MOTORSIM)
    ap.add_argument("--plant-replay", default=DEF_PLANT_REPLAY)
    ap.add_argument("--scenario", default=DEF_SCENARIO)
    ap.add_argument("--repeats", type=int, default=5, help="runs of each of ours (median), default 5")
    ap.add_argument("--accurate", action="store_true", help="also GEM's env with DOP853 at 1e-12 (~150 s)")
    ap.add_argument("--no-gem-system", action="store_true", help="skip the bare GEM physical-system line")
    ap.add_argument("--no-plant-replay", action="store_true",
                    help="skip the plant-only line (our plant on the same voltages, plant_replay's loop timer)")
    ap.add_argument("--gem-samples", type=int, default=0,
                    help="run GEM on the first N samples only (quick checks; 0 = all, the benchmark)")
    ap.add_argument("--tol", type=float, default=0.25,
                    help="max |i_GEM - i_ours| allowed on GEM's default-solver lines [A] (default 0.25)")
    ap.add_argument("--markdown", action="store_true", help="print the table as markdown")
    ap.add_argument("--json", help="write the raw results here")
    a = ap.parse_args(argv)
    if a.repeats < 1 or a.gem_samples < 0:
        ap.error("--repeats must be >= 1 and --gem-samples >= 0")
    for path, what in ((a.motorsim, "--motorsim"), (a.scenario, "--scenario")) + (
            ((a.plant_replay, "--plant-replay"),) if not a.no_plant_replay else ()):
        if not os.path.isfile(path):
            print(f"sim_speed: error: {what}: {path} not found (build the host preset first)", file=sys.stderr)
            return 2
    try:
        setup = load_setup(a.scenario)
    except (OSError, KeyError, ValueError, tomllib.TOMLDecodeError) as e:
        print(f"sim_speed: error: {a.scenario}: {e}", file=sys.stderr)
        return 2
    t_imp = time.perf_counter()
    try:
        _import_gem()
    except ImportError as e:
        print(f"sim_speed: error: gym_electric_motor not importable ({e}); pip install -r tools/requirements.txt",
              file=sys.stderr)
        return 3
    t_imp = time.perf_counter() - t_imp

    info_machine = machine()
    res = {}
    try:
        with tempfile.TemporaryDirectory(prefix="sim_speed.") as tmp:
            data = run_ours_csv(a.motorsim, setup, tmp)
            n_all = len(data["t_s"])
            res["ours"] = time_ours_closed_loop(a.motorsim, setup, tmp, a.repeats)
            if res["ours"]["n"] != n_all:
                raise BenchError(f"CSV has {n_all} rows, metrics say {res['ours']['n']} samples")
            if not a.no_plant_replay:
                res["replay"] = time_ours_plant_replay(a.plant_replay, setup, data, tmp, a.repeats)
        n_gem = n_all if a.gem_samples == 0 else min(a.gem_samples, n_all)
        res["gem_env"] = time_gem_env(setup, data, n_gem)
        if not a.no_gem_system:
            res["gem_system"] = time_gem_system(setup, data, n_gem)
        if a.accurate:
            res["gem_dop853"] = time_gem_env(setup, data, n_gem, solver=_dop853)
    except BenchError as e:
        print(f"sim_speed: error: {e}", file=sys.stderr)
        return 1

    rows = rows_of(res, setup["ts_s"])
    load_end = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    cmd = " ".join([os.path.relpath(os.path.abspath(__file__), REPO)] + (sys.argv[1:] if argv is None else list(argv)))
    info = (f"{os.path.relpath(setup['scenario'], REPO)}: {n_all} samples, Ts = {setup['ts_s']:g} s; "
            f"ours: median of {a.repeats} runs (loop {min(res['ours']['runs']):.4f}-"
            f"{max(res['ours']['runs']):.4f} s, process {res['ours']['e2e_s']:.4f} s); "
            f"GEM: import {t_imp:.2f} s, speed vs our trajectory within "
            f"{max(res[k]['dw'] for k in res if k.startswith('gem')):.1g} rad/s, CPU/wall "
            f"{min(res[k]['cpu_s'] / res[k]['wall_s'] for k in res if k.startswith('gem')):.3f} (lowest line). "
            f"Machine: {info_machine} at the start, {load_end:.2f} at the end. Command: `{cmd}`")
    busy = [k for k in res if k.startswith("gem") and res[k]["cpu_s"] < 0.95 * res[k]["wall_s"]]
    if busy:
        print(f"sim_speed: warning: the machine was busy during {', '.join(busy)} (CPU < 95 % of wall time): "
              "GEM's wall time and the ratio are inflated; run again on a quiet machine", file=sys.stderr)
    # the two like-for-like ratios: plant against plant (the same voltages
    # through each simulator's motor model), and each simulator's whole run
    def per_sample(k):
        return res[k]["wall_s"] / res[k]["n"]
    pairs = []
    if "replay" in res and "gem_system" in res:
        pairs.append(("plant against plant (GEM physical system / our plant_replay loop)",
                      per_sample("gem_system") / per_sample("replay")))
    if "replay" in res and "gem_env" in res:
        pairs.append(("GEM env (plant + env layer) / our plant_replay loop",
                      per_sample("gem_env") / per_sample("replay")))
    pairs.append(("GEM env / our whole closed loop (sensor + drive + plant + metrics)",
                  per_sample("gem_env") / per_sample("ours")))
    summary = "; ".join(f"{name}: {r:.0f}×" for name, r in pairs)
    info = info + " Ratios: " + summary + "."
    if a.markdown:
        print_markdown(rows, info)
    else:
        print_text(rows, info)
    if a.json:
        with open(a.json, "w", encoding="utf-8") as f:
            json.dump(dict(setup=setup, results=res, rows=rows, machine=info_machine), f, indent=1)
    if "replay" in res and not res["replay"]["di_A"] <= REPLAY_TOL_A:
        print(f"sim_speed: error: plant_replay's currents differ from the closed-loop run's by "
              f"{res['replay']['di_A']:.3g} A (> {REPLAY_TOL_A} A): not the same run", file=sys.stderr)
        return 1
    bad = [k for k in ("gem_env", "gem_system") if k in res and not res[k]["di_A"] <= a.tol]
    if bad:
        print(f"sim_speed: error: GEM and ours disagree beyond {a.tol} A on {', '.join(bad)}: "
              "not the same run", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
