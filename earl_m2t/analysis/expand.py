"""Conditions of one subsystem as propositional formulas over atoms.

A primitive predicate reference is replaced by its body (in the EARL language, recursively;
a reference back into a body being expanded stays one opaque atom), replications are
expanded with the subsystem's counts, and what remains - boolean fields, comparisons,
``newData`` terms and predicates whose body is user code - are the atoms. Memory written
``x/mi.msg`` and ``x/m.data`` is one atom. Each condition also keeps its *terms*: the
primitive predicates and atoms written in it, which counterexamples are printed with.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

from earl_m2t.model.conditions import Condition
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import Subsystem
from earl_m2t.model.naming import split
from earl_m2t.model.scope import Scope
from earl_m2t.predicate import (
    And,
    Compare,
    Const,
    Expr,
    FieldRef,
    NewData,
    Not,
    Number,
    Or,
    PredicateRef,
    Replicated,
    format_predicate,
)

_MEMORY = frozenset({"m", "mi", "mo"})
_FLIP = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "==", "!=": "!="}
_COMPARE: dict[str, Callable[[Any, Any], bool]] = {
    "<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge, "==": operator.eq, "!=": operator.ne,
}


class Unanalysable(Exception):
    """A condition that does not parse (B008) or resolve (B005), or that uses such a predicate."""


@dataclass(frozen=True, slots=True)
class Term:
    """A primitive predicate or an atom as written in a condition, and its formula."""

    label: str
    formula: Expr


@dataclass(frozen=True, slots=True)
class Formula:
    """An analysed condition: its expansion over atoms and the terms it was written with."""

    expr: Expr
    terms: tuple[Term, ...]


class Expander:
    """Expands the conditions of one subsystem; results are cached per primitive predicate."""

    def __init__(self, subsystem: Subsystem, datatypes: Mapping[str, DataType]) -> None:
        assert subsystem.scope is not None, "a lifted subsystem"
        self.subsystem = subsystem
        self.scope: Scope = subsystem.scope
        self.datatypes = datatypes
        self._predicates: dict[str, Expr | None] = {}
        self._expanding: list[str] = []

    def condition(self, condition: Condition | None, missing: bool) -> Formula | None:
        """The formula of a condition (``missing`` is the value of an absent one), or None
        when it cannot be analysed."""
        if condition is None:
            return Formula(Const(missing), ())
        try:
            terms: dict[str, Term] = {}
            expr = self._expand(self._resolved(condition), terms)
        except Unanalysable:
            return None
        return Formula(expr, tuple(terms.values()))

    def predicate(self, name: str) -> Expr | None:
        """The expanded body of a primitive predicate (an opaque atom for user code)."""
        resolved = self.scope.predicate(name)
        if resolved is None:
            return None
        try:
            return self._predicate(resolved)
        except Unanalysable:
            return None

    def field_kind(self, ref: FieldRef) -> str | None:
        return self.scope.field_kind(ref, self.datatypes)

    # -- internals ---------------------------------------------------------------------

    @staticmethod
    def _resolved(condition: Condition) -> Expr:
        resolved = condition.resolved
        if resolved is None:
            raise Unanalysable(condition.owner)
        return resolved

    def _predicate(self, name: str) -> Expr:
        if name in self._expanding:  # a cycle of bodies: the inner reference stays opaque
            return PredicateRef(name)
        if name in self._predicates:
            cached = self._predicates[name]
            if cached is None:
                raise Unanalysable(name)
            return cached
        pp = self.subsystem.predicate(name)
        assert pp is not None
        if pp.fun is None:
            result: Expr | None = PredicateRef(name)  # user code: an atom of its own
        else:
            self._expanding.append(name)
            try:
                result = self._expand(self._resolved(pp.fun), None)
            except Unanalysable:
                result = None
            finally:
                self._expanding.pop()
        self._predicates[name] = result
        if result is None:
            raise Unanalysable(name)
        return result

    def _expand(self, node: Expr, terms: dict[str, Term] | None) -> Expr:
        if isinstance(node, Const):
            return node
        if isinstance(node, Not):
            return Not(self._expand(node.operand, terms))
        if isinstance(node, (And, Or)):
            return type(node)(tuple(self._expand(o, terms) for o in node.operands))
        if isinstance(node, Replicated):
            raise Unanalysable("replication")
        if isinstance(node, PredicateRef):
            name = self.scope.predicate(node.name)
            if name is not None:
                expr = self._predicate(name)
                if terms is not None:
                    terms.setdefault(split(name)[0], Term(split(name)[0], expr))
                return expr
            node_as_field: Expr = FieldRef(node.name)
            atom = _atom(node_as_field)
            label = node.name
        else:
            atom = _atom(node)
            label = format_predicate(node)
        if terms is not None and not isinstance(atom, Const):
            terms.setdefault(label, Term(label, atom))
        return atom


def _atom(node: Expr) -> Expr:
    """The atom a term stands for, with equal meanings made equal values."""
    if isinstance(node, FieldRef):
        return _field(node)
    if isinstance(node, NewData):
        return NewData(_field(node.ref))
    if isinstance(node, Compare):
        left, right, op = node.left, node.right, node.op
        if isinstance(left, Number) and isinstance(right, Number):
            return Const(_COMPARE[op](left.value, right.value))
        if isinstance(left, Number):
            left, right, op = right, left, _FLIP[op]
        return Compare(op, _operand(left), _operand(right))
    return replace(node, line=1, column=1)


def _operand(operand: FieldRef | Number) -> FieldRef | Number:
    return _field(operand) if isinstance(operand, FieldRef) else Number(operand.value)


def _field(ref: FieldRef) -> FieldRef:
    base, suffix = split(ref.head)
    if suffix in _MEMORY:
        member = "data" if ref.member in ("msg", "data") else ref.member
        return FieldRef(f"{base}/m", member, ref.path)
    return FieldRef(ref.head, ref.member, ref.path)
