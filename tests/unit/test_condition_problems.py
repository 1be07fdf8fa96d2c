"""The lift resolves a condition once per text and scope (earl_m2t.lift.conditions):
subsystems alike in every name share one scope, and each gets the answers at its own
condition's place; a subsystem that names other buffers, memory or predicates has a scope,
and answers, of its own."""

from __future__ import annotations

import dataclasses

from earl_m2t.api import load
from earl_m2t.lift.conditions import ConditionLifter
from earl_m2t.model.conditions import Condition, ConditionRole, ProblemKind
from earl_m2t.model.elements import EarlModel, Subsystem
from earl_m2t.model.location import Location
from earl_m2t.model.scope import Scope
from tests.support.paths import SAMPLE

TEXT = "newJointPos/pp and manipulatorCommand/ib.msg.nowhere > 1 and ghost/pp"


def _manipulator() -> tuple[EarlModel, Subsystem]:
    model = load(SAMPLE).model
    return model, next(s for s in model.subsystems if s.path == "manip/a.cs")


def _scope(lifter: ConditionLifter, sub: Subsystem) -> Scope:
    return lifter.scope(sub.buffers, sub.memory, sub.predicates)


def _problems(lifter: ConditionLifter, scope: Scope, line: int) -> list[tuple[str, Location]]:
    condition = lifter.resolve(Condition(TEXT, "", Location("m.uml", line, 0, f"id{line}"), "x", ConditionRole.IC),
                               scope)
    assert condition is not None and condition.expr is not None
    assert all(p.kind is ProblemKind.REFERENCE for p in condition.problems)
    return [(p.message, p.location) for p in condition.problems]


def test_a_twin_shares_the_scope_and_gets_the_answers_at_its_own_condition() -> None:
    model, sub = _manipulator()
    lifter = ConditionLifter(model.datatypes)
    twin = dataclasses.replace(sub, path="twin/a.cs", agent="twin/a", block_id=sub.block_id + "-twin")
    scope = _scope(lifter, sub)
    assert _scope(lifter, twin) is scope
    first, second = _problems(lifter, scope, 10), _problems(lifter, scope, 40)
    assert [m for m, _ in first] == ["'manipulatorCommand/ib.msg.nowhere' names no field of its dataType",
                                     "unknown primitive predicate 'ghost/pp'"]
    assert [m for m, _ in second] == [m for m, _ in first]
    assert [loc.line for _, loc in first] == [10, 10] and [loc.line for _, loc in second] == [40, 40]
    assert [loc.xmi_id for _, loc in second] == ["id40", "id40"]
    assert [loc.column for _, loc in second] == [loc.column for _, loc in first] != [0, 0]


def test_a_subsystem_that_names_other_things_gets_a_scope_and_answers_of_its_own() -> None:
    model, sub = _manipulator()
    lifter = ConditionLifter(model.datatypes)
    scope = _scope(lifter, sub)
    ghost = sub.predicates + (dataclasses.replace(sub.predicates[0], name="ghost/pp", path=f"{sub.path}.ghost/pp"),)
    with_ghost = lifter.scope(sub.buffers, sub.memory, ghost)
    assert with_ghost is not scope
    assert [m for m, _ in _problems(lifter, with_ghost, 10)] == [
        "'manipulatorCommand/ib.msg.nowhere' names no field of its dataType"]
    retyped = tuple(dataclasses.replace(b, datatype="Real") if b.name == "manipulatorCommand/ib" else b
                    for b in sub.buffers)
    other = lifter.scope(retyped, sub.memory, sub.predicates)
    assert other is not scope
    assert "'manipulatorCommand/ib.msg.nowhere' names no field of its dataType" in [
        m for m, _ in _problems(lifter, other, 10)]


def test_the_lifted_model_holds_each_condition_resolved() -> None:
    model, sub = _manipulator()
    assert sub.scope is not None
    conditions = list(sub.conditions())
    assert conditions and all(c.expr is not None and c.expanded is not None and not c.problems for c in conditions)
    assert all(s.scope is not None for s in model.subsystems)
