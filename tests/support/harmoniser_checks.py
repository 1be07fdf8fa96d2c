"""The checks of a run of ``samples/harmoniser``, for every runtime (C++ stepped or threaded, ROS,
Orocos). The lines of different subsystems may interleave in any order (threads, processes), so
every check reads the lines of one subsystem in their own order, or only what does not depend
on order across subsystems.

A run passes when tha/a switched none → guiding → fallResponse → guiding, each switch within
the configuration's switchTimeout, nothing undelivered and no overflow; fallHelp/a started from
its initial state; and guide/a, ``resume``d after the fall, went on from its FSM state and its
memory (``resumed_problems``). A guide/a restarted instead fails the last.
"""

from __future__ import annotations

import re

SWITCHES = [("none", "guiding"), ("guiding", "fallResponse"), ("fallResponse", "guiding")]
TIMEOUT_MS = 500.0  # switchTimeout of every configuration of the sample

SWITCH = re.compile(r"^switch (\w+) -> (\w+) in (\d+(?:\.\d+)?) (cycles|ms)$")
LEAD = re.compile(r"^guide/a\.cs: lead to waypoint (\d+)$")
PARK = re.compile(r"^guide/a\.cs: park after command (\d+)$")
ASSIST = re.compile(r"^fallHelp/a\.cs: assist step (\d+)$")
GUIDE_STEP = re.compile(r"^step (\d+) guide/a\.cs: (\w+) -> (\w+) ")
GUIDE_START = re.compile(r"^step \d+ guide/a\.cs: start in (\w+)$")


def switches(lines: list[str]) -> list[tuple[str, str]]:
    return [(m.group(1), m.group(2)) for m in map(SWITCH.match, lines) if m]


def latencies_ms(lines: list[str], cycle_ms: float = 1.0) -> list[float]:
    """Each switch's latency in ms (a stepped run's cycles at ``cycle_ms`` each)."""
    return [float(m.group(3)) * (cycle_ms if m.group(4) == "cycles" else 1.0) for m in map(SWITCH.match, lines) if m]


def problems(lines: list[str], cycle_ms: float = 1.0) -> list[str]:
    """Everything the run shows against the checks; empty when it passes them all."""
    found: list[str] = []
    if switches(lines) != SWITCHES:
        found.append(f"switches {switches(lines)}, not {SWITCHES}")
    found += [f"a switch took {ms} ms, beyond {TIMEOUT_MS} ms"
              for ms in latencies_ms(lines, cycle_ms) if ms > TIMEOUT_MS]
    found += [line for line in lines if "undelivered at switch" in line or "overflowed" in line]
    steps = [int(m.group(1)) for m in map(ASSIST.match, lines) if m]
    if not steps or steps != list(range(1, len(steps) + 1)):
        found.append(f"fallHelp/a's assist steps are not 1, 2, …: {steps[:5]}…")
    return found + resumed_problems(lines)


def resumed_problems(lines: list[str]) -> list[str]:
    """What shows that guide/a did not go on from its state and memory after the fall; empty
    when it did. Reads guide/a's own lines only."""
    guide = [line for line in lines if line.startswith("guide/a.cs: ") or GUIDE_STEP.match(line)
             or GUIDE_START.match(line)]
    found: list[str] = []
    starts = [line for line in guide if GUIDE_START.match(line)]
    if len(starts) != 1:
        found.append(f"guide/a started {len(starts)} times")
    waypoints = [int(m.group(1)) for m in map(LEAD.match, guide) if m]
    if not waypoints or waypoints != list(range(1, len(waypoints) + 1)):
        restarts = [i for i, w in enumerate(waypoints) if w == 1]
        found.append(f"guide/a's waypoints are not 1, 2, … without a break (waypoint 1 at {restarts[:3]})")
    # its FSM: leaving() took it from leading to waiting, where it stopped; it resumes there at
    # the next step of its own count
    moves = [(int(m.group(1)), m.group(2), m.group(3)) for m in map(GUIDE_STEP.match, guide) if m]
    stopped = next((i for i, move in enumerate(moves) if move[1:] == ("leading", "waiting")), None)
    if stopped is None or stopped + 1 >= len(moves):
        found.append("guide/a never went from leading to waiting and back")
    elif moves[stopped + 1] != (moves[stopped][0] + 1, "waiting", "leading"):
        found.append(f"after {moves[stopped]}, guide/a went on with {moves[stopped + 1]}, not from step "
                     f"{moves[stopped][0] + 1} in waiting")
    # its memory: the park it runs in waiting when resumed numbers its command after the ones it
    # sent before (the first park, then one per waypoint)
    parks = [(i, int(m.group(1))) for i, m in enumerate(map(PARK.match, guide)) if m]
    if len(parks) < 2:
        found.append(f"guide/a parked {len(parks)} time(s), not before guiding and again when resumed")
    else:
        index, number = parks[1]
        before = [int(m.group(1)) for m in map(LEAD.match, guide[:index]) if m]
        if not before or number != before[-1] + 2:
            found.append(f"the resumed park numbers its command {number}, not after the "
                         f"{before[-1] + 1 if before else 0} sent before")
    return found
