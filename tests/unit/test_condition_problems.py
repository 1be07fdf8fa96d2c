"""B005's answers shared between subsystems alike (earl_m2t.model.conditions): a condition's
unknown references are worked out once for a text and what the subsystem names, and each
subsystem gets them at its own condition's place; a subsystem that names other buffers,
memory or predicates gets answers of its own."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from earl_m2t.api import load  # noqa: E402
from earl_m2t.model.conditions import ConditionResolver, parse_condition  # noqa: E402
from earl_m2t.model.elements import Condition, EarlModel, Subsystem  # noqa: E402
from earl_m2t.model.location import Location  # noqa: E402

SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
TEXT = "newJointPos/pp and manipulatorCommand/ib.msg.nowhere > 1 and ghost/pp"


def _manipulator() -> tuple[EarlModel, Subsystem]:
    model = load(SAMPLE).model
    return model, next(s for s in model.subsystems if s.path == "manip/a.cs")


def _problems(model: EarlModel, sub: Subsystem, condition: Condition) -> list[tuple[str, Location]]:
    expr, problem = parse_condition(condition)
    assert expr is not None and problem is None
    return [(p.message, p.location) for p in ConditionResolver(model, sub).problems(expr, condition)]


def _condition(line: int) -> Condition:
    return Condition(TEXT, "", Location("m.uml", line, 0, f"id{line}"), "x", "ic")


def _answers(model: EarlModel) -> int:
    shared = model.derived.get("condition-problems")
    assert isinstance(shared, dict)
    return len(shared)


def test_a_twin_gets_the_answers_at_its_own_condition_from_one_walk() -> None:
    model, sub = _manipulator()
    first = _problems(model, sub, _condition(10))
    twin = dataclasses.replace(sub, path="twin/a.cs", agent="twin/a", block_id=sub.block_id + "-twin")
    second = _problems(model, twin, _condition(40))
    assert [m for m, _ in first] == ["'manipulatorCommand/ib.msg.nowhere' names no field of its dataType",
                                     "unknown primitive predicate 'ghost/pp'"]
    assert [m for m, _ in second] == [m for m, _ in first]
    assert [loc.line for _, loc in first] == [10, 10] and [loc.line for _, loc in second] == [40, 40]
    assert [loc.xmi_id for _, loc in second] == ["id40", "id40"]
    assert [loc.column for _, loc in second] == [loc.column for _, loc in first] != [0, 0]
    assert _answers(model) == 1


def test_a_subsystem_that_names_other_things_gets_answers_of_its_own() -> None:
    model, sub = _manipulator()
    _problems(model, sub, _condition(10))
    with_ghost = dataclasses.replace(sub, predicates=sub.predicates + (
        dataclasses.replace(sub.predicates[0], name="ghost/pp", path=f"{sub.path}.ghost/pp"),))
    assert [m for m, _ in _problems(model, with_ghost, _condition(10))] == [
        "'manipulatorCommand/ib.msg.nowhere' names no field of its dataType"]
    retyped = tuple(dataclasses.replace(b, datatype="Real") if b.name == "manipulatorCommand/ib" else b
                    for b in sub.inputs)
    assert "'manipulatorCommand/ib.msg.nowhere' names no field of its dataType" in [
        m for m, _ in _problems(model, dataclasses.replace(sub, inputs=retyped), _condition(10))]
    assert _answers(model) == 3


def test_a_changed_model_does_not_carry_the_answers_over() -> None:
    model, _ = _manipulator()
    model.derived["condition-problems"] = {"stale": ()}
    assert "condition-problems" not in dataclasses.replace(model, name="other").derived
