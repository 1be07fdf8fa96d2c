"""Which constructs of a SysML v2 model lie outside the subset earl-m2t reads (rule R007).

The subset is data: ``metamodel/grammar/sysml2-subset.toml`` lists the definition and usage
kinds that are read; the reserved words that name a construct come from the grammar's rule
BasicName. A construct outside the subset is reported once, by its leading keywords, and
what it contains is not looked at.
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cache
from typing import Any

from earl_m2t.resources import metamodel_path
from earl_m2t.sysml2.parser import GRAMMAR, location, members, rule

SUBSET_TABLE = ("grammar", "sysml2-subset.toml")
_NAME = re.compile(r"'(?:[^'\\]|\\.)*'|[A-Za-z_][A-Za-z_0-9]*")
_VALUE = re.compile(r"(?<![=<>!])=(?!=)")
_RESERVED = re.compile(r"\(\?!\(([a-z|]+)\)\\b\)")


@dataclass(frozen=True, slots=True)
class Outside:
    """A construct outside the subset: what it is (``perform``, ``requirement def``) and where."""

    construct: str
    line: int
    column: int
    # the construct is one the subset reads (`part`, `state def`), written in a form it does not
    malformed: bool = False


@dataclass(frozen=True)
class Subset:
    definitions: frozenset[str]
    usages: frozenset[str]
    construct_words: int
    keywords: frozenset[str]
    parts_outside: dict[str, tuple[str, ...]]


@cache
def subset() -> Subset:
    table = tomllib.loads(metamodel_path(*SUBSET_TABLE).read_text(encoding="utf-8"))
    grammar = metamodel_path(*GRAMMAR).read_text(encoding="utf-8")
    reserved = _RESERVED.search(grammar)
    keywords = frozenset(reserved.group(1).split("|")) if reserved else frozenset()
    return Subset(
        definitions=frozenset(table["definitions"]),
        usages=frozenset(table["usages"]),
        construct_words=int(table["construct_words"]),
        keywords=keywords,
        parts_outside={k: tuple(v) for k, v in table["parts-outside"].items()},
    )


def outside_constructs(root: Any) -> list[Outside]:
    """Every construct of a parsed model outside the subset, in text order."""
    return list(_walk(root, subset()))


def _walk(element: Any, table: Subset) -> Iterator[Outside]:
    for member in members(element):
        construct = _outside(member, table)
        if construct:
            line, column = location(member)
            yield Outside(construct, line, column, rule(member) == "OutsideSubset" and _is_read(construct, table))
            continue
        yield from _walk(member, table)
        if rule(member) in ("TargetSuccession",) and member.usage is not None:
            yield from _walk(member.usage, table)


def _outside(member: Any, table: Subset) -> str:
    kind = rule(member)
    if kind == "OutsideSubset":
        return _leading_words(member, table)
    if kind == "Definition" and member.kind not in table.definitions:
        return f"{member.kind} def"
    if kind == "Usage" and member.kind and member.kind not in table.usages:
        return f"exhibit {member.kind}" if member.isExhibit else str(member.kind)
    if kind == "Usage" and member.isExhibit and member.kind != "state":
        return f"exhibit {member.kind or ''}".strip()
    if kind == "TargetSuccession" and member.usage is not None:
        return _outside(member.usage, table)
    return ""


def _is_read(construct: str, table: Subset) -> bool:
    words = construct.split()
    if len(words) == 2 and words[1] == "def":
        return words[0] in table.definitions
    return len(words) == 1 and words[0] in table.usages


def _leading_words(member: Any, table: Subset) -> str:
    """``perform``, ``exhibit state``; ``feature x`` for a usage without keyword;
    ``expression`` for the result of a body (``{ a * b > c }``); and ``… with a value
    expression`` when the construct assigns a value (units, arithmetic)."""
    tokens = [str(member.head), *(str(t) for t in member.tokens)]
    words: list[str] = []
    for token in tokens[: table.construct_words]:
        if token not in table.keywords:
            break
        words.append(token)
    name = _NAME.match(tokens[0])
    if not words and not member.end and member.block is None:
        return "expression"
    construct = " ".join(words) if words else f"feature {name.group(0)}" if name else tokens[0]
    key = construct if construct in table.parts_outside else words[0] if words else ""
    part = next((token for token in tokens[len(words):] if token in table.parts_outside.get(key, ())), "")
    if part:
        return f"{key} … {part}"
    if any(token == "default" or _VALUE.search(token) for token in tokens[1:]
           if token[:1] not in "\"'/" and "(" not in token):
        construct += " with a value expression"
    return construct
