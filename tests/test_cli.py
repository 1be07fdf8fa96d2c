"""The command line as a user runs it: exit codes, output formats, one-line errors."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
BAD = ROOT / "tests" / "fixtures" / "bad"


def earl(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120)


def test_check_on_the_clean_sample_exits_0_with_a_summary() -> None:
    result = earl("check", str(SAMPLE))
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip().splitlines() == ["1 file checked: 0 error(s), 0 warning(s), 0 info"]
    assert result.stderr == ""


def _broken_sample(tmp_path: Path) -> Path:
    """The sample with one guard referring to a primitive predicate that does not exist."""
    text = SAMPLE.read_text(encoding="utf-8").replace("newJointPos/pp.fun ∧", "newJointPosition/pp.fun ∧", 1)
    broken = tmp_path / "broken.uml"
    broken.write_text(text, encoding="utf-8")
    return broken


def test_check_reports_errors_in_the_text_format_and_exits_1(tmp_path: Path) -> None:
    result = earl("check", str(_broken_sample(tmp_path)))
    assert result.returncode == 1
    first = result.stdout.splitlines()[0]
    # FILE:LINE[:COL]: CODE severity: message [element path]
    assert first.startswith(f"{tmp_path / 'broken.uml'}:")
    assert ": B005 error: " in first and "newJointPosition/pp" in first
    assert first.endswith("[manip/a.cs.fsm.idle,jointMove/t]")
    assert result.stdout.splitlines()[-1] == "1 file checked: 1 error(s), 0 warning(s), 0 info"


def test_check_json_has_the_documented_keys(tmp_path: Path) -> None:
    result = earl("check", "--format", "json", str(_broken_sample(tmp_path)))
    assert result.returncode == 1
    document = json.loads(result.stdout)
    assert document["summary"] == {"error": 1, "warning": 0, "info": 0}
    (diag,) = document["diagnostics"]
    assert {"code", "severity", "message", "element", "file", "line", "xmi_id"} <= set(diag)
    assert diag["code"] == "B005" and diag["severity"] == "error" and diag["line"] > 0 and diag["xmi_id"]


def test_select_and_ignore_filter_the_findings(tmp_path: Path) -> None:
    broken = str(_broken_sample(tmp_path))
    assert earl("check", "--ignore", "B005", broken).returncode == 0
    assert earl("check", "--select", "S,C", broken).returncode == 0
    assert earl("check", "--select", "B", broken).returncode == 1
    assert earl("check", "--select", "predicate-unknown-reference", broken).returncode == 1
    unknown = earl("check", "--select", "X999", broken)
    assert unknown.returncode == 2 and unknown.stderr.count("\n") == 1 and "X999" in unknown.stderr


@pytest.mark.parametrize("name", sorted(p.name for p in BAD.iterdir()))
def test_unreadable_input_gives_one_line_and_exit_2_without_traceback(name: str) -> None:
    start = time.monotonic()
    result = earl("check", str(BAD / name))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith(str(BAD / name)) and ": error: " in result.stderr
    assert "Traceback" not in result.stderr + result.stdout
    assert time.monotonic() - start < 30


def earl_measured(*args: str) -> tuple[int, str, str, int]:
    """(exit status, stdout, stderr, peak resident KiB) of one earl-m2t process: its own rusage
    (wait4), not the peak of every child the test process ever had (a build before it, say)."""
    process = subprocess.Popen([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    assert process.stdout is not None and process.stderr is not None
    out, err = process.stdout.read(), process.stderr.read()  # a few lines each: no pipe fills
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, out, err, usage.ru_maxrss


def test_entity_attacks_are_refused_without_expanding_anything() -> None:
    for name in ("billion-laughs.uml", "external-entity.uml", "external-dtd.uml"):
        status, out, err, peak_kib = earl_measured("show", str(BAD / name))
        assert status == 2
        assert "not allowed" in err
        assert "root:" not in out + err  # /etc/passwd never read
        assert peak_kib < 500 * 1024  # bounded memory: nothing was expanded


def test_the_parser_itself_refuses_entity_expansion_when_the_prolog_scan_is_bypassed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.read import safe_xml

    monkeypatch.setattr(safe_xml, "refuse_doctype_in_prolog", lambda head, file: None)
    for name in ("billion-laughs.uml", "external-entity.uml"):
        with pytest.raises(ModelReadError):
            safe_xml.parse_xml_bytes((BAD / name).read_bytes(), name)


def test_missing_files_and_directories_are_reported_in_one_line(tmp_path: Path) -> None:
    missing = earl("check", str(tmp_path / "nope.uml"))
    assert missing.returncode == 2 and "no such file" in missing.stderr
    directory = earl("show", str(tmp_path))
    assert directory.returncode == 2 and "directory" in directory.stderr


def test_several_models_are_checked_and_an_unreadable_one_makes_exit_2(tmp_path: Path) -> None:
    result = earl("check", str(SAMPLE), str(BAD / "malformed.uml"))
    assert result.returncode == 2
    assert "1 file checked, 1 could not be read" in result.stdout


def test_show_prints_the_structure_of_the_sample() -> None:
    result = earl("show", str(SAMPLE))
    assert result.returncode == 0
    text = result.stdout
    assert "agent manip/a [ManipulatorAgent] in pickAndPlace/r  type CET, declared CET" in text
    assert "agent task/a [TaskAgent]  type CT, declared CT" in text
    assert "ve motorControllerK/ve ×6 (motorController1/ve … motorController6/ve) [MotorController]" in text
    assert ("jointMove,jointMove/t: jointMove → jointMove if newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun  priority 1"
            in text)
    assert "task/a,manip/a: task/a.cs.manipulatorCommand/ob → manip/a.cs.manipulatorCommand/ib" in text


def test_show_json_is_deterministic_and_complete() -> None:
    first = earl("show", "--format", "json", str(SAMPLE))
    second = earl("show", "--format", "json", str(SAMPLE))
    assert first.returncode == 0 and first.stdout == second.stdout
    document = json.loads(first.stdout)
    (system,) = document["systems"]
    agents = {a["name"]: a for a in system["agents"]}
    assert set(agents) == {"task/a", "manip/a", "grip/a"}
    assert agents["manip/a"]["type"] == "CET" and agents["task/a"]["type"] == "CT"
    cs = next(s for s in agents["manip/a"]["subsystems"] if s["kind"] == "cs")
    assert cs["fsm"]["initial"] == "idle"
    assert [b["name"] for b in cs["behaviours"]] == [
        "idle/bb", "jointMove/bb", "operationalMove/bb", "emergencyStop/bb"]
    assert {link["name"] for link in system["links"]} == {
        "task/a,manip/a", "manip/a,task/a", "task/a,grip/a", "grip/a,task/a"}
    assert any(d["name"] == "ManipulatorCommand" for d in document["datatypes"])


def test_show_says_plainly_when_a_file_holds_no_earl_model() -> None:
    corpus = ROOT.parent / "shared" / "corpus" / "papyrus" / "electric-kettle-sysml16.uml"
    if not corpus.exists():
        pytest.skip("shared corpus not beside the checkout")
    result = earl("show", str(corpus))
    assert result.returncode == 0
    assert "holds no EARL model" in result.stdout
    checked = earl("check", str(corpus))
    assert checked.returncode == 1 and "R003" in checked.stdout


def test_rules_lists_every_rule_and_explains_one() -> None:
    listing = earl("rules")
    assert listing.returncode == 0
    codes = [line.split()[0] for line in listing.stdout.splitlines()]
    assert codes[:3] == ["S001", "S002", "S003"] and "B008" in codes and "D004" in codes
    explained = earl("rules", "B005")
    assert explained.returncode == 0 and explained.stdout.startswith("# B005")
    as_json = json.loads(earl("rules", "--format", "json").stdout)
    assert {r["code"] for r in as_json} == set(codes)
    assert earl("rules", "Z123").returncode == 2


def test_no_command_prints_help_and_exits_2() -> None:
    result = earl()
    assert result.returncode == 2 and "usage" in result.stderr.lower()
