"""Parse predicate text into the typed tree of :mod:`earl_m2t.predicate.ast`.

The grammar is data (``metamodel/grammar/predicate.tx``); textX parses the text into a
model that :class:`_Builder` walks to make AST nodes, flattening chains, resolving the
paper's ``a1 ∨ … ∨ aN`` replication form and deciding, for each name, whether it is a
primitive predicate or a buffer / memory reference.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass
from functools import cache
from typing import Any, Literal

from textx import metamodel_from_file
from textx.exceptions import TextXError, TextXSyntaxError

from earl_m2t.model.limits import MAX_OPERATORS
from earl_m2t.predicate.ast import (
    FIELD_SUFFIXES,
    BuiltIn,
    BuiltInPredicate,
    Compare,
    Const,
    Expr,
    FieldRef,
    NewData,
    Not,
    Number,
    Operand,
    PredicateRef,
    Replicated,
)
from earl_m2t.predicate.errors import PredicateSyntaxError, where
from earl_m2t.predicate.printer import format_node
from earl_m2t.predicate.transform import OperandsDiffer, is_indexed, join, replication_template
from earl_m2t.predicate.walk import references
from earl_m2t.resources import metamodel_path

# Spaces between tokens: ASCII white space and the no-break / thin spaces of pasted text.
_WHITESPACE = " \t\r\n\f\v\u00a0\u2007\u2009\u202f"
# the binary and prefix operators of the grammar (metamodel/grammar/predicate.tx), comparisons included
_OPERATOR = re.compile(r"(?<![\w/])(?:or|and|not)(?![\w/])|[∨∧¬≤≥≠]|\|\||&&|[<>=!]=?")

_COMPARISONS = {"=": "==", "≤": "<=", "≥": ">=", "≠": "!="}


@cache
def _metamodel() -> Any:
    """The textX metamodel of the predicate grammar, built once."""
    return metamodel_from_file(str(metamodel_path("grammar", "predicate.tx")), ws=_WHITESPACE)


def parse_predicate(text: str) -> Expr:
    """Parse a predicate, e.g. ``newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun``.

    Raises :class:`PredicateSyntaxError` (message, 1-based line and column) when the text
    is empty or malformed, including a replication ``a1 ∨ … ∨ aN`` whose operands do
    not match.
    """
    if not isinstance(text, str):
        raise TypeError(f"predicate text must be a str, not {type(text).__name__}")
    if not text.strip(_WHITESPACE):
        raise PredicateSyntaxError(
            "the predicate is empty: expected a predicate name or '(' at column 1", 1, 1
        )
    _refuse_long(text)
    try:
        model = _metamodel().model_from_str(text)
        return _Builder(text).or_expr(model.expr)
    except TextXSyntaxError as err:
        raise _syntax_error(text, err) from None
    except TextXError as err:  # not raised by this grammar; never let textX types escape
        line, column = err.line or 1, err.col or 1
        message = f"{err.message} at {where(line, column)}"
        raise PredicateSyntaxError(message, line, column) from None
    except RecursionError:
        message = "the predicate is nested too deeply (at column 1)"
        raise PredicateSyntaxError(message, 1, 1) from None


def _refuse_long(text: str) -> None:
    """More than ``MAX_OPERATORS`` operators: refused before parsing, whose cost grows faster."""
    operators = _OPERATOR.findall(text)
    if len(operators) > MAX_OPERATORS:
        raise PredicateSyntaxError(f"the predicate has more than {MAX_OPERATORS} operators: not read", 1, 1)


# -- from the textX model to AST nodes ------------------------------------------------


@dataclass(frozen=True, slots=True)
class _Ellipsis:
    """A ``…`` operand of a chain, replaced by a Replicated node once its neighbours are known."""

    line: int
    column: int


class _Builder:
    def __init__(self, text: str) -> None:
        self.line_starts = [0] + [i + 1 for i, char in enumerate(text) if char == "\n"]

    def at(self, obj: Any) -> dict[str, int]:
        """``line`` and ``column`` of a textX object, as keyword arguments for a node."""
        offset = obj._tx_position
        line = bisect.bisect_right(self.line_starts, offset)
        return {"line": line, "column": offset - self.line_starts[line - 1] + 1}

    def error(self, obj: Any, message: str) -> PredicateSyntaxError:
        pos = self.at(obj)
        return PredicateSyntaxError(f"{message} at {where(pos['line'], pos['column'])}",
                                    pos["line"], pos["column"])

    # chains

    def or_expr(self, obj: Any) -> Expr:
        items: list[tuple[Any, Expr | _Ellipsis]] = []
        for and_expr in obj.operands:
            operands = and_expr.operands
            if len(operands) == 1 and _kind(operands[0]) == "Ellipsis":
                items.append((and_expr, _Ellipsis(**self.at(operands[0]))))
            else:
                items.append((and_expr, self.and_expr(and_expr)))
        return self.chain("or", obj, items)

    def and_expr(self, obj: Any) -> Expr:
        items: list[tuple[Any, Expr | _Ellipsis]] = [
            (o, _Ellipsis(**self.at(o)) if _kind(o) == "Ellipsis" else self.expr(o))
            for o in obj.operands
        ]
        return self.chain("and", obj, items)

    def chain(self, op: Literal["and", "or"], obj: Any,
              items: list[tuple[Any, Expr | _Ellipsis]]) -> Expr:
        """Resolve the ``first ∨ … ∨ last`` triples of a chain, then join it (flattened).

        ``items`` pairs each operand with the textX object where its text starts.
        """
        out: list[Expr] = []
        may_open = False  # whether out[-1] is an operand as written, able to open a replication
        i = 0
        while i < len(items):
            item = items[i][1]
            if isinstance(item, _Ellipsis):
                after = items[i + 1][1] if i + 1 < len(items) else None
                if not may_open or after is None or isinstance(after, _Ellipsis):
                    raise PredicateSyntaxError(
                        "'…' must stand between two operands joined by the same operator, "
                        f"as in 'a1 ∨ … ∨ aN', at {where(item.line, item.column)}",
                        item.line,
                        item.column,
                    )
                first = out.pop()
                try:
                    template = replication_template(first, after, line=item.line, column=item.column)
                except OperandsDiffer as differ:
                    raise _operands_differ(differ) from None
                out.append(Replicated(op, template, "K", **self.at(items[i - 1][0])))
                may_open = False
                i += 2
                continue
            out.append(item)
            may_open = True
            i += 1
        return join(op, out, **self.at(obj))

    # operands

    def expr(self, obj: Any) -> Expr:
        kind = _kind(obj)
        if kind == "Negation":
            return Not(self.expr(obj.operand), **self.at(obj))
        if kind == "Group":
            return self.or_expr(obj.expr)
        if kind == "Quantified":
            return self.quantified(obj)
        if kind == "NewData":
            ref = self.field(obj.ref, "newData(...) takes a buffer or memory")
            return NewData(ref, **self.at(obj))
        if kind == "BuiltIn":
            return BuiltIn(BuiltInPredicate(obj.name), **self.at(obj))
        if kind == "Constant":
            return Const(obj.value.lower() == "true", **self.at(obj))
        if kind == "NumberComparison":
            return Compare(_COMPARISONS.get(obj.op, obj.op), self.number(obj.left),
                           self.operand(obj.right), **self.at(obj))
        if kind == "RefAtom":
            if obj.op is None:
                return self.reference(obj.ref)
            return Compare(_COMPARISONS.get(obj.op, obj.op),
                           self.field(obj.ref, "a comparison takes fields and numbers"),
                           self.operand(obj.right), **self.at(obj))
        raise AssertionError(f"unexpected rule {kind} in the predicate grammar")

    def quantified(self, obj: Any) -> Replicated:
        op: Literal["and", "or"] = "or" if obj.quantifier in ("any", "∃") else "and"
        body = self.or_expr(obj.body)
        if not any(is_indexed(r.name if isinstance(r, PredicateRef) else r.head, obj.var)
                   for r in references(body)):
            raise self.error(
                obj,
                f"the body of '{obj.quantifier} {obj.var}:' names no replicated instance "
                f"(write {obj.var} at the end of a name, e.g. 'motor{obj.var}/ib')",
            )
        return Replicated(op, body, obj.var, **self.at(obj))

    def reference(self, obj: Any) -> PredicateRef | FieldRef:
        """A name in a boolean position: a predicate, or a buffer / memory (field)."""
        head = _head(obj.head)
        if obj.fun:
            return PredicateRef(head, **self.at(obj))
        if obj.member is None and obj.head.suffix not in FIELD_SUFFIXES:
            return PredicateRef(head, **self.at(obj))
        return self.field(obj, "")

    def field(self, obj: Any, context: str) -> FieldRef:
        """A name where only a buffer / memory (field) may stand."""
        if obj.fun:
            raise self.error(obj, f"{context}, not the predicate '{_head(obj.head)}.fun'")
        path = tuple(s.name if s.index is None else f"{s.name}[{s.index}]" for s in obj.path)
        return FieldRef(_head(obj.head), obj.member, path, **self.at(obj))

    def operand(self, obj: Any) -> Operand:
        if _kind(obj) == "Number":
            return self.number(obj)
        return self.field(obj, "a comparison takes fields and numbers")

    def number(self, obj: Any) -> Number:
        return Number(float(obj.value), **self.at(obj))


def _kind(obj: Any) -> str:
    return type(obj).__name__


def _head(name: Any) -> str:
    return name.base if name.suffix is None else f"{name.base}/{name.suffix}"


def _operands_differ(differ: OperandsDiffer) -> PredicateSyntaxError:
    """The error of a replication whose operands differ in more than the index, with both texts."""
    before, after = differ.before, differ.after
    message = (f"'{format_node(after)}' after '…' does not repeat '{format_node(before)}' before it "
               f"(only the index may change, from 1 to {differ.last_index})")
    return PredicateSyntaxError(f"{message} at {where(after.line, after.column)}", after.line, after.column)


# -- readable syntax errors -------------------------------------------------------------

_OPERAND = "a predicate name or '('"
_TOKEN_LABELS: dict[str, str] = {
    "ID": "a name",
    "NUMBER": "a number",
    "FUN": "'msg', 'data' or 'fun'",
    "MEMBER": "'msg', 'data' or 'fun'",
    "SUFFIX": "a name suffix such as 'ib'",
    "INDEX": "an index",
    "EOF": "the end of the text",
    ")": "')'",
    "]": "']'",
    "(": "'('",
    ":": "':'",
}
_OPERATORS = {"AND", "OR", "COMPARISON"}
_OPERAND_STARTS = {"ELLIPSIS", "NOT", "QUANTIFIER", "(", "NEWDATA", "BOOLEAN", "NUMBER", "ID"}
_ORDER = [_OPERAND, "a field reference or a number", "a name", "'msg', 'data' or 'fun'",
          "a name suffix such as 'ib'", "an index", "')'", "']'", "'('", "':'", "an operator",
          "a comparison operator", "the end of the text"]
_TOKEN = re.compile(r"\w+|&&|\|\||\.\.\.|<=|>=|==|!=|\S")


def _syntax_error(text: str, err: TextXSyntaxError) -> PredicateSyntaxError:
    line, column = err.line or 1, err.col or 1
    starts = [0] + [i + 1 for i, char in enumerate(text) if char == "\n"]
    offset = starts[min(line, len(starts)) - 1] + column - 1
    token = _TOKEN.search(text, offset)
    found = f"'{token.group()}'" if token else "the end of the text"
    expected = _expected(err.expected_rules or [])
    return PredicateSyntaxError(f"expected {expected} at {where(line, column)}, found {found}",
                                line, column)


def _expected(rules: list[Any]) -> str:
    """Describe what the parser expected, by kind of token rather than by regex."""
    keys = {rule.rule_name or getattr(rule, "to_match", "") for rule in rules}
    labels: set[str] = set()
    if "ID" in keys and "(" in keys:
        labels.add(_OPERAND)
        keys -= _OPERAND_STARTS
    elif {"ID", "NUMBER"} <= keys:
        labels.add("a field reference or a number")
        keys -= {"ID", "NUMBER"}
    for key in keys:
        if key in _OPERATORS:
            only_comparison = not keys & {"AND", "OR"}
            labels.add("a comparison operator" if only_comparison else "an operator")
        elif key in _TOKEN_LABELS:
            labels.add(_TOKEN_LABELS[key])
    if not labels:  # only optional continuations of a name, such as '/' or '.'
        labels = {f"'{key}'" for key in keys if key}
    ordered = sorted(labels, key=lambda label: (_ORDER.index(label) if label in _ORDER else -1,
                                                label))
    if not ordered:
        return "a predicate"
    return ordered[0] if len(ordered) == 1 else ", ".join(ordered[:-1]) + " or " + ordered[-1]
