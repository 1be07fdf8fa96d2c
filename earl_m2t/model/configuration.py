"""A configuration of a variable-structure system: the variable agents and links present while
it holds (the model's other elements are in :mod:`earl_m2t.model.elements`)."""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.model.location import Location


@dataclass(frozen=True, slots=True)
class Configuration:
    """A particular structure of a variable-structure system (paper l.195–199): the variable
    agents and links present while it holds. Agents and links that no configuration names are
    always present."""

    name: str
    path: str  # system name + "." + name
    agents: tuple[str, ...]  # paths of the agents it names that exist
    links: tuple[str, ...]  # paths of the links it names that exist
    unknown_agents: tuple[str, ...]  # names in its tag ``agents`` that are no agent, as written
    unknown_links: tuple[str, ...]  # names in its tag ``links`` that are no link, as written
    switch_timeout: float | None  # seconds; None when not given, NaN when unreadable
    location: Location

    @property
    def unknown(self) -> tuple[str, ...]:
        """Every name it gives that resolves to nothing."""
        return self.unknown_agents + self.unknown_links
