"""``inError()`` read where it has a known value: in a terminal condition ``tc`` and in the
guards of the transitions leaving a state it is the value of the state's error condition
``ec`` in the same iteration (the runtime writes it right after ``ec`` is evaluated). In
``ec`` itself it is the previous iteration's value and stays an atom of either value, as does
``behaviourOk()`` everywhere (the environment's: whether a pf failed)."""

from __future__ import annotations

from typing import cast

from earl_m2t.analysis.expand import Formula, Term
from earl_m2t.predicate import BuiltIn, BuiltInPredicate, Expr, map_children, walk

_IN_ERROR = BuiltIn(BuiltInPredicate.IN_ERROR)


def with_error(formula: Formula | None, ec: Formula | None) -> Formula | None:
    """``formula`` (a tc or a guard) with ``inError()`` replaced by ``ec``'s expansion."""
    if formula is None or ec is None or not any(node == _IN_ERROR for node in walk(formula.expr)):
        return formula

    def substitute(node: Expr) -> Expr:
        if node == _IN_ERROR:
            return ec.expr
        return cast(Expr, map_children(node, lambda child: substitute(cast(Expr, child))))

    return Formula(substitute(formula.expr), tuple(Term(t.label, substitute(t.formula)) for t in formula.terms))
