"""Variable structure as functions of the lifted model: which agents and links vary, which are
present in a configuration, and which subsystem switches between configurations.

The model is the general (superset) model of the paper (l.195): every agent and link of any
configuration. An agent or link that some configuration names is *variable*, present only
while a configuration naming it holds; everything else is always present, except that a
subsystem of a variable agent, and a link inside it that no configuration names, follow their
agent.
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.model.elements import Agent, Configuration, EarlModel, Link, Subsystem, System
from earl_m2t.model.kinds import LinkScope, SubsystemKind


def variable_agents(system: System) -> frozenset[str]:
    """Paths of the agents some configuration names."""
    return frozenset(path for c in system.configurations for path in c.agents)


def variable_links(system: System) -> frozenset[str]:
    """Paths of the links some configuration names."""
    return frozenset(path for c in system.configurations for path in c.links)


def system_links(system: System) -> tuple[Link, ...]:
    """Every link of the system: inter-agent and inter-subsystem."""
    return tuple(link for a in system.agents for link in a.links) + system.links


@dataclass(frozen=True, slots=True)
class Structure:
    """What is present while a configuration holds: always-present ∪ the configuration's."""

    configuration: Configuration
    agents: frozenset[str]  # agent paths
    links: frozenset[str]  # link paths

    def has_agent(self, path: str) -> bool:
        return path in self.agents

    def has_link(self, path: str) -> bool:
        return path in self.links


def present(system: System, configuration: Configuration) -> Structure:
    """The structure induced by ``configuration``: the agents and links no configuration names
    (a link inside an agent only while its agent is present) and those ``configuration`` names."""
    varying_agents = variable_agents(system)
    varying_links = variable_links(system)
    agents = frozenset(a.path for a in system.agents if a.path not in varying_agents) | frozenset(
        configuration.agents)
    links = frozenset(link.path for link in system_links(system) if link.path not in varying_links
                      and (link.scope != LinkScope.AGENT or link.owner in agents)) | frozenset(configuration.links)
    return Structure(configuration, agents, links)


def structures(system: System) -> tuple[Structure, ...]:
    """The structure of each configuration, in model order."""
    return tuple(present(system, c) for c in system.configurations)


def coordinators(model: EarlModel) -> tuple[Subsystem, ...]:
    """Subsystems whose FSM has a state naming a configuration (at most one is valid)."""
    return tuple(sub for sub in model.subsystems
                 if sub.fsm is not None and any(state.configuration for state in sub.fsm.states))


def coordinator(model: EarlModel) -> Subsystem | None:
    """The one control subsystem that switches configurations, None when there is none or the
    model is ambiguous (the rules report that)."""
    found = coordinators(model)
    if len(found) != 1 or found[0].kind != SubsystemKind.CS:
        return None
    return found[0]


def is_variable(model: EarlModel) -> bool:
    """True when the model declares configurations."""
    return any(s.configurations for s in model.systems)


def agent_of(system: System, path: str) -> Agent | None:
    return next((a for a in system.agents if a.path == path), None)


def link_agents(system: System, link: Link) -> tuple[str, str]:
    """The paths of the agents that send and receive ``link`` ("" for an end that is no buffer
    of an agent of ``system``)."""
    owner = {buf.path: agent.path for agent in system.agents for sub in agent.subsystems for buf in sub.buffers}
    return owner.get(link.source, ""), owner.get(link.target, "")


def lingers(system: System, link: Link, before: Structure, after: Structure) -> bool:
    """Whether ``link`` stays open through a switch from ``before`` to ``after`` although
    ``after`` lacks it: its sender leaves and its receiver stays, so what the leaving agent sends
    until it stops (its last iterations, a safe-stop command) is delivered. It closes when the
    sender has stopped. Every other link ``after`` lacks closes when the switch is decided."""
    if not before.has_link(link.path) or after.has_link(link.path):
        return False
    sender, receiver = link_agents(system, link)
    leaves = before.has_agent(sender) and not after.has_agent(sender)
    stays = before.has_agent(receiver) and after.has_agent(receiver)
    return leaves and stays


__all__ = [
    "Structure",
    "agent_of",
    "coordinator",
    "coordinators",
    "is_variable",
    "lingers",
    "link_agents",
    "present",
    "structures",
    "system_links",
    "variable_agents",
    "variable_links",
]
