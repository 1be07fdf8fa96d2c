"""A generic SysML summary of a raw model: what ``earl-m2t stats`` prints.

The definitions (which UML types and which SysML stereotypes count) are data, in
``metamodel/stats.toml``; :func:`model_stats` applies them to a :class:`RawModel` and touches
nothing else. Only definitions count: the elements of the reader's id index (elements with an
``xmi:id`` in the model content, tool ``xmi:Extension`` sections left out).
"""

from __future__ import annotations

import tomllib
from collections import Counter
from dataclasses import dataclass
from functools import cache
from typing import Any

from earl_m2t.model.elements import EarlModel
from earl_m2t.read.xmi import RawModel, stereotype_key
from earl_m2t.resources import metamodel_path

TYPE_COUNTS = ("ports", "connectors", "state_machines", "transitions", "activities", "data_types", "packages")
STEREOTYPE_COUNTS = ("blocks", "requirements", "value_types")
COUNTS = (
    "blocks", "parts", "ports", "connectors", "state_machines", "transitions", "activities",
    "requirements", "value_types", "data_types", "packages",
)
FAMILIES = ("sysml", "earl", "other")


@dataclass(frozen=True)
class StereotypeCount:
    """SysML stereotypes (local names as :func:`stereotype_key` reduces them) and the metaclasses they may extend."""

    names: frozenset[str]
    extends: frozenset[str]


@dataclass(frozen=True)
class StatsDefinitions:
    """The tables of ``metamodel/stats.toml``."""

    types: dict[str, frozenset[str]]  # count name -> UML types
    part_types: frozenset[str]
    part_features: frozenset[str]
    part_aggregation: str
    stereotypes: dict[str, StereotypeCount]  # count name -> stereotype definition

    def __hash__(self) -> int:
        return id(self)


def _strings(value: Any, where: str) -> frozenset[str]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ValueError(f"metamodel/stats.toml: {where} must be a list of strings")
    return frozenset(value)


def _keys(table: Any, expected: tuple[str, ...], where: str) -> dict[str, Any]:
    if not isinstance(table, dict) or set(table) != set(expected):
        found = sorted(table) if isinstance(table, dict) else []
        raise ValueError(f"metamodel/stats.toml: [{where}] must define exactly {', '.join(expected)}; found {found}")
    return table


def parse_definitions(text: str) -> StatsDefinitions:
    data = tomllib.loads(text)
    types = _keys(data.get("types"), TYPE_COUNTS, "types")
    parts = data.get("parts")
    if not isinstance(parts, dict) or not isinstance(parts.get("aggregation"), str):
        raise ValueError("metamodel/stats.toml: [parts] needs types, features and aggregation")
    stereotypes = _keys(data.get("stereotypes"), STEREOTYPE_COUNTS, "stereotypes")
    return StatsDefinitions(
        types={key: _strings(types[key], f"types.{key}") for key in TYPE_COUNTS},
        part_types=_strings(parts.get("types"), "parts.types"),
        part_features=_strings(parts.get("features"), "parts.features"),
        part_aggregation=parts["aggregation"],
        stereotypes={
            key: StereotypeCount(
                names=frozenset(
                    stereotype_key(n) for n in _strings(stereotypes[key].get("names"), f"stereotypes.{key}.names")
                ),
                extends=_strings(stereotypes[key].get("extends"), f"stereotypes.{key}.extends"),
            )
            for key in STEREOTYPE_COUNTS
        },
    )


@cache
def stats_definitions() -> StatsDefinitions:
    return parse_definitions(metamodel_path("stats.toml").read_text(encoding="utf-8"))


@dataclass(frozen=True)
class EarlCounts:
    """What the EARL lifter recognised (the model that ``earl-m2t show`` prints)."""

    agents: int
    subsystems: int
    links: int


@dataclass(frozen=True)
class Stats:
    """The summary of one model file."""

    file: str
    dialect: str
    file_size: int | None  # bytes of the file as given (a .mdzip archive, not its member); None if unknown
    elements: int  # definitions: elements with an xmi:id in the model content
    blocks: int
    parts: int
    ports: int
    connectors: int
    state_machines: int
    transitions: int
    activities: int
    requirements: int
    value_types: int
    data_types: int
    packages: int
    stereotypes_sysml: int  # stereotype applications by profile family
    stereotypes_earl: int
    stereotypes_other: int
    earl: EarlCounts | None = None  # None when the file holds no EARL model (or it was not lifted)

    def counts(self) -> dict[str, int]:
        """The element counts, in the documented order."""
        return {key: int(getattr(self, key)) for key in COUNTS}

    def stereotype_applications(self) -> dict[str, int]:
        return {family: int(getattr(self, f"stereotypes_{family}")) for family in FAMILIES}


def model_stats(
    raw: RawModel,
    *,
    file_size: int | None = None,
    earl: EarlModel | None = None,
    definitions: StatsDefinitions | None = None,
) -> Stats:
    """Count the SysML elements of ``raw``; ``earl`` (the lifted model, if any) adds the EARL figures."""
    defs = definitions or stats_definitions()
    by_type: dict[str, list[str]] = {}
    for key, types in defs.types.items():
        for uml_type in types:
            by_type.setdefault(uml_type, []).append(key)

    counts: Counter[str] = Counter()
    for el in raw.by_id.values():
        if raw.is_copy(el):
            continue  # a tool's copy of a port or part shown on a part (Enterprise Architect)
        uml_type = raw.uml_type(el)
        for key in by_type.get(uml_type, ()):
            counts[key] += 1
        if (
            uml_type in defs.part_types
            and el.tag in defs.part_features
            and el.get("aggregation") == defs.part_aggregation
        ):
            counts["parts"] += 1

    by_name: dict[str, list[tuple[str, StereotypeCount]]] = {}
    for key, definition in defs.stereotypes.items():
        for name in definition.names:
            by_name.setdefault(name, []).append((key, definition))
    families: Counter[str] = Counter()
    for base_id, applications in raw.stereotypes.items():
        copied = raw.by_id.get(base_id)
        if copied is not None and raw.is_copy(copied):
            continue
        for app in applications:
            families[app.family if app.family in FAMILIES else "other"] += 1
            if app.family != "sysml":
                continue
            matches = by_name.get(stereotype_key(app.name))
            if not matches:
                continue
            base = raw.by_id.get(base_id)
            if base is None:
                continue  # extends nothing defined in this file
            base_type = raw.uml_type(base)
            for key, definition in matches:
                if base_type in definition.extends:
                    counts[key] += 1

    earl_counts = None
    if earl is not None and earl.has_earl_content:
        earl_counts = EarlCounts(len(earl.agents), len(earl.subsystems), len(earl.links))
    return Stats(
        file=raw.file,
        dialect=raw.dialect,
        file_size=file_size,
        elements=len(raw.by_id),
        blocks=counts["blocks"],
        parts=counts["parts"],
        ports=counts["ports"],
        connectors=counts["connectors"],
        state_machines=counts["state_machines"],
        transitions=counts["transitions"],
        activities=counts["activities"],
        requirements=counts["requirements"],
        value_types=counts["value_types"],
        data_types=counts["data_types"],
        packages=counts["packages"],
        stereotypes_sysml=families["sysml"],
        stereotypes_earl=families["earl"],
        stereotypes_other=families["other"],
        earl=earl_counts,
    )
