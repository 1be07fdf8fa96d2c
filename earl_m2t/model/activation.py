"""When a subsystem runs an iteration: FABRIC's buffer groups and each FSM state's activation,
and FABRIC's simulated clock (the model elements of earl_m2t.model.elements use them)."""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.model.location import Location


@dataclass(frozen=True, slots=True)
class BufferGroup:
    """FABRIC's buffer group: the Input Buffers an iteration waits for (obligatory) and those it
    reads when they have new data (optional)."""

    name: str
    path: str  # subsystem path + "." + name
    obligatory: tuple[str, ...]  # Input Buffer names as written
    optional: tuple[str, ...]
    location: Location


@dataclass(frozen=True, slots=True)
class Activation:
    """When a subsystem in an FSM state runs an iteration (FABRIC's per-state buffer group).
    The default, no group, is EARL's free-running period: every input read when present."""

    group: str = ""  # a BufferGroup name of the subsystem, "" for none
    min_period: float | None = None  # seconds; None: the subsystem's own period
    first_timeout: float | None = None  # seconds to wait for the obligatory inputs on entry
    next_timeout: float | None = None  # ... and in later iterations
    # FABRIC's times under simulated time and the clock it uses (tags minPeriodSim,
    # firstTimeoutSim, usedTime): None / "" when not given
    min_period_sim: float | None = None
    first_timeout_sim: float | None = None
    used_time: str = ""


@dataclass(frozen=True, slots=True)
class Simulation:
    """FABRIC's ``<simulation>``: whether the subsystem runs on ROS's or Gazebo's simulated clock."""

    use_ros_sim_clock: bool
    use_sim_clock: bool
    trigger_gazebo: bool | None = None  # None: not given
