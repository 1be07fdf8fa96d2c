"""The reference sample runs as a controller: generated with its shipped user code
(``samples/pick_and_place/user/``), built with CMake (warnings are errors) and run by the
system executor, manip/a.cs goes idle -> jointMove -> idle -> emergencyStop, the joints reach
the task's setpoint, and after the emergency stop the winding currents are zero.

The trace lines checked here are printed by the sample's user code (see the sample's README,
*Running the sample*); the state changes by the runtime's PrintObserver."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.support import known_bad
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.cpp_sample import cmake_project
from tests.support.load import cpu_hogs, run_until

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
USER = SAMPLE.parent / "user"
CYCLES = 1000  # the scripted task ends with the emergency stop at about cycle 850
TOLERANCE = 1e-3  # rad: every joint within this of its setpoint once the motion is finished
JOINTS = 6
NUMBERS = r"((?: -?\d+\.\d+){6})"
STATE = re.compile(r"^step (\d+) manip/a\.cs: (?:start in (\w+)|(\w+) -> (\w+) \(([^)]*)\))$")
POSITIONS = re.compile(rf"^step (\d+) manip/a\.cs: q{NUMBERS} finished ([01]) estop ([01])$")
CURRENTS = re.compile(rf"^step (\d+) manip/a\.cs: i{NUMBERS} estop ([01])$")
SETPOINT = re.compile(rf"^step (\d+) task/a\.cs: jointMove setpoint{NUMBERS}$")
TASK = re.compile(r"^step \d+ task/a\.cs: (jointMove setpoint|motion finished|emergency stop)")

# The loaded threaded campaign: 50 runs, each stopped as soon as manip/a.cs reached
# emergencyStop (about 0.85 s of the sample's script at the threaded period of 1 ms), with
# one busy process per CPU; about 50 s in all.
CAMPAIGN = "cpp pick_and_place"  # tests/support/campaigns.toml
LOADED_RUNS = loaded_runs(CAMPAIGN)
LOADED_TIMEOUT = 20.0  # s per run: far beyond the 0.85 s the script needs
SEQUENCE = ["idle", "jointMove", "idle", "emergencyStop"]

pytestmark = pytest.mark.skipif(shutil.which("g++") is None or shutil.which("cmake") is None,
                                reason="g++ and cmake are needed")


def run(*command: str | Path, env: dict[str, str] | None = None, timeout: int = 120) -> str:
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=timeout, env=env)
    assert result.returncode == 0, f"{command[0]} failed:\n{result.stdout}\n{result.stderr}"
    return result.stdout


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """(the build folder, gen's output): the sample's user code copied into an empty folder,
    gen run over it, the project built once."""
    base = tmp_path_factory.mktemp("sample_runs")
    out = base / "out"
    shutil.copytree(USER, out / "user")
    gen = run(sys.executable, "-m", "earl_m2t", "gen", SAMPLE, "--target", "cpp", "-o", out)
    return cmake_project(out), gen


@pytest.fixture(scope="module")
def trace(project: tuple[Path, str]) -> list[str]:
    build, _ = project
    return run(build / "PickAndPlace_system", "--cycles", str(CYCLES)).splitlines()


def numbers(text: str) -> list[float]:
    return [float(x) for x in text.split()]


def test_gen_keeps_every_shipped_user_file_and_creates_none(project: tuple[Path, str]) -> None:
    _, gen = project
    kept = [line for line in gen.splitlines() if line.startswith("kept ")]
    assert len(kept) == len(list(USER.glob("*/*/*.hpp"))) == 14
    assert not [line for line in gen.splitlines() if line.startswith(("created ", "orphaned "))]


def test_manip_cs_goes_idle_joint_move_idle_emergency_stop(trace: list[str]) -> None:
    states = []
    for line in trace:
        match = STATE.match(line)
        if match:
            states.append(match.group(2) or match.group(4))
    assert states == ["idle", "jointMove", "idle", "emergencyStop"]
    assert any(re.match(r"^step \d+ task/a\.cs: supervise -> abort \(supervise,abort/t\)$", line) for line in trace)
    assert trace[-1] == f"ran PickAndPlaceSystem for {CYCLES} cycles"


def test_the_joints_reach_the_setpoint_and_stay_there(trace: list[str]) -> None:
    [setpoint] = [numbers(m.group(2)) for m in map(SETPOINT.match, trace) if m]
    rows = [(int(m.group(1)), numbers(m.group(2)), m.group(3) == "1") for m in map(POSITIONS.match, trace) if m]
    assert [step for step, _, _ in rows] == list(range(CYCLES))  # one line per cycle
    assert all(q == [0.0] * JOINTS for _, q, _ in rows[:3])  # at rest until the move starts
    finished_at = next(step for step, _, finished in rows if finished)
    assert all(finished for _, _, finished in rows[finished_at:])
    for step, q, _ in rows[finished_at:]:
        errors = [abs(a - b) for a, b in zip(q, setpoint)]
        assert max(errors) <= TOLERANCE, f"step {step}: {q} is not within {TOLERANCE} of {setpoint}"
    # the move is a real one: halfway, no joint is near its setpoint yet
    _, halfway, _ = rows[finished_at // 2]
    assert all(abs(a - b) > 0.02 for a, b in zip(halfway, setpoint))
    # the interpolation bounds the speed: no joint overshoots its setpoint by more than 1 %
    for k in range(JOINTS):
        peak = max(abs(q[k]) for _, q, _ in rows)
        assert peak <= abs(setpoint[k]) * 1.01


def test_after_the_emergency_stop_the_winding_currents_are_zero(trace: list[str]) -> None:
    stop_at = next(int(m.group(1)) for m in map(STATE.match, trace) if m and m.group(4) == "emergencyStop")
    currents = [(int(m.group(1)), numbers(m.group(2)), m.group(3) == "1") for m in map(CURRENTS.match, trace) if m]
    assert [step for step, _, _ in currents] == list(range(CYCLES))
    assert max(abs(i) for step, row, _ in currents if step < stop_at for i in row) > 0.5  # the motion drew current
    assert not any(stop for step, _, stop in currents if step < stop_at)
    after = [(row, stop) for step, row, stop in currents if step >= stop_at]
    assert len(after) > 100
    assert all(stop and row == [0.0] * JOINTS for row, stop in after)
    states = [m for m in map(POSITIONS.match, trace) if m and int(m.group(1)) >= stop_at]
    assert all(m.group(4) == "1" for m in states)  # manipulatorState reports the stop


def test_the_run_is_deterministic_and_the_user_trace_can_be_silenced(project: tuple[Path, str],
                                                                      trace: list[str]) -> None:
    build, _ = project
    assert run(build / "PickAndPlace_system", "--cycles", str(CYCLES)).splitlines() == trace
    quiet = run(build / "PickAndPlace_system", "--cycles", str(CYCLES),
                env={**os.environ, "PICK_AND_PLACE_QUIET": "1"}).splitlines()
    printed_by_user_code = [line for line in trace if POSITIONS.match(line) or CURRENTS.match(line) or TASK.match(line)]
    assert len(printed_by_user_code) == 2 * CYCLES + 3
    user_lines = set(printed_by_user_code)
    assert quiet == [line for line in trace if line not in user_lines]


def manip_states(lines: list[str]) -> list[str]:
    """The states manip/a.cs entered, in order, from the runtime's trace."""
    return [m.group(2) or m.group(4) for m in map(STATE.match, lines) if m]


def missed_sequence(build: Path, plan: str, seen: Callable[[list[str]], bool] | None = None) -> str | None:
    """One threaded run at 1 ms, stopped once manip/a.cs reached emergencyStop (or ``seen``
    held): what went wrong, or None when manip/a.cs went through SEQUENCE."""
    env = {**os.environ, "PICK_AND_PLACE_QUIET": "1"}
    command = [build / "PickAndPlace_system", "--threaded", str(LOADED_TIMEOUT), "--threads", plan]
    lines, reached = run_until(command, seen or (lambda out: "emergencyStop" in manip_states(out)),
                               LOADED_TIMEOUT, env)
    return None if reached and manip_states(lines) == SEQUENCE else f"{manip_states(lines)}"


@pytest.mark.loaded
@pytest.mark.parametrize("plan", ["period", "subsystem"])
def test_threaded_runs_reach_the_sequence_under_load(project: tuple[Path, str], plan: str) -> None:
    """Threaded at 1 ms (the periodic subsystems a thread per period, or each its own), the
    machine loaded: task/a's one-shot setpoint is never lost (manipulatorCommand/ib is a queue
    and activates manip/a.cs), so every run goes idle -> jointMove -> idle -> emergencyStop."""
    build, _ = project
    failures = []
    with cpu_hogs():
        for attempt in range(LOADED_RUNS):
            missed = missed_sequence(build, plan)
            if missed:
                failures.append(f"run {attempt + 1}: {missed}")
    assert not failures, f"{len(failures)} of {LOADED_RUNS} runs missed the sequence:\n" + "\n".join(failures)


@pytest.mark.loaded
def test_the_checks_catch_a_one_shot_command_into_a_latest_value_input(tmp_path: Path) -> None:
    """The known-bad variant (tests/support/known_bad.py): manip/a.cs's commands kept as the
    latest value only, manip/a.cs on its own clock in a thread of its own. Stepped, the executor
    runs task/a.cs and manip/a.cs in turn and the setpoint is read; threaded under load, a later
    command overwrites it in one of the runs the campaign keeps."""
    out = tmp_path / "out"
    shutil.copytree(USER, out / "user")
    model = known_bad.one_shot_into_latest_value(tmp_path)
    run(sys.executable, "-m", "earl_m2t", "gen", model, "--target", "cpp", "-o", out)
    build = cmake_project(out)
    stepped = run(build / "PickAndPlace_system", "--cycles", str(CYCLES))
    assert manip_states(stepped.splitlines()) == SEQUENCE
    with cpu_hogs():
        caught = next((attempt for attempt in range(1, catch_runs(CAMPAIGN) + 1)
                       if missed_sequence(build, "subsystem", known_bad.SetpointWatch(manip_states))), None)
    assert caught is not None, f"all {catch_runs(CAMPAIGN)} runs of the latest-value variant reached the sequence"
