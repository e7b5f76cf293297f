#!/usr/bin/env python3
"""Plots one motorsim run (the CSV it writes) into a PNG.

usage: plot_run.py [--t-start S] [--t-end S] [--panels NAME,...] RUN.csv OUT.png

The kind of run is told from the CSV header (each drive's facts file,
firmware/drives/<name>/tools.toml, names the kind its runs are, `plot`:
the drives of each kind are named in the title and in --help):

* position run (paper 000's drive, column theta_ref_rad), like Figs. 4-8
  of paper 000. Panels: position (reference, true, estimated), position
  errors, velocity with the estimation error, currents in the (f-g) frame
  with the observer error, back-EMFs e_f = L d_f, e_g = L d_g and their
  estimates, load torque (true: Coulomb friction + load; estimated), phase
  voltages. Estimates are drawn in closed loop only (where the drive uses
  them; in open loop it reports the reference). The (f-g) frame is the
  rotating frame at the reference electrical angle n_p θ_ref (paper 000
  eqs. (6)-(8)), not d-q: the d-q frame is at the estimated angle n_p θ_est
  (eq. (44)); f ≈ d and g ≈ q while θ ≈ θ_ref.
* speed run (any speed drive, through the drive interface: paper 001's, the
  sensored FOC; column omega_ref_rad_s). Panels: speed
  (reference ω*, true, estimated; rpm), speed errors (rpm), electrical angle
  estimation error (degrees), load torque (true: load + Coulomb and viscous
  friction; estimated), d-q currents (in the drive's estimated frame) with
  the i_q reference, phase voltages (v_c left out when it is 0: two phases).
  Noisy estimates are drawn under the true traces.
* EKF speed run (ekf_speed: paper 002's drive, column omega_d_rad_s). Panels: speed
  (reference ω_d, true, the EKF's; rad/s), speed errors, the lumped
  disturbance M_0 (load + friction) with the EKF's estimate and the torque
  demand, d-q currents (encoder frame) with the MTPA references, d-q
  voltages.

A CSV's columns are motorsim's scoring's (time, the plant's truth, the
reference, the drive's status) and then the drive's signals, under the names
its signal list gives them (firmware/drives/drive.h, drive_signal_t; each
drive's list in docs/motorsim.md): the observer's currents and back-EMFs of
the position panels and the d-q currents of the speed and EKF panels are
signals. A default panel that needs a column the CSV lacks (a drive without
that signal) is left out and named on stderr; one asked for by --panels is
an error.

Markings, all in the legend under the title: green background, drive in
closed loop (mode 1); magenta lines, open/closed-loop switches; blue band at
the bottom of the panels, speed runs' estimate-valid flag; red background,
fault (mode 2: safe state, 0 V); red line and text, the first fault (code,
name from drive_fault_t in firmware/supervisor/supervisor.h, time), also in
the title. If RUN_metrics.json sits next to the CSV its headline metrics
(whole run, against the scenario's reference, with units) go into the title.
Each panel's legend sits in the corner its traces cross least.

Options: --t-start, --t-end (s) plot a time window; --panels picks and
orders panels by name (see --help). Exit status: 0 ok, 2 bad input (usage,
bad option value, unreadable CSV, unknown CSV kind, missing column), 3
matplotlib or numpy not installed.

Fast enough to run after every motorsim run (about 1 s for the 42,500
samples of paper 000's experiment): only the plotted columns are parsed;
each solid trace is drawn from its min/max envelope over bins of half a
pixel column (the samples where each bin reaches its minimum and its
maximum, in time order), which looks the same as drawing every sample,
chattering amplitude and spikes included, at a fifth of the points; dashed
and dotted traces are drawn from every sample (thinned, their pattern would
look sparser); the axes are placed by arrange(), as constrained layout
placed them, in one pass instead of two; Agg without pyplot, fixed width,
height by the number of panels, fixed dpi, fast PNG compression.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import drive_facts  # noqa: E402

MODE_OPEN, MODE_CLOSED, MODE_FAULT = 0, 1, 2  # drive_mode_t
# drive_fault_t (firmware/supervisor/supervisor.h): code -> (name, meaning).
FAULT_NAMES = {
    1: ("OVERCURRENT", "a measured phase current beyond i_trip_A"),
    2: ("BAD_INPUT", "inconsistent configuration or a sample of the wrong phase count"),
    3: ("I2T", "the I^2 t integral beyond its limit (thermal overload)"),
    4: ("VOLTAGE_SATURATION", "the voltage limit active for too long"),
    5: ("LOSS_OF_SYNC", "the estimate is inconsistent or the rotor lost the reference"),
    6: ("NON_FINITE", "NaN or inf in a sample, a state or a command"),
    7: ("SENSOR_STUCK", "a current sample that does not change while its voltage does"),
    8: ("SENSOR_RAIL", "a current sample at the ADC's full scale"),
    9: ("ADC", "the backend reported a converter error"),
    10: ("HW_TRIP", "the power stage's own trip fired"),
    11: ("OVERRUN", "control steps overran their period too often"),
    12: ("LOSS_OF_LOCK", "a speed drive's estimate no longer explains the currents"),
}
FIG_WIDTH_IN, DPI = 12, 90
PANEL_IN = 2.35  # figure height per panel (axes + gap)
HEADER_IN = 1.1  # figure height for the x axis, a one-line title and the markings legend
TITLE_LINE_IN = 0.22  # per further title line
# Envelope bins across the time axis: two per pixel column of the figure (so
# at least two per column of the narrower axes): a noisy trace drawn with thin
# lines comes out as dense as with every sample (one bin per column: lighter).
ENVELOPE_BINS = 2 * FIG_WIDTH_IN * DPI
# zlib level of the PNG: 1 encodes in half the time of the default 6 for a
# file ~15% larger.
PNG_COMPRESS_LEVEL = 1
# Panel legends go to the corner (or edge middle) their traces cross least:
# legend_spot() counts the decimated samples under each; matplotlib's "best"
# does the same on every vertex and every artist, a quarter of the run time.
LEGEND_SPOTS = ("upper right", "upper left", "lower right", "lower left", "upper center", "lower center")
LEGEND_SLACK = 1.3  # a spot covering up to 1.3 times the fewest samples is as good
RAD_S_TO_RPM = 60.0 / (2.0 * math.pi)
# Noisy estimates (and the i_q reference computed from them) under the true
# traces (Line2D default zorder 2): a noise band would hide them.
EST_Z = 1.9
F_G_NOTE = ("(f-g): frame at the reference electrical angle n_p θ_ref, paper 000 eqs. (6)-(8); "
            "d-q is at the estimated angle n_p θ_est (eq. (44)); f ≈ d, g ≈ q while θ ≈ θ_ref")


class InputError(Exception):
    """Bad input: the message is printed on one line, exit status 2."""


# ---------------------------------------------------------------- run kinds --
# Each kind: the column that identifies it, the columns every plot needs, the
# panels (name -> help, columns) in default order, the headline metrics
# (key, label, unit). The panels are drawn by PANEL_DRAW[kind][name]. The
# drives whose runs are of a kind say so in their facts file (plot = KIND).
KINDS = {
    "position": {
        "title": "position run",
        "key": "theta_ref_rad",
        # the metrics of a faulted run against what is plotted
        "fault_note": "metrics of the whole run, against the scenario's reference "
                      "(the drive's reference plotted here freezes at the fault):",
        "base": ["t_s", "mode", "fault"],
        "panels": {
            "position": ("θ_ref, θ, θ_est [rad]", ["theta_ref_rad", "theta_rad", "theta_est_rad"]),
            "position_error": ("θ - θ_ref, θ - θ_est [rad]", ["theta_rad", "theta_ref_rad", "theta_est_rad"]),
            "velocity": ("ω_ref, ω, ω_est; ω - ω_est [rad/s]", ["omega_ref_rad_s", "omega_rad_s", "omega_est_rad_s"]),
            "current": ("(f-g) currents and observer error [A]", ["i_f_A", "i_g_A", "i_f_est_A", "i_g_est_A"]),
            "disturbance": ("(f-g) back-EMFs e_f = L d_f, e_g = L d_g and estimates [V]",
                            ["e_f_V", "e_g_V", "e_f_est_V", "e_g_est_V"]),
            "load": ("load torque, true and estimated [N m]", ["load_Nm", "load_est_Nm"]),
            "voltage": ("phase voltages v_a, v_b [V]", ["v_a_V", "v_b_V"]),
        },
        "metrics": [
            ("theta_track_max_rad", "max|θ-θ_ref|", "rad"),
            ("theta_est_max_rad", "max|θ-θ_est|", "rad"),
            ("omega_est_peak_max_rad_s", "max|ω-ω_est| (|ω_ref| ≥ 15 rad/s)", "rad/s"),
            ("final_theta_err_rad", "final |θ-θ_target|", "rad"),
            ("max_abs_current_A", "max|i_phase|", "A"),
        ],
    },
    "speed": {
        "title": "speed run",
        "key": "omega_ref_rad_s",
        "fault_note": "metrics of the whole run, the part after the fault included:",
        "base": ["t_s", "mode", "fault", "estimate_valid"],
        "panels": {
            "speed": ("ω*, ω, ω_est [rpm]", ["omega_ref_rad_s", "omega_rad_s", "omega_est_rad_s"]),
            "speed_error": ("ω - ω*, ω - ω_est [rpm]", ["omega_ref_rad_s", "omega_rad_s", "omega_est_rad_s"]),
            "angle_error": ("electrical angle error θ_e,est - θ_e [° el.]", ["theta_e_err_rad"]),
            "load": ("load torque, true and estimated [N m]", ["load_Nm", "load_est_Nm"]),
            "current": ("d-q currents and the i_q reference [A]", ["i_d_meas_A", "i_q_meas_A", "i_q_ref_A"]),
            "voltage": ("phase voltages v_a, v_b, v_c [V]", ["v_a_V", "v_b_V", "v_c_V"]),
        },
        "metrics": [
            ("speed_err_settled_max_rpm", "settled max|ω-ω*|", "rpm"),
            ("speed_err_ramp_max_rpm", "ramp max|ω-ω*|", "rpm"),
            ("speed_err_rms_rpm", "rms(ω-ω*)", "rpm"),
            ("load_est_err_settled_nm", "settled max|τ_est-τ_L|", "N m"),
            ("lock_time_s", "angle lock at t", "s"),
            ("theta_est_max_deg_e", "max|θ_e,est-θ_e| after lock", "° el."),
            ("max_abs_current_A", "max|i_phase|", "A"),
        ],
    },
    "ekf_speed": {
        "title": "EKF speed run",
        "key": "omega_d_rad_s",
        "fault_note": "metrics of the whole run, the part after the fault included:",
        "base": ["t_s", "mode", "fault"],
        "panels": {
            "speed": ("ω_d, ω, ω_est [rad/s]", ["omega_d_rad_s", "omega_rad_s", "omega_est_rad_s"]),
            "speed_error": ("ω_d - ω, ω_est - ω [rad/s]", ["omega_d_rad_s", "omega_rad_s", "omega_est_rad_s"]),
            "disturbance": ("lumped disturbance M_0, its EKF estimate, torque demand [N m]",
                            ["M0_Nm", "M0_est_Nm", "M_d_Nm"]),
            "current": ("d-q currents and references [A]", ["i_d_A", "i_q_A", "i_d_ref_A", "i_q_ref_A"]),
            "voltage": ("d-q voltages u_d, u_q [V]", ["u_d_V", "u_q_V"]),
        },
        "metrics": [
            ("speed_rmse_rad_s", "rms(ω_d-ω) over [0, 1] s", "rad/s"),
            ("speed_rmse_after_50ms_rad_s", "after 50 ms", "rad/s"),
            ("speed_err_max_rad_s", "max|ω_d-ω|", "rad/s"),
            ("omega_est_rmse_rad_s", "rms(ω_est-ω)", "rad/s"),
            ("voltage_hf_rms_V", "voltage above 1 kHz (steady state)", "V"),
            ("max_abs_current_A", "max|i_phase|", "A"),
        ],
    },
}
TITLE_LINE_CHARS = 140  # metrics per title line: up to this many characters
MARKS_ROW_CHARS = 190  # the markings legend in one row up to this many characters, else two


def kind_drives() -> dict[str, list[str]]:
    """The drives of each kind, in the registry's order: the `plot` of each
    drive's facts file (InputError naming the file and the key when one is
    missing or wrong, or names no kind of KINDS)."""
    global _KIND_DRIVES
    if _KIND_DRIVES is None:
        try:
            facts = drive_facts.load_all()
        except drive_facts.FactsError as e:
            raise InputError(str(e)) from None
        out: dict[str, list[str]] = {kind: [] for kind in KINDS}
        for name, f in facts.items():
            if f.plot not in KINDS:
                raise InputError(f"{f.rel()}: plot: unknown kind {f.plot!r} (plot_run.py's: {', '.join(KINDS)})")
            out[f.plot].append(name)
        _KIND_DRIVES = out
    return _KIND_DRIVES


_KIND_DRIVES: dict[str, list[str]] | None = None


def kind_title(kind: str) -> str:
    """'speed run, drive a / b': the kind's title and its drives (without
    them, and a warning, when a facts file is wrong: the plot does not need
    them; ctest tools.drive_facts fails on it)."""
    try:
        drives = kind_drives()[kind]
    except InputError as e:
        print(f"plot_run.py: warning: {e}", file=sys.stderr)
        drives = []
    return f"{KINDS[kind]['title']}, drive {' / '.join(drives)}" if drives else KINDS[kind]["title"]


def panel_help() -> str:
    lines = []
    try:
        drives = kind_drives()
    except InputError as e:
        drives, lines = {}, [f"({e})"]
    for kind, k in KINDS.items():
        of = f"; drive {' / '.join(drives[kind])}" if drives.get(kind) else ""
        lines.append(f"{kind} runs (CSV header with {k['key']}{of}), in the default order:")
        lines += [f"  {name:15s} {h}" for name, (h, _) in k["panels"].items()]
    return "\n".join(lines)


# ------------------------------------------------------------------ helpers --
def fail(msg: str, code: int = 2) -> int:
    print(f"plot_run.py: {msg}", file=sys.stderr)
    return code


def read_header(path: Path) -> tuple[list[str], int | None]:
    """Column names, and the number of values in the first data row (None: no rows)."""
    with path.open(encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        first = f.readline().strip()
    return header, (len(first.split(",")) if first else None)


def detect_kind(header: list[str]) -> str:
    """A kind of KINDS, from the column that identifies it."""
    for kind, k in KINDS.items():
        if k["key"] in header:
            return kind
    keys = " or ".join(k["key"] for k in KINDS.values())
    kinds = ", ".join(f"{kind} run" for kind in KINDS)
    raise InputError(f"not a motorsim run CSV: the header has no {keys} column "
                     f"({kinds}); it starts with {','.join(header[:4])}")


def parse_panels(spec: str | None, kind: str) -> list[str]:
    """The panel names of a --panels list (order kept, repeats dropped); all by default."""
    names = list(KINDS[kind]["panels"])
    if spec is None:
        return names
    asked = [p.strip() for p in spec.split(",") if p.strip()]
    if not asked:
        raise InputError(f"--panels: no panel named (available for a {kind} run: {', '.join(names)})")
    unknown = [p for p in asked if p not in names]
    if unknown:
        raise InputError(f"--panels: unknown panel(s) {', '.join(unknown)} for a {kind} run "
                         f"(available: {', '.join(names)})")
    return list(dict.fromkeys(asked))


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


def find_fault(t, mode, fault, np) -> tuple[int, float] | None:
    """(code, time) of the first sample with a fault code or in fault mode; None: no fault."""
    hit = np.flatnonzero((fault != 0) | (mode == MODE_FAULT))
    if len(hit) == 0:
        return None
    k = hit[0]
    codes = fault[hit]
    code = int(codes[codes != 0][0]) if np.any(codes != 0) else 0
    return code, float(t[k])


def fault_name(code: int) -> str:
    name = FAULT_NAMES.get(code, (None,))[0]
    return f"{code} {name}" if name else f"{code} (unknown code, see drive_fault_t)"


def fault_text(code: int, t_s: float) -> str:
    """The title line of a faulted run: 'FAULT 1 OVERCURRENT at t = 0.2436 s (...)'."""
    meaning = FAULT_NAMES.get(code, (None, None))[1]
    why = f" ({meaning})" if meaning else ""
    return (f"FAULT {fault_name(code)} at t = {t_s:.6g} s{why}: "
            "the drive is in its safe state (0 V) from then on")


def fmt_value(v, unit: str) -> str:
    return f"{v:.3g} {unit}"


def headline(csv: Path, kind: str, faulted: bool = False, windowed: bool = False) -> list[str]:
    """Title lines with the headline metrics of RUN_metrics.json, with units ([]: no file)."""
    metrics = csv.with_name(csv.stem + "_metrics.json")
    if not metrics.is_file():
        return []
    try:
        m = json.loads(metrics.read_text())
    except (OSError, ValueError):
        return []
    if not isinstance(m, dict):
        return []
    parts = []
    for key, label, unit in KINDS[kind]["metrics"]:
        if key not in m:
            continue
        v = m[key]
        if isinstance(v, bool):
            continue
        if isinstance(v, (int, float)) and math.isfinite(v):
            parts.append(f"{label} = {fmt_value(v, unit)}")
        elif v is None and key == "lock_time_s":
            parts.append("angle lock: never")
    if not parts:
        return []
    lines = [parts[0]]
    for part in parts[1:]:
        if len(lines[-1]) + 3 + len(part) > TITLE_LINE_CHARS:
            lines.append(part)
        else:
            lines[-1] += "   " + part
    if faulted:
        lines.insert(0, KINDS[kind]["fault_note"])
    elif windowed:
        lines[0] = "whole run: " + lines[0]
    return lines


def title_lines(csv: Path, kind: str, window: tuple[float, float] | None,
                fault: tuple[int, float] | None) -> tuple[str, str | None]:
    """(black title text, red fault line or None)."""
    head = f"motorsim: {csv.stem} ({kind_title(kind)})"
    if window is not None:
        head += f", t = {window[0]:.6g} s to {window[1]:.6g} s"
    lines = [head] + headline(csv, kind, faulted=fault is not None, windowed=window is not None)
    return "\n".join(lines), (fault_text(*fault) if fault is not None else None)


def legend_spot(leg, axes, traces, r, np, avoid=()) -> str:
    """The first LEGEND_SPOTS entry where leg covers about the fewest samples of traces.

    traces: (axes, [(x, y)]) pairs, the panel's and its twin's (each in
    its own y limits); avoid: window extents (pixels) of texts the legend
    must not hide, each counted as a full box of samples.
    """
    box = axes.get_window_extent(r)
    lb = leg.get_window_extent(r)
    pad = leg.borderaxespad * leg.prop.get_size_in_points() * axes.figure.dpi / 72
    w, h = (lb.width + pad) / box.width, (lb.height + pad) / box.height
    xs, ys = [], []
    for ax, lines in traces:
        x0, x1 = ax.get_xlim()
        y0, y1 = ax.get_ylim()
        for x, y in lines:
            xs.append((x - x0) / (x1 - x0))
            ys.append((y - y0) / (y1 - y0))
    x = np.concatenate(xs) if xs else np.empty(0)
    y = np.concatenate(ys) if ys else np.empty(0)
    ok = np.isfinite(y)
    x, y = x[ok], y[ok]
    counts = []
    for s in LEGEND_SPOTS:
        bx = {"right": (1 - w, 1), "left": (0, w), "center": ((1 - w) / 2, (1 + w) / 2)}[s.split()[1]]
        by = (1 - h, 1) if s.startswith("upper") else (0, h)
        n = np.count_nonzero((x >= bx[0]) & (x <= bx[1]) & (y >= by[0]) & (y <= by[1]))
        for e in avoid:  # a text under the legend: as bad as a box full of samples
            ex0, ex1 = (e.x0 - box.x0) / box.width, (e.x1 - box.x0) / box.width
            ey0, ey1 = (e.y0 - box.y0) / box.height, (e.y1 - box.y0) / box.height
            if ex0 < bx[1] and ex1 > bx[0] and ey0 < by[1] and ey1 > by[0]:
                n += len(x) + 1
        counts.append(n)
    # The first spot (in order of preference) about as free as the freest:
    # over a flat line the legend hides as many samples as over a transient.
    good = min(counts) * LEGEND_SLACK + 0.005 * len(x)
    return next(s for s, n in zip(LEGEND_SPOTS, counts) if n <= good)


def twin(a):
    """Right-hand axis for an error signal, drawn below the main curves."""
    b = a.twinx()
    a.set_zorder(b.get_zorder() + 1)
    a.patch.set_visible(False)
    return b


def arrange(fig, header, axes, twins) -> None:
    """Places the header and the stacked axes as layout="constrained" did, in one pass.

    header: the figure-level artists stacked from the top (texts with
    va="top", legends with loc="upper center"), each below the previous.
    Constrained layout measures every axis of every axes twice, about a
    quarter of the time this script took. Here the margins come from the
    parts that set them: the header (top), the bottom x axis (bottom), the y
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

    top = pad
    for item in header:
        y = 1 - top / H
        if hasattr(item, "set_bbox_to_anchor"):  # a legend
            item.set_bbox_to_anchor((0.5, y), transform=fig.transFigure)
        else:
            item.set_y(y)
        top += item.get_window_extent(r).height + pad
    top += 2 * pad
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


# ------------------------------------------------------------------- panels --
# Each draws one panel on axes a from the context c and returns its twin
# axes (or None). c.plot(axis, y, fmt, ...) draws against the window's time.

def pos_position(a, c):
    d = c.d
    c.plot(a, d["theta_ref_rad"], "r", lw=1.2, label="θ_ref")
    c.plot(a, d["theta_rad"], "b", lw=1.0, label="θ (true)")
    c.plot(a, c.est(d["theta_est_rad"]), "g--", lw=1.0, label="θ_est")
    a.set_ylabel("position [rad]")


def pos_position_error(a, c):
    d = c.d
    c.plot(a, c.est(d["theta_rad"] - d["theta_ref_rad"]), "b", lw=0.8, label="θ - θ_ref (tracking)")
    c.plot(a, c.est(d["theta_rad"] - d["theta_est_rad"]), "g", lw=0.8, label="θ - θ_est (observation)")
    a.set_ylabel("position error [rad]")


def pos_velocity(a, c):
    d = c.d
    c.plot(a, d["omega_ref_rad_s"], "r", lw=1.2, label="ω_ref")
    c.plot(a, d["omega_rad_s"], "b", lw=0.8, label="ω (true)")
    c.plot(a, c.est(d["omega_est_rad_s"]), "g", lw=0.6, label="ω_est")
    a.set_ylabel("velocity [rad/s]")
    b = twin(a)
    c.plot(b, c.est(d["omega_rad_s"] - d["omega_est_rad_s"]), "-", color="0.5", lw=0.5,
           label="ω - ω_est (right axis)")
    b.set_ylabel("ω - ω_est [rad/s]", color="0.4")
    return b


def pos_current(a, c):
    d = c.d
    c.plot(a, d["i_f_A"], "b", lw=0.6, label="i_f")
    c.plot(a, d["i_g_A"], "c", lw=0.6, label="i_g")
    c.plot(a, d["i_f_est_A"], "m:", lw=0.8, label="i_f est.")
    c.plot(a, d["i_g_est_A"], "y:", lw=0.8, label="i_g est.")
    a.set_ylabel("(f-g) current [A]\nframe at n_p θ_ref")
    b = twin(a)
    c.plot(b, c.est(d["i_f_A"] - d["i_f_est_A"]), "-", color="0.3", lw=0.4, label="i_f - i_f est. (right axis)")
    c.plot(b, c.est(d["i_g_A"] - d["i_g_est_A"]), "-", color="0.6", lw=0.4, label="i_g - i_g est. (right axis)")
    b.set_ylabel("observer error [A]", color="0.4")
    return b


def pos_disturbance(a, c):
    d = c.d
    c.plot(a, d["e_f_V"], "b", lw=0.8, label="e_f = K ω sin(n_p Δθ)")
    c.plot(a, d["e_g_V"], "c", lw=0.8, label="e_g = -K ω cos(n_p Δθ)")
    c.plot(a, d["e_f_est_V"], "m:", lw=0.8, label="e_f est.")
    c.plot(a, d["e_g_est_V"], "y:", lw=0.8, label="e_g est.")
    a.set_ylabel("(f-g) back-EMF [V]\nframe at n_p θ_ref")


def pos_load(a, c):
    d = c.d
    c.plot(a, d["load_Nm"], "b", lw=1.0, label="C_r true (Coulomb friction + load)")
    c.plot(a, c.est(d["load_est_Nm"]), "g", lw=0.8, label="C_r est. (mech. observer (33)-(37))", zorder=EST_Z)
    a.set_ylabel("load torque [N m]")


def pos_voltage(a, c):
    d = c.d
    c.plot(a, d["v_a_V"], "b", lw=0.4, label="v_a")
    c.plot(a, d["v_b_V"], "c", lw=0.4, label="v_b")
    a.set_ylabel("phase voltage [V]")


def spd_speed(a, c):
    d = c.d
    c.plot(a, d["omega_ref_rad_s"] * RAD_S_TO_RPM, "r", lw=1.4, label="ω* (reference)")
    c.plot(a, d["omega_rad_s"] * RAD_S_TO_RPM, "b", lw=1.0, label="ω (true)")
    c.plot(a, d["omega_est_rad_s"] * RAD_S_TO_RPM, "g", lw=0.6, label="ω_est", zorder=EST_Z)
    a.set_ylabel("speed [rpm]")


def spd_speed_error(a, c):
    d = c.d
    c.plot(a, (d["omega_rad_s"] - d["omega_ref_rad_s"]) * RAD_S_TO_RPM, "b", lw=0.8,
           label="ω - ω* (tracking)")
    c.plot(a, (d["omega_rad_s"] - d["omega_est_rad_s"]) * RAD_S_TO_RPM, "g", lw=0.6,
           label="ω - ω_est (estimation)", zorder=EST_Z)
    a.set_ylabel("speed error [rpm]")


def spd_angle_error(a, c):
    c.plot(a, c.np.degrees(c.d["theta_e_err_rad"]), "-", color="tab:purple", lw=0.6,
           label="θ_e,est - θ_e (electrical, wrapped to ±180°)")
    a.set_ylabel("angle error [° el.]")


def spd_load(a, c):
    d = c.d
    c.plot(a, d["load_Nm"], "b", lw=1.2, label="τ_L true (load + friction)")
    c.plot(a, d["load_est_Nm"], "g", lw=0.7, label="τ_L est. (I&I observer)", zorder=EST_Z)
    a.set_ylabel("load torque [N m]")


def spd_current(a, c):
    d = c.d
    c.plot(a, d["i_d_meas_A"], "-", color="tab:blue", lw=0.6, label="i_d")
    c.plot(a, d["i_q_meas_A"], "-", color="tab:orange", lw=0.6, label="i_q")
    c.plot(a, d["i_q_ref_A"], "k", lw=0.9, label="i_q reference", zorder=EST_Z)
    a.set_ylabel("d-q current [A]\n(frame at θ_e,est)")


def spd_voltage(a, c):
    d = c.d
    c.plot(a, d["v_a_V"], "b", lw=0.4, label="v_a")
    c.plot(a, d["v_b_V"], "c", lw=0.4, label="v_b")
    if c.np.any(d["v_c_V"] != 0):  # two-phase motors: v_c is 0
        c.plot(a, d["v_c_V"], "-", color="tab:orange", lw=0.4, label="v_c")
    a.set_ylabel("phase voltage [V]")


def ekf_speed(a, c):
    d = c.d
    c.plot(a, d["omega_d_rad_s"], "r", lw=1.4, label="ω_d (reference)")
    c.plot(a, d["omega_rad_s"], "b", lw=1.0, label="ω (true)")
    c.plot(a, d["omega_est_rad_s"], "g", lw=0.6, label="ω_est (EKF)", zorder=EST_Z)
    a.set_ylabel("speed [rad/s]")


def ekf_speed_error(a, c):
    d = c.d
    c.plot(a, d["omega_d_rad_s"] - d["omega_rad_s"], "b", lw=0.8, label="ω_d - ω (tracking)")
    c.plot(a, d["omega_est_rad_s"] - d["omega_rad_s"], "g", lw=0.5, label="ω_est - ω (estimation)", zorder=EST_Z)
    a.set_ylabel("speed error [rad/s]")


def ekf_disturbance(a, c):
    d = c.d
    c.plot(a, d["M0_Nm"], "b", lw=1.2, label="M_0 true (load + friction)")
    c.plot(a, d["M0_est_Nm"], "g", lw=0.6, label="M_0 est. (EKF)", zorder=EST_Z)
    c.plot(a, d["M_d_Nm"], "k", lw=0.6, label="torque demand")
    a.set_ylabel("torque [N m]")


def ekf_current(a, c):
    d = c.d
    c.plot(a, d["i_d_A"], "-", color="tab:blue", lw=0.6, label="i_d")
    c.plot(a, d["i_q_A"], "-", color="tab:orange", lw=0.6, label="i_q")
    c.plot(a, d["i_d_ref_A"], "k--", lw=0.8, label="i_d reference (MTPA)", zorder=EST_Z)
    c.plot(a, d["i_q_ref_A"], "k", lw=0.8, label="i_q reference", zorder=EST_Z)
    a.set_ylabel("d-q current [A]\n(encoder frame)")


def ekf_voltage(a, c):
    d = c.d
    c.plot(a, d["u_d_V"], "b", lw=0.4, label="u_d")
    c.plot(a, d["u_q_V"], "c", lw=0.4, label="u_q")
    a.set_ylabel("d-q voltage [V]")


PANEL_DRAW = {
    "position": {"position": pos_position, "position_error": pos_position_error, "velocity": pos_velocity,
                 "current": pos_current, "disturbance": pos_disturbance, "load": pos_load,
                 "voltage": pos_voltage},
    "speed": {"speed": spd_speed, "speed_error": spd_speed_error, "angle_error": spd_angle_error,
              "load": spd_load, "current": spd_current, "voltage": spd_voltage},
    "ekf_speed": {"speed": ekf_speed, "speed_error": ekf_speed_error, "disturbance": ekf_disturbance,
                  "current": ekf_current, "voltage": ekf_voltage},
}


class Context:
    """What the panel functions draw from: the window's columns d, time t, np."""

    def __init__(self, t, d, mode, np):
        self.t, self.d, self.np = t, d, np
        self.closed = mode == MODE_CLOSED
        self.pick = envelope(len(t), ENVELOPE_BINS, np)
        self.drawn = {}  # axes -> True once a trace with a finite sample is drawn
        self.traces = {}  # axes -> [(t, y)] as drawn, decimated (for legend_spot)

    def est(self, x):
        """Estimates only where the drive uses them (closed loop), as in the paper."""
        return self.np.where(self.closed, x, self.np.nan)

    def plot(self, axis, y, fmt, **kw):
        """axis.plot(t, y, fmt, ...): a solid line from y's min/max envelope,
        a dashed or dotted one from every sample (its pattern runs along the
        whole path: thinned, a noisy trace would look sparser)."""
        if self.np.any(self.np.isfinite(y)):
            self.drawn[axis] = True
        idx = self.pick(y)
        self.traces.setdefault(axis, []).append((self.t[idx], y[idx]))
        if any(style in fmt for style in ("--", "-.", ":")):
            return axis.plot(self.t, y, fmt, **kw)
        return axis.plot(self.t[idx], y[idx], fmt, **kw)


# --------------------------------------------------------------------- plot --
def import_plotting():
    """numpy, Figure, FigureCanvasAgg (ImportError if not installed)."""
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")  # files only, no display needed
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    return np, Figure, FigureCanvasAgg


def make_figure(csv: Path, t_start: float | None = None, t_end: float | None = None,
                panels: str | None = None):
    """The Figure of one run CSV (InputError: bad input; ImportError: no numpy/matplotlib)."""
    np, Figure, FigureCanvasAgg = import_plotting()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    if not csv.is_file():
        raise InputError(f"no such file: {csv}")
    try:
        header, n_first = read_header(csv)
    except (OSError, ValueError) as e:
        raise InputError(f"cannot read {csv}: {e}") from None
    kind = detect_kind(header)
    names = parse_panels(panels, kind)
    spec = KINDS[kind]
    if panels is None:  # the default panels the drive's signals allow
        lacking = {p: [c for c in spec["panels"][p][1] if c not in header] for p in names}
        skipped = [p for p in names if lacking[p]]
        if skipped and len(skipped) < len(names):
            print("plot_run.py: panel(s) left out, their columns not in the CSV (signals the drive does not "
                  "have): " + "; ".join(f"{p} ({', '.join(lacking[p])})" for p in skipped), file=sys.stderr)
            names = [p for p in names if not lacking[p]]
    needed = list(dict.fromkeys(spec["base"] + [c for p in names for c in spec["panels"][p][1]]))
    missing = [c for c in needed if c not in header]
    if missing:
        raise InputError(f"{csv}: missing column(s) for a {kind} run: {', '.join(missing)}")
    if n_first is None:
        raise InputError(f"{csv}: no data rows")
    if n_first != len(header):
        raise InputError(f"cannot read {csv}: {n_first} values per row, {len(header)} column names")
    try:
        d = load_columns(csv, header, needed, np)
    except (OSError, ValueError) as e:
        raise InputError(f"cannot read {csv}: {e}") from None

    t_all = d["t_s"]
    fault = find_fault(t_all, d["mode"], d["fault"], np)  # of the whole run, also outside the window
    window = None
    if t_start is not None or t_end is not None:
        lo = t_all[0] if t_start is None else max(t_start, t_all[0])
        hi = t_all[-1] if t_end is None else min(t_end, t_all[-1])
        keep = (t_all >= lo) & (t_all <= hi)
        if np.count_nonzero(keep) < 2:
            span = f"the run covers {t_all[0]:.6g} s to {t_all[-1]:.6g} s"
            if t_start is not None and t_start >= t_all[-1]:
                raise InputError(f"--t-start {t_start:g} s: at or after the end of the run ({span})")
            if t_end is not None and t_end <= t_all[0]:
                raise InputError(f"--t-end {t_end:g} s: at or before the start of the run ({span})")
            raise InputError(f"fewer than 2 samples from {lo:.6g} s to {hi:.6g} s ({span})")
        d = {k: v[keep] for k, v in d.items()}
        window = (lo, hi)
    t = d["t_s"]
    mode = d["mode"].astype(int)
    c = Context(t, d, mode, np)

    # Markings: the same on every panel, in one legend under the title.
    marks = []
    closed_iv = intervals(c.closed, t, np)
    fault_iv = intervals(mode == MODE_FAULT, t, np)
    normal = mode != MODE_FAULT
    sw = np.flatnonzero((np.diff(mode) != 0) & normal[1:] & normal[:-1]) + 1
    switches = t[sw]
    valid_iv = intervals(d["estimate_valid"] != 0, t, np) if kind == "speed" else []
    t_fault = fault[1] if fault is not None and t[0] <= fault[1] <= t[-1] else None
    green, valid_c = dict(color="tab:green", alpha=0.09, lw=0), dict(color="tab:blue", alpha=0.45, lw=0)
    red = dict(color="tab:red", alpha=0.13, lw=0)
    marks.append(Patch(**green, label="closed loop (drive mode 1)" if closed_iv else
                       "closed loop (drive mode 1): none in this plot"))
    if len(switches):
        marks.append(Line2D([], [], color="magenta", lw=0.8, label="open/closed-loop switch"))
    if kind == "speed":
        marks.append(Patch(**valid_c, label="estimate valid (drive flag; band at the bottom)" if valid_iv else
                           "estimate valid: never in this plot"))
    if fault_iv:
        marks.append(Patch(**red, label="fault: safe state, 0 V (drive mode 2)"))
    if fault is not None:
        where = "" if t_fault is not None else " (outside this plot)"
        marks.append(Line2D([], [], color="red", lw=1.6,
                            label=f"FAULT {fault_name(fault[0])} at t = {fault[1]:.6g} s{where}"))
    one_row = sum(len(m.get_label()) + 8 for m in marks) <= MARKS_ROW_CHARS

    title, fault_line = title_lines(csv, kind, window, fault)
    fg_note = kind == "position" and any(p in ("current", "disturbance") for p in names)
    n_title = title.count("\n") + 1 + (fault_line is not None) + fg_note + (not one_row)
    fig_h = HEADER_IN + TITLE_LINE_IN * n_title + PANEL_IN * len(names)
    fig = Figure(figsize=(FIG_WIDTH_IN, fig_h), dpi=DPI)
    FigureCanvasAgg(fig)
    ax = fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
    header_artists = [fig.suptitle(title, fontsize=11, va="top")]
    if fault_line is not None:
        header_artists.append(fig.text(0.5, 1, fault_line, color="red", fontsize=11, fontweight="bold",
                                       ha="center", va="top"))

    twins = []
    panel_twin = []
    for a, name in zip(ax, names):
        b = PANEL_DRAW[kind][name](a, c)
        panel_twin.append(b)
        if b is not None:
            twins.append(b)

    for a in ax:  # the markings
        for (t0, t1) in closed_iv:
            a.axvspan(t0, t1, **green)
        for (t0, t1) in valid_iv:
            a.axvspan(t0, t1, ymin=0, ymax=0.025, **valid_c)
        for (t0, t1) in fault_iv:
            a.axvspan(t0, t1, **red)
        for ts in switches:
            a.axvline(ts, color="magenta", lw=0.8)
        if t_fault is not None:
            a.axvline(t_fault, color="red", lw=1.6)
    header_artists.append(fig.legend(handles=marks, loc="upper center", fontsize=9, frameon=False,
                                     ncol=len(marks) if one_row else (len(marks) + 1) // 2,
                                     handlelength=2.0, columnspacing=1.5))
    if fg_note:
        header_artists.append(fig.text(0.5, 1, F_G_NOTE, fontsize=9, color="0.25", ha="center", va="top"))
    if t_fault is not None:
        right = (t_fault - t[0]) > 0.75 * (t[-1] - t[0])
        ax[0].annotate(f"FAULT {fault_name(fault[0])}\nt = {fault[1]:.6g} s", xy=(t_fault, 0.5),
                       xycoords=("data", "axes fraction"), xytext=(-6 if right else 6, 0),
                       textcoords="offset points", ha="right" if right else "left", va="center",
                       color="red", fontweight="bold", fontsize=10, zorder=6,
                       bbox=dict(boxstyle="round,pad=0.3", fc="white", ec="red", alpha=0.9))

    legends = []
    for a, b in zip(ax, panel_twin):
        a.grid(True, lw=0.3)
        handles, labels = a.get_legend_handles_labels()
        if b is not None:
            h2, l2 = b.get_legend_handles_labels()
            handles, labels = handles + h2, labels + l2
        if b is not None and not c.drawn.get(b):
            b.set_yticks([])  # no closed loop: no error to scale (not a fake 0.05 range)
        if not c.drawn.get(a) and not (b is not None and c.drawn.get(b)):
            a.text(0.5, 0.5, "no closed loop in this plot: estimates are drawn in closed loop only",
                   transform=a.transAxes, ha="center", va="center", fontsize=9, color="0.3")
        legends.append(a.legend(handles, labels, loc=LEGEND_SPOTS[0], fontsize=8,
                                ncol=1 if len(handles) <= 2 else 2 if len(handles) <= 4 else 3,
                                framealpha=0.85))
    ax[-1].set_xlabel("time [s]")
    if t[-1] > t[0]:
        ax[0].set_xlim(t[0], t[-1])
    arrange(fig, header_artists, ax, twins)
    r = fig.canvas.get_renderer()
    for a, b, leg in zip(ax, panel_twin, legends):
        traces = [(a, c.traces.get(a, []))] + ([(b, c.traces.get(b, []))] if b is not None else [])
        avoid = [x.get_window_extent(r) for x in a.texts]
        leg.set_loc(legend_spot(leg, a, traces, r, np, avoid))
    return fig


class ArgError(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2, instead of argparse's usage block
        raise ArgError(message)


def parse_args(argv: list[str]) -> argparse.Namespace:
    p = Parser(prog="plot_run.py", formatter_class=argparse.RawDescriptionHelpFormatter,
               description="Plots one motorsim run CSV (a position, speed or EKF speed run, told from the "
                           "header) into a PNG.",
               epilog="panels (--panels NAME,...):\n" + panel_help() + "\n\n" + F_G_NOTE + ".\n"
                      "Exit status: 0 ok, 2 bad input, 3 numpy/matplotlib missing.")
    p.add_argument("csv", metavar="RUN.csv", type=Path, help="the CSV motorsim wrote")
    p.add_argument("png", metavar="OUT.png", type=Path, help="the PNG to write")
    p.add_argument("--t-start", type=float, metavar="S", help="start of the time window [s] (default: run start)")
    p.add_argument("--t-end", type=float, metavar="S", help="end of the time window [s] (default: run end)")
    p.add_argument("--panels", metavar="NAME,...",
                   help="comma list of panels to draw, in this order (default: all; names below)")
    a = p.parse_args(argv)
    for opt in ("t_start", "t_end"):
        v = getattr(a, opt)
        if v is not None and not math.isfinite(v):
            raise ArgError(f"--{opt.replace('_', '-')} must be a finite time in seconds (got {v})")
    if a.t_start is not None and a.t_end is not None and a.t_end <= a.t_start:
        raise ArgError(f"--t-end ({a.t_end:g} s) must be greater than --t-start ({a.t_start:g} s)")
    return a


USAGE = "usage: plot_run.py [--t-start S] [--t-end S] [--panels NAME,...] RUN.csv OUT.png; --help lists the panels"


def main(argv: list[str]) -> int:
    try:
        args = parse_args(argv[1:])
    except ArgError as e:
        return fail(f"{e}; {USAGE}")
    try:
        fig = make_figure(args.csv, args.t_start, args.t_end, args.panels)
    except ImportError as e:
        return fail(f"{e.name} is not installed (run scripts/setup.sh for the project venv)", 3)
    except InputError as e:
        return fail(str(e))
    args.png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.png, dpi=DPI, pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})
    return 0


if __name__ == "__main__":
    status = main(sys.argv)
    # Everything is written and closed: skip the interpreter's teardown of
    # numpy and matplotlib (~0.1 s of a ~1 s run).
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
