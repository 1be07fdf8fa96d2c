"""What one iteration of a subsystem in a state can decide, with predicates as free booleans.

Every atom of the expanded conditions (a boolean field, a comparison, a ``newData`` term, a
predicate written in user code) is a free boolean, constrained only by the model's exclusions.
For a state, each assignment of the atoms its behaviour's tc/ec and its outgoing guards use
gives an *outcome*: the behaviour goes on, or it ends and a transition (by priority, then model
order) or none is taken. The distinct outcomes, each with the first assignment found for it,
are all the Promela process needs: the data itself never enters the state space.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations, product

from earl_m2t.analysis.expand import Expander, Formula
from earl_m2t.analysis.in_error import with_error
from earl_m2t.model.elements import EarlModel, State, Subsystem, Transition
from earl_m2t.model.naming import split
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

MAX_ATOMS = 16  # 65536 assignments per state; above this every outcome is taken as possible


@dataclass(frozen=True, slots=True)
class Outcome:
    ended: bool  # tc or ec held
    transition: Transition | None  # the transition taken, None when the state stays
    witness: tuple[tuple[str, bool], ...]  # the predicates and terms written, and their values
    observed: tuple[bool, ...] = ()  # the values of the predicates an LTL property reads


@dataclass(frozen=True, slots=True)
class StateOutcomes:
    state: State
    outcomes: tuple[Outcome, ...]
    never_ends_by_design: bool  # tc and ec are FALSE once expanded: a behaviour meant to run on
    exact: bool  # False when the conditions had too many atoms or could not be analysed


def state_outcomes(model: EarlModel, subsystem: Subsystem, observed: tuple[str, ...] = (),
                   built_ins: tuple[BuiltInPredicate, ...] = ()) -> tuple[StateOutcomes, ...]:
    """The outcomes of each state; with ``observed`` primitive predicates (read by LTL
    properties), outcomes that differ only in those predicates' values are told apart, and so
    are they by the values of ``built_ins`` (``leaving()``, set by a switch), observed after them."""
    if subsystem.fsm is None:
        return ()
    expander = Expander(subsystem, model.datatypes)
    exclusions = _exclusions(expander, subsystem)
    watched = tuple((split(name)[0], expander.predicate(name) or PredicateRef(name)) for name in observed) + tuple(
        (f"{name}()", BuiltIn(name)) for name in built_ins)
    return tuple(_one_state(expander, subsystem, state, exclusions, watched) for state in subsystem.fsm.states)


def _exclusions(expander: Expander, subsystem: Subsystem) -> list[Expr]:
    constraints: list[Expr] = []
    for exclusion in subsystem.exclusions:
        bodies = [expander.predicate(name) for name in exclusion.predicates]
        known = [b for b in bodies if b is not None]
        constraints.extend(Not(And((a, b))) for a, b in combinations(known, 2))
    return constraints


def _one_state(expander: Expander, subsystem: Subsystem, state: State, exclusions: list[Expr],
               watched: tuple[tuple[str, Expr], ...]) -> StateOutcomes:
    fsm = subsystem.fsm
    assert fsm is not None
    bb = subsystem.behaviour(state.behaviours[0]) if len(state.behaviours) == 1 else None
    tc = expander.condition(bb.tc if bb else None, missing=False)
    ec = expander.condition(bb.ec if bb else None, missing=False)
    outgoing = sorted(
        (t for t in fsm.transitions if t.source == state.name and not t.source_foreign and not t.target_foreign),
        key=lambda t: (-t.priority, t.order),
    )
    guards = [expander.condition(t.condition, missing=True) for t in outgoing]
    tc, guards = with_error(tc, ec), [with_error(g, ec) for g in guards]  # inError() is ec's value
    formulas = [tc, ec, *guards]
    by_design = tc is not None and ec is not None and not _atoms(tc.expr) and not _atoms(ec.expr) \
        and not _value(tc.expr, {}) and not _value(ec.expr, {})
    if any(f is None for f in formulas):
        return StateOutcomes(state, _every_outcome(outgoing, len(watched)), by_design, exact=False)
    known = [f for f in formulas if f is not None]
    atoms = sorted({a for f in known for a in _atoms(f.expr)} | {a for c in exclusions for a in _atoms(c)}
                   | {a for _, expr in watched for a in _atoms(expr)}, key=format_predicate)
    relevant = [c for c in exclusions if _atoms(c) <= set(atoms)]
    if len(atoms) > MAX_ATOMS:
        return StateOutcomes(state, _every_outcome(outgoing, len(watched)), by_design, exact=False)
    found: dict[tuple[bool, str, tuple[bool, ...]], Outcome] = {}
    terms = {t.label: t.formula for f in known for t in f.terms}
    for label, expr in watched:
        terms.setdefault(label, expr)
    for values in product((False, True), repeat=len(atoms)):
        env = dict(zip(atoms, values))
        if not all(_value(c, env) for c in relevant):
            continue
        assert tc is not None and ec is not None
        ended = _value(tc.expr, env) or _value(ec.expr, env)
        taken = None
        if ended:
            taken = next((t for t, g in zip(outgoing, guards) if g is not None and _value(g.expr, env)), None)
        seen = tuple(_value(expr, env) for _, expr in watched)
        key = (ended, taken.path if taken else "", seen)
        if key not in found:
            witness = tuple((label, _value(expr, env)) for label, expr in terms.items())
            found[key] = Outcome(ended, taken, witness, seen)
    ordered = sorted(found.values(),
                     key=lambda o: (o.ended, o.transition.order if o.transition else -1, o.observed))
    return StateOutcomes(state, tuple(ordered), by_design, exact=True)


def _every_outcome(outgoing: list[Transition], watched: int) -> tuple[Outcome, ...]:
    """Every outcome, with every combination of the observed predicates' values."""
    decisions: list[tuple[bool, Transition | None]] = [(False, None), (True, None), *((True, t) for t in outgoing)]
    return tuple(Outcome(ended, t, (), seen)
                 for ended, t in decisions for seen in product((False, True), repeat=watched))


def _atoms(expr: Expr) -> set[Expr]:
    if isinstance(expr, Const):
        return set()
    if isinstance(expr, Not):
        return _atoms(expr.operand)
    if isinstance(expr, (And, Or)):
        return set().union(*(_atoms(o) for o in expr.operands))
    return {expr}


def _value(expr: Expr, env: dict[Expr, bool]) -> bool:
    """The truth value of ``expr`` under the assignment ``env`` (an atom without a value is false)."""
    return evaluate_atoms(expr, lambda atom: env.get(atom, False))


def describe(formula: Formula | None) -> str:
    return "" if formula is None else format_predicate(formula.expr)
