"""tests/support/campaigns.toml against the tests: every loaded test (a CPU hog per core) is a
campaign's run or a known-bad variant's, every test the table names is there, and the counts
choose as tests/support/campaign.py says."""

from __future__ import annotations

import ast

import pytest

from tests.support import campaign
from tests.support.paths import ROOT


def decorators(function: ast.FunctionDef) -> list[str]:
    return [ast.unparse(d) for d in function.decorator_list]


DIFFERENTIAL = "tests/test_differential_switching.py::"


def suite_functions() -> dict[str, ast.FunctionDef]:
    """Every test function of the suite by ``path::name``."""
    found = {}
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.FunctionDef) and node.name.startswith("test_"):
                found[f"{path.relative_to(ROOT).as_posix()}::{node.name}"] = node
    return found


def function_of(node_id: str) -> tuple[str, str | None]:
    """(path::name, the parameter id or None) of a pytest node id."""
    name, _, parameters = node_id.partition("[")
    return name, parameters.removesuffix("]") or None


def test_every_loaded_test_is_a_campaign_or_a_known_bad_variant() -> None:
    functions = suite_functions()
    loaded = {name for name, function in functions.items() if "pytest.mark.loaded" in decorators(function)}
    assert len(loaded) > 20
    named = {function_of(node_id)[0] for c in campaign.campaigns().values() for node_id in (*c.tests, c.known_bad)}
    assert sorted(loaded - named) == []
    assert sorted(named - set(functions)) == []
    # a known-bad variant that needs a loaded run is marked so; the restarted agent and the
    # forced switch's forgotten value are caught deterministically, and the differential test of
    # verify against the generated code needs no load at all
    unloaded = sorted(named - loaded)
    assert all("restarted" in name or "deterministic" in name or name.startswith(DIFFERENTIAL)
               for name in unloaded), unloaded


def test_a_parameter_id_in_the_table_is_one_the_test_is_parametrized_with() -> None:
    functions = suite_functions()
    for entry in campaign.campaigns().values():
        for node_id in (*entry.tests, entry.known_bad):
            name, parameter = function_of(node_id)
            if parameter is not None:
                parametrized = [d for d in decorators(functions[name]) if d.startswith("pytest.mark.parametrize")]
                assert parametrized and f"'{parameter}'" in parametrized[0], node_id


def test_the_suite_keeps_fewer_runs_than_the_full_campaign_and_at_least_one() -> None:
    for entry in campaign.campaigns().values():
        assert 1 <= entry.suite <= entry.full, entry


@pytest.mark.parametrize(("setting", "runs"), [("", "full"), ("full", "full"), ("suite", "suite"), ("7", 7)])
def test_the_variable_chooses_the_count(monkeypatch: pytest.MonkeyPatch, setting: str, runs: str | int) -> None:
    monkeypatch.setenv(campaign.VARIABLE, setting)
    hosts = campaign.campaigns()["ros2 hosts"]
    expected = getattr(hosts, runs) if isinstance(runs, str) else runs
    assert campaign.loaded_runs("ros2 hosts") == expected == campaign.catch_runs("ros2 hosts")


@pytest.mark.parametrize("setting", ["0", "-3", "many"])
def test_a_count_that_is_no_count_is_refused(monkeypatch: pytest.MonkeyPatch, setting: str) -> None:
    monkeypatch.setenv(campaign.VARIABLE, setting)
    with pytest.raises(ValueError, match="EARL_CAMPAIGN_RUNS"):
        campaign.loaded_runs("cpp two_arm")


def test_the_makefile_runs_the_suite_counts_in_the_suite() -> None:
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert "SUITE_RUNS ?= suite" in makefile and "EARL_CAMPAIGN_RUNS=$(SUITE_RUNS)" in makefile
