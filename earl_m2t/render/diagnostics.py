"""Diagnostics as text (``FILE:LINE: CODE severity: message [element]``), JSON, and the CI
formats of :mod:`earl_m2t.render.sarif`, :mod:`earl_m2t.render.junit` and :mod:`earl_m2t.render.github`."""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Callable, Iterable

from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.render.check_report import CheckReport
from earl_m2t.render.github import render_github
from earl_m2t.render.junit import render_junit
from earl_m2t.render.sarif import render_sarif


def summary_counts(diagnostics: Iterable[Diagnostic]) -> dict[str, int]:
    counts = Counter(d.severity for d in diagnostics)
    return {s.value: counts.get(s, 0) for s in Severity}


def text_line(diag: Diagnostic) -> str:
    loc = diag.location
    where = f"{loc.file}:{loc.line}" if loc.line else loc.file
    element = f" [{diag.element}]" if diag.element else ""
    return f"{where}: {diag.code} {diag.severity.value}: {diag.message}{element}"


def render_text(diagnostics: list[Diagnostic], files: int, unreadable: int = 0) -> str:
    lines = [text_line(d) for d in diagnostics]
    counts = summary_counts(diagnostics)
    noun = "file" if files == 1 else "files"
    not_read = f", {unreadable} could not be read" if unreadable else ""
    lines.append(
        f"{files} {noun} checked{not_read}: {counts['error']} error(s), {counts['warning']} warning(s), "
        f"{counts['info']} info"
    )
    return "\n".join(lines) + "\n"


def diagnostic_dict(diag: Diagnostic) -> dict[str, object]:
    loc = diag.location
    return {
        "code": diag.code,
        "severity": diag.severity.value,
        "message": diag.message,
        "element": diag.element,
        "file": loc.file,
        "line": loc.line,
        "column": loc.column,
        "xmi_id": loc.xmi_id,
    }


def render_json(diagnostics: list[Diagnostic], files: list[str], unreadable: list[dict[str, object]]) -> str:
    document = {
        "files": files,
        "unreadable": unreadable,
        "diagnostics": [diagnostic_dict(d) for d in diagnostics],
        "summary": summary_counts(diagnostics),
    }
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"


def _text(report: CheckReport) -> str:
    return render_text(report.diagnostics, len(report.checked), len(report.unreadable))


def _json(report: CheckReport) -> str:
    return render_json(report.diagnostics, report.checked, report.unreadable)


# Output formats of ``earl-m2t check --format``: each renders a whole report to one string.
FORMATS: dict[str, Callable[[CheckReport], str]] = {
    "text": _text,
    "json": _json,
    "sarif": render_sarif,
    "junit": render_junit,
    "github": render_github,
}
