"""The EARL profile, loaded from ``profiles/earl.sysml`` (SysML v2 textual notation).

The profile file is the single definition of the EARL concepts. Every definition of package
``EARL::Model`` is one :class:`Concept`:

- its name and short name (``part def <cs> ControlSubsystem``) give the concept name and the
  paper's abbreviation;
- ``:>`` gives its supertypes, ``abstract`` marks concepts that are never instantiated;
- ``@Stereotype { metaclass = "..."; }`` names the UML metaclass its stereotype extends;
- its usages are its :class:`Feature` s, with the multiplicities of the general model;
  usages marked ``#Tag`` are stereotype attributes (tagged values);
- its ``doc`` is its meaning.

Enumerations (``enum def``) anywhere in package ``EARL`` are the value sets of tags.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from types import MappingProxyType
from typing import Any

from earl_m2t import resources
from earl_m2t.cache import cached
from earl_m2t.diagnostics import SourceTextError
from earl_m2t.sysml2 import (
    Sysml2SyntaxError,
    doc_text,
    identification,
    literal_value,
    location,
    members,
    multiplicity,
    name_segments,
    parse_file,
    rule,
    simple_name,
)

__all__ = ["Concept", "Feature", "Profile", "ProfileError", "load_profile"]

ROOT_PACKAGE = "EARL"
MODEL_PACKAGE = "Model"
STEREOTYPE_METADATA = "Stereotype"
METACLASS_ATTRIBUTE = "metaclass"
TAG_METADATA = "Tag"

# Definition kinds that are not concepts: enumerations used by tags, and the metadata and
# calculation definitions that models use (`@Priority`, `newData(x)`).
_NOT_CONCEPTS = frozenset({"enum", "metadata", "calc"})
# Types of the SysML v2 library package ScalarValues, usable as feature types.
_SCALAR_VALUES = frozenset(
    {
        "ScalarValue",
        "Boolean",
        "String",
        "NumericalValue",
        "Number",
        "Complex",
        "Real",
        "Rational",
        "Integer",
        "Natural",
        "Positive",
    }
)


def _enum_literal(value: object, type_name: str | None) -> object:
    """``ReceiveMode::latest`` of a feature typed ReceiveMode is the literal ``latest``."""
    if isinstance(value, str) and type_name and value.startswith(f"{simple_name(type_name)}::"):
        return value.rpartition("::")[2]
    return value


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

    def multiplicity_text(self) -> str:
        """``1``, ``0..1``, ``1..*``..."""
        upper = "*" if self.upper is None else str(self.upper)
        return str(self.lower) if upper == str(self.lower) else f"{self.lower}..{upper}"


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


# ---------------------------------------------------------------- loading


def load_profile(path: Path | None = None) -> Profile:
    """Load the EARL profile; by default the installed ``profiles/earl.sysml`` (cached).

    Raises ProfileError when the file cannot be read, does not parse, or is inconsistent.
    """
    if path is None:
        return _default_profile()
    return _load(Path(path))


@cache
def _default_profile() -> Profile:
    path = resources.profile_path()
    return cached("profile", path, lambda: _load(path))


def _load(path: Path) -> Profile:
    file = str(path)
    try:
        root = parse_file(path)
    except Sysml2SyntaxError as error:
        raise ProfileError(error.file, error.line, error.column, error.message) from None
    return _Builder(file).build(root)


@dataclass
class _RawFeature:
    node: Any
    name: str
    type: str
    bounds: tuple[int, int | None] | None
    kind: str
    default: object
    tag: bool
    redefines: str | None


@dataclass
class _RawConcept:
    node: Any
    name: str
    abbreviation: str | None
    supertypes: tuple[str, ...]
    abstract: bool
    metaclass: str | None
    features: list[_RawFeature]
    doc: str


class _Builder:
    """Turns the parse tree of the profile into a Profile, checking it on the way."""

    def __init__(self, file: str) -> None:
        self.file = file
        self.type_names: set[str] = set(_SCALAR_VALUES)

    def error(self, node: Any, message: str) -> ProfileError:
        line, column = location(node) if node is not None else (0, 0)
        return ProfileError(self.file, line, column, message)

    def build(self, root: Any) -> Profile:
        earl = self.package(root, ROOT_PACKAGE)
        model = self.package(earl, MODEL_PACKAGE)
        enums: dict[str, tuple[str, ...]] = {}
        for definition in _definitions(earl):
            _, name = identification(definition)
            if name:
                self.type_names.add(name)
            if definition.kind == "enum":
                enums[self.required_name(definition)] = self.literals(definition)
        raw = [self.concept(d) for d in _definitions(model) if d.kind not in _NOT_CONCEPTS]
        self.check_unique(raw)
        return Profile(concepts=self.resolve(raw), enums=enums)

    def package(self, parent: Any, name: str) -> Any:
        for element in members(parent):
            if rule(element) == "Package" and identification(element)[1] == name:
                return element
        raise self.error(
            parent if rule(parent) != "RootNamespace" else None,
            f"the profile has no package '{name}'",
        )

    def required_name(self, definition: Any) -> str:
        _, name = identification(definition)
        if not name:
            raise self.error(definition, f"a {definition.kind} def of the profile has no name")
        return name

    def literals(self, definition: Any) -> tuple[str, ...]:
        names = []
        for element in members(definition):
            if rule(element) == "Usage":
                _, name = identification(element)
                if name:
                    names.append(name)
        return tuple(names)

    # -------------------------------------------------------- concepts

    def concept(self, definition: Any) -> _RawConcept:
        abbreviation, _ = identification(definition)
        name = self.required_name(definition)
        doc = ""
        metaclass: str | None = None
        features: list[_RawFeature] = []
        for element in members(definition):
            kind = rule(element)
            if kind == "Documentation" and not doc:
                doc = doc_text(element.body)
            elif kind == "MetadataUsage" and simple_name(element.type) == STEREOTYPE_METADATA:
                metaclass = self.metaclass(element)
            elif kind == "Usage":
                features.append(self.feature(element))
        return _RawConcept(
            node=definition,
            name=name,
            abbreviation=abbreviation,
            supertypes=tuple(simple_name(s) for s in definition.supertypes),
            abstract=bool(definition.isAbstract),
            metaclass=metaclass,
            features=features,
            doc=doc,
        )

    def metaclass(self, usage: Any) -> str:
        items = getattr(usage.body, "items", None) or []
        for item in items:
            if (
                rule(item) == "MetadataBodyUsage"
                and simple_name(item.feature) == METACLASS_ATTRIBUTE
            ):
                value = self.value(item.value.value, item) if item.value else None
                if not isinstance(value, str) or not value:
                    raise self.error(item, "the metaclass of a stereotype must be a string")
                return value
        raise self.error(usage, f"@{STEREOTYPE_METADATA} without '{METACLASS_ATTRIBUTE} = ...'")

    def feature(self, usage: Any) -> _RawFeature:
        declaration = usage.declaration
        _, name = identification(usage)
        redefines = None
        type_name = ""
        for specialization in getattr(declaration, "specializations", None) or []:
            if rule(specialization) == "Redefinition" and redefines is None:
                redefines = simple_name(specialization.features[0])
            elif rule(specialization) == "Typing" and not type_name:
                type_name = "::".join(name_segments(specialization.types[0].name))
        if not name:
            name = redefines
        if not name:
            raise self.error(usage, "a feature of the profile has neither a name nor ':>> name'")
        if type_name and simple_name(type_name) not in self.type_names:
            raise self.error(usage, f"unknown type '{type_name}' of feature '{name}'")
        try:
            bounds = multiplicity(declaration) if declaration is not None else None
        except ValueError as error:
            raise self.error(usage, f"feature '{name}': {error}") from None
        if bounds is not None and bounds[1] is not None and bounds[1] < bounds[0]:
            raise self.error(usage, f"multiplicity of '{name}' has upper < lower")
        return _RawFeature(
            node=usage,
            name=name,
            type=type_name,
            bounds=bounds,
            kind=_feature_kind(usage),
            default=_enum_literal(self.value(usage.value.value, usage), type_name) if usage.value else None,
            tag=_is_tag(usage),
            redefines=redefines,
        )

    def value(self, expression: Any, owner: Any) -> object:
        try:
            return literal_value(expression)
        except ValueError:
            raise self.error(owner, "only literal values are supported in the profile") from None

    def check_unique(self, raw: list[_RawConcept]) -> None:
        names: set[str] = set()
        abbreviations: set[str] = set()
        for concept in raw:
            if concept.name in names:
                raise self.error(concept.node, f"concept '{concept.name}' is defined twice")
            names.add(concept.name)
            if concept.abbreviation:
                if concept.abbreviation in abbreviations:
                    raise self.error(
                        concept.node, f"abbreviation '{concept.abbreviation}' is used twice"
                    )
                abbreviations.add(concept.abbreviation)
        for concept in raw:
            for supertype in concept.supertypes:
                if supertype not in names:
                    raise self.error(
                        concept.node,
                        f"concept '{concept.name}' specialises '{supertype}', "
                        "which is not a concept of the profile",
                    )

    # -------------------------------------------------------- redefinitions

    def resolve(self, raw: list[_RawConcept]) -> dict[str, Concept]:
        """Build the concepts, supertypes first, completing each redefinition with the
        type (and, when it gives none, the multiplicity) of the feature it redefines."""
        by_name = {c.name: c for c in raw}
        done: dict[str, Concept] = {}
        visiting: set[str] = set()

        def visit(concept: _RawConcept) -> Concept:
            if concept.name in done:
                return done[concept.name]
            if concept.name in visiting:
                raise self.error(concept.node, f"concept '{concept.name}' specialises itself")
            visiting.add(concept.name)
            inherited: dict[str, Feature] = {}
            for supertype in reversed(concept.supertypes):
                parent = visit(by_name[supertype])
                inherited.update(_effective(parent, done))
            features = tuple(self.complete(f, inherited, concept.name) for f in concept.features)
            visiting.discard(concept.name)
            done[concept.name] = Concept(
                name=concept.name,
                abbreviation=concept.abbreviation,
                supertypes=concept.supertypes,
                abstract=concept.abstract,
                metaclass=concept.metaclass,
                features=features,
                doc=concept.doc,
            )
            return done[concept.name]

        for concept in raw:
            visit(concept)
        return {c.name: done[c.name] for c in raw}

    def complete(self, raw: _RawFeature, inherited: dict[str, Feature], owner: str) -> Feature:
        type_name, bounds = raw.type, raw.bounds
        if raw.redefines is not None:
            redefined = inherited.get(raw.redefines)
            if redefined is None:
                raise self.error(
                    raw.node, f"'{owner}' redefines '{raw.redefines}', which it does not inherit"
                )
            type_name = type_name or redefined.type
            bounds = bounds or (redefined.lower, redefined.upper)
        lower, upper = bounds or (1, 1)
        return Feature(
            name=raw.name,
            type=type_name,
            lower=lower,
            upper=upper,
            kind=raw.kind,
            default=raw.default,
            tag=raw.tag,
            redefines=raw.redefines,
        )


def _effective(concept: Concept, done: Mapping[str, Concept]) -> dict[str, Feature]:
    """The features of an already resolved concept, inherited ones included."""
    effective: dict[str, Feature] = {}
    for supertype in reversed(concept.supertypes):
        effective.update(_effective(done[supertype], done))
    for feature in concept.features:
        effective[feature.redefines or feature.name] = feature
    return effective


def _definitions(namespace: Any) -> Iterator[Any]:
    """Definitions owned by a package and its sub-packages, in text order."""
    for element in members(namespace):
        if rule(element) == "Definition":
            yield element
        elif rule(element) == "Package":
            yield from _definitions(element)


def _feature_kind(usage: Any) -> str:
    if usage.isRef or (not usage.kind and not usage.isEnd):
        return "ref"
    if not usage.kind:
        return "end"
    return str(usage.kind)


def _is_tag(usage: Any) -> bool:
    if any(simple_name(p.type) == TAG_METADATA for p in usage.prefixMetadata):
        return True
    return any(
        rule(e) == "MetadataUsage" and simple_name(e.type) == TAG_METADATA for e in members(usage)
    )
