"""tools/plot/plot_run.py on a synthetic motorsim CSV: PNG written, bad
input rejected with a clear message."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

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
