"""Two FABRIC subsystem definitions compared element by element, as FABRIC's own parser
(``parseSubsystemXml``) reads them: buffers, buffer groups, predicates, behaviours, states with
their next states and buffer group attributes, the initial state and ``<simulation>``.
Conditions are compared as logic (every assignment of their atoms), not as text; behaviours
by name, not by their order."""

from __future__ import annotations

import itertools
from typing import Any

from earl_m2t.fabric.conditions import ConditionError, parse_fabric_condition
from earl_m2t.predicate import And, BuiltIn, Const, Expr, Not, Or

GROUP_ATTRIBUTES = ("buffer_group_name", "buffer_group_min_period", "buffer_group_min_period_sim",
                    "buffer_group_first_timeout", "buffer_group_next_timeout", "buffer_group_first_timeout_sim",
                    "buffer_group_used_time")
SIMULATION = ("use_ros_sim_clock", "use_sim_clock", "trigger_gazebo")
MAX_ATOMS = 20


def differences(original: Any, regenerated: Any) -> list[str]:
    """What differs between two parsed specs (FABRIC's SubsystemDefinition), one line each."""
    found: list[str] = []

    def same(what: str, a: Any, b: Any) -> None:
        if a != b:
            found.append(f"{what}: {a!r} != {b!r}")

    for kind in ("buffers_in", "buffers_out"):
        same(kind, [_buffer(b) for b in getattr(original, kind)], [_buffer(b) for b in getattr(regenerated, kind)])
    same("buffer_groups", [(g.name, g.obligatory, g.optional) for g in original.buffer_groups],
         [(g.name, g.obligatory, g.optional) for g in regenerated.buffer_groups])
    same("predicates", original.predicates, regenerated.predicates)
    same("initial", original.initial_state_name, regenerated.initial_state_name)
    # FABRIC finds behaviours by name (states name them); their order only numbers them in the
    # generated master, and an EARL model does not keep it (docs/fabric-import.md)
    same("behaviors", sorted(b.name for b in original.behaviors), sorted(b.name for b in regenerated.behaviors))
    by_name = {b.name: b for b in regenerated.behaviors}
    for a in original.behaviors:
        b = by_name.get(a.name)
        if b is None:
            continue
        same(f"behavior {a.name} running", a.running_components, b.running_components)
        for attribute in ("stop_cond", "err_cond"):
            found += _logic(f"behavior {a.name} {attribute}", getattr(a, attribute), original.predicates,
                            getattr(b, attribute), regenerated.predicates)
    same("states", [s.name for s in original.states], [s.name for s in regenerated.states])
    for a, b in zip(original.states, regenerated.states):
        same(f"state {a.name} behaviors", a.behaviors, b.behaviors)
        same(f"state {a.name} next states", [n for n, _ in a.next_states], [n for n, _ in b.next_states])
        for (name, cond_a), (_, cond_b) in zip(a.next_states, b.next_states):
            found += _logic(f"state {a.name} next_state {name} init_cond", cond_a, original.predicates,
                            cond_b, regenerated.predicates)
        for attribute in GROUP_ATTRIBUTES:
            same(f"state {a.name} {attribute}", getattr(a, attribute), getattr(b, attribute))
    for attribute in SIMULATION:
        same(f"simulation {attribute}", getattr(original, attribute), getattr(regenerated, attribute))
    return found


def _buffer(port: Any) -> tuple[str, str, str, str]:
    return (port.alias, port.getTypeCpp(), port.side, port.converter)


def _logic(what: str, text_a: str, predicates_a: list[str], text_b: str, predicates_b: list[str]) -> list[str]:
    try:
        a = parse_fabric_condition(text_a, {p: p for p in predicates_a})
        b = parse_fabric_condition(text_b, {p: p for p in predicates_b})
    except ConditionError as exc:
        return [f"{what}: {exc} ({text_a!r} / {text_b!r})"]
    return [] if equivalent(a, b) else [f"{what}: {text_a!r} is not {text_b!r}"]


def equivalent(a: Expr, b: Expr) -> bool:
    """The same truth value under every assignment of the atoms of both (or, beyond
    MAX_ATOMS of them, the same expression)."""
    atoms = list(dict.fromkeys(_atoms(a) + _atoms(b)))
    if len(atoms) > MAX_ATOMS:
        return a == b
    return all(_value(a, dict(zip(atoms, bits))) == _value(b, dict(zip(atoms, bits)))
               for bits in itertools.product((False, True), repeat=len(atoms)))


def _atoms(expr: Expr) -> list[Any]:
    if isinstance(expr, Not):
        return _atoms(expr.operand)
    if isinstance(expr, (And, Or)):
        return [atom for operand in expr.operands for atom in _atoms(operand)]
    if isinstance(expr, Const):
        return []
    return [_key(expr)]


def _key(expr: Expr) -> Any:
    return ("builtin", expr.name) if isinstance(expr, BuiltIn) else expr


def _value(expr: Expr, values: dict[Any, bool]) -> bool:
    if isinstance(expr, Const):
        return expr.value
    if isinstance(expr, Not):
        return not _value(expr.operand, values)
    if isinstance(expr, And):
        return all(_value(o, values) for o in expr.operands)
    if isinstance(expr, Or):
        return any(_value(o, values) for o in expr.operands)
    return values[_key(expr)]
