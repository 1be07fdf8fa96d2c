"""The threaded C++ runtime wakes on data and takes real-time settings.

* ``tests/cpp/test_wake.cpp`` (built with g++, run): an event-driven subsystem wakes on every
  write into its obligatory input before its timeout and never runs without it outside a
  timeout; one whose input never comes runs at its timeout; ``stop()`` returns promptly with
  every thread asleep.
* The sample's generated system executable (g++ over the generated code) runs each
  event-driven subsystem in a thread of its own and the periodic ones in one thread per period
  and settings (``--threads subsystem``: a thread each); it applies
  ``--priority``, ``--cpu`` and ``--mlockall`` in the subsystems' threads, and refuses, in one
  line naming the subsystem, the setting and the reason, what it cannot apply: a priority out
  of 1..99 or an unknown subsystem before anything starts (exit 2), a CPU that does not exist
  and a SCHED_FIFO priority without CAP_SYS_NICE (exit 3).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import generate
from earl_m2t.model.elements import Activation

ROOT = Path(__file__).resolve().parents[1]
RUNTIME = ROOT / "transforms" / "cpp" / "runtime"
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
CXXFLAGS = ["-std=c++17", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", "-pthread"]
SCHED_FIFO = 1

pytestmark = pytest.mark.skipif(shutil.which("g++") is None, reason="g++ is needed")


def build(binary: Path, source: Path, *includes: Path) -> Path:
    flags = [f"-I{i}" for i in includes]
    result = subprocess.run(["g++", *CXXFLAGS, *flags, str(source), "-o", str(binary)],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"build failed:\n{result.stderr}"
    return binary


def test_threaded_runner_wakes_on_data_at_timeouts_and_at_stop(tmp_path: Path) -> None:
    binary = build(tmp_path / "test_wake", ROOT / "tests" / "cpp" / "test_wake.cpp", RUNTIME)
    result = subprocess.run([str(binary)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0 and result.stdout == "ok\n", result.stdout + result.stderr


def event_driven_subsystems() -> int:
    """How many of the sample's subsystem instances have activation (a thread of their own)."""
    model = load(SAMPLE).model
    assert model.system is not None
    return sum(1 for agent in model.system.agents for sub in agent.subsystems
               if sub.buffer_groups or any(s.activation != Activation() for s in (sub.fsm.states if sub.fsm else ())))


@pytest.fixture(scope="module")
def system(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wake") / "gen"
    generate(load(SAMPLE).model, out)
    return build(out / "system", out / "generated" / "src" / "system_main.cpp",
                 out / "runtime", out / "generated" / "include", out / "user")


def run(*command: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=60)


def thread_settings(pid: int) -> list[tuple[int, int, frozenset[int]]]:
    """(policy, rt priority, CPUs) of every thread of ``pid`` but the main one."""
    found = []
    for task in sorted(Path(f"/proc/{pid}/task").iterdir()):
        if int(task.name) == pid:
            continue
        fields = (task / "stat").read_text().rsplit(")", 1)[1].split()
        found.append((int(fields[38]), int(fields[37]), frozenset(os.sched_getaffinity(int(task.name)))))
    return found


def threads_while_running(system: Path, *arguments: str) -> tuple[list[tuple[int, int, frozenset[int]]], str]:
    """The settings of the executable's threads a moment after it started, and its output."""
    process = subprocess.Popen([str(system), "--threaded", "2", "--quiet", *arguments],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        time.sleep(0.7)
        threads = thread_settings(process.pid)
    finally:
        stdout, stderr = process.communicate(timeout=30)
    assert process.returncode == 0, stderr
    return threads, stdout


@pytest.mark.parametrize("subsystem", ["manip/a.cs", "grip/a.cs"], ids=["event-driven", "periodic"])
def test_priority_and_cpu_are_applied_in_the_subsystems_thread(system: Path, subsystem: str) -> None:
    threads, stdout = threads_while_running(system, "--mlockall", "--priority", f"{subsystem}=2",
                                            "--cpu", f"{subsystem}=0")
    # the event-driven subsystems, one thread each; the periodic ones of one period share one,
    # but a subsystem with settings of its own has its own
    expected = event_driven_subsystems() + (1 if subsystem == "manip/a.cs" else 2)
    assert len(threads) == expected and f"in {expected} thread(s)" in stdout, stdout
    assert [t for t in threads if t[0] == SCHED_FIFO] == [(SCHED_FIFO, 2, frozenset({0}))]


@pytest.mark.parametrize(("plan", "count"), [([], lambda: event_driven_subsystems() + 1),
                                             (["--threads", "period"], lambda: event_driven_subsystems() + 1),
                                             (["--threads", "subsystem"], lambda: 17)],
                         ids=["default", "period", "subsystem"])
def test_default_priority_applies_to_every_thread(system: Path, plan: list[str], count: Callable[[], int]) -> None:
    threads, stdout = threads_while_running(system, *plan, "--priority", "1")
    assert len(threads) == count() and f"in {count()} thread(s)" in stdout, stdout
    assert all(t[:2] == (SCHED_FIFO, 1) for t in threads)


@pytest.mark.parametrize(("arguments", "line"), [
    (["--priority", "0"], "earl: --priority 0 refused: expected [SUBSYSTEM=]N with N a whole number from 1 to 99"),
    (["--priority", "manip/a.cs=100"],
     "earl: --priority manip/a.cs=100 refused: expected [SUBSYSTEM=]N with N a whole number from 1 to 99"),
    (["--priority", "manip/a.nope=5"], "earl: --priority manip/a.nope=5 refused: no subsystem manip/a.nope"),
    (["--cpu", "-1"], "earl: --cpu -1 refused: expected [SUBSYSTEM=]N with N a whole number from 0 to 1023"),
])
def test_a_setting_out_of_range_is_refused_before_starting(system: Path, arguments: list[str], line: str) -> None:
    result = run(system, "--threaded", "5", *arguments)
    assert result.returncode == 2
    assert result.stderr == line + "\n" and result.stdout == ""


def test_a_cpu_that_does_not_exist_is_refused_naming_the_subsystem(system: Path) -> None:
    result = run(system, "--threaded", "5", "--cpu", "grip/a.cs=1000")
    assert result.returncode == 3
    assert result.stderr == ("earl: subsystem grip/a.cs: --cpu 1000 refused: invalid argument "
                             "(no such CPU, or not one this process may use)\n")
    assert "ran " not in result.stdout


@pytest.mark.skipif(shutil.which("setpriv") is None, reason="setpriv (util-linux) is needed")
def test_a_priority_without_the_capability_is_refused(system: Path) -> None:
    # without CAP_SYS_NICE (dropped from the bounding set) and RLIMIT_RTPRIO 0
    result = subprocess.run(["setpriv", "--bounding-set=-sys_nice", "prlimit", "--rtprio=0", str(system),
                             "--threaded", "5", "--priority", "manip/a.cs=80"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 3, result.stderr
    assert result.stderr == ("earl: subsystem manip/a.cs: --priority 80 (SCHED_FIFO) refused: operation not "
                             "permitted (needs CAP_SYS_NICE or an RLIMIT_RTPRIO of at least 80)\n")
