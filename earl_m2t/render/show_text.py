"""``earl-m2t show``: the lifted model as an indented outline for people."""

from __future__ import annotations

from itertools import groupby

from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import Activation, Agent, Buffer, Configuration, EarlModel, Group, Link, State, Subsystem
from earl_m2t.model.kinds import Reactivation


def _multiplicity(lower: int, upper: int | None) -> str:
    if lower == 1 and upper == 1:
        return ""
    upper_text = "*" if upper is None else str(upper)
    return f"[{upper_text}]" if lower == upper else f"[{lower}..{upper_text}]"


def render_model(model: EarlModel) -> str:
    """The outline; the LTL properties written in the model come last."""
    lines = _outline(model)
    if model.properties:
        lines.append("ltl properties")
        lines.extend(f"  {p.title}: {p.text}  (line {p.location.line})" for p in model.properties)
    return "\n".join(lines) + "\n"


def _outline(model: EarlModel) -> list[str]:
    lines: list[str] = [f"model {model.name or '(unnamed)'}  ({model.dialect}) {model.file}"]
    if not model.has_earl_content:
        lines.append("  holds no EARL model: no System, Robot or Agent was recognised")
        return lines
    if not model.systems:
        lines.append("  has EARL elements but no System block holding robots or agents")
    for system in model.systems:
        lines.append(f"system {system.name}")
        for robot in system.robots:
            lines.append(f"  robot {robot.name} [{robot.block}]: {', '.join(robot.agents) or '(no agent)'}")
        for agent in system.agents:
            declared = f", declared {agent.declared_type}" if agent.declared_type else ""
            where = f" in {agent.robot}" if agent.robot else ""
            lines.append(f"  agent {agent.name} [{agent.block}]{where}  type {agent.computed_type}{declared}"
                         f"{_variability(agent)}")
            for _, group in groupby(agent.subsystems, key=lambda s: (s.block_id, s.template)):
                instances = list(group)
                lines.extend(_subsystem(instances))
            lines.extend(_group(group, "    ") for group in agent.groups)
            if agent.links:
                lines.append("    links")
                lines.extend(_link(link, "      ") for link in agent.links)
        lines.extend(_group(group, "  ") for group in system.groups)
        if system.links:
            lines.append("  inter-agent links")
            lines.extend(_link(link, "    ") for link in system.links)
        if system.configurations:
            lines.append("  configurations")
            lines.extend(_configuration(c, "    ") for c in system.configurations)
    if model.datatypes:
        lines.append("datatypes")
        lines.extend(_datatype(d) for d in model.datatypes.values())
    return lines


def _group(group: Group, indent: str) -> str:
    members = ", ".join(m.rpartition(".")[2] if group.kind == "gs" else m for m in group.members)
    return f"{indent}group {group.kind} {group.name} [{group.block}] in {group.owner}: {members or '(empty)'}"


def _subsystem(instances: list[Subsystem]) -> list[str]:
    sub = instances[0]
    name = (sub.name if len(instances) == 1
            else f"{sub.template} ×{len(instances)} ({instances[0].name} … {instances[-1].name})")
    out = [f"    {sub.kind} {name} [{sub.block}]"]
    ind = "      "
    for buf in _unique_templates(sub.inputs):
        out.append(f"{ind}ib {buf.template}{_count(sub.inputs, buf.template)} : {buf.datatype or '?'}"
                   f"{_receive(buf)}{_reliability(buf)}")
    for buf in _unique_templates(sub.outputs):
        out.append(f"{ind}ob {buf.template}{_count(sub.outputs, buf.template)} : {buf.datatype or '?'}"
                   f"{_reliability(buf)}")
    for mem in _unique_templates(sub.memory):
        out.append(f"{ind}m  {mem.template}{_count(sub.memory, mem.template)} : {mem.datatype or '?'}")
    if sub.fsm is not None:
        fsm = sub.fsm
        out.append(f"{ind}fsm {fsm.name}  initial {fsm.initial or '?'}")
        for state in fsm.states:
            out.append(f"{ind}  state {state.name} → {', '.join(state.behaviours) or '(no behaviour)'}"
                       f"{_activation(state.activation)}{_state_variability(state)}")
        for tr in fsm.transitions:
            condition = tr.condition.text if tr.condition is not None else "TRUE"
            priority = f"  priority {tr.priority}" if tr.priority else ""
            out.append(f"{ind}  {tr.name}: {tr.source} → {tr.target} if {condition}{priority}")
    for bb in sub.behaviours:
        tc = bb.tc.text if bb.tc is not None else "FALSE"
        ec = bb.ec.text if bb.ec is not None else "FALSE"
        out.append(f"{ind}bb {bb.name}  tc: {tc}  ec: {ec}")
        for number, stage in enumerate(bb.stages, start=1):
            out.append(f"{ind}  stage {number}: {', '.join(stage)}")
    for pf in sub.functions:
        reads = ", ".join(dict.fromkeys(a.name for a in pf.accesses if a.mode != "write")) or "-"
        writes = ", ".join(dict.fromkeys(a.name for a in pf.accesses if a.mode != "read")) or "-"
        out.append(f"{ind}pf {pf.name}  reads {reads}  writes {writes}")
    for pp in sub.predicates:
        body = pp.fun.text if pp.fun is not None else f"(user code, {pp.language})"
        out.append(f"{ind}pp {pp.name} = {body}")
    for exclusion in sub.exclusions:
        out.append(f"{ind}exclusive {', '.join(exclusion.predicates)}")
    for group in sub.buffer_groups:
        out.append(f"{ind}buffer group {group.name}: obligatory {', '.join(group.obligatory) or '-'}"
                   f"  optional {', '.join(group.optional) or '-'}")
    return out


def _variability(agent: Agent) -> str:
    """``  optional, reactivation resume, host arm``; nothing for an agent of a fixed structure
    on the default host."""
    parts = ["optional"] if agent.optional else []
    if agent.reactivation != Reactivation.RESTART:
        parts.append(f"reactivation {agent.reactivation}")
    if agent.host:
        parts.append(f"host {agent.host}")
    return f"  {', '.join(parts)}" if parts else ""


def _state_variability(state: State) -> str:
    parts = [f"configuration {state.configuration}"] if state.configuration else []
    if state.quiescent:
        parts.append("quiescent")
    return f"  ({', '.join(parts)})" if parts else ""


def _configuration(configuration: Configuration, indent: str) -> str:
    agents = " ".join(configuration.agents) or "-"
    links = " ".join(configuration.links) or "-"
    timeout = (f"  switch timeout {seconds(configuration.switch_timeout)}"
               if configuration.switch_timeout is not None else "")
    unknown = f"  unknown {', '.join(configuration.unknown)}" if configuration.unknown else ""
    return f"{indent}{configuration.name}: agents {agents}  links {links}{timeout}{unknown}"


def _receive(buffer: Buffer) -> str:
    """How an Input Buffer receives, when not EARL's default (the latest value)."""
    if buffer.receive == "queue":
        return f"  receive queue of {buffer.queue_size}"
    return "" if buffer.receive == "latest" else f"  receive {buffer.receive}"


def _reliability(buffer: Buffer) -> str:
    """``  best_effort`` for a buffer whose link may drop values; nothing for EARL's default."""
    return "" if buffer.reliability == "reliable" else f"  {buffer.reliability}"


def seconds(value: float) -> str:
    return f"{value:g} s"


def _activation(activation: Activation) -> str:
    """``  [group command, min period 0.001 s, …]``; nothing for the default (own period)."""
    parts = [f"group {activation.group}"] if activation.group else []
    for label, value in (("min period", activation.min_period), ("first timeout", activation.first_timeout),
                         ("next timeout", activation.next_timeout)):
        if value is not None:
            parts.append(f"{label} {seconds(value)}")
    return f"  [{', '.join(parts)}]" if parts else ""


def _unique_templates(items):
    seen = set()
    for item in items:
        if item.template not in seen:
            seen.add(item.template)
            yield item


def _count(items, template: str) -> str:
    n = sum(1 for item in items if item.template == template)
    return f"[{n}]" if n > 1 else ""


def _link(link: Link, indent: str) -> str:
    name = link.name or "(unnamed)"
    if link.source and link.target:
        return f"{indent}{name}: {link.source} → {link.target}"
    return f"{indent}{name}: {link.ends[0] or '?'} — {link.ends[1] or '?'} (direction unclear)"


def _datatype(datatype: DataType) -> str:
    if datatype.kind == "primitive":
        return f"  {datatype.qualified_name}: primitive {datatype.primitive}"
    if datatype.kind == "enumeration":
        return f"  {datatype.qualified_name}: enumeration {', '.join(datatype.literals)}"
    fields = ", ".join(f"{f.name}: {f.type or '?'}{_multiplicity(f.lower, f.upper)}" for f in datatype.fields)
    return f"  {datatype.qualified_name} {{{fields}}}"
