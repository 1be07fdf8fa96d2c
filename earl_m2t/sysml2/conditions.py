"""EARL conditions written as SysML v2 expressions, as text of the predicate language.

A guard ``if 'newJointPos/pp'() and not 'emergencyStop/pp'()`` reads as the predicate
``newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun`` (``metamodel/grammar/predicate.tx``): ``or``,
``and``, ``not`` become ``∨``, ``∧``, ``¬``, ``true``/``false`` ``TRUE``/``FALSE``, quoted
names lose their quotes, an invocation without arguments of a primitive predicate's
``calc def`` (``'x/pp'()``) is its function ``x/pp.fun``; comparisons, other invocations
(``newData(x)``, the built-in ``leaving()``), feature chains (``'x/pp'.fun``, read as
written) and parentheses stay as written; an element of a sequence, ``q#(6)`` (1-based), is
the predicate language's ``q[5]`` (0-based).
"""

from __future__ import annotations

from typing import Any

from earl_m2t.predicate.ast import BuiltInPredicate
from earl_m2t.sysml2.parser import name_segments, rule

OPERATORS = {"OrExpression": " ∨ ", "AndExpression": " ∧ "}
UNARY = {"not": "¬", "-": "-", "+": "+", "~": "~"}
# Expressions the predicate language has no form for, as the messages name them.
NOT_CONDITIONS = {"LiteralString": "a string", "LiteralNull": "null"}
# The function of a primitive predicate in the predicate language: `x/pp.fun`.
FUNCTION = "fun"
# Built-in predicates the profile declares as calculations (`leaving()`), written unquoted.
BUILT_INS = frozenset(BuiltInPredicate)


class NotACondition(ValueError):
    """An expression that the predicate language cannot say."""


def predicate_text(expression: Any) -> str:
    """The predicate-language text of a SysML v2 expression; raises NotACondition."""
    kind = rule(expression)
    if kind in OPERATORS:
        operands = [expression.first, *expression.rest]
        return OPERATORS[kind].join(predicate_text(o) for o in operands)
    if kind == "ComparisonExpression":
        left = predicate_text(expression.left)
        if expression.right is None:
            return left
        return f"{left} {expression.operator} {predicate_text(expression.right)}"
    if kind == "UnaryExpression":
        return UNARY[expression.operator] + predicate_text(expression.operand)
    if kind == "ParenthesizedExpression":
        return f"({predicate_text(expression.inner)})"
    if kind == "InvocationExpression":
        if not expression.arguments and expression.function in BUILT_INS:
            return f"{expression.function}()"
        if not expression.arguments:
            return f"{_name(expression.function)}.{FUNCTION}"
        arguments = ", ".join(predicate_text(a) for a in expression.arguments)
        return f"{_name(expression.function)}({arguments})"
    if kind == "FeatureReference":
        steps = [(expression.name, expression.index), *((c.name, c.index) for c in expression.chain)]
        return ".".join(_name(name) + _index(index) for name, index in steps)
    if kind == "LiteralBoolean":
        return "TRUE" if expression.value == "true" else "FALSE"
    if kind in ("LiteralInteger", "LiteralReal"):
        return str(expression.value)
    raise NotACondition(NOT_CONDITIONS.get(kind, kind))


def _name(raw: str) -> str:
    return "::".join(name_segments(raw))


def _index(suffix: Any) -> str:
    """``#(n)``, whose first element is ``#(1)``, as the predicate language's ``[n - 1]``."""
    if suffix is None:
        return ""
    position = int(suffix.value)
    if position < 1:
        raise NotACondition(f"#({suffix.value}): the elements of a sequence are numbered from 1")
    return f"[{position - 1}]"
