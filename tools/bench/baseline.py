#!/usr/bin/env python3
"""Metrics of the shipped scenarios: write the ratchet baseline, or compare with it.

The file holds two sections, both measured with one motorsim binary:

  entries  the ratchet (tests/sim/check_metrics.py --baseline): paper
           000's ideal and experiment runs (seeds 1-10), the metrics of
           MARGINS only; no run may get worse than these by its margin.
  exact    every drive's shipped scenarios (sim/scenarios/*.toml and
           tests/sim/design_runs/*.toml), seeds 1-3 of each, the other
           estimator, half a sample of computation delay and the emulated
           board (EXACT_VARIANTS): every metric but the wall-clock ones,
           plus the SHA-256 of the run's CSV log. Paper 002's drive is
           float only (docs/paper002.md); a fixed-point binary skips it.

  --write FILE     measures both and writes them (a new baseline), or
  --compare FILE   measures both and prints every value that differs from
                   FILE at all, and exits 1 if any does (the bit-exactness
                   check of a restructuring: the printed digits of all
                   three drives must not move). --metrics-only leaves the
                   CSV hashes out of the comparison (for a change of the
                   log's columns that changes no number).

usage: baseline.py --binary build/host/sim/motorsim (--write F | --compare F)
                   [--jobs N] [--metrics-only]
Standard library only.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))  # the toolbox, tools/lib
from lib import motorsim  # noqa: E402
SCENARIOS = ROOT / "sim" / "scenarios"

# Which way is worse, and by how much a metric may get worse before the
# ratchet fails: rel * |baseline| + abs. The runs are deterministic for a
# given build, so any change comes from the code (or from the host's libm
# in the plant's sin/cos); 10 % lets a deliberate trade-off through while
# catching the mutants seen so far (tracking +26 %, estimation +57 %). The
# absolute parts are the resolution below which a metric means nothing:
# 1e-4 rad of final position (the fixed-point angle LSB is 7.6e-6 rad, the
# plant's settling 5e-7 rad), 1e-4 rad, 1e-4 A, 1e-3 rad/s, and one
# hundredth of the run for the closed-loop share.
MARGINS = {
    "theta_track_max_rad": {"worse": "max", "rel": 0.10, "abs": 1e-4},
    "theta_est_max_rad": {"worse": "max", "rel": 0.10, "abs": 1e-4},
    "current_obs_max_a": {"worse": "max", "rel": 0.10, "abs": 1e-4},
    "omega_est_peak_max_rad_s": {"worse": "max", "rel": 0.10, "abs": 1e-3},
    "final_theta_err_rad": {"worse": "max", "rel": 0.10, "abs": 1e-4},
    "closed_loop_fraction": {"worse": "min", "rel": 0.0, "abs": 0.01},
}


def entries() -> dict[str, list[str]]:
    """Entry name -> [scenario, further motorsim arguments] (the names of tests/sim/CMakeLists.txt)."""
    e = {
        "paper000_ideal": [str(SCENARIOS / "paper000_ideal.toml")],
        "paper000_experiment": [str(SCENARIOS / "paper000_experiment.toml")],
    }
    for seed in range(1, 11):
        e[f"paper000_experiment_seed{seed}"] = [str(SCENARIOS / "paper000_experiment.toml"),
                                                "--seed", str(seed)]
    return e


# Metrics that measure the host, not the drive.
NOT_EXACT = {"wall_time_s", "realtime_factor"}

# Variants of every exact entry: (suffix, extra motorsim arguments, which
# scenarios). "speed" = the scenarios of paper 001's drive (files named
# paper001_* or with [speed]), "p002" = paper 002's, "pos" = paper 000's.
EXACT_VARIANTS = [
    ("", [], {"pos", "speed", "p002"}),
    ("_seed1", ["--seed", "1"], {"pos", "speed", "p002"}),
    ("_seed2", ["--seed", "2"], {"pos", "speed", "p002"}),
    ("_seed3", ["--seed", "3"], {"pos", "speed", "p002"}),
    ("_delay0.5", ["--compute-delay-samples", "0.5"], {"pos", "speed", "p002"}),
    ("_back_emf", ["--estimator", "back_emf"], {"speed"}),
    ("_flux", ["--estimator", "flux"], {"p002"}),
    ("_board", ["--backend", "board-emulated"], {"pos"}),
]


def scenario_kind(path: Path) -> str:
    text = path.read_text(encoding="utf-8")
    if "[paper002]" in text:
        return "p002"
    if "[speed]" in text:
        return "speed"
    return "pos"


def exact_entries(fixed: bool) -> dict[str, list[str]]:
    """Entry name -> [scenario, further motorsim arguments], for every drive's shipped scenarios."""
    files = sorted(SCENARIOS.glob("*.toml")) + sorted((ROOT / "tests/sim/design_runs").glob("*.toml"))
    e = {}
    for f in files:
        kind = scenario_kind(f)
        if fixed and kind == "p002":
            continue
        # an MCU board's inverter has no DAC board to emulate (motorsim refuses the pair)
        has_inverter = "[inverter]" in f.read_text(encoding="utf-8")
        # the HF injection refuses a delay of half a sample (its alternating
        # voltage would cancel: firmware/estimators/hf_injection.h)
        hfi = 'estimator = "hfi"' in f.read_text(encoding="utf-8")
        for suffix, extra, kinds in EXACT_VARIANTS:
            if kind in kinds and not (has_inverter and suffix == "_board") and not (hfi and suffix == "_delay0.5"):
                e[f"{f.stem}{suffix}"] = [str(f), "--no-expect", *extra]
    return e


def run_exact(binary: str, name: str, args: list[str], work: Path) -> tuple[str, dict]:
    """Every metric of one run and the SHA-256 of its CSV log."""
    try:
        r = motorsim.run(binary, args[0], extra=args[1:], out=work / name,
                         ok=(motorsim.OK, motorsim.FAULT, motorsim.EXPECT_MISSED))
    except motorsim.MotorsimError as e:
        raise RuntimeError(f"{name}: {e}") from None
    m = {k: v for k, v in r.metrics.items() if k not in NOT_EXACT}
    m["exit_status"] = r.status
    m["csv_sha256"] = hashlib.sha256(r.csv.read_bytes()).hexdigest()
    return name, m


def run(binary: str, name: str, args: list[str], work: Path) -> tuple[str, dict]:
    try:
        m = motorsim.metrics(binary, args[0], extra=args[1:])
    except motorsim.MotorsimError as e:
        raise RuntimeError(f"{name}: {e}") from None
    return name, {k: m[k] for k in MARGINS if k in m}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default=str(ROOT / "build/host/sim/motorsim"))
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--write", metavar="FILE")
    g.add_argument("--compare", metavar="FILE")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--metrics-only", action="store_true", help="leave the CSV hashes out of --compare")
    a = ap.parse_args()
    if not Path(a.binary).is_file():
        print(f"baseline.py: --binary: no such file '{a.binary}'", file=sys.stderr)
        return 2
    try:
        fixed = "fixed point" in motorsim.version(a.binary)
    except motorsim.MotorsimError as e:
        print(f"baseline.py: {e}", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory() as tmp:
        with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
            try:
                got = dict(ex.map(lambda kv: run(a.binary, kv[0], kv[1], Path(tmp)), entries().items()))
                exact = dict(ex.map(lambda kv: run_exact(a.binary, kv[0], kv[1], Path(tmp)),
                                    exact_entries(fixed).items()))
            except RuntimeError as e:
                print(f"baseline.py: {e}", file=sys.stderr)
                return 1
    if a.write:
        doc = {"about": "ratchet of tests/sim/check_metrics.py (entries) and the bit-exactness "
                        "reference of every drive (exact); written by tools/bench/baseline.py",
               "margins": MARGINS, "entries": dict(sorted(got.items())), "exact": dict(sorted(exact.items()))}
        tmp_path = Path(a.write).with_suffix(".tmp")
        tmp_path.write_text(json.dumps(doc, indent=1, sort_keys=False) + "\n", encoding="utf-8")
        tmp_path.replace(a.write)
        print(f"baseline.py: wrote {len(got)} ratchet and {len(exact)} exact entries to {a.write}")
        return 0
    try:
        with open(a.compare, encoding="utf-8") as f:
            doc = json.load(f)
        ref, ref_exact = doc["entries"], doc["exact"]
    except (OSError, json.JSONDecodeError, KeyError) as e:
        print(f"baseline.py: cannot read {a.compare}: {e}", file=sys.stderr)
        return 2
    diffs = 0
    for section, now, then in (("entries", got, ref), ("exact", exact, ref_exact)):
        for name in sorted(set(now) | set(then)):
            if name not in then or name not in now:
                diffs += 1
                print(f"DIFF {section} {name}: {'new entry' if name not in then else 'entry gone'}")
                continue
            for k in sorted(set(now[name]) | set(then[name])):
                if a.metrics_only and k == "csv_sha256":
                    continue
                was, v = then[name].get(k), now[name].get(k)
                if was != v:
                    diffs += 1
                    print(f"DIFF {section} {name} {k}: {was} -> {v}")
    print(json.dumps({"entries": len(got), "exact_entries": len(exact), "differences": diffs}))
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
