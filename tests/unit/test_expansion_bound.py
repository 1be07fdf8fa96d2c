"""Replications are written out only within a bound: a replication rebinding the variable of
one it is in, or an expansion past ``MAX_EXPANSION`` nodes, is refused before anything is
expanded (nested quantifiers grow as the product of their counts)."""

from __future__ import annotations

import pytest

from earl_m2t.model.limits import MAX_EXPANSION
from earl_m2t.predicate.ast import Or, PredicateRef, Replicated
from earl_m2t.predicate.transform import ExpansionRefused, expand_replicated


def nested(vars_: str) -> Replicated:
    """``any <v1>: any <v2>: … a<v1><v2>…/pp`` over the variables in ``vars_``."""
    expr: Replicated | PredicateRef = PredicateRef("a" + vars_ + "/pp")
    for var in reversed(vars_):
        expr = Replicated("or", expr, var)
    assert isinstance(expr, Replicated)
    return expr


def test_a_replication_within_the_bound_is_written_out() -> None:
    expanded = expand_replicated(nested("K"), lambda node: 6)
    assert isinstance(expanded, Or) and len(expanded.operands) == 6


def test_nested_replications_past_the_bound_are_refused_before_expanding() -> None:
    with pytest.raises(ExpansionRefused, match=f"more than {MAX_EXPANSION} terms"):
        expand_replicated(nested("KJ"), lambda node: 200)  # 200 × 200 instances


def test_a_replication_over_the_variable_of_one_it_is_in_is_refused() -> None:
    with pytest.raises(ExpansionRefused, match="inside another over K"):
        expand_replicated(nested("KK"), lambda node: 2)


def test_a_long_expression_without_replications_is_not_an_expansion() -> None:
    long = Or(tuple(PredicateRef(f"p{k}/pp") for k in range(MAX_EXPANSION + 1)))
    assert expand_replicated(long, lambda node: 6) is long
