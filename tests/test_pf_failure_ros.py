"""A failing pf puts its subsystem in error on ROS 1: the pick_and_place sample's packages
built by catkin with the user code of tests/support/faulty_user.py and launched by roslaunch.
When jointMove/pf throws, or outputMotorCon/pf writes NaN, manip/a.cs goes idle -> jointMove
-> emergencyStop, its node logs the pf and the reason with ROS_ERROR and keeps stepping (no
node dies: the launch's nodes are required, one dying would end the launch). With
``non_finite:=report`` the NaN is reported with ROS_WARN, sent, and no state changes on it."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support.faulty_user import NAN_FROM, THROWN, copy_faulty_user
from tests.support.load import run_until
from tests.support.ros_launch import (
    catkin_make,
    clear_start_barrier,
    environment,
    generate,
    needs_catkin,
    needs_roslaunch,
    roscore,
)

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
STATE = re.compile(r"^step \d+ manip/a\.cs: (?:start in (\w+)|(\w+) -> (\w+) \([^)]*\))$")
TRACE = re.compile(r"^step (\d+) manip/a\.cs: i ")
LAUNCH_TIMEOUT = 90.0  # s: start-up of the 17 nodes, then the script at 1 ms
AFTER = 300  # iterations of manip/a.cs seen after the event: it keeps stepping
COLOUR = re.compile(r"\x1b\[[0-9;]*m")  # rosconsole colours its levels

pytestmark = [needs_catkin, needs_roslaunch]


@pytest.fixture(scope="module")
def ros(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[dict[str, str], object]]:
    """(the launch environment, the master) of the workspace built with the faulty user code."""
    base = tmp_path_factory.mktemp("pf_failure_ros")
    ws = base / "ws"
    user = copy_faulty_user(base / "user")
    generate(SAMPLE, user, ws)
    ws = catkin_make(ws)
    with roscore(base) as (port, master):
        yield environment(ws, base, port), master


def manip_states(lines: list[str]) -> list[str]:
    return [m.group(1) or m.group(3) for m in map(STATE.match, (line.strip() for line in lines)) if m]


def manip_step(lines: list[str]) -> int:
    """The last iteration manip/a.cs's own trace printed, -1 before the first."""
    steps = [int(m.group(1)) for m in map(TRACE.match, (line.strip() for line in lines)) if m]
    return steps[-1] if steps else -1


def launch(ros: tuple[dict[str, str], object], fault: str, until: str, *arguments: str) -> list[str]:
    """The output of one launch with EARL_FAULT=fault, stopped once ``until`` was printed and
    manip/a.cs stepped AFTER more times."""
    env, master = ros
    clear_start_barrier(master)  # type: ignore[arg-type]
    seen_at: list[int] = []

    def done(lines: list[str]) -> bool:
        if not seen_at and any(until in line for line in lines):
            seen_at.append(manip_step(lines))
        return bool(seen_at) and manip_step(lines) >= seen_at[0] + AFTER

    lines, reached = run_until(["roslaunch", "--wait", "pick_and_place_bringup", "system.launch", "period:=0.001",
                                *arguments], done, LAUNCH_TIMEOUT, {**env, "EARL_FAULT": fault},
                               graceful=False)  # every node killed with it: they run in sessions of their own
    assert reached, f"{until!r} and {AFTER} more iterations not seen:\n" + "\n".join(lines[-60:])
    assert not [line for line in lines if "has died" in line or "required" in line.lower()], "\n".join(lines[-60:])
    return [COLOUR.sub("", line).rstrip() for line in lines]


def test_a_pf_that_throws_takes_manip_to_its_emergency_stop(ros: tuple[dict[str, str], object]) -> None:
    lines = launch(ros, "throw", "jointMove -> emergencyStop")
    assert manip_states(lines) == ["idle", "jointMove", "emergencyStop"]
    errors = [line for line in lines if "failed:" in line]
    assert len(errors) == 1 and "[ERROR]" in errors[0], errors
    assert errors[0].endswith(f"manip/a.cs: jointMove/pf failed: {THROWN}")


def test_a_nan_written_fails_the_pf(ros: tuple[dict[str, str], object]) -> None:
    lines = launch(ros, "nan", "jointMove -> emergencyStop")
    assert manip_states(lines) == ["idle", "jointMove", "emergencyStop"]
    errors = [line for line in lines if "failed:" in line]
    assert errors and all("[ERROR]" in line for line in errors)
    assert errors[0].endswith(f"step {NAN_FROM} manip/a.cs: outputMotorCon/pf failed: "
                              "a non-finite number in motorControllerCommandK/ob")


def test_with_the_report_policy_a_nan_is_reported_and_changes_no_state(ros: tuple[dict[str, str], object]) -> None:
    lines = launch(ros, "nan", "wrote a non-finite number", "non_finite:=report")
    assert manip_states(lines) == ["idle", "jointMove"]
    reports = [line for line in lines if "non-finite" in line]
    assert "[ WARN]" in reports[0] or "[WARN]" in reports[0], reports
    assert reports[0].endswith(f"step {NAN_FROM} manip/a.cs: outputMotorCon/pf wrote a non-finite number "
                               "into motorControllerCommandK/ob (sent)")
    assert not [line for line in lines if "failed:" in line]
    # once per pf and buffer until the value is finite again, no flood: the NaN sent comes back
    # through the motor and its controller, so a pf may write a finite value in between and
    # then a NaN again, but not one line per iteration of the AFTER seen
    pairs = [re.sub(r"^.*step \d+ ", "", line) for line in reports]
    assert all(pairs.count(pair) <= 3 for pair in pairs) and len(reports) < 20, reports
