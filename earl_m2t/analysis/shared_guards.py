"""Guard analyses shared by subsystems whose guards read alike (B006, B007).

Models repeat subsystems: every joint controller of an arm, every agent of a fleet. Two
subsystems with the same states, transitions (priorities, relative order, condition texts),
terminal and error conditions, primitive predicates and exclusions, whose conditions name
buffers and memory of the same shape, get the same overlaps and gaps, witnesses included
(they are written with local names). So the SAT work runs once per distinct content and the
answers are mapped, by position, onto each subsystem that has it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from earl_m2t.analysis.guards import MAX_OVERLAPS_PER_STATE, GuardAnalysis
from earl_m2t.model.conditions import conditions_of
from earl_m2t.model.elements import Condition, EarlModel, Subsystem, Transition

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


class SharedGuards:
    """The guard findings of one subsystem, answered from any subsystem with the same signature."""

    def __init__(self, model: EarlModel, subsystem: Subsystem) -> None:
        assert subsystem.fsm is not None
        self.subsystem = subsystem
        self._transitions = subsystem.fsm.transitions
        key = ("guard-answers", signature(model, subsystem))
        answers = model.derived.get(key)
        if not isinstance(answers, _Answers):
            answers = model.derived[key] = _Answers(GuardAnalysis(model, subsystem))
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


def signature(model: EarlModel, subsystem: Subsystem) -> Signature:
    """Everything the guard analysis of a subsystem reads, with its own names and no locations.

    Buffers and memory count only when a condition could name them (their name or template
    occurs in a condition's text), and by the shape of their data type: the field names and the
    primitive kinds at their ends, which decide what a comparison or a boolean field means.
    """
    fsm = subsystem.fsm
    assert fsm is not None
    rank = {id(t): i for i, t in enumerate(sorted(fsm.transitions, key=lambda t: t.order))}
    texts = "\n".join(c.text for c in conditions_of(subsystem))
    shapes = model.derived.setdefault(("datatype-shapes",), {})
    assert isinstance(shapes, dict)

    def named(*names: str) -> bool:
        return any(_stem(name) in texts for name in names)

    return (
        tuple((s.name, s.behaviours) for s in fsm.states),
        tuple((t.source, t.source_foreign, t.priority, rank[id(t)], _text(t.condition)) for t in fsm.transitions),
        tuple((b.name, _text(b.tc), _text(b.ec)) for b in subsystem.behaviours),
        tuple((p.name, _text(p.fun)) for p in subsystem.predicates),
        tuple(e.predicates for e in subsystem.exclusions),
        tuple((b.name, b.template, b.direction, b.index, _shape(model, b.datatype, shapes, ()))
              for b in subsystem.buffers if named(b.name, b.template)),
        tuple((m.name, m.template, m.index, _shape(model, m.datatype, shapes, ()))
              for m in subsystem.memory if named(m.name, m.template)),
    )


def _shape(model: EarlModel, key: str, shapes: dict[str, object], visiting: tuple[str, ...]) -> object:
    """A data type as the guard analysis sees it: primitive kinds, and fields by name."""
    if key in shapes:
        return shapes[key]
    datatype = model.datatypes.get(key)
    if key in visiting:
        return ("cycle", key)
    if datatype is None:
        shape: object = ("unknown",)
    elif datatype.kind == "struct":
        shape = ("struct", tuple((f.name, f.lower, f.upper, _shape(model, f.type, shapes, (*visiting, key)))
                                 for f in datatype.fields))
    else:
        shape = (datatype.kind, datatype.primitive)
    if not visiting:
        shapes[key] = shape
    return shape


def _stem(name: str) -> str:
    return name.rpartition("/")[0] if "/" in name else name


def _text(condition: Condition | None) -> str | None:
    return None if condition is None else condition.text
