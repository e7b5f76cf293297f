"""What the tools know of a drive: the registry's drives and each one's
facts file, firmware/drives/<name>/tools.toml.

The tools of tools/ (pil.py, stm32_qemu.py, plot_run.py) name no drive:
they take the drives from the firmware registry (firmware/drives/registry.c,
each `&<name>_drive_ops`, in its order) and what they need of each from the
file beside its code, so that a drive is added with its files and one line
of the registry, and no tool is edited. The file is called tools.toml for
who reads it, as the folder's needs.cmake is what CMake reads (what the
drive needs of a board) and boards/ holds its configurations.

    # firmware/drives/<name>/tools.toml (paths relative to the repository)
    scenario = "sim/scenarios/<name>_benchmark.toml"  # its benchmark: the
                                     # default scenario of pil.py, stm32_qemu.py
    types = ["float", "fixed"]       # the numeric types its design runs in
    estimators = ["a", "b"]          # what --estimator takes for it (mc_pil_gen,
                                     # motorsim), [] or absent: one estimator
    plot = "speed"                   # plot_run.py's panel set of its CSV (a kind
                                     # of plot_run.KINDS, told from the columns)
    [pil]                            # tools/bench/pil.py (the table may be absent)
    prefix = "name"                  # its keys' prefix: "name" (<name>_m4f_float_...),
                                     # "short" (its short name, short_name(): p001_...),
                                     # "none" (no prefix: m4f_float_...; the one drive
                                     # pil.py measures by default)
    estimators = ["a", "b"]          # measured one by one, the estimator in the
                                     # keys (<prefix>_<estimator>_m4f_float_...); [] or
                                     # absent: the scenario's
    images = ["mc_selftest"]         # further images built beside mc_pil, their
                                     # sizes recorded (<p>_selftest_image_flash_bytes)
    targets.float = { instr_mean = 2500 }    # cost targets, <p>_<key> <= value
    targets.a.float = { part_x_instr_mean = 600 }  # of one estimator's runs
    [pil.probe]                      # its probe, tools/bench/pil_probes/<name>_probe.c:
    columns = ["x", "empty", ...]    # "P <period> <columns>" in SysTick ticks; a
                                     # part's count is its column minus the first
                                     # "empty" after it (an empty call timed alike)
    sums = { xy = ["x", "y"] }       # parts summed per period (<p>_part_xy_instr_*)
    [stm32]                          # tools/bench/stm32_qemu.py --check-budget, beyond
                                     # the share of the period every image keeps
    isr = { instr_mean = 1000 }      # the control interrupt's (isr_instr_mean <= 1000)
    step = "pil"                     # its step within [pil] targets.float (images of
                                     # the drive's own estimator, no variant), or a
                                     # table { instr_mean = ... } of its own

Every key is checked: a missing or unknown key, or a value of the wrong
kind, is a FactsError naming the file and the key.

Standard library only (Python 3.11: tomllib).
"""
from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FILE = "tools.toml"
TYPES = ("float", "fixed")
PREFIXES = ("none", "short", "name")
EMPTY = "empty"  # a probe column that times an empty call


class FactsError(ValueError):
    """A facts file is missing or wrong: the message names the file and the key."""


@dataclass(frozen=True)
class Probe:
    columns: tuple[str, ...]
    sums: dict[str, tuple[str, ...]]

    def parts(self) -> list[tuple[str, int, int]]:
        """(part, its column, its empty twin's column), columns counted
        from 1 after the period (as in the P line's fields)."""
        out = []
        for k, c in enumerate(self.columns):
            if c == EMPTY:
                continue
            twin = next(j for j in range(k + 1, len(self.columns)) if self.columns[j] == EMPTY)
            out.append((c, k + 1, twin + 1))
        return out

    def first_empty(self) -> int:
        return self.columns.index(EMPTY) + 1


@dataclass(frozen=True)
class Pil:
    prefix: str = "name"
    estimators: tuple[str, ...] = ()
    images: tuple[str, ...] = ()
    probe: Probe | None = None
    # (estimator or None, type) -> {key suffix: limit}
    targets: dict[tuple[str | None, str], dict[str, float]] = field(default_factory=dict)


@dataclass(frozen=True)
class Stm32:
    isr: dict[str, float] = field(default_factory=dict)
    step: str | dict[str, float] | None = None


@dataclass(frozen=True)
class Facts:
    name: str
    path: Path
    scenario: Path
    types: tuple[str, ...]
    estimators: tuple[str, ...]
    plot: str
    pil: Pil
    stm32: Stm32

    def rel(self, root: Path = ROOT) -> str:
        return _rel(self.path, root)

    def head(self) -> str:
        """The prefix of its pil.py keys, with its underscore ("" for none)."""
        return {"none": "", "short": short_name(self.name) + "_", "name": self.name + "_"}[self.pil.prefix]

    def targets_of(self, estimator: str | None, typ: str) -> dict[str, float]:
        """The PIL targets of one run: the type's, then the estimator's."""
        out = dict(self.pil.targets.get((None, typ), {}))
        if estimator is not None:
            out.update(self.pil.targets.get((estimator, typ), {}))
        return out

    def step_budget(self) -> dict[str, float]:
        """The limits of its STM32 image's drive step (keys without the drive_step_ prefix)."""
        if self.stm32.step == "pil":
            return dict(self.pil.targets.get((None, "float"), {}))
        return dict(self.stm32.step or {})


def _rel(p: Path, root: Path) -> str:
    try:
        return p.resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return str(p)


def short_name(name: str) -> str:
    """paper001 -> p001; a name of words (sensored_foc) -> the initials of
    all but the last word and the last word (sfoc); else the name."""
    m = re.fullmatch(r"paper(\d{3})", name)
    if m:
        return "p" + m.group(1)
    words = name.split("_")
    return "".join(w[0] for w in words[:-1]) + words[-1]


def registry_drives(root: Path = ROOT) -> list[str]:
    """The drives of firmware/drives/registry.c (each `&<name>_drive_ops`), in its order."""
    path = Path(root) / "firmware" / "drives" / "registry.c"
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise FactsError(f"{path}: {e.strerror}") from None
    names = re.findall(r"&(\w+)_drive_ops", text)
    if not names:
        raise FactsError(f"{_rel(path, Path(root))}: no drive (`&<name>_drive_ops`) in drive_registry[]")
    return names


class _Checker:
    """Checks one file's tables: errors name the file and the dotted key."""

    def __init__(self, rel: str):
        self.rel = rel

    def fail(self, key: str, msg: str):
        raise FactsError(f"{self.rel}: {key}: {msg}")

    def table(self, t, key: str, known: tuple[str, ...], required: tuple[str, ...] = ()) -> dict:
        if not isinstance(t, dict):
            self.fail(key, f"must be a table (got {t!r})")
        where = key + "." if key else ""
        for k in t:
            if k not in known:
                self.fail(where + k, f"unknown key (known here: {', '.join(known)})")
        for k in required:
            if k not in t:
                self.fail(where + k, "missing")
        return t

    def string(self, v, key: str, choices: tuple[str, ...] | None = None) -> str:
        if not isinstance(v, str) or not v:
            self.fail(key, f"must be a non-empty string (got {v!r})")
        if choices is not None and v not in choices:
            self.fail(key, f"must be one of {', '.join(choices)} (got {v!r})")
        return v

    def names(self, v, key: str, choices: tuple[str, ...] | None = None, nonempty: bool = False) -> tuple[str, ...]:
        if not isinstance(v, list) or any(not isinstance(x, str) or not x for x in v):
            self.fail(key, f"must be a list of names (got {v!r})")
        if nonempty and not v:
            self.fail(key, "must not be empty")
        if len(set(v)) != len(v):
            self.fail(key, f"names a value twice ({v!r})")
        if choices is not None:
            bad = [x for x in v if x not in choices]
            if bad:
                self.fail(key, f"{', '.join(bad)}: not one of {', '.join(choices) or '(none)'}")
        return tuple(v)

    def limits(self, v, key: str) -> dict[str, float]:
        t = v if isinstance(v, dict) else self.fail(key, f"must be a table of limits (got {v!r})")
        for k, lim in t.items():
            if isinstance(lim, bool) or not isinstance(lim, (int, float)) or not re.fullmatch(r"[a-z0-9_]+", k):
                self.fail(f"{key}.{k}", f"must be a number under a lower-case key (got {lim!r})")
        return dict(t)


def _pil(c: _Checker, t, estimators: tuple[str, ...], types: tuple[str, ...]) -> Pil:
    c.table(t, "pil", ("prefix", "estimators", "images", "targets", "probe"))
    prefix = c.string(t.get("prefix", "name"), "pil.prefix", PREFIXES)
    ests = c.names(t.get("estimators", []), "pil.estimators", estimators)
    images = c.names(t.get("images", []), "pil.images")
    for k, img in enumerate(images):
        if not re.fullmatch(r"mc_[a-z0-9_]+", img):
            c.fail(f"pil.images[{k}]", f"a CMake target of hal/backends/mcu, mc_<name> (got {img!r})")
    targets: dict[tuple[str | None, str], dict[str, float]] = {}
    tt = c.table(t.get("targets", {}), "pil.targets", types + ests)
    for k, v in tt.items():
        if k in types:
            targets[(None, k)] = c.limits(v, f"pil.targets.{k}")
        else:
            for typ, lims in c.table(v, f"pil.targets.{k}", types).items():
                targets[(k, typ)] = c.limits(lims, f"pil.targets.{k}.{typ}")
    probe = None
    if "probe" in t:
        pt = c.table(t["probe"], "pil.probe", ("columns", "sums"), ("columns",))
        cols = pt["columns"]
        if not isinstance(cols, list) or any(not isinstance(x, str) or not x for x in cols):
            c.fail("pil.probe.columns", f"must be a list of names (got {cols!r})")
        cols = tuple(cols)
        parts = [x for x in cols if x != EMPTY]
        if len(set(parts)) != len(parts):
            c.fail("pil.probe.columns", f"names a part twice ({list(cols)!r})")
        if not cols or cols[-1] != EMPTY or cols[0] == EMPTY:
            c.fail("pil.probe.columns", f"parts, each followed (not necessarily at once) by an \"{EMPTY}\" column "
                                        f"that times an empty call, the last column one (got {list(cols)!r})")
        sums = {}
        for k, v in c.table(pt.get("sums", {}), "pil.probe.sums", tuple(pt.get("sums", {}))).items():
            sums[k] = c.names(v, f"pil.probe.sums.{k}", tuple(x for x in cols if x != EMPTY), nonempty=True)
        probe = Probe(cols, sums)
    return Pil(prefix, ests, images, probe, targets)


def _stm32(c: _Checker, t) -> Stm32:
    c.table(t, "stm32", ("isr", "step"))
    isr = c.limits(t.get("isr", {}), "stm32.isr")
    step = t.get("step")
    if step is not None and step != "pil":
        step = c.limits(step, "stm32.step") if isinstance(step, dict) else \
            c.fail("stm32.step", f"must be \"pil\" (its [pil] targets.float) or a table of limits (got {step!r})")
    return Stm32(isr, step)


def load(name: str, root: Path = ROOT) -> Facts:
    """The facts of drive name (FactsError naming the file and the key)."""
    root = Path(root)
    path = root / "firmware" / "drives" / name / FILE
    rel = _rel(path, root)
    try:
        with path.open("rb") as f:
            t = tomllib.load(f)
    except FileNotFoundError:
        raise FactsError(f"{rel}: missing: every drive of firmware/drives/registry.c has one "
                         f"(what the tools take from the drive, tools/lib/drive_facts.py)") from None
    except tomllib.TOMLDecodeError as e:
        raise FactsError(f"{rel}: not TOML: {e}") from None
    c = _Checker(rel)
    c.table(t, "", ("scenario", "types", "estimators", "plot", "pil", "stm32"), ("scenario", "types", "plot"))
    scenario = root / c.string(t["scenario"], "scenario")
    if not scenario.is_file():
        c.fail("scenario", f"no such file: {t['scenario']} (a path relative to the repository)")
    types = c.names(t["types"], "types", TYPES, nonempty=True)
    estimators = c.names(t.get("estimators", []), "estimators")
    plot = c.string(t["plot"], "plot")
    pil = _pil(c, t.get("pil", {}), estimators, types)
    stm32 = _stm32(c, t.get("stm32", {}))
    return Facts(name, path, scenario, types, estimators, plot, pil, stm32)


def load_all(root: Path = ROOT) -> dict[str, Facts]:
    """Every drive of the registry with its facts, in the registry's order;
    checks what concerns several files (one drive at most without a prefix,
    no two with the same prefix)."""
    out = {n: load(n, root) for n in registry_drives(root)}
    heads: dict[str, str] = {}
    for n, f in out.items():
        h = f.head()
        if h in heads:
            what = "no prefix" if not h else f"the prefix {h}"
            raise FactsError(f"{f.rel(root)}: pil.prefix: {what}, as {heads[h]} has")
        heads[h] = f.rel(root)
    return out


def default_drive(facts: dict[str, Facts]) -> str | None:
    """The drive pil.py measures by default: the one whose keys carry no prefix."""
    return next((n for n, f in facts.items() if f.pil.prefix == "none"), None)
