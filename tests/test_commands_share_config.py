"""``gen`` and ``report`` check the model with the repository's configuration, as ``check``
does: a rule the team ignores does not stop ``gen`` nor appear in the report, and a broken
configuration is one line and exit 2 for every command."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "tests" / "fixtures" / "guide" / "agent-type-mismatch.uml"  # one S007 error, nothing else


def earl(cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120)


@pytest.fixture()
def repository(tmp_path: Path) -> Path:
    shutil.copy(MODEL, tmp_path / "model.uml")
    return tmp_path


def test_without_configuration_gen_refuses_the_model_and_the_report_lists_the_error(repository: Path) -> None:
    gen = earl(repository, "gen", "model.uml", "--target", "msg", "-o", "out")
    assert gen.returncode == 1 and "S007 error" in gen.stderr
    assert not (repository / "out").exists()
    report = earl(repository, "report", "model.uml", "-o", "report")
    assert report.returncode == 0, report.stderr
    assert "S007" in (repository / "report" / "index.html").read_text(encoding="utf-8")


def test_an_ignored_rule_neither_stops_gen_nor_shows_in_the_report(repository: Path) -> None:
    (repository / "earl-m2t.toml").write_text('ignore = ["S007"]\n', encoding="utf-8")
    gen = earl(repository, "gen", "model.uml", "--target", "msg", "-o", "out")
    assert gen.returncode == 0, gen.stderr
    assert any((repository / "out").rglob("*.msg"))
    report = earl(repository, "report", "model.uml", "-o", "report")
    assert report.returncode == 0, report.stderr
    assert "S007" not in (repository / "report" / "index.html").read_text(encoding="utf-8")
    # --no-config brings the finding back
    again = earl(repository, "gen", "model.uml", "--target", "msg", "-o", "out2", "--no-config")
    assert again.returncode == 1 and "S007 error" in again.stderr


@pytest.mark.parametrize("command", [["check", "model.uml"], ["gen", "model.uml", "-o", "out"],
                                     ["report", "model.uml", "-o", "out"]])
def test_a_broken_configuration_is_one_line_and_exit_2(repository: Path, command: list[str]) -> None:
    (repository / "earl-m2t.toml").write_text('ignore = ["NOPE1"]\n', encoding="utf-8")
    result = earl(repository, *command)
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1 and "NOPE1" in result.stderr
    assert not (repository / "out").exists()
