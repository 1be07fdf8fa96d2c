"""The EARL profile as data (:class:`Profile`): its concepts, their features and the
enumerations of tag values; and the names of the profile file's packages and metadata that
:mod:`earl_m2t.profile_reader` reads them by."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

from earl_m2t.diagnostics import SourceTextError

__all__ = ["Concept", "Feature", "Profile", "ProfileError"]

ROOT_PACKAGE = "EARL"
MODEL_PACKAGE = "Model"
STEREOTYPE_METADATA = "Stereotype"
METACLASS_ATTRIBUTE = "metaclass"
TAG_METADATA = "Tag"


class ProfileError(SourceTextError):
    """The profile file cannot be read, does not parse, or is inconsistent."""


@dataclass(frozen=True, slots=True)
class Feature:
    """A feature of a concept (a usage in its definition).

    ``kind`` is the usage keyword (``part``, ``port``, ``attribute``, ``interface``, ...),
    ``ref`` for a reference usage (``ref x : T;`` or a usage without keyword) and ``end``
    for the end of a link. ``type`` is the type as written (``Agent``,
    ``DataTypes::DataType``); ``upper`` is None for ``*``. A feature without a
    multiplicity has 1..1. ``tag`` marks a stereotype attribute (``#Tag``);
    ``redefines`` names the inherited feature that this one redefines (``:>> ib``).
    """

    name: str
    type: str
    lower: int
    upper: int | None
    kind: str
    default: object = None
    tag: bool = False
    redefines: str | None = None

    @property
    def many(self) -> bool:
        """True when more than one value is allowed."""
        return self.upper is None or self.upper > 1


@dataclass(frozen=True, slots=True)
class Concept:
    """An EARL concept: one definition of package ``EARL::Model``.

    ``features`` are the features declared by this definition only, in profile order
    (redefinitions completed with the type they redefine); see
    :meth:`Profile.all_features` for the inherited ones.
    """

    name: str
    abbreviation: str | None
    supertypes: tuple[str, ...]
    abstract: bool
    metaclass: str | None
    features: tuple[Feature, ...]
    doc: str

    def feature(self, name: str) -> Feature | None:
        """The declared feature called ``name``, if any."""
        return next((f for f in self.features if f.name == name), None)


@dataclass(frozen=True)
class Profile:
    """The EARL concepts by name (in profile order) and the enumerations of the profile."""

    concepts: Mapping[str, Concept]
    enums: Mapping[str, tuple[str, ...]]
    _by_abbreviation: Mapping[str, Concept] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "concepts", MappingProxyType(dict(self.concepts)))
        object.__setattr__(self, "enums", MappingProxyType(dict(self.enums)))
        index = {c.abbreviation: c for c in self.concepts.values() if c.abbreviation}
        object.__setattr__(self, "_by_abbreviation", MappingProxyType(index))

    def __reduce__(self) -> tuple[type, tuple[dict[str, Concept], dict[str, tuple[str, ...]]]]:
        return (Profile, (dict(self.concepts), dict(self.enums)))

    def by_abbreviation(self, abbr: str) -> Concept | None:
        """The concept whose abbreviation (short name) is ``abbr``: ``cs`` → ControlSubsystem."""
        return self._by_abbreviation.get(abbr)

    def ancestors(self, name: str) -> tuple[str, ...]:
        """All supertypes of concept ``name``, nearest first, without ``name`` itself.

        Raises KeyError for an unknown concept.
        """
        if name not in self.concepts:
            raise KeyError(name)
        found: list[str] = []
        frontier = list(self.concepts[name].supertypes)
        while frontier:
            following: list[str] = []
            for supertype in frontier:
                if supertype in found or supertype == name or supertype not in self.concepts:
                    continue
                found.append(supertype)
                following.extend(self.concepts[supertype].supertypes)
            frontier = following
        return tuple(found)

    def is_a(self, name: str, ancestor: str) -> bool:
        """True when concept ``name`` is ``ancestor`` or specialises it; False if unknown."""
        if name not in self.concepts:
            return False
        return name == ancestor or ancestor in self.ancestors(name)

    def concrete_kinds(self, ancestor: str) -> tuple[Concept, ...]:
        """The non-abstract concepts that are ``ancestor`` or specialise it, in profile order."""
        return tuple(
            c for c in self.concepts.values() if not c.abstract and self.is_a(c.name, ancestor)
        )

    def all_features(self, name: str) -> tuple[Feature, ...]:
        """The features of concept ``name`` including inherited ones: the farthest
        ancestor's first; a redefinition takes the place of the feature it redefines.

        Raises KeyError for an unknown concept.
        """
        if name not in self.concepts:
            raise KeyError(name)
        effective: dict[str, Feature] = {}
        for concept_name in (*reversed(self.ancestors(name)), name):
            for feature in self.concepts[concept_name].features:
                effective[feature.redefines or feature.name] = feature
        return tuple(effective.values())

    def tags(self, name: str) -> tuple[Feature, ...]:
        """The stereotype attributes (``#Tag`` features) of concept ``name``, inherited included."""
        return tuple(f for f in self.all_features(name) if f.tag)
