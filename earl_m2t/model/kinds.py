"""The closed sets of values the lifted model's elements take: what kind of subsystem, which
direction a buffer has, how it receives, what a link connects, what a group gathers, how a pf
accesses a buffer, what a dataType is. Each is a ``StrEnum``: a member is its text (``"cs"``),
in comparisons, f-strings, JSON and templates alike."""

from __future__ import annotations

from enum import StrEnum


class SubsystemKind(StrEnum):
    CS = "cs"  # Control Subsystem
    VE = "ve"  # Virtual Effector
    RE = "re"  # Real Effector
    VR = "vr"  # Virtual Receptor
    RR = "rr"  # Real Receptor


class Direction(StrEnum):
    IN = "in"  # an Input Buffer
    OUT = "out"  # an Output Buffer


class ReceiveMode(StrEnum):
    """How an Input Buffer receives (its tag ``receive``; another value is kept as written for B011)."""

    LATEST = "latest"  # keeps the newest value (EARL's default)
    QUEUE = "queue"  # keeps up to queueSize values in arrival order and reports an overflow


class Reliability(StrEnum):
    """What a buffer's link may do with its values (its tag ``reliability``; another value is
    kept as written for B011)."""

    RELIABLE = "reliable"  # every value is delivered (EARL's default)
    BEST_EFFORT = "best_effort"  # the transport may drop values (ROS 2: a best-effort publisher or subscription)


class LinkScope(StrEnum):
    AGENT = "agent"  # an inter-subsystem link, inside one agent
    SYSTEM = "system"  # an inter-agent link


class GroupKind(StrEnum):
    AGENTS = "ga"  # an Agent Group (the authors' GpAgents)
    SUBSYSTEMS = "gs"  # a Subsystem Group (GpSubsys)


class AccessMode(StrEnum):
    READ = "read"
    WRITE = "write"
    READWRITE = "readwrite"


class Reactivation(StrEnum):
    """How a variable agent comes back when a switch makes it present again (its tag ``reactivation``)."""

    RESTART = "restart"  # from its initial FSM state, memory and inputs reset
    RESUME = "resume"  # where it stopped: FSM state and memory kept, inputs empty


class DataTypeKind(StrEnum):
    PRIMITIVE = "primitive"
    ENUMERATION = "enumeration"
    STRUCT = "struct"


SUBSYSTEM_KINDS = tuple(SubsystemKind)
RECEIVE_MODES = tuple(ReceiveMode)
RELIABILITIES = tuple(Reliability)
REACTIVATIONS = tuple(Reactivation)
