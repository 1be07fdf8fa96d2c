"""Exact analysis of an FSM's guards: overlapping transitions (B006) and gaps (B007).

Semantics (earl-metamodel.md §2): a state's basic behaviour returns when its error condition
``ec`` or its terminal condition ``tc`` holds; ``selectState`` then takes, among the
transitions leaving the state whose initial condition ``ic`` holds, the one of highest
priority, ties broken by model order. A missing guard is ``TRUE``, a missing ``tc``/``ec``
``FALSE``. So

* two transitions of equal priority *p* are in conflict (B006) when
  ``(tc ∨ ec) ∧ ic1 ∧ ic2 ∧ ¬(every ic of priority > p) ∧ exclusions`` is satisfiable:
  only then does model order, rather than the conditions, decide;
* a state has a gap (B007) when ``tc ∧ ¬ec ∧ ¬(ic1 ∨ … ∨ icn) ∧ exclusions`` is
  satisfiable: the behaviour ended normally and no transition is enabled. Ending by the error
  condition is not a gap (the designer decides where errors lead); a ``tc`` that is
  ``FALSE`` never ends the behaviour, so such a state has no gap.

Satisfiability is decided by a SAT solver over the atoms (:mod:`earl_m2t.analysis.cnf`),
with the model's exclusions (at most one of the predicates holds) and, for comparisons of one
field with constants, the combinations of truth values some value of the field gives. Each
finding has a counterexample: a conjunction of the predicates and terms written in the
conditions, shortened until no literal can be dropped (every assignment that agrees with it
and respects the constraints satisfies the formula).
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from itertools import combinations

from earl_m2t.analysis.cnf import Cnf
from earl_m2t.analysis.expand import Expander, Formula, Term
from earl_m2t.analysis.in_error import with_error
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import BasicBehaviour, State, Subsystem, Transition
from earl_m2t.predicate import And, Compare, Const, Expr, FieldRef, Not, Number, Or

MAX_OVERLAPS_PER_STATE = 20  # B006 reports this many pairs of one state, then says it stopped


@dataclass(frozen=True, slots=True)
class Overlap:
    """Two transitions of equal priority out of one state that can be enabled together (B006)."""

    state: State
    first: Transition  # the one model order picks
    second: Transition
    witness: str


@dataclass(frozen=True, slots=True)
class Gap:
    """A state whose behaviour can terminate with no outgoing transition enabled (B007)."""

    state: State
    behaviour: BasicBehaviour
    transitions: tuple[Transition, ...]
    witness: str


class GuardAnalysis:
    """The guards, terminal and error conditions of one subsystem, encoded once."""

    def __init__(self, subsystem: Subsystem, datatypes: Mapping[str, DataType]) -> None:
        self.subsystem = subsystem
        self.expander = Expander(subsystem, datatypes)
        self.cnf = Cnf()
        self._formulas: dict[str, tuple[Formula, int] | None] = {}
        fsm = subsystem.fsm
        errors = {bb.name: self.expander.condition(bb.ec, missing=False) for bb in subsystem.behaviours}
        states = {s.name: s.behaviours[0] for s in fsm.states if len(s.behaviours) == 1} if fsm is not None else {}
        for tr in fsm.transitions if fsm is not None else ():
            ec = errors.get(states.get(tr.source, ""))
            self._add(tr.path, with_error(self.expander.condition(tr.condition, missing=True), ec))
        for bb in subsystem.behaviours:
            self._add(f"{bb.path}#tc", with_error(self.expander.condition(bb.tc, missing=False), errors[bb.name]))
            self._add(f"{bb.path}#ec", errors[bb.name])
        self.background = self._exclusions()
        self.background += self._comparisons()

    # -- setup -------------------------------------------------------------------------

    def _add(self, key: str, formula: Formula | None) -> None:
        self._formulas[key] = None if formula is None else (formula, self.cnf.literal(formula.expr))

    def _exclusions(self) -> list[int]:
        """At most one predicate of each declared exclusion holds."""
        literals = []
        for exclusion in self.subsystem.exclusions:
            bodies = [self.expander.predicate(name) for name in exclusion.predicates]
            if any(body is None for body in bodies):
                continue  # an unknown predicate: B005 reports the exclusion
            for a, b in combinations(bodies, 2):
                assert a is not None and b is not None
                literals.append(self.cnf.literal(Not(And((a, b)))))
        return literals

    def _comparisons(self) -> list[int]:
        """Comparisons of one field with constants take only the truth values some value gives."""
        groups: dict[FieldRef, list[Compare]] = {}
        for atom in list(self.cnf.atoms):
            if isinstance(atom, Compare) and isinstance(atom.left, FieldRef) and isinstance(atom.right, Number):
                groups.setdefault(atom.left, []).append(atom)
        literals = []
        for ref, compares in groups.items():
            integral = self.expander.field_kind(ref) == "integer"
            rows: dict[tuple[bool, ...], None] = {}
            for value in _sample_values(sorted({c.right.value for c in compares}), integral):  # type: ignore[union-attr]
                rows[tuple(_holds(c, value) for c in compares)] = None
            options: list[Expr] = [And(tuple(c if v else Not(c) for c, v in zip(compares, row))) for row in rows]
            constraint: Expr = Or(tuple(options)) if len(options) > 1 else (options[0] if options else Const(False))
            literals.append(self.cnf.literal(constraint))
        return literals

    # -- queries -----------------------------------------------------------------------

    def outgoing(self, state: State) -> tuple[Transition, ...]:
        fsm = self.subsystem.fsm
        assert fsm is not None
        return tuple(t for t in fsm.transitions if t.source == state.name and not t.source_foreign)

    def behaviour_of(self, state: State) -> BasicBehaviour | None:
        return self.subsystem.behaviour(state.behaviours[0]) if len(state.behaviours) == 1 else None

    def overlaps(self, state: State, limit: int = MAX_OVERLAPS_PER_STATE) -> Iterator[Overlap]:
        """The overlapping pairs leaving ``state``, at most ``limit`` of them: with n transitions
        of one priority there are n(n-1)/2 pairs, so a state holding hundreds of them would
        cost hundreds of thousands of solver calls and findings."""
        bb = self.behaviour_of(state)
        if bb is None:
            return
        tc, ec = self._formulas[f"{bb.path}#tc"], self._formulas[f"{bb.path}#ec"]
        if tc is None or ec is None:
            return
        ended = self.cnf.literal(Or((tc[0].expr, ec[0].expr)))
        transitions = sorted(self.outgoing(state), key=lambda t: t.order)
        for first, second in combinations(transitions, 2):
            if first.priority != second.priority:
                continue
            higher = [t for t in transitions if t.priority > first.priority]
            parts = [self._formulas[t.path] for t in (first, second, *higher)]
            if any(part is None for part in parts):
                continue
            known = [p for p in parts if p is not None]
            query = [known[0][1], known[1][1], *(-p[1] for p in known[2:]), ended]
            witness = self.witness(query, [*known, tc, ec])
            if witness is not None:
                yield Overlap(state, first, second, witness)
                limit -= 1
                if limit == 0:
                    return

    def gap(self, state: State) -> Gap | None:
        bb = self.behaviour_of(state)
        if bb is None:
            return None
        transitions = tuple(sorted(self.outgoing(state), key=lambda t: t.order))
        parts = [self._formulas[f"{bb.path}#tc"], self._formulas[f"{bb.path}#ec"],
                 *(self._formulas[t.path] for t in transitions)]
        if any(part is None for part in parts):
            return None
        known = [p for p in parts if p is not None]
        query = [known[0][1], -known[1][1], *(-p[1] for p in known[2:])]
        witness = self.witness(query, known)
        return None if witness is None else Gap(state, bb, transitions, witness)

    def witness(self, query: Sequence[int], formulas: Sequence[tuple[Formula, int]]) -> str | None:
        """A short counterexample for the conjunction ``query``, or None if it is unsatisfiable."""
        model = self.cnf.solve([*self.background, *query])
        if model is None:
            return None
        terms: dict[str, Term] = {}
        for formula, _ in formulas:
            for term in formula.terms:
                terms.setdefault(term.label, term)
        cube = []  # (label, value in the model, literal that holds)
        for term in terms.values():
            lit = self.cnf.literal(term.formula)
            cube.append((term.label, lit in model, lit if lit in model else -lit))
        negated = [-q for q in query]
        for item in reversed(list(cube)):
            trial = [c for c in cube if c is not item]
            if self.cnf.solve([*self.background, *(lit for _, _, lit in trial)], negated) is None:
                cube = trial
        return describe([(label, value) for label, value, _ in cube])


def describe(cube: Sequence[tuple[str, bool]]) -> str:
    """``a ∧ b ∧ ¬c``: true terms first, then false ones, each in the order given."""
    if not cube:
        return "TRUE"
    shown = [label for label, value in cube if value]
    shown += ["¬" + (f"({label})" if " " in label else label) for label, value in cube if not value]
    return " ∧ ".join(shown)


def _holds(compare: Compare, value: float) -> bool:
    right = compare.right
    assert isinstance(right, Number)
    return {"<": value < right.value, "<=": value <= right.value, ">": value > right.value,
            ">=": value >= right.value, "==": value == right.value, "!=": value != right.value}[compare.op]


def _sample_values(constants: list[float], integral: bool) -> list[float]:
    """One value of each region the constants cut the number line into (points and gaps)."""
    finite = [c for c in constants if math.isfinite(c)]
    if not finite:
        return [0.0, *constants]
    values: list[float] = [*constants]
    if integral:
        values = [c for c in constants if float(c).is_integer()]
        values.append(math.ceil(finite[0]) - 1.0)
        values.append(math.floor(finite[-1]) + 1.0)
        for low, high in zip(finite, finite[1:]):
            between = math.floor(low) + 1.0
            if between < high:
                values.append(between)
    else:
        values.append(finite[0] - 1.0)
        values.append(finite[-1] + 1.0)
        values.extend((low + high) / 2 for low, high in zip(finite, finite[1:]))
    return values
