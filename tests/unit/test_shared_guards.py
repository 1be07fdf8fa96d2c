"""Guard answers shared between subsystems of the same content (B006, B007): a twin of a
subsystem gets the same witnesses on its own transitions, from one analysis; a twin that
differs in a guard, a priority or a buffer's data type gets an analysis of its own."""

from __future__ import annotations

import dataclasses

from earl_m2t.analysis.guards import GuardAnalysis
from earl_m2t.analysis.shared_guards import SharedGuards, model_guards
from earl_m2t.api import load
from earl_m2t.lift.conditions import resolve_subsystem
from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import EarlModel, Subsystem, Transition
from tests.support.paths import SAMPLE


def _manipulator() -> tuple[EarlModel, Subsystem]:
    """The sample's manip/a.cs without its exclusion: idle,jointMove/t and idle,operationalMove/t overlap."""
    model = load(SAMPLE).model
    sub = next(s for s in model.subsystems if s.path == "manip/a.cs")
    return model, dataclasses.replace(sub, exclusions=())


def _twin(model: EarlModel, sub: Subsystem, **transition_changes: object) -> Subsystem:
    """A copy of ``sub`` under another path, resolved as the lift resolves it;
    ``transition_changes`` apply to idle,jointMove/t."""
    assert sub.fsm is not None

    def copy(t: Transition) -> Transition:
        changes = transition_changes if t.name == "idle,jointMove/t" else {}
        return dataclasses.replace(t, path=t.path.replace("manip/a", "twin/a"), **changes)  # type: ignore[arg-type]

    fsm = dataclasses.replace(sub.fsm, transitions=tuple(copy(t) for t in sub.fsm.transitions))
    twin = dataclasses.replace(sub, path="twin/a.cs", agent="twin/a", block_id=sub.block_id + "-twin", fsm=fsm)
    return resolve_subsystem(twin, model.datatypes)


def _overlaps(model: EarlModel, sub: Subsystem) -> list[tuple[Transition, Transition, str]]:
    guards = SharedGuards(model_guards(model), sub)
    assert sub.fsm is not None
    return [(o.first, o.second, o.witness) for i in range(len(sub.fsm.states)) for o in guards.overlaps(i)]


def _analyses(model: EarlModel) -> int:
    return len(model_guards(model).answers)


def test_a_twin_gets_the_same_witnesses_on_its_own_transitions_from_one_analysis() -> None:
    model, sub = _manipulator()
    twin = _twin(model, sub)
    original, copied = _overlaps(model, sub), _overlaps(model, twin)
    assert [w for _, _, w in original] == ["newJointPos ∧ newOperationalPos ∧ ¬emergencyStop ∧ ¬inError()"]
    assert [w for _, _, w in copied] == [w for _, _, w in original]
    assert twin.fsm is not None
    assert all(first in twin.fsm.transitions and second in twin.fsm.transitions for first, second, _ in copied)
    assert [first.path for first, _, _ in copied] == ["twin/a.cs.fsm.idle,jointMove/t"]
    assert _analyses(model) == 1


def test_answers_equal_those_of_an_analysis_of_its_own() -> None:
    model, sub = _manipulator()
    twin = _twin(model, sub)
    _overlaps(model, sub)
    assert twin.fsm is not None
    alone = GuardAnalysis(twin, model.datatypes)
    expected = [(o.first, o.second, o.witness) for s in twin.fsm.states for o in alone.overlaps(s)]
    assert _overlaps(model, twin) == expected
    guards = SharedGuards(model_guards(model), twin)
    for position, state in enumerate(twin.fsm.states):
        own, shared = alone.gap(state), guards.gap(position)
        assert (own is None) == (shared is None)
        if own is not None and shared is not None:
            assert (own.transitions, own.witness) == (shared.transitions, shared.witness)


def test_a_different_guard_or_priority_is_analysed_on_its_own() -> None:
    model, sub = _manipulator()
    _overlaps(model, sub)
    condition = next(t.condition for t in sub.fsm.transitions if t.name == "idle,jointMove/t")  # type: ignore[union-attr]
    assert isinstance(condition, Condition)
    exclusive = dataclasses.replace(condition, text=condition.text + " ∧ ¬newOperationalPos/pp.fun")
    assert _overlaps(model, _twin(model, sub, condition=exclusive)) == []
    assert _overlaps(model, _twin(model, sub, priority=5)) == []
    assert _analyses(model) == 3


def test_a_buffer_of_another_shape_is_analysed_on_its_own() -> None:
    model, sub = _manipulator()
    _overlaps(model, sub)
    retyped = tuple(dataclasses.replace(b, datatype="Real") if b.name == "manipulatorCommand/ib" else b
                    for b in sub.inputs)
    assert any(b.datatype == "Real" for b in retyped)
    _overlaps(model, resolve_subsystem(dataclasses.replace(_twin(model, sub), inputs=retyped), model.datatypes))
    assert _analyses(model) == 2
