"""Lifting activation (FABRIC's buffer groups): how an Input Buffer receives, the buffer groups
of a subsystem and the activation of each FSM state, all read from stereotype tags.

Values the lift cannot read are kept recognisably wrong (an unknown receive mode as written, a
number as NaN, a queue size as -1) so that rule B011 reports them with their element.
"""

from __future__ import annotations

import math
import re

from earl_m2t.lift.recognise import Recogniser
from earl_m2t.model.elements import Activation, BufferGroup
from earl_m2t.model.kinds import RECEIVE_MODES, ReceiveMode
from earl_m2t.read.xmi import Element, RawModel

_SEPARATORS = re.compile(r"[\s,;]+")


def _tag(tags: dict[str, str], name: str) -> str | None:
    """A tag by name, as tools spell it (``queueSize``, ``queuesize``, ``queue_size``)."""
    wanted = name.lower()
    for key, value in tags.items():
        if key.lower().replace("_", "") == wanted:
            return value.strip()
    return None


def _literal(raw: RawModel, value: str) -> str:
    """An enumeration tag value as its literal name: ``queue``, ``ReceiveMode::queue`` or the id
    of the literal (Cameo, EA)."""
    target = raw.by_id.get(value)
    if target is not None:
        value = raw.name(target) or value
    return value.rpartition("::")[2].strip()


def _seconds(value: str | None) -> float | None:
    if value is None or value == "":
        return None
    try:
        return float(value)
    except ValueError:
        return math.nan


def receive_of(raw: RawModel, tags: dict[str, str]) -> tuple[str, int]:
    """(receive mode, queue size) of an Input Buffer: ``(LATEST, 0)`` unless tagged; a mode that
    is none is kept as written (rule B011)."""
    mode = _tag(tags, "receive")
    size_text = _tag(tags, "queueSize")
    receive = (_literal(raw, mode) if mode else "") or ReceiveMode.LATEST
    try:
        size = int(size_text) if size_text else 0
    except ValueError:
        size = -1
    return next((known for known in RECEIVE_MODES if known == receive), receive), size


def activation_of(tags: dict[str, str]) -> Activation:
    """The activation an «FsmState»'s tags give; no tags: the subsystem's own period."""
    return Activation(
        _tag(tags, "bufferGroup") or "",
        _seconds(_tag(tags, "minPeriod")),
        _seconds(_tag(tags, "firstTimeout")),
        _seconds(_tag(tags, "nextTimeout")),
    )


def _names(raw: RawModel, value: str | None) -> tuple[str, ...]:
    """Buffer names of a group tag: names separated by spaces or commas, or port ids."""
    if not value:
        return ()
    names = []
    for token in _SEPARATORS.split(value):
        if not token:
            continue
        target = raw.by_id.get(token)
        names.append(raw.name(target) if target is not None else token)
    return tuple(names)


def buffer_groups(raw: RawModel, recogniser: Recogniser, block: Element, path: str) -> tuple[BufferGroup, ...]:
    """The «BufferGroup» constraints a subsystem block owns, in model order."""
    groups = []
    for rule in raw.children(block, "ownedRule"):
        if recogniser.recognise(rule).concept != "BufferGroup":
            continue
        tags = recogniser.tags(rule)
        name = raw.name(rule)
        groups.append(BufferGroup(name, f"{path}.{name}", _names(raw, _tag(tags, "obligatory")),
                                  _names(raw, _tag(tags, "optional")), raw.location(rule)))
    return tuple(groups)


__all__ = ["activation_of", "buffer_groups", "receive_of"]
