"""LTL properties written in the model: a comment ``earl-m2t: ltl NAME: FORMULA``.

Like the ``earl-m2t: ignore[…]`` suppressions, the directive is a comment (UML ``ownedComment``,
a SysML v2 ``comment``/``doc``), so every tool can hold it; one directive per line, on any
element. ``NAME`` labels the property in the findings.
"""

from __future__ import annotations

import re

from earl_m2t.check.suppress import comment_body
from earl_m2t.model.location import Location
from earl_m2t.read.xmi import RawModel
from earl_m2t.verify.ltl import LtlProperty

DIRECTIVE = re.compile(r"earl-m2t:\s*ltl\s+([A-Za-z_][\w-]*)\s*:\s*(.*)")


def read_properties(raw: RawModel) -> tuple[LtlProperty, ...]:
    found: list[LtlProperty] = []
    for root in raw.model_roots:
        for comment in root.iter("ownedComment"):
            where = raw.location(comment)
            for line in comment_body(comment).splitlines():
                match = DIRECTIVE.search(line)
                if match is None:
                    continue
                formula = match.group(2).strip()
                column = match.start(2) + 1
                found.append(LtlProperty(f"ltl{len(found)}", formula, Location(where.file, where.line, column),
                                         label=match.group(1)))
    return tuple(found)
