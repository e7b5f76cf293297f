#!/usr/bin/env python3
"""Replay a phase-voltage sequence through gym-electric-motor's PMSM.

Part of the cross-check of our PMSM plant against the independent simulator
gym-electric-motor (GEM, PyPI ``gym-electric-motor==3.0.3``).

Input: leg voltages v_a, v_b, v_c (V, relative to the DC-bus midpoint of a
star-connected motor), row k held constant on [k*ts, (k+1)*ts).  The motor
sees only their differential part.  The rotor turns at a constant
mechanical speed omega (rad/s); electrical angle theta = theta0 + n_p*omega*t.
Output: i_a, i_b, i_c at t = k*ts, i.e. *before* row k is applied (i[0] is
the initial state, zero current).

GEM conventions relied on (read from its 3.0.3 source):
  * abc -> alpha/beta: amplitude-invariant Clarke, 2/3*[[1,-1/2,-1/2],
    [0,sqrt3/2,-sqrt3/2]]; inverse without factor.  Common mode drops out.
  * alpha/beta -> dq: rotation by the electrical angle epsilon, d-axis on the
    magnet flux psi_p; epsilon' = p*omega (omega mechanical, rad/s).
  * dq equations: l_d i_d' = u_d - r_s i_d + p*omega*l_q*i_q,
                  l_q i_q' = u_q - r_s i_q - p*omega*(l_d*i_d + psi_p);
    torque 3/2*p*(psi_p + (l_d-l_q) i_d) i_q.
  * 'Cont-B6C' converter: action a in [-1,1] per leg, leg voltage relative to
    the midpoint = a*u_dc/2.

Two modes:
  ``model`` (default, exact): GEM's PermanentMagnetSynchronousMotor
    (electrical_ode, t_23/t_32/q/q_inv), GEM's ContB6BridgeConverter and
    IdealVoltageSupply for the voltage mapping, GEM's ScipySolveIvpSolver
    (DOP853, rtol=atol=1e-12).  The held abc voltage is transformed to dq
    inside the right-hand side at the current angle, so it is held in the
    stationary frame as an inverter does.
  ``env``: GEM's own SynchronousMotorSystem (the physical system inside its
    environments) with ConstantSpeedLoad.  GEM converts the abc voltage to dq
    ONCE per step at the step's start angle and holds u_dq constant, so the
    applied voltage rotates with the rotor within a step: an O(omega_el*tau)
    error that ``substeps`` (GEM tau = ts/substeps) reduces only linearly.
    Its reported i_a/i_b/i_c are also rotated with the stale start angle, so
    this module rebuilds abc currents from i_sd, i_sq and the end angle.

CLI: python gem_replay.py --in V.csv --out I.csv --R .. --Ld .. --Lq ..
     --Phi .. --np .. --J .. --omega .. --ts .. [--theta0 ..] [--mode ..]
V.csv header ``v_a_V,v_b_V,v_c_V``; I.csv gets ``t_s,i_a_A,i_b_A,i_c_A``.
Exit 0 ok, 2 bad input (one line on stderr, nothing written), 3 GEM missing.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import warnings

import numpy as np

PARAM_KEYS = ("R_ohm", "L_d_H", "L_q_H", "Phi_Wb", "n_p", "J_kgm2")
IN_HEADER = ("v_a_V", "v_b_V", "v_c_V")
OUT_HEADER = ("t_s", "i_a_A", "i_b_A", "i_c_A")
MODES = ("model", "env")


class ReplayInputError(ValueError):
    """Bad parameters or voltage data (CLI exit 2)."""


def _import_gem():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import gym_electric_motor  # noqa: F401
        from gym_electric_motor import physical_systems as ps
        from gym_electric_motor.physical_systems.physical_systems import SynchronousMotorSystem
    return ps, SynchronousMotorSystem


def _check(params, v, omega, ts, theta0, mode, substeps):
    missing = [k for k in PARAM_KEYS if k not in params]
    if missing:
        raise ReplayInputError(f"missing parameter(s): {', '.join(missing)}")
    p = {}
    for k in PARAM_KEYS:
        try:
            p[k] = float(params[k])
        except (TypeError, ValueError):
            raise ReplayInputError(f"parameter {k} is not a number: {params[k]!r}") from None
        if not math.isfinite(p[k]):
            raise ReplayInputError(f"parameter {k} is not finite: {params[k]!r}")
    for k in ("L_d_H", "L_q_H", "J_kgm2"):
        if p[k] <= 0:
            raise ReplayInputError(f"parameter {k} must be > 0, got {p[k]!r}")
    if p["R_ohm"] < 0 or p["Phi_Wb"] < 0:
        raise ReplayInputError("parameters R_ohm and Phi_Wb must be >= 0")
    if p["n_p"] < 1 or p["n_p"] != int(p["n_p"]):
        raise ReplayInputError(f"parameter n_p must be a positive integer, got {params['n_p']!r}")
    for name, x in (("omega_mech_rad_s", omega), ("ts_s", ts), ("theta0_elec_rad", theta0)):
        if not isinstance(x, (int, float, np.floating, np.integer)) or not math.isfinite(x):
            raise ReplayInputError(f"{name} must be a finite number, got {x!r}")
    if ts <= 0:
        raise ReplayInputError(f"ts_s must be > 0, got {ts!r}")
    v = np.asarray(v, dtype=float)
    if v.ndim != 2 or v.shape[1] != 3 or v.shape[0] < 1:
        raise ReplayInputError(f"v_abc_V must have shape (N>=1, 3), got {v.shape}")
    bad = ~np.isfinite(v)
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise ReplayInputError(f"non-finite voltage at row {r}, column {IN_HEADER[c]}")
    if mode not in MODES:
        raise ReplayInputError(f"mode must be one of {MODES}, got {mode!r}")
    if int(substeps) != substeps or substeps < 1:
        raise ReplayInputError(f"substeps must be a positive integer, got {substeps!r}")
    return p, v


def _u_dc(v):
    """DC-bus voltage: a power of two >= 2*max|v| + 1 V, so |action| <= 1 with margin."""
    need = 2.0 * float(np.max(np.abs(v))) + 1.0
    return float(2.0 ** math.ceil(math.log2(need)))


def _motor(ps, p, omega, u_dc, theta0_wrapped):
    big_w = max(2.0 * abs(omega), 4e3 * math.pi / 30)
    return ps.PermanentMagnetSynchronousMotor(
        motor_parameter=dict(r_s=p["R_ohm"], l_d=p["L_d_H"], l_q=p["L_q_H"], psi_p=p["Phi_Wb"],
                             p=int(p["n_p"]), j_rotor=p["J_kgm2"]),
        # limits/nominal values only scale GEM's normalised observations and bound
        # its initial-state check; set them wide so nothing clips or refuses.
        limit_values=dict(omega=big_w, i=1e4, u=u_dc),
        nominal_values=dict(omega=big_w, i=1e4, u=u_dc),
        motor_initializer=dict(states=dict(i_sd=0.0, i_sq=0.0, epsilon=theta0_wrapped)),
    )


def _wrap(theta):
    w = math.remainder(theta, 2 * math.pi)  # in [-pi, pi]
    return w


def replay(params: dict, v_abc_V, omega_mech_rad_s: float, ts_s: float,
           theta0_elec_rad: float = 0.0, *, mode: str = "model", substeps: int = 1,
           rtol: float = 1e-12, atol: float = 1e-12, interlocking_time_s: float = 0.0,
           u_dc_V: float | None = None) -> dict:
    """Replay held leg voltages through GEM's PMSM at constant mechanical speed.

    Returns a dict of arrays of length N (state at t = k*ts, before row k):
    t_s, i_a_A, i_b_A, i_c_A, i_d_A, i_q_A, theta_elec_rad (electrical angle,
    unwrapped, theta0 + n_p*omega*t), v_applied_V (N x 3, model mode: the
    converter's leg voltages over row k); plus scalars u_dc_V, mode and
    max_voltage_error_V (|GEM converter output - requested|, model mode).

    interlocking_time_s (model mode): GEM's converter interlocking (dead)
    time, which its continuous converters subtract from each leg's duty as
    sign(i_leg) * interlocking_time / tau, tau = ts (one switching period
    per step), the leg current taken at the step's start; the voltages are
    then no longer the requested ones. u_dc_V: the bus (default: the power
    of two of _u_dc).
    """
    p, v = _check(params, v_abc_V, omega_mech_rad_s, ts_s, theta0_elec_rad, mode, substeps)
    ps, SynchronousMotorSystem = _import_gem()
    omega = float(omega_mech_rad_s)
    ts = float(ts_s)
    theta0 = float(theta0_elec_rad)
    n = v.shape[0]
    u_dc = _u_dc(v) if u_dc_V is None else float(u_dc_V)
    if not (u_dc > 2.0 * float(np.max(np.abs(v)))):
        raise ReplayInputError(f"u_dc_V {u_dc!r} must exceed twice the largest |voltage|")
    if mode != "model" and interlocking_time_s:
        raise ReplayInputError("interlocking_time_s needs mode 'model'")
    actions = v * (2.0 / u_dc)  # Cont-B6C: leg voltage = a * u_dc / 2 (exact scaling, u_dc = 2^k)
    t = np.arange(n) * ts
    out = dict(t_s=t, i_a_A=np.zeros(n), i_b_A=np.zeros(n), i_c_A=np.zeros(n),
               i_d_A=np.zeros(n), i_q_A=np.zeros(n), theta_elec_rad=theta0 + p["n_p"] * omega * t,
               u_dc_V=u_dc, mode=mode, max_voltage_error_V=float("nan"), v_applied_V=np.zeros((n, 3)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if mode == "model":
            _replay_model(ps, p, actions, v, omega, ts, theta0, u_dc, rtol, atol, out, interlocking_time_s)
        else:
            _replay_env(ps, SynchronousMotorSystem, p, actions, omega, ts, theta0, u_dc,
                        int(substeps), rtol, atol, out)
    return out


def _store(out, k, motor, i_dq, eps):
    i_abc = motor.t_32(motor.q(i_dq, eps))
    out["i_a_A"][k], out["i_b_A"][k], out["i_c_A"][k] = i_abc
    out["i_d_A"][k], out["i_q_A"][k] = i_dq


def _replay_model(ps, p, actions, v, omega, ts, theta0, u_dc, rtol, atol, out, interlocking_time_s=0.0):
    motor = _motor(ps, p, omega, u_dc, _wrap(theta0))
    supply = ps.IdealVoltageSupply(u_nominal=u_dc)
    conv = ps.ContB6BridgeConverter(tau=ts, interlocking_time=float(interlocking_time_s))
    conv.reset()

    def rhs(_t, y, u_ab):
        # abc voltage held in the stationary frame: rotate to dq at the current angle
        return motor.electrical_ode(y, motor.q_inv(u_ab, y[2]), omega)

    solver = ps.ScipySolveIvpSolver(method="DOP853", rtol=rtol, atol=atol)
    solver.set_system_equation(rhs)
    y = np.array([0.0, 0.0, theta0])  # [i_sd, i_sq, epsilon] (GEM ODE order)
    solver.set_initial_value(y, 0.0)
    verr = 0.0
    n = actions.shape[0]
    for k in range(n):
        y = solver.y
        _store(out, k, motor, y[:2], y[2])
        if k == n - 1:
            break  # the last row only affects the state at t = N*ts, which is not reported
        i_abc = motor.t_32(motor.q(y[:2], y[2]))
        conv.set_action(actions[k], k * ts)
        u_sup = supply.get_voltage(k * ts, conv.i_sup(i_abc))
        u_abc = np.array([u * u_sup[0] for u in conv.convert(i_abc, k * ts)])
        out["v_applied_V"][k] = u_abc
        verr = max(verr, float(np.max(np.abs(u_abc - v[k]))))
        solver.set_f_params(motor.t_23(u_abc))
        solver.integrate((k + 1) * ts)
    out["max_voltage_error_V"] = verr


def _replay_env(ps, SynchronousMotorSystem, p, actions, omega, ts, theta0, u_dc, substeps, rtol, atol, out):
    motor = _motor(ps, p, omega, u_dc, _wrap(theta0))
    system = SynchronousMotorSystem(
        converter=ps.ContB6BridgeConverter(),
        motor=motor,
        # pass a fresh initializer: ConstantSpeedLoad.__init__ otherwise writes omega_fixed
        # into its class-level default dict, leaking the speed into later instances.
        load=ps.ConstantSpeedLoad(omega_fixed=omega, load_initializer=dict(
            states=dict(omega=omega), interval=None, random_init=None, random_params=(None, None))),
        supply=ps.IdealVoltageSupply(u_nominal=u_dc),
        ode_solver=ps.ScipySolveIvpSolver(method="DOP853", rtol=rtol, atol=atol),
        tau=ts / substeps,
    )
    pos = system.state_positions
    lim = np.asarray(system.limits, dtype=float)
    state = np.asarray(system.reset(), dtype=float) * lim
    n = actions.shape[0]
    for k in range(n):
        i_dq = np.array([state[pos["i_sd"]], state[pos["i_sq"]]])
        _store(out, k, motor, i_dq, state[pos["epsilon"]])
        if k == n - 1:
            break
        for _ in range(substeps):
            state = np.asarray(system.simulate(actions[k]), dtype=float) * lim
    out["max_voltage_error_V"] = float("nan")  # applied voltage rotates within a step (see module doc)


# ----------------------------------------------------------------------------- CLI


def _read_voltages(path):
    if not os.path.isfile(path):
        raise ReplayInputError(f"input file not found: {path}")
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise ReplayInputError(f"cannot read input file {path}: {e}") from None
    lines = [ln for ln in lines if ln.strip()]
    if not lines:
        raise ReplayInputError(f"input file is empty: {path}")
    header = tuple(c.strip() for c in lines[0].split(","))
    if header != IN_HEADER:
        raise ReplayInputError(f"wrong columns in {path}: expected header {','.join(IN_HEADER)}, got {lines[0].strip()}")
    if len(lines) < 2:
        raise ReplayInputError(f"no data rows in {path}")
    v = np.empty((len(lines) - 1, 3))
    for r, ln in enumerate(lines[1:]):
        cells = ln.split(",")
        if len(cells) != 3:
            raise ReplayInputError(f"{path} data row {r}: expected 3 values, got {len(cells)}")
        for c, cell in enumerate(cells):
            try:
                x = float(cell)
            except ValueError:
                raise ReplayInputError(f"{path} data row {r}, column {IN_HEADER[c]}: not a number: {cell.strip()!r}") from None
            if not math.isfinite(x):
                raise ReplayInputError(f"{path} data row {r}, column {IN_HEADER[c]}: non-finite value {cell.strip()!r}")
            v[r, c] = x
    return v


def _write_atomic(path, res):
    d = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(d):
        raise ReplayInputError(f"output directory does not exist: {d}")
    fd, tmp = tempfile.mkstemp(prefix=".gem_replay.", suffix=".tmp", dir=d)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(",".join(OUT_HEADER) + "\n")
            for row in zip(res["t_s"], res["i_a_A"], res["i_b_A"], res["i_c_A"]):
                f.write(",".join(repr(float(x)) for x in row) + "\n")
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2
        sys.stderr.write(f"gem_replay: error: {message}\n")
        sys.exit(2)


def main(argv=None) -> int:
    ap = _Parser(description="Replay held phase voltages through gym-electric-motor's PMSM at constant speed.")
    ap.add_argument("--in", dest="inp", required=True, help="CSV with header v_a_V,v_b_V,v_c_V")
    ap.add_argument("--out", required=True, help="CSV to write: t_s,i_a_A,i_b_A,i_c_A")
    ap.add_argument("--R", type=float, required=True, help="stator resistance, ohm")
    ap.add_argument("--Ld", type=float, required=True, help="d-axis inductance, H")
    ap.add_argument("--Lq", type=float, required=True, help="q-axis inductance, H")
    ap.add_argument("--Phi", type=float, required=True, help="PM flux linkage (peak, amplitude-invariant), Wb")
    ap.add_argument("--np", dest="n_p", type=float, required=True, help="pole pairs")
    ap.add_argument("--J", type=float, required=True, help="rotor inertia, kg m^2")
    ap.add_argument("--omega", type=float, required=True, help="constant mechanical speed, rad/s")
    ap.add_argument("--ts", type=float, required=True, help="hold time of each voltage row, s")
    ap.add_argument("--theta0", type=float, default=0.0, help="initial electrical angle, rad (default 0)")
    ap.add_argument("--mode", choices=MODES, default="model", help="model (exact, default) or env (GEM system glue)")
    ap.add_argument("--substeps", type=int, default=1, help="GEM steps per sample in env mode (default 1)")
    a = ap.parse_args(argv)
    params = dict(R_ohm=a.R, L_d_H=a.Ld, L_q_H=a.Lq, Phi_Wb=a.Phi, n_p=a.n_p, J_kgm2=a.J)
    try:
        v = _read_voltages(a.inp)
        _check(params, v, a.omega, a.ts, a.theta0, a.mode, a.substeps)
        out_dir = os.path.dirname(os.path.abspath(a.out))
        if not os.path.isdir(out_dir):
            raise ReplayInputError(f"output directory does not exist: {out_dir}")
        try:
            _import_gem()
        except ImportError as e:
            sys.stderr.write(f"gem_replay: error: gym_electric_motor is not importable ({e}); "
                             "pip install gym-electric-motor==3.0.3\n")
            return 3
        res = replay(params, v, a.omega, a.ts, a.theta0, mode=a.mode, substeps=a.substeps)
        _write_atomic(a.out, res)
    except ReplayInputError as e:
        sys.stderr.write(f"gem_replay: error: {e}\n")
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
