#!/usr/bin/env python3
"""The README's facts that go stale, checked against the code they describe.

fault table  (`<!-- fault table ... -->` to `<!-- end fault table -->`, rows
             `| CODE | NAME | cause |`): every code of drive_fault_t
             (firmware/supervisor/supervisor.h) with the name
             drive_fault_name() returns for it (supervisor.c), no more, no
             fewer, in order.
DBC          tools/can/drive.dbc's FaultCode comment ("drive_fault_t: 0 none,
             1 ...") lists every code of drive_fault_t, in order, no more.
drives table (`<!-- drives table ... -->`): one row per drive of the
             registry (firmware/drives/registry.c), first cell `NAME` then
             words; the STM32F405 column says "yes" exactly for the drives
             with a board configuration (firmware/drives/NAME/boards/).
layout       (the code block after `<!-- layout ... -->`): every directory
             it names exists; every top-level directory of the repository,
             every folder of firmware/ and of hal/backends/ is named.
links        every relative link and image of README.md, tools/README.md
             and docs/*.md names a file that exists (sections moved to
             docs/ must not leave a dangling link behind).

    python3 tools/checks/readme_facts.py [--readme README.md]   exit 1 on a mismatch (each one printed)
    python3 tools/checks/readme_facts.py --print-faults          the fault rows from the firmware

Standard library only.
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HEADER = ROOT / "firmware" / "supervisor" / "supervisor.h"
SOURCE = ROOT / "firmware" / "supervisor" / "supervisor.c"


def firmware_codes() -> list[tuple[int, str, str]]:
    """(code, name, comment) for every code of drive_fault_t but the count."""
    h = HEADER.read_text()
    m = re.search(r"typedef\s+enum\s*\{(.*?)\}\s*drive_fault_t\s*;", h, re.S)
    if not m:
        raise SystemExit(f"readme_facts: no 'typedef enum {{...}} drive_fault_t;' in {HEADER}")
    enum = {}
    for name, code, comment in re.findall(r"(DRIVE_FAULT_\w+)\s*=\s*(\d+)\s*,?\s*(?:/\*(.*?)\*/)?", m.group(1)):
        if name != "DRIVE_FAULT_COUNT":
            enum[name] = (int(code), (comment or "").strip())
    c = SOURCE.read_text()
    f = re.search(r"const char \*drive_fault_name\(drive_fault_t f\)\s*\{(.*?)\n\}", c, re.S)
    if not f:
        raise SystemExit(f"readme_facts: no drive_fault_name() in {SOURCE}")
    names = dict(re.findall(r"case (DRIVE_FAULT_\w+): return \"([^\"]*)\";", f.group(1)))
    out = []
    for sym, (code, comment) in enum.items():
        if sym not in names:
            raise SystemExit(f"readme_facts: drive_fault_name() has no case for {sym} ({SOURCE})")
        out.append((code, names[sym], comment))
    return sorted(out)


def readme_rows(readme: Path) -> list[tuple[str, str]]:
    text = readme.read_text()
    m = re.search(r"<!-- fault table[^>]*-->\n(.*?)<!-- end fault table -->", text, re.S)
    if not m:
        raise SystemExit(f"readme_facts: {readme}: no block between '<!-- fault table -->' and "
                         "'<!-- end fault table -->'")
    rows = []
    for line in m.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or not cells[0].isdigit():
            continue  # header, separator
        rows.append((cells[0], cells[1].strip("`")))
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--readme", type=Path, default=ROOT / "README.md")
    ap.add_argument("--print-faults", action="store_true", help="print the fault rows from the firmware")
    a = ap.parse_args()
    fw = firmware_codes()
    if a.print_faults:
        for code, name, comment in fw:
            print(f"| {code} | `{name}` | {comment} |")
        return 0
    text = a.readme.read_text()
    bad = check_faults(fw, readme_rows(a.readme), a.readme.name)
    bad += check_dbc_faults(fw)
    bad += check_drives(text, a.readme.name)
    bad += check_layout(text, a.readme.name)
    bad += check_links([a.readme, ROOT / "tools" / "README.md"] + sorted((ROOT / "docs").glob("*.md")))
    for msg in bad:
        print(f"readme_facts: {msg}")
    if bad:
        return 1
    print(f"readme_facts: {a.readme.name}: the {len(fw)} fault codes, the {len(registry())} drives and the "
          "layout agree with the code; every link resolves")
    return 0


def check_faults(fw: list, got: list, name: str) -> list[str]:
    want = [(str(code), n) for code, n, _ in fw]
    bad = []
    for w in want:
        if w not in got:
            bad.append(f"{name}: fault table lacks code {w[0]} `{w[1]}` (supervisor.h / drive_fault_name)")
    for g in got:
        if g not in want:
            bad.append(f"{name}: fault table lists code {g[0]} `{g[1]}`, which the firmware does not have")
    if not bad and got != want:
        bad.append(f"{name}: fault table: the codes are not in order")
    return bad


def check_dbc_faults(fw: list) -> list[str]:
    dbc = ROOT / "tools" / "can" / "drive.dbc"
    m = re.search(r'CM_ SG_ \d+ FaultCode "drive_fault_t: ([^"]*)";', dbc.read_text())
    if not m:
        return [f"{dbc.relative_to(ROOT)}: no FaultCode comment 'drive_fault_t: 0 none, ...'"]
    got = [int(c) for c in re.findall(r"(?:^|, )(\d+) ", m.group(1))]
    want = [code for code, _, _ in fw]
    if got != want:
        return [f"{dbc.relative_to(ROOT)}: FaultCode comment lists the codes {got}, drive_fault_t has {want} "
                "(supervisor.h); run tools/can/gen_c.py after editing the DBC"]
    return []


def registry() -> list[str]:
    c = (ROOT / "firmware" / "drives" / "registry.c").read_text()
    m = re.search(r"drive_registry\[\]\s*=\s*\{(.*?)\}", c, re.S)
    if not m:
        raise SystemExit("readme_facts: no drive_registry[] in firmware/drives/registry.c")
    return re.findall(r"&(\w+)_drive_ops", m.group(1))


def table(text: str, marker: str) -> list[list[str]]:
    m = re.search(rf"<!-- {marker}[^>]*-->\n(.*?)<!-- end {marker} -->", text, re.S)
    if not m:
        return []
    rows = []
    for line in m.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) > 1 and not set(cells[0]) <= set("- "):
            rows.append(cells)
    return rows


def board_title(board: str) -> str:
    """The board's short title: MC_BOARD_TITLE of hal/backends/stm32f405/boards/<board>.cmake before " (",
    e.g. "VESC 6"; empty if the board has no such file."""
    path = ROOT / "hal" / "backends" / "stm32f405" / "boards" / (board + ".cmake")
    if not path.exists():
        return ""
    m = re.search(r'set\(MC_BOARD_TITLE "([^"(]+)', path.read_text())
    return m.group(1).strip() if m else ""


def check_drives(text: str, name: str) -> list[str]:
    rows = table(text, "drives table")
    if not rows:
        return [f"{name}: no drives table between '<!-- drives table -->' and '<!-- end drives table -->'"]
    head, body = rows[0], rows[1:]
    try:
        stm = head.index("STM32F405 image")
    except ValueError:
        return [f"{name}: drives table: needs the column 'STM32F405 image'"]
    bad = []
    listed = {}
    for r in body:
        m = re.match(r"`(\w+)`", r[0])
        if not m:
            bad.append(f"{name}: drives table: row '{r[0]}' does not start with a `drive` name")
            continue
        listed[m.group(1)] = r
    reg = registry()
    for d in reg:
        if d not in listed:
            bad.append(f"{name}: drives table lacks the drive `{d}` of firmware/drives/registry.c")
    for d, r in listed.items():
        if d not in reg:
            bad.append(f"{name}: drives table lists `{d}`, which is not in firmware/drives/registry.c")
            continue
        boards = sorted(p.stem.removesuffix("_params") for p in (ROOT / "firmware" / "drives" / d / "boards")
                        .glob("*_params.c"))
        says = r[stm].lower().startswith("yes")
        if says != bool(boards):
            bad.append(f"{name}: drives table: `{d}` STM32F405 image '{r[stm]}', but firmware/drives/{d}/boards/ "
                       f"has {'the board configurations ' + ', '.join(boards) if boards else 'no board configuration'}")
        # each board the drive has a configuration for is named in the cell
        # by its title (boards/<board>.cmake MC_BOARD_TITLE, before " (")
        for b in sorted({c.split("_")[0] for c in boards}):
            title = board_title(b)
            if title and title not in r[stm]:
                bad.append(f"{name}: drives table: `{d}` runs on the {title} (firmware/drives/{d}/boards/{b}*.toml), "
                           f"its STM32F405 image cell '{r[stm]}' does not name it")
    return bad


def check_links(pages: list[Path]) -> list[str]:
    bad = []
    for page in pages:
        for m in re.finditer(r"\]\(([^)#\s]+)(?:#[^)]*)?\)|<img src=\"([^\"]+)\"", page.read_text()):
            target = m.group(1) or m.group(2)
            if re.match(r"[a-z]+:", target):
                continue  # https:, mailto:
            if not (page.parent / target).exists():
                bad.append(f"{page.relative_to(ROOT)}: link to {target}, which does not exist")
    return bad


def check_layout(text: str, name: str) -> list[str]:
    m = re.search(r"<!-- layout[^>]*-->\n```\w*\n(.*?)```", text, re.S)
    if not m:
        return [f"{name}: no layout block ('<!-- layout -->' then a code block)"]
    named, stack = set(), []
    for line in m.group(1).splitlines():
        mm = re.match(r"^( *)([\w.]+/)(?=\s|$)", line)
        if not mm:
            continue
        depth = len(mm.group(1)) // 2
        stack = stack[:depth] + [mm.group(2).rstrip("/")]
        named.add("/".join(stack))
    bad = [f"{name}: layout names {p}/, which does not exist" for p in sorted(named) if not (ROOT / p).is_dir()]
    want = {p.name for p in ROOT.iterdir() if p.is_dir() and p.name not in (".git", "build", "out", ".venv")
            and not p.name.startswith((".pytest", ".cache")) and (p.name == ".ci" or not p.name.startswith("."))}
    want |= {f"firmware/{p.name}" for p in (ROOT / "firmware").iterdir() if p.is_dir()}
    want |= {f"hal/backends/{p.name}" for p in (ROOT / "hal" / "backends").iterdir() if p.is_dir()}
    bad += [f"{name}: layout does not name {p}/" for p in sorted(want - named)]
    return bad


if __name__ == "__main__":
    sys.exit(main())
