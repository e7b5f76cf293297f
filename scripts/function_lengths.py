#!/usr/bin/env python3
"""Function lengths in C and C++ sources, from Universal Ctags.

A function's length is its lines from the line ctags gives as its start
(the line of its name) to its closing brace, both counted: end - line + 1.
Lambdas (ctags' anonymous __anon... functions) are counted in the function
that holds them, not on their own.

  scripts/function_lengths.py --max 80 firmware/drives
      prints every function over 80 lines under the folders given;
      exit 1 if there is one (the issue's check: every drive's step and
      every function in firmware/drives/ at most 80 lines)
  scripts/function_lengths.py --list
      prints every function over --max (default 80) in firmware/ sim/
      design/ with a count per folder; exit 0 (a survey, not a check)
  scripts/function_lengths.py --all firmware/drives/paper000
      prints every function with its length, longest first

Needs universal-ctags (apt package universal-ctags, installed by
scripts/setup.sh's toolchain list or by hand). Exit 2 when it is missing.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXTS = (".c", ".h", ".cpp", ".hpp", ".cc", ".cxx", ".hh")
LIST_FOLDERS = ("firmware", "sim", "design")


def sources(folders):
    for folder in folders:
        if os.path.isfile(folder):
            yield folder
            continue
        for base, dirs, files in os.walk(folder):
            dirs[:] = sorted(d for d in dirs if not d.startswith("."))
            for f in sorted(files):
                if f.endswith(EXTS):
                    yield os.path.join(base, f)


def functions(paths):
    """(path, name, start, length) of every function defined in paths."""
    paths = list(paths)
    if not paths:
        return []
    out = []
    # C files as C (C++ parsing would misread C11 keywords); the rest as C++
    for lang, group in (("C", [p for p in paths if p.endswith(".c")]),
                        ("C++", [p for p in paths if not p.endswith(".c")])):
        if not group:
            continue
        cmd = ["ctags", "--output-format=json", "--fields=+ne", "--kinds-C=f", "--kinds-C++=f",
               "--language-force=" + lang, "-o", "-", "-L", "-"]
        r = subprocess.run(cmd, input="\n".join(group) + "\n", capture_output=True, text=True, check=True)
        for line in r.stdout.splitlines():
            t = json.loads(line)
            if t.get("_type") != "tag" or t.get("kind") != "function" or "end" not in t:
                continue
            if t["name"].startswith("__anon"):
                continue
            name = t["name"]
            scope = [s for s in t.get("scope", "").split("::") if s and not s.startswith("__anon")]
            if scope:  # anonymous namespaces left out of the name
                name = "::".join(scope) + "::" + name
            out.append((t["path"], name, int(t["line"]), int(t["end"]) - int(t["line"]) + 1))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folders", nargs="*", help="folders or files (default with --list: firmware sim design)")
    ap.add_argument("--max", type=int, default=80, help="longest allowed function, in lines (default 80)")
    ap.add_argument("--list", action="store_true", help="survey firmware/ sim/ design/ (or the folders given); exit 0")
    ap.add_argument("--all", action="store_true", help="print every function with its length")
    a = ap.parse_args()
    if shutil.which("ctags") is None:
        print("function_lengths.py: universal-ctags is not installed (apt install universal-ctags)", file=sys.stderr)
        return 2
    folders = a.folders or (list(LIST_FOLDERS) if a.list else [])
    if not folders:
        ap.error("give the folders to check, or --list")
    if not all(os.path.exists(f) for f in folders):
        os.chdir(ROOT)  # folders named from the repository's root
    missing = [f for f in folders if not os.path.exists(f)]
    if missing:
        ap.error("no such folder: " + ", ".join(missing))
    over_total = 0
    for folder in folders:
        fns = sorted(functions(sources([folder])), key=lambda f: (-f[3], f[0], f[2]))
        shown = fns if a.all else [f for f in fns if f[3] > a.max]
        for path, name, start, n in shown:
            print(f"{n:5d}  {path}:{start}  {name}")
        over = sum(1 for f in fns if f[3] > a.max)
        over_total += over
        if a.list or len(folders) > 1:
            print(f"{folder}: {over} function(s) over {a.max} lines, of {len(fns)}")
    if a.list or a.all:
        return 0
    return 1 if over_total else 0


if __name__ == "__main__":
    sys.exit(main())
