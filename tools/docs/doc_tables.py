#!/usr/bin/env python3
"""Tables of figures in the docs come from the scripts that measure them.

A generated block in README.md or docs/*.md looks like

    <!-- table KIND: python3 tools/tables/paper001_tables.py --build {build} -->
    ... the command's output ...
    <!-- end table -->

KIND says which build the command needs and whether ctest checks it:
  float   checked by ctest in the float host build ({build} = that build)
  fixed   checked by ctest in the fixed-point host build
  manual  timing or emulator figures that move with the machine: regenerated
          by hand (--update --kind manual), never compared

  doc_tables.py --check  --kind float --build build/host   exit 1 on a stale block (diff printed)
  doc_tables.py --update --kind float --build build/host   rewrite the blocks in place
  doc_tables.py --list                                      the blocks and their commands

A change that moves a number must update its table: run --update and commit.
Standard library only.
"""
from __future__ import annotations

import argparse
import difflib
import re
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BLOCK = re.compile(r"(<!-- table (float|fixed|manual): (.*?) -->\n)(.*?)(<!-- end table -->)", re.S)


def docs() -> list[Path]:
    return [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))


def run(cmd: str, build: Path) -> str:
    args = [a.replace("{build}", str(build)) for a in shlex.split(cmd)]
    if args and args[0] == "python3":
        args[0] = sys.executable
    r = subprocess.run(args, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"doc_tables: '{cmd}' failed (exit {r.returncode}): {r.stderr.strip()}")
    return r.stdout.rstrip("\n") + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true")
    mode.add_argument("--update", action="store_true")
    mode.add_argument("--list", action="store_true")
    ap.add_argument("--kind", choices=("float", "fixed", "manual"), default="float")
    ap.add_argument("--build", default=str(ROOT / "build" / "host"))
    a = ap.parse_args()
    build = Path(a.build).resolve()
    stale = 0
    n = 0
    for doc in docs():
        text = doc.read_text()
        out, pos = [], 0
        for m in BLOCK.finditer(text):
            kind, cmd, body = m.group(2), m.group(3), m.group(4)
            out.append(text[pos:m.start()])
            pos = m.end()
            if a.list:
                print(f"{doc.relative_to(ROOT)}: {kind}: {cmd}")
            if a.list or kind != a.kind:
                out.append(m.group(0))
                continue
            n += 1
            fresh = run(cmd, build)
            if a.check and fresh != body:
                stale += 1
                print(f"STALE {doc.relative_to(ROOT)}: {cmd}")
                sys.stdout.writelines(difflib.unified_diff(body.splitlines(True), fresh.splitlines(True),
                                                           "committed", "fresh run"))
            out.append(m.group(1) + fresh + m.group(5))
        out.append(text[pos:])
        if a.update:
            new = "".join(out)
            if new != text:
                doc.write_text(new)
                print(f"updated {doc.relative_to(ROOT)}")
    if a.check:
        if stale:
            print(f"doc_tables: {stale} of {n} {a.kind} table(s) differ from a fresh run; "
                  f"run: python3 tools/docs/doc_tables.py --update --kind {a.kind} --build {a.build}")
            return 1
        print(f"doc_tables: {n} {a.kind} table(s) match a fresh run")
    return 0


if __name__ == "__main__":
    sys.exit(main())
