"""How model names become C++ / ROS identifiers and file names (rules D003, D004; generators)."""

from __future__ import annotations

import re
import tomllib
from functools import cache

from earl_m2t.resources import metamodel_path


@cache
def _table() -> dict:
    return tomllib.loads(metamodel_path("tables", "identifiers.toml").read_text(encoding="utf-8"))


def identifier_stem(name: str) -> str:
    """The descriptive part of an EARL name: ``manipulatorCommand/ib`` → ``manipulatorCommand``."""
    return name.rpartition("/")[0] if "/" in name else name


def identifier(name: str) -> str:
    """The identifier generators use: the abbreviation stays, so ``motionFinished/m`` and
    ``motionFinished/pp`` (both in the paper) become ``motionFinished_m`` and ``motionFinished_pp``."""
    stem, slash, abbr = name.rpartition("/")
    return f"{stem}_{abbr}" if slash else name


def identifier_problem(name: str) -> str:
    """Why a name cannot become an identifier, or "" when it can."""
    table = _table()
    stem = identifier_stem(name).strip()
    if not stem:
        return "its descriptive part is empty"
    if not re.match(table["pattern"], stem):
        return f"'{stem}' is not of the form {table['pattern']}"
    ident = identifier(name)
    if "/" in name and not re.match(table["pattern"], ident):
        return f"'{ident}' is not of the form {table['pattern']}"
    if ident in table["cpp_keywords"]:
        return f"'{ident}' is a C++ keyword"
    if ident in table["ros_reserved"]:
        return f"'{ident}' is reserved in ROS messages"
    return ""


def sanitised(name: str) -> str:
    """The identifier a generator derives: non-identifier characters become '_'."""
    return re.sub(r"[^A-Za-z0-9_]", "_", identifier(name))


def collision_key(name: str) -> str:
    """Two names with the same key clash as identifiers or as file names on a case-insensitive disk."""
    return sanitised(name).lower()
