"""Which stereotype names mean which EARL concept, beyond the concept names themselves."""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cache
from types import MappingProxyType
from typing import Any

from earl_m2t.read.xmi import stereotype_key
from earl_m2t.resources import metamodel_path

_TABLE = ("xmi", "stereotype-names.toml")


@cache
def _table() -> Mapping[str, Any]:
    return tomllib.loads(metamodel_path(*_TABLE).read_text(encoding="utf-8"))


def other_names() -> Mapping[str, str]:
    """The authors' names of EARL stereotypes, as written in the table: ``ContSubsys`` →
    ``ControlSubsystem``."""
    return MappingProxyType(dict(_table()["names"]))


def specialising_profile_settings() -> Mapping[str, Any]:
    """The ``[specialising_profiles]`` settings: file patterns, root elements, qualifiers."""
    return MappingProxyType(dict(_table()["specialising_profiles"]))


@dataclass(frozen=True)
class SpecialisingProfile:
    """A profile that specialises EARL: its name (the namespace segment its applications are
    written under, ``SPSys``), the file it came from, and for each of its stereotypes that
    generalises an EARL stereotype, directly or through others of its own, the concept
    (keys compared as :func:`stereotype_key` does)."""

    name: str
    file: str
    concepts: Mapping[str, str]

    def concept(self, stereotype: str) -> str:
        return self.concepts.get(stereotype_key(stereotype), "")

    def writes(self, namespace_uri: str) -> bool:
        """True when an application in ``namespace_uri`` is one of this profile's: a segment of
        the URI is the profile's name (``http://www.sparxsystems.com/profiles/SPSys/1.0``)."""
        wanted = self.name.strip().lower()
        segments = namespace_uri.replace("#", "/").split("/")
        return any(segment.strip().lower() in (wanted, f"{wanted}.xmi") for segment in segments)


@dataclass(frozen=True)
class Vocabulary:
    """Every stereotype name that means an EARL concept: the profile's concept names, the
    authors' names of the table, and the stereotypes of the specialising profiles given."""

    concept_names: tuple[str, ...]
    profiles: tuple[SpecialisingProfile, ...] = ()
    _earl: Mapping[str, str] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        names = {stereotype_key(name): name for name in self.concept_names}
        for other, concept in other_names().items():
            if concept in self.concept_names:
                names.setdefault(stereotype_key(other), concept)
        object.__setattr__(self, "_earl", MappingProxyType(names))

    def earl_concept(self, name: str) -> str:
        """The concept an EARL stereotype (or an EARL Model block) of this name stands for."""
        return self._earl.get(stereotype_key(name), "")

    def specialised_concept(self, namespace_uri: str, name: str) -> str:
        """The concept a stereotype of another profile stands for, "" when none does."""
        for profile in self.profiles:
            if profile.writes(namespace_uri):
                concept = profile.concept(name)
                if concept:
                    return concept
        return ""
