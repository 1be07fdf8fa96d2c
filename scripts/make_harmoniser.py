"""Write the variable-structure sample ``samples/harmoniser/`` in three tool dialects.

A TIAGo-like service robot harmonises two tasks: it guides a person, and when the person falls
it drops the guiding and responds to the fall, then takes the guiding up again where it stopped.
The harmoniser agent ``tha/a`` is the coordinator; the two task agents ``guide/a`` and
``fallHelp/a`` (multiplicity ``[0..1]``, «Agent» tag ``reactivation = resume``) are present
only in the configuration that names them, ``guiding`` or ``fallResponse``; in ``none`` neither
is. The robot's agent ``tiago/a`` (a mobile base, an arm and a lidar) is always present; its
lidar sees the fall and its control subsystem raises the alarm to ``tha/a``.

The content is built once against the builder interface of ``tests/support/sample_kit.py``
and written the way each tool saves a model:

- ``harmoniser.uml``: Eclipse Papyrus 6.x with SysML 1.6 (Eclipse UML2 5.x XMI); the EARL
  profile is the one beside the reference sample, ``../pick_and_place/EARL.profile.uml``;
- ``harmoniser.cameo.xmi``: Cameo Systems Modeler 2022x native project XMI;
- ``harmoniser.ea.xml``: Enterprise Architect 16 "XMI 2.1" export (windows-1252).

``harmoniser.sysml``, the same model in SysML v2 text, is written by hand.

Usage: ``python scripts/make_harmoniser.py`` writes the three files;
``python scripts/make_harmoniser.py [--dialect papyrus|cameo|ea] OUTPUT`` writes one of them
to ``OUTPUT`` (Papyrus by default). The output is deterministic.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
TASK_QUEUE = 256  # tiago/a.cs's queue of task commands: a task phase's commands, should the robot be starved
TIAGO_ACTIVATION = {"bufferGroup": "tasks", "minPeriod": "0.0005", "firstTimeout": "0.002", "nextTimeout": "0.002"}
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.support.sample_kit import (  # noqa: E402
    Block,
    Package,
    Property,
    inter_agent_link,
    link,
    single_state,
    start_model,
    write_dialects,
)

SAMPLE_DIR = ROOT / "samples" / "harmoniser"
FILES = {
    "papyrus": SAMPLE_DIR / "harmoniser.uml",
    "cameo": SAMPLE_DIR / "harmoniser.cameo.xmi",
    "ea": SAMPLE_DIR / "harmoniser.ea.xml",
}
PAPYRUS_PROFILE = "../pick_and_place/EARL.profile.uml"

ARM_JOINTS = 7
SCAN_RAYS = 32
SWITCH_TIMEOUT = 0.5  # s: a switch that has not drained by then stops the leaving task agent anyway
GUIDE_OFF_IN_FALL_RESPONSE = "[] (config@fallResponse -> !guide/a@active)"
# the task agents, by the configuration that brings each one in with its links to and from tiago/a.cs
TASKS = {"guiding": "guide/a", "fallResponse": "fallHelp/a"}


class DataTypes:
    """The DataTypes package: the messages between the agents and inside tiago/a."""

    def __init__(self, pkg: Package, real: Any, boolean: Any, integer: Any) -> None:
        self.real, self.boolean, self.integer = real, boolean, integer
        self.base_velocity = pkg.data_type("BaseVelocity")
        self.base_velocity.field("vx", real)
        self.base_velocity.field("wz", real)
        self.joint_position = pkg.data_type("JointPosition")
        self.joint_position.field("q", real, ARM_JOINTS)
        self.laser_scan = pkg.data_type("LaserScan")
        self.laser_scan.field("ranges", real, SCAN_RAYS)
        self.person_state = pkg.data_type("PersonState")
        self.person_state.field("x", real)
        self.person_state.field("y", real)
        self.person_state.field("fallen", boolean)
        self.task_command = pkg.data_type("TaskCommand")
        self.task_command.field("seq", integer)
        self.task_command.field("base", self.base_velocity)
        self.task_command.field("arm", self.joint_position)
        self.robot_status = pkg.data_type("RobotStatus")
        self.robot_status.field("lastSeq", integer)
        self.robot_status.field("person", self.person_state)
        self.fall_alarm = pkg.data_type("FallAlarm")
        self.fall_alarm.field("fallen", boolean)


# ---- tiago/a: the robot's agent --------------------------------------------------------------


def virtual_effector(pkg: Package, name: str, command: Any, drive: Any, pf_name: str, body: str) -> Block:
    """A virtual effector: takes tiago/a.cs's ``command/ib``, drives its real effector
    (``drive/ob``) and reads its ``feedback/ib``."""
    ve = pkg.block(name, "VirtualEffector")
    cmd = ve.input_buffer("command/ib", command)
    out = ve.output_buffer("drive/ob", drive)
    feedback = ve.input_buffer("feedback/ib", drive)
    pf = ve.partial_transition_function(pf_name, reads=[cmd, feedback], writes=[out], body=body)
    single_state(ve, "regulate", pf)
    return ve


def real_effector(pkg: Package, name: str, drive: Any, pf_name: str, body: str) -> Block:
    """A real effector: the driver of the hardware, ``drive/ib`` in and ``feedback/ob`` out."""
    re = pkg.block(name, "RealEffector")
    cmd = re.input_buffer("drive/ib", drive)
    feedback = re.output_buffer("feedback/ob", drive)
    pf = re.partial_transition_function(pf_name, reads=[cmd], writes=[feedback], body=body)
    single_state(re, "drive", pf)
    return re


def tiago_control(pkg: Package, dt: DataTypes) -> Block:
    """tiago/a.cs: carries out the task agent's commands and raises the fall alarm."""
    cs = pkg.block("TiagoControl", "ControlSubsystem")
    task = cs.input_buffer("taskCommand/ib", dt.task_command)
    # every command of the task agents is carried out once, in order, those a leaving agent
    # sends in its last iterations included: they queue (one taken per iteration)
    task.stereotype("InputBuffer", {"receive": "queue", "queueSize": TASK_QUEUE})
    person = cs.input_buffer("person/ib", dt.person_state)
    base = cs.output_buffer("baseCommand/ob", dt.base_velocity)
    arm = cs.output_buffer("armCommand/ob", dt.joint_position)
    status = cs.output_buffer("robotStatus/ob", dt.robot_status)
    alarm = cs.output_buffer("fallAlarm/ob", dt.fall_alarm)
    pf = cs.partial_transition_function(
        "control/pf",
        reads=[task, person],
        writes=[base, arm, status, alarm],
        body="// Passes the task agent's base and arm setpoints on, reports the robot and the person it sees "
             "and raises the fall alarm while the person lies on the floor.",
    )  # fmt: skip
    # each command activates an iteration, at most one per half period of the task agents, so
    # that the queue drains what a starved robot let pile up; without one, every 2 ms
    cs.buffer_group("tasks", obligatory=[task])
    operate = cs.state_machine().state("operate", initial=True)
    operate.do_activity(tc="FALSE", ec="FALSE").stages([[pf]])
    operate.stereotype("FsmState", TIAGO_ACTIVATION)
    return cs


def tiago_agent(pkg: Package, dt: DataTypes, end_at: Callable[..., Any]) -> tuple[Block, Block, Property]:
    """The block TiagoAgent (CERT) with its subsystems and their links; its control subsystem's
    block and part."""
    agent = pkg.block("TiagoAgent", "Agent", {"declaredType": "CERT"})
    agent.comment("tiago/a: the robot's control subsystem, its mobile base and arm, and its lidar.")
    cs = tiago_control(pkg, dt)
    base_ve = virtual_effector(pkg, "BaseController", dt.base_velocity, dt.base_velocity, "regulateBase/pf",
                               "// Wheel speeds from the commanded base velocity and the odometry.")
    base_re = real_effector(pkg, "BaseDriver", dt.base_velocity, "driveBase/pf",
                            "// Sets the wheel speeds on the hardware and reads the odometry.")
    arm_ve = virtual_effector(pkg, "ArmController", dt.joint_position, dt.joint_position, "regulateArm/pf",
                              "// Joint setpoints interpolated towards the commanded arm pose.")
    arm_re = real_effector(pkg, "ArmDriver", dt.joint_position, "driveArm/pf",
                           "// Sets the joint setpoints on the hardware and reads the joint positions.")
    lidar_rr = pkg.block("LidarDriver", "RealReceptor")
    raw = lidar_rr.output_buffer("scan/ob", dt.laser_scan)
    single_state(lidar_rr, "sense", lidar_rr.partial_transition_function(
        "readScan/pf", writes=[raw], body="// Reads one scan from the lidar."))
    lidar_vr = pkg.block("PersonDetector", "VirtualReceptor")
    scan = lidar_vr.input_buffer("scan/ib", dt.laser_scan)
    person = lidar_vr.output_buffer("person/ob", dt.person_state)
    single_state(lidar_vr, "detect", lidar_vr.partial_transition_function(
        "detectPerson/pf", reads=[scan], writes=[person],
        body="// Finds the person in the scan: where they are and whether they lie on the floor."))

    cs_part = agent.part("cs", cs)
    base_ve_part = agent.part("base/ve", base_ve)
    base_re_part = agent.part("base/re", base_re)
    arm_ve_part = agent.part("arm/ve", arm_ve)
    arm_re_part = agent.part("arm/re", arm_re)
    lidar_vr_part = agent.part("lidar/vr", lidar_vr)
    lidar_rr_part = agent.part("lidar/rr", lidar_rr)
    links = (
        ((cs_part, "baseCommand/ob"), (base_ve_part, "command/ib")),
        ((base_ve_part, "drive/ob"), (base_re_part, "drive/ib")),
        ((base_re_part, "feedback/ob"), (base_ve_part, "feedback/ib")),
        ((cs_part, "armCommand/ob"), (arm_ve_part, "command/ib")),
        ((arm_ve_part, "drive/ob"), (arm_re_part, "drive/ib")),
        ((arm_re_part, "feedback/ob"), (arm_ve_part, "feedback/ib")),
        ((lidar_rr_part, "scan/ob"), (lidar_vr_part, "scan/ib")),
        ((lidar_vr_part, "person/ob"), (cs_part, "person/ib")),
    )
    for source, target in links:
        link(agent, source, target, end_at)
    return agent, cs, cs_part


# ---- tha/a, the coordinator, and the two task agents -----------------------------------------


def harmoniser_control(pkg: Package, dt: DataTypes) -> Block:
    """tha/a.cs, the coordinator: guides the person, and responds to a fall while one lasts."""
    cs = pkg.block("HarmoniserControl", "ControlSubsystem")
    alarm = cs.input_buffer("fallAlarm/ib", dt.fall_alarm)
    falls = cs.memory("falls/m", dt.integer)
    cs.primitive_predicate("fall/pp", "fallAlarm/ib.msg.fallen")
    monitor = cs.partial_transition_function(
        "monitor/pf", reads=[alarm, falls], writes=[falls],
        body="// Counts the falls: one more each time the alarm rises.",
    )  # fmt: skip

    fsm = cs.state_machine()
    idle = fsm.state("idle", initial=True)
    guiding = fsm.state("guiding")
    fall_response = fsm.state("fallResponse")
    fsm.transition(idle, guiding, "¬fall/pp.fun")
    fsm.transition(guiding, fall_response, "fall/pp.fun")
    fsm.transition(fall_response, guiding, "¬fall/pp.fun")
    for st, tc, configuration in ((idle, "¬fall/pp.fun", "none"), (guiding, "fall/pp.fun", "guiding"),
                                  (fall_response, "¬fall/pp.fun", "fallResponse")):
        st.do_activity(tc=tc, ec="FALSE").stages([[monitor]])
        st.stereotype("FsmState", {"configuration": configuration})
    return cs


def task_control(pkg: Package, dt: DataTypes, name: str, active: str, progress: str,
                 work: tuple[str, str], rest: tuple[str, str]) -> Block:
    """The control subsystem of a task agent: ``waiting`` (initial, quiescent) and ``active``.

    While a switch removes the agent (``leaving()``), ``active`` ends and the agent goes to
    ``waiting``, whose ``rest`` pf stops what it commanded and takes the robot's status (a value
    left in an input would hold the switch until its timeout); there the switch stops it. Brought
    back (``reactivation = resume``), it is still in ``waiting`` with its memory, ``progress``
    included, and goes on from there."""
    cs = pkg.block(name, "ControlSubsystem")
    status = cs.input_buffer("robotStatus/ib", dt.robot_status)
    command = cs.output_buffer("taskCommand/ob", dt.task_command)
    seq = cs.memory("seq/m", dt.integer)
    done = cs.memory(progress, dt.integer)
    work_pf = cs.partial_transition_function(work[0], reads=[status, seq, done], writes=[command, seq, done],
                                             body=work[1])
    # the rest pf reads the status too: waiting, where a switch stops the agent, takes what tiago/a sent
    rest_pf = cs.partial_transition_function(rest[0], reads=[status, seq], writes=[command, seq], body=rest[1])

    fsm = cs.state_machine()
    waiting = fsm.state("waiting", initial=True)
    working = fsm.state(active)
    fsm.transition(waiting, working, "¬leaving()")
    fsm.transition(working, waiting, "leaving()")
    waiting.do_activity(tc="¬leaving()", ec="FALSE").stages([[rest_pf]])
    working.do_activity(tc="leaving()", ec="FALSE").stages([[work_pf]])
    waiting.stereotype("FsmState", {"quiescent": True})
    return cs


def build(stereotypes: bool = True, dialect: str = "papyrus") -> bytes:
    """Build the sample in ``dialect`` and return its XMI; ``stereotypes=False`` gives the
    suffix-only variant."""
    kit, mb = start_model(dialect, "Harmoniser", stereotypes, PAPYRUS_PROFILE)
    mb.comment(
        "Task harmonisation on a TIAGo-like robot: a harmoniser agent brings in the agent of the task in hand, "
        "guiding a person or responding to their fall; the system's structure varies with the task."
    )
    dt = DataTypes(mb.package("DataTypes"), kit.real, kit.boolean, kit.integer)
    pkg = mb.package("SystemInstance")

    system = pkg.block("HarmoniserSystem", "System")
    robot = pkg.block("Tiago", "Robot")
    tha_agent = pkg.block("HarmoniserAgent", "Agent", {"declaredType": "CT"})
    tha_agent.comment("tha/a names, in each state of its control subsystem, the task agent it needs.")
    tiago, tiago_cs, tiago_cs_part = tiago_agent(pkg, dt, kit.end_at)
    guide_agent = pkg.block("GuideAgent", "Agent", {"declaredType": "CT", "reactivation": "resume"})
    guide_agent.comment("guide/a leads the person along a route; resumed where it stopped after a fall.")
    help_agent = pkg.block("FallHelpAgent", "Agent", {"declaredType": "CT", "reactivation": "resume"})
    help_agent.comment("fallHelp/a responds to a fall: it brings the robot to the person and offers the arm.")
    tha_cs = harmoniser_control(pkg, dt)
    guide_cs = task_control(
        pkg, dt, "GuideControl", "leading", "waypoint/m",
        ("lead/pf", "// Base velocity towards the next waypoint of the route, the person following; one waypoint "
                    "more when it is reached."),
        ("park/pf", "// Stops the base (and apologises to the person): the guiding is suspended."),
    )
    help_cs = task_control(
        pkg, dt, "FallHelpControl", "helping", "step/m",
        ("assist/pf", "// Brings the robot next to the person and holds the arm out for them; one step more "
                      "each time one is done."),
        ("standBy/pf", "// Stops the base and folds the arm."),
    )

    robot_part = system.part("tiago/r", robot)
    tha_part = system.part("tha/a", tha_agent)
    guide_part = system.part("guide/a", guide_agent, "0..1")
    help_part = system.part("fallHelp/a", help_agent, "0..1")
    tiago_part = robot.part("tiago/a", tiago)

    ends: dict[str, tuple[Block, tuple[Property, ...]]] = {
        "tiago/a": (tiago_cs, (robot_part, tiago_part, tiago_cs_part)),
        "tha/a": (tha_cs, (tha_part, tha_agent.part("cs", tha_cs))),
        "guide/a": (guide_cs, (guide_part, guide_agent.part("cs", guide_cs))),
        "fallHelp/a": (help_cs, (help_part, help_agent.part("cs", help_cs))),
    }
    inter_agent_link(system, "tiago/a,tha/a", ends["tiago/a"], ends["tha/a"], "fallAlarm", kit.end_at)
    for task in TASKS.values():
        inter_agent_link(system, f"{task},tiago/a", ends[task], ends["tiago/a"], "taskCommand", kit.end_at)
        inter_agent_link(system, f"tiago/a,{task}", ends["tiago/a"], ends[task], "robotStatus", kit.end_at)
    system.configuration("none", switch_timeout=SWITCH_TIMEOUT)
    for name, task in TASKS.items():
        system.configuration(name, agents=[task], links=[f"{task},tiago/a", f"tiago/a,{task}"],
                             switch_timeout=SWITCH_TIMEOUT)
    # A property `earl-m2t verify` proves: while fallResponse holds, guide/a does not run.
    system.ltl_property("guideOffInFallResponse", GUIDE_OFF_IN_FALL_RESPONSE)
    return mb.to_bytes()


def main(argv: list[str] | None = None) -> int:
    return write_dialects(sys.argv[1:] if argv is None else argv, FILES, build, ROOT)


if __name__ == "__main__":
    raise SystemExit(main())
