"""What the SysML v2 template writes, taken from a lifted EARL model.

Replicated instances are folded back into their template with a multiplicity
(``motorController1/ve`` … ``motorController6/ve`` → ``'motorControllerK/ve' [6]``), one
connector per link template, one definition per block. Names are quoted, conditions turned
into SysML v2 expressions where one reads back as the same predicate text, else kept as a
textual representation ``language "EARL" /* … */``.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Any

from earl_m2t.convert.names import expression, qualified, quoted
from earl_m2t.convert.tags import (
    activation_tags,
    buffer_tags,
    composition_tags,
    names_string,
    simulation_tags,
    string_literal,
)
from earl_m2t.lift.recognise import suffix_of
from earl_m2t.model.conditions import Condition
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import (
    Agent,
    BasicBehaviour,
    Configuration,
    EarlModel,
    Group,
    Link,
    State,
    Subsystem,
    System,
)
from earl_m2t.model.kinds import Reactivation
from earl_m2t.profile import load_profile
from earl_m2t.profile_types import Profile

PRIMITIVE_TYPES = {"boolean": "Boolean", "integer": "Integer", "real": "Real", "string": "String"}
DIRECTIONS = {"read": "in", "write": "out", "readwrite": "inout"}
PREDICATE_LANGUAGE = "EARL"
LINE_LENGTH = 96  # longer link and transition declarations are written on several lines


@dataclass
class Definition:
    """A ``part def`` with the lines of its body."""

    name: str
    concept: str
    lines: list[str] = field(default_factory=list)


def model_view(model: EarlModel, profile: Profile | None = None) -> dict[str, Any]:
    """The model's elements as SysML v2 definitions; its LTL properties are written as
    «LtlProperty» metadata of the first System."""
    return _View(model, profile or load_profile()).build()


class _View:
    def __init__(self, model: EarlModel, profile: Profile) -> None:
        self.model = model
        self.profile = profile
        self.blocks: dict[str, Definition] = {}

    def build(self) -> dict[str, Any]:
        for system in self.model.systems:
            self.system(system)
        if self.model.systems and self.model.properties:
            definition = self.blocks.get(self.model.systems[0].name)
            if definition is not None:
                definition.lines.extend(f"metadata {quoted(p.title)} : Ltl {{ formula = {string_literal(p.text)}; }}"
                                        for p in self.model.properties)
        return {
            "model": quoted(self.model.name or "Model"),
            "datatypes": self.datatype_lines(),
            "definitions": list(self.blocks.values()),
        }

    # -- datatypes ----------------------------------------------------------------------
    def datatype_lines(self) -> list[str]:
        """The dataTypes, in packages nested as their qualified names say (``DataTypes::Pose``)."""
        tree: dict[str, Any] = {}
        for datatype in self.model.datatypes.values():
            if datatype.location.file == "<builtin>":
                continue
            node = tree
            for package in datatype.qualified_name.split("::")[:-1]:
                node = node.setdefault(package, {})
            node.setdefault("", []).append(self.datatype(datatype))
        return _package_lines(tree)

    def datatype(self, datatype: DataType) -> list[str]:
        name = quoted(datatype.name)
        if datatype.kind == "enumeration":
            return [f"enum def {name} {{"] + [f"    enum {quoted(v)};" for v in datatype.literals] + ["}"]
        if datatype.kind == "primitive":
            return [f"attribute def {name} :> {PRIMITIVE_TYPES.get(datatype.primitive, 'Real')};"]
        if not datatype.fields:
            return [f"attribute def {name};"]
        lines = [f"attribute def {name} {{"]
        for f in datatype.fields:
            typed = f" : {self.type_name(f.type)}" if f.type else ""
            lines.append(f"    attribute {quoted(f.name)}{typed}{_multiplicity(f.lower, f.upper)};")
        return lines + ["}"]

    def type_name(self, key: str) -> str:
        found = self.model.datatypes.get(key)
        if found is not None and found.location.file == "<builtin>":
            return PRIMITIVE_TYPES.get(found.primitive, key)
        return qualified(key)

    # -- structure ----------------------------------------------------------------------
    def block(self, name: str, concept: str) -> Definition | None:
        if name in self.blocks:
            return None
        self.blocks[name] = Definition(qualified(name), concept)
        return self.blocks[name]

    def system(self, system: System) -> None:
        definition = self.block(system.name, "System")
        group_of = {member: group for group in system.groups for member in group.members}
        parts = [(r.location.line, f"part {quoted(r.name)} : {quoted(r.block)};") for r in system.robots]
        parts += [(a.location.line, f"part {quoted(a.name)} : {quoted(a.block)}{_optional(a)};")
                  for a in system.agents if not a.robot and a.path not in group_of]
        parts += [(g.location.line, f"part {quoted(g.name)} : {quoted(g.block)};")
                  for g in system.groups if g.owner == system.name]
        for robot in system.robots:
            robot_definition = self.block(robot.block, "Robot")
            if robot_definition is not None:
                held = [(a.location.line, f"part {quoted(a.name)} : {quoted(a.block)}{_optional(a)};")
                        for a in system.agents if a.robot == robot.path and a.path not in group_of]
                held += [(g.location.line, f"part {quoted(g.name)} : {quoted(g.block)};")
                         for g in system.groups if g.owner == robot.path]
                robot_definition.lines.extend(line for _, line in sorted(held, key=lambda p: p[0]))
        agents = {a.path: a for a in system.agents}
        for group in system.groups:
            self.agent_group(group, [agents[m] for m in group.members if m in agents])
        for agent in system.agents:
            self.agent(agent)
        if definition is None:
            return
        definition.lines.extend(line for _, line in sorted(parts, key=lambda p: p[0]))
        ends = {b.path: self.system_end(agents[s.agent], group_of.get(s.agent), s, b.template)
                for a in system.agents for s in a.subsystems for b in s.buffers}
        definition.lines.extend(self.links(system.links, ends, "InterAgentLink"))
        definition.lines.extend(_configuration(c) for c in system.configurations)

    def agent_group(self, group: Group, members: list[Agent]) -> None:
        """An Agent Group's block: a part for each of its Agents."""
        definition = self.block(group.block, "AgentGroup")
        if definition is not None:
            definition.lines.extend(f"part {quoted(a.name)} : {quoted(a.block)};" for a in members)

    def system_end(self, agent: Agent, group: Group | None, subsystem: Subsystem, buffer: str) -> str:
        """A buffer as the System reaches it: through the robot, Agent Group, agent and
        Subsystem Group that hold it."""
        chain = ([agent.robot] if agent.robot else []) + ([group.name] if group else []) + [agent.name]
        chain += [g.name for g in agent.groups if subsystem.path in g.members] + [subsystem.template, buffer]
        return ".".join(quoted(c) for c in chain)

    def agent(self, agent: Agent) -> None:
        definition = self.block(agent.block, "Agent")
        if definition is None:
            return
        if agent.declared_type:
            definition.lines.append(f"attribute :>> declaredType = AgentType::{agent.declared_type};")
        if agent.reactivation != Reactivation.RESTART:
            definition.lines.append(f"@AgentReactivation {{ reactivation = Reactivation::{agent.reactivation}; }}")
        if agent.host:
            host = agent.host.replace("\\", "\\\\").replace('"', '\\"')
            definition.lines.append(f'@AgentHost {{ host = "{host}"; }}')
        group_of = {member: group for group in agent.groups for member in group.members}
        for template, subsystems in _grouped(agent.subsystems, lambda s: group_of.get(s.path) or s.template):
            group = group_of.get(subsystems[0].path)
            if group is None:
                definition.lines.append(self.subsystem_part(template, subsystems))
                continue
            definition.lines.append(f"part {quoted(group.name)} : {quoted(group.block)};")
            group_definition = self.block(group.block, "SubsystemGroup")
            for member_template, members in _grouped(subsystems, lambda s: s.template):
                part = self.subsystem_part(member_template, members)
                if group_definition is not None:
                    group_definition.lines.append(part)
        ends = {b.path: ".".join(quoted(c) for c in ([group_of[s.path].name] if s.path in group_of else [])
                                 + [s.template, b.template])
                for s in agent.subsystems for b in s.buffers}
        definition.lines.extend(self.links(agent.links, ends, "InterSubsystemLink"))

    def subsystem_part(self, template: str, subsystems: list[Subsystem]) -> str:
        """The part of a subsystem template (``'motorControllerK/ve' : MotorController[6]``),
        its block written once."""
        first = subsystems[0]
        count = f"[{len(subsystems)}]" if first.index else ""
        self.subsystem(first, len(subsystems))
        return f"part {quoted(template)} : {quoted(first.block)}{count};"

    def links(self, links: tuple[Link, ...], ends: dict[str, str], concept: str) -> list[str]:
        lines = []
        for _, group in _grouped(links, lambda link: (link.template, link.location.line)):
            link = group[0]
            first, second = (ends.get(e, quoted(e)) for e in link.ends)
            name = f" {quoted(link.template)}" if link.template else ""
            lines.extend(_wrapped(f"interface{name} : {concept}", f"connect {first} to {second};"))
        return lines

    # -- subsystems ---------------------------------------------------------------------
    def subsystem(self, subsystem: Subsystem, count: int) -> None:
        concept = self.concept(subsystem.kind)
        definition = self.block(subsystem.block, concept)
        if definition is None:
            return
        lines = definition.lines
        lines.extend(simulation_tags(subsystem.simulation, concept))
        for buffers, buffer_concept in ((subsystem.inputs, "InputBuffer"), (subsystem.outputs, "OutputBuffer")):
            for template, group in _grouped(buffers, lambda b: b.template):
                size = f"[{len(group)}]" if group[0].index else ""
                body = [f"attribute :>> msg : {self.type_name(group[0].datatype)};"] if group[0].datatype else []
                body += buffer_tags(group[0], buffer_concept)
                message = f" {{ {' '.join(body)} }}" if body else ";"
                lines.append(f"port {quoted(template)} : {buffer_concept}{size}{message}")
        for template, group in _grouped(subsystem.memory, lambda m: m.template):
            size = f"[{len(group)}]" if group[0].index else ""
            typed = f" : {self.type_name(group[0].datatype)}" if group[0].datatype else ""
            marker = "" if suffix_of(template) == "m" else "#Memory "
            lines.append(f"{marker}attribute {quoted(template)}{typed}{size};")
        for exclusion in subsystem.exclusions:
            about = ", ".join(quoted(p) for p in exclusion.predicates)
            head = f"metadata {quoted(exclusion.name)} : Exclusive" if exclusion.name else "@Exclusive"
            lines.append(f"{head} about {about};")
        for buffer_group in subsystem.buffer_groups:
            obligatory, optional = names_string(buffer_group.obligatory), names_string(buffer_group.optional)
            lines.append(f"metadata {quoted(buffer_group.name)} : Group {{ obligatory = {obligatory}; "
                         f"optional = {optional}; }}")
        for predicate in subsystem.predicates:
            lines.extend(self.predicate(predicate.name, predicate.language, predicate.body, predicate.fun))
        for function in subsystem.functions:
            specialises = "" if suffix_of(function.name) == "pf" else " :> PartialTransitionFunction"
            lines.append(f"action def {quoted(function.name)}{specialises} {{")
            lines.extend(f"    {DIRECTIONS[a.mode]} {quoted(a.name)};" for a in function.accesses)
            lines.extend("    " + line for line in _representation(function.language, function.body))
            lines.append("}")
        states = subsystem.fsm.states if subsystem.fsm else ()
        shared = self.shared_behaviours(subsystem)
        for behaviour in subsystem.behaviours:
            if behaviour.name in shared:
                specialises = "" if suffix_of(behaviour.name) == "bb" else " :> BasicBehaviour"
                lines.append(f"action def {quoted(behaviour.name)}{specialises} {{")
                lines.extend("    " + line for line in self.activity(behaviour))
                lines.append("}")
        if subsystem.fsm is not None:
            fsm = subsystem.fsm
            lines.append(f"state {quoted(fsm.name)} {{")
            for initial in fsm.initial_states:
                lines.append(f"    entry; then {quoted(initial)};" if initial else "    entry;")
            for state in states:
                lines.extend("    " + line for line in self.state(subsystem, state, shared))
            called = Counter(transition.name for transition in fsm.transitions)
            for transition in fsm.transitions:
                # an unnamed transition is written with the name it is called by, unless another
                # transition is called so too: then unnamed (two of one name are an error, S012)
                name = transition.name if transition.named or called[transition.name] == 1 else ""
                lines.extend("    " + line for line in self.transition(name, transition.source, transition.target,
                                                                          transition.condition, transition.priority))
            lines.append("}")

    def concept(self, kind: str) -> str:
        found = self.profile.by_abbreviation(kind)
        return found.name if found is not None else "Subsystem"

    def shared_behaviours(self, subsystem: Subsystem) -> set[str]:
        """Basic behaviours written once as ``action def``: used by several states, or by none."""
        uses: dict[str, int] = {}
        for state in subsystem.fsm.states if subsystem.fsm else ():
            for name in state.behaviours:
                uses[name] = uses.get(name, 0) + 1
        return {b.name for b in subsystem.behaviours if uses.get(b.name, 0) != 1}

    def predicate(self, name: str, language: str, body: str, fun: Condition | None) -> list[str]:
        lines = [f"calc def {quoted(name)} {{", "    return : Boolean;"]
        written = expression(body.strip()) if language == PREDICATE_LANGUAGE and fun is not None else None
        if written is not None:
            lines.append(f"    {written}")
        else:
            lines.extend("    " + line for line in _representation(language, body))
        return lines + ["}"]

    def state(self, subsystem: Subsystem, state: State, shared: set[str]) -> list[str]:
        activation = activation_tags(state.activation) + _state_variability(state) + composition_tags(state)
        if not state.behaviours and not activation:
            return [f"state {quoted(state.name)};"]
        lines = [f"state {quoted(state.name)} {{"] + [f"    {line}" for line in activation]
        for behaviour_name in state.behaviours:
            behaviour = subsystem.behaviour(behaviour_name)
            if behaviour is None or behaviour_name in shared:
                lines.append(f"    do action : {quoted(behaviour_name)};")
                continue
            lines.append(f"    do action {quoted(behaviour_name)} {{")
            lines.extend("        " + line for line in self.activity(behaviour))
            lines.append("    }")
        return lines + ["}"]

    def activity(self, behaviour: BasicBehaviour) -> list[str]:
        lines: list[str] = []
        taken: set[str] = set()
        if behaviour.stages:
            lines.append("first start;")
        for number, stage in enumerate(behaviour.stages, start=1):
            actions = [(_action_name(pf, taken), pf) for pf in stage]
            if len(actions) == 1:
                action, pf = actions[0]
                lines.append(f"then action {quoted(action)} : {quoted(pf)};")
                continue
            join = _action_name(f"stage{number}", taken)
            lines.append("then fork;")
            lines.extend(f"    then {quoted(action)};" for action, _ in actions)
            for action, pf in actions:
                lines.append(f"action {quoted(action)} : {quoted(pf)};")
                lines.append(f"    then {quoted(join)};")
            lines.append(f"join {quoted(join)};")
        if behaviour.stages:
            lines.append("then done;")
        for role, condition in (("tc", behaviour.tc), ("ec", behaviour.ec)):
            if condition is not None:
                lines.extend(self.condition_usage(role, condition))
        return lines

    def condition_usage(self, role: str, condition: Condition) -> list[str]:
        written = expression(condition.text) if condition.language == PREDICATE_LANGUAGE else None
        if written is not None:
            return [f"constraint {role} {{ {written} }}"]
        body = _representation(condition.language, condition.text)
        return [f"constraint {role} {{"] + ["    " + line for line in body] + ["}"]

    def transition(self, name: str, source: str, target: str, condition: Condition | None, priority: int) -> list[str]:
        predicate = condition is not None and condition.language == PREDICATE_LANGUAGE
        written = expression(condition.text) if predicate and condition is not None else None
        guard = f" if {written}" if written is not None else ""
        body: list[str] = []
        if condition is not None and written is None:
            body.extend(_representation(condition.language, condition.text))
        if priority:
            body.append(f"@Priority {{ priority = {priority}; }}")
        first = f"transition {quoted(name)}" if name else "transition"
        rest = [f"first {quoted(source)}{guard}", f"then {quoted(target)}"]
        if not body:
            rest[-1] += ";"
        elif len(body) == 1:
            rest[-1] += f" {{ {body[0]} }}"
        else:
            return [" ".join([first, *rest]) + " {"] + ["    " + line for line in body] + ["}"]
        return _wrapped(first, *rest)


def _package_lines(tree: dict[str, Any]) -> list[str]:
    """Lines of the dataTypes of a package tree: its own (key "") first, then sub-packages."""
    lines = [line for datatype in tree.get("", []) for line in datatype]
    for name, subtree in tree.items():
        if name:
            if lines:
                lines.append("")
            lines.append(f"package {quoted(name)} {{")
            lines.extend(f"    {line}" if line else "" for line in _package_lines(subtree))
            lines.append("}")
    return lines


def _wrapped(first: str, *rest: str) -> list[str]:
    """One line when it is short enough, else the parts after the first indented below it."""
    line = " ".join([first, *rest])
    if len(line) <= LINE_LENGTH:
        return [line]
    return [first] + [f"    {part}" for part in rest]


def _grouped(items: Any, key: Any) -> list[tuple[Any, list[Any]]]:
    groups: dict[Any, list[Any]] = {}
    for item in items:
        groups.setdefault(key(item), []).append(item)
    return list(groups.items())


def _multiplicity(lower: int, upper: int | None) -> str:
    if lower == upper == 1:
        return ""
    if lower == upper:
        return f"[{lower}]"
    return f"[{lower}..{'*' if upper is None else upper}]"


def _action_name(pf: str, taken: set[str]) -> str:
    stem = pf.rpartition("/")[0] if "/" in pf else pf
    name, n = stem, 1
    while name in taken:
        n += 1
        name = f"{stem}{n}"
    taken.add(name)
    return name


def _representation(language: str, body: str) -> list[str]:
    """``language "L" /* body */`` lines; a ``*/`` in the body cannot be written and is split."""
    if not language and not body:
        return []
    text = body.replace("*/", "* /")
    escaped = language.replace("\\", "\\\\").replace('"', '\\"')
    lines = text.split("\n")
    if len(lines) == 1:
        return [f'language "{escaped}" /* {text} */']
    return [f'language "{escaped}"', "/*"] + [f" * {line}".rstrip() for line in lines] + [" */"]


def _optional(agent: Agent) -> str:
    return "[0..1]" if agent.optional else ""


def _configuration(configuration: Configuration) -> str:
    """``metadata useA : Structure { … }`` of a System: the names as the model gives them."""
    tags = [f"agents = {names_string(configuration.agents + configuration.unknown_agents)};",
            f"links = {names_string(configuration.links + configuration.unknown_links)};"]
    if configuration.switch_timeout is not None:
        tags.append(f"switchTimeout = {configuration.switch_timeout!r};")
    return f"metadata {quoted(configuration.name)} : Structure {{ {' '.join(tags)} }}"


def _state_variability(state: State) -> list[str]:
    lines = []
    if state.configuration:
        lines.append(f"@Reconfigure {{ configuration = {string_literal(state.configuration)}; }}")
    return lines + (["@Quiescent;"] if state.quiescent else [])
