"""Lifting the structure (bdd/ibd): system, robots, agents, subsystems, buffers, memory, links."""

from __future__ import annotations

from dataclasses import replace
from functools import partial

from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.lift.activation import buffer_groups, receive_of, reliability_of, simulation_of
from earl_m2t.lift.behaviour import BehaviourContext, BehaviourLifter
from earl_m2t.lift.conditions import ConditionLifter
from earl_m2t.lift.datatypes import DataTypeLifter
from earl_m2t.lift.links import AgentInstance, LinkLifter, SubsystemInstance
from earl_m2t.lift.recognise import Recogniser, Recognition
from earl_m2t.lift.replication import expand, instance_count, multiplicity, over_bound
from earl_m2t.lift.tags import tag
from earl_m2t.lift.variability import configurations, host_of, is_optional, reactivation_of
from earl_m2t.model.elements import (
    Agent,
    BasicBehaviour,
    Buffer,
    Fsm,
    Group,
    GroupMember,
    Memory,
    Robot,
    Subsystem,
    System,
)
from earl_m2t.model.kinds import Direction, GroupKind, ReceiveMode, SubsystemKind
from earl_m2t.model.limits import MAX_QUEUE
from earl_m2t.model.location import Location
from earl_m2t.read.xmi import Element, ExternalRef, RawModel


def computed_agent_type(has_e: bool, has_r: bool, has_t: bool) -> str:
    """Paper Table 2: C always, E with effectors, R with receptors, T with inter-agent links."""
    return "C" + ("E" if has_e else "") + ("R" if has_r else "") + ("T" if has_t else "")


class StructureLifter:
    """Finds the systems of a model and lifts everything under them; collects R001 and C001 notes."""

    def __init__(self, raw: RawModel, recogniser: Recogniser, types: DataTypeLifter) -> None:
        self.raw = raw
        self.recogniser = recogniser
        self.types = types
        self.conditions = ConditionLifter(types.datatypes)
        self.diagnostics: list[Diagnostic] = []
        self.recognised_anything = False
        self._outputs: set[str] = set()  # paths of every Output Buffer lifted so far
        self._templates: dict[str, tuple[str, str]] = {}  # instance path -> (template, instance name)
        self._owners: dict[str, tuple[str, str]] = {}  # buffer path -> (agent path, subsystem path)
        self._agent_group_blocks: list[Element] = []  # blocks of the Agent Groups met in the system
        self.links = LinkLifter(raw, recogniser, self.diagnostics, self._outputs, self._owners, self._templates)

    # -- helpers -----------------------------------------------------------------------------
    def _note(self, code: str, severity: Severity, message: str, el: Element, element: str = "") -> None:
        self.diagnostics.append(Diagnostic(code, severity, message, self.raw.location(el), element))

    def _recognise(self, el: Element, *names: str, path: str = "") -> Recognition:
        recognition = self.recogniser.recognise(el, *names)
        if recognition.concept:
            self.recognised_anything = True
        if recognition.conflict:
            element = path or self.raw.name(el)
            self._note("R001", Severity.WARNING,
                       f"{self.raw.uml_type(el).lower() or 'element'} '{self.raw.name(el)}': conflicting EARL "
                       f"evidence: {recognition.conflict}", el, element)
        return recognition

    def _parts(self, block: Element) -> list[tuple[Element, Element]]:
        """(part property, its block type) for every typed part of a block."""
        parts = []
        for attr in self.raw.children(block, "ownedAttribute"):
            if self.raw.uml_type(attr) != "Property":
                continue
            part_type = self.raw.ref(attr, "type")
            if part_type is None or isinstance(part_type, ExternalRef):
                continue
            if self.raw.uml_type(part_type) == "Class":
                parts.append((attr, part_type))
        return parts

    def _part_concept(self, part: Element, block: Element, path: str = "") -> tuple[str, str]:
        by_block = self._recognise(block, path=path)
        if by_block.concept:
            by_part = self.recogniser.by_suffix(self.raw.name(part))
            if by_part and not self.recogniser.compatible(by_block.concept, by_part):
                self._note("R001", Severity.WARNING,
                           f"part '{self.raw.name(part)}': conflicting EARL evidence: its block "
                           f"{self.raw.name(block)} is {by_block.concept} but the part name says {by_part}",
                           part, f"{path}.{self.raw.name(part)}" if path else self.raw.name(part))
            return by_block.concept, by_block.route
        by_part = self.recogniser.by_suffix(self.raw.name(part))
        if by_part:
            self.recognised_anything = True
        return by_part, ("suffix" if by_part else "")

    # -- systems -----------------------------------------------------------------------------
    def systems(self) -> list[System]:
        classes = self._all_classes()
        system_blocks = [c for c in classes if self._recognise(c).concept == "System"]
        if not system_blocks:
            system_blocks = self._implicit_systems(classes)
        return [self._system(block) for block in system_blocks]

    def _all_classes(self) -> list[Element]:
        """Every block of the model (the tag filter runs in lxml, not in Python)."""
        raw = self.raw
        found = []
        for top in raw.model_roots:
            for el in top.iter("packagedElement", "nestedClassifier"):
                # an element indexed under its own id is model content, not a tool extension's copy
                if raw.uml_type(el) == "Class" and raw.by_id.get(raw.xmi_id(el)) is el:
                    found.append(el)
        return found

    def _implicit_systems(self, classes: list[Element]) -> list[Element]:
        """Top-level blocks whose parts are robots or agents, when no block is declared a System."""
        used_as_part = {id(t) for c in classes for _, t in self._parts(c)}
        systems = []
        for block in classes:
            if id(block) in used_as_part:
                continue
            concepts = {self._part_concept(p, t)[0] for p, t in self._parts(block)}
            if concepts & {"Robot", "Agent", "AgentGroup"}:
                systems.append(block)
        return systems

    def _system(self, block: Element) -> System:
        name = self.raw.name(block)
        recognition = self.recogniser.recognise(block)
        robots: list[Robot] = []
        agents: list[AgentInstance] = []
        groups: list[Group] = []
        self._agent_group_blocks = []
        for part, part_type in self._parts(block):
            concept, _ = self._part_concept(part, part_type, name)
            if concept == "Robot":
                for robot_part_name, robot_index in self._instances(part):
                    robot_path = robot_part_name
                    robot_agents: list[str] = []
                    # agents of replicated robots are told apart by their robot
                    prefix = f"{robot_path}." if robot_index else ""
                    for agent_part, agent_block in self._parts(part_type):
                        agent_concept = self._part_concept(agent_part, agent_block, robot_path)[0]
                        if agent_concept == "Agent":
                            found = self._agents(agent_part, agent_block, robot_path, part, prefix)
                        elif agent_concept == "AgentGroup":
                            found = self._agent_group(agent_part, agent_block, robot_path, robot_path, prefix, groups)
                        else:
                            continue
                        agents.extend(found)
                        robot_agents.extend(inst.agent.path for inst in found)
                    route = self.recogniser.recognise(part_type).route or "suffix"
                    robots.append(Robot(robot_part_name, robot_path, self.raw.name(part_type), tuple(robot_agents),
                                        self.raw.location(part), route))
            elif concept == "Agent":
                agents.extend(self._agents(part, part_type, "", None))
            elif concept == "AgentGroup":
                agents.extend(self._agent_group(part, part_type, name, "", "", groups))
        links = self.links.system_links(block, name, agents, self._agent_group_blocks)
        linked_agents = {self._owners[end][0] for link in links for end in link.ends if end in self._owners}
        final_agents = []
        for inst in agents:
            agent = inst.agent
            has_t = agent.path in linked_agents
            has_e = bool(agent.ve) and bool(agent.re)
            has_r = bool(agent.vr) and bool(agent.rr)
            final_agents.append(replace(agent, computed_type=computed_agent_type(has_e, has_r, has_t)))
        every_link = [link for agent in final_agents for link in agent.links] + list(links)
        return System(name, name, tuple(robots), tuple(final_agents), tuple(links), self.raw.location(block),
                      recognition.route or "structure", tuple(groups),
                      configurations(self.raw, self.recogniser, block, name, final_agents, every_link))

    def _agent_group(self, part: Element, block: Element, owner: str, robot: str, prefix: str,
                     groups: list[Group]) -> list[AgentInstance]:
        """The Agents of an Agent Group part; the group itself is added to ``groups``."""
        path = f"{prefix}{self.raw.name(part)}"
        if all(b is not block for b in self._agent_group_blocks):
            self._agent_group_blocks.append(block)
        agents: list[AgentInstance] = []
        held: list[GroupMember] = []
        for member, member_block in self._parts(block):
            concept = self._part_concept(member, member_block, path)[0]
            held.append(GroupMember(self.raw.name(member), concept, self.raw.location(member)))
            if concept == "Agent":
                agents.extend(self._agents(member, member_block, robot, part, prefix))
        groups.append(Group(self.raw.name(part), path, GroupKind.AGENTS, self.raw.name(block), owner,
                            tuple(inst.agent.path for inst in agents), tuple(held), self.raw.location(part),
                            self.recogniser.recognise(block).route or "suffix"))
        return agents

    def _instances(self, part: Element) -> list[tuple[str, int]]:
        return expand(self.raw.name(part), self._count(part))

    def _count(self, el: Element) -> int:
        """How many instances ``el`` stands for; beyond the bound an R008 error, and one."""
        lower, upper = multiplicity(self.raw, el)
        if problem := over_bound(lower, upper):
            self._note("R008", Severity.ERROR, f"{self.raw.name(el)}: {problem}", el, self.raw.name(el))
            return 1
        return instance_count(lower, upper)

    # -- agents ------------------------------------------------------------------------------
    def _agents(self, part: Element, block: Element, robot: str, robot_part: Element | None,
                prefix: str = "") -> list[AgentInstance]:
        return [self._agent(name, f"{prefix}{name}", part, block, robot, robot_part)
                for name, _ in self._instances(part)]

    def _agent(self, name: str, path: str, part: Element, block: Element, robot: str,
               robot_part: Element | None) -> AgentInstance:
        self._templates[path] = (self.raw.name(part), name)
        subsystem_parts = []
        group_parts: list[tuple[Element, Element, list[GroupMember], list[Element]]] = []
        for sub_part, sub_block in self._parts(block):
            concept, route = self._part_concept(sub_part, sub_block, path)
            if concept == "SubsystemGroup":
                held, grouped = self._subsystem_group(sub_block, f"{path}.{self.raw.name(sub_part)}")
                subsystem_parts.extend(grouped)
                group_parts.append((sub_part, sub_block, held, [g[0] for g in grouped]))
                continue
            kind = self.recogniser.abbreviation(concept) if self.recogniser.is_a(concept, "Subsystem") else ""
            if kind:
                subsystem_parts.append((sub_part, sub_block, kind, route))
        instances: list[SubsystemInstance] = []
        for sub_part, sub_block, kind, route in subsystem_parts:
            for sub_name, index in self._instances(sub_part):
                instances.append(self._subsystem(sub_part, sub_block, kind, route, path, sub_name, index))
        links = self.links.agent_links(block, path, instances)
        groups = []
        for group_part, group_block, held, members in group_parts:
            links.extend(self.links.agent_links(group_block, path, instances))
            member_paths = tuple(i.subsystem.path for i in instances if any(i.part is m for m in members))
            group_name = self.raw.name(group_part)
            groups.append(Group(group_name, f"{path}.{group_name}", GroupKind.SUBSYSTEMS, self.raw.name(group_block),
                                path, member_paths, tuple(held), self.raw.location(group_part),
                                self.recogniser.recognise(group_block).route or "suffix"))
        tags = self.recogniser.tags(block)
        declared = (tags.get("declaredType") or tags.get("type") or "").strip()
        agent = Agent(name, path, self.raw.name(block), robot, tuple(i.subsystem for i in instances), tuple(links),
                      declared, "", self.raw.location(part), self.recogniser.recognise(block).route or "suffix",
                      tuple(groups), is_optional(self.raw, part), reactivation_of(self.raw, tags), host_of(tags))
        return AgentInstance(agent, part, robot_part, instances)

    def _subsystem_group(self, block: Element,
                         path: str) -> tuple[list[GroupMember], list[tuple[Element, Element, str, str]]]:
        """The parts of a Subsystem Group's block, and those it contributes to its Agent: Virtual
        and Real Effectors and Receptors (a Control Subsystem belongs in the Agent itself, S011)."""
        held: list[GroupMember] = []
        grouped: list[tuple[Element, Element, str, str]] = []
        for sub_part, sub_block in self._parts(block):
            concept, route = self._part_concept(sub_part, sub_block, path)
            held.append(GroupMember(self.raw.name(sub_part), concept, self.raw.location(sub_part)))
            if self.recogniser.is_a(concept, "Subsystem") and concept != "ControlSubsystem":
                grouped.append((sub_part, sub_block, self.recogniser.abbreviation(concept), route))
        return held, grouped

    # -- subsystems --------------------------------------------------------------------------
    def _subsystem(self, part: Element, block: Element, kind: str, route: str, agent_path: str,
                   name: str, index: int) -> SubsystemInstance:
        raw = self.raw
        path = f"{agent_path}.{name}"
        inputs: list[Buffer] = []
        outputs: list[Buffer] = []
        memory: list[Memory] = []
        ports: dict[int, list[Buffer]] = {}
        for attr in raw.children(block, "ownedAttribute") + raw.children(block, "ownedPort"):
            attr_type = raw.uml_type(attr)
            attr_name = raw.name(attr)
            recognition = self._recognise(attr, path=f"{path}.{attr_name}")
            concept = recognition.concept
            if attr_type == "Port" or concept in ("InputBuffer", "OutputBuffer"):
                if concept not in ("InputBuffer", "OutputBuffer"):
                    continue
                direction = Direction.IN if concept == "InputBuffer" else Direction.OUT
                datatype, unresolved = self.types.type_of(attr)
                count = self._count(attr)
                tags = self.recogniser.tags(attr)
                receive, queue_size = (receive_of(raw, tags) if direction is Direction.IN
                                       else (ReceiveMode.LATEST, 0))
                if queue_size > MAX_QUEUE:
                    self._note("R008", Severity.ERROR, f"{path}.{attr_name}: a queue of {queue_size} values, more "
                               f"than the {MAX_QUEUE} earl-m2t generates", attr, f"{path}.{attr_name}")
                buffers = [
                    Buffer(inst, f"{path}.{inst}", direction, datatype, attr_name, k, raw.location(attr),
                           recognition.route, unresolved, receive, queue_size, tag(tags, "side") or "",
                           tag(tags, "converter") or "", tag(tags, "channel") or "", reliability_of(raw, tags))
                    for inst, k in expand(attr_name, count)
                ]
                ports[id(attr)] = buffers
                self._owners.update((b.path, (agent_path, path)) for b in buffers)
                if direction == "out":
                    self._outputs.update(b.path for b in buffers)
                (inputs if direction == "in" else outputs).extend(buffers)
            elif concept == "InternalMemory":
                datatype, unresolved = self.types.type_of(attr)
                count = self._count(attr)
                memory.extend(
                    Memory(inst, f"{path}.{inst}", datatype, attr_name, k, raw.location(attr), recognition.route,
                           unresolved)
                    for inst, k in expand(attr_name, count)
                )
        ctx = BehaviourContext(raw, self.recogniser, path, tuple(inputs), tuple(outputs), tuple(memory))
        lifter = BehaviourLifter(ctx)
        predicates = lifter.predicates(block)
        scope = self.conditions.scope(inputs + outputs, memory, predicates)
        ctx.make_condition = partial(self.conditions.make, scope=scope)
        predicates = self.conditions.resolve_predicates(predicates, scope)
        machines = lifter.state_machines(block)
        fsm: Fsm | None = None
        behaviours: list[BasicBehaviour] = []
        if machines:
            fsm, behaviours = lifter.fsm(machines[0])
        # one basic behaviour per activity: the states that call a shared one name it, and it is
        # an owned behaviour of the block too; two activities of one name are two (rule S012)
        shared = [b for b, concept in lifter.owned_behaviours(block) if concept == "BasicBehaviour"]
        known = {(b.name, b.location) for b in behaviours}
        for activity in shared:
            if (raw.name(activity), raw.location(activity)) not in known:
                behaviours.append(lifter.basic_behaviour(activity, raw.name(activity)))
                known.add((raw.name(activity), raw.location(activity)))
        unique = []
        seen: set[tuple[str, Location]] = set()
        for bb in behaviours:
            if (bb.name, bb.location) not in seen:
                seen.add((bb.name, bb.location))
                unique.append(bb)
        subsystem = Subsystem(
            name, path, SubsystemKind(kind), agent_path, raw.name(block), raw.xmi_id(block), raw.name(part), index,
            tuple(inputs), tuple(outputs), tuple(memory), fsm, tuple(unique), lifter.functions(block),
            predicates, lifter.exclusions(block), len(machines), raw.location(part), route,
            buffer_groups(raw, self.recogniser, block, path), scope, simulation_of(self.recogniser.tags(block)),
        )
        self._templates[path] = (raw.name(part), name)
        return SubsystemInstance(subsystem, part, ports)
