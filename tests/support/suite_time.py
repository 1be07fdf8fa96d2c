"""Where the test suite's time goes, read from pytest's JUnit XML.

``./dev test`` writes ``build/test-results/parallel.xml`` and ``loaded.xml`` (its two phases)
and prints this summary at its end: the
time per area (``suite_areas.toml``: the readers, the rules, each target's build, each
runtime's campaigns, fuzz), per module, and the slowest tests. A test's time is pytest's
"total" duration: its setup (a module's build fixture is paid by the first test that uses it),
its call and its teardown.

    python tests/support/suite_time.py build/test-results/*.xml [--slowest 20] [--markdown]

Standard library only, so it runs with any Python 3.11 (``./dev test`` runs it after pytest,
also when tests failed).
"""

from __future__ import annotations

import argparse
import fnmatch
import sys
import tomllib
import xml.etree.ElementTree as ElementTree
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
AREAS_FILE = Path(__file__).with_name("suite_areas.toml")
OTHER = "other"


@dataclass(frozen=True)
class TestTime:
    module: str  # the test file, relative to the checkout ("tests/test_gen_ros2.py")
    name: str  # the test's name within its module, with its class and parameters
    seconds: float
    outcome: str  # "passed", "failed", "error" or "skipped"


@dataclass(frozen=True)
class Area:
    name: str
    patterns: tuple[str, ...]


def load_areas(path: Path = AREAS_FILE) -> list[Area]:
    with path.open("rb") as file:
        table = tomllib.load(file)
    return [Area(entry["name"], tuple(entry["patterns"])) for entry in table["area"]]


def area_of(module: str, areas: Sequence[Area]) -> str:
    """The first area with a pattern ``module`` matches, else ``OTHER``."""
    return next((area.name for area in areas if any(fnmatch.fnmatchcase(module, p) for p in area.patterns)), OTHER)


def module_of(classname: str, root: Path = ROOT) -> tuple[str, str]:
    """(the test file, the rest) of a JUnit classname: ``tests.rules.test_x.TestY`` is
    ``tests/rules/test_x.py`` and ``TestY``; the longest dotted prefix naming a file wins."""
    parts = classname.split(".")
    for end in range(len(parts), 0, -1):
        candidate = "/".join(parts[:end]) + ".py"
        if (root / candidate).is_file():
            return candidate, ".".join(parts[end:])
    return classname.replace(".", "/") + ".py", ""


def outcome_of(case: ElementTree.Element) -> str:
    for tag, outcome in (("failure", "failed"), ("error", "error"), ("skipped", "skipped")):
        if case.find(tag) is not None:
            return outcome
    return "passed"


def read_junit(path: Path, root: Path = ROOT) -> list[TestTime]:
    tests = []
    for case in ElementTree.parse(path).getroot().iter("testcase"):
        module, inner = module_of(case.get("classname", ""), root)
        name = f"{inner}::{case.get('name', '')}" if inner else case.get("name", "")
        tests.append(TestTime(module, name, float(case.get("time") or 0.0), outcome_of(case)))
    return tests


@dataclass(frozen=True)
class Row:
    key: str
    tests: int
    seconds: float


def totals(tests: Iterable[TestTime], key_of: Callable[[TestTime], str]) -> list[Row]:
    """Rows of (key, number of tests, seconds), the largest time first."""
    count: dict[str, int] = {}
    seconds: dict[str, float] = {}
    for test in tests:
        key = key_of(test)
        count[key] = count.get(key, 0) + 1
        seconds[key] = seconds.get(key, 0.0) + test.seconds
    return sorted((Row(k, count[k], seconds[k]) for k in count), key=lambda row: (-row.seconds, row.key))


def minutes(seconds: float) -> str:
    return f"{int(seconds // 60)}:{seconds % 60:04.1f}"


def table(headers: Sequence[str], rows: Sequence[Sequence[str]], markdown: bool) -> list[str]:
    """Rows aligned in columns, the first left and the others right; a Markdown table if asked."""
    if markdown:
        lines = ["| " + " | ".join(headers) + " |", "|" + "|".join(["---"] + ["---:"] * (len(headers) - 1)) + "|"]
        return lines + ["| " + " | ".join(row) + " |" for row in rows]
    widths = [max(len(str(cell)) for cell in column) for column in zip(headers, *rows)]

    def line(cells: Sequence[str]) -> str:
        first, *rest = cells
        return "  ".join([first.ljust(widths[0]), *(c.rjust(w) for c, w in zip(rest, widths[1:]))]).rstrip()

    return [line(headers), *(line(row) for row in rows)]


def share(seconds: float, whole: float) -> str:
    return f"{100 * seconds / whole:.0f} %" if whole else "-"


def report(tests: Sequence[TestTime], areas: Sequence[Area], slowest: int, markdown: bool) -> list[str]:
    whole = sum(t.seconds for t in tests)
    outcomes = totals(tests, lambda t: t.outcome)
    counted = ", ".join(f"{row.tests} {row.key}" for row in sorted(outcomes, key=lambda r: r.key))
    lines = [f"{len(tests)} tests ({counted}), {minutes(whole)} in tests", ""]
    by_area = totals(tests, lambda t: area_of(t.module, areas))
    lines += ["time per area:"]
    lines += table(["area", "tests", "time", "share"],
                   [[r.key, str(r.tests), minutes(r.seconds), share(r.seconds, whole)] for r in by_area], markdown)
    lines += ["", "time per module:"]
    lines += table(["module", "tests", "time", "share"],
                   [[r.key, str(r.tests), minutes(r.seconds), share(r.seconds, whole)]
                    for r in totals(tests, lambda t: t.module)], markdown)
    ranked = sorted(tests, key=lambda t: (-t.seconds, t.module, t.name))[:slowest]
    lines += ["", f"the {len(ranked)} slowest tests:"]
    lines += table(["test", "time"], [[f"{t.module}::{t.name}", minutes(t.seconds)] for t in ranked], markdown)
    return lines


def closing_line(tests: Sequence[TestTime]) -> str:
    """The counts as the plain closing line CI reads when this summary ends the output."""
    count = {outcome: sum(t.outcome == outcome for t in tests) for outcome in ("passed", "failed", "error", "skipped")}
    return f"suite: {count['passed']} passed, {count['failed'] + count['error']} failed, {count['skipped']} skipped"


def main(argv: Sequence[str]) -> int:
    parser = argparse.ArgumentParser(description="Where the test suite's time goes, from pytest's JUnit XML.")
    parser.add_argument("junit", type=Path, nargs="+", help="JUnit XML files of one suite run (its phases)")
    parser.add_argument("--slowest", type=int, default=20, help="how many of the slowest tests to list")
    parser.add_argument("--markdown", action="store_true", help="Markdown tables (for docs/ci.md)")
    options = parser.parse_args(argv)
    tests: list[TestTime] = []
    for path in options.junit:
        if not path.is_file():
            print(f"suite_time: {path}: no such file (pytest wrote no JUnit XML)", file=sys.stderr)
            return 2
        try:
            tests += read_junit(path)
        except ElementTree.ParseError as error:
            print(f"suite_time: {path}: not JUnit XML: {error}", file=sys.stderr)
            return 2
    print("\n".join(report(tests, load_areas(), options.slowest, options.markdown)))
    print("\n" + closing_line(tests))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
