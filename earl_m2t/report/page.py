"""``earl-m2t report``: a static HTML specification of a model, in one folder.

``index.html`` (style inline, no script, nothing from the network) shows the diagrams of
:mod:`earl_m2t.gen.diagrams` (files in ``diagrams/`` beside it), the paper-style tables of
:mod:`earl_m2t.gen.views.tables` and the findings of the check, each linked to the element
it is about; with ``--verify``, also the result of the model checker
(:mod:`earl_m2t.report.verification`). Every element has an id derived from its path
(:mod:`earl_m2t.gen.views.anchors`); the page's own sections use ids starting with ``report-``.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from html import escape
from pathlib import Path

from markupsafe import Markup

from earl_m2t.diagnostics import Diagnostic
from earl_m2t.gen.diagrams import RenderedDiagram, diagram_files, render_diagrams
from earl_m2t.gen.engine import environment, load_target
from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.views.tables import SpecTables, build_tables
from earl_m2t.model.elements import EarlModel
from earl_m2t.report.verification import verification_view
from earl_m2t.verify.run import VerifyResult

TARGET = "report"


@dataclass(frozen=True)
class FindingRow:
    code: str
    severity: str
    message: str
    element: str
    anchor: str  # id of the element (or its closest enclosing one), "" when none
    line: int


@dataclass(frozen=True)
class DiagramRef:
    name: str
    title: str
    src: str  # path relative to index.html


def diagram_folder() -> str:
    """The report's folder of diagrams, ``diagrams/`` unless ``transforms/report/target.toml``
    says otherwise."""
    return str(load_target(TARGET).get("diagrams_folder", "diagrams")).strip("/") + "/"


def render_report(model: EarlModel, findings: Sequence[Diagnostic], png: bool = False,
                  templates: Path | None = None, verification: VerifyResult | None = None) -> dict[str, bytes]:
    """``{relative path: bytes}`` of the report, with the result of ``earl-m2t verify`` and its
    counterexamples as sequence diagrams when given. Raises GenError (DotError when ``dot`` is
    missing or warns)."""
    folder = diagram_folder()
    tables = build_tables(model)
    rendered = render_diagrams(model, ("svg", "png") if png else ("svg",), tables=tables)
    files = diagram_files(rendered, folder)
    env = environment(TARGET, templates)
    env.autoescape = True
    env.filters["breakable"] = breakable
    rows = _findings(findings, tables)
    context = {
        "t": tables,
        "diagrams": _diagram_refs(rendered, folder),
        "findings": rows,
        "counts": Counter(row.severity for row in rows),
        "verification": None if verification is None else verification_view(model, verification, folder, files,
                                                                             tables),
    }
    for template, path in sorted(load_target(TARGET)["templates"].items()):
        files[path] = render_template(env, template, **context)
    return files


def breakable(name: object) -> Markup:
    """A long camelCase name that may wrap before its inner capitals (``<wbr>``), escaped."""
    return Markup(_INNER_CAPITAL.sub("<wbr>", escape(str(name))))


_INNER_CAPITAL = re.compile(r"(?<=[a-z0-9])(?=[A-Z])")


def _diagram_refs(rendered: tuple[RenderedDiagram, ...], folder: str) -> dict[str, DiagramRef]:
    """Diagrams by the id of the element they show."""
    return {item.diagram.element: DiagramRef(item.diagram.name, item.diagram.title,
                                             f"{folder}{item.diagram.name}.svg") for item in rendered}


def _findings(findings: Sequence[Diagnostic], tables: SpecTables) -> list[FindingRow]:
    return [FindingRow(code=d.code, severity=d.severity.value, message=d.message, element=d.element,
                       anchor=tables.anchors.nearest(d.element) if d.element else "", line=d.location.line)
            for d in findings]
