"""Write the reference sample ``samples/pick_and_place/`` in three tool dialects.

The sample is the pick-and-place system of the EARL paper (Electronics 2020, 9(2), 379,
Section 3) with N = 6 joints, following ``docs/modelling-guide.md``: an EARL stereotype on
every EARL element, names with the paper's suffixes, Tables 4-7 for the manipulator's
control subsystem. The content is built once, by the functions below, against the builder
interface that ``tests/support/papyrus_builder.py``, ``cameo_builder.py`` and
``ea_builder.py`` share (``tests/support/sample_kit.py``); each builder writes it the way its
tool saves a model:

- ``pick_and_place.uml``: Eclipse Papyrus 6.x with SysML 1.6 (Eclipse UML2 5.x XMI);
- ``pick_and_place.cameo.xmi``: Cameo Systems Modeler 2022x native project XMI (the
  ``com.nomagic.magicdraw.uml_model.model`` member of an ``.mdzip``);
- ``pick_and_place.ea.xml``: Enterprise Architect 16 "XMI 2.1" export (windows-1252).

Two variants of the Enterprise Architect file name the stereotypes as other EA profiles do
(``samples/pick_and_place/variants/``): ``pick_and_place.earl-mdg.ea.xml`` with the names of the
EARL authors' MDG Technology (``EARL:ContSubsys``, ``EARL:VirtEff`` …) and
``pick_and_place.spsys.ea.xml`` with the stereotypes of SPSysML's SPSys profile, which
specialise those (``SPSys:PhyAgent``, ``SPSys:PhyContSubsys`` …; read with that profile file).

Usage: ``python scripts/make_sample.py`` writes the three files and the variants;
``python scripts/make_sample.py [--dialect papyrus|cameo|ea] OUTPUT`` writes one of them to
``OUTPUT`` (Papyrus by default). The output is deterministic: running the script twice gives
byte-identical files.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.support.sample_kit import (  # noqa: E402
    DIALECTS,
    Block,
    Package,
    inter_agent_link,
    link,
    single_state,
    write_dialects,
)

N_JOINTS = 6
SAMPLE_DIR = ROOT / "samples" / "pick_and_place"
SAMPLE = SAMPLE_DIR / "pick_and_place.uml"
FILES = {
    "papyrus": SAMPLE,
    "cameo": SAMPLE_DIR / "pick_and_place.cameo.xmi",
    "ea": SAMPLE_DIR / "pick_and_place.ea.xml",
}
VARIANT_DIR = SAMPLE_DIR / "variants"
ESTOP_LATCHES = "[] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop)"

# Stereotypes of the EA variants, by EARL concept: (profile prefix, stereotype name); concepts
# not listed keep their EARL stereotype. The authors' MDG names are those of
# metamodel/xmi/stereotype-names.toml; SPSys (SPSysML) specialises them.
EARL_MDG_NAMES = {
    "Agent": ("EARL", "Agent"),
    "ControlSubsystem": ("EARL", "ContSubsys"),
    "VirtualEffector": ("EARL", "VirtEff"),
    "VirtualReceptor": ("EARL", "VirtRec"),
    "RealEffector": ("EARL", "RealEff"),
    "RealReceptor": ("EARL", "RealRec"),
}
SPSYS_NAMES = {
    "Agent": ("SPSys", "PhyAgent"),
    "ControlSubsystem": ("SPSys", "PhyContSubsys"),
    "VirtualEffector": ("SPSys", "PhyVirtEff"),
    "VirtualReceptor": ("SPSys", "PhyVirtRec"),
    "RealEffector": ("SPSys", "PhyRealEff"),
    "RealReceptor": ("SPSys", "PhyRealRec"),
}
SPSYS_NS = "http://www.sparxsystems.com/profiles/SPSys/1.0"
VARIANTS = {
    "pick_and_place.earl-mdg.ea.xml": EARL_MDG_NAMES,
    "pick_and_place.spsys.ea.xml": SPSYS_NAMES,
}

# ---- the content ---------------------------------------------------------------------------------

# Table 6: initial conditions of manip/a.cs transitions and terminal conditions of its behaviours.
NEW_JOINT = "newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun"
NEW_OPERATIONAL = "newOperationalPos/pp.fun ∧ ¬emergencyStop/pp.fun"
NO_EMERGENCY = "¬emergencyStop/pp.fun"
EMERGENCY = "emergencyStop/pp.fun"
# into emergencyStop also when the behaviour's error condition held (a pf failed: ¬behaviourOk())
EMERGENCY_OR_ERROR = "emergencyStop/pp.fun ∨ inError()"
BEHAVIOUR_FAILED = "¬behaviourOk()"
MOTION_TC = "motionFinished/pp.fun ∨ emergencyStop/pp.fun"
IDLE_TC = "newJointPos/pp.fun ∨ newOperationalPos/pp.fun ∨ emergencyStop/pp.fun"
COMMAND_QUEUE = 8  # manip/a.cs's manipulatorCommand/ib: task/a's commands, in order
# every state of manip/a.cs: an iteration per command of task/a (waiting at most 100 ms on
# entering a state, 20 ms later), at most one per 0.5 ms, so that it catches up when behind
MANIPULATOR_ACTIVATION = {"bufferGroup": "commands", "minPeriod": "0.0005", "firstTimeout": "0.1",
                          "nextTimeout": "0.02"}


class DataTypes:
    """The DataTypes package (paper Figs. 9 and 11)."""

    def __init__(self, pkg: Package, real: Any, boolean: Any) -> None:
        self.real, self.boolean = real, boolean
        self.vector3 = pkg.data_type("Vector3")
        for axis in ("x", "y", "z"):
            self.vector3.field(axis, real)
        self.quaternion = pkg.data_type("Quaternion")
        for axis in ("x", "y", "z", "w"):
            self.quaternion.field(axis, real)
        self.joint_position = pkg.data_type("JointPosition")
        self.joint_position.field("q", real, N_JOINTS)
        self.oper_position = pkg.data_type("OperPosition")
        self.oper_position.field("position", self.vector3)
        self.oper_position.field("orientation", self.quaternion)

        self.manipulator_command = pkg.data_type("ManipulatorCommand")
        self.manipulator_command.field("jointPosSetpoint", self.joint_position, "0..1")
        self.manipulator_command.field("operationalPosSetpoint", self.oper_position, "0..1")
        self.manipulator_command.field("emergencyStopCommand", boolean)
        self.manipulator_state = pkg.data_type("ManipulatorState")
        self.manipulator_state.field("currentJointPos", self.joint_position)
        self.manipulator_state.field("currentOperationalPos", self.oper_position)
        self.manipulator_state.field("motionFinished", boolean)
        self.manipulator_state.field("emergencyStop", boolean)
        self.gripper_command = pkg.data_type("GripperCommand")
        self.gripper_command.field("desiredFingerPos", real)
        self.gripper_command.field("emergencyStopCommand", boolean)
        self.gripper_status = pkg.data_type("GripperStatus")
        self.gripper_status.field("currentFingerPos", real)
        self.gripper_status.field("motionFinished", boolean)
        self.gripper_status.field("emergencyStop", boolean)

        self.motor_controller_command = pkg.data_type("MotorControllerCommand")
        self.motor_controller_command.field("desiredWindingCurrent", real)
        self.motor_controller_command.field("emergencyStopCommand", boolean)
        self.motor_controller_state = pkg.data_type("MotorControllerState")
        self.motor_controller_state.field("motorPos", real)
        self.motor_controller_state.field("emergencyStopCommand", boolean)
        self.motor_current = pkg.data_type("MotorCurrent")
        self.motor_current.field("current", real)
        self.encoder_reading = pkg.data_type("EncoderReading")
        self.encoder_reading.field("position", real)


def motor_controller(pkg: Package, dt: DataTypes, name: str, pf_name: str) -> Block:
    """A Virtual Effector regulating one motor: a PI current regulator on the encoder reading."""
    ve = pkg.block(name, "VirtualEffector")
    command = ve.input_buffer("motorControllerCommand/ib", dt.motor_controller_command)
    state = ve.output_buffer("motorControllerState/ob", dt.motor_controller_state)
    current = ve.output_buffer("desiredCurrent/ob", dt.motor_current)
    encoder = ve.input_buffer("encoder/ib", dt.encoder_reading)
    ve.memory("desiredPosition/m", dt.real)
    integral = ve.memory("integralError/m", dt.real)
    pf = ve.partial_transition_function(
        pf_name,
        reads=[command, encoder, integral],
        writes=[current, state, integral],
        body="// PI regulator: desired winding current from the position error; reports the motor state.",
    )
    single_state(ve, "regulate", pf)
    return ve


def motor(pkg: Package, dt: DataTypes, name: str, pf_name: str) -> Block:
    """A Real Effector: the driver of one motor with its encoder."""
    re = pkg.block(name, "RealEffector")
    current = re.input_buffer("desiredCurrent/ib", dt.motor_current)
    encoder = re.output_buffer("encoder/ob", dt.encoder_reading)
    position = re.memory("position/m", dt.real)
    pf = re.partial_transition_function(
        pf_name,
        reads=[current, position],
        writes=[encoder, position],
        body="// Sets the winding current on the hardware and reads the encoder.",
    )
    single_state(re, "drive", pf)
    return re


def task_control(pkg: Package, dt: DataTypes) -> Block:
    """task/a.cs: supervises the pick-and-place task."""
    cs = pkg.block("TaskControl", "ControlSubsystem")
    manip_cmd = cs.output_buffer("manipulatorCommand/ob", dt.manipulator_command)
    grip_cmd = cs.output_buffer("gripperCommand/ob", dt.gripper_command)
    manip_state = cs.input_buffer("manipulatorState/ib", dt.manipulator_state)
    grip_status = cs.input_buffer("gripperStatus/ib", dt.gripper_status)

    cs.primitive_predicate(
        "taskAborted/pp", "manipulatorState/ib.msg.emergencyStop ∨ gripperStatus/ib.msg.emergencyStop"
    )
    plan = cs.partial_transition_function(
        "planTask/pf",
        reads=[manip_state, grip_status],
        writes=[manip_cmd, grip_cmd],
        body="// Plans the next pick or place motion and the gripper setpoint.",
    )
    hold = cs.partial_transition_function(
        "holdCommands/pf",
        writes=[manip_cmd, grip_cmd],
        body="// Keeps sending the last commands with the emergency stop set.",
    )

    fsm = cs.state_machine()
    supervise = fsm.state("supervise", initial=True)
    abort = fsm.state("abort")
    fsm.transition(supervise, abort, "taskAborted/pp")
    supervise.do_activity(tc="taskAborted/pp", ec="FALSE").stages([[plan]])
    abort.do_activity(tc="FALSE", ec="FALSE").stages([[hold]])
    return cs


def manipulator_control(pkg: Package, dt: DataTypes) -> Block:
    """manip/a.cs exactly as the paper's Tables 4-7."""
    cs = pkg.block("ManipulatorControl", "ControlSubsystem")
    command = cs.input_buffer("manipulatorCommand/ib", dt.manipulator_command)
    state = cs.output_buffer("manipulatorState/ob", dt.manipulator_state)
    mc_state = cs.input_buffer("motorControllerStateK/ib", dt.motor_controller_state, N_JOINTS)
    mc_command = cs.output_buffer("motorControllerCommandK/ob", dt.motor_controller_command, N_JOINTS)

    # Table 4
    motion_finished = cs.memory("motionFinished/m", dt.boolean)
    operational_pos = cs.memory("currentOperationalPos/m", dt.oper_position)
    joint_pos = cs.memory("currentJointPos/m", dt.joint_position)
    stop_command = cs.memory("emergencyStopCommandK/m", dt.boolean, N_JOINTS)
    winding_current = cs.memory("windingCurrentK/m", dt.real, N_JOINTS)

    # Table 5
    cs.primitive_predicate(
        "emergencyStop/pp",
        "manipulatorCommand/ib.msg.emergencyStopCommand ∨ motorControllerState1/ib.msg.emergencyStopCommand"
        " ∨ … ∨ motorControllerStateN/ib.msg.emergencyStopCommand",
    )
    cs.primitive_predicate("motionFinished/pp", "motionFinished/mi.msg")
    new_joint = cs.primitive_predicate("newJointPos/pp", "newData(manipulatorCommand/ib.msg.jointPosSetpoint)")
    new_operational = cs.primitive_predicate(
        "newOperationalPos/pp", "newData(manipulatorCommand/ib.msg.operationalPosSetpoint)"
    )
    cs.primitive_predicate("false/pp", "FALSE")
    # Table 6 note: task/a never sets a joint and an operational setpoint at once.
    cs.exclusion(
        "jointOrOperational", [new_joint, new_operational], "exclusive(newJointPos/pp, newOperationalPos/pp)"
    )

    # Table 7 and Section 3.2. Stage-1 pf take their arguments from the input buffers (paper
    # eq. 4): reading memory that calculatePosition/pf writes in the same stage would race.
    calculate = cs.partial_transition_function(
        "calculatePosition/pf",
        reads=[mc_state],
        writes=[joint_pos, operational_pos],
        body="// Joint positions from the motor positions; end-effector pose by forward kinematics.",
    )
    passive = cs.partial_transition_function(
        "passiveRegulation/pf",
        reads=[mc_state],
        writes=[winding_current],
        body="// Winding currents that keep the manipulator still.",
    )
    joint_move = cs.partial_transition_function(
        "jointMove/pf",
        reads=[command, mc_state],
        writes=[motion_finished, winding_current],
        body="// Joint-space trajectory; PI regulator per joint: i = Kp*e + Ki*integral(e), e = desired - current.",
    )
    operational_move = cs.partial_transition_function(
        "operationalMove/pf",
        reads=[command, mc_state],
        writes=[motion_finished, winding_current],
        body="// Operational-space trajectory and the winding currents that realise it.",
    )
    emergency_stop = cs.partial_transition_function(
        "emergencyStop/pf",
        reads=[command, mc_state],
        writes=[stop_command],
        body="// Copies the emergency stop to every motor controller command.",
    )
    output_state = cs.partial_transition_function(
        "outputManipState/pf",
        reads=[joint_pos, operational_pos, motion_finished, stop_command],
        writes=[state],
        body="// Composes ManipulatorState from the internal memory.",
    )
    output_motor = cs.partial_transition_function(
        "outputMotorCon/pf",
        reads=[winding_current, stop_command],
        writes=[mc_command],
        body="// Composes one MotorControllerCommand per joint.",
    )

    # Activation (FABRIC's buffer groups): task/a's commands queue and each one activates an
    # iteration, so that its one-shot setpoint is read even when manip/a.cs falls behind; the
    # motor controllers' states are read when new.
    command.stereotype("InputBuffer", {"receive": "queue", "queueSize": COMMAND_QUEUE})
    cs.buffer_group("commands", obligatory=[command], optional=[mc_state])

    # Table 6 and Fig. 12
    fsm = cs.state_machine()
    idle = fsm.state("idle", initial=True)
    joint = fsm.state("jointMove")
    operational = fsm.state("operationalMove")
    stop = fsm.state("emergencyStop")
    fsm.transition(idle, joint, NEW_JOINT)
    fsm.transition(joint, joint, NEW_JOINT, priority=1)
    fsm.transition(idle, operational, NEW_OPERATIONAL)
    fsm.transition(operational, operational, NEW_OPERATIONAL, priority=1)
    fsm.transition(joint, idle, NO_EMERGENCY)
    fsm.transition(operational, idle, NO_EMERGENCY)
    for source in (idle, joint, operational):
        fsm.transition(source, stop, EMERGENCY_OR_ERROR, priority=2)

    # Table 7 and Fig. 15: stage 1 writes memory, stage 2 the output buffers.
    # emergencyStop, the error state, has no way out: its ec stays FALSE
    for st, tc, ec, pf in (
        (idle, IDLE_TC, BEHAVIOUR_FAILED, passive),
        (joint, MOTION_TC, BEHAVIOUR_FAILED, joint_move),
        (operational, MOTION_TC, BEHAVIOUR_FAILED, operational_move),
        (stop, "false/pp.fun", "FALSE", emergency_stop),
    ):
        st.do_activity(tc=tc, ec=ec).stages([[calculate, pf], [output_state, output_motor]])
        st.stereotype("FsmState", MANIPULATOR_ACTIVATION)
    return cs


def gripper_control(pkg: Package, dt: DataTypes) -> Block:
    """grip/a.cs: turns gripper commands into finger motor controller commands."""
    cs = pkg.block("GripperControl", "ControlSubsystem")
    command = cs.input_buffer("gripperCommand/ib", dt.gripper_command)
    status = cs.output_buffer("gripperStatus/ob", dt.gripper_status)
    finger_command = cs.output_buffer("fingerCommand/ob", dt.motor_controller_command)
    finger_state = cs.input_buffer("fingerState/ib", dt.motor_controller_state)
    pf = cs.partial_transition_function(
        "gripperControl/pf",
        reads=[command, finger_state],
        writes=[status, finger_command],
        body="// Finger setpoint from the gripper command; gripper status from the finger state.",
    )
    single_state(cs, "operate", pf)
    return cs


def build(stereotypes: bool = True, dialect: str = "papyrus") -> bytes:
    """Build the sample in ``dialect`` and return its XMI; ``stereotypes=False`` gives the
    suffix-only variant."""
    kit = DIALECTS[dialect]
    mb = kit.model_builder("PickAndPlace", stereotypes=stereotypes)
    mb.comment(
        "Pick-and-place robot system of the EARL paper (Electronics 2020, 9(2), 379, Section 3): "
        f"a {N_JOINTS}-DOF manipulator agent, a gripper agent and a task agent supervising them."
    )
    dt = DataTypes(mb.package("DataTypes"), kit.real, kit.boolean)
    pkg = mb.package("SystemInstance")

    system = pkg.block("PickAndPlaceSystem", "System")
    robot = pkg.block("PickAndPlaceRobot", "Robot")
    task_agent = pkg.block("TaskAgent", "Agent", {"declaredType": "CT"})
    task_agent.comment("task/a supervises picking and placing objects; it commands manip/a and grip/a.")
    manip_agent = pkg.block("ManipulatorAgent", "Agent", {"declaredType": "CET"})
    manip_agent.comment(
        f"manip/a controls the {N_JOINTS}-DOF manipulator: one motor controller (ve) and one motor (re) "
        "per joint under one control subsystem."
    )
    grip_agent = pkg.block("GripperAgent", "Agent", {"declaredType": "CET"})
    grip_agent.comment("grip/a controls the gripper fingers; a separate agent so that grippers can be swapped.")

    task_cs = task_control(pkg, dt)
    manip_cs = manipulator_control(pkg, dt)
    motor_ctrl = motor_controller(pkg, dt, "MotorController", "regulateMotor/pf")
    motor_blk = motor(pkg, dt, "Motor", "driveMotor/pf")
    grip_cs = gripper_control(pkg, dt)
    finger_ctrl = motor_controller(pkg, dt, "FingerController", "regulateFinger/pf")
    finger_motor = motor(pkg, dt, "FingerMotor", "driveFinger/pf")

    # Structure (Figs. 8 and 10)
    robot_part = system.part("pickAndPlace/r", robot)
    task_part = system.part("task/a", task_agent)
    manip_part = robot.part("manip/a", manip_agent)
    grip_part = robot.part("grip/a", grip_agent)
    task_cs_part = task_agent.part("cs", task_cs)

    manip_cs_part = manip_agent.part("cs", manip_cs)
    mc_part = manip_agent.part("motorControllerK/ve", motor_ctrl, N_JOINTS)
    motor_part = manip_agent.part("motorK/re", motor_blk, N_JOINTS)
    link(manip_agent, (manip_cs_part, "motorControllerCommandK/ob"), (mc_part, "motorControllerCommand/ib"), kit.end_at)
    link(manip_agent, (mc_part, "motorControllerState/ob"), (manip_cs_part, "motorControllerStateK/ib"), kit.end_at)
    link(manip_agent, (mc_part, "desiredCurrent/ob"), (motor_part, "desiredCurrent/ib"), kit.end_at)
    link(manip_agent, (motor_part, "encoder/ob"), (mc_part, "encoder/ib"), kit.end_at)

    grip_cs_part = grip_agent.part("cs", grip_cs)
    finger_ctrl_part = grip_agent.part("fingerController/ve", finger_ctrl)
    finger_motor_part = grip_agent.part("fingerMotor/re", finger_motor)
    link(grip_agent, (grip_cs_part, "fingerCommand/ob"), (finger_ctrl_part, "motorControllerCommand/ib"), kit.end_at)
    link(grip_agent, (finger_ctrl_part, "motorControllerState/ob"), (grip_cs_part, "fingerState/ib"), kit.end_at)
    link(grip_agent, (finger_ctrl_part, "desiredCurrent/ob"), (finger_motor_part, "desiredCurrent/ib"), kit.end_at)
    link(grip_agent, (finger_motor_part, "encoder/ob"), (finger_ctrl_part, "encoder/ib"), kit.end_at)

    # Inter-agent links (Fig. 9): ends reach the cs ports through nested parts.
    task_path = (task_part, task_cs_part)
    manip_path = (robot_part, manip_part, manip_cs_part)
    grip_path = (robot_part, grip_part, grip_cs_part)
    ends = {
        "task/a": (task_cs, task_path),
        "manip/a": (manip_cs, manip_path),
        "grip/a": (grip_cs, grip_path),
    }
    for source, target, message in (
        ("task/a", "manip/a", "manipulatorCommand"),
        ("manip/a", "task/a", "manipulatorState"),
        ("task/a", "grip/a", "gripperCommand"),
        ("grip/a", "task/a", "gripperStatus"),
    ):
        inter_agent_link(system, f"{source},{target}", ends[source], ends[target], message, kit.end_at)
    # The property `earl-m2t verify` proves (docs/verify.md): once manip/a.cs is in its
    # emergency stop, it stays there.
    system.ltl_property("estopLatches", ESTOP_LATCHES)
    return mb.to_bytes()


def renamed_stereotypes(ea_xml: bytes, names: Mapping[str, tuple[str, str]]) -> bytes:
    """The EA export with the EARL stereotypes of ``names`` applied under other names, in the
    applications (``<EARL:Agent …/>``) and in EA's own record of them (``FQName=EARL::Agent``)."""
    text = ea_xml.decode("windows-1252")
    for concept, (prefix, name) in names.items():
        text = re.sub(rf"<EARL:{concept}(?=[ />])", f"<{prefix}:{name}", text)
        text = text.replace(f"@STEREO;Name={concept};FQName=EARL::{concept};",
                            f"@STEREO;Name={name};FQName={prefix}::{name};")
    if any(prefix == "SPSys" for prefix, _ in names.values()):
        text = text.replace(' xmlns:EARL="', f' xmlns:SPSys="{SPSYS_NS}" xmlns:EARL="', 1)
    return text.encode("windows-1252")


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else list(argv)
    status = write_dialects(args, FILES, build, ROOT)
    if status == 0 and not args:
        VARIANT_DIR.mkdir(exist_ok=True)
        ea_xml = FILES["ea"].read_bytes()
        for name, names in VARIANTS.items():
            (VARIANT_DIR / name).write_bytes(renamed_stereotypes(ea_xml, names))
            print(f"wrote {(VARIANT_DIR / name).relative_to(ROOT)}")
    return status


if __name__ == "__main__":
    raise SystemExit(main())
