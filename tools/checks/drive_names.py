#!/usr/bin/env python3
"""No program names a drive: the check of the drive interface (issue 27).

A drive lives in its own folder and is named only there and in the
registries. This script reads the registered drives from
firmware/drives/registry.c (each `&<name>_drive_ops`) and fails when the
code (comments stripped) of a C, C++ or CMake file of firmware/, design/,
hal/ or sim/ names one (`paper001_...`, `P001_...`, `p001_...`,
`sensored_foc...`, `SFOC_...`) outside
  firmware/drives/<name>/          the drive itself
  firmware/drives/registry.{h,c}   the firmware registry
  design/<name>_design.{h,c}       its host-side design (file named after it)
  sim/host_drives/<name>_host.{cpp,h}  its host part (the header for that
                                   drive's other host code), and
                                   host_registry.cpp
  sim/motorsim/drive_runs/<name>_*  its part of motorsim's run (its probe of
                                   the recorder), and drive_runs/registry.cpp.
tests/, tools/ and docs/ may name drives (a test or a table is about one).

Files that still name drives are listed in PENDING with what makes them
generic; the list may only shrink: a file not on it that names a drive
fails, and so does a listed file that no longer names one (take it off).

usage: drive_names.py [--root DIR] [--list]   (--list: every file that names a drive)
Standard library only.
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCOPE = ("firmware", "design", "hal", "sim")
SUFFIXES = {".c", ".h", ".cpp", ".hpp", ".txt"}

# Files that name drives today, and what makes each generic: none left
# (issue 28 emptied it; it may only shrink).
PENDING: dict[str, str] = {}

COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
CMAKE_COMMENT = re.compile(r"#[^\n]*")


def drives(root: Path) -> list[str]:
    text = (root / "firmware/drives/registry.c").read_text(encoding="utf-8")
    return re.findall(r"&(\w+)_drive_ops", text)


def patterns(names: list[str]) -> re.Pattern:
    """Each name, upper- and lower-case, and its short prefix: paper001 ->
    p001/P001; a name of words (sensored_foc) -> the initials of all but the
    last word and the last word (sfoc/SFOC)."""
    alts = []
    for n in names:
        m = re.fullmatch(r"paper(\d{3})", n)
        words = n.split("_")
        short = f"p{m.group(1)}" if m else "".join(w[0] for w in words[:-1]) + words[-1]
        alts += [n, n.upper(), short, short.upper()]
    return re.compile(r"(?<![A-Za-z0-9])(" + "|".join(map(re.escape, sorted(set(alts), key=len, reverse=True)))
                      + r")(?=[A-Za-z0-9_]|\b)")


def allowed(rel: str, names: list[str]) -> bool:
    if rel in ("firmware/drives/registry.h", "firmware/drives/registry.c", "sim/host_drives/host_registry.cpp",
               "sim/host_drives/host_drive.h", "sim/motorsim/drive_runs/registry.cpp"):
        return True
    for n in names:
        if rel.startswith(f"firmware/drives/{n}/") or rel.startswith(f"design/{n}_design.") or \
                rel in (f"sim/host_drives/{n}_host.cpp", f"sim/host_drives/{n}_host.h") or \
                rel.startswith(f"sim/motorsim/drive_runs/{n}_"):
            return True
    return False


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
