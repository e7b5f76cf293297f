#!/usr/bin/env python3
"""Checks a motorsim metrics JSON against thresholds.

usage: check_metrics.py METRICS.json CHECK [CHECK ...]

CHECK is KEY<VALUE, KEY<=VALUE, KEY>VALUE, KEY>=VALUE or KEY (report only).
Prints every checked metric with its verdict; exits 1 if any check fails or
a metric is missing or not a finite number, 2 on bad usage. Standard library
only, so it runs with any python3.
"""
from __future__ import annotations

import json
import math
import operator
import re
import sys

OPS = {"<=": operator.le, ">=": operator.ge, "<": operator.lt, ">": operator.gt}
CHECK_RE = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)(?:(<=|>=|<|>)(.+))?$")


def main(argv: list[str]) -> int:
    if len(argv) < 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    path = argv[1]
    try:
        with open(path, encoding="utf-8") as f:
            metrics = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        print(f"check_metrics: cannot read {path}: {e}", file=sys.stderr)
        return 1
    failed = 0
    for check in argv[2:]:
        m = CHECK_RE.match(check.replace(" ", ""))
        if not m:
            print(f"check_metrics: bad check '{check}'", file=sys.stderr)
            return 2
        key, op, limit = m.group(1), m.group(2), m.group(3)
        value = metrics.get(key)
        ok_number = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        if op is None:
            print(f"  {key} = {value}  (reported)")
            continue
        bound = float(limit)
        ok = ok_number and OPS[op](value, bound)
        failed += 0 if ok else 1
        print(f"{'  ok  ' if ok else 'FAILED'} {key} = {value}  (want {op} {bound:g})")
    if failed:
        print(f"check_metrics: {failed} check(s) failed in {path}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
