"""Diagnostics as text (``FILE:LINE: CODE severity: message [element]``) and as JSON."""

from __future__ import annotations

import json
from collections import Counter
from typing import Iterable

from earl_m2t.diagnostics import Diagnostic, Severity


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
