"""No heap allocation per cycle after start-up in the generated C++ of the sample.

The sample is generated into a temporary folder and built with ``bench/cpp/count_new.cpp``,
which replaces the global operator new and delete with counting versions. The system is
built twice: with the generated pf stubs, and with the sample's own user code
(``samples/pick_and_place/user/``, copied over the stubs) when it is there.

* ``bench/cpp/alloc_main.cpp`` runs the whole system: 10,000 deterministic cycles after
  start-up, then one thread per subsystem for 0.2 s, and reports the operator new calls
  made in each counted phase;
* ``bench/cpp/driver.cpp`` (the per-cycle benchmark of manip/a.cs, ``bench/cpp_cycle.py``)
  runs a few thousand cycles of the generated subsystem and of the hand-written loop in
  both scenarios, including a transition on every cycle.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import generate

ROOT = Path(__file__).resolve().parents[1]

SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
SOURCES = ROOT / "bench" / "cpp"
SAMPLE_USER = SAMPLE.parent / "user"
CXXFLAGS = ["-std=c++17", "-O2", "-DNDEBUG", "-Wall", "-Wextra", "-Werror", "-pthread"]

pytestmark = pytest.mark.skipif(shutil.which("g++") is None, reason="g++ is needed")


def compile_(gen: Path, binary: Path, *sources: str, defines: tuple[str, ...] = ()) -> Path:
    includes = [f"-I{gen / 'runtime'}", f"-I{gen / 'generated' / 'include'}", f"-I{gen / 'user'}", f"-I{SOURCES}"]
    command = ["g++", *CXXFLAGS, *defines, *includes, *(str(SOURCES / s) for s in sources), "-o", str(binary)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, f"build failed:\n{result.stderr}"
    return binary


def run_json(*command: str | Path) -> list[dict]:
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    # user code may print its own lines; the reports are the JSON objects
    return [json.loads(line) for line in result.stdout.splitlines() if line.startswith("{\"")]


@pytest.fixture(scope="module")
def gen(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("cpp_alloc") / "gen"
    generate(load(SAMPLE).model, out)
    return out


@pytest.fixture(scope="module")
def alloc_main(gen: Path) -> Path:
    return compile_(gen, gen.parent / "alloc_main", "alloc_main.cpp", "count_new.cpp")


@pytest.fixture(scope="module", params=["stubs", "sample user code"])
def system_build(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory, alloc_main: Path) -> Path:
    if request.param == "stubs":
        return alloc_main
    if not any(SAMPLE_USER.glob("*/*/*.hpp")):
        pytest.skip("the sample has no user code")
    out = tmp_path_factory.mktemp("cpp_alloc_user") / "gen"
    generate(load(SAMPLE).model, out)
    shutil.copytree(SAMPLE_USER, out / "user", dirs_exist_ok=True)
    return compile_(out, out.parent / "alloc_main", "alloc_main.cpp", "count_new.cpp")


def test_the_system_allocates_nothing_per_cycle_after_start_up(system_build: Path) -> None:
    [report] = run_json(system_build, "--startup", "100", "--cycles", "10000", "--threaded", "0.2")
    assert report["components"] == 17
    assert report["cs_steps"] == 100 + 10000  # manip/a.cs ran every deterministic cycle
    assert report["allocations"] == 0, f"{report['allocations'] / 10000} allocations per cycle"
    # threaded: creating the threads allocates (start-up, and proof the counter works) ...
    assert report["threads"] >= 2 and report["threaded_start_allocations"] >= report["threads"]
    assert report["threaded_cs_steps"] > 0
    # ... running them does not
    assert report["threaded_allocations"] == 0, report


def test_the_counting_allocator_sees_an_allocation_in_the_counted_phase(alloc_main: Path) -> None:
    [report] = run_json(alloc_main, "--cycles", "100", "--threaded", "0", "--selftest")
    assert report["allocations"] == 1


def test_the_benchmark_driver_allocates_nothing_and_both_loops_agree(gen: Path) -> None:
    driver = compile_(gen, gen.parent / "driver", "driver.cpp", "baseline.cpp", "count_new.cpp",
                      defines=("-DBENCH_COUNT_NEW",))
    rows = run_json(driver, "--cycles", "5000", "--repeats", "2")
    assert [row["scenario"] for row in rows] == ["hold", "switching"]
    for row in rows:
        assert row["allocations"] == 0, row
        generated, baseline = row["generated"], row["baseline"]
        assert (generated["state"], generated["iteration"]) == (baseline["state"], baseline["iteration"]), row
        assert generated["best"] > 0 and baseline["best"] > 0
    hold, switching = rows
    assert hold["generated"]["state"] == "idle" and hold["generated"]["iteration"] > 0
    # a self-transition on every cycle: the behaviour restarts, iteration is 0 after each cycle
    assert switching["generated"]["state"] == "jointMove" and switching["generated"]["iteration"] == 0
