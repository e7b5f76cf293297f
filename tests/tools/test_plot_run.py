"""tools/plot/plot_run.py on a synthetic motorsim CSV: PNG written, bad
input rejected with a clear message; long runs drawn from min/max envelopes
that keep every bin's extremes, with the axes laid out inside the figure."""
from __future__ import annotations

import importlib.util
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PLOT = ROOT / "tools" / "plot" / "plot_run.py"

COLUMNS = ("t_s,mode,theta_ref,omega_ref,accel_ref,theta,theta_est,omega,omega_est,accel,accel_est,"
           "load_true_Nm,load_est_Nm,i_a,i_b,i_a_meas,i_b_meas,i_f,i_g,i_f_hat,i_g_hat,d_f,d_g,"
           "d_f_hat,d_g_hat,v_a,v_b,v_f,v_g,delta_theta_est,jump_count,delta_theta,i_f_ref,i_g_ref,"
           "fault").split(",")


def write_csv(path: Path, n: int = 400, drop: str | None = None) -> None:
    cols = [c for c in COLUMNS if c != drop]
    lines = [",".join(cols)]
    for k in range(n):
        t = k * 1e-3
        w = 10 * math.sin(math.pi * t / (n * 1e-3))
        row = {c: 0.01 * math.sin(k * 0.1 + i) for i, c in enumerate(COLUMNS)}
        row.update(t_s=t, omega_ref=w, omega=w, omega_est=w + 0.1, mode=1 if abs(w) >= 3 else 0,
                   fault=0, jump_count=0)
        lines.append(",".join(f"{row[c]:.9g}" for c in cols))
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
    write_csv(csv, drop="d_f_hat")
    r = plot(str(csv), str(tmp_path / "x.png"))
    assert r.returncode == 2
    assert "d_f_hat" in r.stderr
    assert not (tmp_path / "x.png").exists()


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
    data[:, col["omega_ref"]] = w
    data[:, col["omega"]] = w
    data[:, col["mode"]] = (np.abs(w) >= 3).astype(float)
    data[:, col["d_f"]] = 12345.678 * np.sin(t)  # wide tick labels must not be clipped
    data[:, col["v_b"]] = -1e-7 * np.cos(t)  # an offset / scientific tick label
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
    boxes = sorted((a.get_position() for a in fig.axes[:6]), key=lambda p: -p.y0)
    assert all(upper.y0 > lower.y1 for upper, lower in zip(boxes, boxes[1:]))
