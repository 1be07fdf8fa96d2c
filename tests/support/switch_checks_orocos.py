"""The checks of the two variable-structure samples' traces, whatever runs them (the C++ system
executor, OCL's deployer): the lines the samples' user code prints and the switch lines of
``earl::SwitchPrintObserver``. A subsystem's own step lines name it as its runner does
(``guide/a.cs`` in C++, the component ``guide_a_cs`` under Orocos): the checks take that name.

two_arm: task/a.cs sends 201 numbered commands and hands the job over between manipA/a and
manipB/a 20 times; every command must be taken exactly once, by the arm of the configuration it
was sent in, with no value undelivered at a switch, no queue overflow, 20 switches each within
the switchTimeout.

harmoniser: guide/a (reactivation resume), stopped by the fall, goes on from its state and
memory once brought back.
"""

from __future__ import annotations

import re

from tests.support.switch_checks import SWITCH, Harmoniser, TwoArm

# ---------------------------------------------------------------- two_arm

COMMANDS = 201  # 10 per configuration before each of the 20 hand-overs, then one more
SWITCHES = 20
TIMEOUT_MS = TwoArm.TIMEOUT_MS  # the configurations' switchTimeout, one value for every runtime

SENT = re.compile(r"^task/a\.cs: sent seq (\d+) to (manip[AB]/a)$")
TOOK = re.compile(r"^(manip[AB]/a)\.cs: took seq (\d+)$")


def switches(lines: list[str]) -> list[tuple[str, str]]:
    """(from, to) of every switch line."""
    return [(m.group(1), m.group(2)) for m in map(SWITCH.match, lines) if m]


def latencies_ms(lines: list[str]) -> list[float]:
    """The measured latency of every switch line counted on the clock."""
    return [float(m.group(3)) for m in map(SWITCH.match, lines) if m and m.group(4) == "ms"]


def two_arm_problems(lines: list[str], timeout_ms: float = TIMEOUT_MS) -> list[str]:
    """What a two_arm run shows against the checks; empty when it passes them."""
    sent: dict[int, str] = {}
    found: list[str] = []
    for match in filter(None, map(SENT.match, lines)):
        seq, arm = int(match.group(1)), match.group(2)
        if seq in sent:
            found.append(f"seq {seq} sent twice")
        sent[seq] = arm
    if sorted(sent) != list(range(1, COMMANDS + 1)):
        found.append(f"{len(sent)} numbered commands sent, not 1..{COMMANDS}")
    taken: dict[int, list[str]] = {}
    for match in filter(None, map(TOOK.match, lines)):
        taken.setdefault(int(match.group(2)), []).append(match.group(1))
    for seq, arm in sorted(sent.items()):
        arms = taken.get(seq, [])
        if arms != [arm]:
            found.append(f"seq {seq} sent to {arm}, taken by {arms or 'none'}")
    found += [f"taken but never sent: {seq}" for seq in sorted(set(taken) - set(sent))]
    matched = [m for m in map(SWITCH.match, lines) if m]
    if len(matched) != SWITCHES:
        found.append(f"{len(matched)} switches")
    found += [f"{m.group(0)}: beyond {timeout_ms} ms" for m in matched
              if m.group(4) == "ms" and float(m.group(3)) > timeout_ms]
    found += [line for line in lines if "undelivered at switch" in line or "overflowed" in line]
    return found[:12]


def two_arm_finished(lines: list[str], task: str) -> bool:
    """task/a (its step lines name it ``task``) has finished and the last command was taken."""
    finished = re.compile(rf"^step \d+ {re.escape(task)}: with[AB] -> finished ")
    return any(finished.match(line) for line in lines) and any(line.endswith(f"took seq {COMMANDS}")
                                                                 for line in lines)


# ---------------------------------------------------------------- harmoniser

HARMONISER_SWITCHES = [("none", "guiding"), ("guiding", "fallResponse"), ("fallResponse", "guiding")]
LEAD = re.compile(r"^guide/a\.cs: lead to waypoint (\d+) \(command (\d+)\)$")
PARK = re.compile(r"^guide/a\.cs: park after command (\d+)$")
ASSIST = re.compile(r"^fallHelp/a\.cs: assist step (\d+) \(command (\d+)\)$")
FALL_HELP = re.compile(r"^fallHelp/a\.cs: ")


def _steps(trace: list[str], name: str) -> list[tuple[int, str, str]]:
    step = re.compile(rf"^step (\d+) {re.escape(name)}: (\w+) -> (\w+) ")
    return [(int(m.group(1)), m.group(2), m.group(3)) for m in map(step.match, trace) if m]


def back_index(trace: list[str]) -> int:
    """The line of the switch that brings guide/a back."""
    return next(i for i, line in enumerate(trace) if SWITCH.match(line) and "fallResponse -> guiding" in line)


def resume_index(trace: list[str]) -> int:
    """The first line guide/a prints after the switch to fallResponse: its first iteration once
    brought back. Between components that comes before the line of the switch back, which the
    coordinator prints once every node has opened the new configuration."""
    fall = next(i for i, line in enumerate(trace) if SWITCH.match(line) and "-> fallResponse" in line)
    return next(i for i in range(fall, len(trace)) if LEAD.match(trace[i]) or PARK.match(trace[i]))


def harmoniser_finished(lines: list[str]) -> bool:
    """guide/a, brought back after the fall, has led to a waypoint, and tiago/a has taken a
    command of guide/a's again (the third run of its numbers: guide/a's, fallHelp/a's, guide/a's)."""
    back = next((i for i, line in enumerate(lines) if SWITCH.match(line) and "fallResponse -> guiding" in line), None)
    return (back is not None and any(LEAD.match(line) for line in lines[back:])
            and len(Harmoniser.taken_runs(lines)) >= 3)


def assert_resumed(trace: list[str], guide: str) -> None:
    """Asserts that guide/a (its step lines name it ``guide``), resumed after the fall, goes on
    from its state and memory."""
    fall = next(i for i, line in enumerate(trace) if SWITCH.match(line) and "-> fallResponse" in line)
    resume = resume_index(trace)
    before, after = trace[:fall], trace[resume:]

    # the waypoints carry on: 1, 2, … up to the fall, then the next one, never 1 again
    waypoints_before = [int(m.group(1)) for m in map(LEAD.match, before) if m]
    waypoints_after = [int(m.group(1)) for m in map(LEAD.match, after) if m]
    assert waypoints_before == list(range(1, len(waypoints_before) + 1)) and len(waypoints_before) > 1
    assert waypoints_after[0] == waypoints_before[-1] + 1
    assert waypoints_after == list(range(waypoints_after[0], waypoints_after[0] + len(waypoints_after)))
    # stopped while fallResponse holds: fallHelp/a has printed its last line before guide/a runs again
    assert resume > max(i for i, line in enumerate(trace) if FALL_HELP.match(line) and i > fall)

    # its FSM: leaving() took it from leading to waiting, where it ran until stopped (at once in
    # one process; until the switch's stop round between components), and it resumes in
    # waiting at its next step
    guide_steps = _steps(trace, guide)
    stopped = next((s for s in guide_steps if s[1:] == ("leading", "waiting")), None)
    assert stopped is not None
    stop_line = next(i for i, line in enumerate(trace) if line.startswith(f"step {stopped[0]} {guide}: leading -> "))
    parked_while_leaving = len([line for line in trace[stop_line:fall] if PARK.match(line)])
    resumed = [s for s in guide_steps if s[0] > stopped[0]]
    assert resumed[0] == (stopped[0] + 1 + parked_while_leaving, "waiting", "leading")
    assert not any(line.startswith(f"step 0 {guide}: start") for line in after)

    # its memory: the resumed park (in waiting, where it stopped) numbers its command after
    # every one sent before it stopped (the first park, one per waypoint, the parks while leaving)
    commands_before = len([line for line in trace[:fall] if LEAD.match(line) or PARK.match(line)])
    (first_park_after, *_) = [int(m.group(1)) for m in map(PARK.match, after) if m]
    assert first_park_after == commands_before + 1


def assert_fall_help_starts_initially(trace: list[str], fall_help: str) -> None:
    """fallHelp/a, brought in for the first time, starts from its initial state."""
    steps = [int(m.group(1)) for m in map(ASSIST.match, trace) if m]
    assert steps == list(range(1, len(steps) + 1)) and len(steps) > 1
    assert (1, "waiting", "helping") in _steps(trace, fall_help)
