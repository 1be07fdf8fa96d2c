"""The paper-style tables of a model (EARL paper Tables 2 and 4–7), as plain data.

Computed once from the :class:`EarlModel` and shared by the HTML report, the markdown
target and the diagrams: agent types (Table 2), per subsystem definition its buffers,
memory (Table 4), primitive predicates (Table 5), transition conditions and terminal /
error conditions (Table 6), and the composition matrix of the transition functions: which
pf of which stage writes which memory and output buffer (Table 7). Replicated elements
are listed once, by their template (``windingCurrentK/m`` ×6). Conditions are printed
with ∧ ∨ ¬ (:func:`earl_m2t.predicate.format_predicate`); a condition that does not parse
keeps its text.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import PurePosixPath
from typing import Any

from earl_m2t import resources
from earl_m2t.gen.views.anchors import AnchorIndex
from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import Activation, Agent, EarlModel, Link, Subsystem
from earl_m2t.model.kinds import SUBSYSTEM_KINDS
from earl_m2t.model.naming import stem
from earl_m2t.model.variability import coordinator
from earl_m2t.predicate import format_predicate


@cache
def wording() -> dict[str, Any]:
    """``transforms/report/tables.toml``: agent type descriptions and subsystem kind titles."""
    path = resources.data_dir("transforms") / "report" / "tables.toml"
    return tomllib.loads(path.read_text(encoding="utf-8"))


@dataclass(frozen=True)
class AgentTypeRow:
    """Paper Table 2 for one agent: its type and the numbers that make it."""

    name: str
    anchor: str
    block: str
    robot: str
    type: str
    declared: str
    description: str
    counts: tuple[int, ...]  # |cs| |ve| |re| |vr| |rr| |aa|
    configurations: tuple[str, ...] = ()  # those it is present in; () when always present


@dataclass(frozen=True)
class GroupRow:
    """An Agent Group or a Subsystem Group: what it gathers, for which system, robot or agent."""

    name: str
    kind: str  # "agent group" | "subsystem group"
    block: str
    owner: str
    members: tuple[str, ...]  # agent paths, or subsystem names within the owner


@dataclass(frozen=True)
class StorageRow:
    """A buffer or memory (Table 4 for memory); replicated ones once, with their count."""

    name: str  # the template name (``windingCurrentK/m``)
    anchor: str
    kind: str  # "ib" | "ob" | "m"
    datatype: str
    count: int  # number of replicated instances, 0 when not replicated
    receive: str = ""  # how an Input Buffer receives when not the latest value: "queue of 8"


@dataclass(frozen=True)
class PredicateRow:
    """Table 5: a primitive predicate and its ``fun``."""

    name: str
    anchor: str
    fun: str
    language: str  # "EARL", or the language of a body in user code


@dataclass(frozen=True)
class TransitionRow:
    """Table 6 (upper part): a transition and its initial condition."""

    name: str
    anchor: str
    source: str
    target: str
    condition: str
    priority: int


@dataclass(frozen=True)
class BehaviourRow:
    """Table 6 (lower part): a basic behaviour, its terminal and error conditions, its tf stages."""

    name: str
    anchor: str
    tc: str
    ec: str
    stages: tuple[tuple[str, ...], ...]
    states: tuple[str, ...]  # FSM states it is associated with


@dataclass(frozen=True)
class StateRow:
    name: str
    anchor: str
    behaviour: str  # its basic behaviour ("" when it has none; several are joined with ", ")
    activation: str = ""  # "group motors, min period 0.001 s, …"; "" for the subsystem's own period
    configuration: str = ""  # the configuration a coordinator's state names
    quiescent: bool = False  # a switch may stop its agent while it is current


@dataclass(frozen=True)
class BufferGroupRow:
    """A buffer group: the Input Buffers an iteration waits for, and those read when new."""

    name: str
    anchor: str
    obligatory: tuple[str, ...]
    optional: tuple[str, ...]


@dataclass(frozen=True)
class FunctionRow:
    """A partial transition function and what it reads and writes (template names)."""

    name: str
    anchor: str
    reads: tuple[str, ...]
    writes: tuple[str, ...]


@dataclass(frozen=True)
class CompositionRow:
    """Table 7, one row: a pf of a behaviour's tf, its stage, and a mark per column."""

    behaviour: str
    behaviour_anchor: str
    stage: int
    function: str
    function_anchor: str  # "" when the tf names a pf the subsystem does not have
    memory: tuple[bool, ...]
    outputs: tuple[bool, ...]


@dataclass(frozen=True)
class Composition:
    """Table 7: the tf composition matrix of one subsystem."""

    memory_columns: tuple[str, ...]  # memory templates, without the ``/m`` suffix
    output_columns: tuple[str, ...]  # output buffer templates, without the ``/ob`` suffix
    rows: tuple[CompositionRow, ...]


@dataclass(frozen=True)
class LinkRow:
    name: str
    anchor: str
    source: str  # owner of the Output Buffer end (subsystem or agent) and the buffer
    target: str
    datatype: str
    configurations: tuple[str, ...] = ()  # those it is present in; () when always present


@dataclass(frozen=True)
class ConfigurationRow:
    """A configuration of a variable-structure system: what it holds and which coordinator
    states switch to it."""

    name: str
    anchor: str
    agents: tuple[str, ...]
    links: tuple[str, ...]
    switch_timeout: str  # "0.05 s", "" when not given
    states: tuple[str, ...]  # the coordinator's states that name it


@dataclass(frozen=True)
class SubsystemTables:
    """Every table of one subsystem definition."""

    name: str  # the template name (``motorControllerK/ve``)
    path: str  # the definition's template path (``manip/a.motorControllerK/ve``)
    anchor: str
    kind: str
    block: str
    instances: tuple[str, ...]  # instance paths (one for a subsystem that is not replicated)
    instance_anchors: tuple[str, ...]  # their ids when replicated, else ()
    inputs: tuple[StorageRow, ...]
    outputs: tuple[StorageRow, ...]
    memory: tuple[StorageRow, ...]
    predicates: tuple[PredicateRow, ...]
    exclusions: tuple[tuple[str, ...], ...]
    fsm_anchor: str
    initial: str
    states: tuple[StateRow, ...]
    transitions: tuple[TransitionRow, ...]
    behaviours: tuple[BehaviourRow, ...]
    functions: tuple[FunctionRow, ...]
    composition: Composition
    buffer_groups: tuple[BufferGroupRow, ...] = ()


@dataclass(frozen=True)
class AgentTables:
    name: str
    anchor: str
    type: str
    subsystems: tuple[SubsystemTables, ...]
    links: tuple[LinkRow, ...]


@dataclass(frozen=True)
class SpecTables:
    """The tables of a whole model, and the anchors of its elements."""

    model: str
    file: str  # the model's file name, without its folder
    system: str
    system_anchor: str
    kinds: dict[str, str]
    agent_types: tuple[AgentTypeRow, ...]
    links: tuple[LinkRow, ...]  # inter-agent links
    agents: tuple[AgentTables, ...]
    anchors: AnchorIndex
    groups: tuple[GroupRow, ...] = ()
    configurations: tuple[ConfigurationRow, ...] = ()
    coordinator: str = ""  # path of the subsystem that switches configurations

    @property
    def subsystems(self) -> tuple[SubsystemTables, ...]:
        return tuple(sub for agent in self.agents for sub in agent.subsystems)


def build_tables(model: EarlModel) -> SpecTables:
    anchors = AnchorIndex()
    system = model.system
    system_name = system.name if system is not None else model.name
    system_anchor = anchors.add(system.path if system is not None else model.name)
    agents = tuple(_agent(model, agent, anchors) for agent in model.agents)
    links = tuple(_link(model, link, anchors) for s in model.systems for link in s.links)
    found = coordinator(model)
    return SpecTables(model=model.name, file=PurePosixPath(model.file.replace("\\", "/")).name,
                      system=system_name, system_anchor=system_anchor,
                      kinds=dict(wording()["kinds"]),
                      agent_types=tuple(_agent_type(model, agent, anchors) for agent in model.agents),
                      links=links, agents=agents, anchors=anchors, groups=_groups(model),
                      configurations=_configurations(model, found, anchors),
                      coordinator=found.path if found is not None else "")


def _configurations(model: EarlModel, switching: Subsystem | None,
                    anchors: AnchorIndex) -> tuple[ConfigurationRow, ...]:
    states = switching.fsm.states if switching is not None and switching.fsm is not None else ()
    return tuple(
        ConfigurationRow(c.name, anchors.add(c.path), c.agents, c.links,
                         f"{c.switch_timeout:g} s" if c.switch_timeout is not None else "",
                         tuple(s.name for s in states if s.configuration == c.name))
        for system in model.systems for c in system.configurations)


def _present_in(model: EarlModel, path: str, agent: bool) -> tuple[str, ...]:
    """The configurations naming an agent or link; () for one that is always present."""
    return tuple(c.name for system in model.systems for c in system.configurations
                 if path in (c.agents if agent else c.links))


def _groups(model: EarlModel) -> tuple[GroupRow, ...]:
    rows = []
    for system in model.systems:
        groups = [*system.groups, *(group for agent in system.agents for group in agent.groups)]
        for group in groups:
            members = tuple(m.removeprefix(f"{group.owner}.") for m in group.members)
            rows.append(GroupRow(group.name, "agent group" if group.kind == "ga" else "subsystem group",
                                 group.block, group.owner, members))
    return tuple(rows)


def activation_text(activation: Activation) -> str:
    """``group motors, min period 0.001 s, first timeout 0.1 s, next timeout 0.02 s``; "" for none."""
    parts = [f"group {activation.group}"] if activation.group else []
    for label, value in (("min period", activation.min_period), ("first timeout", activation.first_timeout),
                         ("next timeout", activation.next_timeout)):
        if value is not None:
            parts.append(f"{label} {value:g} s")
    return ", ".join(parts)


def condition_text(condition: Condition | None) -> str:
    """A condition printed with ∧ ∨ ¬, its text as written when it does not parse, "" when absent."""
    if condition is None:
        return ""
    return format_predicate(condition.expr) if condition.expr is not None else condition.text.strip()


def _agent_type(model: EarlModel, agent: Agent, anchors: AnchorIndex) -> AgentTypeRow:
    counts = tuple(len(agent.of_kind(kind)) for kind in SUBSYSTEM_KINDS)
    inter_agent = sum(1 for s in model.systems for link in s.links
                      if _agent_of(model, link.source) == agent.path or _agent_of(model, link.target) == agent.path)
    return AgentTypeRow(name=agent.name, anchor=anchors.add(agent.path), block=agent.block, robot=agent.robot,
                        type=agent.computed_type, declared=agent.declared_type,
                        description=str(wording()["agent_types"].get(agent.computed_type, "")),
                        counts=counts + (inter_agent,), configurations=_present_in(model, agent.path, agent=True))


def _agent_of(model: EarlModel, buffer_path: str) -> str:
    sub = model.subsystem_of(buffer_path)
    return sub.agent if sub is not None else ""


def _agent(model: EarlModel, agent: Agent, anchors: AnchorIndex) -> AgentTables:
    anchor = anchors.add(agent.path)
    definitions: dict[str, list[Subsystem]] = {}
    for sub in agent.subsystems:
        definitions.setdefault(sub.block_id or sub.path, []).append(sub)
    ordered = sorted(definitions.values(), key=lambda group: SUBSYSTEM_KINDS.index(group[0].kind)
                     if group[0].kind in SUBSYSTEM_KINDS else len(SUBSYSTEM_KINDS))
    subsystems = tuple(_subsystem(model, agent, group, anchors) for group in ordered)
    links = tuple(_link(model, link, anchors) for link in agent.links)
    return AgentTables(name=agent.name, anchor=anchor, type=agent.computed_type, subsystems=subsystems, links=links)


def _subsystem(model: EarlModel, agent: Agent, instances: list[Subsystem], anchors: AnchorIndex) -> SubsystemTables:
    sub = instances[0]
    name = sub.template if sub.index else sub.name
    path = f"{agent.path}.{name}"
    paths = [s.path for s in instances]
    instance_anchors = tuple(anchors.add(p) for p in paths) if path not in paths else ()
    anchor = anchors.add(path, *paths)

    def child(relative: str) -> str:
        return anchors.add(f"{path}.{relative}", *(f"{p}.{relative}" for p in paths))

    template_of = {item.path: item.template for item in sub.buffers + sub.memory}
    inputs = _storage(model, sub.inputs, "ib", child)
    outputs = _storage(model, sub.outputs, "ob", child)
    memory = _storage(model, sub.memory, "m", child)
    predicates = tuple(PredicateRow(name=pp.name, anchor=child(pp.name),
                                    fun=condition_text(pp.fun) if pp.fun is not None else pp.body.strip(),
                                    language="EARL" if pp.fun is not None else pp.language)
                       for pp in sub.predicates)
    fsm = sub.fsm
    transitions: tuple[TransitionRow, ...] = ()
    initial = fsm_anchor = ""
    states: tuple[StateRow, ...] = ()
    states_of: dict[str, list[str]] = {}
    if fsm is not None:
        fsm_anchor = child("fsm")
        initial = fsm.initial or ""
        states = tuple(StateRow(name=state.name, anchor=child(f"fsm.{state.name}"),
                                behaviour=", ".join(state.behaviours), activation=activation_text(state.activation),
                                configuration=state.configuration, quiescent=state.quiescent)
                       for state in fsm.states)
        for state in fsm.states:
            for bb in state.behaviours:
                states_of.setdefault(bb, []).append(state.name)
        transitions = tuple(TransitionRow(name=tr.name, anchor=child(f"fsm.{tr.name}"), source=tr.source,
                                          target=tr.target, condition=condition_text(tr.condition),
                                          priority=tr.priority)
                            for tr in fsm.transitions)
    behaviours = tuple(BehaviourRow(name=bb.name, anchor=child(bb.name), tc=condition_text(bb.tc),
                                    ec=condition_text(bb.ec), stages=bb.stages,
                                    states=tuple(states_of.get(bb.name, ())))
                       for bb in sub.behaviours)
    functions = tuple(FunctionRow(name=pf.name, anchor=child(pf.name),
                                  reads=_unique(template_of.get(p, p) for p in pf.reads),
                                  writes=_unique(template_of.get(p, p) for p in pf.writes))
                      for pf in sub.functions)
    return SubsystemTables(
        name=name, path=path, anchor=anchor, kind=sub.kind, block=sub.block, instances=tuple(paths),
        instance_anchors=instance_anchors,
        inputs=inputs, outputs=outputs, memory=memory, predicates=predicates,
        exclusions=tuple(e.predicates for e in sub.exclusions), fsm_anchor=fsm_anchor, initial=initial,
        states=states, transitions=transitions,
        behaviours=behaviours, functions=functions,
        composition=_composition(behaviours, functions, memory, outputs),
        buffer_groups=tuple(BufferGroupRow(name=g.name, anchor=child(g.name), obligatory=g.obligatory,
                                           optional=g.optional) for g in sub.buffer_groups))


def _composition(behaviours: tuple[BehaviourRow, ...], functions: tuple[FunctionRow, ...],
                 memory: tuple[StorageRow, ...], outputs: tuple[StorageRow, ...]) -> Composition:
    by_name = {f.name: f for f in functions}
    rows: list[CompositionRow] = []
    for bb in behaviours:
        for stage_number, stage in enumerate(bb.stages, start=1):
            for pf_name in stage:
                pf = by_name.get(pf_name)
                writes = set(pf.writes) if pf is not None else set()
                rows.append(CompositionRow(
                    behaviour=bb.name, behaviour_anchor=bb.anchor, stage=stage_number, function=pf_name,
                    function_anchor=pf.anchor if pf is not None else "",
                    memory=tuple(m.name in writes for m in memory),
                    outputs=tuple(o.name in writes for o in outputs)))
    return Composition(memory_columns=tuple(stem(m.name) for m in memory),
                       output_columns=tuple(stem(o.name) for o in outputs), rows=tuple(rows))


def _storage(model: EarlModel, items: tuple[Any, ...], kind: str, child: Any) -> tuple[StorageRow, ...]:
    rows: dict[str, StorageRow] = {}
    counts: dict[str, int] = {}
    for item in items:
        counts[item.template] = counts.get(item.template, 0) + (1 if item.index else 0)
    for item in items:
        if item.template not in rows:
            receive = getattr(item, "receive", "latest")
            rows[item.template] = StorageRow(name=item.template, anchor=child(item.template), kind=kind,
                                             datatype=_datatype(model, item.datatype, item.type_ref),
                                             count=counts[item.template],
                                             receive=f"queue of {item.queue_size}" if receive == "queue" else
                                             ("" if receive == "latest" else receive))
    return tuple(rows.values())


def _datatype(model: EarlModel, key: str, type_ref: str = "") -> str:
    datatype = model.datatypes.get(key)
    if datatype is not None:
        return datatype.name
    return type_ref or key or "?"


def _link(model: EarlModel, link: Link, anchors: AnchorIndex) -> LinkRow:
    source = model.buffer(link.source)
    target = model.buffer(link.target)
    datatype = source or target
    return LinkRow(name=link.name, anchor=anchors.add(link.path), source=link.source or link.ends[0],
                   target=link.target or link.ends[1],
                   datatype=_datatype(model, datatype.datatype, datatype.type_ref) if datatype is not None else "?",
                   configurations=_present_in(model, link.path, agent=False))


def _unique(items: Any) -> tuple[str, ...]:
    return tuple(dict.fromkeys(items))
