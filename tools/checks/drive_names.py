#!/usr/bin/env python3
"""No program names a drive: the check of the drive interface (issue 27),
extended to tools/ (issue 43).

A drive lives in its own folder and is named only there and in the
registries. This script reads the registered drives from
firmware/drives/registry.c (each `&<name>_drive_ops`) and fails when the
code of a C, C++, CMake or Python file of firmware/, design/, hal/, sim/ or
tools/ names one (`paper001_...`, `P001_...`, `p001_...`, `sensored_foc...`,
`SFOC_...`; comments stripped, and a Python file's docstrings) outside
  firmware/drives/<name>/          the drive itself (its tools.toml: what the
                                   tools take from it, tools/lib/drive_facts.py)
  firmware/drives/registry.{h,c}   the firmware registry
  design/<name>_design.{h,c}       its host-side design (file named after it)
  design/ops/<name>_design_ops.c   its design as an image runs it, and
                                   design/ops/design_ops_registry.c
  sim/host_drives/<name>_host.{cpp,h}  its host part (the header for that
                                   drive's other host code; what motorsim does
                                   for it beyond the interface: its scoring,
                                   its commissioning), and host_registry.cpp
  tools/**/<name>_*                a tool about that drive alone, named after
                                   it (tools/bench/pil_probes/<name>_probe.c,
                                   tools/tables/<name>_tables.py)
  tools/tables/                    the generators of the docs' tables of
                                   results, each about given drives' runs.
The other tools take the drives from the registry and what they need of each
from its facts file: tools/bench/pil.py, pil_gen.cpp, stm32_qemu.py and
tools/plot/plot_run.py name none. tests/ and docs/ may name drives (a test
or a page is about one).

Files that still name drives are listed in PENDING with what makes them
generic; the list may only shrink: a file not on it that names a drive
fails, and so does a listed file that no longer names one (take it off).

usage: drive_names.py [--root DIR] [--list]   (--list: every file that names a drive)
Standard library only.
"""
from __future__ import annotations

import argparse
import io
import re
import sys
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))  # the toolbox: the drives' short names
from lib.drive_facts import short_name  # noqa: E402

SCOPE = ("firmware", "design", "hal", "sim", "tools")
SUFFIXES = {".c", ".h", ".cpp", ".hpp", ".txt", ".py"}

# Files that name drives today, and what makes each generic (issue 28
# emptied it for firmware/ ... sim/; issue 43 added tools/'s; it may only
# shrink).
PENDING: dict[str, str] = {
    "tools/bench/baseline.py": "its scenario list and the kinds of scenario it runs variants of (paper 000's "
                               "seeds, paper 002's table's estimator and float-only runs) from each drive's "
                               "tools.toml (types, estimators) and the scenarios' [drive] kind",
    "tools/bench/long_runs.py": "its scenario (paper 000's experiment) from a --drive's tools.toml",
    "tools/bench/mutants.py": "each drive's mutants in a file of its own folder, read from the registry's drives",
    "tools/bench/pil_profile.py": "--drive: its step <name>_drive_step and its scenario from the drive's "
                                  "tools.toml, as pil.py",
    "tools/bench/realtime.py": "its default scenario (paper 000's experiment) from the default drive's tools.toml",
    "tools/bench/rtloop.py": "its default scenario (paper 000's experiment) from the default drive's tools.toml",
    "tools/bench/sim_speed.py": "its scenario and motor (paper 001's benchmark) from a --drive's tools.toml",
    "tools/checks/compare_builds.py": "its default scenarios (paper 000's) from the tools.toml of every drive "
                                      "whose types are float and fixed",
}

COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
CMAKE_COMMENT = re.compile(r"#[^\n]*")
PY_OPENERS = (tokenize.NEWLINE, tokenize.NL, tokenize.INDENT, tokenize.DEDENT, tokenize.ENCODING)


def python_code(text: str) -> str:
    """A Python file's tokens without its comments and docstrings (a string
    that is a statement of its own), joined by spaces."""
    out, prev = [], tokenize.NEWLINE
    try:
        toks = list(tokenize.generate_tokens(io.StringIO(text).readline))
    except (tokenize.TokenError, SyntaxError):
        return CMAKE_COMMENT.sub("", text)  # not Python: at least no # comment
    for i, t in enumerate(toks):
        if t.type == tokenize.COMMENT:
            continue
        if t.type == tokenize.STRING and prev in PY_OPENERS:
            nxt = next((u for u in toks[i + 1:] if u.type not in (tokenize.NL, tokenize.COMMENT)), None)
            if nxt is None or nxt.type in (tokenize.NEWLINE, tokenize.ENDMARKER):
                prev = tokenize.STRING
                continue
        if t.type != tokenize.NL:
            prev = t.type
        out.append(t.string)
    return " ".join(out)


def drives(root: Path) -> list[str]:
    text = (root / "firmware/drives/registry.c").read_text(encoding="utf-8")
    return re.findall(r"&(\w+)_drive_ops", text)


def patterns(names: list[str]) -> re.Pattern:
    """Each name, upper- and lower-case, and its short prefix: paper001 ->
    p001/P001; a name of words (sensored_foc) -> the initials of all but the
    last word and the last word (sfoc/SFOC)."""
    alts = []
    for n in names:
        short = short_name(n)  # tools/lib/drive_facts.py: the one rule
        alts += [n, n.upper(), short, short.upper()]
    return re.compile(r"(?<![A-Za-z0-9])(" + "|".join(map(re.escape, sorted(set(alts), key=len, reverse=True)))
                      + r")(?=[A-Za-z0-9_]|\b)")


def allowed(rel: str, names: list[str]) -> bool:
    if rel in ("firmware/drives/registry.h", "firmware/drives/registry.c", "sim/host_drives/host_registry.cpp",
               "sim/host_drives/host_drive.h", "design/ops/design_ops_registry.c"):
        return True
    for n in names:
        if rel.startswith(f"firmware/drives/{n}/") or rel.startswith(f"design/{n}_design.") or \
                rel == f"design/ops/{n}_design_ops.c" or \
                rel in (f"sim/host_drives/{n}_host.cpp", f"sim/host_drives/{n}_host.h"):
            return True
        if rel.startswith("tools/") and rel.rsplit("/", 1)[-1].startswith(f"{n}_"):
            return True  # a tool about that drive alone, named after it
    return rel.startswith("tools/tables/")  # the docs' tables of results


def naming_files(root: Path, names: list[str]) -> dict[str, str]:
    pat = patterns(names)
    found = {}
    for top in SCOPE:
        for f in sorted((root / top).rglob("*")):
            if f.suffix not in SUFFIXES or not f.is_file() or "generated" in f.parts:
                continue
            if f.suffix == ".txt" and f.name != "CMakeLists.txt":
                continue
            text = f.read_text(encoding="utf-8", errors="replace")
            if f.suffix == ".py":
                code = python_code(text)
            else:
                code = CMAKE_COMMENT.sub("", text) if f.suffix == ".txt" else COMMENT.sub("", text)
            m = pat.search(code)
            if m:
                found[f.relative_to(root).as_posix()] = m.group(0)
    return found


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=str(ROOT))
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    root = Path(a.root)
    names = drives(root)
    if not names:
        print("drive_names.py: no drive found in firmware/drives/registry.c", file=sys.stderr)
        return 2
    found = naming_files(root, names)
    if a.list:
        for f, tok in found.items():
            print(f"{f}: {tok}")
        return 0
    bad = 0
    for f, tok in found.items():
        if not allowed(f, names) and f not in PENDING:
            print(f"drive_names.py: {f} names a drive ('{tok}') outside the drive's folder and the registries "
                  "(go through drives/drive.h and the registry)", file=sys.stderr)
            bad += 1
    for f in PENDING:
        if f not in found:
            print(f"drive_names.py: {f} no longer names a drive: take it off PENDING", file=sys.stderr)
            bad += 1
    n_ok = sum(1 for f in found if allowed(f, names))
    print(f"drive_names.py: drives {', '.join(names)}; {n_ok} files of their own, {len(PENDING)} pending, "
          f"{bad} problems")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
