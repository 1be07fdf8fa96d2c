"""One subsystem with an FSM, built in memory (no model file), for the guard analysis.

The subsystem ``cs`` has an Input Buffer ``in/ib`` of dataType ``Signals``: boolean fields
``b0`` … ``b<n-1>``, a real ``v`` and an integer ``n``; primitive predicates, exclusions,
states (with the ``tc``/``ec`` of their basic behaviours) and transitions as given.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from earl_m2t.lift.conditions import resolve_subsystem
from earl_m2t.model.conditions import Condition, ConditionRole
from earl_m2t.model.datatypes import DataType, Field
from earl_m2t.model.elements import (
    BasicBehaviour,
    Buffer,
    EarlModel,
    Exclusion,
    Fsm,
    PrimitivePredicate,
    State,
    Subsystem,
    Transition,
)
from earl_m2t.model.location import Location

HERE = Location("memory.uml", 1)
SIGNALS = "Signals"


def _datatypes(booleans: int) -> dict[str, DataType]:
    kinds = {"Boolean": "boolean", "Real": "real", "Integer": "integer"}
    types = {name: DataType(name, name, "primitive", primitive=kind) for name, kind in kinds.items()}
    fields = [Field(f"b{i}", "Boolean", 1, 1, HERE) for i in range(booleans)]
    fields += [Field("v", "Real", 1, 1, HERE), Field("n", "Integer", 1, 1, HERE)]
    types[SIGNALS] = DataType(SIGNALS, SIGNALS, "struct", fields=tuple(fields))
    return types


def _condition(text: str | None, owner: str, role: ConditionRole) -> Condition | None:
    return None if text is None else Condition(text, "EARL", HERE, owner, role)


def build(
    predicates: Mapping[str, str | None],
    states: Mapping[str, tuple[str | None, str | None]],
    transitions: Iterable[tuple[str, str, str | None, int]],
    exclusions: Iterable[Iterable[str]] = (),
    booleans: int = 8,
) -> tuple[EarlModel, Subsystem]:
    """``predicates``: name (``x/pp``) → EARL body, or None for user code; ``states``: name →
    (tc, ec) of its behaviour ``name/bb``; ``transitions``: (source, target, guard, priority),
    a guard of None being absent; the first state is the initial one."""
    path = "a/a.cs"
    fsm_path = f"{path}.fsm"
    pps = tuple(
        PrimitivePredicate(name, f"{path}.{name}", _condition(body, f"{path}.{name}", ConditionRole.FUN),
                           "EARL" if body is not None else "C++", body or "return true;", HERE, "suffix")
        for name, body in predicates.items()
    )
    bbs = tuple(
        BasicBehaviour(f"{name}/bb", f"{path}.{name}/bb", _condition(tc, f"{path}.{name}/bb", ConditionRole.TC),
                       _condition(ec, f"{path}.{name}/bb", ConditionRole.EC), (), (), HERE, "suffix")
        for name, (tc, ec) in states.items()
    )
    fsm_states = tuple(State(name, f"{fsm_path}.{name}", (f"{name}/bb",), HERE) for name in states)
    trs = []
    for order, (source, target, guard, priority) in enumerate(transitions):
        name = f"{source},{target}/t"
        if any(t.name == name for t in trs):
            name = f"{source},{target}#{order}/t"
        trs.append(Transition(name, f"{fsm_path}.{name}", source, target, False, False,
                              _condition(guard, f"{fsm_path}.{name}", ConditionRole.IC), priority, order, HERE))
    fsm = Fsm("fsm", fsm_path, fsm_states, tuple(trs), (next(iter(states)),), HERE)
    buffer = Buffer("in/ib", f"{path}.in/ib", "in", SIGNALS, "in/ib", 0, HERE, "suffix")
    excl = tuple(Exclusion(f"x{i}", tuple(names), HERE) for i, names in enumerate(exclusions))
    sub = Subsystem("cs", path, "cs", "a/a", "Control", "_control", "cs", 0, (buffer,), (), (), fsm, bbs, (),
                    pps, excl, 1, HERE, "suffix")
    model = EarlModel("memory.uml", "papyrus", "memory", (), _datatypes(booleans))
    return model, resolve_subsystem(sub, model.datatypes)
