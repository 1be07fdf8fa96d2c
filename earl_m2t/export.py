"""The lifted model as plain data: what ``earl-m2t show --format json`` prints.

The keys are documented in docs/show-and-stats.md (`earl-m2t show`) and kept stable.
"""

from __future__ import annotations

import math
from contextvars import ContextVar
from typing import Any

from earl_m2t.model.conditions import Condition
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import (
    Activation,
    Agent,
    BasicBehaviour,
    Buffer,
    Configuration,
    EarlModel,
    Fsm,
    Group,
    Link,
    Memory,
    State,
    Subsystem,
    System,
)
from earl_m2t.model.kinds import Reactivation
from earl_m2t.model.location import Location

FORMAT_VERSION = 1
_DOCUMENT_FILE: ContextVar[str] = ContextVar("document_file", default="")


def _where(location: Location) -> dict[str, Any]:
    """Line and id; and the file, for an element read from another file than the model's."""
    where: dict[str, Any] = {"line": location.line, "xmi_id": location.xmi_id}
    if location.line and location.file != _DOCUMENT_FILE.get():
        where["file"] = location.file
    return where


def _condition(condition: Condition | None) -> str | None:
    return condition.text if condition is not None else None


def _multiplicity(lower: int, upper: int | None) -> str:
    upper_text = "*" if upper is None else str(upper)
    return upper_text if lower == upper else f"{lower}..{upper_text}"


def model_to_dict(model: EarlModel) -> dict[str, Any]:
    token = _DOCUMENT_FILE.set(model.file)
    try:
        return {
            "format": FORMAT_VERSION,
            "file": model.file,
            "dialect": model.dialect,
            "model": model.name,
            "earl": model.has_earl_content,
            "systems": [_system(s) for s in model.systems],
            "datatypes": [_datatype(d) for d in model.datatypes.values()],
        }
    finally:
        _DOCUMENT_FILE.reset(token)


def _system(system: System) -> dict[str, Any]:
    return {
        "name": system.name,
        "recognised_by": system.recognised_by,
        **_where(system.location),
        "robots": [
            {"name": r.name, "block": r.block, "agents": list(r.agents), "recognised_by": r.recognised_by,
             **_where(r.location)}
            for r in system.robots
        ],
        "agents": [_agent(a) for a in system.agents],
        "links": [_link(link) for link in system.links],
        "groups": [_group(g) for g in system.groups],
        **({"configurations": [_configuration(c) for c in system.configurations]} if system.configurations else {}),
    }


def _configuration(configuration: Configuration) -> dict[str, Any]:
    return {"name": configuration.name, "path": configuration.path, "agents": list(configuration.agents),
            "links": list(configuration.links), "unknown_agents": list(configuration.unknown_agents),
            "unknown_links": list(configuration.unknown_links),
            "switch_timeout": _seconds(configuration.switch_timeout), **_where(configuration.location)}


def _variability(agent: Agent) -> dict[str, Any]:
    """An agent's variable-structure fields, only where they differ from a fixed structure's (so
    the JSON of a model without configurations stays as it was)."""
    if not agent.optional and agent.reactivation == Reactivation.RESTART:
        return {}
    return {"optional": agent.optional, "reactivation": agent.reactivation}


def _state_variability(state: State) -> dict[str, Any]:
    found: dict[str, Any] = {}
    if state.configuration:
        found["configuration"] = state.configuration
    if state.quiescent:
        found["quiescent"] = True
    return found


def _group(group: Group) -> dict[str, Any]:
    return {"name": group.name, "path": group.path, "kind": group.kind, "block": group.block, "owner": group.owner,
            "members": list(group.members), "recognised_by": group.recognised_by, **_where(group.location)}


def _agent(agent: Agent) -> dict[str, Any]:
    return {
        "name": agent.name,
        "path": agent.path,
        "block": agent.block,
        "robot": agent.robot or None,
        "type": agent.computed_type,
        "declared_type": agent.declared_type or None,
        **_variability(agent),
        **({"host": agent.host} if agent.host else {}),
        "recognised_by": agent.recognised_by,
        **_where(agent.location),
        "subsystems": [_subsystem(s) for s in agent.subsystems],
        "links": [_link(link) for link in agent.links],
        "groups": [_group(g) for g in agent.groups],
    }


def _buffer(buf: Buffer | Memory) -> dict[str, Any]:
    return {"name": buf.name, "path": buf.path, "datatype": buf.datatype or None, "template": buf.template,
            **_where(buf.location)}


def _input(buf: Buffer) -> dict[str, Any]:
    return {**_output(buf), "receive": buf.receive, "queue_size": buf.queue_size if buf.receive == "queue" else None}


def _output(buf: Buffer) -> dict[str, Any]:
    return {**_buffer(buf), **({"reliability": buf.reliability} if buf.reliability != "reliable" else {})}


def _activation(activation: Activation) -> dict[str, Any]:
    return {"group": activation.group or None, "min_period": _seconds(activation.min_period),
            "first_timeout": _seconds(activation.first_timeout), "next_timeout": _seconds(activation.next_timeout)}


def _seconds(value: float | None) -> float | None:
    """Seconds as JSON: a value that is not a number (rule B011 reports it) as null."""
    return None if value is None or math.isnan(value) else value


def _subsystem(sub: Subsystem) -> dict[str, Any]:
    return {
        "name": sub.name,
        "path": sub.path,
        "kind": sub.kind,
        "block": sub.block,
        "template": sub.template,
        "recognised_by": sub.recognised_by,
        **_where(sub.location),
        "inputs": [_input(b) for b in sub.inputs],
        "outputs": [_output(b) for b in sub.outputs],
        "memory": [_buffer(m) for m in sub.memory],
        "fsm": _fsm(sub.fsm) if sub.fsm is not None else None,
        "behaviours": [_behaviour(b) for b in sub.behaviours],
        "functions": [
            {"name": pf.name, "reads": [p.rpartition(".")[2] for p in pf.reads],
             "writes": [p.rpartition(".")[2] for p in pf.writes], "language": pf.language or None,
             **_where(pf.location)}
            for pf in sub.functions
        ],
        "predicates": [
            {"name": pp.name, "fun": _condition(pp.fun), "language": pp.language or None,
             "user_code": pp.fun is None, **_where(pp.location)}
            for pp in sub.predicates
        ],
        "exclusions": [{"name": e.name, "predicates": list(e.predicates), **_where(e.location)}
                       for e in sub.exclusions],
        "buffer_groups": [{"name": g.name, "obligatory": list(g.obligatory), "optional": list(g.optional),
                           **_where(g.location)} for g in sub.buffer_groups],
    }


def _fsm(fsm: Fsm) -> dict[str, Any]:
    return {
        "name": fsm.name,
        "initial": fsm.initial,
        **_where(fsm.location),
        "states": [{"name": s.name, "behaviour": s.behaviours[0] if len(s.behaviours) == 1 else None,
                    "activation": _activation(s.activation), **_state_variability(s), **_where(s.location)}
                   for s in fsm.states],
        "transitions": [
            {"name": t.name, "source": t.source, "target": t.target, "condition": _condition(t.condition),
             "priority": t.priority, **_where(t.location)}
            for t in fsm.transitions
        ],
    }


def _behaviour(bb: BasicBehaviour) -> dict[str, Any]:
    return {
        "name": bb.name,
        "tc": _condition(bb.tc),
        "ec": _condition(bb.ec),
        "stages": [list(stage) for stage in bb.stages],
        **_where(bb.location),
    }


def _link(link: Link) -> dict[str, Any]:
    return {
        "name": link.name or None,
        "path": link.path,
        "source": link.source or None,
        "target": link.target or None,
        "scope": "inter-agent" if link.scope == "system" else "inter-subsystem",
        **_where(link.location),
    }


def _datatype(datatype: DataType) -> dict[str, Any]:
    return {
        "name": datatype.name,
        "qualified_name": datatype.qualified_name,
        "kind": datatype.kind,
        "primitive": datatype.primitive or None,
        "fields": [{"name": f.name, "type": f.type or None, "multiplicity": _multiplicity(f.lower, f.upper)}
                   for f in datatype.fields],
        "literals": list(datatype.literals),
        **_where(datatype.location),
    }
