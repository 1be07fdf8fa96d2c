"""Guard analyses shared by subsystems whose guards read alike (B006, B007).

Models repeat subsystems: every joint controller of an arm, every agent of a fleet. Two
subsystems with the same states, transitions (priorities, relative order, condition texts),
terminal and error conditions, primitive predicates and exclusions, whose conditions name
buffers and memory of the same shape, get the same overlaps and gaps, witnesses included
(they are written with local names). So the SAT work runs once per distinct content and the
answers are mapped, by position, onto each subsystem that has it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from earl_m2t.analysis.guards import MAX_OVERLAPS_PER_STATE, GuardAnalysis
from earl_m2t.model.conditions import Condition
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import EarlModel, Subsystem, Transition
from earl_m2t.model.memo import PerModel
from earl_m2t.model.naming import stem

Signature = tuple[object, ...]


@dataclass(frozen=True, slots=True)
class StateOverlap:
    first: Transition
    second: Transition
    witness: str


@dataclass(frozen=True, slots=True)
class StateGap:
    transitions: tuple[Transition, ...]
    witness: str


@dataclass
class _Answers:
    """What one analysed subsystem found, by state and transition position."""

    analysis: GuardAnalysis
    overlaps: dict[int, tuple[tuple[int, int, str], ...]] = field(default_factory=dict)
    gaps: dict[int, tuple[tuple[int, ...], str] | None] = field(default_factory=dict)


@dataclass
class ModelGuards:
    """The guard analyses of one model: one per distinct signature, one view per subsystem block."""

    datatypes: Mapping[str, DataType]
    answers: dict[Signature, _Answers] = field(default_factory=dict)
    by_block: dict[str, SharedGuards] = field(default_factory=dict)
    shapes: dict[str, object] = field(default_factory=dict)  # _shape of each dataType


_MODEL_GUARDS = PerModel(lambda model: ModelGuards(model.datatypes))


def model_guards(model: EarlModel) -> ModelGuards:
    return _MODEL_GUARDS(model)


def shared_guards(model: EarlModel, subsystem: Subsystem) -> SharedGuards:
    """The guard findings of a subsystem (with an FSM), analysed once per model and signature."""
    guards = model_guards(model)
    found = guards.by_block.get(subsystem.block_id)
    if found is None:
        found = guards.by_block[subsystem.block_id] = SharedGuards(guards, subsystem)
    return found


class SharedGuards:
    """The guard findings of one subsystem, answered from any subsystem with the same signature."""

    def __init__(self, guards: ModelGuards, subsystem: Subsystem) -> None:
        assert subsystem.fsm is not None
        self.subsystem = subsystem
        self._transitions = subsystem.fsm.transitions
        key = signature(guards, subsystem)
        answers = guards.answers.get(key)
        if answers is None:
            answers = guards.answers[key] = _Answers(GuardAnalysis(subsystem, guards.datatypes))
        self._answers = answers

    def overlaps(self, position: int) -> tuple[StateOverlap, ...]:
        """At most MAX_OVERLAPS_PER_STATE overlapping pairs leaving the state at ``position``."""
        answers = self._answers
        if position not in answers.overlaps:
            analysed = answers.analysis.subsystem.fsm
            assert analysed is not None
            where = {id(t): i for i, t in enumerate(analysed.transitions)}
            answers.overlaps[position] = tuple(
                (where[id(o.first)], where[id(o.second)], o.witness)
                for o in answers.analysis.overlaps(analysed.states[position], MAX_OVERLAPS_PER_STATE))
        return tuple(StateOverlap(self._transitions[a], self._transitions[b], witness)
                     for a, b, witness in answers.overlaps[position])

    def gap(self, position: int) -> StateGap | None:
        """How the behaviour of the state at ``position`` can end with no transition enabled."""
        answers = self._answers
        if position not in answers.gaps:
            analysed = answers.analysis.subsystem.fsm
            assert analysed is not None
            where = {id(t): i for i, t in enumerate(analysed.transitions)}
            found = answers.analysis.gap(analysed.states[position])
            answers.gaps[position] = None if found is None else (
                tuple(where[id(t)] for t in found.transitions), found.witness)
        answer = answers.gaps[position]
        if answer is None:
            return None
        return StateGap(tuple(self._transitions[i] for i in answer[0]), answer[1])


def signature(guards: ModelGuards, subsystem: Subsystem) -> Signature:
    """Everything the guard analysis of a subsystem reads, with its own names and no locations.

    Buffers and memory count only when a condition could name them (their name or template
    occurs in a condition's text), and by the shape of their data type: the field names and the
    primitive kinds at their ends, which decide what a comparison or a boolean field means.
    """
    fsm = subsystem.fsm
    assert fsm is not None
    rank = {id(t): i for i, t in enumerate(sorted(fsm.transitions, key=lambda t: t.order))}
    texts = "\n".join(c.text for c in subsystem.conditions())

    def named(*names: str) -> bool:
        return any(stem(name) in texts for name in names)

    return (
        tuple((s.name, s.behaviours) for s in fsm.states),
        tuple((t.source, t.source_foreign, t.priority, rank[id(t)], _text(t.condition)) for t in fsm.transitions),
        tuple((b.name, _text(b.tc), _text(b.ec)) for b in subsystem.behaviours),
        tuple((p.name, _text(p.fun)) for p in subsystem.predicates),
        tuple(e.predicates for e in subsystem.exclusions),
        tuple((b.name, b.template, b.direction, b.index, _shape(guards, b.datatype, ()))
              for b in subsystem.buffers if named(b.name, b.template)),
        tuple((m.name, m.template, m.index, _shape(guards, m.datatype, ()))
              for m in subsystem.memory if named(m.name, m.template)),
    )


def _shape(guards: ModelGuards, key: str, visiting: tuple[str, ...]) -> object:
    """A data type as the guard analysis sees it: primitive kinds, and fields by name."""
    shapes = guards.shapes
    if key in shapes:
        return shapes[key]
    datatype = guards.datatypes.get(key)
    if key in visiting:
        return ("cycle", key)
    if datatype is None:
        shape: object = ("unknown",)
    elif datatype.kind == "struct":
        shape = ("struct", tuple((f.name, f.lower, f.upper, _shape(guards, f.type, (*visiting, key)))
                                 for f in datatype.fields))
    else:
        shape = (datatype.kind, datatype.primitive)
    if not visiting:
        shapes[key] = shape
    return shape


def _text(condition: Condition | None) -> str | None:
    return None if condition is None else condition.text
