"""The harmoniser sample runs as C++: ``samples/harmoniser`` generated with its shipped user code
(``samples/harmoniser/user/``), built with CMake (warnings are errors) and run by the system
executor, deterministically (twice, byte-identical) and threaded (50 runs with one busy process
per CPU, each passing ``tests/support/harmoniser_checks.py``). The scripted lidar sees the
person fall once and get up again: tha/a switches guiding → fallResponse → guiding. guide/a,
whose reactivation is ``resume``, sees ``leaving()``, parks and stops in ``waiting``; brought
back, it goes on from that state with its memory: the waypoints it leads to carry on from the
last one before the fall, its commands' numbers too, and its FSM leaves ``waiting`` again at
the next step of its own count.
fallHelp/a, brought in for the first time, starts from its initial state.

Sensitivity controls: a build that skips the drain (``-DEARL_SWITCH_DRAIN=0``) fails the checks
in a loaded run; the same sample with guide/a restarted instead (its ``reactivation`` tag
taken out of the SysML v2 file) leads from the first waypoint again after the fall, which the
checks of the resumed agent reject.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from tests.support import harmoniser_checks
from tests.support.cpp_sample import cmake_build, generate_with_user_code, run
from tests.support.load import cpu_hogs, run_until

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "harmoniser" / "harmoniser.uml"
SAMPLE_SYSML = SAMPLE.with_suffix(".sysml")
USER = SAMPLE.parent / "user"
# GuideAgent's tag reactivation = resume, and the line after it, in the SysML v2 file
GUIDE_RESUMES = ("            @AgentReactivation { reactivation = Reactivation::resume; }\n"
                 "            part cs : GuideControl;\n")
CYCLES = 140
LOADED_RUNS = 50
THREADED_SECONDS = 0.5  # the fall is at the lidar's 40th scan, the person up at its 70th: 1 ms each

LEAD = re.compile(r"^guide/a\.cs: lead to waypoint (\d+)$")
PARK = re.compile(r"^guide/a\.cs: park after command (\d+)$")
ASSIST = re.compile(r"^fallHelp/a\.cs: assist step (\d+)$")
SWITCH = re.compile(r"^switch (\w+) -> (\w+) in \d+ cycles$")
GUIDE_STEP = re.compile(r"^step (\d+) guide/a\.cs: (\w+) -> (\w+) ")

pytestmark = pytest.mark.skipif(shutil.which("g++") is None or shutil.which("cmake") is None,
                                reason="g++ and cmake are needed")


def build(model: Path, folder: Path, *flags: str) -> Path:
    """The sample's user code copied into ``folder/out``, gen run over it for ``model``, built."""
    out = generate_with_user_code(model, USER, folder / "out")
    return cmake_build(out, folder / "build", "Harmoniser_system", *flags)


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
    switches = [(m.group(1), m.group(2)) for m in map(SWITCH.match, trace) if m]
    assert switches == [("none", "guiding"), ("guiding", "fallResponse"), ("fallResponse", "guiding")]
    assert not [line for line in trace if "undelivered at switch" in line or "overflowed" in line]


def assert_resumed(trace: list[str]) -> None:
    """Asserts that guide/a, resumed after the fall, goes on from its state and memory."""
    fall = next(i for i, line in enumerate(trace) if SWITCH.match(line) and "-> fallResponse" in line)
    back = next(i for i, line in enumerate(trace) if SWITCH.match(line) and "fallResponse -> guiding" in line)
    before, after = trace[:fall], trace[back:]

    # the waypoints carry on: 1, 2, … up to the fall, then the next one, never 1 again
    waypoints_before = [int(m.group(1)) for m in map(LEAD.match, before) if m]
    waypoints_after = [int(m.group(1)) for m in map(LEAD.match, after) if m]
    assert waypoints_before == list(range(1, len(waypoints_before) + 1)) and len(waypoints_before) > 1
    assert waypoints_after[0] == waypoints_before[-1] + 1
    assert waypoints_after == list(range(waypoints_after[0], waypoints_after[0] + len(waypoints_after)))
    assert not [line for line in trace[fall:back] if LEAD.match(line)]  # stopped while fallResponse holds

    # its FSM: leaving() took it from leading to waiting, and it resumes in waiting at its next step
    guide_steps = [(int(m.group(1)), m.group(2), m.group(3)) for m in map(GUIDE_STEP.match, trace) if m]
    stopped = next((s for s in guide_steps if s[1:] == ("leading", "waiting")), None)
    assert stopped is not None
    resumed = [s for s in guide_steps if s[0] > stopped[0]]
    assert resumed[0] == (stopped[0] + 1, "waiting", "leading")
    assert not any(line.startswith("step 0 guide/a.cs: start") for line in after)

    # its memory: the resumed park (in waiting, where it stopped) numbers its command after the
    # ones sent before the fall
    commands_before = waypoints_before[-1] + 1  # the first park, then one command per waypoint
    (first_park_after, *_) = [int(m.group(1)) for m in map(PARK.match, after) if m]
    assert first_park_after == commands_before + 1


def test_the_resumed_guide_agent_goes_on_from_its_state_and_memory(trace: list[str]) -> None:
    assert_resumed(trace)


def test_a_restarted_guide_agent_fails_the_checks(tmp_path: Path) -> None:
    text = SAMPLE_SYSML.read_text(encoding="utf-8")
    assert text.count(GUIDE_RESUMES) == 1
    restarted = tmp_path / "harmoniser.sysml"
    restarted.write_text(text.replace(GUIDE_RESUMES, "            part cs : GuideControl;\n"), encoding="utf-8")
    lines = run(build(restarted, tmp_path), "--cycles", str(CYCLES)).splitlines()
    back = next(i for i, line in enumerate(lines) if line.startswith("switch fallResponse -> guiding"))
    assert next(m for m in map(LEAD.match, lines[back:]) if m).group(1) == "1"
    with pytest.raises(AssertionError):
        assert_resumed(lines)
    assert harmoniser_checks.resumed_problems(lines)


def test_the_stepped_run_passes_the_checks_of_every_runtime(trace: list[str]) -> None:
    assert harmoniser_checks.problems(trace) == []


def threaded_run(binary: Path) -> list[str]:
    lines, _ = run_until([binary, "--threaded", str(THREADED_SECONDS)],
                         lambda out: bool(out) and out[-1].startswith("ran HarmoniserSystem"), 30, graceful=False)
    return lines


def test_threaded_runs_under_load_resume_the_guide_agent(binary: Path) -> None:
    failures, latencies = [], []
    with cpu_hogs():
        for attempt in range(LOADED_RUNS):
            lines = threaded_run(binary)
            latencies += harmoniser_checks.latencies_ms(lines)
            found = harmoniser_checks.problems(lines)
            if found:
                failures.append(f"run {attempt + 1}: {found[:4]}")
    assert not failures, f"{len(failures)} of {LOADED_RUNS} runs failed:\n" + "\n".join(failures)
    latencies.sort()
    print(f"harmoniser C++ threaded: {LOADED_RUNS} runs, {len(latencies)} switches, median "
          f"{latencies[len(latencies) // 2]:.3f} ms, worst {latencies[-1]:.3f} ms")


def test_the_checks_catch_a_switch_that_skips_the_drain(tmp_path: Path) -> None:
    """Built with the drain skipped (test-only), guide/a stops at once, wherever it is: it is
    not resumed in waiting, which the checks see in at least one loaded run."""
    undrained = build(SAMPLE, tmp_path, "-DEARL_SWITCH_DRAIN=0")
    with cpu_hogs():
        caught = next((attempt for attempt in range(LOADED_RUNS)
                       if harmoniser_checks.problems(threaded_run(undrained))), None)
    assert caught is not None, f"all {LOADED_RUNS} runs of the drain-skipping build passed the checks"


def test_the_fall_help_agent_starts_from_its_initial_state(trace: list[str]) -> None:
    steps = [int(m.group(1)) for m in map(ASSIST.match, trace) if m]
    assert steps == list(range(1, len(steps) + 1)) and len(steps) > 1
    assert "step 1 fallHelp/a.cs: waiting -> helping (waiting,helping/t)" in trace
