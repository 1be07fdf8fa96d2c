"""Text of a predicate tree, with the fewest parentheses that keep its meaning.

``parse_predicate(format_predicate(e, style)) == e`` for every tree the parser makes.
"""

from __future__ import annotations

import math
from typing import Literal

from earl_m2t.model.naming import split
from earl_m2t.predicate.ast import (
    FIELD_SUFFIXES,
    And,
    BuiltIn,
    Compare,
    Const,
    FieldRef,
    NewData,
    Node,
    Not,
    Number,
    Or,
    PredicateRef,
    Replicated,
)
from earl_m2t.predicate.errors import PredicateSyntaxError
from earl_m2t.predicate.transform import OperandsDiffer, replication_template, substitute_index
from earl_m2t.predicate.walk import walk

Style = Literal["unicode", "ascii"]

_SYMBOLS: dict[str, dict[str, str]] = {
    "unicode": {"and": " ∧ ", "or": " ∨ ", "not": "¬", "true": "TRUE", "false": "FALSE",
                "any": "∃", "all": "∀"},
    "ascii": {"and": " and ", "or": " or ", "not": "not ", "true": "true", "false": "false",
              "any": "any ", "all": "all "},
}

# Binding strength; a quantifier's body reaches as far right as it can.
_QUANTIFIER, _OR, _AND, _NOT, _ATOM = 0, 1, 2, 3, 4

# Bare names that the parser would read as a keyword or constant without ``.fun``.
_KEYWORD_NAMES = frozenset({"and", "or", "not", "any", "all", "newData"})


def format_predicate(expr: Node, style: Style = "unicode") -> str:
    """The text of ``expr``.

    ``unicode`` writes ``∧ ∨ ¬ TRUE FALSE`` and replications in the paper's form
    ``a1 ∨ … ∨ aN`` (``∃K:`` / ``∀K:`` when that form cannot express them, e.g. nested
    replications); ``ascii`` writes ``and or not true false`` and ``any K:`` / ``all K:``.
    Predicate references are written without ``.fun`` unless the name needs it to stay a
    predicate (``x/ib.fun``, ``false.fun``).
    """
    if style not in _SYMBOLS:
        raise ValueError(f"unknown style {style!r}: expected 'unicode' or 'ascii'")
    return _Printer(style).expr(expr, _QUANTIFIER, followed=False)


def format_node(node: Node) -> str:
    """The unicode text of one node (used in messages)."""
    return format_predicate(node)


class _Printer:
    def __init__(self, style: Style) -> None:
        self.style = style
        self.sym = _SYMBOLS[style]
        self._ellipsis: dict[int, tuple[Node, Node] | None] = {}

    # -- precedence -------------------------------------------------------------------

    def ellipsis_operands(self, rep: Replicated) -> tuple[Node, Node] | None:
        """First and last operand of ``a1 ∨ … ∨ aN`` when that form reads back as ``rep``."""
        key = id(rep)
        if key not in self._ellipsis:
            self._ellipsis[key] = _ellipsis_operands(rep) if self.style == "unicode" else None
        return self._ellipsis[key]

    def precedence(self, node: Node) -> int:
        if isinstance(node, Or):
            return _OR
        if isinstance(node, And):
            return _AND
        if isinstance(node, Not):
            return _NOT
        if isinstance(node, Replicated):
            if self.ellipsis_operands(node) is None:
                return _QUANTIFIER
            return _AND if node.op == "and" else _OR
        return _ATOM

    # -- text ------------------------------------------------------------------------

    def expr(self, node: Node, min_precedence: int, followed: bool) -> str:
        """``node`` inside a context binding at ``min_precedence``; ``followed`` tells
        whether more text follows it before the context closes."""
        precedence = self.precedence(node)
        if precedence == _QUANTIFIER:
            needs_parentheses = followed
        else:
            needs_parentheses = precedence < min_precedence
        if needs_parentheses:
            return "(" + self.expr(node, _QUANTIFIER, followed=False) + ")"
        return self.bare(node, followed)

    def chain(self, op: str, operands: tuple[Node, ...], followed: bool) -> str:
        own = _AND if op == "and" else _OR
        texts = []
        for i, operand in enumerate(operands):
            # the paper's a1 ∨ … ∨ aN stands in an or-chain without parentheses
            same_replication = (isinstance(operand, Replicated) and operand.op == op
                                and self.ellipsis_operands(operand) is not None)
            minimum = own if same_replication else own + 1
            last = i == len(operands) - 1
            texts.append(self.expr(operand, minimum, followed if last else True))
        return self.sym[op].join(texts)

    def bare(self, node: Node, followed: bool) -> str:
        if isinstance(node, Const):
            return self.sym["true" if node.value else "false"]
        if isinstance(node, Not):
            return self.sym["not"] + self.expr(node.operand, _NOT, followed)
        if isinstance(node, And):
            return self.chain("and", node.operands, followed)
        if isinstance(node, Or):
            return self.chain("or", node.operands, followed)
        if isinstance(node, Replicated):
            return self.replicated(node, followed)
        if isinstance(node, PredicateRef):
            return _predicate_name(node.name)
        if isinstance(node, FieldRef):
            return _field(node)
        if isinstance(node, NewData):
            return f"newData({_field(node.ref)})"
        if isinstance(node, BuiltIn):
            return f"{node.name}()"
        if isinstance(node, Compare):
            return f"{self.bare(node.left, True)} {node.op} {self.bare(node.right, followed)}"
        if isinstance(node, Number):
            return _number(node.value)
        raise TypeError(f"not a predicate node: {node!r}")

    def replicated(self, node: Replicated, followed: bool) -> str:
        operands = self.ellipsis_operands(node)
        if operands is None:
            quantifier = self.sym["any" if node.op == "or" else "all"]
            return f"{quantifier}{node.var}: {self.expr(node.template, _QUANTIFIER, followed)}"
        first, last = operands
        minimum = _AND if node.op == "or" else _NOT
        op = self.sym[node.op]
        return (f"{self.expr(first, minimum, True)}{op}…{op}"
                f"{self.expr(last, minimum, followed)}")


def _ellipsis_operands(rep: Replicated) -> tuple[Node, Node] | None:
    if rep.var != "K" or any(isinstance(n, Replicated) for n in walk(rep.template)):
        return None
    first = substitute_index(rep.template, rep.var, 1)
    last = substitute_index(rep.template, rep.var, "N")
    try:
        template = replication_template(first, last, var=rep.var)
    except (PredicateSyntaxError, OperandsDiffer):
        return None
    return (first, last) if template == rep.template else None


def _predicate_name(name: str) -> str:
    base, suffix = split(name)
    if suffix is None:
        keyword = base.lower() in ("true", "false") or base in _KEYWORD_NAMES
    else:
        keyword = suffix in FIELD_SUFFIXES
    return f"{name}.fun" if keyword else name


def _field(ref: FieldRef) -> str:
    if ref.member is None:
        return ref.head
    return ".".join((ref.head, ref.member, *ref.path))


def _number(value: float) -> str:
    if math.isnan(value):
        raise ValueError("NaN has no text in the predicate language")
    if math.isinf(value):
        return "1e999" if value > 0 else "-1e999"
    if value.is_integer() and abs(value) < 1e16:
        return str(int(value))
    return repr(value)
