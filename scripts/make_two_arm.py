"""Write the variable-structure sample ``samples/two_arm/`` in three tool dialects.

A task agent hands a job over between two manipulators, again and again: the system's
structure varies at run time (the EARL paper's Dynamic Variability). The general model
holds both manipulator agents, ``manipA/a`` and ``manipB/a`` (one block, multiplicity
``[0..1]``), and the four inter-agent links; the System block's two «Configuration»
constraints, ``useA`` and ``useB``, say which manipulator and which links are present, and
the states of task/a.cs name the configuration they need (task/a.cs is the coordinator).

The content is built once against the builder interface of ``tests/support/sample_kit.py``
and written the way each tool saves a model:

- ``two_arm.uml``: Eclipse Papyrus 6.x with SysML 1.6 (Eclipse UML2 5.x XMI); the EARL
  profile is the one beside the reference sample, ``../pick_and_place/EARL.profile.uml``;
- ``two_arm.cameo.xmi``: Cameo Systems Modeler 2022x native project XMI;
- ``two_arm.ea.xml``: Enterprise Architect 16 "XMI 2.1" export (windows-1252).

``two_arm.sysml``, the same model in SysML v2 text, is written by hand.

Usage: ``python scripts/make_two_arm.py`` writes the three files;
``python scripts/make_two_arm.py [--dialect papyrus|cameo|ea] OUTPUT`` writes one of them to
``OUTPUT`` (Papyrus by default). The output is deterministic.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.support.sample_kit import (  # noqa: E402
    Block,
    Package,
    Property,
    inter_agent_link,
    start_model,
    write_dialects,
)

SAMPLE_DIR = ROOT / "samples" / "two_arm"
FILES = {
    "papyrus": SAMPLE_DIR / "two_arm.uml",
    "cameo": SAMPLE_DIR / "two_arm.cameo.xmi",
    "ea": SAMPLE_DIR / "two_arm.ea.xml",
}
PAPYRUS_PROFILE = "../pick_and_place/EARL.profile.uml"

N_JOINTS = 6
COMMANDS_PER_ARM = 10  # task/a hands the job over after this many commands to one arm ...
HAND_OVERS = 20  # ... and has finished after this many hand-overs
COMMAND_QUEUE = 32  # manipX/a.cs's manipulatorCommand/ib: task/a's commands, in order
SWITCH_TIMEOUT = 0.1  # s: a switch that has not drained by then stops the leaving arm anyway
ARM_A_OFF_IN_USE_B = "[] (config@useB -> !manipA/a@active)"
# every state of a manipulator's cs: an iteration per command of task/a (waiting at most 100 ms
# on entering a state, 20 ms later), at most one per 0.5 ms, so that it catches up when behind
MANIPULATOR_ACTIVATION = {"bufferGroup": "commands", "minPeriod": "0.0005", "firstTimeout": "0.1",
                          "nextTimeout": "0.02"}

# Conditions of manipX/a.cs: a command is new when it arrived and carries a seq beyond the last
# one taken (task/a repeats its last command once it has finished). While a switch removes the
# arm (leaving()), moving ends at every iteration: a new command still continues the motion
# (moving,moving/t wins by its priority), so the arm takes every command queued for it, and
# once none is left it goes back to idle, where the switch stops it.
NEW_COMMAND = "newData(manipulatorCommand/ib.msg.seq) ∧ manipulatorCommand/ib.msg.seq > lastSeq/mi.data"
MOVING_TC = "motionFinished/pp.fun ∨ newCommand/pp.fun ∨ leaving()"
NEXT_COMMAND = "newCommand/pp.fun"
STOP_MOVING = "leaving() ∨ ¬newCommand/pp.fun"


class DataTypes:
    """The DataTypes package: the messages between task/a and the manipulators."""

    def __init__(self, pkg: Package, real: Any, boolean: Any, integer: Any) -> None:
        self.real, self.boolean, self.integer = real, boolean, integer
        self.joint_position = pkg.data_type("JointPosition")
        self.joint_position.field("q", real, N_JOINTS)
        self.manipulator_command = pkg.data_type("ManipulatorCommand")
        self.manipulator_command.field("seq", integer)
        self.manipulator_command.field("jointPosSetpoint", self.joint_position)
        self.manipulator_state = pkg.data_type("ManipulatorState")
        self.manipulator_state.field("lastSeq", integer)
        self.manipulator_state.field("busy", boolean)


def task_control(pkg: Package, dt: DataTypes) -> Block:
    """task/a.cs, the coordinator: commands one arm at a time and hands the job over."""
    cs = pkg.block("TaskControl", "ControlSubsystem")
    command = cs.output_buffer("manipulatorCommand/ob", dt.manipulator_command)
    state = cs.input_buffer("manipulatorState/ib", dt.manipulator_state)
    next_seq = cs.memory("nextSeq/m", dt.integer)
    sent = cs.memory("sentToArm/m", dt.integer)
    hand_overs = cs.memory("handOvers/m", dt.integer)

    cs.primitive_predicate("handOver/pp", f"sentToArm/mi.data >= {COMMANDS_PER_ARM}")
    cs.primitive_predicate("allHandedOver/pp", f"handOvers/mi.data >= {HAND_OVERS}")
    send = cs.partial_transition_function(
        "sendCommand/pf",
        reads=[state, next_seq, sent, hand_overs],
        writes=[command, next_seq, sent, hand_overs],
        body=f"// Sends command number nextSeq with the next setpoint to the arm in use; counts the commands "
             f"sent to it (from 1 again, and one hand-over more, after the {COMMANDS_PER_ARM}th).",
    )
    hold = cs.partial_transition_function(
        "holdCommand/pf",
        reads=[next_seq],
        writes=[command],
        body="// Repeats the last command sent, its seq unchanged: the arm in use holds its setpoint.",
    )

    fsm = cs.state_machine()
    with_a = fsm.state("withA", initial=True)
    with_b = fsm.state("withB")
    finished = fsm.state("finished")
    fsm.transition(with_a, with_b, "handOver/pp.fun")
    fsm.transition(with_b, with_a, "handOver/pp.fun")
    fsm.transition(with_a, finished, "allHandedOver/pp.fun", priority=1)
    fsm.transition(with_b, finished, "allHandedOver/pp.fun", priority=1)
    for st, configuration in ((with_a, "useA"), (with_b, "useB")):
        st.do_activity(tc="handOver/pp.fun ∨ allHandedOver/pp.fun", ec="FALSE").stages([[send]])
        st.stereotype("FsmState", {"configuration": configuration})
    # no configuration: finished keeps the one it is entered with
    finished.do_activity(tc="FALSE", ec="FALSE").stages([[hold]])
    return cs


def manipulator_control(pkg: Package, dt: DataTypes) -> Block:
    """manipX/a.cs: moves the arm to each commanded setpoint; idle is where it may be switched off."""
    cs = pkg.block("ManipulatorControl", "ControlSubsystem")
    command = cs.input_buffer("manipulatorCommand/ib", dt.manipulator_command)
    state = cs.output_buffer("manipulatorState/ob", dt.manipulator_state)
    last_seq = cs.memory("lastSeq/m", dt.integer)
    joint_pos = cs.memory("jointPos/m", dt.joint_position)
    finished = cs.memory("motionFinished/m", dt.boolean)

    cs.primitive_predicate("newCommand/pp", NEW_COMMAND)
    cs.primitive_predicate("motionFinished/pp", "motionFinished/mi.data")
    move = cs.partial_transition_function(
        "moveArm/pf",
        reads=[command, joint_pos],
        writes=[joint_pos, last_seq, finished],
        body="// Takes the command (its seq and setpoint) and moves the joints a step towards the setpoint.",
    )
    output = cs.partial_transition_function(
        "outputState/pf",
        reads=[last_seq, finished],
        writes=[state],
        body="// Composes ManipulatorState: the seq of the last command taken, busy while moving.",
    )

    # Every command activates one iteration, in order, in every state: the queue drains whatever
    # the state, so a manipulator that leaves the structure can always empty its input.
    command.stereotype("InputBuffer", {"receive": "queue", "queueSize": COMMAND_QUEUE})
    cs.buffer_group("commands", obligatory=[command])

    fsm = cs.state_machine()
    idle = fsm.state("idle", initial=True)
    moving = fsm.state("moving")
    fsm.transition(idle, moving, "newCommand/pp.fun")
    fsm.transition(moving, moving, NEXT_COMMAND, priority=1)
    fsm.transition(moving, idle, STOP_MOVING)
    idle.do_activity(tc="newCommand/pp.fun", ec="FALSE").stages([[output]])
    moving.do_activity(tc=MOVING_TC, ec="FALSE").stages([[move], [output]])
    idle.stereotype("FsmState", {**MANIPULATOR_ACTIVATION, "quiescent": True})
    moving.stereotype("FsmState", MANIPULATOR_ACTIVATION)
    return cs


def build(stereotypes: bool = True, dialect: str = "papyrus") -> bytes:
    """Build the sample in ``dialect`` and return its XMI; ``stereotypes=False`` gives the
    suffix-only variant."""
    kit, mb = start_model(dialect, "TwoArm", stereotypes, PAPYRUS_PROFILE)
    mb.comment(
        "Two-arm hand-over cell: a task agent commands one of two manipulator agents at a time and hands the "
        f"job over between them {HAND_OVERS} times; the system's structure varies with the arm in use."
    )
    dt = DataTypes(mb.package("DataTypes"), kit.real, kit.boolean, kit.integer)
    pkg = mb.package("SystemInstance")

    system = pkg.block("TwoArmCell", "System")
    cell = pkg.block("Cell", "Robot")
    task_agent = pkg.block("TaskAgent", "Agent", {"declaredType": "CT"})
    task_agent.comment("task/a numbers its commands and sends them to the arm of the configuration in use.")
    manip_agent = pkg.block("ManipulatorAgent", "Agent", {"declaredType": "CT"})
    manip_agent.comment(
        "manipA/a and manipB/a: one block, so both arms share their definitions; restarted (FSM at idle, memory "
        "and inputs reset) each time a switch brings one back."
    )
    task_cs = task_control(pkg, dt)
    manip_cs = manipulator_control(pkg, dt)

    cell_part = system.part("cell/r", cell)
    task_part = system.part("task/a", task_agent)
    arm_a = cell.part("manipA/a", manip_agent, "0..1")
    arm_b = cell.part("manipB/a", manip_agent, "0..1")
    task_cs_part = task_agent.part("cs", task_cs)
    manip_cs_part = manip_agent.part("cs", manip_cs)

    ends: dict[str, tuple[Block, tuple[Property, ...]]] = {
        "task/a": (task_cs, (task_part, task_cs_part)),
        "manipA/a": (manip_cs, (cell_part, arm_a, manip_cs_part)),
        "manipB/a": (manip_cs, (cell_part, arm_b, manip_cs_part)),
    }
    for arm in ("manipA/a", "manipB/a"):
        inter_agent_link(system, f"task/a,{arm}", ends["task/a"], ends[arm], "manipulatorCommand", kit.end_at)
        inter_agent_link(system, f"{arm},task/a", ends[arm], ends["task/a"], "manipulatorState", kit.end_at)
    for name, arm in (("useA", "manipA/a"), ("useB", "manipB/a")):
        system.configuration(name, agents=[arm], links=[f"task/a,{arm}", f"{arm},task/a"],
                             switch_timeout=SWITCH_TIMEOUT)
    # A property `earl-m2t verify` proves: while useB holds, manipA/a does not run.
    system.ltl_property("armAOffInUseB", ARM_A_OFF_IN_USE_B)
    return mb.to_bytes()


def main(argv: list[str] | None = None) -> int:
    return write_dialects(sys.argv[1:] if argv is None else argv, FILES, build, ROOT)


if __name__ == "__main__":
    raise SystemExit(main())
