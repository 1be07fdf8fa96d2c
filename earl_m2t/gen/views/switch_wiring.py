"""Who takes part in a switch when every subsystem instance runs apart (a ROS node, an Orocos
component): the numbering the generated ``earl::SwitchMember`` and ``earl::SwitchCoordinator``
(earl/switch_protocol.hpp) share with the C++ ``System`` tables.

Nodes are the subsystem instances in model order (agents, then their subsystems); variable
agents and links are numbered as in the C++ view's tables (``cpp_switch``), so an index means
the same thing in every generated file.
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.gen.views.cpp_switch import variable_paths
from earl_m2t.model import variability
from earl_m2t.model.elements import EarlModel, Link
from earl_m2t.model.kinds import SubsystemKind


@dataclass(frozen=True, slots=True)
class NodeWiring:
    """One subsystem instance in the switch."""

    index: int  # its node number: SwitchMember's and SwitchAck's ``node``
    path: str  # the subsystem instance
    agent: int  # its agent among the variable agents, -1 for an agent of every configuration
    control: bool  # the control subsystem of its (variable) agent
    coordinator: bool  # the subsystem that switches configurations
    sends: tuple[int, ...]  # the variable links from its Output Buffers
    receives: tuple[int, ...]  # the variable links into its Input Buffers


@dataclass(frozen=True, slots=True)
class SwitchWiring:
    agents: tuple[str, ...]  # variable agent paths, by index
    links: tuple[Link, ...]  # variable links, by index
    nodes: tuple[NodeWiring, ...]  # by node number

    def node(self, path: str) -> NodeWiring:
        return next(n for n in self.nodes if n.path == path)

    def link_index(self, path: str) -> int:
        """The index of the variable link ``path``, -1 for a link of every configuration."""
        return next((i for i, link in enumerate(self.links) if link.path == path), -1)


def switch_wiring(model: EarlModel) -> SwitchWiring | None:
    """The wiring of ``model``'s switch, None for a model without configurations."""
    system = model.system
    if system is None or not variability.is_variable(model):
        return None
    agent_paths, link_paths = variable_paths(system)
    by_path = {link.path: link for link in variability.system_links(system)}
    links = tuple(by_path[path] for path in link_paths if path in by_path)
    coordinator = variability.coordinator(model)
    subsystem_of_buffer = {buf.path: sub.path for sub in model.subsystems for buf in sub.buffers}
    nodes: list[NodeWiring] = []
    for agent in system.agents:
        agent_index = agent_paths.index(agent.path) if agent.path in agent_paths else -1
        for sub in agent.subsystems:
            sends = tuple(i for i, link in enumerate(links) if subsystem_of_buffer.get(link.source) == sub.path)
            receives = tuple(i for i, link in enumerate(links) if subsystem_of_buffer.get(link.target) == sub.path)
            nodes.append(NodeWiring(index=len(nodes), path=sub.path, agent=agent_index,
                                    control=sub.kind == SubsystemKind.CS,
                                    coordinator=coordinator is not None and coordinator.path == sub.path,
                                    sends=sends, receives=receives))
    return SwitchWiring(agents=tuple(agent_paths), links=links, nodes=tuple(nodes))
