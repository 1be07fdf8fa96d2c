"""Conditions a SysML v2 model states in a form the predicate language cannot say reach B008
with their reason, and only those."""

from __future__ import annotations

from pathlib import Path

import pytest

from earl_m2t.api import check
from earl_m2t.lift.conditions import parse_condition
from earl_m2t.model.conditions import Condition, ConditionRole
from earl_m2t.model.location import Location
from earl_m2t.predicate.unsayable import unsayable, unsayable_reason

ROOT = Path(__file__).resolve().parents[2]
FORMS = ROOT / "tests" / "fixtures" / "sysml2" / "forms.sysml"
HIGH = "'level/ib'.msg.values#(1) >= 3.5"  # the body of high/pp


def test_the_reason_is_kept_and_other_texts_are_left_alone() -> None:
    assert unsayable_reason(unsayable("a string")) == "a string"
    assert unsayable_reason("  <null> ") == "null"
    for text in ("a < b", "<b>x</b>", "<>", "a/pp.fun", "x < 1 ∧ y > 2"):
        assert unsayable_reason(text) is None, text


def test_markup_in_a_body_stays_a_syntax_error() -> None:
    expr, problem = parse_condition(Condition("<b>x</b>", "EARL", Location("m.uml", 3), "t", ConditionRole.IC))
    assert expr is None and problem is not None
    assert problem.message.startswith("initial condition does not parse: ")


@pytest.mark.parametrize(("body", "reason"), [
    ('"high"', "a string"),
    ("null", "null"),
    ("'level/ib'.msg.values#(0) >= 3.5", "#(0): the elements of a sequence are numbered from 1"),
])
def test_a_sysml_v2_body_the_predicate_language_cannot_say_is_b008_with_its_reason(
        body: str, reason: str, tmp_path: Path) -> None:
    text = FORMS.read_text(encoding="utf-8")
    assert text.count(HIGH) == 1
    model = tmp_path / "forms.sysml"
    model.write_text(text.replace(HIGH, body), encoding="utf-8")
    line = next(n for n, row in enumerate(model.read_text(encoding="utf-8").splitlines(), 1) if body in row)
    errors = [d for d in check(model) if d.code == "B008"]
    assert [(d.location.line, d.message) for d in errors] == [
        (line, f"level/a.cs.high/pp: primitive predicate body is not in the predicate language ({reason})")]
