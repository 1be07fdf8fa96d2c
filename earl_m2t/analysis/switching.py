"""What the rules of variable structure (family X) compute from the lifted model: which
configurations can hold while a state is current, which agents a switch can remove, the drain
bound of a queued input, and the structure a configuration induces as a model of its own (the
structural rules are run on it). Whether a state receives an input is
earl_m2t.analysis.receiving's.

Functions of the lifted model only; nothing here reads XML or condition text.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace

from earl_m2t.analysis.receiving import receives
from earl_m2t.model.elements import Agent, Buffer, Configuration, EarlModel, Link, State, Subsystem, System
from earl_m2t.model.graph import unreachable_states
from earl_m2t.model.kinds import ReceiveMode
from earl_m2t.model.variability import coordinator, present, variable_agents


def system_of(model: EarlModel, sub: Subsystem) -> System | None:
    """The system whose agent owns ``sub``."""
    return next((s for s in model.systems if any(a.path == sub.agent for a in s.agents)), None)


def reachable_states(sub: Subsystem) -> tuple[State, ...]:
    """The states of ``sub``'s FSM reachable from its initial state (none without an initial state)."""
    if sub.fsm is None or sub.fsm.initial is None:
        return ()
    unreached = set(unreachable_states(sub.fsm))
    return tuple(s for s in sub.fsm.states if s.name not in unreached)


def holding(sub: Subsystem) -> dict[str, frozenset[str]]:
    """For each reachable state of a coordinator, the names of the configurations that can hold
    while it is current: the one it names, else those of the states it can be entered from (a
    state without a configuration keeps the current one)."""
    fsm = sub.fsm
    if fsm is None or fsm.initial is None or fsm.state(fsm.initial) is None:
        return {}
    named = {s.name: s.configuration for s in fsm.states}
    held: dict[str, frozenset[str]] = {fsm.initial: frozenset({named[fsm.initial]} - {""})}
    changed = True
    while changed:
        changed = False
        for tr in fsm.transitions:
            if tr.source_foreign or tr.target_foreign or tr.source not in held or tr.target not in named:
                continue
            entering = frozenset({named[tr.target]}) if named[tr.target] else held[tr.source]
            before = held.get(tr.target, frozenset())
            if not entering <= before:
                held[tr.target] = before | entering
                changed = True
    return held


def reachable_configurations(model: EarlModel, system: System) -> tuple[Configuration, ...]:
    """The configurations of ``system`` its coordinator can switch to; all of them when the model
    has no single coordinator (rule X003 reports that)."""
    boss = coordinator(model)
    if boss is None or system_of(model, boss) is not system:
        return system.configurations
    names = frozenset().union(*holding(boss).values())
    return tuple(c for c in system.configurations if c.name in names)


def configurations_while(model: EarlModel, system: System, sub: Subsystem, state: State) -> tuple[Configuration, ...]:
    """The configurations that can hold while ``state`` of ``sub`` is current: for the
    coordinator those its FSM can reach the state with, for any other subsystem the reachable
    configurations its agent is present in."""
    boss = coordinator(model)
    if boss is not None and boss.path == sub.path:
        names = holding(sub).get(state.name, frozenset())
        return tuple(c for c in system.configurations if c.name in names)
    return tuple(c for c in reachable_configurations(model, system) if present(system, c).has_agent(sub.agent))


def leaving_agents(system: System) -> tuple[Agent, ...]:
    """The agents a switch can remove: named by a configuration and absent from another."""
    named = variable_agents(system)
    return tuple(a for a in system.agents
                 if a.path in named and not all(a.path in c.agents for c in system.configurations))


def silent_outputs(model: EarlModel, definition: Subsystem, behaviour: str) -> frozenset[str]:
    """The Output Buffers (by template) of ``definition`` whose every link is closed wherever its
    basic behaviour ``behaviour`` runs: in each instance, in every configuration that can hold
    while a reachable state running it is current. What such a buffer holds goes nowhere then.
    Empty for a model without configurations, and for an instance where no reachable state runs
    the behaviour (nothing is known of where it runs)."""
    links_from: dict[str, list[str]] = {}
    for link in model.links:
        if link.source:
            links_from.setdefault(link.source, []).append(link.path)
    linked: set[str] = set()
    heard: set[str] = set()
    for system in (s for s in model.systems if s.configurations):
        for sub in (sub for agent in system.agents for sub in agent.subsystems if sub.block_id == definition.block_id):
            states = [s for s in reachable_states(sub) if s.behaviours[:1] == (behaviour,)]
            if not states:
                return frozenset()
            holding_now = [present(system, c) for state in states
                           for c in configurations_while(model, system, sub, state)]
            for buffer in sub.outputs:
                paths = links_from.get(buffer.path, [])
                if paths:
                    linked.add(buffer.template)
                if any(structure.has_link(path) for structure in holding_now for path in paths):
                    heard.add(buffer.template)
    return frozenset(linked - heard)


def names_buffer(names: Iterable[str], buffer: Buffer) -> bool:
    """True when a list of Input Buffer names (a group's, as written) names ``buffer``."""
    return bool({buffer.name, buffer.template} & set(names))


def waits_without_bound(state: State) -> bool:
    """True when an iteration in ``state`` can wait for its obligatory inputs without bound: the
    first iteration after entering it has no firstTimeout, or later ones no nextTimeout."""
    return state.activation.first_timeout is None or state.activation.next_timeout is None


def obligatory_inputs(sub: Subsystem, state: State) -> tuple[Buffer, ...]:
    """The Input Buffers of ``sub`` obligatory in ``state``'s buffer group."""
    group = next((g for g in sub.buffer_groups if g.name == state.activation.group), None)
    if group is None:
        return ()
    return tuple(b for b in sub.inputs if names_buffer(group.obligatory, b))


def fed_inputs(model: EarlModel, links: frozenset[str] | None = None) -> dict[str, tuple[str, ...]]:
    """Input Buffer path → the paths of the links into it (only those in ``links`` when given)."""
    fed: dict[str, tuple[str, ...]] = {}
    for link in model.links:
        if link.target and (links is None or link.path in links):
            fed[link.target] = fed.get(link.target, ()) + (link.path,)
    return fed


def queued_inputs(model: EarlModel, agent: Agent) -> tuple[tuple[Subsystem, Buffer], ...]:
    """The queued Input Buffers of ``agent`` some link feeds, with their subsystems."""
    fed = fed_inputs(model)
    return tuple((sub, b) for sub in agent.subsystems for b in sub.inputs
                 if b.receive == ReceiveMode.QUEUE and b.path in fed)


def _finite(value: float | None) -> float | None:
    return value if value is not None and math.isfinite(value) and value >= 0 else None


def iteration_period(sub: Subsystem, states: Iterable[State]) -> float | None:
    """The longest minimal period (tag minPeriod) of ``states``: with values waiting for an
    obligatory input, ``sub`` iterates once per minimal period. None when no state gives one:
    the subsystem's own period is a setting of the target, not of the model."""
    periods = [p for s in states if (p := _finite(s.activation.min_period)) is not None]
    return max(periods) if periods else None


@dataclass(frozen=True, slots=True)
class DrainBound:
    """A lower estimate of the time a switch needs to empty a queued input of a leaving agent:
    ``queue_size`` values, one per ``receiver_period``, and one ``coordinator_period``."""

    buffer: Buffer
    queue_size: int
    receiver_period: float
    coordinator_period: float

    @property
    def seconds(self) -> float:
        return self.queue_size * self.receiver_period + self.coordinator_period


def drain_bound(model: EarlModel, sub: Subsystem, buffer: Buffer) -> DrainBound | None:
    """The drain bound of the queued ``buffer`` of ``sub``; None when the model gives no minimal
    period for the states of ``sub`` that receive it."""
    period = iteration_period(sub, (s for s in reachable_states(sub) if receives(sub, s, buffer)))
    if period is None:
        return None
    boss = coordinator(model)
    boss_period = iteration_period(boss, reachable_states(boss)) if boss is not None else None
    return DrainBound(buffer, buffer.queue_size, period, boss_period or 0.0)


def induced_model(model: EarlModel, system: System, configuration: Configuration) -> EarlModel:
    """``model`` with ``system`` reduced to the structure ``configuration`` induces: its absent
    agents and links left out, each agent's type T (inter-agent links) as its present links
    make it."""
    structure = present(system, configuration)
    links = tuple(link for link in system.links if structure.has_link(link.path))
    agents = tuple(_induced_agent(agent, structure.links, links) for agent in system.agents
                   if structure.has_agent(agent.path))
    robots = tuple(replace(r, agents=tuple(a for a in r.agents if structure.has_agent(a))) for r in system.robots)
    reduced = replace(system, robots=robots, agents=agents, links=links)
    return replace(model, systems=tuple(reduced if s is system else s for s in model.systems))


def _induced_agent(agent: Agent, present_links: frozenset[str], links: tuple[Link, ...]) -> Agent:
    inner = tuple(link for link in agent.links if link.path in present_links)
    ends = {end for link in links for end in link.ends if end}
    talks = any(b.path in ends for sub in agent.subsystems for b in sub.buffers)
    kind = agent.computed_type.replace("T", "") + ("T" if talks else "")
    return replace(agent, links=inner, computed_type=kind)


__all__ = [
    "DrainBound",
    "configurations_while",
    "drain_bound",
    "fed_inputs",
    "holding",
    "induced_model",
    "iteration_period",
    "leaving_agents",
    "names_buffer",
    "obligatory_inputs",
    "queued_inputs",
    "reachable_configurations",
    "reachable_states",
    "silent_outputs",
    "system_of",
    "waits_without_bound",
]
