"""Variable structure in the C++ runtime, on a hand-written system: task/a hands numbered
commands over between manipA/a and manipB/a, 20 switches per run. Each test runs twice:

* ``tests/cpp/test_switch.cpp``: the switch of one process (``earl/switch.hpp``);
* ``tests/cpp/test_switch_protocol.cpp``: the switch in rounds between nodes that share no
  memory (``earl/switch_protocol.hpp``, what the ROS and Orocos targets carry), each subsystem
  a node whose values, commands and acknowledgements go through in-order pipes.

The checks:

* deterministic: two runs give byte-identical traces; every command is received exactly once,
  in order, by the manipulator of the configuration it was sent in; nothing is undelivered;
* a short switch timeout: the switch ends by it within the timeout, and every command is
  received or counted undelivered, never both, never lost silently;
* rounds: a node that acknowledges the stop late makes the coordinator force it after the
  others acknowledged it; they acknowledge the forced round again and the switch ends; with
  every round slowed as well, it still ends by its timeout;
* threaded, one busy process per CPU: the same in every run, 0 heap allocations while running;
* sensitivity control: a build that skips the drain (``-DEARL_SWITCH_DRAIN=0``, test-only)
  fails these checks in at least one run, so the checks can fail.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.support.campaign import catch_runs, loaded_runs
from tests.support.load import cpu_hogs

ROOT = Path(__file__).resolve().parents[1]
RUNTIME = ROOT / "transforms" / "cpp" / "runtime"
SOURCES = {"one-process": ROOT / "tests" / "cpp" / "test_switch.cpp",
           "rounds": ROOT / "tests" / "cpp" / "test_switch_protocol.cpp"}
CXXFLAGS = ["-std=c++17", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", "-pthread"]
SWITCHES = 20
PER = 50  # commands per configuration
TIMEOUT_MS = 50.0
CAMPAIGN = "cpp switch"  # tests/support/campaigns.toml
THREADED_RUNS = loaded_runs(CAMPAIGN)
SWITCH_LINE = re.compile(r"^switch (useA -> useB|useB -> useA) in (\d+) cycles$")

pytestmark = pytest.mark.skipif(shutil.which("g++") is None, reason="g++ is needed")


def build(source: Path, folder: Path, *defines: str) -> Path:
    binary = folder / source.stem
    command = ["g++", *CXXFLAGS, *defines, "-I", str(RUNTIME), str(source), "-o", str(binary)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"build failed:\n{result.stderr}"
    return binary


@pytest.fixture(scope="module", params=sorted(SOURCES))
def source(request: pytest.FixtureRequest) -> Path:
    return SOURCES[request.param]


@pytest.fixture(scope="module")
def drained(source: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build(source, tmp_path_factory.mktemp("switch"))


@pytest.fixture(scope="module")
def undrained(source: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build(source, tmp_path_factory.mktemp("switch_undrained"), "-DEARL_SWITCH_DRAIN=0")


def run(binary: Path, *args: str) -> list[str]:
    result = subprocess.run([str(binary), *args, "--switches", str(SWITCHES), "--per", str(PER)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout.splitlines()


def summary(lines: list[str]) -> dict[str, int | str]:
    words = lines[-1].split()
    assert words[0] == "summary", lines[-1]
    return {key: int(value) if value.lstrip("-").isdigit() else value for key, value in zip(words[1::2], words[2::2])}


def violations(s: dict[str, int | str], timeout_ms: float = TIMEOUT_MS) -> list[str]:
    """What a correct switch must never show: empty when every command was received exactly
    once, in order, by the manipulator of its configuration, and every switch kept its bound."""
    found = [f"{key} {s[key]}" for key in ("lost", "duplicates", "misrouted", "out_of_order", "overlaps",
                                            "undelivered", "overflows", "timeouts", "allocations", "dropped")
             if s.get(key, 0) != 0]
    if s["sent"] != (SWITCHES + 1) * PER or s["received"] != s["sent"]:
        found.append(f"sent {s['sent']} received {s['received']}")
    if s["switches"] != SWITCHES:
        found.append(f"switches {s['switches']}")
    if int(s["max_latency_ns"]) > timeout_ms * 1e6:
        found.append(f"latency {s['max_latency_ns']} ns")
    if s["forced"] != s["timeouts"]:
        found.append(f"{s['timeouts']} timeouts, {s['forced']} switches reported forced")
    return found


def forced_lines(lines: list[str]) -> int:
    """The switch lines that say the switch was forced."""
    return sum(line.startswith("switch ") and line.endswith(" (forced)") for line in lines)


def test_the_deterministic_run_is_repeatable_and_loses_nothing(drained: Path) -> None:
    first = run(drained, "--cycles", "3000")
    assert run(drained, "--cycles", "3000") == first
    s = summary(first)
    assert violations(s) == [] and s["forced"] == 0
    switches = [SWITCH_LINE.match(line) for line in first if line.startswith("switch ")]
    assert len(switches) == SWITCHES and all(switches)
    assert all(1 <= int(m.group(2)) <= TIMEOUT_MS for m in switches if m)  # 1 cycle = 1 ms
    # the task enters its new state only once the switch has opened
    for index, line in enumerate(first):
        if line.startswith("switch "):
            assert re.match(r"^step \d+ task/a\.cs: with(A|B) -> with(A|B) ", first[index + 1]), first[index + 1]
    # manipA/a restarts (FSM at idle again: a start line each time it joins), manipB/a resumes
    assert s["restarts_a"] == SWITCHES // 2 and s["restarts_b"] == 1
    assert sum(line.startswith("step ") and "manipA/a.cs: start in idle" in line for line in first) == SWITCHES // 2 + 1
    assert sum("manipB/a.cs: start in idle" in line for line in first) == 1
    assert s["statuses"] == "yes"


def test_a_switch_ends_by_its_timeout_and_counts_what_it_clears(drained: Path) -> None:
    lines = run(drained, "--cycles", "3000", "--timeout-ms", "5")
    s = summary(lines)
    assert s["timeouts"] == SWITCHES and s["switches"] == SWITCHES
    assert s["forced"] == forced_lines(lines) == SWITCHES  # each switch line says so
    assert s["max_latency_cycles"] <= 5
    assert int(s["undelivered"]) > 0 and s["lost"] == s["undelivered"]  # counted once, never silent
    assert s["duplicates"] == s["misrouted"] == s["out_of_order"] == s["overlaps"] == 0
    reported = sum(int(m.group(1)) for m in map(re.compile(r"^link task/a,manip[AB]/a: (\d+) value\(s\) "
                                                            r"undelivered at switch$").match, lines) if m)
    assert reported == s["undelivered"]


def test_a_stop_forced_after_some_nodes_acknowledged_it_is_acknowledged_again(tmp_path: Path) -> None:
    """manipA/a's node answers the stop round late (as a node asleep until its next data): the
    coordinator forces the stop after the other nodes acknowledged the unforced one, and the
    switch must still end, by its timeout, with every command delivered."""
    rounds = build(SOURCES["rounds"], tmp_path)  # the one-process switch has no acknowledgements
    lines = run(rounds, "--cycles", "6000", "--late-stop-ack", "100")
    s = summary(lines)
    assert s["switches"] == SWITCHES and s["timeouts"] == SWITCHES, s
    assert s["forced"] == forced_lines(lines) == SWITCHES
    assert s["max_latency_cycles"] <= TIMEOUT_MS
    assert s["sent"] == s["received"] == (SWITCHES + 1) * PER and s["lost"] == s["undelivered"] == 0


def test_slow_rounds_force_the_stop_earlier_so_the_switch_still_ends_by_its_timeout(tmp_path: Path) -> None:
    """Besides the late stop, manipB/a's node answers every round two loops late (a busy node,
    a slow transport): the rounds a forced switch still takes are each that much slower, so
    the coordinator must force the stop that much earlier, from the rounds it measured, for
    the switch to end by its timeout. Forcing a fixed poll per round before it ends 8 cycles
    late."""
    rounds = build(SOURCES["rounds"], tmp_path)
    s = summary(run(rounds, "--cycles", "8000", "--late-stop-ack", "100", "--slow-acks", "2"))
    assert s["switches"] == SWITCHES and s["timeouts"] == SWITCHES, s
    assert s["max_latency_cycles"] <= TIMEOUT_MS, s
    assert s["sent"] == s["received"] == (SWITCHES + 1) * PER and s["lost"] == s["undelivered"] == 0


@pytest.mark.loaded
def test_threaded_runs_under_load_deliver_every_command_once(drained: Path) -> None:
    failures = []
    with cpu_hogs():
        for attempt in range(THREADED_RUNS):
            found = violations(summary(run(drained, "--threaded")))
            if found:
                failures.append(f"run {attempt + 1}: {found}")
    assert not failures, "\n".join(failures)


@pytest.mark.loaded
def test_the_checks_catch_a_switch_that_skips_the_drain(undrained: Path) -> None:
    assert violations(summary(run(undrained, "--cycles", "3000")))
    with cpu_hogs():
        caught = next((attempt for attempt in range(1, catch_runs(CAMPAIGN) + 1)
                       if violations(summary(run(undrained, "--threaded")))), None)
    assert caught is not None, f"all {catch_runs(CAMPAIGN)} runs of the drain-skipping build passed the checks"
