"""tests/support/suite_time.py, the summary ``./dev test`` prints of where the suite's time went:
every test module has an area, and the figures are those of the JUnit XML it reads."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.support import suite_time
from tests.support.paths import ROOT

JUNIT = """<?xml version="1.0" encoding="utf-8"?>
<testsuites><testsuite name="pytest" tests="5">
<testcase classname="tests.test_gen_ros2" name="test_launches[true-10]" time="75.5" />
<testcase classname="tests.test_gen_ros2" name="test_remaps" time="1.5"><failure message="x">x</failure></testcase>
<testcase classname="tests.rules.test_rule_triggers" name="test_b005" time="0.25" />
<testcase classname="tests.unit.test_ocl.TestParser" name="test_nested" time="0.75"><skipped message="y" /></testcase>
<testcase classname="tests.test_sample_runs" name="test_threaded" time="12.0"><error message="z">z</error></testcase>
</testsuite></testsuites>
"""


def test_every_test_module_belongs_to_an_area() -> None:
    areas = suite_time.load_areas()
    modules = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "tests").rglob("test_*.py"))
    assert len(modules) > 50
    assert [m for m in modules if suite_time.area_of(m, areas) == suite_time.OTHER] == []
    assert suite_time.area_of("tests/test_new_thing.py", areas) == suite_time.OTHER


def test_the_junit_classname_names_the_module_and_its_class() -> None:
    assert suite_time.module_of("tests.unit.test_ocl.TestParser") == ("tests/unit/test_ocl.py", "TestParser")
    assert suite_time.module_of("tests.test_gen_ros2") == ("tests/test_gen_ros2.py", "")


def test_the_summary_adds_up_the_junit_times_per_area_module_and_test(tmp_path: Path) -> None:
    junit = tmp_path / "junit.xml"
    junit.write_text(JUNIT, encoding="utf-8")
    result = subprocess.run([sys.executable, str(ROOT / "tests" / "support" / "suite_time.py"), str(junit),
                             "--slowest", "2"], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "5 tests (1 error, 1 failed, 2 passed, 1 skipped), 1:30.0 in tests"
    rows = [line.split() for line in lines]
    assert ["campaigns", "2", "1:17.0", "86", "%"] == rows[lines.index("time per area:") + 2][-5:]
    assert ["tests/test_sample_runs.py", "1", "0:12.0", "13", "%"] in rows
    assert ["tests/unit/test_ocl.py", "1", "0:00.8", "1", "%"] in rows
    slowest = lines[lines.index("the 2 slowest tests:") + 2:][:2]
    assert [line.split()[0] for line in slowest] == ["tests/test_gen_ros2.py::test_launches[true-10]",
                                                     "tests/test_sample_runs.py::test_threaded"]
    assert lines[-1] == "suite: 2 passed, 2 failed, 1 skipped"


def test_a_missing_result_file_is_one_line_and_exit_2(tmp_path: Path) -> None:
    result = subprocess.run([sys.executable, str(ROOT / "tests" / "support" / "suite_time.py"),
                             str(tmp_path / "none.xml")], capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "none.xml: no such file" in result.stderr
