"""Replicated instances: ``motorControllerK/ve`` with multiplicity [6] stands for six instances."""

from __future__ import annotations

from earl_m2t.model.limits import MAX_INSTANCES
from earl_m2t.model.naming import instance_name
from earl_m2t.read.xmi import Element, RawModel


def multiplicity(raw: RawModel, el: Element) -> tuple[int, int | None]:
    """(lower, upper) of a multiplicity element; upper None is ``*``. UML defaults to 1..1."""
    lower_el = next(iter(raw.children(el, "lowerValue")), None)
    upper_el = next(iter(raw.children(el, "upperValue")), None)
    lower = _literal(lower_el, default=1, missing_value=0)
    upper = _literal(upper_el, default=1, missing_value=0)
    if lower is None:
        lower = 0
    return lower, upper


def _literal(el: Element | None, default: int, missing_value: int) -> int | None:
    if el is None:
        return default
    value = el.get("value")
    if value is None:
        return missing_value
    value = value.strip()
    if value in ("*", "-1"):
        return None
    try:
        return int(value)
    except ValueError:
        return default


def instance_count(lower: int, upper: int | None) -> int:
    """How many instances a multiplicity stands for: N when fixed (lower = upper = N), else 1."""
    if upper is not None and lower == upper and upper > 1:
        return upper
    return 1


def over_bound(lower: int, upper: int | None) -> str:
    """Why a multiplicity stands for more instances than earl-m2t expands, "" when it does not."""
    count = instance_count(lower, upper)
    if count <= MAX_INSTANCES:
        return ""
    return f"a multiplicity of {count} instances, more than the {MAX_INSTANCES} earl-m2t expands: not replicated"


def expand(template: str, count: int) -> list[tuple[str, int]]:
    """The (name, index) of each instance; index 0 marks a single, unreplicated element."""
    if count <= 1:
        return [(template, 0)]
    return [(instance_name(template, k), k) for k in range(1, count + 1)]
