"""tools/sweep.py: the Monte Carlo sweep of plant parameters.

(1) a small local sweep of paper 000's experiment: the JSON keys, the
    metrics-only motorsim runs judged against [expect], the drawn factors
    inside their stated distributions; a deliberately impossible spread
    (R, L, K +-90 %) fails, and the replay commands of its failures really
    reproduce them (same exit status, reason and metrics);
(2) the same sweep through a dask.distributed LocalCluster started here
    gives the same per-run results as the local pool for the same --seed.

Uses the real motorsim (MOTORSIM, else build/host/sim/motorsim): about 20 ms
a run, so a sweep of 8 runs takes well under a second.
"""
from __future__ import annotations

import importlib.util
import json
import math
import os
import shlex
import stat
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SWEEP = ROOT / "tools" / "sweep.py"
MOTORSIM = Path(os.environ.get("MOTORSIM", ROOT / "build" / "host" / "sim" / "motorsim"))
SCENARIO = ROOT / "sim" / "scenarios" / "paper000_experiment.toml"
IMPOSSIBLE = ["--spread", "R=90,L=90,K=90"]

spec = importlib.util.spec_from_file_location("sweep", SWEEP)
sweep = importlib.util.module_from_spec(spec)
spec.loader.exec_module(sweep)

pytestmark = pytest.mark.skipif(not MOTORSIM.is_file(), reason=f"no motorsim at {MOTORSIM} (build the host preset)")


def run(*args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SWEEP), "--binary", str(MOTORSIM), "--no-progress", *args],
                          capture_output=True, text=True, timeout=timeout)


def sweep_json(*args: str) -> dict:
    r = run(*args)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


@pytest.fixture(scope="module")
def impossible(tmp_path_factory) -> dict:
    keep = tmp_path_factory.mktemp("keep_impossible")
    out = sweep_json("--scenario", str(SCENARIO), "--runs", "8", *IMPOSSIBLE, "--seed", "7", "--per-run",
                     "--keep", str(keep))
    out["_keep"] = keep
    return out


# ------------------------------------------------------------ (1) local ----
def test_small_sweep_json_and_metrics_only_runs(tmp_path):
    # A wrapper that logs motorsim's arguments, then runs the real one.
    log = tmp_path / "calls.log"
    wrapper = tmp_path / "motorsim"
    wrapper.write_text(f"#!/bin/sh\necho \"$@\" >> {shlex.quote(str(log))}\nexec {shlex.quote(str(MOTORSIM))} \"$@\"\n")
    wrapper.chmod(wrapper.stat().st_mode | stat.S_IXUSR)
    png = tmp_path / "plane.png"
    r = subprocess.run([sys.executable, str(SWEEP), "--binary", str(wrapper), "--scenario", str(SCENARIO),
                        "--runs", "8", "--spread-pct", "5", "--j-range", "0.8,1.25", "--jobs", "2", "--seed", "3",
                        "--keep", str(tmp_path / "keep"), "--plot", str(png), "--plot-axes", "K,J", "--per-run"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    for key in ("runs", "passed", "failed", "errors", "pass_rate", "pass_rate_ci95", "spreads", "seed",
                "wall_time_s", "metric", "metric_stats", "worst", "failures", "error_runs", "keep_dir", "per_run"):
        assert key in out, key
    assert out["runs"] == 8 and out["seed"] == 3 and out["errors"] == 0
    assert out["passed"] + out["failed"] == 8
    assert out["pass_rate"] == pytest.approx(out["passed"] / 8)
    assert out["metric"] == "theta_track_max_rad"
    assert out["spreads"]["R"] == {"keys": ["R_ohm"], "dist": "uniform", "lo": 0.95, "hi": 1.05, "pct": 5.0}
    assert out["spreads"]["J"]["dist"] == "log-uniform" and out["spreads"]["J"]["lo"] == 0.8
    assert out["drive_model"]["R_ohm"] == 3.01  # the motor file's value: the drive stays nominal
    # metrics-only runs, judged against [expect], one noise seed each
    calls = log.read_text().splitlines()
    assert len(calls) == 8
    for c in calls:
        argv = c.split()
        assert "--metrics-out" in argv and "--out" not in argv and "--no-expect" not in argv
    seeds = [run["seed"] for run in out["per_run"]]
    assert len(set(seeds)) == 8
    for run_ in out["per_run"]:
        f = run_["factors"]
        assert all(0.95 <= f[p] <= 1.05 for p in "RLK") and 0.8 <= f["J"] <= 1.25
        assert run_["plant"]["R_ohm"] == pytest.approx(3.01 * f["R"], rel=1e-5)
        assert (run_["outcome"] == "pass") == (run_["status"] == 0)
    # worst cases: sorted by the main metric, each with a replayable variant
    worst = out["worst"]
    assert len(worst) == 5
    assert [w["metric"] for w in worst] == sorted((w["metric"] for w in worst), reverse=True)
    assert worst[0]["metric"] == out["metric_stats"]["max"]
    for w in worst:
        assert Path(w["scenario"]).is_file() and w["replay"].startswith(str(wrapper))
        # the variant: the plant drawn in [motor], the nominal model in [drive_model]
        variant = tomllib.loads(Path(w["scenario"]).read_text())
        motor = tomllib.loads((SCENARIO.parent / "../motors/paper000_stepper.toml").read_text())
        assert variant["drive_model"] == {k: motor[k] for k in ("L_H", "R_ohm", "K_Nm_per_A", "J_kgm2",
                                                                 "fv_Nms_per_rad", "n_p")}
        for p, key in (("R", "R_ohm"), ("L", "L_H"), ("K", "K_Nm_per_A"), ("J", "J_kgm2")):
            assert variant["motor"][key] == pytest.approx(motor[key] * w["factors"][p], rel=1e-5)
        assert variant["run"]["seed"] == w["seed"] and variant["expect"]
    assert png.stat().st_size > 10_000
    # the progress bar (one line per 10 % off a terminal) and the summary
    assert "sweep [##############################] 8/8" in r.stderr and "sweep: passed" in r.stderr


def test_impossible_spread_fails_and_replays_reproduce(impossible):
    out = impossible
    assert out["runs"] == 8 and out["errors"] == 0
    assert out["failed"] >= 4, out["fail_reasons"]
    assert out["passed"] == 8 - out["failed"]
    assert sum(out["fail_reasons"].values()) == out["failed"]
    per_run = {r["index"]: r for r in out["per_run"]}
    fails = out["failures"]
    assert len(fails) == out["failed"]
    for f in fails:
        assert f["status"] in (3, 4, 5) and f["reason"] and f["replay"]
    # Replay some (a fault and an [expect] miss when there are both): the same
    # exit status, the same FAILED lines, the same metrics.
    picked = {}
    for f in fails:
        picked.setdefault(f["status"], f)
    for f in list(picked.values())[:3]:
        argv = shlex.split(f["replay"])
        assert argv[0] == str(MOTORSIM.resolve()) and "--no-expect" not in argv
        rep = subprocess.run(argv + ["--no-plot"], capture_output=True, text=True, timeout=60)
        assert rep.returncode == f["status"], (f["replay"], rep.stderr)
        assert sweep.reason_of(rep.returncode, rep.stderr) == f["reason"]
        out_dir = Path(argv[argv.index("--out") + 1])
        metrics = json.loads((out_dir / f"{out_dir.name}_metrics.json").read_text())
        for key, value in per_run[f["index"]]["metrics"].items():
            assert metrics[key] == value, key


def test_distributions_and_seed():
    spreads = sweep.parse_spreads(10, "R=20", "0.5,2")
    assert (spreads["R"].lo, spreads["R"].hi) == (0.8, 1.2)
    assert (spreads["L"].lo, spreads["K"].hi) == (0.9, 1.1)
    runs = sweep.draw_runs(4000, 5, spreads)
    j = [r["factors"]["J"] for r in runs]
    assert 0.5 <= min(j) and max(j) <= 2.0
    # log-uniform: ln J uniform in [ln 0.5, ln 2], so half the draws below 1
    # and a quarter below 1/sqrt(2)
    assert abs(sum(x < 1 for x in j) / 4000 - 0.5) < 0.03
    assert abs(sum(x < 2 ** -0.5 for x in j) / 4000 - 0.25) < 0.03
    r = [x["factors"]["R"] for x in runs]
    assert 0.8 <= min(r) < 0.81 and 1.19 < max(r) <= 1.2
    assert abs(sum(x < 0.9 for x in r) / 4000 - 0.25) < 0.03  # uniform
    # same seed, same draws; a zero spread draws too (others not reshuffled)
    assert sweep.draw_runs(3, 5, spreads) == runs[:3]
    zero_r = sweep.parse_spreads(10, "R=0", "0.5,2")
    again = sweep.draw_runs(3, 5, zero_r)
    assert [x["factors"]["R"] for x in again] == [1.0] * 3
    assert [x["factors"]["J"] for x in again] == [x["factors"]["J"] for x in runs[:3]]
    assert [x["seed"] for x in again] == [x["seed"] for x in runs[:3]]
    assert sweep.draw_runs(3, 6, spreads) != runs[:3]


@pytest.mark.parametrize("args, message", [
    (["--spread-pct", "100"], "[0, 100)"),
    (["--spread", "Q=5"], "NAME=PCT"),
    (["--j-range", "2,0.5"], "0 < LO <= HI"),
    (["--plot-axes", "R,R"], "--plot-axes"),
    (["--runs", "0"], "--runs"),
])
def test_bad_arguments(args, message, tmp_path):
    base = ["--scenario", str(SCENARIO), "--runs", "2", "--keep", str(tmp_path)]
    r = run(*base, *args)
    assert r.returncode == 2 and message in r.stderr, r.stderr


def test_tool_errors_are_not_fails(tmp_path):
    bad = tmp_path / "motorsim"
    bad.write_text("#!/bin/sh\necho 'error: cannot write' >&2\nexit 1\n")
    bad.chmod(bad.stat().st_mode | stat.S_IXUSR)
    r = subprocess.run([sys.executable, str(SWEEP), "--binary", str(bad), "--scenario", str(SCENARIO),
                        "--runs", "3", "--keep", str(tmp_path / "keep"), "--no-progress"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 1, r.stderr
    out = json.loads(r.stdout)
    assert out["errors"] == 3 and out["failed"] == 0 and out["passed"] == 0
    assert out["error_runs"][0]["reason"] == "error: cannot write" and out["error_runs"][0]["replay"]


# ------------------------------------------------------------- (2) dask ----
def test_dask_local_cluster_gives_the_same_runs(impossible, tmp_path):
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp", host="127.0.0.1",
                      dashboard_address=None) as cluster:
        out = sweep_json("--scenario", str(SCENARIO), "--runs", "8", *IMPOSSIBLE, "--seed", "7", "--per-run",
                         "--keep", str(tmp_path), "--dask", cluster.scheduler_address)
    assert out["backend"] == "dask" and out["jobs"] == 2
    assert out["per_run"] == impossible["per_run"]
    for key in ("passed", "failed", "fail_reasons", "expect_misses", "metric_stats"):
        assert out[key] == impossible[key], key
    # and a sweep with mostly passing runs
    local = sweep_json("--scenario", str(SCENARIO), "--runs", "6", "--spread-pct", "10", "--per-run",
                       "--keep", str(tmp_path / "l"))
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, protocol="tcp", host="127.0.0.1",
                      dashboard_address=None) as cluster:
        dask = sweep_json("--scenario", str(SCENARIO), "--runs", "6", "--spread-pct", "10", "--per-run",
                          "--keep", str(tmp_path / "d"), "--dask", cluster.scheduler_address)
    assert dask["per_run"] == local["per_run"] and dask["passed"] == local["passed"]
    assert math.isclose(dask["pass_rate"], local["pass_rate"])


def test_dead_time_spread_keeps_the_drives_compensation_nominal(tmp_path):
    # --dead-time-pct (issue 30): the board's dead time drawn after each
    # run's noise seed (the other draws as without it), the variant's
    # [inverter] with the drawn plant value and the nominal for the drive
    spreads = sweep.parse_spreads(20, None, None)
    plain = sweep.draw_runs(5, 3, spreads)
    with_d = sweep.draw_runs(5, 3, spreads, 50.0)
    for a, b in zip(plain, with_d):
        assert {k: v for k, v in b["factors"].items() if k != "D"} == a["factors"]
        assert 0.5 <= b["factors"]["D"] <= 1.5
    assert [r["seed"] for r in plain] == [r["seed"] for r in with_d]
    hw = ROOT / "sim" / "scenarios" / "paper000_experiment_hw.toml"
    out = sweep_json("--scenario", str(hw), "--runs", "2", "--dead-time-pct", "50", "--keep", str(tmp_path),
                     "--per-run")
    assert out["errors"] == 0 and out["nominal_dead_time_s"] == pytest.approx(119e-9)
    run0 = out["per_run"][0]
    sc = tomllib.loads(Path(run0["scenario"]).read_text()) if run0.get("scenario") else None
    if sc is not None:
        assert sc["inverter"]["compensation_dead_time_s"] == pytest.approx(119e-9)
        assert sc["inverter"]["dead_time_s"] == pytest.approx(119e-9 * run0["factors"]["D"])
        assert Path(sc["inverter"]["file"]).is_absolute()
    # a scenario without an inverter is refused
    r = run("--scenario", str(SCENARIO), "--runs", "2", "--dead-time-pct", "10", "--keep", str(tmp_path))
    assert r.returncode == 2 and "no [inverter] table" in r.stderr, r.stderr
