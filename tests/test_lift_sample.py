"""Lifting the reference sample gives the paper's Section 3 system (earl-metamodel.md §5)."""

from __future__ import annotations

from pathlib import Path

import pytest

from earl_m2t import load
from earl_m2t.model.elements import EarlModel, Subsystem

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
CORPUS = ROOT.parent / "shared" / "corpus"


@pytest.fixture(scope="module")
def model() -> EarlModel:
    loaded = load(SAMPLE)
    assert loaded.diagnostics == ()
    return loaded.model


@pytest.fixture(scope="module")
def cs(model: EarlModel) -> Subsystem:
    found = model.subsystem("manip/a.cs")
    assert found is not None
    return found


def test_the_system_has_one_robot_and_three_agents(model: EarlModel) -> None:
    (system,) = model.systems
    assert system.name == "PickAndPlaceSystem"
    assert [r.name for r in system.robots] == ["pickAndPlace/r"]
    assert system.robots[0].agents == ("manip/a", "grip/a")
    assert sorted(a.name for a in system.agents) == ["grip/a", "manip/a", "task/a"]


def test_manip_is_cet_with_six_virtual_and_six_real_effectors(model: EarlModel) -> None:
    manip = next(a for a in model.agents if a.name == "manip/a")
    assert manip.computed_type == "CET" and manip.declared_type == "CET"
    assert [s.name for s in manip.ve] == [f"motorController{k}/ve" for k in range(1, 7)]
    assert [s.name for s in manip.re] == [f"motor{k}/re" for k in range(1, 7)]
    assert [s.name for s in manip.cs] == ["cs"]


def test_task_is_ct_and_grip_is_cet(model: EarlModel) -> None:
    types = {a.name: a.computed_type for a in model.agents}
    assert types["task/a"] == "CT" and types["grip/a"] == "CET"


def test_replicated_links_connect_instance_k_to_instance_k(model: EarlModel) -> None:
    manip = next(a for a in model.agents if a.name == "manip/a")
    links = {link.name: link for link in manip.links}
    assert len(manip.links) == 24
    link = links["cs,motorController3/ve"]
    assert link.source == "manip/a.cs.motorControllerCommand3/ob"
    assert link.target == "manip/a.motorController3/ve.motorControllerCommand/ib"
    back = links["motor5/re,motorController5/ve"]
    assert back.source == "manip/a.motor5/re.encoder/ob"


def test_inter_agent_links_join_control_subsystems(model: EarlModel) -> None:
    (system,) = model.systems
    links = {link.name: (link.source, link.target) for link in system.links}
    assert links["task/a,manip/a"] == ("task/a.cs.manipulatorCommand/ob", "manip/a.cs.manipulatorCommand/ib")
    assert links["grip/a,task/a"] == ("grip/a.cs.gripperStatus/ob", "task/a.cs.gripperStatus/ib")


def test_the_control_subsystem_memory_is_table_4(model: EarlModel, cs: Subsystem) -> None:
    memory = {m.template: m.datatype for m in cs.memory}
    assert memory == {
        "motionFinished/m": "Boolean",
        "currentOperationalPos/m": "DataTypes::OperPosition",
        "currentJointPos/m": "DataTypes::JointPosition",
        "emergencyStopCommandK/m": "Boolean",
        "windingCurrentK/m": "Real",
    }
    assert len(cs.memory) == 3 + 6 + 6


def test_the_primitive_predicates_are_table_5(cs: Subsystem) -> None:
    bodies = {p.name: p.fun.text for p in cs.predicates if p.fun is not None}
    assert set(bodies) == {"emergencyStop/pp", "motionFinished/pp", "newJointPos/pp", "newOperationalPos/pp",
                           "false/pp"}
    assert bodies["newJointPos/pp"] == "newData(manipulatorCommand/ib.msg.jointPosSetpoint)"
    assert [e.predicates for e in cs.exclusions] == [("newJointPos/pp", "newOperationalPos/pp")]


def test_the_fsm_has_the_table_6_transitions_and_priorities(cs: Subsystem) -> None:
    assert cs.fsm is not None
    assert cs.fsm.initial == "idle"
    assert [s.name for s in cs.fsm.states] == ["idle", "jointMove", "operationalMove", "emergencyStop"]
    table = {(t.source, t.target): (t.condition.text if t.condition else None, t.priority) for t in cs.fsm.transitions}
    new_joint = "newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun"
    new_oper = "newOperationalPos/pp.fun ∧ ¬emergencyStop/pp.fun"
    assert table == {
        ("idle", "jointMove"): (new_joint, 0),
        ("jointMove", "jointMove"): (new_joint, 1),
        ("idle", "operationalMove"): (new_oper, 0),
        ("operationalMove", "operationalMove"): (new_oper, 1),
        ("jointMove", "idle"): ("¬emergencyStop/pp.fun", 0),
        ("operationalMove", "idle"): ("¬emergencyStop/pp.fun", 0),
        ("idle", "emergencyStop"): ("emergencyStop/pp.fun ∨ inError()", 2),
        ("jointMove", "emergencyStop"): ("emergencyStop/pp.fun ∨ inError()", 2),
        ("operationalMove", "emergencyStop"): ("emergencyStop/pp.fun ∨ inError()", 2),
    }


def test_the_transition_functions_are_table_7_in_two_stages(cs: Subsystem) -> None:
    specific = {"idle/bb": "passiveRegulation/pf", "jointMove/bb": "jointMove/pf",
                "operationalMove/bb": "operationalMove/pf", "emergencyStop/bb": "emergencyStop/pf"}
    for bb in cs.behaviours:
        assert bb.stages == (("calculatePosition/pf", specific[bb.name]), ("outputManipState/pf", "outputMotorCon/pf"))
    writes = {pf.name: sorted({w.rpartition(".")[2].rstrip("0123456789/m").rstrip("K") for w in pf.writes})
              for pf in cs.functions}
    assert writes["calculatePosition/pf"] == ["currentJointPos", "currentOperationalPos"]
    assert writes["jointMove/pf"] == ["motionFinished", "windingCurrent"]
    assert writes["emergencyStop/pf"] == ["emergencyStopCommand"]
    assert [w.rpartition(".")[2] for w in cs.function("outputManipState/pf").writes] == ["manipulatorState/ob"]


def test_every_element_keeps_its_file_and_line(model: EarlModel, cs: Subsystem) -> None:
    assert cs.fsm is not None
    for element in (*cs.buffers, *cs.memory, *cs.fsm.transitions, *cs.behaviours, *cs.functions, *model.links):
        assert element.location.file == str(SAMPLE)
        assert element.location.line > 0 and element.location.xmi_id


@pytest.mark.parametrize("name", sorted(p.name for p in (CORPUS / "papyrus").glob("*.uml")) if CORPUS.exists() else [])
def test_every_papyrus_corpus_file_lifts_without_error(name: str) -> None:
    loaded = load(CORPUS / "papyrus" / name)
    assert not loaded.model.has_earl_content
