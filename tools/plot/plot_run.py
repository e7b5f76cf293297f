#!/usr/bin/env python3
"""Plots one motorsim run (the CSV it writes) like Figs. 4-8 of paper 000.

usage: plot_run.py RUN.csv OUT.png

Six panels over time: position (reference, true, estimated), position
errors, velocity, currents in the (f-g) frame with the observer error,
back-EMF disturbances d_f, d_g and their estimates, phase voltages. Shaded
background: drive in closed loop; magenta lines: open/closed-loop switches
(as in the paper's figures); red: fault. If RUN_metrics.json sits next to
the CSV its headline metrics go into the title.

Fast enough to run after every motorsim run: for the 42,500 samples of
paper 000's experiment it takes about half the time it took drawing every
sample under constrained layout. Only the plotted columns are parsed; each
solid trace is drawn from its min/max envelope over bins of half a pixel
column (the samples where each bin reaches its minimum and its maximum, in
time order), which looks the same as drawing every sample, chattering
amplitude and spikes included, at a fifth of the points; the axes are placed
by arrange(), as constrained layout placed them, in one pass instead of two;
Agg without pyplot, fixed size and dpi, fast PNG compression.

Exit status: 0 ok, 2 bad input (usage, unreadable CSV, missing column),
3 matplotlib or numpy not installed.
"""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

REQUIRED = [
    "t_s", "mode", "theta_ref", "theta", "theta_est", "omega_ref", "omega", "omega_est",
    "i_f", "i_g", "i_f_hat", "i_g_hat", "d_f", "d_g", "d_f_hat", "d_g_hat", "v_a", "v_b",
]
MODE_CLOSED, MODE_FAULT = 1, 2
FIGSIZE_IN, DPI = (12, 17), 90
# Envelope bins across the time axis: two per pixel column of the figure (so
# at least two per column of the narrower axes): a noisy trace drawn with thin
# lines comes out as dense as with every sample (one bin per column: lighter).
ENVELOPE_BINS = 2 * FIGSIZE_IN[0] * DPI
# zlib level of the PNG: 1 encodes in half the time of the default 6 for a
# file ~15% larger.
PNG_COMPRESS_LEVEL = 1


def fail(msg: str, code: int = 2) -> int:
    print(f"plot_run.py: {msg}", file=sys.stderr)
    return code


def read_header(path: Path) -> tuple[list[str], int | None]:
    """Column names, and the number of values in the first data row (None: no rows)."""
    with path.open(encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        first = f.readline().strip()
    return header, (len(first.split(",")) if first else None)


def load_columns(path: Path, header: list[str], names: list[str], np) -> dict:
    """The named columns of the CSV (parsed alone: the others are skipped)."""
    cols = [header.index(n) for n in names]
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, usecols=cols)
    return {name: data[:, k] for k, name in enumerate(names)}


def envelope(n: int, n_bins: int, np):
    """Index maker for drawing n samples in n_bins columns.

    Returns pick(y): the indices, in time order, of the minimum and the
    maximum of y over each bin of consecutive samples (NaN ignored; an
    all-NaN bin yields a NaN point, i.e. the gap stays). With n <= 2 n_bins,
    every sample is kept.
    """
    if n <= 2 * n_bins:
        every = np.arange(n)
        return lambda y: every
    k = -(-n // n_bins)  # samples per bin
    nb = -(-n // k)
    base = np.arange(nb) * k
    pad = nb * k - n

    def pick(y):
        b = np.concatenate([y, np.full(pad, np.nan)]).reshape(nb, k)
        nan = np.isnan(b)
        i_lo = np.where(nan, np.inf, b).argmin(axis=1)
        i_hi = np.where(nan, -np.inf, b).argmax(axis=1)
        idx = np.empty(2 * nb, dtype=np.intp)
        idx[0::2] = base + np.minimum(i_lo, i_hi)
        idx[1::2] = base + np.maximum(i_lo, i_hi)
        return idx

    return pick


def intervals(mask, t, np):
    """(start, end) times of the runs of True in mask."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(t[s], t[e] if e < len(t) else t[-1]) for s, e in zip(starts, ends)]


def twin(a):
    """Right-hand axis for an error signal, drawn below the main curves."""
    b = a.twinx()
    a.set_zorder(b.get_zorder() + 1)
    a.patch.set_visible(False)
    return b


def arrange(fig, title, axes, twins) -> None:
    """Places the title and the stacked axes as layout="constrained" did, in one pass.

    Constrained layout measures every axis of every axes twice, about a
    quarter of the time this script took. Here the margins come from the
    parts that set them: the title (top), the bottom x axis (bottom), the y
    axes of the panels (left) and of the twins (right), the y offset texts
    ("1e-5", gaps). Ticks and texts made while measuring are reused by the
    drawing.
    """
    r = fig.canvas.get_renderer()
    W, H = fig.bbox.width, fig.bbox.height
    pad = 3 / 72 * fig.dpi  # constrained layout's default w_pad / h_pad
    # Between panels: the x tick marks of the upper one (no labels: shared x).
    gap = 2 * pad + max(axes[0].xaxis.majorTicks[0].get_tick_padding(), 0) * fig.dpi / 72

    def adjust(left, right, bottom, top, gap):
        height = (H - top - bottom - (len(axes) - 1) * gap) / len(axes)
        fig.subplots_adjust(left=left / W, right=1 - right / W, bottom=bottom / H, top=1 - top / H,
                            hspace=gap / height)

    title.set_y(1 - pad / H)  # va="top": the title's top edge
    top = title.get_window_extent(r).height + 3 * pad
    adjust(8 * gap, 6 * gap, 4 * gap, top, gap)  # provisional: sets the bottom axis' length
    low = axes[-1]
    bottom = low.get_window_extent(r).y0 - low.xaxis.get_tightbbox(r).y0 + pad
    adjust(8 * gap, 6 * gap, bottom, top, gap)  # final heights: set the y ticks
    left, right, offset = pad, pad, 0.0
    for a in list(axes) + list(twins):
        box, ybox = a.get_window_extent(r), a.yaxis.get_tightbbox(r)
        if ybox is None:
            continue
        left = max(left, box.x0 - ybox.x0 + pad)
        right = max(right, ybox.x1 - box.x1 + pad)
        if a.yaxis.offsetText.get_visible() and a.yaxis.offsetText.get_text():
            offset = max(offset, a.yaxis.offsetText.get_window_extent(r).height)
    xbox = low.xaxis.get_tightbbox(r)
    right = max(right, xbox.x1 - low.get_window_extent(r).x1 + pad)
    adjust(left, right, bottom, top + offset, gap + offset)


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
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as e:
        return fail(f"{e.name} is not installed (run scripts/setup.sh for the project venv)", 3)

    if not csv.is_file():
        return fail(f"no such file: {csv}")
    try:
        header, n_first = read_header(csv)
    except (OSError, ValueError) as e:
        return fail(f"cannot read {csv}: {e}")
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        return fail(f"{csv}: missing column(s): {', '.join(missing)}")
    if n_first is None:
        return fail(f"{csv}: no data rows")
    if n_first != len(header):
        return fail(f"cannot read {csv}: {n_first} values per row, {len(header)} column names")
    try:
        d = load_columns(csv, header, REQUIRED, np)
    except (OSError, ValueError) as e:
        return fail(f"cannot read {csv}: {e}")

    t = d["t_s"]
    mode = d["mode"].astype(int)
    closed = mode == MODE_CLOSED
    # The paper plots estimates only where the drive uses them (closed loop).
    est = lambda x: np.where(closed, x, np.nan)  # noqa: E731

    fig = Figure(figsize=FIGSIZE_IN, dpi=DPI)
    FigureCanvasAgg(fig)
    ax = fig.subplots(6, 1, sharex=True)
    twins = [None, None]
    pick = envelope(len(t), ENVELOPE_BINS, np)

    def plot(axis, y, fmt, **kw):
        """axis.plot(t, y, fmt, ...): a solid line from y's min/max envelope,
        a dashed or dotted one from every sample (its pattern runs along the
        whole path: thinned, a noisy trace would look sparser)."""
        if any(style in fmt for style in ("--", "-.", ":")):
            return axis.plot(t, y, fmt, **kw)
        idx = pick(y)
        return axis.plot(t[idx], y[idx], fmt, **kw)

    title = f"motorsim: {csv.stem}"
    extra = headline(csv)
    suptitle = fig.suptitle(title + ("\n" + extra if extra else ""), fontsize=11)

    a = ax[0]
    plot(a, d["theta_ref"], "r", lw=1.2, label="θ_ref")
    plot(a, d["theta"], "b", lw=1.0, label="θ (true)")
    plot(a, est(d["theta_est"]), "g--", lw=1.0, label="θ_est")
    a.set_ylabel("position [rad]")

    a = ax[1]
    plot(a, est(d["theta"] - d["theta_ref"]), "b", lw=0.8, label="θ - θ_ref (tracking)")
    plot(a, est(d["theta"] - d["theta_est"]), "g", lw=0.8, label="θ - θ_est (observation)")
    a.set_ylabel("position error [rad]")

    a = ax[2]
    plot(a, d["omega_ref"], "r", lw=1.2, label="ω_ref")
    plot(a, d["omega"], "b", lw=0.8, label="ω (true)")
    plot(a, est(d["omega_est"]), "g", lw=0.6, label="ω_est")
    a.set_ylabel("velocity [rad/s]")
    b = twins[0] = twin(a)
    plot(b, est(d["omega"] - d["omega_est"]), "-", color="0.5", lw=0.5, label="ω - ω_est")
    b.set_ylabel("ω - ω_est [rad/s]", color="0.4")
    b.legend(loc="lower right", fontsize=8)

    a = ax[3]
    plot(a, d["i_f"], "b", lw=0.6, label="i_f")
    plot(a, d["i_g"], "c", lw=0.6, label="i_g")
    plot(a, d["i_f_hat"], "m:", lw=0.8, label="î_f")
    plot(a, d["i_g_hat"], "y:", lw=0.8, label="î_g")
    a.set_ylabel("current [A]")
    b = twins[1] = twin(a)
    plot(b, est(d["i_f"] - d["i_f_hat"]), "-", color="0.3", lw=0.4, label="i_f - î_f")
    plot(b, est(d["i_g"] - d["i_g_hat"]), "-", color="0.6", lw=0.4, label="i_g - î_g")
    b.set_ylabel("observer error [A]", color="0.4")
    b.legend(loc="lower right", fontsize=8)

    a = ax[4]
    plot(a, d["d_f"], "b", lw=0.8, label="d_f = K/L ω sin(n_p Δθ)")
    plot(a, d["d_g"], "c", lw=0.8, label="d_g = -K/L ω cos(n_p Δθ)")
    plot(a, d["d_f_hat"], "m:", lw=0.8, label="d̂_f")
    plot(a, d["d_g_hat"], "y:", lw=0.8, label="d̂_g")
    a.set_ylabel("back-EMF dist. [A/s]")

    a = ax[5]
    plot(a, d["v_a"], "b", lw=0.4, label="v_a")
    plot(a, d["v_b"], "c", lw=0.4, label="v_b")
    a.set_ylabel("phase voltage [V]")
    a.set_xlabel("time [s]")

    switches = t[1:][np.diff(mode) != 0] if len(mode) > 1 else []
    for a in ax:
        for (t0, t1) in intervals(closed, t, np):
            a.axvspan(t0, t1, color="tab:green", alpha=0.07, lw=0)
        for (t0, t1) in intervals(mode == MODE_FAULT, t, np):
            a.axvspan(t0, t1, color="tab:red", alpha=0.15, lw=0)
        for ts in switches:
            a.axvline(ts, color="magenta", lw=0.8)
        a.grid(True, lw=0.3)
        a.legend(loc="upper right", fontsize=8, ncol=2)
    ax[0].set_xlim(t[0], t[-1])
    arrange(fig, suptitle, ax, twins)

    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=DPI, pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})
    return 0


if __name__ == "__main__":
    status = main(sys.argv)
    # Everything is written and closed: skip the interpreter's teardown of
    # numpy and matplotlib (~0.1 s of a ~1 s run).
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
