#!/usr/bin/env python3
"""[drive] kind names every drive (issue 28): a paper's scenario with
`[drive] kind = "<its drive>"` added runs the same drive as the scenario
without it (the drive its table chose): every metric equal, wall time
aside. A kind that does not read the scenario's table is refused, naming
both.

usage: check_drive_kind.py MOTORSIM SCENARIOS_DIR WORKDIR
Standard library only.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

# (scenario, its drive, a drive that reads another table); short runs
CASES = [
    ("paper000_ideal.toml", "paper000", "paper001"),
    ("stepper_speed.toml", "paper001", "paper002"),
    ("paper002_reference.toml", "paper002", "paper000"),
]
WALL = {"wall_time_s", "realtime_factor"}


def local(text: str, scen: Path) -> str:
    """The scenario's text for a copy elsewhere: its motor file, relative to
    the scenario, made absolute."""
    return text.replace('file = "../motors/', f'file = "{scen.parent / "motors"}/')


def run(motorsim: str, scenario: Path, out: Path) -> tuple[int, dict, str]:
    p = subprocess.run([motorsim, "--scenario", str(scenario), "--metrics-out", str(out), "--quiet", "--no-expect"],
                       capture_output=True, text=True)
    m = json.loads(out.read_text()) if p.returncode == 0 else {}
    return p.returncode, {k: v for k, v in m.items() if k not in WALL}, p.stderr


def main() -> int:
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    motorsim, scen, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    bad = 0
    for name, kind, other in CASES:
        text = (scen / name).read_text()
        rc0, m0, err0 = run(motorsim, scen / name, work / f"{kind}_table.json")
        with_kind = work / name.replace(".toml", "_kind.toml")
        with_kind.write_text(local(text, scen) + f'\n[drive]\nkind = "{kind}"\n')
        rc1, m1, err1 = run(motorsim, with_kind, work / f"{kind}_kind.json")
        if rc0 == rc1 != 0 and err0.split(": ", 2)[-1] == err1.split(": ", 2)[-1]:
            # a drive this build refuses (paper 002 in fixed point): refused
            # the same way either way
            print(f"ok   {name}: refused the same way with kind = {kind!r}: {err1.strip()}")
            continue
        if rc0 != 0 or rc1 != 0:
            print(f"FAIL {name}: exit {rc0} without [drive], {rc1} with kind = {kind!r}: {err0.strip()} {err1.strip()}")
            bad += 1
            continue
        diff = sorted(k for k in set(m0) | set(m1) if m0.get(k) != m1.get(k))
        if diff:
            print(f"FAIL {name}: [drive] kind = {kind!r} changes {', '.join(f'{k} {m0.get(k)} -> {m1.get(k)}' for k in diff[:5])}")
            bad += 1
        else:
            print(f"ok   {name}: [drive] kind = {kind!r}: {len(m0)} metrics equal")
        wrong = work / name.replace(".toml", "_wrong.toml")
        wrong.write_text(local(text, scen) + f'\n[drive]\nkind = "{other}"\n')
        p = subprocess.run([motorsim, "--scenario", str(wrong), "--metrics-out", str(work / "wrong.json"), "--quiet"],
                           capture_output=True, text=True)
        if p.returncode != 2 or f'"{other}" reads [' not in p.stderr or "is the table of" not in p.stderr:
            print(f"FAIL {name}: kind = {other!r} on its table: exit {p.returncode}, {p.stderr.strip()!r}")
            bad += 1
        else:
            print(f"ok   {name}: kind = {other!r} refused: {p.stderr.strip()}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
