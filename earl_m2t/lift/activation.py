"""Lifting activation (FABRIC's buffer groups): how an Input Buffer receives, how reliable a
buffer's link is, the buffer groups of a subsystem and the activation of each FSM state, all
read from stereotype tags.

Values the lift cannot read are kept recognisably wrong (an unknown receive mode as written, a
number as NaN, a queue size as -1) so that rule B011 reports them with their element.
"""

from __future__ import annotations

from earl_m2t.lift.recognise import Recogniser
from earl_m2t.lift.tags import flag, literal, names, seconds, tag
from earl_m2t.model.elements import Activation, BufferGroup, Simulation
from earl_m2t.model.kinds import RECEIVE_MODES, RELIABILITIES, ReceiveMode, Reliability
from earl_m2t.read.xmi import Element, RawModel


def receive_of(raw: RawModel, tags: dict[str, str]) -> tuple[str, int]:
    """(receive mode, queue size) of an Input Buffer: ``(LATEST, 0)`` unless tagged; a mode that
    is none is kept as written (rule B011)."""
    mode = tag(tags, "receive")
    size_text = tag(tags, "queueSize")
    receive = (literal(raw, mode) if mode else "") or ReceiveMode.LATEST
    try:
        size = int(size_text) if size_text else 0
    except ValueError:
        size = -1
    return next((known for known in RECEIVE_MODES if known == receive), receive), size


def reliability_of(raw: RawModel, tags: dict[str, str]) -> str:
    """A buffer's reliability: ``RELIABLE`` unless tagged; a value that is none is kept as
    written (rule B011)."""
    written = tag(tags, "reliability")
    value = (literal(raw, written) if written else "") or Reliability.RELIABLE
    return next((known for known in RELIABILITIES if known == value), value)


def activation_of(tags: dict[str, str]) -> Activation:
    """The activation an «FsmState»'s tags give; no tags: the subsystem's own period."""
    return Activation(
        tag(tags, "bufferGroup") or "",
        seconds(tag(tags, "minPeriod")),
        seconds(tag(tags, "firstTimeout")),
        seconds(tag(tags, "nextTimeout")),
        seconds(tag(tags, "minPeriodSim")),
        seconds(tag(tags, "firstTimeoutSim")),
        tag(tags, "usedTime") or "",
    )


def simulation_of(tags: dict[str, str]) -> Simulation | None:
    """FABRIC's ``<simulation>`` a subsystem's tags give, None without them."""
    ros, sim = tag(tags, "useRosSimClock"), tag(tags, "useSimClock")
    if ros is None and sim is None:
        return None
    gazebo = tag(tags, "triggerGazebo")
    return Simulation(flag(ros), flag(sim), None if gazebo is None else flag(gazebo))


def buffer_groups(raw: RawModel, recogniser: Recogniser, block: Element, path: str) -> tuple[BufferGroup, ...]:
    """The «BufferGroup» constraints a subsystem block owns, in model order."""
    groups = []
    for rule in raw.children(block, "ownedRule"):
        if recogniser.recognise(rule).concept != "BufferGroup":
            continue
        tags = recogniser.tags(rule)
        name = raw.name(rule)
        groups.append(BufferGroup(name, f"{path}.{name}", names(raw, tag(tags, "obligatory")),
                                  names(raw, tag(tags, "optional")), raw.location(rule)))
    return tuple(groups)


__all__ = ["activation_of", "buffer_groups", "receive_of", "simulation_of"]
