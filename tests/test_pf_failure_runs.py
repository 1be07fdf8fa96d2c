"""A failing pf puts its subsystem in error, in the C++ executables: the pick_and_place sample
built with its user code changed (tests/support/faulty_user.py) so that jointMove/pf throws or
calls fail() when a command arrives, or outputMotorCon/pf writes NaN into an output buffer.
manip/a.cs (ec ``¬behaviourOk()``, the transitions into emergencyStop also on ``inError()``)
goes idle -> jointMove -> emergencyStop, the trace names the pf and the reason, the process
keeps running to its last cycle. Under ``--non-finite report`` the NaN is reported once per pf
and buffer it reaches, and sent; no state changes because of it."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.cpp_sample import cmake_build
from tests.support.faulty_user import FAILED, NAN_FROM, THROWN, copy_faulty_user
from tests.test_cpp_allocations import compile_

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
CYCLES = 1000
STATE = re.compile(r"^step (\d+) manip/a\.cs: (?:start in (\w+)|(\w+) -> (\w+) \(([^)]*)\))$")
CURRENTS = re.compile(r"^step (\d+) manip/a\.cs: i( -?\d+\.\d+| -?nan){6} estop [01]$")
SETPOINT = re.compile(r"^step \d+ task/a\.cs: jointMove setpoint")

pytestmark = pytest.mark.skipif(shutil.which("g++") is None or shutil.which("cmake") is None,
                                reason="g++ and cmake are needed")


def run(*command: str | Path, env: dict[str, str] | None = None,
        timeout: int = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=timeout, env=env)


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """gen's output for the sample over the faulty user code."""
    out = tmp_path_factory.mktemp("pf_failure") / "out"
    copy_faulty_user(out / "user")
    gen = run(sys.executable, "-m", "earl_m2t", "gen", SAMPLE, "--target", "cpp", "-o", out)
    assert gen.returncode == 0, gen.stderr
    return out


@pytest.fixture(scope="module")
def system(generated: Path) -> Path:
    return cmake_build(generated, "PickAndPlace_system")


def trace(system: Path, fault: str, *arguments: str) -> list[str]:
    env = {**os.environ, "EARL_FAULT": fault}
    result = run(system, "--cycles", str(CYCLES), *arguments, env=env)
    assert result.returncode == 0, f"exit {result.returncode}:\n{result.stdout[-2000:]}\n{result.stderr}"
    return result.stdout.splitlines()


def manip(lines: list[str]) -> list[tuple[int, str, str]]:
    """(step, state entered, transition) of manip/a.cs."""
    return [(int(m.group(1)), m.group(2) or m.group(4), m.group(5) or "") for m in map(STATE.match, lines) if m]


def failures(lines: list[str]) -> list[str]:
    return [line for line in lines if " failed: " in line or "non-finite" in line]


def assert_kept_running(lines: list[str]) -> None:
    """Every subsystem stepped to the last cycle: manip/a.cs's own trace has a line per cycle
    and the system ran all its cycles."""
    assert [int(m.group(1)) for m in map(CURRENTS.match, lines) if m] == list(range(CYCLES))
    assert lines[-1] == f"ran PickAndPlaceSystem for {CYCLES} cycles"
    assert any(SETPOINT.match(line) for line in lines)


@pytest.mark.parametrize(("fault", "reason"), [("throw", THROWN), ("fail", FAILED)])
def test_a_pf_that_throws_or_fails_takes_manip_to_its_emergency_stop(system: Path, fault: str, reason: str) -> None:
    lines = trace(system, fault)
    states = manip(lines)
    assert [s for _, s, _ in states] == ["idle", "jointMove", "emergencyStop"], states
    entered_move = states[1][0]
    [failure] = failures(lines)
    assert failure == f"step {entered_move} manip/a.cs: jointMove/pf failed: {reason}"
    assert states[2] == (entered_move + 1, "emergencyStop", "jointMove,emergencyStop/t")
    assert_kept_running(lines)


def test_a_nan_written_fails_the_pf_and_is_not_sent(system: Path) -> None:
    lines = trace(system, "nan")
    states = manip(lines)
    assert [s for _, s, _ in states] == ["idle", "jointMove", "emergencyStop"], states
    # the NaN comes in NAN_FROM .. NAN_UNTIL - 1: the pf fails in jointMove, and again in
    # emergencyStop, reported once in each state (a state entered makes every pf healthy again)
    failure = "manip/a.cs: outputMotorCon/pf failed: a non-finite number in motorControllerCommandK/ob"
    assert failures(lines) == [f"step {NAN_FROM} {failure}", f"step {NAN_FROM + 1} {failure}"]
    assert states[2] == (NAN_FROM + 1, "emergencyStop", "jointMove,emergencyStop/t")
    sent = [line for line in lines if re.match(rf"^step {NAN_FROM} manip/a\.cs: i ", line)]
    assert sent and "nan" in sent[0]  # the pf wrote it (its own trace), the runtime did not send it
    assert_kept_running(lines)


def test_with_the_report_policy_a_nan_is_reported_once_and_changes_no_state(system: Path) -> None:
    """The NaN is sent: the motor controller and the motor it reaches turn NaN too (the sample's
    simulated joint 3 never recovers), each pf reported once per buffer, no flood; no pf fails,
    so manip/a.cs stays in jointMove (the joint never reaches its setpoint)."""
    lines = trace(system, "nan", "--non-finite", "report")
    assert [s for _, s, _ in manip(lines)] == ["idle", "jointMove"]
    reports = failures(lines)
    assert reports[0] == (f"step {NAN_FROM} manip/a.cs: outputMotorCon/pf wrote a non-finite number "
                          "into motorControllerCommandK/ob (sent)")
    assert not [line for line in reports if " failed: " in line]
    pairs = [re.sub(r"^step \d+ ", "", line) for line in reports]
    assert len(pairs) == len(set(pairs)) <= 8, reports
    assert_kept_running(lines)


def test_without_a_fault_the_run_is_the_samples(system: Path) -> None:
    lines = trace(system, "")
    assert [s for _, s, _ in manip(lines)] == ["idle", "jointMove", "idle", "emergencyStop"]
    assert failures(lines) == []


def test_a_policy_that_is_not_one_is_refused(system: Path) -> None:
    result = run(system, "--non-finite", "ignore")
    assert result.returncode == 2
    assert "--non-finite" in result.stderr


@pytest.mark.parametrize("fault", ["fail", "nan"])
def test_the_failure_path_allocates_nothing(generated: Path, fault: str) -> None:
    """bench/cpp/alloc_main.cpp over the faulty build: one start-up cycle, then the cycles in
    which the pf fails (fail() at manip/a.cs's third, NaN from its 100th) are counted."""
    binary = compile_(generated, generated.parent / "alloc_main", "alloc_main.cpp", "count_new.cpp")
    result = subprocess.run([str(binary), "--startup", "1", "--cycles", "2000", "--threaded", "0"],
                            capture_output=True, text=True, timeout=120, env={**os.environ, "EARL_FAULT": fault})
    assert result.returncode == 0, result.stderr
    [report] = [json.loads(line) for line in result.stdout.splitlines() if line.startswith('{"')]
    assert report["allocations"] == 0, report
