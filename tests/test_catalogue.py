"""Catalogue, implementations and docs match one to one."""

from __future__ import annotations

from earl_m2t.check.engine import builtin_invariants
from earl_m2t.check.registry import catalogue
from earl_m2t.check.rules import python_rules
from earl_m2t.resources import metamodel_path


def test_every_ocl_rule_has_an_invariant_and_every_invariant_a_rule() -> None:
    rules = catalogue()
    invariant_codes = {inv.name for inv in builtin_invariants()}
    ocl_codes = {code for code, info in rules.items() if info.engine == "ocl"}
    assert invariant_codes == ocl_codes


def test_every_python_rule_is_implemented_and_every_implementation_is_catalogued() -> None:
    rules = catalogue()
    python_codes = {code for code, info in rules.items() if info.engine == "python"}
    assert set(python_rules()) == python_codes


def test_every_rule_has_a_page_with_a_bad_and_a_good_example() -> None:
    for code, info in catalogue().items():
        page = metamodel_path("rules", "docs", f"{code}.md")
        assert page.is_file(), f"{code} has no page"
        text = page.read_text(encoding="utf-8")
        assert text.startswith(f"# {code} {info.name} ({info.severity.value})"), code
        for heading in ("## What it checks", "## Why it matters", "## Bad", "## Good", "## How to fix"):
            assert heading in text, f"{code} lacks {heading}"
        assert info.rationale and info.rationale != info.summary


def test_codes_are_well_formed_and_names_unique() -> None:
    rules = catalogue()
    assert all(len(code) == 4 and code[0] in "SCBTDRVX" and code[1:].isdigit() for code in rules)
    names = [info.name for info in rules.values()]
    assert len(names) == len(set(names))
