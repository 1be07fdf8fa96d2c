"""Variable structure in the lifted model and everything that reads it without generating code:
the lift of configurations, coordinator states, quiescent states, reactivation and [0..1] parts;
`leaving()`; `show` (text and JSON); `convert` round trip; `diff`; the diagrams and the
specification (real Graphviz renders the diagrams)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.kinds import Reactivation
from earl_m2t.model.variability import coordinator, present, variable_agents, variable_links
from earl_m2t.predicate import BuiltIn, BuiltInPredicate, walk
from tests.support.paths import ROOT

FIXTURE = ROOT / "tests" / "fixtures" / "variability" / "handover.sysml"


def earl_m2t(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=300)


@pytest.fixture(scope="module")
def model() -> EarlModel:
    return load(FIXTURE).model


def test_configurations_resolve_their_agents_and_links(model: EarlModel) -> None:
    system = model.system
    assert system is not None
    use_a, use_b = system.configurations
    assert (use_a.name, use_a.path, use_a.agents, use_a.links) == (
        "useA", "Cell.useA", ("manipA/a",), ("task/a,manipA/a", "manipA/a,task/a"))
    assert use_b.agents == ("manipB/a",) and use_b.switch_timeout == 0.05
    assert use_a.unknown == () and use_a.location.line == 29
    assert variable_agents(system) == {"manipA/a", "manipB/a"}
    assert len(variable_links(system)) == 4


def test_the_structure_of_a_configuration_is_the_always_present_part_and_its_own(model: EarlModel) -> None:
    system = model.system
    assert system is not None
    structure = present(system, system.configurations[1])
    assert structure.agents == {"task/a", "manipB/a"}
    assert structure.links == {"task/a,manipB/a", "manipB/a,task/a"}


def test_agents_states_and_the_coordinator(model: EarlModel) -> None:
    agents = {a.path: a for a in model.agents}
    assert agents["manipA/a"].optional and agents["manipA/a"].reactivation == Reactivation.RESUME
    assert not agents["task/a"].optional and agents["task/a"].reactivation == Reactivation.RESTART
    switching = coordinator(model)
    assert switching is not None and switching.path == "task/a.cs"
    assert switching.fsm is not None
    assert [(s.name, s.configuration) for s in switching.fsm.states] == [("withA", "useA"), ("withB", "useB")]
    manipulator = model.subsystem("manipA/a.cs")
    assert manipulator is not None and manipulator.fsm is not None
    assert [(s.name, s.quiescent) for s in manipulator.fsm.states] == [("idle", True), ("moving", False)]


def test_leaving_is_a_built_in_predicate_of_the_lifted_conditions(model: EarlModel) -> None:
    manipulator = model.subsystem("manipA/a.cs")
    assert manipulator is not None
    built_ins = [node for condition in manipulator.conditions() if condition.expr is not None
                 for node in walk(condition.expr) if isinstance(node, BuiltIn)]
    assert built_ins and {node.name for node in built_ins} == {BuiltInPredicate.LEAVING}
    assert all(not condition.problems for condition in manipulator.conditions())


def test_leaving_written_as_a_sysml_v2_expression_is_the_built_in(tmp_path: Path) -> None:
    text = FIXTURE.read_text(encoding="utf-8").replace(
        'constraint tc { language "EARL" /* leaving() or not newCommand/pp */ }',
        "constraint tc { leaving() or not 'newCommand/pp'() }")
    changed = tmp_path / "handover.sysml"
    changed.write_text(text, encoding="utf-8")
    manipulator = load(changed).model.subsystem("manipA/a.cs")
    assert manipulator is not None
    moving = manipulator.behaviour("moving/bb")
    assert moving is not None and moving.tc is not None and not moving.tc.problems
    assert any(isinstance(node, BuiltIn) for node in walk(moving.tc.expr))


def test_a_name_a_configuration_cannot_resolve_is_kept_as_written(tmp_path: Path) -> None:
    text = FIXTURE.read_text(encoding="utf-8").replace('agents = "manipA/a";', 'agents = "manipA/a manipC/a";')
    text = text.replace('links = "task/a,manipA/a manipA/a,task/a";', 'links = "task/a,manipA/a task/a,nobody/a";')
    changed = tmp_path / "handover.sysml"
    changed.write_text(text, encoding="utf-8")
    system = load(changed).model.system
    assert system is not None
    use_a = system.configurations[0]
    assert (use_a.agents, use_a.unknown_agents) == (("manipA/a",), ("manipC/a",))
    assert (use_a.links, use_a.unknown_links) == (("task/a,manipA/a",), ("task/a,nobody/a",))


def test_show_prints_configurations_and_the_variable_elements() -> None:
    result = earl_m2t("show", str(FIXTURE.relative_to(ROOT)))
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert "  agent manipA/a [ManipulatorAgent] in cell/r  type CT  optional, reactivation resume" in lines
    assert "  configurations" in lines
    assert ("    useA: agents manipA/a  links task/a,manipA/a manipA/a,task/a  switch timeout 0.05 s"
            in lines)
    assert any(line.strip().startswith("state withA → withA/bb") and line.endswith("(configuration useA)")
               for line in lines)
    assert any(line.strip().startswith("state idle → idle/bb") and line.endswith("(quiescent)") for line in lines)


def test_show_json_carries_them() -> None:
    result = earl_m2t("show", "--format", "json", str(FIXTURE.relative_to(ROOT)))
    assert result.returncode == 0, result.stderr
    system = json.loads(result.stdout)["systems"][0]
    assert [c["name"] for c in system["configurations"]] == ["useA", "useB"]
    assert system["configurations"][0]["links"] == ["task/a,manipA/a", "manipA/a,task/a"]
    agents = {a["path"]: a for a in system["agents"]}
    assert (agents["manipB/a"]["optional"], agents["manipB/a"]["reactivation"]) == (True, "resume")
    assert "optional" not in agents["task/a"]  # a fixed-structure agent's JSON is as it was
    states = agents["task/a"]["subsystems"][0]["fsm"]["states"]
    assert [s.get("configuration") for s in states] == ["useA", "useB"]


def _without_places(document: object) -> object:
    """The JSON of `show` without where the elements were written (file, line, id)."""
    if isinstance(document, dict):
        return {k: _without_places(v) for k, v in document.items() if k not in ("file", "line", "xmi_id")}
    if isinstance(document, list):
        return [_without_places(v) for v in document]
    return document


def test_convert_and_read_back_gives_the_same_model(tmp_path: Path) -> None:
    converted = tmp_path / "converted.sysml"
    result = earl_m2t("convert", "--to", "sysml", str(FIXTURE), "-o", str(converted))
    assert result.returncode == 0, result.stderr
    text = converted.read_text(encoding="utf-8")
    assert "metadata useA : Structure" in text and "@Quiescent;" in text and "@Reconfigure" in text
    shown = [json.loads(earl_m2t("show", "--format", "json", str(path)).stdout) for path in (FIXTURE, converted)]
    assert _without_places(shown[0]) == _without_places(shown[1])


def test_diff_reports_a_changed_configuration(tmp_path: Path) -> None:
    changed = tmp_path / "handover.sysml"
    changed.write_text(FIXTURE.read_text(encoding="utf-8").replace(
        'links = "task/a,manipB/a manipB/a,task/a"; switchTimeout = 0.05;',
        'links = "task/a,manipB/a"; switchTimeout = 0.1;'), encoding="utf-8")
    result = earl_m2t("diff", str(FIXTURE), str(changed))
    assert result.returncode == 1, result.stderr
    assert "changed  configuration Cell.useB" in result.stdout
    assert "switch timeout: 0.05 → 0.1" in result.stdout


def test_diagrams_draw_each_configuration_and_mark_what_varies(tmp_path: Path) -> None:
    result = earl_m2t("gen", str(FIXTURE), "--target", "diagrams", "-o", str(tmp_path))
    assert result.returncode == 0, result.stderr
    general = (tmp_path / "system.dot").read_text(encoding="utf-8")
    assert general.count("style=dashed") == 4 and general.count('style="rounded,filled,dashed"') == 2
    use_a = (tmp_path / "system-Cell-useA.dot").read_text(encoding="utf-8")
    assert "manipA/a" in use_a and "manipB/a" not in use_a and use_a.count("->") == 2
    assert (tmp_path / "system-Cell-useA.svg").stat().st_size > 0  # rendered by Graphviz
    fsm = (tmp_path / "fsm-manipA-a-cs.dot").read_text(encoding="utf-8")
    assert "peripheries=2" in fsm and "quiescent" in fsm


def test_the_specification_lists_the_configurations(tmp_path: Path) -> None:
    result = earl_m2t("gen", str(FIXTURE), "--target", "markdown", "-o", str(tmp_path))
    assert result.returncode == 0, result.stderr
    (spec,) = tmp_path.glob("*.md")
    text = spec.read_text(encoding="utf-8")
    assert "### Configurations" in text and "withA → useA, withB → useB" in text
    assert "Quiescent states (a switch may stop the agent while one is current): idle." in text


def test_the_orocos_target_runs_the_switch_and_notes_what_fabric_cannot(tmp_path: Path) -> None:
    """gen --target orocos writes the switch's ports, connections and per-instance properties
    (tests/test_orocos_switch_runs.py runs them), and says in one note that FABRIC's own
    runtime cannot switch."""
    result = earl_m2t("gen", str(FIXTURE), "--target", "orocos", "-o", str(tmp_path))
    assert result.returncode == 0, result.stderr
    notes = [line for line in result.stdout.splitlines() if line.startswith("note: ")]
    assert notes == [line for line in notes if "FABRIC" in line] and len(
        [n for n in notes if "cannot switch configurations" in n]) == 1
    system = (tmp_path / "deploy" / "system.ops").read_text(encoding="utf-8")
    masters = [line for line in system.splitlines() if line.startswith("loadComponent(")]
    controls = [line for line in system.splitlines() if line.startswith("connect(") and "earl_switch" in line]
    assert len(masters) == 3 and len(controls) == 2 * (len(masters) - 1)
    links = [line for line in system.splitlines() if line.startswith("connect(") and "earl_switch" not in line]
    assert len(links) == len(load(FIXTURE).model.links)
    assert all("__" in line for line in links)  # every link of the fixture is variable: its own ports
    coordinator_script = (tmp_path / "deploy" / "task_a_cs.ops").read_text(encoding="utf-8")
    assert "task_a_cs.earl_coordinator = true" in coordinator_script
    sources = "".join(p.read_text(encoding="utf-8") for p in tmp_path.glob("orocos/*/*/components.cpp"))
    assert sources.count("earl::SwitchCoordinator<") == 1 and "earl::SwitchMember<" in sources
