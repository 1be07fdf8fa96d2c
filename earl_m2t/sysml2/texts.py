"""The texts and values a SysML v2 member carries: names of feature chains, bodies of textual
representations (``language "C++" /* … */``), conditions (as predicate text), tag values."""

from __future__ import annotations

import textwrap
from typing import Any

from earl_m2t.predicate.unsayable import unsayable
from earl_m2t.sysml2.conditions import NotACondition, predicate_text
from earl_m2t.sysml2.parser import (
    identification,
    literal_value,
    location,
    members,
    name_segments,
    rule,
    simple_name,
    unwrap,
)

PREDICATE_LANGUAGE = "EARL"

# (language, text, line) of a condition
ConditionText = tuple[str, str, int]


def chain_name(chain: str) -> str:
    """The last name of a feature chain: ``S2.S3`` → ``S3``, ``'x/ib'`` → ``x/ib``."""
    segments = name_segments(chain)
    return segments[-1] if segments else chain


def string_value(raw: str) -> str:
    """The text of a string literal as written (``"C++"`` → ``C++``)."""
    body = raw[1:-1] if len(raw) >= 2 and raw[0] == raw[-1] == '"' else raw
    return body.replace('\\"', '"').replace("\\\\", "\\")


def representation_text(body: str) -> str:
    """The text of ``/* ... */``: markers removed; when every line after the first starts with
    ``*`` (comment style) that column is removed; the lines after the first are dedented
    together (the first starts right after ``/*``); blank lines around are dropped."""
    text = body[2:-2] if body.startswith("/*") and body.endswith("*/") else body
    lines = [line.rstrip() for line in text.split("\n")]
    rest = [line for line in lines[1:] if line.strip()]
    if rest and all(line.lstrip().startswith("*") for line in rest):
        lines = [lines[0]] + [_after_star(line) for line in lines[1:]]
    first, following = lines[0].strip(), textwrap.dedent("\n".join(lines[1:]))
    return (f"{first}\n{following}" if first else following).strip("\n").strip()


def _after_star(line: str) -> str:
    stripped = line.lstrip()
    if not stripped.startswith("*"):
        return line
    rest = stripped[1:]
    return rest[1:] if rest.startswith(" ") else rest


def representation(node: Any) -> ConditionText | None:
    """The first ``language "L" /* text */`` among a member's members."""
    for member in members(node):
        if rule(member) == "TextualRepresentation":
            return string_value(member.language), representation_text(member.body), location(member)[0]
    return None


def guard(expression: Any, owner: Any) -> ConditionText | None:
    """A transition's guard: a textual representation in its body, else its ``if`` expression."""
    written = representation(owner)
    if written is not None or expression is None:
        return written
    return PREDICATE_LANGUAGE, _predicate(expression), location(expression)[0]


def body_condition(node: Any) -> ConditionText | None:
    """``constraint tc { expression }`` or ``constraint tc { language "EARL" /* … */ }``."""
    written = representation(node)
    if written is not None:
        return written
    found = result_expression(node)
    return (PREDICATE_LANGUAGE, found[0], found[1]) if found is not None else None


def result_expression(node: Any) -> tuple[str, int] | None:
    """(predicate text, line) of the result expression of a body, if it has one."""
    for member in members(node):
        if rule(member) == "ResultExpression":
            return _predicate(member.expression), location(member)[0]
    return None


def _predicate(expression: Any) -> str:
    """The predicate text of an expression; one the predicate language cannot say is kept with
    the reason (:mod:`earl_m2t.predicate.unsayable`), which rule B008 reports."""
    try:
        return predicate_text(unwrap(expression))
    except NotACondition as error:
        return unsayable(str(error))


def metadata_tags(node: Any) -> dict[str, str]:
    """``@X { name = value; }`` → ``{name: value}``."""
    tags: dict[str, str] = {}
    for item in getattr(node.body, "items", None) or []:
        if rule(item) == "MetadataBodyUsage" and item.value is not None:
            tags[simple_name(item.feature)] = tag_value(item.value.value)
    return tags


def redefined_values(node: Any) -> dict[str, str]:
    """``:>> name = value`` features of a definition: the tags of the stereotype it applies."""
    tags: dict[str, str] = {}
    for member in members(node):
        if rule(member) != "Usage" or member.value is None or member.declaration is None:
            continue
        for specialization in member.declaration.specializations or []:
            if rule(specialization) == "Redefinition":
                tags[simple_name(specialization.features[0])] = tag_value(member.value.value)
    return tags


def tag_value(expression: Any) -> str:
    """A literal as a tag value: ``AgentType::CET`` → ``CET``, ``2`` → ``2``, ``true``; a
    string as written (``"pkg::Converter"``)."""
    try:
        value = literal_value(expression)
    except ValueError:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return value if rule(unwrap(expression)) == "LiteralString" else value.rpartition("::")[2]
    return "" if value is None else str(value)


def message_type(node: Any) -> str | None:
    """The type of the ``msg`` that a buffer port (or port definition) declares or redefines."""
    for member in members(node):
        if rule(member) != "Usage" or member.declaration is None:
            continue
        specializations = member.declaration.specializations or []
        named = identification(member)[1] == "msg" or any(
            rule(s) == "Redefinition" and simple_name(s.features[0]) == "msg" for s in specializations)
        if not named:
            continue
        for specialization in specializations:
            if rule(specialization) == "Typing":
                return str(specialization.types[0].name)
    return None
