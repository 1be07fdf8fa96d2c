"""Lifting variable structure: the «Configuration» constraints of a System block, resolved
against the agents and links lifted under it, and an agent's reactivation and optionality."""

from __future__ import annotations

from earl_m2t.lift.recognise import Recogniser
from earl_m2t.lift.replication import multiplicity
from earl_m2t.lift.tags import literal, names, seconds, tag
from earl_m2t.model.elements import Agent, Configuration, Link
from earl_m2t.model.kinds import REACTIVATIONS, Reactivation
from earl_m2t.read.xmi import Element, RawModel

CONFIGURATION = "Configuration"


def configurations(raw: RawModel, recogniser: Recogniser, block: Element, system: str,
                   agents: list[Agent], links: list[Link]) -> tuple[Configuration, ...]:
    """The «Configuration» constraints ``block`` owns, in model order. A name resolves to the
    agent or link whose path it is (or, for a link, whose name it is, when only one link has it);
    one that resolves to nothing is kept as written."""
    agent_paths = {a.path for a in agents}
    link_paths = {link.path for link in links}
    by_name: dict[str, list[str]] = {}
    for link in links:
        by_name.setdefault(link.name, []).append(link.path)
    found = []
    for rule in raw.children(block, "ownedRule"):
        if recogniser.recognise(rule).concept != CONFIGURATION:
            continue
        tags = recogniser.tags(rule)
        named_agents: list[str] = []
        named_links: list[str] = []
        unknown_agents: list[str] = []
        unknown_links: list[str] = []
        for name in names(raw, tag(tags, "agents"), paths=True):
            (named_agents if name in agent_paths else unknown_agents).append(name)
        for name in names(raw, tag(tags, "links"), paths=True):
            if name in link_paths:
                named_links.append(name)
            elif len(by_name.get(name, ())) == 1:
                named_links.append(by_name[name][0])
            else:
                unknown_links.append(name)
        name = raw.name(rule)
        found.append(Configuration(name, f"{system}.{name}", _unique(named_agents), _unique(named_links),
                                   tuple(unknown_agents), tuple(unknown_links),
                                   seconds(tag(tags, "switchTimeout")), raw.location(rule)))
    return tuple(found)


def _unique(paths: list[str]) -> tuple[str, ...]:
    return tuple(dict.fromkeys(paths))


def reactivation_of(raw: RawModel, tags: dict[str, str]) -> str:
    """An «Agent»'s reactivation: ``restart`` unless tagged; a value that is none is kept as written."""
    value = tag(tags, "reactivation")
    written = (literal(raw, value) if value else "") or Reactivation.RESTART
    return next((known for known in REACTIVATIONS if known == written), written)


def host_of(tags: dict[str, str]) -> str:
    """An «Agent»'s host: the tag ``host`` as written (rule D007 checks it), "" when untagged."""
    return tag(tags, "host") or ""


def is_optional(raw: RawModel, part: Element) -> bool:
    """True for a part of multiplicity [0..1]: the general model may leave its agent out."""
    return multiplicity(raw, part) == (0, 1)


__all__ = ["CONFIGURATION", "configurations", "host_of", "is_optional", "reactivation_of"]
