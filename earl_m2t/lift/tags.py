"""Reading stereotype tag values as tools write them: a tag by any spelling of its name, an
enumeration literal by name or id, seconds, a flag, and a list of names or element ids.

Values the lift cannot read are kept recognisably wrong (a literal as written, a number as
NaN) so that a rule reports them with their element.
"""

from __future__ import annotations

import math
import re

from earl_m2t.read.xmi import RawModel

_SEPARATORS = re.compile(r"[\s,;]+")
_PATH_SEPARATORS = re.compile(r"[\s;]+")  # a link's path has a comma of its own (``task/a,manip/a``)
_TRUE = frozenset({"true", "1", "yes"})


def tag(tags: dict[str, str], name: str) -> str | None:
    """A tag by name, as tools spell it (``queueSize``, ``queuesize``, ``queue_size``)."""
    wanted = name.lower()
    for key, value in tags.items():
        if key.lower().replace("_", "") == wanted:
            return value.strip()
    return None


def literal(raw: RawModel, value: str) -> str:
    """An enumeration tag value as its literal name: ``queue``, ``ReceiveMode::queue`` or the id
    of the literal (Cameo, EA)."""
    target = raw.by_id.get(value)
    if target is not None:
        value = raw.name(target) or value
    return value.rpartition("::")[2].strip()


def seconds(value: str | None) -> float | None:
    if value is None or value == "":
        return None
    try:
        return float(value)
    except ValueError:
        return math.nan


def flag(value: str | None) -> bool:
    """A Boolean tag: ``true`` (any case), ``1`` or ``yes``; anything else, or none, is false."""
    return value is not None and value.strip().lower() in _TRUE


def names(raw: RawModel, value: str | None, paths: bool = False) -> tuple[str, ...]:
    """Names of a list tag: names separated by spaces, commas or semicolons, or element ids;
    ``paths``: element paths, separated by spaces or semicolons."""
    if not value:
        return ()
    found = []
    for token in (_PATH_SEPARATORS if paths else _SEPARATORS).split(value):
        if not token:
            continue
        target = raw.by_id.get(token)
        found.append(raw.name(target) if target is not None else token)
    return tuple(found)


__all__ = ["flag", "literal", "names", "seconds", "tag"]
