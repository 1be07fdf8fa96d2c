"""The abstract syntax of OCL expressions: small frozen dataclasses, free of textX objects."""

from __future__ import annotations

from dataclasses import dataclass


class Node:
    """Base class of every expression node."""

    __slots__ = ()


@dataclass(frozen=True, slots=True)
class Literal(Node):
    """An integer, real, string, boolean or null literal."""

    value: object


@dataclass(frozen=True, slots=True)
class Variable(Node):
    """A variable reference; ``self`` is the variable named ``self``."""

    name: str


@dataclass(frozen=True, slots=True)
class Navigation(Node):
    """``source.name``: attribute access, applied to each element of a collection."""

    source: Node
    name: str


@dataclass(frozen=True, slots=True)
class MethodCall(Node):
    """``source.name(arguments)``: an operation on a single value (``matches``, ``size`` …)."""

    source: Node
    name: str
    arguments: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class CollectionCall(Node):
    """``source->name(arguments)``: an operation on a collection (``size``, ``includes`` …)."""

    source: Node
    name: str
    arguments: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Iterate(Node):
    """``source->name(variable | body)``: an iterator (``forAll``, ``select`` …)."""

    source: Node
    name: str
    variable: str
    body: Node


@dataclass(frozen=True, slots=True)
class Unary(Node):
    """``not operand`` or ``-operand``."""

    operator: str
    operand: Node


@dataclass(frozen=True, slots=True)
class Binary(Node):
    """``left operator right`` for boolean, comparison and arithmetic operators."""

    operator: str
    left: Node
    right: Node


@dataclass(frozen=True, slots=True)
class If(Node):
    """``if condition then then_branch else else_branch endif``."""

    condition: Node
    then_branch: Node
    else_branch: Node


@dataclass(frozen=True, slots=True)
class Let(Node):
    """``let variable = value in body``."""

    variable: str
    value: Node
    body: Node


# Operation names accepted by the parser, with their number of arguments. The evaluator
# implements exactly these; the parser rejects anything else with a located syntax error.
METHOD_ARITY: dict[str, int] = {
    "matches": 1,
    "startsWith": 1,
    "endsWith": 1,
    "concat": 1,
    "toLower": 0,
    "toUpper": 0,
    "size": 0,
    "oclIsUndefined": 0,
}

COLLECTION_ARITY: dict[str, int] = {
    "notEmpty": 0,
    "isEmpty": 0,
    "size": 0,
    "includes": 1,
    "excludes": 1,
    "includesAll": 1,
    "excludesAll": 1,
    "count": 1,
    "sum": 0,
    "min": 0,
    "max": 0,
    "first": 0,
    "last": 0,
    "asSet": 0,
    "asSequence": 0,
    "union": 1,
}

ITERATORS: frozenset[str] = frozenset(
    {"forAll", "exists", "select", "reject", "collect", "any", "one", "isUnique"}
)
