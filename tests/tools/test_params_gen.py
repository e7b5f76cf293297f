"""tools/params/gen_params.py refuses a wrong parameters' source, naming the
file, the parameter and why (issue 44): on a copy of the sources it reads,
each case one edit. The generated files' currency is ctest
tools.params_current."""
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
GEN = ROOT / "tools" / "params" / "gen_params.py"
SOURCES = ["firmware/config/params.h", "firmware/config/board_params.toml", "tools/can/drive.dbc"]


@pytest.fixture
def repo(tmp_path):
    for rel in SOURCES:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / rel, tmp_path / rel)
    for p in (ROOT / "firmware" / "drives").glob("*/params.toml"):
        dst = tmp_path / p.relative_to(ROOT)
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(p, dst)
    shutil.copytree(ROOT / "hal" / "backends" / "stm32f405" / "boards", tmp_path / "hal/backends/stm32f405/boards")
    return tmp_path


def run(root, *args):
    return subprocess.run([sys.executable, str(GEN), "--root", str(root), *args], capture_output=True, text=True)


def edit(root, rel, old, new):
    p = root / rel
    text = p.read_text()
    assert old in text, (rel, old)
    p.write_text(text.replace(old, new, 1))


def test_the_copy_generates(repo):
    r = run(repo)
    assert r.returncode == 0, r.stderr
    assert (repo / "docs" / "parameters.md").exists()
    assert run(repo, "--check").returncode == 0


CASES = [
    ("firmware/drives/paper001/params.toml", "default = 543.0", "default = 1e8",
     "paper001/params.toml: param 15 (gamma): default 100000000.0 outside [0.0, 10000000.0]"),
    ("firmware/drives/paper001/params.toml", "id = 0x0109", "id = 0x0108",
     "n_p is id 0x0108 i32 '' here, 0x0109 i32 '' in firmware/drives/paper000/params.toml"),
    ("firmware/drives/paper001/params.toml", "id = 0x0102", "id = 0x0101", "id used twice: [257]"),
    ("firmware/drives/paper001/params.toml", "id = 0x0101", "id = 0x0042", "R_ohm: id 0x0042 outside 0x0100-0xfffe"),
    ("firmware/drives/paper001/params.toml", 'access = "ro"', 'access = "sometimes"', "access must be one of"),
    ("firmware/drives/paper001/params.toml", 'default = "flux"', 'default = "hall"', "default 'hall' not one of"),
    ("firmware/config/board_params.toml", "dead_time_s = 119e-9", "dead_time_s = 120e-9",
     "boards.odrive36.dead_time_s = 1.2e-07, the board's .dead_time_ns gives"),
    ("firmware/config/params.h", "PARAM_ERR_BAD_REQUEST = 8", "PARAM_ERR_BAD_REQUEST = 16",
     "param_status_t beyond 15 does not fit ParamReply's 4-bit Status"),
]


@pytest.mark.parametrize("rel,old,new,want", CASES, ids=[c[3][:40] for c in CASES])
def test_a_wrong_source_is_refused(repo, rel, old, new, want):
    edit(repo, rel, old, new)
    r = run(repo)
    assert r.returncode == 1
    assert want in r.stderr, r.stderr


def test_a_stale_generated_file_is_found(repo):
    assert run(repo).returncode == 0
    edit(repo, "firmware/drives/paper001/params.toml", "default = 543.0", "default = 544.0")
    r = run(repo, "--check")
    assert r.returncode == 1
    assert "paper001_params.c" in r.stderr and "docs/parameters.md" in r.stderr, r.stderr
