"""tools/bench/mutants.py without a build: the list's checks (every mutant
applies, every firmware file with a decision or a formula has a mutant or a
stated reason) and the table written from a run's JSON (invalid mutants and
those only the golden master catches are told apart from kills)."""
from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "bench"))
import mutants  # noqa: E402


def tree(tmp_path: Path) -> Path:
    shutil.copytree(ROOT / "firmware", tmp_path / "firmware")
    return tmp_path


def test_the_list_applies_to_the_tree(capsys):
    assert mutants.check_list(ROOT) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["mutants"] == len(mutants.MUTANTS) >= 90
    assert out["files_without_mutant"] == []


def test_a_mutant_whose_text_moved_fails_the_check(tmp_path, capsys):
    src = tree(tmp_path)
    mut = next(m for m in mutants.MUTANTS if m.id == "p002_stall_band_no_abs")
    f = src / "firmware" / mut.file
    f.write_text(f.read_text().replace(mut.edits[0][0], mut.edits[0][0].replace("mc_abs", "mc_fabs")))
    assert mutants.check_list(src) == 1
    assert "p002_stall_band_no_abs" in capsys.readouterr().err


def test_a_file_with_a_formula_and_no_mutant_fails_the_check(tmp_path, capsys):
    src = tree(tmp_path)
    (src / "firmware" / "control" / "new_law.c").write_text("int law(int x) { return x > 0 ? 2 * x : 0; }\n")
    (src / "firmware" / "control" / "new_law.h").write_text("int law(int x);\n")  # declarations: none needed
    assert mutants.check_list(src) == 1
    err = capsys.readouterr().err
    assert "firmware/control/new_law.c" in err and "new_law.h" not in err


def test_every_stated_reason_names_a_file_without_mutants():
    counts, _ = mutants.coverage(ROOT)
    for f in mutants.NO_MUTANT:
        assert counts.get(f) == 0, f


def test_markdown_tells_invalid_and_golden_only_apart(tmp_path, capsys):
    ids = [m.id for m in mutants.MUTANTS[:4]]
    run = {"mutants": 4, "killed": 1, "survived": 2, "invalid": 1, "golden": False,
           "golden_only": [ids[2]],
           "results": [
               {"id": ids[0], "killed": True, "invalid": False, "by": "firmware.X.Y", "golden_only": False},
               {"id": ids[1], "killed": False, "invalid": True, "by": "build", "golden_only": False},
               {"id": ids[2], "killed": False, "invalid": False, "by": "", "golden_only": True},
               {"id": ids[3], "killed": False, "invalid": False, "by": "", "golden_only": False}]}
    p = tmp_path / "run.json"
    p.write_text(json.dumps(run))
    assert mutants.markdown(p) == 0
    out = capsys.readouterr().out
    assert "1 of 3 valid mutants killed, 2 survived, 1 invalid" in out
    assert "1 survivor(s) caught by them alone" in out
    rows = {line.split("`")[1]: line for line in out.splitlines() if line.startswith("| `")}
    assert "1: X.Y" in rows[ids[0]]
    assert "**invalid**" in rows[ids[1]]
    assert "golden master only" in rows[ids[2]]
    assert rows[ids[3]].rstrip().endswith("**survived** |")
