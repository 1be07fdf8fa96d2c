"""Structural comparison of dataTypes (rule C006): names do not matter, structure does."""

from __future__ import annotations

from collections.abc import Mapping

from earl_m2t.model.datatypes import DataType


def structural_difference(datatypes: Mapping[str, DataType], left: str, right: str) -> str:
    """A short description of the first structural difference, or "" when they match."""
    return _compare(datatypes, left, right, "", set())


def _compare(datatypes: Mapping[str, DataType], left: str, right: str, where: str, seen: set[tuple[str, str]]) -> str:
    if left == right or (left, right) in seen:
        return ""
    seen.add((left, right))
    a, b = datatypes.get(left), datatypes.get(right)
    if a is None or b is None:
        return ""
    at = f" at {where}" if where else ""
    if a.kind != b.kind:
        return f"{a.kind} vs {b.kind}{at}"
    if a.kind == "primitive":
        return "" if a.primitive == b.primitive else f"{a.primitive} vs {b.primitive}{at}"
    if a.kind == "enumeration":
        return "" if a.literals == b.literals else f"different enumeration literals{at}"
    names_a = [f.name for f in a.fields]
    names_b = [f.name for f in b.fields]
    if names_a != names_b:
        missing = sorted(set(names_a) ^ set(names_b))
        detail = f"fields {', '.join(missing)} differ" if missing else "fields in another order"
        return f"{detail}{at}"
    for fa, fb in zip(a.fields, b.fields):
        path = f"{where}.{fa.name}" if where else fa.name
        if (fa.lower, fa.upper) != (fb.lower, fb.upper):
            return f"multiplicity of {path} differs"
        difference = _compare(datatypes, fa.type, fb.type, path, seen)
        if difference:
            return difference
    return ""
