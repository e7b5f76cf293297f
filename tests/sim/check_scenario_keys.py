#!/usr/bin/env python3
"""sim/scenarios/README.md against the scenario parser, both ways (issue 28):
every key the parser accepts is documented in its table's section, and every
key a section documents is one the parser accepts.

The parser's keys come from the program scenario_keys (mcsim::scenario_keys():
"TABLE KEY ..." lines). The README's: the first column's `backticked` names
of every markdown table in the section `### \`[TABLE]\`` (or
`#### \`[[TABLE]]\``), several names in a cell separated by commas; the top
level is `### top level`'s table plus every `[TABLE]` heading; [motor]
documents "file" and the motor file's keys. [expect] (its keys are the
drive's metrics, checked by motorsim before a run) and [board] (its keys
are documented in docs/board.md, checked there) are not compared.

usage: check_scenario_keys.py SCENARIO_KEYS_PROGRAM README.md
Standard library only.
"""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

NOT_COMPARED = {"expect": "its keys are metrics (motorsim checks them)", "board": "docs/board.md"}
HEADING = re.compile(r"^#{3,4} +(?:`\[\[?([A-Za-z0-9_.]+)\]?\]`|(top level))", re.M)
KEY = re.compile(r"`([A-Za-z_][A-Za-z0-9_]*)`")


def readme_sections(text: str) -> dict[str, str]:
    """Section name -> its text, up to the next heading of any level."""
    out = {}
    marks = [(m.start(), m.end(), m.group(1) or "top") for m in HEADING.finditer(text)]
    for i, (_, end, name) in enumerate(marks):
        nxt = re.compile(r"^#{1,4} ", re.M).search(text, end)
        out[name] = text[end:nxt.start() if nxt else len(text)]
    return out


def table_keys(section: str) -> set[str]:
    """The backticked names of the first column of every markdown table."""
    keys = set()
    for line in section.splitlines():
        if not line.startswith("|") or set(line) <= set("|-: "):
            continue
        first = line.split("|")[1]
        if first.strip() in ("key",):
            continue
        for part in first.split(","):
            m = KEY.fullmatch(part.strip())
            if m:
                keys.add(m.group(1))
    return keys


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    prog, readme = sys.argv[1], Path(sys.argv[2])
    p = subprocess.run([prog], capture_output=True, text=True)
    if p.returncode != 0:
        print(f"check_scenario_keys.py: {prog} exited {p.returncode}: {p.stderr}", file=sys.stderr)
        return 1
    parser = {}
    for line in p.stdout.splitlines():
        name, *keys = line.split()
        parser.setdefault(name, set()).update(keys)
    text = readme.read_text(encoding="utf-8")
    sections = readme_sections(text)
    documented = {n: table_keys(s) for n, s in sections.items()}
    documented["top"] |= {n for n in sections if n != "top" and "." not in n}
    # [motor]: "file" and the motor file's keys (its second table)
    parser["motor"] = parser.pop("motor_file") | {"file"}
    bad = 0
    for name, keys in sorted(parser.items()):
        if name in NOT_COMPARED:
            continue
        if name not in documented:
            print(f"{readme}: no section for [{name}] (the parser reads {', '.join(sorted(keys))})")
            bad += 1
            continue
        for k in sorted(keys - documented[name]):
            print(f"{readme}: [{name}] {k}: the parser accepts it, the README does not document it")
            bad += 1
        for k in sorted(documented[name] - keys):
            print(f"{readme}: [{name}] {k}: documented, but the parser does not know it")
            bad += 1
    for name in sorted(set(documented) - set(parser) - set(NOT_COMPARED)):
        if documented[name]:
            print(f"{readme}: section [{name}] documents keys of a table the parser does not read")
            bad += 1
    n = sum(len(v) for k, v in parser.items() if k not in NOT_COMPARED)
    print(f"check_scenario_keys.py: {len(parser) - len(NOT_COMPARED)} tables, {n} keys; {bad} problems")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
