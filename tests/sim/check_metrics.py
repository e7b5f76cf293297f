#!/usr/bin/env python3
"""Checks a motorsim metrics JSON against thresholds and a committed baseline.

usage: check_metrics.py METRICS.json [--baseline BASE.json --entry NAME] CHECK [CHECK ...]

CHECK is KEY<VALUE, KEY<=VALUE, KEY>VALUE, KEY>=VALUE or KEY (report only).
Every named key must be present and a finite number, report-only ones too.
Prints every checked metric with its verdict; exits 1 if any check fails or
a metric is missing or not a finite number, 2 on bad usage.

--baseline BASE.json --entry NAME: the ratchet. BASE.json holds, per entry
(a scenario run, e.g. "paper000_experiment_seed3"), the metrics measured
when the baseline was committed; its "margins" say, per key, which way is
worse ("max": larger is worse, "min": smaller is worse) and by how much it
may get worse: `rel` of the baseline value plus `abs`. Every key of the
entry is compared; a metric that got worse by more than its margin fails.
A missing entry fails (regenerate with tools/bench/baseline.py).
Standard library only, so it runs with any python3.
"""
from __future__ import annotations

import json
import math
import operator
import re
import sys

OPS = {"<=": operator.le, ">=": operator.ge, "<": operator.lt, ">": operator.gt}
CHECK_RE = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)(?:(<=|>=|<|>)(.+))?$")
USAGE = "usage: check_metrics.py METRICS.json [--baseline BASE.json --entry NAME] CHECK [CHECK ...]"


def is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def load_object(path: str, what: str) -> dict | None:
    """The JSON object in path, or None after a one-line error naming it."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        print(f"check_metrics: cannot read {what}{path}: {e}", file=sys.stderr)
        return None
    if not isinstance(doc, dict):
        print(f"check_metrics: {what}{path}: not a JSON object", file=sys.stderr)
        return None
    return doc


def ratchet(metrics: dict, base_path: str, entry: str) -> int:
    """Compares metrics with the baseline entry; returns the number of failures."""
    base = load_object(base_path, "baseline ")
    if base is None:
        return 1
    margins = base.get("margins", {})
    ref = base.get("entries", {}).get(entry)
    if not isinstance(ref, dict) or not ref:
        print(f"FAILED baseline entry '{entry}' missing in {base_path}")
        return 1
    failed = 0
    for key, was in sorted(ref.items()):
        m = margins.get(key)
        if not isinstance(m, dict) or m.get("worse") not in ("max", "min"):
            print(f"FAILED baseline {key}: no margin for it in {base_path}")
            failed += 1
            continue
        now = metrics.get(key)
        if not is_number(now) or not is_number(was):
            print(f"FAILED baseline {key} = {now} (baseline {was}): not a finite number")
            failed += 1
            continue
        slack = float(m.get("rel", 0.0)) * abs(was) + float(m.get("abs", 0.0))
        if m["worse"] == "max":
            limit, ok = was + slack, now <= was + slack
        else:
            limit, ok = was - slack, now >= was - slack
        failed += 0 if ok else 1
        sign = "<=" if m["worse"] == "max" else ">="
        print(f"{'  ok  ' if ok else 'FAILED'} baseline {key} = {now:.6g}  (was {was:.6g}, want {sign} {limit:.6g})")
    return failed


def main(argv: list[str]) -> int:
    args = argv[1:]
    base_path = entry = None
    rest: list[str] = []
    i = 0
    while i < len(args):
        if args[i] in ("--baseline", "--entry"):
            if i + 1 >= len(args):
                print(f"check_metrics: {args[i]} needs a value\n{USAGE}", file=sys.stderr)
                return 2
            if args[i] == "--baseline":
                base_path = args[i + 1]
            else:
                entry = args[i + 1]
            i += 2
            continue
        rest.append(args[i])
        i += 1
    if (base_path is None) != (entry is None):
        print(f"check_metrics: --baseline and --entry go together\n{USAGE}", file=sys.stderr)
        return 2
    if len(rest) < 2 and base_path is None or len(rest) < 1:
        print(USAGE, file=sys.stderr)
        return 2
    path = rest[0]
    metrics = load_object(path, "")
    if metrics is None:
        return 1
    failed = 0
    for check in rest[1:]:
        m = CHECK_RE.match(check.replace(" ", ""))
        if not m:
            print(f"check_metrics: bad check '{check}'", file=sys.stderr)
            return 2
        key, op, limit = m.group(1), m.group(2), m.group(3)
        value = metrics.get(key)
        ok_number = is_number(value)
        if op is None:
            failed += 0 if ok_number else 1
            print(f"{'  --  ' if ok_number else 'FAILED'} {key} = {value}  "
                  f"({'reported' if ok_number else 'missing or not a finite number'})")
            continue
        try:
            bound = float(limit)
        except ValueError:
            print(f"check_metrics: bad bound in '{check}'", file=sys.stderr)
            return 2
        ok = ok_number and OPS[op](value, bound)
        failed += 0 if ok else 1
        print(f"{'  ok  ' if ok else 'FAILED'} {key} = {value}  (want {op} {bound:g})")
    if base_path is not None:
        failed += ratchet(metrics, base_path, entry)
    if failed:
        print(f"check_metrics: {failed} check(s) failed in {path}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
