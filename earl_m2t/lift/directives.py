"""The model's directives to earl-m2t, read from its comments and constraints:

* suppressions, a comment ``earl-m2t: ignore[CODE, …] reason`` on an element (UML
  ``ownedComment``; its ``annotatedElement``s, else its owner, are the elements it is on);
* LTL properties, in the two forms the profile defines (profiles/earl.sysml): a Constraint
  stereotyped «LtlProperty» on any element, its name naming the property and its
  specification (an opaque expression, language ``LTL``) holding the formula (in SysML v2
  ``metadata NAME : Ltl { formula = "…"; }``); or a comment ``earl-m2t: ltl NAME: FORMULA``,
  one directive a line (a UML ``ownedComment``, a SysML v2 ``comment``/``doc``).
"""

from __future__ import annotations

import html
import re
from pathlib import Path

from earl_m2t.model.directives import LtlProperty, Suppression
from earl_m2t.model.location import Location
from earl_m2t.read.xmi import Element, ExternalRef, RawModel, stereotype_key

# Linear in the comment's length however it is written: the code list is bounded (an unclosed
# ``ignore[`` repeated along one line would otherwise be scanned to the line's end each time),
# and a tag cannot hold ``<`` (an unclosed ``<`` would otherwise be scanned to the text's end).
# A tag (of a tool's HTML notes) starts with a name, ``/`` or ``!``: the LTL operators ``<>`` and
# ``<->`` of an ``earl-m2t: ltl`` directive written as plain text are no tags.
IGNORE = re.compile(r"earl-m2t:\s*ignore\[([^\]\n]{0,200})\]([^\n]*)")
LTL = re.compile(r"earl-m2t:\s*ltl\s+([A-Za-z_][\w-]*)\s*:\s*(.*)")
_TAG = re.compile(r"</?[A-Za-z!][^<>]*>")
LTL_STEREOTYPE = "LtlProperty"


def comment_body(comment: Element) -> str:
    text = comment.get("body") or ""  # Cameo, Enterprise Architect
    text += "\n".join(b.text or "" for b in comment.iterchildren("body"))  # Papyrus
    return html.unescape(_TAG.sub("\n", text)) if "<" in text else text


def read_suppressions(raw: RawModel) -> tuple[Suppression, ...]:
    """Every suppression directive in the comments of the model's own documents."""
    found: list[Suppression] = []
    for root in raw.model_roots:
        for comment in root.iter("ownedComment"):
            directives = IGNORE.findall(comment_body(comment))
            if not directives:
                continue
            targets = [t for t in raw.refs(comment, "annotatedElement") if not isinstance(t, ExternalRef)]
            owner = raw.owner(comment)
            if not targets and owner is not None:
                targets = [owner]
            for codes, reason in directives:
                written = tuple(c.strip() for c in codes.split(",") if c.strip())
                for target in targets:
                    name = f"{raw.uml_type(target) or 'element'} '{raw.name(target)}'"
                    found.append(Suppression(written, reason.strip(" \t-–—:;,."), raw.xmi_id(target), name,
                                             raw.location(comment)))
    return tuple(found)


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
                match = LTL.search(line)
                if match is not None:
                    found.append((match.group(1), match.group(2).strip(),
                                  Location(where.file, where.line, match.start(2) + 1)))
    return tuple(LtlProperty(f"ltl{i}", formula, where, label=name) for i, (name, formula, where) in enumerate(found))


def _is_ltl_property(raw: RawModel, rule: Element) -> bool:
    key = stereotype_key(LTL_STEREOTYPE)
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
