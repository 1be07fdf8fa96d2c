"""Conditions as the lifted model holds them: the text as written, its parsed expression, the
expression with its replications written out, and what is wrong with it.

The lift parses and resolves every condition once (:mod:`earl_m2t.lift.conditions`); rules
report the problems, and generators, analyses and verification read the expressions.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from earl_m2t.model.location import Location
from earl_m2t.predicate.ast import Expr


class ConditionRole(StrEnum):
    """What a condition is to the element that owns it."""

    IC = "ic"  # a transition's guard (initial condition of the next state)
    TC = "tc"  # a basic behaviour's terminal condition
    EC = "ec"  # a basic behaviour's error condition
    FUN = "fun"  # a primitive predicate's body
    EXCLUSION = "exclusion"  # an exclusion written as text

    @property
    def description(self) -> str:
        return _DESCRIPTIONS[self]


_DESCRIPTIONS = {
    ConditionRole.IC: "initial condition",
    ConditionRole.TC: "terminal condition",
    ConditionRole.EC: "error condition",
    ConditionRole.FUN: "primitive predicate body",
    ConditionRole.EXCLUSION: "exclusion",
}


class ProblemKind(StrEnum):
    SYNTAX = "syntax"  # the text is no expression of the predicate language
    REFERENCE = "reference"  # it names what its subsystem does not have, or uses a value as it cannot be


@dataclass(frozen=True, slots=True)
class ConditionProblem:
    kind: ProblemKind
    message: str
    location: Location  # where in the model file, the column within the condition's text


@dataclass(frozen=True, slots=True)
class Condition:
    """A predicate as written in the model (``text``), where it was written, and what the lift
    made of it in its subsystem."""

    text: str
    language: str
    location: Location
    owner: str  # path of the element owning it (transition, behaviour, predicate)
    role: ConditionRole
    expr: Expr | None = None  # the parsed text; None when it does not parse
    expanded: Expr | None = None  # ``expr`` with each replication (``any K: …``) written out for its instances
    problems: tuple[ConditionProblem, ...] = ()  # a SYNTAX problem, or the REFERENCE problems of ``expr``

    @property
    def syntax_problem(self) -> ConditionProblem | None:
        return next((p for p in self.problems if p.kind is ProblemKind.SYNTAX), None)

    @property
    def resolved(self) -> Expr | None:
        """The expanded expression when everything in it resolved, else None."""
        return self.expanded if not self.problems else None
