#!/usr/bin/env python3
"""Metrics of the shipped scenarios: write the ratchet baseline, or compare with it.

The ratchet (tests/sim/check_metrics.py --baseline) lets no shipped scenario
get worse than the committed baseline by more than a stated margin. This
script measures the entries (paper000_ideal, paper000_experiment and its
seeds 1-10) with one motorsim binary, metrics-only runs, and

  --write FILE     writes them with the margins (a new baseline), or
  --compare FILE   prints every metric that differs from FILE at all and
                   exits 1 if any does (the bit-exactness check of a
                   refactoring: the printed digits must not move).

usage: baseline.py --binary build/host/sim/motorsim (--write F | --compare F) [--jobs N]
Standard library only.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
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
    """Entry name -> motorsim arguments (the names of tests/sim/CMakeLists.txt)."""
    e = {
        "paper000_ideal": ["--scenario", str(SCENARIOS / "paper000_ideal.toml")],
        "paper000_experiment": ["--scenario", str(SCENARIOS / "paper000_experiment.toml")],
    }
    for seed in range(1, 11):
        e[f"paper000_experiment_seed{seed}"] = ["--scenario", str(SCENARIOS / "paper000_experiment.toml"),
                                                "--seed", str(seed)]
    return e


def run(binary: str, name: str, args: list[str], work: Path) -> tuple[str, dict]:
    out = work / f"{name}.json"
    p = subprocess.run([binary, *args, "--metrics-out", str(out), "--quiet"], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{name}: motorsim exited {p.returncode}: {p.stderr.strip()}")
    with open(out, encoding="utf-8") as f:
        m = json.load(f)
    return name, {k: m[k] for k in MARGINS if k in m}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default=str(ROOT / "build/host/sim/motorsim"))
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--write", metavar="FILE")
    g.add_argument("--compare", metavar="FILE")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    if not Path(a.binary).is_file():
        print(f"baseline.py: --binary: no such file '{a.binary}'", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
            try:
                got = dict(ex.map(lambda kv: run(a.binary, kv[0], kv[1], Path(tmp)), entries().items()))
            except RuntimeError as e:
                print(f"baseline.py: {e}", file=sys.stderr)
                return 1
    if a.write:
        doc = {"about": "ratchet of tests/sim/check_metrics.py; written by tools/bench/baseline.py",
               "margins": MARGINS, "entries": dict(sorted(got.items()))}
        tmp_path = Path(a.write).with_suffix(".tmp")
        tmp_path.write_text(json.dumps(doc, indent=1, sort_keys=False) + "\n", encoding="utf-8")
        tmp_path.replace(a.write)
        print(f"baseline.py: wrote {len(got)} entries to {a.write}")
        return 0
    try:
        with open(a.compare, encoding="utf-8") as f:
            ref = json.load(f)["entries"]
    except (OSError, json.JSONDecodeError, KeyError) as e:
        print(f"baseline.py: cannot read {a.compare}: {e}", file=sys.stderr)
        return 2
    diffs = 0
    for name, m in sorted(got.items()):
        for k, v in sorted(m.items()):
            was = ref.get(name, {}).get(k)
            if was != v:
                diffs += 1
                print(f"DIFF {name} {k}: {was} -> {v}")
    print(json.dumps({"entries": len(got), "differences": diffs}))
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
