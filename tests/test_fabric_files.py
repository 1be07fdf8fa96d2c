"""FABRIC's own code reads what gen --target orocos writes: FABRIC's parser accepts every
spec/subsystem.xml, FABRIC's logicExprToCpp turns every condition into C++ that g++ compiles
against the predicate struct, and every config/*.xml holds only what the deployer's runXmls()
reads, with connections between components that exist (tests/support/fabric.py)."""

from __future__ import annotations

import itertools
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import render
from tests.support import fabric

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
FIXTURES = ROOT / "tests" / "fixtures"


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("fabric")
    for name, content in render(load(SAMPLE).model, "orocos").generated.items():
        if name.startswith("fabric/"):
            (folder / name).parent.mkdir(parents=True, exist_ok=True)
            (folder / name).write_bytes(content)
    return folder / "fabric"


def specs(folder: Path) -> list[Path]:
    return sorted(folder.glob("*/spec/subsystem.xml"))


def test_a_package_per_definition_with_a_configuration_per_instance(generated: Path) -> None:
    model = load(SAMPLE).model
    assert len(specs(generated)) == len(list(model.definitions())) == 7
    assert len(list(generated.glob("*/config/*.xml"))) == len(model.subsystems) == 17
    assert sorted(p.name for p in (generated / "manip_a_motorControllerK_ve" / "config").iterdir()) == [
        f"manip_a_motorController{k}_ve.xml" for k in range(1, 7)]


def test_fabrics_parser_accepts_every_generated_spec(generated: Path) -> None:
    for path in specs(generated):
        sd = fabric.parse_spec(path)
        assert sd.states and sd.buffer_groups and sd.buffers_in, path
    manip = fabric.parse_spec(generated / "manip_a_cs" / "spec" / "subsystem.xml")
    assert manip.initial_state_name == "idle"
    assert manip.predicates == ["emergencyStop", "motionFinished", "newJointPos", "newOperationalPos", "false_pp"]
    joint_move = next(s for s in manip.states if s.name == "jointMove")
    # highest priority first: emergencyStop (2), the self-transition (1), idle (0)
    # (FABRIC takes the first guard that holds: each one excludes those of higher priority)
    assert joint_move.next_states == [
        ("emergencyStop", "emergencyStop or IN_ERROR"),
        ("jointMove", "newJointPos and not emergencyStop and not (emergencyStop or IN_ERROR)"),
        ("idle", "not emergencyStop and not (emergencyStop or IN_ERROR) and not (newJointPos and not emergencyStop)")]
    # the sample's activation: each command of task/a activates an iteration of manip/a.cs
    assert [(g.name, g.obligatory, g.optional) for g in manip.buffer_groups] == [
        ("commands", ["manipulatorCommand"], [f"motorControllerState{k}" for k in range(1, 7)])]
    assert {(s.buffer_group_name, s.buffer_group_min_period, s.buffer_group_first_timeout,
             s.buffer_group_next_timeout, s.buffer_group_used_time) for s in manip.states} == {
        ("commands", 0.0005, 0.1, 0.02, "real")}
    # a subsystem without groups: one group reading every input when present, at the model's period
    task = fabric.parse_spec(generated / "task_a_cs" / "spec" / "subsystem.xml")
    assert [(g.name, g.obligatory, g.optional) for g in task.buffer_groups] == [
        ("inputs", [], ["manipulatorState", "gripperStatus"])]
    assert {(s.buffer_group_name, s.buffer_group_min_period, s.buffer_group_first_timeout) for s in task.states} == {
        ("inputs", 0.01, 0.01)}
    idle = next(b for b in manip.behaviors if b.name == "idle")
    assert idle.stop_cond == "newJointPos or newOperationalPos or emergencyStop"
    assert idle.running_components == ["calculatePosition", "passiveRegulation", "outputManipState",
                                       "outputMotorCon"]


def test_every_condition_becomes_cpp_that_compiles(generated: Path, tmp_path: Path) -> None:
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")
    total = 0
    for n, path in enumerate(specs(generated)):
        sd = fabric.parse_spec(path)
        total += len(fabric.conditions(sd))
        work = tmp_path / str(n)
        work.mkdir()
        result = fabric.compile_conditions(sd, work)
        assert result.returncode == 0, (path, result.stderr)
    assert total == 2 * 11 + 10  # stop and err of 11 behaviours, 10 transitions


def test_a_condition_fabric_cannot_translate_does_not_compile(tmp_path: Path) -> None:
    """The compile check can fail: logicExprToCpp replaces a predicate named ``d`` inside ``and``
    (the generator never names a predicate after a part of and/or/not)."""
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")

    class Spec:
        predicates = ["d", "ready"]
        behaviors: list[object] = []
        states = [type("S", (), {"name": "a", "next_states": [("b", "ready and d")]})()]

    assert fabric.compile_conditions(Spec(), tmp_path).returncode != 0


def test_every_configuration_holds_what_the_deployer_reads(generated: Path) -> None:
    for config in sorted(generated.glob("*/config/*.xml")):
        spec = fabric.parse_spec(config.parent.parent / "spec" / "subsystem.xml")
        assert fabric.configuration_problems(config, spec) == [], config
    manip = ElementTree.parse(generated / "manip_a_cs" / "config" / "manip_a_cs.xml").getroot()
    channels = {b.get("alias"): b.get("name") for b in manip.iter("io_buffer")}
    # a linked input reads the channel its writer's output writes
    assert channels["manipulatorCommand"] == "task_a_cs_manipulatorCommand"
    task = ElementTree.parse(generated / "task_a_cs" / "config" / "task_a_cs.xml").getroot()
    assert {b.get("alias"): b.get("name") for b in task.iter("io_buffer")}["manipulatorCommand"] == channels[
        "manipulatorCommand"]
    running = {r.get("name") for r in ElementTree.parse(generated / "manip_a_cs" / "spec" / "subsystem.xml")
               .getroot().iter("running_component")}
    assert running == {c.get("name") for c in manip.iter("component")}


def test_the_real_configurations_pass_the_same_check() -> None:
    configs = sorted(fabric.EXAMPLES.glob("**/config/*.xml"))
    assert len(configs) == 3
    for config in configs:
        spec = fabric.parse_spec(config.parent.parent / "spec" / "subsystem.xml")
        assert fabric.configuration_problems(config, spec) == [], config


@pytest.mark.parametrize(("old", "new", "problem"), [
    ('<conn_policy type="data"/>', '<conn_policy type="data" size="4"/>', "conn_policy data with a size"),
    ('<conn_policy type="data"/>', '<conn_policy type="buffer"/>', "conn_policy buffer without a positive size"),
    ('<io_buffer alias="manipulatorCommand" ', '<io_buffer alias="command" ', "io_buffer aliases not in the spec"),
    ('to="calculatePosition.', 'to="calculatePositionX.', "names no component"),
    ('<component name="jointMove" type=', '<component name="jointMove" kind=', "<component> without type"),
])
def test_a_broken_configuration_is_found(generated: Path, tmp_path: Path, old: str, new: str, problem: str) -> None:
    config = generated / "manip_a_cs" / "config" / "manip_a_cs.xml"
    spec = fabric.parse_spec(generated / "manip_a_cs" / "spec" / "subsystem.xml")
    text = config.read_text(encoding="utf-8")
    assert old in text
    broken = tmp_path / "broken.xml"
    broken.write_text(text.replace(old, new, 1), encoding="utf-8")
    assert any(problem in p for p in fabric.configuration_problems(broken, spec))


def _evaluate(cpp: str, values: dict[str, bool]) -> bool:
    """The C++ logicExprToCpp made (``p->a && !(p->b || false)``), evaluated for ``values``."""
    python = re.sub(r"p->(\w+)", lambda m: str(values[m.group(1)]), cpp)
    python = python.replace("&&", " and ").replace("||", " or ").replace("!", " not ")
    python = python.replace("true", "True").replace("false", "False")
    assert re.fullmatch(r"[\sA-Za-z()]*", python), python
    result: bool = eval(python)  # noqa: S307 - only True/False/and/or/not/parentheses, checked above
    return result


def test_fabric_chooses_the_next_state_the_model_chooses(generated: Path) -> None:
    """FABRIC refuses to choose when two next states' conditions hold; EARL takes the transition
    of highest priority. The conditions exclude those of higher priority, so for every value of
    the predicates at most one holds, and it is the one of highest priority whose own guard holds."""
    to_cpp = fabric.logic_expr_to_cpp()
    sd = fabric.parse_spec(generated / "manip_a_cs" / "spec" / "subsystem.xml")
    joint_move = next(s for s in sd.states if s.name == "jointMove")
    own = {"emergencyStop": "emergencyStop", "jointMove": "newJointPos and not emergencyStop",
           "idle": "not emergencyStop"}  # the model's guards, highest priority first
    for bits in itertools.product((False, True), repeat=len(sd.predicates)):
        values = dict(zip(sd.predicates, bits), IN_ERROR=False, CURRENT_BEHAVIOR_OK=False)
        for state in sd.states:
            holding = [name for name, cond in state.next_states if _evaluate(to_cpp(cond, sd.predicates), values)]
            assert len(holding) <= 1, (state.name, values, holding)
        chosen = [name for name, cond in joint_move.next_states if _evaluate(to_cpp(cond, sd.predicates), values)]
        expected = [name for name, cond in own.items() if _evaluate(to_cpp(cond, sd.predicates), values)][:1]
        assert chosen == expected, values


THERMOSTAT = FIXTURES / "sysml2" / "thermostat.sysml"


def test_a_subsystem_without_inputs_gets_no_package_and_a_note(tmp_path: Path) -> None:
    """The thermostat's control subsystem has no Input Buffer, so no buffer group FABRIC accepts:
    gen writes the other packages and says which one it could not write."""
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(THERMOSTAT), "--target", "orocos", "-o",
                             str(tmp_path)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert ("note: no FABRIC package for thermostat/a.cs: a FABRIC subsystem needs an Input Buffer in a buffer "
            "group, it has none") in result.stdout.splitlines()
    assert sorted(p.name for p in (tmp_path / "fabric").iterdir()) == ["thermostat_a_heaterDriver_ve",
                                                                        "thermostat_a_heater_re"]
    assert (tmp_path / "orocos" / "thermostat_a" / "cs" / "components.cpp").is_file()
    for path in specs(tmp_path / "fabric"):
        fabric.parse_spec(path)


def test_terms_that_are_not_predicates_become_fabric_predicates(tmp_path: Path) -> None:
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")
    text = THERMOSTAT.read_text(encoding="utf-8").replace(
        "then action drive : 'drive/pf'; then done; }",
        "then action drive : 'drive/pf'; then done; "
        "constraint tc { language \"EARL\" /* newData(command/ib) ∧ ¬command/ib.msg.on */ } }")
    assert "newData(command/ib)" in text
    model_file = tmp_path / "thermostat.sysml"
    model_file.write_text(text, encoding="utf-8")
    files = render(load(model_file).model, "orocos").generated
    spec = tmp_path / "subsystem.xml"
    spec.write_bytes(files["fabric/thermostat_a_heaterDriver_ve/spec/subsystem.xml"])
    sd = fabric.parse_spec(spec)
    assert sd.predicates == ["newData_command_ib", "command_ib_msg_on"]
    assert [b.stop_cond for b in sd.behaviors] == ["newData_command_ib and not command_ib_msg_on"]
    assert fabric.compile_conditions(sd, tmp_path).returncode == 0


def test_a_model_with_configurations_carries_every_variable_link_as_an_io_buffer(tmp_path: Path) -> None:
    """two_arm: task/a.cs's manipulatorState is linked from both arms, one link per configuration;
    its FABRIC configuration reads both channels (the superset: FABRIC's own runtime cannot
    switch them), and FABRIC's parser and the deployer's rules accept every file."""
    model = load(ROOT / "samples" / "two_arm" / "two_arm.uml").model
    for name, content in render(model, "orocos").generated.items():
        if name.startswith("fabric/"):
            (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
            (tmp_path / name).write_bytes(content)
    for config in sorted((tmp_path / "fabric").glob("*/config/*.xml")):
        spec = fabric.parse_spec(config.parent.parent / "spec" / "subsystem.xml")
        assert fabric.configuration_problems(config, spec) == [], config
    task = ElementTree.parse(tmp_path / "fabric" / "task_a_cs" / "config" / "task_a_cs.xml").getroot()
    assert sorted((b.get("alias"), b.get("name")) for b in task.iter("io_buffer")) == [
        ("manipulatorCommand", "task_a_cs_manipulatorCommand"),
        ("manipulatorState", "manipA_a_cs_manipulatorState"), ("manipulatorState", "manipB_a_cs_manipulatorState")]
    arm_b = ElementTree.parse(tmp_path / "fabric" / "manipA_a_cs" / "config" / "manipB_a_cs.xml").getroot()
    assert {b.get("alias"): b.get("name") for b in arm_b.iter("io_buffer")}["manipulatorCommand"] == (
        "task_a_cs_manipulatorCommand")
