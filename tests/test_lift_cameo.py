"""A model written as Cameo writes it lifts to the same EARL model as the same model written by Papyrus.

``tests/fixtures/cameo/arm-cameo2022x.xmi`` is written by hand in MagicDraw 2022x's native XMI
(single quotes, tabs, stereotype applications after the model with ``_application`` ids, the EARL
profile in its MagicDraw namespace, bodies before languages, child idrefs, NestedConnectorEnd
paths as IDREFS, idref children and ``local:/`` hrefs, types from the SysML and MagicDraw
libraries, diagram and modelExtension blocks that repeat ids). :func:`arm_model` builds the same
model with the Papyrus builder.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from earl_m2t.api import check, load
from earl_m2t.export import model_to_dict
from tests.support.papyrus_builder import BOOLEAN, REAL, End, ModelBuilder

ROOT = Path(__file__).resolve().parents[1]
CAMEO_ARM = ROOT / "tests" / "fixtures" / "cameo" / "arm-cameo2022x.xmi"
IGNORED = frozenset({"line", "xmi_id", "file", "dialect"})


def arm_model() -> ModelBuilder:
    """Robot ``arm/r`` with ``manip/a`` (cs, ve, re; an FSM of two states) and ``task/a`` (cs)."""
    mb = ModelBuilder("Arm")
    types = mb.package("DataTypes")
    command = types.data_type("JointCommand")
    command.field("position", REAL)
    command.field("valid", BOOLEAN)
    state = types.data_type("JointState")
    state.field("position", REAL, 6)
    inst = mb.package("SystemInstance")
    system = inst.block("ArmSystem", "System")
    robot = inst.block("ArmRobot", "Robot")
    manip = inst.block("ManipulatorAgent", "Agent", {"declaredType": "CET"})
    task = inst.block("TaskAgent", "Agent", {"declaredType": "CT"})
    cs = inst.block("ManipulatorControl", "ControlSubsystem")
    ve = inst.block("JointController", "VirtualEffector")
    re = inst.block("JointMotor", "RealEffector")
    tcs = inst.block("TaskControl", "ControlSubsystem")

    goal_ib = cs.input_buffer("goal/ib", command)
    state_ib = cs.input_buffer("state/ib", state)
    command_ob = cs.output_buffer("command/ob", command)
    done_ob = cs.output_buffer("done/ob", BOOLEAN)
    target_m = cs.memory("target/m", REAL)
    plan = cs.partial_transition_function("plan/pf", reads=[goal_ib], writes=[command_ob, target_m])
    report = cs.partial_transition_function("report/pf", reads=[state_ib], writes=[done_ob])
    cs.primitive_predicate("newGoal/pp", "newData(goal/ib.msg.position)")
    fsm = cs.state_machine()
    idle = fsm.state("idle", initial=True)
    move = fsm.state("move")
    fsm.transition(idle, move, "newGoal/pp")
    fsm.transition(move, idle, "¬newGoal/pp", priority=1)
    idle.do_activity().stages([[report]])
    move.do_activity(tc="TRUE").stages([[plan, report]])

    command_ib = ve.input_buffer("command/ib", command)
    state_ob = ve.output_buffer("state/ob", state)
    drive_ob = ve.output_buffer("drive/ob", command)
    sense_ib = ve.input_buffer("sense/ib", state)
    drive = ve.partial_transition_function("drive/pf", reads=[command_ib], writes=[drive_ob])
    sense = ve.partial_transition_function("sense/pf", reads=[sense_ib], writes=[state_ob])
    ve.state_machine().state("run", initial=True).do_activity().stages([[drive], [sense]])

    drive_ib = re.input_buffer("drive/ib", command)
    sense_ob = re.output_buffer("sense/ob", state)
    relay = re.partial_transition_function("relay/pf", reads=[drive_ib], writes=[sense_ob])
    re.state_machine().state("on", initial=True).do_activity().stages([[relay]])

    goal_ob = tcs.output_buffer("goal/ob", command)
    done_ib = tcs.input_buffer("done/ib", BOOLEAN)
    send = tcs.partial_transition_function("send/pf", reads=[done_ib], writes=[goal_ob])
    tcs.state_machine().state("work", initial=True).do_activity().stages([[send]])

    robot_part = system.part("arm/r", robot)
    manip_part = robot.part("manip/a", manip)
    task_part = robot.part("task/a", task)
    cs_part = manip.part("cs", cs)
    ve_part = manip.part("joint/ve", ve)
    re_part = manip.part("motor/re", re)
    tcs_part = task.part("cs", tcs)
    manip.connector("cs,joint/ve", End.at(command_ob, cs_part), End.at(command_ib, ve_part), "InterSubsystemLink")
    manip.connector("joint/ve,cs", End.at(state_ob, ve_part), End.at(state_ib, cs_part), "InterSubsystemLink")
    manip.connector("joint/ve,motor/re", End.at(drive_ob, ve_part), End.at(drive_ib, re_part), "InterSubsystemLink")
    manip.connector("motor/re,joint/ve", End.at(sense_ob, re_part), End.at(sense_ib, ve_part), "InterSubsystemLink")
    system.connector("task/a,manip/a", End.at(goal_ob, robot_part, task_part, tcs_part),
                     End.at(goal_ib, robot_part, manip_part, cs_part), "InterAgentLink")
    system.connector("manip/a,task/a", End.at(done_ob, robot_part, manip_part, cs_part),
                     End.at(done_ib, robot_part, task_part, tcs_part), "InterAgentLink")
    return mb


def without_places(value: Any) -> Any:
    """The exported model without what depends on the file: lines, ids, file name, dialect."""
    if isinstance(value, dict):
        return {k: without_places(v) for k, v in value.items() if k not in IGNORED}
    if isinstance(value, list):
        return [without_places(v) for v in value]
    return value


def test_the_cameo_model_lifts_to_the_same_earl_model_as_the_papyrus_one(tmp_path: Path) -> None:
    papyrus = tmp_path / "arm.uml"
    arm_model().write(papyrus)
    from_papyrus = model_to_dict(load(papyrus).model)
    from_cameo = model_to_dict(load(CAMEO_ARM).model)
    assert (from_papyrus["dialect"], from_cameo["dialect"]) == ("papyrus", "cameo")
    assert without_places(from_cameo) == without_places(from_papyrus)
    assert from_cameo["earl"] is True and len(from_cameo["systems"][0]["agents"]) == 2


def test_the_cameo_model_checks_like_the_papyrus_one(tmp_path: Path) -> None:
    """No errors, and the same two behaviour warnings from both: idle/bb leaves command/ob
    unwritten (T006), and move/bb (tc TRUE) can end while newGoal holds, when its only
    transition (¬newGoal) is not enabled (B007)."""
    papyrus = tmp_path / "arm.uml"
    arm_model().write(papyrus)
    expected = [("B007", "manip/a.cs.fsm.move"), ("T006", "manip/a.cs.idle/bb")]
    from_papyrus, from_cameo = check(papyrus), check(CAMEO_ARM)
    assert sorted((d.code, d.element) for d in from_papyrus) == expected
    assert [(d.code, d.message) for d in from_cameo] == [(d.code, d.message) for d in from_papyrus]


def test_cameo_locations_point_into_the_cameo_file() -> None:
    model = load(CAMEO_ARM).model
    lines = CAMEO_ARM.read_text(encoding="utf-8").splitlines()
    manip = model.agents[0]
    assert manip.location.file == str(CAMEO_ARM)
    assert "name='manip/a'" in lines[manip.location.line - 1]
    transition = manip.subsystems[0].fsm.transitions[1] if manip.subsystems[0].fsm else None
    assert transition is not None and transition.condition is not None
    assert lines[transition.condition.location.line - 1].strip() == "<body>¬newGoal/pp</body>"
