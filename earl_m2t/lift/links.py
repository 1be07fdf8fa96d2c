"""Lifting the links (ibd connectors): between the subsystems of an agent, and between agents
(through robot and agent parts, and Agent Groups); collects the C001 notes of connectors that do
not join two subsystem buffers."""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.lift.recognise import Recogniser
from earl_m2t.model.elements import Agent, Buffer, Link, Subsystem
from earl_m2t.model.kinds import LinkScope
from earl_m2t.read.connector_ends import EndTarget, resolve_end
from earl_m2t.read.xmi import Element, ExternalRef, RawModel


@dataclass
class SubsystemInstance:
    """A lifted subsystem plus the raw part/port elements links are resolved against."""

    subsystem: Subsystem
    part: Element
    ports: dict[int, list[Buffer]]  # id(port element) -> buffer instances


@dataclass
class AgentInstance:
    agent: Agent
    part: Element
    robot_part: Element | None  # the robot part holding the agent part, None directly in the system
    subsystems: list[SubsystemInstance]


@dataclass
class LinkLifter:
    """Lifts connectors into links, given what the structure lift found of the buffers."""

    raw: RawModel
    recogniser: Recogniser
    diagnostics: list[Diagnostic]
    outputs: set[str]  # paths of every Output Buffer
    owners: dict[str, tuple[str, str]]  # buffer path -> (agent path, subsystem path)
    templates: dict[str, tuple[str, str]]  # agent or subsystem instance path -> (template, instance name)

    def _note(self, message: str, el: Element, element: str) -> None:
        self.diagnostics.append(Diagnostic("C001", Severity.ERROR, message, self.raw.location(el), element))

    def _end_buffers(self, end: EndTarget, parts: dict[int, list[SubsystemInstance]]) -> list[str] | None:
        """Buffer paths one connector end stands for; None when it is not a subsystem buffer."""
        role, part = end.role, end.part_with_port
        if role is None or part is None:
            return None
        instances = parts.get(id(part))
        if not instances:
            return None
        found: list[str] = []
        for inst in instances:
            buffers = inst.ports.get(id(role))
            if buffers is None:
                return None
            found.extend(b.path for b in buffers)
        return found

    def agent_links(self, block: Element, agent_path: str, instances: list[SubsystemInstance]) -> list[Link]:
        parts: dict[int, list[SubsystemInstance]] = {}
        for inst in instances:
            parts.setdefault(id(inst.part), []).append(inst)
        links = []
        for connector in self.raw.in_connector_order(self.raw.children(block, "ownedConnector")):
            ends = [self._end_buffers(resolve_end(self.raw, e), parts) for e in self.raw.children(connector, "end")]
            links.extend(self._links(connector, ends, LinkScope.AGENT, agent_path))
        return links

    def system_links(self, block: Element, system: str, agents: list[AgentInstance],
                     group_blocks: list[Element]) -> list[Link]:
        """Links between agents: connectors of the system block, and of the Agent Groups' blocks."""
        connectors = self.raw.children(block, "ownedConnector")
        for group_block in group_blocks:
            connectors = connectors + self.raw.children(group_block, "ownedConnector")
        links = []
        for connector in self.raw.in_connector_order(connectors):
            ends = [self._nested_end_buffers(e, agents) for e in self.raw.children(connector, "end")]
            links.extend(self._links(connector, ends, LinkScope.SYSTEM, system))
        return links

    def _nested_end_buffers(self, end: Element, agents: list[AgentInstance]) -> list[str] | None:
        """Resolve an end nested through a robot part and an agent part (SysML NestedConnectorEnd)."""
        target = resolve_end(self.raw, end)
        path_parts = list(target.path)
        agent_parts = {id(a.part) for a in agents}
        agent_part = next((p for p in reversed(path_parts) if id(p) in agent_parts), None)
        if agent_part is None:
            return None
        outer = path_parts[: path_parts.index(agent_part)]
        robot_part = outer[-1] if outer else None
        found: list[str] = []
        for agent in agents:
            if agent.part is not agent_part or (robot_part is not None and agent.robot_part is not robot_part):
                continue
            parts: dict[int, list[SubsystemInstance]] = {}
            for inst in agent.subsystems:
                parts.setdefault(id(inst.part), []).append(inst)
            buffers = self._end_buffers(target, parts)
            if buffers is None:
                return None
            found.extend(buffers)
        return found or None

    def _links(self, connector: Element, ends: list[list[str] | None], scope: LinkScope, owner: str) -> list[Link]:
        raw = self.raw
        name = raw.name(connector)
        location = raw.location(connector)
        first = ends[0] if len(ends) == 2 else None
        second = ends[1] if len(ends) == 2 else None
        if first is None or second is None:
            if self._looks_like_link(connector):
                self._note(f"connector '{name or raw.xmi_id(connector)}' does not connect two subsystem buffers",
                           connector, f"{owner}.{name}" if name else owner)
            return []
        if len(first) == len(second):
            pairs = list(zip(first, second))
            replicated = len(first) > 1
        elif len(first) == 1 or len(second) == 1:
            pairs = [(a, b) for a in first for b in second]
            replicated = len(pairs) > 1
        else:
            self._note(f"connector '{name}' joins {len(first)} and {len(second)} replicated buffers: cannot pair them",
                       connector, f"{owner}.{name}")
            return []
        links = []
        for a, b in pairs:
            a_out, b_out = self._is_output(a), self._is_output(b)
            if a_out and not b_out:
                source, target = a, b
            elif b_out and not a_out:
                source, target = b, a
            else:
                source, target = "", ""  # two outputs or two inputs: rule C001
            instance = self._instance_link_name(name, (a, b), scope) if name and replicated else name
            display = instance or f"{self._end_owner(source or a, scope)[1]},{self._end_owner(target or b, scope)[1]}"
            links.append(Link(instance, f"{owner}.{display}" if scope == "agent" else display, (a, b),
                              source, target, scope, owner, name, location))
        return links

    def _is_output(self, buffer_path: str) -> bool:
        return buffer_path in self.outputs

    def _end_owner(self, buffer_path: str, scope: LinkScope) -> tuple[str, str]:
        """(template, instance name) of the subsystem (inside an agent) or agent (between agents)
        a link end belongs to."""
        agent, subsystem = self.owners.get(buffer_path, ("", ""))
        owner = agent if scope == "system" else subsystem
        return self.templates.get(owner, ("", "?"))

    def _instance_link_name(self, template: str, ends: tuple[str, str], scope: LinkScope) -> str:
        """``cs,motorControllerK/ve`` → ``cs,motorController3/ve``: each part naming a replicated
        end's template becomes that instance's name."""
        names: dict[str, str] = {}
        for end in ends:
            part_template, instance = self._end_owner(end, scope)
            names.setdefault(part_template, instance)
        return ",".join(names.get(part.strip(), part) for part in template.split(","))

    def _looks_like_link(self, connector: Element) -> bool:
        """A connector meant as an EARL link: stereotyped as one, or joining ports."""
        if self.recogniser.recognise(connector).concept:
            return True
        for end in self.raw.children(connector, "end"):
            role = self.raw.ref(end, "role")
            if role is not None and not isinstance(role, ExternalRef) and self.raw.uml_type(role) == "Port":
                return True
        return False
