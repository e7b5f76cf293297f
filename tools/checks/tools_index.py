#!/usr/bin/env python3
"""tools/README.md names every tool, and only the toolbox runs motorsim.

1. Every file of tools/ (scripts, sources, the DBC, the requirements; not
   READMEs, results/ snapshots or caches) is a row of the index in
   tools/README.md (between '<!-- tools index' and '<!-- end tools index -->'),
   and every row names a file that exists.
2. No Python file of tools/ outside tools/lib/ builds a motorsim command
   line: a list or tuple literal holding "--scenario" or "--metrics-out"
   followed by a value is one. They call tools/lib/motorsim.py instead.
   OTHER_PROGRAM lists the files whose such vector is for another program,
   each with which; a listed file that no longer builds one fails too, so
   the list cannot rot.

    python3 tools/checks/tools_index.py     exit 1 on any finding (each printed)

Standard library only.
"""
from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

TOOLS = Path(__file__).resolve().parents[1]
SKIP_DIRS = {"__pycache__", "results"}
SKIP_NAMES = {"README.md", "__init__.py"}
FLAGS = {"--scenario", "--metrics-out"}
OTHER_PROGRAM = {
    "bench/rtloop.py": "runs build/host/sim/rtloop (the real-time loop program), not motorsim",
}


def tool_files() -> list[str]:
    out = []
    for p in sorted(TOOLS.rglob("*")):
        rel = p.relative_to(TOOLS)
        if p.is_dir() or any(part in SKIP_DIRS for part in rel.parts) or p.name in SKIP_NAMES:
            continue
        if p.suffix in (".pyc",):
            continue
        out.append(rel.as_posix())
    return out


def index_rows() -> list[str]:
    text = (TOOLS / "README.md").read_text()
    m = re.search(r"<!-- tools index[^>]*-->\n(.*?)<!-- end tools index -->", text, re.S)
    if not m:
        raise SystemExit("tools_index: tools/README.md has no '<!-- tools index ... -->' block")
    return re.findall(r"^\|\s*`([^`]+)`\s*\|", m.group(1), re.M)


def builds_motorsim_cmd(path: Path) -> list[int]:
    tree = ast.parse(path.read_text(), str(path))
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.List, ast.Tuple)):
            # a flag followed by its value: an argument vector, not a label
            if any(isinstance(e, ast.Constant) and e.value in FLAGS for e in node.elts[:-1]):
                lines.append(node.lineno)
    return sorted(set(lines))


def main() -> int:
    bad = []
    files, rows = tool_files(), index_rows()
    for f in files:
        if f not in rows:
            bad.append(f"tools/{f}: not in the index of tools/README.md (one line: what it is)")
    for r in rows:
        if not (TOOLS / r).is_file():
            bad.append(f"tools/README.md names tools/{r}, which does not exist")
    for f in files:
        if not f.endswith(".py") or f.startswith("lib/"):
            continue
        hits = builds_motorsim_cmd(TOOLS / f)
        if hits and f not in OTHER_PROGRAM:
            bad.append(f"tools/{f}:{hits[0]}: builds a motorsim command line; call tools/lib/motorsim.py")
        if not hits and f in OTHER_PROGRAM:
            bad.append(f"tools/{f}: no longer builds a command line: take it off OTHER_PROGRAM in {Path(__file__).name}")
    for msg in bad:
        print(msg)
    if bad:
        return 1
    print(f"tools_index: {len(files)} files indexed; motorsim is run through tools/lib only "
          f"(and {', '.join(sorted(OTHER_PROGRAM))} runs another program)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
