"""Generate large, valid EARL models in the Papyrus dialect for the benchmark.

    python bench/generate.py --agents A --subsystems S --behaviours B -o bench/out/model.uml
    python bench/generate.py --target-mb 100 -o bench/out/model_100mb.uml

The model is written with ``tests/support/papyrus_builder.py`` (the same builder the test
suite uses), so it is the XMI Papyrus saves: ``uml:Model`` with a ``DataTypes`` and a
``SystemInstance`` package, ``Blocks:Block`` and ``EARL:*`` stereotype applications after
the model, ids derived from each element's qualified path (the output is byte-identical
from run to run).

The shape follows the reference sample ``samples/pick_and_place/pick_and_place.uml``:

* a System block; agent 1 sits directly in it (like ``task/a``), the other agents sit in
  Robot blocks of up to four agents (like ``manip/a`` and ``grip/a`` in ``pickAndPlace/r``;
  a one-agent model puts its agent in a robot, since a System needs one);
* every agent is like ``manip/a``: a control subsystem ``cs`` and ``S`` (``--subsystems``) pairs of a virtual
  effector ``jointNController/ve`` and a real effector ``jointNMotor/re``, linked
  ``cs ⇄ ve ⇄ re`` by four inter-subsystem links per pair;
* agents form a supervision tree (fan-out 3); each supervisor's ``cs`` sends a command to
  and receives a status from each supervised agent's ``cs`` (two inter-agent links, with
  ``Blocks:NestedConnectorEnd`` property paths, like ``task/a ⇄ manip/a``);
* every subsystem has its own block: buffers (ports), internal memory, primitive
  predicates in the EARL predicate language, partial transition functions with their
  parameters and an FSM of ``B`` (``--behaviours``) states (``idle``, ``B - 2`` modes, a
  stop state), each with a basic behaviour (``tc``/``ec`` rules, a two-stage transition
  function of fork/join calls) and guarded, prioritised transitions; the control
  subsystem also has a replicated memory (``jointTorqueK/m [S]``, read with ``any K:``)
  and an exclusion of its mode predicates; some predicates compare with thresholds that
  differ from subsystem to subsystem, so condition texts are not all alike;
* dataTypes: a few shared message types plus three per agent (joint position, command,
  status).

``earl-m2t check`` reports nothing on these models (0 errors, 0 warnings, 0 info).
``--describe FILE`` prints the element mix of any model file (element kinds per MB), to
compare a generated model with the sample.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.support.papyrus_builder import (  # noqa: E402  (after the path set-up)
    BOOLEAN,
    INTEGER,
    REAL,
    Block,
    End,
    ModelBuilder,
    OpaqueBehavior,
)

DEFAULT_SUBSYSTEMS = 4  # ve/re pairs per agent in --target-mb mode
DEFAULT_BEHAVIOURS = 4  # FSM states (and basic behaviours) per subsystem in --target-mb mode
FAN_OUT = 3  # agents supervised by one agent
AGENTS_PER_ROBOT = 4

CS_MODES = ("jointMove", "operationalMove", "approach", "grasp", "place", "follow", "homing", "calibrate")
VE_MODES = ("position", "velocity", "torque", "impedance", "admittance", "gravityComp", "friction", "trajectory")
RE_MODES = ("drive", "brake", "coast", "boost", "regenerate", "hold", "pulse", "ramp")


def _modes(pool: tuple[str, ...], count: int) -> list[str]:
    """``count`` distinct mode names: the pool first, then the pool again with a number."""
    names = []
    for k in range(count):
        base = pool[k % len(pool)]
        names.append(base if k < len(pool) else f"{base}{k // len(pool) + 1}")
    return names


def _cap(name: str) -> str:
    return name[0].upper() + name[1:]


def _threshold(*indices: int) -> str:
    """A deterministic, varied numeric literal, so that condition texts differ between subsystems."""
    value = 0
    for index in indices:
        value = (value * 131 + index * 17 + 7) % 9973
    return f"{value % 90 + 10}.{value % 7}"


def _or(*terms: str) -> str:
    return " ∨ ".join(terms)


class _Generator:
    def __init__(self, agents: int, subsystems: int, behaviours: int, name: str) -> None:
        if agents < 1 or subsystems < 1 or behaviours < 1:
            raise ValueError("--agents, --subsystems and --behaviours must be at least 1")
        self.n_agents = agents
        self.n_pairs = subsystems
        self.n_states = behaviours
        self.mb = ModelBuilder(name)

    # ---- data types ---------------------------------------------------------------------

    def _shared_types(self) -> None:
        types = self.types
        vector = types.data_type("Vector3")
        for axis in "xyz":
            vector.field(axis, REAL)
        quaternion = types.data_type("Quaternion")
        for axis in "xyzw":
            quaternion.field(axis, REAL)
        self.oper_position = types.data_type("OperPosition")
        self.oper_position.field("position", vector)
        self.oper_position.field("orientation", quaternion)
        self.mc_command = types.data_type("MotorControllerCommand")
        self.mc_command.field("desiredPosition", REAL)
        self.mc_command.field("mode", INTEGER)
        self.mc_command.field("emergencyStopCommand", BOOLEAN)
        self.mc_state = types.data_type("MotorControllerState")
        self.mc_state.field("motorPos", REAL)
        self.mc_state.field("windingCurrent", REAL)
        self.mc_state.field("emergencyStop", BOOLEAN)
        self.gains = types.data_type("PidGains")
        for gain in ("kp", "ki", "kd"):
            self.gains.field(gain, REAL)
        self.current = types.data_type("MotorCurrent")
        self.current.field("current", REAL)
        self.current.field("mode", INTEGER)
        self.encoder = types.data_type("EncoderReading")
        self.encoder.field("position", REAL)
        self.encoder.field("velocity", REAL)

    def _agent_types(self, i: int) -> dict:
        types = self.types
        joints = types.data_type(f"Agent{i}JointPosition")
        joints.field("q", REAL, self.n_pairs)
        command = types.data_type(f"Agent{i}Command")
        for mode in _modes(CS_MODES, max(self.n_states - 2, 0)):
            command.field(f"{mode}Setpoint", joints, "0..1")
        command.field("operationalPosSetpoint", self.oper_position, "0..1")
        command.field("emergencyStopCommand", BOOLEAN)
        status = types.data_type(f"Agent{i}Status")
        status.field("currentJointPos", joints)
        status.field("currentOperationalPos", self.oper_position)
        status.field("jointTorque", REAL, self.n_pairs)
        status.field("motionFinished", BOOLEAN)
        status.field("emergencyStop", BOOLEAN)
        return {"joints": joints, "command": command, "status": status}

    # ---- behaviour common to every subsystem ---------------------------------------------

    def _fsm(
        self,
        block: Block,
        modes: list[str],
        triggers: list[OpaqueBehavior],
        stop_state: str,
        stop_pp: OpaqueBehavior,
        done_pp: OpaqueBehavior,
        stop_tc: str,
        stage1: Callable[[str], list[OpaqueBehavior]],
        stage2: list[OpaqueBehavior],
        extra_done: str | None = None,
    ) -> None:
        """States idle, modes…, stop (``B`` in all), their basic behaviours and the transitions."""
        fsm = block.state_machine()
        if self.n_states == 1:
            names = ["operate"]
        else:
            names = ["idle", *modes, stop_state]
        states = {}
        for k, name in enumerate(names):
            states[name] = fsm.state(name, initial=(k == 0))
        stop = f"{stop_pp.name}.fun"
        for name, state in states.items():
            if self.n_states == 1:
                tc = "FALSE"
            elif name == "idle":
                tc = _or(*(f"{t.name}.fun" for t in triggers), stop)
            elif name == stop_state:
                tc = stop_tc
            else:
                tc = _or(f"{done_pp.name}.fun", *([extra_done] if extra_done else []), stop)
            act = state.do_activity(tc=tc, ec="FALSE")
            act.stages([stage1(name), stage2])
        if self.n_states == 1:
            return
        idle = states["idle"]
        for mode, trigger in zip(modes, triggers):
            guard = f"{trigger.name}.fun ∧ ¬{stop}"
            fsm.transition(idle, states[mode], guard)
            fsm.transition(states[mode], states[mode], guard, priority=1)
        for mode in modes:
            fsm.transition(states[mode], idle, f"¬{stop}")
        for name in ["idle", *modes]:
            fsm.transition(states[name], states[stop_state], stop, priority=2)

    # ---- control subsystem ---------------------------------------------------------------

    def _control(self, i: int, types: dict, parent: int | None, children: list[int]) -> Block:
        cs = self.inst.block(f"Agent{i}Control", "ControlSubsystem")
        ports = {}
        if parent is not None:
            # a queue, as in the sample: a one-shot setpoint from the supervisor is never lost (C009)
            ports["command"] = cs.input_buffer("command/ib", types["command"])
            ports["command"].stereotype("InputBuffer", {"receive": "queue", "queueSize": 8})
            ports["status"] = cs.output_buffer("status/ob", types["status"])
        for c in children:
            ctypes = self.agent_types[c]
            ports[("childCommand", c)] = cs.output_buffer(f"agent{c}Command/ob", ctypes["command"])
            ports[("childStatus", c)] = cs.input_buffer(f"agent{c}Status/ib", ctypes["status"])
        joint_state, joint_command = [], []
        for j in range(1, self.n_pairs + 1):
            joint_command.append(cs.output_buffer(f"joint{j}Command/ob", self.mc_command))
            joint_state.append(cs.input_buffer(f"joint{j}State/ib", self.mc_state))
        ports["jointCommand"], ports["jointState"] = joint_command, joint_state
        motion_finished = cs.memory("motionFinished/m", BOOLEAN)
        estop = cs.memory("emergencyStopCommand/m", BOOLEAN)
        current_joint = cs.memory("currentJointPos/m", types["joints"])
        current_oper = cs.memory("currentOperationalPos/m", self.oper_position)
        setpoint = cs.memory("jointSetpoint/m", types["joints"])
        if self.n_pairs > 1:  # replicated: jointTorque1/m … jointTorqueS/m, as windingCurrentK/m in the sample
            torque = cs.memory("jointTorqueK/m", REAL, self.n_pairs)
            overload = f"any K: jointTorqueK/m.data > {_threshold(i, 3)}"
        else:
            torque = cs.memory("jointTorque/m", REAL)
            overload = f"jointTorque/m.data > {_threshold(i, 3)}"

        modes = _modes(CS_MODES, max(self.n_states - 2, 0))
        stop_terms = [f"joint{j}State/ib.msg.emergencyStop" for j in range(1, self.n_pairs + 1)]
        if parent is not None:
            stop_terms.insert(0, "command/ib.msg.emergencyStopCommand")
        stop_pp = cs.primitive_predicate("emergencyStop/pp", _or(*stop_terms))
        done_pp = cs.primitive_predicate("motionFinished/pp", "motionFinished/mi.msg")
        triggers = []
        for k, mode in enumerate(modes, start=1):
            if parent is not None:
                body = f"newData(command/ib.msg.{mode}Setpoint)"
            else:
                j = (k - 1) % self.n_pairs + 1
                body = f"joint{j}State/ib.msg.motorPos > {_threshold(i, k)}"
            triggers.append(cs.primitive_predicate(f"new{_cap(mode)}/pp", body))
        false_pp = cs.primitive_predicate("false/pp", "FALSE")
        overload_pp = cs.primitive_predicate("overload/pp", overload)
        if len(triggers) >= 2:  # one mode at a time (B006), as the sample declares for its two moves
            names = ", ".join(t.name for t in triggers)
            cs.exclusion("modesExclusive", triggers, body=f"exclusive({names})")

        upstream = [ports["command"]] if parent is not None else []
        calculate = cs.partial_transition_function(
            "calculatePosition/pf", reads=joint_state, writes=[current_joint, current_oper, torque],
            body="// Joint positions from the motor positions; end-effector pose by forward kinematics.")
        passive = cs.partial_transition_function(
            "passiveRegulation/pf", reads=joint_state, writes=[setpoint],
            body="// Setpoints that keep the joints still.")
        mode_pfs = {
            mode: cs.partial_transition_function(
                f"{mode}/pf", reads=[*upstream, *joint_state], writes=[motion_finished, setpoint],
                body=f"// {_cap(mode)}: next joint setpoints along the trajectory.")
            for mode in modes
        }
        stop_pf = cs.partial_transition_function(
            "emergencyStop/pf", reads=[*upstream, *joint_state], writes=[estop],
            body="// Latches the emergency stop for every joint.")
        child_status = [ports[("childStatus", c)] for c in children]
        child_command = [ports[("childCommand", c)] for c in children]
        state_out = [ports["status"]] if parent is not None else []
        stage2 = []
        if state_out or child_command:
            stage2.append(cs.partial_transition_function(
                "outputState/pf",
                reads=[current_joint, current_oper, torque, motion_finished, estop, *child_status],
                writes=[*state_out, *child_command],
                body="// Composes the status for the supervisor and the commands for supervised agents."))
        stage2.append(cs.partial_transition_function(
            "outputJointCommands/pf", reads=[setpoint, estop], writes=joint_command,
            body="// One MotorControllerCommand per joint."))

        def stage1(state: str) -> list:
            if state in ("idle", "operate"):
                return [calculate, passive]
            if state == "emergencyStop":
                return [calculate, stop_pf]
            return [calculate, mode_pfs[state]]

        self._fsm(cs, modes, triggers, "emergencyStop", stop_pp, done_pp, f"{false_pp.name}.fun", stage1, stage2,
                  extra_done=f"{overload_pp.name}.fun")
        self.cs_ports[i] = ports
        return cs

    # ---- effectors -----------------------------------------------------------------------

    def _controller(self, i: int, j: int) -> tuple[Block, dict]:
        ve = self.inst.block(f"Agent{i}Joint{j}Controller", "VirtualEffector")
        command = ve.input_buffer("motorControllerCommand/ib", self.mc_command)
        state_out = ve.output_buffer("motorControllerState/ob", self.mc_state)
        current = ve.output_buffer("desiredCurrent/ob", self.current)
        encoder = ve.input_buffer("encoder/ib", self.encoder)
        desired = ve.memory("desiredPosition/m", REAL)
        integral = ve.memory("integralError/m", REAL)
        gains = ve.memory("gains/m", self.gains)
        modes = _modes(VE_MODES, max(self.n_states - 2, 0))
        fault = ve.primitive_predicate(
            "fault/pp",
            f"motorControllerCommand/ib.msg.emergencyStopCommand ∨ integralError/mi.data > {_threshold(i, j, 1)}")
        settled = ve.primitive_predicate("settled/pp", f"integralError/mi.data < 0.0{j % 9 + 1}")
        triggers = [ve.primitive_predicate(f"{mode}Requested/pp", f"motorControllerCommand/ib.msg.mode == {k}")
                    for k, mode in enumerate(modes, start=1)]
        estimate = ve.partial_transition_function(
            "estimate/pf", reads=[command, encoder], writes=[desired],
            body="// Desired position from the command; filters the encoder reading.")
        hold = ve.partial_transition_function(
            "hold/pf", reads=[encoder], writes=[integral], body="// Holds the current position.")
        mode_pfs = {
            mode: ve.partial_transition_function(
                f"{mode}Control/pf", reads=[command, encoder, integral, gains], writes=[integral],
                body=f"// PI regulator in {mode} mode: i = Kp*e + Ki*integral(e).")
            for mode in modes
        }
        safe = ve.partial_transition_function(
            "safeStop/pf", reads=[command], writes=[integral], body="// Resets the regulator and brakes.")
        out_current = ve.partial_transition_function(
            "outputCurrent/pf", reads=[desired, integral, gains], writes=[current],
            body="// Desired winding current from the regulator state.")
        report = ve.partial_transition_function(
            "reportState/pf", reads=[encoder, desired], writes=[state_out],
            body="// Reports the motor state to the control subsystem.")

        def stage1(state: str) -> list:
            if state in ("idle", "operate"):
                return [estimate, hold]
            if state == "fault":
                return [estimate, safe]
            return [estimate, mode_pfs[state]]

        self._fsm(ve, modes, triggers, "fault", fault, settled, "FALSE", stage1, [out_current, report])
        return ve, {"command": command, "state": state_out, "current": current, "encoder": encoder}

    def _motor(self, i: int, j: int) -> tuple[Block, dict]:
        re = self.inst.block(f"Agent{i}Joint{j}Motor", "RealEffector")
        current = re.input_buffer("desiredCurrent/ib", self.current)
        encoder = re.output_buffer("encoder/ob", self.encoder)
        position = re.memory("position/m", REAL)
        temperature = re.memory("temperature/m", REAL)
        modes = _modes(RE_MODES, max(self.n_states - 2, 0))
        fault = re.primitive_predicate("overheated/pp", f"temperature/mi.data > {_threshold(i, j, 2)}")
        stopped = re.primitive_predicate("stopped/pp", "desiredCurrent/ib.msg.current < 0.001")
        triggers = [re.primitive_predicate(f"{mode}Requested/pp", f"desiredCurrent/ib.msg.mode == {k}")
                    for k, mode in enumerate(modes, start=1)]
        sense = re.partial_transition_function(
            "sense/pf", reads=[current], writes=[temperature], body="// Reads the winding temperature.")
        idle_pf = re.partial_transition_function(
            "brakeHold/pf", reads=[position], writes=[position], body="// Keeps the brake engaged.")
        mode_pfs = {
            mode: re.partial_transition_function(
                f"{mode}/pf", reads=[current, position], writes=[position],
                body=f"// Sets the winding current on the hardware ({mode}) and reads the encoder.")
            for mode in modes
        }
        power_off = re.partial_transition_function(
            "powerOff/pf", reads=[position], writes=[position], body="// Cuts the power stage.")
        publish = re.partial_transition_function(
            "publishEncoder/pf", reads=[position], writes=[encoder], body="// Publishes the encoder reading.")

        def stage1(state: str) -> list:
            if state in ("idle", "operate"):
                return [sense, idle_pf]
            if state == "overheat":
                return [sense, power_off]
            return [sense, mode_pfs[state]]

        self._fsm(re, modes, triggers, "overheat", fault, stopped, "FALSE", stage1, [publish])
        return re, {"current": current, "encoder": encoder}

    # ---- the model -----------------------------------------------------------------------

    def build(self) -> ModelBuilder:
        mb = self.mb
        n = self.n_agents
        mb.comment(f"Generated benchmark model: {n} agents, {self.n_pairs} effector pairs per agent, "
                   f"{self.n_states} FSM states per subsystem (bench/generate.py).")
        self.types = mb.package("DataTypes")
        self._shared_types()
        self.agent_types = {i: self._agent_types(i) for i in range(1, n + 1)}
        self.inst = mb.package("SystemInstance")
        system = self.inst.block("BenchSystem", "System")
        robot_of = {}
        in_robots = list(range(2, n + 1)) if n > 1 else [1]
        robots = {}
        for k, i in enumerate(in_robots):
            r = k // AGENTS_PER_ROBOT + 1
            robot_of[i] = r
            if r not in robots:
                robots[r] = self.inst.block(f"Robot{r}", "Robot")
        parent = {i: (None if i == 1 else (i - 2) // FAN_OUT + 1) for i in range(1, n + 1)}
        children: dict[int, list[int]] = {i: [] for i in range(1, n + 1)}
        for i, p in parent.items():
            if p is not None:
                children[p].append(i)
        declared = "CET" if n > 1 else "CE"
        self.cs_ports: dict[int, dict] = {}
        agent_blocks, cs_parts = {}, {}
        for i in range(1, n + 1):
            agent = self.inst.block(f"Agent{i}", "Agent", {"declaredType": declared})
            sup = f"supervised by agent{parent[i]}/a" if parent[i] else "the supervisor of the system"
            agent.comment(f"agent{i}/a drives {self.n_pairs} joints, one motor controller (ve) and one motor "
                          f"(re) per joint under one control subsystem; {sup}.")
            cs_block = self._control(i, self.agent_types[i], parent[i], children[i])
            cs_part = agent.part("cs", cs_block)
            cs_parts[i] = cs_part
            ports = self.cs_ports[i]
            pairs = []
            for j in range(1, self.n_pairs + 1):
                ve_block, ve_ports = self._controller(i, j)
                re_block, re_ports = self._motor(i, j)
                ve_part = agent.part(f"joint{j}Controller/ve", ve_block)
                re_part = agent.part(f"joint{j}Motor/re", re_block)
                pairs.append((j, ve_part, ve_ports, re_part, re_ports))
            for j, ve_part, ve_ports, re_part, re_ports in pairs:
                ve_name, re_name = ve_part.name, re_part.name
                agent.connector(f"cs,{ve_name}", End.at(ports["jointCommand"][j - 1], cs_part),
                                End.at(ve_ports["command"], ve_part), "InterSubsystemLink")
                agent.connector(f"{ve_name},cs", End.at(ve_ports["state"], ve_part),
                                End.at(ports["jointState"][j - 1], cs_part), "InterSubsystemLink")
                agent.connector(f"{ve_name},{re_name}", End.at(ve_ports["current"], ve_part),
                                End.at(re_ports["current"], re_part), "InterSubsystemLink")
                agent.connector(f"{re_name},{ve_name}", End.at(re_ports["encoder"], re_part),
                                End.at(ve_ports["encoder"], ve_part), "InterSubsystemLink")
            agent_blocks[i] = agent
        robot_parts = {r: system.part(f"robot{r}/r", block) for r, block in robots.items()}
        agent_parts = {}
        for i in range(1, n + 1):
            owner = robots[robot_of[i]] if i in robot_of else system
            agent_parts[i] = owner.part(f"agent{i}/a", agent_blocks[i])

        def path(i: int) -> tuple:
            head = (robot_parts[robot_of[i]],) if i in robot_of else ()
            return (*head, agent_parts[i], cs_parts[i])

        for i in range(2, n + 1):
            p = parent[i]
            system.connector(f"agent{p}/a,agent{i}/a", End.at(self.cs_ports[p][("childCommand", i)], *path(p)),
                             End.at(self.cs_ports[i]["command"], *path(i)), "InterAgentLink")
            system.connector(f"agent{i}/a,agent{p}/a", End.at(self.cs_ports[i]["status"], *path(i)),
                             End.at(self.cs_ports[p][("childStatus", i)], *path(p)), "InterAgentLink")
        return mb


def generate(agents: int, subsystems: int, behaviours: int, name: str = "BenchModel") -> bytes:
    """The XMI bytes of one generated model."""
    return _Generator(agents, subsystems, behaviours, name).build().to_bytes()


def _fit(subsystems: int, behaviours: int) -> tuple[float, float]:
    """(fixed bytes, bytes per agent): the size is affine in the number of agents."""
    a1, a2 = 2, 5
    s1 = len(generate(a1, subsystems, behaviours))
    s2 = len(generate(a2, subsystems, behaviours))
    per_agent = (s2 - s1) / (a2 - a1)
    return s1 - per_agent * a1, per_agent


def sizes_for_target(target_mb: float, subsystems: int = DEFAULT_SUBSYSTEMS,
                     behaviours: int = DEFAULT_BEHAVIOURS, tolerance: float = 0.03) -> tuple[int, int, int]:
    """(agents, subsystems, behaviours) whose model is about ``target_mb`` MB (10^6 bytes).

    The number of agents does the scaling. When whole agents cannot come within
    ``tolerance`` of the target (small models), neighbouring numbers of effector pairs are
    tried too, nearest to the requested one first.
    """
    target = target_mb * 1e6
    best: tuple[float, int, int] | None = None
    for s in sorted({max(1, subsystems + d) for d in (0, -1, 1, -2, 2)}, key=lambda v: abs(v - subsystems)):
        fixed, per_agent = _fit(s, behaviours)
        agents = max(1, round((target - fixed) / per_agent))
        error = abs(fixed + per_agent * agents - target) / target
        if best is None or error < best[0]:
            best = (error, agents, s)
        if error <= tolerance:
            break
    assert best is not None
    return best[1], best[2], behaviours


def describe(path: Path) -> None:
    """Print the element mix of a model file: element kinds per MB and per cent of elements."""
    from lxml import etree

    size = path.stat().st_size
    kinds: Counter[str] = Counter()
    xmi_type = "{http://www.omg.org/spec/XMI/20131001}type"
    parser_options = {"huge_tree": True, "resolve_entities": False, "no_network": True}
    for _, el in etree.iterparse(str(path), events=("end",), **parser_options):
        if not isinstance(el.tag, str):
            continue
        kind = el.get(xmi_type) or (f"{el.prefix}:" if el.prefix else "") + etree.QName(el).localname
        kinds[kind] += 1
        el.clear(keep_tail=True)
    total = sum(kinds.values())
    print(f"{path.name}: {size / 1e6:.2f} MB, {total} XML elements ({total / (size / 1e6):.0f} per MB)")
    for kind, count in kinds.most_common():
        print(f"  {kind:40s} {count:9d}  {100 * count / total:5.1f} %  {count / (size / 1e6):8.0f}/MB")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--agents", type=int, help="number of agents")
    parser.add_argument("--subsystems", type=int, default=None,
                        help=f"ve/re pairs per agent (each agent has 1 + 2*S subsystems; default {DEFAULT_SUBSYSTEMS})")
    parser.add_argument("--behaviours", type=int, default=None,
                        help=f"FSM states (= basic behaviours) per subsystem (default {DEFAULT_BEHAVIOURS})")
    parser.add_argument("--target-mb", type=float, help="pick --agents to reach about this many MB (10^6 bytes)")
    parser.add_argument("--name", default="BenchModel", help="name of the uml:Model")
    parser.add_argument("-o", "--output", type=Path, help="output file (.uml)")
    parser.add_argument("--describe", type=Path, metavar="FILE", help="print the element mix of FILE and exit")
    args = parser.parse_args(argv)
    if args.describe:
        describe(args.describe)
        return 0
    if args.output is None:
        parser.error("-o/--output is required")
    subsystems = args.subsystems if args.subsystems is not None else DEFAULT_SUBSYSTEMS
    behaviours = args.behaviours if args.behaviours is not None else DEFAULT_BEHAVIOURS
    if args.target_mb is not None:
        if args.agents is not None:
            parser.error("give either --target-mb or --agents")
        agents, subsystems, behaviours = sizes_for_target(args.target_mb, subsystems, behaviours)
    elif args.agents is None:
        parser.error("give --agents or --target-mb")
    else:
        agents = args.agents
    start = time.perf_counter()
    data = generate(agents, subsystems, behaviours, args.name)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_bytes(data)
    print(f"{args.output}: {len(data) / 1e6:.2f} MB, agents={agents} subsystems={subsystems} "
          f"behaviours={behaviours} ({time.perf_counter() - start:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
