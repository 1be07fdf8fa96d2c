"""Reads the EARL profile (``profiles/earl.sysml``, SysML v2 text) into a
:class:`~earl_m2t.profile_types.Profile`, checking it on the way. Only a cache miss of
:func:`earl_m2t.profile.load_profile` runs it."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from earl_m2t.profile_types import (
    METACLASS_ATTRIBUTE,
    MODEL_PACKAGE,
    ROOT_PACKAGE,
    STEREOTYPE_METADATA,
    TAG_METADATA,
    Concept,
    Feature,
    Profile,
    ProfileError,
)
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


def read_profile(path: Path) -> Profile:
    """The profile of a SysML v2 file. Raises ProfileError."""
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
