"""The drives' facts files (firmware/drives/<name>/tools.toml, read by
tools/lib/drive_facts.py) and the check that no tool names a drive
(tools/checks/drive_names.py over tools/), issue 43.

Every drive of the registry has a facts file that loads, whose plot kind is
one of plot_run.py's; a wrong file is refused naming the file and the key;
a drive named in a tool's code is found, in its comments and docstrings
not, and the tools about one drive (named after it, or the docs' tables)
may name it.
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
from lib import drive_facts  # noqa: E402


def load_module(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


drive_names = load_module(ROOT / "tools" / "checks" / "drive_names.py", "drive_names")
GENERIC_TOOLS = ("tools/bench/pil.py", "tools/bench/pil_gen.cpp", "tools/bench/stm32_qemu.py",
                 "tools/plot/plot_run.py")


# ------------------------------------------------------------ the shipped --
def test_every_drive_has_facts():
    facts = drive_facts.load_all()
    assert list(facts) == drive_facts.registry_drives()
    plot = load_module(ROOT / "tools" / "plot" / "plot_run.py", "plot_run")
    for name, f in facts.items():
        assert f.plot in plot.KINDS, f"{f.rel()}: plot {f.plot!r}"
        assert f.scenario.is_file()
        assert set(f.types) <= {"float", "fixed"}
    assert drive_facts.default_drive(facts) is not None, "pil.py measures one drive by default (pil.prefix none)"


def test_short_names():
    assert drive_facts.short_name("paper001") == "p001"
    assert drive_facts.short_name("sensored_foc") == "sfoc"


def test_the_four_tools_name_no_drive():
    names = drive_facts.registry_drives()
    found = drive_names.naming_files(ROOT, names)
    for rel in GENERIC_TOOLS:
        assert rel not in found, f"{rel} names {found.get(rel)}"
        assert rel not in drive_names.PENDING


# ------------------------------------------------------- wrong facts files --
def fake_root(tmp_path: Path, toml: str | None, drives=("alpha",)) -> Path:
    (tmp_path / "firmware" / "drives").mkdir(parents=True)
    (tmp_path / "firmware" / "drives" / "registry.c").write_text(
        "const drive_ops_t *const drive_registry[] = {\n" + "".join(f"    &{d}_drive_ops,\n" for d in drives) + "};\n")
    (tmp_path / "sim" / "scenarios").mkdir(parents=True)
    (tmp_path / "sim" / "scenarios" / "bench.toml").write_text("")
    for d in drives:
        (tmp_path / "firmware" / "drives" / d).mkdir()
        if toml is not None:
            (tmp_path / "firmware" / "drives" / d / "tools.toml").write_text(toml)
    return tmp_path


GOOD = 'scenario = "sim/scenarios/bench.toml"\ntypes = ["float"]\nplot = "speed"\n'


def test_a_good_file(tmp_path):
    root = fake_root(tmp_path, GOOD + '[pil]\nprefix = "short"\nestimators = []\ntargets.float = { instr_mean = 9 }\n'
                                      '[stm32]\nstep = "pil"\n')
    f = drive_facts.load("alpha", root)
    assert f.head() == drive_facts.short_name("alpha") + "_" == "alpha_"
    assert f.targets_of(None, "float") == {"instr_mean": 9}
    assert f.step_budget() == {"instr_mean": 9}


@pytest.mark.parametrize("toml, words", [
    (None, ["firmware/drives/alpha/tools.toml", "missing"]),
    ('types = ["float"]\nplot = "speed"\n', ["firmware/drives/alpha/tools.toml", "scenario: missing"]),
    (GOOD + "colour = 3\n", ["firmware/drives/alpha/tools.toml", "colour: unknown key"]),
    (GOOD + "[pil]\nprefixx = \"name\"\n", ["tools.toml", "pil.prefixx: unknown key"]),
    (GOOD + "[pil]\nprefix = \"long\"\n", ["tools.toml", "pil.prefix: must be one of none, short, name"]),
    (GOOD.replace('["float"]', '["double"]'), ["tools.toml", "types: double: not one of float, fixed"]),
    (GOOD.replace("bench.toml", "nope.toml"), ["tools.toml", "scenario: no such file"]),
    (GOOD + "[pil]\ntargets.fixed.x = 1\n", ["tools.toml", "pil.targets.fixed: unknown key"]),
    (GOOD + "[pil]\ntargets.float = { instr_mean = \"a\" }\n", ["tools.toml", "pil.targets.float.instr_mean"]),
    (GOOD + "[pil]\nestimators = [\"x\"]\n", ["tools.toml", "pil.estimators: x: not one of"]),
    (GOOD + "[pil.probe]\ncolumns = [\"a\", \"b\"]\n", ["tools.toml", "pil.probe.columns"]),
    (GOOD + "[stm32]\nstep = 3\n", ["tools.toml", "stm32.step"]),
    ("scenario = \n", ["tools.toml", "not TOML"]),
])
def test_a_wrong_file_names_file_and_key(tmp_path, toml, words):
    root = fake_root(tmp_path, toml)
    with pytest.raises(drive_facts.FactsError) as e:
        drive_facts.load_all(root)
    for w in words:
        assert w in str(e.value)


def test_two_drives_without_prefix_refused(tmp_path):
    root = fake_root(tmp_path, GOOD + '[pil]\nprefix = "none"\n', drives=("alpha", "beta"))
    with pytest.raises(drive_facts.FactsError, match="firmware/drives/beta/tools.toml: pil.prefix: no prefix"):
        drive_facts.load_all(root)


# ----------------------------------------------------- drive_names on tools --
@pytest.mark.parametrize("rel, text, names_it", [
    ("tools/bench/pil.py", 'SCENARIO = "alpha_benchmark.toml"\n', True),
    ("tools/bench/pil.py", 'x = 1  # alpha_drive_step: a comment\n', False),
    ("tools/bench/pil.py", '"""The alpha drive: alpha_drive_step."""\nx = 1\n', False),
    ("tools/bench/pil.py", 'def f():\n    """alpha_x"""\n    return "ALPHA_Y"\n', True),
    ("tools/plot/plot_run.py", 'KINDS = {"alpha": 1}\n', True),
    ("tools/bench/pil_gen.cpp", '// alpha_drive_t\nint x;\n', False),
    ("tools/bench/pil_gen.cpp", 'const char* n = "alpha";\n', True),
])
def test_names_found_in_code_only(tmp_path, rel, text, names_it):
    root = fake_root(tmp_path, GOOD)
    (root / rel).parent.mkdir(parents=True, exist_ok=True)
    (root / rel).write_text(text)
    found = drive_names.naming_files(root, ["alpha"])
    assert (rel in found) == names_it, found
    if names_it:
        assert not drive_names.allowed(rel, ["alpha"])


@pytest.mark.parametrize("rel", ["tools/bench/pil_probes/alpha_probe.c", "tools/tables/alpha_tables.py",
                                 "tools/tables/observers.py", "firmware/drives/alpha/tools.toml"])
def test_tools_about_one_drive_may_name_it(rel):
    assert drive_names.allowed(rel, ["alpha"])
