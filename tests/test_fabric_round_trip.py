"""Every FABRIC package under ../shared/fabric/examples (found there, so that packages added later
are covered) and our own tests/fixtures/fabric/gripper_cs_control, which uses IN_ERROR and
CURRENT_BEHAVIOR_OK in stop, error and initial conditions: ``import fabric`` → ``check`` without
errors → ``gen --target orocos`` → FABRIC's parser and logicExprToCpp accept the regenerated
spec, the configurations give the buffers the same channels, and the spec equals the original
element by element (tests/support/fabric_compare.py, tests/support/fabric_round_trip.py)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.fabric import packages_to_model, read_package
from earl_m2t.fabric.conditions import parse_fabric_condition
from earl_m2t.gen import render
from earl_m2t.predicate import BuiltIn, BuiltInPredicate
from tests.support import fabric
from tests.support.fabric_compare import differences
from tests.support.fabric_round_trip import round_trip, unusable_conditions

ROOT = Path(__file__).resolve().parents[1]
FIXTURE = ROOT / "tests" / "fixtures" / "fabric" / "gripper_cs_control"
EXAMPLES = sorted(spec.parent.parent for spec in fabric.EXAMPLES.glob("**/spec/subsystem.xml"))
PACKAGES = [*EXAMPLES, FIXTURE]


def test_the_examples_are_found() -> None:
    assert {p.name for p in EXAMPLES} >= {"velma_core_ve_body", "velma_task_cs_ros_interface",
                                           "velma_pred_ctrl_interface"}


@pytest.mark.parametrize("package", PACKAGES, ids=[p.name for p in PACKAGES])
def test_a_package_round_trips(package: Path, tmp_path: Path) -> None:
    outcome = round_trip([package], tmp_path)
    assert outcome.failures == [], "\n".join(outcome.steps)
    assert any("equal element by element" in step for step in outcome.steps)


def test_the_packages_round_trip_together(tmp_path: Path) -> None:
    outcome = round_trip(PACKAGES, tmp_path)
    assert outcome.failures == [], "\n".join(outcome.steps)


def test_fabrics_flags_are_the_built_ins() -> None:
    spec = fabric.parse_spec(FIXTURE / "spec" / "subsystem.xml")
    used = {text for _, text in fabric.conditions(spec)}
    assert any("IN_ERROR" in t for t in used) and any("CURRENT_BEHAVIOR_OK" in t for t in used)
    assert parse_fabric_condition("IN_ERROR", {}) == BuiltIn(BuiltInPredicate.IN_ERROR)
    assert parse_fabric_condition("CURRENT_BEHAVIOR_OK", {}) == BuiltIn(BuiltInPredicate.BEHAVIOUR_OK)


def test_the_fixture_imports_its_flags_states_and_simulation() -> None:
    model, notes = packages_to_model([read_package(FIXTURE)], "gripper")
    assert notes == []
    sub = model.subsystems[0]
    assert sub.path == "gripper.cs_control"
    bb = {b.name: b for b in sub.behaviours}
    assert bb["open/bb"].ec is not None and bb["open/bb"].ec.text == "¬behaviourOk()"
    assert bb["close/bb"].ec is not None and bb["close/bb"].ec.text == "inError() ∨ ¬hwOk/pp.fun"
    assert sub.fsm is not None
    opening = next(s for s in sub.fsm.states if s.name == "opening")
    assert opening.behaviours == ("monitor__open/bb",) and opening.composes == ("monitor/bb", "open/bb")
    assert opening.exclusive_guards
    composed = bb["monitor__open/bb"]
    assert composed.stages == (("Monitor/pf", "Y/pf", "Opener/pf"),)
    assert [t.condition.text for t in sub.fsm.transitions if t.source == "opening" and t.condition] == [
        "inError()", "¬inError() ∧ recvClose/pp.fun", "¬inError() ∧ ¬recvClose/pp.fun"]
    closing = next(s for s in sub.fsm.states if s.name == "closing")
    assert (closing.activation.min_period_sim, closing.activation.first_timeout_sim,
            closing.activation.used_time) == (0.01, 2.0, "real")
    assert sub.simulation is not None and (sub.simulation.use_ros_sim_clock, sub.simulation.use_sim_clock,
                                           sub.simulation.trigger_gazebo) == (True, False, False)
    hw = next(b for b in sub.inputs if b.name == "hw_st/ib")
    assert (hw.side, hw.converter, hw.channel) == ("bottom", "gripper_hw_msgs::StateConverter", "gripper_hw_st")


@pytest.mark.parametrize(("old", "new", "difference"), [
    ('init_cond="(not IN_ERROR) and recvClose"', 'init_cond="recvClose"',
     "state opening next_state closing init_cond"),
    ('err_cond="not CURRENT_BEHAVIOR_OK"', 'err_cond="not IN_ERROR"', "behavior open err_cond"),
    ('stop_cond="recvOpen"', 'stop_cond="recvOpen or CURRENT_BEHAVIOR_OK"', "behavior close stop_cond"),
    ('converter="gripper_hw_msgs::StateConverter" ', "", "buffers_in"),
    ('first_timeout_sim="2.0"', 'first_timeout_sim="2.5"', "state closing buffer_group_first_timeout_sim"),
    ('used_time="real"', 'used_time="sim"', "state closing buffer_group_used_time"),
    ('trigger_gazebo="false" ', "", None),
    ('<behavior name="monitor" />\n            <behavior name="close" />', '<behavior name="close" />',
     "state closing behaviors"),
    ('use_sim_clock="false"', 'use_sim_clock="true"', "simulation use_sim_clock"),
])
def test_the_comparison_finds_a_change(tmp_path: Path, old: str, new: str, difference: str | None) -> None:
    """Each element the comparison covers, changed in a copy of the fixture, is a difference
    (trigger_gazebo="false" is FABRIC's default, so leaving it out is none)."""
    copy = tmp_path / FIXTURE.name
    shutil.copytree(FIXTURE, copy)
    spec = copy / "spec" / "subsystem.xml"
    text = spec.read_text(encoding="utf-8")
    assert old in text
    spec.write_text(text.replace(old, new, 1), encoding="utf-8")
    found = differences(fabric.parse_spec(FIXTURE / "spec" / "subsystem.xml"), fabric.parse_spec(spec))
    if difference is None:
        assert found == []
    else:
        assert len(found) == 1 and found[0].startswith(difference), found


def test_conditions_equal_as_logic_not_as_text(tmp_path: Path) -> None:
    copy = tmp_path / FIXTURE.name
    shutil.copytree(FIXTURE, copy)
    spec = copy / "spec" / "subsystem.xml"
    text = spec.read_text(encoding="utf-8").replace('err_cond="IN_ERROR or not hwOk"',
                                                     'err_cond="not (hwOk and not IN_ERROR)"')
    spec.write_text(text, encoding="utf-8")
    assert differences(fabric.parse_spec(FIXTURE / "spec" / "subsystem.xml"), fabric.parse_spec(spec)) == []


def test_a_model_written_by_hand_writes_the_built_ins_as_fabrics_flags(tmp_path: Path) -> None:
    """inError() and behaviourOk() in a hand-written SysML v2 model (the sample with an error
    condition and a guard changed) become IN_ERROR and CURRENT_BEHAVIOR_OK, which FABRIC's
    parser and logicExprToCpp accept."""
    text = (ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml").read_text(encoding="utf-8")
    guard = "transition 'jointMove,idle/t' first jointMove if not 'emergencyStop/pp'() then idle;"
    assert guard in text and "constraint ec { false }" in text
    text = text.replace("constraint ec { false }", "constraint ec { not behaviourOk() }", 1).replace(
        guard, "transition 'jointMove,idle/t' first jointMove if inError() or not 'emergencyStop/pp'() then idle;")
    model = tmp_path / "pick_and_place.sysml"
    model.write_text(text, encoding="utf-8")
    spec = tmp_path / "subsystem.xml"
    spec.write_bytes(render(load(model).model, "orocos").generated["fabric/manip_a_cs/spec/subsystem.xml"])
    sd = fabric.parse_spec(spec)
    assert next(b for b in sd.behaviors if b.name == "idle").err_cond == "not CURRENT_BEHAVIOR_OK"
    joint_move = next(s for s in sd.states if s.name == "jointMove")
    assert ("idle", "(IN_ERROR or not emergencyStop) and not (emergencyStop or IN_ERROR) "
                    "and not (newJointPos and not emergencyStop)") in joint_move.next_states
    assert "IN_ERROR" not in sd.predicates and "CURRENT_BEHAVIOR_OK" not in sd.predicates
    assert unusable_conditions(sd) == []
