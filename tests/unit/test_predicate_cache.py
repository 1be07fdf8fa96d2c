"""Parsed predicate texts kept between runs (earl_m2t/predicate/known.py): the trees and the
syntax errors read back are those the parser gives, and the entry stays bounded."""

from __future__ import annotations

from pathlib import Path

import pytest

from earl_m2t import cache
from earl_m2t.predicate import known
from earl_m2t.predicate.errors import PredicateSyntaxError
from earl_m2t.predicate.parser import parse_predicate

GOOD = ("newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun", "newData(cmd/ib) ∨ x/m.data > 3")
BAD = "newJointPos/pp.fun ∧"


@pytest.fixture
def fresh_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> pytest.MonkeyPatch:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.delenv("EARL_M2T_NO_CACHE", raising=False)
    monkeypatch.setattr(known, "_known", known._Known())
    return monkeypatch


def _stored() -> dict[str, object]:
    table = cache.read_cached("predicates", known._grammar())
    assert isinstance(table, dict)
    return table


def test_trees_and_syntax_errors_come_back_as_the_parser_gives_them(fresh_run: pytest.MonkeyPatch) -> None:
    for text in (*GOOD, BAD):
        known.parsed(text)
    known.save()
    fresh_run.setattr(known, "_known", known._Known())  # the next run
    for text in GOOD:
        assert known.parsed(text) == parse_predicate(text)
    error = known.parsed(BAD)
    assert isinstance(error, PredicateSyntaxError)
    with pytest.raises(PredicateSyntaxError) as raised:
        parse_predicate(BAD)
    assert (error.message, error.line, error.column) == (raised.value.message, raised.value.line, raised.value.column)
    assert known._known.added is False  # nothing was parsed again


def test_the_entry_keeps_only_the_latest_run_once_it_is_full(fresh_run: pytest.MonkeyPatch) -> None:
    fresh_run.setattr(known, "_MAX_TEXTS", 2)
    for text in (*GOOD, BAD):
        known.parsed(text)
    known.save()
    assert sorted(_stored()) == sorted((*GOOD, BAD))  # everything this run used
    fresh_run.setattr(known, "_known", known._Known())
    known.parsed("other/pp.fun")
    known.save()
    assert list(_stored()) == ["other/pp.fun"]


def test_nothing_is_written_when_the_cache_is_off(fresh_run: pytest.MonkeyPatch, tmp_path: Path) -> None:
    fresh_run.setenv("EARL_M2T_NO_CACHE", "1")
    assert known.parsed(GOOD[0]) == parse_predicate(GOOD[0])
    known.save()
    assert not (tmp_path / "cache").exists()
