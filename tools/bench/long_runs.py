#!/usr/bin/env python3
"""Real-time factor of long runs: paper 000's experiment (the move, then a
hold at rest) run for 4.25 s, 100 s and 1,000 s. A benchmark, not a test.

Long holds used to slow the simulator down tenfold (realtime_factor 276 at
4.25 s, 51 at 100 s, about 35 from 390 s on): the plant's state decayed into
subnormal numbers. The plant now sets components below 1e-200 to zero after
each step (sim/model/pm_plant.h, kStateFloor); the firmware produces none
(tests/sim/test_drive_plant.cpp, LongHoldGivesNoSubnormals*). The target:
every duration within 10 % of the 4.25 s run's factor. The 4.25 s run is
two thirds closed loop, the longer ones almost all hold at rest (the
open-loop law, cheaper), so the script also prints the factor of the hold
alone over each added span (4.25 -> 100 s, 100 -> 1,000 s): like against
like, a slowdown with the run's length shows there as a falling factor.

    python3 tools/bench/long_runs.py [--binary build/host/sim/motorsim] [--runs 3] [--markdown]

Metrics-only runs (no CSV: 1,000 s is beyond the in-memory log), pinned to
one CPU with taskset when available; median of --runs. Standard library only.
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: the toolbox
from lib import motorsim  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "sim" / "scenarios" / "paper000_experiment.toml"
DURATIONS = (4.25, 100.0, 1000.0)


def rtf(binary: Path, duration: float, runs: int) -> float:
    text = SCENARIO.read_text()
    text, n = re.subn(r"(?m)^duration_s = .*$", f"duration_s = {duration}", text, count=1)
    if n != 1:
        sys.exit("long_runs: duration_s not found in the scenario")
    pin = ["taskset", "-c", "0"] if shutil.which("taskset") else []
    vals = []
    for _ in range(runs):
        try:
            m = motorsim.metrics(binary, text=text, name=f"long_{duration:g}s", text_dir=SCENARIO.parent,
                                 expect=False, prefix=pin)
        except motorsim.MotorsimError as e:
            sys.exit(f"long_runs: {duration:g} s: {e}")
        vals.append(m["realtime_factor"])
    return statistics.median(vals)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", type=Path, default=ROOT / "build" / "host" / "sim" / "motorsim")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--markdown", action="store_true")
    a = ap.parse_args()
    try:
        a.binary = motorsim.find(binary=a.binary)
    except motorsim.MotorsimError as e:
        print(f"long_runs: {e}", file=sys.stderr)
        return 2
    res = [(d, rtf(a.binary, d, a.runs)) for d in DURATIONS]
    base = res[0][1]
    # The hold's own factor, like against like: the simulated seconds one
    # run adds over the shorter one (all hold at rest) per wall second they
    # cost. A slowdown that grows with the run's length (the subnormals)
    # shows here as a falling factor from one span to the next.
    wall = [d / f for d, f in res]
    spans = [(res[k][0], res[k + 1][0], (res[k + 1][0] - res[k][0]) / (wall[k + 1] - wall[k]))
             for k in range(len(res) - 1)]
    if a.markdown:
        print("| run length (s) | realtime_factor | vs 4.25 s |")
        print("|---|---|---|")
        for d, f in res:
            print(f"| {d:g} | {f:.0f} | {100.0 * (f / base - 1.0):+.1f} % |")
        print()
        print("| hold at rest, added span (s) | realtime_factor of the span | vs the first span |")
        print("|---|---|---|")
        for t0, t1, f in spans:
            print(f"| {t0:g} → {t1:g} | {f:.0f} | {100.0 * (f / spans[0][2] - 1.0):+.1f} % |")
    else:
        for d, f in res:
            print(f"{d:8g} s  realtime_factor {f:7.1f}  {100.0 * (f / base - 1.0):+6.1f} % vs 4.25 s")
        for t0, t1, f in spans:
            print(f"hold {t0:g} -> {t1:g} s  realtime_factor {f:7.1f}  {100.0 * (f / spans[0][2] - 1.0):+6.1f} % "
                  "vs the first span")
        print(json.dumps({"realtime_factor": {str(d): f for d, f in res},
                          "hold_span_realtime_factor": {f"{t0:g}-{t1:g}": f for t0, t1, f in spans}}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
