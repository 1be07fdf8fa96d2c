"""The verification rules (V001-V005) with the real SPIN: a broken variant of the SysML v2 sample
per rule, the sample itself as the clean case, and the properties the sample must satisfy."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from earl_m2t.cli.app import main

ROOT = Path(__file__).resolve().parents[2]
SAMPLE_SYSML = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"
SAMPLE_UML = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
ESTOP = "[] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop)"

EXCLUSIVE = "'newJointPos/pp'() and 'newOperationalPos/pp'()"

# rule → (replacements in the sample, the element the finding names, a text of its message)
VARIANTS: dict[str, tuple[list[tuple[str, str]], str, str]] = {
    "V001": ([("first idle if 'newOperationalPos/pp'() and not 'emergencyStop/pp'()",
               f"first idle if {EXCLUSIVE}")],
             "manip/a.cs.fsm.operationalMove", "never entered"),
    "V002": ([("firstTimeout = 0.1; nextTimeout = 0.02; ", ""),
              ("connect 'task/a'.cs.'manipulatorCommand/ob' to "
               "'pickAndPlace/r'.'manip/a'.cs.'manipulatorCommand/ib';", "")],
             "manip/a.cs", "waits for manipulatorCommand/ib"),
    "V003": ([("constraint tc { 'motionFinished/pp'() or 'emergencyStop/pp'() }\n"
               "                        constraint ec { not behaviourOk() }",
               f"constraint tc {{ {EXCLUSIVE} }}\n                        constraint ec {{ false }}")],
             "manip/a.cs.jointMove/bb", "never ends"),
    "V004": ([("first jointMove if not 'emergencyStop/pp'() then idle", "first jointMove if 'false/pp'() then idle"),
              ("first jointMove if 'emergencyStop/pp'() or inError()\n", "first jointMove if 'false/pp'()\n")],
             "manip/a.cs.fsm.jointMove", "no way out"),
}


def _verify(path: Path, capsys: pytest.CaptureFixture[str], *extra: str) -> tuple[int, dict]:
    """verify's JSON; with --force, as a mutant may also break a rule of check (V002's does)."""
    code = main(["verify", str(path), "--format", "json", "--force", *extra])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("rule", sorted(VARIANTS))
def test_variant_triggers_its_verification_rule(rule: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    replacements, element, text = VARIANTS[rule]
    source = SAMPLE_SYSML.read_text(encoding="utf-8")
    for old, new in replacements:
        assert old in source, f"{rule}: the sample no longer has {old!r}"
        source = source.replace(old, new)
    path = tmp_path / "variant.sysml"
    path.write_text(source, encoding="utf-8")

    code, result = _verify(path, capsys)

    assert code == 1
    codes = {f["code"] for f in result["findings"]}
    assert rule in codes, result["findings"]
    finding = next(f for f in result["findings"] if f["code"] == rule)
    assert finding["element"].startswith(element) and text in finding["message"], finding


@pytest.mark.parametrize("sample", [SAMPLE_UML, SAMPLE_SYSML], ids=["papyrus", "sysml"])
def test_sample_is_clean_and_keeps_its_emergency_stop(sample: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, result = _verify(sample, capsys, "--ltl", ESTOP)

    assert result["findings"] == []
    assert code == 0 and result["not_proven"] == []
    assert f"{ESTOP} holds" in result["proven"]
    assert any(line.startswith("no deadlock") for line in result["proven"])
    assert result["explored"]["states"] > 0


def test_a_violated_property_has_a_model_level_counterexample(capsys: pytest.CaptureFixture[str]) -> None:
    code, result = _verify(SAMPLE_UML, capsys, "--ltl", "[] (manip/a.cs@jointMove -> [] manip/a.cs@jointMove)")

    assert code == 1
    (finding,) = result["findings"]
    assert finding["code"] == "V005"
    steps = [(s["subsystem"], s["from"], s["to"]) for s in finding["trace"]]
    assert ("manip/a.cs", "idle", "jointMove") in steps
    left = steps.index(("manip/a.cs", "idle", "jointMove"))
    assert any(sub == "manip/a.cs" and frm == "jointMove" and to != "jointMove" for sub, frm, to in steps[left:])
    entering = finding["trace"][left]
    assert entering["values"]["newJointPos"] is True and entering["values"]["emergencyStop"] is False


def test_deadlock_without_timeouts_needs_the_missing_writer(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Without timeouts manip/a.cs waits for each command: task/a sends one every iteration, so no deadlock."""
    path = tmp_path / "no_timeouts.sysml"
    path.write_text(SAMPLE_SYSML.read_text(encoding="utf-8").replace("firstTimeout = 0.1; nextTimeout = 0.02; ", ""),
                    encoding="utf-8")
    code, result = _verify(path, capsys)
    assert code == 0, result
    assert "no deadlock: no reachable state has a subsystem waiting for an input nobody sends" in result["proven"]


def test_a_bound_says_not_proven(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["verify", str(SAMPLE_UML), "--depth", "2", "--ltl", ESTOP])
    out = capsys.readouterr().out
    assert code == 3
    assert "not proven: " in out and " holds" not in out


def test_a_property_error_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["verify", str(SAMPLE_UML), "--ltl", "[] (manip/a.cs@nowhere)"])
    err = capsys.readouterr().err
    assert code == 2
    assert err.strip() == "earl-m2t: verify: --ltl:1:5: no state nowhere of a subsystem manip/a.cs"


WRITTEN = "earl-m2t: ltl estopLatches: " + ESTOP
BROKEN = "earl-m2t: ltl stayIdle: [] (manip/a.cs@idle -> [] manip/a.cs@idle)"


def _with_comment(sample: Path, tmp_path: Path, body: str) -> Path:
    """The sample with a comment holding ``body`` on its system block, as each tool writes one."""
    encoding = "cp1252" if ".ea." in sample.name else "utf-8"  # Enterprise Architect writes windows-1252
    text = sample.read_text(encoding=encoding)
    escaped = body.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    if sample.suffix == ".sysml":
        anchor = "part def PickAndPlaceSystem :> System {"
        new = f"{anchor}\n            comment /* {body} */"
    elif "cameo" in sample.name:
        anchor = "name='PickAndPlaceSystem'>"
        new = f"{anchor}\n<ownedComment xmi:type='uml:Comment' xmi:id='_ltl_note' body='{escaped}'/>"
    elif ".ea." in sample.name:
        anchor = 'name="PickAndPlaceSystem" visibility="public">'
        new = f'{anchor}\n<ownedComment xmi:type="uml:Comment" xmi:id="EAID_LTL_NOTE" body="{escaped}"/>'
    else:
        anchor = 'name="PickAndPlaceSystem">'
        new = f'{anchor}\n<ownedComment xmi:type="uml:Comment" xmi:id="_ltl_note"><body>{escaped}</body></ownedComment>'
    assert text.count(anchor) == 1, sample
    path = tmp_path / sample.name
    path.write_text(text.replace(anchor, new), encoding=encoding)
    return path


SAMPLES = {
    "papyrus": SAMPLE_UML,
    "cameo": ROOT / "samples" / "pick_and_place" / "pick_and_place.cameo.xmi",
    "ea": ROOT / "samples" / "pick_and_place" / "pick_and_place.ea.xml",
    "sysml": SAMPLE_SYSML,
}


@pytest.mark.parametrize("dialect", sorted(SAMPLES))
def test_a_property_written_in_the_model_is_proven(dialect: str, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    path = _with_comment(SAMPLES[dialect], tmp_path, WRITTEN)
    code, result = _verify(path, capsys)
    assert code == 0, result
    assert f"{ESTOP} holds" in result["proven"]


@pytest.mark.parametrize("dialect", ["papyrus", "sysml"])
def test_a_violated_property_in_the_model_points_at_its_comment(dialect: str, tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    path = _with_comment(SAMPLES[dialect], tmp_path, BROKEN)
    code, result = _verify(path, capsys)
    assert code == 1
    (finding,) = result["findings"]
    assert finding["code"] == "V005" and finding["element"] == "stayIdle"
    assert finding["file"] == str(path) and finding["line"] > 0
    assert "stayIdle" in path.read_text(encoding="utf-8").splitlines()[finding["line"] - 1]


def test_a_syntax_error_in_the_model_is_one_line_with_file_line_and_column(tmp_path: Path,
                                                                           capsys: pytest.CaptureFixture[str]) -> None:
    path = _with_comment(SAMPLE_SYSML, tmp_path, "earl-m2t: ltl typo: [] (manip/a.cs@idle => x)")
    code = main(["verify", str(path)])
    err = capsys.readouterr().err.strip()
    assert code == 2
    line = next(i for i, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1) if "ltl typo" in text)
    assert err.startswith(f"earl-m2t: verify: {path}:{line}:") and "unexpected '=>" in err, err
    assert len(err.splitlines()) == 1


def test_a_removed_transition_leaves_its_target_unreachable(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """task/a.cs without its transition supervise → abort: abort is never entered (V001), and supervise,
    whose behaviour still ends when taskAborted holds, has no way out (V004)."""
    source = SAMPLE_SYSML.read_text(encoding="utf-8")
    start = source.index("transition 'supervise,abort/t'")
    end = source.index("}", start) + 1
    path = tmp_path / "no_abort.sysml"
    path.write_text(source[:start] + source[end:], encoding="utf-8")
    code, result = _verify(path, capsys)
    assert code == 1
    assert sorted((f["code"], f["element"]) for f in result["findings"]) == [
        ("V001", "task/a.cs.fsm.abort"), ("V004", "task/a.cs.fsm.supervise")]


def test_sarif_carries_the_counterexample_as_a_code_flow(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["verify", str(SAMPLE_UML), "--format", "sarif", "--ltl",
                 "[] (manip/a.cs@jointMove -> [] manip/a.cs@jointMove)"])
    sarif = json.loads(capsys.readouterr().out)
    assert code == 1 and sarif["version"] == "2.1.0"
    (result,) = sarif["runs"][0]["results"]
    assert result["ruleId"] == "V005"
    steps = [loc["location"]["message"]["text"] for loc in result["codeFlows"][0]["threadFlows"][0]["locations"]]
    assert any("manip/a.cs: idle → jointMove" in step for step in steps)


def test_the_output_is_the_same_from_run_to_run(capsys: pytest.CaptureFixture[str]) -> None:
    runs = []
    for _ in range(2):
        main(["verify", str(SAMPLE_UML), "--ltl", "[] (manip/a.cs@jointMove -> [] manip/a.cs@jointMove)"])
        runs.append(capsys.readouterr().out)
    assert runs[0] == runs[1] and "counterexample:" in runs[0]
