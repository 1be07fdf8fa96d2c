"""Typed syntax tree of the EARL predicate language.

Every node is an immutable, hashable value. ``line`` and ``column`` (1-based) say where
the node's first character stands in the parsed text; they are keyword-only and do not
take part in equality, so two predicates written differently compare equal when they
mean the same tree.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any, Literal, TypeAlias

from earl_m2t.model.naming import split

#: Name suffixes of buffers and memory: a name carrying one of them, written without a
#: member (``.msg`` / ``.data``), is a field reference rather than a predicate reference.
FIELD_SUFFIXES: frozenset[str] = frozenset({"ib", "ob", "m", "mi", "mo"})

#: Comparison operators after normalisation (``=`` → ``==``, ``≤`` → ``<=`` …).
COMPARISON_OPERATORS: tuple[str, ...] = ("<", "<=", ">", ">=", "==", "!=")


def _position() -> Any:
    return field(default=1, compare=False, kw_only=True)


@dataclass(frozen=True, slots=True)
class Const:
    """``TRUE`` or ``FALSE``."""

    value: bool
    line: int = _position()
    column: int = _position()


@dataclass(frozen=True, slots=True)
class Not:
    """Negation: ``¬a``, ``not a``, ``!a``."""

    operand: Expr
    line: int = _position()
    column: int = _position()


@dataclass(frozen=True, slots=True)
class And:
    """Conjunction of two or more operands (chains are flattened)."""

    operands: tuple[Expr, ...]
    line: int = _position()
    column: int = _position()


@dataclass(frozen=True, slots=True)
class Or:
    """Disjunction of two or more operands (chains are flattened)."""

    operands: tuple[Expr, ...]
    line: int = _position()
    column: int = _position()


@dataclass(frozen=True, slots=True)
class PredicateRef:
    """A primitive predicate, by name as written without ``.fun``: ``emergencyStop/pp``.

    A bare name (``emergencyStop``) is kept as is; the caller resolves it.
    """

    name: str
    line: int = _position()
    column: int = _position()

    @property
    def base(self) -> str:
        """The name without its ``/abbr`` suffix."""
        return split(self.name)[0]

    @property
    def suffix(self) -> str | None:
        """The ``abbr`` of ``name/abbr``, or None."""
        return split(self.name)[1]


@dataclass(frozen=True, slots=True)
class FieldRef:
    """A buffer or memory, or a field inside it.

    ``manipulatorCommand/ib.msg.emergencyStopCommand`` is
    ``FieldRef("manipulatorCommand/ib", "msg", ("emergencyStopCommand",))``; a path
    segment with an array index keeps it in the text of the segment (``"q[2]"``).
    ``member`` is ``"msg"``, ``"data"`` or None (the whole buffer or memory).
    """

    head: str
    member: str | None = None
    path: tuple[str, ...] = ()
    line: int = _position()
    column: int = _position()

    @property
    def base(self) -> str:
        """The head name without its ``/abbr`` suffix."""
        return split(self.head)[0]

    @property
    def suffix(self) -> str | None:
        """The ``abbr`` of the head ``name/abbr``, or None."""
        return split(self.head)[1]


@dataclass(frozen=True, slots=True)
class NewData:
    """``newData(ref)``: the last receive() delivered a value not consumed yet."""

    ref: FieldRef
    line: int = _position()
    column: int = _position()


class BuiltInPredicate(StrEnum):
    """The predicates the runtime answers, written ``name()``."""

    LEAVING = "leaving"  # a switch that removes the subsystem's agent is pending
    IN_ERROR = "inError"  # the current behaviour's error condition held (FABRIC's IN_ERROR)
    BEHAVIOUR_OK = "behaviourOk"  # no pf of the current behaviour failed (CURRENT_BEHAVIOR_OK)


@dataclass(frozen=True, slots=True)
class BuiltIn:
    """``leaving()``, ``inError()``, ``behaviourOk()``: a built-in predicate of the runtime."""

    name: BuiltInPredicate
    line: int = _position()
    column: int = _position()


@dataclass(frozen=True, slots=True)
class Number:
    """A numeric literal; only an operand of a comparison."""

    value: float
    line: int = _position()
    column: int = _position()


#: An operand of a comparison.
Operand: TypeAlias = FieldRef | Number


@dataclass(frozen=True, slots=True)
class Compare:
    """``left op right`` with ``op`` one of :data:`COMPARISON_OPERATORS`."""

    op: str
    left: Operand
    right: Operand
    line: int = _position()
    column: int = _position()


@dataclass(frozen=True, slots=True)
class Replicated:
    """``template`` joined by ``op`` over the replicated instances ``var`` = 1..N.

    Written ``a1 ∨ … ∨ aN`` or ``any K: aK`` (``∧`` / ``all`` for ``op == "and"``); the
    template names the instances with the placeholder ``var`` at the end of the head
    name, before the suffix: ``motorControllerStateK/ib``.
    """

    op: Literal["and", "or"]
    template: Expr
    var: str = "K"
    line: int = _position()
    column: int = _position()


#: A boolean expression (usable with ``isinstance``).
Expr: TypeAlias = (
    Const | Not | And | Or | PredicateRef | FieldRef | NewData | BuiltIn | Compare | Replicated
)

#: Any node of the tree (a :class:`Number` is not a boolean expression).
Node: TypeAlias = Expr | Number


def children(node: Node) -> tuple[Node, ...]:
    """The direct sub-nodes of ``node``, in text order."""
    if isinstance(node, Not):
        return (node.operand,)
    if isinstance(node, (And, Or)):
        return node.operands
    if isinstance(node, NewData):
        return (node.ref,)
    if isinstance(node, Compare):
        return (node.left, node.right)
    if isinstance(node, Replicated):
        return (node.template,)
    return ()
