"""EARL conditions as FABRIC condition text, the syntax FABRIC's ``logicExprToCpp`` translates:
``and``, ``or``, ``not``, parentheses, ``TRUE``, ``FALSE`` over predicate names and FABRIC's
run-time flags ``IN_ERROR`` (EARL's ``inError()``) and ``CURRENT_BEHAVIOR_OK`` (``behaviourOk()``).

An atom of an EARL condition that is not a primitive predicate (``newData(x/ib)``, a comparison,
a field) becomes a FABRIC predicate of its own, named after its text: FABRIC computes every
predicate in the master's code. The guards of a state's next states are made exclusive where
they can hold together, since FABRIC refuses to choose between two that hold.
"""

from __future__ import annotations

import itertools
from typing import Protocol

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import cpp_identifier
from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import Subsystem
from earl_m2t.predicate import (
    And,
    BuiltIn,
    BuiltInPredicate,
    Const,
    Expr,
    Not,
    Or,
    PredicateRef,
    evaluate_atoms,
    format_predicate,
)

# the built-ins FABRIC's master computes itself (create_master_cpp.py)
FLAGS = {BuiltInPredicate.IN_ERROR: "IN_ERROR", BuiltInPredicate.BEHAVIOUR_OK: "CURRENT_BEHAVIOR_OK"}
MAX_ATOMS = 16  # beyond this many atoms two guards are taken to overlap without trying


class Names(Protocol):
    """Hands out distinct FABRIC names (fabric.FabricNames)."""

    def take(self, earl_name: str) -> str: ...


class ConditionWriter:
    """EARL conditions of one subsystem as FABRIC condition text."""

    def __init__(self, sub: Subsystem, predicates: Names, pp_names: dict[str, str]) -> None:
        assert sub.scope is not None, "a lifted subsystem"
        self.scope = sub.scope
        self.names = predicates
        self.pp_names = pp_names
        self.derived: dict[str, str] = {}  # atom text -> FABRIC predicate name, in order of use

    def text(self, condition: Condition | None, default: bool, what: str) -> str:
        return self._expr(self.expression(condition, default, what), top=True)

    def guard(self, condition: Condition | None, what: str, before: list[Expr]) -> str:
        """A transition's init_cond that also excludes the guards tried before it that can hold
        with it: FABRIC refuses to choose when two next states' conditions hold
        (calculateNextState() == -1), EARL takes the first that holds in priority order."""
        expr = self.expression(condition, True, what)
        overlapping = [b for b in before if _can_both_hold(expr, b)]
        if not overlapping:
            return self._expr(expr, top=True)
        operands = (expr.operands if isinstance(expr, And) else (expr,)) + tuple(Not(b) for b in overlapping)
        return self._expr(And(tuple(dict.fromkeys(operands))), top=True)

    def expression(self, condition: Condition | None, default: bool, what: str) -> Expr:
        if condition is None:
            return Const(default)
        if condition.expanded is None:
            problem = condition.syntax_problem
            raise GenError(f"{what}: {problem.message if problem else 'does not parse'}")
        return condition.expanded

    def _expr(self, node: Expr, top: bool = False) -> str:
        if isinstance(node, Const):
            return "TRUE" if node.value else "FALSE"
        if isinstance(node, Not):
            return f"not {self._operand(node.operand)}"
        if isinstance(node, (And, Or)):
            op = " and " if isinstance(node, And) else " or "
            text = op.join(self._operand(o) for o in node.operands)
            return text if top else f"({text})"
        if isinstance(node, PredicateRef):
            pp = self.scope.predicate(node.name)
            if pp is not None:
                return self.pp_names[pp]
        if isinstance(node, BuiltIn) and node.name in FLAGS:
            return FLAGS[node.name]
        return self._atom(node)

    def _operand(self, node: Expr) -> str:
        return self._expr(node, top=False)

    def _atom(self, node: Expr) -> str:
        text = format_predicate(node)
        if text not in self.derived:
            self.derived[text] = self.names.take(cpp_identifier(text))
        return self.derived[text]


def _atoms(expr: Expr) -> list[Expr]:
    if isinstance(expr, Not):
        return _atoms(expr.operand)
    if isinstance(expr, (And, Or)):
        return [a for o in expr.operands for a in _atoms(o)]
    return [] if isinstance(expr, Const) else [expr]


def _value(expr: Expr, values: dict[Expr, bool]) -> bool:
    """The truth value of ``expr`` under the assignment ``values`` (every atom must have a value)."""
    return evaluate_atoms(expr, values.__getitem__)


def _can_both_hold(a: Expr, b: Expr) -> bool:
    """Whether some value of their atoms (predicates, other terms taken as free) makes both true."""
    atoms = list(dict.fromkeys(_atoms(a) + _atoms(b)))
    if len(atoms) > MAX_ATOMS:
        return True
    both = And((a, b))
    return any(_value(both, dict(zip(atoms, bits))) for bits in itertools.product((False, True), repeat=len(atoms)))
