"""SysML v2 text as input: the sample's ``.sysml`` lifts to the Papyrus model, `convert` writes
SysML v2 text that reads back as the same model, and text outside the subset or not parsing
is reported with line and column, never with a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from test_sample_dialects_equal import FILES, SAMPLE_FILES, lifted, without_location

from earl_m2t.api import check, load
from earl_m2t.cli.app import main
from earl_m2t.convert import to_sysml
from earl_m2t.export import model_to_dict

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"


def shown(path: Path) -> dict[str, Any]:
    return without_location(model_to_dict(load(path).model))


@pytest.fixture(scope="module")
def papyrus() -> dict[str, Any]:
    return lifted("papyrus")


def test_the_sysml_sample_lifts_to_the_papyrus_model(papyrus: dict[str, Any]) -> None:
    assert shown(SAMPLE) == papyrus


def test_the_sysml_sample_is_read_as_sysml_v2_and_checks_clean() -> None:
    loaded = load(SAMPLE)
    assert loaded.model.dialect == "sysml-v2" and loaded.model.name == "PickAndPlace"
    assert [str(d) for d in check(SAMPLE)] == []


def test_locations_point_into_the_sysml_text() -> None:
    model = load(SAMPLE).model
    lines = SAMPLE.read_text(encoding="utf-8").splitlines()
    manip = model.agents[0]
    assert lines[manip.location.line - 1].strip().startswith("part 'manip/a' : ManipulatorAgent")
    transition = manip.subsystems[0].fsm.transitions[1]  # type: ignore[union-attr]
    assert lines[transition.location.line - 1].strip().startswith("transition 'jointMove,jointMove/t'")


@pytest.mark.parametrize(("sample", "name"), [(sample, name) for sample, files in SAMPLE_FILES.items()
                                               for name in files if name != "sysml"])
def test_a_converted_sample_reads_back_as_the_same_model(sample: str, name: str, tmp_path: Path) -> None:
    target = tmp_path / "converted.sysml"
    assert main(["convert", str(SAMPLE_FILES[sample][name]), "--to", "sysml", "-o", str(target)]) == 0
    assert shown(target) == lifted("papyrus", sample)
    assert [str(d) for d in check(target)] == []


def test_convert_never_replaces_an_edited_file_unless_forced(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "model.sysml"
    assert main(["convert", str(FILES["papyrus"]), "--to", "sysml", "-o", str(target)]) == 0
    assert main(["convert", str(FILES["papyrus"]), "--to", "sysml", "-o", str(target)]) == 0  # unchanged
    edited = target.read_text(encoding="utf-8") + "// my note\n"
    target.write_text(edited, encoding="utf-8")
    capsys.readouterr()
    assert main(["convert", str(FILES["papyrus"]), "--to", "sysml", "-o", str(target)]) == 1
    assert capsys.readouterr().err == (f"earl-m2t: convert: {target} exists and differs from the conversion; "
                                       "nothing written (--force to replace it)\n")
    assert target.read_text(encoding="utf-8") == edited
    assert main(["convert", str(FILES["papyrus"]), "--to", "sysml", "-o", str(target), "--force"]) == 0
    assert "// my note" not in target.read_text(encoding="utf-8")


def test_converting_the_sysml_sample_gives_back_the_same_model(tmp_path: Path, papyrus: dict[str, Any]) -> None:
    target = tmp_path / "again.sysml"
    target.write_text(to_sysml(load(SAMPLE).model), encoding="utf-8")
    assert shown(target) == papyrus


def test_convert_is_deterministic_and_writes_to_stdout() -> None:
    def run() -> str:
        result = subprocess.run([sys.executable, "-m", "earl_m2t", "convert", str(FILES["papyrus"]), "--to", "sysml"],
                                cwd=ROOT, capture_output=True, text=True, timeout=120)
        assert result.returncode == 0 and result.stderr == ""
        return result.stdout

    first = run()
    assert first == run()
    assert first.startswith("// EARL model PickAndPlace") and "package PickAndPlace {" in first


def test_text_that_does_not_parse_is_one_line_with_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "broken.sysml"
    path.write_text("package P {\n    part def A {\n        part x : B;\n    }\n}\n}\n", encoding="utf-8")
    for command in ("show", "check", "convert"):
        extra = ["--to", "sysml"] if command == "convert" else []
        result = subprocess.run([sys.executable, "-m", "earl_m2t", command, str(path), *extra],
                                cwd=ROOT, capture_output=True, text=True, timeout=120)
        assert result.returncode == 2, result.stderr
        assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
        assert result.stderr.startswith(f"{path}:6:1: error: syntax error at '}}'"), result.stderr


def test_each_construct_outside_the_subset_is_one_warning_with_its_column(tmp_path: Path) -> None:
    path = tmp_path / "outside.sysml"
    path.write_text(
        "package P {\n"
        "    requirement def R { doc /* r */ }\n"
        "    part def A {\n"
        "        perform act.step { in x = 1; }\n"
        "        exit act;\n"
        "        part b : B;\n"
        "    }\n"
        "    part def B;\n"
        "}\n",
        encoding="utf-8",
    )
    loaded = load(path)
    found = [(d.code, d.location.line, d.location.column, d.element) for d in loaded.diagnostics]
    assert found == [("R007", 2, 5, "requirement def"), ("R007", 4, 9, "perform"), ("R007", 5, 9, "exit")]
    assert "construct 'perform' is outside the EARL SysML v2 subset" in loaded.diagnostics[1].message


def test_a_construct_of_the_subset_in_a_form_it_does_not_read_is_named_as_such(tmp_path: Path) -> None:
    path = tmp_path / "malformed.sysml"
    path.write_text("package P {\n    part def A {\n        part b : ;\n        part c : A;\n    }\n}\n",
                    encoding="utf-8")
    loaded = load(path)
    assert [(d.code, d.location.line, d.location.column, d.element) for d in loaded.diagnostics] == [
        ("R007", 3, 9, "part")]
    assert loaded.diagnostics[0].message.startswith("this 'part' is not in a form the EARL SysML v2 subset reads")


def test_the_documented_example_is_read_as_written(tmp_path: Path) -> None:
    """The small agent of docs/sysml-v2.md (*At a glance*), placed in a system, lifts with its
    buffer, FSM and stage."""
    page = (ROOT / "docs" / "sysml-v2.md").read_text(encoding="utf-8")
    section = page[page.index("## At a glance"):]
    start = section.index("```sysml\n") + len("```sysml\n")
    example = section[start:section.index("```\n", start)]
    path = tmp_path / "heater.sysml"
    path.write_text(
        "package Example {\n    private import ScalarValues::*;\n    private import EARL::Model::*;\n"
        "    package DataTypes { attribute def Power { attribute watts : Real; } }\n"
        "    part def Home :> System { part 'heating/r' : Heating; }\n"
        "    part def Heating :> Robot { part 'heater/a' : HeaterAgent; }\n"
        "    part def HeaterAgent :> Agent { part cs : HeaterControl; part 'heater/re' : Heater; }\n"
        "    part def HeaterControl :> ControlSubsystem;\n"
        f"{example}}}\n", encoding="utf-8")
    loaded = load(path)
    assert [d.code for d in loaded.diagnostics] == []
    heater = loaded.model.agents[0].subsystems[1]
    assert (heater.name, heater.kind, heater.block) == ("heater/re", "re", "Heater")
    assert [(b.name, b.datatype) for b in heater.inputs] == [("power/ib", "DataTypes::Power")]
    assert heater.fsm is not None and heater.fsm.initial == "heat"
    assert [b.stages for b in heater.behaviours] == [(("heat/pf",),)]


def test_converting_converted_text_gives_the_same_text(tmp_path: Path) -> None:
    once = to_sysml(load(FILES["papyrus"]).model)
    path = tmp_path / "once.sysml"
    path.write_text(once, encoding="utf-8")
    assert to_sysml(load(path).model) == once


def test_the_sysml_sample_generates_the_same_cpp_project_as_the_papyrus_one(tmp_path: Path) -> None:
    trees = {}
    for name, model in (("uml", FILES["papyrus"]), ("sysml", SAMPLE)):
        out = tmp_path / name
        assert main(["gen", str(model), "--target", "cpp", "-o", str(out)]) == 0
        # the source map differs: it names the model file and the lines of its elements
        trees[name] = {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*"))
                       if p.is_file() and p.name != ".earl-trace.json"}
    assert trees["uml"] and trees["sysml"] == trees["uml"]


def test_the_metadata_definitions_of_the_profile_apply_their_stereotypes() -> None:
    """SysML v2 types metadata by metadata definitions: EARL::Model declares one for each
    stereotype that models apply as metadata, and the reader knows which stereotype each one
    applies; `Priority` carries the tag of «FsmTransition»."""
    from earl_m2t.profile import load_profile
    from earl_m2t.sysml2.parser import identification, members, parse_file, rule
    from earl_m2t.sysml2.scope import METADATA_CONCEPTS

    (earl,) = members(parse_file(ROOT / "profiles" / "earl.sysml"))
    (model,) = [m for m in members(earl) if rule(m) == "Package" and identification(m)[1] == "Model"]
    declared = {identification(d)[1]: d for d in members(model) if rule(d) == "Definition" and d.kind == "metadata"}
    assert set(declared) == set(METADATA_CONCEPTS)
    profile = load_profile()
    assert all(concept in profile.concepts for concept in METADATA_CONCEPTS.values())
    priority = [identification(f)[1] for f in members(declared["Priority"]) if rule(f) == "Usage"]
    assert priority == [t.name for t in profile.tags("FsmTransition")] == ["priority"]


def test_priorities_and_exclusions_typed_by_the_concepts_still_read(tmp_path: Path, papyrus: dict[str, Any]) -> None:
    """`@FsmTransition { priority = 1; }` and `metadata x : Exclusion about …`, as earlier
    versions wrote them, apply the same stereotypes as `@Priority` and `Exclusive`."""
    text = SAMPLE.read_text(encoding="utf-8")
    assert "@Priority {" in text and ": Exclusive about" in text
    path = tmp_path / "earlier.sysml"
    path.write_text(text.replace("@Priority {", "@FsmTransition {").replace(": Exclusive about", ": Exclusion about"),
                    encoding="utf-8")
    assert shown(path) == papyrus
