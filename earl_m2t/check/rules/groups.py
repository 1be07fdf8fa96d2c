"""Group rules: what an Agent Group (GpAgents) and a Subsystem Group (GpSubsys) may hold
(earl-m2t: the EARL authors' EA profile defines the groups, the paper does not)."""

from __future__ import annotations

from collections.abc import Iterator

from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.elements import EarlModel, Group

# Concepts a group of each kind may hold.
_MAY_HOLD = {
    "ga": frozenset({"Agent"}),
    "gs": frozenset({"VirtualEffector", "VirtualReceptor", "RealEffector", "RealReceptor"}),
}
_WHAT = {"ga": "Agents", "gs": "Virtual or Real Effectors and Receptors"}


def _content(group: Group, title: str) -> Iterator[Finding]:
    allowed = _MAY_HOLD[group.kind]
    for part in group.parts:
        if part.concept and part.concept not in allowed:
            yield Finding(f"{title} {group.path} holds {part.name}, a {part.concept}: it may hold "
                          f"{_WHAT[group.kind]} only", part.location, f"{group.path}.{part.name}")
    if not any(part.concept in allowed for part in group.parts):
        yield Finding(f"{title} {group.path} holds no {_WHAT[group.kind]}", group.location, group.path)


@rule("S010")
def agent_group_content(model: EarlModel) -> Iterator[Finding]:
    for system in model.systems:
        for group in system.groups:
            yield from _content(group, "agent group")


@rule("S011")
def subsystem_group_content(model: EarlModel) -> Iterator[Finding]:
    for system in model.systems:
        for agent in system.agents:
            for group in agent.groups:
                yield from _content(group, "subsystem group")
