"""Traversal of predicate trees and their truth value."""

from __future__ import annotations

import operator
from collections.abc import Callable, Iterator
from typing import Any

from earl_m2t.predicate.ast import (
    And,
    BuiltIn,
    BuiltInPredicate,
    Compare,
    Const,
    Expr,
    FieldRef,
    NewData,
    Node,
    Not,
    Number,
    Or,
    PredicateRef,
    Replicated,
    children,
)

_COMPARE: dict[str, Callable[[Any, Any], bool]] = {
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
    "==": operator.eq,
    "!=": operator.ne,
}


def walk(expr: Node) -> Iterator[Node]:
    """Every node of the tree, parents before children, in text order."""
    stack: list[Node] = [expr]
    while stack:
        node = stack.pop()
        yield node
        stack.extend(reversed(children(node)))


def references(expr: Node) -> Iterator[PredicateRef | FieldRef]:
    """The predicate and field references of the tree, in text order.

    Includes the buffer of ``newData(...)``, comparison operands and the templates of
    replications (with their placeholder names, e.g. ``motorControllerStateK/ib``).
    """
    for node in walk(expr):
        if isinstance(node, (PredicateRef, FieldRef)):
            yield node


def evaluate_atoms(expr: Expr, atom_value: Callable[[Expr], bool]) -> bool:
    """The truth value of the and/or/not structure of ``expr``, every other node an atom whose
    value ``atom_value`` gives (a truth assignment, as in guard and outcome enumeration)."""
    if isinstance(expr, Const):
        return expr.value
    if isinstance(expr, Not):
        return not evaluate_atoms(expr.operand, atom_value)
    if isinstance(expr, And):
        return all(evaluate_atoms(o, atom_value) for o in expr.operands)
    if isinstance(expr, Or):
        return any(evaluate_atoms(o, atom_value) for o in expr.operands)
    return atom_value(expr)


def evaluate(
    expr: Expr,
    predicate_value: Callable[[PredicateRef], bool],
    field_value: Callable[[FieldRef], object],
    new_data: Callable[[FieldRef], bool],
    built_in: Callable[[BuiltInPredicate], bool] = lambda name: False,
) -> bool:
    """The truth value of ``expr``, asking the callbacks for the values of references.

    ``field_value`` gives the value of a buffer or memory field (a field standing alone
    counts by its truth value, e.g. a boolean flag); ``new_data`` answers ``newData(ref)``,
    ``built_in`` a built-in predicate such as ``leaving()`` (false unless given).
    And / Or short-circuit from left to right. Replications must have been expanded
    first (see ``expand_replicated``): a :class:`Replicated` raises ValueError.
    """

    def value_of(operand: Node) -> Any:
        if isinstance(operand, Number):
            return operand.value
        if isinstance(operand, FieldRef):
            return field_value(operand)
        raise ValueError(f"not a comparison operand: {operand!r}")

    def truth(node: Node) -> bool:
        if isinstance(node, Const):
            return node.value
        if isinstance(node, Not):
            return not truth(node.operand)
        if isinstance(node, And):
            return all(truth(o) for o in node.operands)
        if isinstance(node, Or):
            return any(truth(o) for o in node.operands)
        if isinstance(node, PredicateRef):
            return bool(predicate_value(node))
        if isinstance(node, FieldRef):
            return bool(field_value(node))
        if isinstance(node, NewData):
            return bool(new_data(node.ref))
        if isinstance(node, BuiltIn):
            return bool(built_in(node.name))
        if isinstance(node, Compare):
            return bool(_COMPARE[node.op](value_of(node.left), value_of(node.right)))
        if isinstance(node, Replicated):
            raise ValueError(
                f"replication over {node.var} at column {node.column} must be expanded "
                "before evaluation (expand_replicated)"
            )
        raise ValueError(f"not a boolean expression: {node!r}")

    return truth(expr)
