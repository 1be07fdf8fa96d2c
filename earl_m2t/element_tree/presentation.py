"""How the elements of the model tree are called and shown, from ``metamodel/diff/presentation.toml``:
the fields left out of the tree, the EARL name of each kind of element, the labels of fields."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache

from earl_m2t import resources


@dataclass(frozen=True)
class Presentation:
    ignored: frozenset[str]
    kinds: dict[str, str]
    kind_by_field: dict[str, dict[str, dict[str, str]]]
    fields: dict[str, str]
    plurals: dict[str, str]
    details: dict[str, list[str]]

    def plural(self, kind: str, count: int) -> str:
        return kind if count == 1 else self.plurals.get(kind, kind + "s")

    def field_label(self, name: str) -> str:
        return ".".join(self.fields.get(part, part) for part in name.split("."))


@cache
def presentation() -> Presentation:
    data = tomllib.loads(resources.metamodel_path("diff", "presentation.toml").read_text(encoding="utf-8"))
    return Presentation(frozenset(data["ignored"]), dict(data["kinds"]), dict(data.get("kind_by_field", {})),
                        dict(data.get("fields", {})), dict(data.get("plurals", {})),
                        dict(data.get("details", {})))
