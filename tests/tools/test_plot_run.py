"""tools/plot/plot_run.py on synthetic motorsim CSVs (position runs of paper
000, speed runs of paper 001): PNG written, bad input rejected with a clear
one-line message and exit 2; --t-start/--t-end/--panels; faults named in
the title and on the plot; every marking in a legend; long runs drawn from
min/max envelopes that keep every bin's extremes, with the axes laid out
inside the figure."""
from __future__ import annotations

import importlib.util
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PLOT = ROOT / "tools" / "plot" / "plot_run.py"

# sim/motorsim/position_recorder.cpp, kPositionColumnNames, then paper 000's
# signals (firmware/drives/paper000/paper000_ops.c)
COLUMNS = ("t_s,mode,theta_ref_rad,omega_ref_rad_s,accel_ref_rad_s2,theta_rad,theta_est_rad,omega_rad_s,"
           "omega_est_rad_s,accel_rad_s2,accel_est_rad_s2,load_Nm,load_est_Nm,i_a_A,i_b_A,i_a_meas_A,i_b_meas_A,"
           "i_f_A,i_g_A,e_f_V,e_g_V,v_a_V,v_b_V,delta_theta_rad,fault,i_f_meas_A,i_g_meas_A,i_f_ref_A,i_g_ref_A,"
           "i_f_est_A,i_g_est_A,e_f_est_V,e_g_est_V,v_f_V,v_g_V,delta_theta_est_rad,jump_count,model_R_ohm,"
           "model_L_H,model_K_V_s,rl_id_state,k_id_state,relocks").split(",")


# sim/motorsim/speed_recorder.cpp, kSpeedColumnNames, then the d-q signals
# of paper 001's drive (firmware/drives/paper001/paper001_ops.c)
SPEED_COLUMNS = ("t_s,mode,omega_ref_rad_s,omega_rad_s,omega_est_rad_s,theta_e_rad,theta_e_est_rad,"
                 "theta_e_err_rad,load_Nm,load_est_Nm,i_a_A,i_b_A,i_c_A,v_alpha_V,v_beta_V,v_a_V,v_b_V,v_c_V,"
                 "estimate_quality,estimate_valid,fault,i_d_meas_A,i_q_meas_A,i_q_ref_A,v_d_V,v_q_V,"
                 "R_obs_ohm").split(",")


def write_csv(path: Path, n: int = 400, drop: str | None = None, fault_at: int | None = None) -> None:
    """A position run: open loop, closed loop from |ω| >= 3, open loop; a
    fault (code 1) from sample fault_at on."""
    cols = [c for c in COLUMNS if c != drop]
    lines = [",".join(cols)]
    for k in range(n):
        t = k * 1e-3
        w = 10 * math.sin(math.pi * t / (n * 1e-3))
        row = {c: 0.01 * math.sin(k * 0.1 + i) for i, c in enumerate(COLUMNS)}
        row.update(t_s=t, omega_ref_rad_s=w, omega_rad_s=w, omega_est_rad_s=w + 0.1, mode=1 if abs(w) >= 3 else 0,
                   fault=0, jump_count=0)
        if fault_at is not None and k >= fault_at:
            row.update(mode=2, fault=1)
        lines.append(",".join(f"{row[c]:.9g}" for c in cols))
    path.write_text("\n".join(lines) + "\n")


def write_speed_csv(path: Path, n: int = 3000, fault_at: int | None = None, two_phase: bool = False) -> None:
    """A speed run: open-loop start, closed loop with a valid estimate from
    0.5 s, a load step at 1.5 s; a fault (code 1) from sample fault_at on."""
    lines = [",".join(SPEED_COLUMNS)]
    for k in range(n):
        t = k * 1e-3
        w = min(t, 1.0) * 10.0
        row = {c: 0.01 * math.sin(k * 0.1 + i) for i, c in enumerate(SPEED_COLUMNS)}
        closed = t >= 0.5
        row.update(t_s=t, mode=1 if closed else 0, omega_ref_rad_s=w, omega_rad_s=w + 0.05 * math.sin(t * 30),
                   omega_est_rad_s=w, load_Nm=1.0 if t >= 1.5 else 0.0, load_est_Nm=0.9 if t >= 1.55 else 0.0,
                   estimate_valid=1 if closed else 0, fault=0)
        for i, ph in enumerate("abc"):
            row[f"v_{ph}_V"] = 0.0 if (two_phase and ph == "c") else 5 * math.sin(20 * t - 2.0944 * i)
        if fault_at is not None and k >= fault_at:
            row.update(mode=2, fault=1, estimate_valid=0)
        lines.append(",".join(f"{row[c]:.9g}" for c in SPEED_COLUMNS))
    path.write_text("\n".join(lines) + "\n")


def plot(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(PLOT), *args], capture_output=True, text=True, timeout=120)


def test_writes_png_with_metrics_title(tmp_path):
    csv = tmp_path / "run.csv"
    write_csv(csv)
    (tmp_path / "run_metrics.json").write_text(json.dumps({"theta_track_max_rad": 0.012}))
    png = tmp_path / "sub" / "run.png"
    r = plot(str(csv), str(png))
    assert r.returncode == 0, r.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 20000


def test_missing_column_is_named(tmp_path):
    csv = tmp_path / "run.csv"
    write_csv(csv, drop="mode")  # one every plot needs
    r = plot(str(csv), str(tmp_path / "x.png"))
    assert r.returncode == 2
    assert "mode" in r.stderr
    assert not (tmp_path / "x.png").exists()


def test_panel_of_a_missing_signal(tmp_path):
    """A drive without a signal a default panel needs: that panel is left
    out (named); asked for by --panels, it is an error naming the column."""
    csv = tmp_path / "run.csv"
    write_csv(csv, drop="e_f_est_V")
    r = plot(str(csv), str(tmp_path / "x.png"))
    assert r.returncode == 0, r.stderr
    assert "disturbance (e_f_est_V)" in r.stderr
    assert (tmp_path / "x.png").is_file()
    r = plot("--panels", "position,disturbance", str(csv), str(tmp_path / "y.png"))
    assert r.returncode == 2
    assert "e_f_est_V" in r.stderr
    assert not (tmp_path / "y.png").exists()


def test_missing_csv(tmp_path):
    r = plot(str(tmp_path / "nope.csv"), str(tmp_path / "x.png"))
    assert r.returncode == 2
    assert "no such file" in r.stderr


def test_usage():
    r = plot()
    assert r.returncode == 2
    assert "usage:" in r.stderr
    assert plot("--help").returncode == 0


def load_module():
    spec = importlib.util.spec_from_file_location("plot_run", PLOT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_envelope_keeps_every_bin_extreme():
    np = pytest.importorskip("numpy")
    mod = load_module()
    rng = np.random.default_rng(1)
    n, bins = 100_003, 1000
    y = np.sin(np.arange(n) * 1e-4) + 0.3 * rng.standard_normal(n)  # chattering on a slow wave
    y[20_000:30_000] = np.nan  # an estimate masked out (open loop)
    y[55_555] = 9.0  # a one-sample spike
    idx = mod.envelope(n, bins, np)(y)
    assert len(idx) <= 2 * bins + 2
    assert np.all(np.diff(idx) >= 0), "indices in time order"
    k = -(-n // bins)
    for b0 in range(0, n, k):
        seg = y[b0:b0 + k]
        mine = y[idx[(idx >= b0) & (idx < b0 + k)]]
        if np.all(np.isnan(seg)):
            assert np.all(np.isnan(mine)), "a masked span stays a gap"
        else:
            assert np.nanmin(seg) in mine and np.nanmax(seg) in mine
    assert 9.0 in y[idx]
    # short traces are drawn whole
    assert list(mod.envelope(500, bins, np)(np.zeros(500))) == list(range(500))


def test_long_run_decimated_and_laid_out(tmp_path, monkeypatch):
    np = pytest.importorskip("numpy")
    mod = load_module()
    n = 42_500
    rng = np.random.default_rng(2)
    t = np.arange(n) * 1e-4
    data = 0.01 * rng.standard_normal((n, len(COLUMNS)))
    col = {c: i for i, c in enumerate(COLUMNS)}
    w = 20 * np.sin(np.pi * t / t[-1])
    data[:, col["t_s"]] = t
    data[:, col["omega_ref_rad_s"]] = w
    data[:, col["omega_rad_s"]] = w
    data[:, col["mode"]] = (np.abs(w) >= 3).astype(float)
    data[:, col["e_f_V"]] = 12345.678 * np.sin(t)  # wide tick labels must not be clipped
    data[:, col["v_b_V"]] = -1e-7 * np.cos(t)  # an offset / scientific tick label
    csv = tmp_path / "long.csv"
    np.savetxt(csv, data, delimiter=",", header=",".join(COLUMNS), comments="", fmt="%.9g")

    from matplotlib.figure import Figure
    figs = []
    save = Figure.savefig

    def capture(self, *a, **kw):
        figs.append(self)
        return save(self, *a, **kw)

    monkeypatch.setattr(Figure, "savefig", capture)
    png = tmp_path / "long.png"
    assert mod.main(["plot_run.py", str(csv), str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fig = figs[0]
    lines = [ln for a in fig.axes for ln in a.get_lines() if len(ln.get_xdata()) > 2]
    solid = [ln for ln in lines if ln.get_linestyle() == "-"]
    styled = [ln for ln in lines if ln.get_linestyle() != "-"]
    assert solid and all(len(ln.get_xdata()) <= 2 * mod.ENVELOPE_BINS + 2 for ln in solid)
    assert styled and all(len(ln.get_xdata()) == n for ln in styled)
    # arrange(): every axes, tick labels and axis labels included, inside the figure
    r = fig.canvas.get_renderer()
    W, H = fig.bbox.width, fig.bbox.height
    for a in fig.axes:
        bb = a.get_tightbbox(r)
        assert bb.x0 >= 0 and bb.y0 >= 0 and bb.x1 <= W and bb.y1 <= H, (a.get_ylabel(), bb)
    # panels do not overlap
    n_panels = len(mod.KINDS["position"]["panels"])
    boxes = sorted((a.get_position() for a in fig.axes[:n_panels]), key=lambda p: -p.y0)
    assert all(upper.y0 > lower.y1 for upper, lower in zip(boxes, boxes[1:]))


# ------------------------------------------------------- speed runs (paper 001) --
def test_speed_run_png(tmp_path):
    csv = tmp_path / "speed.csv"
    write_speed_csv(csv)
    (tmp_path / "speed_metrics.json").write_text(json.dumps({"speed_err_settled_max_rpm": 0.05}))
    png = tmp_path / "speed.png"
    r = plot(str(csv), str(png))
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 20000


def labels(ax):
    return [ln.get_label() for ln in ax.get_lines() if not ln.get_label().startswith("_")]


def test_speed_run_panels(tmp_path):
    mod = load_module()
    csv = tmp_path / "speed.csv"
    write_speed_csv(csv, two_phase=True)
    fig = mod.make_figure(csv)
    names = list(mod.KINDS["speed"]["panels"])
    ax = fig.axes[:len(names)]
    ylabels = [a.get_ylabel() for a in ax]
    assert ylabels[0] == "speed [rpm]"
    assert ylabels[2].startswith("angle error [°")
    assert ylabels[3] == "load torque [N m]"
    assert any("τ_L true" in x for x in labels(ax[3])) and any("τ_L est" in x for x in labels(ax[3]))
    assert {"i_d", "i_q", "i_q reference"} <= set(labels(ax[4]))
    assert labels(ax[5]) == ["v_a", "v_b"], "two phases: v_c (all 0) left out"
    # speeds in rpm: 10 rad/s -> 95.5 rpm
    ref = [ln for ln in ax[0].get_lines() if ln.get_label().startswith("ω*")][0]
    assert max(ref.get_ydata()) == pytest.approx(10 * 60 / (2 * math.pi), rel=1e-6)
    assert all(re.search(r"\[.+\]", y) for y in ylabels), "every axis label has a unit"


# ------------------------------------------------------ window and panel choice --
def test_window_and_panels(tmp_path):
    mod = load_module()
    csv = tmp_path / "run.csv"
    write_csv(csv)
    fig = mod.make_figure(csv, t_start=0.1, t_end=0.25, panels="load,position")
    ax = fig.axes
    assert [a.get_ylabel() for a in ax[:2]] == ["load torque [N m]", "position [rad]"]
    assert len(ax) == 2, "no twin: neither panel has one"
    assert ax[0].get_xlim() == pytest.approx((0.1, 0.25))
    for ln in ax[1].get_lines():
        x = ln.get_xdata()
        if len(x) > 2:
            assert min(x) >= 0.1 - 1e-12 and max(x) <= 0.25 + 1e-12
    assert "t = 0.1 s to 0.25 s" in fig._suptitle.get_text()
    # the CLI, with a window open at one end
    png = tmp_path / "w.png"
    r = plot(str(csv), str(png), "--t-start", "0.2", "--panels", "velocity")
    assert r.returncode == 0, r.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("args, words", [
    (["--t-start", "0.3", "--t-end", "0.2"], ["--t-end", "greater than --t-start"]),
    (["--t-start", "0.2", "--t-end", "0.2"], ["--t-end", "greater than --t-start"]),
    (["--t-start", "abc"], ["--t-start", "abc"]),
    (["--t-end", "nan"], ["--t-end", "finite"]),
    (["--t-start", "5"], ["--t-start", "after the end of the run"]),
    (["--t-end", "-1"], ["--t-end", "before the start of the run"]),
    (["--panels", "position,bogus"], ["unknown panel", "bogus", "available: position, position_error"]),
    (["--panels", "speed"], ["unknown panel", "speed", "position run"]),
    (["--panels", ","], ["--panels", "no panel"]),
    (["--colour"], ["unrecognized", "--colour"]),
])
def test_bad_options_exit_2(tmp_path, args, words):
    csv = tmp_path / "run.csv"
    write_csv(csv)
    png = tmp_path / "x.png"
    r = plot(str(csv), str(png), *args)
    assert r.returncode == 2, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert r.stderr.startswith("plot_run.py: ")
    for w in words:
        assert w in r.stderr
    assert not png.exists()


def test_speed_panel_names_checked(tmp_path):
    csv = tmp_path / "speed.csv"
    write_speed_csv(csv, n=200)
    r = plot(str(csv), str(tmp_path / "x.png"), "--panels", "position")
    assert r.returncode == 2
    assert "speed run" in r.stderr and "angle_error" in r.stderr


def test_help_lists_panels():
    mod = load_module()
    r = plot("--help")
    assert r.returncode == 0
    for kind in mod.KINDS.values():
        for name in kind["panels"]:
            assert name in r.stdout
    assert "--t-start" in r.stdout and "--t-end" in r.stdout and "--panels" in r.stdout


def test_not_a_run_csv(tmp_path):
    csv = tmp_path / "other.csv"
    csv.write_text("a,b\n1,2\n")
    r = plot(str(csv), str(tmp_path / "x.png"))
    assert r.returncode == 2
    assert "not a motorsim run CSV" in r.stderr and "theta_ref_rad" in r.stderr


# --------------------------------------------------------------------- faults --
def test_fault_text():
    mod = load_module()
    text = mod.fault_text(1, 0.2436)
    assert text.startswith("FAULT 1 OVERCURRENT at t = 0.2436 s")
    assert "i_trip_A" in text
    assert "FAULT 2 BAD_INPUT" in mod.fault_text(2, 0.0)
    assert "FAULT 99" in mod.fault_text(99, 1.5) and "unknown" in mod.fault_text(99, 1.5)


def test_find_fault():
    np = pytest.importorskip("numpy")
    mod = load_module()
    t = np.arange(10) * 0.1
    mode = np.array([0, 1, 1, 1, 2, 2, 2, 2, 2, 2])
    fault = np.array([0, 0, 0, 0, 1, 1, 1, 1, 1, 1])
    assert mod.find_fault(t, mode, fault, np) == (1, pytest.approx(0.4))
    assert mod.find_fault(t, np.minimum(mode, 1), 0 * fault, np) is None


def test_fault_names_match_firmware():
    header = ROOT / "firmware" / "supervisor" / "supervisor.h"
    if not header.is_file():
        pytest.skip("no firmware/supervisor/supervisor.h")
    enum = re.search(r"typedef enum \{([^}]*)\} drive_fault_t;", header.read_text())
    assert enum, "drive_fault_t not found"
    codes = {int(v): n for n, v in re.findall(r"DRIVE_FAULT_(\w+)\s*=\s*(\d+)", enum.group(1))}
    mod = load_module()
    codes = {c: n for c, n in codes.items() if n not in ("NONE", "COUNT")}  # COUNT: a sentinel
    assert codes == {c: v[0] for c, v in mod.FAULT_NAMES.items()}


@pytest.mark.parametrize("kind", ["position", "speed"])
def test_faulted_run_is_marked(tmp_path, kind):
    mod = load_module()
    csv = tmp_path / "run.csv"
    if kind == "position":
        write_csv(csv, fault_at=300)  # t = 0.3 s
        (tmp_path / "run_metrics.json").write_text(json.dumps({"final_theta_err_rad": 17.4, "fault": 1}))
    else:
        write_speed_csv(csv, fault_at=300)
        (tmp_path / "run_metrics.json").write_text(json.dumps({"speed_err_rms_rpm": 80.3, "fault": 1}))
    fig = mod.make_figure(csv)
    texts = [t.get_text() for t in fig.texts]
    fault_lines = [t for t in fig.texts if t.get_text().startswith("FAULT 1 OVERCURRENT at t = 0.3 s")]
    assert fault_lines and fault_lines[0].get_color() == "red", texts
    title = fig._suptitle.get_text()
    assert "whole run" in title  # the metrics say what they cover
    assert ("final |θ-θ_target| = 17.4 rad" in title) if kind == "position" else ("= 80.3 rpm" in title)
    # on the plot: the annotation in the top panel and a red line in every panel
    notes = [t.get_text() for t in fig.axes[0].texts]
    assert any("FAULT 1 OVERCURRENT" in n and "t = 0.3 s" in n for n in notes), notes
    n_panels = len(mod.KINDS[kind]["panels"])
    for a in fig.axes[:n_panels]:
        assert any(ln.get_color() == "red" and list(ln.get_xdata()) == [0.3, 0.3] for ln in a.get_lines())
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any(x.startswith("FAULT 1 OVERCURRENT at t = 0.3 s") for x in legend), legend
    assert any("fault" in x and "mode 2" in x for x in legend), legend


def test_fault_outside_window_still_in_title(tmp_path):
    mod = load_module()
    csv = tmp_path / "run.csv"
    write_csv(csv, fault_at=300)
    fig = mod.make_figure(csv, t_end=0.2)
    assert any(t.get_text().startswith("FAULT 1 OVERCURRENT at t = 0.3 s") for t in fig.texts)
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any("outside this plot" in x for x in legend), legend


# ------------------------------------------------------ legends, units, notes --
def rgb(c):
    from matplotlib.colors import to_rgb
    return tuple(round(v, 3) for v in to_rgb(c))


@pytest.mark.parametrize("kind", ["position", "speed"])
def test_every_marking_in_the_legend(tmp_path, kind):
    mod = load_module()
    csv = tmp_path / "run.csv"
    (write_csv if kind == "position" else write_speed_csv)(csv, fault_at=350 if kind == "position" else 2500)
    fig = mod.make_figure(csv)
    leg = fig.legends[0]
    handles = leg.legend_handles
    legend_colors = {rgb(h.get_facecolor() if hasattr(h, "get_facecolor") and not hasattr(h, "get_xdata")
                         else h.get_color()) for h in handles}
    names = [t.get_text() for t in leg.get_texts()]
    assert any(n.startswith("closed loop") for n in names)
    assert "open/closed-loop switch" in names
    assert any(n.startswith("fault: safe state") for n in names)
    if kind == "speed":
        assert any(n.startswith("estimate valid") for n in names)
    n_panels = len(mod.KINDS[kind]["panels"])
    marks = set()
    for a in fig.axes[:n_panels]:
        marks |= {rgb(p.get_facecolor()) for p in a.patches}  # axvspan
        marks |= {rgb(ln.get_color()) for ln in a.get_lines()  # axvline
                  if len(ln.get_xdata()) == 2 and ln.get_xdata()[0] == ln.get_xdata()[1]}
    assert marks and marks <= legend_colors, (marks, legend_colors)
    # and every trace is in its panel's legend
    for a in fig.axes[:n_panels]:
        entries = {t.get_text() for t in a.get_legend().get_texts()}
        for ln in a.get_lines():
            if not ln.get_label().startswith("_"):
                assert ln.get_label() in entries


def test_position_run_load_panel_and_units(tmp_path):
    mod = load_module()
    csv = tmp_path / "run.csv"
    write_csv(csv)
    (tmp_path / "run_metrics.json").write_text(json.dumps({
        "theta_track_max_rad": 0.0121, "theta_est_max_rad": 0.00894, "omega_est_peak_max_rad_s": 0.933,
        "final_theta_err_rad": 5.37e-07}))
    fig = mod.make_figure(csv)
    ax = fig.axes[:len(mod.KINDS["position"]["panels"])]
    load = [a for a in ax if a.get_ylabel() == "load torque [N m]"]
    assert len(load) == 1
    assert any("C_r true" in x for x in labels(load[0])) and any("C_r est" in x for x in labels(load[0]))
    title = fig._suptitle.get_text()
    for part in ("= 0.0121 rad", "= 0.00894 rad", "= 0.933 rad/s", "= 5.37e-07 rad"):
        assert part in title
    assert all(re.search(r"\[.+\]", a.get_ylabel()) for a in fig.axes), "every axis label has a unit"
    assert ax[-1].get_xlabel() == "time [s]"
    # (f-g) explained on the plot and in the docstring
    assert any(t.get_text().startswith("(f-g): frame at the reference electrical angle n_p θ_ref")
               for t in fig.texts)
    assert "eqs. (6)-(8)" in mod.__doc__ and "d-q" in mod.__doc__


def test_speed_metrics_units(tmp_path):
    mod = load_module()
    csv = tmp_path / "s.csv"
    (tmp_path / "s_metrics.json").write_text(json.dumps({
        "speed_err_settled_max_rpm": 0.0457, "load_est_err_settled_nm": 0.00241, "lock_time_s": None,
        "theta_est_max_deg_e": None, "max_abs_current_A": 5.47}))
    text = "\n".join(mod.headline(csv, "speed"))
    assert "settled max|ω-ω*| = 0.0457 rpm" in text
    assert "= 0.00241 N m" in text and "= 5.47 A" in text
    assert "angle lock: never" in text


def test_no_closed_loop_panel_says_so(tmp_path):
    mod = load_module()
    csv = tmp_path / "run.csv"
    write_csv(csv, fault_at=10)  # faults before the loop closes: no estimates
    fig = mod.make_figure(csv, panels="position_error")
    assert any("no closed loop" in t.get_text() for t in fig.axes[0].texts)
