"""What the diagrams show, as plain data for the DOT templates of ``transforms/diagrams/``.

Four kinds of diagram, each named by the anchor of its element (see
:mod:`earl_m2t.gen.views.anchors`):

- ``system``: the agents (with their Table 2 type), grouped by robot and by Agent Group, and
  the inter-agent links labelled with their dataType; variable agents and links drawn dashed,
  with the configurations they are present in;
- ``system-<configuration>``: the same for one configuration of a variable-structure system,
  only what is present while it holds;
- ``agent-<agent>``: the agent's subsystems grouped by kind, each with its buffers (and the
  Subsystem Group it belongs to), and the inter-subsystem links from Output Buffer to Input
  Buffer labelled with their dataType;
- ``fsm-<subsystem>``: the FSM of a subsystem definition: states with their basic
  behaviour (and the configuration a coordinator's state switches to, a quiescent state
  drawn with a double border), the initial state, transitions labelled with condition and
  priority;
- ``tf-<behaviour>``: a basic behaviour's transition function: its pf stage by stage, what
  each pf reads (Input Buffers, memory) and writes (memory, Output Buffers).

Node and edge order follows the model, so ``dot`` lays a model out the same way every time.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from earl_m2t.gen.views.tables import ConfigurationRow, SpecTables, SubsystemTables
from earl_m2t.model.elements import Agent, EarlModel
from earl_m2t.model.kinds import SUBSYSTEM_KINDS


@dataclass(frozen=True)
class Diagram:
    name: str  # file stem: ``system``, ``agent-manip-a`` …
    kind: str  # "system" | "agent" | "fsm" | "tf"
    title: str
    element: str  # anchor of the element it shows
    context: dict[str, Any]  # the template's data


def build_diagrams(model: EarlModel, tables: SpecTables) -> tuple[Diagram, ...]:
    diagrams = [_system(model, tables)]
    diagrams.extend(_system(model, tables, row) for row in tables.configurations)
    agents = {a.path: a for a in model.agents}
    for agent_tables in tables.agents:
        diagrams.append(_agent(model, agents[agent_tables.name], tables))
    for sub in tables.subsystems:
        if sub.states:
            diagrams.append(_fsm(sub))
        for index, _bb in enumerate(sub.behaviours):
            diagrams.append(_tf(sub, index))
    return tuple(diagrams)


def _system(model: EarlModel, tables: SpecTables, configuration: ConfigurationRow | None = None) -> Diagram:
    """The agents and inter-agent links; with a configuration, only what is present while it holds."""
    present_agents = _present(tables.agent_types, configuration)
    ids = {row.name: f"a{i}" for i, row in enumerate(tables.agent_types) if row.name in present_agents}
    agents = [{"id": ids[row.name], "name": row.name, "type": row.type, "description": row.description,
               "block": row.block, "variable": ", ".join(row.configurations) if configuration is None else ""}
              for row in tables.agent_types if row.name in ids]
    groups = [group for system in model.systems for group in system.groups]
    grouped = {member for group in groups for member in group.members}

    def agent_groups(owner: str) -> list[dict[str, Any]]:
        return [{"id": f"cluster_g{i}", "name": group.name,
                 "agents": [ids[a] for a in group.members if a in ids]}
                for i, group in enumerate(groups) if group.owner == owner]

    robots = [{"id": f"cluster_r{i}", "name": robot.name, "groups": agent_groups(robot.path),
               "agents": [ids[a] for a in robot.agents if a in ids and a not in grouped]}
              for i, robot in enumerate(model.robots)]
    links = []
    present_links = _present(tables.links, configuration)
    for link in tables.links:
        source, target = model.subsystem_of(link.source), model.subsystem_of(link.target)
        if source is None or target is None or source.agent not in ids or target.agent not in ids:
            continue
        if link.name not in present_links:
            continue
        links.append({"source": ids[source.agent], "target": ids[target.agent], "datatype": link.datatype,
                      "name": link.name,
                      "variable": ", ".join(link.configurations) if configuration is None else ""})
    if configuration is None:
        return Diagram(name="system", kind="system", title=f"system {tables.system}", element=tables.system_anchor,
                       context={"title": f"{tables.system}: agents and inter-agent links", "agents": agents,
                                "robots": robots, "groups": agent_groups(tables.system), "links": links})
    return Diagram(name=f"system-{configuration.anchor}", kind="system",
                   title=f"configuration {configuration.name}", element=configuration.anchor,
                   context={"title": f"{tables.system} in configuration {configuration.name}", "agents": agents,
                            "robots": robots, "groups": agent_groups(tables.system), "links": links})


def _present(rows: tuple[Any, ...], configuration: ConfigurationRow | None) -> frozenset[str]:
    """Names of the agents or links present in a configuration: those always present and those
    it names; every one for the general model."""
    if configuration is None:
        return frozenset(row.name for row in rows)
    return frozenset(row.name for row in rows
                     if not row.configurations or configuration.name in row.configurations)


def _agent(model: EarlModel, agent: Agent, tables: SpecTables) -> Diagram:
    anchor = tables.anchors.get(agent.path)
    node_of: dict[str, str] = {}  # subsystem path -> node id
    port_of: dict[str, tuple[str, str]] = {}  # buffer path -> (node id, port)
    groups = []
    group_of = {member: group.name for group in agent.groups for member in group.members}
    for kind in SUBSYSTEM_KINDS:
        members = []
        for sub in agent.of_kind(kind):
            node = f"s{len(node_of)}"
            node_of[sub.path] = node
            buffers = []
            for number, buf in enumerate(sub.buffers):
                port = f"p{number}"
                port_of[buf.path] = (node, port)
                datatype = model.datatypes.get(buf.datatype)
                buffers.append({"port": port, "name": buf.name, "direction": buf.direction,
                                "datatype": datatype.name if datatype else (buf.type_ref or "?")})
            members.append({"id": node, "name": sub.name, "block": sub.block, "group": group_of.get(sub.path, ""),
                            "inputs": [b for b in buffers if b["direction"] == "in"],
                            "outputs": [b for b in buffers if b["direction"] == "out"]})
        if members:
            groups.append({"id": f"cluster_{kind}", "kind": kind, "title": tables.kinds.get(kind, kind),
                           "members": members})
    links = []
    for link in agent.links:
        if link.source in port_of and link.target in port_of:
            source = model.buffer(link.source)
            datatype = model.datatypes.get(source.datatype) if source is not None else None
            links.append({"source": port_of[link.source], "target": port_of[link.target],
                          "datatype": datatype.name if datatype else "?"})
    return Diagram(name=f"agent-{anchor}", kind="agent", title=f"agent {agent.name}", element=anchor,
                   context={"title": f"{agent.name} (type {agent.computed_type}): subsystems, buffers and links",
                            "groups": groups, "links": links})


def _fsm(sub: SubsystemTables) -> Diagram:
    ids = {state.name: f"q{i}" for i, state in enumerate(sub.states)}
    states = [{"id": ids[s.name], "name": s.name, "behaviour": s.behaviour, "initial": s.name == sub.initial,
               "configuration": s.configuration, "quiescent": s.quiescent}
              for s in sub.states]
    transitions = [{"source": ids[t.source], "target": ids[t.target], "name": t.name,
                    "condition": t.condition or "TRUE", "priority": t.priority}
                   for t in sub.transitions if t.source in ids and t.target in ids]
    return Diagram(name=f"fsm-{sub.anchor}", kind="fsm", title=f"FSM of {sub.path}", element=sub.fsm_anchor,
                   context={"title": f"{sub.path}.fsm", "states": states, "transitions": transitions,
                            "initial": ids.get(sub.initial, "")})


def _tf(sub: SubsystemTables, index: int) -> Diagram:
    bb = sub.behaviours[index]
    functions = {f.name: f for f in sub.functions}
    kind_of = {row.name: row.kind for row in sub.inputs + sub.outputs + sub.memory}
    storage: dict[str, dict[str, str]] = {}

    def node(name: str) -> str:
        if name not in storage:
            storage[name] = {"id": f"d{len(storage)}", "name": name, "kind": kind_of.get(name, "m")}
        return storage[name]["id"]

    stages: list[dict[str, Any]] = []
    reads: list[dict[str, str]] = []
    writes: list[dict[str, str]] = []
    for number, stage in enumerate(bb.stages, start=1):
        members = []
        for position, pf_name in enumerate(stage):
            pf_id = f"f{number}_{position}"
            members.append({"id": pf_id, "name": pf_name, "known": pf_name in functions})
            pf = functions.get(pf_name)
            if pf is None:
                continue
            reads.extend({"source": node(name), "target": pf_id} for name in pf.reads)
            writes.extend({"source": pf_id, "target": node(name)} for name in pf.writes)
        stages.append({"id": f"cluster_stage{number}", "number": number, "functions": members})
    return Diagram(name=f"tf-{bb.anchor}", kind="tf", title=f"transition function of {sub.path}.{bb.name}",
                   element=bb.anchor,
                   context={"title": f"{sub.path}.{bb.name}.tf", "stages": stages,
                            "storage": list(storage.values()), "reads": reads, "writes": writes})
