"""tools/bench/realtime.py: argument errors, missing inputs, and a full run
against a stand-in motorsim (the real one is not needed)."""
from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "tools" / "bench" / "realtime.py"

# A stand-in for motorsim: same flags, writes metrics JSON / CSV, behaviour
# steered by environment variables.
FAKE_MOTORSIM = """\
import argparse, json, os, sys
from pathlib import Path
p = argparse.ArgumentParser(prog="motorsim")
p.add_argument("--scenario", required=True)
p.add_argument("--out")
p.add_argument("--metrics-out")
p.add_argument("--seed", type=int)
p.add_argument("--quiet", action="store_true")
if os.environ.get("FAKE_NO_PLOT_FLAG") != "0":
    p.add_argument("--no-plot", action="store_true")
a = p.parse_args()
log = os.environ.get("FAKE_LOG")
if log:
    with open(log, "a") as f:
        f.write(json.dumps(sys.argv[1:]) + "\\n")
if os.environ.get("FAKE_FAIL") or (a.seed is not None and str(a.seed) == os.environ.get("FAKE_FAIL_SEED")):
    print("boom: scenario rejected", file=sys.stderr)
    sys.exit(3)
metrics = {"theta_track_max_rad": 0.01}
if not os.environ.get("FAKE_NO_RF"):
    metrics["realtime_factor"] = float(os.environ.get("FAKE_RF", "100")) + (a.seed or 0)
if a.metrics_out:
    Path(a.metrics_out).write_text(json.dumps({"metrics": metrics}))
if a.out:
    Path(a.out).mkdir(parents=True, exist_ok=True)
    (Path(a.out) / "run.csv").write_text("t,theta\\n0,0\\n")
print(json.dumps(metrics))
"""


@pytest.fixture
def fake(tmp_path: Path) -> dict:
    exe = tmp_path / "motorsim"
    exe.write_text(f"#!{sys.executable}\n" + FAKE_MOTORSIM)
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    scenario = tmp_path / "scenario.toml"
    scenario.write_text("# stand-in\n")
    return {"exe": exe, "scenario": scenario, "log": tmp_path / "calls.log", "dir": tmp_path}


def bench(*args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    full_env = dict(os.environ)
    full_env.update(env or {})
    return subprocess.run([sys.executable, str(BENCH), *args], capture_output=True,
                          text=True, env=full_env, timeout=120)


def calls(log: Path) -> list[list[str]]:
    return [json.loads(line) for line in log.read_text().splitlines()]


def test_help():
    r = bench("--help")
    assert r.returncode == 0
    for flag in ("--runs", "--variants", "--jobs", "--binary", "--no-pin"):
        assert flag in r.stdout


def test_missing_binary_is_a_clear_error(tmp_path):
    missing = tmp_path / "no" / "motorsim"
    r = bench("--binary", str(missing))
    assert r.returncode == 2
    assert "motorsim binary not found" in r.stderr
    assert str(missing) in r.stderr
    assert "cmake --build --preset host" in r.stderr
    assert r.stdout == ""


def test_binary_not_executable(tmp_path):
    f = tmp_path / "motorsim"
    f.write_text("not a program")
    f.chmod(0o644)
    r = bench("--binary", str(f))
    assert r.returncode == 2
    assert "not executable" in r.stderr


def test_missing_scenario(fake):
    r = bench("--binary", str(fake["exe"]), "--scenario", str(fake["dir"] / "nope.toml"))
    assert r.returncode == 2
    assert "scenario not found" in r.stderr


@pytest.mark.parametrize("args, message", [
    (["--runs", "0"], "must be >= 1"),
    (["--runs", "two"], "not an integer"),
    (["--variants", "-1"], "must be >= 0"),
    (["--jobs", "0"], "must be >= 1"),
    (["--cpu", "0", "--no-pin"], "not allowed with"),
    (["--bogus"], "unrecognized arguments"),
])
def test_argument_errors(args, message):
    r = bench(*args)
    assert r.returncode == 2
    assert message in r.stderr
    assert "usage:" in r.stderr


def test_full_run_reports_median_and_json(fake):
    env = {"FAKE_RF": "250", "FAKE_LOG": str(fake["log"])}
    r = bench("--binary", str(fake["exe"]), "--scenario", str(fake["scenario"]),
              "--runs", "3", "--variants", "4", "--seed-base", "10", env=env)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.strip().splitlines()
    result = json.loads(lines[-1])
    assert result["realtime_factor_median"] == 250.0
    assert result["realtime_factor_runs"] == [250.0] * 3
    assert result["runs"] == 3
    assert result["variants"] == 4
    assert result["variants_jobs"] == 1
    assert result["variants_total_s"] > 0
    assert result["variants_per_variant_s"] == pytest.approx(result["variants_total_s"] / 4, rel=1e-3)
    assert result["variants_run_wall_s_median"] > 0
    assert result["wall_full_s_median"] > 0
    assert result["wall_full_no_plot_s_median"] > 0
    assert "realtime_factor" in r.stdout and "250.0x" in r.stdout
    made = calls(fake["log"])
    # 3 realtime runs + 3 full + 3 full --no-plot + 4 variants
    assert len(made) == 13
    assert sum("--no-plot" in c for c in made) == 3
    seeds = [c[c.index("--seed") + 1] for c in made if "--seed" in c]
    assert seeds == ["10", "11", "12", "13"]
    assert all(c[:2] == ["--scenario", str(fake["scenario"])] for c in made)
    # variants and realtime runs: metrics only (--metrics-out, no --out)
    metrics_only = [c for c in made if "--out" not in c]
    assert len(metrics_only) == 3 + 4
    assert all("--metrics-out" in c for c in metrics_only)
    assert "variants: 4 seeds (metrics only), 1 at a time" in r.stdout
    assert "ms per variant" in r.stdout


@pytest.mark.parametrize("pin", [[], ["--no-pin"]])
def test_variants_in_parallel(fake, pin):
    env = {"FAKE_LOG": str(fake["log"])}
    r = bench("--binary", str(fake["exe"]), "--scenario", str(fake["scenario"]), "--runs", "1",
              "--no-full", "--variants", "7", "--jobs", "3", *pin, env=env)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout.strip().splitlines()[-1])
    assert result["variants"] == 7
    assert result["variants_jobs"] == 3
    assert result["variants_total_s"] > 0
    made = calls(fake["log"])
    seeds = sorted(int(c[c.index("--seed") + 1]) for c in made if "--seed" in c)
    assert seeds == list(range(1, 8))
    assert all("--out" not in c for c in made)
    # every variant wrote its own metrics file
    outs = [c[c.index("--metrics-out") + 1] for c in made if "--seed" in c]
    assert len(set(outs)) == 7
    assert "3 at a time" in r.stdout


def test_parallel_variant_failure_is_reported(fake):
    r = bench("--binary", str(fake["exe"]), "--scenario", str(fake["scenario"]), "--runs", "1",
              "--no-full", "--variants", "4", "--jobs", "2", env={"FAKE_FAIL_SEED": "3"})
    assert r.returncode == 1
    assert "motorsim failed (exit 3)" in r.stderr
    assert "--seed 3" in r.stderr
    assert "boom: scenario rejected" in r.stderr


def test_without_no_plot_flag_and_json_out(fake):
    out = fake["dir"] / "bench.json"
    env = {"FAKE_NO_PLOT_FLAG": "0", "FAKE_LOG": str(fake["log"])}
    r = bench("--binary", str(fake["exe"]), "--scenario", str(fake["scenario"]),
              "--runs", "1", "--no-pin", "--json-out", str(out), env=env)
    assert r.returncode == 0, r.stderr
    result = json.loads(out.read_text())
    assert result["wall_full_no_plot_s_median"] is None
    assert result["pinned_cpu"] is None
    assert not any("--no-plot" in c for c in calls(fake["log"]))


def test_relative_binary_path(fake):
    # "motorsim" in the current directory must not be looked up in PATH.
    r = subprocess.run([sys.executable, str(BENCH), "--binary", "motorsim", "--scenario",
                        "scenario.toml", "--runs", "1", "--no-full"],
                       capture_output=True, text=True, cwd=fake["dir"], timeout=120)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout.splitlines()[-1])["wall_full_s_median"] is None


def test_motorsim_failure_is_reported(fake):
    r = bench("--binary", str(fake["exe"]), "--scenario", str(fake["scenario"]),
              "--runs", "1", env={"FAKE_FAIL": "1"})
    assert r.returncode == 1
    assert "motorsim failed (exit 3)" in r.stderr
    assert "boom: scenario rejected" in r.stderr


def test_metrics_without_realtime_factor(fake):
    r = bench("--binary", str(fake["exe"]), "--scenario", str(fake["scenario"]),
              "--runs", "1", env={"FAKE_NO_RF": "1"})
    assert r.returncode == 1
    assert "no numeric realtime_factor" in r.stderr
