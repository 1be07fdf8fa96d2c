"""Activation rules: buffer groups, the activation of FSM states and how Input Buffers receive
(FABRIC's buffer groups; earl-m2t beyond the paper)."""

from __future__ import annotations

import math
from collections.abc import Iterator

from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.elements import Buffer, EarlModel, State, Subsystem
from earl_m2t.model.kinds import RECEIVE_MODES, RELIABILITIES
from earl_m2t.model.limits import MAX_SECONDS
from earl_m2t.predicate import FieldRef, NewData
from earl_m2t.predicate.walk import walk


def _input_names(sub: Subsystem) -> set[str]:
    """What a group may name: each Input Buffer by its name and by its template."""
    return {name for b in sub.inputs for name in (b.name, b.template)}


@rule("B009")
def buffer_group_unknown_buffer(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        inputs = _input_names(sub)
        outputs = {name for b in sub.outputs for name in (b.name, b.template)}
        for group in sub.buffer_groups:
            if not group.obligatory and not group.optional:
                yield Finding(f"buffer group {group.path} names no Input Buffer (neither obligatory nor optional)",
                              group.location, group.path)
            for role, names in (("obligatory", group.obligatory), ("optional", group.optional)):
                for name in names:
                    if name in inputs:
                        continue
                    what = "an Output Buffer" if name in outputs else "no Input Buffer"
                    yield Finding(f"buffer group {group.path} names {role} '{name}', which is {what} of "
                                  f"{sub.path}", group.location, group.path)
            both = set(group.obligatory) & set(group.optional)
            for name in sorted(both):
                yield Finding(f"buffer group {group.path} names '{name}' both obligatory and optional",
                              group.location, group.path)


@rule("B010")
def state_without_buffer_group(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        if sub.fsm is None:
            continue
        groups = {g.name for g in sub.buffer_groups}
        for state in sub.fsm.states:
            activation = state.activation
            if activation.group and activation.group not in groups:
                known = ", ".join(sorted(groups)) or "none"
                yield Finding(f"state {state.path} is activated by buffer group '{activation.group}', which "
                              f"{sub.path} does not have (its groups: {known})", state.location, state.path)
            elif not activation.group and groups:
                yield Finding(f"state {state.path} has no buffer group, but {sub.path} is activated by buffer "
                              f"groups ({', '.join(sorted(groups))}): name one in the state's tag bufferGroup",
                              state.location, state.path)
            elif not activation.group and (activation.first_timeout is not None or activation.next_timeout is not None):
                yield Finding(f"state {state.path} has a timeout but no buffer group: the timeout waits for the "
                              "group's obligatory inputs", state.location, state.path)


def _bad_seconds(value: float | None) -> bool:
    return value is not None and not (math.isfinite(value) and 0 <= value <= MAX_SECONDS)


@rule("B011")
def activation_value_invalid(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        for buffer in sub.inputs:
            if buffer.index > 1:
                continue  # replicated instances share the port and its tags
            if buffer.receive not in RECEIVE_MODES:
                yield Finding(f"Input Buffer {buffer.path} receives '{buffer.receive}'; the receive modes are "
                              f"{', '.join(RECEIVE_MODES)}", buffer.location, buffer.path)
            elif buffer.receive == "queue" and buffer.queue_size == -1:
                yield Finding(f"Input Buffer {buffer.path} receives a queue, but its tag queueSize is not a whole "
                              "number", buffer.location, buffer.path)
            elif buffer.receive == "queue" and buffer.queue_size < 1:
                yield Finding(f"Input Buffer {buffer.path} receives a queue of {buffer.queue_size}; a queue holds "
                              "at least one value (tag queueSize ≥ 1)", buffer.location, buffer.path)
        for buffer in sub.inputs + sub.outputs:
            if buffer.index <= 1 and buffer.reliability not in RELIABILITIES:
                yield Finding(f"{buffer.path} has the reliability '{buffer.reliability}'; the reliabilities are "
                              f"{', '.join(RELIABILITIES)}", buffer.location, buffer.path)
        for state in sub.fsm.states if sub.fsm is not None else ():
            yield from _state_values(state)


def _state_values(state: State) -> Iterator[Finding]:
    activation = state.activation
    for tag, value in (("minPeriod", activation.min_period), ("firstTimeout", activation.first_timeout),
                       ("nextTimeout", activation.next_timeout)):
        if _bad_seconds(value):
            yield Finding(f"state {state.path}: {tag} is not a number of seconds from 0 to {MAX_SECONDS:.0f} (a "
                          "year)", state.location, state.path)


def _optional_field(model: EarlModel, sub: Subsystem, ref: FieldRef) -> bool:
    """True when ``ref`` ends at a field of multiplicity 0..1 of the buffer's message: a command
    present in some messages only (a setpoint), as opposed to a value every message carries."""
    buffer = next((b for b in sub.inputs if ref.head in (b.name, b.template)), None)
    datatype = model.datatypes.get(buffer.datatype) if buffer is not None else None
    found = None
    for segment in ref.path:
        found = datatype.field_named(segment.partition("[")[0]) if datatype is not None else None
        if found is None:
            return False
        datatype = model.datatypes.get(found.type)
    return found is not None and found.lower == 0 and found.upper == 1


def _one_shot_inputs(model: EarlModel, sub: Subsystem) -> dict[str, str]:
    """Input Buffers carrying a one-shot command, an optional field whose new data a condition
    tests (``newData(x/ib.msg.setpoint)``): buffer name or template → the element testing it."""
    found: dict[str, str] = {}
    for condition in sub.conditions():
        if condition.expr is None:
            continue
        for node in walk(condition.expr):
            if isinstance(node, NewData) and _optional_field(model, sub, node.ref):
                found.setdefault(node.ref.head, condition.owner)
    return found


def _activated_by(sub: Subsystem, buffer: Buffer) -> bool:
    """True when every state waits for the buffer: it is obligatory in the group of each state."""
    if sub.fsm is None or not sub.fsm.states:
        return False
    groups = {g.name: g for g in sub.buffer_groups}
    for state in sub.fsm.states:
        group = groups.get(state.activation.group)
        if group is None or not ({buffer.name, buffer.template} & set(group.obligatory)):
            return False
    return True


@rule("C009")
def one_shot_into_latest_value(model: EarlModel) -> Iterator[Finding]:
    linked = {link.target: link for link in model.links if link.target}
    tested_by_block: dict[str, dict[str, str]] = {}  # instances of one block test the same conditions
    for sub in model.subsystems:
        tested = tested_by_block.get(sub.block_id)
        if tested is None:
            tested = tested_by_block[sub.block_id] = _one_shot_inputs(model, sub)
        for buffer in sub.inputs:
            link = linked.get(buffer.path)
            where = tested.get(buffer.name) or tested.get(buffer.template)
            if link is None or where is None or buffer.receive != "latest" or _activated_by(sub, buffer):
                continue
            sender = model.subsystem_of(link.source)
            source = sender.path if sender is not None else link.source
            yield Finding(
                f"{buffer.path} keeps the latest value only, but {where} tests newData() on it: a command that "
                f"{source} sends in one period only is lost when a newer message arrives before {sub.path}, "
                f"which runs on its own clock, iterates again; receive it as a queue (tags receive = queue, "
                f"queueSize) or make it obligatory in the buffer group of every state", buffer.location, buffer.path)
