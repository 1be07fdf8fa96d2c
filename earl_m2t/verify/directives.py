"""LTL properties written in the model, in the two forms the profile defines (profiles/earl.sysml):

* a UML Constraint stereotyped «LtlProperty» on any element: its name names the property, its
  specification (an opaque expression, language ``LTL``) holds the formula; in SysML v2
  ``metadata NAME : Ltl { formula = "…"; }``;
* a comment ``earl-m2t: ltl NAME: FORMULA`` on any element, one directive a line, like the
  ``earl-m2t: ignore[…]`` suppressions (UML ``ownedComment``, a SysML v2 ``comment``/``doc``).

``NAME`` labels the property in the findings, which point at the constraint or the comment.
"""

from __future__ import annotations

import re
from pathlib import Path

from earl_m2t.check.suppress import comment_body
from earl_m2t.model.location import Location
from earl_m2t.read.xmi import Element, ExternalRef, RawModel, stereotype_key
from earl_m2t.verify.ltl import LtlProperty

DIRECTIVE = re.compile(r"earl-m2t:\s*ltl\s+([A-Za-z_][\w-]*)\s*:\s*(.*)")
STEREOTYPE = "LtlProperty"


def read_properties(raw: RawModel) -> tuple[LtlProperty, ...]:
    """The model's properties: the stereotyped constraints, then the comments, in file order."""
    found: list[tuple[str, str, Location]] = []
    lines: dict[str, list[str]] = {}
    for root in raw.model_roots:
        for rule in root.iter("ownedRule"):
            if _is_ltl_property(raw, rule):
                formula, where = _specification(raw, rule)
                found.append((raw.name(rule), formula, _column_in_file(where, formula, lines)))
    for root in raw.model_roots:
        for comment in root.iter("ownedComment"):
            where = raw.location(comment)
            for line in comment_body(comment).splitlines():
                match = DIRECTIVE.search(line)
                if match is not None:
                    found.append((match.group(1), match.group(2).strip(),
                                  Location(where.file, where.line, match.start(2) + 1)))
    return tuple(LtlProperty(f"ltl{i}", formula, where, label=name) for i, (name, formula, where) in enumerate(found))


def _is_ltl_property(raw: RawModel, rule: Element) -> bool:
    key = stereotype_key(STEREOTYPE)
    return any(app.family == "earl" and stereotype_key(app.name) == key for app in raw.applied(rule))


def _specification(raw: RawModel, rule: Element) -> tuple[str, Location]:
    """The formula and where its text starts (the constraint itself when it has none)."""
    specs = list(raw.children(rule, "specification"))
    if not specs:
        ref = raw.ref(rule, "specification")
        specs = [ref] if ref is not None and not isinstance(ref, ExternalRef) else []
    bodies = raw.opaque_bodies(specs[0]) if specs else []
    if not bodies:
        return "", raw.location(rule)
    return bodies[0][1].strip(), raw.body_location(specs[0])


def _column_in_file(where: Location, formula: str, lines: dict[str, list[str]]) -> Location:
    """``where`` with the column of the formula on its line when written there verbatim (a
    SysML v2 string, an XML body without escapes); else column 1: columns count in the formula."""
    if where.line > 0 and formula:
        if where.file not in lines:
            try:
                lines[where.file] = Path(where.file).read_text(encoding="utf-8", errors="replace").splitlines()
            except OSError:
                lines[where.file] = []
        text = lines[where.file][where.line - 1] if where.line <= len(lines[where.file]) else ""
        column = text.find(formula)
        if column >= 0:
            return Location(where.file, where.line, column + 1, where.xmi_id)
    return Location(where.file, where.line, 1, where.xmi_id)
