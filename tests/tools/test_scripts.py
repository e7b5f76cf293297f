"""scripts/*.sh, .ci/run and the README's two commands: syntax, usage errors,
and the contracts between them. Nothing here installs or builds anything."""
from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ["scripts/setup.sh", "scripts/run_paper000.sh", "scripts/test_all.sh",
           "scripts/check_static.sh", "scripts/fuzz.sh"]


def run(*cmd: str) -> subprocess.CompletedProcess:
    return subprocess.run(list(cmd), capture_output=True, text=True, cwd=ROOT, timeout=60)


@pytest.mark.parametrize("script", SCRIPTS + [".ci/run"])
def test_syntax_and_executable(script):
    path = ROOT / script
    assert path.is_file()
    assert path.stat().st_mode & 0o111, f"{script} is not executable"
    r = run("bash", "-n", str(path))
    assert r.returncode == 0, r.stderr
    assert "set -euo pipefail" in path.read_text()


@pytest.mark.parametrize("script", SCRIPTS)
def test_help(script):
    r = run(str(ROOT / script), "--help")
    assert r.returncode == 0, r.stderr
    assert "usage:" in r.stdout
    assert "setup:" not in r.stdout  # --help does nothing else


@pytest.mark.parametrize("script", ["scripts/setup.sh", "scripts/test_all.sh",
                                    "scripts/check_static.sh", "scripts/fuzz.sh"])
def test_unknown_option(script):
    r = run(str(ROOT / script), "--definitely-not-an-option")
    assert r.returncode == 2
    assert "unknown option" in r.stderr


def test_test_all_rejects_unknown_preset_before_setup():
    r = run(str(ROOT / "scripts/test_all.sh"), "no-such-preset")
    assert r.returncode == 2
    assert "no configure preset 'no-such-preset'" in r.stderr
    assert "setup:" not in r.stdout


def test_test_all_presets_exist():
    """Every name in test_all.sh's PRESETS list is a configure and build preset."""
    text = (ROOT / "scripts/test_all.sh").read_text()
    m = re.search(r"^PRESETS=\(\s*(.*?)\s*\)", text, re.S | re.M)
    assert m, "PRESETS=( ... ) not found in scripts/test_all.sh"
    names = [w for line in m.group(1).splitlines()
             for w in line.split("#")[0].split()]
    assert names and names[0] == "host"
    presets = json.loads((ROOT / "CMakePresets.json").read_text())
    configure = {p["name"] for p in presets.get("configurePresets", [])}
    build = {p["name"] for p in presets.get("buildPresets", [])}
    for n in names:
        assert n in configure, f"{n} is not a configure preset"
        assert n in build, f"{n} is not a build preset"


def test_ci_runs_the_tests_then_static_analysis_and_fuzzing():
    """.ci/run: test_all.sh (the README's command 2), check_static.sh and
    fuzz.sh, in that order, each even if an earlier one failed, and fails
    if any did."""
    lines = [ln.strip() for ln in (ROOT / ".ci/run").read_text().splitlines()]
    commands = [ln for ln in lines if ln and not ln.startswith("#")
                and not ln.startswith("set ") and not ln.startswith("cd ")]
    assert commands == ["rc=0",
                        "scripts/test_all.sh || rc=1",
                        "scripts/check_static.sh || rc=1",
                        "scripts/fuzz.sh || rc=1",
                        'exit "$rc"']


def test_readme_opens_with_the_two_commands():
    """The first screen (the first 40 lines): what the project is, then its
    first code block is exactly the two commands."""
    lines = (ROOT / "README.md").read_text().splitlines()
    assert lines[0].startswith("# ")
    body = [ln for ln in lines[1:] if ln.strip()]
    assert not body[0].startswith(("```", "|", "!", "<")), "a sentence saying what it is comes first"
    start = next(i for i, ln in enumerate(lines) if ln.startswith("```"))
    assert start < 40, f"the two commands start on line {start + 1}, below the first screen"
    assert lines[start] in ("```bash", "```sh", "```")
    end = lines.index("```", start + 1)
    commands = [ln.split("#")[0].strip() for ln in lines[start + 1:end]]
    assert commands == ["./scripts/run_paper000.sh", "./scripts/test_all.sh"]
    for c in commands:
        assert (ROOT / c).is_file()
