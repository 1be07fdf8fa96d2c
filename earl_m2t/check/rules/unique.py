"""Names that must tell elements apart: two Agents of a System, or two Subsystems of an Agent,
with one path are one element to every reader of the model (show, diff, the generated files,
topics and components named after it)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.location import Location


def _repeated(elements: Iterable[tuple[str, Location]], what: str) -> Iterator[Finding]:
    first: dict[str, Location] = {}
    for path, location in elements:
        if path in first:
            yield Finding(f"{what} {path} is named twice (first at line {first[path].line}): every element "
                          "needs a path of its own", location, path)
        else:
            first[path] = location


@rule("S012")
def path_not_unique(model: EarlModel) -> Iterator[Finding]:
    for system in model.systems:
        yield from _repeated(((agent.path, agent.location) for agent in system.agents), "agent")
        for agent in system.agents:
            yield from _repeated(((sub.path, sub.location) for sub in agent.subsystems), "subsystem")
