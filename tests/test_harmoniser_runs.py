"""The harmoniser sample runs as C++: ``samples/harmoniser`` generated with its shipped user code
(``samples/harmoniser/user/``), built with CMake (warnings are errors) and run by the system
executor, deterministically (twice, byte-identical) and threaded (50 runs with one busy process
per CPU, each passing every check of ``Harmoniser.problems``). The scripted lidar sees the
person fall once and get up again: tha/a switches guiding → fallResponse → guiding. guide/a,
whose reactivation is ``resume``, sees ``leaving()``, parks and stops in ``waiting``; brought
back, it goes on from that state with its memory: the waypoints it leads to carry on from the
last one before the fall, its commands' numbers too, and its FSM leaves ``waiting`` again at
the next step of its own count. fallHelp/a, brought in for the first time, starts from its
initial state.

tiago/a takes every command of the task agents once, in order, those a leaving agent sends in
its last iterations included (its links to tiago/a, which stays, are open until it stops).

Sensitivity controls: a build that skips the drain (``-DEARL_SWITCH_DRAIN=0``) fails the checks
in a loaded run; one that closes a leaving agent's links at the decision
(``-DEARL_SWITCH_LINGER=0``) loses its last commands, each counted as written while closed;
the same sample with guide/a restarted instead (its ``reactivation`` tag
taken out of the SysML v2 file) leads from the first waypoint again after the fall, which the
checks of the resumed agent reject.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from tests.support.campaign import catch_runs, loaded_runs
from tests.support.cpp_sample import cmake_build, generate_with_user_code, run
from tests.support.load import cpu_hogs, run_until
from tests.support.switch_checks import (
    SWITCH,
    Harmoniser,
    latencies_ms,
    latency_summary,
    restarted_harmoniser,
    switches,
    undelivered,
)

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "harmoniser" / "harmoniser.uml"
USER = SAMPLE.parent / "user"
CYCLES = 230
CAMPAIGN = "cpp harmoniser"  # tests/support/campaigns.toml
LOADED_RUNS = loaded_runs(CAMPAIGN)
WRITTEN_CLOSED = re.compile(r"^link (\S+): (\d+) value\(s\) written while closed$")
THREADED_SECONDS = 0.5  # the fall is at the lidar's 40th scan, the person up at its 160th: 1 ms each

pytestmark = pytest.mark.skipif(shutil.which("g++") is None or shutil.which("cmake") is None,
                                reason="g++ and cmake are needed")


def build(model: Path, folder: Path, *flags: str) -> Path:
    """The sample's user code copied into ``folder/out``, gen run over it for ``model``, built."""
    out = generate_with_user_code(model, USER, folder / "out")
    return cmake_build(out, "Harmoniser_system", *flags)


@pytest.fixture(scope="module")
def binary(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build(SAMPLE, tmp_path_factory.mktemp("harmoniser"))


@pytest.fixture(scope="module")
def trace(binary: Path) -> list[str]:
    first = run(binary, "--cycles", str(CYCLES)).splitlines()
    assert run(binary, "--cycles", str(CYCLES)).splitlines() == first
    assert first[-1] == f"ran HarmoniserSystem for {CYCLES} cycles"
    return first


def test_the_fall_switches_to_fall_response_and_back(trace: list[str]) -> None:
    assert switches(trace) == Harmoniser.SWITCHES
    assert all(m.group(4) == "cycles" for m in map(SWITCH.match, trace) if m)
    assert not undelivered(trace)


assert_resumed = Harmoniser.assert_resumed


def test_the_resumed_guide_agent_goes_on_from_its_state_and_memory(trace: list[str]) -> None:
    assert_resumed(trace)


def test_a_restarted_guide_agent_fails_the_checks(tmp_path: Path) -> None:
    lines = run(build(restarted_harmoniser(tmp_path / "model"), tmp_path), "--cycles", str(CYCLES)).splitlines()
    assert Harmoniser.first_waypoint_back(lines) == 1
    with pytest.raises(AssertionError):
        assert_resumed(lines)


def test_the_fall_help_agent_starts_from_its_initial_state(trace: list[str]) -> None:
    steps = Harmoniser.assist_steps(trace)
    assert steps == list(range(1, len(steps) + 1)) and len(steps) > 1
    assert "step 1 fallHelp/a.cs: waiting -> helping (waiting,helping/t)" in trace


def test_the_stepped_run_passes_the_checks_of_every_runtime(trace: list[str]) -> None:
    assert Harmoniser.problems(trace) == []


def test_tiago_takes_what_a_leaving_agent_sends_in_its_last_iterations(trace: list[str]) -> None:
    """guide/a leaving, and fallHelp/a, send a park or stand-by command in each iteration until
    they stop; the links to tiago/a, which stays, are open until then: tiago/a takes every one."""
    taken = [int(m.group(1)) for m in map(Harmoniser.TOOK.match, trace) if m]
    fall = Harmoniser.resumed_at(trace)[0]
    last_before_fall = max(int(m.group(1)) for m in map(Harmoniser.PARK.match, trace[:fall]) if m)
    assert last_before_fall in taken and taken.index(last_before_fall) < taken.index(1, 1)
    assert Harmoniser.commands_not_taken_once(trace) == []
    assert not [line for line in trace if "written while closed" in line and ",tiago/a:" in line]


def test_links_closed_at_the_decision_lose_the_last_sends_and_count_them(tmp_path: Path) -> None:
    """The closed-gate behaviour of before (test-only ``-DEARL_SWITCH_LINGER=0``: a leaving
    agent's links to tiago/a close when the switch is decided): its last sends are skipped, which
    the checks catch, and each one is counted as written while closed, none silently."""
    lines = run(build(SAMPLE, tmp_path, "-DEARL_SWITCH_LINGER=0"), "--cycles", str(CYCLES)).splitlines()
    assert Harmoniser.commands_not_taken_once(lines)
    taken = [int(m.group(1)) for m in map(Harmoniser.TOOK.match, lines) if m]
    _, fall_help = Harmoniser.commands_sent(lines)
    # guide/a's numbering runs on across the fall: it sent 1 … the last one taken
    missing = taken[-1] + max(fall_help) - len(taken)
    closed = {m.group(1): int(m.group(2)) for m in map(WRITTEN_CLOSED.match, lines) if m}
    assert missing > 0 and closed.get("guide/a,tiago/a", 0) + closed.get("fallHelp/a,tiago/a", 0) == missing, lines[-6:]


def threaded_run(binary: Path) -> list[str]:
    lines, _ = run_until([binary, "--threaded", str(THREADED_SECONDS)],
                         lambda out: bool(out) and out[-1].startswith("ran HarmoniserSystem"), 30, graceful=False)
    return lines


@pytest.mark.loaded
def test_threaded_runs_under_load_resume_the_guide_agent(binary: Path) -> None:
    failures, latencies = [], []
    with cpu_hogs():
        for attempt in range(LOADED_RUNS):
            lines = threaded_run(binary)
            latencies += latencies_ms(lines)
            found = Harmoniser.problems(lines)
            if found:
                failures.append(f"run {attempt + 1}: {found[:4]}")
    assert not failures, f"{len(failures)} of {LOADED_RUNS} runs failed:\n" + "\n".join(failures)
    print(f"harmoniser C++ threaded: {LOADED_RUNS} runs, {latency_summary(latencies)}")


@pytest.mark.loaded
def test_the_checks_catch_a_switch_that_skips_the_drain(tmp_path: Path) -> None:
    """Built with the drain skipped (test-only), guide/a stops at once, wherever it is: it is
    not resumed in waiting, which the checks see in at least one loaded run."""
    undrained = build(SAMPLE, tmp_path, "-DEARL_SWITCH_DRAIN=0")
    with cpu_hogs():
        caught = next((attempt for attempt in range(catch_runs(CAMPAIGN))
                       if Harmoniser.problems(threaded_run(undrained))), None)
    assert caught is not None, f"all {catch_runs(CAMPAIGN)} runs of the drain-skipping build passed the checks"
