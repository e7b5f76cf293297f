#!/usr/bin/env python3
"""Plots one motorsim run (the CSV it writes) like Figs. 4-8 of paper 000.

usage: plot_run.py RUN.csv OUT.png

Six panels over time: position (reference, true, estimated), position
errors, velocity, currents in the (f-g) frame with the observer error,
back-EMF disturbances d_f, d_g and their estimates, phase voltages. Shaded
background: drive in closed loop; magenta lines: open/closed-loop switches
(as in the paper's figures); red: fault. If RUN_metrics.json sits next to
the CSV its headline metrics go into the title.

Exit status: 0 ok, 2 bad input (usage, unreadable CSV, missing column),
3 matplotlib or numpy not installed.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

REQUIRED = [
    "t_s", "mode", "theta_ref", "theta", "theta_est", "omega_ref", "omega", "omega_est",
    "i_f", "i_g", "i_f_hat", "i_g_hat", "d_f", "d_g", "d_f_hat", "d_g_hat", "v_a", "v_b",
]
MODE_CLOSED, MODE_FAULT = 1, 2


def fail(msg: str, code: int = 2) -> int:
    print(f"plot_run.py: {msg}", file=sys.stderr)
    return code


def load_csv(path: Path, np):
    with path.open(encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.shape[1] != len(header):
        raise ValueError(f"{path}: {data.shape[1]} values per row, {len(header)} column names")
    return {name: data[:, k] for k, name in enumerate(header)}


def intervals(mask, t):
    """(start, end) times of the runs of True in mask."""
    out, start = [], None
    for k, m in enumerate(mask):
        if m and start is None:
            start = t[k]
        elif not m and start is not None:
            out.append((start, t[k]))
            start = None
    if start is not None:
        out.append((start, t[-1]))
    return out


def twin(a):
    """Right-hand axis for an error signal, drawn below the main curves."""
    b = a.twinx()
    a.set_zorder(b.get_zorder() + 1)
    a.patch.set_visible(False)
    return b


def headline(csv: Path) -> str:
    metrics = csv.with_name(csv.stem + "_metrics.json")
    if not metrics.is_file():
        return ""
    try:
        m = json.loads(metrics.read_text())
    except (OSError, ValueError):
        return ""
    parts = []
    for key, label in [("theta_track_max_rad", "max|θ-θr|"), ("theta_est_max_rad", "max|θ-θ̂|"),
                       ("omega_est_peak_max_rad_s", "max|ω-ω̂| (peak)"), ("final_theta_err_rad", "final err")]:
        v = m.get(key)
        if isinstance(v, (int, float)):
            parts.append(f"{label} = {v:.3g}")
    return "   ".join(parts)


def main(argv: list[str]) -> int:
    if len(argv) != 3 or argv[1] in ("-h", "--help"):
        print(__doc__.strip().splitlines()[2], file=sys.stderr if len(argv) != 2 else sys.stdout)
        return 0 if len(argv) == 2 and argv[1] in ("-h", "--help") else 2
    csv, png = Path(argv[1]), Path(argv[2])
    try:
        import numpy as np
        import matplotlib
        matplotlib.use("Agg")  # files only, no display needed
        import matplotlib.pyplot as plt
    except ImportError as e:
        return fail(f"{e.name} is not installed (run scripts/setup.sh for the project venv)", 3)

    if not csv.is_file():
        return fail(f"no such file: {csv}")
    try:
        d = load_csv(csv, np)
    except (OSError, ValueError) as e:
        return fail(f"cannot read {csv}: {e}")
    missing = [c for c in REQUIRED if c not in d]
    if missing:
        return fail(f"{csv}: missing column(s): {', '.join(missing)}")
    if len(d["t_s"]) == 0:
        return fail(f"{csv}: no data rows")

    t = d["t_s"]
    mode = d["mode"].astype(int)
    closed = mode == MODE_CLOSED
    # The paper plots estimates only where the drive uses them (closed loop).
    est = lambda x: np.where(closed, x, np.nan)  # noqa: E731

    fig, ax = plt.subplots(6, 1, sharex=True, figsize=(12, 17), constrained_layout=True)
    title = f"motorsim: {csv.stem}"
    extra = headline(csv)
    fig.suptitle(title + ("\n" + extra if extra else ""), fontsize=11)

    a = ax[0]
    a.plot(t, d["theta_ref"], "r", lw=1.2, label="θ_ref")
    a.plot(t, d["theta"], "b", lw=1.0, label="θ (true)")
    a.plot(t, est(d["theta_est"]), "g--", lw=1.0, label="θ_est")
    a.set_ylabel("position [rad]")

    a = ax[1]
    a.plot(t, est(d["theta"] - d["theta_ref"]), "b", lw=0.8, label="θ - θ_ref (tracking)")
    a.plot(t, est(d["theta"] - d["theta_est"]), "g", lw=0.8, label="θ - θ_est (observation)")
    a.set_ylabel("position error [rad]")

    a = ax[2]
    a.plot(t, d["omega_ref"], "r", lw=1.2, label="ω_ref")
    a.plot(t, d["omega"], "b", lw=0.8, label="ω (true)")
    a.plot(t, est(d["omega_est"]), "g", lw=0.6, label="ω_est")
    a.set_ylabel("velocity [rad/s]")
    b = twin(a)
    b.plot(t, est(d["omega"] - d["omega_est"]), color="0.5", lw=0.5, label="ω - ω_est")
    b.set_ylabel("ω - ω_est [rad/s]", color="0.4")
    b.legend(loc="lower right", fontsize=8)

    a = ax[3]
    a.plot(t, d["i_f"], "b", lw=0.6, label="i_f")
    a.plot(t, d["i_g"], "c", lw=0.6, label="i_g")
    a.plot(t, d["i_f_hat"], "m:", lw=0.8, label="î_f")
    a.plot(t, d["i_g_hat"], "y:", lw=0.8, label="î_g")
    a.set_ylabel("current [A]")
    b = twin(a)
    b.plot(t, est(d["i_f"] - d["i_f_hat"]), color="0.3", lw=0.4, label="i_f - î_f")
    b.plot(t, est(d["i_g"] - d["i_g_hat"]), color="0.6", lw=0.4, label="i_g - î_g")
    b.set_ylabel("observer error [A]", color="0.4")
    b.legend(loc="lower right", fontsize=8)

    a = ax[4]
    a.plot(t, d["d_f"], "b", lw=0.8, label="d_f = K/L ω sin(n_p Δθ)")
    a.plot(t, d["d_g"], "c", lw=0.8, label="d_g = -K/L ω cos(n_p Δθ)")
    a.plot(t, d["d_f_hat"], "m:", lw=0.8, label="d̂_f")
    a.plot(t, d["d_g_hat"], "y:", lw=0.8, label="d̂_g")
    a.set_ylabel("back-EMF dist. [A/s]")

    a = ax[5]
    a.plot(t, d["v_a"], "b", lw=0.4, label="v_a")
    a.plot(t, d["v_b"], "c", lw=0.4, label="v_b")
    a.set_ylabel("phase voltage [V]")
    a.set_xlabel("time [s]")

    switches = t[1:][np.diff(mode) != 0] if len(mode) > 1 else []
    for a in ax:
        for (t0, t1) in intervals(closed, t):
            a.axvspan(t0, t1, color="tab:green", alpha=0.07, lw=0)
        for (t0, t1) in intervals(mode == MODE_FAULT, t):
            a.axvspan(t0, t1, color="tab:red", alpha=0.15, lw=0)
        for ts in switches:
            a.axvline(ts, color="magenta", lw=0.8)
        a.grid(True, lw=0.3)
        a.legend(loc="upper right", fontsize=8, ncol=2)
    ax[0].set_xlim(t[0], t[-1])

    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=90)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
