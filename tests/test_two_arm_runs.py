"""The variable-structure sample runs as C++: ``samples/two_arm`` generated with its shipped user
code (``samples/two_arm/user/``), built with CMake (warnings are errors) and run by the system
executor. task/a.cs sends 201 numbered commands and hands the job over between manipA/a and
manipB/a 20 times (configurations useA and useB); each arm prints the seq of every command it
takes, task/a the arm it sent each one to, the runtime every switch and every value a switch
could not deliver.

* deterministic: two runs give byte-identical traces, and pass the checks below;
* threaded, with one busy process per CPU: 50 runs, every one passes the checks below;
* 0 heap allocations per cycle, switches included, stepped and threaded;
* sensitivity control: a build that skips the drain (``-DEARL_SWITCH_DRAIN=0``, test-only)
  fails the checks in at least one of 50 threaded runs;
* forced switches (``switchTimeout = 0.001``): every command is taken or named undelivered at a
  switch, including the one a manipulator had taken and not yet run its pfs on; a build that
  forgets that value (``-DEARL_SWITCH_SETTLE=0``, test-only) fails the deterministic check.

The checks: every numbered command is taken exactly once, by the arm of the configuration it
was sent in; no value is undelivered at a switch and no queue overflows; 20 switches, each
within the configuration's switchTimeout (100 ms: 100 cycles of 1 ms, or 100 ms measured).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.campaign import catch_runs, loaded_runs
from tests.support.cpp_sample import cmake_build, generate_with_user_code, run
from tests.support.load import cpu_hogs, run_until
from tests.support.switch_checks import SWITCH, TwoArm, forced_switches, forced_two_arm

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "two_arm" / "two_arm.uml"
USER = SAMPLE.parent / "user"
COMMANDS = TwoArm.COMMANDS
SWITCHES = TwoArm.SWITCHES
TIMEOUT_MS = TwoArm.TIMEOUT_MS
CYCLES = 6000
CAMPAIGN = "cpp two_arm"  # tests/support/campaigns.toml
FORCED_CAMPAIGN = "cpp two_arm forced"
LOADED_RUNS = loaded_runs(CAMPAIGN)
RUN_TIMEOUT = 10.0  # s per threaded run: the sample needs about 0.25 s

pytestmark = pytest.mark.skipif(shutil.which("g++") is None or shutil.which("cmake") is None,
                                reason="g++ and cmake are needed")


def build(out: Path, *flags: str) -> Path:
    return cmake_build(out, "TwoArm_system", *flags)


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """gen's output: the sample's user code copied into an empty folder, gen run over it."""
    return generate_with_user_code(SAMPLE, USER, tmp_path_factory.mktemp("two_arm") / "out")


@pytest.fixture(scope="module")
def drained(generated: Path) -> Path:
    return build(generated)


@pytest.fixture(scope="module")
def undrained(generated: Path) -> Path:
    return build(generated, "-DEARL_SWITCH_DRAIN=0")


@pytest.fixture(scope="module")
def forced_generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The sample with switchTimeout = 0.001 (1 ms, one coordinator cycle), generated."""
    model = forced_two_arm(tmp_path_factory.mktemp("two_arm_forced"))
    out = model.parent / "out"
    shutil.copytree(model.parent / "user", out / "user")
    run(sys.executable, "-m", "earl_m2t", "gen", model, "--target", "cpp", "-o", out, "--force")
    return out


@pytest.fixture(scope="module")
def forced(forced_generated: Path) -> Path:
    return build(forced_generated)


@pytest.fixture(scope="module")
def unsettled(forced_generated: Path) -> Path:
    return build(forced_generated, "-DEARL_SWITCH_SETTLE=0")


problems = TwoArm.problems
finished = TwoArm.finished


def threaded_run(binary: Path) -> list[str]:
    lines, _ = run_until([binary, "--threaded", str(RUN_TIMEOUT)], finished, RUN_TIMEOUT, graceful=False)
    return lines


def test_the_deterministic_run_is_repeatable_and_hands_every_command_over(drained: Path) -> None:
    first = run(drained, "--cycles", str(CYCLES)).splitlines()
    assert run(drained, "--cycles", str(CYCLES)).splitlines() == first
    assert problems(first) == []
    assert all(m.group(4) == "cycles" for m in map(SWITCH.match, first) if m)
    assert first[-1] == f"ran TwoArmCell for {CYCLES} cycles"


def test_each_arm_resets_its_pfs_every_time_it_restarts(drained: Path) -> None:
    """Every runtime calls a restarting arm's pf reset() (21 starts: manipA/a's first and 10 of
    each arm after a switch); the check sees one that a runtime skipped."""
    lines = run(drained, "--cycles", str(CYCLES)).splitlines()
    resets = [line for line in lines if TwoArm.RESET.match(line)]
    assert len(resets) == SWITCHES + 1 and TwoArm.not_reset_at_restart(lines) == []
    skipped = resets[len(resets) // 2]
    assert TwoArm.not_reset_at_restart([line for line in lines if line != skipped])


@pytest.mark.loaded
def test_threaded_runs_under_load_hand_every_command_over(drained: Path) -> None:
    failures, latencies = [], []
    with cpu_hogs():
        for attempt in range(LOADED_RUNS):
            lines = threaded_run(drained)
            latencies += [float(m.group(3)) for m in map(SWITCH.match, lines) if m]
            found = problems(lines)
            if found:
                failures.append(f"run {attempt + 1}: {found}")
    assert not failures, f"{len(failures)} of {LOADED_RUNS} runs failed:\n" + "\n".join(failures)
    latencies.sort()
    print(f"two_arm C++ threaded: {LOADED_RUNS} runs, {len(latencies)} switches, median "
          f"{latencies[len(latencies) // 2]:.3f} ms, worst {latencies[-1]:.3f} ms")


@pytest.mark.loaded
def test_the_checks_catch_a_switch_that_skips_the_drain(undrained: Path) -> None:
    assert problems(run(undrained, "--cycles", str(CYCLES)).splitlines())
    with cpu_hogs():
        caught = next((attempt for attempt in range(catch_runs(CAMPAIGN)) if problems(threaded_run(undrained))), None)
    assert caught is not None, f"all {catch_runs(CAMPAIGN)} runs of the drain-skipping build passed the checks"


def test_a_forced_switch_names_every_command_it_loses(forced: Path) -> None:
    """Deterministic: every switch is forced (its timeout is one cycle), and each one finds the
    command the leaving arm took in its last iteration and had not yet run its pfs on."""
    lines = run(forced, "--cycles", str(CYCLES)).splitlines()
    assert TwoArm.unreconciled(lines) == []
    assert forced_switches(lines) == SWITCHES
    assert any(TwoArm.NAMED.match(line) for line in lines)


@pytest.mark.loaded
def test_threaded_forced_switches_under_load_name_every_command_they_lose(forced: Path) -> None:
    failures, count = [], 0
    with cpu_hogs():
        for attempt in range(loaded_runs(FORCED_CAMPAIGN)):
            lines = threaded_run(forced)
            count += forced_switches(lines)
            found = TwoArm.unreconciled(lines)
            if found:
                failures.append(f"run {attempt + 1}: {found}")
    assert not failures, "\n".join(failures)
    print(f"two_arm C++ threaded, switchTimeout 1 ms: {loaded_runs(FORCED_CAMPAIGN)} runs, "
          f"{count} forced switches, every command taken or named")


def test_the_deterministic_checks_catch_a_forced_switch_that_forgets_the_value_taken(unsettled: Path) -> None:
    """The runtime of before: the value a leaving arm took in its last iteration is neither run
    through its pfs nor counted. Deterministic, where every switch is forced (a threaded run on a
    quiet machine forces few: 3 switches in 20 runs under load, 1 of them caught)."""
    lines = run(unsettled, "--cycles", str(CYCLES)).splitlines()
    assert forced_switches(lines) == SWITCHES
    assert len(TwoArm.unreconciled(lines)) >= SWITCHES // 2, TwoArm.unreconciled(lines)


def test_no_heap_allocation_per_cycle_switches_included(generated: Path) -> None:
    binary = generated.parent / "two_arm_alloc"
    sources = ROOT / "bench" / "cpp"
    run("g++", "-std=c++17", "-O2", "-DNDEBUG", "-Wall", "-Wextra", "-Werror", "-pthread",
        f"-I{generated / 'runtime'}", f"-I{generated / 'generated' / 'include'}", f"-I{generated / 'user'}",
        f"-I{sources}", ROOT / "tests" / "cpp" / "two_arm_alloc.cpp", sources / "count_new.cpp", "-o", binary)
    result = subprocess.run([str(binary), "--cycles", str(CYCLES), "--threaded", "0.5"], capture_output=True,
                            text=True, timeout=60, env={**os.environ, "TWO_ARM_QUIET": "1"})
    assert result.returncode == 0, result.stderr
    [report] = [json.loads(line) for line in result.stdout.splitlines() if line.startswith("{\"")]
    assert report["switches"] == SWITCHES and report["threaded_switches"] == SWITCHES, report
    assert report["allocations"] == 0 and report["threaded_allocations"] == 0, report
    assert report["threaded_start_allocations"] > 0  # creating the threads allocates: the counter works
